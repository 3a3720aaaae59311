"""Overload probe: a bare viser server streaming per-client scenes, old pacing vs app.backpressure.

No physics.  The server runs in a subprocess (its own GIL): on connect each client gets
``--nodes`` frames plus one arrow in ``client.scene``; a loop thread at 60 Hz assigns, per
client per frame and inside ``client.atomic()``, every frame's ``.wxyz``, the first frame's
``.position`` and the arrow's ``.points`` (nodes + 2 messages per client frame).

Policies (``--policies``):
  old    tick every client back to back, then sleep to the next 1/60 s boundary (as app/main.py:
         behind by more than 5 periods -> restart the schedule).
  new    app.backpressure.FramePacer: skip clients whose previous frame is still queued in viser,
         hold all buffers atomic while drawing, flush them together, sleep until the sender has
         taken the frames (and >= idle_ratio x work, and >= 1/60 s).
  nohold new without hold(); nodrain: new without waiting for the sender (idle share only).

The N clients run in THIS process (asyncio, pure-Python websockets, no viser decoding: a frame
is one websocket message after the initial replay; with atomic() + culling that is one
per-client scene update).  ``--stalled S`` extra clients connect and stop reading their socket
(SO_RCVBUF 4 KiB, websockets max_queue 1); they are not counted, they must not slow the others.
Loopback kernel buffers hold minutes of such frames, so pair it with ``--sndbuf 8192`` (server
SO_SNDBUF per connection) to make the stall reach viser within seconds.

Per config: per-client fps min / median / max over ``--seconds`` after ``--warmup``, the worst
gap between two frames of any client, total frames/s, server CPU % (/proc, 100 % = one core),
this process's CPU %, loop Hz and the share of client frames skipped by the pacer.

    python benchmarks/overload_probe.py                       # 20,40,60,80 x old,new, 10 s
    python benchmarks/overload_probe.py --clients 60 --policies new --seconds 20 --stalled 2
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import math
import os
import socket
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

CLK_TCK = os.sysconf("SC_CLK_TCK")
POLICIES = ("old", "new", "nohold", "nodrain")


# ============================================================================ server process
def serve(args: argparse.Namespace) -> None:
    """--serve: viser on 127.0.0.1:0, prints 'PORT <port>'; answers 'stats' lines on stdin with
    one JSON line; exits on EOF or after --max-lifetime seconds."""
    import numpy as np
    import viser

    from app.backpressure import FramePacer

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    lock = threading.Lock()
    scenes: dict[int, tuple[Any, list[Any], Any]] = {}  # client_id -> (client, frames, arrow)

    @server.on_client_connect
    def _connect(client: viser.ClientHandle) -> None:
        if args.sndbuf:  # small kernel send buffer: a stalled client backs up within seconds
            with contextlib.suppress(Exception):
                connection = server._websock_server._live_connections[client.client_id]
                connection.transport.get_extra_info("socket").setsockopt(
                    socket.SOL_SOCKET, socket.SO_SNDBUF, args.sndbuf)
        with client.atomic():
            frames = [client.scene.add_frame(f"/b{i}", axes_length=0.3, position=(i * 0.5, 0, 0))
                      for i in range(args.nodes)]
            arrow = client.scene.add_arrows("/omega", points=np.zeros((1, 2, 3), np.float32),
                                            colors=(255, 0, 0))
        with lock:
            scenes[client.client_id] = (client, frames, arrow)

    @server.on_client_disconnect
    def _disconnect(client: viser.ClientHandle) -> None:
        with lock:
            scenes.pop(client.client_id, None)

    def draw(entry: tuple[Any, list[Any], Any], t: float) -> None:
        client, frames, arrow = entry
        phase = t + 0.37 * client.client_id
        with client.atomic():
            for i, frame in enumerate(frames):
                a = 0.5 * (phase + 0.1 * i)
                frame.wxyz = (math.cos(a), 0.0, math.sin(a) * 0.6, math.sin(a) * 0.8)
            frames[0].position = (0.1 * math.sin(phase), 0.0, 0.0)
            arrow.points = np.array([[[0, 0, 0], [math.cos(phase), math.sin(phase), 1.0]]],
                                    np.float32)

    stop = threading.Event()
    stats: dict[str, Any] = {"frames": 0, "drawn": 0, "skipped": 0, "work_s": 0.0}
    period = 1.0 / args.rate

    def old_loop() -> None:
        next_time = time.perf_counter()
        while not stop.is_set():
            start = time.perf_counter()
            with lock:
                entries = list(scenes.values())
            for entry in entries:
                draw(entry, start)
            stats["frames"] += 1
            stats["drawn"] += len(entries)
            stats["work_s"] += time.perf_counter() - start
            next_time += period
            delay = next_time - time.perf_counter()
            if delay < -5 * period:
                next_time = time.perf_counter()
                delay = 0.0
            stop.wait(max(delay, 0.0))

    def new_loop() -> None:
        pacer = FramePacer(args.rate, idle_ratio=args.idle_ratio, max_wait=args.max_wait,
                           drain=args.policy != "nodrain")
        hold = args.policy != "nohold"
        while not stop.is_set():
            pacer.begin()
            start = time.perf_counter()
            with lock:
                entries = list(scenes.values())
            drawn = []
            clients = [e[0] for e in entries]
            with pacer.hold(clients) if hold else _null():
                for entry in entries:
                    if pacer.ready(entry[0]):
                        draw(entry, start)
                        drawn.append(entry[0])
            stats["work_s"] += time.perf_counter() - start
            pacer.end(drawn)
            stats["frames"] += 1
            stats["drawn"] = pacer.stats.drawn
            stats["skipped"] = pacer.stats.skipped
            stats["drain_timeouts"] = pacer.stats.drain_timeouts

    _null = contextlib.nullcontext
    loop = threading.Thread(target=old_loop if args.policy == "old" else new_loop, daemon=True)
    loop.start()
    print(f"PORT {server.get_port()}", flush=True)

    def lifetime() -> None:
        time.sleep(args.max_lifetime)
        os._exit(3)

    threading.Thread(target=lifetime, daemon=True).start()
    for line in sys.stdin:
        if line.strip() == "stats":
            with lock:
                n = len(scenes)
            print(json.dumps({**stats, "clients": n, "t": time.monotonic()}), flush=True)
        elif line.strip() == "quit":
            break
    stop.set()
    os._exit(0)


# ============================================================================ clients (this process)
class Counter:
    __slots__ = ("error", "frames", "last", "max_gap", "measuring")

    def __init__(self) -> None:
        self.frames = 0
        self.last = math.nan
        self.max_gap = 0.0
        self.measuring = False
        self.error = ""


async def run_client(port: int, counter: Counter, stop: asyncio.Event) -> None:
    from websockets.asyncio.client import connect

    from benchmarks.ws_client import camera_message, encode_message, subprotocol

    try:
        async with connect(f"ws://127.0.0.1:{port}", subprotocols=[subprotocol()],
                           max_size=None, compression=None, open_timeout=30) as ws:
            await ws.send(encode_message(camera_message()))
            reader = asyncio.ensure_future(_count(ws, counter))
            await stop.wait()
            reader.cancel()
    except Exception as error:  # noqa: BLE001 - e.g. keepalive ping timeout under overload
        counter.error = f"{type(error).__name__}: {error}"


async def _count(ws: Any, counter: Counter) -> None:
    try:
        await _count_frames(ws, counter)
    except Exception as error:  # noqa: BLE001
        counter.error = f"{type(error).__name__}: {error}"


async def _count_frames(ws: Any, counter: Counter) -> None:
    loop_time = time.monotonic
    async for _data in ws:
        now = loop_time()
        counter.frames += 1
        if counter.measuring and now - counter.last > counter.max_gap:
            counter.max_gap = now - counter.last
        counter.last = now


async def run_stalled(port: int, stop: asyncio.Event) -> None:
    """Connect, send the camera, then never read (small receive buffer)."""
    from websockets.asyncio.client import connect

    from benchmarks.ws_client import camera_message, encode_message, subprotocol

    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect(("127.0.0.1", port))
    async with connect(f"ws://127.0.0.1:{port}", sock=sock, subprotocols=[subprotocol()],
                       max_size=None, compression=None, max_queue=1, open_timeout=30) as ws:
        await ws.send(encode_message(camera_message()))
        await stop.wait()


def proc_cpu(pid: int) -> float:
    stat = Path(f"/proc/{pid}/stat").read_text()
    fields = stat[stat.rindex(")") + 2:].split()
    return (int(fields[11]) + int(fields[12])) / CLK_TCK


async def run_config(args: argparse.Namespace, policy: str, n: int) -> dict[str, Any]:
    cmd = [sys.executable, __file__, "--serve", "--policy", policy, "--nodes", str(args.nodes),
           "--rate", str(args.rate), "--idle-ratio", str(args.idle_ratio),
           "--max-wait", str(args.max_wait), "--sndbuf", str(args.sndbuf),
           "--max-lifetime", str(args.warmup + args.seconds + 120)]
    proc = await asyncio.to_thread(subprocess.Popen, cmd, stdin=subprocess.PIPE,
                                   stdout=subprocess.PIPE, text=True, cwd=ROOT)
    assert proc.stdin is not None and proc.stdout is not None
    try:
        line = ""
        while not line.startswith("PORT "):  # viser prints its URL panel first
            line = await asyncio.to_thread(proc.stdout.readline)
            if not line:
                raise RuntimeError("server exited before printing its port")
        port = int(line.split()[1])

        def query() -> dict[str, Any]:
            proc.stdin.write("stats\n")
            proc.stdin.flush()
            while True:
                reply = proc.stdout.readline()
                if not reply:
                    raise RuntimeError("server exited")
                if reply.startswith("{"):
                    return json.loads(reply)

        stop = asyncio.Event()
        counters = [Counter() for _ in range(n)]
        tasks = []
        for counter in counters:
            tasks.append(asyncio.ensure_future(run_client(port, counter, stop)))
            await asyncio.sleep(0.01)
        for _ in range(args.stalled):
            tasks.append(asyncio.ensure_future(run_stalled(port, stop)))
        deadline = time.monotonic() + 60
        while (await asyncio.to_thread(query))["clients"] < n + args.stalled:
            if time.monotonic() > deadline:
                raise RuntimeError("clients did not all connect")
            await asyncio.sleep(0.2)
        await asyncio.sleep(args.warmup)

        s0 = await asyncio.to_thread(query)
        cpu0, my0, t0 = proc_cpu(proc.pid), time.process_time(), time.monotonic()
        f0 = [c.frames for c in counters]
        for c in counters:
            c.measuring = True
            c.max_gap = 0.0
        await asyncio.sleep(args.seconds)
        f1 = [c.frames for c in counters]
        cpu1, my1, t1 = proc_cpu(proc.pid), time.process_time(), time.monotonic()
        s1 = await asyncio.to_thread(query)
        stop.set()
        await asyncio.wait(tasks, timeout=5)
    finally:
        with _suppress():
            proc.stdin.write("quit\n")
            proc.stdin.flush()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    wall = t1 - t0
    fps = sorted((b - a) / wall for a, b in zip(f0, f1))
    frames = s1["frames"] - s0["frames"]
    drawn = s1["drawn"] - s0["drawn"]
    skipped = s1["skipped"] - s0["skipped"]
    return {
        "policy": policy, "clients": n, "stalled": args.stalled,
        "fps_min": fps[0], "fps_median": statistics.median(fps), "fps_max": fps[-1],
        "total_fps": sum(fps), "worst_gap_ms": 1e3 * max(c.max_gap for c in counters),
        "server_cpu": 100.0 * (cpu1 - cpu0) / wall, "client_cpu": 100.0 * (my1 - my0) / wall,
        "loop_hz": frames / wall, "loop_busy": (s1["work_s"] - s0["work_s"]) / wall,
        "skipped_share": skipped / max(drawn + skipped, 1),
        "errors": sorted({c.error for c in counters if c.error}),
    }


class _suppress:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> bool:
        return True


HEADER = (f"{'policy':8} {'N':>3} {'fps min':>8} {'median':>7} {'max':>6} {'total/s':>8} "
          f"{'gap ms':>7} {'srv CPU':>8} {'cli CPU':>8} {'loop Hz':>8} {'busy':>5} {'skip':>5}")


def format_row(r: dict[str, Any]) -> str:
    return (f"{r['policy']:8} {r['clients']:>3} {r['fps_min']:8.1f} {r['fps_median']:7.1f} "
            f"{r['fps_max']:6.1f} {r['total_fps']:8.0f} {r['worst_gap_ms']:7.0f} "
            f"{r['server_cpu']:7.0f}% {r['client_cpu']:7.0f}% {r['loop_hz']:8.1f} "
            f"{r['loop_busy']:5.2f} {r['skipped_share']:5.2f}")


async def main_async(args: argparse.Namespace) -> list[dict[str, Any]]:
    results = []
    print(f"nodes/client {args.nodes} (+position +points), stalled {args.stalled}, "
          f"{args.seconds:g} s after {args.warmup:g} s warm-up, repeats {args.repeat}", flush=True)
    print(HEADER, flush=True)
    for n in args.clients:
        for _ in range(args.repeat):
            for policy in args.policies:
                r = await run_config(args, policy, n)
                results.append(r)
                print(format_row(r), flush=True)
                for error in r["errors"]:
                    print(f"    client error: {error}", flush=True)
    return results


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--clients", default="20,40,60,80",
                        type=lambda s: [int(x) for x in s.split(",")])
    parser.add_argument("--policies", default="old,new",
                        type=lambda s: [p for p in s.split(",") if p in POLICIES])
    parser.add_argument("--nodes", type=int, default=6)
    parser.add_argument("--rate", type=float, default=60.0)
    parser.add_argument("--idle-ratio", type=float, default=0.25)
    parser.add_argument("--max-wait", type=float, default=0.25)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--warmup", type=float, default=3.0)
    parser.add_argument("--stalled", type=int, default=0)
    parser.add_argument("--sndbuf", type=int, default=0,
                        help="server-side SO_SNDBUF per connection [B] (0: kernel default)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--json", type=Path, default=None, help="also write the rows here")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--policy", default="old", help=argparse.SUPPRESS)
    parser.add_argument("--max-lifetime", type=float, default=600.0, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.serve:
        serve(args)
        return
    results = asyncio.run(main_async(args))
    if args.json is not None:
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
