"""From the hand to the pixels: how long after a mouse move on the φ slider's thumb the body moves.

The app runs in its own process (`python -m app`, one process, the Euler angles scene, paused)
from a source tree; Debian's Chromium opens it (Playwright, 1280×800) and drags the φ thumb,
one 5 px mouse step every 250 ms (**slow**: a lecturer turning φ while talking) or every 60 ms
(**fast**; the page sends at most one value per 50 ms), `--steps` steps.

The pixels are read in the page (`PROBE_JS`): after every animation frame the body region of the
WebGL canvas is compared with the previous frame's (a change: more than 0.2 % of its pixels by
more than 8/255), and mouse moves are timestamped on the same clock.  A step's latency is the
time from its mouse move to the first change after it not owed to an earlier step; a step whose
body had not moved by the end of the drag (one gap after the last step) is "never": the body
moved only after the thumb stopped.  p50 / p95 count "never" as infinite.

Each configuration is run quiet and with two busy cores (two `yes > /dev/null`), for this tree
and, with `--baseline REF`, for REF checked out in a temporary git worktree (same machine, same
minutes, alternating).

    python benchmarks/drag_latency.py                      # this tree, quiet and busy
    python benchmarks/drag_latency.py --baseline 1f19119   # and the tree before, side by side
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.frame_cost import _worktree  # noqa: E402
from scripts.chromium import CHROMIUM, CHROMIUM_ARGS  # noqa: E402

__all__ = ["Drag", "busy_cores", "main", "measure"]

CLIP = {"x": 440, "y": 200, "width": 400, "height": 400}  # [CSS px] around the body (the view's centre)
CHANGED = 0.002  # fraction of the region's pixels that must change for "the body moved"
SLOW_GAP_S = 0.25  # [s] between mouse steps of a slow drag
FAST_GAP_S = 0.06  # [s] a fast drag: just above the page's one value per 50 ms


@dataclass
class Drag:
    """One drag's result: per step the latency [s] (math.inf: not moved before the drag ended)."""

    tree: str
    load: str
    kind: str
    latencies: list[float]
    fps: float  # frames a second the page drew while the probe ran

    def row(self) -> str:
        moved = [x for x in self.latencies if math.isfinite(x)]
        p50, p95 = _quantile(self.latencies, 0.5), _quantile(self.latencies, 0.95)
        return (f"| {self.tree} | {self.load} | {self.kind} | {len(moved)} of {len(self.latencies)} | "
                f"{_ms(p50)} | {_ms(p95)} | {self.fps:.0f} |")


def _quantile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(math.ceil(q * len(ordered))) - 1)]


def _ms(x: float) -> str:
    return "never" if not math.isfinite(x) else f"{x * 1e3:.0f} ms"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextlib.contextmanager
def _app(tree: Path) -> Iterator[int]:
    """`python -m app` from `tree` on a free port (its output to a file); the port."""
    port = _free_port()
    env = dict(os.environ, PYTHONPATH=str(tree))
    with tempfile.TemporaryFile() as log:
        process = subprocess.Popen([sys.executable, "-m", "app", "--host", "127.0.0.1", "--port", str(port)],
                                   cwd=tree, env=env, stdout=log, stderr=log)
        try:
            deadline = time.monotonic() + 60.0
            while time.monotonic() < deadline:
                with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=0.5):
                    break
                time.sleep(0.2)
            yield port
        finally:
            process.terminate()
            process.wait(timeout=20)


@contextlib.contextmanager
def busy_cores(cores: int = 2) -> Iterator[None]:
    """`cores` processes that keep a core each busy (`yes > /dev/null`) while the block runs."""
    hogs = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(cores)]
    try:
        yield
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


PROBE_JS = """
(() => {
  const canvases = [...document.querySelectorAll("canvas")];
  const gl = canvases.reduce((a, b) => (a.width * a.height >= b.width * b.height ? a : b));
  const k = gl.width / gl.clientWidth;
  const [sx, sy, sw, sh] = [@X@ * k, @Y@ * k, @W@ * k, @H@ * k];
  const small = document.createElement("canvas");
  small.width = 96; small.height = 96;
  const ctx = small.getContext("2d", { willReadFrequently: true });
  const probe = { moves: [], changes: [], frames: 0, since: performance.now() };
  let last = null;
  function frame() {
    requestAnimationFrame(frame);
    ctx.drawImage(gl, sx, sy, sw, sh, 0, 0, 96, 96);
    const data = ctx.getImageData(0, 0, 96, 96).data;
    probe.frames += 1;
    if (last !== null) {
      let n = 0;
      for (let i = 0; i < data.length; i += 4) {
        if (Math.abs(data[i] - last[i]) > 8 || Math.abs(data[i + 1] - last[i + 1]) > 8
            || Math.abs(data[i + 2] - last[i + 2]) > 8) n += 1;
      }
      if (n > @CHANGED@ * 96 * 96) probe.changes.push(performance.now());
    }
    last = data;
  }
  requestAnimationFrame(frame);
  window.addEventListener("pointermove", (e) => { if (e.buttons & 1) probe.moves.push(performance.now()); }, true);
  window.__dragProbe = probe;
})();
"""
"""In the page: after each animation frame (registered after the 3D view's own, so it reads the
frame just rendered) the body region of the WebGL canvas, 96×96, is compared with the last; the
times [ms, performance.now()] of changes and of mouse moves with the button down are kept."""


def _drag(page, steps: int, gap_s: float, px: float) -> tuple[list[float], float]:  # type: ignore[no-untyped-def]
    """Drag the φ thumb `steps` times by `px`, every gap_s; (latency per step [s], frames a second)."""
    label = page.locator("label", has_text="φ [deg]").first
    thumb = page.locator(f'[id="{label.get_attribute("for")}"] [role="slider"]')
    box = thumb.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    page.evaluate(PROBE_JS.replace("@X@", str(CLIP["x"])).replace("@Y@", str(CLIP["y"]))
                  .replace("@W@", str(CLIP["width"])).replace("@H@", str(CLIP["height"]))
                  .replace("@CHANGED@", str(CHANGED)))
    time.sleep(0.5)
    try:
        t0 = time.perf_counter()
        for k in range(1, steps + 1):
            time.sleep(max(0.0, t0 + gap_s * (k - 1) - time.perf_counter()))
            page.mouse.move(x + px * k, y)
        time.sleep(gap_s)
        probe = page.evaluate("({moves: window.__dragProbe.moves, changes: window.__dragProbe.changes,"
                              " frames: window.__dragProbe.frames, ms: performance.now() - window.__dragProbe.since})")
    finally:
        page.mouse.up()
    return _latencies(probe["moves"], probe["changes"]), 1e3 * probe["frames"] / max(probe["ms"], 1.0)


def _latencies(moves: list[float], changes: list[float]) -> list[float]:
    """[s] per move: the time to the first change of the body's pixels after it not already
    taken by an earlier move (so a change is owed to one move; a move coalesced with the next
    waits for a later change: an upper bound); inf if none came before the drag ended."""
    out, j = [], 0
    for t_move in moves:
        while j < len(changes) and changes[j] < t_move:
            j += 1
        if j < len(changes):
            out.append((changes[j] - t_move) / 1e3)
            j += 1
        else:
            out.append(math.inf)
    return out


def measure(tree: Path, name: str, steps: int, loads: tuple[str, ...]) -> list[Drag]:
    """Slow and fast drags on the app of `tree`, quiet and/or busy; one fresh app and page per drag."""
    from playwright.sync_api import sync_playwright

    results = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        try:
            for load in loads:
                for kind, gap in (("slow", SLOW_GAP_S), ("fast", FAST_GAP_S)):
                    with _app(tree) as port:
                        context = browser.new_context(viewport={"width": 1280, "height": 800})
                        page = context.new_page()
                        ratio = page.evaluate("window.devicePixelRatio")
                        page.goto(f"http://127.0.0.1:{port}/?fixedDpr={ratio}")
                        page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=60_000)
                        time.sleep(2.0)  # objects fade in
                        closers = page.locator(".mantine-Notification-closeButton")
                        for i in range(closers.count()):
                            closers.nth(i).click(force=True)
                        with busy_cores() if load == "busy" else contextlib.nullcontext():
                            time.sleep(0.5)
                            latencies, fps = _drag(page, steps, gap, px=5.0)
                        context.close()
                    results.append(Drag(name, load, kind, latencies, fps))
                    print(results[-1].row(), flush=True)
        finally:
            browser.close()
    return results


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", metavar="REF", help="also measure REF (a git commit), in a temporary worktree")
    parser.add_argument("--steps", type=int, default=12, help="mouse steps per drag (default 12)")
    parser.add_argument("--load", choices=("quiet", "busy", "both"), default="both")
    args = parser.parse_args(argv)
    loads = ("quiet", "busy") if args.load == "both" else (args.load,)
    print("| tree | machine | drag | steps the body followed | p50 | p95 | page fps |")
    print("|---|---|---|---|---|---|---|")
    if args.baseline:
        with _worktree(args.baseline) as tree:
            measure(tree, args.baseline, args.steps, loads)
    measure(ROOT, "this tree", args.steps, loads)


if __name__ == "__main__":
    main()
