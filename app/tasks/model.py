"""Tasks between lectures, as data (no viser, no storage): a `Task` (one question or several in
order, a worksheet), its `Policy` of attempts, a student's `Submission`, the verdict of an
answer and the gradebook's CSV.

- A task is made by the lecturer (`make_task`): its questions (`app.ask.questions`, any kind),
  the scene and preset the student's own room opens with, the lecturer's words, a due time `due`
  [s since the epoch], attempts allowed (1, N or unlimited) and which counts (the best or the
  last).  It is kept `expire_after_s` [s] after it is due, then its code opens nothing.
- A code is a share code (`app.sharestore`: 8 characters of Crockford's base 32, typed with
  its forgiveness: case, spaces, dashes, O for 0, I and L for 1): `normalize_task_code`.
- A student gives a name or a student number once per task (`check_student`: printable words,
  at most MAX_NAME_CHARS / MAX_STUDENT_NUMBER_CHARS); every submission gets a receipt code.
- `verdict(question, value)` is an answer's score (1 right, 0 wrong, None: not judged) and its
  words as the judge words them; `gradebook_rows` / `gradebook_csv` one row a student: name,
  number, score 0–1 (the mean over the questions of the counted attempt's score), attempts,
  last submitted (UTC, ISO 8601), verdict words.
"""

from __future__ import annotations

import csv
import io
import math
import time
import unicodedata
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from app.ask.questions import Question, question_from_dict, question_to_dict
from app.i18n import N_
from app.sharestore import EXAMPLE, ShareCodeError, format_code, normalize_code
from physics.refusal import Refusal

__all__ = ["COUNTS", "DEFAULT_EXPIRE_AFTER_S", "GRADEBOOK_COLUMNS", "MAX_ATTEMPTS", "MAX_NAME_CHARS",
           "MAX_QUESTIONS", "MAX_STUDENT_NUMBER_CHARS", "MAX_WORDS_CHARS", "GradebookRow", "Policy", "Student",
           "Submission", "Task", "TaskCodeError", "TaskRefused", "check_student", "counted", "gradebook_csv",
           "gradebook_rows", "iso_time", "make_task", "normalize_task_code", "verdict"]

COUNTS = ("best", "last")  # which attempt counts for the grade
MAX_ATTEMPTS = 100  # a finite number of attempts is 1..MAX_ATTEMPTS (None: unlimited)
MAX_QUESTIONS = 20  # a worksheet's questions
MAX_WORDS_CHARS = 2000  # the lecturer's words
MAX_NAME_CHARS = 80
MAX_STUDENT_NUMBER_CHARS = 32
MAX_SCENE_CHARS = 80
DEFAULT_EXPIRE_AFTER_S = 180 * 24 * 3600.0  # [s] a task is kept half a year after it is due
MAX_DUE_AHEAD_S = 400 * 24 * 3600.0  # [s] a due time at most this far ahead
GRADEBOOK_COLUMNS = ("name", "number", "score", "attempts", "last_submitted", "verdict")


class TaskCodeError(Refusal):
    """A task code that opens nothing: malformed, unknown or expired (the message says which:
    English; its `template` a msgid and its `fields` for the panel to say it in a browser's language)."""


class TaskRefused(Refusal):
    """A submission or an action refused; the message is the student's (or lecturer's) to read
    (English; a `template` msgid and its `fields` where the panel says it in a browser's language)."""


def normalize_task_code(text: Any) -> str:
    """The code in `text` as stored (a share code's 8 characters, typed with its forgiveness);
    TaskCodeError saying what a task code is otherwise."""
    try:
        return normalize_code(text)
    except ShareCodeError:
        if not isinstance(text, str):
            raise TaskCodeError(N_("That is not a task code: a code is 8 letters and digits, like {example}."),
                                example=EXAMPLE) from None
        raise TaskCodeError(N_("{shown} is not a task code: a code is 8 letters and digits, like {example}."),
                            shown=repr(text.strip()[:20]), example=EXAMPLE) from None


def iso_time(seconds: float | None) -> str:
    """`seconds` since the epoch as "2026-11-28 14:05 UTC" ("" for None)."""
    if seconds is None:
        return ""
    return datetime.fromtimestamp(seconds, UTC).strftime("%Y-%m-%d %H:%M UTC")


def _clean_text(value: Any, where: str, most: int, *, allow_newlines: bool = False) -> str:
    """`value` as a stripped text of at most `most` characters without control characters;
    TaskRefused naming `where` otherwise."""
    if value is None:
        return ""
    if not isinstance(value, str):
        raise TaskRefused(N_("{where}: a text wanted"), where=where)
    if len(value) > most:
        raise TaskRefused(N_("{where}: at most {most} characters, got {count}"), where=where, most=most,
                          count=len(value))
    for char in value:
        if allow_newlines and char in "\n\t":
            continue
        if unicodedata.category(char) in ("Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp"):
            raise TaskRefused(N_("{where}: no control or invisible characters, please (found {char})"), where=where,
                              char=f"U+{ord(char):04X}")
    return value.strip()


@dataclass(frozen=True)
class Policy:
    """Attempts allowed per question (`attempts` 1..MAX_ATTEMPTS, or None: unlimited) and which
    counts for the grade (`counts`: "best" or "last")."""

    attempts: int | None = 1
    counts: str = "best"

    def __post_init__(self) -> None:
        a = self.attempts
        if a is not None and (isinstance(a, bool) or not isinstance(a, int) or not 1 <= a <= MAX_ATTEMPTS):
            raise TaskRefused(N_("{where}: 1 to {most}, or unlimited, got {got}"), where="attempts", most=MAX_ATTEMPTS,
                              got=repr(a))
        if self.counts not in COUNTS:
            raise TaskRefused(N_("{where}: one of {choices}, got {got}"), where="counts", choices=", ".join(COUNTS),
                              got=repr(self.counts))

    def words(self) -> str:
        """"1 attempt", "3 attempts, the best counts", "unlimited attempts, the last counts"."""
        if self.attempts == 1:
            return "1 attempt"
        many = "unlimited attempts" if self.attempts is None else f"{self.attempts} attempts"
        return f"{many}, the {self.counts} counts"


@dataclass(frozen=True)
class Task:
    """A task: `questions` in order (one, or several: a worksheet), the `scene` (a title of
    `app.session.SCENES`, or None: the student's own) and `preset` the student's room opens
    with, the lecturer's `words`, `due` and `created` [s since the epoch], the `policy`,
    `closed` by the lecturer, kept `expire_after_s` [s] after `due`."""

    code: str
    questions: tuple[Question, ...]
    due: float
    created: float
    policy: Policy = field(default_factory=Policy)
    scene: str | None = None
    preset: str | None = None
    words: str = ""
    closed: bool = False
    expire_after_s: float = DEFAULT_EXPIRE_AFTER_S
    places: tuple[tuple[str | None, str | None], ...] = ()
    """(scene, preset) per question of a worksheet made of lesson steps in several scenes; () the
    task's `scene` and `preset` for every question."""

    def place(self, index: int) -> tuple[str | None, str | None]:
        """(scene, preset) the student's room opens with for question `index`."""
        return self.places[index] if index < len(self.places) else (self.scene, self.preset)

    @property
    def shown_code(self) -> str:
        return format_code(self.code)

    @property
    def expires(self) -> float:
        """[s since the epoch] when its code stops opening it."""
        return self.due + self.expire_after_s

    def open_now(self, now: float) -> bool:
        return not self.closed and now < self.due

    def check_open(self, now: float) -> None:
        """TaskRefused saying why a submission is refused now (closed, or past the due time)."""
        if self.closed:
            raise TaskRefused(N_("The task {code} was closed by the lecturer: no more submissions."),
                              code=self.shown_code)
        if now >= self.due:
            raise TaskRefused(N_("The task {code} was due {due}: a submission after the due time is not accepted."),
                              code=self.shown_code, due=iso_time(self.due))

    def to_dict(self) -> dict[str, Any]:
        return {"code": self.code, "questions": [question_to_dict(q) for q in self.questions], "due": self.due,
                "created": self.created, "attempts": self.policy.attempts, "counts": self.policy.counts,
                "scene": self.scene, "preset": self.preset, "words": self.words, "closed": self.closed,
                "expire_after_s": self.expire_after_s, "places": [list(p) for p in self.places]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Task:
        return cls(code=str(d["code"]), questions=tuple(question_from_dict(q) for q in d["questions"]),
                   due=float(d["due"]), created=float(d["created"]),
                   policy=Policy(d.get("attempts"), str(d.get("counts", "best"))), scene=d.get("scene"),
                   preset=d.get("preset"), words=str(d.get("words", "")), closed=bool(d.get("closed", False)),
                   expire_after_s=float(d.get("expire_after_s", DEFAULT_EXPIRE_AFTER_S)),
                   places=tuple((p[0], p[1]) for p in d.get("places", ())))


def make_task(code: str, questions: Any, *, due: float, now: float, attempts: int | None = 1,
              counts: str = "best", scene: str | None = None, preset: str | None = None, words: str = "",
              expire_after_s: float = DEFAULT_EXPIRE_AFTER_S, places: Any = ()) -> Task:
    """A checked task; `questions` a question, its dict, or a list of them (a worksheet);
    `places` () or (scene, preset) per question.
    TaskRefused (or ValueError from a question) naming what is wrong."""
    items = list(questions) if isinstance(questions, list | tuple) else [questions]
    if not 1 <= len(items) <= MAX_QUESTIONS:
        raise TaskRefused(N_("{where}: 1 to {most} wanted, got {count}"), where="questions", most=MAX_QUESTIONS,
                          count=len(items))
    checked = tuple(question_from_dict(q) for q in items)
    if isinstance(due, bool) or not isinstance(due, int | float) or not math.isfinite(due):
        raise TaskRefused(N_("{where}: a time wanted"), where="due")
    if due <= now:
        raise TaskRefused(N_("{where}: the due time has passed already"), where="due")
    if due > now + MAX_DUE_AHEAD_S:
        raise TaskRefused(N_("{where}: at most {days} days ahead"), where="due", days=f"{MAX_DUE_AHEAD_S / 86400:.0f}")
    if not math.isfinite(expire_after_s) or expire_after_s <= 0:
        raise TaskRefused(N_("{where}: a positive number of seconds wanted"), where="expire_after_s")
    given = tuple(places or ())
    if given and len(given) != len(checked):
        raise TaskRefused(N_("{where}: one (scene, preset) per question wanted, got {count} for {questions}"),
                          where="places", count=len(given), questions=len(checked))
    cleaned = tuple((_clean_text(scene_, "scene", MAX_SCENE_CHARS) or None,
                     _clean_text(preset_, "preset", MAX_SCENE_CHARS) or None) for scene_, preset_ in given)
    return Task(code=code, questions=checked, places=cleaned, due=float(due), created=float(now),
                policy=Policy(attempts, counts),
                scene=_clean_text(scene, "scene", MAX_SCENE_CHARS) or None,
                preset=_clean_text(preset, "preset", MAX_SCENE_CHARS) or None,
                words=_clean_text(words, "words", MAX_WORDS_CHARS, allow_newlines=True),
                expire_after_s=float(expire_after_s))


@dataclass(frozen=True)
class Student:
    """Who submits: `name` and/or `number` as given; `key` the one they are known by in a task
    (the number if given, else the name, case and spacing aside)."""

    key: str
    name: str
    number: str


def check_student(name: Any, number: Any) -> Student:
    """The student from the name and student number typed (either may be empty, not both);
    TaskRefused saying what is wrong (too long, control characters, both missing)."""
    name_text = " ".join(_clean_text(name, "Name", MAX_NAME_CHARS).split())
    number_text = "".join(_clean_text(number, "Student number", MAX_STUDENT_NUMBER_CHARS).split())
    if not name_text and not number_text:
        raise TaskRefused(N_("To be counted, give your name or your student number."))
    key = f"number:{number_text.casefold()}" if number_text else f"name:{name_text.casefold()}"
    return Student(key=key, name=name_text, number=number_text)


@dataclass(frozen=True)
class Submission:
    """One submitted answer: `receipt` its code, `question` the question's index (0-based),
    `attempt` its number for this student and question (1-based), `value` the answer as the
    question checked it (JSON-like), `score` 1.0/0.0 (None: not judged), `words` the verdict,
    `at` [s since the epoch]."""

    receipt: str
    task: str
    student: Student
    question: int
    attempt: int
    value: Any
    score: float | None
    words: str
    at: float

    def to_dict(self) -> dict[str, Any]:
        return {"receipt": self.receipt, "task": self.task, "key": self.student.key, "name": self.student.name,
                "number": self.student.number, "question": self.question, "attempt": self.attempt,
                "value": _plain(self.value), "score": self.score, "words": self.words, "at": self.at}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Submission:
        return cls(receipt=str(d["receipt"]), task=str(d["task"]),
                   student=Student(str(d["key"]), str(d["name"]), str(d["number"])), question=int(d["question"]),
                   attempt=int(d["attempt"]), value=d["value"],
                   score=None if d["score"] is None else float(d["score"]), words=str(d["words"]), at=float(d["at"]))


def _plain(value: Any) -> Any:
    """`value` as JSON values (tuples as lists, numpy scalars as floats)."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, bool | int | float | str) or value is None:
        return value
    try:
        return float(value)
    except (TypeError, ValueError):
        return str(value)


def verdict(question: Question, value: Any) -> tuple[float | None, str]:
    """(score, words) of a checked answer: score 1.0 right, 0.0 wrong, None not judged (a
    question without a right answer); words as the judge words them ("2.4 s: right").  Each
    kind says it (`QuestionKind.verdict`)."""
    return question.verdict(value)


def is_judged(question: Question) -> bool:
    """The question has a right answer the app judges (a score 0 or 1), not only collected."""
    return question.has_truth or getattr(question, "judge", None) is not None


def counted(submissions: Sequence[Submission], counts: str) -> Submission | None:
    """The submission that counts among one student's attempts at one question (in the order
    made): the last, or the best (the highest score; the later of equals)."""
    if not submissions:
        return None
    ordered = sorted(submissions, key=lambda s: (s.at, s.attempt))
    if counts == "last":
        return ordered[-1]
    return max(reversed(ordered), key=lambda s: -1.0 if s.score is None else s.score)


@dataclass(frozen=True)
class GradebookRow:
    """One student's line: score 0–1 (None: nothing judged), attempts (the most at any question),
    last submitted [s since the epoch], verdict words (per question of a worksheet)."""

    name: str
    number: str
    score: float | None
    attempts: int
    last_submitted: float
    verdict: str
    scores: tuple[float | None, ...] = ()  # the counted score per question (None: not judged or not answered)
    answered: tuple[bool, ...] = ()  # per question


def gradebook_rows(task: Task, submissions: Iterable[Submission]) -> list[GradebookRow]:
    """One row a student, in the order they first submitted."""
    by_student: dict[str, list[Submission]] = {}
    for s in sorted(submissions, key=lambda s: (s.at, s.attempt)):
        by_student.setdefault(s.student.key, []).append(s)
    rows = []
    many = len(task.questions) > 1
    for subs in by_student.values():
        student = subs[-1].student
        scores, words, attempts = [], [], 0
        for index in range(len(task.questions)):
            mine = [s for s in subs if s.question == index]
            attempts = max(attempts, len(mine))
            chosen = counted(mine, task.policy.counts)
            prefix = f"Q{index + 1}: " if many else ""
            if chosen is None:
                scores.append(0.0 if is_judged(task.questions[index]) else None)
                words.append(f"{prefix}not answered")
            else:
                scores.append(chosen.score)
                words.append(prefix + chosen.words)
        judged = [s for s in scores if s is not None]
        score = sum(judged) / len(judged) if judged else None
        rows.append(GradebookRow(student.name, student.number, score, attempts, max(s.at for s in subs),
                                 "; ".join(words), tuple(scores), tuple(
                                     any(s.question == k for s in subs) for k in range(len(task.questions)))))
    return rows


def gradebook_csv(task: Task, submissions: Iterable[Submission]) -> str:
    """The gradebook's CSV (a header row, then one row a student; score 0–1 with 3 decimals,
    empty when nothing was judged; last_submitted in UTC, ISO 8601)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(GRADEBOOK_COLUMNS)
    for row in gradebook_rows(task, submissions):
        writer.writerow([_csv_safe(row.name), _csv_safe(row.number), "" if row.score is None else f"{row.score:.3f}",
                         row.attempts, datetime.fromtimestamp(row.last_submitted, UTC).isoformat(timespec="seconds"),
                         _csv_safe(row.verdict)])
    return out.getvalue()


def _csv_safe(text: str) -> str:
    """A text a spreadsheet shows as text, never runs as a formula (a leading = + - @ quoted)."""
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


def now_s() -> float:
    """The wall clock [s since the epoch] (a task's times are wall times: they survive a restart)."""
    return time.time()
