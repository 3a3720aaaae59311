"""The server's cost per displayed frame at 60 fps: physics step + scene update, one client.

For each physics scene (free body, heavy top) it builds the app in this process with its tick
loop NOT running, connects one pure-Python client (ws_client.py), selects the scene and presses
Play through the GUI messages a browser sends, and then calls `Session.tick(1/60)` itself,
`--frames` times, paced at 60 Hz (as the app's loop does; --unpaced runs them back to back),
timing each call with `time.perf_counter`.  The "physics only" column replays the same motion
with `physics.realtime.RealtimeStepper` alone (one kept stepper, as the app does), from the
same model and state the scene had when the timed ticks began; the scene-update share is the
difference of the medians.

    python benchmarks/frame_cost.py                 # 2000 frames per scene, paced (~70 s)
    python benchmarks/frame_cost.py --frames 600 --unpaced
    python benchmarks/frame_cost.py --baseline 2cce6d0   # and the same at that commit, side by side
    python benchmarks/frame_cost.py --frames 1200 --baseline 21f6295 --rounds 3   # alternating, 3 each

--baseline REF checks REF out in a temporary git worktree and runs REF's own frame_cost.py
there, in a subprocess, right before this tree's run: the same machine, the same minute.  This
machine's speed drifts by a quarter within minutes, so one pair can mislead: --rounds N runs REF
and this tree alternately N times each (every run in its own process): every round's medians
and the median of them.

Target (scene-kit issue): tick median <= 0.4 ms per frame, one client.  Times in ms; p95 and
max include garbage collection and whatever else shares the machine.  "tick CPU" is the ticking thread's own CPU time
(`time.thread_time`): the wall time also holds waits for the GIL, which viser's event-loop
thread takes when a tick's atomic block ends and wakes it to send the frame.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import io
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.load_clients import SCENES, find_play_control, find_scene_dropdown  # noqa: E402
from benchmarks.ws_client import ViserClient, gui_update_message  # noqa: E402
from physics.dynamics import Model, State  # noqa: E402

try:  # the app keeps one stepper per simulation
    from physics.realtime import RealtimeStepper  # noqa: E402
except ImportError:  # an older tree (--baseline): the stateless function
    RealtimeStepper = None  # type: ignore[assignment,misc]
from physics.integrators import step_realtime  # noqa: E402

__all__ = ["FrameCost", "compare_rounds", "find_model_and_state", "format_table", "main", "measure_scene",
           "tick_medians"]

FRAME_DT = 1.0 / 60.0


@dataclasses.dataclass
class FrameCost:
    """Per-frame times [ms] of one scene: tick = App.frame(1/60) (or Session.tick(1/60) in a
    tree without it; wall time, and CPU time of the ticking thread), sent = the process's CPU time
    (all threads) from the frame's start until it was written to the socket, physics =
    step_realtime (wall time)."""

    scene: str
    frames: int
    tick_ms: list[float]
    tick_cpu_ms: list[float]
    physics_ms: list[float]
    sim_time_advanced_s: float
    paced: bool
    sent_cpu_ms: list[float] = dataclasses.field(default_factory=list)

    @staticmethod
    def _stats(values: list[float]) -> tuple[float, float, float]:
        ordered = sorted(values)
        p95 = ordered[min(len(ordered) - 1, math.ceil(0.95 * len(ordered)) - 1)]
        return statistics.median(ordered), p95, ordered[-1]

    @property
    def tick_stats(self) -> tuple[float, float, float]:
        """(median, p95, max) [ms] of the whole tick."""
        return self._stats(self.tick_ms)

    @property
    def tick_cpu_stats(self) -> tuple[float, float, float]:
        """(median, p95, max) [ms] of the ticking thread's CPU time (without GIL waits)."""
        return self._stats(self.tick_cpu_ms)

    @property
    def physics_stats(self) -> tuple[float, float, float]:
        """(median, p95, max) [ms] of step_realtime alone."""
        return self._stats(self.physics_ms)


def find_model_and_state(obj: Any, depth: int = 3) -> tuple[Model, State] | None:
    """The physics Model and State a scene holds (attributes searched `depth` levels deep)."""
    model: Model | None = None
    state: State | None = None
    seen: set[int] = set()
    queue: list[tuple[Any, int]] = [(obj, 0)]
    while queue:
        current, level = queue.pop(0)
        if id(current) in seen:
            continue
        seen.add(id(current))
        try:
            attributes = list(vars(current).values())
        except TypeError:
            continue
        for value in attributes:
            if isinstance(value, Model) and model is None:
                model = value
            elif isinstance(value, State) and state is None:
                state = value
            elif level + 1 < depth and hasattr(value, "__dict__") and type(value).__module__.startswith(
                    ("app", "physics")):
                queue.append((value, level + 1))
    return (model, state) if model is not None and state is not None else None


def _start_playing(app: Any, client: ViserClient, scene: str, timeout: float = 15.0) -> Any:
    """Select `scene` and press Play through GUI messages (what a browser sends); the session.

    The app's loop is not running here, so the client cannot see motion: success is checked on
    the server side (the scene holds a physics state that advances when ticked).
    """
    session = next(iter(app.wait_for_sessions(1, timeout).values()))
    state = client.state
    state.wait_for(lambda: find_play_control(state) is not None, timeout)  # the first scene's panel is here
    dropdown, option = state.wait_for(lambda: find_scene_dropdown(state, scene), timeout)
    old_uuids: set[str] = set()
    if dropdown.value != option:
        old_uuids = set(state.gui)
        client.send(gui_update_message(dropdown.uuid, option))
    play = state.wait_for(lambda: find_play_control(state, old_uuids), timeout)  # the new scene's
    time.sleep(0.2)
    client.send(gui_update_message(play.uuid, True))
    # The click's callback runs on viser's thread pool; check that it took effect.
    deadline = time.monotonic() + timeout
    while not (session.room.playing if hasattr(session, "room") else getattr(session.scene, "playing", False)):
        if time.monotonic() > deadline:
            raise TimeoutError(f"{scene}: the session is not playing after clicking {play.label!r}")
        time.sleep(0.01)
    title = getattr(session.scene, "title", scene)
    if title != option:
        raise RuntimeError(f"asked for {option!r}, the session shows {title!r}")
    return session


def measure_scene(scene: str, frames: int = 2000, paced: bool = True, warmup: int = 60) -> FrameCost:
    """Time `frames` calls of Session.tick(1/60) on `scene` (one connected client), then the
    same motion with step_realtime alone."""
    from app.main import create_server

    with contextlib.redirect_stdout(io.StringIO()):  # viser prints its URL panel regardless
        app = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    client = ViserClient(app.port, keep_messages=100)
    try:
        session = _start_playing(app, client, scene)
        # The loop's own frame where the tree has one (App.frame: the views draw through app.wire,
        # whose encode and socket writes then run on viser's event loop); else Session.tick.
        tick = app.frame if hasattr(app, "frame") else session.tick
        sent = getattr(app, "frames_sent", lambda: True)
        for _ in range(warmup):
            tick(FRAME_DT)
        found = find_model_and_state(session.scene)
        if found is None:
            raise RuntimeError(f"{scene}: no physics Model/State found on {type(session.scene).__name__}")
        model, state0 = found
        tick_ms: list[float] = []
        tick_cpu_ms: list[float] = []
        sent_cpu_ms: list[float] = []  # the process's CPU (all threads) from the frame's start to its delivery
        next_time = time.perf_counter()
        for _ in range(frames):
            start, start_cpu, start_process = time.perf_counter(), time.thread_time(), time.process_time()
            tick(FRAME_DT)
            tick_cpu_ms.append(1e3 * (time.thread_time() - start_cpu))
            tick_ms.append(1e3 * (time.perf_counter() - start))
            while not sent():  # the frame's delivery (app.wire) is part of its cost
                time.sleep(0.0002)
            sent_cpu_ms.append(1e3 * (time.process_time() - start_process))
            if paced:
                next_time += FRAME_DT
                time.sleep(max(0.0, next_time - time.perf_counter()))
        found_after = find_model_and_state(session.scene)
        advanced = found_after[1].t - state0.t if found_after is not None else math.nan
        if session.last_error is not None:
            raise RuntimeError(f"{scene}: the session reported an error: {session.last_error}")
    finally:
        client.close()
        with contextlib.redirect_stdout(io.StringIO()):
            app.stop()

    physics_ms: list[float] = []
    state = State(state0.R_space_body.copy(), state0.omega_body.copy(), state0.t)
    stepper = RealtimeStepper(model, state) if RealtimeStepper is not None else None
    next_time = time.perf_counter()
    for _ in range(frames):
        start = time.perf_counter()
        if stepper is not None:
            stepper.step(FRAME_DT)
        else:
            state, _evaluations = step_realtime(model, state, FRAME_DT)
        physics_ms.append(1e3 * (time.perf_counter() - start))
        if paced:
            next_time += FRAME_DT
            time.sleep(max(0.0, next_time - time.perf_counter()))
    return FrameCost(scene, frames, tick_ms, tick_cpu_ms, physics_ms, advanced, paced, sent_cpu_ms)


def format_table(results: list[FrameCost]) -> str:
    """Markdown table: tick and physics-only median / p95 / max [ms], physics share."""
    lines = [
        "| scene | frames | tick median [ms] | tick p95 | tick max | tick CPU median [ms] "
        "| to the socket, process CPU median [ms] "
        "| physics median [ms] | physics p95 | physics share of median | sim time advanced [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        t_med, t_p95, t_max = r.tick_stats
        p_med, p_p95, _p_max = r.physics_stats
        c_med = r.tick_cpu_stats[0]
        lines.append(
            f"| {r.scene} | {r.frames} | {t_med:.3f} | {t_p95:.3f} | {t_max:.2f} | {c_med:.3f} "
            f"| {statistics.median(r.sent_cpu_ms) if r.sent_cpu_ms else math.nan:.3f} | {p_med:.3f} "
            f"| {p_p95:.3f} | {100.0 * p_med / t_med:.0f} % | {r.sim_time_advanced_s:.2f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=2000, help="timed frames per scene (default %(default)s)")
    parser.add_argument("--scene", action="append", help=f"scene(s) to time (default: {', '.join(SCENES)})")
    parser.add_argument("--unpaced", action="store_true", help="tick back to back instead of at 60 Hz")
    parser.add_argument("--baseline", metavar="REF", help="also run REF's frame_cost.py (a git commit) first")
    parser.add_argument("--rounds", type=int, default=1,
                        help="with --baseline: alternate REF and this tree this many times, each in its own "
                             "process: every round's medians and their median (default %(default)s)")
    args = parser.parse_args(argv)
    if args.frames < 1 or args.rounds < 1:
        parser.error("--frames and --rounds must be >= 1")
    passed = list(argv if argv is not None else sys.argv[1:])
    for option in ("--baseline", "--rounds"):  # not passed on to the runs
        for k, a in reversed(list(enumerate(passed))):
            if a == option:
                del passed[k:k + 2]
            elif a.startswith(option + "="):
                del passed[k]
    if args.baseline and args.rounds > 1:
        compare_rounds(args.baseline, args.rounds, passed)
        return
    if args.baseline:
        print(f"## baseline: {args.baseline}\n")
        with _worktree(args.baseline) as tree:
            print(_run_tree(tree, passed))
        print("\n## this tree\n")
    results = [measure_scene(scene, args.frames, paced=not args.unpaced) for scene in (args.scene or SCENES)]
    print(format_table(results))
    print(f"\n{'paced at 60 Hz' if not args.unpaced else 'back to back'}; one connected client; "
          "target: tick median <= 0.4 ms.")


def tick_medians(output: str) -> dict[str, float]:
    """{scene: tick median [ms]} read from a table frame_cost.py printed (this tree's or an older one's)."""
    medians: dict[str, float] = {}
    column = None
    for line in output.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if column is None and "tick median [ms]" in cells:
            column = cells.index("tick median [ms]")
        elif column is not None and len(cells) > column and cells[0] in SCENES:
            medians[cells[0]] = float(cells[column])
    return medians


def compare_rounds(ref: str, rounds: int, argv: list[str]) -> None:
    """REF and this tree alternately, `rounds` times each, every run in a process of its own (this
    machine's speed drifts by a quarter within minutes: alternating spreads the drift over both);
    each run's table, then per scene the medians of every round and their median."""
    runs: dict[str, list[dict[str, float]]] = {ref: [], "this tree": []}
    with _worktree(ref) as tree:
        for k in range(rounds):
            for name, where in ((ref, tree), ("this tree", ROOT)):
                out = _run_tree(where, argv)
                print(f"## round {k + 1}: {name}\n\n{out}\n")
                runs[name].append(tick_medians(out))
    print(f"## {rounds} rounds, tick median [ms] of each run (alternating, {ref} first)\n")
    print(f"| scene | {ref}: each round | this tree: each round | median of rounds, {ref} / this tree | ratio |")
    print("|---|---|---|---|---:|")
    for scene in SCENES:
        base = [r[scene] for r in runs[ref] if scene in r]
        own = [r[scene] for r in runs["this tree"] if scene in r]
        if base and own:
            b, o = statistics.median(base), statistics.median(own)
            print(f"| {scene} | {', '.join(f'{x:.3f}' for x in base)} | {', '.join(f'{x:.3f}' for x in own)} "
                  f"| {b:.3f} / {o:.3f} | {o / b:.2f} |")


@contextlib.contextmanager
def _worktree(ref: str) -> Any:
    """A temporary git worktree of REF (its path), removed afterwards."""
    with tempfile.TemporaryDirectory(prefix="frame_cost_") as tmp:
        tree = Path(tmp) / "tree"
        subprocess.run(["git", "worktree", "add", "--detach", "--quiet", str(tree), ref], cwd=ROOT, check=True)
        try:
            yield tree
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, check=False)


def _run_tree(tree: Path, argv: list[str]) -> str:
    """`tree`'s own frame_cost.py run in a subprocess (its output, as printed)."""
    out = subprocess.run([sys.executable, "benchmarks/frame_cost.py", *argv], cwd=tree, check=True,
                         capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(tree)})
    return out.stdout.strip()


if __name__ == "__main__":
    main()
