"""Ask the class under load: N light browser stand-ins follow a playing presenter and answer one
question; how soon the tally is complete, and the followers' frame rate with and without a round.

The app runs in a subprocess (its own interpreter: the clients never share its GIL), the
clients are pure-Python viser clients (`benchmarks/ws_client.py`) on one asyncio loop here.  A
presenter client types the code, presses Present, picks the scene and presses Play; N followers
join and count the frames of the shared scene (not decoding them).  Then:

1. the followers' frames per second over `--seconds` (no question);
2. the presenter's session asks a choice question (the server's `Session.ask`, by a command on
   the subprocess's stdin); every follower finds its own option button (its panel is decoded
   until then) and presses it, all at once; the server reports the moment its tally counts N
   answers (it polls `App.rounds` every 2 ms): "tally complete" is that moment minus the moment
   the last answer was sent (both `time.monotonic()`, one clock on Linux);
3. the followers' frames per second over `--seconds` with the round open, then again once the
   question has ended (a busy machine's load drifts: the two windows without a round bracket
   the one with it); the ratio of the medians, with / (the mean of the two without), is printed
   (the issue's target: within 10 %, ratio >= 0.9; and the tally complete
   within 1 s of the last answer).

    python benchmarks/ask_load.py                       # 300 followers, 10 s windows
    python benchmarks/ask_load.py --clients 50 --seconds 5

Bounded: at most --clients + 1 connections; the server exits when this process ends or after a
hard time limit.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import queue
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

from benchmarks.load_clients import PRESENTER_CODE, present_and_play, run_async  # noqa: E402
from benchmarks.ws_client import AsyncViserClient  # noqa: E402

QUESTION = {"kind": "choice", "prompt": "Which axis is stable?", "options": ["x′", "y′", "z′"], "correct": 2}
LABELS = [f"{k + 1}. {option}" for k, option in enumerate(QUESTION["options"])]


def serve(max_lifetime: float) -> None:
    """--serve: the app on 127.0.0.1:0, printing 'BENCH_PORT <port>'.  stdin commands: 'ask N'
    (the presenter asks QUESTION; then 'BENCH_COMPLETE <monotonic time>' once the tally counts N
    answers), 'tally' ('BENCH_TALLY <answered> <counts...>').  Exits when stdin closes."""
    from app.main import create_server

    app = create_server("127.0.0.1", 0, verbose=False, presenter_code=PRESENTER_CODE)
    print(f"BENCH_PORT {app.port}", flush=True)
    done = threading.Event()

    def watch(expected: int) -> None:
        deadline = time.monotonic() + max_lifetime
        while time.monotonic() < deadline:
            tally = app.rounds.tally()
            if tally is not None and tally.answered >= expected:
                print(f"BENCH_COMPLETE {time.monotonic()}", flush=True)
                return
            time.sleep(0.002)

    def commands() -> None:
        for line in sys.stdin:
            words = line.split()
            if words[:1] == ["ask"]:
                presenter = app.lectern.presenter
                assert presenter is not None, "nobody presents"
                presenter.ask(QUESTION)  # type: ignore[attr-defined]
                threading.Thread(target=watch, args=(int(words[1]),), daemon=True).start()
            elif words[:1] == ["end"]:
                app.rounds.end()
            elif words[:1] == ["tally"]:
                tally = app.rounds.tally()
                counts = () if tally is None else tally.counts
                print(f"BENCH_TALLY {0 if tally is None else tally.answered} {' '.join(map(str, counts))}",
                      flush=True)
        done.set()

    threading.Thread(target=commands, daemon=True).start()
    done.wait(max_lifetime)
    app.stop()


class Server:
    """This file with --serve, in a subprocess: `port`, `pid`, `send(line)`, `read(tag)`, `stop()`."""

    def __init__(self, max_lifetime: float) -> None:
        self._log = tempfile.TemporaryFile(mode="w+")
        self.process = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), "--serve", "--max-lifetime", str(max_lifetime)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._log, text=True, cwd=ROOT)
        self.pid = self.process.pid
        self.lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._reader, daemon=True).start()
        self.port = int(self.read("BENCH_PORT", 60.0)[0])

    def _reader(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            if line.startswith("BENCH_"):
                self.lines.put(line.strip())

    def read(self, tag: str, timeout: float) -> list[str]:
        deadline = time.monotonic() + timeout
        while True:
            try:
                line = self.lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise RuntimeError(f"no {tag} from the app: {self.log_tail()}") from None
            if line.startswith(tag + " "):
                return line.split()[1:]

    def send(self, line: str) -> None:
        assert self.process.stdin is not None
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()

    def log_tail(self, chars: int = 2000) -> str:
        self._log.seek(0)
        return self._log.read()[-chars:]

    def stop(self) -> None:
        if self.process.poll() is None:
            try:
                assert self.process.stdin is not None
                self.process.stdin.close()
                self.process.wait(timeout=20.0)
            except Exception:  # noqa: BLE001 - hung: end it
                self.process.terminate()
                self.process.wait(timeout=10.0)


async def _fps(clients: list[AsyncViserClient], seconds: float) -> list[float]:
    frames0, t0 = [c.state.frames for c in clients], time.monotonic()
    await asyncio.sleep(seconds)
    window = time.monotonic() - t0
    return [(c.state.frames - f0) / window for c, f0 in zip(clients, frames0, strict=True)]


async def _run(server: Server, count: int, seconds: float, scene: str) -> dict[str, Any]:
    port = server.port
    presenter = await AsyncViserClient.connect(port, keep_messages=200)
    followers: list[AsyncViserClient] = []
    try:
        await present_and_play(presenter, scene, timeout=60.0)
        presenter.state.count_only = True
        for _ in range(count):
            followers.append(await AsyncViserClient.connect(port, keep_messages=50, open_timeout=60.0))
        await asyncio.gather(*(c.wait_for(lambda c=c: c.state.replay_done and c.state.find_gui("Explore on my own"),
                                          60.0 + 0.5 * count)
                               for c in followers))  # its panel (and its hidden question) has arrived
        for c in followers:
            c.state.count_only = True
        await asyncio.sleep(2.0)  # warm-up
        without = await _fps(followers, seconds)
        for c in followers:
            c.state.count_only = False  # decode until its question arrives
        server.send(f"ask {count}")
        await asyncio.gather(*(c.wait_for(lambda c=c: c.state.find_gui(LABELS[-1], "Button"), 60.0 + 0.2 * count)
                               for c in followers))
        for c in followers:
            c.state.count_only = True
        await asyncio.gather(*(c.click(LABELS[k % len(LABELS)]) for k, c in enumerate(followers)))
        last_sent = time.monotonic()
        complete = float(server.read("BENCH_COMPLETE", 60.0)[0])
        server.send("tally")
        tally = server.read("BENCH_TALLY", 10.0)
        await asyncio.sleep(1.0)
        with_round = await _fps(followers, seconds)
        server.send("end")  # no question again: the machine's load may have changed meanwhile
        await asyncio.sleep(1.0)
        after = await _fps(followers, seconds)
        return {"fps_after": statistics.median(after), "clients": count,
                "tally_after_last_answer_s": complete - last_sent, "tally": tally,
                "fps_without": statistics.median(without), "fps_with": statistics.median(with_round),
                "fps_min_without": min(without), "fps_min_with": min(with_round)}
    finally:
        await asyncio.gather(*(c.close() for c in [presenter, *followers]), return_exceptions=True)


def run(clients: int = 300, seconds: float = 10.0, scene: str = "Free body") -> dict[str, Any]:
    """The whole measurement (module docstring); its figures."""
    server = Server(max_lifetime=120.0 + 2.0 * seconds + 1.0 * clients)
    try:
        return run_async(_run(server, clients, seconds, scene))
    except Exception as error:
        raise RuntimeError(f"{error}\n--- server log ---\n{server.log_tail()}") from error
    finally:
        server.stop()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clients", type=int, default=300)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--scene", default="Free body")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--max-lifetime", type=float, default=600.0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve:
        serve(args.max_lifetime)
        return
    result = run(args.clients, args.seconds, args.scene)
    base = 0.5 * (result["fps_without"] + result["fps_after"])
    ratio = result["fps_with"] / base if base else float("nan")
    print(f"{result['clients']} followers of {args.scene!r}, {os.cpu_count()} cores")
    print(f"tally complete {1e3 * result['tally_after_last_answer_s']:.0f} ms after the last answer was sent "
          f"(answered, counts: {' '.join(result['tally'])})")
    print(f"followers' fps (median, min): no question {result['fps_without']:.1f}, {result['fps_min_without']:.1f}; "
          f"round open {result['fps_with']:.1f}, {result['fps_min_with']:.1f}; after it {result['fps_after']:.1f}; "
          f"ratio {ratio:.2f}")


if __name__ == "__main__":
    main()
