"""The presenter lock through nginx with two workers, in Debian's Chromium, through the pages only:
the lecturer types the code with a dash and presents; a student's browser on the other worker
types the right code and then a wrong one and reads one answer for both, "Someone else is
presenting"; when the lecturer stops, the student's right code (typed without its space) works.
Needs Debian's Chromium, nginx and redis-server."""

from __future__ import annotations

import os
from typing import Any

import pytest
from cluster import CODE, Cluster, cluster_fixture
from conftest import poll_until
from test_browser import app_url
from test_browser_lecture import close_toasts, open_folder, received, text_input

pytestmark = pytest.mark.browser

cluster = cluster_fixture(workers=2)

BUSY = "Someone else is presenting; they must stop first."


def _open(browser: Any, cluster: Cluster, contexts: list[Any]) -> tuple[Any, int, Any]:
    before = {id(session) for _, session in cluster.sessions()}
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    contexts.append(context)
    page = context.new_page()
    page.goto(app_url(page, cluster.port))
    index, session = poll_until(lambda: next(((i, s) for i, s in cluster.sessions() if id(s) not in before), None),
                                timeout=60.0, interval=0.2)
    page.locator("canvas").first.wait_for(timeout=60_000)
    close_toasts(page)
    open_folder(page, "Lecture", "Presenter code")
    return page, index, session


def _type_and_present(page: Any, session: Any, code: str) -> None:
    field = text_input(page, "Presenter code")
    field.click()
    field.fill("")
    page.keyboard.type(code, delay=20)
    received(page, session, "Presenter code", code)
    page.get_by_role("button", name="Present").click()


def test_one_answer_for_every_code_while_the_lecturer_on_the_other_worker_presents(
        browser: Any, cluster: Cluster, wait_until: Any, tmp_path: Any) -> None:
    contexts: list[Any] = []
    try:
        lecturer_page, lw, lecturer = _open(browser, cluster, contexts)
        student_page, sw, student = _open(browser, cluster, contexts)
        assert lw != sw  # least_conn: the two browsers' websockets on the two workers
        _type_and_present(lecturer_page, lecturer, CODE.replace(" ", "-"))
        wait_until(lambda: lecturer.mode == "presenting", timeout=20.0)
        lecturer_page.get_by_role("button", name="Stop presenting").wait_for(timeout=20_000)
        for code in (CODE, "9999 9999"):  # right, then wrong: the page says the same
            _type_and_present(student_page, student, code)
            student_page.get_by_text(BUSY).first.wait_for(timeout=20_000)
            assert student.mode != "presenting"
        assert int(cluster.redis.zcard("rbl:gate:wrong")) == 0  # neither was evaluated
        if os.environ.get("GATE_SCREENSHOT"):
            student_page.screenshot(path=os.environ["GATE_SCREENSHOT"])
        lecturer_page.get_by_role("button", name="Stop presenting").click()
        student_page.get_by_text(BUSY).first.wait_for(state="hidden", timeout=20_000)  # the note goes
        _type_and_present(student_page, student, CODE.replace(" ", ""))
        wait_until(lambda: student.mode == "presenting", timeout=20.0)
    finally:
        for context in contexts:
            context.close()
