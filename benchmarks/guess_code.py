"""A script that guesses the presenter code, against `rigid-body-lab --workers N` (or a running app).

    python benchmarks/guess_code.py [--workers 2] [--connections 24] [--seconds 60] [--port P]

It starts the app with `--workers N` (0: the one-process app) on a free port and a random code it keeps (or, with
`--port`, attacks what listens there: then it cannot say when the lecturer gets in), and then
runs `--connections` websocket clients (`benchmarks.ws_client.AsyncViserClient`: what a browser
sends) that type a code into `Presenter code` and press `Present` as fast as the answers come,
each reconnecting as a new browser when its own limit of wrong codes is reached.  It counts the
codes the app evaluated (the answer "Wrong presenter code ...") and the refusals that evaluated
nothing (the hall's limit, "someone else is presenting").  Then the attack stops and the
lecturer's browser, which has the code, tries it once a second until it presents.

Prints: wrong codes evaluated per minute, the chance that a guesser at that rate presents in a
90-minute lecture against a random code (`app.lecture.gate.guess_chance`), and the seconds the
lecturer waited after the attack.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import random
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from app.cluster.services import free_port  # noqa: E402
from app.lecture.gate import guess_chance, new_code  # noqa: E402
from benchmarks.ws_client import AsyncViserClient  # noqa: E402

ANSWER_S = 2.0  # [s] an answer that does not come in this long: the words did not change


def _note(client: AsyncViserClient) -> str:
    """The lecture panel's note (the refusal), "" if none."""
    with client.state.lock:
        for element in client.state.gui.values():
            content = str(element.props.get("_markdown", element.props.get("content", "")))
            if "Markdown" in element.type and "⚠" in content and element.props.get("visible", True):
                return content
    return ""


def _presenting(client: AsyncViserClient) -> bool:
    stop = client.state.find_gui("Stop presenting", "Button")
    return stop is not None and bool(stop.props.get("visible", False))


async def _try(client: AsyncViserClient, code: str) -> str:
    """Type `code`, press Present; the note after the answer ("" if the browser presents)."""
    before = _note(client)
    await client.set_value("Presenter code", code)
    await client.click("Present")
    deadline = time.monotonic() + ANSWER_S
    while time.monotonic() < deadline:
        now = _note(client)
        if now != before or _presenting(client):
            break
        await asyncio.sleep(0.005)
    return "" if _presenting(client) else _note(client)


class Tally:
    def __init__(self) -> None:
        self.evaluated = 0  # wrong codes the app compared
        self.hall = 0  # refused by the hall's limit (not evaluated)
        self.busy = 0  # refused: someone presents (not evaluated)
        self.reconnects = 0
        self.other: dict[str, int] = {}


async def _attacker(port: int, stop_at: float, tally: Tally, rng: random.Random) -> None:
    while time.monotonic() < stop_at:
        try:
            client = await AsyncViserClient.connect(port, open_timeout=30.0)
        except Exception:  # noqa: BLE001 - refused: try again
            await asyncio.sleep(0.2)
            continue
        try:
            await client.wait_for_label("Present", timeout=30.0)
            while time.monotonic() < stop_at and not client.closed:
                words = await _try(client, f"{rng.randrange(10**8):08d}")
                if "Wrong presenter code" in words:
                    tally.evaluated += 1
                    if "no tries left" in words:
                        break  # this browser's own limit: come back as a new one
                elif "in this lecture hall" in words:
                    tally.hall += 1
                elif "Someone else" in words:
                    tally.busy += 1
                elif "Too many wrong codes" in words:
                    break
                else:
                    tally.other[words[:60]] = tally.other.get(words[:60], 0) + 1
        except Exception:  # noqa: BLE001 - a dropped connection: reconnect
            pass
        finally:
            with contextlib.suppress(Exception):
                await client.close()
            tally.reconnects += 1


async def _lecturer_waits(port: int, code: str, limit_s: float) -> float | None:
    """Seconds until the lecturer's browser presents with `code` (trying once a second)."""
    client = await AsyncViserClient.connect(port, open_timeout=30.0)
    try:
        await client.wait_for_label("Present", timeout=30.0)
        started = time.monotonic()
        while time.monotonic() - started < limit_s:
            if await _try(client, code) == "":
                return time.monotonic() - started
            await asyncio.sleep(1.0)
        return None
    finally:
        await client.close()


async def _run(args: argparse.Namespace, port: int, code: str | None) -> None:
    tally = Tally()
    rng = random.Random(args.seed)
    started = time.monotonic()
    stop_at = started + args.seconds
    await asyncio.gather(*(_attacker(port, stop_at, tally, rng) for _ in range(args.connections)))
    seconds = time.monotonic() - started
    per_minute = tally.evaluated / seconds * 60.0
    where = f"--workers {args.workers}" if args.workers else "one process"
    print(f"{where}; {args.connections} connections, {seconds:.0f} s: {tally.evaluated} wrong codes evaluated "
          f"({per_minute:.1f} a minute), {tally.hall} refused by the hall's limit, {tally.busy} while someone "
          f"presented, {tally.reconnects} reconnections; other answers: {tally.other or 'none'}")
    print(f"chance to present in a 90-minute lecture at {per_minute:.1f} a minute against a random 8-digit code: "
          f"{guess_chance(90.0, max_wrong=max(1, round(per_minute))):.1e}")
    if code is not None:
        waited = await _lecturer_waits(port, code, 120.0)
        print("the lecturer presented " + (f"{waited:.1f} s after the attack stopped" if waited is not None
                                            else "not within 120 s of the attack"))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2, help="app processes behind nginx (0: one process)")
    parser.add_argument("--connections", type=int, default=24)
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--port", type=int, help="attack the app on this port (started elsewhere)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    if args.port is not None:
        asyncio.run(_run(args, args.port, None))
        return
    code, port = new_code(), free_port()
    log = Path(tempfile.mkdtemp(prefix="guess-code-")) / "app.log"
    with open(log, "wb") as out:
        workers = ["--workers", str(args.workers)] if args.workers > 0 else []
        app = subprocess.Popen([sys.executable, "-m", "app", *workers, "--port", str(port), "--presenter-code", code],
                               stdout=out, stderr=subprocess.STDOUT, cwd=Path(__file__).resolve().parents[1])
    try:
        deadline = time.monotonic() + 180.0
        while "open http" not in log.read_text(errors="replace"):
            if app.poll() is not None or time.monotonic() > deadline:
                raise SystemExit(f"the app did not start:\n{log.read_text(errors='replace')}")
            time.sleep(0.2)
        asyncio.run(_run(args, port, code))
    finally:
        app.terminate()
        app.wait(60)
        shutil.rmtree(log.parent, ignore_errors=True)


if __name__ == "__main__":
    main()
