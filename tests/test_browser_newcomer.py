"""A visitor after the lecture (issue 34 row 9), in Debian's Chromium, through the pages: the
presenter plays Heavy top, presents and closes its tab; a new browser that opens the URL then
lands in its own room (the Scene dropdown on its own scene, no "Following the presenter"), with a
line saying the lecture has ended, and `Open the last lecture's room` shows the room the presenter
left at its time t.

Pictures for people: $RBL_TEST_SHOTS/newcomer/ (newcomer_landing.png, newcomer_last_room.png).
"""

from __future__ import annotations

import time

import pytest
from conftest import DESK, TEST_SHOTS, keep_picture
from test_browser_lecture import close_toasts, hall_app, play_and_present  # noqa: F401 - hall_app: a fixture
from test_browser_lecture import open_page as lecture_open_page
from test_browser_typing import number_box

from app.lecture.follower import Hall
from app.main import App
from app.scenes import DEFAULT_SCENE

pytestmark = pytest.mark.browser

LAPTOP = DESK


def open_page(browser, hall: App, **context):  # type: ignore[no-untyped-def]
    """test_browser_lecture's `open_page` with a generous timeout (90 s) for a busy machine."""
    return lecture_open_page(browser, hall, 90.0, **context)


def waited(wait_until, what: str, predicate, seen, timeout: float) -> None:  # type: ignore[no-untyped-def]
    """`wait_until(predicate, timeout)`, failing with what it waited for and what it saw (`seen()`)."""
    try:
        wait_until(predicate, timeout=timeout)
    except AssertionError:
        raise AssertionError(f"waited {timeout:g} s for {what}; saw {seen()!r}") from None


def shot(page, name: str) -> None:  # type: ignore[no-untyped-def]
    """The page as `name` under $RBL_TEST_SHOTS/newcomer (if set)."""
    if TEST_SHOTS:
        close_toasts(page)
        time.sleep(1.0)  # the nodes fade in (a picture for people, not a wait for a state)
        keep_picture(page, f"newcomer/{name}", timeout=120_000)


def test_a_visitor_after_the_lecture_lands_in_its_own_room_and_opens_the_last_one(browser, hall_app: App,  # noqa: F811
                                                                                  wait_until) -> None:
    hall = hall_app
    presenter_page, presenter = open_page(browser, hall, **LAPTOP)
    play_and_present(presenter_page, presenter, "Heavy top")
    waited(wait_until, "the presenter's t > 1 s", lambda: presenter.room.sim.t > 1.0,
           lambda: (presenter.room.sim.t, presenter.room.playing), 120.0)
    presenter_page.close()  # the presenter closes its tab
    waited(wait_until, "the hall to say the presenter left and its room to stand still",  # the hall says it first
           lambda: hall.lectern.hall is Hall.LEFT and hall.lectern.live_room is not None
           and not hall.lectern.live_room.playing,
           lambda: (hall.lectern.hall, hall.lectern.live_room and hall.lectern.live_room.playing), 60.0)
    last = hall.lectern.live_room
    assert last is not None
    t_last = last.sim.t

    page, newcomer = open_page(browser, hall, **LAPTOP)
    landing = page.get_by_text("The lecture has ended").or_(page.get_by_text("The presenter has left")).first
    landing.wait_for(state="visible", timeout=90_000)
    shot(page, "newcomer_landing.png")
    # Its own room: the Scene dropdown on its own scene, not the frozen last state.
    page.get_by_text("The lecture has ended").first.wait_for(state="visible", timeout=30_000)
    assert not page.get_by_text("Following the presenter").first.is_visible(), "it follows the last state"
    dropdown = page.locator(f'[id="{newcomer.gui_scene._impl.uuid}"]')
    dropdown.wait_for(state="visible", timeout=30_000)
    assert dropdown.input_value() == DEFAULT_SCENE, dropdown.input_value()
    assert "has left" in page.get_by_text("The lecture has ended").first.locator("xpath=..").inner_text()
    # One click: the room the presenter left, at its time.
    page.get_by_role("button", name="Open the last lecture's room").click()
    waited(wait_until, "the page's Scene dropdown on Heavy top", lambda: dropdown.input_value() == "Heavy top",
           lambda: (dropdown.input_value(), newcomer.room.scene.title, newcomer.last_error), 60.0)
    waited(wait_until, "the session's room on Heavy top", lambda: newcomer.room.scene.title == "Heavy top",
           lambda: newcomer.room.scene.title, 30.0)
    box = number_box(page, newcomer.scene.timeline.gui_slider)
    waited(wait_until, f"the page's Timeline at the last room's t = {t_last:.3f} s",
           lambda: abs(float(box.input_value()) - t_last) < 0.02, box.input_value, 60.0)
    assert newcomer.mode == "own" and newcomer.room is not last and newcomer.room.sim.t == t_last
    assert newcomer.error_count == 0, newcomer.last_error
    shot(page, "newcomer_last_room.png")
