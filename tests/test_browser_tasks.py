"""A task between lectures (issue 37) through the pages, in Debian's Chromium: the presenter fills
the Ask form (a number question), sets two attempts and presses `Make a task`; a student on a
laptop opens the `Task` folder, types the code as said aloud (lower case, a space), gives a name,
submits a wrong number, sees the verdict, tries again and is right; a second student on a phone
is wrong once; the lecturer opens the task with the presenter code and the live table shows
each.  The server's state is read only to check."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import DESK, keep_picture, keep_words
from test_browser import choose
from test_browser_lecture import CODE, close_toasts, hall_app, open_folder_to, open_page, type_into  # noqa: F401 - hall_app: a fixture

from app.main import App

pytestmark = pytest.mark.browser

WAIT_MS = 30_000  # a busy machine


def _type_into(page, label: str, text: str, session=None) -> None:  # type: ignore[no-untyped-def]
    """`type_into` (test_browser_lecture): typed, and with `session` awaited on the server."""
    type_into(page, label, text, session)


def _button(page, name: str):  # type: ignore[no-untyped-def]
    return page.get_by_role("button", name=name, exact=True)


def _student_submits(page, session, value: str, expected: str) -> str:  # type: ignore[no-untyped-def]
    """Type `value` in the number box, press Submit, wait for the verdict `expected`; the folder's text."""
    _type_into(page, "Your number [s]", value, session)
    _button(page, "Submit").click()
    page.get_by_text(expected, exact=False).first.wait_for(timeout=WAIT_MS)
    return page.locator("body").inner_text()


def _open_task(page, session, typed: str) -> None:  # type: ignore[no-untyped-def]
    """A student types the task code `typed` in the Task folder and opens the task."""
    open_folder_to(page, "Task", "Task code")
    _type_into(page, "Task code", typed, session)
    _button(page, "Open the task").click()


def _presenting(browser, app: App):  # type: ignore[no-untyped-def]
    """The lecturer's page on a 1280×900 projector, presenting: (page, session)."""
    projector, presenter = open_page(browser, app, timeout=90.0, viewport={"width": 1280, "height": 900})
    presenter.present(CODE)
    close_toasts(projector)
    return projector, presenter


def _open_as_lecturer(page, session, code: str) -> None:  # type: ignore[no-untyped-def]
    """The lecturer opens the task `code` with the presenter code, through the Task folder."""
    open_folder_to(page, "Task", "Task code")
    _type_into(page, "Task code", code, session)
    _type_into(page, "Lecturer's code", CODE, session)
    _button(page, "Open as lecturer").click()


def test_a_lecturer_makes_a_task_students_do_it_and_the_table_shows_them(browser, hall_app: App,  # noqa: F811
                                                                        wait_until) -> None:
    app = hall_app
    projector, presenter = _presenting(browser, app)
    ask = presenter.ask_panel
    choose(projector, ask.gui_kind, "Number")
    wait_until(lambda: ask.forms["number"].gui_unit.visible, timeout=20.0)
    _type_into(projector, "Question", "The book flips: its flip period?", presenter)
    _type_into(projector, "Right value", "2.5", presenter)
    _type_into(projector, "Unit", "s", presenter)
    _type_into(projector, "Tolerance", "0.2", presenter)
    choose(projector, presenter.task_panel.gui_attempts, "2")
    _type_into(projector, "Words for the task", "Spin the book about its middle axis and time a flip.", presenter)
    wait_until(lambda: (ask.forms["number"].gui_tolerance.value, presenter.task_panel.gui_attempts.value)
               == ("0.2", "2"), timeout=20.0)
    _button(projector, "Make a task").click()
    projector.get_by_text("Task code", exact=False).first.wait_for(timeout=WAIT_MS)
    made = re.search(r"Task code ([0-9A-Z]{4}-[0-9A-Z]{4})", projector.locator("body").inner_text())
    assert made is not None, "no task code on the presenter's page"
    code = made.group(1)
    assert app.task_store.task(code).policy.attempts == 2

    laptop, ann = open_page(browser, app, timeout=90.0, **DESK)
    close_toasts(laptop)
    _open_task(laptop, ann, code.lower().replace("-", " "))  # as read aloud
    wait_text(laptop, "The book flips: its flip period?", "Ann's question", ann)
    _type_into(laptop, "Your name", "Ann Lee", ann)
    wrong = _student_submits(laptop, ann, "3.1", "3.1 s: wrong")
    assert "1 attempt left" in wrong and "Receipt" in wrong, wrong
    right = _student_submits(laptop, ann, "2.6", "2.6 s: right")
    assert "no attempts left" in right, right
    verdict = next(line for line in right.splitlines() if "Your attempt 2" in line)

    phone, bea = open_page(browser, app, timeout=90.0, viewport={"width": 390, "height": 844}, is_mobile=True,
                           has_touch=True)
    close_toasts(phone)
    _open_task(phone, bea, code)
    wait_text(phone, "The book flips: its flip period?", "Bea's question", bea)
    _type_into(phone, "Student number", "s 2041", bea)
    _student_submits(phone, bea, "4", "4 s: wrong")

    _open_as_lecturer(projector, presenter, code)
    projector.get_by_text("2 students", exact=False).first.wait_for(timeout=WAIT_MS)
    table = presenter.task_panel.gui_table.content
    assert "| Ann Lee | – | 2 | 1.00 | 2.6 s: right |" in table, table
    assert "| – | s2041 | 1 | 0.00 | 4 s: wrong |" in table, table
    body = projector.locator("body").inner_text()
    assert "Ann Lee" in body and "s2041" in body and "2.6 s: right" in body, body
    # live: a later attempt shows in the open table without a click of the lecturer's
    _student_submits(phone, bea, "2.45", "2.45 s: right")
    projector.get_by_text("2.45 s: right", exact=False).first.wait_for(timeout=WAIT_MS)
    keep_picture(projector, "tasks/lecturer-table.png")
    keep_picture(laptop, "tasks/student-verdict.png")
    keep_words("tasks/lecturer-table.md", presenter.task_panel.gui_table.content + "\n\n" + verdict + "\n")
    # the CSV the lecturer downloads
    with projector.expect_download(timeout=WAIT_MS) as download:
        _button(projector, "Download results (CSV)").click()
    rows = Path(download.value.path()).read_text().splitlines()
    assert rows[0] == "name,number,score,attempts,last_submitted,verdict", rows
    assert rows[1].startswith("Ann Lee,,1.000,2,") and rows[1].endswith(",2.6 s: right"), rows
    assert rows[2].startswith(",s2041,1.000,2,") and rows[2].endswith(",2.45 s: right"), rows
    for session in (presenter, ann, bea):
        assert session.error_count == 0, session.last_error


WORKSHEET = "Worksheet on the memo (a task for home: one rotation, the flip, a top that loops)"


def wait_text(page, text: str, what: str, session=None, timeout_ms: int = WAIT_MS) -> None:  # type: ignore[no-untyped-def]
    """Wait until `text` shows on `page`; AssertionError naming `what` and what the page (and its
    session's last error) showed otherwise."""
    try:
        page.get_by_text(text, exact=False).first.wait_for(timeout=timeout_ms)
    except Exception as error:  # noqa: BLE001 - said with what was seen
        said = "" if session is None else f"; the session's last error {session.last_error!r}"
        raise AssertionError(f"waited {timeout_ms / 1000:g} s for {what} ({text!r}){said}; the page showed:\n"
                             f"{page.locator('body').inner_text()[-1500:]}") from error


def make_memo_worksheet(projector, presenter, wait_until, attempts: str) -> str:  # type: ignore[no-untyped-def]
    """The presenter's page starts the memo worksheet lesson, adds each step's question to the
    worksheet, sets `attempts` and presses `Make a task`; the task code shown ("K7M2-QX9P")."""
    ask = presenter.ask_panel
    projector.get_by_text("Lesson", exact=True).first.click()
    choose(projector, presenter.lesson_runner.gui_lesson, WORKSHEET)
    wait_until(lambda: presenter.lesson is not None, timeout=30.0, what="the worksheet lesson started",
               seen=lambda: presenter.last_error)
    with presenter.lock:  # the lesson's start has ended
        pass
    for k, start in enumerate(("One rotation", "The flip", "A heavy top that loops")):
        if k > 0 or presenter.lesson_step < 0:
            _button(projector, "Next ▶").click()
        wait_until(lambda start=start: str(ask.gui_prompt.value).startswith(start), timeout=30.0,
                   what=f"the Ask form filled with {start!r}", seen=lambda: ask.gui_prompt.value)
        _button(projector, "Add to the worksheet").click()
        wait_text(projector, f"{k + 1} question", f"{k + 1} question(s) in the worksheet", presenter)
    choose(projector, presenter.task_panel.gui_attempts, attempts)
    wait_until(lambda: presenter.task_panel.gui_attempts.value == attempts, timeout=20.0,
               what=f"Attempts {attempts}", seen=lambda: presenter.task_panel.gui_attempts.value)
    _button(projector, "Make a task").click()
    wait_text(projector, "Task code", "the task code under Make a task", presenter)
    made = re.search(r"Task code ([0-9A-Z]{4}-[0-9A-Z]{4})", projector.locator("body").inner_text())
    assert made is not None, "no task code on the presenter's page"
    return made.group(1)


def test_a_worksheet_of_three_judged_questions_from_a_lesson_through_the_pages(browser, hall_app: App,  # noqa: F811
                                                                             wait_until) -> None:
    app = hall_app
    projector, presenter = _presenting(browser, app)
    code = make_memo_worksheet(projector, presenter, wait_until, attempts="unlimited")
    task = app.task_store.task(code)
    assert [q.judge for q in task.questions] == ["attitude", "axis_stays", "top_motion"]

    laptop, cem = open_page(browser, app, timeout=90.0, **DESK)
    close_toasts(laptop)
    _open_task(laptop, cem, code)
    wait_text(laptop, "Question 1 of 3", "Cem's first question", cem)
    _type_into(laptop, "Your name", "Cem", cem)
    submit = "Submit the state of my room"
    for k, expected in enumerate(("✗ not what was asked", "✓ as asked", "✗ not what was asked")):
        if k:
            _button(laptop, "Next question").click()
            laptop.get_by_text(f"Question {k + 1} of 3", exact=False).first.wait_for(timeout=WAIT_MS)
            wait_until(lambda k=k: cem.room.scene.title == task.places[k][0], timeout=30.0)
        _button(laptop, submit).click()
        wait_until(lambda k=k: len([s for s in app.task_store.mine(code, cem.answer_token) if s.question == k]) == 1,
                   timeout=30.0)
        laptop.get_by_text(expected, exact=False).first.wait_for(timeout=WAIT_MS)

    _open_as_lecturer(projector, presenter, code)
    projector.get_by_text("1 student", exact=False).first.wait_for(timeout=WAIT_MS)
    table = presenter.task_panel.gui_table.content
    assert "| Cem | – | 1 | 0.33 | 1 ✗ · 2 ✓ · 3 ✗ |" in table, table
    assert "**Q2** · 1 answered · 1 right" in table, table
    keep_picture(projector, "tasks/worksheet-lecturer.png")
    keep_picture(laptop, "tasks/worksheet-student.png")
    for session in (presenter, cem):
        assert session.error_count == 0, session.last_error
