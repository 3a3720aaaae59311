"""Soak: a presenter plays while browsers keep joining and leaving; does the server hold up?

The app runs in a subprocess (`load_clients.py --serve`).  One presenter types the code,
presses Present, picks the free body's Dzhanibekov preset and presses Play.  `--browsers`
followers join; every `--churn` seconds the oldest one leaves and a new one joins (a class
coming and going).  Every 10 s the server's resident memory is sampled.  At the end: memory
after the first minute ("settled") and at the end, the largest growth after the first minute,
the frames a follower that stayed all along received per second, and the errors the server
logged (ERROR or Traceback lines in its log).

    python benchmarks/soak.py                      # an hour, 20 browsers (the issue's soak)
    python benchmarks/soak.py --minutes 2 --hostile   # the version tests/test_soak.py runs

Target (lecture-hall issue): memory at the end within 10 MiB of where it settled after the
first minute; no error logged.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import dataclasses
import sys
import time
from pathlib import Path

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


@dataclasses.dataclass
class SoakResult:
    minutes: float
    browsers: int
    joins: int
    rss_mib: list[tuple[float, float]]  # (seconds since start, VmRSS [MiB])
    settled_mib: float  # the first sample at or after one minute
    end_mib: float
    steady_fps: float  # frames/s received by a follower that stayed all along
    errors: list[str]

    @property
    def growth_mib(self) -> float:
        """End memory minus the settled memory [MiB]."""
        return self.end_mib - self.settled_mib

    def summary(self) -> str:
        return (f"{self.minutes:g} min, {self.browsers} browsers, {self.joins} joins: RSS settled "
                f"{self.settled_mib:.1f} MiB after 1 min, {self.end_mib:.1f} MiB at the end "
                f"({self.growth_mib:+.1f} MiB); a follower that stayed got {self.steady_fps:.1f} fps; "
                f"{len(self.errors)} error line(s) logged")


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


async def _soak(server: ServerProcess, minutes: float, browsers: int, churn: float,
                hostile: bool = False) -> SoakResult:
    presenter = await AsyncViserClient.connect(server.port, keep_messages=100)
    await presenter.wait_for_label("Presenter code", 30.0)
    await presenter.set_value("Presenter code", PRESENTER_CODE)
    await asyncio.sleep(0.2)
    await presenter.click("Present")
    await asyncio.sleep(0.5)
    await start_playing(presenter, "Free body", timeout=30.0)
    presenter.state.count_only = True

    async def join() -> AsyncViserClient:
        client = await AsyncViserClient.connect(server.port, keep_messages=20)
        await client.wait_for(lambda: client.state.replay_done, 60.0)
        client.state.count_only = True
        return client

    stop = asyncio.Event()
    hostiles = asyncio.create_task(_hostile(server.port, stop)) if hostile else None
    steady = await join()
    crowd: collections.deque[AsyncViserClient] = collections.deque([await join() for _ in range(browsers - 1)])
    joins = browsers
    start = time.monotonic()
    frames0 = steady.state.frames
    samples: list[tuple[float, float]] = [(0.0, sample_process(server.pid).rss_mib)]
    next_sample, next_churn = start + SAMPLE_PERIOD, start + churn
    end = start + 60.0 * minutes
    try:
        while (now := time.monotonic()) < end:
            if now >= next_churn:
                await crowd.popleft().close()
                crowd.append(await join())
                joins += 1
                next_churn += churn
            if now >= next_sample:
                samples.append((now - start, sample_process(server.pid).rss_mib))
                next_sample += SAMPLE_PERIOD
            await asyncio.sleep(0.05)
        samples.append((time.monotonic() - start, sample_process(server.pid).rss_mib))
        fps = (steady.state.frames - frames0) / (time.monotonic() - start)
    finally:
        stop.set()
        if hostiles is not None:
            await asyncio.gather(hostiles, return_exceptions=True)
        await asyncio.gather(*(c.close() for c in [presenter, steady, *crowd]), return_exceptions=True)
    settled = next((rss for t, rss in samples if t >= 60.0), samples[-1][1])
    log = server.log_tail(1_000_000)
    errors = [line for line in log.splitlines() if "ERROR" in line or "Traceback" in line]
    return SoakResult(minutes, browsers, joins, samples, settled, samples[-1][1], fps, errors)


def run_soak(minutes: float = 60.0, browsers: int = 20, churn: float = 3.0, hostile: bool = False
             ) -> SoakResult:
    """Run the soak (see the module docstring) against a fresh server subprocess."""
    if minutes <= 0 or browsers < 1 or churn <= 0:
        raise ValueError("need minutes > 0, browsers >= 1, churn > 0")
    server = ServerProcess(max_lifetime=60.0 * minutes + 120.0)
    try:
        return run_async(_soak(server, minutes, browsers, churn, hostile))
    finally:
        server.stop()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    parser.add_argument("--browsers", type=int, default=20)
    parser.add_argument("--churn", type=float, default=3.0, help="seconds between a leave and a join")
    parser.add_argument("--hostile", action="store_true",
                        help="add a browser that never reads, one that guesses codes, one that sends foreign updates")
    args = parser.parse_args(argv)
    result = run_soak(args.minutes, args.browsers, args.churn, args.hostile)
    print(result.summary())
    print("RSS [MiB] every 10 s: " + " ".join(f"{rss:.0f}" for _, rss in result.rss_mib))
    for line in result.errors[:10]:
        print("logged:", line)


if __name__ == "__main__":
    main()
