"""The simulation of a rigid body for the animated scenes (free body, heavy top): no viser here.

`RigidBodySimulation` owns the model, the state, the integrator (a method of the registry
`physics.methods`, by its name there, stepped through its `Stepper`: for splitting4 the
real-time `physics.realtime.GridStepper`, fixed steps of 1/60 s whatever the frame rate; for
exact the closed form evaluated at the simulated time), the exact solution where one exists
(for the attitude error and the "exact ghost"), the drift references of this run, the plot
samples and the traces of the points a scene follows (`track`: the heavy top's tip, Poinsot's
herpolhode), so that a view built later draws them so far.  `restart(state)` starts a run at
t = 0 from a state it is given, `reset()` goes back to this run's own initial state: a
simulation never reads a widget.  Several views may draw one simulation.  `fork()` is an
exact, independent copy.

Conventions as in `physics` (docs/CONVENTIONS.md): R = R_space_body, z-x-z Euler angles,
hat(ω_b) = Rᵀ Ṙ, L_s = R I ω_b, SI units.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from app.kit.core.common import fork_sharing
from app.kit.core.history import Snapshot
from app.kit.core.samples import SampleBuffer
from app.kit.core.trace import Trace
from physics._types import Vec3
from physics.dynamics import Model, State, angular_momentum_space, energy, kinetic_energy
from physics.euler import GimbalLockError, euler_zxz_from_matrix, euler_zxz_from_matrix_near
from physics.methods import Method, Stepper, exact_solution, methods, realtime_method
from physics.poinsot import flip_times, motion
from physics.so3 import exp_so3, log_so3

__all__ = ["ERROR_BATCH", "R_COLUMNS", "SAMPLE_COLUMNS", "RigidBodySimulation", "magnified_attitude", "turn_angles"]

SAMPLE_COLUMNS = ("E", "T", "V", "L_norm", "L_z", "phi", "theta", "psi", "w1", "w2", "w3",
                  "drift_E", "drift_L", "attitude_error")
R_COLUMNS = tuple(f"R{k}" for k in range(9))
"""Columns the samples also keep: R_space_body row by row, the attitude check's input."""
ERROR_BATCH = 5
"""The attitude error (integrated against the closed form) is worked out for this many samples at
once, when the last of them is taken (sample numbers 5, 10, ... since the run's start): one call
of the closed form for five times instead of five (a call costs about the same whatever the
number of times), so the newest ERROR_BATCH - 1 samples may not have theirs yet (NaN; the plot's line ends
at most 0.4 s of samples earlier)."""
PLOT_CAPACITY = 300  # samples in the sliding window (30 s of wall time at 10 Hz)
PLOT_SPARE = 620  # samples stored beyond it for the replay (62 s at 1×; less at slow motion)

ExactSolution = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
PointOf = Callable[[State], np.ndarray]
"""A followed point (3,) of a state (a module-level function: a fork shares it)."""


def magnified_attitude(R_exact: np.ndarray, R: np.ndarray, k: float) -> np.ndarray:
    """The exact attitude turned by k times the error: R_exact exp(k log(R_exactᵀ R)).

    The error log(R_exactᵀ R) is a rotation vector in body components (R = R_exact exp(error));
    k = 0 gives R_exact, k = 1 gives R itself, k = 10⁶ shows a 1e-7 rad error as 0.1 rad.  The
    angle k |error| is taken modulo 2π (beyond π the magnified error wraps around).
    """
    R_exact = np.asarray(R_exact, dtype=float)
    if not math.isfinite(k) or k < 0.0:
        raise ValueError(f"the magnification k must be finite and >= 0, got {k!r}")
    return R_exact @ exp_so3(k * log_so3(R_exact.T @ np.asarray(R, dtype=float)))


def turn_angles(R_a: np.ndarray, R_b: np.ndarray) -> np.ndarray:
    """The angles [rad] of the turns R_aᵀ R_b, (N, 3, 3) each -> (N,): atan2(|vee(M - Mᵀ)| / 2,
    (tr M - 1) / 2) for M = R_aᵀ R_b, accurate to rounding for small turns as for large ones."""
    M = np.einsum("nji,njk->nik", R_a, R_b)
    vee = np.stack([M[:, 2, 1] - M[:, 1, 2], M[:, 0, 2] - M[:, 2, 0], M[:, 1, 0] - M[:, 0, 1]], axis=-1)
    return np.arctan2(0.5 * np.linalg.norm(vee, axis=-1), 0.5 * (np.trace(M, axis1=1, axis2=2) - 1.0))


class RigidBodySimulation:
    """One rigid body in motion.

    Attributes:
        model: the `physics.dynamics.Model`.  state: the current `State` (t since the restart).
        initial_state, initial_angles: where `reset` goes back to.
        angles: continuous z-x-z angles (φ, θ, ψ) [rad] of the state (φ, ψ unwrapped), for display.
        integrator: the name of the method stepping it (`physics.methods.methods()`; `method` is
            its entry); it starts with `physics.methods.realtime_method()`.  substeps: of the
            last step (0 for a method without sub-steps).
        momentum_kind: "norm" (|L|, conserved by a free body) or "z" (L_z, by a heavy top).
        samples: the plot window; max_drift: the largest |drift| of this run per drift column.
        traces: name -> `Trace` of a followed point (`track`), cleared at every restart.
        restarts, version: counters (a view redraws when `version` changed).
    """

    def __init__(self, model: Model, state: State, *, angles: Vec3 | None = None,
                 momentum_kind: str = "norm") -> None:
        self.model = model
        self.momentum_kind = momentum_kind
        self.preset: str | None = None  # the preset this run started from, if any
        self.mesh: tuple[np.ndarray, np.ndarray] | None = None  # a body's own mesh (handed on), or None
        self.integrator = realtime_method()
        self.substeps = 0
        self.restarts = 0
        self.version = 0
        self.samples = SampleBuffer(SAMPLE_COLUMNS + R_COLUMNS, PLOT_CAPACITY, PLOT_SPARE)
        self.max_drift = {"drift_E": 0.0, "drift_L": 0.0, "attitude_error": 0.0}
        self.traces: dict[str, Trace] = {}
        self._tracked: dict[str, PointOf] = {}
        self.restart(state, angles=angles)

    def track(self, name: str, point_of: PointOf, *, seconds: float, spacing: float, chunk_points: int) -> Trace:
        """Follow `point_of(state)` from now on in `traces[name]` (at every advance; cleared at a
        restart); a name already followed keeps its trace (every view of a scene asks)."""
        if name not in self.traces:
            self.traces[name] = Trace(seconds, spacing, chunk_points)
            self._tracked[name] = point_of
            self.traces[name].add(self.state.t, point_of(self.state))
        return self.traces[name]

    def _record(self) -> None:
        for name, point_of in self._tracked.items():
            self.traces[name].add(self.state.t, point_of(self.state))

    def fork(self) -> RigidBodySimulation:
        """An exact, independent copy: the same t and state bit for bit, initial state, integrator
        with its internal state (the stepper is copied), closed form, drift references and maxima,
        samples, traces, preset, mesh and version; nothing mutable is shared (a handed-on mesh is
        shared read-only).  Advancing both by the same steps gives the same states bit for bit."""
        return fork_sharing(self, self.mesh or ())

    def fork_with(self, refs: tuple[tuple[Any, ...], ...]) -> tuple[RigidBodySimulation, tuple[tuple[Any, ...], ...]]:
        """`fork()` and a copy of snapshots' `refs` made in the same pass: a stepper they share
        with this simulation is the fork's own stepper in the copy (`app.kit.core.history.fork_with_refs`)."""
        fork, copies = fork_sharing((self, refs), self.mesh or ())
        return fork, copies

    # ------------------------------------------------------------------ replay (app.kit.core.history)
    @property
    def run(self) -> int:
        """Changes at every restart (a new run: the replay's history starts afresh)."""
        return self.restarts

    def snapshot(self) -> Snapshot:
        """The moment now: t, R (9), ω_b (3), the shown angles (3), sub-steps, the drift maxima
        (3), the samples' mark, each trace's (count, first), the stepper's floats
        (`physics.methods.Stepper.snapshot`); refs: the integrator's name, its stepper, the
        trace names."""
        state = self.state
        marks = [float(m) for trace in self.traces.values() for m in trace.mark()]
        values = [state.t, *state.R_space_body.ravel().tolist(), *state.omega_body.tolist(),
                  *self.angles.tolist(), float(self.substeps), *self.max_drift.values(),
                  float(self.samples.mark()), *marks, *self._stepper.snapshot()]
        return Snapshot(np.array(values, dtype=float), (self.integrator, self._stepper, tuple(self.traces)))

    def restore(self, snapshot: Snapshot, later: float = 0.0) -> None:
        """The recorded moment back, bit for bit, histories rewound to it; then the state
        `later` [s] further on for display (histories untouched).  ValueError, nothing
        changed, if the snapshot is not one of this run's."""
        integrator, stepper, names = snapshot.refs
        v = snapshot.values
        n_traces = len(names)
        marks_at = 21  # t, R, ω_b, angles, sub-steps, drift maxima, the samples' mark: 21 values
        trace_marks = [(int(v[marks_at + 2 * k]), int(v[marks_at + 2 * k + 1])) for k in range(n_traces)]
        if names != tuple(self.traces) or integrator not in methods() or not isinstance(stepper, Stepper) or not (
                0 <= int(v[20]) <= self.samples.written) or not all(
                self.traces[name].can_rewind(mark) for name, mark in zip(names, trace_marks)):
            raise ValueError("this snapshot is not one of this run's moments")
        stepper.restore(v[marks_at + 2 * n_traces:].tolist())
        self._stepper = stepper
        self.integrator = integrator
        self.state = State(v[1:10].reshape(3, 3).copy(), v[10:13].copy(), float(v[0]))
        self.angles = v[13:16].copy()
        self.substeps = int(v[16])
        self.max_drift = dict(zip(self.max_drift, (float(x) for x in v[17:20])))
        self.samples.rewind(int(v[20]))
        self._recheck_attitudes()
        for name, mark in zip(names, trace_marks):
            self.traces[name].rewind(mark)
        if later > 0.0:
            self._show_later(later)
        self.version += 1

    def _show_later(self, dt: float) -> None:
        """The state dt [s] after a restored moment, for display: the stepper steps (a grid is
        the recorded one, so this is the state the run showed, or would have shown, at t + dt);
        a step that fails (a singular method, IntegrationError) leaves the recorded state shown
        and the method in use."""
        try:
            state = self._stepper.step(dt)
        except (ArithmeticError, ValueError, RuntimeError):  # IntegrationError is a RuntimeError
            return
        self._moved(state)

    def truncate(self) -> None:
        """Forget the histories after now (a branch from a replayed moment)."""
        self.samples.truncate()
        for trace in self.traces.values():
            trace.truncate()

    # ------------------------------------------------------------------ runs
    @property
    def t(self) -> float:
        return self.state.t

    def restart(self, state: State, *, angles: Vec3 | None = None) -> None:
        """Start a new run from `state` at t = 0; drift references, exact solution and samples
        start afresh.  angles: the z-x-z angles [rad] to show (e.g. the sliders' values at
        gimbal lock, where the matrix alone does not fix φ and ψ)."""
        R = np.array(state.R_space_body, dtype=float)
        omega = np.array(state.omega_body, dtype=float)
        self.state = self.initial_state = State(R, omega, 0.0)
        self.initial_angles = (np.array(angles, dtype=float) if angles is not None
                               else euler_zxz_from_matrix(R))
        self.angles = self.initial_angles.copy()
        self._exact: ExactSolution | None = None
        self._exact_at: tuple[float, np.ndarray] | None = None  # (t, R_exact(t)), the last one asked
        self.exact_failed: str | None = None
        self.restarts += 1
        self._E0 = energy(self.model, R, omega)
        self._energy_scale = kinetic_energy(self.model, omega) + abs(self.model.mgl)
        self._momentum0 = self.momentum(R, omega)
        self._momentum_scale = float(np.linalg.norm(angular_momentum_space(self.model, R, omega)))
        self.max_drift = dict.fromkeys(self.max_drift, 0.0)
        try:  # the method in use, from the new start; the real-time one where it cannot start
            self._stepper = self.method.stepper(self.model, self.state)
        except (ValueError, ArithmeticError):
            self.integrator = realtime_method()
            self._stepper = self.method.stepper(self.model, self.state)
        self.samples.clear()
        self.take_sample()
        for trace in self.traces.values():
            trace.clear()
        self._record()
        self.version += 1

    def reset(self) -> None:
        self.restart(self.initial_state, angles=self.initial_angles)

    def set_model(self, model: Model) -> None:
        """A new body (or gravity) from the current attitude and ω_b: a new run."""
        self.model = model
        self.restart(self.state, angles=self.angles)

    @property
    def method(self) -> Method:
        """The registry entry of the integrator in use."""
        return methods()[self.integrator]

    def set_integrator(self, name: str) -> str | None:
        """Go on with the method `name` of `physics.methods` from the current state (a method
        whose motion is the closed form goes on along the closed form of this run); returns a
        message, and keeps the method in use, if `name` does not apply to this body or cannot
        start from this state.  ValueError for a name that is not in the registry."""
        registry = methods()
        if name not in registry:
            raise ValueError(f"unknown integrator {name!r}; the methods are {', '.join(registry)}")
        if name == self.integrator:
            return None
        try:
            stepper = registry[name].stepper(self.model, self.state, self.initial_state)
        except (ValueError, ArithmeticError) as error:
            return f"{name} cannot go on from here: {error}. Staying with {self.integrator}."
        self.integrator = name
        self._stepper = stepper
        self.version += 1
        return None

    def exact(self) -> ExactSolution | None:
        """The closed form from this run's initial state (built once per run), or None."""
        if self._exact is None and self.exact_failed is None:
            try:
                self._exact = exact_solution(self.model, self.initial_state)
            except (ValueError, ArithmeticError) as error:
                self.exact_failed = str(error)
        return self._exact

    # ------------------------------------------------------------------ motion
    def advance(self, dt: float) -> None:
        """Advance by dt [s] of simulated time (IntegrationError, ValueError on failure)."""
        if not dt > 0.0:
            return
        self._move(dt)
        self._record()
        self.version += 1

    def _move(self, dt: float) -> None:
        """The state dt [s] on (state, angles, sub-steps; no history).  Where the method's
        coordinates are singular (GimbalLockError from its stepper) the state stays, the
        simulation changes to `physics.methods.realtime_method()` and ValueError says why."""
        try:
            state = self._stepper.step(dt)
        except GimbalLockError as error:
            stopped, going_on = self.integrator, realtime_method()
            self.set_integrator(going_on)
            raise ValueError(f"{stopped} stopped: {error}. Press Play to go on with {going_on}.") from None
        self._moved(state)

    def _moved(self, state: State) -> None:
        self.state = state
        self.substeps = self._stepper.substeps
        self.angles = euler_zxz_from_matrix_near(state.R_space_body, self.angles)

    # ------------------------------------------------------------------ derived quantities
    def momentum(self, R: np.ndarray, omega_body: Vec3) -> float:
        """The conserved momentum the accuracy panel follows: |L| or L_z [kg m²/s]."""
        L = angular_momentum_space(self.model, R, omega_body)
        return float(L[2]) if self.momentum_kind == "z" else float(np.linalg.norm(L))

    def exact_attitude(self, keep: bool = True) -> np.ndarray | None:
        """R_space_body of the exact solution at the current time (3, 3), None without a closed
        form; evaluated once per simulated time (the ghost draws it every frame; `keep`: remember
        it for the next call at the same time)."""
        t = self.state.t
        if self._exact_at is not None and self._exact_at[0] == t:
            return self._exact_at[1]
        exact = self.exact()
        if exact is None:
            return None
        R_exact, _ = exact(np.array([t]))
        if keep:
            self._exact_at = (t, R_exact[0])
        return R_exact[0]

    def attitude_error(self) -> float | None:
        """Angle [rad] of R_exactᵀ R at the current time, 0 for a method whose motion is the
        closed form (`Method.reference`), None without a closed form."""
        if self.method.reference:
            return 0.0
        R_exact = self.exact_attitude(keep=False)  # a panel's question leaves no trace in the simulation
        if R_exact is None:
            return None
        return float(turn_angles(R_exact[None], self.state.R_space_body[None])[0])  # as the samples' check

    def flips(self, t_lo: float, t_hi: float) -> np.ndarray:
        """Times [s] in [t_lo, t_hi] at which the exact solution of this run flips (ω along the
        intermediate axis changes sign; `physics.poinsot.flip_times`): a free body with three
        different moments off the separatrix only, else empty."""
        if self.model.kind != "free":
            return np.zeros(0)
        inertia = np.asarray(self.model.inertia, dtype=float)
        omega0 = self.initial_state.omega_body
        T = kinetic_energy(self.model, omega0)
        if T <= 0.0 or len(set(inertia.tolist())) < 3:
            return np.zeros(0)
        try:
            if motion(inertia, T, float(np.linalg.norm(inertia * omega0))).kind != "flip":
                return np.zeros(0)
            return flip_times(inertia, omega0, 0.0, t_lo, t_hi)
        except ValueError:
            return np.zeros(0)

    def take_sample(self) -> None:
        """Append the plot columns of the current state to `samples`."""
        R, omega = self.state.R_space_body, self.state.omega_body
        T = kinetic_energy(self.model, omega)
        V = self.model.potential_energy(R)
        L = angular_momentum_space(self.model, R, omega)
        drift_E = (T + V - self._E0) / self._energy_scale if self._energy_scale > 0.0 else 0.0
        drift_L = ((self.momentum(R, omega) - self._momentum0) / self._momentum_scale
                   if self._momentum_scale > 0.0 else 0.0)
        phi, theta, psi = np.degrees(self.angles)
        values = {"E": T + V, "T": T, "V": V, "L_norm": float(np.linalg.norm(L)), "L_z": float(L[2]),
                  "phi": math.remainder(phi, 360.0), "theta": float(theta), "psi": math.remainder(psi, 360.0),
                  "w1": omega[0], "w2": omega[1], "w3": omega[2], "drift_E": drift_E, "drift_L": drift_L,
                  "attitude_error": math.nan,  # `_check_attitudes`
                  **dict(zip(R_COLUMNS, R.ravel().tolist()))}
        for key in self.max_drift:
            if math.isfinite(values[key]):
                self.max_drift[key] = max(self.max_drift[key], abs(values[key]))
        self.samples.append(self.state.t, values)
        if self.samples.mark() % ERROR_BATCH == 0:
            self._check_attitudes()

    def _check_attitudes(self, stop: int | None = None) -> None:
        """The attitude errors of the batch of samples ending before sample number `stop` (default:
        the newest), from one call of the closed form at their times (0 with a method whose
        motion is the closed form); their maximum into `max_drift`."""
        samples = self.samples
        stop = samples.mark() if stop is None else stop
        first = max(samples.oldest, stop - ERROR_BATCH)
        rows = samples.rows(first, stop)
        pending = np.flatnonzero(np.isnan(rows[:, 1 + SAMPLE_COLUMNS.index("attitude_error")]))
        if not pending.size:
            return
        if self.method.reference:
            errors = np.zeros(pending.size)
        else:
            exact = self.exact()
            if exact is None:
                return
            R_exact, _ = exact(rows[pending, 0])
            errors = turn_angles(R_exact, rows[pending, 1 + len(SAMPLE_COLUMNS):].reshape(-1, 3, 3))
        for k, error in zip(pending, errors):
            samples.put(first + int(k), "attitude_error", float(error))
        self.max_drift["attitude_error"] = max(self.max_drift["attitude_error"], float(np.max(errors)))

    def _recheck_attitudes(self) -> None:
        """After a rewind: the open batch (samples after the last multiple of ERROR_BATCH) has no
        attitude errors yet, as when it was live; a closed batch of the window that lost its
        errors in an earlier rewind gets them back (the same call, the same numbers)."""
        samples = self.samples
        mark = samples.mark()
        opened = mark - mark % ERROR_BATCH
        for number in range(max(opened, samples.oldest), mark):
            samples.put(number, "attitude_error", math.nan)
        first = max(samples.oldest, mark - len(samples))
        if opened <= first or self.exact() is None and not self.method.reference:
            return
        errors = samples.rows(first, opened)[:, 1 + SAMPLE_COLUMNS.index("attitude_error")]
        for stop in sorted({(first + int(k)) // ERROR_BATCH * ERROR_BATCH + ERROR_BATCH
                            for k in np.flatnonzero(np.isnan(errors))}):
            self._check_attitudes(stop)
