"""The "Moving frame" texts (app.scenes.moving_frame.readouts) as pure functions of a simulation:
no browser, no viser.  The numbers they print are read back and checked against values computed
here independently: C′'s attitude from SciPy's `Rotation.from_euler("ZXZ")` of φ = φ₀ + φ̇ t,
|ω| from the rates, Earth's sidereal day, and the forces on a tilted turntable (the force holding a
point at rest in C′ is m ω × (ω × D x′), the centrifugal force its opposite; Coriolis −2m ω_b × ẋ′)."""

from __future__ import annotations

import math
import re

import numpy as np
from scipy.spatial.transform import Rotation

from app.scenes.moving_frame import KEYS, MovingFrameSetup, MovingFrameSimulation, readout_text, status_text

PHI_DOT = 30.0  # [deg/s] a turntable about space z, tilted by θ₀
ANGLES0 = (10.0, 40.0, 20.0)  # [deg] φ₀ θ₀ ψ₀
MASS = 2.0


def _setup(forces_on: float, **changes: float) -> MovingFrameSetup:
    values = dict(phi_dot=PHI_DOT, theta_dot=0.0, psi_dot=0.0, phi_ddot=0.0, spin_up=600.0, offset=0.0, line_accel=0.0,
                  line_omega=0.0, mass=MASS, k=0.0, free_x=1.0, free_y=0.0, free_vx=0.5, free_vy=0.2,
                  rider_x=1.5, rider_y=0.5, anchor_x=0.0, anchor_y=0.0, stretch_x=0.5, stretch_y=0.0,
                  force_scale=0.5, disc_radius=2.0, forces_on=forces_on)
    values.update(changes)
    return MovingFrameSetup(tuple(values[k] for k in KEYS), ANGLES0)


def _text(sim: MovingFrameSimulation) -> str:
    x_body, _ = sim.body_coordinates()
    return readout_text(sim, sim.forces(), x_body)


def _row(text: str, name: str) -> np.ndarray:
    match = re.search(re.escape(name) + r"\s+(-?\d+\.\d{3})\s+(-?\d+\.\d{3})\s+(-?\d+\.\d{3})", text)
    assert match, f"no row {name!r} in the readout"
    return np.array([float(g) for g in match.groups()])


def _attitude(t: float) -> np.ndarray:
    phi0, theta0, psi0 = np.radians(ANGLES0)
    return Rotation.from_euler("ZXZ", [phi0 + math.radians(PHI_DOT) * t, theta0, psi0]).as_matrix()


def test_the_readout_shows_C_prime_now_and_the_rate_in_earth_rotations() -> None:
    sim = MovingFrameSimulation(_setup(2.0))
    sim.advance(1.0)
    text = _text(sim)
    assert "C′ now: φ θ ψ = 40.0°, 40.0°, 20.0°" in text  # φ = 10° + 30°/s × 1 s
    w = math.radians(PHI_DOT)
    sidereal = 2.0 * math.pi / (23 * 3600 + 56 * 60 + 4.1)  # [rad/s] 23 h 56 min 4.1 s
    assert f"|ω| = {w:.3f} rad/s = {w / sidereal:,.0f} × Earth's" in text
    omega_body = _attitude(1.0).T @ np.array([0.0, 0.0, w])
    assert f"ω_b = ({omega_body[0]:.3f}, {omega_body[1]:.3f}, {omega_body[2]:.3f}) rad/s" in text


def test_the_particle_at_rest_in_C_prime_is_held_against_the_centrifugal_force() -> None:
    sim = MovingFrameSimulation(_setup(2.0))
    sim.advance(1.0)
    text = _text(sim)
    assert "**at rest in C′**: x′ = (1.500, 0.500, 0.000) m, ẋ′ = (0.000, 0.000, 0.000) m/s" in text
    D = _attitude(1.0)
    omega = np.array([0.0, 0.0, math.radians(PHI_DOT)])
    x = D @ np.array([1.5, 0.5, 0.0])
    held = D.T @ (MASS * np.cross(omega, np.cross(omega, x)))  # m ẍ of a point turning with C′, in C′
    np.testing.assert_allclose(_row(text, "Dᵀ F (real)"), held, atol=6e-4)
    np.testing.assert_allclose(_row(text, "−m ω×(ω×x′)"), -held, atol=6e-4)
    for name in ("−m Dᵀ ä", "−m ω̇ × x′", "−2m ω × ẋ′", "sum", "m ẍ′"):
        np.testing.assert_array_equal(_row(text, name), np.zeros(3))  # printed as 0.000, never −0.000
    residual = float(re.search(r"\|m ẍ′ − sum\| = (\S+) N", text).group(1))  # type: ignore[union-attr]
    assert residual < 1e-12


def test_the_free_particle_feels_coriolis_and_centrifugal_forces_and_no_real_one() -> None:
    sim = MovingFrameSimulation(_setup(1.0))
    text = _text(sim)  # t = 0: x′ = (1, 0, 0) m, ẋ′ = (0.5, 0.2, 0) m/s
    assert "**free**: x′ = (1.000, 0.000, 0.000) m, ẋ′ = (0.500, 0.200, 0.000) m/s" in text
    omega_body = _attitude(0.0).T @ np.array([0.0, 0.0, math.radians(PHI_DOT)])
    x, v = np.array([1.0, 0.0, 0.0]), np.array([0.5, 0.2, 0.0])
    np.testing.assert_array_equal(_row(text, "Dᵀ F (real)"), np.zeros(3))
    np.testing.assert_allclose(_row(text, "−2m ω × ẋ′"), -2.0 * MASS * np.cross(omega_body, v), atol=6e-4)
    np.testing.assert_allclose(_row(text, "−m ω×(ω×x′)"), -MASS * np.cross(omega_body, np.cross(omega_body, x)),
                               atol=6e-4)


def test_the_status_line() -> None:
    assert status_text(1.234, True, 0.5, False) == "**t = 1.23 s** · ▶ playing · 0.5× · inertial view (C)"
    assert status_text(0.0, False, 2.0, True) == "**t = 0.00 s** · paused · 2× · riding with C′"
