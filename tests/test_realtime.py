"""physics.realtime: the stepper owns its state, steppers never interfere, and the stateless
`step_realtime` is the same step."""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from physics.dynamics import IntegrationError, Model, State
from physics.guards import rate_scale
from physics.methods import simulate_realtime
from physics.realtime import MAX_SUBSTEPS, REALTIME_SUBSTEP_ANGLE, RealtimeStepper, step_realtime
from physics.splitting import STAGES

R0 = Rotation.from_euler("ZXZ", [0.3, 0.4, -0.2]).as_matrix()
HEAVY = Model((1.0, 1.5, 2.0), mgl=1.0)
FREE = Model((1.0, 2.0, 2.5))


def run_alone(model: Model, state: State, dts: list[float]) -> list[State]:
    stepper = RealtimeStepper(model, state)
    return [stepper.step(dt) for dt in dts]


def assert_same(a: State, b: State) -> None:
    assert a.t == b.t
    assert np.array_equal(a.R_space_body, b.R_space_body)  # bit for bit
    assert np.array_equal(a.omega_body, b.omega_body)


def test_attributes_after_construction_and_a_step() -> None:
    state0 = State(R0, np.array([0.3, 0.2, 3.0]), 1.5)
    stepper = RealtimeStepper(HEAVY, state0)
    assert stepper.state is state0
    assert (stepper.substeps, stepper.evaluations) == (0, 0)
    assert stepper.stages_per_substep == STAGES[4] == 5
    state = stepper.step(1 / 60)
    assert state is stepper.state
    assert state.t == 1.5 + 1 / 60
    n = max(1, math.ceil(rate_scale(HEAVY, R0, state0.omega_body) / 60 / REALTIME_SUBSTEP_ANGLE))
    assert stepper.substeps == n
    assert stepper.evaluations == n * stepper.stages_per_substep


def test_two_steppers_on_the_same_model_do_not_interfere() -> None:
    """Interleaved steppers (same Model object, equal models, different states and dt) give
    bit for bit what each gives alone."""
    a0 = State(R0, np.array([0.3, 0.2, 3.0]))
    b0 = State(R0.T, np.array([-1.0, 0.5, 0.7]), 2.0)
    dts_a = [1 / 240] * 50 + [1 / 60] * 10
    dts_b = [1 / 60] * 30 + [1 / 30] * 30
    for model_b in (HEAVY, Model((1.0, 1.5, 2.0), mgl=1.0)):
        alone_a, alone_b = run_alone(HEAVY, a0, dts_a), run_alone(model_b, b0, dts_b)
        sa, sb = RealtimeStepper(HEAVY, a0), RealtimeStepper(model_b, b0)
        for k in range(len(dts_a)):
            assert_same(sa.step(dts_a[k]), alone_a[k])
            assert_same(sb.step(dts_b[k]), alone_b[k])


def test_steppers_in_threads_do_not_interfere() -> None:
    states = [State(R0, np.array([0.3, 0.2, 3.0 + k])) for k in range(4)]
    expected = [run_alone(HEAVY, s, [1 / 240] * 200)[-1] for s in states]
    results: list[State | None] = [None] * 4

    def work(k: int) -> None:
        results[k] = run_alone(HEAVY, states[k], [1 / 240] * 200)[-1]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for got, want in zip(results, expected):
        assert got is not None
        assert_same(got, want)


@pytest.mark.parametrize("model", [HEAVY, FREE, Model((1.0, 1.2, 2.0), extra_torque=lambda t, R, w: -0.1 * (R @ w))])
def test_step_realtime_is_one_stepper_step(model: Model) -> None:
    state0 = State(R0, np.array([0.3, 0.2, 3.0]), 0.5)
    stepper = RealtimeStepper(model, state0)
    new, evaluations = step_realtime(model, state0, 1 / 60)
    assert_same(new, stepper.step(1 / 60))
    assert evaluations == stepper.evaluations
    # Frame after frame the stateless function restarts from the State's matrix each time: the
    # same motion to rounding.
    state = new
    for _ in range(60):
        state, _ = step_realtime(model, state, 1 / 60)
        stepper.step(1 / 60)
    np.testing.assert_allclose(state.R_space_body, stepper.state.R_space_body, atol=1e-13)
    np.testing.assert_allclose(state.omega_body, stepper.state.omega_body, atol=1e-12)


def test_returned_arrays_belong_to_the_caller() -> None:
    stepper = RealtimeStepper(HEAVY, State(R0, np.array([0.3, 0.2, 3.0])))
    first = stepper.step(1 / 60)
    reference = RealtimeStepper(HEAVY, State(R0, np.array([0.3, 0.2, 3.0])))
    reference.step(1 / 60)
    first.R_space_body[:] = 0.0  # the stepper keeps its own floats
    assert_same(stepper.step(1 / 60), reference.step(1 / 60))


def test_simulate_realtime_uses_the_stepper() -> None:
    state0 = State(R0, np.array([0.3, 0.2, 3.0]))
    traj = simulate_realtime(HEAVY, state0, 1.0, 1 / 60)
    alone = run_alone(HEAVY, state0, [1 / 60] * 60)
    assert np.array_equal(traj.R_space_body[1:], np.array([s.R_space_body for s in alone]))
    assert traj.evaluations == 60 * STAGES[4]


def test_bad_dt_and_too_many_substeps() -> None:
    stepper = RealtimeStepper(HEAVY, State(R0, np.array([0.3, 0.2, 3.0])))
    for dt in (0.0, -1.0, math.inf, math.nan):
        with pytest.raises(ValueError, match="dt"):
            stepper.step(dt)
    fast = RealtimeStepper(FREE, State(R0, np.array([0.0, 0.0, 3e5])))
    with pytest.raises(IntegrationError, match="MAX_SUBSTEPS"):
        fast.step(1 / 60)
    assert MAX_SUBSTEPS == 1000
    with pytest.raises(ValueError, match="order"):
        RealtimeStepper(HEAVY, fast.state, order=3)


# --- the lean frames (issue 16): same floats, less work per frame --------------------------------

LEAN_CASES = {
    "free body": (FREE, [0.5, 0.2, 1.5]),
    "heavy asymmetric top (gravity on work axis x: merged remainders)": (HEAVY, [0.3, 0.2, 3.0]),
    "heavy symmetric top": (Model((1.0, 1.0, 0.5), mgl=2.0), [0.3, 0.0, 12.0]),
    "constant torque (rate re-evaluated every frame)": (Model((2.0, 1.5, 1.0), torque_space=(0.1, -0.2, 0.3)),
                                                        [0.5, -0.4, 2.0]),
    "fast spin (sub-steps)": (FREE, [300.0, 200.0, 950.0]),
}


@pytest.mark.parametrize("name", list(LEAN_CASES))
def test_step_many_equals_step_after_step_bit_for_bit(name: str) -> None:
    model, omega0 = LEAN_CASES[name]
    state0 = State(R0, np.array(omega0))
    dt, frames = 1.0 / 240.0, 50
    alone = run_alone(model, state0, [dt] * frames)
    stepper = RealtimeStepper(model, state0)
    R, omega, evaluations = stepper.step_many(dt, frames)
    assert np.array_equal(R, np.array([s.R_space_body for s in alone]))
    assert np.array_equal(omega, np.array([s.omega_body for s in alone]))
    assert_same(stepper.state, alone[-1])
    reference = RealtimeStepper(model, state0)
    counted = 0
    for _ in range(frames):
        reference.step(dt)
        counted += reference.evaluations
    assert evaluations == counted and stepper.evaluations == reference.evaluations
    assert_same(stepper.step(dt), reference.step(dt))  # and it carries on as the stepper would


def test_step_many_refuses_bad_input_and_stops_at_the_last_good_frame() -> None:
    stepper = RealtimeStepper(HEAVY, State(R0, np.array([0.3, 0.2, 3.0])))
    before = stepper.state
    for dt, frames in ((0.0, 3), (math.nan, 3), (1 / 60, 0)):
        with pytest.raises(ValueError):
            stepper.step_many(dt, frames)
    assert stepper.state is before and stepper.t == 0.0  # nothing changed
    # A hook that runs away: the blow-up check stops the run; the stepper keeps the frames before it.
    runaway = Model((1.0, 1.5, 2.0), extra_torque=lambda t, R, w: R @ (50.0 * np.array([1.0, 1.5, 2.0]) * w))
    stepper = RealtimeStepper(runaway, State(R0, np.array([0.3, 0.2, 3.0])))
    with pytest.raises(IntegrationError):
        stepper.step_many(1 / 60, 10_000)
    reached = stepper.t
    assert 0.0 < reached < 10_000 / 60
    alone = RealtimeStepper(runaway, State(R0, np.array([0.3, 0.2, 3.0])))
    for _ in range(round(reached * 60)):
        alone.step(1 / 60)
    assert_same(stepper.state, alone.state)


@pytest.mark.parametrize("name", list(LEAN_CASES))
def test_peek_is_the_step_it_does_not_take(name: str) -> None:
    """A peek (kernel taking h as an argument) gives the floats a step of the same dt gives (a
    kernel with h folded in), sub-steps included, and leaves the stepper where it was."""
    model, omega0 = LEAN_CASES[name]
    a = RealtimeStepper(model, State(R0, np.array(omega0)))
    b = RealtimeStepper(model, State(R0, np.array(omega0)))
    for dt in (1 / 240, 1 / 60, 0.0123, 1 / 240):
        peeked = a.peek(dt)
        assert a.t == b.t
        assert_same(peeked, b.step(dt))
        a.step(dt)


def test_simulate_realtime_samples_are_the_stepper_states_at_1_240() -> None:
    state0 = State(R0, np.array([0.5, 0.2, 1.5]))
    traj = simulate_realtime(FREE, state0, 0.5, 1 / 240)
    alone = run_alone(FREE, state0, [1 / 240] * 120)
    assert len(traj.t) == 121 and np.array_equal(traj.R_space_body[0], R0)
    assert np.array_equal(traj.R_space_body[1:], np.array([s.R_space_body for s in alone]))
    assert np.array_equal(traj.omega_body[1:], np.array([s.omega_body for s in alone]))
    assert traj.evaluations == 120 * STAGES[4]
