"""A worksheet done at different times (issue 37's "Done when"), in Debian's Chromium, through
the pages: the presenter's page makes the three-question memo worksheet from its lesson, and
students do it

1. on one process with a data folder (SQLite): Ann on a laptop before a restart; the server
   stopped and started again on the same folder, Bea on a phone opens the code on the new
   server; then the due time passes (the store's clock, the app's one clock of tasks, moved on)
   and Cem on a laptop is told plainly, and nothing of his is kept;
2. on two workers sharing Redis: the task made on worker A, Dana on a laptop on worker B.

The lecturer opens the task with its code and the presenter code: the table, the gallery of a
question's states and the CSV show exactly what each did.  The server's state is read only to
check (and to wait for what a page cannot show, the room's scene)."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterator
from datetime import datetime
from pathlib import Path
from typing import Any

import pytest
from conftest import DESK, keep_picture, keep_words, poll_until
from test_browser import choose
from test_browser_lecture import _CONTEXTS, CODE, close_toasts, open_page
from test_browser_tasks import (
    WAIT_MS,
    _button,
    _open_as_lecturer,
    _open_task,
    _presenting,
    _type_into,
    make_memo_worksheet,
    wait_text,
)

from app.main import App, create_server

pytestmark = pytest.mark.browser

SUBMIT = "Submit the state of my room"
WRONG, RIGHT = "✗ not what was asked", "✓ as asked"
LAPTOP = DESK
PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True}
LECTURER = {"viewport": {"width": 1280, "height": 900}}
DAY_S = 24 * 3600.0


@contextlib.contextmanager
def _server(**options: Any) -> Iterator[App]:
    """The app with the presenter code CODE; its pages' contexts closed, then it stops."""
    app = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE, **options)
    try:
        yield app
    finally:
        while _CONTEXTS:
            _CONTEXTS.pop().close()
        app.stop()


def _student_opens(browser: Any, app: App, code: str, who: str, **context: Any) -> tuple[Any, Any]:
    """A new page on `app` types `code` in the Task folder and opens it: (page, session), its first
    question shown."""
    page, session = open_page(browser, app, timeout=90.0, **context)
    close_toasts(page)
    _open_task(page, session, code)
    wait_text(page, "Question 1 of 3", f"{who}'s first question", session)
    return page, session


def _answers(page: Any, session: Any, app: App, code: str, question: int, expected: str) -> None:
    """The student's page submits the state of its room for `question` (0-based, shown); the
    verdict `expected` awaited on the page after the store kept one more of theirs."""
    def mine() -> list[Any]:
        return [s for s in app.task_store.mine(code, session.answer_token) if s.question == question]

    before = len(mine())
    _button(page, SUBMIT).click()
    page_said = lambda: (session.task_panel.gui_note.content, session.task_panel.gui_verdict.content)  # noqa: E731
    try:
        poll_until(lambda: len(mine()) == before + 1, timeout=WAIT_MS / 1000, interval=0.1,
                   what=f"submission {before + 1} of question {question + 1} kept", seen=page_said)
    except AssertionError as error:
        raise AssertionError(f"{error}; last error {session.last_error!r}") from None
    wait_text(page, expected, f"the verdict of question {question + 1}", session)


def _next_question(page: Any, session: Any, task: Any, question: int, wait_until: Any) -> None:
    """`Next question` pressed: question `question` (0-based) shown, its scene in the student's room."""
    _button(page, "Next question").click()
    wait_text(page, f"Question {question + 1} of 3", f"question {question + 1}", session)
    scene = task.places[question][0]
    wait_until(lambda: session.room.scene.title == scene, timeout=30.0, what=f"the student's room in {scene}",
               seen=lambda: session.room.scene.title)


def _verdict_line(page: Any) -> str:
    """The student's verdict as their page shows it (the line under Submit)."""
    body = page.locator("body").inner_text()
    return " ".join(line.strip() for line in body.splitlines() if "Your attempt" in line or "Receipt " in line)


def _csv_rows(page: Any) -> list[str]:
    """`Download results (CSV)` pressed on the lecturer's page: the file's lines."""
    with page.expect_download(timeout=WAIT_MS) as download:
        _button(page, "Download results (CSV)").click()
    return Path(download.value.path()).read_text().splitlines()


def test_a_worksheet_done_before_and_after_a_restart_and_once_too_late(browser, tmp_path: Path,
                                                                     wait_until) -> None:
    with _server(data_dir=tmp_path) as first:
        projector, presenter = _presenting(browser, first)
        code = make_memo_worksheet(projector, presenter, wait_until, attempts="2")
        task = first.task_store.task(code)
        laptop, ann = _student_opens(browser, first, code, "Ann", **LAPTOP)
        _type_into(laptop, "Your name", "Ann Lee", ann)
        _answers(laptop, ann, first, code, 0, WRONG)  # D = 1 is no turn about x
        _next_question(laptop, ann, task, 1, wait_until)
        _answers(laptop, ann, first, code, 1, RIGHT)  # the Dzhanibekov start flips
        _next_question(laptop, ann, task, 2, wait_until)
        _answers(laptop, ann, first, code, 2, WRONG)  # Steady: no loops
        _button(laptop, "Loop").click()
        wait_until(lambda: getattr(ann.room.sim, "preset", None) == "Loop", timeout=30.0,
                   what="Ann's room playing the Loop preset", seen=lambda: getattr(ann.room.sim, "preset", None))
        _answers(laptop, ann, first, code, 2, RIGHT)
        wait_text(laptop, "no attempts left", "Ann's attempts used up at question 3", ann)
        ann_verdict = _verdict_line(laptop)
        keep_picture(laptop, "tasks2/ann-laptop-verdict.png")
        for session in (presenter, ann):
            assert session.error_count == 0, session.last_error

    with _server(data_dir=tmp_path) as second:  # the same data folder: the restart
        phone, bea = _student_opens(browser, second, code.lower().replace("-", " "), "Bea (after the restart)",
                                    **PHONE)
        _type_into(phone, "Student number", "s 2041", bea)
        _answers(phone, bea, second, code, 0, WRONG)
        _next_question(phone, bea, task, 1, wait_until)
        _answers(phone, bea, second, code, 1, RIGHT)  # and she stops there
        keep_picture(phone, "tasks2/bea-phone-after-restart.png")
        kept = second.task_store.submissions(code)
        assert len(kept) == 6, [(s.student.key, s.question, s.attempt) for s in kept]

        real_clock = second.task_store.clock
        second.task_store.clock = lambda: real_clock() + 8 * DAY_S  # a week and a day later: due a day ago
        late, cem = _student_opens(browser, second, code, "Cem (too late)", **LAPTOP)
        wait_text(late, "no longer open", "the task said closed to Cem", cem)
        _type_into(late, "Your name", "Cem", cem)
        _button(late, SUBMIT).click()
        wait_text(late, "a submission after the due time is not accepted", "Cem told he is too late", cem)
        late_words = cem.task_panel.gui_note.content
        keep_picture(late, "tasks2/cem-too-late.png")
        assert second.task_store.submissions(code) == kept, "a late submission was kept"
        assert second.task_store.student(code, cem.answer_token) is None, "the late student's name was kept"

        desk, teacher = open_page(browser, second, timeout=90.0, **LECTURER)
        close_toasts(desk)
        _open_as_lecturer(desk, teacher, code)
        wait_text(desk, "2 students, 6 submissions", "the lecturer's table", teacher)
        table = teacher.task_panel.gui_table.content
        assert "past its due time" in table, table
        assert "| Ann Lee | – | 2 | 0.67 | 1 ✗ · 2 ✓ · 3 ✓ |" in table, table
        assert "| – | s2041 | 1 | 0.33 | 1 ✗ · 2 ✓ · 3 – |" in table, table
        assert "Cem" not in table, table
        # the 3D view of the first question's states, shown at once: both students' bodies
        wait_text(desk, "2 answers drawn faint at once", "the gallery of question 1", teacher)
        choose(desk, teacher.task_panel.views.gui_view, "Q3 · gallery")
        wait_text(desk, "1 answer drawn faint at once", "the gallery of question 3", teacher)
        desk.get_by_role("button", name="Next", exact=True).click()
        wait_text(desk, "Answer 1 of 1: loops", "Ann's counted state of question 3, alone", teacher)
        keep_picture(desk, "tasks2/lecturer-table-after-restart.png")
        rows = _csv_rows(desk)
        assert rows[0] == "name,number,score,attempts,last_submitted,verdict", rows
        assert len(rows) == 3, rows  # Ann, Bea; nothing of Cem's
        assert rows[1].startswith("Ann Lee,,0.667,2,"), rows
        assert "Q1: 90.0° from the target ✗" in rows[1] and "Q2: flips" in rows[1], rows
        assert "Q3: loops" in rows[1] and rows[1].endswith("✓ as asked"), rows  # the best of two attempts
        assert rows[2].startswith(",s2041,0.333,1,") and rows[2].endswith("Q3: not answered"), rows
        # Play this answer: Ann's loops in the lecturer's own room, its scene opened first
        _button(desk, "Play this answer").click()
        wait_text(desk, "Playing answer 1 in your room.", "Ann's answer playing", teacher)
        wait_until(lambda: teacher.room.scene.title == "Heavy top" and teacher.room.playing, timeout=30.0,
                   what="the lecturer's room playing a Heavy top",
                   seen=lambda: (teacher.room.scene.title, teacher.room.playing))
        keep_picture(desk, "tasks2/lecturer-plays-anns-answer.png")
        keep_words("tasks2/restart-table.md", f"{table}\n\nAnn's verdict: {ann_verdict}\n\nCem: {late_words}\n\n"
                                                + "\n".join(rows) + "\n")
        for session in (bea, cem, teacher):
            assert session.error_count == 0, session.last_error


@pytest.fixture
def two_workers(tmp_path: Path) -> Iterator[tuple[App, App]]:
    """Workers A and B of one lecture (both in this process), sharing a redis-server of their own."""
    from app.cluster import services

    try:
        url, redis = services.start_redis()
    except services.MissingProgram as error:
        pytest.skip(str(error))
    with contextlib.ExitStack() as stack:
        stack.callback(services.stop_process, redis)
        apps = [stack.enter_context(_server(redis_url=url, worker_id=worker, data_dir=tmp_path / worker))
                for worker in ("a", "b")]
        yield apps[0], apps[1]


def test_a_worksheet_made_on_one_worker_is_done_on_the_other(browser, two_workers, wait_until) -> None:
    a, b = two_workers
    projector, presenter = _presenting(browser, a)
    code = make_memo_worksheet(projector, presenter, wait_until, attempts="1")
    task = a.task_store.task(code)
    laptop, dana = _student_opens(browser, b, code, "Dana (on worker B)", **LAPTOP)
    _type_into(laptop, "Student number", "s77", dana)
    _answers(laptop, dana, b, code, 0, WRONG)
    _next_question(laptop, dana, task, 1, wait_until)
    started = time.time()
    _answers(laptop, dana, b, code, 1, RIGHT)
    wait_text(laptop, "no attempts left", "Dana's one attempt at question 2 used", dana)
    dana_verdict = _verdict_line(laptop)
    _button(laptop, SUBMIT).click()  # once more: refused, said, nothing kept
    wait_text(laptop, "You have used your 1 attempt at question 2", "Dana's second attempt refused", dana)
    keep_picture(laptop, "tasks2/dana-worker-b-verdict.png")

    _open_as_lecturer(projector, presenter, code)  # on worker A
    wait_text(projector, "1 student, 2 submissions", "the lecturer's table on worker A", presenter)
    table = presenter.task_panel.gui_table.content
    assert "| – | s77 | 1 | 0.33 | 1 ✗ · 2 ✓ · 3 – |" in table, table
    wait_text(projector, "1 answer drawn faint at once", "the gallery of question 1 on worker A", presenter)
    keep_picture(projector, "tasks2/lecturer-table-worker-a.png")
    rows = _csv_rows(projector)
    assert len(rows) == 2 and rows[1].startswith(",s77,0.333,1,"), rows
    last_submitted = datetime.fromisoformat(rows[1].split(",")[4]).timestamp()
    assert started - 1.0 <= last_submitted <= time.time(), (rows, started)
    keep_words("tasks2/workers-table.md", f"{table}\n\nDana's verdict: {dana_verdict}\n\n" + "\n".join(rows) + "\n")
    for session in (presenter, dana):
        assert session.error_count == 0, session.last_error
