"""Load test, side by side in one run: one app process against `--workers 2` behind nginx with the bus.

The same light websocket clients as benchmarks/load_clients.py (one asyncio loop in this
process): own rooms (each client picks the scene and presses Play in its own room) and
followers (a presenter types the code, presents and plays; the followers only count frames).
Two set-ups, measured one after the other with the same clients:

- "1 process": the app as `python -m app` starts it (load_clients.py --serve);
- "2 plain processes": two app processes without Redis behind the same nginx (own rooms only:
  they share no lecture), the reference the issue's targets compare with;
- "2 workers": redis-server on a free port, two app processes (`create_server(redis_url=...,
  worker_id=...)`, this file with --serve-worker) and nginx in front of them (`least_conn`,
  websockets proxied; `nginx_conf`).  The clients connect to nginx, which spreads them.

Per row: fps min / median over the clients, the CPU % of every process (100 % = one core:
each worker, nginx (all its processes), redis-server), and for the workers' bus: the delay it
adds from the presenter's frame to a follower on the other process (publish on the presenting
worker -> taken into the other worker's loop, p50/p95 [ms]; the wall clocks of one machine),
and the bytes it publishes per frame (msgpack of the scene batch).

    python benchmarks/cluster_load.py                                  # 80,120,160 rooms; 500,1000 followers
    python benchmarks/cluster_load.py --rooms 80 --followers 500 --seconds 8

Bounded: every process it starts is stopped at the end (and the servers exit when their stdin
closes).  The load on the machine from other work is printed with the tables (load average).
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.load_clients import (  # noqa: E402
    PRESENTER_CODE,
    ServerProcess,
    cpu_percent,
    present_and_play,
    run_async,
    sample_process,
    start_playing,
)
from benchmarks.ws_client import AsyncViserClient  # noqa: E402

__all__ = ["main", "nginx_conf"]

WORKER_CODE = "31415926"  # the workers' presenter code (the gate wants 8 digits by default)


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
    """--serve-worker: one worker on 127.0.0.1:0; prints 'BENCH_PORT <port>', answers 'stats'
    with 'BENCH_JSON {...}' (loop iterations, bus delays p50/p95 [ms], bytes and batches
    published); exits when stdin closes or after `max_lifetime` [s]."""
    from app.main import create_server, tune_collector

    tune_collector()  # as `python -m app` does
    app = (create_server("127.0.0.1", 0, verbose=False, presenter_code=WORKER_CODE, redis_url=redis_url,
                         worker_id=worker_id) if redis_url else
           create_server("127.0.0.1", 0, verbose=False, presenter_code=WORKER_CODE))
    print(f"BENCH_PORT {app.port}", flush=True)
    done = threading.Event()

    def commands() -> None:
        for line in sys.stdin:
            if line.strip() == "stats":
                bus = app.bus
                delays = sorted(bus.delays) if bus is not None else []
                if bus is not None:
                    bus.delays.clear()

                def pick(q: float, delays: list[float] = delays) -> float:
                    return 1e3 * delays[min(len(delays) - 1, int(q * len(delays)))] if delays else float("nan")

                print("BENCH_JSON " + json.dumps({
                    "ticks": app.tick_count, "sessions": len(app.sessions), "p50_ms": pick(0.5), "p95_ms": pick(0.95),
                    "bytes": bus.published_bytes if bus else 0, "batches": bus.published_batches if bus else 0}),
                    flush=True)
        done.set()

    threading.Thread(target=commands, daemon=True).start()
    done.wait(max_lifetime)
    app.stop()


class Worker:
    """A worker process (this file with --serve-worker): `port`, `pid`, `stats()`, `stop()`."""

    def __init__(self, redis_url: str | None, worker_id: str, max_lifetime: float) -> None:
        self._log = tempfile.TemporaryFile(mode="w+")
        self.process = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), "--serve-worker", "--redis", redis_url or "",
             "--worker-id", worker_id, "--max-lifetime", str(max_lifetime)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._log, text=True, cwd=ROOT)
        self.pid = self.process.pid
        self._lines: list[str] = []
        self._event = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()
        self.port = int(self._wait("BENCH_PORT ", 60.0))

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
    `stop()`.  Without `bus`: plain app processes (no Redis, no shared lecture), the reference."""

    def __init__(self, workers: int, max_lifetime: float, bus: bool = True) -> None:
        from app.cluster import services

        self._folder = Path(tempfile.mkdtemp(prefix="rbl-cluster-bench-"))
        self.redis_url, self.redis = services.start_redis() if bus else (None, None)
        self.workers: list[Worker] = []
        self.nginx: subprocess.Popen[bytes] | None = None
        try:
            self.workers = [Worker(self.redis_url, f"w{i + 1}", max_lifetime) for i in range(workers)]
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


def _cpu(pids: dict[str, list[int]]) -> dict[str, Any]:
    samples = {}
    for role, ids in pids.items():
        for pid in ids:
            with contextlib.suppress(OSError):
                samples.setdefault(role, []).append(sample_process(pid))
    return samples


async def _measure(clients: list[AsyncViserClient], pids: dict[str, list[int]], warmup: float, seconds: float,
                   start: Any = None) -> tuple[list[float], dict[str, float]]:
    """fps per client and CPU % per role over `seconds` after `warmup`; `start()` is called when
    the window opens (the workers' bus delays are counted from then)."""
    for client in clients:
        client.state.count_only = True
    await asyncio.sleep(warmup)
    if start is not None:
        await asyncio.get_running_loop().run_in_executor(None, start)
    first, t0 = _cpu(pids), time.monotonic()
    frames0 = [c.state.frames for c in clients]
    await asyncio.sleep(seconds)
    frames1, t1 = [c.state.frames for c in clients], time.monotonic()
    last = _cpu(pids)
    cpu = {role: sum(cpu_percent(a, b) for a, b in zip(first[role], last.get(role, []))) for role in first}
    return [(b - a) / (t1 - t0) for a, b in zip(frames0, frames1)], cpu


async def _own_rooms(port: int, count: int, pids: dict[str, list[int]], warmup: float, seconds: float,
                     start: Any = None) -> tuple[list[float], dict[str, float]]:
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
                     start: Any = None) -> tuple[list[float], dict[str, float]]:
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


def _row(setup: str, case: str, fps: list[float], cpu: dict[str, float], bus: str) -> str:
    cpus = ", ".join(f"{role} {value:.0f} %" for role, value in cpu.items())
    return (f"| {setup} | {case} | {min(fps):.1f} / {statistics.median(fps):.1f} | {cpus} | {bus} |")


def run(rooms: list[int], followers: list[int], warmup: float, seconds: float) -> list[str]:
    rows = ["| set-up | load | fps min / median | CPU (100 % = a core) | bus p50 / p95 [ms], bytes a frame |",
            "|---|---|---|---|---|"]
    cases = [("rooms", n) for n in rooms] + [("followers", n) for n in followers]
    for kind, count in cases:
        label = f"{count} own rooms" if kind == "rooms" else f"{count} followers"
        lifetime = warmup + seconds + 180.0 + 2.0 * count
        single = ServerProcess(max_lifetime=lifetime)
        try:
            pids = {"app": [single.pid]}
            fps, cpu = (run_async(_own_rooms(single.port, count, pids, warmup, seconds)) if kind == "rooms" else
                        run_async(_followers(single.port, count, PRESENTER_CODE, pids, warmup, seconds)))
            rows.append(_row("1 process", label, fps, cpu, "-"))
        except TimeoutError as error:  # a machine too busy to start them all
            rows.append(f"| 1 process | {label} | did not start: {error} | | |")
        finally:
            single.stop()
        print(rows[-1], flush=True)
        for setup, bus in (("2 plain processes", False), ("2 workers", True)):
            if kind == "followers" and not bus:
                continue  # plain processes share no lecture
            cluster = Cluster(2, lifetime, bus=bus)
            try:
                pids = cluster.pids()

                def clear(cluster: Cluster = cluster) -> None:  # the delays from the window's start on
                    for worker in cluster.workers:
                        worker.stats()

                fps, cpu = (run_async(_own_rooms(cluster.port, count, pids, warmup, seconds, clear))
                            if kind == "rooms" else
                            run_async(_followers(cluster.port, count, WORKER_CODE, pids, warmup, seconds, clear)))
                stats = [worker.stats() for worker in cluster.workers]
                source = max(stats, key=lambda s: s["batches"])
                other = min(stats, key=lambda s: s["batches"])
                note = ("-" if not bus else "no lecture" if not source["batches"] else
                        f"{other['p50_ms']:.1f} / {other['p95_ms']:.1f}, "
                        f"{source['bytes'] / max(1, source['batches']):.0f} B")
                rows.append(_row(setup, label, fps, cpu, note))
            except TimeoutError as error:
                rows.append(f"| {setup} | {label} | did not start: {error} | | |")
            finally:
                cluster.stop()
            print(rows[-1], flush=True)
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rooms", default="80,120,160", help="own rooms, comma-separated (default %(default)s)")
    parser.add_argument("--followers", default="500,1000", help="followers, comma-separated (default %(default)s)")
    parser.add_argument("--seconds", type=float, default=10.0, help="measured window [s] (default %(default)s)")
    parser.add_argument("--warmup", type=float, default=3.0, help="warm-up [s] (default %(default)s)")
    parser.add_argument("--serve-worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--redis", help=argparse.SUPPRESS)
    parser.add_argument("--worker-id", help=argparse.SUPPRESS)
    parser.add_argument("--max-lifetime", type=float, default=600.0, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.serve_worker:
        serve_worker(args.redis, args.worker_id, args.max_lifetime)
        return
    numbers = [[int(x) for x in text.split(",") if x.strip()] for text in (args.rooms, args.followers)]
    print(f"load average before: {os.getloadavg()[0]:.1f} (2 cores: others' work shares them)", flush=True)
    rows = run(numbers[0], numbers[1], args.warmup, args.seconds)
    print(f"load average after: {os.getloadavg()[0]:.1f}")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
