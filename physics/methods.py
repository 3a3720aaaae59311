"""The registry of ways to compute a motion, each with its order and what it conserves: the
one list the command line (`python -m physics methods`, `--method NAME`) and the app's
integrator menu read, under the same names.

`simulate(model, state0, t, method)` runs one by name; `default_method(model)` is the most
accurate the project has for that model (the exact solution where one exists).  For the app,
`Method.stepper(model, state, origin)` builds a `Stepper` that advances (R, ω_b) display step by
display step; `applicable(model)` are the names of the methods that apply to a body, in
registry order; `realtime_method()` is the method the app starts with and falls back on.

Adding a method is one entry in `_registry()`, e.g. for a method of any torque

    Method("name", "one line: order, what it conserves", always, run)

with `run(model, state0, t) -> Trajectory`.  `run` is all the command line needs, and by
default the app steps it frame by frame through `run` (`RunStepper`: from the current state to
t + dt, nothing carried between frames but the state), so the new name appears in the CLI and,
for every body it `applies` to, in the app's menu.  Give `start` only when the method carries
more than the state between frames (a fixed grid, a closed form from the run's start:
`GridStepper`, `ExactStepper`) or must refuse a starting state; set `realtime=True` only when
a frame costs a bounded, small time whatever the body does.  A method that cannot go on from a
state where the motion can (a singularity of its coordinates) raises a `GimbalLockError` from
`Stepper.step`: the app then goes on with `realtime_method()`.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from physics.dynamics import Model, State, Trajectory

__all__ = ["ExactStepper", "Method", "RunStepper", "Stepper", "applicable", "default_method", "exact_solution",
           "methods", "realtime_method", "simulate"]

Run = Callable[[Model, State, np.ndarray], Trajectory]
"""run(model, state0, t (N,) [s]) -> the Trajectory sampled at t (t[0] >= state0.t)."""


@runtime_checkable
class Stepper(Protocol):
    """Advances one body display step by display step and owns its state between frames.

    state: the current State (R_space_body (3, 3), omega_body (3,) [rad/s], t [s]).
    substeps: sub-steps taken by the last `step` (0 for a method without them).
    step(dt): the state dt [s] later (dt > 0 and finite, else ValueError; IntegrationError when
        the motion cannot be computed; GimbalLockError where the method's coordinates are
        singular though the motion is not).
    snapshot(): everything that changes as it steps, as floats; restore(values) puts it back
        bit for bit (ValueError, nothing changed, if the values are not this stepper's).
    """

    substeps: int

    @property
    def state(self) -> State: ...

    def step(self, dt: float) -> State: ...

    def snapshot(self) -> tuple[float, ...]: ...

    def restore(self, values: list[float]) -> None: ...


StartStepper = Callable[[Model, State, State], Stepper]
"""start(model, state, origin) -> a Stepper at `state`; origin: the start of the run (a method
whose motion is the closed form follows the closed form from there)."""


def _checked_dt(dt: float) -> float:
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"display step dt must be positive and finite, got {dt}")
    return float(dt)


def _state_floats(state: State) -> tuple[float, ...]:
    return (*np.asarray(state.R_space_body, dtype=float).ravel().tolist(),
            *np.asarray(state.omega_body, dtype=float).tolist(), float(state.t))


def _state_of(values: list[float]) -> State:
    if len(values) != 13:
        raise ValueError(f"not a snapshot of this stepper ({len(values)} values, 13 wanted)")
    return State(np.array(values[:9], dtype=float).reshape(3, 3), np.array(values[9:12], dtype=float),
                 float(values[12]))


class RunStepper:
    """A method's `run` frame by frame: each `step(dt)` is run(model, state, [t + dt]) from the
    current state, so nothing but the state is carried between frames.  substeps is 0."""

    def __init__(self, run: Run, model: Model, state: State) -> None:
        self._run = run
        self.model = model
        self._state = state
        self.substeps = 0

    @property
    def state(self) -> State:
        return self._state

    def step(self, dt: float) -> State:
        state = self._state
        trajectory = self._run(self.model, state, np.array([state.t + _checked_dt(dt)]))
        self._state = State(trajectory.R_space_body[0], trajectory.omega_body[0], float(trajectory.t[0]))
        return self._state

    def snapshot(self) -> tuple[float, ...]:
        """The state: R (9), ω_b (3), t."""
        return _state_floats(self._state)

    def restore(self, values: list[float]) -> None:
        self._state = _state_of(values)


class ExactStepper:
    """The closed form (`exact_solution`) from the run's start `origin`, evaluated at each time
    asked: `step(dt)` is the exact state at state.t + dt, whatever `state` was (a stepper built
    mid-run joins the exact motion at its next step).  substeps is 0.  ValueError (no closed
    form) as `exact_solution`."""

    def __init__(self, model: Model, state: State, origin: State) -> None:
        self._solution = exact_solution(model, origin)
        self._t0 = float(origin.t)
        self._state = state
        self.model = model
        self.substeps = 0

    @property
    def state(self) -> State:
        return self._state

    def step(self, dt: float) -> State:
        t = self._state.t + _checked_dt(dt)
        R, omega = self._solution(np.array([t - self._t0]))
        self._state = State(R[0], omega[0], t)
        return self._state

    def snapshot(self) -> tuple[float, ...]:
        """The state: R (9), ω_b (3), t."""
        return _state_floats(self._state)

    def restore(self, values: list[float]) -> None:
        self._state = _state_of(values)


@dataclass(frozen=True)
class Method:
    """One way to compute a motion.

    name: the registry name (the CLI's --method, the app's menu).  summary: one line on its
    order and what it conserves.  applies(model): whether it can compute this body's motion;
    bodies: the same in words (for messages).  run(model, state0, t): the motion sampled
    at t.  realtime: a frame costs a small, bounded time whatever the body does (the app can
    run it at any display rate).  reference: its motion IS the reference the app measures the
    attitude error against (the closed form), so its error is 0 by definition.  start: how
    the app's `Stepper` is built (None: `RunStepper` over `run`).
    """

    name: str
    summary: str
    applies: Callable[[Model], bool]
    run: Run
    bodies: str = "any torque"
    realtime: bool = False
    reference: bool = False
    start: StartStepper | None = None

    def __post_init__(self) -> None:
        for part in (self.run, self.start):
            name = getattr(part, "__qualname__", "")
            if part is not None and ("<" in name or "." in name):
                raise TypeError(f"method {self.name!r}: {name} must be a function defined at the top level of "
                                "its module (a room saved as bytes names it; the codec refuses a lambda or a "
                                "nested function)")

    def stepper(self, model: Model, state: State, origin: State | None = None) -> Stepper:
        """A Stepper for `model` at `state`; origin: the run's start (default: state).
        ValueError if the method does not apply to the model or cannot start from `state`."""
        if not self.applies(model):
            raise ValueError(f"{self.name} does not apply to a {model.kind} model with inertia {model.inertia} "
                             f"(it applies to: {self.bodies})")
        if self.start is None:
            return RunStepper(self.run, model, state)
        return self.start(model, state, state if origin is None else origin)


def _has_closed_form(model: Model) -> bool:
    return model.kind == "free" or (model.kind == "heavy_top" and model.inertia[0] == model.inertia[1])


def exact_solution(model: Model, state0: State) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """The closed-form motion t -> (R_space_body (N,3,3), omega_body (N,3)) for a model with one
    (torque-free body; heavy symmetric top).  ValueError otherwise."""
    from physics.exact_free import FreeBodyExact
    from physics.exact_top import HeavySymmetricTopExact

    if model.kind == "free":
        return FreeBodyExact(np.array(model.inertia), state0.R_space_body, state0.omega_body)
    if _has_closed_form(model):
        I1, _, I3 = model.inertia
        return HeavySymmetricTopExact(I1, I3, model.mgl, state0.R_space_body, state0.omega_body)
    raise ValueError(f"no closed-form solution for a {model.kind} model with inertia {model.inertia}")


def _run_exact(model: Model, state0: State, t: np.ndarray) -> Trajectory:
    """The closed form, timed like the integrators: the solution's set-up and evaluation, not
    the imports (`exact_solution` imports its module on first use, outside the clock)."""
    import physics.exact_free  # noqa: F401
    import physics.exact_top  # noqa: F401

    start = time.perf_counter()
    solution = exact_solution(model, state0)
    R, omega = solution(np.asarray(t) - state0.t)
    return Trajectory(np.asarray(t), R, omega, 0, time.perf_counter() - start, "exact")


def _start_grid(model: Model, state: State, origin: State) -> Stepper:
    from physics.realtime import GridStepper

    return GridStepper(model, state)


def _start_exact(model: Model, state: State, origin: State) -> Stepper:
    return ExactStepper(model, state, origin)


def _start_euler_lagrange(model: Model, state: State, origin: State) -> Stepper:
    """A RunStepper, refused (EulerLagrangeSingularityError, a ValueError) where sin θ of the
    state is below the method's stop (`physics.lagrange.SIN_THETA_STOP`)."""
    from physics.euler import euler_zxz_from_matrix
    from physics.lagrange import SIN_THETA_STOP, EulerLagrangeSingularityError, integrate_euler_lagrange

    theta = float(euler_zxz_from_matrix(np.asarray(state.R_space_body, dtype=float))[1])
    if not abs(math.sin(theta)) >= SIN_THETA_STOP:
        raise EulerLagrangeSingularityError(state.t, theta, " (the starting state)")
    return RunStepper(integrate_euler_lagrange, model, state)


# The runs by name (not lambdas): a stepper that holds one can be encoded by reference (app.codec).
def _always(model: Model) -> bool:
    return True


def _run_splitting(m: Model, s: State, t: np.ndarray) -> Trajectory:
    from physics import integrators

    return integrators.integrate_splitting(m, s, t)


def _run_free_kick(m: Model, s: State, t: np.ndarray) -> Trajectory:
    from physics import free_kick

    return free_kick.integrate_free_kick(m, s, t)


def _run_adaptive(m: Model, s: State, t: np.ndarray) -> Trajectory:
    from physics import integrators

    return integrators.integrate_adaptive(m, s, t)


def _run_dop853(m: Model, s: State, t: np.ndarray) -> Trajectory:
    from physics import integrators

    return integrators.integrate_dop853(m, s, t)


def _run_euler_lagrange(m: Model, s: State, t: np.ndarray) -> Trajectory:
    from physics import lagrange

    return lagrange.integrate_euler_lagrange(m, s, t)


def _registry() -> dict[str, Method]:
    from physics import free_kick

    always = _always
    return {
        method.name: method
        for method in (
            Method("exact", "closed form (elliptic functions): exact to rounding; free body and "
                   "heavy symmetric top only", _has_closed_form, _run_exact,
                   bodies="torque-free body, heavy symmetric top", realtime=True, reference=True,
                   start=_start_exact),
            Method("splitting4", "4th-order symplectic splitting, fixed step with sub-steps: "
                   "exact |L| (free) and L·e_z (top), no energy drift; the real-time method",
                   always, _run_splitting,
                   realtime=True, start=_start_grid),
            Method("free_kick", "exact free-body drift + torque kicks, Blanes-Moan 6th-order RKN composition "
                   "(11 kicks a step, step from tol 1e-12): symplectic, |L| (free) and L·e_z (top) exact, "
                   "energy bounded; torques of the attitude only", free_kick.applies,
                   _run_free_kick, bodies="any torque but a hook"),
            Method("adaptive", "adaptive high-order Runge-Kutta on the singularity-free state "
                   "(rtol 1e-12): accurate to the tolerance, conserves nothing exactly",
                   always, _run_adaptive),
            Method("dop853", "scipy solve_ivp DOP853 (8th order, adaptive) on the quaternion ODE "
                   "(rtol 1e-12): the usual choice, for comparison", always,
                   _run_dop853),
            Method("euler_lagrange", "Lagrange's equations in z-x-z angles (memo 5.13, 6.4, 6.10), "
                   "adaptive scipy solver: literal and for teaching; fails at sin θ = 0",
                   always, _run_euler_lagrange,
                   start=_start_euler_lagrange),
        )
    }


@functools.cache
def methods() -> dict[str, Method]:
    """The registry by name (built on first use so importing `physics` stays cheap)."""
    return _registry()


def applicable(model: Model) -> list[str]:
    """The names of the methods that apply to `model`, in registry order (the app's menu)."""
    return [name for name, method in methods().items() if method.applies(model)]


def realtime_method() -> str:
    """The method the app starts with and goes on with when another stops: real time, any
    torque, no singularity."""
    return "splitting4"


def default_method(model: Model) -> str:
    """'exact' where a closed form exists, else the accurate adaptive method: on torqued bodies
    it is also the fastest at equal error: `free_kick` (the exact free drift with torque kicks)
    takes 11 drifts a step, each several evaluations' worth of work, where DOP853 takes 12
    evaluations (benchmarks/free_kick_ratio.py measures both)."""
    return "exact" if _has_closed_form(model) else "adaptive"


def simulate(model: Model, state0: State, t: np.ndarray, method: str | None = None) -> Trajectory:
    """Samples of the motion at times t (N,) [s] by the named method (default: `default_method`)."""
    name = method or default_method(model)
    registry = methods()
    if name not in registry:
        raise ValueError(f"unknown method {name!r}; choose one of {', '.join(registry)}")
    chosen = registry[name]
    if not chosen.applies(model):
        raise ValueError(f"method {name!r} does not apply to a {model.kind} model with inertia {model.inertia}")
    return chosen.run(model, state0, np.asarray(t, dtype=float))


def simulate_realtime(model: Model, state0: State, t_end: float, frame_dt: float = 1.0 / 60.0) -> Trajectory:
    """Advance frame by frame with the app's real-time integrator (one `realtime.RealtimeStepper`
    stepped by frame_dt [s], its sub-steps included), one sample per frame from t = 0 to the
    last frame <= t_end: frame k is `stepper.step(frame_dt)` called k times, bit for bit
    (`RealtimeStepper.step_many`, which builds the samples at the end instead of a State per
    frame).  wall_s: the stepper's construction and the frames, samples included."""
    from physics.realtime import RealtimeStepper

    if not frame_dt > 0.0:
        raise ValueError(f"frame dt must be positive, got {frame_dt}")
    n_frames = int(np.floor(t_end / frame_dt + 1e-9)) + 1
    R = np.empty((n_frames, 3, 3))
    omega = np.empty((n_frames, 3))
    start = time.perf_counter()
    stepper = RealtimeStepper(model, state0)
    R[0], omega[0] = state0.R_space_body, state0.omega_body
    evaluations = 0
    if n_frames > 1:
        R[1:], omega[1:], evaluations = stepper.step_many(frame_dt, n_frames - 1)
    wall = time.perf_counter() - start
    return Trajectory(state0.t + frame_dt * np.arange(n_frames), R, omega, evaluations, wall, "realtime")
