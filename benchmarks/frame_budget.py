"""The frame budget: what ONE playing browser receives, per scene, in its own room and as a follower.

The app runs in a subprocess (`load_clients.ServerProcess`, its own interpreter) on 127.0.0.1
and an ephemeral port; the clients are pure-Python viser clients (ws_client.py) in this process
that press what a user presses, and this time they decode every frame (one client at a time,
cheap) to count the messages by category (`ws_client.message_category`): scene messages
(SetOrientation, SetPosition, SceneNodeUpdate, visibility, nodes created or removed) and GUI
messages (the panel, notifications, commands).

- own room: for each scene, a new browser connects, picks the scene in the Scene dropdown
  (its default preset), presses Play;
- follower: one presenter types the code 314159, presses Present, and for each scene picks it
  and presses Play; then a new browser joins (it follows the presenter) and is measured.

Per scene: warm-up `--warmup` s after Play (a follower: after its replay), then measured over
`--seconds` s: kB/s received (wire bytes, websocket frames as sent), drawn frames per second
(websocket frames with at least one scene message), scene messages per drawn frame, bytes per
drawn frame, GUI messages per second.  A scene the tree does not have, or that has no Play
(Inertia), or that does not move after Play, is "n/a".

    python benchmarks/frame_budget.py                        # every scene, 2 s warm-up, 5 s each
    python benchmarks/frame_budget.py --scenes "Free body,Heavy top" --seconds 10
    python benchmarks/frame_budget.py --baseline 21f6295     # and that commit's app, side by side

--baseline REF checks REF out in a temporary git worktree and runs its app (BENCH_APP_ROOT, as
load_clients.py --baseline does) with this tree's clients, in the same run, before this tree's.
Budget (frame-budget issue): 15 kB/s per playing browser, 250 B per frame at 60 fps.  Counted
over wall-clock windows: the figures depend on the app keeping 60 fps on this machine, which
the fps column shows.  The deterministic, counted version is tests/test_frame_budget.py.
"""

from __future__ import annotations

import argparse
import asyncio
import dataclasses
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.load_clients import (  # noqa: E402
    PRESENTER_CODE,
    ServerProcess,
    find_play_control,
    find_scene_dropdown,
    run_async,
    scene_option,
)
from benchmarks.ws_client import AsyncViserClient, ClientState, GuiElement, gui_update_message  # noqa: E402

__all__ = ["ALL_SCENES", "BUDGET_BYTES_PER_SECOND", "Figures", "format_table", "main", "measure_tree"]

ALL_SCENES = ("Free body", "Heavy top", "Poinsot", "Euler angles", "Moving frame", "Constrained particles",
              "Inertia")
HOW = ("own", "follower")
BUDGET_BYTES_PER_SECOND = 15_000.0  # [B/s] per playing browser (250 B a frame at 60 fps)
PLAY_TIMEOUT = 6.0  # [s] for the scene's Play control to appear, and for motion after pressing it
MIN_MOVING_FRAMES = 10  # drawn frames within PLAY_TIMEOUT after Play: the scene plays


@dataclasses.dataclass(frozen=True)
class Figures:
    """What one browser received over `seconds` [s]: wire bytes, websocket frames, drawn frames
    (frames with a scene message), scene and GUI messages."""

    seconds: float
    bytes: int
    frames: int
    drawn_frames: int
    scene_messages: int
    gui_messages: int

    @property
    def kbytes_per_s(self) -> float:
        return self.bytes / self.seconds / 1e3

    @property
    def fps(self) -> float:
        """Drawn frames received per second."""
        return self.drawn_frames / self.seconds

    @property
    def bytes_per_frame(self) -> float:
        return self.bytes / max(self.drawn_frames, 1)

    @property
    def scene_messages_per_frame(self) -> float:
        return self.scene_messages / max(self.drawn_frames, 1)

    @property
    def gui_messages_per_s(self) -> float:
        return self.gui_messages / self.seconds


Result = Figures | str  # a string: why there is no figure ("n/a: ...")


def _counts(state: ClientState) -> tuple[int, int, int, int, int]:
    with state.lock:
        return (state.bytes_received, state.frames, state.scene_frames, state.category_counts["scene"],
                state.category_counts["gui"])


async def _measure(state: ClientState, warmup: float, seconds: float) -> Figures:
    await asyncio.sleep(warmup)
    before, t0 = _counts(state), time.monotonic()
    await asyncio.sleep(seconds)
    after, t1 = _counts(state), time.monotonic()
    delta = [b - a for a, b in zip(before, after)]
    return Figures(t1 - t0, *delta)


def _scene_dropdown(state: ClientState, scene: str) -> tuple[GuiElement, str] | None:
    """The dropdown labelled "Scene" and its option for `scene`; None if it has none (an older
    tree without that scene).  Any dropdown naming it, if none is labelled "Scene"."""
    element = state.find_gui("Scene", "Dropdown")
    if element is None:
        return find_scene_dropdown(state, scene)
    option = scene_option(tuple(element.props.get("options", ())), scene)
    return None if option is None else (element, option)


async def _settle(state: ClientState, quiet: float = 0.3, timeout: float = 10.0) -> None:
    """Wait until no GUI element has been added or removed for `quiet` [s] (a first panel can
    come in several windows), at most `timeout` [s]."""
    deadline = time.monotonic() + timeout
    last = -1
    while time.monotonic() < deadline:
        with state.lock:
            count = len(state.gui)
        if count == last:
            return
        last = count
        await asyncio.sleep(quiet)


async def _select_and_play(client: AsyncViserClient, scene: str) -> str | None:
    """Pick `scene` in the Scene dropdown and press its Play, as a browser would; None once it
    moves, else why not ("n/a: ...")."""
    state = client.state
    try:
        await client.wait_for(lambda: state.find_gui("Scene", "Dropdown") or find_scene_dropdown(state, scene),
                              30.0)
    except TimeoutError:
        return "n/a: no scene dropdown"
    await _settle(state)  # the whole panel: its Play is not the new scene's
    found = _scene_dropdown(state, scene)
    if found is None:
        return "n/a: no such scene"
    dropdown, option = found
    old_uuids: set[str] = set()
    if dropdown.value != option:
        old_uuids = set(state.gui)
        await client.send(gui_update_message(dropdown.uuid, option))
        dropdown.value = option
    try:  # the scene's own Play (its panel is rebuilt; the old panel's Play is excluded)
        play = await client.wait_for(lambda: find_play_control(state, old_uuids), PLAY_TIMEOUT)
    except TimeoutError:
        return "n/a: no Play"
    await asyncio.sleep(0.3)  # the rest of the scene's panel and nodes arrive
    drawn = state.scene_frames
    await client.send(gui_update_message(play.uuid, True))
    try:
        await client.wait_for(lambda: state.scene_frames >= drawn + MIN_MOVING_FRAMES, PLAY_TIMEOUT)
    except TimeoutError:
        return "n/a: no motion after Play"
    return None


async def _own(port: int, scene: str, warmup: float, seconds: float) -> Result:
    client = await AsyncViserClient.connect(port, keep_messages=200)
    try:
        why_not = await _select_and_play(client, scene)
        return why_not if why_not is not None else await _measure(client.state, warmup, seconds)
    finally:
        await client.close()


async def _present(port: int) -> AsyncViserClient:
    presenter = await AsyncViserClient.connect(port, keep_messages=200)
    await presenter.wait_for_label("Presenter code", 30.0)
    await presenter.set_value("Presenter code", PRESENTER_CODE)
    await asyncio.sleep(0.2)
    await presenter.click("Present")
    await asyncio.sleep(0.5)
    return presenter


async def _follow(port: int, presenter: AsyncViserClient, scene: str, warmup: float, seconds: float) -> Result:
    why_not = await _select_and_play(presenter, scene)
    if why_not is not None:
        return why_not
    follower = await AsyncViserClient.connect(port, keep_messages=200)
    try:
        await follower.wait_for(lambda: follower.state.replay_done, 30.0)
        return await _measure(follower.state, warmup, seconds)
    finally:
        await follower.close()


async def _measure_all(port: int, scenes: tuple[str, ...], warmup: float, seconds: float
                       ) -> dict[tuple[str, str], Result]:
    results: dict[tuple[str, str], Result] = {}
    for scene in scenes:
        results[scene, "own"] = await _own(port, scene, warmup, seconds)
    presenter = await _present(port)
    try:
        for scene in scenes:
            results[scene, "follower"] = await _follow(port, presenter, scene, warmup, seconds)
    finally:
        await presenter.close()
    return results


def measure_tree(scenes: tuple[str, ...], warmup: float = 2.0, seconds: float = 5.0,
                 app_root: Path | None = None) -> dict[tuple[str, str], Result]:
    """{(scene, "own" | "follower"): Figures or "n/a: why"} for the app of `app_root` (this tree
    if None), in a subprocess."""
    if not scenes or not (seconds > 0.0) or warmup < 0.0:
        raise ValueError("need at least one scene, seconds > 0, warmup >= 0")
    lifetime = 120.0 + 2 * len(scenes) * (warmup + seconds + 3 * PLAY_TIMEOUT)
    server = ServerProcess(max_lifetime=lifetime, app_root=app_root)
    try:
        return run_async(_measure_all(server.port, scenes, warmup, seconds))
    except Exception as error:
        raise RuntimeError(f"{error}\n--- server log ---\n{server.log_tail()}") from error
    finally:
        server.stop()


def _cell(results: list[dict[tuple[str, str], Result]], key: tuple[str, str], figure: str, digits: int) -> str:
    """The figure for `key` in each run, joined by " → " (baseline → now)."""
    values = []
    for run in results:
        result = run.get(key, "n/a")
        values.append(result.split(":")[0] if isinstance(result, str) else f"{getattr(result, figure):.{digits}f}")
    return " → ".join(values)


def format_table(scenes: tuple[str, ...], results: list[dict[tuple[str, str], Result]]) -> str:
    """Markdown table, one row per scene; with two runs each cell is "baseline → now"."""
    columns = (("kB/s", "kbytes_per_s", 1), ("scene msgs/frame", "scene_messages_per_frame", 1),
               ("fps", "fps", 0), ("B/frame", "bytes_per_frame", 0), ("GUI msgs/s", "gui_messages_per_s", 1))
    header = ["scene"] + [f"{how} {name}" for name, _, _ in columns for how in HOW]
    lines = ["| " + " | ".join(header) + " |", "|---|" + "---:|" * (len(header) - 1)]
    for scene in scenes:
        cells = [scene] + [_cell(results, (scene, how), figure, digits)
                           for _, figure, digits in columns for how in HOW]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _reasons(results: list[dict[tuple[str, str], Result]], labels: list[str]) -> list[str]:
    notes = []
    for label, run in zip(labels, results):
        for (scene, how), result in run.items():
            if isinstance(result, str):
                notes.append(f"{label}, {scene} ({how}): {result}")
    return notes


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--scenes", default=",".join(ALL_SCENES),
                        help="comma-separated scene titles (default: %(default)s)")
    parser.add_argument("--warmup", type=float, default=2.0, help="warm-up after Play [s] (default %(default)s)")
    parser.add_argument("--seconds", type=float, default=5.0, help="measured window [s] (default %(default)s)")
    parser.add_argument("--baseline", metavar="REF",
                        help="first measure the app at git commit REF (a temporary worktree), then this tree")
    args = parser.parse_args(argv)
    scenes = tuple(s.strip() for s in args.scenes.split(",") if s.strip())
    if not scenes:
        parser.error("--scenes: at least one scene")
    if not (args.seconds > 0.0) or args.warmup < 0.0:
        parser.error("--seconds must be > 0 and --warmup >= 0")
    results: list[dict[tuple[str, str], Result]] = []
    labels: list[str] = []
    if args.baseline:
        with tempfile.TemporaryDirectory(prefix="frame_budget_") as tmp:
            tree = Path(tmp) / "tree"
            subprocess.run(["git", "worktree", "add", "--detach", "--quiet", str(tree), args.baseline],
                           cwd=ROOT, check=True)
            try:
                results.append(measure_tree(scenes, args.warmup, args.seconds, app_root=tree))
            finally:
                subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, check=False)
        labels.append(args.baseline)
    load = os.getloadavg()[0]
    results.append(measure_tree(scenes, args.warmup, args.seconds))
    labels.append("this tree")
    if args.baseline:
        print(f"## frame budget: {args.baseline} → this tree (one browser, its own room / following)\n")
    else:
        print("## frame budget: this tree (one browser, its own room / following)\n")
    print(format_table(scenes, results))
    budget_frame = BUDGET_BYTES_PER_SECOND / 60.0
    print(f"\nbudget: {BUDGET_BYTES_PER_SECOND / 1e3:g} kB/s per playing browser ({budget_frame:.0f} B/frame "
          f"at 60 fps).  fps: drawn frames received (websocket frames with a scene message); "
          f"B/frame = bytes / drawn frames; GUI msgs/s: every other message.  {args.warmup:g} s warm-up, "
          f"{args.seconds:g} s measured per scene; {os.cpu_count()} CPUs, 1-min load average {load:.1f} "
          f"before this tree's run (other jobs may share the machine).")
    notes = _reasons(results, labels)
    if notes:
        print("\n" + "\n".join(notes))


if __name__ == "__main__":
    main()
