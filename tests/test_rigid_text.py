"""The rigid-body texts (app.kit.rigid.text) as pure functions of a simulation: no browser, no
viser; the numbers they print are read back and checked against independent formulas (SciPy's
Rotation for D, ½ ω·Iω for T, m g ℓ cos θ for V, M·e for Q)."""

from __future__ import annotations

import math
import re

import numpy as np
from scipy.spatial.transform import Rotation

from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.rigid.text import accuracy_text, ghost_note, lagrange_text, legend_text, readout_text, status_text
from physics.dynamics import Model, State
from physics.lagrange import lagrange_terms

ANGLES = np.radians([30.0, 50.0, 20.0])
OMEGA_BODY = np.array([0.3, -0.4, 9.0])


def _top() -> RigidBodySimulation:
    R = Rotation.from_euler("ZXZ", ANGLES).as_matrix()
    return RigidBodySimulation(Model(inertia=(1.0, 1.0, 0.5), mgl=6.0), State(R, OMEGA_BODY.copy(), 0.0),
                               angles=ANGLES, momentum_kind="z")


def _number(text: str, pattern: str) -> float:
    match = re.search(pattern, text)
    assert match, f"{pattern!r} not in the text"
    return float(match.group(1))


def test_the_readout_prints_D_T_V_and_Q_of_the_state() -> None:
    sim = _top()
    text = readout_text(sim, (30.0, 50.0, 20.0), extras="conserved: L_z")
    rows = re.findall(r"\[\s*([-\d.]+)\s+([-\d.]+)\s+([-\d.]+)\s*\]", text)
    D = np.array([[float(x) for x in row] for row in rows[:3]])
    np.testing.assert_allclose(D, Rotation.from_euler("ZXZ", ANGLES).as_matrix(), atol=5e-5)  # 4 decimals
    T = 0.5 * float(OMEGA_BODY @ (np.array([1.0, 1.0, 0.5]) * OMEGA_BODY))
    assert _number(text, r"T = ([-\d.]+) J") == round(T, 5)
    V = 6.0 * math.cos(ANGLES[1])  # m g ℓ cos θ: the centre of mass at +ℓ on z′
    assert abs(_number(text, r"V = ([-\d.]+) J") - V) <= 5e-6
    # Q_φ = M·e_z = 0 (gravity's torque is horizontal), Q_θ = M·e_n = m g ℓ sin θ, Q_ψ = M·e_z′ = 0.
    assert abs(_number(text, r"Q_θ = M·e_n  = ([-\d.]+) N m") - 6.0 * math.sin(ANGLES[1])) <= 5e-5
    assert _number(text, r"Q_φ = M·e_z  = ([-\d.]+) N m") == 0.0
    assert "conserved: L_z" in text and "φ = 30.00°" in text


def test_angles_are_wrapped_and_the_gimbal_combination_said() -> None:
    sim = _top()
    text = readout_text(sim, (530.0, 1.0, -190.0))
    assert "φ = 170.00°" in text and "ψ = 170.00°" in text
    assert "gimbal lock: only φ + ψ = -20.00°" in text


def test_the_lagrange_text_prints_the_terms_and_a_small_residual() -> None:
    sim = _top()
    terms = lagrange_terms(sim.model, sim.t, sim.state.R_space_body, sim.state.omega_body, sim.angles)
    text = lagrange_text(sim, terms)
    residuals = [float(x) for x in re.search(r"residual[^\n]*\n\s+(.+)", text).group(1).split()]  # type: ignore[union-attr]
    assert len(residuals) == 3 and max(abs(r) for r in residuals) < 1e-9
    assert "30.00000" in text and "50.00000" in text  # q [deg]
    assert "singular" in lagrange_text(sim, None)


def test_status_accuracy_ghost_and_legend() -> None:
    sim = _top()
    for _ in range(30):
        sim.advance(1.0 / 60.0)
        sim.take_sample()
    status = status_text(sim, True, 0.5)
    assert f"t = {sim.t:.2f} s" in status and "▶ playing" in status and "0.5×" in status
    accuracy = accuracy_text(sim, "L_z")
    error = _number(accuracy, r"attitude \[rad\]\s+([-\d.e+]+)")
    assert error == float(f"{sim.attitude_error():.2e}")
    assert "|ΔL_z|/|L₀|" in accuracy
    assert max(len(line) for line in accuracy.split("```")[1].splitlines()) <= 34  # the follower's panel width
    note = ghost_note(sim, 1e6, "10⁶")
    assert f"{sim.attitude_error():.2e} rad" in note and "k = 10⁶" in note
    sim.set_integrator("exact")
    assert "IS the exact solution" in accuracy_text(sim, "L_z")
    legend = legend_text(True, 0.25, 0.5)
    assert "from the pivot" in legend and "1 unit = 4 rad/s" in legend and "1 unit = 2 kg m²/s" in legend
