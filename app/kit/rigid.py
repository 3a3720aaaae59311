"""The simulation of a rigid body for the animated scenes (free body, heavy top): no viser here.

`RigidBodySimulation` owns the model, the state, the integrator (the real-time splitting
`physics.realtime.GridStepper`: fixed steps of 1/60 s whatever the frame rate, or the closed
form of `physics.methods.exact_solution` evaluated at the simulated time), the exact solution
where one exists (for the attitude error and the "exact ghost"), the drift references of this
run, the plot samples and the traces of the points a scene follows (`track`: the heavy top's
tip, Poinsot's herpolhode), so that a view built later draws them so far.  `restart(state)`
starts a run at t = 0 from a state it is given, `reset()` goes back to this run's own initial
state: a simulation never reads a widget.  Several views may draw one simulation.  `fork()` is
an exact, independent copy.

Conventions as in `physics` (docs/CONVENTIONS.md): R = R_space_body, z-x-z Euler angles,
hat(ω_b) = Rᵀ Ṙ, L_s = R I ω_b, SI units.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from app.kit.samples import SampleBuffer
from app.kit.trace import Trace
from physics._types import Vec3
from physics.dynamics import Model, State, angular_momentum_space, energy, kinetic_energy
from physics.euler import euler_zxz_from_matrix, euler_zxz_from_matrix_near
from physics.lagrange import SIN_THETA_STOP, EulerLagrangeSingularityError, integrate_euler_lagrange
from physics.methods import exact_solution
from physics.poinsot import flip_times, motion
from physics.realtime import GridStepper
from physics.so3 import exp_so3, log_so3

__all__ = ["INTEGRATOR_EXACT", "INTEGRATOR_LAGRANGE", "INTEGRATOR_REALTIME", "SAMPLE_COLUMNS", "RigidBodySimulation",
           "magnified_attitude"]

INTEGRATOR_REALTIME = "splitting4 (real time)"
INTEGRATOR_EXACT = "exact"
INTEGRATOR_LAGRANGE = "Euler-angle Lagrangian"
"""physics.lagrange.integrate_euler_lagrange from frame to frame: the memo's (5.13) in φ θ ψ,
singular where sin θ = 0 (it stops there, and the simulation goes on with splitting4)."""
SAMPLE_COLUMNS = ("E", "T", "V", "L_norm", "L_z", "phi", "theta", "psi", "w1", "w2", "w3",
                  "drift_E", "drift_L", "attitude_error")
PLOT_CAPACITY = 300  # samples in the sliding window (30 s of wall time at 10 Hz)

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


class RigidBodySimulation:
    """One rigid body in motion.

    Attributes:
        model: the `physics.dynamics.Model`.  state: the current `State` (t since the restart).
        initial_state, initial_angles: where `reset` goes back to.
        angles: continuous z-x-z angles (φ, θ, ψ) [rad] of the state (φ, ψ unwrapped), for display.
        integrator: INTEGRATOR_REALTIME or INTEGRATOR_EXACT.  substeps: of the last real-time step.
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
        self.integrator = INTEGRATOR_REALTIME
        self.substeps = 0
        self.restarts = 0
        self.version = 0
        self.samples = SampleBuffer(SAMPLE_COLUMNS, PLOT_CAPACITY)
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
        memo: dict[int, Any] = {}
        if self.mesh is not None:
            for array in self.mesh:
                array.flags.writeable = False
                memo[id(array)] = array
        return copy.deepcopy(self, memo)
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
        self._stepper = GridStepper(self.model, self.state)
        self._exact: ExactSolution | None = None
        self._exact_at: tuple[float, np.ndarray] | None = None  # (t, R_exact(t)), the last one asked
        self.exact_failed: str | None = None
        self.restarts += 1
        self._E0 = energy(self.model, R, omega)
        self._energy_scale = kinetic_energy(self.model, omega) + abs(self.model.mgl)
        self._momentum0 = self.momentum(R, omega)
        self._momentum_scale = float(np.linalg.norm(angular_momentum_space(self.model, R, omega)))
        self.max_drift = dict.fromkeys(self.max_drift, 0.0)
        if self.integrator == INTEGRATOR_EXACT and self.exact() is None:
            self.integrator = INTEGRATOR_REALTIME
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

    def set_integrator(self, name: str) -> str | None:
        """Use `name`; returns a message (and keeps the real-time method) if there is no closed form."""
        message = None
        if name == INTEGRATOR_EXACT and self.exact() is None:
            message = f"No closed form here ({self.exact_failed}); using {INTEGRATOR_REALTIME}."
            name = INTEGRATOR_REALTIME
        if name == INTEGRATOR_LAGRANGE and abs(math.sin(float(self.angles[1]))) < SIN_THETA_STOP:
            message = (f"The Euler-angle equations are singular at θ = {math.degrees(float(self.angles[1])):.2f}° "
                       f"(sin θ in a denominator); staying with {self.integrator}.")
            name = self.integrator
        if name != self.integrator:
            self.integrator = name
            if name == INTEGRATOR_REALTIME:  # go on from where the other method is
                self._stepper = GridStepper(self.model, self.state)
            self.version += 1
        return message

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
        exact = self.exact() if self.integrator == INTEGRATOR_EXACT else None
        if exact is not None:
            t = self.state.t + dt
            R, omega = exact(np.array([t]))
            self.state = State(R[0], omega[0], t)
            self.substeps = 0
        elif self.integrator == INTEGRATOR_LAGRANGE:
            try:
                trajectory = integrate_euler_lagrange(self.model, self.state, np.array([self.state.t + dt]))
            except EulerLagrangeSingularityError as error:
                self.set_integrator(INTEGRATOR_REALTIME)
                raise ValueError(
                    f"the Euler-angle equations are singular near θ = 0° or 180° (sin θ in a "
                    f"denominator): {error}. Press Play to go on with {INTEGRATOR_REALTIME}, which has no "
                    "singularity.") from None
            self.state = State(trajectory.R_space_body[0], trajectory.omega_body[0], float(trajectory.t[0]))
            self.substeps = 0
        else:
            self.state = self._stepper.step(dt)
            self.substeps = self._stepper.substeps
        self.angles = euler_zxz_from_matrix_near(self.state.R_space_body, self.angles)
        self._record()
        self.version += 1

    # ------------------------------------------------------------------ derived quantities
    def momentum(self, R: np.ndarray, omega_body: Vec3) -> float:
        """The conserved momentum the accuracy panel follows: |L| or L_z [kg m²/s]."""
        L = angular_momentum_space(self.model, R, omega_body)
        return float(L[2]) if self.momentum_kind == "z" else float(np.linalg.norm(L))

    def exact_attitude(self) -> np.ndarray | None:
        """R_space_body of the exact solution at the current time (3, 3), None without a closed
        form; evaluated once per simulated time (the ghost and the accuracy panel share it)."""
        t = self.state.t
        if self._exact_at is not None and self._exact_at[0] == t:
            return self._exact_at[1]
        exact = self.exact()
        if exact is None:
            return None
        R_exact, _ = exact(np.array([t]))
        self._exact_at = (t, R_exact[0])
        return R_exact[0]

    def attitude_error(self) -> float | None:
        """Angle [rad] of R_exactᵀ R at the current time, 0 for the exact method, None without
        a closed form."""
        if self.integrator == INTEGRATOR_EXACT:
            return 0.0
        R_exact = self.exact_attitude()
        if R_exact is None:
            return None
        return float(np.linalg.norm(log_so3(R_exact.T @ self.state.R_space_body)))

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
        error = self.attitude_error()
        phi, theta, psi = np.degrees(self.angles)
        values = {"E": T + V, "T": T, "V": V, "L_norm": float(np.linalg.norm(L)), "L_z": float(L[2]),
                  "phi": math.remainder(phi, 360.0), "theta": float(theta), "psi": math.remainder(psi, 360.0),
                  "w1": omega[0], "w2": omega[1], "w3": omega[2], "drift_E": drift_E, "drift_L": drift_L,
                  "attitude_error": math.nan if error is None else error}
        for key in self.max_drift:
            if math.isfinite(values[key]):
                self.max_drift[key] = max(self.max_drift[key], abs(values[key]))
        self.samples.append(self.state.t, values)
