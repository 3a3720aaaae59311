"""Wall time per simulated second of real-time stepping, this tree against a baseline commit.

    python benchmarks/realtime_cost.py [--baseline REF] [--previous REF] [--seconds S]
                                       [--cases NAME ...] [--frame-dt H ...]

For each case of benchmarks/cases (default: all) and each display step (default 1/240 s and
1/60 s) it prints the milliseconds of wall time per simulated second of
* the CLI path, `physics.methods.simulate_realtime` (what `python -m physics simulate --realtime
  --frame-dt H` runs; its own `wall_s`, so the stepper's construction and the samples included),
* the app's stepper, `physics.realtime.GridStepper.step(H)` frame after frame (a tree without
  GridStepper, such as 21f6295, runs `RealtimeStepper.step(H)`, which the app used then; at
  H < 1/60 s GridStepper does more: a 1/60 s grid step every 1/60 s and a peek from the grid
  point at every other frame),
* `RealtimeStepper.step(H)` frame after frame (the CLI's stepper, one State per frame),
for this tree and for the physics/ of git REF (--baseline, default 21f6295, the commit of the issue
"Lean frames"; --previous adds a second ref), and the largest attitude difference [rad] between the
two trees' CLI trajectories (round-off is ~1e-14; a changed method would show at ~1e-9).

Each tree runs in its own Python process on its own copy of physics/ (`git archive`), two rounds
alternating between the trees; each figure is the best of 9 runs (--runs) per round of S simulated
seconds (default 2: short runs, many of them, so that the best finds a quiet moment of the
machine).  The issue's target: <= 2 ms per simulated second at 1/240 s through the CLI on the
asymmetric heavy top and the free body.  Figures, not asserts: the machine is shared, and figures
move by ~10-20 % with its load.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tarfile
import tempfile
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "benchmarks" / "cases"
FRAME_STEPS = ("1/240", "1/60")
RUNS = 9
ROUNDS = 2


def seconds(text: str) -> float:
    """A display step as typed on the CLI: a float or p/q (float(p) / float(q))."""
    p, _, q = text.partition("/")
    return float(p) / float(q) if q else float(p)


def tree_of(ref: str, into: Path) -> Path:
    """physics/ of git REF extracted under `into` (raises CalledProcessError for an unknown REF)."""
    archive = subprocess.run(["git", "archive", ref, "physics"], cwd=ROOT, check=True, capture_output=True).stdout
    target = into / ref.replace("/", "_")
    target.mkdir(parents=True)
    with tempfile.TemporaryFile() as tmp:
        tmp.write(archive)
        tmp.seek(0)
        with tarfile.open(fileobj=tmp) as tar:
            tar.extractall(target, filter="data")
    return target


def worker(tree: str, cases: list[str], steps: list[str], simulated: float, out_dir: str, runs: int = RUNS) -> None:
    """Run in a fresh process with `tree` first on sys.path: time the CLI path and the app's
    stepper of that tree's physics; print one JSON object per (case, step); save the CLI's R."""
    sys.path.insert(0, tree)
    from physics import realtime
    from physics.casefile import load_case
    from physics.methods import simulate_realtime

    assert Path(realtime.__file__).resolve().is_relative_to(Path(tree).resolve()), realtime.__file__
    stepper_class = getattr(realtime, "GridStepper", None) or realtime.RealtimeStepper
    for name in cases:
        case = load_case(CASES / f"{name}.json")
        for text in steps:
            dt = seconds(text)
            frames = round(simulated / dt)
            span = frames * dt
            simulate_realtime(case.model, case.state0, dt, dt)  # warm-up, as the CLI's _warm_up
            cli = min(simulate_realtime(case.model, case.state0, span, dt).wall_s for _ in range(runs))
            trajectory = simulate_realtime(case.model, case.state0, span, dt)
            np.save(Path(out_dir) / f"{name}_{Fraction(text).numerator}_{Fraction(text).denominator}.npy",
                    trajectory.R_space_body)
            wall = {}
            for column, cls in (("app", stepper_class), ("stepper", realtime.RealtimeStepper)):
                wall[column] = float("inf")
                for _ in range(runs):
                    start = time.perf_counter()
                    stepper = cls(case.model, case.state0)
                    for _ in range(frames):
                        stepper.step(dt)
                    wall[column] = min(wall[column], time.perf_counter() - start)
            print(json.dumps({"case": name, "step": text, "cli": 1e3 * cli / span, "app": 1e3 * wall["app"] / span,
                              "stepper": 1e3 * wall["stepper"] / span, "app_class": stepper_class.__name__}),
                  flush=True)


def measure(tree: Path, cases: list[str], steps: list[str], simulated: float, out_dir: Path, runs: int) -> dict:
    """{(case, step): row} from one worker process on `tree` (rows missing if it failed)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    command = [sys.executable, __file__, "--worker", str(tree), "--seconds", str(simulated), "--out", str(out_dir),
               "--runs", str(runs), "--cases", *cases, "--frame-dt", *steps]
    result = subprocess.run(command, capture_output=True, text=True, cwd=tempfile.gettempdir())
    if result.returncode != 0:
        print(f"worker on {tree} failed: {result.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
    rows = {}
    for line in result.stdout.splitlines():
        row = json.loads(line)
        rows[(row["case"], row["step"])] = row
    return rows


def attitude_difference(a: Path, b: Path) -> float:
    """Largest rotation angle [rad] between two saved (N, 3, 3) trajectories (nan if missing)."""
    if not (a.exists() and b.exists()):
        return float("nan")
    Ra, Rb = np.load(a), np.load(b)
    if Ra.shape != Rb.shape:
        return float("nan")
    half_sin = np.linalg.norm(Rb - Ra, axis=(1, 2)) / np.sqrt(8.0)  # |Rb - Ra|_F = 2 sqrt(2) sin(angle / 2)
    return float(np.max(2.0 * np.arcsin(np.clip(half_sin, 0.0, 1.0))))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--baseline", default="21f6295", help="git ref whose physics/ is compared (default 21f6295)")
    parser.add_argument("--previous", default="", help="a second git ref to compare (default: none)")
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated seconds per run (default 2)")
    parser.add_argument("--runs", type=int, default=RUNS, help=f"runs per round, the best counts (default {RUNS})")
    parser.add_argument("--cases", nargs="+", default=sorted(p.stem for p in CASES.glob("*.json")))
    parser.add_argument("--frame-dt", nargs="+", default=list(FRAME_STEPS), help="display steps, e.g. 1/240 0.01")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        worker(args.worker, args.cases, args.frame_dt, args.seconds, args.out, args.runs)
        return 0
    refs = [ref for ref in (args.baseline, args.previous) if ref]
    with tempfile.TemporaryDirectory() as scratch_name:
        scratch = Path(scratch_name)
        trees: dict[str, Path] = {"this tree": ROOT}
        for ref in refs:
            try:
                trees[ref] = tree_of(ref, scratch / "trees")
            except subprocess.CalledProcessError as error:
                print(f"no physics/ at {ref}: {error.stderr.decode().strip()}", file=sys.stderr)
        best: dict[str, dict] = {label: {} for label in trees}
        for _ in range(ROUNDS):  # alternate the trees, so a busy moment does not favour one
            for k, (label, tree) in enumerate(trees.items()):
                rows = measure(tree, args.cases, args.frame_dt, args.seconds, scratch / f"R{k}", args.runs)
                for key, row in rows.items():
                    old = best[label].get(key)
                    best[label][key] = row if old is None else {
                        **row, **{c: min(row[c], old[c]) for c in ("cli", "app", "stepper")}}
        others = [label for label in trees if label != "this tree"]
        stepper = {label: next((r["app_class"] for r in best[label].values()), "?") for label in trees}
        print(f"ms of wall per simulated second (best of {ROUNDS} x {args.runs} runs of {args.seconds:g} s); "
              f"CLI = simulate_realtime, app = {stepper['this tree']}.step"
              + "".join(f"; app @ {ref} = {stepper[ref]}.step" for ref in others))
        header = ["case", "frame dt [s]", "CLI"] + [f"CLI @ {ref}" for ref in others] + ["app"]
        header += [f"app @ {ref}" for ref in others] + ["RealtimeStepper.step"]
        header += [f"RealtimeStepper.step @ {ref}" for ref in others]
        header += [f"max attitude diff vs {ref} [rad]" for ref in others]
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
        for name in args.cases:
            for text in args.frame_dt:
                key = (name, text)

                def cell(label: str, column: str, key: tuple[str, str] = key) -> str:
                    row = best[label].get(key)
                    return "n/a" if row is None else f"{row[column]:.2f}"

                cells = [name, text, cell("this tree", "cli"), *(cell(ref, "cli") for ref in others),
                         cell("this tree", "app"), *(cell(ref, "app") for ref in others),
                         cell("this tree", "stepper"), *(cell(ref, "stepper") for ref in others)]
                f = Fraction(text)
                file = f"{name}_{f.numerator}_{f.denominator}.npy"
                for k, _ref in enumerate(others, start=1):
                    cells.append(f"{attitude_difference(scratch / 'R0' / file, scratch / f'R{k}' / file):.1e}")
                print("| " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
