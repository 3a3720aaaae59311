"""Tasks between lectures (issue 37), without a browser: the model (attempts, best or last, due
time, expiry, names), the SQLite store's rules (rate, receipts, one name per browser), the
gradebook's CSV and what survives a reopen (a restart)."""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from app.ask.round import RateLimit
from app.tasks.model import (
    Policy,
    TaskCodeError,
    TaskRefused,
    check_student,
    gradebook_csv,
    gradebook_rows,
    normalize_task_code,
    verdict,
)
from app.tasks.store import RATE, SqliteTaskStore, TaskRules

NUMBER = {"kind": "number", "prompt": "The flip period?", "value": 2.5, "unit": "s", "tolerance": 0.2}
CHOICE = {"kind": "choice", "prompt": "Which axis is unstable?", "options": ["smallest", "middle", "largest"],
          "correct": 1}
HOUR = 3600.0
T0 = 1_800_000_000.0  # [s since the epoch] 2027-01-15


class Clock:
    """A wall clock a test moves [s since the epoch]."""

    def __init__(self) -> None:
        self.t = T0

    def __call__(self) -> float:
        return self.t


class Tick:
    """A monotonic clock for the rate limit [s]."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


@pytest.fixture(params=["sqlite", "redis"])
def store_at(request: pytest.FixtureRequest, tmp_path: Path) -> Callable[..., TaskRules]:
    """(clock, tick=None) -> a store (SQLite in tmp_path, or Redis) on the same data each time (a reopen)."""
    def opener(clock: Clock, tick: Tick | None = None) -> TaskRules:
        rate = RateLimit(RATE, 10.0, clock=tick or Tick())
        if request.param == "sqlite":
            return SqliteTaskStore(tmp_path / "tasks.sqlite3", clock=clock, rate=rate)
        from app.tasks.redis_store import RedisTaskStore

        return RedisTaskStore(request.getfixturevalue("redis_url"), clock=clock, rate=rate)

    return opener


@pytest.fixture
def clock() -> Clock:
    return Clock()


@pytest.fixture
def store(store_at: Callable[..., TaskRules], clock: Clock) -> Iterator[TaskRules]:
    s = store_at(clock)
    yield s
    s.close()


# ---------------------------------------------------------------------- the model
def test_a_task_code_is_typed_with_the_share_codes_forgiveness() -> None:
    assert normalize_task_code(" k7m2-qx9p ") == "K7M2QX9P"
    assert normalize_task_code("K7M2 QX9P") == normalize_task_code("k7m2qx9p")
    assert normalize_task_code("1O1L-0000") == "10110000"  # O for 0, I and L for 1
    for bad in ("K7M2", "K7M2-QX9PZ", "U7M2-QX9P", 42, "x" * 10_000):
        with pytest.raises(TaskCodeError, match="not a task code"):
            normalize_task_code(bad)


@pytest.mark.parametrize("name, number, words", [
    ("x" * 10_000, "", "Name: at most 80"),
    ("Ann\x00", "", "control"),
    ("Ann\u202eevil", "", "control"),
    ("Ann\nBee", "", "control"),
    ("", "1234\x1b[2J", "control"),
    ("", "9" * 100, "Student number: at most 32"),
    ("  ", "", "give your name or your student number"),
    (["Ann"], "", "Name: a text"),
])
def test_a_bad_name_is_refused_with_a_clear_message(name: Any, number: Any, words: str) -> None:
    with pytest.raises(TaskRefused, match=words):
        check_student(name, number)


def test_a_student_is_known_by_the_number_else_the_name_case_and_spacing_aside() -> None:
    assert check_student("Ann  Lee", "").key == check_student("ann lee", "").key
    assert check_student("Ann", "s 123").key == check_student("Bea", "S123").key == "number:s123"


def test_verdicts_are_worded_by_the_kind_and_scored() -> None:
    from app.ask.questions import question_from_dict

    number = question_from_dict(NUMBER)
    assert verdict(number, 2.6) == (1.0, "2.6 s: right")
    assert verdict(number, 3.0) == (0.0, "3 s: wrong")
    choice = question_from_dict(CHOICE)
    assert verdict(choice, 1) == (1.0, "2. middle: right")
    assert verdict(question_from_dict({**CHOICE, "correct": None}), 0)[0] is None
    direction = question_from_dict({"kind": "direction", "prompt": "Where?", "truth": [0, 0, 1]})
    assert verdict(direction, (0.0, 0.0, 1.0)) == (1.0, "0° from the true direction: right")
    assert verdict(direction, (1.0, 0.0, 0.0))[0] == 0.0


def test_a_policy_is_checked() -> None:
    assert Policy(None, "last").words() == "unlimited attempts, the last counts"
    for bad in (0, -1, 101, True, 2.5):
        with pytest.raises(TaskRefused, match="attempts"):
            Policy(bad)
    with pytest.raises(TaskRefused, match="counts"):
        Policy(2, "first")


# ---------------------------------------------------------------------- the store's rules
def test_one_attempt_is_one_and_a_second_is_refused_saying_so(store: TaskRules, clock: Clock) -> None:
    task = store.create(NUMBER, due=T0 + HOUR, attempts=1)
    first = store.submit(task.shown_code.lower(), "tok-a", "Ann", "", 0, 2.4)
    assert first.score == 1.0 and first.words == "2.4 s: right" and first.attempt == 1
    with pytest.raises(TaskRefused, match="used your 1 attempt"):
        store.submit(task.code, "tok-a", "Ann", "", 0, 2.5)
    assert [s.receipt for s in store.submissions(task.code)] == [first.receipt]


def test_n_attempts_best_or_last_counts(store_at: Callable[..., TaskRules], clock: Clock) -> None:
    store = store_at(clock)
    best = store.create(NUMBER, due=T0 + HOUR, attempts=3, counts="best")
    last = store.create(NUMBER, due=T0 + HOUR, attempts=3, counts="last")
    for task in (best, last):
        for value in (2.5, 9.0, 9.0):
            clock.t += 1.0
            store.submit(task.code, f"tok-{task.code}", "Ann", "", 0, value)
        with pytest.raises(TaskRefused, match="used your 3 attempts"):
            store.submit(task.code, f"tok-{task.code}", "Ann", "", 0, 2.5)
    (row_best,) = gradebook_rows(best, store.submissions(best.code))
    (row_last,) = gradebook_rows(last, store.submissions(last.code))
    assert (row_best.score, row_best.attempts, row_best.verdict) == (1.0, 3, "2.5 s: right")
    assert (row_last.score, row_last.attempts, row_last.verdict) == (0.0, 3, "9 s: wrong")
    store.close()


def test_unlimited_attempts_are_limited_only_by_the_rate(store_at: Callable[..., TaskRules], clock: Clock) -> None:
    tick = Tick()
    store = store_at(clock, tick)
    task = store.create(NUMBER, due=T0 + HOUR, attempts=None)
    for _ in range(3 * RATE):
        tick.t += 10.0 / RATE + 0.01  # at the allowed pace: every one is kept
        store.submit(task.code, "tok-a", "Ann", "", 0, 1.0)
    assert len(store.submissions(task.code)) == 3 * RATE
    store.close()


def test_ten_thousand_submissions_from_one_socket_count_once_per_allowed_attempt(
        store_at: Callable[..., TaskRules], clock: Clock) -> None:
    tick = Tick()
    store = store_at(clock, tick)
    limited = store.create(NUMBER, due=T0 + HOUR, attempts=2)
    unlimited = store.create(NUMBER, due=T0 + HOUR, attempts=None)
    refusals: dict[str, int] = {}
    for k in range(10_000):
        tick.t = k * 0.001  # ten seconds in all
        for task in (limited, unlimited):
            try:
                store.submit(task.code, "tok-hostile", "Mallory", "", 0, 2.5)
            except TaskRefused as error:
                refusals[str(error).split(":")[0]] = refusals.get(str(error).split(":")[0], 0) + 1
    assert len(store.submissions(limited.code)) == 2  # once per allowed attempt
    assert len(store.submissions(unlimited.code)) <= 2 * RATE  # the browser's rate, over both tasks
    assert "You have used your 2 attempts" in refusals and "Too many submissions from this browser" in refusals, \
        refusals
    store.close()


def test_a_submission_after_the_due_time_is_refused_with_a_clear_message(store: TaskRules,
                                                                       clock: Clock) -> None:
    task = store.create(NUMBER, due=T0 + HOUR)
    clock.t = T0 + HOUR
    with pytest.raises(TaskRefused, match=r"was due 2027-01-15 \d\d:\d\d UTC: a submission after the due time"):
        store.submit(task.code, "tok-a", "Ann", "", 0, 2.5)
    assert store.submissions(task.code) == []
    store.extend(task.code, T0 + 2 * HOUR)  # the lecturer extends it: open again
    assert store.submit(task.code, "tok-a", "Ann", "", 0, 2.5).score == 1.0
    store.close_task(task.code)
    with pytest.raises(TaskRefused, match="closed by the lecturer"):
        store.submit(task.code, "tok-b", "Bea", "", 0, 2.5)


def test_a_wrong_or_expired_code_opens_nothing(store: TaskRules, clock: Clock) -> None:
    task = store.create(NUMBER, due=T0 + HOUR, expire_after_s=24 * HOUR)
    with pytest.raises(TaskCodeError, match="No task has the code"):
        store.task("ZZZZ-ZZZZ" if task.code != "ZZZZZZZZ" else "YYYY-YYYY")
    clock.t = T0 + 25 * HOUR
    with pytest.raises(TaskCodeError, match="expired on 2027-01-16"):
        store.task(task.code)
    with pytest.raises(TaskCodeError, match="expired"):
        store.submit(task.code, "tok-a", "Ann", "", 0, 2.5)


def test_bad_answers_and_questions_change_nothing(store: TaskRules) -> None:
    task = store.create([NUMBER, CHOICE], due=T0 + HOUR, attempts=1)
    for question, value, words in ((0, float("nan"), "Not an answer"), (0, "2.5", "Not an answer"),
                                   (1, 7, "Not an answer"), (2, 1, "question: 1 to 2"),
                                   (-1, 1, "question"), (True, 1, "question")):
        with pytest.raises(TaskRefused, match=words):
            store.submit(task.code, "tok-a", "Ann", "", question, value)
    assert store.submissions(task.code) == [] and store.student(task.code, "tok-a") is None


def test_a_name_is_given_once_per_task_and_another_browser_cannot_take_it(store: TaskRules) -> None:
    task = store.create(NUMBER, due=T0 + HOUR, attempts=None)
    store.submit(task.code, "tok-a", "Ann", "", 0, 9.0)
    # the same browser keeps its name whatever it types later
    assert store.submit(task.code, "tok-a", "Someone else", "", 0, 2.5).student.name == "Ann"
    with pytest.raises(TaskRefused, match="ann already answers this task from another browser"):
        store.submit(task.code, "tok-b", "ann", "", 0, 2.5)
    assert {s.student.name for s in store.submissions(task.code)} == {"Ann"}
    assert [s.value for s in store.mine(task.code, "tok-b")] == []  # nothing of Ann's
    assert [s.value for s in store.mine(task.code, "tok-a")] == [9.0, 2.5]


def test_a_receipt_shows_its_submission_later(store: TaskRules) -> None:
    task = store.create(NUMBER, due=T0 + HOUR)
    submission = store.submit(task.code, "tok-a", "", "s1234", 0, 2.5)
    shown = submission.receipt[:4].lower() + " - " + submission.receipt[4:]
    assert store.receipt(shown) == submission
    with pytest.raises(TaskCodeError, match="not a receipt code"):
        store.receipt("xyz")


def test_the_gradebook_csv_has_one_row_a_student(store: TaskRules, clock: Clock) -> None:
    task = store.create([NUMBER, CHOICE], due=T0 + HOUR, attempts=2, counts="best")
    clock.t += 60
    store.submit(task.code, "tok-a", "Ann Lee", "s1", 0, 2.5)
    clock.t += 60
    store.submit(task.code, "tok-a", "", "", 1, 0)
    clock.t += 60
    store.submit(task.code, "tok-a", "", "", 1, 1)
    clock.t += 60
    store.submit(task.code, "tok-b", "=HYPERLINK(1)", "", 0, 3.0)
    rows = list(csv.reader(io.StringIO(gradebook_csv(task, store.submissions(task.code)))))
    assert rows[0] == ["name", "number", "score", "attempts", "last_submitted", "verdict"]
    assert rows[1] == ["Ann Lee", "s1", "1.000", "2", "2027-01-15T08:03:00+00:00",
                       "Q1: 2.5 s: right; Q2: 2. middle: right"]
    assert rows[2] == ["'=HYPERLINK(1)", "", "0.000", "1", "2027-01-15T08:04:00+00:00",
                       "Q1: 3 s: wrong; Q2: not answered"]
    assert len(rows) == 3


def test_tasks_and_submissions_survive_a_reopen(store_at: Callable[..., TaskRules], clock: Clock) -> None:
    before = store_at(clock)
    task = before.create([NUMBER, CHOICE], due=T0 + HOUR, attempts=1, scene="Heavy top", words="Do it at home.")
    kept = before.submit(task.code, "tok-a", "Ann", "", 0, 2.5)
    before.close()
    after = store_at(clock)  # a restart
    assert after.task(task.code) == task
    assert after.submissions(task.code) == [kept] and after.receipt(kept.receipt) == kept
    with pytest.raises(TaskRefused, match="used your 1 attempt at question 1"):
        after.submit(task.code, "tok-a", "Ann", "", 0, 2.5)  # the attempt still counts
    assert after.student(task.code, "tok-a") == kept.student
    after.close()


def test_a_bad_task_is_refused_naming_what(store: TaskRules) -> None:
    with pytest.raises(TaskRefused, match="due: the due time has passed"):
        store.create(NUMBER, due=T0 - 1)
    with pytest.raises(ValueError, match="prompt"):
        store.create({**NUMBER, "prompt": ""}, due=T0 + HOUR)
    with pytest.raises(TaskRefused, match="questions: 1 to 20"):
        store.create([], due=T0 + HOUR)
    with pytest.raises(TaskRefused, match="words: at most"):
        store.create(NUMBER, due=T0 + HOUR, words="w" * 10_000)


def test_the_apps_own_redis_keeps_tasks_across_its_restart(tmp_path: Path, clock: Clock) -> None:
    """`--workers` starts redis-server with its append-only file in the data folder: a task and
    its submissions are there after redis-server itself restarted."""
    from app.cluster import services
    from app.tasks.redis_store import RedisTaskStore

    try:
        url, process = services.start_redis(keep_in=tmp_path / "redis")
    except services.MissingProgram as error:
        pytest.skip(str(error))
    try:
        store = RedisTaskStore(url, clock=clock)
        task = store.create([NUMBER, CHOICE], due=T0 + HOUR, attempts=1)
        kept = store.submit(task.code, "tok-a", "Ann", "", 1, 1)
        store.close()
    finally:
        services.stop_process(process)
    assert any((tmp_path / "redis").rglob("*.aof")), "no append-only file"
    url, process = services.start_redis(keep_in=tmp_path / "redis")
    try:
        store = RedisTaskStore(url, clock=clock)
        assert store.task(task.code) == task and store.submissions(task.code) == [kept]
        with pytest.raises(TaskRefused, match="used your 1 attempt at question 2"):
            store.submit(task.code, "tok-a", "Ann", "", 1, 1)
        store.close()
    finally:
        services.stop_process(process)


def test_the_lecturers_tally_counts_each_students_counted_answer_once(store: TaskRules, clock: Clock) -> None:
    from app.tasks.panel import table_text, tallies_text

    task = store.create([CHOICE, NUMBER], due=T0 + HOUR, attempts=3, counts="best")
    for token, name, answers in (("tok-a", "Ann", (0, 1)), ("tok-b", "Bea", (2,))):
        for option in answers:
            clock.t += 1.0
            store.submit(task.code, token, name, "", 0, option)
    text = tallies_text(task, store.submissions(task.code), clock())
    lines = text.split("  \n")
    assert lines[0] == "**Q1** · 2 answered · 1 right", text  # Ann's best (option 2), Bea's (option 3)
    assert lines[1].startswith("1. smallest") and "**0**" in lines[2] and "**1**" in lines[4] and "**1**" in lines[6]
    assert lines[-1] == "**Q2** · 0 answered · 0 right", text
    table = table_text(task, store.submissions(task.code), clock())
    assert "2 students, 3 submissions · mean score 0.25" in table, table  # (1 + 0) / 2 and (0 + 0) / 2
    assert "| Ann | – | 2 | 0.50 | 1 ✓ · 2 – |" in table, table


def test_a_student_goes_on_from_another_browser_with_a_receipt(store: TaskRules) -> None:
    task = store.create([NUMBER, CHOICE], due=T0 + HOUR, attempts=1)
    other = store.create(NUMBER, due=T0 + HOUR)
    first = store.submit(task.code, "tok-laptop", "Ann", "", 0, 2.5)
    elsewhere = store.submit(other.code, "tok-x", "Zed", "", 0, 2.5)
    for bad in ("ZZZZ-ZZZZ", elsewhere.receipt, "nonsense!"):
        with pytest.raises(TaskRefused, match="not one of this task's"):
            store.submit(task.code, "tok-phone", "Ann", "", 1, 1, receipt=bad)
    with pytest.raises(TaskRefused, match="already answers this task from another browser"):
        store.submit(task.code, "tok-phone", "Ann", "", 1, 1)
    later = store.submit(task.code, "tok-phone", "", "", 1, 1, receipt=first.receipt.lower())  # after a restart, say
    assert later.student == first.student and store.student(task.code, "tok-phone") == first.student
    with pytest.raises(TaskRefused, match="used your 1 attempt at question 1"):
        store.submit(task.code, "tok-phone", "", "", 0, 2.5)  # the attempts are the student's, not the browser's
    assert [s.receipt for s in store.mine(task.code, "tok-laptop")] == [first.receipt, later.receipt]
