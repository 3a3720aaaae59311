"""Tasks in the app (issue 37), with raw websocket clients: a hostile client cannot read or
change another student's submission or the task, and a task and its submissions survive a
restart of the app on its data folder."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import RawClient, poll_until

from app.main import App, create_server

CODE = "13572468"
DEADLINE_S = 30.0  # a busy machine


def _click(client: RawClient, handle: Any) -> None:
    from viser import _messages

    client.send(_messages.GuiUpdateMessage(handle._impl.uuid, {"value": True}))


def _typed(client: RawClient, handle: Any, value: Any) -> None:
    client.set_value(handle, value)
    poll_until(lambda: handle.value == value, timeout=DEADLINE_S)


def _new_session(app: App, client_factory: Any = RawClient) -> tuple[Any, Any]:
    before = set(app.sessions)
    client = client_factory(app.port)
    session = poll_until(lambda: next((s for cid, s in dict(app.sessions).items() if cid not in before), None),
                         timeout=DEADLINE_S)
    return client, session


def _make_task(app: App, lecturer: Any, **form: Any) -> Any:
    """The presenter fills the Ask form with a number question and makes a task (server side)."""
    with lecturer.lock:
        lecturer.present(CODE)
    ask, panel = lecturer.ask_panel, lecturer.task_panel
    ask.gui_kind.value = "Number"
    ask.gui_prompt.value = "The flip period of the book?"
    number = ask.forms["number"]
    number.gui_value.value, number.gui_unit.value, number.gui_tolerance.value = "2.5", "s", "0.2"
    panel.gui_attempts.value = form.get("attempts", "1")
    with lecturer.lock:
        return panel.make_from_form()


def _submit(client: RawClient, session: Any, code: str, name: str, value: float, receipt: str = "") -> str:
    """Through the raw client: the code, Open the task, the name, the number, Submit; the words
    said after it (the verdict, or the refusal)."""
    panel = session.task_panel
    _typed(client, panel.gui_code, code)
    _click(client, panel.gui_open)
    poll_until(lambda: panel.task is not None and panel.gui_submit.visible, timeout=DEADLINE_S)
    if panel.gui_name.visible:
        _typed(client, panel.gui_name, name)
    if receipt:
        _typed(client, panel.gui_my_receipt, receipt)
    _typed(client, panel.gui_value, value)
    before = (panel.gui_verdict.content, panel.gui_note.content)
    _click(client, panel.gui_submit)
    poll_until(lambda: (panel.gui_verdict.content, panel.gui_note.content) != before, timeout=DEADLINE_S)
    with session.lock:
        pass
    return panel.gui_note.content or panel.gui_verdict.content


@pytest.fixture
def hall(tmp_path: Path) -> Iterator[App]:
    running = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE, data_dir=tmp_path)
    try:
        yield running
    finally:
        running.stop()


def _open_as_lecturer(client: RawClient, session: Any, task: Any) -> Any:
    """`client` opens `task` as its lecturer (the task code and the presenter code typed, the
    button pressed); its session's task panel."""
    panel = session.task_panel
    _typed(client, panel.gui_code, task.shown_code)
    _typed(client, panel.gui_lecturer_code, CODE)
    _click(client, panel.gui_lecturer)
    return panel


def test_a_hostile_client_cannot_read_or_change_another_students_submission(hall: App) -> None:
    app = hall
    clients = []
    try:
        lecturer_client, lecturer = _new_session(app)
        ann_client, ann = _new_session(app)
        bad_client, bad = _new_session(app)
        clients += [lecturer_client, ann_client, bad_client]
        task = _make_task(app, lecturer, attempts="2")
        words = _submit(ann_client, ann, task.shown_code, "Ann Lee", 2.6)
        assert "2.6 s: right" in words and "Receipt" in words, words
        kept = app.task_store.submissions(task.code)
        assert len(kept) == 1
        # The hostile client: Ann's name, then hidden buttons, wrong codes, junk values.
        words = _submit(bad_client, bad, task.shown_code.replace("-", " ").lower(), "ann lee", 9.0)
        assert "already answers this task from another browser" in words, words
        panel = bad.task_panel
        for handle in (panel.gui_csv, panel.gui_close, panel.gui_extend, panel.gui_make, panel.gui_add,
                       panel.gui_check):
            _click(bad_client, handle)
        for value in ("x" * 100_000, "\x00", None, 12345678, [CODE]):
            bad_client.set_value(panel.gui_lecturer_code, value)
            _click(bad_client, panel.gui_lecturer)
        for guess in range(40):
            bad_client.set_value(panel.gui_lecturer_code, f"{guess:08d}")
            _click(bad_client, panel.gui_lecturer)
        bad_client.set_value(panel.gui_extend_hours, 1e9)
        _click(bad_client, panel.gui_extend)
        bad_client.set_value(panel.gui_receipt, kept[0].receipt)
        _click(bad_client, panel.gui_check)
        # eight refusals said (six hidden buttons, Extend again, Check a receipt), the guesses' note
        poll_until(lambda: bad.error_count >= 8 and "lecturer's code" in panel.gui_note.content, timeout=DEADLINE_S)
        with bad.lock:
            pass
        assert "only the lecturer" in str(bad.last_error), bad.last_error
        assert app.task_store.submissions(task.code) == kept  # Ann's, unchanged; nothing of the client's
        assert app.task_store.task(task.code) == task  # not closed, not extended
        assert panel.lecturer_task is None and not panel.gui_table.visible and panel.gui_table.content == ""
        shown = " ".join(h.content for h in (panel.gui_verdict, panel.gui_note, panel.gui_about, panel.gui_table,
                                             panel.gui_receipt_note))
        assert "Ann" not in shown and "2.6" not in shown, shown  # nothing of Ann's reached it
        assert app.task_store.mine(task.code, bad.answer_token) == []
        assert lecturer.task_panel.made == task and ann.task_panel.gui_verdict.content.count("Receipt") == 1
    finally:
        for client in clients:
            client.close()


def test_a_task_and_its_submissions_survive_a_restart(tmp_path: Path) -> None:
    first = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE, data_dir=tmp_path)
    clients = []
    try:
        lecturer_client, lecturer = _new_session(first)
        ann_client, ann = _new_session(first)
        clients += [lecturer_client, ann_client]
        task = _make_task(first, lecturer)
        assert "2.4 s: right" in _submit(ann_client, ann, task.code, "Ann", 2.4)
    finally:
        for client in clients:
            client.close()
        first.stop()
    second = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE, data_dir=tmp_path)
    clients = []
    try:
        bea_client, bea = _new_session(second)
        teacher_client, teacher = _new_session(second)
        clients += [bea_client, teacher_client]
        assert "3 s: wrong" in _submit(bea_client, bea, task.code, "Bea", 3.0)  # after the restart
        panel = _open_as_lecturer(teacher_client, teacher, task)
        poll_until(lambda: "| Bea |" in panel.gui_table.content, timeout=DEADLINE_S)
        table = panel.gui_table.content
        assert "| Ann | – | 1 | 1.00 | 2.4 s: right |" in table, table
        assert "| Bea | – | 1 | 0.00 | 3 s: wrong |" in table, table
        # a student shows the receipt of their submission made before the restart
        ann_receipt = second.task_store.submissions(task.code)[0].receipt
        _typed(teacher_client, panel.gui_receipt, ann_receipt.lower())
        _click(teacher_client, panel.gui_check)
        poll_until(lambda: "Ann, question 1, attempt 1: 2.4 s: right" in panel.gui_receipt_note.content,
                   timeout=DEADLINE_S)
        # Ann goes on in a new browser after the restart, with her receipt: she is Ann (her attempt is used)
        ann2_client, ann2 = _new_session(second)
        clients.append(ann2_client)
        again = _submit(ann2_client, ann2, task.shown_code, "", 2.5, receipt=ann_receipt)
        assert "You have used your 1 attempt" in again, again
        assert second.task_store.student(task.code, ann2.answer_token).name == "Ann"
        # a week and a day later (the store's wall clock moved): one too late is refused, nothing kept
        second.task_store.clock = lambda: time.time() + 8 * 24 * 3600.0
        cem_client, cem = _new_session(second)
        clients.append(cem_client)
        late = _submit(cem_client, cem, task.shown_code, "Cem", 2.5)
        assert "a submission after the due time is not accepted" in late, late
        assert len(second.task_store.submissions(task.code)) == 2
        assert teacher.error_count == 0 and bea.error_count == 0, (teacher.last_error, bea.last_error)
    finally:
        for client in clients:
            client.close()
        second.stop()


WORKSHEET = "Worksheet on the memo (a task for home: one rotation, the flip, a top that loops)"


def _state_submit(client: RawClient, session: Any, expected: str) -> str:
    """Press Submit (the state of the student's room) through the raw client; wait for `expected`."""
    panel = session.task_panel
    _click(client, panel.gui_submit)
    try:
        poll_until(lambda: expected in panel.gui_verdict.content or expected in panel.gui_note.content,
                   timeout=DEADLINE_S)
    except AssertionError:
        raise AssertionError(f"waited for {expected!r}; the verdict said {panel.gui_verdict.content!r}, the note "
                             f"{panel.gui_note.content!r}, the last error {session.last_error!r}") from None
    return panel.gui_verdict.content


def test_a_worksheet_from_a_lesson_done_on_the_other_worker_shows_in_the_lecturers_table(tmp_path: Path) -> None:
    from app.cluster import services

    try:
        url, process = services.start_redis()
    except services.MissingProgram as error:
        pytest.skip(str(error))
    apps: list[App] = []
    clients: list[RawClient] = []
    try:
        for worker in ("w1", "w2"):
            apps.append(create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE, redis_url=url,
                                      worker_id=worker, data_dir=tmp_path / worker))
        lecturer_client, lecturer = _new_session(apps[0])
        student_client, student = _new_session(apps[1])
        clients += [lecturer_client, student_client]
        with lecturer.lock:
            lecturer.present(CODE)
            lecturer.start_lesson(WORKSHEET)
        panel = lecturer.task_panel
        for step in range(3):  # each step's question, in its scene, joins the worksheet
            with lecturer.lock:
                if step:
                    lecturer.next_step(1)
                panel.add_to_worksheet()
        panel.gui_attempts.value = "2"
        with lecturer.lock:
            task = panel.make_from_form()
        assert [q.judge for q in task.questions] == ["attitude", "axis_stays", "top_motion"]
        assert [p[0] for p in task.places] == ["Euler angles", "Free body", "Heavy top"]
        assert task.places[1][1] == "Dzhanibekov"
        mine = student.task_panel
        _typed(student_client, mine.gui_code, task.shown_code)
        _click(student_client, mine.gui_open)
        poll_until(lambda: mine.task is not None and student.room.scene.title == "Euler angles", timeout=DEADLINE_S)
        _typed(student_client, mine.gui_name, "Cem")
        first = _state_submit(student_client, student, "not what was asked")  # D = 1 is no 90° turn about x
        assert "90.0° from the target" in first, first
        _click(student_client, mine.gui_next)
        poll_until(lambda: student.room.scene.title == "Free body", timeout=DEADLINE_S, what="question 2's scene",
                   seen=lambda: (student.room.scene.title, mine.question, student.last_error))
        second = _state_submit(student_client, student, "✓ as asked")  # the Dzhanibekov start flips
        _click(student_client, mine.gui_next)
        poll_until(lambda: student.room.scene.title == "Heavy top", timeout=DEADLINE_S)
        _state_submit(student_client, student, "not what was asked")  # steady precession
        with student.lock:
            student.apply_preset("Loop")
        third = _state_submit(student_client, student, "✓ as asked")
        assert "no attempts left" in third, third
        lecturer_panel = _open_as_lecturer(lecturer_client, lecturer, task)
        poll_until(lambda: "| Cem |" in lecturer_panel.gui_table.content, timeout=DEADLINE_S)
        table = lecturer_panel.gui_table.content
        assert "| Cem | – | 2 | 0.67 | 1 ✗ · 2 ✓ · 3 ✓ |" in table, table
        # another student on the other worker, seen by the lecturer's open table (polled across processes)
        dana_client, dana = _new_session(apps[1])
        clients.append(dana_client)
        _typed(dana_client, dana.task_panel.gui_code, task.shown_code)
        _click(dana_client, dana.task_panel.gui_open)
        poll_until(lambda: dana.task_panel.task is not None and dana.room.scene.title == "Euler angles",
                   timeout=DEADLINE_S)
        _typed(dana_client, dana.task_panel.gui_student_number, "s77")
        _state_submit(dana_client, dana, "not what was asked")
        poll_until(lambda: "| – | s77 | 1 | 0.00 | 1 ✗ · 2 – · 3 – |" in lecturer_panel.gui_table.content,
                   timeout=DEADLINE_S)
        print(lecturer_panel.gui_table.content, "\n", first, "\n", second, "\n", third, sep="")
        for session in (lecturer, student, dana):
            assert session.error_count == 0, session.last_error
    finally:
        for client in clients:
            client.close()
        for app in apps:
            app.stop()
        services.stop_process(process)


def test_make_a_task_is_part_of_the_ask_form_hidden_while_a_round_runs(hall: App) -> None:
    client, lecturer = _new_session(hall)
    try:
        with lecturer.lock:
            lecturer.present(CODE)
        panel = lecturer.task_panel
        poll_until(lambda: panel.gui_make.visible and panel.gui_due.visible, timeout=DEADLINE_S)
        lecturer.ask({"kind": "choice", "prompt": "Which?", "options": ["a", "b"]})
        poll_until(lambda: not panel.gui_make.visible and not panel.gui_attempts.visible, timeout=DEADLINE_S)
        with lecturer.lock:
            hall.lectern.rounds.end()
            lecturer.ask_panel.refresh()
        poll_until(lambda: panel.gui_make.visible and panel.gui_words.visible, timeout=DEADLINE_S)
    finally:
        client.close()


def test_the_lecturer_sees_a_direction_tasks_answers_as_tips_on_the_sphere(hall: App) -> None:
    """Opened as lecturer, a task of a direction question shows every student's counted answer as a
    tip on the sphere of `Ask the class` (and the true direction), in the lecturer's own scene only;
    `3D view` none hides them.  A student's browser has no such view."""
    import numpy as np

    from app.hall.ask_kinds import direction_of
    from app.hall.ask_presenter import SPHERE_RADIUS

    app = hall
    clients = []
    try:
        lecturer_client, lecturer = _new_session(app)
        clients.append(lecturer_client)
        with lecturer.lock:
            lecturer.present(CODE)
        ask, panel = lecturer.ask_panel, lecturer.task_panel
        ask.gui_kind.value = "Direction"
        ask.gui_prompt.value = "Where does the angular momentum point?"
        ask.forms["direction"].gui_truth.value = "0, 0, 1"
        panel.gui_attempts.value = "2"
        panel.gui_counts.value = "last"
        with lecturer.lock:
            task = panel.make_from_form()
        answers = {"Ann": [(0.0, 80.0), (90.0, 10.0)], "Bea": [(180.0, 88.0)]}  # azimuth, elevation [deg]
        for name, tries in answers.items():
            client, student = _new_session(app)
            clients.append(client)
            mine = student.task_panel
            _typed(client, mine.gui_code, task.shown_code)
            _click(client, mine.gui_open)
            poll_until(lambda mine=mine: mine.task is not None and mine.gui_azimuth.visible, timeout=DEADLINE_S)
            _typed(client, mine.gui_name, name)
            for azimuth, elevation in tries:
                _typed(client, mine.gui_azimuth, azimuth)
                _typed(client, mine.gui_elevation, elevation)
                before = mine.gui_verdict.content
                _click(client, mine.gui_submit)
                poll_until(lambda mine=mine, before=before: mine.gui_verdict.content != before, timeout=DEADLINE_S,
                           what=f"{name}'s verdict", seen=lambda mine=mine: mine.gui_note.content)
            assert mine.views is None  # a student's browser never builds the lecturer's views
        opened = _open_as_lecturer(lecturer_client, lecturer, task)
        poll_until(lambda: opened.views is not None and opened.views.sphere.handles[1].visible, timeout=DEADLINE_S,
                   what="the tips on the lecturer's sphere", seen=lambda: opened.gui_note.content)
        views = opened.views
        assert views.gui_view.value == "Q1 · sphere of tips" and views.gui_view.visible
        sphere, tips, truth = views.sphere.handles
        assert sphere.visible and truth.visible
        counted = [direction_of(90.0, 10.0), direction_of(180.0, 88.0)]  # Ann's last attempt counts, then Bea's
        np.testing.assert_allclose(tips.points, SPHERE_RADIUS * np.array(counted), atol=2e-3)  # viser: float16
        assert np.allclose(truth.points[0, 1] / np.linalg.norm(truth.points[0, 1]), (0.0, 0.0, 1.0))
        assert not views.gallery_panel.folder.visible
        assert tips._impl.name.startswith("/task_views/"), tips._impl.name  # the lecturer's own, not the Ask round's
        _typed(lecturer_client, views.gui_view, "none")
        poll_until(lambda: not any(h.visible for h in views.sphere.handles), timeout=DEADLINE_S,
                   what="the sphere hidden by 3D view none", seen=lambda: [h.visible for h in views.sphere.handles])
        assert lecturer.error_count == 0, lecturer.last_error
    finally:
        for client in clients:
            client.close()


def test_a_german_student_reads_the_verdict_in_german_and_the_task_keeps_it_in_english(hall: App) -> None:
    """The verdict is stored as the kind words it (English: the lecturer's table, the CSV, a
    receipt read later) and written in the student's language where the student reads it."""
    lecturer_client, lecturer = _new_session(hall)
    dirk_client, dirk = _new_session(hall)
    try:
        task = _make_task(hall, lecturer)
        _typed(dirk_client, dirk.gui_language, "Deutsch")
        poll_until(lambda: dirk.languages.code == "de", timeout=DEADLINE_S)
        said = _submit(dirk_client, dirk, task.code, "Dirk", 2.4)
        assert "**2.4 s: richtig**" in said and "right" not in said, said
        assert hall.task_store is not None
        (submission,) = hall.task_store.submissions(task.code)
        assert submission.words == "2.4 s: right"
        assert dirk.error_count == 0, dirk.last_error
    finally:
        lecturer_client.close()
        dirk_client.close()


def test_a_student_doing_a_task_stays_in_their_room_when_a_lecture_starts(hall: App) -> None:
    """A student who opened a task while nobody presented keeps their room and the task when a
    presenter starts; a browser that only looks on is pulled along (it follows by default)."""
    clients: list[RawClient] = []
    try:
        lecturer_client, lecturer = _new_session(hall)
        clients.append(lecturer_client)
        task = _make_task(hall, lecturer)
        with lecturer.lock:
            lecturer.stop_presenting()
        student_client, student = _new_session(hall)
        onlooker_client, onlooker = _new_session(hall)
        clients += [student_client, onlooker_client]
        assert student.mode == onlooker.mode == "own"
        mine = student.task_panel
        _typed(student_client, mine.gui_code, task.shown_code)
        _click(student_client, mine.gui_open)
        scene = task.place(0)[0]
        poll_until(lambda: mine.task is not None and student.room.scene.title == scene, timeout=DEADLINE_S,
                   what=f"the task opened in {scene}", seen=lambda: (mine.task, student.room.scene.title))
        with student.lock:
            room = student.room
        with lecturer.lock:
            lecturer.present(CODE)
        poll_until(lambda: onlooker.mode == "following", timeout=DEADLINE_S, what="the onlooker following",
                   seen=lambda: onlooker.mode)
        assert student.mode == "own", "pulled along by the lecture"
        assert student.room is room and mine.task is not None and mine.task.shown_code == task.shown_code
        for session in (lecturer, student, onlooker):
            assert session.error_count == 0, session.last_error
    finally:
        for client in clients:
            client.close()
