"""A question round ends with the presenter who asked it (issue 34, row 1), and every download
saves at once (row 4).

On one process: the presenter stops presenting, or closes its tab; across workers: the presenter
on the source worker stops, or the source worker is killed (a real `python -m app` worker, SIGKILL).
After each end nobody's panel shows the round, answers are refused, a newcomer gets its normal
panel, the next presenter gets the form (and the ended round's answers as `Download earlier
rounds (CSV)`), and the 3D sphere of the tips is gone.  A hostile raw websocket that clicks every
button it was sent keeps nothing alive."""

from __future__ import annotations

import csv
import io
import time
from typing import Any

import pytest
from conftest import RawClient, WorkerProcess, lecturer_presenting, shared_hall_fixtures
from test_bus import Workers, workers_fixture

from app.ask import Refused

CODE = "975310"
DIRECTION = {"kind": "direction", "prompt": "Where does L point?", "truth": [0, 0, 1]}
CHOICE = {"kind": "choice", "prompt": "Which axis is stable?", "options": ["x", "y", "z"], "correct": 0}


_one_hall, hall = shared_hall_fixtures(CODE)  # one app for the one-process tests; each test's browsers leave after it
workers = workers_fixture(CODE)  # the apps across workers, on one redis-server for the module (`redis_url`)


def _frames_until(hall: Any, predicate: Any, what: str, timeout: float = 15.0) -> None:
    """Frames of the app loop until `predicate()`; AssertionError naming `what` otherwise."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        for _ in range(4):
            hall.app.frame(1.0 / 60.0)
        if predicate():
            return
        time.sleep(0.02)
    raise AssertionError(f"not within {timeout} s: {what}")


def _asked_and_answered(hall: Any) -> tuple[Any, Any, Any]:
    """A presenter asks a direction, a follower answers it: (presenter, its client, the follower)."""
    presenter, presenter_client = hall.join_with_client()
    presenter.present(CODE)
    alice = hall.join()
    _frames_until(hall, lambda: alice.mode == "following", "the student follows")
    presenter.ask(DIRECTION)
    _frames_until(hall, lambda: alice.question.folder.visible, "the student sees the question")
    alice.answer((0.0, 0.0, 1.0))
    _frames_until(hall, lambda: presenter.ask_panel._sphere[1].visible, "the answer's tip on the presenter's sphere")
    return presenter, presenter_client, alice


def _round_is_gone(hall: Any, students: list[Any], why: str) -> None:
    """Nobody is asked any more; the ended round is kept (1 answer) as an earlier round, `why`."""
    rounds = hall.app.rounds
    _frames_until(hall, lambda: not any(s.question.folder.visible for s in students if not s.closed),
                  "no student's panel shows the question")
    assert rounds.current is None and rounds.shown() is None
    for student in students:
        if not student.closed:
            with pytest.raises(Refused, match="no question"):
                student.answer((1.0, 0.0, 0.0))
    (ended,) = rounds.earlier
    assert ended.why == why and len(ended.round_) == 1 and not ended.round_.open


def _recorded_downloads(session: Any) -> list[tuple[str, bytes, bool]]:
    """(name, data, save_immediately) of every download sent to `session`'s browser from now on."""
    sent: list[tuple[str, bytes, bool]] = []
    original = session.client.send_file_download

    def record(name: str, data: bytes, **kwargs: Any) -> None:
        sent.append((name, data, bool(kwargs.get("save_immediately"))))
        original(name, data, **kwargs)

    session.client.send_file_download = record
    return sent


def _next_presenter_starts_with_the_form(hall: Any, why: str) -> None:
    """A newcomer has its normal panel; the next presenter the form, no sphere, and the ended
    round as `Download earlier rounds (CSV)`, saved at once."""
    newcomer = hall.join()
    _frames_until(hall, lambda: newcomer.question.drawn != (), "the newcomer's question panel drawn")
    assert not newcomer.question.folder.visible
    bob = hall.join()
    bob.present(CODE)
    _frames_until(hall, lambda: bob.ask_panel.folder.visible, "the next presenter's Ask folder")
    panel = bob.ask_panel
    assert panel.gui_ask.visible and panel.gui_prompt.visible, "the next presenter has the form"
    assert not panel.gui_count.visible and not panel.gui_close.visible, "not the old round"
    assert not any(handle.visible for handle in panel._sphere), "no sphere, tips or arrow of the old round"
    assert panel.gui_earlier.visible
    sent = _recorded_downloads(bob)
    panel.download_earlier()
    ((name, data, at_once),) = sent
    assert name == "answers-earlier-rounds.csv" and at_once
    text = data.decode("utf-8")
    assert f"ended: {why}" in text and "Where does L point?" in text
    rows = list(csv.DictReader(line for line in io.StringIO(text) if not line.startswith("#")))
    assert len(rows) == 1 and float(rows[0]["z"]) == pytest.approx(1.0)
    bob.ask(CHOICE)  # the next presenter asks its own round
    assert hall.app.rounds.shown().question.prompt == "Which axis is stable?"  # type: ignore[union-attr]
    assert bob.error_count == 0, bob.last_error


def test_a_round_ends_when_its_presenter_stops(hall: Any) -> None:
    presenter, _, alice = _asked_and_answered(hall)
    presenter.stop_presenting()
    _round_is_gone(hall, [alice, presenter], "the presenter stopped")
    assert not any(handle.visible for handle in presenter.ask_panel._sphere), "the sphere left after Stop"
    question = presenter.question
    assert not (question.gui_send_direction.visible and question.gui_mine.visible and question.folder.visible)
    _next_presenter_starts_with_the_form(hall, "the presenter stopped")


def test_a_round_ends_when_its_presenters_tab_closes(hall: Any) -> None:
    from conftest import poll_until

    presenter, presenter_client, alice = _asked_and_answered(hall)
    presenter_client.close()
    poll_until(lambda: presenter.closed and hall.app.lectern.presenter is None, timeout=10.0)
    _round_is_gone(hall, [alice], "the presenter left")
    _next_presenter_starts_with_the_form(hall, "the presenter left")


def test_an_answered_round_shown_again_shows_the_answer_not_both(hall: Any) -> None:
    """A panel that stopped showing a round (its browser presented meanwhile) and shows it again
    shows the answer given, not `Send my direction` beside "Your answer: …"."""
    _presenter, _, alice = _asked_and_answered(hall)
    panel = alice.question
    panel.refresh()  # its panel shows the answer given through the automation API
    assert panel.gui_mine.visible and not panel.gui_send_direction.visible, "the answer not shown"
    panel.active = False  # as while its browser presents
    panel.refresh()
    assert not panel.folder.visible
    panel.active = True
    panel.refresh()
    assert panel.folder.visible and panel.gui_mine.visible
    assert not panel.gui_send_direction.visible, "Send my direction beside Your answer"


def test_a_hostile_client_keeps_no_round_alive_after_its_presenter_left(hall: Any) -> None:
    """A raw websocket that answers, then clicks every button it was ever sent (its own hidden
    `Ask the class`, `Vote again`, `Reveal` ... included) after the presenter left: the round
    stays ended, its count frozen, no newcomer is asked."""
    from benchmarks.ws_client import ViserClient, gui_update_message

    presenter, presenter_client, _alice = _asked_and_answered(hall)
    hostile, client = hall.join_with_client(lambda port: ViserClient(port))
    _frames_until(hall, lambda: hostile.question.folder.visible, "the hostile client is asked")
    client.send(gui_update_message(hostile.question.gui_send_direction._impl.uuid, True))
    _frames_until(hall, lambda: len(hall.app.rounds.current or ()) == 2, "the hostile answer counted")
    presenter_client.close()
    _frames_until(hall, lambda: hall.app.rounds.current is None, "the round ends with its presenter")
    client.wait_for_label("Send my direction", timeout=20.0, type_contains="Button")
    client.wait_for_label("Ask the class", timeout=20.0, type_contains="Button")
    with client.state.lock:
        buttons = [e.uuid for e in client.state.gui.values() if "Button" in e.type]
    assert len(buttons) > 10
    for _ in range(3):
        for uuid in buttons:
            client.send(gui_update_message(uuid, True))
        _frames_until(hall, lambda: True, "frames")
        time.sleep(0.2)
    _frames_until(hall, lambda: True, "frames")
    rounds = hall.app.rounds
    assert rounds.current is None and rounds.shown() is None, "a hostile client revived a round"
    (ended,) = rounds.earlier
    assert len(ended.round_) == 2 and not ended.round_.open
    newcomer = hall.join()
    _frames_until(hall, lambda: newcomer.question.drawn != (), "the newcomer's question panel drawn")
    assert not newcomer.question.folder.visible
    assert hall.app.lectern.presenter is None


# ---------------------------------------------------------------------- across workers (app.cluster.askbus)
def _join(workers: Workers, worker: str) -> Any:
    """A raw browser's session on `worker`."""
    return workers.connect(worker, RawClient)[0]


def test_a_round_on_another_worker_ends_when_its_presenter_stops(workers: Workers) -> None:
    from conftest import poll_until

    from app.cluster.askbus import ROUND_KEY

    apps = [workers.start("w1"), workers.start("w2")]
    presenter, student = _join(workers, "w1"), _join(workers, "w2")
    presenter.present(CODE)
    presenter.ask(CHOICE)
    poll_until(lambda: student.question.folder.visible, timeout=10.0)
    student.answer(2)
    poll_until(lambda: apps[0].rounds.tally() is not None and apps[0].rounds.tally().answered == 1, timeout=10.0)
    presenter.stop_presenting()
    poll_until(lambda: not student.question.folder.visible)
    poll_until(lambda: apps[0].ask_bus.redis.get(ROUND_KEY) is None, timeout=2.0)  # the source deletes it
    with pytest.raises(Refused):
        student.answer(1)
    newcomer = _join(workers, "w2")
    newcomer.present(CODE)
    poll_until(lambda: newcomer.ask_panel.folder.visible)
    assert newcomer.ask_panel.gui_ask.visible and not newcomer.ask_panel.gui_count.visible
    assert apps[1].rounds.shown() is None
    (ended,) = apps[0].rounds.earlier
    assert ended.why == "the presenter stopped" and ended.round_.tally().counts == (0, 0, 1)
    # the next presenter, on the other worker, downloads the ended round (saved at once)
    poll_until(lambda: newcomer.ask_panel.gui_earlier.visible, timeout=10.0)
    sent = _recorded_downloads(newcomer)
    newcomer.ask_panel.download_earlier()
    ((name, data, at_once),) = sent
    text = data.decode("utf-8")
    assert at_once and "ended: the presenter stopped" in text and "Which axis is stable?" in text, text
    rows = list(csv.DictReader(line for line in io.StringIO(text) if not line.startswith("#")))
    assert [row["option"] for row in rows] == ["3"]


def test_a_round_ends_on_the_other_workers_when_its_worker_is_killed(workers: Workers) -> None:
    """w1 is a real worker process (`python -m app --redis URL --worker-id w1`) whose presenter,
    a raw websocket, asks through its panel; w2's student sees the question.  SIGKILL w1: w2's
    student stops seeing it within a few seconds (the presenter lock's lease, the round key's
    TTL), and w2's next presenter gets the form."""
    from conftest import poll_until

    from app.cluster.askbus import ROUND_KEY, ROUND_LIVE_S
    from app.lecture.gate import LEASE_S

    with WorkerProcess(workers.url, CODE, "w1") as w1:
        w2 = workers.start("w2")
        student = _join(workers, "w2")
        lecturer = lecturer_presenting(w1.port, CODE)
        workers.clients.append(lecturer)
        lecturer.set_value("Question", "Which axis is stable?", "Text")
        lecturer.set_value("Options", "x | y | z", "Text")
        lecturer.click("Ask the class")
        poll_until(lambda: student.question.folder.visible, timeout=20.0)
        assert "Which axis is stable?" in student.question.gui_prompt.content
        student.answer(0)
        successor = _join(workers, "w2")  # explores before the kill (a killed worker's room cannot be copied)
        poll_until(lambda: successor.mode == "following", timeout=20.0)
        successor.explore()
        assert successor.mode == "own", successor.last_error
        redis = w2.ask_bus.redis
        w1.kill()
        killed = time.monotonic()
        poll_until(lambda: not student.question.folder.visible, timeout=3 * ROUND_LIVE_S)
        hidden_after = time.monotonic() - killed
        assert w2.rounds.shown() is None
        with pytest.raises(Refused):
            student.answer(1)
        assert hidden_after < LEASE_S + 2.0, f"the killed worker's round showed {hidden_after:.1f} s"
        poll_until(lambda: redis.get(ROUND_KEY) is None, timeout=ROUND_LIVE_S + 2.0)
        gone_after = time.monotonic() - killed
        assert gone_after < ROUND_LIVE_S + 2.0
        print(f"killed worker's round: hidden on w2 after {hidden_after:.2f} s, key gone after {gone_after:.2f} s")
        poll_until(lambda: w2.lectern.gate.presenter() is None, timeout=2 * LEASE_S)
        successor.present(CODE)
        poll_until(lambda: successor.ask_panel.folder.visible)
        assert successor.ask_panel.gui_ask.visible and not successor.ask_panel.gui_count.visible


def test_a_killed_workers_pointer_marker_leaves_the_other_workers_screens(workers: Workers) -> None:
    """The presenter on a points; b's followers see the marker.  a dies without a word (no
    removal said): once b takes it that the presenter left, the marker leaves b's shared scene
    (the rest stays, the last state)."""
    from conftest import poll_until
    from test_bus import _live_nodes, _present

    from app.lecture.follower import Hall
    from app.lecture.lectern import POINTER_ROOT

    a, b = workers.start("a"), workers.start("b")
    presenter = _present(workers, "a")
    follower_b, mirror_b = workers.connect("b")
    poll_until(lambda: follower_b.mode == "following" and b.lectern.hall is Hall.LIVE, timeout=10.0)
    a.lectern.point(presenter, (0.0, -6.0, 1.0), (0.0, 1.0, 0.0), "here")
    a.lectern.pointer.tick = lambda _dt: None  # the marker does not fade: a dies before it would

    def markers() -> list[str]:
        return [name for name in _live_nodes(mirror_b) if name.startswith(POINTER_ROOT + "/")]

    poll_until(lambda: markers(), timeout=10.0)
    assert any(name.startswith(POINTER_ROOT + "/") for name in b.bus.shared.applied.nodes())
    a.bus.source = False  # as if killed: no "left" said, no removal sent
    a.stop()
    del workers.apps["a"]
    poll_until(lambda: b.lectern.hall is Hall.LEFT, timeout=10.0)
    poll_until(lambda: not markers())
    assert _live_nodes(mirror_b), "the last state stays on b's screens"


@pytest.mark.parametrize("end", ["stop", "tab closed"])
def test_the_presenters_caption_plot_lesson_and_pointer_leave_the_followers(end: str) -> None:
    """Everything the presenter owns on the followers' screens but the last state of the room:
    the lesson caption, the plot tab's copy, the lesson step in the status, the pointer's marker,
    ends when it stops or closes its tab (the room itself stays, paused, with a note)."""
    from conftest import LectureHall, poll_until

    from app.lecture.lectern import FOLLOW_PERIOD, POINTER_ROOT

    frames = int(round(FOLLOW_PERIOD * 60)) + 2
    hall = LectureHall(CODE)
    try:
        presenter, presenter_client = hall.join_with_client()
        presenter.present(CODE)
        presenter.start_lesson("§6 The free body and the heavy top")
        for _ in range(2):
            presenter.next_step(1)  # "Watch ω_y′ change sign in the Plots tab"
        follower = hall.join()
        hall.frames(frames)
        hall.app.lectern.point(presenter, (0.0, -6.0, 1.0), (0.0, 1.0, 0.0), "here")
        panel = follower.scene
        nodes = hall.app.server.scene._handle_from_node_name

        def markers() -> list[str]:
            return [name for name in list(nodes) if name.startswith(POINTER_ROOT + "/")]

        step = presenter.lesson.steps[2].text
        assert panel.caption.text == step and panel.caption.handle.visible
        assert panel.plot.tab == "Plots" and panel.plot.copies
        assert "step 3/7" in hall.app.lectern.status() and markers()
        if end == "stop":
            presenter.stop_presenting()
        else:
            presenter_client.close()
            poll_until(lambda: hall.app.lectern.presenter is None, timeout=10.0)
        # Frames until the followers' panel is refreshed without them (on a busy machine the
        # refresh of a closed tab's end may come some frames later), up to a generous deadline.
        deadline = time.monotonic() + 20.0
        while time.monotonic() < deadline and (panel.caption.text or panel.plot.tab or panel.plot.copies):
            hall.frames(1)
        assert panel.caption.text == "" and not panel.caption.handle.visible, "the caption stayed"
        assert panel.plot.tab == "" and not panel.plot.copies, f"the plot copy stayed: {panel.plot.copies}"
        assert "step 3/7" not in hall.app.lectern.status(), "the lesson step stayed"
        assert not markers(), "the pointer's marker stayed"
        assert hall.app.lectern.live_room is not None and not hall.app.lectern.live_room.playing  # the last state
        assert follower.error_count == 0, follower.last_error
    finally:
        hall.close()
