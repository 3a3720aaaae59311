"""Command line: `python -m physics simulate CASE.json --out TRAJ.npz` and `python -m physics
methods` (docs/CASEFILE.md).  Exit 0 on success, 2 for a case that is not a physical problem (one
line on stderr, no output file), 1 when a run fails (a non-finite state, a singularity)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from physics.casefile import Case, CaseError, load_case
from physics.dynamics import IntegrationError, Model, Trajectory, angular_momentum_space, energy
from physics.euler import euler_zxz_from_matrix, euler_zxz_from_matrix_near
from physics.methods import default_method, methods, simulate, simulate_realtime


def _euler_along(R: np.ndarray) -> np.ndarray:
    """(N, 3) z-x-z angles continuous along the samples R (N, 3, 3)."""
    angles = np.empty((len(R), 3))
    angles[0] = euler_zxz_from_matrix(R[0])
    for k in range(1, len(R)):
        angles[k] = euler_zxz_from_matrix_near(R[k], angles[k - 1])
    return angles


def write_trajectory(path: Path, model: Model, trajectory: Trajectory) -> None:
    """TRAJ.npz with the keys of docs/CASEFILE.md."""
    R, omega = trajectory.R_space_body, trajectory.omega_body
    np.savez(
        path,
        t=trajectory.t,
        R=R,
        omega_body=omega,
        euler_zxz=_euler_along(R),
        energy=np.array([energy(model, r, w) for r, w in zip(R, omega)]),
        L_space=np.array([angular_momentum_space(model, r, w) for r, w in zip(R, omega)]),
        evaluations=np.array(trajectory.evaluations),
        wall_s=np.array(trajectory.wall_s),
        method=np.array(trajectory.method),
    )


def _warm_up(case: Case, realtime: bool, frame_dt: float, name: str) -> None:
    """Run the method once, untimed, on the first output interval: imports and first-use set-up
    (lazy imports, SciPy's first calls) then stay out of the `wall_s` of the real run, which
    measures the computation only (docs/CASEFILE.md).  A failure here is left to the real run."""
    try:
        if realtime:
            simulate_realtime(case.model, case.state0, frame_dt, frame_dt)
        else:
            simulate(case.model, case.state0, case.t[:2], name)
    except (IntegrationError, ArithmeticError, ValueError):
        pass


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m physics", description=__doc__.split("\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    run = commands.add_parser("simulate", help="integrate a case file and write TRAJ.npz")
    run.add_argument("case", type=Path, help="CASE.json (see docs/CASEFILE.md)")
    run.add_argument("--out", type=Path, required=True, help="output TRAJ.npz")
    run.add_argument("--method", help="a name from `python -m physics methods` (default: the most accurate)")
    run.add_argument("--realtime", action="store_true", help="step frame by frame as the app does")
    run.add_argument("--frame-dt", type=float, default=1.0 / 60.0, help="display step [s] with --realtime")
    commands.add_parser("methods", help="list the methods, their order and what they conserve")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command == "methods":
        for method in methods().values():
            print(f"{method.name:15s} {method.summary}")
        print(f"{'realtime':15s} --realtime: the app's frame-by-frame stepping (splitting4 with sub-steps)")
        return 0
    try:
        case = load_case(args.case)
        if args.realtime and args.method:
            raise CaseError("--method and --realtime exclude each other (--realtime uses the app's method)")
        if args.realtime and not (np.isfinite(args.frame_dt) and args.frame_dt > 0.0):
            raise CaseError(f"--frame-dt: must be a positive number, got {args.frame_dt}")
        name = args.method or default_method(case.model)
        if not args.realtime and name not in methods():
            raise CaseError(f"--method: unknown {name!r}; choose one of {', '.join(methods())}")
        if not args.realtime and not methods()[name].applies(case.model):
            raise CaseError(
                f"--method {name}: does not apply to a {case.model.kind} model with inertia {case.model.inertia}"
            )
    except CaseError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    _warm_up(case, args.realtime, args.frame_dt, name)
    try:
        if args.realtime:
            trajectory = simulate_realtime(case.model, case.state0, float(case.t[-1]), args.frame_dt)
        else:
            trajectory = simulate(case.model, case.state0, case.t, name)
    except (IntegrationError, ArithmeticError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    write_trajectory(args.out, case.model, trajectory)
    return 0


if __name__ == "__main__":
    sys.exit(main())
