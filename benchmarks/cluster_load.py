"""Load test, side by side in one run: one app process against `--workers 2` behind nginx with the bus,
each figure beside the same figure of a reference commit measured in the same minutes.

The same light websocket clients as benchmarks/load_clients.py (one asyncio loop in this
process, frames counted undecoded): own rooms (each client picks the scene and presses Play in
its own room) and followers (a presenter types the code, presents and plays; the followers only
count frames).  Three set-ups, measured one after the other with the same clients:

- "1 process": the app as `python -m app` starts it (load_clients.py --serve);
- "2 plain processes": two app processes without Redis behind the same nginx (own rooms only:
  they share no lecture);
- "2 workers": redis-server on a free port, two app processes (`create_server(redis_url=...,
  worker_id=...)`, this file with --serve-worker) and nginx in front of them (`least_conn`,
  websockets proxied; `nginx_conf`).  The clients connect to nginx, which spreads them.

Calibration (a table says how fast the machine was when it was measured):

- `--reference REV` (default `REFERENCE`): the app of that git commit, checked out with `git
  worktree add` into a temporary folder and served by the same Python, is measured in every row
  beside this tree, interleaved (this, reference, reference, this, ... `--rounds`): its figures
  and the ratios of this tree's to them are in the table.  `--reference none` leaves it out.
- The machine must be quiet before the run: the 1-minute load average per core and the share of
  the cores busy during a 2-second probe (/proc/stat) must not exceed `--max-load`; otherwise
  it refuses (exit status 2) unless `--force`, which marks the table "measured on a busy machine".
- Per row: fps min / median over the clients; the CPU of every server process (100 % = one
  core: each worker, nginx (all its processes), redis-server), of the clients (this process),
  and of everything else on the machine over the same window (/proc/stat minus those), and the
  time the hypervisor took away (steal); for the workers' bus: the delay it adds from the
  presenter's frame to a follower on the other process (p50/p95 [ms]) and the bytes it
  publishes per frame.
- The table is Markdown (for docs/performance.md) headed by the date, both commits, the machine
  (CPUs, model name), the load average before and after; `--output FILE` also writes it there.

    python benchmarks/cluster_load.py --rooms 80 --followers 100 --seconds 8 --output capacity.md
    python benchmarks/cluster_load.py --rooms 4 --followers 4 --seconds 2 --rounds 1   # a try

Bounded: every process it starts is stopped at the end (and the servers exit when their stdin
closes); the reference's worktree is removed.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import dataclasses
import datetime
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.load_clients import (  # noqa: E402
    CLK_TCK,
    PRESENTER_CODE,
    ServerProcess,
    cpu_percent,
    present_and_play,
    run_async,
    sample_process,
    start_playing,
)
from benchmarks.ws_client import AsyncViserClient  # noqa: E402

__all__ = [
    "REFERENCE",
    "Measured",
    "busy_reason",
    "cpu_probe",
    "format_report",
    "interleaved",
    "main",
    "nginx_conf",
    "ratio",
]

WORKER_CODE = "31415926"  # the workers' presenter code (the gate wants 8 digits by default)
# The default reference: main on 2026-11-27, the commit the re-measurement ran (one
# process 42.4 fps at 80 own rooms that day).  A fixed commit, so tables of different days compare.
REFERENCE = "697f073"
THIS, REF = "this tree", "reference"
SETUPS = ("1 process", "2 plain processes", "2 workers")


def nginx_conf(prefix: Path, port: int, upstreams: list[int]) -> str:
    """An nginx configuration: `port` on 127.0.0.1 in front of `upstreams` (least connections,
    websockets proxied), everything it writes under `prefix`, in the foreground."""
    servers = "\n".join(f"    server 127.0.0.1:{p};" for p in upstreams)
    return f"""daemon off;
worker_processes 1;
pid {prefix}/nginx.pid;
error_log {prefix}/error.log warn;
events {{ worker_connections 8192; }}
http {{
  access_log off;
  client_body_temp_path {prefix}/body; proxy_temp_path {prefix}/proxy; fastcgi_temp_path {prefix}/fastcgi;
  uwsgi_temp_path {prefix}/uwsgi; scgi_temp_path {prefix}/scgi;
  map $http_upgrade $connection_upgrade {{ default upgrade; '' close; }}
  upstream app {{
    least_conn;
{servers}
  }}
  server {{
    listen 127.0.0.1:{port};
    location / {{
      proxy_pass http://app;
      proxy_http_version 1.1;
      proxy_set_header Upgrade $http_upgrade;
      proxy_set_header Connection $connection_upgrade;
      proxy_read_timeout 3600s;
      proxy_buffering off;
    }}
  }}
}}
"""


def serve_worker(redis_url: str, worker_id: str, max_lifetime: float) -> None:
    """--serve-worker: one worker on 127.0.0.1:0 (the app of the tree in BENCH_APP_ROOT if set:
    --reference); prints 'BENCH_APP <the app package's folder>' and 'BENCH_PORT <port>', answers
    'stats' with 'BENCH_JSON {...}' (loop iterations, bus delays p50/p95 [ms], bytes and batches
    published); exits when stdin closes or after `max_lifetime` [s]."""
    if os.environ.get("BENCH_APP_ROOT"):  # --reference: the app of another tree, this Python
        sys.path.insert(0, os.environ["BENCH_APP_ROOT"])
    import app.main
    from app.main import create_server

    if hasattr(app.main, "tune_collector"):  # as `python -m app` does (a tree from before: Python's)
        app.main.tune_collector()
    server = (create_server("127.0.0.1", 0, verbose=False, presenter_code=WORKER_CODE, redis_url=redis_url,
                            worker_id=worker_id) if redis_url else
              create_server("127.0.0.1", 0, verbose=False, presenter_code=WORKER_CODE))
    print(f"BENCH_APP {Path(app.main.__file__).resolve().parent}", flush=True)
    print(f"BENCH_PORT {server.port}", flush=True)
    done = threading.Event()

    def commands() -> None:
        for line in sys.stdin:
            if line.strip() == "stats":
                bus = server.bus
                delays = sorted(bus.delays) if bus is not None else []
                if bus is not None:
                    bus.delays.clear()

                def pick(q: float, delays: list[float] = delays) -> float:
                    return 1e3 * delays[min(len(delays) - 1, int(q * len(delays)))] if delays else float("nan")

                print("BENCH_JSON " + json.dumps({
                    "ticks": server.tick_count, "sessions": len(server.sessions),
                    "p50_ms": pick(0.5), "p95_ms": pick(0.95),
                    "bytes": bus.published_bytes if bus else 0, "batches": bus.published_batches if bus else 0}),
                    flush=True)
        done.set()

    threading.Thread(target=commands, daemon=True).start()
    done.wait(max_lifetime)
    server.stop()


class Worker:
    """A worker process (this file with --serve-worker): `port`, `pid`, `stats()`, `stop()`."""

    def __init__(self, redis_url: str | None, worker_id: str, max_lifetime: float,
                 app_root: Path | None = None) -> None:
        self._log = tempfile.TemporaryFile(mode="w+")
        env = dict(os.environ, BENCH_APP_ROOT=str(app_root)) if app_root is not None else None
        self.process = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), "--serve-worker", "--redis", redis_url or "",
             "--worker-id", worker_id, "--max-lifetime", str(max_lifetime)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._log, text=True, cwd=ROOT, env=env)
        self.pid = self.process.pid
        self._lines: list[str] = []
        self._event = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()
        try:
            self.app_folder = Path(self._wait("BENCH_APP ", 60.0))
            expected = (app_root or ROOT).resolve() / "app"
            if self.app_folder != expected:
                raise RuntimeError(f"worker: runs the app in {self.app_folder}, not {expected}")
            self.port = int(self._wait("BENCH_PORT ", 60.0))
        except BaseException:
            self.stop()
            raise

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            with self._event:
                self._lines.append(line.strip())
                self._event.notify_all()

    def _wait(self, tag: str, timeout: float) -> str:
        deadline = time.monotonic() + timeout
        with self._event:
            while True:
                for i, line in enumerate(self._lines):
                    if line.startswith(tag):
                        del self._lines[i]
                        return line[len(tag):]
                if self.process.poll() is not None or time.monotonic() > deadline:
                    self._log.seek(0)
                    raise RuntimeError(f"worker: no {tag!r}: {self._log.read()[-2000:]}")
                self._event.wait(0.1)

    def stats(self) -> dict[str, Any]:
        assert self.process.stdin is not None
        self.process.stdin.write("stats\n")
        self.process.stdin.flush()
        return dict(json.loads(self._wait("BENCH_JSON ", 10.0)))

    def stop(self) -> None:
        with contextlib.suppress(Exception):
            assert self.process.stdin is not None
            self.process.stdin.close()
        try:
            self.process.wait(timeout=10.0)
        except subprocess.TimeoutExpired:
            self.process.terminate()
            self.process.wait(timeout=5.0)


class Cluster:
    """redis-server (with `bus`), workers and nginx in front; `port` (nginx's), `pids()` by role,
    `stop()`.  Without `bus`: plain app processes (no Redis, no shared lecture).  `app_root`: the
    workers run the app of that tree (--reference)."""

    def __init__(self, workers: int, max_lifetime: float, bus: bool = True, app_root: Path | None = None) -> None:
        from app.cluster import services

        self._folder = Path(tempfile.mkdtemp(prefix="rbl-cluster-bench-"))
        self.redis_url, self.redis = services.start_redis() if bus else (None, None)
        self.workers: list[Worker] = []
        self.nginx: subprocess.Popen[bytes] | None = None
        try:
            self.workers = [Worker(self.redis_url, f"w{i + 1}", max_lifetime, app_root) for i in range(workers)]
            self.port = services.free_port()
            conf = self._folder / "nginx.conf"
            conf.write_text(nginx_conf(self._folder, self.port, [w.port for w in self.workers]))
            self.nginx = subprocess.Popen([services.require("nginx"), "-c", str(conf), "-p", str(self._folder)],
                                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            services.wait_for_port(self.port, process=self.nginx)
        except BaseException:
            self.stop()
            raise

    def pids(self) -> dict[str, list[int]]:
        nginx = [self.nginx.pid] if self.nginx is not None else []
        with contextlib.suppress(OSError):  # nginx's worker processes are the master's children
            for entry in Path("/proc").iterdir():
                if entry.name.isdigit():
                    stat = (entry / "stat").read_text()
                    if int(stat[stat.rindex(")") + 2:].split()[1]) in nginx[:1]:
                        nginx.append(int(entry.name))
        return {**{f"worker {i + 1}": [w.pid] for i, w in enumerate(self.workers)}, "nginx": nginx,
                **({"redis": [self.redis.pid]} if self.redis is not None else {})}

    def stop(self) -> None:
        from app.cluster import services

        for worker in self.workers:
            worker.stop()
        services.stop_process(self.nginx)
        services.stop_process(self.redis)


# ---------------------------------------------------------------------------- the machine


@dataclasses.dataclass(frozen=True)
class MachineSample:
    """The machine's CPU time from /proc/stat's first line, summed over its cores [s]: `busy_s`
    (user, nice, system, irq, softirq), `steal_s` (wanted but given to other virtual machines by
    the hypervisor), at `wall_s` [s, monotonic]."""

    busy_s: float
    steal_s: float
    wall_s: float


def sample_machine(stat_text: str | None = None) -> MachineSample:
    """Read /proc/stat (or `stat_text`, its content) now."""
    text = stat_text if stat_text is not None else Path("/proc/stat").read_text()
    fields = [int(x) for x in text.splitlines()[0].split()[1:]] + [0] * 8
    user, nice, system, _idle, _iowait, irq, softirq, steal = fields[:8]
    return MachineSample((user + nice + system + irq + softirq) / CLK_TCK, steal / CLK_TCK, time.monotonic())


def machine_percent(first: MachineSample, last: MachineSample) -> tuple[float, float]:
    """(busy, stolen) between two samples, in % of one core (200 % = two cores busy)."""
    wall_s = max(last.wall_s - first.wall_s, 1e-9)
    return 100.0 * (last.busy_s - first.busy_s) / wall_s, 100.0 * (last.steal_s - first.steal_s) / wall_s


def cpu_probe(seconds: float = 2.0) -> tuple[float, float]:
    """(busy, stolen) share of all the machine's cores over `seconds` from now, each 0..1 (this
    process sleeps meanwhile: what is busy is others' work)."""
    first = sample_machine()
    time.sleep(seconds)
    busy, steal = machine_percent(first, sample_machine())
    cores = os.cpu_count() or 1
    return busy / 100.0 / cores, steal / 100.0 / cores


def busy_reason(load_1min: float, cores: int, probe: tuple[float, float], max_load: float) -> str | None:
    """Why the machine is too busy for a capacity table, or None when it is quiet: the 1-minute
    load average per core, or the share of the cores busy or stolen during the probe (`probe`,
    from `cpu_probe`), above `max_load`."""
    reasons = []
    if load_1min / cores > max_load:
        reasons.append(f"1-minute load average {load_1min:.2f} on {cores} cores "
                       f"({load_1min / cores:.2f} a core, more than {max_load:g})")
    if sum(probe) > max_load:
        reasons.append(f"{100 * probe[0]:.0f} % of the cores busy and {100 * probe[1]:.0f} % stolen during the "
                       f"probe (more than {100 * max_load:.0f} %)")
    return "; ".join(reasons) or None


def machine_model() -> str:
    """The CPU's model name (/proc/cpuinfo), or what `platform` knows."""
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return platform.processor() or platform.machine() or "unknown CPU"


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True, text=True).stdout.strip()


def this_commit() -> str:
    """This tree's short commit, with '+ uncommitted changes' when tracked files differ from it."""
    try:
        dirty = bool(_git("status", "--porcelain", "--untracked-files=no"))
        return _git("rev-parse", "--short", "HEAD") + (" + uncommitted changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"


@contextlib.contextmanager
def reference_tree(rev: str) -> Iterator[Path]:
    """A detached `git worktree` of `rev` in a temporary folder, removed at the end."""
    with tempfile.TemporaryDirectory(prefix="cluster_load_reference_") as folder:
        tree = Path(folder) / "tree"
        subprocess.run(["git", "worktree", "add", "--detach", "--quiet", str(tree), rev], cwd=ROOT, check=True)
        try:
            yield tree
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, check=False)


# ---------------------------------------------------------------------------- one run


@dataclasses.dataclass
class Measured:
    """One run of one set-up under one load with the app of `tree` (THIS or REF): fps per client
    [1/s]; CPU over the window in % of one core: `servers` by role ('app', 'worker 1', 'nginx',
    'redis', ...), `clients` (this process), `others` (the rest of the machine's busy time),
    `steal` (taken by the hypervisor); `bus` the workers' bus delay and bytes ('-' without a bus);
    `error` why it gave no figures (then `fps` is empty)."""

    setup: str
    load: str
    tree: str
    fps: list[float] = dataclasses.field(default_factory=list)
    servers: dict[str, float] = dataclasses.field(default_factory=dict)
    clients: float = math.nan
    others: float = math.nan
    steal: float = math.nan
    bus: str = "-"
    error: str = ""


def _cpu(pids: dict[str, list[int]]) -> dict[str, Any]:
    samples = {}
    for role, ids in pids.items():
        for pid in ids:
            with contextlib.suppress(OSError):
                samples.setdefault(role, []).append(sample_process(pid))
    return samples


async def _measure(clients: list[AsyncViserClient], pids: dict[str, list[int]], warmup: float, seconds: float,
                   start: Any = None) -> Measured:
    """fps per client and the CPU figures over `seconds` after `warmup` (a Measured without its
    set-up, load and tree); `start()` is called when the window opens (the workers' bus delays are
    counted from then)."""
    for client in clients:
        client.state.count_only = True
    await asyncio.sleep(warmup)
    if start is not None:
        await asyncio.get_running_loop().run_in_executor(None, start)
    first, me0, machine0, t0 = _cpu(pids), sample_process(os.getpid()), sample_machine(), time.monotonic()
    frames0 = [c.state.frames for c in clients]
    await asyncio.sleep(seconds)
    frames1, t1 = [c.state.frames for c in clients], time.monotonic()
    last, me1, machine1 = _cpu(pids), sample_process(os.getpid()), sample_machine()
    servers = {role: sum(cpu_percent(a, b) for a, b in zip(first[role], last.get(role, []))) for role in first}
    mine = cpu_percent(me0, me1)
    busy, steal = machine_percent(machine0, machine1)
    return Measured("", "", "", [(b - a) / (t1 - t0) for a, b in zip(frames0, frames1)], servers, mine,
                    max(0.0, busy - sum(servers.values()) - mine), steal)


async def _own_rooms(port: int, count: int, pids: dict[str, list[int]], warmup: float, seconds: float,
                     start: Any = None) -> Measured:
    clients: list[AsyncViserClient] = []
    try:
        for _ in range(count):
            clients.append(await AsyncViserClient.connect(port, keep_messages=200, open_timeout=60.0))

        async def play(client: AsyncViserClient) -> None:
            await start_playing(client, "Free body", timeout=60.0 + 2.0 * count)
            client.state.count_only = True  # pressed what it needs: decoding every frame would starve the server

        await asyncio.gather(*(play(c) for c in clients))
        return await _measure(clients, pids, warmup, seconds, start)
    finally:
        await asyncio.gather(*(c.close() for c in clients), return_exceptions=True)


async def _followers(port: int, count: int, code: str, pids: dict[str, list[int]], warmup: float, seconds: float,
                     start: Any = None) -> Measured:
    presenter = await AsyncViserClient.connect(port, keep_messages=200)
    clients: list[AsyncViserClient] = []
    try:
        await present_and_play(presenter, "Free body", timeout=30.0, code=code)
        presenter.state.count_only = True

        async def joined(client: AsyncViserClient) -> None:
            await client.wait_for(lambda: client.state.replay_done, 60.0 + 0.5 * count)
            client.state.count_only = True  # it has the scene: decoding every frame would starve the server

        waits = []
        for _ in range(count):  # one after the other, as a class arrives
            clients.append(await AsyncViserClient.connect(port, keep_messages=20, open_timeout=60.0))
            waits.append(asyncio.ensure_future(joined(clients[-1])))
        await asyncio.gather(*waits)
        return await _measure(clients, pids, warmup, seconds, start)
    finally:
        await asyncio.gather(*(c.close() for c in [presenter, *clients]), return_exceptions=True)


def load_label(kind: str, count: int) -> str:
    """'80 own rooms' / '1,000 followers'."""
    return f"{count:,} own rooms" if kind == "rooms" else f"{count:,} followers"


def measure_once(setup: str, kind: str, count: int, tree: str, app_root: Path | None, warmup: float,
                 seconds: float) -> Measured:
    """One run: `setup` (one of SETUPS) under `count` own rooms or followers (`kind` 'rooms' /
    'followers'), the servers running the app of `app_root` (None: this tree)."""
    lifetime = warmup + seconds + 180.0 + 2.0 * count
    label = load_label(kind, count)
    try:
        if setup == SETUPS[0]:
            single = ServerProcess(max_lifetime=lifetime, start_timeout=60.0, app_root=app_root)
            try:
                expected = (app_root or ROOT).resolve() / "app"
                if single.app_folder != expected:
                    raise RuntimeError(f"the server runs the app in {single.app_folder}, not {expected}")
                pids = {"app": [single.pid]}
                result = (run_async(_own_rooms(single.port, count, pids, warmup, seconds)) if kind == "rooms" else
                          run_async(_followers(single.port, count, PRESENTER_CODE, pids, warmup, seconds)))
            finally:
                single.stop()
        else:
            result = _measure_cluster(setup == SETUPS[2], kind, count, app_root, lifetime, warmup, seconds)
    except (TimeoutError, RuntimeError) as error:  # a machine too busy to start them all; a reference that fails
        return Measured(setup, label, tree, error=" ".join(str(error).split())[:200] or type(error).__name__)
    return dataclasses.replace(result, setup=setup, load=label, tree=tree)


def _measure_cluster(bus: bool, kind: str, count: int, app_root: Path | None, lifetime: float, warmup: float,
                     seconds: float) -> Measured:
    cluster = Cluster(2, lifetime, bus=bus, app_root=app_root)
    try:
        pids = cluster.pids()

        def clear() -> None:  # the delays from the window's start on
            for worker in cluster.workers:
                worker.stats()

        result = (run_async(_own_rooms(cluster.port, count, pids, warmup, seconds, clear)) if kind == "rooms" else
                  run_async(_followers(cluster.port, count, WORKER_CODE, pids, warmup, seconds, clear)))
        stats = [worker.stats() for worker in cluster.workers]
    finally:
        cluster.stop()
    source = max(stats, key=lambda s: s["batches"])
    other = min(stats, key=lambda s: s["batches"])
    per_frame = source["bytes"] / max(1, source["batches"])
    result.bus = ("-" if not bus else "no lecture" if not source["batches"] else
                  f"{other['p50_ms']:.1f} / {other['p95_ms']:.1f} ms, {per_frame:.0f} B")
    return result


def interleaved(rounds: int, reference: bool) -> list[str]:
    """The order of one row's runs: this tree and the reference in mirrored pairs (this,
    reference, reference, this, ...) so that a drift of the machine's speed weighs on both alike;
    without a reference, `rounds` runs of this tree."""
    if not reference:
        return [THIS] * rounds
    return [tree for i in range(rounds) for tree in ((THIS, REF) if i % 2 == 0 else (REF, THIS))]


def run(cases: list[tuple[str, int]], order: list[str], app_roots: dict[str, Path | None], warmup: float,
        seconds: float, report: Callable[[str], None] = print) -> list[Measured]:
    """Every set-up under every case ('rooms' / 'followers', count), each row's runs in `order`
    (trees, keys of `app_roots`) one right after the other; `report` gets a line per run."""
    rows = [(kind, count, setup) for kind, count in cases for setup in SETUPS
            if not (kind == "followers" and setup == SETUPS[1])]  # plain processes share no lecture
    results = []
    for kind, count, setup in rows:
        for tree in order:
            started = time.monotonic()
            result = measure_once(setup, kind, count, tree, app_roots[tree], warmup, seconds)
            results.append(result)
            figures = (result.error or f"fps {min(result.fps):.1f} / {statistics.median(result.fps):.1f}, "
                       f"CPU {_servers_cpu(result.servers)}, clients {result.clients:.0f}, "
                       f"others {result.others:.0f}")
            report(f"[{len(results)}/{len(rows) * len(order)}] {setup}, {result.load}, {tree}: {figures} "
                   f"({time.monotonic() - started:.0f} s, load average {os.getloadavg()[0]:.2f})")
    return results


# ---------------------------------------------------------------------------- the table


def ratio(value: float, reference: float) -> float:
    """value / reference; nan unless both are finite, `value` >= 0 and `reference` > 0."""
    if not (math.isfinite(value) and math.isfinite(reference)) or value < 0 or reference <= 0:
        return math.nan
    return value / reference


def _ratio_text(value: float, reference: float) -> str:
    r = ratio(value, reference)
    return f"×{r:.2f}" if math.isfinite(r) else "—"


def _servers_cpu(servers: dict[str, float]) -> str:
    """'app 89' / '81 + 76, nginx 9, redis 0' (% of one core)."""
    workers = [f"{v:.0f}" for role, v in servers.items() if role.startswith("worker")]
    rest = [f"{role} {v:.0f}" for role, v in servers.items() if not role.startswith("worker")]
    return ", ".join(([" + ".join(workers)] if workers else []) + rest) or "-"


@dataclasses.dataclass(frozen=True)
class Cell:
    """The runs of one tree in one row, summarized: medians over the runs with figures of the
    fps min and median over the clients, of the CPU figures; `medians` each run's fps median;
    `bus` the runs' notes; `failed` how many runs gave no figures."""

    fps_min: float
    fps_median: float
    medians: list[float]
    servers: dict[str, float]
    clients: float
    others: float
    steal: float
    bus: str
    failed: int


def summarize(runs: list[Measured]) -> Cell:
    """One Cell from the runs of one tree in one row (nan where no run gave figures)."""
    good = [r for r in runs if r.fps and not r.error]

    def median(values: list[float]) -> float:
        return statistics.median(values) if values else math.nan

    roles = list(dict.fromkeys(role for r in good for role in r.servers))
    notes = list(dict.fromkeys(r.bus for r in good))
    return Cell(median([min(r.fps) for r in good]), median([statistics.median(r.fps) for r in good]),
                [statistics.median(r.fps) for r in good],
                {role: median([r.servers[role] for r in good if role in r.servers]) for role in roles},
                median([r.clients for r in good]), median([r.others for r in good]),
                median([r.steal for r in good]), "; ".join(notes) or "-", len(runs) - len(good))


@dataclasses.dataclass(frozen=True)
class ReportInfo:
    """What heads a table: the window [UTC], this tree's commit, the reference (its name as given
    and its short commit; None without one), the machine, the load average (1 min) before and
    after, the probe before (busy, stolen shares), `busy` the reason when measured anyway
    (--force), the window's warm-up and length [s] and each row's order of runs."""

    started: datetime.datetime
    ended: datetime.datetime
    commit: str
    reference: tuple[str, str] | None
    cpus: int
    model: str
    python: str
    load_before: float
    load_after: float
    probe: tuple[float, float]
    busy: str | None
    warmup: float
    seconds: float
    order: list[str]


TABLE_HEAD = ["| set-up | load | app | fps min / median | × reference (min / median) | fps median of each run "
              "| CPU servers | CPU clients | CPU others | steal | bus p50 / p95, bytes a frame |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]


def format_report(results: list[Measured], info: ReportInfo) -> str:
    """The Markdown section for docs/performance.md: a heading with the date, the calibration
    (commits, machine, load), the table (a row per set-up, load and tree), its legend and the
    runs that failed."""
    day = info.started.strftime("%Y-%m-%d")
    lines = [f"### Capacity (benchmarks/cluster_load.py), {day} {info.started:%H:%M}–{info.ended:%H:%M} UTC"
             + (", measured on a busy machine" if info.busy else ""), ""]
    if info.busy:
        lines += [f"**Measured on a busy machine** (`--force`): {info.busy}. These figures are not the "
                  "app's capacity.", ""]
    if info.reference is not None:
        name, sha = info.reference
        ref = (f"reference: {sha}" + (f" (`--reference {name}`)" if name != sha else "")
               + ", its app from a git worktree, served by the same Python to the same clients")
    else:
        ref = "no reference (`--reference none`): these figures carry no calibration"
    lines += [f"- this tree: {info.commit}; {ref}",
              f"- machine: {info.cpus} CPUs, {info.model}, Python {info.python}; 1-minute load average "
              f"{info.load_before:.2f} before, {info.load_after:.2f} after; before the run {100 * info.probe[0]:.0f} % "
              f"of the cores busy, {100 * info.probe[1]:.0f} % stolen (a probe of /proc/stat)",
              f"- each row: {info.order.count(THIS)} run(s) a tree, in the order {', '.join(info.order)}; "
              f"window {info.seconds:g} s after {info.warmup:g} s warm-up; the figures are medians over the runs",
              *_others_line(results), "", *TABLE_HEAD]
    failures = []
    rows = list(dict.fromkeys((r.setup, r.load) for r in results))
    for setup, load in rows:
        runs = [r for r in results if (r.setup, r.load) == (setup, load)]
        cells = {tree: summarize([r for r in runs if r.tree == tree])
                 for tree in dict.fromkeys(r.tree for r in runs)}
        reference = cells.get(REF)
        for tree, cell in cells.items():
            failures += [f"- {setup}, {load}, {tree}: {r.error}" for r in runs if r.tree == tree and r.error]
            lines.append(_row(setup, load, tree, cell, reference if tree != REF else None))
    lines += ["", "fps: frames a second each client received (min / median over the clients). × reference: "
              "this tree's figure over the reference's in the same row. CPU in % of one core over the window: "
              "servers (each app process; nginx with all its processes; redis-server), clients (the "
              "websocket clients: the benchmark's own process), others (the rest of the machine's busy time, "
              "/proc/stat), steal (time the hypervisor gave to other machines)."]
    if failures:
        lines += ["", "Runs without figures:", *failures]
    return "\n".join(lines) + "\n"


def _others_line(results: list[Measured]) -> list[str]:
    """'- during the runs: ...' (other work's and the hypervisor's share), or nothing without figures."""
    good = [r for r in results if r.fps and not r.error]
    if not good:
        return []
    others = [r.others for r in good]
    return [f"- during the runs other work took {statistics.median(others):.0f} % of one core (median; at most "
            f"{max(others):.0f} %), the hypervisor stole at most {max(r.steal for r in good):.0f} %"]


def _row(setup: str, load: str, tree: str, cell: Cell, reference: Cell | None) -> str:
    if not cell.medians:
        return f"| {setup} | {load} | {tree} | no run gave figures | | | | | | | |"
    fps = f"{cell.fps_min:.1f} / {cell.fps_median:.1f}"
    if cell.failed:
        fps += f" ({cell.failed} run(s) failed)"
    ratios = (f"{_ratio_text(cell.fps_min, reference.fps_min)} / {_ratio_text(cell.fps_median, reference.fps_median)}"
              if reference is not None and reference.medians else "—")
    return (f"| {setup} | {load} | {tree} | {fps} | {ratios} | {', '.join(f'{m:.1f}' for m in cell.medians)} "
            f"| {_servers_cpu(cell.servers)} | {cell.clients:.0f} | {cell.others:.0f} | {cell.steal:.0f} "
            f"| {cell.bus} |")


# ---------------------------------------------------------------------------- the command


def quiet_check(max_load: float, probe_seconds: float) -> tuple[str | None, float, tuple[float, float]]:
    """(why the machine is busy or None, the 1-minute load average, the probe's shares)."""
    load_1min = os.getloadavg()[0]
    probe = cpu_probe(probe_seconds)
    return busy_reason(load_1min, os.cpu_count() or 1, probe, max_load), load_1min, probe


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rooms", default="80,120,160", help="own rooms, comma-separated (default %(default)s)")
    parser.add_argument("--followers", default="500,1000", help="followers, comma-separated (default %(default)s)")
    parser.add_argument("--seconds", type=float, default=10.0, help="measured window [s] (default %(default)s)")
    parser.add_argument("--warmup", type=float, default=3.0, help="warm-up [s] (default %(default)s)")
    parser.add_argument("--reference", default=REFERENCE, metavar="REV",
                        help="the git commit (or tag) measured beside this tree; 'none' for none "
                             "(default %(default)s)")
    parser.add_argument("--rounds", type=int, default=2,
                        help="runs a tree in each row, interleaved with the reference's (default %(default)s)")
    parser.add_argument("--max-load", type=float, default=0.5,
                        help="refuse when the 1-minute load average per core, or the share of the cores busy "
                             "during the probe, is above this (default %(default)s)")
    parser.add_argument("--force", action="store_true",
                        help="measure on a busy machine anyway; the table says so")
    parser.add_argument("--output", type=Path, help="also write the Markdown table to this file")
    parser.add_argument("--probe-seconds", type=float, default=2.0, help=argparse.SUPPRESS)
    parser.add_argument("--serve-worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--redis", help=argparse.SUPPRESS)
    parser.add_argument("--worker-id", help=argparse.SUPPRESS)
    parser.add_argument("--max-lifetime", type=float, default=600.0, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.serve_worker:
        serve_worker(args.redis, args.worker_id, args.max_lifetime)
        return
    numbers = [[int(x) for x in text.split(",") if x.strip()] for text in (args.rooms, args.followers)]
    if args.rounds < 1:
        parser.error("--rounds: at least 1")
    reference = None if args.reference.lower() == "none" else args.reference
    if reference is not None:
        try:
            reference_sha = _git("rev-parse", "--short", "--verify", f"{reference}^{{commit}}")
        except (OSError, subprocess.CalledProcessError):
            parser.error(f"--reference {reference}: not a commit of this repository")
    busy, load_before, probe = quiet_check(args.max_load, args.probe_seconds)
    if busy and not args.force:
        print(f"cluster_load: the machine is busy before the run: {busy}. No table written: wait for a quiet "
              "machine, or pass --force (the table is then marked 'measured on a busy machine').",
              file=sys.stderr)
        raise SystemExit(2)
    cases = [("rooms", n) for n in numbers[0]] + [("followers", n) for n in numbers[1]]
    order = interleaved(args.rounds, reference is not None)
    started = datetime.datetime.now(datetime.UTC)
    with contextlib.ExitStack() as stack:
        roots: dict[str, Path | None] = {THIS: None}
        if reference is not None:
            roots[REF] = stack.enter_context(reference_tree(reference_sha))
        results = run(cases, order, roots, args.warmup, args.seconds)
    info = ReportInfo(started, datetime.datetime.now(datetime.UTC), this_commit(),
                      (reference, reference_sha) if reference is not None else None, os.cpu_count() or 1,
                      machine_model(), platform.python_version(), load_before, os.getloadavg()[0], probe, busy,
                      args.warmup, args.seconds, order)
    table = format_report(results, info)
    print("\n" + table, end="")
    if args.output is not None:
        args.output.write_text(table)


if __name__ == "__main__":
    main()
