"""Screenshot of the Euler-angle explorer in headless Chromium, for the docs.

    python3 scripts/screenshot.py [--out docs/img/explorer.png] [--angles 30 50 20]
                                  [--size 1280x800] [--chromium /usr/lib/chromium/chromium]

Starts the app on a loopback ephemeral port, opens it in Debian's Chromium through Playwright
(software WebGL via SwiftShader, the flags of shared/VISER.md), sets the angles server-side on
that browser's session, waits for the scene to settle and writes the PNG.  Needs
`apt-get install chromium` and `pip install playwright` (no `playwright install` step).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app.main import create_server  # noqa: E402

CHROMIUM = "/usr/lib/chromium/chromium"
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--run-all-compositor-stages-before-draw",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def take_screenshot(
    out: Path,
    angles_deg: tuple[float, float, float] | None,
    width: int = 1280,
    height: int = 800,
    chromium: str = CHROMIUM,
    expand: tuple[str, ...] = (),
) -> Path:
    """Start the app, shoot one PNG of it into `out`, stop the app; returns `out`."""
    from playwright.sync_api import sync_playwright

    app = create_server("127.0.0.1", 0, verbose=False)
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, headless=True, args=CHROMIUM_ARGS)
            try:
                page = browser.new_page(viewport={"width": width, "height": height})
                page.goto(f"http://127.0.0.1:{app.port}")
                session = next(iter(app.wait_for_sessions(1, timeout=30.0).values()))
                page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
                if angles_deg is not None:
                    session.scene.set_angles_deg(*angles_deg)
                for label in expand:
                    page.get_by_text(label, exact=True).first.click()
                time.sleep(2.0)  # objects fade in (VISER.md pitfall 6)
                toasts = page.locator(".mantine-Notification-closeButton")
                for i in range(toasts.count()):
                    toasts.nth(i).click(force=True)
                time.sleep(1.0)
                out.parent.mkdir(parents=True, exist_ok=True)
                page.screenshot(path=str(out))
            finally:
                browser.close()
    finally:
        app.stop()
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img" / "explorer.png")
    parser.add_argument("--angles", type=float, nargs=3, metavar=("PHI", "THETA", "PSI"),
                        default=(30.0, 50.0, 20.0), help="z-x-z angles [deg] set before the shot")
    parser.add_argument("--size", default="1280x800", help="viewport WIDTHxHEIGHT [px]")
    parser.add_argument("--chromium", default=CHROMIUM)
    parser.add_argument("--expand", nargs="*", default=[], help="GUI folder titles to click open")
    args = parser.parse_args(argv)
    width, height = (int(n) for n in args.size.lower().split("x"))
    path = take_screenshot(args.out, tuple(args.angles), width, height, args.chromium, tuple(args.expand))
    print(path)


if __name__ == "__main__":
    main()
