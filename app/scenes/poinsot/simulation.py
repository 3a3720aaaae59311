"""The "Poinsot" scene's numbers of a run (no viser): the Energy setting of a motion and the state
at another setting, the herpolhode's point, the next flip (`app.scenes.poinsot`).  The simulation
itself is the kit's `RigidBodySimulation` (`app.kit.rigid.torque_free`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from app.kit.rigid.simulation import RigidBodySimulation
from physics.dynamics import State
from physics.poinsot import polhode_L
from physics.refusal import N_, Refusal
from physics.so3 import exp_so3

__all__ = ["CURVE_POINTS", "HERPOLHODE_SECONDS", "energy_setting", "next_flip_time", "omega_space", "run_energy",
           "sorted_moments", "state_at_energy", "track_herpolhode"]

HERPOLHODE_SECONDS = 40.0  # [s] of simulated time kept in the herpolhode
HERPOLHODE_SPACING = 1.0 / 30.0  # [s] of simulated time between its points
HERPOLHODE_CHUNK = 7  # points per chunk of the herpolhode (one every 0.2 s at time scale 1)
CURVE_POINTS = 256


def sorted_moments(inertia: Any) -> tuple[float, float, float]:
    """The principal moments (3,) [kg m²] sorted: (I_min, I_mid, I_max)."""
    lo, mid, hi = (float(x) for x in np.sort(np.asarray(inertia, dtype=float)))
    return lo, mid, hi


def energy_setting(inertia: Any, T: float, L_norm: float) -> float:
    """The Energy slider's value of a motion: -1 .. 0 .. 1 as |L|²/(2T) goes I_min .. I_mid .. I_max."""
    lo, mid, hi = sorted_moments(inertia)
    effective = L_norm * L_norm / (2.0 * T)
    if effective >= mid:
        return 0.0 if hi == mid else min(1.0, (effective - mid) / (hi - mid))
    return 0.0 if mid == lo else max(-1.0, (effective - mid) / (mid - lo))


def state_at_energy(inertia: Any, state: State, setting: float) -> State:
    """A state at the Energy setting (−1 .. 1) with the same |L| and L in space: L_b moves to
    the nearest point of the new polhode and the body turns so that R L_b stays L_s.  ValueError
    if the body has no such motion (a sphere; the side of an axis that two equal moments close)."""
    I = np.asarray(inertia, dtype=float)
    lo, mid, hi = sorted_moments(I)
    if not -1.0 <= setting <= 1.0:
        raise Refusal(N_("the energy setting must be in [-1, 1], got {setting}"), setting=repr(setting))
    if lo == hi:
        raise Refusal(N_("a ball (I1 = I2 = I3) turns steadily about any axis: every energy is |L|²/(2I)"))
    if setting < 0.0 and lo == mid or setting > 0.0 and mid == hi:
        raise Refusal(N_("two equal moments: there is no polhode on that side of the separatrix"))
    L_body = I * state.omega_body
    L_norm = float(np.linalg.norm(L_body))
    if L_norm == 0.0:
        raise Refusal(N_("the body is not turning (|L| = 0)"))
    effective = mid + setting * ((hi - mid) if setting >= 0.0 else (mid - lo))
    T = L_norm * L_norm / (2.0 * effective)
    candidates = np.concatenate([polhode_L(I, T, L_norm, CURVE_POINTS, sign) for sign in (1.0, -1.0)])
    new_L = candidates[int(np.argmin(np.linalg.norm(candidates - L_body, axis=1)))]
    axis = np.cross(new_L, L_body)
    angle = math.atan2(float(np.linalg.norm(axis)), float(new_L @ L_body))
    turn = exp_so3(axis / np.linalg.norm(axis) * angle) if angle > 0.0 else np.eye(3)  # turn @ new_L ∥ L_body
    return State(state.R_space_body @ turn, new_L / I, 0.0)


def omega_space(state: State) -> np.ndarray:
    """ω in space components (3,) [rad/s]: the contact point of the ellipsoid and the plane
    (drawn at the scene's ω scale); its path is the herpolhode."""
    return state.R_space_body @ state.omega_body



def run_energy(sim: RigidBodySimulation) -> float:
    """T = ½ ω·Iω [J] of the run (at its start: it is conserved), the energy Poinsot's ellipsoid
    is drawn for."""
    omega = sim.initial_state.omega_body
    I = np.asarray(sim.model.inertia, dtype=float)
    return 0.5 * float(omega @ (I * omega))


def track_herpolhode(sim: RigidBodySimulation) -> None:
    """Ask the simulation to keep the herpolhode: the last HERPOLHODE_SECONDS of ω in space."""
    sim.track("herpolhode", omega_space, seconds=HERPOLHODE_SECONDS, spacing=HERPOLHODE_SPACING,
              chunk_points=HERPOLHODE_CHUNK)


def next_flip_time(schedule: tuple[float, float] | None, t: float) -> float | None:
    """The time [s] of the first flip after t [s] (at t itself if t is before the first), of a
    schedule (first flip, flip period) [s]; None without one (no flip)."""
    if schedule is None:
        return None
    first, period = schedule
    return first if t < first else first + period * (math.floor((t - first) / period) + 1)
