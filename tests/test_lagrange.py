"""Lagrange's equations (memo §5-6) in physics.lagrange, against independent derivations.

References used (none of them the formula under test): finite differences of R(q) built by
SciPy's Rotation.from_euler("ZXZ"), Euler's equations (physics.dynamics.omega_body_dot), a
hand-differentiated ω̇_b(q, q̇, q̈), hand-derived equations of small systems, closed-form
rotations, and scipy solve_ivp DOP853 at rtol 1e-12 on Ṙ = R hat(ω_b) + Euler's equations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

from physics.dynamics import IntegrationError, Model, State, energy, omega_body_dot
from physics.euler import GimbalLockError, euler_rates_from_omega_body, omega_body_from_euler_rates
from physics.lagrange import (
    SIN_THETA_STOP,
    EulerLagrangeSingularityError,
    LagrangianSystem,
    euler_accelerations,
    generalized_forces,
    integrate_euler_lagrange,
    mass_matrix,
    mass_matrix_derivatives,
    mass_matrix_derivatives_fd,
    rigid_body_system,
)

SETTINGS = settings(max_examples=60, deadline=None)
angle = st.floats(-math.pi, math.pi)
nutation = st.floats(math.asin(0.1), math.pi - math.asin(0.1))  # sin θ >= 0.1
rate = st.floats(-3.0, 3.0)
seeds = st.integers(0, 2**32 - 1)


def R_scipy(q: np.ndarray) -> np.ndarray:
    """Independent R(q) = Rz(φ) Rx(θ) Rz(ψ): SciPy's intrinsic "ZXZ"."""
    return Rotation.from_euler("ZXZ", q).as_matrix()


def vee(A: np.ndarray) -> np.ndarray:
    return 0.5 * np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]])


def R_dot_fd(q: np.ndarray, qdot: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """d/dt R(q + t q̇) at t = 0 by central differences (error ~h² + 1e-16/h ≈ 1e-10)."""
    return (R_scipy(q + h * qdot) - R_scipy(q - h * qdot)) / (2.0 * h)


def random_inertia(rng: np.random.Generator) -> np.ndarray:
    """Principal moments that satisfy the triangle inequalities."""
    while True:
        moments = rng.uniform(0.3, 3.0, 3)
        if all(moments[k] + moments[(k + 1) % 3] > moments[(k + 2) % 3] for k in range(3)):
            return moments


MODELS = {
    "free_asymmetric": Model((1.0, 2.0, 2.5)),
    "heavy_top_symmetric": Model((1.5, 1.5, 0.8), mgl=2.0),
    "heavy_top_asymmetric": Model((1.2, 1.7, 0.9), mgl=1.3),
    "constant_torque": Model((0.7, 1.1, 1.4), torque_space=(0.3, -0.8, 0.5)),
    "hook_damping": Model(
        (1.0, 2.0, 2.5), extra_torque=lambda t, R, w: -0.4 * (R @ w) + np.array([0.0, math.sin(t), 0.0])
    ),
}


# ---------------------------------------------------------------- generalized forces (6.10)


@SETTINGS
@given(angle, st.floats(0.05, math.pi - 0.05), angle, seeds)
def test_generalized_forces_equal_virtual_work_of_torque(phi, theta, psi, seed):
    """Q_j = M · ω_s(δq_j): ω_s of a unit rate in q_j alone, from FD of SciPy's R(q)."""
    rng = np.random.default_rng(seed)
    q = np.array([phi, theta, psi])
    torque = rng.normal(size=3) * 2.0
    R = R_scipy(q)
    expected = np.array([torque @ vee(R_dot_fd(q, np.eye(3)[j]) @ R.T) for j in range(3)])
    atol = 1e-9 * (1 + np.linalg.norm(torque))
    np.testing.assert_allclose(generalized_forces(q, torque), expected, rtol=0, atol=atol)


@SETTINGS
@given(angle, st.floats(0.05, math.pi - 0.05), angle, seeds)
def test_virtual_work_of_small_rotation(phi, theta, psi, seed):
    """Σ Q_j δq_j = M · δθ_vec, δθ_vec the rotation vector of R(q + δq) R(q)ᵀ (error O(|δq|²))."""
    rng = np.random.default_rng(seed)
    q = np.array([phi, theta, psi])
    torque = rng.normal(size=3)
    dq = rng.normal(size=3) * 1e-6
    dtheta_vec = Rotation.from_matrix(R_scipy(q + dq) @ R_scipy(q).T).as_rotvec()
    lhs = generalized_forces(q, torque) @ dq
    assert abs(lhs - torque @ dtheta_vec) <= 1e-14 + 1e-4 * np.linalg.norm(torque) * np.linalg.norm(dq)


# ---------------------------------------------------------------- mass matrix (6.4)


@SETTINGS
@given(angle, st.floats(0.05, math.pi - 0.05), angle, rate, rate, rate, seeds)
def test_quadratic_form_equals_rotational_kinetic_energy(phi, theta, psi, dphi, dtheta, dpsi, seed):
    """½ q̇ᵀ M q̇ == ½ ω_bᵀ I ω_b with hat(ω_b) = Rᵀ Ṙ, Ṙ by FD of R(q(t)) along q̇."""
    inertia = random_inertia(np.random.default_rng(seed))
    q, qdot = np.array([phi, theta, psi]), np.array([dphi, dtheta, dpsi])
    omega_b = vee(R_scipy(q).T @ R_dot_fd(q, qdot))
    expected = 0.5 * float(omega_b @ (inertia * omega_b))
    actual = 0.5 * float(qdot @ mass_matrix(q, inertia) @ qdot)
    assert abs(actual - expected) <= 1e-9 * (1.0 + float(inertia.sum() * qdot @ qdot))


@SETTINGS
@given(angle, st.floats(0.05, math.pi - 0.05), angle, seeds)
def test_mass_matrix_is_J_transpose_I_J_with_fd_jacobian(phi, theta, psi, seed):
    """Whole matrix: columns of J are ω_b of unit rates (FD of SciPy's R); and det M."""
    inertia = random_inertia(np.random.default_rng(seed))
    q = np.array([phi, theta, psi])
    R = R_scipy(q)
    J = np.column_stack([vee(R.T @ R_dot_fd(q, e)) for e in np.eye(3)])
    M = mass_matrix(q, inertia)
    np.testing.assert_allclose(M, J.T @ np.diag(inertia) @ J, rtol=0, atol=1e-9 * inertia.sum())
    np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-15)
    assert np.linalg.det(M) == pytest.approx(np.prod(inertia) * math.sin(theta) ** 2, rel=1e-9, abs=1e-14)


@SETTINGS
@given(angle, st.floats(-math.pi, math.pi), angle, seeds)
def test_analytic_mass_matrix_derivatives_match_finite_differences(phi, theta, psi, seed):
    inertia = random_inertia(np.random.default_rng(seed))
    q = np.array([phi, theta, psi])
    h = 1e-6
    expected = np.array(
        [(mass_matrix(q + h * e, inertia, 0.0) - mass_matrix(q - h * e, inertia, 0.0)) / (2 * h) for e in np.eye(3)]
    )
    np.testing.assert_allclose(mass_matrix_derivatives(q, inertia), expected, rtol=0, atol=1e-8 * inertia.sum())


@pytest.mark.parametrize("theta", [0.0, math.pi, 1e-9, math.pi - 1e-9, -1e-8, float("nan")])
def test_gimbal_lock_is_refused_with_a_message(theta):
    q = np.array([0.3, theta, -0.2])
    with pytest.raises(GimbalLockError, match="singular at θ"):
        mass_matrix(q, (1.0, 2.0, 2.5))
    with pytest.raises(GimbalLockError, match="singular at θ"):
        euler_accelerations(Model((1.0, 2.0, 2.5)), 0.0, q, np.array([1.0, 0.5, 0.2]))


def test_just_above_threshold_is_finite():
    q = np.array([0.3, 2e-6, -0.2])  # sin θ = 2e-6 > MIN_SIN_THETA = 1e-6
    qddot = euler_accelerations(Model((1.0, 2.0, 2.5)), 0.0, q, np.array([1.0, 0.5, 0.2]))
    assert np.all(np.isfinite(qddot))


# ---------------------------------------------------------------- accelerations vs Euler's equations


def omega_body_dot_from_euler(q: np.ndarray, qdot: np.ndarray, qddot: np.ndarray) -> np.ndarray:
    """d/dt of ω_b = (φ̇ sθ sψ + θ̇ cψ, φ̇ sθ cψ - θ̇ sψ, φ̇ cθ + ψ̇), differentiated by hand."""
    _, th, ps = q
    dph, dth, dps = qdot
    ddph, ddth, ddps = qddot
    st_, ct, ss, cs = math.sin(th), math.cos(th), math.sin(ps), math.cos(ps)
    return np.array([
        ddph * st_ * ss + dph * (ct * dth * ss + st_ * cs * dps) + ddth * cs - dth * ss * dps,
        ddph * st_ * cs + dph * (ct * dth * cs - st_ * ss * dps) - ddth * ss - dth * cs * dps,
        ddph * ct - dph * st_ * dth + ddps,
    ])


def euler_state(phi, theta, psi, seed):
    rng = np.random.default_rng(seed)
    q = np.array([phi, theta, psi])
    return q, R_scipy(q), rng.normal(size=3) * 1.5, rng.uniform(0.0, 10.0)


@pytest.mark.parametrize("name", sorted(MODELS))
@settings(max_examples=40, deadline=None)
@given(phi=angle, theta=nutation, psi=angle, seed=seeds)
def test_lagrange_angular_acceleration_equals_euler_equations(name, phi, theta, psi, seed):
    """ω̇_b implied by q̈ (hand-differentiated ω_b(q, q̇)) == omega_body_dot, to 1e-10 relative."""
    model = MODELS[name]
    q, R, omega_b, t = euler_state(phi, theta, psi, seed)
    qdot = euler_rates_from_omega_body(q, omega_b)
    qddot = euler_accelerations(model, t, q, qdot)
    expected = omega_body_dot(model, t, R, omega_b)
    scale = np.linalg.norm(omega_b) ** 2 + np.linalg.norm(model.torque_space_at(t, R, omega_b)) / min(model.inertia)
    np.testing.assert_allclose(omega_body_dot_from_euler(q, qdot, qddot), expected, rtol=0, atol=1e-10 * (1 + scale))


@pytest.mark.parametrize("name", sorted(MODELS))
@settings(max_examples=40, deadline=None)
@given(phi=angle, theta=nutation, psi=angle, seed=seeds)
def test_lagrange_euler_angle_accelerations_equal_fd_conversion(name, phi, theta, psi, seed):
    """q̈ == J⁻¹(ω̇_b - J̇ q̇), ω̇_b from Euler's equations, J̇ q̇ by FD of omega_body_from_euler_rates."""
    model = MODELS[name]
    q, R, omega_b, t = euler_state(phi, theta, psi, seed)
    qdot = euler_rates_from_omega_body(q, omega_b)
    h = 1e-5
    w_plus, w_minus = omega_body_from_euler_rates(q + h * qdot, qdot), omega_body_from_euler_rates(q - h * qdot, qdot)
    Jdot_qdot = (w_plus - w_minus) / (2 * h)
    expected = euler_rates_from_omega_body(q, omega_body_dot(model, t, R, omega_b) - Jdot_qdot)
    for derivatives in ("analytic", "fd"):
        qddot = euler_accelerations(model, t, q, qdot, derivatives=derivatives)
        np.testing.assert_allclose(qddot, expected, rtol=0, atol=1e-7 * (1 + np.linalg.norm(expected)))


# ---------------------------------------------------------------- generic solver (5.13)

G = 9.81


def test_spherical_pendulum_fd_solver_matches_hand_derived_equations():
    """T = ½ m l² (θ̇² + sin²θ φ̇²), V = -m g l cos θ (θ from the downward vertical):
    θ̈ = sin θ cos θ φ̇² - (g/l) sin θ,  φ̈ = -2 cot θ θ̇ φ̇."""
    m, l = 1.3, 0.8
    system = LagrangianSystem(
        mass_matrix=lambda q: m * l**2 * np.diag([1.0, math.sin(q[0]) ** 2]),
        generalized_forces=lambda t, q, qd: np.array([-m * G * l * math.sin(q[0]), 0.0]),
    )
    rng = np.random.default_rng(1)
    for _ in range(50):
        q = np.array([rng.uniform(0.2, math.pi - 0.2), rng.uniform(-3, 3)])
        qd = rng.normal(size=2) * 2
        th = q[0]
        expected = np.array([math.sin(th) * math.cos(th) * qd[1] ** 2 - G / l * math.sin(th),
                             -2.0 * qd[0] * qd[1] * math.cos(th) / math.sin(th)])
        atol = 1e-8 * (1 + np.abs(expected).max())
        np.testing.assert_allclose(system.accelerations(0.0, q, qd), expected, rtol=0, atol=atol)


def test_bead_on_rotating_hoop_uses_T0():
    """Hoop of radius a spinning at Ω about the vertical: T = ½ m a² (θ̇² + Ω² sin²θ),
    V = -m g a cos θ:  θ̈ = Ω² sin θ cos θ - (g/a) sin θ."""
    m, a, Omega = 0.4, 0.5, 6.0
    system = LagrangianSystem(
        mass_matrix=lambda q: np.array([[m * a**2]]),
        generalized_forces=lambda t, q, qd: np.array([-m * G * a * math.sin(q[0])]),
        kinetic_energy_0=lambda t, q: 0.5 * m * a**2 * Omega**2 * math.sin(q[0]) ** 2,
    )
    for th in np.linspace(-3.0, 3.0, 13):
        expected = Omega**2 * math.sin(th) * math.cos(th) - G / a * math.sin(th)
        assert system.accelerations(0.0, np.array([th]), np.array([0.7]))[0] == pytest.approx(expected, abs=1e-8)


def test_particle_in_rotating_plane_coriolis_centrifugal_euler_forces():
    """Rotating coordinates (x, y), Ω(t) = Ω0 + α t about z: T = ½ m |ẋ' + Ω × x'|²
    = ½ m (ẋ² + ẏ²) + m Ω (x ẏ - y ẋ) + ½ m Ω² (x² + y²); force F (space-fixed in the frame).
    ẍ = 2Ωẏ + Ω²x + α y + F_x/m,  ÿ = -2Ωẋ + Ω²y - α x + F_y/m."""
    m, Omega0, alpha, F = 2.0, 1.7, 0.3, np.array([0.4, -1.1])
    Omega = lambda t: Omega0 + alpha * t  # noqa: E731
    system = LagrangianSystem(
        mass_matrix=lambda q: m * np.eye(2),
        generalized_forces=lambda t, q, qd: F,
        gyroscopic=lambda t, q: m * Omega(t) * np.array([-q[1], q[0]]),
        kinetic_energy_0=lambda t, q: 0.5 * m * Omega(t) ** 2 * float(q @ q),
    )
    rng = np.random.default_rng(2)
    for _ in range(20):
        t, q, qd = rng.uniform(0, 3), rng.normal(size=2), rng.normal(size=2)
        W = Omega(t)
        expected = F / m + np.array(
            [2 * W * qd[1] + W**2 * q[0] + alpha * q[1], -2 * W * qd[0] + W**2 * q[1] - alpha * q[0]]
        )
        atol = 1e-8 * (1 + np.abs(expected).max())
        np.testing.assert_allclose(system.accelerations(t, q, qd), expected, rtol=0, atol=atol)
        # T as written equals ½ m |v_inertial|² with v = ẋ' + Ω × x'
        v = qd + W * np.array([-q[1], q[0]])
        assert system.kinetic_energy(t, q, qd) == pytest.approx(0.5 * m * v @ v, rel=1e-12)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_generic_fd_system_reproduces_rigid_body(name):
    """The rigid body through the generic FD solver vs Euler's equations (FD accuracy ~1e-8)."""
    model = MODELS[name]
    rng = np.random.default_rng(3)
    fd_system, analytic_system = rigid_body_system(model, analytic_derivatives=False), rigid_body_system(model)
    for _ in range(10):
        q = np.array([rng.uniform(-3, 3), rng.uniform(0.2, math.pi - 0.2), rng.uniform(-3, 3)])
        R, omega_b, t = R_scipy(q), rng.normal(size=3), rng.uniform(0, 5)
        qdot = euler_rates_from_omega_body(q, omega_b)
        expected = omega_body_dot(model, t, R, omega_b)
        for system, tol in ((fd_system, 1e-7), (analytic_system, 1e-10)):
            w_dot = omega_body_dot_from_euler(q, qdot, system.accelerations(t, q, qdot))
            np.testing.assert_allclose(w_dot, expected, rtol=0, atol=tol * (1 + np.abs(expected).max()))


def test_fd_mass_matrix_derivatives_accuracy_on_closed_form():
    """M(q) = diag(sin²q0, e^{q1}) q-derivatives to ~1e-10 (documented accuracy)."""
    q = np.array([0.7, -0.4])
    dM = mass_matrix_derivatives_fd(lambda q: np.diag([math.sin(q[0]) ** 2, math.exp(q[1])]), q)
    expected = np.zeros((2, 2, 2))
    expected[0, 0, 0] = math.sin(2 * q[0])
    expected[1, 1, 1] = math.exp(q[1])
    np.testing.assert_allclose(dM, expected, rtol=0, atol=1e-10)


def test_non_positive_definite_mass_matrix_is_refused():
    system = LagrangianSystem(lambda q: np.diag([1.0, -1.0]), lambda t, q, qd: np.zeros(2))
    with pytest.raises(ValueError, match="positive definite"):
        system.accelerations(0.0, np.zeros(2), np.zeros(2))


# ---------------------------------------------------------------- integrator (1)


def reference_motion(model: Model, state0: State, t_eval: np.ndarray):
    """DOP853 at rtol 1e-12 on y = (R (9), ω_b (3)): Ṙ = R hat(ω_b), Euler's equations."""

    def rhs(t, y):
        R, w = y[:9].reshape(3, 3), y[9:]
        hat_w = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([(R @ hat_w).ravel(), omega_body_dot(model, t, R, w)])

    y0 = np.concatenate([state0.R_space_body.ravel(), state0.omega_body])
    sol = solve_ivp(rhs, (state0.t, t_eval[-1]), y0, method="DOP853", t_eval=t_eval, rtol=1e-12, atol=1e-13)
    assert sol.success
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


@pytest.mark.parametrize("name", sorted(MODELS))
def test_integrator_matches_direct_euler_equations(name):
    model = MODELS[name]
    q0 = np.array([0.3, 1.1, -0.4])
    state0 = State(R_scipy(q0), np.array([0.5, 0.2, 1.5]), t=0.5)
    t_eval = np.linspace(0.5, 3.5, 31)
    R_ref, w_ref = reference_motion(model, state0, t_eval)
    sin_theta_ref = np.hypot(R_ref[:, 0, 2], R_ref[:, 1, 2])
    assert sin_theta_ref.min() > 0.1  # away from the poles, as the comparison intends
    traj = integrate_euler_lagrange(model, state0, t_eval)
    assert np.abs(traj.R_space_body - R_ref).max() < 1e-8
    assert np.abs(traj.omega_body - w_ref).max() < 1e-8
    np.testing.assert_allclose(traj.t, t_eval)
    np.testing.assert_allclose(traj.R_space_body[0], state0.R_space_body, atol=1e-14)
    assert traj.method == "euler_lagrange" and traj.evaluations > 0 and traj.wall_s > 0


def test_energy_is_conserved_to_the_tolerance_only():
    model = MODELS["heavy_top_asymmetric"]
    state0 = State(R_scipy(np.array([0.0, 1.2, 0.0])), np.array([0.3, -0.4, 4.0]))
    traj = integrate_euler_lagrange(model, state0, np.linspace(0.0, 10.0, 101))
    E = np.array([energy(model, R, w) for R, w in zip(traj.R_space_body, traj.omega_body)])
    drift = np.abs(E - E[0]).max() / abs(E[0])
    assert drift < 1e-8
    assert drift > 0.0  # not exact: nothing in the scheme enforces it


@pytest.mark.parametrize("R0", [np.eye(3), np.diag([1.0, -1.0, -1.0]), R_scipy(np.array([0.4, 1e-7, 0.2]))])
def test_start_at_gimbal_lock_raises_immediately(R0):
    """Refused before the first evaluation of the equations (a zero hook counts them)."""
    hook = CountingHook(lambda t, R, w: np.zeros(3))
    message = r"Lagrangian is singular at θ = .*t = 0 s.*use another method"
    with pytest.raises(EulerLagrangeSingularityError, match=message):
        integrate_euler_lagrange(Model((1.0, 2.0, 2.5), extra_torque=hook), State(R0, np.array([1.0, 0.5, 0.2])),
                                 np.linspace(0, 1, 5))
    assert hook.calls == 0


class CountingHook:
    """A torque hook that counts its calls: the work a run did, without a clock."""

    def __init__(self, torque):
        self.torque, self.calls = torque, 0

    def __call__(self, t, R, w):
        self.calls += 1
        return self.torque(t, R, w)


def steady_rotation_near_pole(axis_z: float, theta0: float, w: float):
    """Free body spinning about its principal x' axis a (fixed in space, a_z = axis_z) at w:
    R(t) = R0 Rx(w t); z'(t) = cos(theta0 + w t) v + sin(theta0 + w t) u sweeps the great circle
    ⊥ a, with v its point nearest +e_z (closest approach to ±e_z: sin θ = |a_z|), u = a × v."""
    a = np.array([math.sqrt(1 - axis_z**2), 0.0, axis_z])
    v = np.array([0.0, 0.0, 1.0]) - axis_z * a
    v /= np.linalg.norm(v)
    u = np.cross(a, v)
    z0 = math.cos(theta0) * v + math.sin(theta0) * u
    R0 = np.column_stack([a, np.cross(z0, a), z0])
    assert abs(np.linalg.det(R0) - 1) < 1e-12 and np.abs(R0.T @ R0 - np.eye(3)).max() < 1e-14
    model, state0 = Model((1.0, 2.0, 2.5)), State(R0, np.array([w, 0.0, 0.0]))
    sin_theta = lambda t: float(np.hypot(*(R0 @ Rotation.from_rotvec([w * t, 0, 0]).as_matrix())[:2, 2]))  # noqa: E731
    return model, state0, sin_theta


@pytest.mark.parametrize("pole", ["north", "south"])
def test_trajectory_through_pole_stops_at_the_right_time(pole):
    """z' heads for e_z (θ -> 0) or -e_z (θ -> π), closest at t = 0.5 s with sin θ = 1e-4."""
    theta0, w = (1.0, -2.0) if pole == "north" else (math.pi - 1.0, 2.0)
    model, state0, sin_theta = steady_rotation_near_pole(1e-4, theta0, w)
    assert sin_theta(0.5) == pytest.approx(1e-4, rel=1e-6)
    t_hit = brentq(lambda t: sin_theta(t) - SIN_THETA_STOP, 0.0, 0.5, xtol=1e-14)
    hook = CountingHook(lambda t, R, w: np.zeros(3))  # counts the evaluations (measured ~1300)
    with pytest.raises(EulerLagrangeSingularityError, match="singular at θ") as info:
        integrate_euler_lagrange(Model(model.inertia, extra_torque=hook), state0, np.linspace(0.0, 3.0, 61))
    assert hook.calls < 5000  # stops at the threshold instead of grinding into the pole
    assert info.value.t == pytest.approx(t_hit, abs=1e-8)
    assert math.sin(info.value.theta) == pytest.approx(SIN_THETA_STOP, rel=1e-6)
    assert (info.value.theta < 0.5) == (pole == "north")
    assert isinstance(info.value, IntegrationError) and isinstance(info.value, GimbalLockError)


def test_trajectory_just_outside_threshold_integrates():
    """Closest approach sin θ = 3e-3 > SIN_THETA_STOP: runs through, matches the closed form."""
    model, state0, _ = steady_rotation_near_pole(3e-3, 1.0, -2.0)
    t_eval = np.linspace(0.0, 1.0, 21)  # the closest approach is at t = 0.5
    traj = integrate_euler_lagrange(model, state0, t_eval)
    R_exact = np.array([state0.R_space_body @ Rotation.from_rotvec([-2.0 * t, 0, 0]).as_matrix() for t in t_eval])
    assert np.abs(traj.R_space_body - R_exact).max() < 1e-8
    assert traj.evaluations < 5000  # measured ~1950: the near-pole stretch does not stall the solver


@pytest.mark.parametrize("bad", ["R", "omega"])
def test_nan_input_raises(bad):
    R0, w0 = R_scipy(np.array([0.3, 1.1, -0.4])), np.array([0.5, 0.2, 1.5])
    if bad == "R":
        R0 = R0.copy()
        R0[1, 2] = np.nan
    else:
        w0 = np.array([0.5, np.nan, 1.5])
    with pytest.raises(IntegrationError, match="non-finite"):
        integrate_euler_lagrange(MODELS["free_asymmetric"], State(R0, w0), np.linspace(0, 1, 5))


def test_non_finite_torque_during_run_stops_with_time():
    hook = CountingHook(lambda t, R, w: np.full(3, np.nan) if t > 0.5 else np.zeros(3))
    with pytest.raises(IntegrationError, match=r"at t = 0\.5.*non-finite"):
        state0 = State(R_scipy(np.array([0.3, 1.1, -0.4])), np.array([0.5, 0.2, 1.5]))
        integrate_euler_lagrange(Model((1.0, 2.0, 2.5), extra_torque=hook), state0, np.linspace(0, 2, 5))
    assert hook.calls < 500  # stops at the first NaN (measured ~85), does not keep shrinking the step


def test_bad_times_are_refused():
    state0 = State(R_scipy(np.array([0.3, 1.1, -0.4])), np.array([0.5, 0.2, 1.5]), t=1.0)
    for t_eval in ([1.0, 0.5], [0.0, 2.0], [1.0, 1.0, 2.0]):
        with pytest.raises(ValueError, match="t_eval"):
            integrate_euler_lagrange(MODELS["free_asymmetric"], state0, np.array(t_eval))
    traj = integrate_euler_lagrange(MODELS["free_asymmetric"], state0, np.array([1.0]))
    np.testing.assert_allclose(traj.R_space_body[0], state0.R_space_body, atol=1e-14)
    np.testing.assert_allclose(traj.omega_body[0], state0.omega_body, atol=1e-14)
