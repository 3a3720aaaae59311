"""Speed against error: every method on the public cases in benchmarks/cases/, measured in one run.

For each case and method (over a sweep of tolerances or step sizes) it records the maximum
attitude error against the reference (the exact solution where one exists, otherwise DOP853 at
rtol 1e-14 checked against the adaptive method at the same tolerance), the energy and |L| drift,
the number of evaluations and the wall time.  The peer is what a user would otherwise pick:
scipy `solve_ivp` DOP853 on the quaternion ODE; MuJoCo's RK4 joins when `mujoco` is installed.
Ratios "at equal error" interpolate each method's wall time at the peer's error levels on the
log-log work-precision curve.

    python benchmarks/work_precision.py            # writes benchmarks/results.md, docs/img/work_precision.png
    python benchmarks/work_precision.py --quick    # fewer points, for a smoke run
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from physics import integrators  # noqa: E402
from physics.casefile import Case, load_case  # noqa: E402
from physics.dynamics import Model, Trajectory, angular_momentum_space, energy  # noqa: E402
from physics.methods import exact_solution, simulate_realtime  # noqa: E402

CASES = ROOT / "benchmarks" / "cases"


@dataclass
class Point:
    """One run: method, setting (tolerance or step), errors, cost."""

    case: str
    method: str
    setting: str
    attitude_error: float  # max rotation angle of R_refᵀ R [rad]
    energy_drift: float  # max |E - E0| / |E0|
    L_drift: float  # max ||L_s| - |L_s0|| / |L_s0|
    evaluations: int
    wall_s: float


def attitude_error(R_ref: np.ndarray, R: np.ndarray) -> float:
    return float(Rotation.from_matrix(np.swapaxes(R_ref, 1, 2) @ R).magnitude().max())


def drifts(model: Model, traj: Trajectory) -> tuple[float, float]:
    E = np.array([energy(model, r, w) for r, w in zip(traj.R_space_body, traj.omega_body)])
    L = np.linalg.norm([angular_momentum_space(model, r, w) for r, w in zip(traj.R_space_body, traj.omega_body)],
                       axis=1)
    return float(np.max(np.abs(E - E[0])) / max(abs(E[0]), 1e-300)), float(np.max(np.abs(L - L[0])) / max(L[0], 1e-300))


def reference(case: Case) -> tuple[np.ndarray, str]:
    """R (N,3,3) of the reference and how it was obtained."""
    try:
        R, _ = exact_solution(case.model, case.state0)(case.t)
        return R, "exact solution"
    except ValueError:
        R = integrators.integrate_dop853(case.model, case.state0, case.t, rtol=1e-14, atol=1e-16).R_space_body
        R2 = integrators.integrate_adaptive(case.model, case.state0, case.t, rtol=1e-14, atol=1e-16).R_space_body
        return R, f"DOP853 rtol 1e-14 (adaptive at 1e-14 agrees to {attitude_error(R, R2):.1e} rad)"


def best_of(runs: int, fn):
    """The run with the least wall time of `runs` repeats (the others only warm up)."""
    best = None
    for _ in range(runs):
        traj = fn()
        if best is None or traj.wall_s < best.wall_s:
            best = traj
    return best
