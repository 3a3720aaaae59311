"""The number question (issue 35): a value with a unit and a tolerance, one kind behind the
question protocol: its check, dict, tally, CSV, the panels and two workers."""

from __future__ import annotations

import csv
import io
import math
import time
from typing import Any

import pytest
from conftest import RawClient, hall_fixture, poll_until
from test_ask import Clock
from test_bus import Workers, workers_fixture

from app.ask import Refused, Round, question_from_dict, question_to_dict
from app.ask.questions import KINDS, Number

FLIP = {"kind": "number", "prompt": "The flip period?", "value": 2.5, "unit": "s", "tolerance": 0.2}
HALL_CODE = "864299"


def test_a_number_question_round_trips_through_its_dict_and_is_registered() -> None:
    question = question_from_dict(FLIP)
    assert isinstance(question, Number) and KINDS["number"] is Number
    assert question_to_dict(question) == {**FLIP, "value": 2.5, "tolerance": 0.2}
    assert question_from_dict(question_to_dict(question)) == question
    bare = question_from_dict({"kind": "number", "prompt": "Guess"})  # no right value: only collected
    assert question_from_dict(question_to_dict(bare)) == bare and not bare.has_truth


@pytest.mark.parametrize("bad, words", [
    ({**FLIP, "value": float("nan")}, "value"),
    ({**FLIP, "value": float("inf")}, "value"),
    ({**FLIP, "value": "2.5"}, "value"),
    ({**FLIP, "value": 10 ** 400}, "value"),
    ({**FLIP, "tolerance": -1.0}, "tolerance"),
    ({**FLIP, "tolerance": float("nan")}, "tolerance"),
    ({**FLIP, "unit": "s" * 21}, "unit"),
    ({**FLIP, "unit": 3}, "unit"),
    ({**FLIP, "options": ["a", "b"]}, "options"),
])
def test_a_bad_number_question_is_refused_naming_its_field(bad: dict[str, Any], words: str) -> None:
    with pytest.raises(ValueError, match=words):
        question_from_dict(bad)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf"), "2.5", 10 ** 400, True, None, [2.5],
                                 1e13])
def test_a_bad_number_answer_is_refused_with_a_message_and_changes_nothing(bad: object) -> None:
    round_ = Round(FLIP, clock=Clock())
    round_.answer("kept", 2.4)
    before = (round_.tally(), round_.rows(), round_.version)
    with pytest.raises(Refused, match="not an answer: answer: .*number"):
        round_.answer("kept", bad)
    with pytest.raises(Refused, match="number"):
        round_.answer("other", bad)
    assert (round_.tally(), round_.rows(), round_.version) == before


def test_a_number_is_right_within_its_tolerance_and_the_tally_is_a_histogram() -> None:
    question = question_from_dict(FLIP)
    assert isinstance(question, Number)
    assert question.right(2.7) and question.right(2.3) and question.right(2.5)
    assert not question.right(2.71) and not question.right(2.29)
    clock = Clock()
    round_ = Round(question, clock=clock)
    for k, value in enumerate((2.4, 2.5, 2.6, 3.4, 1, 2.45)):
        clock.t += 1.0
        round_.answer(f"t{k}", value)
    tally = round_.tally()
    assert tally.answered == 6 and sorted(tally.values) == [1.0, 2.4, 2.45, 2.5, 2.6, 3.4]
    hidden = question.tally_text(tally, revealed=False)
    shown = question.tally_text(tally, revealed=True)
    assert "█" in hidden and "✓" not in hidden and "4 of 6" not in hidden
    assert "**4 of 6** within ±0.2 s of 2.5 s" in shown and "✓" in shown
    bins = question.bins(tally.values)
    assert len(bins) == 4 and sum(n for _, _, n in bins) == 6  # 1 + log2(6) bins, every answer in one
    assert bins[0][:2] == (1.0, 1.6) and bins[-1][2] == 1  # 1.0 in the first, 3.4 alone in the last
    again = round_.vote_again()
    again.answer("t0", 2.5)
    assert "round 1: 6 answers" in question.tally_text(again.tally(), revealed=False)


def test_the_number_csv_has_each_answer_its_error_and_whether_it_is_right() -> None:
    clock = Clock()
    round_ = Round(FLIP, clock=clock)
    clock.t += 1.5
    round_.answer("a", 2.6)
    clock.t += 1.0
    round_.answer("b", 3)
    text = round_.csv()
    lines = text.splitlines()
    assert lines[0] == "# number: The flip period?" and lines[1] == "# right: 2.5 s ± 0.2 s"
    rows = list(csv.DictReader(io.StringIO("\n".join(lines[2:]))))
    assert [(r["answer"], r["seconds"], r["value"], r["judged_words"]) for r in rows] == [
        ("1", "1.50", "2.6", "right"), ("2", "2.50", "3", "wrong")]
    assert math.isclose(float(rows[0]["judged"]), 0.1) and float(rows[1]["judged"]) == 0.5
    assert "a" not in {r["value"] for r in rows} and "token" not in text


def test_every_kind_is_registered_once_with_its_panels() -> None:
    from app.hall.ask_kinds import PANELS
    from app.hall.ask_presenter import LABELS

    assert list(PANELS) == list(KINDS) and len(LABELS) == len(KINDS)
    for kind, cls in KINDS.items():
        assert cls.kind == kind and "kind" in cls.FIELDS


# ---------------------------------------------------------------------- the app: the presenter's form, the panels
hall = hall_fixture(HALL_CODE)
workers = workers_fixture(HALL_CODE)  # the apps across workers, on one redis-server for the module (`redis_url`)


def _frames_until(hall: Any, predicate: Any, timeout: float = 20.0) -> None:
    from conftest import poll_until

    def step() -> bool:
        for _ in range(4):
            hall.app.frame(1.0 / 60.0)
        return bool(predicate())

    poll_until(step, timeout=timeout)


def test_the_presenter_asks_a_number_two_students_answer_and_the_tally_and_csv_are_right(hall: Any) -> None:
    from viser import _messages

    presenter = hall.join()
    presenter.present(HALL_CODE)
    (alice, alice_client), (bob, _) = hall.join_with_client(), hall.join_with_client()
    panel = presenter.ask_panel
    panel.gui_kind.value = "Number"  # the presenter's form: the kind, its value, unit and tolerance
    panel._kind_shown()
    form = panel.forms["number"]
    assert form.gui_value.visible and form.gui_unit.visible and not panel.gui_options.visible
    panel.gui_prompt.value = "The flip period?"
    form.gui_value.value, form.gui_unit.value, form.gui_tolerance.value = "2.5", "s", "nan"
    with pytest.raises(ValueError, match="tolerance"):  # bad input in the form: said, nothing asked
        panel.ask_from_form()
    assert hall.app.rounds.current is None
    form.gui_tolerance.value = "0.2"
    panel.ask_from_form()
    current = hall.app.rounds.current
    assert current is not None and current.question == question_from_dict(FLIP)
    _frames_until(hall, lambda: alice.question.gui_number.visible and bob.question.gui_send_number.visible)
    assert alice.question.gui_number.label == "Your answer [s]" and not alice.question.gui_options[0].visible
    # Alice types 2.6 in her number box and presses Send my number (what her page sends).
    alice_client.send(_messages.GuiUpdateMessage(alice.question.gui_number._impl.uuid, {"value": 2.6}))
    _frames_until(hall, lambda: alice.question.gui_number.value == 2.6)
    alice_client.send(_messages.GuiUpdateMessage(alice.question.gui_send_number._impl.uuid, {"value": True}))
    _frames_until(hall, lambda: alice.my_answer() == 2.6)
    with pytest.raises(Refused, match="finite"):
        bob.answer(float("inf"))
    bob.answer(3.1)
    _frames_until(hall, lambda: "2 of 2 answered" in panel.gui_count.content)
    assert sorted(hall.app.rounds.tally().values) == [2.6, 3.1]
    assert "█" in panel.gui_histogram.content and "Your answer: **2.6 s**" in alice.question.gui_mine.content
    assert panel.gui_reveal.visible
    hall.app.rounds.reveal(True)  # Reveal the answer
    _frames_until(hall, lambda: "**1 of 2** within ±0.2 s of 2.5 s" in panel.gui_histogram.content)
    rows = list(csv.DictReader(io.StringIO("\n".join(hall.app.rounds.csv().splitlines()[2:]))))
    assert sorted((r["value"], r["judged_words"]) for r in rows) == [("2.6", "right"), ("3.1", "wrong")]
    assert presenter.error_count == 0 and alice.error_count == 0, (presenter.last_error, alice.last_error)
    presenter.ask_panel.fill(question_from_dict({**FLIP, "value": 7.0}))  # a lesson's number question
    assert panel.gui_kind.value == "Number" and form.gui_value.value == "7"


# ---------------------------------------------------------------------- across processes (app.cluster.askbus)
def test_a_number_answer_on_worker_b_reaches_the_tally_on_worker_a(workers: Workers) -> None:
    apps = [workers.start("w1"), workers.start("w2")]

    def join(worker: str) -> Any:
        return workers.connect(worker, RawClient)[0]

    presenter = join("w1")
    presenter.present(HALL_CODE)
    a, b = join("w1"), join("w2")
    presenter.ask(FLIP)
    poll_until(lambda: b.question.gui_number.visible, timeout=15.0)
    shown = apps[1].rounds.shown()
    assert shown is not None and shown.question == question_from_dict(FLIP)  # came over the bus whole
    a.answer(2.45)
    b.answer(2.9)
    with pytest.raises(Refused, match="finite"):
        b.answer(float("nan"))
    poll_until(lambda: apps[0].rounds.tally().answered == 2, timeout=15.0)
    time.sleep(0.3)  # three more polls: nothing more arrives
    assert sorted(apps[0].rounds.tally().values) == [2.45, 2.9]
    assert b.error_count == 0 and presenter.error_count == 0, (b.last_error, presenter.last_error)
