"""The Euler-angles scene's texts as pure functions (`app.scenes.euler_angles.readouts`), no server.

References independent of the scene's code: SciPy's `Rotation` for D = Rz(φ) Rx(θ) Rz(ψ)
("ZXZ", intrinsic), its factors, the single rotation (magnitude, rotvec, quaternion); ω in space
components from a central difference of D(t) at the set rates, vee(Ḋ Dᵀ), and ω_b = Dᵀ ω_s;
the uniform box's moments written out for the body line.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app.scenes.euler_angles.readouts import (
    arc_text,
    body_text,
    factors_text,
    matrix_text,
    moments_refused_message,
    moments_refused_text,
    omega_text,
    single_angle_text,
    single_rotation_text,
    status_text,
)
from physics.inertia import InertiaError
from physics.so3 import single_rotation

MATRIX_TOL = 0.51e-4  # matrices are printed to 4 decimals
VECTOR_TOL = 0.51e-3  # e_n and e_z′ to 3
RATE_TOL = 0.51e-3  # [deg/s] the ω table to 3
_NUMBER = r"-?\d+\.\d+"
POSES_DEG = [(30.0, 50.0, 20.0), (-120.0, 100.0, 170.0), (90.0, 180.0, 0.0), (10.0, 1.0, -10.0), (0.0, 0.0, 0.0)]


def matrices(text: str) -> list[np.ndarray]:
    """The 3×3 matrices printed in `text` (rows '[ a  b  c ]'), in order."""
    rows = [[float(x) for x in row] for row in
            re.findall(r"\[\s*(" + _NUMBER + r")\s+(" + _NUMBER + r")\s+(" + _NUMBER + r")\s*\]", text)]
    assert len(rows) % 3 == 0, text
    return [np.array(rows[k:k + 3]) for k in range(0, len(rows), 3)]


def vector(text: str, name: str) -> np.ndarray:
    match = re.search(re.escape(name) + r" = \((" + _NUMBER + r"(?:, " + _NUMBER + r")+)\)", text)
    assert match, (name, text)
    return np.array([float(x) for x in match.group(1).split(", ")])


def D_of(angles_deg) -> np.ndarray:  # type: ignore[no-untyped-def]
    return Rotation.from_euler("ZXZ", angles_deg, degrees=True).as_matrix()


@pytest.mark.parametrize("angles_deg", POSES_DEG)
def test_the_D_tab_is_scipys_zxz_matrix_its_line_of_nodes_and_z_axis(angles_deg) -> None:  # type: ignore[no-untyped-def]
    text = matrix_text(angles_deg)
    (shown,) = matrices(text)
    D = D_of(angles_deg)
    np.testing.assert_allclose(shown, D, atol=MATRIX_TOL)
    phi = math.radians(angles_deg[0])
    np.testing.assert_allclose(vector(text, "e_n"), [math.cos(phi), math.sin(phi), 0.0], atol=VECTOR_TOL)
    np.testing.assert_allclose(vector(text, "e_z′"), D[:, 2], atol=VECTOR_TOL)
    assert "-0.0000" not in text and "-0.000," not in text


def test_the_factors_tab_is_the_three_elementary_turns_under_their_angles() -> None:
    angles_deg = (-120.0, 100.0, 170.0)
    text = factors_text(angles_deg)
    Rz_phi, Rx_theta, Rz_psi = matrices(text)
    np.testing.assert_allclose(Rz_phi, Rotation.from_euler("z", -120.0, degrees=True).as_matrix(), atol=MATRIX_TOL)
    np.testing.assert_allclose(Rx_theta, Rotation.from_euler("x", 100.0, degrees=True).as_matrix(), atol=MATRIX_TOL)
    np.testing.assert_allclose(Rz_psi, Rotation.from_euler("z", 170.0, degrees=True).as_matrix(), atol=MATRIX_TOL)
    np.testing.assert_allclose(Rz_phi @ Rx_theta @ Rz_psi, D_of(angles_deg), atol=3 * MATRIX_TOL)
    assert "Rz(φ), φ = -120.00°" in text and "Rx(θ), θ = 100.00°" in text and "Rz(ψ), ψ = 170.00°" in text


@pytest.mark.parametrize(("angles_deg", "rates_deg"), [((30.0, 50.0, 20.0), (20.0, 10.0, 45.0)),
                                                        ((-120.0, 100.0, 170.0), (-90.0, 35.0, 0.0)),
                                                        ((10.0, 1.0, -10.0), (0.0, -60.0, 180.0))])
def test_the_omega_tab_is_the_angular_velocity_of_D_of_t(angles_deg, rates_deg) -> None:  # type: ignore[no-untyped-def]
    text = omega_text(angles_deg, rates_deg)
    rows = {name.strip(): np.array([float(x) for x in values.split()])
            for name, values in re.findall(r"^(\S.{13})((?:\s+" + _NUMBER + r"){3})$", text, re.M)}
    assert set(rows) == {"(dφ/dt) e_z", "(dθ/dt) e_n", "(dψ/dt) e_z′", "ω_s (space)", "ω_b (body)"}, text
    h = 1e-5  # [s]
    D = D_of(angles_deg)
    step = np.multiply(rates_deg, h)  # [deg] the angles' change in h
    D_dot = (D_of(np.add(angles_deg, step)) - D_of(np.subtract(angles_deg, step))) / (2 * h)
    W = D_dot @ D.T  # hat(ω_s) [rad/s]
    omega_space = np.degrees(np.array([W[2, 1], W[0, 2], W[1, 0]]))  # [deg/s]
    np.testing.assert_allclose(rows["ω_s (space)"], omega_space, atol=RATE_TOL)
    np.testing.assert_allclose(rows["ω_b (body)"], D.T @ omega_space, atol=RATE_TOL)
    phi = math.radians(angles_deg[0])
    np.testing.assert_allclose(rows["(dφ/dt) e_z"], [0.0, 0.0, rates_deg[0]], atol=RATE_TOL)
    np.testing.assert_allclose(rows["(dθ/dt) e_n"], rates_deg[1] * np.array([math.cos(phi), math.sin(phi), 0.0]),
                               atol=RATE_TOL)
    np.testing.assert_allclose(rows["(dψ/dt) e_z′"], rates_deg[2] * D[:, 2], atol=RATE_TOL)
    magnitude = float(re.search(r"\|ω\| = (" + _NUMBER + r") deg/s", text).group(1))  # type: ignore[union-attr]
    assert magnitude == pytest.approx(float(np.linalg.norm(omega_space)), abs=RATE_TOL)
    assert f"dφ/dt = {rates_deg[0]:g}   dθ/dt = {rates_deg[1]:g}   dψ/dt = {rates_deg[2]:g}" in text


@pytest.mark.parametrize("angles_deg", [(30.0, 50.0, 20.0), (-120.0, 100.0, 170.0), (0.0, 60.0, 180.0)])
def test_the_single_rotation_readout_is_scipys_rotation_vector(angles_deg) -> None:  # type: ignore[no-untyped-def]
    D = D_of(angles_deg)
    text = single_rotation_text(single_rotation(D), D)
    reference = Rotation.from_matrix(D)
    angle = float(re.search(r"Φ = (" + _NUMBER + r")°", text).group(1))  # type: ignore[union-attr]
    assert angle == pytest.approx(math.degrees(reference.magnitude()), abs=0.0051)
    rotvec = reference.as_rotvec()
    quat = reference.as_quat(canonical=True, scalar_first=True)
    if reference.magnitude() > math.pi - 1e-9:  # a half turn: ±π d are the same D, the sign is the app's
        sign = 1.0 if float(vector(text, "Φ d") @ rotvec) > 0.0 else -1.0
        rotvec, quat = sign * rotvec, np.concatenate([[abs(quat[0])], sign * np.sign(quat[0] or 1.0) * quat[1:]])
        assert "Half turn" in text
    np.testing.assert_allclose(vector(text, "Φ d"), rotvec, atol=MATRIX_TOL)
    np.testing.assert_allclose(vector(text, "**d"), rotvec / reference.magnitude(), atol=MATRIX_TOL)
    np.testing.assert_allclose(vector(text, " "), quat, atol=MATRIX_TOL)  # the line under "q = (cos Φ/2, sin Φ/2 d)"
    (A,) = matrices(text)
    np.testing.assert_allclose(A, [[0.0, -rotvec[2], rotvec[1]], [rotvec[2], 0.0, -rotvec[0]],
                                   [-rotvec[1], rotvec[0], 0.0]], atol=MATRIX_TOL)
    cos_angle = float(re.search(r"\(tr D − 1\)/2 = (" + _NUMBER + ")", text).group(1))  # type: ignore[union-attr]
    assert cos_angle == pytest.approx(math.cos(reference.magnitude()), abs=MATRIX_TOL)
    assert single_angle_text(reference.magnitude()) == f"Φ = {math.degrees(reference.magnitude()):.1f}°"


def test_no_turn_says_the_axis_is_undefined() -> None:
    text = single_rotation_text(single_rotation(np.eye(3)), np.eye(3))
    assert "**Φ = 0.00°** = 0.0000 rad" in text and "**d undefined**" in text and "Half turn" not in text
    np.testing.assert_allclose(vector(text, "Φ d"), 0.0)
    np.testing.assert_allclose(vector(text, " "), [1.0, 0.0, 0.0, 0.0])


def test_the_body_line_gives_the_uniform_boxs_edge_ratios() -> None:
    def moments(a: float, b: float, c: float) -> tuple[float, float, float]:  # m/12 (b² + c², ...), m = 12
        return b * b + c * c, a * a + c * c, a * a + b * b

    box = body_text(moments(3.0, 2.0, 1.0))
    assert "ratio **3.00, 2.00, 1.00**" in box and "lamina" not in box
    assert body_text((1.0, 2.0, 2.6)) == box  # the same shape: only the ratios are read out
    lamina = body_text(moments(2.0, 1.0, 0.0))  # c = 0: I1 + I2 = I3, drawn MIN_EDGE thick
    assert "A flat lamina" in lamina
    ratios = [float(x) for x in re.search(r"ratio \*\*(.*)\*\*", lamina).group(1).split(", ")]  # type: ignore[union-attr]
    assert ratios[0] / ratios[1] == pytest.approx(2.0, abs=0.01) and ratios[2] == 1.0


def test_status_arcs_and_refusals() -> None:
    assert status_text(1.234, True, 0.5) == "**t = 1.23 s** · ▶ playing · 0.5×"
    assert status_text(0.0, False, 1.0) == "**t = 0.00 s** · paused · 1×"
    assert arc_text("phi", 30.6) == "φ = 31°" and arc_text("theta", 90.0) == "θ = 90°"
    assert arc_text("psi", -179.8) == "ψ = 180°"  # wrapped after rounding: never -180°
    error = InertiaError("I2 + I3 >= I1 fails")
    assert moments_refused_text(error, (1.0, 2.0, 2.6)).endswith("I = (1.00, 2.00, 2.60) kg m².")
    assert "I2 + I3 >= I1 fails" in moments_refused_text(error, (1.0, 2.0, 2.6))
    assert moments_refused_message(0, 4.9, error, (1.0, 2.0, 2.6)) == (
        "I1 = 4.9 refused: not a rigid body (I2 + I3 >= I1 fails); the body stays I = (1.00, 2.00, 2.60) kg m².")
