"""Tests of physics.moving_frames against finite differences of x(t) = a(t) + R(t) x'(t).

a(t), R(t) (from z-x-z Euler angles that are smooth functions of t, built with SciPy) and
x'(t) are smooth; every derivative the formulas need (ȧ, ä, ẋ, ẍ, ẋ', ẍ', ω_s, ω_b, ω̇_b) is
taken by 5-point central differences, never from the code under test.  Truncation error of
the stencils is O(h⁴); the tolerances below are written next to each check.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.spatial.transform import Rotation

from physics.inertia import inertia_tensor_of_particles
from physics.moving_frames import (
    FrameMotion,
    InertialForce,
    acceleration_body,
    inertial_force_body,
    kinetic_energy_particle,
    velocity_space,
)

H1 = 1e-3  # step of the first-derivative stencil [s]: error ~h⁴ f⁽⁵⁾/30 + eps/h ≈ 1e-12
H2 = 3e-3  # step of the second-derivative stencil [s]: error ~h⁴ f⁽⁶⁾/90 + eps/h² ≈ 1e-10

Fn = Callable[[float], np.ndarray]


def d1(f: Fn, t: float, h: float = H1) -> np.ndarray:
    """5-point central first derivative."""
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h)


def d2(f: Fn, t: float, h: float = H2) -> np.ndarray:
    """5-point central second derivative."""
    return (-f(t - 2 * h) + 16 * f(t - h) - 30 * f(t) + 16 * f(t + h) - f(t + 2 * h)) / (12 * h * h)


def vee(A: np.ndarray) -> np.ndarray:
    """Vector of a skew matrix (written out here, not imported from the code under test)."""
    return np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]]) / 2.0


@dataclass(frozen=True)
class Motion:
    """Smooth a(t) [m], R(t) from Euler angles (φ, θ, ψ)(t) [rad], and particles x'_i(t) [m]."""

    a_coef: np.ndarray  # (3, 3): a_k(t) = c0 sin(c1 t) + c2 t²
    euler_coef: np.ndarray  # (3, 3): angle_k(t) = c0 + c1 t + 0.5 sin(c2 t)
    x_coef: np.ndarray  # (N, 3, 2): x'_ik(t) = c0 + c1 sin(t + k)

    def a(self, t: float) -> np.ndarray:
        c = self.a_coef
        return c[:, 0] * np.sin(c[:, 1] * t) + c[:, 2] * t * t

    def angles(self, t: float) -> np.ndarray:
        c = self.euler_coef
        return c[:, 0] + c[:, 1] * t + 0.5 * np.sin(c[:, 2] * t)

    def R(self, t: float) -> np.ndarray:
        return Rotation.from_euler("ZXZ", self.angles(t)).as_matrix()

    def x_body(self, t: float) -> np.ndarray:  # (N, 3)
        c = self.x_coef
        return c[..., 0] + c[..., 1] * np.sin(t + np.arange(3.0))

    def x_space(self, t: float) -> np.ndarray:  # (N, 3), x = a + R x'
        return self.a(t) + self.x_body(t) @ self.R(t).T

    def omega_space(self, t: float) -> np.ndarray:
        """hat(ω_s) = Ṙ Rᵀ, Ṙ by finite differences."""
        return vee(d1(self.R, t) @ self.R(t).T)

    def omega_body(self, t: float) -> np.ndarray:
        """hat(ω_b) = Rᵀ Ṙ, Ṙ by finite differences."""
        return vee(self.R(t).T @ d1(self.R, t))


def default_motion(n_particles: int = 4, seed: int = 0) -> Motion:
    rng = np.random.default_rng(seed)
    return Motion(
        a_coef=rng.uniform(-1.0, 1.0, (3, 3)) * [1.0, 2.0, 0.5],
        euler_coef=rng.uniform(-1.0, 1.0, (3, 3)) * [2.0, 1.5, 2.0] + [0.0, 0.0, 0.0],
        x_coef=rng.uniform(-1.0, 1.0, (n_particles, 3, 2)),
    )


coef = st.floats(-1.0, 1.0)
motions = st.builds(
    Motion,
    a_coef=hnp.arrays(np.float64, (3, 3), elements=coef),
    euler_coef=hnp.arrays(np.float64, (3, 3), elements=st.floats(-2.0, 2.0)),
    x_coef=hnp.arrays(np.float64, (3, 3, 2), elements=coef),
)
times = st.floats(-1.0, 1.0)


@settings(max_examples=60, deadline=None)
@given(motions, times)
def test_velocity_space_matches_finite_differences(motion: Motion, t: float) -> None:
    """ẋ = ȧ + ω_s × (R x') + R ẋ' (1.19) against d/dt of x(t) = a + R x'."""
    expected = d1(motion.x_space, t)
    actual = velocity_space(
        d1(motion.a, t), motion.R(t), motion.omega_space(t), motion.x_body(t), d1(motion.x_body, t)
    )
    np.testing.assert_allclose(actual, expected, atol=1e-8)
    # One particle at a time ((3,) input) gives the same rows.
    for i in range(len(expected)):
        row = velocity_space(
            d1(motion.a, t), motion.R(t), motion.omega_space(t), motion.x_body(t)[i], d1(motion.x_body, t)[i]
        )
        np.testing.assert_allclose(row, actual[i], atol=1e-14)


@settings(max_examples=60, deadline=None)
@given(motions, times)
def test_acceleration_body_matches_finite_differences(motion: Motion, t: float) -> None:
    """ẍ' (1.28) given ẍ, ä, ω_b, ω̇_b, all by FD, equals the FD of x'(t) twice."""
    omega_dot_body = d1(motion.omega_body, t, h=2e-3)  # FD of an FD: error ~1e-10
    actual = acceleration_body(
        d2(motion.x_space, t),
        d2(motion.a, t),
        motion.R(t),
        motion.omega_body(t),
        omega_dot_body,
        motion.x_body(t),
        d1(motion.x_body, t),
    )
    np.testing.assert_allclose(actual, d2(motion.x_body, t), atol=1e-6)


def test_memo_sign_convention_of_1_28() -> None:
    """The memo's (1.28) with its ω = -ω_b: ẍ' = D⁻¹ẍ - D⁻¹ä + ω̇ × x' - ω × (ω × x') + 2 ω × ẋ'."""
    motion = default_motion()
    t = 0.37
    R, x, v = motion.R(t), motion.x_body(t), d1(motion.x_body, t)
    omega_memo = -motion.omega_body(t)
    omega_memo_dot = -d1(motion.omega_body, t, h=2e-3)
    memo = (
        (d2(motion.x_space, t) - d2(motion.a, t)) @ R
        + np.cross(omega_memo_dot, x)
        - np.cross(omega_memo, np.cross(omega_memo, x))
        + 2.0 * np.cross(omega_memo, v)
    )
    np.testing.assert_allclose(memo, d2(motion.x_body, t), atol=1e-6)
    ours = acceleration_body(
        d2(motion.x_space, t), d2(motion.a, t), R, -omega_memo, -omega_memo_dot, x, v
    )
    np.testing.assert_allclose(ours, memo, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(motions, times, hnp.arrays(np.float64, 3, elements=st.floats(0.1, 5.0)))
def test_newton_in_moving_frame_with_inertial_forces(motion: Motion, t: float, masses: np.ndarray) -> None:
    """m ẍ' = Rᵀ F_real + (translational + Euler + centrifugal + Coriolis), F_real = m ẍ (4.5)."""
    R = motion.R(t)
    F_real_space = masses[:, None] * d2(motion.x_space, t)
    forces = inertial_force_body(
        masses,
        d2(motion.a, t),
        R,
        motion.omega_body(t),
        d1(motion.omega_body, t, h=2e-3),
        motion.x_body(t),
        d1(motion.x_body, t),
    )
    assert isinstance(forces, InertialForce)
    lhs = masses[:, None] * d2(motion.x_body, t)
    np.testing.assert_allclose(F_real_space @ R + forces.total, lhs, atol=5e-6)
    assert forces.total.shape == (3, 3)
    for field in forces:
        assert field.shape == (3, 3)
    np.testing.assert_allclose(
        forces.total, forces.translational + forces.euler + forces.centrifugal + forces.coriolis
    )


def test_inertial_forces_vectorised_equal_one_particle_at_a_time() -> None:
    motion = default_motion(n_particles=7, seed=3)
    t = -0.2
    masses = np.linspace(0.5, 2.0, 7)
    args = (d2(motion.a, t), motion.R(t), motion.omega_body(t), d1(motion.omega_body, t))
    x, v = motion.x_body(t), d1(motion.x_body, t)
    many = inertial_force_body(masses, *args, x, v)
    for i in range(7):
        one = inertial_force_body(masses[i], *args, x[i], v[i])
        for field_many, field_one in zip(many, one):
            np.testing.assert_allclose(field_many[i], field_one, rtol=1e-15, atol=1e-15)
    # A single particle seen as (3,) gives (3,) fields.
    assert inertial_force_body(1.0, *args, x[0], v[0]).total.shape == (3,)
    with pytest.raises(ValueError):
        inertial_force_body(masses[:3], *args, x, v)


def test_particle_at_rest_on_turntable_feels_only_centrifugal() -> None:
    """R = Rz(Ω t), a = 0, x' fixed: centrifugal force m Ω² r outward, nothing else; the real
    (centripetal) force plus the inertial force vanish, since ẍ' = 0."""
    Omega, mass = 2.5, 0.8
    x_body = np.array([0.6, -0.8, 0.3])  # r = 1 from the axis
    t = 0.9

    def R(s: float) -> np.ndarray:
        return Rotation.from_rotvec([0.0, 0.0, Omega * s]).as_matrix()

    omega_body = vee(R(t).T @ d1(R, t))
    np.testing.assert_allclose(omega_body, [0.0, 0.0, Omega], atol=1e-10)
    forces = inertial_force_body(mass, np.zeros(3), R(t), omega_body, np.zeros(3), x_body, np.zeros(3))
    radial = np.array([x_body[0], x_body[1], 0.0])
    np.testing.assert_allclose(forces.centrifugal, mass * Omega**2 * radial, rtol=1e-9)
    assert np.linalg.norm(forces.centrifugal) == pytest.approx(mass * Omega**2 * 1.0, rel=1e-9)
    for zero in (forces.translational, forces.euler, forces.coriolis):
        np.testing.assert_array_equal(zero, 0.0)
    x_ddot_space = d2(lambda s: R(s) @ x_body, t)  # centripetal acceleration by FD
    np.testing.assert_allclose(mass * x_ddot_space @ R(t) + forces.total, 0.0, atol=1e-8)


@settings(max_examples=100, deadline=None)
@given(
    hnp.arrays(np.float64, 3, elements=st.floats(-5.0, 5.0)),
    hnp.arrays(np.float64, 3, elements=st.floats(-5.0, 5.0)),
    st.floats(0.1, 10.0),
)
def test_coriolis_is_perpendicular_to_velocity_and_omega(omega_body, x_body_dot, mass) -> None:
    forces = inertial_force_body(mass, np.zeros(3), np.eye(3), omega_body, np.zeros(3), np.ones(3), x_body_dot)
    coriolis = forces.coriolis
    w, v = np.linalg.norm(omega_body), np.linalg.norm(x_body_dot)
    assert abs(coriolis @ x_body_dot) <= 1e-12 * (1.0 + mass * w * v * v)
    assert abs(coriolis @ omega_body) <= 1e-12 * (1.0 + mass * w * w * v)
    if w > 1e-3 and v > 1e-3:
        cos_angle = np.clip(omega_body @ x_body_dot / (w * v), -1.0, 1.0)
        expected = 2.0 * mass * w * v * math.sqrt(1.0 - cos_angle**2)
        # sqrt(1 - cos²) carries an absolute error ~sqrt(eps) near parallel vectors.
        assert np.linalg.norm(coriolis) == pytest.approx(expected, rel=1e-9, abs=1e-7 * mass * w * v)


@settings(max_examples=60, deadline=None)
@given(motions, times, st.floats(0.1, 5.0))
def test_kinetic_energy_matches_finite_differences(motion: Motion, t: float, mass: float) -> None:
    """Particle at rest in C' (x' fixed): T (1.25) = ½ m |ẋ|² with ẋ by FD of a + R x'."""
    x_fixed = motion.x_body(0.0)[0]
    x_dot = d1(lambda s: motion.a(s) + motion.R(s) @ x_fixed, t)
    T = kinetic_energy_particle(mass, d1(motion.a, t), motion.R(t), motion.omega_space(t), x_fixed)
    assert isinstance(T, float)
    assert T == pytest.approx(0.5 * mass * x_dot @ x_dot, rel=1e-9, abs=1e-10)
    # The memo's last term with body components: ½ m |ω_b × x'|² = ½ m |ω_s × R x'|².
    a_dot = d1(motion.a, t)
    memo = (
        0.5 * mass * a_dot @ a_dot
        + mass * a_dot @ np.cross(motion.omega_space(t), motion.R(t) @ x_fixed)
        + 0.5 * mass * np.sum(np.cross(motion.omega_body(t), x_fixed) ** 2)
    )
    assert T == pytest.approx(memo, rel=1e-9, abs=1e-10)


def test_kinetic_energy_of_rigid_particles_is_translation_plus_rotation() -> None:
    """Σ T_i (1.25) with a = centre of mass equals ½ M |ȧ|² + ½ ω_b·I_cm ω_b (6.4), and the FD."""
    motion = default_motion(seed=5)
    rng = np.random.default_rng(11)
    masses = rng.uniform(0.2, 2.0, 9)
    x_body = rng.normal(size=(9, 3))
    x_body -= masses @ x_body / masses.sum()  # the origin of C' is the centre of mass
    t = 0.61
    a_dot, R, omega_space = d1(motion.a, t), motion.R(t), motion.omega_space(t)
    T = kinetic_energy_particle(masses, a_dot, R, omega_space, x_body)
    omega_body = motion.omega_body(t)
    I_cm = inertia_tensor_of_particles(masses, x_body)
    expected = 0.5 * masses.sum() * a_dot @ a_dot + 0.5 * omega_body @ I_cm @ omega_body
    assert T == pytest.approx(expected, rel=1e-9)
    velocities = d1(lambda s: motion.a(s) + x_body @ motion.R(s).T, t)
    assert T == pytest.approx(0.5 * np.sum(masses * np.sum(velocities**2, axis=1)), rel=1e-9)


def test_shape_errors() -> None:
    with pytest.raises(ValueError, match="x_body"):
        velocity_space(np.zeros(3), np.eye(3), np.zeros(3), np.zeros((2, 2)), np.zeros(3))
    with pytest.raises(ValueError, match="R_space_body"):
        acceleration_body(np.zeros(3), np.zeros(3), np.eye(2), np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="omega_space"):
        kinetic_energy_particle(1.0, np.zeros(3), np.eye(3), np.zeros(2), np.zeros(3))


def test_accelerations_act_for_accel_seconds_then_the_rates_hold() -> None:
    """A turntable sped up for T = 4 s: before T the same motion as with no limit (bit for bit);
    after T the rates stay rates + accels T (ω̇_b that of constant rates), and angle, rate and pose
    are continuous at T."""
    kwargs = dict(angles0=(0.1, 0.4, -0.2), rates=(0.3, 0.0, 0.5), accels=(0.2, 0.0, -0.1))
    held = FrameMotion(accel_seconds=4.0, **kwargs)  # type: ignore[arg-type]
    free = FrameMotion(**kwargs)  # type: ignore[arg-type]
    for t in (0.0, 1.3, 4.0):
        a, b = held.at(t), free.at(t)
        assert np.array_equal(a.R_space_body, b.R_space_body) and np.array_equal(a.omega_dot_body, b.omega_dot_body)
    np.testing.assert_allclose(held.angle_rates(9.0), np.array(kwargs["rates"]) + 4.0 * np.array(kwargs["accels"]),
                               atol=1e-15)
    h = 1e-4  # ω̇_b after T is that of constant rates: a central difference of ω_b (error ~h² ω⃛ ≈ 1e-9)
    difference = (held.at(9.0 + h).omega_body - held.at(9.0 - h).omega_body) / (2.0 * h)
    np.testing.assert_allclose(held.at(9.0).omega_dot_body, difference, atol=1e-7)
    eps = 1e-9
    np.testing.assert_allclose(held.at(4.0 + eps).R_space_body, held.at(4.0).R_space_body, atol=1e-8)
    np.testing.assert_allclose(held.at(4.0 + eps).omega_body, held.at(4.0).omega_body, atol=1e-8)
    np.testing.assert_allclose(held.angles(9.0), held.angles(4.0) + 5.0 * held.angle_rates(9.0), atol=1e-12)
    with pytest.raises(ValueError, match="accel_seconds"):
        FrameMotion(accel_seconds=0.0)
