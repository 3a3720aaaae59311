"""Load test: N browser stand-ins watch a physics scene play; frames per second each one receives.

The app runs in a subprocess (its own interpreter, so the clients never share its GIL) on
127.0.0.1 and an ephemeral port.  The clients are pure-Python viser clients (ws_client.py),
all on one asyncio loop in this process.  Each one does what a user does in a browser: picks
the scene in the scene dropdown and clicks Play; nothing is started from the server side.

Measured over `--seconds` after a warm-up, per client: the frames per second it receives, the
longest gap between two frames, and the bytes per second.  Once a client has pressed Play it
only counts frames, without decoding them (decoding every frame in this process would starve
the server on a 2-core machine): a frame is one websocket message, which is one drawn frame of
its view (the view draws inside one atomic block, sent as one window).  For the server
process: CPU % (from /proc/<pid>/stat; 100 % = one core) and resident memory (VmRSS, peak
VmHWM); the app loop's rate [Hz] and the share of wall time it spends advancing rooms and
drawing views ("loop busy", timed by wrapping Room.advance and Room.draw in the server
process).  The clients' own CPU % is printed too: if it nears 100 %, the clients, not the
server, limit the figures.

    python benchmarks/load_clients.py                     # 20 clients, free body, 20 s
    python benchmarks/load_clients.py --clients 40 --scene "Heavy top" --seconds 30
    python benchmarks/load_clients.py --clients 1,10,20 --seconds 10   # one row per count
    python benchmarks/load_clients.py --clients 20,60,80 --baseline 2cce6d0   # and that commit's app
    python benchmarks/load_clients.py --followers --clients 50,200,500 --baseline 21f6295   # the hall

Targets (lean-frames issue): 500 followers >= 30 fps median and >= 27 for the slowest; 60
clients each playing their own free body >= 40 fps median and >= 36 for the slowest; 80 clients
>= 15 fps each, and the total frames delivered do not fall as clients are added.
Bounded: at most --clients connections, everything stops after warm-up + seconds (the server
also exits by itself when this process ends or after a hard time limit).
"""

from __future__ import annotations

import argparse
import asyncio
import dataclasses
import gc
import math
import os
import queue
import re
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
PRESENTER_CODE = "314159"  # the --serve app's presenter code (--followers)
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.ws_client import AsyncViserClient, ClientState, GuiElement  # noqa: E402

__all__ = [
    "LoadResult",
    "ProcessSample",
    "ServerProcess",
    "cpu_percent",
    "serve",
    "start_playing",
    "find_play_control",
    "find_scene_dropdown",
    "format_table",
    "main",
    "run_load",
    "sample_process",
    "scene_option",
]

SCENES = ("Free body", "Heavy top")
MAX_CLIENTS = 600
PLAY_LABEL = re.compile(r"(^|\W)(play|run|start)(\W|$)|▶", re.IGNORECASE)
PAUSE_LABEL = re.compile(r"pause|stop|⏸", re.IGNORECASE)
CLK_TCK = os.sysconf("SC_CLK_TCK")


# ---------------------------------------------------------------------------- GUI discovery
def _option_key(text: str) -> str:
    return re.sub(r"[\W_]+", " ", text).strip().lower()


def scene_option(options: tuple[str, ...] | list[str], scene: str, exact: bool = True) -> str | None:
    """The dropdown option naming `scene`: equal ignoring case and punctuation, or (exact=False)
    containing it."""
    wanted = _option_key(scene)
    for option in options:
        key = _option_key(option)
        if key == wanted or (not exact and wanted in key):
            return option
    return None


def find_scene_dropdown(state: ClientState, scene: str) -> tuple[GuiElement, str] | None:
    """(the dropdown whose options name `scene`, that option) or None; an exact match in any
    dropdown wins over a partial one."""
    with state.lock:
        dropdowns = [e for e in state.gui.values() if "Dropdown" in e.type]
    for exact in (True, False):
        for element in dropdowns:
            option = scene_option(tuple(element.props.get("options", ())), scene, exact)
            if option is not None:
                return element, option
    return None


def find_play_control(state: ClientState, exclude: set[str] | frozenset[str] = frozenset()
                      ) -> GuiElement | None:
    """The visible, enabled Play button (or Play/Run checkbox) not in `exclude` (uuids), or None."""
    with state.lock:
        elements = [e for e in state.gui.values() if e.uuid not in exclude]
    for element in reversed(elements):
        if not element.props.get("visible", True) or element.props.get("disabled", False):
            continue
        if ("Button" in element.type and "Group" not in element.type) or "Checkbox" in element.type:
            if PLAY_LABEL.search(element.label) and not PAUSE_LABEL.search(element.label):
                return element
    return None


def _gui_send(element: GuiElement, value: Any) -> Any:
    from benchmarks.ws_client import gui_update_message

    return gui_update_message(element.uuid, value)


async def present_and_play(presenter: AsyncViserClient, scene: str, timeout: float = 30.0,
                           code: str = PRESENTER_CODE) -> str:
    """Type the presenter `code`, press Present, then `start_playing(scene)`, as a browser would;
    the body node."""
    await presenter.wait_for_label("Presenter code", timeout)
    await presenter.set_value("Presenter code", code)
    await asyncio.sleep(0.2)
    await presenter.click("Present")
    await asyncio.sleep(0.5)
    return await start_playing(presenter, scene, timeout=timeout)


PRESS_AGAIN_S = 15.0  # [s] Play is pressed again when neither motion nor Pause came this long after a press


async def start_playing(client: AsyncViserClient, scene: str, timeout: float = 15.0) -> str:
    """Select `scene` and press Play through GUI messages, as a browser would; wait until the
    client sees its body move (>= 5 orientation messages of one node).  Returns the body node.

    Raises:
        TimeoutError: the dropdown, the Play control or the motion did not appear in time.
    """
    state = client.state
    await client.wait_for(lambda: find_play_control(state) is not None, timeout)  # the first panel is here
    found = await client.wait_for(lambda: find_scene_dropdown(state, scene), timeout)
    dropdown, option = found
    old_uuids: set[str] = set()
    if dropdown.value != option:
        old_uuids = set(state.gui)
        await client.send(_gui_send(dropdown, option))
        dropdown.value = option
        # The scene's GUI is rebuilt: wait for ITS Play control (callbacks run on the server's
        # thread pool, so a click sent earlier could overtake the selection).
    deadline = time.monotonic() + timeout
    while True:
        play = await client.wait_for(lambda: find_play_control(state, old_uuids),
                                     max(deadline - time.monotonic(), 0.1))
        await asyncio.sleep(0.2)  # let the rest of the scene's GUI arrive
        state.reset_pose_stats()
        await client.send(_gui_send(play, True))
        # Wait for the motion, or for the control to show Pause (the press was taken: a busy server
        # is slow to start drawing); press again only when neither came within PRESS_AGAIN_S (a
        # second press too soon would pause what the first one started).
        try:
            await client.wait_for(lambda: find_play_control(state, old_uuids) is None or (
                (b := state.busiest_node()) is not None and b[1].orientations >= 5),
                min(PRESS_AGAIN_S, max(deadline - time.monotonic(), 0.1)))
        except TimeoutError:
            if time.monotonic() > deadline:
                raise TimeoutError(f"{scene}: no motion after pressing {play.label!r}") from None
            continue
        try:
            busiest = await client.wait_for(
                lambda: (b := state.busiest_node()) is not None and b[1].orientations >= 5 and b,
                max(deadline - time.monotonic(), 0.1))
        except TimeoutError:
            raise TimeoutError(f"{scene}: no motion after pressing {play.label!r}") from None
        return busiest[0]


# ---------------------------------------------------------------------------- server process
@dataclasses.dataclass(frozen=True)
class ProcessSample:
    """CPU time (user + system) [s], wall time [s, monotonic], VmRSS and VmHWM [MiB]."""

    cpu_s: float
    wall_s: float
    rss_mib: float
    hwm_mib: float


def sample_process(pid: int) -> ProcessSample:
    """Read /proc/<pid>/stat (utime, stime) and /proc/<pid>/status (VmRSS, VmHWM)."""
    wall = time.monotonic()
    stat = Path(f"/proc/{pid}/stat").read_text()
    fields = stat[stat.rindex(")") + 2:].split()  # after "pid (comm) ": fields from #3 on
    cpu = (int(fields[11]) + int(fields[12])) / CLK_TCK  # utime #14, stime #15
    memory = {}
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(("VmRSS:", "VmHWM:")):
            key, value, _unit = line.split()
            memory[key[:-1]] = int(value) / 1024.0
    return ProcessSample(cpu, wall, memory.get("VmRSS", math.nan), memory.get("VmHWM", math.nan))


def cpu_percent(first: ProcessSample, last: ProcessSample) -> float:
    """CPU % between two samples (100 % = one core busy)."""
    return 100.0 * (last.cpu_s - first.cpu_s) / max(last.wall_s - first.wall_s, 1e-9)


def serve(max_lifetime: float) -> None:
    """--serve: the app on 127.0.0.1:0; prints 'BENCH_PORT <port>'.  Each line 'stats' on stdin
    is answered with 'BENCH_STATS <loop iterations> <monotonic time> <sessions> <seconds spent in
    Room.tick>' (the benchmark times the ticks by wrapping Room.tick).  Exits when
    stdin closes (this process's parent is gone) or after `max_lifetime` seconds."""
    if os.environ.get("BENCH_APP_ROOT"):  # --baseline: the app of another tree
        sys.path.insert(0, os.environ["BENCH_APP_ROOT"])
    import app.main
    from app.main import create_server

    if hasattr(app.main, "tune_collector"):  # as the command line does (a tree from before: Python's)
        app.main.tune_collector()
    full_passes = [0, 0.0, 0.0]  # the collector's full passes: count, total and longest [s]
    started = [0.0]

    def on_collect(phase: str, info: dict[str, int]) -> None:
        if info["generation"] != 2:
            return
        if phase == "start":
            started[0] = time.perf_counter()
            return
        took = time.perf_counter() - started[0]
        full_passes[0] += 1
        full_passes[1] += took
        full_passes[2] = max(full_passes[2], took)

    gc.callbacks.append(on_collect)

    tick_seconds = [0.0]  # wall time spent in Room.advance and Room.draw (the app loop's thread)

    def timed(method: Any) -> Any:
        def run(self: Any, *args: Any) -> None:
            start = time.perf_counter()
            try:
                method(self, *args)
            finally:
                tick_seconds[0] += time.perf_counter() - start

        return run

    try:
        from app.kit.core.room import Room
    except ImportError:  # a tree from before the scene kit: its loop calls Session.tick
        from app.session import Session

        Session.tick = timed(Session.tick)  # type: ignore[method-assign]
    else:
        Room.advance = timed(Room.advance)  # type: ignore[method-assign]  # this process only
        Room.draw = timed(Room.draw)  # type: ignore[method-assign]
    try:
        server = create_server("127.0.0.1", 0, verbose=False, presenter_code=PRESENTER_CODE)
    except TypeError:  # --baseline: an app from before the lecture hall
        server = create_server("127.0.0.1", 0, verbose=False)
    print(f"BENCH_APP {Path(app.main.__file__).resolve().parent}", flush=True)  # which tree's app
    print(f"BENCH_PORT {server.port}", flush=True)
    done = threading.Event()

    def commands() -> None:
        for line in sys.stdin:
            if line.strip() == "stats":
                print(f"BENCH_STATS {server.tick_count} {time.monotonic()} {len(server.sessions)} "
                      f"{tick_seconds[0]} {full_passes[0]} {full_passes[1]} {full_passes[2]}", flush=True)
                full_passes[2] = 0.0  # the longest since the last stats
        done.set()

    threading.Thread(target=commands, daemon=True).start()
    done.wait(max_lifetime)
    server.stop()


class ServerProcess:
    """The app in a subprocess (this file with --serve); `port`, `pid`, `stop()`."""

    def __init__(self, max_lifetime: float, start_timeout: float = 30.0,
                 argv: list[str] | None = None, app_root: Path | None = None) -> None:
        self._log = tempfile.TemporaryFile(mode="w+")
        argv = argv or [sys.executable, str(Path(__file__).resolve()), "--serve"]
        env = dict(os.environ, BENCH_APP_ROOT=str(app_root)) if app_root is not None else None
        self.process = subprocess.Popen(
            [*argv, "--max-lifetime", str(max_lifetime)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._log, text=True, cwd=ROOT, env=env,
        )
        self.pid = self.process.pid
        self.port = self._read_port(start_timeout)

    def _read_port(self, timeout: float) -> int:
        self._stats: queue.Queue[tuple[int, float, int, float, int, float, float]] = queue.Queue()
        self.app_folder: Path | None = None  # the app package the server imported (printed before its port)
        found: list[int] = []

        def reader() -> None:
            assert self.process.stdout is not None
            for line in self.process.stdout:  # drained to the end (rich prints the URL panel)
                if line.startswith("BENCH_APP "):
                    self.app_folder = Path(line[len("BENCH_APP "):].strip())
                elif line.startswith("BENCH_PORT "):
                    found.append(int(line.split()[1]))
                elif line.startswith("BENCH_STATS "):
                    _tag, ticks, now, sessions, tick_s, passes, passes_s, longest_s = line.split()
                    self._stats.put((int(ticks), float(now), int(sessions), float(tick_s), int(passes),
                                     float(passes_s), float(longest_s)))

        threading.Thread(target=reader, daemon=True).start()
        deadline = time.monotonic() + timeout
        while not found:
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"the app did not start: {self.log_tail()}")
            time.sleep(0.02)
        return found[0]

    def loop_stats(self, timeout: float = 5.0) -> tuple[int, float, int, float, int, float, float]:
        """(app loop iterations so far, the server's monotonic time [s], open sessions, total time
        spent in Room.advance and Room.draw [s], the garbage collector's full passes so far, their
        total time [s], the longest since the previous call [s])."""
        assert self.process.stdin is not None
        self.process.stdin.write("stats\n")
        self.process.stdin.flush()
        return self._stats.get(timeout=timeout)

    def log_tail(self, chars: int = 2000) -> str:
        self._log.seek(0)
        return self._log.read()[-chars:]

    def stop(self) -> None:
        """Close its stdin (it exits by itself), then wait; terminate only if it hangs."""
        if self.process.poll() is None:
            try:
                assert self.process.stdin is not None
                self.process.stdin.close()
                self.process.wait(timeout=10.0)
            except (subprocess.TimeoutExpired, OSError):
                self.process.terminate()
                self.process.wait(timeout=5.0)


# ---------------------------------------------------------------------------- the run
@dataclasses.dataclass
class LoadResult:
    """One load run.  fps[i], max_gap_s[i], kbytes_per_s[i]: client i over the window."""

    clients: int
    scene: str
    seconds: float
    fps: list[float]
    max_gap_s: list[float]
    kbytes_per_s: list[float]
    server_cpu_percent: float
    server_rss_mib: float
    server_hwm_mib: float
    server_rss_idle_mib: float
    client_cpu_percent: float
    body_nodes: list[str]
    decode_errors: int
    loop_hz: float = math.nan
    loop_busy_percent: float = math.nan  # share of wall time the loop spent in Room.tick
    sessions: int = -1
    gc_full_passes: int = -1  # the server's garbage collector's full passes in the window
    gc_full_longest_ms: float = math.nan  # the longest of them
    gc_full_percent: float = math.nan  # their share of wall time

    def summary(self) -> dict[str, float]:
        return {
            "fps_min": min(self.fps), "fps_median": statistics.median(self.fps),
            "fps_max": max(self.fps), "clients_below_30": sum(f < 30.0 for f in self.fps),
            "max_gap_ms": 1e3 * max(self.max_gap_s),
        }


def run_async(coroutine: Any) -> Any:
    """asyncio.run(coroutine) in a thread of its own: callers may already run an event loop
    (pytest after Playwright's sync API, a notebook)."""
    import concurrent.futures

    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        return pool.submit(asyncio.run, coroutine).result()


async def _measure(server: ServerProcess, connected: list[AsyncViserClient], scene: str, warmup: float,
                   seconds: float, idle: ProcessSample, body_nodes: list[str]) -> LoadResult:
    """Count the frames `connected` clients receive over `seconds` after `warmup` (they only
    count from now on: decoding would starve the server on these 2 cores), with the server's
    CPU, memory and loop figures over the same window."""
    pid = server.pid
    for c in connected:
        c.state.count_only = True
    await asyncio.sleep(warmup)
    loop0 = await asyncio.to_thread(server.loop_stats)
    server0, client_cpu0, t0 = sample_process(pid), time.process_time(), time.monotonic()
    for c in connected:
        c.state.max_frame_gap = 0.0
    frames0 = [c.state.frames for c in connected]
    bytes0 = [c.state.bytes_received for c in connected]
    await asyncio.sleep(seconds)
    frames1 = [c.state.frames for c in connected]
    gaps = [c.state.max_frame_gap for c in connected]
    bytes1 = [c.state.bytes_received for c in connected]
    server1, client_cpu1, t1 = sample_process(pid), time.process_time(), time.monotonic()
    loop1 = await asyncio.to_thread(server.loop_stats)
    window = t1 - t0
    return LoadResult(
        clients=len(connected), scene=scene, seconds=window,
        fps=[(f1 - f0) / window for f0, f1 in zip(frames0, frames1)], max_gap_s=gaps,
        kbytes_per_s=[(b1 - b0) / window / 1e3 for b0, b1 in zip(bytes0, bytes1)],
        server_cpu_percent=cpu_percent(server0, server1), server_rss_mib=server1.rss_mib,
        server_hwm_mib=server1.hwm_mib, server_rss_idle_mib=idle.rss_mib,
        client_cpu_percent=100.0 * (client_cpu1 - client_cpu0) / window, body_nodes=body_nodes,
        decode_errors=sum(len(c.state.errors) for c in connected),
        loop_hz=(loop1[0] - loop0[0]) / (loop1[1] - loop0[1]), sessions=loop1[2],
        loop_busy_percent=100.0 * (loop1[3] - loop0[3]) / (loop1[1] - loop0[1]),
        gc_full_passes=loop1[4] - loop0[4], gc_full_longest_ms=1e3 * loop1[6],
        gc_full_percent=100.0 * (loop1[5] - loop0[5]) / (loop1[1] - loop0[1]),
    )


async def _run_clients(server: ServerProcess, clients: int, scene: str, warmup: float, seconds: float
                       ) -> LoadResult:
    port, pid = server.port, server.pid
    idle = sample_process(pid)
    connected: list[AsyncViserClient] = []
    try:
        for _ in range(clients):  # one after the other, as a class of students would arrive
            connected.append(await AsyncViserClient.connect(port, keep_messages=200))
        # Building a physics scene takes a while when 20 clients ask at once on a busy machine:
        # the start-up is not measured, so it gets a generous time limit.
        bodies = await asyncio.gather(*(start_playing(c, scene, timeout=30.0 + 2.0 * clients)
                                        for c in connected))
        return await _measure(server, connected, scene, warmup, seconds, idle, sorted(set(bodies)))
    finally:
        await asyncio.gather(*(c.close() for c in connected), return_exceptions=True)


async def _run_followers(server: ServerProcess, followers: int, scene: str, warmup: float, seconds: float
                         ) -> LoadResult:
    """One presenter (types the code, presses Present, picks `scene`, presses Play) and
    `followers` browsers that join and only count the frames of the shared scene."""
    port, pid = server.port, server.pid
    idle = sample_process(pid)
    presenter = await AsyncViserClient.connect(port, keep_messages=200)
    connected: list[AsyncViserClient] = []
    try:
        await present_and_play(presenter, scene, timeout=30.0)
        presenter.state.count_only = True
        for _ in range(followers):
            connected.append(await AsyncViserClient.connect(port, keep_messages=50))
        await asyncio.gather(*(c.wait_for(lambda c=c: c.state.replay_done, 60.0 + 0.5 * followers)
                               for c in connected))
        return await _measure(server, connected, f"{scene} (followers)", warmup, seconds, idle, [])
    finally:
        await asyncio.gather(*(c.close() for c in [presenter, *connected]), return_exceptions=True)


def run_followers(followers: int, seconds: float = 20.0, scene: str = "Free body", warmup: float = 3.0,
                  app_root: Path | None = None) -> LoadResult:
    """Start the app in a subprocess, a presenter playing `scene` and `followers` followers; measure."""
    server = ServerProcess(max_lifetime=warmup + seconds + 120.0 + 1.0 * followers, app_root=app_root)
    try:
        return run_async(_run_followers(server, followers, scene, warmup, seconds))
    except Exception as error:
        raise RuntimeError(f"{error}\n--- server log ---\n{server.log_tail()}") from error
    finally:
        server.stop()


def run_load(clients: int = 20, seconds: float = 20.0, scene: str = "Free body", warmup: float = 3.0,
             server_argv: list[str] | None = None, app_root: Path | None = None) -> LoadResult:
    """Start the app in a subprocess, run `clients` clients playing `scene`, measure, stop.

    server_argv: another server command (it must accept --max-lifetime and print
    'BENCH_PORT <port>'); default: this file with --serve.
    """
    if clients < 1 or not (seconds > 0.0) or warmup < 0.0:
        raise ValueError("need clients >= 1, seconds > 0, warmup >= 0")
    server = ServerProcess(max_lifetime=warmup + seconds + 90.0 + 5.0 * clients, argv=server_argv,
                           app_root=app_root)
    try:
        return run_async(_run_clients(server, clients, scene, warmup, seconds))
    except Exception as error:
        raise RuntimeError(f"{error}\n--- server log ---\n{server.log_tail()}") from error
    finally:
        server.stop()


def format_table(results: list[LoadResult]) -> str:
    """Markdown table, one row per run."""
    lines = [
        "| scene | clients | fps min | fps median | fps max | clients < 30 fps | max gap [ms] "
        "| kB/s per client | app loop [Hz] | loop busy % | server CPU % | server RSS [MiB] (idle → loaded, peak) "
        "| full GC passes (longest [ms], % of time) | client CPU % |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        s = r.summary()
        lines.append(
            f"| {r.scene} | {r.clients} | {s['fps_min']:.1f} | {s['fps_median']:.1f} | {s['fps_max']:.1f} "
            f"| {s['clients_below_30']} | {s['max_gap_ms']:.0f} | {statistics.median(r.kbytes_per_s):.1f} "
            f"| {r.loop_hz:.1f} | {r.loop_busy_percent:.0f} | {r.server_cpu_percent:.0f} "
            f"| {r.server_rss_idle_mib:.0f} → {r.server_rss_mib:.0f}, "
            f"{r.server_hwm_mib:.0f} | {r.gc_full_passes} ({r.gc_full_longest_ms:.0f}, {r.gc_full_percent:.0f} %) "
            f"| {r.client_cpu_percent:.0f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clients", default="20",
                        help="number of clients, or a comma-separated list for one row each (default %(default)s)")
    parser.add_argument("--seconds", type=float, default=20.0, help="measured window [s] (default %(default)s)")
    parser.add_argument("--warmup", type=float, default=3.0, help="warm-up after Play [s] (default %(default)s)")
    parser.add_argument("--scene", default="Free body", help=f"scene to play, e.g. {' / '.join(SCENES)}")
    parser.add_argument("--followers", action="store_true",
                        help="one presenter plays, the clients follow it (the lecture hall)")
    parser.add_argument("--baseline", metavar="REF",
                        help="first run the same clients against the app at git commit REF (a worktree)")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--max-lifetime", type=float, default=300.0, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.serve:
        serve(args.max_lifetime)
        return
    counts = [int(n) for n in str(args.clients).split(",")]
    if any(n < 1 or n > MAX_CLIENTS for n in counts):
        parser.error(f"--clients: between 1 and {MAX_CLIENTS}")

    def run(n: int, app_root: Path | None = None) -> LoadResult:
        if args.followers:
            return run_followers(n, args.seconds, args.scene, args.warmup, app_root=app_root)
        return run_load(n, args.seconds, args.scene, args.warmup, app_root=app_root)

    if args.baseline:
        with tempfile.TemporaryDirectory(prefix="load_clients_") as tmp:
            tree = Path(tmp) / "tree"
            subprocess.run(["git", "worktree", "add", "--detach", "--quiet", str(tree), args.baseline],
                           cwd=ROOT, check=True)
            baseline, failed = [], []
            try:
                for n in counts:
                    try:
                        baseline.append(run(n, app_root=tree))
                    except RuntimeError as error:  # e.g. frozen: the clients never got their Play button
                        failed.append(f"{n} clients: the run failed: {str(error).splitlines()[0]}")
            finally:
                subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, check=False)
        print(f"## baseline: the app at {args.baseline}, the same clients\n")
        print(format_table(baseline) if baseline else "(no run finished)")
        print("\n".join(["", *failed]) if failed else "")
        print("\n## this tree\n")
    results, loads = [], []
    for n in counts:
        loads.append(os.getloadavg()[0])
        results.append(run(n))
    print(format_table(results))
    print(f"\nbody node(s): {', '.join(sorted({b for r in results for b in r.body_nodes})) or '-'}; "
          f"window {args.seconds:g} s after {args.warmup:g} s warm-up; {os.cpu_count()} CPUs; "
          f"1-min load average before each run: {', '.join(f'{x:.1f}' for x in loads)} (other jobs "
          f"may share the machine); decode errors: {sum(r.decode_errors for r in results)}")
    if args.followers:
        print("followers count websocket messages: the shared scene's frames plus their panel's "
              "refresh (2 a second)")
    for r in results:
        print(f"fps per client ({r.clients}): min {min(r.fps):.1f}, "
              f"deciles {' '.join(f'{q:.0f}' for q in statistics.quantiles(r.fps, n=10))}"
              if len(r.fps) > 1 else f"fps per client ({r.clients}): {r.fps[0]:.0f}")


if __name__ == "__main__":
    main()
