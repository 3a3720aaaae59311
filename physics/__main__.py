"""Command line: `python -m physics simulate CASE.json --out TRAJ.npz`, `python -m physics
methods` and `python -m physics inertia FILE [--mass M | --density RHO] [--about X Y Z]`
(docs/CASEFILE.md).  Exit 0 on success, 2 for input that is not a physical problem (one line on
stderr, no output file), 1 when a run fails (a non-finite state, a singularity)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import NoReturn

import numpy as np

from physics.casefile import Case, CaseError, load_case
from physics.dynamics import IntegrationError, Model, Trajectory, angular_momentum_space, energy
from physics.euler import euler_zxz_from_matrix, euler_zxz_from_matrix_near
from physics.meshfile import MESH_SUFFIXES, read_mesh_file
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


def seconds_or_fraction(text: str) -> float:
    """A time step [s] as typed: a float (`0.004`, `4e-3`) or a fraction p/q (`1/240`, `1.5/360`).

    p/q is the float division float(p) / float(q), so `1/240` is exactly the double 1.0 / 240.0.
    argparse.ArgumentTypeError, naming what was typed, for anything else (whether the value is
    positive and finite is checked with the other inputs)."""
    wanted = f"a number of seconds or a fraction p/q (e.g. 0.004 or 1/240) wanted, got {text!r}"
    parts = text.strip().split("/")
    if len(parts) > 2:
        raise argparse.ArgumentTypeError(wanted)
    try:
        values = [float(part) for part in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(wanted) from None
    if len(values) == 1:
        return values[0]
    if values[1] == 0.0:
        raise argparse.ArgumentTypeError(f"{text!r}: the denominator of p/q is zero")
    return values[0] / values[1]


_USAGE = {
    "inertia": "python -m physics inertia FILE [--mass M | --density RHO] [--about X Y Z]",
    "simulate": "python -m physics simulate CASE.json --out TRAJ.npz [--method NAME] [--realtime] [--frame-dt H]",
}


def _one_line_error(command: str) -> Callable[[str], NoReturn]:
    """argparse's error for `command`: one line on stderr (no usage block), exit 2, as for a bad case."""

    def error(message: str) -> NoReturn:
        print(f"error: {message} (usage: {_USAGE[command]})", file=sys.stderr)
        raise SystemExit(2)

    return error


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m physics", description=__doc__.split("\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    run = commands.add_parser("simulate", help="integrate a case file and write TRAJ.npz")
    run.error = _one_line_error("simulate")  # type: ignore[method-assign,assignment]  # as a bad case: one line
    run.add_argument("case", type=Path, help="CASE.json (see docs/CASEFILE.md)")
    run.add_argument("--out", type=Path, required=True, help="output TRAJ.npz")
    run.add_argument("--method", help="a name from `python -m physics methods` (default: the most accurate)")
    run.add_argument("--realtime", action="store_true", help="step frame by frame as the app does")
    run.add_argument("--frame-dt", type=seconds_or_fraction, default=1.0 / 60.0, metavar="H",
                     help="display step [s] with --realtime: a number or a fraction p/q such as 1/240 (default 1/60)")
    commands.add_parser("methods", help="list the methods, their order and what they conserve")
    inertia = commands.add_parser("inertia", help="mass, centre of mass, inertia tensor and principal axes")
    inertia.error = _one_line_error("inertia")  # type: ignore[method-assign,assignment]  # bad values: one line, exit 2
    inertia.add_argument("file", type=Path, help="a mesh (STL, OBJ, PLY, OFF, GLB) or a JSON of point masses")
    inertia.add_argument("--mass", type=float, help="[kg] of a mesh (default density 1)")
    inertia.add_argument("--density", type=float, help="[kg/m³] of a mesh (default 1)")
    inertia.add_argument("--about", type=float, nargs=3, metavar=("X", "Y", "Z"),
                         help="the tensor about this point [m] (default: the centre of mass)")
    return parser


def inertia_report(args: argparse.Namespace) -> dict[str, object]:
    """The JSON object `python -m physics inertia` prints (CaseError for bad input)."""
    import json

    from physics.inertia import (
        InertiaError,
        MeshError,
        inertia_tensor_of_particles,
        mesh_mass_properties,
        parallel_axis,
        principal_axes,
    )

    if args.mass is not None and args.density is not None:
        raise CaseError("--mass and --density exclude each other")
    for name in ("mass", "density"):
        value = getattr(args, name)
        if value is not None and not (np.isfinite(value) and value > 0.0):
            raise CaseError(f"--{name}: a positive number wanted, got {value}")
    about = None if args.about is None else np.asarray(args.about, dtype=float)
    if about is not None and not np.all(np.isfinite(about)):
        raise CaseError(f"--about: three finite numbers wanted, got {args.about}")
    path = args.file
    if not path.exists():
        raise CaseError(f"{path}: no such file")
    try:
        if path.suffix.lower() == ".json":
            if args.mass is not None or args.density is not None:
                raise CaseError("--mass and --density are for meshes; point masses carry their own")
            try:
                data = json.loads(path.read_text(encoding="utf-8"))
                masses = np.asarray(data["masses"], dtype=float)
                positions = np.asarray(data["positions"], dtype=float)
            except (OSError, ValueError, KeyError, TypeError) as error:
                raise CaseError(f"{path}: a JSON object with masses (N,) and positions (N, 3) wanted: "
                                f"{type(error).__name__}: {error}") from None
            if (masses.ndim != 1 or positions.shape != (len(masses), 3) or not len(masses)
                    or not np.all(np.isfinite(masses)) or not np.all(masses > 0) or not np.all(np.isfinite(positions))):
                raise CaseError(f"{path}: masses must be N positive numbers and positions N finite [x, y, z]")
            mass = float(masses.sum())
            com = (masses[:, None] * positions).sum(axis=0) / mass
            I_cm = inertia_tensor_of_particles(masses, positions, about=com)
        elif path.suffix.lower() in MESH_SUFFIXES:
            vertices, faces = read_mesh_file(path)  # NumPy only: physics never imports trimesh
            properties = mesh_mass_properties(vertices, faces, density=1.0 if args.density is None else args.density)
            scale = 1.0 if args.mass is None else args.mass / properties.mass
            mass = properties.mass * scale
            com = np.asarray(properties.center_of_mass)
            I_cm = np.asarray(properties.inertia_cm) * scale
        else:
            raise CaseError(f"{path}: a mesh ({', '.join(MESH_SUFFIXES)}) or a .json of point masses wanted")
        I = I_cm if about is None else parallel_axis(I_cm, mass, com - about)
        moments, axes = principal_axes(I)
    except (MeshError, InertiaError) as error:
        raise CaseError(f"{path}: {error}") from None
    return {"mass": mass, "center_of_mass": com.tolist(), "inertia": np.asarray(I).tolist(),
            "about": (com if about is None else about).tolist(),
            "principal_moments": np.asarray(moments).tolist(), "principal_axes": np.asarray(axes).tolist()}


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command == "inertia":
        import json

        try:
            report = inertia_report(args)
        except CaseError as error:
            print(f"error: {error}", file=sys.stderr)
            return 2
        print(json.dumps(report))
        return 0
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
