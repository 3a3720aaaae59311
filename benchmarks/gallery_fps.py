"""The gallery's cost (app.ask.gallery): N judged state answers drawn faint at once on the
presenter's screen, against none.

Starts the app, a presenter in Debian's headless Chromium (1024×768) presenting the heavy top
(Wave, playing) with a State question asked and N answers given through the app's rounds, then
measures the page's frame rate (requestAnimationFrame, WINDOW_S windows) alternately with the
gallery hidden and shown, REPEATS times each, and the server's time to send the gallery's arrays
(`Gallery.draw`; it runs only when answers change or another is chosen, at most every
`REDRAW_PERIOD`, never per frame).  Prints one JSON line.

    python benchmarks/gallery_fps.py [N]      # N = 40 by default

The browser's frame rate under SwiftShader depends on the machine's load: compare the two
medians of one run, on an idle machine.
"""

from __future__ import annotations

import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from app.ask.judges import AnswerState  # noqa: E402
from app.main import create_server  # noqa: E402
from physics.euler import omega_body_from_euler_rates  # noqa: E402
from scripts.chromium import CHROMIUM, CHROMIUM_ARGS  # noqa: E402

CODE = "246810"
WINDOW_S = 3.0
REPEATS = 4
FPS_JS = ("() => new Promise(r => { let n = 0; const t0 = performance.now(); function f() { n++; "
          f"if (performance.now() - t0 < {WINDOW_S * 1000:.0f}) requestAnimationFrame(f); "
          "else r(n * 1000 / (performance.now() - t0)); } requestAnimationFrame(f); })")


def _wait(predicate, timeout: float = 30.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise TimeoutError("condition not met")


def main(n: int = 40) -> dict[str, object]:
    from playwright.sync_api import sync_playwright

    app = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE)
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
            page = browser.new_context(viewport={"width": 1024, "height": 768}).new_page()
            before = set(app.sessions)
            page.goto(f"http://127.0.0.1:{app.port}")
            presenter = _wait(lambda: next((s for c, s in dict(app.sessions).items() if c not in before), None))
            page.locator("canvas").first.wait_for(timeout=30_000)
            presenter.select_scene("Heavy top")
            presenter.apply_preset("Wave")
            presenter.present(CODE)
            presenter.ask({"kind": "state", "prompt": "Find a start that makes the top loop", "scene": "Heavy top",
                           "judge": "top_motion"})
            rng = np.random.default_rng(1)
            for k in range(n):
                theta, phi = math.radians(rng.uniform(35, 75)), rng.uniform(-math.pi, math.pi)
                R = Rotation.from_euler("ZXZ", [phi, theta, 0.0]).as_matrix()
                omega = omega_body_from_euler_rates(np.array([phi, theta, 0.0]),
                                                    np.array([math.radians(rng.uniform(-50, 70)), 0.0, 0.0]))
                omega[2] = 12.0
                app.lectern.rounds.answer(f"b{k}", AnswerState("Heavy top", R, omega, (1.0, 1.0, 0.5), 6.0).to_dict())
            presenter.play()
            gallery = presenter.ask_panel.gallery
            _wait(lambda: len(gallery.entries) == n)
            start = time.perf_counter()
            for _ in range(20):
                gallery.draw()
            draw_ms = (time.perf_counter() - start) / 20 * 1e3
            fps: dict[str, list[float]] = {"without": [], "with": []}
            for _ in range(REPEATS):
                for mode in ("without", "with"):
                    gallery.hide() if mode == "without" else gallery.show_all()
                    time.sleep(1.0)
                    fps[mode].append(float(page.evaluate(FPS_JS)))
            browser.close()
    finally:
        app.stop()
    return {"answers": n, "draw_ms": round(draw_ms, 2), "fps_without": fps["without"], "fps_with": fps["with"],
            "median_without": statistics.median(fps["without"]), "median_with": statistics.median(fps["with"])}


if __name__ == "__main__":
    print(json.dumps(main(int(sys.argv[1]) if len(sys.argv) > 1 else 40)))
