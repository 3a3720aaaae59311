"""The room reads the lecture, in Debian's Chromium, through the pages: a presenter on a 1024x768
projector, a laptop follower and a phone follower (390x844, touch).

The presenter ticks `Projector`, starts the §6 lesson and goes to its third step ("Watch ω_y′
change sign in the Plots tab") with the → key.  Then:

- every page shows the step's words in the caption band (read back from the DOM), on the
  projector at PROJECTOR_CAPTION_PX (>= 1/30 of a 768 px screen; app.lecture.caption says why),
  and the band covers none of the body's projected points (each browser's own camera);
- the laptop follower sees the presenter's Plots tab, read only, and its chart moves while the
  presenter plays (two screenshots of it differ); it unticks its own `Caption`: its band goes,
  the presenter's stays (its page then closes: SwiftShader renders one page fewer);
- the presenter unticks `Caption` in its Lesson folder: the band goes from every screen.
"""

from __future__ import annotations

import re
import time

import numpy as np
import pytest
from conftest import DESK, keep_picture
from test_browser_lecture import _CONTEXTS, CODE, close_toasts, hall_app, open_page, project

from app.lecture.caption import CAPTION_CLASS, PROJECTOR_CAPTION_PX
from app.main import App

pytestmark = pytest.mark.browser
__all__ = ["hall_app"]  # the fixture, imported for pytest

LESSON = "§6 The free body and the heavy top"
BAND = f".{CAPTION_CLASS}"
CAPTION_JS = f"""() => {{ const c = document.querySelector('{BAND}');
  if (!c) return null;
  const r = c.getBoundingClientRect(); if (r.width === 0 || r.height === 0) return null;
  return {{left: r.left, top: r.top, right: r.right, bottom: r.bottom, text: c.innerText,
          size: parseFloat(getComputedStyle(c).fontSize)}}; }}"""


def _words(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def _caption(page):  # type: ignore[no-untyped-def]
    return page.evaluate(CAPTION_JS)


def _body_points(sim) -> list[np.ndarray]:  # type: ignore[no-untyped-def]
    """The body's centre and points 0.2 along its axes either way (inside the book) [scene units]
    (read while it spins: the band is far from all of them, a few frames' turn changes nothing)."""
    R = np.asarray(sim.state.R_space_body)
    return [np.zeros(3)] + [sign * 0.2 * R[:, k] for k in range(3) for sign in (-1.0, 1.0)]


def _assert_clear_of_body(page, camera, sim, where: str) -> None:  # type: ignore[no-untyped-def]
    band = _caption(page)
    assert band is not None, f"{where}: no caption"
    canvas = page.locator("canvas[data-engine]").first.bounding_box()  # three.js's, not a chart's
    assert canvas is not None
    for point in _body_points(sim):
        x, y = project(camera, point, canvas["width"], canvas["height"])
        x, y = x + canvas["x"], y + canvas["y"]
        assert 0 < x < canvas["x"] + canvas["width"] and 0 < y < canvas["y"] + canvas["height"], \
            f"{where}: the body is off the screen at ({x:.0f}, {y:.0f})"
        inside = band["left"] <= x <= band["right"] and band["top"] <= y <= band["bottom"]
        assert not inside, f"{where}: the caption {band} covers the body at ({x:.0f}, {y:.0f})"


def test_the_room_reads_the_lesson_and_the_presenters_plot(browser, hall_app: App, wait_until) -> None:
    app = hall_app
    presenter_page, presenter = open_page(browser, app, 120.0, viewport={"width": 1024, "height": 768})
    close_toasts(presenter_page)
    presenter_page.locator(f'[id="{presenter.gui_projector._impl.uuid}"]').click()
    wait_until(lambda: presenter.projector, timeout=10.0)
    presenter.present(CODE)

    # The presenter runs the lesson to its third step: → twice in its page.
    presenter.start_lesson(LESSON)
    presenter_page.mouse.click(200, 400)  # the 3D view has the keys
    for k in (1, 2):
        presenter_page.keyboard.press("ArrowRight")
        wait_until(lambda k=k: presenter.lesson_step == k, timeout=10.0)
        with presenter.lock:  # the step's callback has finished (its scene, tab, play)
            pass
    step = presenter.lesson.steps[2]
    assert presenter.scene.tabs.shown == "Plots" and presenter.room.playing

    def reads_the_step(page, where: str) -> None:  # type: ignore[no-untyped-def]
        close_toasts(page)
        wait_until(lambda: _words(step.text) in _words((_caption(page) or {}).get("text", "")), timeout=20.0)
        assert "step 3 of 7" in _caption(page)["text"], where

    reads_the_step(presenter_page, "projector")
    assert _caption(presenter_page)["size"] >= PROJECTOR_CAPTION_PX
    _assert_clear_of_body(presenter_page, presenter.client.camera, presenter.room.sim, "projector")

    # A laptop follower: the caption, clear of the body; the presenter's Plots tab, moving with it.
    laptop, follower = open_page(browser, app, 120.0, **DESK)
    wait_until(lambda: follower.mode == "following", timeout=15.0)
    reads_the_step(laptop, "laptop")
    time.sleep(1.0)  # the presenter's camera has reached it
    _assert_clear_of_body(laptop, follower.client.camera, presenter.room.sim, "laptop")
    keep_picture(laptop, "caption_laptop.png", timeout=120_000)
    laptop.get_by_text("The presenter's Plots tab (read only)").first.wait_for(timeout=15_000)
    chart = laptop.get_by_text("ω, body components [rad/s]").first.locator("xpath=ancestor::div[.//canvas][1]")
    chart.scroll_into_view_if_needed()
    first = chart.screenshot(timeout=60_000)
    wait_until(lambda: chart.screenshot(timeout=60_000) != first, timeout=20.0)
    # ... its copied Accuracy lines fit the panel, as in the presenter's own (none runs past the edge).
    laptop.get_by_text("attitude [rad]").first.wait_for(timeout=15_000)
    for who, shown in (("presenter", presenter_page), ("laptop", laptop)):
        assert _cut_lines(shown) == [], (who, _cut_lines(shown))
        keep_picture(shown.locator("pre", has_text="attitude [rad]").first, f"caption_{who}_accuracy.png",
                     timeout=120_000)
    # ... which hides the caption on its own screen only.
    laptop.locator(f'[id="{follower.scene.gui_caption._impl.uuid}"]').click()
    wait_until(lambda: _caption(laptop) is None, timeout=10.0)
    assert _caption(presenter_page) is not None
    _CONTEXTS.pop().close()  # one page fewer for SwiftShader
    wait_until(lambda: follower.closed and len(app.sessions) == 1, timeout=15.0)

    # A phone follower: the caption along the top, clear of the body.
    phone, pocket = open_page(browser, app, 120.0, viewport={"width": 390, "height": 844}, is_mobile=True,
                              has_touch=True, device_scale_factor=2)
    wait_until(lambda: pocket.mode == "following" and pocket.scene.narrow, timeout=15.0)
    reads_the_step(phone, "phone")
    time.sleep(1.0)
    _assert_clear_of_body(phone, pocket.client.camera, presenter.room.sim, "phone")
    keep_picture(phone, "caption_phone.png", timeout=120_000)

    # The presenter unticks Caption (its Lesson folder): gone from every screen.
    presenter_page.get_by_text("Lesson", exact=True).first.click()
    presenter_page.locator(f'[id="{presenter.lesson_runner.gui_caption._impl.uuid}"]').click()
    wait_until(lambda: _caption(phone) is None and _caption(presenter_page) is None, timeout=10.0)
    assert presenter.error_count == 0 and follower.error_count == 0, (presenter.last_error, follower.last_error)


def _cut_lines(page) -> list[str]:  # type: ignore[no-untyped-def]
    """The first line of each monospace block on `page` wider than its box (cut at the right edge), with
    its width and the box's."""
    return page.evaluate("""() => [...document.querySelectorAll('pre')]
        .filter(pre => pre.offsetParent !== null && pre.scrollWidth > pre.clientWidth + 1)
        .map(pre => `${pre.innerText.split('\\n')[0]} (${pre.scrollWidth} px in ${pre.clientWidth})`)""")
