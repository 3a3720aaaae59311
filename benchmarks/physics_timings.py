"""Speed figures that used to be timed asserts in the physics tests (figures, not asserts).

    python benchmarks/physics_timings.py

Prints best-of-5 wall times [ms] of: the exact torque-free solution at 1e4 samples, the mass
properties of a 20480-face mesh, the Euler-Lagrange run that stops at the pole, the
integrators refusing a blow-up (the tests count the work done instead), and the real-time
stepping of the CLI (`simulate_realtime`, `--frame-dt 1/240`) on the two cases of issue 16, in ms
of wall per simulated second (target <= 2; benchmarks/realtime_cost.py has every case, side by
side with a baseline commit).
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from physics.casefile import load_case  # noqa: E402
from physics.dynamics import IntegrationError, Model, State  # noqa: E402
from physics.exact_free import FreeBodyExact  # noqa: E402
from physics.inertia import mesh_mass_properties  # noqa: E402
from physics.integrators import integrate_adaptive, integrate_dop853, integrate_splitting  # noqa: E402
from physics.lagrange import integrate_euler_lagrange  # noqa: E402
from physics.methods import simulate_realtime  # noqa: E402
from physics.so3 import rot_x  # noqa: E402


def best_ms(fn: Callable[[], object], runs: int = 5) -> float:
    best = math.inf
    for _ in range(runs):
        start = time.perf_counter()
        try:
            fn()
        except IntegrationError:
            pass
        best = min(best, time.perf_counter() - start)
    return 1e3 * best


def icosphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of a unit icosphere (no trimesh: the benchmark needs physics only)."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(p, dtype=float) / np.linalg.norm(p) for p in vertices]
    for _ in range(subdivisions):
        cache: dict[tuple[int, int], int] = {}

        def mid(a: int, b: int, cache: dict[tuple[int, int], int] = cache) -> int:
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = v[a] + v[b]
                v.append(m / np.linalg.norm(m))
                cache[key] = len(v) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return np.array(v), np.array(faces)


def main() -> int:
    exact = FreeBodyExact([1.0, 2.0, 3.0], rot_x(0.4), [0.3, 1.0, 0.2])
    t = np.linspace(0.0, 1e4, 10_000)
    print(f"exact free body, 1e4 samples:           {best_ms(lambda: exact(t)):8.2f} ms")
    vertices, faces = icosphere(5)
    ms = best_ms(lambda: mesh_mass_properties(vertices, faces))
    print(f"mesh_mass_properties, {len(faces)} faces:    {ms:8.2f} ms")
    a = np.array([math.sqrt(1 - 1e-8), 0.0, 1e-4])
    v = np.array([0.0, 0.0, 1.0]) - 1e-4 * a
    v /= np.linalg.norm(v)
    z0 = math.cos(1.0) * v + math.sin(1.0) * np.cross(a, v)
    pole = State(np.column_stack([a, np.cross(z0, a), z0]), np.array([-2.0, 0.0, 0.0]))
    ms = best_ms(lambda: integrate_euler_lagrange(Model((1.0, 2.0, 2.5)), pole, np.linspace(0.0, 3.0, 61)))
    print(f"euler_lagrange stopping at the pole:    {ms:8.2f} ms")
    blow_up = Model((1.0, 1.5, 2.0), extra_torque=lambda t, R, w: R @ (50.0 * np.array([1.0, 1.5, 2.0]) * w))
    state = State(rot_x(0.4), np.array([0.3, 0.2, 3.0]))
    times = np.linspace(0.0, 5.0, 11)
    runs = (("splitting", integrate_splitting), ("adaptive", integrate_adaptive), ("dop853", integrate_dop853))
    for name, run in runs:
        print(f"{name:10s} refusing a blow-up:        {best_ms(lambda run=run: run(blow_up, state, times)):8.2f} ms")
    simulated = 5.0  # [s] per run
    for case_name in ("asymmetric_heavy_top", "free_asymmetric"):
        case = load_case(ROOT / "benchmarks" / "cases" / f"{case_name}.json")
        ms = best_ms(lambda case=case: simulate_realtime(case.model, case.state0, simulated, 1.0 / 240.0), runs=9)
        print(f"simulate_realtime 1/240, {case_name:21s} {ms / simulated:8.2f} ms per simulated s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
