"""Screenshots of the lecture app's scenes in headless Chromium, for the docs.

    python3 scripts/screenshot.py                       # all three into docs/img/
    python3 scripts/screenshot.py --scenes top --outdir /tmp/shots --size 1920x1080

Shots (each from the running app, through a real browser):
    scene_euler.png  Euler angles at (30°, 50°, 20°), ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′ drawn, D read out.
    scene_free.png   the Dzhanibekov preset playing, caught mid-flip, with the Plots tab open.
    scene_inertia.png  the L-shape: its tensor, principal frame and momental ellipsoid.
    scene_top.png    the heavy top's "Loop" preset after a few seconds, with its tip trace.
    projector_1024.png  the same in the projector layout at 1024×768.
    scene_poinsot.png  Poinsot's ellipsoid on the invariable plane (Dzhanibekov preset, mid-run),
                     the polhode, the herpolhode, and the body's L-space picture beside it.
    scene_moving.png   the moving frame's "Turntable" preset after a few seconds: paths in C and C′,
                       the real and inertial forces on the free particle (`--scenes moving`).
    scene_constrained.png  the bead on a fast-turning hoop (memo §2, §5): virtual displacement,
                       applied and constraint force (`--scenes constrained`).
    phone_follower.png a phone (390×844, touch) following a presenter who plays the heavy top's
                       "Loop": one status line, the body in view (`--scenes phone`).
    scene_<title>.png  any other scene of the registry by its title (`--scenes "Heavy top"`): its
                       first preset played for a few seconds (a new scene needs no edit here).

Starts the app on a loopback ephemeral port, opens it in Debian's Chromium through Playwright
(software WebGL via SwiftShader, the flags of docs/VISER.md), drives that browser's session
from the server side (scene, preset, play), waits for the scene to settle and writes the PNGs.
Needs `apt-get install chromium` and `pip install playwright` (no `playwright install` step).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app.main import create_server  # noqa: E402
from app.scenes import SCENES as REGISTRY  # noqa: E402
from scripts.chromium import CHROMIUM, CHROMIUM_ARGS  # noqa: E402

SCENES = ("euler", "inertia", "free", "top", "poinsot", "moving", "constrained", "projector", "phone")
PLAYED = {  # shot: (scene, preset, a heading that shows it is drawn, simulated time [s] of the shot)
    "top": ("Heavy top", "Loop", "Heavy symmetric top", 5.5),
    "poinsot": ("Poinsot", "Dzhanibekov", "Poinsot: the ellipsoid rolls", 5.0),
    "moving": ("Moving frame", "Turntable", "Moving frame C′", 2.6),
    "constrained": ("Constrained particles", "Fast hoop", "Constrained particles (memo §2, §5)", 2.5),
}
PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True, "device_scale_factor": 2}
PROJECTOR_SIZE = (1024, 768)  # the "projector" shot: a common projector's resolution


def _wait_for(predicate: Callable[[], Any], timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise TimeoutError("the scene did not reach the state for the screenshot")
        time.sleep(0.01)


def _slow_motion(session: Any) -> None:
    """Time scale 0.1x (through the session's guard: the app's loop draws meanwhile), so that the
    software renderer's frame matches the labels."""
    session.guard("time scale", lambda: session.room.set_time_scale(0.1))()


def _close_toasts(page: Any) -> None:
    toasts = page.locator(".mantine-Notification-closeButton")  # "software WebGL" notice
    for i in range(toasts.count()):
        toasts.nth(i).click(force=True)


def _prepare(page: Any, session: Any, scene: str) -> None:
    """Bring `session` (the page's) to the state of the shot; returns when it is time to shoot."""
    if scene == "euler":
        session.scene.set_angles_deg(30.0, 50.0, 20.0)
        page.get_by_role("button", name="ω", exact=True).click()  # the readout tab ω
        time.sleep(1.5)
        return
    if scene == "free":
        session.select_scene("Free body")
        session.apply_preset("Dzhanibekov")
        page.get_by_text("Free body (no torque)").wait_for(timeout=30_000)
        page.get_by_role("button", name="Plots").click()
        time.sleep(1.5)
        session.play()
        # Mid-flip: ω_y′ (the intermediate axis) on its way through zero for the first time;
        # then slow motion (0.1x), so that the software renderer's frame matches the labels.
        _wait_for(lambda: session.simulation.state.omega_body[1] < 2.5, 30.0)
        _slow_motion(session)
        time.sleep(2.0)
        return
    if scene == "projector":  # the heavy top's shot, in the projector layout
        session.guard("projector", session.set_projector)(True)
        scene = "top"
    if scene == "inertia":
        session.select_scene("Inertia")
        session.apply_preset("L-shape")
        page.get_by_text("Inertia tensor (memo §3)").wait_for(timeout=30_000)
        session.guard("screenshot", session.scene._set_about)((1.0, 0.25, 0.5))  # O off c: the parallel-axis term
        page.get_by_text("Principal moments I1").scroll_into_view_if_needed()  # the readout on screen
        time.sleep(2.0)
        return
    if scene in PLAYED:  # a preset played for a few seconds, then slow motion for the shot
        title, preset, heading, t_shot = PLAYED[scene]
        session.select_scene(title)
        session.apply_preset(preset)
        page.get_by_text(heading).first.wait_for(timeout=30_000)
        time.sleep(1.0)
        session.play()
        _wait_for(lambda: session.simulation.t > t_shot, 60.0)
        _slow_motion(session)
        time.sleep(2.0)
        return
    if scene in REGISTRY:  # any scene by its title: its first preset, played a few seconds
        session.select_scene(scene)
        session.apply_preset(REGISTRY[scene].presets()[0].name)
        _wait_for(lambda: getattr(session.scene, "title", None) == scene, 30.0)
        time.sleep(1.0)
        session.play()
        _wait_for(lambda: session.simulation.t > 3.0 or not session.room.playing, 60.0)
        _slow_motion(session)
        time.sleep(2.0)
        return
    raise ValueError(f"unknown scene {scene!r}; choose from {', '.join((*SCENES, *REGISTRY))}")


def _phone_shot(browser: Any, app: Any, out: Path) -> Path:
    """A presenter (1280×800) plays the heavy top's Loop; a phone follows: its screenshot."""
    presenter_page = browser.new_page(viewport={"width": 1280, "height": 800})
    presenter_page.goto(f"http://127.0.0.1:{app.port}")
    presenter = next(iter(app.wait_for_sessions(1, timeout=30.0).values()))
    presenter.select_scene("Heavy top")
    presenter.apply_preset("Loop")
    presenter.present(app.lectern.code)
    presenter.play()
    context = browser.new_context(**PHONE)
    phone = context.new_page()
    phone.goto(f"http://127.0.0.1:{app.port}")
    app.wait_for_sessions(2, timeout=30.0)
    phone.get_by_role("button", name="Details").wait_for(timeout=30_000)
    time.sleep(2.0)
    _close_toasts(phone)
    _wait_for(lambda: presenter.simulation.t > 6.0, 60.0)
    out.parent.mkdir(parents=True, exist_ok=True)
    phone.screenshot(path=str(out))
    context.close()
    presenter_page.close()
    app.wait_for_sessions(0, timeout=10.0)
    return out


def take_screenshots(
    outdir: Path,
    scenes: tuple[str, ...] = SCENES,
    width: int = 1280,
    height: int = 800,
    chromium: str = CHROMIUM,
) -> list[Path]:
    """Start the app, shoot one PNG per scene into `outdir`, stop the app; the paths."""
    from playwright.sync_api import sync_playwright

    app = create_server("127.0.0.1", 0, verbose=False, presenter_code="000000")
    written = []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, headless=True, args=CHROMIUM_ARGS)
            try:
                for scene in scenes:
                    if scene == "phone":
                        written.append(_phone_shot(browser, app, outdir / "phone_follower.png"))
                        continue
                    size = PROJECTOR_SIZE if scene == "projector" else (width, height)
                    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
                    page.goto(f"http://127.0.0.1:{app.port}")
                    session = next(iter(app.wait_for_sessions(1, timeout=30.0).values()))
                    page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
                    time.sleep(1.0)
                    _close_toasts(page)
                    _prepare(page, session, scene)
                    _close_toasts(page)
                    name = scene.lower().replace(" ", "_")
                    out = outdir / ("projector_1024.png" if scene == "projector" else f"scene_{name}.png")
                    out.parent.mkdir(parents=True, exist_ok=True)
                    page.screenshot(path=str(out))
                    written.append(out)
                    page.close()
                    app.wait_for_sessions(0, timeout=10.0)
            finally:
                browser.close()
    finally:
        app.stop()
    return written


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--outdir", type=Path, default=ROOT / "docs" / "img")
    parser.add_argument("--scenes", nargs="*", default=list(SCENES), choices=(*SCENES, *REGISTRY))
    parser.add_argument("--size", default="1280x800", help="viewport WIDTHxHEIGHT [px]")
    parser.add_argument("--chromium", default=CHROMIUM)
    args = parser.parse_args(argv)
    width, height = (int(n) for n in args.size.lower().split("x"))
    for path in take_screenshots(args.outdir, tuple(args.scenes), width, height, args.chromium):
        print(path)


if __name__ == "__main__":
    main()
