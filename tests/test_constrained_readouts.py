"""The "Constrained particles" texts (app.scenes.constrained.readouts) as pure functions of a
simulation: no browser, no viser.  The numbers they print are read back and checked against
values computed here from the textbook formulas of each system (the bead on a hoop turning at Ω:
T₂ = ½ m R² θ̇², T₀ = ½ m Ω² R² sin² θ, V = −m g R cos θ, θ̈ = sin θ (Ω² cos θ − g/R); the
spherical pendulum's L_z = m L² sin² θ φ̇; ideal constraints do no virtual work in total)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from app.scenes.constrained import ConstrainedSetup, ConstrainedSimulation, conserved_text, readout_text, status_text

R, OMEGA, M, G = 1.0, 5.0, 2.0, 9.81
THETA, THETA_DOT = math.radians(60.0), math.radians(90.0)


def _hoop(omega: float = OMEGA) -> ConstrainedSimulation:
    return ConstrainedSimulation(ConstrainedSetup("hoop", (R, omega, M, G, 0.1), (60.0,), (90.0,)))


def _numbers(text: str, head: str) -> list[float]:
    """The numbers on the line of `text` that starts with `head`."""
    line = next(line for line in text.splitlines() if line.startswith(head))
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]\d+)?", line[len(head):])]


def _value(text: str, name: str) -> float:
    match = re.search(re.escape(name) + r" = (-?\d+\.\d+)", text)
    assert match, f"{name!r} not in the text"
    return float(match.group(1))


def test_the_turning_hoop_energies_and_jacobis_integral() -> None:
    sim = _hoop()
    ev = sim.evaluation()
    text, note = readout_text(sim, ev), conserved_text(sim, ev)
    T2 = 0.5 * M * R * R * THETA_DOT**2
    T0 = 0.5 * M * (OMEGA * R * math.sin(THETA)) ** 2
    V = -M * G * R * math.cos(THETA)
    for name, value in (("T₂", T2), ("T₁", 0.0), ("T₀", T0), ("V", V), ("T", T2 + T0)):
        assert _value(text, name) == pytest.approx(value, abs=6e-5), name
    assert "\nq               60   (deg or m)\nq̇               90   (deg/s or m/s)\n" in text
    assert "is not conserved" in note
    assert _value(note, "the energy T + V") == pytest.approx(T2 + T0 + V, abs=6e-5)
    assert _value(note, "Jacobi's integral h = T₂ − T₀ + V") == pytest.approx(T2 - T0 + V, abs=6e-7)
    star = math.degrees(math.acos(G / (OMEGA * OMEGA * R)))
    assert f"θ∗ = ±{star:.1f}°" in note and "the bottom is unstable" in note


def test_the_turning_hoop_constraint_force_and_its_virtual_work() -> None:
    sim = _hoop()
    ev = sim.evaluation()
    text = readout_text(sim, ev)
    s, c = math.sin(THETA), math.cos(THETA)
    theta_ddot = s * (OMEGA * OMEGA * c - G / R)
    # x = R (sin θ cos Ωt, sin θ sin Ωt, −cos θ), differentiated twice by hand at t = 0:
    x_ddot = R * np.array([c * theta_ddot - s * THETA_DOT**2 - s * OMEGA**2, 2.0 * c * THETA_DOT * OMEGA,
                           s * theta_ddot + c * THETA_DOT**2])
    F = np.array([0.0, 0.0, -M * G])
    np.testing.assert_allclose(_numbers(text, "F1 "), F, rtol=1e-3)
    np.testing.assert_allclose(_numbers(text, "C1=mẍ−F"), M * x_ddot - F, rtol=1e-3)
    assert abs(_numbers(text, "particle 1")[-1]) < 1e-9  # (5.7): C ⊥ ∂x/∂θ


def test_a_fixed_hoop_conserves_its_energy() -> None:
    sim = _hoop(omega=0.0)
    ev = sim.evaluation()
    note = conserved_text(sim, ev)
    energy = 0.5 * M * R * R * THETA_DOT**2 - M * G * R * math.cos(THETA)
    assert note.startswith("Fixed constraints")
    assert float(re.search(r"conserved: (-?\d+\.\d+) J", note).group(1)) == pytest.approx(energy, abs=6e-7)  # type: ignore[union-attr]
    assert f"Ω² R = 0 ≤ g = {G:g}: the bottom θ = 0 is stable." in note


def test_the_spherical_pendulum_shows_its_conserved_L_z() -> None:
    L, m = 1.5, 2.0
    sim = ConstrainedSimulation(ConstrainedSetup("spherical", (L, m, G, 0.1), (60.0, 0.0), (0.0, 45.0)))
    note = conserved_text(sim, sim.evaluation())
    L_z = m * L * L * math.sin(math.radians(60.0)) ** 2 * math.radians(45.0)
    assert _value(note, "L_z = m (x ẏ − y ẋ) = p_φ") == pytest.approx(L_z, abs=6e-7)


def test_the_double_pendulum_rods_do_no_virtual_work_in_total() -> None:
    sim = ConstrainedSimulation(ConstrainedSetup("double", (1.0, 0.8, 1.0, 2.0, G, 0.1), (30.0, -20.0),
                                                 (40.0, 10.0)))
    sim.advance(0.3)
    text = readout_text(sim, sim.evaluation())
    first, second, total = _numbers(text, "particle 1"), _numbers(text, "particle 2"), _numbers(text, "sum ")
    assert abs(first[0]) > 0.1  # the middle rod pushes the upper particle along θ₁ ...
    np.testing.assert_allclose(total, [0.0, 0.0], atol=1e-9)  # ... and the two together not at all
    np.testing.assert_allclose(np.add(first, second), total, atol=2e-3)
    assert "the **sum** is what" in text


def test_the_status_line() -> None:
    assert status_text(1.234, True, 2.0) == "**t = 1.23 s** · ▶ playing · 2× · RK8, steps of 1/120 s"
    assert status_text(0.0, False, 0.25) == "**t = 0.00 s** · paused · 0.25× · RK8, steps of 1/120 s"
