"""The Euler-angles scene's texts as pure functions, from numbers to Markdown (no viser).

Angles come in degrees as the sliders show them (φ, ψ in (−180°, 180°], θ in [0°, 180°]),
rates in deg/s, moments in kg m²; D = Rz(φ) Rx(θ) Rz(ψ) (`physics.euler`).  The view
(`app.scenes.euler_angles.view`, and the single rotation's part) puts them into the panel and
the 3D labels at the rates it chooses.  Tested without a browser in tests/test_euler_readouts.py.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from app.i18n import Translator, refusal_text, translator
from app.kit.core.common import format_deg, format_matrix, format_vector
from app.scenes.euler_angles.simulation import GREEK, MIN_EDGE, box_edges
from physics.euler import (
    body_z_axis,
    euler_frames,
    line_of_nodes,
    omega_body_from_euler_rates,
    omega_space_from_euler_rates,
)
from physics.so3 import HALF_TURN_BAND, SingleRotation, rot_x, rot_z

__all__ = ["arc_text", "body_text", "factors_text", "matrix_text", "moments_refused_message", "moments_refused_text",
           "omega_text", "single_angle_text", "single_rotation_text", "status_text"]


ENGLISH = translator("en")


def _radians(angles_deg: Sequence[float]) -> tuple[float, float, float]:
    phi, theta, psi = (math.radians(a) for a in angles_deg)
    return phi, theta, psi


def status_text(t: float, playing: bool, time_scale: float, tr: Translator = ENGLISH) -> str:
    """The transport's status line: t [s], playing or paused, the time scale (words and numbers
    in the language of `tr`)."""
    state = tr.gettext("▶ playing") if playing else tr.gettext("paused")
    return f"**t = {tr.decimal(t, 2)} s** · {state} · {tr.general(time_scale)}×"


def _numbers(values: Sequence[float], tr: Translator) -> str:
    """Numbers a person reads, 2 decimals, in a list: "1.00, 2.00" (English), "1,00; 2,00"
    (a language whose decimal separator is the comma)."""
    written = [tr.decimal(float(v), 2) for v in values]
    return ("; " if any("," in w for w in written) else ", ").join(written)


def body_text(moments: Sequence[float], tr: Translator = ENGLISH) -> str:
    """The body folder's line: the drawn box's edge ratios (`box_edges`, shortest = 1) for the
    principal moments (3,) [kg m²], and whether it is a flat lamina (in the language of `tr`)."""
    edges = box_edges(moments)
    flat = edges.min() <= MIN_EDGE
    shown = edges / edges.min()
    status = tr.gettext("Uniform box with edges along x′, y′, z′ in the ratio **{ratios}**.").format(
        ratios=_numbers(shown, tr))
    if flat:
        status += "  \n" + tr.gettext("A flat lamina: one triangle inequality holds with equality.")
    return status


def moments_refused_text(error: BaseException, moments: Sequence[float], tr: Translator = ENGLISH) -> str:
    """The body folder's line when a moment was refused (`error`, physics' own words, English),
    `moments` [kg m²] staying."""
    return tr.gettext("**⚠ Not a rigid body:** {error}  \n"
                      "Each moment must be at most the sum of the other two "
                      "(I1 + I2 ≥ I3 and cyclic).  Showing the last valid body, I = ({moments}) kg m².").format(
        error=_error_words(error, tr), moments=_numbers(moments, tr))


def _error_words(error: BaseException, tr: Translator) -> str:
    """physics' refusal ("I1 + I2 >= I3 fails: 1 + 1 < 3") in the language of `tr` (`refusal_text`)."""
    return refusal_text(error, tr)


def moments_refused_message(index: int, value: float, error: BaseException, moments: Sequence[float],
                            tr: Translator = ENGLISH) -> str:
    """The message line when I_{index+1} = `value` was refused, `moments` [kg m²] staying."""
    return tr.gettext("I{number} = {value} refused: not a rigid body ({error}); "
                      "the body stays I = ({moments}) kg m².").format(
        number=index + 1, value=tr.general(value), error=_error_words(error, tr), moments=_numbers(moments, tr))


def arc_text(key: str, angle_deg: float) -> str:
    """An angle arc's reading, whole degrees: "φ = 31°" (`key` phi, theta or psi)."""
    return f"{GREEK[key]} = {format_deg(angle_deg, 0)}°"


def matrix_text(angles_deg: Sequence[float]) -> str:
    """The D tab: D (3, 3) to 4 decimals, the line of nodes e_n and the body's z′ axis in space."""
    phi, theta, psi = _radians(angles_deg)
    R = euler_frames(phi, theta, psi).body
    return (f"```\n{format_matrix(R, 4)}\n```\n"
            f"e_n = {format_vector(line_of_nodes(phi))}  \n"
            f"e_z′ = {format_vector(body_z_axis(phi, theta))}")


def factors_text(angles_deg: Sequence[float]) -> str:
    """The Factors tab: Rz(φ), Rx(θ), Rz(ψ), each under its angle [deg]."""
    phi, theta, psi = _radians(angles_deg)
    factors = ((f"Rz(φ), φ = {format_deg(angles_deg[0])}°", rot_z(phi)),
               (f"Rx(θ), θ = {angles_deg[1]:.2f}°", rot_x(theta)),
               (f"Rz(ψ), ψ = {format_deg(angles_deg[2])}°", rot_z(psi)))
    return "\n".join(f"{title}\n```\n{format_matrix(M, 4)}\n```" for title, M in factors)


def omega_text(angles_deg: Sequence[float], rates_deg: Sequence[float], tr: Translator = ENGLISH) -> str:
    """The ω tab [deg/s]: the rates, ω's three components φ̇ e_z, θ̇ e_n, ψ̇ e_z′ and ω in space
    components (x y z), ω_b in body components (x′ y′ z′), |ω|; 3 decimals, |x| < 5e-4 shown as 0
    (a table in a code block: its numbers as written in English, its words in the language of `tr`)."""
    phi, theta, psi = _radians(angles_deg)
    angles, rates = np.array([phi, theta, psi]), np.radians(rates_deg)
    omega_space = np.degrees(omega_space_from_euler_rates(angles, rates))
    omega_body = np.degrees(omega_body_from_euler_rates(angles, rates))
    dphi, dtheta, dpsi = rates_deg

    unit, space, body = tr.gettext("deg/s"), tr.gettext("ω_s (space)"), tr.gettext("ω_b (body)")

    def row(name: str, v: Any) -> str:
        return f"{name:<14}" + "".join(f"{(0.0 if abs(x) < 5e-4 else x):10.3f}" for x in v)

    return (
        "```\n"
        f"dφ/dt = {dphi:g}   dθ/dt = {dtheta:g}   dψ/dt = {dpsi:g}   [{unit}]\n\n"
        f"{'':<14}{'x | x′':>10}{'y | y′':>10}{'z | z′':>10}\n"
        f"{row('(dφ/dt) e_z', (0.0, 0.0, dphi))}\n"
        f"{row('(dθ/dt) e_n', dtheta * line_of_nodes(phi))}\n"
        f"{row('(dψ/dt) e_z′', dpsi * body_z_axis(phi, theta))}\n"
        f"{row(space, omega_space)}\n"
        f"{row(body, omega_body)}\n"
        f"|ω| = {float(np.linalg.norm(omega_space)):.3f} {unit}\n```"
    )


def single_angle_text(angle: float) -> str:
    """The Φ arc's label: the single rotation's angle `angle` [rad] in degrees, 1 decimal."""
    return f"Φ = {math.degrees(angle):.1f}°"


def single_rotation_text(rotation: SingleRotation, D: np.ndarray) -> str:
    """The single rotation's readout: Φ [deg and rad] with cos Φ = (tr D − 1)/2 from D (3, 3),
    the axis d (or that it is undefined at Φ = 0; the half-turn note within HALF_TURN_BAND of
    π), A = Φ hat(d), the rotation vector Φ d [rad] and the quaternion (w, x, y, z); 4 decimals."""
    angle_deg = math.degrees(rotation.angle)
    lines = [f"**Φ = {angle_deg:.2f}°** = {rotation.angle:.4f} rad;  "
             f"cos Φ = (tr D − 1)/2 = {0.5 * (float(np.trace(D)) - 1.0):.4f} (1.1)  "]
    if rotation.axis is None:
        lines.append("**d undefined**: Φ = 0, D = 1 — a turn by 0 about any axis.  ")
    else:
        lines.append(f"**d = {format_vector(rotation.axis, 4)}** (D d = d)  ")
        if math.pi - rotation.angle <= HALF_TURN_BAND:
            lines.append("Half turn: d and −d give the same D; d from (D + 1)/2 = d dᵀ, "
                         "its sign kept from the axis drawn before.  ")
    w, x, y, z = rotation.wxyz
    lines.append(
        "```\n"
        f"A = Φ hat(d), D = exp(A) (1.2, 1.3)\n{format_matrix(rotation.A, 4)}\n"
        f"Φ d = {format_vector(rotation.rotvec, 4)} rad\n"
        f"q = (cos Φ/2, sin Φ/2 d)\n  = {format_vector(np.array([w, x, y, z]), 4)}\n```"
    )
    return "\n".join(lines)
