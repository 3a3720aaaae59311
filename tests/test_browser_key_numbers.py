"""The room reads the simulation, not the presenter's widgets (issue 34, row 2), in Debian's
Chromium, through the pages: the presenter presents, picks Heavy top, preset Loop, presses Play
and opens the Energy tab (where its own sliders are not kept current); the follower's key
numbers, read from its page, keep moving with t, and once the presenter pauses they are the
state's (Euler angles of R_space_body, in degrees, as the φ slider would show them).

A picture for people: $RBL_TEST_SHOTS/key_numbers/follower_panel.png, the follower's panel while
the presenter plays on the Energy tab.  Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import DESK, keep_picture
from test_browser import choose
from test_browser_lecture import close_toasts, hall_app, open_page, present_and_follow

from app.kit.core.common import wrap_deg
from app.kit.rigid.view import ANGLE_SPECS
from app.main import App
from physics.euler import euler_zxz_from_matrix

pytestmark = pytest.mark.browser
__all__ = ["hall_app"]  # the fixture, imported for pytest

PHI_LINE = re.compile(r"φ \[deg\] = (-?[0-9.]+)")
T_LINE = re.compile(r"t = ([0-9.]+) s")


def _status_block(page):  # type: ignore[no-untyped-def]
    """The paragraph of the follower's status with the key numbers (its Markdown's lines)."""
    return page.locator("p", has_text=PHI_LINE).filter(has_text=T_LINE).first


def _status(page, follower) -> str:  # type: ignore[no-untyped-def]
    """The follower's status as its page shows it ("" while it has no key numbers)."""
    block = _status_block(page)
    return str(block.inner_text(timeout=10_000)) if block.count() else ""


def _reading(page, follower) -> tuple[float, float] | None:  # type: ignore[no-untyped-def]
    """(t [s], φ [deg]) read from the follower's page, or None if either line is missing."""
    text = _status(page, follower)
    t, phi = T_LINE.search(text), PHI_LINE.search(text)
    return (float(t.group(1)), float(phi.group(1))) if t and phi else None


def test_followers_key_numbers_move_while_the_presenter_shows_the_energy_tab(  # type: ignore[no-untyped-def]
        browser, hall_app: App, wait_until) -> None:
    app = hall_app
    presenter_page, presenter = open_page(browser, app, **DESK)
    presenter_page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    close_toasts(presenter_page)
    follower_page, follower = present_and_follow(browser, app, presenter_page, presenter, wait_until)

    choose(presenter_page, presenter.gui_scene, "Heavy top")
    wait_until(lambda: presenter.room.scene.title == "Heavy top", timeout=30.0)
    presenter_page.get_by_role("button", name="Loop", exact=True).click()
    wait_until(lambda: presenter.room.sim.preset == "Loop", timeout=15.0)
    presenter_page.get_by_role("button", name="Play", exact=True).click()
    presenter_page.get_by_role("button", name="Energy", exact=True).click()
    wait_until(lambda: presenter.scene.tabs.shown == "Energy" and presenter.room.playing, timeout=15.0)
    follower_page.get_by_text("preset Loop").first.wait_for(timeout=30_000)
    # The tab's callback sets `shown` and then refreshes the whole panel, sliders too, under the
    # room's lock: read the slider once that callback has ended.
    with presenter.room.lock:
        phi_widget = float(presenter.scene.gui_angles[0].value)

    # Playing on the Energy tab: the follower's φ moves as its t does.
    readings: list[tuple[float, float]] = []

    def moved() -> bool:
        reading = _reading(follower_page, follower)
        if reading is not None and (not readings or reading[0] > readings[-1][0]):
            readings.append(reading)
        return len({phi for _, phi in readings}) >= 3

    try:
        wait_until(moved, timeout=60.0)
    except AssertionError:
        raise AssertionError(f"waited 60 s for the follower's φ to take 3 values as t runs on; its page read "
                             f"(t, φ): {readings}, presenter at t = {presenter.room.sim.t:.1f} s") from None
    finally:
        keep_picture(_status_block(follower_page).locator("xpath=.."), "key_numbers/follower_panel.png",
                     timeout=60_000)
    assert len({t for t, _ in readings}) == len(readings), readings
    assert float(presenter.scene.gui_angles[0].value) == phi_widget  # the presenter's φ slider stood still meanwhile

    # Paused (still on the Energy tab): the follower reads the state's φ.
    presenter_page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not presenter.room.playing, timeout=15.0)
    with presenter.room.lock:
        R = presenter.room.sim.state.R_space_body.copy()
        t_paused = presenter.room.sim.t
    phi_state = ANGLE_SPECS[0].rounded(wrap_deg(math.degrees(float(np.asarray(euler_zxz_from_matrix(R))[0]))))
    # A reading of the same rounded t may still be one made a few ms before the pause (φ runs at
    # ~60°/s in Loop): wait for the page to show the paused state's t and φ.
    def paused_state_shown() -> bool:
        shown = _reading(follower_page, follower)
        return shown is not None and shown[0] == round(t_paused, 1) \
            and abs((shown[1] - phi_state + 180.0) % 360.0 - 180.0) <= ANGLE_SPECS[0].step

    try:
        wait_until(paused_state_shown, timeout=30.0)
    except AssertionError:
        raise AssertionError(f"waited 30 s for the follower's page to show the paused state (t, φ) = "
                             f"({t_paused:.1f}, {phi_state}); it read {_reading(follower_page, follower)}") from None
    assert presenter.error_count == 0 and follower.error_count == 0, (presenter.last_error, follower.last_error)
