"""Real-time stepping: the app's frame-by-frame integration with automatic sub-steps.

`RealtimeStepper(model, state)` owns its state as plain floats between frames (the working-
frame quaternion and L_b of `physics.splitting`, and t) and advances it by one display step at
a time with the 4th-order splitting, in n = max(1, ceil(dt Ω / max_substep_angle)) equal
sub-steps, Ω = `physics.guards.rate_scale`.  Each stepper keeps its own caches: two steppers,
on equal models or the same one, never share state, so no lock is needed (one stepper is not
meant to be stepped from two threads at once).

`GridStepper(model, state)` is the app's: it steps a `RealtimeStepper` in whole steps of a fixed
h = NOMINAL_STEP and shows the time between grid points by a `RealtimeStepper.peek`, so that the
trajectory does not depend on the frame rate or on the frames' jitter (see its docstring).

`RealtimeStepper.step_many(dt, frames)` is `frames` steps at once, the same floats as step after
step, returned as arrays without a State per frame: the CLI's `simulate_realtime` (issue 16: about
1.5-1.8 ms of wall per simulated second at 1/240 s on the free body and the asymmetric heavy top,
against 2.2-2.8 with a State per frame; `benchmarks/realtime_cost.py`).

`step_realtime(model, state, dt)` is the same step as a pure function of (model, state); it
builds a stepper per call, so it validates and converts the state every time (a stepper skips
that: keep one per simulation).
"""

from __future__ import annotations

import math
from itertools import chain

import numpy as np

from physics.dynamics import IntegrationError, Model, State
from physics.guards import omega_limit, validated_state
from physics.splitting import CHECK_EVERY, STAGES, Kernel, Splitting, StepKernel, gammas_of, state_builder

__all__ = ["GRID_TOLERANCE", "MAX_SUBSTEPS", "NOMINAL_STEP", "REALTIME_SUBSTEP_ANGLE", "GridStepper", "RealtimeStepper",
           "step_realtime"]

REALTIME_SUBSTEP_ANGLE = 0.25
"""Real-time sub-step bound: h Ω <= this [rad] per sub-step, Ω = `rate_scale`.

Chosen for order 4 from measurements (tests/test_integrators.py repeats the worst): the
attitude error grows like C (h Ω)^4 Ω t with C <= 1e-6 on every hard case (worst: a free
asymmetric body spinning at 1000 rad/s about a generic axis), and |ΔE/E| <= 2e-6 (h Ω)^4.  At
0.25 rad that is <= 4e-9 rad per radian turned (1e-3 rad after 2.5e5 rad, e.g. 4 min at
1000 rad/s) and |ΔE/E| <= 1e-8.  A moderate scene (Ω < 60 rad/s at 1/240 s, < 15 rad/s at
1/60 s) never sub-steps.  For order 2 pass a smaller bound: its error is C2 (h Ω)^2 Ω t with
C2 up to 1e-3."""

MAX_SUBSTEPS = 1000
"""A real-time step needing more sub-steps than this raises IntegrationError: |ω| beyond
~1.5e4 rad/s at 1/60 s (6e4 at 1/240 s), far past anything a display can show, and a frame
must stay short (1000 sub-steps ~ 15 ms without a hook) even when a torque hook runs away."""

_FRAMES_KEPT = 64  # distinct (dt, sub-steps) kernels a stepper keeps


class RealtimeStepper:
    """Advances one rigid body frame by frame; owns its state between frames.

    Attributes (read them, do not assign):
        state: the current State (R_space_body (3, 3), omega_body (3,), t [s]); fresh arrays each
            step, built from the internal floats (changing them does not affect the stepper).
        substeps: sub-steps taken by the last `step` (0 before the first).
        evaluations: Strang stages of the last `step` (= torque evaluations when there is a
            torque), substeps * stages_per_substep.
        stages_per_substep: Strang stages per sub-step of the composition (5 for order 4).
        model: the Model stepped.

    For the free body and the heavy top Ω depends on the energy only, which the splitting
    conserves to ~1e-12, so Ω and the sub-step count are fixed when the stepper is built; for
    other torques Ω is re-evaluated every step from |ω_b|.  The blow-up limit is
    max(OMEGA_LIMIT, OMEGA_GROWTH Ω0) with Ω0 the rate scale at construction.
    """

    __slots__ = (
        "_conservative", "_fin", "_frames", "_gammas", "_invariant", "_limit", "_make_state", "_max_angle", "_peek",
        "_rate", "_sp", "_state", "_t", "_y", "evaluations", "model", "stages_per_substep", "substeps",
    )  # fmt: skip

    def __init__(
        self, model: Model, state: State, max_substep_angle: float = REALTIME_SUBSTEP_ANGLE, order: int = 4
    ) -> None:
        """Raises IntegrationError for a bad or non-finite state, ValueError for a bad order or
        max_substep_angle."""
        if not (math.isfinite(max_substep_angle) and max_substep_angle > 0.0):
            raise ValueError(f"max_substep_angle must be positive and finite, got {max_substep_angle}")
        self._gammas = gammas_of(order)
        r, w, t = validated_state(state)
        sp = Splitting(model)
        self._sp = sp
        self.model = model
        self._y: tuple[float, ...] = tuple(sp.work_from_body(r, w))
        self._t = t
        self._invariant = sp.invariant(self._y)
        self._rate = sp.rate_scale(r[8], w)
        self._limit = omega_limit(self._rate)
        self._conservative = model.conservative
        self._max_angle = max_substep_angle
        self._fin = sp.finish_args(self._limit, self._invariant)
        self._frames: dict[object, tuple[Kernel, int, float]] = {}
        self._make_state = state_builder(sp)
        self._state: State | None = state  # None: not built since the last step (see `state`)
        self._peek: StepKernel | None = None
        self.stages_per_substep = STAGES[order]
        self.substeps = 0
        self.evaluations = 0

    @property
    def t(self) -> float:
        """The current time [s]."""
        return self._t

    @property
    def state(self) -> State:
        """The current State (the one the last `step` returned, or the initial one; after
        `step_many` or a `GridStepper`'s grid steps it is built from the floats when first read)."""
        state = self._state
        if state is None:
            state = self._state = self._make_state(self._y, self._t)
        return state

    def step(self, dt: float) -> State:
        """Advance by dt [s] of simulated time (sub-stepping as needed) and return the new state.

        The sub-steps run in generated straight-line code (`Splitting.kernel`), one kernel per
        (dt, sub-step count) kept by the stepper; the State is built from the floats once.

        Raises:
            ValueError: dt not positive and finite.
            IntegrationError: a non-finite state, a blow-up, or more than MAX_SUBSTEPS
                sub-steps needed (|ω| far beyond anything a display can show).
        """
        y, n = self._run(dt)
        self._y = y
        t = self._t = self._t + dt
        self.substeps = n
        self.evaluations = n * self.stages_per_substep
        state = self._state = self._make_state(y, t)
        return state

    def step_many(self, dt: float, frames: int) -> tuple[np.ndarray, np.ndarray, int]:
        """`frames` calls of `step(dt)` at once, for a run that records every frame (the CLI's
        `simulate_realtime`): the same floats bit for bit, without a State per frame.

        Returns (R_space_body (frames, 3, 3), omega_body (frames, 3) [rad/s] after each step,
        Strang stages used by all of them).  Same errors as `step`; after an IntegrationError the
        stepper is at the last frame reached.  `state`, `substeps` and `evaluations` are then
        those of the last step, as after `step`.
        """
        if frames < 1:
            raise ValueError(f"frames must be a positive integer, got {frames}")
        ys: list[tuple[float, ...]] = []
        append = ys.append
        stages = self.stages_per_substep
        evaluations = n = 0
        frame = self._frames.get(dt) if self._conservative else None
        if frame is None and self._conservative:
            frame = self._frame(dt)
        if frame is not None and frame[1] <= CHECK_EVERY:
            # A conservative model: one kernel, one sub-step count for every frame.
            kernel, n, _h = frame
            y, t, fin = self._y, self._t, self._fin
            try:
                for _ in range(frames):
                    y = kernel(y, t, n, fin)
                    t += dt
                    append(y)
            finally:  # after a failure too: the stepper stays at the last good frame
                if ys:
                    self._y, self._t, self._state = y, t, None
            evaluations = frames * n * stages
        else:
            try:
                for _ in range(frames):
                    y, n = self._run(dt)
                    self._y = y
                    self._t += dt
                    append(y)
                    evaluations += n * stages
            finally:
                if ys:
                    self._state = None
        self.substeps = n
        self.evaluations = n * stages
        rows = np.fromiter(chain.from_iterable(ys), float, 7 * len(ys)).reshape(-1, 7)  # 3x faster than np.array
        R, omega = self._sp.body_arrays_from_work(rows)
        return R, omega, evaluations

    def peek(self, dt: float) -> State:
        """The state dt [s] after the current one, without advancing: the stepper stays where
        it is (same sub-step rule, errors and numbers as `step`; `substeps` counts this call's
        sub-steps).  Runs `Splitting.step_kernel` (the step size is an argument), so a dt seen
        once costs no kernel of its own."""
        n = self._count(dt)
        h = dt / n
        step = self._peek
        if step is None:
            step = self._peek = self._sp.step_kernel(self._gammas)
        t0 = self._t
        y, fin = self._y, self._fin
        if n <= CHECK_EVERY:
            y = step(y, t0, n, fin, h)
        else:
            done = 0
            while done < n:
                chunk = min(CHECK_EVERY, n - done)
                y = step(y, t0 + done * h, chunk, fin, h)
                done += chunk
        self.substeps = n
        self.evaluations = n * self.stages_per_substep
        return self._make_state(y, t0 + dt)

    def _advance(self, dt: float) -> None:
        """`step(dt)` without building the State (`state` builds it when read)."""
        y, n = self._run(dt)
        self._y = y
        self._t += dt
        self._state = None
        self.substeps = n
        self.evaluations = n * self.stages_per_substep

    def _run(self, dt: float, keep: bool = True) -> tuple[tuple[float, ...], int]:
        """(y after dt [s] from the current y, sub-steps n); changes nothing but the caches
        (keep=False: not even the stepper's own, for a dt seen once, such as a peek's)."""
        # A conservative model's sub-step count depends on dt only (Ω is fixed): key dt.  A bad
        # dt (0, negative, inf, NaN) is never a key, so `_frame` validates it.
        frame = self._frames.get(dt) if self._conservative else None
        if frame is None:
            frame = self._frame(dt, keep)
        kernel, n, h = frame
        t0 = self._t
        if n <= CHECK_EVERY:
            return kernel(self._y, t0, n, self._fin), n
        y, t, done = self._y, t0, 0
        while done < n:
            chunk = min(CHECK_EVERY, n - done)
            y = kernel(y, t, chunk, self._fin)
            done += chunk
            t = t0 + done * h
        return y, n

    def _count(self, dt: float) -> int:
        """Sub-steps n for a display step dt [s] from the current state (ValueError for a bad dt,
        IntegrationError beyond MAX_SUBSTEPS)."""
        if not 0.0 < dt < math.inf:
            raise ValueError(f"display step dt must be positive and finite, got {dt}")
        if not self._conservative:
            r, w = self._sp.body_from_work(self._y)
            self._rate = self._sp.rate_scale(r[8], w)
        n: int = math.ceil(dt * self._rate / self._max_angle) or 1
        if n > MAX_SUBSTEPS:
            raise IntegrationError(
                f"at t = {self._t:.9g} s the rate scale {self._rate:.3g} rad/s needs {n} sub-steps per display "
                f"step of {dt:g} s, more than MAX_SUBSTEPS = {MAX_SUBSTEPS}: a blow-up, or a spin too fast for "
                "real time"
            )
        return n

    def _frame(self, dt: float, keep: bool = True) -> tuple[Kernel, int, float]:
        """(kernel, sub-steps n, sub-step h) for a display step dt, made and (keep) kept on first use."""
        n = self._count(dt)
        key: object = dt if self._conservative else (dt, n)
        frame = self._frames.get(key)
        if frame is None:
            h = dt / n
            frame = (self._sp.kernel(h, self._gammas), n, h)
            if keep:
                if len(self._frames) >= _FRAMES_KEPT:
                    self._frames.clear()
                self._frames[key] = frame
        return frame


NOMINAL_STEP = 1.0 / 60.0
"""[s] of simulated time: the fixed step of `GridStepper` (the app's), the display step at which
REALTIME_SUBSTEP_ANGLE was tuned and the accuracy figures in docs/performance.md were measured."""

GRID_TOLERANCE = 1e-9
"""A time within this fraction of a step of a grid point is on it (frames of exactly h, summed
in floating point, land on the grid and need no peek)."""


class GridStepper:
    """Real-time stepping that does not depend on the frame rate: whole steps of a fixed h.

    Why: the splitting is symplectic.  At a fixed step it conserves a modified energy within
    O(h⁴) of E, and its attitude error grows like C (h Ω)⁴ Ω t.  A step that changes from
    frame to frame (a real loop's frame times jitter) changes that modified energy every
    frame, so the energy error walks and the phase error grows far faster.  Measured with
    `RealtimeStepper.step(dt)` on the Free body "Dzhanibekov" preset (its flip period is very
    sensitive to E): after 25 s the attitude error is 1.4e-7 rad at a fixed 1/60 s, 5.3e-7 at
    a fixed 1/15 s, but 4.6e-5 with frame times uniform in ±20 % of 1/60 s and 1.5e-3 with
    ±20 % of 1/15 s (tests/test_frame_rate.py).

    So the committed state moves only in whole steps h (each sub-stepped by the angle rule of
    `RealtimeStepper`), the same steps whatever the frames, and the state at a time between
    two grid points is a `RealtimeStepper.peek` from the last one, shown and never committed:
    the trajectory on the grid is independent of the frame rate, a long frame is stepped in
    steps no longer than h, and the shown state is within one short step of it.

    Attributes (read them, do not assign):
        state: the state at the time asked last (t = the sum of the steps' dt, from the start).
        substeps, evaluations: sub-steps and Strang stages of the last `step`, grid and peek.
        h: the grid step [s].  model: the Model stepped.
    """

    __slots__ = ("_grid", "_k", "_state", "_t0", "evaluations", "h", "model", "substeps")

    def __init__(self, model: Model, state: State, h: float = NOMINAL_STEP,
                 max_substep_angle: float = REALTIME_SUBSTEP_ANGLE, order: int = 4) -> None:
        """Same errors as `RealtimeStepper`; ValueError for h not positive and finite."""
        if not (math.isfinite(h) and h > 0.0):
            raise ValueError(f"the grid step h must be positive and finite, got {h}")
        self._grid = RealtimeStepper(model, state, max_substep_angle, order)
        self.model = model
        self.h = h
        self._t0 = self._grid.t
        self._k = 0  # grid steps taken: the grid is at t0 + k h
        self._state = state
        self.substeps = 0
        self.evaluations = 0

    @property
    def t(self) -> float:
        """The current time [s] (of `state`)."""
        return self._state.t

    @property
    def state(self) -> State:
        return self._state

    def step(self, dt: float) -> State:
        """Advance by dt [s]: the grid steps whole steps h up to t + dt, then peeks the rest.

        Raises ValueError (dt not positive and finite) and IntegrationError as `RealtimeStepper`
        (also when a dt would need more than MAX_SUBSTEPS grid steps).  After an IntegrationError
        the state is the last grid point reached.
        """
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"display step dt must be positive and finite, got {dt}")
        h = self.h
        grid = self._grid
        target = self._state.t + dt
        steps = math.floor((target - (self._t0 + self._k * h)) / h + GRID_TOLERANCE)
        if steps > MAX_SUBSTEPS:
            raise IntegrationError(f"a display step of {dt:g} s needs {steps} steps of {h:g} s, more than "
                                   f"MAX_SUBSTEPS = {MAX_SUBSTEPS}")
        substeps = evaluations = 0
        try:
            for _ in range(steps):
                grid._advance(h)  # no State for a grid point that a peek or the next step passes
                self._k += 1
                substeps += grid.substeps
                evaluations += grid.evaluations
            rest = target - (self._t0 + self._k * h)
            if rest > GRID_TOLERANCE * h:
                state = grid.peek(rest)
                substeps += grid.substeps
                evaluations += grid.evaluations
            else:  # on the grid: its state, shown at the time asked
                state = grid._make_state(grid._y, target)
        except IntegrationError:
            self._state = grid.state
            raise
        self._state = state
        self.substeps, self.evaluations = substeps, evaluations
        return state


    # ------------------------------------------------------------------ replay
    def snapshot(self) -> tuple[float, ...]:
        """Everything that changes as the stepper steps, as floats (ints exact below 2**53): the
        grid index k, the state shown (R (9), ω_b (3), t), the counters, the grid stepper's
        working state y, its t, its state (R, ω_b, t) and rate scale.  `restore` puts it back
        bit for bit; the rest (model, h, kernels, invariant, blow-up limit) is fixed for the
        stepper's life, so a snapshot is only restored into the stepper that made it."""
        grid = self._grid
        shown, at_grid = self._state, grid.state
        return (float(self._k), *shown.R_space_body.ravel().tolist(), *shown.omega_body.tolist(), shown.t,
                float(self.substeps), float(self.evaluations), float(len(grid._y)), *grid._y, grid._t,
                *at_grid.R_space_body.ravel().tolist(), *at_grid.omega_body.tolist(), at_grid.t, grid._rate,
                float(grid.substeps), float(grid.evaluations))

    def restore(self, values: tuple[float, ...] | list[float]) -> None:
        """Put back what `snapshot` returned (ValueError, nothing changed, if it does not fit)."""
        n = len(self._grid._y)
        if len(values) != 2 * 13 + 7 + n + 1 or int(values[16]) != n:
            raise ValueError(f"not a snapshot of this stepper ({len(values)} values)")

        def state(at: int) -> State:
            R = np.array(values[at: at + 9], dtype=float).reshape(3, 3)
            return State(R, np.array(values[at + 9: at + 12], dtype=float), float(values[at + 12]))

        grid = self._grid
        self._k = int(values[0])
        self._state = state(1)
        self.substeps, self.evaluations = int(values[14]), int(values[15])
        grid._y = tuple(float(v) for v in values[17: 17 + n])
        grid._t = float(values[17 + n])
        grid._state = state(18 + n)
        grid._rate = float(values[31 + n])
        grid.substeps, grid.evaluations = int(values[32 + n]), int(values[33 + n])


def step_realtime(
    model: Model,
    state: State,
    dt: float,
    max_substep_angle: float = REALTIME_SUBSTEP_ANGLE,
    order: int = 4,
) -> tuple[State, int]:
    """Advance `state` by one display step dt [s]: `RealtimeStepper(model, state).step(dt)`.

    A pure function (nothing is cached between calls).  Returns (new state at t + dt,
    evaluations = Strang stages used).  Same errors as
    `RealtimeStepper` and its `step`.
    """
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"display step dt must be positive and finite, got {dt}")
    stepper = RealtimeStepper(model, state, max_substep_angle, order)
    new = stepper.step(dt)
    return new, stepper.evaluations
