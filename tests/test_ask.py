"""Ask the class (issue 26): the questions as data, a round's rules, its tally and CSV, and the
round across processes."""

from __future__ import annotations

import csv
import io
import time
from typing import Any

import pytest
from conftest import RawClient, poll_until, shared_hall_fixtures
from test_bus import Workers, workers_fixture

from app.ask import Choice, Direction, Refused, Round, State, new_token, question_from_dict, question_to_dict
from app.ask.round import RATE


class Clock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


CHOICE = {"kind": "choice", "prompt": "Which axis is stable?", "options": ["1", "2", "3"], "correct": 0}
DIRECTION = {"kind": "direction", "prompt": "Where does ω point?", "truth": [0, 0, 2]}


@pytest.mark.parametrize("bad, words", [
    ({"kind": "poll", "prompt": "x"}, "kind"),
    ({"kind": "choice", "prompt": "x", "options": ["a"]}, "options"),
    ({"kind": "choice", "prompt": "x", "options": ["a"] * 7}, "options"),
    ({"kind": "choice", "prompt": "x", "options": ["a", "a"]}, "same"),
    ({"kind": "choice", "prompt": "x", "options": ["a", "b"], "correct": 2}, "correct"),
    ({"kind": "choice", "prompt": "x", "options": ["a", "b"], "correct": True}, "correct"),
    ({"kind": "choice", "prompt": " ", "options": ["a", "b"]}, "prompt"),
    ({"kind": "choice", "prompt": "x" * 301, "options": ["a", "b"]}, "prompt"),
    ({"kind": "choice", "prompt": "x", "options": ["a", "b"], "colour": 1}, "colour"),
    ({"kind": "direction", "prompt": "x", "truth": [0, 0, 0]}, "truth"),
    ({"kind": "direction", "prompt": "x", "truth": [0, float("nan"), 1]}, "truth"),
    ({"kind": "direction", "prompt": "x", "frame": "body"}, "frame"),
    ({"kind": "state", "prompt": "x"}, "scene"),
    ("choice", "kind"),
])
def test_a_bad_question_is_refused_naming_its_field(bad: object, words: str) -> None:
    with pytest.raises(ValueError, match=words):
        question_from_dict(bad)


def test_questions_round_trip_through_their_dicts() -> None:
    state = {"kind": "state", "prompt": "Make it loop", "scene": "Heavy top", "judge": None, "target": {"a": 1}}
    for d in (CHOICE, DIRECTION, state):
        question = question_from_dict(d)
        assert question_from_dict(question_to_dict(question)) == question
    assert question_from_dict(DIRECTION).truth == (0.0, 0.0, 1.0)  # type: ignore[union-attr]
    assert isinstance(question_from_dict(CHOICE), Choice)
    assert isinstance(question_from_dict(state), State)


def test_one_answer_per_browser_the_last_counts_and_a_leaver_still_counts() -> None:
    clock = Clock()
    round_ = Round(CHOICE, clock=clock)
    a, b = new_token(), new_token()
    round_.answer(a, 1)
    round_.answer(b, 2)
    clock.t += 1.0
    round_.answer(a, 0)  # a changes its mind
    assert round_.tally().counts == (1, 0, 1) and round_.tally().answered == 2
    assert round_.answer_of(a).value == 0  # type: ignore[union-attr]


def test_bad_answers_are_refused_with_a_message_and_change_nothing() -> None:
    clock = Clock()
    round_ = Round(CHOICE, clock=clock)
    round_.answer("a", 1)
    for bad in (3, -1, True, "1", None, [1], 1.0, {"x": 1}):
        clock.t += 1.0
        with pytest.raises(Refused, match="not an answer"):
            round_.answer("a", bad)
    assert round_.tally().counts == (0, 1, 0)
    directions = Round(DIRECTION, clock=clock)
    for bad in ([0, 0, 0], [1, 2], ["a", 0, 0], [float("inf"), 0, 0], "up", [True, 0, 0]):
        clock.t += 1.0
        with pytest.raises(Refused):
            directions.answer("a", bad)
    assert directions.tally().answered == 0
    directions.answer("a", [0, 3, 4])
    assert directions.tally().directions == ((0.0, 0.6, 0.8),)


def test_a_browser_answers_at_most_RATE_times_a_second() -> None:
    clock = Clock()
    round_ = Round(CHOICE, clock=clock)
    for _ in range(RATE):
        round_.answer("a", 1)
    with pytest.raises(Refused, match="too fast"):
        round_.answer("a", 2)
    assert round_.tally().counts == (0, 1, 0)
    round_.answer("b", 2)  # another browser is not slowed by it
    clock.t += 1.0
    round_.answer("a", 2)
    assert round_.tally().counts == (0, 0, 2)


def test_a_round_is_bounded_and_a_closed_round_takes_nothing() -> None:
    round_ = Round(CHOICE, clock=Clock(), max_browsers=3)
    for token in "abc":
        round_.answer(token, 0)
    with pytest.raises(Refused, match="full"):
        round_.answer("d", 0)
    round_.answer("a", 1)  # an answer already in may still change
    round_.close()
    with pytest.raises(Refused, match="closed"):
        round_.answer("b", 1)
    assert round_.tally().counts == (2, 1, 0) and not round_.tally().open


def test_vote_again_keeps_the_first_result_beside_the_second_and_the_csv_is_anonymous() -> None:
    clock = Clock()
    first = Round(CHOICE, clock=clock)
    tokens = [new_token() for _ in range(3)]
    for token, option in zip(tokens, (1, 1, 0), strict=True):
        first.answer(token, option)
    second = first.vote_again()
    assert not first.open and second.open and second.number == 2
    for token in tokens:
        second.answer(token, 0)
    tally = second.tally()
    assert tally.counts == (3, 0, 0) and tally.previous is not None and tally.previous.counts == (1, 2, 0)
    text = second.csv()
    assert not any(token in text for token in tokens)
    rows = list(csv.DictReader(io.StringIO("\n".join(line for line in text.splitlines()
                                                        if not line.startswith("#")))))
    assert [(r["round"], r["option"]) for r in rows] == [("1", "2"), ("1", "2"), ("1", "1"),
                                                        ("2", "1"), ("2", "1"), ("2", "1")]
    assert text.startswith("# choice: Which axis is stable?")


def test_direction_tally_counts_answers_near_the_truth() -> None:
    round_ = Round(DIRECTION, clock=Clock())
    round_.answer("a", [0, 0, 1])
    round_.answer("b", [0, 0.2, 1])  # 11° off
    round_.answer("c", [1, 0, 0])
    tally = round_.tally()
    assert tally.within(5.0) == 1 and tally.within(15.0) == 2
    assert isinstance(tally.question, Direction)


def test_state_answers_are_bounded_dicts_of_numbers() -> None:
    round_ = Round({"kind": "state", "prompt": "Make it loop", "scene": "Heavy top"}, clock=Clock())
    round_.answer("a", {"theta": 0.5, "psi_dot": 20})
    for bad in ({}, {"x": float("nan")}, {"x": [1]}, {str(k): 1 for k in range(65)}, [1, 2]):
        with pytest.raises(Refused):
            round_.answer("b", bad)
    assert round_.tally().answered == 1 and round_.tally().judged == (None,)


def test_the_apps_rounds_ask_close_vote_again_and_forward_remote_answers() -> None:
    from app.ask import Rounds

    here, there = Rounds(), Rounds()
    round_ = here.ask(CHOICE)
    here.answer("a", 2)
    shown = here.shown()
    assert shown is not None and shown.open and shown.answered == 1 and shown.number == 1
    sent: list[tuple[str, str, object]] = []
    there.forward = lambda rid, token, value: sent.append((rid, token, value))
    there.set_remote(shown)
    assert there.answer("b", 1) == 1 and there.mine("b") == 1
    with pytest.raises(Refused, match="not an answer"):
        there.answer("b", 7)
    for rid, token, value in sent:
        assert rid == here.current_id
        here.current.answer(token, value)  # type: ignore[union-attr]  # what the bus does on the asking process
    assert here.tally().counts == (0, 1, 1)  # type: ignore[union-attr]
    second = here.vote_again()
    assert second is here.current and round_.open is False and here.tally().previous.counts == (0, 1, 1)  # type: ignore[union-attr]
    here.close_round()
    there.set_remote(here.shown())
    with pytest.raises(Refused, match="closed"):
        there.answer("b", 0)
    here.end()
    assert here.shown() is None and here.csv() == ""


# ---------------------------------------------------------------------- the app: presenter, students, panels
HALL_CODE = "864213"


_one_hall, hall = shared_hall_fixtures(HALL_CODE)  # one app for this file's tests (its start is the slow part)
workers = workers_fixture(HALL_CODE)  # the apps across workers, on one redis-server for the module (`redis_url`)


def _frames(hall: Any, count: int = 2) -> None:
    for _ in range(count):
        hall.app.frame(1.0 / 60.0)


def _frames_until(hall: Any, predicate: Any, timeout: float = 30.0) -> None:
    """Frames of the loop until `predicate()` (a browser's callback may hold its panel a moment)."""
    from conftest import poll_until

    poll_until(lambda: _frames(hall, 4) or predicate(), timeout=timeout)


def test_the_presenter_asks_students_answer_through_their_panels_and_the_count_is_live(hall: Any) -> None:
    from conftest import poll_until
    from viser import _messages

    presenter = hall.join()
    presenter.present(HALL_CODE)
    (alice, alice_client), (bob, _) = hall.join_with_client(), hall.join_with_client()
    _frames(hall)
    assert alice.mode == "following" and not alice.question.folder.visible
    with pytest.raises(PermissionError):
        alice.ask(CHOICE)
    presenter.ask(CHOICE)
    _frames_until(hall, lambda: alice.question.folder.visible)
    assert not alice.scene.folder.visible  # the question replaces the follower panel
    assert "Which axis is stable?" in alice.question.gui_prompt.content
    # Alice presses option 2 in her page (a raw websocket sends what the page sends).
    alice_client.send(_messages.GuiUpdateMessage(alice.question.gui_options[1]._impl.uuid, {"value": True}))
    poll_until(lambda: hall.app.rounds.tally().answered == 1)
    bob.answer(2)
    _frames_until(hall, lambda: "2 of 2 answered" in presenter.ask_panel.gui_count.content)  # at ASK_PERIOD
    assert hall.app.rounds.tally().counts == (0, 1, 1)
    assert "█" in presenter.ask_panel.gui_histogram.content
    # answered: the follower panel is back, with her answer
    assert alice.scene.folder.visible and "2. 2" in alice.question.gui_mine.content
    second = presenter.vote_again()
    _frames_until(hall, lambda: alice.question.gui_options[0].visible)  # asked again: her controls are back
    assert second.number == 2 and "round 1: 1" in presenter.ask_panel.gui_histogram.content
    presenter.close_round()
    _frames_until(hall, lambda: "closed" in alice.question.gui_prompt.content)
    assert not alice.question.gui_options[0].visible
    assert alice.error_count == 0 and presenter.error_count == 0
    presenter.ask_panel.download()  # the CSV offered to the presenter's browser
    assert presenter.error_count == 0, presenter.last_error
    with pytest.raises(PermissionError):  # nobody else's panel downloads it
        alice.ask_panel._check()
    # An answer counts after its student leaves.
    counts = hall.app.rounds.tally().counts
    alice_client.close()
    poll_until(lambda: alice.closed, timeout=10.0)
    assert hall.app.rounds.tally().counts == counts and hall.app.rounds.tally().previous.counts == (0, 1, 1)


def test_a_lesson_steps_question_fills_the_presenters_form(hall: Any) -> None:
    presenter = hall.join()
    presenter.present(HALL_CODE)
    presenter.start_lesson("§6 The free body and the heavy top")
    presenter.next_step(1)  # step 1: where will ω point (a direction, with its truth)
    panel = presenter.ask_panel
    assert panel.gui_kind.value == "Direction" and "Where will ω point" in panel.gui_prompt.value
    assert panel.gui_truth.visible and panel.gui_truth.value.startswith("0.287")
    panel.ask_from_form()
    assert hall.app.rounds.current.question.truth[2] == pytest.approx(0.958, abs=1e-3)  # type: ignore[union-attr]
    assert presenter.error_count == 0, presenter.last_error


# ---------------------------------------------------------------------- across processes (app.cluster.askbus)
def test_the_tally_is_the_same_whichever_worker_the_students_are_on(workers: Workers) -> None:
    """Two in-process workers on a real redis-server: a presenter and a student on w1, two
    students on w2 (one answering by pressing its option in its panel); the tally on w1 counts
    all three, once each; closing the round closes it on w2."""
    from viser import _messages

    apps = [workers.start("w1"), workers.start("w2")]

    def join(worker: str) -> tuple[Any, Any]:
        return workers.connect(worker, RawClient)

    presenter, _ = join("w1")
    presenter.present(HALL_CODE)
    (a, _), (b, b_client), (c, _) = join("w1"), join("w2"), join("w2")
    presenter.ask(CHOICE)
    poll_until(lambda: b.question.folder.visible and c.question.folder.visible, timeout=10.0)
    a.answer(0)
    b_client.send(_messages.GuiUpdateMessage(b.question.gui_options[2]._impl.uuid, {"value": True}))
    poll_until(lambda: b.my_answer() == 2, timeout=10.0)
    c.answer(1)
    c.answer(2)  # changes its mind: counted once, the last
    poll_until(lambda: apps[0].rounds.tally().answered == 3, timeout=10.0)
    time.sleep(3 * 0.1)  # three more polls: nothing more arrives
    assert apps[0].rounds.tally().counts == (1, 0, 2)
    poll_until(lambda: "3 of 3 answered" in presenter.ask_panel.gui_count.content)
    presenter.close_round()
    poll_until(lambda: "closed" in b.question.gui_prompt.content, timeout=10.0)
    with pytest.raises(Refused, match="closed"):
        c.answer(0)
    assert b.error_count == 0 and presenter.error_count == 0, (b.last_error, presenter.last_error)


def test_a_state_question_is_answered_from_the_students_own_copy(hall: Any) -> None:
    from viser import _messages

    presenter = hall.join()
    presenter.present(HALL_CODE)
    presenter.select_scene("Heavy top")
    student, client = hall.join_with_client()
    _frames(hall)
    presenter.ask({"kind": "state", "prompt": "Find a start that makes the top loop", "scene": "Heavy top"})
    panel = student.question
    _frames_until(hall, lambda: panel.gui_from_copy.visible)
    assert not panel.gui_send_state.visible
    with pytest.raises(PermissionError):  # following: there is no copy of its own yet
        student.state_answer()
    client.send(_messages.GuiUpdateMessage(panel.gui_from_copy._impl.uuid, {"value": True}))  # Answer from my copy
    from conftest import poll_until

    poll_until(lambda: student.mode == "own" and panel.gui_send_state.visible, timeout=10.0)
    assert student.room is not presenter.room and student.room.scene.title == "Heavy top"
    client.send(_messages.GuiUpdateMessage(panel.gui_send_state._impl.uuid, {"value": True}))  # Send my state
    poll_until(lambda: hall.app.rounds.tally().answered == 1, timeout=10.0)
    assert "t" in hall.app.rounds.mine(student.answer_token)
    poll_until(lambda: "your state" in panel.gui_mine.content, timeout=10.0,  # the panel shows it after the tally
               what="the student's panel saying 'your state'", seen=lambda: panel.gui_mine.content)
    assert student.error_count == 0, student.last_error
