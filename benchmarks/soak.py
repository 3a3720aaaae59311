"""Soak: a presenter plays while browsers keep joining and leaving; does the server hold up?

The app runs in a subprocess (`load_clients.py --serve`).  One presenter types the code,
presses Present, picks the free body's Dzhanibekov preset and presses Play.  `--browsers`
followers join; every `--churn` seconds the oldest one leaves and a new one joins (a class
coming and going).  Every 10 s the server's resident memory is sampled (with `--workers N`:
N workers behind nginx with the lecture's Redis bus, `benchmarks/cluster_load.Cluster`, each
worker's memory), and printed once a minute as the run goes.  At the end: memory after the
first minute ("settled"), after 10 minutes and at the end, the frames a follower that stayed all
along received per second, and the errors the server (every worker) logged (ERROR or Traceback
lines in its log).

    python benchmarks/soak.py                      # an hour, 20 browsers (the issue's soak)
    python benchmarks/soak.py --workers 2          # the same, two workers
    python benchmarks/soak.py --minutes 2 --hostile   # the version tests/test_soak.py runs

Target (lecture-hall issues): memory at the end within 10 MiB of where it settled after the
first minute (issue 34: of where it stands after 10 minutes), on each process; no error logged.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import dataclasses
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.load_clients import (  # noqa: E402
    PRESENTER_CODE,
    ServerProcess,
    run_async,
    sample_process,
    start_playing,
)
from benchmarks.ws_client import AsyncViserClient  # noqa: E402

__all__ = ["SoakResult", "main", "run_soak"]

SAMPLE_PERIOD = 10.0  # [s] between memory samples
START_TIMEOUT_S = 120.0  # [s] for the presenter's motion and a browser's first scene: generous for a busy machine


def rss_at(samples: list[tuple[float, float]], seconds: float) -> float:
    """The first sample at or after `seconds` [s] (the last one if none) [MiB]."""
    return next((rss for t, rss in samples if t >= seconds), samples[-1][1])


@dataclasses.dataclass
class SoakResult:
    minutes: float
    browsers: int
    joins: int
    rss_mib: list[tuple[float, float]]  # (seconds since start, VmRSS [MiB]) of the first process
    settled_mib: float  # the first sample at or after `settle_s`
    end_mib: float
    steady_fps: float  # frames/s received by a follower that stayed all along
    presenter_fps: float  # frames/s the presenter received over the same time: what the room drew
    errors: list[str]
    processes: dict[str, list[tuple[float, float]]] = dataclasses.field(default_factory=dict)
    """Every process's samples by name ("server", or "worker 1", "worker 2", ...)."""
    settle_s: float = 60.0
    """When memory counts as settled [s after the start]: growth is measured from there."""

    @property
    def growth_mib(self) -> float:
        """End memory minus the settled memory [MiB], the largest over the processes."""
        return max((s[-1][1] - rss_at(s, self.settle_s) for s in self.processes.values()),
                   default=self.end_mib - self.settled_mib)

    def growth_after_mib(self, minutes: float) -> dict[str, float]:
        """End memory minus memory after `minutes` [MiB], by process."""
        return {name: s[-1][1] - rss_at(s, 60.0 * minutes) for name, s in self.processes.items()}

    def minute_lines(self, every: int = 10) -> list[str]:
        """RSS after 1 minute, every `every` minutes and at the end, one line per process."""
        marks = sorted({1, *range(every, int(self.minutes) + 1, every)})
        return [f"{name}: RSS [MiB] " + ", ".join(f"{m} min {rss_at(s, 60.0 * m):.1f}" for m in marks)
                + f", end {s[-1][1]:.1f}" for name, s in self.processes.items()]

    def summary(self) -> str:
        return (f"{self.minutes:g} min, {self.browsers} browsers, {self.joins} joins: RSS settled "
                f"{self.settled_mib:.1f} MiB after {self.settle_s:g} s, {self.end_mib:.1f} MiB at the end "
                f"({self.growth_mib:+.1f} MiB, the most of {len(self.processes) or 1} process(es)); "
                f"a follower that stayed got {self.steady_fps:.1f} fps, the presenter "
                f"{self.presenter_fps:.1f}; "
                f"{len(self.errors)} error line(s) logged")


@dataclasses.dataclass
class Target:
    """What the soak runs against: the port browsers connect to, the presenter code, the pids
    whose memory is sampled by name, and `log()` (everything the processes logged)."""

    port: int
    code: str
    pids: dict[str, int]
    log: Any


async def _hostile(port: int, stop: asyncio.Event) -> None:
    """Three hostile browsers: one never reads its socket; one types wrong codes in a loop; one
    sends updates for GUI elements that are not its own (the presenter's, by a guessed uuid)."""
    from websockets.asyncio.client import connect

    from benchmarks.ws_client import camera_message, encode_message, gui_update_message, subprotocol

    silent = await connect(f"ws://127.0.0.1:{port}", subprotocols=[subprotocol()], max_size=None,
                           max_queue=1, compression=None)
    await silent.send(encode_message(camera_message()))  # and then never reads
    guesser = await AsyncViserClient.connect(port, keep_messages=50)
    await guesser.wait_for_label("Presenter code", 30.0)
    try:
        k = 0
        while not stop.is_set():
            k += 1
            await guesser.set_value("Presenter code", f"{k:06d}x")
            await guesser.click("Present")
            await guesser.send(gui_update_message(f"not-mine-{k}", 4.0))
            await asyncio.sleep(0.5)
    finally:
        await guesser.close()
        await silent.close()


def _sample(target: Target, samples: dict[str, list[tuple[float, float]]], seconds: float) -> None:
    for name, pid in target.pids.items():
        samples[name].append((seconds, sample_process(pid).rss_mib))


async def _soak(target: Target, minutes: float, browsers: int, churn: float,
                hostile: bool = False, settle_s: float = 60.0, min_joins: int = 0) -> SoakResult:
    presenter = await AsyncViserClient.connect(target.port, keep_messages=100)
    await presenter.wait_for_label("Presenter code", 30.0)
    await presenter.set_value("Presenter code", target.code)
    await asyncio.sleep(0.2)
    await presenter.click("Present")
    await asyncio.sleep(0.5)
    await start_playing(presenter, "Free body", timeout=START_TIMEOUT_S)
    presenter.state.count_only = True

    async def join() -> AsyncViserClient:
        client = await AsyncViserClient.connect(target.port, keep_messages=20)
        await client.wait_for(lambda: client.state.replay_done, START_TIMEOUT_S)
        client.state.count_only = True
        return client

    stop = asyncio.Event()
    hostiles = asyncio.create_task(_hostile(target.port, stop)) if hostile else None
    steady = await join()
    crowd: collections.deque[AsyncViserClient] = collections.deque([await join() for _ in range(browsers - 1)])
    joins = browsers
    start = time.monotonic()
    frames0, presenter_frames0 = steady.state.frames, presenter.state.frames
    samples: dict[str, list[tuple[float, float]]] = {name: [] for name in target.pids}
    _sample(target, samples, 0.0)
    next_sample, next_churn, next_minute = start + SAMPLE_PERIOD, start + churn, 1
    end = start + 60.0 * minutes
    try:
        while (now := time.monotonic()) < end or joins < min_joins:
            if now >= next_churn:
                await crowd.popleft().close()
                crowd.append(await join())
                joins += 1
                next_churn += churn
            if now >= next_sample:
                _sample(target, samples, now - start)
                next_sample += SAMPLE_PERIOD
                if now - start >= 60.0 * next_minute:
                    print(f"minute {next_minute} ({joins} joins): RSS [MiB] " + ", ".join(
                        f"{name} {s[-1][1]:.1f}" for name, s in samples.items()), flush=True)
                    next_minute += 1
            await asyncio.sleep(0.05)
        _sample(target, samples, time.monotonic() - start)
        elapsed = time.monotonic() - start
        fps = (steady.state.frames - frames0) / elapsed
        presenter_fps = (presenter.state.frames - presenter_frames0) / elapsed
    finally:
        stop.set()
        if hostiles is not None:
            await asyncio.gather(hostiles, return_exceptions=True)
        await asyncio.gather(*(c.close() for c in [presenter, steady, *crowd]), return_exceptions=True)
    first = next(iter(samples.values()))
    errors = [line for line in target.log().splitlines() if "ERROR" in line or "Traceback" in line]
    return SoakResult(minutes, browsers, joins, first, rss_at(first, settle_s), first[-1][1], fps, presenter_fps,
                      errors, samples, settle_s)


def _worker_log(worker: Any) -> str:
    worker._log.seek(0)
    return str(worker._log.read())


def run_soak(minutes: float = 60.0, browsers: int = 20, churn: float = 3.0, hostile: bool = False,
             workers: int = 0, settle_s: float = 60.0, min_joins: int = 0) -> SoakResult:
    """Run the soak (see the module docstring) against a fresh server subprocess (`workers` 0),
    or `workers` worker processes behind nginx with the lecture's Redis bus; memory counts as
    settled `settle_s` [s] after the start.  The run lasts `minutes`, and on until `min_joins`
    browsers have joined (a busy machine joins fewer a minute)."""
    if minutes <= 0 or browsers < 1 or churn <= 0 or workers < 0 or not 0 <= settle_s < 60.0 * minutes:
        raise ValueError("need minutes > 0, browsers >= 1, churn > 0, workers >= 0, 0 <= settle_s < the run")
    lifetime = 60.0 * minutes + 120.0
    if workers:
        from benchmarks.cluster_load import WORKER_CODE, Cluster

        cluster = Cluster(workers, lifetime, bus=True)
        try:
            target = Target(cluster.port, WORKER_CODE,
                            {f"worker {i + 1}": w.pid for i, w in enumerate(cluster.workers)},
                            lambda: "\n".join(_worker_log(w) for w in cluster.workers))
            return run_async(_soak(target, minutes, browsers, churn, hostile, settle_s, min_joins))
        finally:
            cluster.stop()
    server = ServerProcess(max_lifetime=lifetime)
    try:
        target = Target(server.port, PRESENTER_CODE, {"server": server.pid}, lambda: server.log_tail(1_000_000))
        return run_async(_soak(target, minutes, browsers, churn, hostile, settle_s, min_joins))
    finally:
        server.stop()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    parser.add_argument("--browsers", type=int, default=20)
    parser.add_argument("--churn", type=float, default=3.0, help="seconds between a leave and a join")
    parser.add_argument("--workers", type=int, default=0,
                        help="N worker processes behind nginx with the Redis bus (0: one process)")
    parser.add_argument("--hostile", action="store_true",
                        help="add a browser that never reads, one that guesses codes, one that sends foreign updates")
    args = parser.parse_args(argv)
    result = run_soak(args.minutes, args.browsers, args.churn, args.hostile, args.workers)
    print(result.summary())
    for line in result.minute_lines():
        print(line)
    if args.minutes > 10:
        print("end - 10 min [MiB]: " + ", ".join(f"{name} {growth:+.1f}"
                                                for name, growth in result.growth_after_mib(10.0).items()))
    for name, samples in result.processes.items():
        print(f"{name}: RSS [MiB] every 10 s: " + " ".join(f"{rss:.0f}" for _, rss in samples))
    for line in result.errors[:10]:
        print("logged:", line)


if __name__ == "__main__":
    main()
