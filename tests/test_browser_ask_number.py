"""A number question (issue 35) as a lecturer and a class use it, in Debian's Chromium, through
the pages only: the presenter chooses `Number`, types the question, the right value, its unit
and tolerance and asks; two laptop students type a number in their number box and press `Send
my number` (one types a text first, which the box does not take); the presenter's page shows
the count, the histogram and, revealed, how many are right.  The server's state is read only to
check."""

from __future__ import annotations

import pytest
from test_browser import choose
from test_browser_lecture import CODE, button, close_toasts, hall_app, open_page, text_input, type_into  # noqa: F401

from app.main import App

pytestmark = pytest.mark.browser


def test_a_class_answers_a_number_with_its_unit_through_its_pages(browser, hall_app: App,  # noqa: F811
                                                                  wait_until) -> None:
    app = hall_app
    projector, presenter = open_page(browser, app, timeout=90.0, viewport={"width": 1024, "height": 768})
    presenter.present(CODE)
    students = [open_page(browser, app, timeout=90.0, viewport={"width": 800, "height": 600}) for _ in range(2)]
    wait_until(lambda: all(session.mode == "following" for _, session in students), timeout=20.0)
    close_toasts(projector)

    choose(projector, presenter.ask_panel.gui_kind, "Number")
    wait_until(lambda: presenter.ask_panel.forms["number"].gui_unit.visible, timeout=10.0)
    type_into(projector, "Question", "The book flips: its flip period?", presenter)
    type_into(projector, "Right value", "2.5", presenter)
    type_into(projector, "Unit", "s", presenter)
    type_into(projector, "Tolerance", "0.2", presenter)
    wait_until(lambda: presenter.ask_panel.forms["number"].gui_tolerance.value == "0.2", timeout=10.0)
    button(projector, "Ask the class").click()
    wait_until(lambda: app.rounds.current is not None, timeout=10.0)
    for (page, _), typed in zip(students, ("2.6", "3.1"), strict=True):
        button(page, "Send my number").wait_for(timeout=20_000)
        close_toasts(page)
        box = text_input(page, "Your answer [s]")
        box.click()
        box.fill("")
        page.keyboard.type(typed, delay=5)
        box.press("Enter")
    for (page, session), value in zip(students, (2.6, 3.1), strict=True):
        wait_until(lambda session=session, value=value: session.question.gui_number.value == value, timeout=10.0)
        button(page, "Send my number").click()
    projector.get_by_text("2 of 2 answered", exact=False).wait_for(timeout=15_000)
    assert sorted(app.rounds.tally().values) == [2.6, 3.1]
    students[0][0].get_by_text("Your answer: 2.6 s", exact=False).wait_for(timeout=10_000)
    assert "█" in projector.locator("body").inner_text()  # the histogram's bars
    button(projector, "Reveal the answer").click()
    projector.get_by_text("1 of 2", exact=False).first.wait_for(timeout=10_000)
    for _, session in [(projector, presenter), *students]:
        assert session.error_count == 0, session.last_error
