"""A question round ends with the presenter who asked it, and its CSV downloads at once (issue 34,
rows 1 and 4), in Debian's Chromium, through the pages only.

The presenter (a desk page, 800×600) types the code and presents, asks a choice; a student
answers by clicking its option; the presenter's `Download answers (CSV)` is saved by the browser
at once (Playwright's download event, no toast link clicked).  Then the presenter closes its
tab: the student's page loses the question; a newcomer's page shows no question and gets the
Scene dropdown (at most one click on `Explore on my own` away); a new presenter's page shows
the `Ask the class` form, not the old round, and `Download earlier rounds (CSV)` saves the ended
round's answers at once.

Pictures for people: $RBL_TEST_SHOTS/round_ends/ (download_answers.png, student_after_leave.png,
newcomer.png, next_presenter.png; none when unset).  Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import DESK, keep_picture
from test_browser_lecture import button, close_toasts, hall_app, open_page, present_in_page, text_input, type_into  # noqa: F401

from app.main import App

pytestmark = pytest.mark.browser

LAPTOP = DESK


def _shot(page, name: str) -> None:  # type: ignore[no-untyped-def]
    keep_picture(page, f"round_ends/{name}", timeout=60_000)


def _download(page, control) -> tuple[str, str]:  # type: ignore[no-untyped-def]
    """(name, text) of the download that clicking `control` starts: the browser saves it at
    once (a toast's link is never clicked)."""
    with page.expect_download(timeout=30_000) as info:
        control.click()
    done = info.value
    return done.suggested_filename, Path(done.path()).read_text(encoding="utf-8")


def test_a_round_ends_when_its_presenter_closes_the_tab(browser, hall_app: App, wait_until) -> None:  # noqa: F811
    app = hall_app
    lecturer, presenter = open_page(browser, app, timeout=90.0, **LAPTOP)
    present_in_page(lecturer, presenter)
    student_page, student = open_page(browser, app, timeout=90.0, **LAPTOP)
    wait_until(lambda: student.mode == "following", timeout=20.0)
    close_toasts(lecturer)

    type_into(lecturer, "Question", "The book spins about y′. What does it do?", presenter)
    type_into(lecturer, "Options", "spins steadily | wobbles | flips", presenter)
    button(lecturer, "Ask the class").click()
    option = button(student_page, "3. flips")
    option.wait_for(timeout=20_000)
    option.click()
    lecturer.get_by_text("1 of 1 answered", exact=False).wait_for(timeout=15_000)
    close_toasts(lecturer)
    name, text = _download(lecturer, button(lecturer, "Download answers (CSV)"))
    assert name == "answers-round-1.csv" and "flips" in text, (name, text)
    _shot(lecturer, "download_answers.png")  # saved: no toast with a link

    lecturer.context.close()  # the presenter closes its tab without `Close the round`
    wait_until(lambda: presenter.closed and app.lectern.presenter is None, timeout=20.0)
    student_page.get_by_text("Question 1", exact=False).first.wait_for(state="hidden", timeout=20_000)
    assert not button(student_page, "3. flips").is_visible()
    _shot(student_page, "student_after_leave.png")

    newcomer_page, newcomer = open_page(browser, app, timeout=90.0, **LAPTOP)
    scene = newcomer_page.locator(f'[id="{newcomer.gui_scene._impl.uuid}"]')
    explore = button(newcomer_page, "Explore on my own")
    try:
        explore.wait_for(timeout=5_000)  # a newcomer that follows the frozen room: one click to its own
        explore.click()
    except Exception:  # noqa: BLE001 - it landed in its own room: no Explore to press
        pass
    scene.wait_for(state="visible", timeout=20_000)
    assert not newcomer_page.get_by_text("Question 1", exact=False).first.is_visible()
    assert newcomer.error_count == 0, newcomer.last_error
    _shot(newcomer_page, "newcomer.png")

    next_page, successor = open_page(browser, app, timeout=90.0, **LAPTOP)
    present_in_page(next_page, successor)
    button(next_page, "Ask the class").wait_for(timeout=20_000)
    text_input(next_page, "Question").wait_for(timeout=10_000)
    assert not next_page.get_by_text("Round 1", exact=False).first.is_visible(), "the old round on the new presenter"
    assert not button(next_page, "Close the round").is_visible()
    close_toasts(next_page)
    earlier = button(next_page, "Download earlier rounds (CSV)")
    earlier.wait_for(timeout=10_000)
    _shot(next_page, "next_presenter.png")
    name, text = _download(next_page, earlier)
    assert name == "answers-earlier-rounds.csv"
    assert "ended: the presenter left" in text and "flips" in text, text
    for session in (student, successor):
        assert session.error_count == 0, session.last_error
