"""The registry of ways to compute a motion, each with its order and what it conserves.

`simulate(model, state0, t, method)` runs one by name; `default_method(model)` is the most
accurate the project has for that model (the exact solution where one exists).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from physics.dynamics import Model, State, Trajectory

__all__ = ["Method", "default_method", "exact_solution", "methods", "simulate"]


@dataclass(frozen=True)
class Method:
    """name; summary: one line on its order and what it conserves; applies: which models."""

    name: str
    summary: str
    applies: Callable[[Model], bool]
    run: Callable[[Model, State, np.ndarray], Trajectory]


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


def _registry() -> dict[str, Method]:
    from physics import integrators, lagrange

    always = lambda model: True  # noqa: E731
    return {
        method.name: method
        for method in (
            Method("exact", "closed form (elliptic functions): exact to rounding; free body and "
                   "heavy symmetric top only", _has_closed_form, _run_exact),
            Method("splitting4", "4th-order symplectic splitting, fixed step with sub-steps: "
                   "exact |L| (free) and L·e_z (top), no energy drift; the real-time method",
                   always, lambda m, s, t: integrators.integrate_splitting(m, s, t)),
            Method("adaptive", "adaptive high-order Runge-Kutta on the singularity-free state "
                   "(rtol 1e-12): accurate to the tolerance, conserves nothing exactly",
                   always, lambda m, s, t: integrators.integrate_adaptive(m, s, t)),
            Method("dop853", "scipy solve_ivp DOP853 (8th order, adaptive) on the quaternion ODE "
                   "(rtol 1e-12): the usual choice, for comparison", always,
                   lambda m, s, t: integrators.integrate_dop853(m, s, t)),
            Method("euler_lagrange", "Lagrange's equations in z-x-z angles (memo 5.13, 6.4, 6.10), "
                   "adaptive scipy solver: literal and for teaching; fails at sin θ = 0",
                   always, lambda m, s, t: lagrange.integrate_euler_lagrange(m, s, t)),
        )
    }


@functools.cache
def methods() -> dict[str, Method]:
    """The registry by name (built on first use so importing `physics` stays cheap)."""
    return _registry()


def default_method(model: Model) -> str:
    """'exact' where a closed form exists, else the accurate adaptive method."""
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
