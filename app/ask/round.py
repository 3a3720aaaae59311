"""One round of a question to the class: its answers, its rules, its tally and its CSV.

**The rules** (issue 26), held here so that every way in (a browser's panel, another process
over Redis, the automation API) keeps them:

- Anonymous: an answer is keyed by its browser's *token*, a random string the server gives each
  browser session (`new_token`); it is never taken from what a browser sends, never shown, and
  never written to the tally or the CSV.
- One answer per browser per round: a new one replaces the old (until the round closes); an
  answer stays counted after its browser leaves.
- Bounded: at most MAX_BROWSERS answers per round, at most RATE answers per browser per second
  (`RateLimit`), an answer's value checked by its question (`Choice.check`, ...).  A refused
  answer raises `Refused` (a ValueError) with a message for the student, and changes nothing.
- A closed round takes no answers.  `vote_again` closes it and starts the next round of the
  same question, which keeps this one's tally beside it (`Tally.previous`).

No viser here: the panels (`app.hall.ask`) and the bus (`app.cluster.askbus`) call it.
"""

from __future__ import annotations

import collections
import csv
import io
import math
import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from app.ask.judges import Judged
from app.ask.questions import Question, question_from_dict

__all__ = ["MAX_BROWSERS", "RATE", "Answer", "RateLimit", "Refused", "Round", "Tally", "new_token"]

MAX_BROWSERS = 5000  # answers one round keeps (one per browser)
RATE = 5  # answers a browser may send per RATE_WINDOW ...
RATE_WINDOW = 1.0  # ... [s]
TOKEN_BYTES = 16


def new_token() -> str:
    """A browser's anonymous answer token (random, unguessable; kept by the server only)."""
    return secrets.token_urlsafe(TOKEN_BYTES)


class Refused(ValueError):
    """An answer not taken: the message says why, for the student."""


class RateLimit:
    """At most `rate` events per key in any `window` [s] (a sliding window); keys are forgotten
    when their window is empty, and at most `max_keys` are tracked (the oldest go)."""

    def __init__(self, rate: int = RATE, window: float = RATE_WINDOW, clock: Callable[[], float] = time.monotonic,
                 max_keys: int = 4 * MAX_BROWSERS) -> None:
        self.rate, self.window, self.clock, self.max_keys = rate, window, clock, max_keys
        self._times: collections.OrderedDict[str, collections.deque[float]] = collections.OrderedDict()
        self._lock = threading.Lock()

    def allow(self, key: str) -> bool:
        """True (and counted) if `key` may act now; False if it has acted `rate` times within the window."""
        now = self.clock()
        with self._lock:
            times = self._times.get(key)
            if times is None:
                times = self._times[key] = collections.deque()
                while len(self._times) > self.max_keys:
                    self._times.popitem(last=False)
            while times and now - times[0] >= self.window:
                times.popleft()
            if len(times) >= self.rate:
                return False
            times.append(now)
            return True


@dataclass(frozen=True)
class Answer:
    """One browser's answer: `value` as its question checked it (an option's index, a unit
    3-vector in the question's frame, a state dict), `at` [s] after the round opened, `judged`
    a State answer's judgement (or None)."""

    value: Any
    at: float
    judged: Judged | None = None


@dataclass(frozen=True)
class Tally:
    """What the room answered, anonymous.

    Attributes:
        number: the round's number (1, then 2 after Vote again).  question: the question.
        open: the round takes answers.  answered: how many browsers answered.
        counts: a Choice's answers per option (len(options)); () otherwise.
        directions: a Direction's answers, unit 3-vectors in its frame, shape (answered, 3) as
            tuples, in no particular order; () otherwise.
        judged: a State's judged answers (None for an answer no judge judged); () otherwise.
        values: a Number's answers (floats, in its unit), in no particular order; () otherwise.
        previous: the tally of the round before it (Vote again), or None.
    """

    number: int
    question: Question
    open: bool
    answered: int
    counts: tuple[int, ...] = ()
    directions: tuple[tuple[float, float, float], ...] = ()
    judged: tuple[Judged | None, ...] = ()
    values: tuple[float, ...] = ()
    previous: Tally | None = None

    def share(self, option: int) -> float:
        """A Choice's share of answers for `option` (0..1; 0 with no answers)."""
        return self.counts[option] / self.answered if self.answered else 0.0

    def within(self, degrees: float) -> int:
        """A Direction's answers within `degrees` of its truth (0 without a truth)."""
        truth = getattr(self.question, "truth", None)
        if truth is None:
            return 0
        cos = math.cos(math.radians(degrees))
        return sum(1 for d in self.directions if sum(a * b for a, b in zip(d, truth, strict=True)) >= cos)


class Round:
    """One round of `question` (a question or its dict, `question_from_dict`): open when made.

    Args:
        question: what is asked.  number: the round's number.
        previous: the round before (Vote again), kept for its tally and CSV.
        clock: [s], monotonic (tests pass their own).

    Thread-safe: answers arrive from browsers' callbacks and from the bus's thread."""

    def __init__(self, question: Question | dict[str, Any], number: int = 1, *, previous: Round | None = None,
                 clock: Callable[[], float] = time.monotonic, max_browsers: int = MAX_BROWSERS) -> None:
        self.question: Question = question_from_dict(question)
        self.number = int(number)
        self.previous = previous
        self.clock = clock
        self.max_browsers = max_browsers
        self.opened_at = clock()
        self.open = True
        self.revealed = False  # the presenter showed the true answer
        self.version = 0  # bumped by every change (the panels redraw when it moved)
        self._answers: dict[str, Answer] = {}
        self._rate = RateLimit(clock=clock)
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._answers)

    def answer(self, token: str, value: Any) -> Answer:
        """`token`'s browser answers `value` (replacing its earlier answer); the answer as kept.
        Refused (a ValueError, with the student's message) if the round is closed, the browser
        answers too fast or the round is full, or the value is not an answer to the question;
        a refused answer changes nothing."""
        if not isinstance(token, str) or not token:
            raise Refused("this browser has no answer token")
        if not self.open:
            raise Refused("the round is closed: answers are no longer taken")
        if not self._rate.allow(token):
            raise Refused(f"too fast: at most {RATE} answers a second")
        try:
            value = self.question.check(value)
            judged = self.question.judged(value)
        except ValueError as error:  # a judge refuses a body it cannot judge (another scene's, ...)
            raise Refused(f"not an answer: {error}") from None
        with self._lock:
            if not self.open:
                raise Refused("the round is closed: answers are no longer taken")
            if token not in self._answers and len(self._answers) >= self.max_browsers:
                raise Refused(f"the round is full ({self.max_browsers} answers)")
            kept = self._answers[token] = Answer(value, self.clock() - self.opened_at, judged)
            self.version += 1
        return kept

    def answers(self) -> list[Answer]:
        """This round's answers, anonymous, oldest first (numbered 1.. in this order, as `rows`)."""
        with self._lock:
            return sorted(self._answers.values(), key=lambda a: a.at)

    def answer_of(self, token: str) -> Answer | None:
        """`token`'s answer in this round, or None (a browser sees its own answer)."""
        return self._answers.get(token)

    def close(self) -> None:
        """No more answers."""
        with self._lock:
            if self.open:
                self.open = False
                self.version += 1

    def reveal(self, shown: bool = True) -> None:
        """Show (or hide) the true answer on the presenter's screen."""
        with self._lock:
            self.revealed = bool(shown)
            self.version += 1

    def tally(self) -> Tally:
        """The anonymous tally now (`Tally`)."""
        with self._lock:
            answers = list(self._answers.values())
            is_open = self.open
        previous = None if self.previous is None else self.previous.tally()
        fields = self.question.tally_fields([a.value for a in answers], [a.judged for a in answers])
        return Tally(self.number, self.question, is_open, len(answers), previous=previous, **fields)

    def vote_again(self) -> Round:
        """Close this round; the next round of the same question, with this one beside it."""
        self.close()
        return Round(self.question, self.number + 1, previous=self, clock=self.clock, max_browsers=self.max_browsers)

    CSV_COLUMNS = ("round", "answer", "seconds", "option", "option_text", "x", "y", "z", "state", "judged",
                   "judged_words", "value")

    def rows(self) -> list[dict[str, Any]]:
        """This round's answers as anonymous rows (CSV_COLUMNS; "answer" numbers them 1.. by time)."""
        with self._lock:
            answers = sorted(self._answers.values(), key=lambda a: a.at)
        rows = []
        question = self.question
        for k, answer in enumerate(answers, start=1):
            row: dict[str, Any] = dict.fromkeys(self.CSV_COLUMNS, "")
            row.update({"round": self.number, "answer": k, "seconds": f"{answer.at:.2f}"})
            row.update(question.csv_row(answer.value, answer.judged))
            rows.append(row)
        return rows

    def csv(self) -> str:
        """Every round of this question (the earlier ones first) as CSV: a comment line with the
        question, then CSV_COLUMNS and one row per answer; no token, nothing that names a browser."""
        rounds = []
        here: Round | None = self
        while here is not None:
            rounds.append(here)
            here = here.previous
        out = io.StringIO()
        out.write(f"# {self.question.kind}: {self.question.prompt}\n")
        out.write(self.question.csv_head())
        writer = csv.DictWriter(out, fieldnames=self.CSV_COLUMNS, lineterminator="\n")
        writer.writeheader()
        for one in reversed(rounds):
            writer.writerows(one.rows())
        return out.getvalue()
