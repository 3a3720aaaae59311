"""The generated straight-line kernel (`Splitting.kernel`, used by `RealtimeStepper`) against
the plain interpreted splitting (`Splitting.program` + `Splitting.run` + `Splitting.finish`):
the same scheme, so the same numbers to rounding over 1000 frames."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from physics.dynamics import Model, State
from physics.guards import omega_limit, validated_state
from physics.realtime import REALTIME_SUBSTEP_ANGLE, RealtimeStepper
from physics.splitting import COMPOSITIONS, Splitting

R0 = Rotation.from_euler("ZXZ", [0.3, 0.4, -0.2]).as_matrix()

CASES = {
    # name: (model, ω0 [rad/s]); symmetric and asymmetric, free and heavy, every axis order
    "free asymmetric": (Model((1.0, 2.0, 2.5)), [0.5, 0.2, 1.5]),
    "free symmetric": (Model((1.0, 1.0, 2.0)), [0.7, -0.2, 1.5]),
    "free odd permutation": (Model((2.0, 1.0, 1.5)), [0.3, 1.0, 0.2]),
    "heavy symmetric top": (Model((1.0, 1.0, 0.5), mgl=2.0), [0.3, 0.0, 12.0]),
    "heavy asymmetric top": (Model((1.0, 1.5, 2.0), mgl=1.0), [0.3, 0.2, 3.0]),
    "heavy, gravity on work axis 0": (Model((1.5, 2.0, 1.0), mgl=1.0), [0.3, 0.2, 3.0]),
    "heavy, gravity on work axis 1": (Model((2.0, 1.0, 1.5), mgl=1.0), [0.3, 0.2, 3.0]),
    "gravity + constant torque": (Model((2.0, 1.5, 1.0), mgl=0.7, torque_space=(0.1, -0.2, 0.3)), [0.5, -0.4, 2.0]),
    "hook": (Model((1.0, 1.2, 2.0), extra_torque=lambda t, R, w: R @ (-0.1 * w) + np.array([0.0, 0.1 * t, 0.0])),
             [0.5, -0.4, 2.0]),
    "sub-stepped fast asymmetric spin": (Model((1.0, 1.5, 2.0)), [300.0, 200.0, 950.0]),
    "sub-stepped fast heavy top": (Model((1.0, 1.0, 0.5), mgl=1.0), [0.0, 0.0, 1000.0]),
}  # fmt: skip


def plain_frames(model: Model, state0: State, dt: float, frames: int, order: int = 4) -> list[list[float]]:
    """y (7,) after each frame by the interpreted stage loop: the reference implementation."""
    sp = Splitting(model)
    r, w, t = validated_state(state0)
    y = sp.work_from_body(r, w)
    invariant = sp.invariant(y)
    rate = sp.rate_scale(r[8], w)
    limit = omega_limit(rate)
    out = []
    for _ in range(frames):
        if not model.conservative:
            rb, wb = sp.body_from_work(y)
            rate = sp.rate_scale(rb[8], wb)
        n = math.ceil(dt * rate / REALTIME_SUBSTEP_ANGLE) or 1
        y, _ = sp.run(sp.program(dt / n, n, COMPOSITIONS[order]), y, t)
        t += dt
        y = sp.finish(y, t, limit, invariant)
        out.append(y)
    return out


@pytest.mark.parametrize("order", [2, 4, 6])
@pytest.mark.parametrize("name", list(CASES))
def test_generated_kernel_equals_the_plain_splitting(name: str, order: int) -> None:
    model, omega0 = CASES[name]
    state0 = State(R0, np.array(omega0, dtype=float))
    dt = 1.0 / 240.0
    frames = 1000 if order == 4 else 200
    if "fast" in name:
        frames //= 10  # ~20 sub-steps per frame
    expected = plain_frames(model, state0, dt, frames, order)
    stepper = RealtimeStepper(model, state0, order=order)
    scale = max(1.0, float(np.linalg.norm(np.array(model.inertia) * omega0)))
    worst = 0.0
    for k in range(frames):
        state = stepper.step(dt)
        got = np.array(stepper._y)  # the working-frame floats
        worst = max(worst, float(np.max(np.abs(got - expected[k]) / [1, 1, 1, 1, scale, scale, scale])))
        if k == frames - 1:  # the State built from them is body_from_work's
            r, w = Splitting(model).body_from_work(expected[k])
            np.testing.assert_allclose(state.R_space_body, np.reshape(r, (3, 3)), rtol=0.0, atol=1e-12)
            np.testing.assert_allclose(state.omega_body, w, rtol=0.0, atol=1e-12 * scale)
    if "fast" in name:
        assert stepper.substeps > 10
    # Rounding only (products regrouped, |L| and L_z of a step computed once): ~1e-16 per step,
    # amplified along the chaotic motions; a wrong constant would show at 1e-6.
    assert worst < 1e-12, worst


def test_kernels_are_shared_but_steppers_are_not() -> None:
    """Two steppers on equal models reuse one kernel (a pure function) yet keep their own state."""
    model = Model((1.0, 1.5, 2.0), mgl=1.0)
    a = RealtimeStepper(model, State(R0, np.array([0.3, 0.2, 3.0])))
    b = RealtimeStepper(Model((1.0, 1.5, 2.0), mgl=1.0), State(R0, np.array([0.3, 0.2, 3.0])))
    a.step(1 / 240)
    b.step(1 / 240)
    assert a._frames[1 / 240][0] is b._frames[1 / 240][0]
    a.step(1 / 240)
    assert a.t != b.t and not np.array_equal(a.state.R_space_body, b.state.R_space_body)
