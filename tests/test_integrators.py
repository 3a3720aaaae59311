"""The singularity-free integrators (physics.integrators) against independent references.

References (none of them the code under test): scipy solve_ivp DOP853 at rtol 1e-13 on
Ṙ = R hat(ω_b) with Euler's equations from physics.dynamics.omega_body_dot (a 3x3 matrix ODE,
no quaternions), SciPy's Rotation for quaternion <-> matrix, closed forms (a planar pendulum's
energy, a principal-axis spin), the conservation laws of the exact flow, and error ratios when
the step is halved (the order).  No timings: "stops early" is checked by counting the work.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from physics.dynamics import (
    IntegrationError,
    Model,
    State,
    angular_momentum_space,
    energy,
    kinetic_energy,
    omega_body_dot,
)
from physics.integrators import (
    COMPOSITIONS,
    REALTIME_SUBSTEP_ANGLE,
    integrate_adaptive,
    integrate_dop853,
    integrate_splitting,
    rate_scale,
    step_realtime,
)
from physics.quaternion import matrix_from_wxyz, wxyz_from_matrix
from physics.quaternion_ode import quaternion_rhs
from physics.so3 import rot_x

R_GENERIC = Rotation.from_euler("ZXZ", [0.3, 0.4, -0.2]).as_matrix()
HEAVY = Model((1.0, 1.5, 2.0), mgl=1.0)  # asymmetric heavy top about the pivot: no closed form


def hat(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def reference(model: Model, state0: State, t_eval: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(R (N,3,3), ω_b (N,3)) by solve_ivp DOP853, rtol 1e-13, on the matrix ODE Ṙ = R hat(ω_b)."""

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        R, omega = y[:9].reshape(3, 3), y[9:]
        return np.concatenate([(R @ hat(omega)).ravel(), omega_body_dot(model, t, R, omega)])

    y0 = np.concatenate([np.asarray(state0.R_space_body).ravel(), state0.omega_body])
    sol = solve_ivp(rhs, (state0.t, t_eval[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-14, t_eval=t_eval)
    assert sol.status == 0
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


def attitude_error(Ra: np.ndarray, Rb: np.ndarray) -> float:
    """max over samples of the rotation angle [rad] of Raᵀ Rb."""
    rel = np.einsum("nji,njk->nik", Ra, Rb)
    return float(np.max(np.linalg.norm(Rotation.from_matrix(rel).as_rotvec(), axis=1)))


def energies(model: Model, R: np.ndarray, omega: np.ndarray) -> np.ndarray:
    return np.array([energy(model, r, w) for r, w in zip(R, omega)])


def momenta(model: Model, R: np.ndarray, omega: np.ndarray) -> np.ndarray:
    return np.array([angular_momentum_space(model, r, w) for r, w in zip(R, omega)])


# --- the quaternion ODE (quaternion <-> matrix itself: tests/test_quaternion.py) -------------


@pytest.mark.parametrize(
    "model",
    [HEAVY, Model((1.0, 2.0, 3.0)), Model((2.0, 1.5, 1.0), mgl=0.7, torque_space=(0.1, -0.2, 0.3)),
     Model((1.0, 1.2, 2.0), extra_torque=lambda t, R, w: R @ (-0.3 * w) + np.array([0.0, 0.1 * t, 0.0]))],
    ids=["heavy", "free", "gravity+const", "hook"],
)  # fmt: skip
def test_quaternion_rhs_is_eulers_equations_and_kinematics(model: Model) -> None:
    rng = np.random.default_rng(1)
    rhs = quaternion_rhs(model)
    for _ in range(5):
        R = Rotation.random(random_state=rng).as_matrix()
        omega = rng.normal(size=3)
        q = np.array(wxyz_from_matrix(R))
        scale = 1.7  # homogeneous of degree 0 in q: |q| != 1 must not change ω̇
        dy = np.array(rhs(0.4, *(scale * q), *omega))
        np.testing.assert_allclose(dy[4:], omega_body_dot(model, 0.4, R, omega), atol=1e-13)
        # q̇ must give Ṙ = R hat(ω_b): central difference of R(q + ε q̇ / scale).
        eps = 1e-6
        R_plus = matrix_from_wxyz(q + eps * dy[:4] / scale)
        R_minus = matrix_from_wxyz(q - eps * dy[:4] / scale)
        np.testing.assert_allclose((R_plus - R_minus) / (2 * eps), R @ hat(omega), atol=1e-8)


# --- order and agreement with the reference ---------------------------------------------------


@pytest.mark.parametrize(
    ("order", "h", "low", "high"), [(2, 0.02, 3.6, 4.4), (4, 0.04, 14.0, 18.0), (6, 0.1, 48.0, 80.0)]
)
def test_splitting_order_from_halving_the_step(order: int, h: float, low: float, high: float) -> None:
    """Error ratio err(h) / err(h/2) ≈ 2^order on the asymmetric heavy top (2 s)."""
    state0 = State(R_GENERIC, np.array([0.3, 0.2, 3.0]))
    t = np.array([0.0, 2.0])
    R_ref, omega_ref = reference(HEAVY, state0, t)
    errors = []
    for step in (h, h / 2):
        traj = integrate_splitting(HEAVY, state0, t, h=step, order=order)
        errors.append(attitude_error(traj.R_space_body, R_ref) + np.max(np.abs(traj.omega_body - omega_ref)))
    assert errors[1] > 1e-11  # well above the reference's own error
    assert low < errors[0] / errors[1] < high, errors


@pytest.mark.parametrize("inertia", list(itertools.permutations((1.0, 1.5, 2.0))))
def test_every_working_frame_permutation_agrees_with_reference(inertia: tuple[float, float, float]) -> None:
    """The splitting relabels the axes (even and odd permutations); all must give the same motion."""
    model = Model(inertia, mgl=1.0)
    state0 = State(R_GENERIC, np.array([0.3, 0.2, 3.0]))
    t = np.linspace(0.0, 2.0, 5)
    R_ref, omega_ref = reference(model, state0, t)
    traj = integrate_splitting(model, state0, t, h=0.01)
    assert attitude_error(traj.R_space_body, R_ref) < 1e-8
    np.testing.assert_allclose(traj.omega_body, omega_ref, atol=1e-8)


MODELS = {
    "heavy": HEAVY,
    "free": Model((1.0, 2.0, 3.0)),
    "const_torque": Model((2.0, 1.5, 1.0), torque_space=(0.1, 0.2, -0.1)),
    "gravity+const": Model((1.5, 1.0, 2.0), mgl=0.5, torque_space=(0.0, 0.3, 0.0)),
    "hook": Model(
        (1.0, 2.0, 2.5), extra_torque=lambda t, R, w: R @ (-0.1 * w) + np.array([0.0, 0.0, 0.1 * math.sin(t)])
    ),
}


@pytest.mark.parametrize("name", list(MODELS))
def test_all_methods_agree_with_solve_ivp_at_rtol_1e13(name: str) -> None:
    model = MODELS[name]
    state0 = State(R_GENERIC, np.array([0.5, -0.4, 2.0]), 0.5)
    t = np.linspace(0.5, 3.5, 7)
    R_ref, omega_ref = reference(model, state0, t)
    for traj, tol in (
        (integrate_adaptive(model, state0, t), 1e-10),
        (integrate_dop853(model, state0, t), 1e-10),
        (integrate_splitting(model, state0, t, h=0.005), 1e-8),
        (integrate_splitting(model, state0, t), 1e-6),  # default step
    ):
        assert attitude_error(traj.R_space_body, R_ref) < tol, traj.method
        np.testing.assert_allclose(traj.omega_body, omega_ref, atol=tol, err_msg=traj.method)
        np.testing.assert_array_equal(traj.t, t)
        assert traj.evaluations > 0 and traj.wall_s > 0.0


def test_hook_depending_on_omega_is_second_order() -> None:
    """A damping hook makes the kick inexact; the midpoint kick keeps the method 2nd order at least."""
    model = MODELS["hook"]
    state0 = State(R_GENERIC, np.array([0.5, -0.4, 2.0]))
    t = np.array([0.0, 2.0])
    R_ref, _ = reference(model, state0, t)
    e1, e2 = (attitude_error(integrate_splitting(model, state0, t, h=h).R_space_body, R_ref) for h in (0.1, 0.05))
    assert e1 / e2 > 3.5, (e1, e2)


def test_adaptive_takes_the_same_steps_as_scipy_dop853() -> None:
    """Same pair, controller and dense output: the same evaluations to within the start-up."""
    state0 = State(R_GENERIC, np.array([0.3, 0.2, 3.0]))
    t = np.linspace(0.0, 10.0, 41)
    for rtol in (1e-8, 1e-12):
        a = integrate_adaptive(HEAVY, state0, t, rtol=rtol, atol=rtol * 1e-2)
        b = integrate_dop853(HEAVY, state0, t, rtol=rtol, atol=rtol * 1e-2)
        assert abs(a.evaluations - b.evaluations) <= 0.05 * b.evaluations, (a.evaluations, b.evaluations)
        assert attitude_error(a.R_space_body, b.R_space_body) < 1e3 * rtol


# --- conservation ------------------------------------------------------------------------------


def test_free_body_keeps_space_angular_momentum_to_rounding() -> None:
    model = Model((1.0, 2.0, 3.0))
    state0 = State(R_GENERIC, np.array([0.3, 1.0, 0.2]))
    t = np.linspace(0.0, 200.0, 201)
    traj = integrate_splitting(model, state0, t, h=0.05)  # 4000 steps, large energy error allowed
    L = momenta(model, traj.R_space_body, traj.omega_body)
    L0 = np.linalg.norm(L[0])
    assert np.max(np.abs(np.linalg.norm(L, axis=1) - L0)) < 1e-13 * L0
    assert np.max(np.abs(L - L[0])) < 1e-13 * L0  # the vector, not just its length


def test_heavy_top_keeps_vertical_angular_momentum_to_rounding() -> None:
    state0 = State(R_GENERIC, np.array([0.3, 0.2, 3.0]))
    t = np.linspace(0.0, 200.0, 201)
    traj = integrate_splitting(HEAVY, state0, t, h=0.05)
    Lz = momenta(HEAVY, traj.R_space_body, traj.omega_body)[:, 2]
    scale = np.linalg.norm(HEAVY.inertia * state0.omega_body)
    assert np.max(np.abs(Lz - Lz[0])) < 1e-13 * scale
    assert np.max(np.abs(np.einsum("nij,nik->njk", traj.R_space_body, traj.R_space_body) - np.eye(3))) < 1e-14


def test_energy_error_is_bounded_without_trend() -> None:
    """2000 s of the asymmetric heavy top at a coarse step: the error oscillates, it does not grow."""
    state0 = State(R_GENERIC, np.array([0.3, 0.2, 3.0]))
    t = np.linspace(0.0, 2000.0, 2001)
    traj = integrate_splitting(HEAVY, state0, t, h=0.1)  # h Ω ≈ 0.57
    E = energies(HEAVY, traj.R_space_body, traj.omega_body)
    rel = (E - E[0]) / abs(E[0])
    first, second = np.max(np.abs(rel[:1000])), np.max(np.abs(rel[1000:]))
    assert first < 2e-5  # O((h Ω)^4)
    assert second < 1.5 * first  # no growth
    slope = np.polyfit(t, rel, 1)[0]
    assert abs(slope) * t[-1] < 0.1 * first  # no secular trend


def test_adaptive_method_does_not_conserve_but_follows_the_tolerance() -> None:
    state0 = State(R_GENERIC, np.array([0.3, 0.2, 3.0]))
    t = np.linspace(0.0, 100.0, 101)
    E = energies(HEAVY, *(lambda tr: (tr.R_space_body, tr.omega_body))(integrate_adaptive(HEAVY, state0, t)))
    assert np.max(np.abs(E - E[0])) / abs(E[0]) < 1e-9


# --- hard cases --------------------------------------------------------------------------------

HARD = {
    # name: (model, R0, ω0, t_end, splitting tolerance on attitude [rad] and ω / max(1, |ω0|)),
    # the splitting at h Ω = 0.05; tolerances ~10x the measured errors
    "identity start, lamina": (Model((1.0, 2.0, 3.0)), np.eye(3), [0.3, 0.5, 1.0], 10.0, 1e-8),
    "theta = pi start": (HEAVY, rot_x(math.pi), [0.5, 0.2, 2.0], 10.0, 2e-9),
    "over the top through both poles": (HEAVY, rot_x(0.3), [-1.5, 0.0, 0.0], 10.0, 2e-9),
    "separatrix (intermediate axis)": (Model((1.0, 2.0, 3.0)), R_GENERIC, [1e-4, 2.0, 1e-4], 10.0, 3e-8),
    "nearly symmetric": (Model((1.0, 1.0 + 1e-9, 0.6), mgl=1.0), rot_x(0.5), [0.3, 0.1, 8.0], 10.0, 1e-10),
    "symmetric lamina (disc)": (Model((1.0, 1.0, 2.0)), R_GENERIC, [0.7, -0.2, 1.5], 10.0, 1e-11),
    "sleeping top": (Model((1.0, 1.0, 0.5), mgl=1.0), rot_x(1e-3), [0.0, 0.0, 20.0], 5.0, 1e-10),
    "1000 rad/s asymmetric spin": (Model((1.0, 1.5, 2.0)), R_GENERIC, [300.0, 200.0, 950.0], 0.1, 2e-8),
    "1000 rad/s tilted top": (Model((1.0, 1.0, 0.5), mgl=1.0), rot_x(0.5), [0.0, 0.0, 1000.0], 0.2, 1e-10),
}


@pytest.mark.parametrize("name", list(HARD))
def test_hard_cases_against_reference(name: str) -> None:
    model, R0, omega0, t_end, tol = HARD[name]
    state0 = State(R0, np.array(omega0, dtype=float))
    t = np.linspace(0.0, t_end, 6)
    R_ref, omega_ref = reference(model, state0, t)
    scale = max(1.0, float(np.linalg.norm(omega0)))
    h = 0.05 / rate_scale(model, R0, state0.omega_body)
    for traj, tolerance in (
        (integrate_splitting(model, state0, t, h=h), tol),
        (integrate_adaptive(model, state0, t), 1e-9),
        (integrate_dop853(model, state0, t), 1e-9),
    ):
        assert np.all(np.isfinite(traj.R_space_body)) and np.all(np.isfinite(traj.omega_body))
        assert attitude_error(traj.R_space_body, R_ref) < tolerance, traj.method
        assert np.max(np.abs(traj.omega_body - omega_ref)) < tolerance * scale, traj.method


def test_over_the_top_case_really_passes_the_poles() -> None:
    """The planar swing R = rot_x(θ(t)) passes θ = 0 (R = 1) and θ = π; energy from the pendulum."""
    model, R0, omega0, _, _ = HARD["over the top through both poles"]
    state0 = State(R0, np.array(omega0))
    t = np.linspace(0.0, 10.0, 2001)
    traj = integrate_splitting(model, state0, t, h=0.005)
    theta = np.unwrap(np.arctan2(traj.R_space_body[:, 2, 1], traj.R_space_body[:, 1, 1]))
    assert theta.min() < -2 * math.pi  # swung over the top more than once, through 0 and π
    # Pendulum: ½ I1 θ̇² + mgl cos θ = const, θ̇ = ω_x; the motion stays in the x rotation family.
    E = 0.5 * model.inertia[0] * traj.omega_body[:, 0] ** 2 + model.mgl * np.cos(theta)
    assert np.max(np.abs(E - E[0])) < 1e-9
    assert np.max(np.abs(traj.omega_body[:, 1:])) < 1e-12


def test_principal_axis_spin_is_exact() -> None:
    """Spin about a principal axis: R(t) = rot about that axis by ω t, closed form."""
    model = Model((1.0, 1.5, 2.0))
    omega = 1000.0
    state0 = State(np.eye(3), np.array([0.0, omega, 0.0]))
    t = np.linspace(0.0, 1.0, 11)
    traj = integrate_splitting(model, state0, t, h=0.01)  # h ω = 10 rad: still exact
    expected = Rotation.from_rotvec(np.outer(t * omega, [0.0, 1.0, 0.0])).as_matrix()
    assert attitude_error(traj.R_space_body, expected) < 1e-10


def test_realtime_substeps_a_fast_spin_and_stays_accurate() -> None:
    model, R0, omega0, _, _ = HARD["1000 rad/s asymmetric spin"]
    state = State(R0, np.array(omega0))
    dt = 1.0 / 240.0
    frames = 40
    n_expected = math.ceil(dt * rate_scale(model, R0, state.omega_body) / REALTIME_SUBSTEP_ANGLE)
    assert n_expected > 10
    R_ref, omega_ref = reference(model, state, dt * np.arange(frames + 1))
    Rs = [R0]
    for _ in range(frames):
        state, evaluations = step_realtime(model, state, dt)
        assert evaluations == n_expected * len(COMPOSITIONS[4])
        Rs.append(state.R_space_body)
    assert state.t == pytest.approx(frames * dt, abs=1e-12)
    # The documented error model C (h Ω)^4 Ω t with C = 1e-6 (REALTIME_SUBSTEP_ANGLE), x 3.
    omega_scale = rate_scale(model, R0, np.array(omega0))
    assert attitude_error(np.array(Rs), R_ref) < 3 * 1e-6 * REALTIME_SUBSTEP_ANGLE**4 * omega_scale * frames * dt
    relative = np.linalg.norm(state.omega_body - omega_ref[-1]) / np.linalg.norm(omega_ref[-1])
    assert relative < 3 * 1e-6 * REALTIME_SUBSTEP_ANGLE**4 * omega_scale * frames * dt


@pytest.mark.parametrize(
    "name", ["theta = pi start", "over the top through both poles", "separatrix (intermediate axis)", "sleeping top"]
)
def test_realtime_frames_meet_the_real_time_targets(name: str) -> None:
    """dt = 1/240 s for 5 s: attitude error <= 1e-3 rad and |ΔE/E| <= 1e-5 (targets of the issue)."""
    model, R0, omega0, _, _ = HARD[name]
    state = State(R0, np.array(omega0, dtype=float))
    dt = 1.0 / 240.0
    frames = 1200
    R_ref, _ = reference(model, state, dt * np.arange(frames + 1))
    Rs, E = [R0], [energy(model, R0, state.omega_body)]
    for _ in range(frames):
        state, _ = step_realtime(model, state, dt)
        Rs.append(state.R_space_body)
        E.append(energy(model, state.R_space_body, state.omega_body))
    assert attitude_error(np.array(Rs), R_ref) < 1e-3
    assert np.max(np.abs(np.array(E) - E[0])) <= 1e-5 * abs(E[0])


def test_realtime_continues_from_a_fresh_state_as_from_its_own() -> None:
    """A State built by the caller (validated, converted) and the returned one give the same step."""
    state, _ = step_realtime(HEAVY, State(R_GENERIC, np.array([0.3, 0.2, 3.0])), 1 / 60)
    fresh = State(np.array(state.R_space_body), np.array(state.omega_body), state.t)
    a, _ = step_realtime(HEAVY, state, 1 / 60)
    b, _ = step_realtime(HEAVY, fresh, 1 / 60)
    np.testing.assert_allclose(a.R_space_body, b.R_space_body, atol=1e-14)
    np.testing.assert_allclose(a.omega_body, b.omega_body, atol=1e-14)


# --- bad input and blow-ups ----------------------------------------------------------------

def run_realtime(model: Model, state: State, t: np.ndarray) -> State:
    """Frames of 1/60 s up to t[-1], as the app runs them."""
    for _ in range(round(t[-1] * 60)):
        state, _ = step_realtime(model, state, 1 / 60)
    return state


METHODS = {
    "splitting": lambda model, state, t: integrate_splitting(model, state, t),
    "adaptive": integrate_adaptive,
    "dop853": integrate_dop853,
    "realtime": run_realtime,
}


@pytest.mark.parametrize("method", list(METHODS))
@pytest.mark.parametrize("bad", ["nan omega", "inf R", "not orthogonal", "reflection"])
def test_bad_initial_state_raises_at_once(method: str, bad: str) -> None:
    R, omega = R_GENERIC.copy(), np.array([0.3, 0.2, 3.0])
    if bad == "nan omega":
        omega[1] = np.nan
    elif bad == "inf R":
        R[0, 0] = np.inf
    elif bad == "not orthogonal":
        R = R * (1.0 + 1e-6)
    else:
        R = R @ np.diag([1.0, 1.0, -1.0])
    hook = CountingHook(lambda t, R, w: np.zeros(3))
    with pytest.raises(IntegrationError, match="non-finite|orthogonal|reflection"):
        METHODS[method](Model(HEAVY.inertia, HEAVY.mgl, extra_torque=hook), State(R, omega), np.linspace(0.0, 1.0, 3))
    assert hook.calls == 0  # refused before any work


class CountingHook:
    """A torque hook that counts its calls: the work a run did, without a clock."""

    def __init__(self, torque: object) -> None:
        self.torque, self.calls = torque, 0

    def __call__(self, t: float, R: np.ndarray, w: np.ndarray) -> np.ndarray:
        self.calls += 1
        return self.torque(t, R, w)  # type: ignore[operator,no-any-return]


def unstable_hook(t: float, R: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """Anti-damping 50 I ω: |ω| grows like e^(50 t)."""
    return R @ (50.0 * np.array([1.0, 1.5, 2.0]) * omega)


def nan_hook(t: float, R: np.ndarray, omega: np.ndarray) -> np.ndarray:
    return np.array([0.0, 0.0, np.nan]) if t > 0.3 else np.zeros(3)


@pytest.mark.parametrize("method", list(METHODS))
@pytest.mark.parametrize("hook", [unstable_hook, nan_hook], ids=["blow-up", "nan torque"])
def test_blow_up_or_nan_torque_stops_early(method: str, hook: object) -> None:
    """Stopped by the guards after a bounded amount of work (measured <= 15530 hook calls, the
    real-time stepping of the blow-up; 62-310 for a NaN), naming the time."""
    counted = CountingHook(hook)
    model = Model((1.0, 1.5, 2.0), extra_torque=counted)
    with pytest.raises(IntegrationError, match=r"blow-up|non-finite|sub-steps") as info:
        METHODS[method](model, State(R_GENERIC, np.array([0.3, 0.2, 3.0])), np.linspace(0.0, 5.0, 11))
    assert counted.calls < 20_000
    assert "t = " in str(info.value)


def test_bad_arguments_raise_value_error() -> None:
    state = State(R_GENERIC, np.array([0.3, 0.2, 3.0]), 1.0)
    with pytest.raises(ValueError, match="increasing"):
        integrate_splitting(HEAVY, state, [1.0, 0.5])
    with pytest.raises(ValueError, match="state0.t"):
        integrate_adaptive(HEAVY, state, [0.0, 2.0])
    with pytest.raises(ValueError, match="order"):
        integrate_splitting(HEAVY, state, [1.0, 2.0], order=3)
    with pytest.raises(ValueError, match="positive"):
        integrate_splitting(HEAVY, state, [1.0, 2.0], h=-0.1)
    with pytest.raises(ValueError, match="dt"):
        step_realtime(HEAVY, state, 0.0)
    with pytest.raises(ValueError, match="rtol"):
        integrate_dop853(HEAVY, state, [1.0, 2.0], rtol=0.0)


def test_output_at_the_start_time_is_the_initial_state() -> None:
    state = State(R_GENERIC, np.array([0.3, 0.2, 3.0]), 2.0)
    for run in (integrate_splitting, integrate_adaptive, integrate_dop853):
        traj = run(HEAVY, state, np.array([2.0]))
        np.testing.assert_allclose(traj.R_space_body[0], R_GENERIC, atol=1e-15)
        np.testing.assert_allclose(traj.omega_body[0], state.omega_body, atol=0.0)


def test_kinetic_energy_is_half_omega_dot_I_omega() -> None:
    rng = np.random.default_rng(5)
    for _ in range(20):
        inertia = np.sort(rng.uniform(1.0, 1.9, 3))  # physical: I1 + I2 >= I3
        model = Model(tuple(inertia), mgl=rng.uniform(0.0, 3.0))
        omega = rng.normal(size=3) * 5.0
        expected = 0.5 * float(omega @ np.diag(inertia) @ omega)  # ½ ω·I ω (memo 3.6)
        assert kinetic_energy(model, omega) == pytest.approx(expected, rel=1e-14)
        R = Rotation.random(random_state=rng).as_matrix()
        assert kinetic_energy(model, omega) == pytest.approx(energy(model, R, omega) - model.mgl * R[2, 2], rel=1e-12)
    assert type(kinetic_energy(HEAVY, np.array([1.0, 2.0, 3.0]))) is float
