"""Share (issue 27, item 2) as people use it, in Debian's Chromium, through the pages only.

A student picks Heavy top, plays and pauses it, opens `Share` and presses `Share`: the folder
shows a code.  A classmate in another browser types the code into `Shared code` and presses
`Open a shared moment`: their page shows Heavy top, paused, and the server's simulation is the
sharer's bit for bit.  A malformed code and an expired one (the store's clock moved past 30
days) are refused with a message that says which, and the classmate's room stays as it was.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import re

import pytest
from conftest import DESK, keep_picture
from test_browser import choose
from test_browser_lecture import close_toasts, hall_app, open_folder_to, open_page, press_play, received, text_input  # noqa: F401

from app.main import App
from app.sharestore import DEFAULT_TTL_S
from tests.test_codec import drop_caches
from tests.test_fork import assert_same
from tests.test_trust import fingerprint

pytestmark = pytest.mark.browser


def _open_code(page, session, text: str) -> None:  # type: ignore[no-untyped-def]
    field = text_input(page, "Shared code")
    field.wait_for(state="visible", timeout=20_000)
    field.click()
    field.fill("")
    page.keyboard.type(text, delay=10)
    page.keyboard.press("Enter")
    received(page, session, "Shared code", text)
    page.get_by_role("button", name="Open a shared moment").click()


def test_a_moment_shared_in_one_browser_opens_bit_for_bit_in_another(browser, hall_app: App,  # noqa: F811
                                                                      wait_until) -> None:
    sharer_page, sharer = open_page(browser, hall_app, **DESK)
    choose(sharer_page, sharer.gui_scene, "Heavy top")
    wait_until(lambda: sharer.scene.title == "Heavy top", timeout=15.0)
    press_play(sharer_page, sharer)
    wait_until(lambda: sharer.room.sim.t > 0.5, timeout=15.0)
    sharer_page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not sharer.room.playing, timeout=10.0)
    close_toasts(sharer_page)
    open_folder_to(sharer_page, "Share", "Shared code")
    sharer_page.get_by_role("button", name="Share", exact=True).click()
    shown = sharer_page.get_by_text(re.compile(r"Code [0-9A-Z]{4}-[0-9A-Z]{4}")).first
    shown.wait_for(timeout=15_000)
    code = re.search(r"[0-9A-Z]{4}-[0-9A-Z]{4}", shown.inner_text()).group(0)  # type: ignore[union-attr]
    assert code == sharer.share.last_code
    keep_picture(sharer_page, "share_shared.png")

    other_page, other = open_page(browser, hall_app, **DESK)
    close_toasts(other_page)
    open_folder_to(other_page, "Share", "Shared code")
    before_room, before = other.room, fingerprint(other.room.sim)

    _open_code(other_page, other, "hello")
    other_page.get_by_text("is not a share code").first.wait_for(timeout=15_000)
    hall_app.share_store.clock = lambda: 2e9 + DEFAULT_TTL_S  # type: ignore[union-attr]  # 30 days later
    try:
        _open_code(other_page, other, code.lower())
        other_page.get_by_text(f"The shared moment {code} expired").first.wait_for(timeout=15_000)
    finally:
        hall_app.share_store.clock = __import__("time").time  # type: ignore[union-attr]
    assert other.room is before_room and fingerprint(other.room.sim) == before

    _open_code(other_page, other, code)
    wait_until(lambda: other.room.scene.title == "Heavy top", timeout=15.0)
    dropdown = other_page.locator(f'[id="{other.gui_scene._impl.uuid}"]')
    wait_until(lambda: dropdown.input_value() == "Heavy top", timeout=15.0)  # the page says so
    expected = sharer.room.fork()
    opened = other.room.fork()
    drop_caches(expected.sim)
    drop_caches(opened.sim)
    assert_same(expected.sim, opened.sim, "opened")
    assert other.room.playing is False and other.error_count == 0 and sharer.error_count == 0
    keep_picture(other_page, "share_opened.png")
