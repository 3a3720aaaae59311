"""Wall time per simulated second of the app's real-time stepping, old against new.

    python benchmarks/realtime_cost.py [--baseline REF] [--previous REF] [--seconds S]

For each case (the free asymmetric body and the heavy top of benchmarks/cases, and the
asymmetric heavy top) and each display step (1/240 s, 1/60 s) it prints the milliseconds of
wall time per simulated second of
* `RealtimeStepper.step(dt)`, one stepper kept across frames (what the app does),
* `step_realtime(model, state, dt)`, the stateless function (a stepper built per frame),
* the previous stepper: `RealtimeStepper.step(dt)` of physics/realtime.py and physics/splitting.py
  at git --previous (default b277ef6, the interpreted stage loop before the generated kernel),
* the baseline: `physics/integrators.py` at git REF (default 026440c, before the split), its
  `step_realtime` called frame after frame as the app did.
Each figure is the best of 5 runs of S simulated seconds (default 5).  The issue's target is
<= 2 ms per simulated second at 1/240 s on these moderate cases.  Figures, not asserts.
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from physics.casefile import load_case  # noqa: E402
from physics.dynamics import Model, State  # noqa: E402
from physics.realtime import RealtimeStepper, step_realtime  # noqa: E402

CASES = ("free_asymmetric", "heavy_top", "asymmetric_heavy_top")
FRAME_STEPS = (1.0 / 240.0, 1.0 / 60.0)
RUNS = 5


def baseline_module(ref: str, file: str = "physics/integrators.py", name: str = "baseline_integrators",
                    replace: tuple[str, str] = ("", "")) -> object | None:
    """`file` at git REF, imported as the stand-alone module `name` (None if unavailable)."""
    try:
        source = subprocess.run(["git", "show", f"{ref}:{file}"], cwd=ROOT, check=True,
                                capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as error:
        print(f"no baseline: {error}", file=sys.stderr)
        return None
    if replace[0]:
        source = source.replace(*replace)
    path = Path(tempfile.mkdtemp()) / f"{name}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def ms_per_simulated_second(run: Callable[[int], None], frames: int, seconds: float) -> float:
    best = float("inf")
    for _ in range(RUNS):
        start = time.perf_counter()
        run(frames)
        best = min(best, time.perf_counter() - start)
    return 1e3 * best / seconds


def previous_stepper(ref: str) -> type | None:
    """RealtimeStepper of physics/realtime.py at REF, on physics/splitting.py at REF."""
    if baseline_module(ref, "physics/splitting.py", "previous_splitting") is None:
        return None
    module = baseline_module(ref, "physics/realtime.py", "previous_realtime",
                             ("from physics.splitting import", "from previous_splitting import"))
    return None if module is None else module.RealtimeStepper  # type: ignore[attr-defined,no-any-return]


def stepper_run(model: Model, state0: State, dt: float, cls: type = RealtimeStepper) -> Callable[[int], None]:
    def run(frames: int) -> None:
        stepper = cls(model, state0)
        for _ in range(frames):
            stepper.step(dt)

    return run


def function_run(
    step: Callable[..., tuple[State, int]], model: Model, state0: State, dt: float
) -> Callable[[int], None]:
    def run(frames: int) -> None:
        state = state0
        for _ in range(frames):
            state, _ = step(model, state, dt)

    return run


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--baseline", default="026440c", help="git ref of the old physics/integrators.py")
    parser.add_argument("--previous", default="b277ef6", help="git ref of the previous RealtimeStepper")
    parser.add_argument("--seconds", type=float, default=5.0, help="simulated seconds per run")
    args = parser.parse_args(argv)
    old = baseline_module(args.baseline) if args.baseline else None
    previous = previous_stepper(args.previous) if args.previous else None
    print(f"ms of wall per simulated second (best of {RUNS} runs of {args.seconds:g} s)")
    print(f"| case | frame dt [s] | RealtimeStepper.step | RealtimeStepper.step @ {args.previous} | "
          f"step_realtime (stateless) | old step_realtime @ {args.baseline} |")
    print("|---|---|---|---|---|---|")
    for name in CASES:
        case = load_case(ROOT / "benchmarks" / "cases" / f"{name}.json")
        for dt in FRAME_STEPS:
            frames = round(args.seconds / dt)
            new = ms_per_simulated_second(stepper_run(case.model, case.state0, dt), frames, args.seconds)
            stateless = ms_per_simulated_second(function_run(step_realtime, case.model, case.state0, dt), frames,
                                                args.seconds)
            cells = [f"{new:.2f}"]
            if previous is not None:
                before = ms_per_simulated_second(stepper_run(case.model, case.state0, dt, previous), frames,
                                                 args.seconds)
                cells.append(f"{before:.2f}")
            else:
                cells.append("n/a")
            cells.append(f"{stateless:.2f}")
            if old is not None:
                old_step = old.step_realtime  # type: ignore[attr-defined]
                old_ms = ms_per_simulated_second(function_run(old_step, case.model, case.state0, dt), frames,
                                                 args.seconds)
                cells.append(f"{old_ms:.2f}")
            else:
                cells.append("n/a")
            print(f"| {name} | 1/{round(1 / dt)} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
