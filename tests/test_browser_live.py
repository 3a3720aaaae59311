"""The room is live, on the lecturer's screen and on the explorers': one lecture in Debian's
Chromium, through the pages (clicks, taps, typing), a presenter on a 1024×768 projector, a phone
follower (390×844, touch) and a desk follower (800×600).

1. The presenter plays the heavy top, presents and ticks `Projector`: `Stop presenting`,
   `Pointer` and the badge ("● Live · 0 following · 0 exploring") stay in view in the docked
   panel, and the badge counts the browsers as they join and explore.
2. The phone follows, opens `Details` and explores: it keeps the phone layout (the camera it
   had, one line, `Details`): the body's projected points are body pixels, no panel over them;
   "Lecture on" and `Follow presenter` sit at the top of its panel.
3. The laptop follows and explores: "Lecture on" tops its panel, and it types a time SCRUB_BACK_S (4 s) back
   into the `Timeline [s]`: its copy carries the replay history.
4. `Call everyone back`: the phone presses `Stay` and keeps exploring; the laptop, which does
   not, follows again when the countdown ends (the lectern's clock is moved on by the test).

A page that does not act is frozen meanwhile (`frozen`), so that two cores render at most two
pages.  Pictures for people: $RBL_TEST_SHOTS/live/ (live_badge.png, phone_explorer.png).
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import DESK, TEST_SHOTS, keep_picture
from PIL import Image
from test_browser_lecture import close_toasts, hall_app, play_and_present, project  # noqa: F401 - hall_app: a fixture
from test_browser_lecture import open_page as lecture_open_page
from test_browser_typing import number_box

import app.lecture.lectern
from app.main import App

pytestmark = pytest.mark.browser

PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True, "device_scale_factor": 2}
SCRUB_BACK_S = 4.0  # [s] the laptop types a time this far back (a property: any time in the history scrubs there)


def open_page(browser, hall: App, **context):  # type: ignore[no-untyped-def]
    """test_browser_lecture's `open_page` with generous timeouts (90 s): a third page loads while
    two others render their WebGL on the same two cores; (page, session)."""
    return lecture_open_page(browser, hall, 90.0, **context)


@contextlib.contextmanager
def frozen(page):  # type: ignore[no-untyped-def]
    """The page frozen (no script, no rendering) inside the block: the two cores render the pages
    that act.  Its websocket messages wait and are handled when it thaws."""
    cdp = page.context.new_cdp_session(page)
    cdp.send("Page.setWebLifecycleState", {"state": "frozen"})
    try:
        yield page
    finally:
        cdp.send("Page.setWebLifecycleState", {"state": "active"})
        cdp.detach()


def badge(page, following: int, exploring: int):  # type: ignore[no-untyped-def]
    """The presenter's badge saying these counts (waits for it)."""
    locator = page.get_by_text(f"{following} following · {exploring} exploring").first
    locator.wait_for(state="visible", timeout=20_000)
    return locator


def inside(page, locator, width: float, height: float) -> bool:  # type: ignore[no-untyped-def]
    box = locator.bounding_box()
    return box is not None and 0 <= box["x"] and box["x"] + box["width"] <= width and 0 <= box["y"] \
        and box["y"] + box["height"] <= height


def test_the_room_is_live_and_explorers_keep_their_way_back(browser, hall_app: App, wait_until,  # noqa: F811
                                                            monkeypatch, tmp_path) -> None:
    hall = hall_app
    presenter_page, presenter = open_page(browser, hall, viewport={"width": 1024, "height": 768})
    play_and_present(presenter_page, presenter, "Heavy top")

    # 1. The projector layout keeps the lecture's controls and the badge in view.
    presenter_page.get_by_text("Projector", exact=True).first.click()
    wait_until(lambda: presenter.projector, timeout=10.0)
    live = badge(presenter_page, 0, 0)
    stop = presenter_page.get_by_role("button", name="Stop presenting")
    pointer = presenter_page.get_by_text("Pointer", exact=True).first
    for locator in (live, stop, pointer):  # polled: the panel slides to its dock
        locator.wait_for(state="visible", timeout=10_000)
        wait_until(lambda locator=locator: inside(presenter_page, locator, 1024, 768), timeout=10.0)

    # 2. The phone follows, then explores on its own: the phone layout stays.
    phone, phone_session = open_page(browser, hall, **PHONE)
    wait_until(lambda: phone_session.mode == "following" and phone_session.scene.narrow, timeout=30.0)
    badge(presenter_page, 1, 0)
    wait_until(lambda: presenter.room.sim.t > SCRUB_BACK_S + 1.0, timeout=60.0)  # a history to look back on
    presenter_page.get_by_role("button", name="Pause", exact=True).click()  # still bodies: projected = drawn
    wait_until(lambda: not presenter.room.playing, timeout=10.0)
    close_toasts(phone)
    phone.get_by_role("button", name="Details").tap()
    phone.get_by_role("button", name="Explore on my own").tap()
    wait_until(lambda: phone_session.mode == "own", timeout=15.0)
    badge(presenter_page, 0, 1)
    follow_back = phone.get_by_role("button", name="Follow presenter")
    lecture_on = phone.get_by_text("Lecture on").first
    details = phone.get_by_role("button", name="Details")
    for locator in (follow_back, lecture_on, details):
        locator.wait_for(state="visible", timeout=30_000)
    assert not phone.get_by_role("button", name="Play", exact=True).is_visible(), "the panel is not folded"
    close_toasts(phone)
    path = tmp_path / "phone_explorer.png"
    with frozen(presenter_page):  # one page renders the screenshot, not two
        time.sleep(1.0)  # the copy's nodes fade in
        phone.screenshot(path=str(path), timeout=120_000)
    pixels = np.asarray(Image.open(path).convert("RGB"), dtype=int)
    scale = pixels.shape[1] / 390.0
    panel_top = min(box["y"] for box in (lecture_on.bounding_box(), follow_back.bounding_box(),
                                         details.bounding_box()) if box is not None)
    camera, sim = phone_session.client.camera, phone_session.room.sim
    disc = 0.8 * np.asarray(sim.state.R_space_body)[:, 2]
    for point in ((0.0, 0.0, 0.0), tuple(disc)):
        px, py = project(camera, point, 390, 844)
        assert 0 < px < 390 and 0 < py < 844, f"the body at {point} is off the phone's screen: ({px:.0f}, {py:.0f})"
        assert py < panel_top - 20, f"the panel (top {panel_top:.0f}) covers the body at y = {py:.0f}"
        patch = pixels[int(py * scale) - 12:int(py * scale) + 12, int(px * scale) - 12:int(px * scale) + 12]
        assert np.mean(np.any(np.abs(patch - 255) > 30, axis=-1)) > 0.3, "no body pixels where the body is"

    # 3. The laptop follows, then explores: "Lecture on" tops its panel; it scrubs 10 s back.
    with frozen(phone):
        laptop_page, laptop = open_page(browser, hall, **DESK)
        wait_until(lambda: laptop.mode == "following", timeout=30.0)
        badge(presenter_page, 1, 1)
        laptop_page.get_by_text("Following the presenter").first.wait_for(timeout=30_000)
        close_toasts(laptop_page)
        laptop_page.get_by_role("button", name="Explore on my own").click()
        wait_until(lambda: laptop.mode == "own", timeout=15.0)
        badge(presenter_page, 0, 2)
        top = laptop_page.get_by_text("Lecture on").first
        top.wait_for(state="visible", timeout=30_000)
        play = laptop_page.get_by_role("button", name="Play", exact=True)
        play.wait_for(state="visible", timeout=30_000)
        assert top.bounding_box()["y"] < play.bounding_box()["y"], "Lecture on is not at the top of the panel"
        room = laptop.room
        t_back = room.live_t - SCRUB_BACK_S
        box = number_box(laptop_page, laptop.scene.timeline.gui_slider)
        box.fill(f"{t_back:.2f}")
        box.press("Enter")
        wait_until(lambda: room.mode == "scrubbing" and abs(room.shown_t - t_back) < 0.02, timeout=15.0)
        assert laptop.error_count == 0, laptop.last_error

    # 4. Call everyone back: the phone stays, the laptop follows again when the countdown ends
    # (the lectern's clock is moved on once the phone's Stay has arrived: no race with a slow tap).
    offset = [0.0]
    monkeypatch.setattr(hall.lectern, "_clock", lambda: time.monotonic() + offset[0])
    presenter_page.get_by_role("button", name="Call everyone back").click()
    stay = phone.get_by_role("button", name="Stay")
    stay.wait_for(state="visible", timeout=30_000)
    laptop_page.get_by_text("calls everyone back").first.wait_for(timeout=30_000)
    assert laptop.mode == "own"
    stay.tap()
    wait_until(lambda: hall.lectern.call_back_left(phone_session) is None, timeout=15.0)
    offset[0] = app.lecture.lectern.CALL_BACK_SECONDS
    wait_until(lambda: laptop.mode == "following", timeout=15.0)
    ticks = hall.tick_count
    wait_until(lambda: hall.tick_count > ticks + 2, timeout=10.0)  # the frame that moved the laptop is over
    assert phone_session.mode == "own" and phone_session.error_count == 0, phone_session.last_error
    stay.wait_for(state="hidden", timeout=30_000)
    badge(presenter_page, 1, 1)
    assert presenter.error_count == 0, presenter.last_error

    if TEST_SHOTS:  # the projector with the badge, and the phone explorer
        close_toasts(presenter_page)
        time.sleep(1.0)
        keep_picture(presenter_page, "live/live_badge.png")
        Image.open(path).save(Path(TEST_SHOTS) / "live" / "phone_explorer.png")
