"""The "Moving frame" scene's texts as pure functions (no viser): the status line and the
readout, numbers in, Markdown out.  `MovingFrameView` puts them into its panel at READOUT_PERIOD;
tests/test_moving_frame_readouts.py checks them without a browser.  Angles in degrees
(`format_deg`: wrapped to (−180°, 180°]), SI units otherwise; forces in C′ (body components).
"""

from __future__ import annotations

import math

import numpy as np

from app.i18n import DEFAULT_LANGUAGE, Translator, translator
from app.kit.core.common import format_deg, format_vector
from app.scenes.moving_frame.simulation import PARTICLES, ForceReport, MovingFrameSimulation
from physics._types import Array, Vec3

__all__ = ["EARTH_OMEGA", "force_row", "readout_text", "status_text"]

EARTH_OMEGA = 2.0 * math.pi / 86164.1  # [rad/s] Earth's sidereal rotation, for the readout
ENGLISH = translator(DEFAULT_LANGUAGE)


def status_text(t: float, playing: bool, time_scale: float, riding: bool, tr: Translator = ENGLISH) -> str:
    """The transport's status line: t [s], playing or paused, the time scale, the camera (riding
    with C′ or the inertial view), in the language of `tr`."""
    _ = tr.gettext
    state = _("▶ playing") if playing else _("paused")
    view = _("riding with C′") if riding else _("inertial view (C)")
    return f"**t = {tr.decimal(t, 2)} s** · {state} · {tr.general(time_scale)}× · {view}"


def force_row(name: str, v: Vec3) -> str:
    """One row of the forces' table: the name in 15 columns, then x′ y′ z′ [N] in 9 columns of
    3 decimals each (|c| < 5e-4 shown as 0.000, never −0.000)."""
    return f"{name:<15}" + "".join(f"{(0.0 if abs(c) < 5e-4 else c):9.3f}" for c in v)


def readout_text(sim: MovingFrameSimulation, report: ForceReport, x_body: Array, tr: Translator = ENGLISH) -> str:
    """The readout (Markdown): C′ now (its angles [deg], ω_b [rad/s] and |ω| in Earth's rotation
    rates, a and ä), the chosen particle's x′ [m] and ẋ′ [m/s], the table of the forces on it in
    C′ [N] (real, the four inertial ones, their sum, m ẍ′ found without (1.28)) and the residual.

    report: `sim.forces()` now; x_body: (3, 3) the particles' x′ now [m] (`sim.body_coordinates()`).
    """
    _ = tr.gettext
    frame = sim.frame
    focus = sim.setup.focus
    v_body = sim.body_coordinates()[1]
    w = float(np.linalg.norm(frame.omega_body))
    residual = float(np.max(np.abs(report.residual[focus])))
    force_scale = max(1.0, float(np.max(np.abs(report.m_x_ddot_body[focus]))))
    phi, theta, psi = sim.angles_deg
    held = _(" (stopped by the rim, now carried by it)") if focus == 0 and sim.caught_at is not None else ""
    lines = [
        _("C′ now: φ θ ψ = {phi}°, {theta}°, {psi}°").format(phi=format_deg(phi, 1), theta=f"{theta:.1f}",
                                                             psi=format_deg(psi, 1)) + "  \n"
        + _("ω_b = {omega} rad/s, |ω| = {w} rad/s = {earth} × Earth's").format(
            omega=format_vector(frame.omega_body), w=f"{w:.3f}", earth=f"{w / EARTH_OMEGA:,.0f}") + "  \n"
        f"a = {format_vector(frame.a)} m, ä = {format_vector(frame.a_ddot)} m/s²",
        "**" + _(PARTICLES[focus]) + f"**{held}: x′ = {format_vector(x_body[focus])} m, "
        f"ẋ′ = {format_vector(v_body[focus])} m/s",
        "```\n" + _("force in C′ [N]").ljust(15) + "     x′       y′       z′",
        force_row(_("Dᵀ F (real)"), report.real[focus]),
        force_row("−m Dᵀ ä", report.inertial.translational[focus]),
        force_row("−m ω̇ × x′", report.inertial.euler[focus]),
        force_row("−m ω×(ω×x′)", report.inertial.centrifugal[focus]),
        force_row("−2m ω × ẋ′", report.inertial.coriolis[focus]),
        force_row(_("sum"), report.real[focus] + report.inertial.total[focus]),
        force_row("m ẍ′", report.m_x_ddot_body[focus]),
        "```",
        _("m ẍ′ from x′ = Dᵀ(x − a) differentiated (no (1.28)); |m ẍ′ − sum| = {residual} N "
            "({relative} relative).").format(residual=f"{residual:.1e}", relative=f"{residual / force_scale:.1e}"),
    ]
    return "\n".join(lines)
