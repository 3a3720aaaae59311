"""Tests of physics.euler: z-x-z angles, their singularities, frames and angular velocity.

Independent references: scipy.spatial.transform.Rotation (matrices, as_euler, magnitudes),
scipy.linalg.expm, the closed forms of docs/CONVENTIONS.md, and finite differences of R(t).

Tolerances, all visible below:
* MATRIX_TOL = 4e-15 (absolute on rotation matrices): matrix products vs scipy, and
  R recovered from the angles; measured worst 1.0e-15, within 1e-12 of the poles included.
* FD_TOL = 1e-10 [rad/s] for ω from the 5-point central difference of R(t) with step
  h = 2e-4 / (1 + |rates|₁): truncation h⁴ |R⁽⁵⁾| / 30 ≈ 5e-14, rounding ≈ 1.5 ε / h ≈ 1e-12,
  both times (1 + |rates|₁); the tolerance is FD_TOL (1 + |rates|₁).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from physics.euler import (
    EulerFrames,
    GimbalLockError,
    body_z_axis,
    euler_frames,
    euler_rates_from_omega_body,
    euler_zxz_from_matrix,
    euler_zxz_from_matrix_near,
    line_of_nodes,
    matrix_from_euler_zxz,
    memo_omega_from_euler_rates,
    omega_body_from_euler_rates,
    omega_space_from_euler_rates,
    wrap_angle,
)
from physics.so3 import A1, A3, hat, vee

EPS = np.finfo(float).eps
MATRIX_TOL = 4e-15
FD_TOL = 1e-10
RX_PI = np.diag([1.0, -1.0, -1.0])  # Rx(π) exactly; rot_x(math.pi) has sin = 1.2e-16, not 0

SETTINGS = settings(max_examples=150, deadline=None)

# --- strategies and references -----------------------------------------------------------

angles = st.floats(-math.pi, math.pi)
thetas = st.floats(0.0, math.pi)
NEAR_POLE_THETAS = [
    0.0, 1e-12, 1e-9, 1e-6, math.pi - 1e-6, math.pi - 1e-9, math.pi - 1e-12, math.pi,
]  # fmt: skip
thetas_with_poles = st.one_of(thetas, st.sampled_from(NEAR_POLE_THETAS))
thetas_away = st.floats(0.01, math.pi - 0.01)  # away from gimbal lock
rates_st = st.tuples(*[st.floats(-2.0, 2.0)] * 3).map(np.array)


def R_scipy(phi: float, theta: float, psi: float) -> np.ndarray:
    """The reference rotation: SciPy's intrinsic z-x'-z''."""
    return Rotation.from_euler("ZXZ", [phi, theta, psi]).as_matrix()


def Rz(angle: float) -> np.ndarray:
    return Rotation.from_euler("z", angle).as_matrix()


def Rx(angle: float) -> np.ndarray:
    return Rotation.from_euler("x", angle).as_matrix()


def max_err(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


def angle_diff(a: float, b: float) -> float:
    """|a - b| modulo 2π, independent of wrap_angle."""
    return abs(float(np.angle(np.exp(1j * (a - b)))))


def fd_derivative(f: Callable[[float], np.ndarray], h: float) -> np.ndarray:
    """df/dt at t = 0 by the 5-point central difference, error O(h⁴)."""
    return (-f(2 * h) + 8 * f(h) - 8 * f(-h) + f(-2 * h)) / (12 * h)


def R_and_Rdot(euler: np.ndarray, rates: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """R, Ṙ at t = 0 along (φ, θ, ψ) + t (φ̇, θ̇, ψ̇), with the FD tolerance for this motion."""
    scale = 1.0 + float(np.sum(np.abs(rates)))
    h = 2e-4 / scale
    Rdot = fd_derivative(lambda t: R_scipy(*(euler + t * rates)), h)
    return R_scipy(*euler), Rdot, FD_TOL * scale


# --- matrix_from_euler_zxz ---------------------------------------------------------------


@SETTINGS
@given(angles, thetas_with_poles, angles)
def test_matrix_matches_scipy_intrinsic_ZXZ_and_memo_1_13(
    phi: float, theta: float, psi: float
) -> None:
    R = matrix_from_euler_zxz(phi, theta, psi)
    assert max_err(R, R_scipy(phi, theta, psi)) <= MATRIX_TOL
    # (1.13): D = exp(φ A3) exp(θ A1) exp(ψ A3) with expm as the exponential.
    assert max_err(R, expm(phi * A3) @ expm(theta * A1) @ expm(psi * A3)) <= 1e-14
    assert max_err(R.T @ R, np.eye(3)) <= MATRIX_TOL


def test_matrix_hand_checked() -> None:
    # φ = θ = 90°, ψ = 0: the body z' axis is the space x axis, the body x' axis is space y.
    R = matrix_from_euler_zxz(0.5 * math.pi, 0.5 * math.pi, 0.0)
    np.testing.assert_allclose(R, [[0, 0, 1], [1, 0, 0], [0, 1, 0]], rtol=0, atol=2 * EPS)
    np.testing.assert_allclose(body_z_axis(0.5 * math.pi, 0.5 * math.pi), [1, 0, 0], atol=2 * EPS)


def test_lowercase_zxz_is_a_different_rotation() -> None:
    """Documentation: SciPy's lower-case "zxz" (extrinsic) is not our convention; it is the
    intrinsic one with φ and ψ exchanged."""
    phi, theta, psi = 0.3, 0.7, 1.1
    R = matrix_from_euler_zxz(phi, theta, psi)
    assert max_err(R, Rotation.from_euler("zxz", [phi, theta, psi]).as_matrix()) > 0.1
    assert max_err(R, Rotation.from_euler("zxz", [psi, theta, phi]).as_matrix()) <= MATRIX_TOL


# --- euler_zxz_from_matrix ---------------------------------------------------------------


@settings(max_examples=300, deadline=None)
@given(angles, thetas_with_poles, angles)
@example(0.3, 0.0, 0.5)
@example(0.3, math.pi, 0.5)
@example(math.pi, 1e-12, -math.pi)
def test_euler_from_matrix_recovers_R_everywhere(phi: float, theta: float, psi: float) -> None:
    R = R_scipy(phi, theta, psi)
    a = euler_zxz_from_matrix(R)
    assert a.shape == (3,) and np.all(np.isfinite(a))
    assert -math.pi < a[0] <= math.pi and -math.pi < a[2] <= math.pi
    assert 0.0 <= a[1] <= math.pi
    assert max_err(matrix_from_euler_zxz(*a), R) <= MATRIX_TOL
    # θ is well conditioned everywhere (it is the angle between e_z and e_z').
    assert abs(a[1] - theta) <= 4e-15


@SETTINGS
@given(angles, angles)
def test_euler_from_matrix_branch_at_exact_poles(phi: float, psi: float) -> None:
    """At sin θ == 0 exactly, the documented branch ψ = 0 holds and φ carries φ ± ψ."""
    R0 = Rz(phi) @ Rz(psi)  # θ = 0: R02 = R12 = 0 exactly
    a = euler_zxz_from_matrix(R0)
    assert a[1] == 0.0 and a[2] == 0.0
    assert angle_diff(a[0], phi + psi) <= 4 * EPS
    assert max_err(matrix_from_euler_zxz(*a), R0) <= MATRIX_TOL

    Rpi = Rz(phi) @ RX_PI @ Rz(psi)  # θ = π exactly
    a = euler_zxz_from_matrix(Rpi)
    assert a[1] == math.pi and a[2] == 0.0
    assert angle_diff(a[0], phi - psi) <= 4 * EPS
    assert max_err(matrix_from_euler_zxz(*a), Rpi) <= MATRIX_TOL


def test_euler_from_matrix_at_float_pi_is_not_the_exact_pole() -> None:
    """Documentation: rot_x(math.pi) has sin(math.pi) = 1.2e-16, so the matrix is just off
    the pole and the general branch returns the given φ, ψ (still recovering R)."""
    R = matrix_from_euler_zxz(0.3, math.pi, 0.5)
    a = euler_zxz_from_matrix(R)
    np.testing.assert_allclose(a, [0.3, math.pi, 0.5], rtol=0, atol=1e-15)
    a = euler_zxz_from_matrix(RX_PI)
    np.testing.assert_array_equal(a, [0.0, math.pi, 0.0])


@SETTINGS
@given(angles, thetas_away, angles)
def test_euler_from_matrix_agrees_with_scipy_away_from_poles(
    phi: float, theta: float, psi: float
) -> None:
    R = R_scipy(phi, theta, psi)
    ours = euler_zxz_from_matrix(R)
    ref = Rotation.from_matrix(R).as_euler("ZXZ")
    # φ and ψ are conditioned as 1/sin θ <= 100 here.
    tol = 1e-14 / math.sin(theta)
    assert abs(ours[1] - ref[1]) <= tol
    assert angle_diff(ours[0], ref[0]) <= tol
    assert angle_diff(ours[2], ref[2]) <= tol
    # and with the generating angles
    assert angle_diff(ours[0], phi) <= tol and angle_diff(ours[2], psi) <= tol


# --- euler_zxz_from_matrix_near along trajectories ---------------------------------------


def _follow(Rs: Sequence[np.ndarray], dt: float, omega_max: float) -> np.ndarray:
    """Runs euler_zxz_from_matrix_near along Rs and checks every sample; returns the angles.

    Bounds from ω: ω_s3 + ω_b3 = (φ̇ + ψ̇)(1 + cos θ) and ω_s3 - ω_b3 = (φ̇ - ψ̇)(1 - cos θ), so
    |φ̇ + ψ̇| <= 2|ω| where cos θ >= 0 and |φ̇ - ψ̇| <= 2|ω| where cos θ <= 0.  Where sin θ >= s,
    |φ̇| <= |ω| / s and |ψ̇| <= |ω| (1 + 1/s).
    """
    out = [euler_zxz_from_matrix(Rs[0])]
    step_bound = 2.0 * omega_max * dt * (1.0 + 1e-9) + 1e-13
    for R in Rs[1:]:
        prev = out[-1]
        a = euler_zxz_from_matrix_near(R, prev)
        assert np.all(np.isfinite(a))
        assert 0.0 <= a[1] <= math.pi
        assert max_err(matrix_from_euler_zxz(*a), R) <= 1e-14
        both_upper = math.cos(prev[1]) >= 0.0 and math.cos(a[1]) >= 0.0
        both_lower = math.cos(prev[1]) <= 0.0 and math.cos(a[1]) <= 0.0
        if both_upper:
            assert abs((a[0] + a[2]) - (prev[0] + prev[2])) <= step_bound
        if both_lower:
            assert abs((a[0] - a[2]) - (prev[0] - prev[2])) <= step_bound
        s = min(math.sin(prev[1]), math.sin(a[1])) - omega_max * dt  # sin θ on the step
        if s >= 0.3:
            assert abs(a[0] - prev[0]) <= omega_max * dt / s * (1 + 1e-9) + 1e-13
            assert abs(a[2] - prev[2]) <= omega_max * dt * (1 + 1 / s) * (1 + 1e-9) + 1e-13
        out.append(a)
    return np.array(out)


def test_near_follows_trajectory_through_theta_zero() -> None:
    """R(t) = Rz(0.3 t) Rx(t): rotation about the horizontal line of nodes through the pole,
    θ(t) = |t| crosses 0 exactly at the middle sample. |ω| = sqrt(0.3² + 1)."""
    dt = 1e-3
    t = dt * np.arange(-1000, 1001)
    Rs = [Rz(0.3 * tk) @ Rx(tk) for tk in t]
    a = _follow(Rs, dt, math.hypot(0.3, 1.0))
    assert a[1000, 1] == 0.0  # the exact pole was sampled
    # φ alone flips by π across the pole (the line of nodes reverses): that is allowed and
    # shows the test really crossed it; φ + ψ stayed continuous (checked in _follow).
    assert abs(abs(a[1001, 0] - a[999, 0]) - math.pi) < 0.01


def test_near_follows_trajectory_through_theta_pi() -> None:
    """R(t) = Rz(0.3 t) Rx(π + t), with Rx(π) exact: θ = π - |t| crosses π at t = 0."""
    dt = 1e-3
    t = dt * np.arange(-1000, 1001)
    Rs = [Rz(0.3 * tk) @ RX_PI @ Rx(tk) for tk in t]
    a = _follow(Rs, dt, math.hypot(0.3, 1.0))
    assert a[1000, 1] == math.pi
    assert abs(abs(a[1001, 0] - a[999, 0]) - math.pi) < 0.01


def test_near_follows_a_tumbling_spinning_body_through_both_poles() -> None:
    """R(t) = exp(t hat(u)) Rz(0.7 t), u horizontal: the body z' axis passes through θ = 0
    (at t = 0) and θ = π (t = π) and crosses the equator; |ω| <= 1 + 0.7."""
    u = np.array([math.cos(0.4), math.sin(0.4), 0.0])
    dt = 1e-3
    t = dt * np.arange(-1000, 7001)
    Rs = [
        (Rotation.from_rotvec(tk * u) * Rotation.from_euler("z", 0.7 * tk)).as_matrix() for tk in t
    ]
    a = _follow(Rs, dt, 1.7)
    assert a[:, 1].min() == 0.0 and a[:, 1].max() > math.pi - 1e-3


@SETTINGS
@given(angles, thetas_away, angles, st.integers(-3, 3), st.integers(-3, 3))
def test_near_returns_the_branch_nearest_previous(
    phi: float, theta: float, psi: float, k_phi: int, k_psi: int
) -> None:
    previous = np.array([phi + 2 * math.pi * k_phi, theta, psi + 2 * math.pi * k_psi])
    a = euler_zxz_from_matrix_near(R_scipy(phi, theta, psi), previous)
    np.testing.assert_allclose(a, previous, rtol=0, atol=1e-13 / math.sin(theta))


def test_near_at_exact_pole_keeps_previous_phi() -> None:
    previous = np.array([0.2 + 4 * math.pi, 1e-3, -0.1])
    R = Rz(0.25)  # θ = 0 exactly, φ + ψ = 0.25
    a = euler_zxz_from_matrix_near(R, previous)
    assert a[0] == previous[0] and a[1] == 0.0
    assert abs((a[0] + a[2]) - (previous[0] + previous[2]) - 0.15) <= 1e-14
    assert max_err(matrix_from_euler_zxz(*a), R) <= 1e-14


# --- line of nodes, body axis, frames ----------------------------------------------------


@SETTINGS
@given(angles, thetas_with_poles, angles)
def test_line_of_nodes_is_the_axis_of_the_theta_factor(
    phi: float, theta: float, psi: float
) -> None:
    e_n = line_of_nodes(phi)
    frames = euler_frames(phi, theta, psi)
    assert max_err(e_n, frames.after_phi[:, 0]) <= 2 * EPS
    assert max_err(e_n, Rz(phi)[:, 0]) <= 2 * EPS
    R = R_scipy(phi, theta, psi)
    e_z_body = R[:, 2]
    assert e_n[2] == 0.0  # ⟂ e_z, exactly
    assert abs(e_n @ e_z_body) <= 4 * EPS
    # e_z × e_z' = sin θ e_n
    assert max_err(np.cross([0.0, 0.0, 1.0], e_z_body), math.sin(theta) * e_n) <= 4 * EPS
    # R = exp(θ hat(e_n)) Rz(φ) Rz(ψ): the θ rotation turns about e_n.
    assert max_err(R, expm(theta * hat(e_n)) @ Rz(phi) @ Rz(psi)) <= 1e-14


@SETTINGS
@given(angles, thetas_with_poles, angles)
def test_body_z_axis_is_third_column(phi: float, theta: float, psi: float) -> None:
    assert max_err(body_z_axis(phi, theta), R_scipy(phi, theta, psi)[:, 2]) <= 4 * EPS


@SETTINGS
@given(angles, thetas_with_poles, angles)
def test_euler_frames_chain(phi: float, theta: float, psi: float) -> None:
    f = euler_frames(phi, theta, psi)
    assert isinstance(f, EulerFrames)
    np.testing.assert_array_equal(f.space, np.eye(3))
    assert max_err(f.after_phi, Rz(phi)) <= MATRIX_TOL
    assert max_err(f.after_theta, Rz(phi) @ Rx(theta)) <= MATRIX_TOL
    assert max_err(f.body, R_scipy(phi, theta, psi)) <= MATRIX_TOL
    # Rx(θ) keeps the x axis (the line of nodes); Rz(ψ) keeps the z axis (body z').
    assert max_err(f.after_theta[:, 0], f.after_phi[:, 0]) <= 2 * EPS
    assert max_err(f.body[:, 2], f.after_theta[:, 2]) <= 2 * EPS


# --- angular velocity --------------------------------------------------------------------


@SETTINGS
@given(angles, thetas_with_poles, angles, rates_st)
def test_omega_from_euler_rates_against_finite_differences(
    phi: float, theta: float, psi: float, rates: np.ndarray
) -> None:
    euler = np.array([phi, theta, psi])
    R, Rdot, tol = R_and_Rdot(euler, rates)
    W_space, W_body = Rdot @ R.T, R.T @ Rdot
    assert max_err(W_space, -W_space.T) <= 2 * tol  # Ṙ Rᵀ is skew: the FD is sound
    omega_space = omega_space_from_euler_rates(euler, rates)
    omega_body = omega_body_from_euler_rates(euler, rates)
    assert max_err(omega_space, vee(W_space)) <= tol
    assert max_err(omega_body, vee(W_body)) <= tol
    assert max_err(omega_space, R @ omega_body) <= 1e-14 * (1 + np.abs(rates).sum())
    # (1.17): ω_s = φ̇ e_z + θ̇ e_n + ψ̇ e_z' with e_n, e_z' from scipy.
    dphi, dtheta, dpsi = rates
    expected = dphi * np.array([0.0, 0.0, 1.0]) + dtheta * Rz(phi)[:, 0] + dpsi * R[:, 2]
    assert max_err(omega_space, expected) <= 1e-14 * (1 + np.abs(rates).sum())


def test_omega_hand_checked() -> None:
    # Pure spin ψ̇ = 2 at θ = 0: ω = 2 e_z in both frames.
    spin = np.array([0.0, 0.0, 2.0])
    np.testing.assert_allclose(omega_space_from_euler_rates(np.zeros(3), spin), [0, 0, 2])
    np.testing.assert_allclose(omega_body_from_euler_rates(np.zeros(3), spin), [0, 0, 2])
    # Nutation θ̇ = 1 at φ = 90°: rotation about the line of nodes e_n = e_y.
    w = omega_space_from_euler_rates(np.array([0.5 * math.pi, 0.3, 0.0]), np.array([0, 1.0, 0]))
    np.testing.assert_allclose(w, [0, 1, 0], atol=2 * EPS)


@SETTINGS
@given(angles, thetas_away, angles, rates_st)
def test_euler_rates_invert_omega_body(
    phi: float, theta: float, psi: float, rates: np.ndarray
) -> None:
    euler = np.array([phi, theta, psi])
    back = euler_rates_from_omega_body(euler, omega_body_from_euler_rates(euler, rates))
    # conditioning 1/sin θ
    np.testing.assert_allclose(back, rates, rtol=0, atol=2e-14 / math.sin(theta))


@SETTINGS
@given(angles, thetas_away, angles, st.tuples(*[st.floats(-1.0, 1.0)] * 3).map(np.array))
def test_euler_rates_from_omega_body_reproduce_omega_by_finite_differences(
    phi: float, theta: float, psi: float, omega_body: np.ndarray
) -> None:
    euler = np.array([phi, theta, psi])
    rates = euler_rates_from_omega_body(euler, omega_body)
    R, Rdot, tol = R_and_Rdot(euler, rates)
    assert max_err(vee(R.T @ Rdot), omega_body) <= tol


@pytest.mark.parametrize(
    ("theta", "defined"),
    [
        (0.0, r"φ \+ ψ"),
        (1e-12, r"φ \+ ψ"),
        (-1e-12, r"φ \+ ψ"),
        (math.pi, r"φ [-−] ψ"),
        (math.pi - 1e-12, r"φ [-−] ψ"),
        (math.pi + 1e-12, r"φ [-−] ψ"),
    ],
)
def test_euler_rates_raise_gimbal_lock(theta: float, defined: str) -> None:
    with pytest.raises(GimbalLockError) as info:
        euler_rates_from_omega_body(np.array([0.2, theta, -0.4]), np.array([0.1, 0.2, 0.3]))
    assert isinstance(info.value, ValueError)
    assert re.search(defined, str(info.value)), str(info.value)


def test_euler_rates_just_outside_the_lock_threshold_are_finite() -> None:
    rates = euler_rates_from_omega_body(np.array([0.2, 1e-8, -0.4]), np.array([0.1, 0.2, 0.3]))
    assert np.all(np.isfinite(rates))
    with pytest.raises(GimbalLockError):
        euler_rates_from_omega_body(np.array([0.2, 1e-3, -0.4]), np.ones(3), min_sin_theta=1e-2)


# --- the memo's sign conventions ---------------------------------------------------------


@SETTINGS
@given(angles, thetas_with_poles, angles, rates_st)
def test_memo_omega_is_minus_omega_body(
    phi: float, theta: float, psi: float, rates: np.ndarray
) -> None:
    euler = np.array([phi, theta, psi])
    memo = memo_omega_from_euler_rates(euler, rates)
    R, Rdot, tol = R_and_Rdot(euler, rates)
    # (1.21): hat(ω_memo) = (R⁻¹)˙ R = Ṙᵀ R, by finite differences.
    assert max_err(memo, vee(Rdot.T @ R)) <= tol
    # = -ω_b, with ω_b written out from docs/CONVENTIONS.md.
    dphi, dtheta, dpsi = rates
    st_, ct, ss, cs = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    omega_b = [dphi * st_ * ss + dtheta * cs, dphi * st_ * cs - dtheta * ss, dphi * ct + dpsi]
    assert max_err(memo, -np.array(omega_b)) <= 1e-14 * (1 + np.abs(rates).sum())
    # (1.23): R⁻¹ ω' = -ω, ω' = ω_s.
    omega_space = omega_space_from_euler_rates(euler, rates)
    assert max_err(R.T @ omega_space, -memo) <= 1e-14 * (1 + np.abs(rates).sum())


@SETTINGS
@given(angles, thetas_with_poles, angles)
def test_memo_1_20_substitution_transposes_R(phi: float, theta: float, psi: float) -> None:
    """φ → -ψ, θ → -θ, ψ → -φ takes D into D⁻¹ = Dᵀ."""
    R_inverse = matrix_from_euler_zxz(-psi, -theta, -phi)
    assert max_err(R_inverse, R_scipy(phi, theta, psi).T) <= MATRIX_TOL


# --- wrap_angle --------------------------------------------------------------------------


@SETTINGS
@given(st.floats(-1e3, 1e3))
@example(math.pi)
@example(-math.pi)
@example(3 * math.pi)
@example(-3 * math.pi)
def test_wrap_angle_range_and_congruence(angle: float) -> None:
    w = wrap_angle(angle)
    assert -math.pi < w <= math.pi
    turns = (angle - w) / (2 * math.pi)
    assert abs(turns - round(turns)) <= 1e-12
    if -math.pi < angle <= math.pi:
        assert w == angle


def test_wrap_angle_hand_checked() -> None:
    assert wrap_angle(math.pi) == math.pi
    assert wrap_angle(-math.pi) == math.pi
    assert wrap_angle(0.0) == 0.0
    assert wrap_angle(0.5) == 0.5
    assert abs(wrap_angle(2 * math.pi + 0.5) - 0.5) <= 1e-15
    assert abs(wrap_angle(-0.5 - 2 * math.pi) + 0.5) <= 1e-15
    assert abs(wrap_angle(1.5 * math.pi) + 0.5 * math.pi) <= 1e-15
