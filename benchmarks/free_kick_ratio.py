"""free_kick and adaptive against scipy's DOP853 at equal attitude error, repeated, medians.

On a case without a closed form (default: the two torqued tops of benchmarks/cases/), for each
DOP853 tolerance it takes the largest free_kick step (a divisor of the output interval) and the
largest adaptive tolerance whose error is at most DOP853's, times the three interleaved in one
process, `--repeats` times, and prints the median wall-time ratios (below 1 is faster) and
what a free_kick step costs: drifts, and the drift's cost in right-hand-side evaluations of
`adaptive` (its wall time per evaluation in the same repeat).  The reference is DOP853 at rtol
3e-14.  A shared machine moves single timings by tens of percent: read the medians.

    python benchmarks/free_kick_ratio.py [--repeats 5] [--cases torqued_top fast_asymmetric_top]
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from physics import integrators  # noqa: E402
from physics.casefile import load_case  # noqa: E402
from physics.free_kick import SCHEMES, integrate_free_kick  # noqa: E402

TOLERANCES = (1e-10, 1e-12)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cases", nargs="*", default=["torqued_top", "fast_asymmetric_top"])
    args = parser.parse_args(argv)
    drifts_per_step = len(SCHEMES["bm6"][1])
    for name in args.cases:
        case = load_case(ROOT / "benchmarks" / "cases" / f"{name}.json")
        model, s0, t = case.model, case.state0, case.t
        ref = integrators.integrate_dop853(model, s0, t, rtol=3e-14, atol=1e-16).R_space_body

        def error(R: np.ndarray, ref: np.ndarray = ref) -> float:
            return float(Rotation.from_matrix(np.swapaxes(ref, 1, 2) @ R).magnitude().max())

        interval = float(t[1] - t[0])
        for tol in TOLERANCES:
            def peer(tol: float = tol, model=model, s0=s0, t=t):  # noqa: ANN001, ANN202
                return integrators.integrate_dop853(model, s0, t, rtol=tol, atol=tol * 1e-2)

            target = error(peer().R_space_body)
            h = next(interval / n for n in range(1, 4096)
                     if error(integrate_free_kick(model, s0, t, h=interval / n).R_space_body) <= target)
            atol_scale = next(a for a in (tol * 10 ** (k / 2) for k in range(4, -9, -1))
                              if error(integrators.integrate_adaptive(model, s0, t, rtol=a, atol=a * 1e-2).R_space_body)
                              <= target)
            ratios_fk, ratios_ad, drift_in_evals = [], [], []
            for _ in range(args.repeats):
                p = peer()
                f = integrate_free_kick(model, s0, t, h=h)
                a = integrators.integrate_adaptive(model, s0, t, rtol=atol_scale, atol=atol_scale * 1e-2)
                ratios_fk.append(f.wall_s / p.wall_s)
                ratios_ad.append(a.wall_s / p.wall_s)
                drifts = f.evaluations  # one kick per drift (merged)
                drift_in_evals.append((f.wall_s / drifts) / (a.wall_s / a.evaluations))
            steps = round(float(t[-1] - t[0]) / h)
            print(f"{name}: DOP853 rtol {tol:.0e} (error {target:.1e} rad): free_kick h {h:.4g} s "
                  f"({steps} steps x {drifts_per_step} drifts) {statistics.median(ratios_fk):.2f}x, "
                  f"adaptive rtol {atol_scale:.1e} {statistics.median(ratios_ad):.2f}x; "
                  f"a drift (with its kick) costs {statistics.median(drift_in_evals):.1f} adaptive evaluations "
                  f"(medians of {args.repeats})", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
