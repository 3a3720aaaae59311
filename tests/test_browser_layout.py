"""The lecture's layout on the screens people bring, in Debian's Chromium, through the pages:

1. The lecturer's controls stay in sight (issue 34, row 3): a presenter on a 1280×800 laptop, a
   1024×768 projector and a 390×844 phone picks every scene in the Scene dropdown, a preset,
   Play and a long folder, the panel scrolled to its end: `Stop presenting` (and the live
   badge) lie inside the window, the panel does not scroll sideways, and a click on it stops
   the presentation.
2. A phone before class (row 7): with nobody presenting, the phone's panel is folded to one
   line and `Details` from its first frame (no `Play` was ever in the page), covers less than
   35 % of the screen, and the body is in the part it leaves.
3. A phone explorer (row 8): after `Explore on my own`, the heavy top's pivot is in the middle
   of what the bottom sheet leaves, its disc inside it, and the axes' tips (the x, y, z labels,
   their text boxes) are inside it.

Pictures for people: $RBL_TEST_SHOTS/layout/ (none when unset).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import keep_picture, poll_until
from test_browser_lecture import (  # noqa: F401
    CODE,
    button,
    choose,
    close_toasts,
    hall_app,
    open_folder,
    open_page,
    project,
    received,
    text_input,
)

from app.kit.draw.screen import REFERENCE_HEIGHT_PX, SCREEN_EM_PX, text_box
from app.main import App
from app.scenes import SCENES
from app.viser_internals import node_world, scene_nodes

pytestmark = pytest.mark.browser

PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True, "device_scale_factor": 2}
LAPTOP = {"viewport": {"width": 1280, "height": 800}}
PROJECTOR = {"viewport": {"width": 1024, "height": 768}}

PANEL_JS = """() => {
  const at = [...document.querySelectorAll('*')]
    .find(e => e.childElementCount === 0 && e.textContent === 'Rigid-body lab');
  for (let e = at; e; e = e.parentElement) {
    const style = getComputedStyle(e);
    if (style.position === 'fixed' || style.position === 'absolute') {
      const box = e.getBoundingClientRect();
      if (box.width > 100) return {x: box.x, y: box.y, width: box.width, height: box.height};
    }
  }
  return null;
}"""
"""The panel's box on the page [CSS px] (the box floating over the canvas that holds its header, the app's name
in English: `app.roles.language.APP_NAME`)."""

NO_PLAY_YET = """
window.__playSeen = false;
new MutationObserver(() => {
  if (!window.__playSeen && [...document.querySelectorAll('button')].some(b => b.textContent.trim() === 'Play'))
    window.__playSeen = true;
}).observe(document, {childList: true, subtree: true, characterData: true});
"""
"""An init script: `window.__playSeen` turns true if a `Play` button is ever in the page."""


def shot(page, name: str) -> None:  # type: ignore[no-untyped-def]
    keep_picture(page, f"layout/{name}")


def box_inside(box, width: float, height: float) -> bool:  # type: ignore[no-untyped-def]
    return box is not None and box["x"] >= 0 and box["y"] >= 0 and box["x"] + box["width"] <= width \
        and box["y"] + box["height"] <= height


def scroll_panel_to_end(page, at: tuple[float, float]) -> float:  # type: ignore[no-untyped-def]
    """Scroll what is under the point `at` [CSS px] (the panel) as far down as it goes, as a mouse
    wheel there would: each scrollable element from the one under the point up to the page.

    Not `page.mouse.wheel`: Playwright's wheel waits for the renderer to draw a frame, with no
    deadline; a renderer starved by a busy machine held it past the test's 300 s (a CI run).
    How far it scrolled [CSS px]."""
    return page.evaluate("""([x, y]) => {
        let moved = 0;
        for (let e = document.elementFromPoint(x, y); e; e = e.parentElement) {
            const style = getComputedStyle(e).overflowY;
            if (e.scrollHeight > e.clientHeight && (style === 'auto' || style === 'scroll')) {
                const before = e.scrollTop;
                e.scrollTop = e.scrollHeight;
                moved += e.scrollTop - before;
            }
        }
        return moved;
    }""", list(at))


def stop_in_sight(page, session, wait_until, width: float, height: float, where: str):  # type: ignore[no-untyped-def]
    """`Stop presenting` and the live badge inside the window (waited for); the button."""
    stop = page.get_by_role("button", name="Stop presenting")
    badge = page.get_by_text("● Live").first
    seen: list = []

    def in_sight() -> bool:
        seen[:] = [stop.bounding_box(), badge.bounding_box()]
        return all(box_inside(box, width, height) for box in seen)

    try:
        wait_until(in_sight, timeout=20.0)
    except AssertionError:
        raise AssertionError(f"{where}: Stop presenting and the badge not inside the {width:.0f}x{height:.0f} "
                             f"window; their boxes: {seen}") from None
    assert session.mode == "presenting"
    sideways = page.evaluate("() => [...document.querySelectorAll('.mantine-ScrollArea-viewport')]"
                             ".map(v => v.scrollWidth - v.clientWidth)")
    assert max(sideways, default=0) <= 1, f"{where}: the panel scrolls sideways by {sideways} px"
    return stop


def present_through_the_page(page, session, wait_until) -> None:  # type: ignore[no-untyped-def]
    open_folder(page, "Lecture", "Presenter code")
    text_input(page, "Presenter code").click()
    page.keyboard.type(CODE, delay=30)
    received(page, session, "Presenter code", CODE)
    page.get_by_role("button", name="Present").click()
    wait_until(lambda: session.mode == "presenting", timeout=15.0)
    button(page, "Stop presenting").first.wait_for(timeout=30_000)  # the page laid out as the presenter's


def pick_scene(page, session, title: str, wait_until) -> None:  # type: ignore[no-untyped-def]
    choose(page, session.gui_scene, title)
    wait_until(lambda: session.scene.title == title, timeout=20.0)


def open_a_long_folder(page) -> None:  # type: ignore[no-untyped-def]
    """Open the scene's collapsed `Display` folder (or `Solid mesh`), if it has one, and `Lecture`."""
    for label in ("Display", "Solid mesh", "Lecture"):
        header = page.get_by_text(label, exact=True)
        if header.count():
            header.first.click()


@pytest.mark.parametrize("context", [LAPTOP, PROJECTOR], ids=["laptop-1280x800", "projector-1024x768"])
def test_the_lecturers_controls_stay_in_sight_in_every_scene(browser, hall_app: App, wait_until,  # noqa: F811
                                                             context) -> None:
    width, height = context["viewport"]["width"], context["viewport"]["height"]
    page, session = open_page(browser, hall_app, 90.0, **context)
    page.get_by_role("button", name="Play", exact=True).wait_for(timeout=90_000)
    close_toasts(page)
    present_through_the_page(page, session, wait_until)
    for title, scene in SCENES.items():
        pick_scene(page, session, title, wait_until)
        presets = scene.presets()
        if presets:
            page.get_by_role("button", name=presets[-1].name, exact=True).first.click()
        play = page.get_by_role("button", name="Play", exact=True)
        if play.count():
            play.first.click()
        open_a_long_folder(page)
        close_toasts(page)
        assert scroll_panel_to_end(page, (width - 150, height / 2)) > 0, f"{title}: the panel did not scroll"
        stop_in_sight(page, session, wait_until, width, height, f"{title}, {presets[-1].name if presets else ''}")
        if title == "Heavy top":
            shot(page, f"row3_{width}x{height}_heavy_top.png")
    assert session.error_count == 0, session.last_error
    stop_in_sight(page, session, wait_until, width, height, "at the end").click()
    wait_until(lambda: session.mode == "own", timeout=15.0)


def test_a_phone_presenter_keeps_stop_presenting_in_sight(browser, hall_app: App, wait_until) -> None:  # noqa: F811
    page, session = open_page(browser, hall_app, 90.0, **PHONE)
    page.get_by_role("button", name="Details").wait_for(timeout=90_000)
    close_toasts(page)
    page.get_by_role("button", name="Details").tap()
    present_through_the_page(page, session, wait_until)
    pick_scene(page, session, "Heavy top", wait_until)
    page.get_by_role("button", name="Loop", exact=True).first.tap()
    page.get_by_role("button", name="Play", exact=True).first.tap()
    open_a_long_folder(page)
    close_toasts(page)
    scroll_panel_to_end(page, (390 - 100, 844 - 60))
    stop = stop_in_sight(page, session, wait_until, 390, 844, "phone, Heavy top, Loop")
    shot(page, "row3_phone_presenter.png")
    stop.tap()
    wait_until(lambda: session.mode == "own", timeout=15.0)
    assert session.error_count == 0, session.last_error


def test_a_phone_before_class_gets_the_folded_layout_from_its_first_frame(browser, hall_app: App,  # noqa: F811
                                                                           wait_until) -> None:
    context = browser.new_context(**PHONE)
    try:
        context.add_init_script(NO_PLAY_YET)
        before = set(hall_app.sessions)
        page = context.new_page()
        page.goto(f"http://127.0.0.1:{hall_app.port}/?fixedDpr=2", timeout=90_000)
        session = wait_until(lambda: next((s for cid, s in dict(hall_app.sessions).items() if cid not in before),
                                          None), timeout=90.0)
        details = page.get_by_role("button", name="Details")
        details.wait_for(timeout=90_000)
        page.get_by_text("Your scene").first.wait_for(timeout=30_000)
        close_toasts(page)
        shot(page, "row7_phone_first.png")
        assert not page.evaluate("window.__playSeen"), "the phone's page showed the desktop panel (Play) first"
        seen: list = [None]

        def folded() -> bool:  # the panel's fold may still be animating on a busy machine
            seen[0] = page.evaluate(PANEL_JS)
            return seen[0] is not None and seen[0]["width"] * seen[0]["height"] / (390 * 844) < 0.35

        poll_until(folded, 30.0, 0.1, what="the phone's panel to cover under 35 % of the screen",
                   seen=lambda: seen[0])
        panel = seen[0]
        x, y = project(session.client.camera, (0.0, 0.0, 0.0), 390, 844)
        assert 0.2 * 390 < x < 0.8 * 390 and 0.1 * 844 < y < panel["y"] - 40, \
            f"the body projects to ({x:.0f}, {y:.0f}), not in what the panel (top {panel['y']:.0f}) leaves"
        details.tap()
        page.get_by_role("button", name="Play", exact=True).wait_for(timeout=30_000)  # Details unfolds the panel
        assert session.error_count == 0, session.last_error
    finally:
        context.close()


def axis_labels(session, width: int, height: int) -> dict[str, tuple[float, float, float, float]]:  # type: ignore[no-untyped-def]
    """The text boxes [CSS px] of the shown labels "x", "y", "z" of the browser's scene (the world
    axes' tips, own or shared), as its camera draws them in a width x height window."""
    nodes = scene_nodes(session.client.scene)
    poses: dict = {}
    boxes = {}
    for name, handle in nodes.items():
        if type(handle).__name__ != "LabelHandle" or str(handle.text) not in ("x", "y", "z"):
            continue
        _, at, shown = node_world(name, nodes, poses)
        if shown:
            x, y = project(session.client.camera, at, width, height)
            em = SCREEN_EM_PX * float(handle.font_screen_scale) * height / REFERENCE_HEIGHT_PX
            boxes[str(handle.text)] = text_box(str(handle.anchor), x, y, str(handle.text), em)
    return boxes


def test_a_phone_explorer_keeps_the_body_centred_and_the_axes_inside(browser, hall_app: App,  # noqa: F811
                                                                     wait_until) -> None:
    presenter_page, presenter = open_page(browser, hall_app, 90.0, **LAPTOP)
    presenter.select_scene("Heavy top")
    presenter.present(CODE)
    presenter.play()
    phone, session = open_page(browser, hall_app, 90.0, **PHONE)
    wait_until(lambda: session.mode == "following", timeout=30.0)
    wait_until(lambda: presenter.room.sim.t > 2.0, timeout=60.0)
    presenter.pause()
    close_toasts(phone)
    phone.get_by_role("button", name="Details").tap()
    phone.get_by_role("button", name="Explore on my own").tap()
    wait_until(lambda: session.mode == "own", timeout=30.0)
    follow = phone.get_by_role("button", name="Follow presenter")
    follow.wait_for(timeout=30_000)
    close_toasts(phone)
    panel = phone.evaluate(PANEL_JS)
    assert panel is not None
    top = panel["y"]  # the bottom sheet spans the lower part of the screen
    sim = session.room.sim
    tip = 0.8 * np.asarray(sim.state.R_space_body)[:, 2]  # part way up the top's symmetry axis
    pivot = [(0.0, 0.0)]

    def centred() -> bool:  # the camera the server moved at Explore, once the browser reports it
        pivot[0] = project(session.client.camera, (0.0, 0.0, 0.0), 390, 844)
        return abs(pivot[0][0] - 195) < 0.08 * 390

    poll_until(centred, 30.0, 0.1, what="the browser's camera to centre the top's pivot (x within 8 % of 195)",
               seen=lambda: f"pivot at ({pivot[0][0]:.0f}, {pivot[0][1]:.0f}) of 390 x 844")
    (pivot_x, pivot_y), (tip_x, tip_y) = (project(session.client.camera, p, 390, 844)
                                          for p in ((0.0, 0.0, 0.0), tuple(tip)))
    shot(phone, "row8_phone_explorer.png")
    assert abs(pivot_x - 195) < 0.08 * 390, f"the top's pivot is at x = {pivot_x:.0f} of 390: not centred"
    assert 0.25 * top < pivot_y < 0.75 * top, \
        f"the top's pivot is at y = {pivot_y:.0f}, not in the middle of the {top:.0f} px the sheet leaves"
    assert 0 < tip_x < 390 and 0 < tip_y < top, f"the top's disc ({tip_x:.0f}, {tip_y:.0f}) is off the visible part"
    boxes = axis_labels(session, 390, 844)
    assert set(boxes) == {"x", "y", "z"}, f"the axes' labels: {sorted(boxes)}"
    for text, (x0, y0, x1, y1) in boxes.items():
        assert 0 <= x0 and x1 <= 390 and 0 <= y0 and y1 <= top, \
            f"the {text} axis' tip label ({x0:.0f}, {y0:.0f})-({x1:.0f}, {y1:.0f}) leaves the visible part " \
            f"(390 x {top:.0f})"
    assert session.error_count == 0, session.last_error
