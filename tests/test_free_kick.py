"""physics.free_kick: the exact free-body drift composed with torque kicks.

The drift alone is `physics.exact_free` to rounding (zero torque, any body and step); on the
heavy symmetric top the method meets the closed form to 1e-12 rad; on the asymmetric heavy top
(no closed form) it meets DOP853 at rtol 3e-14 and converges at its order (the slope of error
against step); the energy stays bounded.  No timing is asserted (benchmarks/work_precision.py
measures the speed).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from physics import integrators
from physics.dynamics import Model, State, energy
from physics.euler import matrix_from_euler_zxz
from physics.exact_free import FreeBodyExact
from physics.exact_top import HeavySymmetricTopExact
from physics.free_kick import FreeDrift, integrate_free_kick, step_for
from physics.methods import methods, simulate

TORQUED = Model(inertia=(1.0, 1.4, 0.6), mgl=2.0)  # the asymmetric heavy top of issue 28


def _torqued_state() -> State:
    """z-x-z (0.2, 0.9, 0) rad with rates (0.3, 0, 12) rad/s, as the benchmark case."""
    phi, theta, psi = 0.2, 0.9, 0.0
    dphi, dtheta, dpsi = 0.3, 0.0, 12.0
    omega = np.array([dphi * math.sin(theta) * math.sin(psi) + dtheta * math.cos(psi),
                      dphi * math.sin(theta) * math.cos(psi) - dtheta * math.sin(psi),
                      dphi * math.cos(theta) + dpsi])
    return State(matrix_from_euler_zxz(phi, theta, psi), omega)


def _angle(R_a: np.ndarray, R_b: np.ndarray) -> float:
    return float(Rotation.from_matrix(np.swapaxes(R_a, -1, -2) @ R_b).magnitude().max())


@pytest.mark.parametrize("inertia", [(1.0, 1.4, 0.6), (1.0, 2.0, 2.5), (1.0, 1.0, 2.0), (2.0, 1.0, 1.0),
                                     (0.7, 1.9, 1.3)])
def test_the_drift_is_the_exact_free_flow_to_rounding(inertia: tuple[float, float, float]) -> None:
    rng = np.random.default_rng(7)
    drift = FreeDrift(inertia)
    for trial in range(6):
        R0 = Rotation.random(random_state=trial).as_matrix()
        omega0 = rng.normal(size=3) * 3.0
        exact = FreeBodyExact(np.array(inertia), R0, omega0)
        for tau in (1e-3, 0.02, 0.1, 0.4, -0.05):
            R, L = drift.flow(R0.ravel().tolist(), (np.array(inertia) * omega0).tolist(), tau)
            R_exact, omega_exact = exact(tau)
            assert _angle(R_exact, np.array(R).reshape(3, 3)) < 1e-14, (inertia, trial, tau)
            np.testing.assert_allclose(np.array(L) / inertia, omega_exact, rtol=0, atol=1e-14 * np.abs(omega0).max())
    assert drift.slow_drifts == 0  # none of these is near the separatrix


def test_zero_torque_is_the_closed_form() -> None:
    model = Model(inertia=(1.0, 2.0, 2.5))
    state = State(Rotation.from_rotvec([0.3, -0.2, 0.9]).as_matrix(), np.array([0.5, 1.7, -0.4]))
    t = np.linspace(0.0, 50.0, 11)
    trajectory = integrate_free_kick(model, state, t)
    R_exact, omega_exact = FreeBodyExact(np.array(model.inertia), state.R_space_body, state.omega_body)(t)
    assert _angle(R_exact, trajectory.R_space_body) < 1e-13
    np.testing.assert_allclose(trajectory.omega_body, omega_exact, rtol=0, atol=1e-13)


def test_the_symmetric_heavy_top_meets_its_closed_form_to_1e_12_rad() -> None:
    model = Model(inertia=(1.0, 1.0, 0.5), mgl=2.0)
    omega0 = np.array([0.0, 0.3 * math.sin(0.6), 0.3 * math.cos(0.6) + 12.0])
    state = State(matrix_from_euler_zxz(0.0, 0.6, 0.0), omega0)
    t = np.linspace(0.0, 3.0, 61)
    trajectory = integrate_free_kick(model, state, t, h=0.025)
    R_exact, _ = HeavySymmetricTopExact(1.0, 0.5, 2.0, state.R_space_body, state.omega_body)(t)
    assert _angle(R_exact, trajectory.R_space_body) < 1e-12


def test_the_asymmetric_heavy_top_meets_a_tight_reference_and_converges_at_order_six() -> None:
    state = _torqued_state()
    t = np.linspace(0.0, 2.0, 5)
    reference = integrators.integrate_dop853(TORQUED, state, t, rtol=3e-14, atol=1e-16).R_space_body
    steps = (0.1, 0.05, 0.025)
    errors = [_angle(reference, integrate_free_kick(TORQUED, state, t, h=h).R_space_body) for h in steps]
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 5.3 < slope < 7.0, (errors, slope)
    assert errors[-1] < 1e-11
    # and the default step (from tol 1e-12) is within a few times its tolerance
    assert _angle(reference, simulate(TORQUED, state, t, "free_kick").R_space_body) < 5e-12
    assert step_for(TORQUED, state, 1e-12) > 0.01


@pytest.mark.parametrize(("mgl", "spin", "t_end", "steps"), [
    (2.0, 60.0, 1.0, (0.035, 0.025, 0.0175)),  # a fast asymmetric top
    (0.02, 1.0, 40.0, (3.2, 1.6, 0.8)),  # a small torque, slowly turning
])
def test_the_order_is_six_on_the_fast_top_and_under_a_small_torque(mgl: float, spin: float, t_end: float,
                                                                    steps: tuple[float, ...]) -> None:
    model = Model(inertia=(1.0, 1.4, 0.6), mgl=mgl)
    omega0 = np.array([0.0, 0.3 * math.sin(0.9), 0.3 * math.cos(0.9) + spin])
    state = State(matrix_from_euler_zxz(0.2, 0.9, 0.0), omega0)
    t = np.linspace(0.0, t_end, 3)
    reference = integrators.integrate_dop853(model, state, t, rtol=3e-14, atol=1e-16).R_space_body
    errors = [_angle(reference, integrate_free_kick(model, state, t, h=h).R_space_body) for h in steps]
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 5.3 < slope < 7.0, (errors, slope)


def test_energy_stays_bounded_and_l_z_exact() -> None:
    state = _torqued_state()
    t = np.linspace(0.0, 60.0, 121)
    trajectory = integrate_free_kick(TORQUED, state, t, h=0.1)
    E = np.array([energy(TORQUED, R, w) for R, w in zip(trajectory.R_space_body, trajectory.omega_body)])
    drift = np.abs(E - E[0]) / abs(E[0])
    assert drift.max() < 1e-8
    first, last = drift[: len(drift) // 2].max(), drift[len(drift) // 2:].max()
    assert last < 3.0 * first + 1e-14  # bounded: the second half no worse than the first
    L_z = np.einsum("nij,nj->ni", trajectory.R_space_body, trajectory.omega_body * TORQUED.inertia)[:, 2]
    assert np.abs(L_z - L_z[0]).max() < 1e-12 * abs(L_z[0])


def test_the_registry_lists_it_for_torques_of_the_attitude_only() -> None:
    method = methods()["free_kick"]
    assert method.applies(TORQUED) and method.applies(Model(inertia=(1.0, 2.0, 3.0), torque_space=(0.0, 0.1, 0.0)))
    hooked = Model(inertia=(1.0, 2.0, 2.5), extra_torque=lambda t, R, w: np.zeros(3))
    assert not method.applies(hooked)
    with pytest.raises(ValueError, match="hook"):
        integrate_free_kick(hooked, _torqued_state(), np.array([0.0, 1.0]))
