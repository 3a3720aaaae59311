"""The app's questions to the class: the current round, and what every browser is asked.

`Rounds` is one per app (`app.lectern.Lectern.rounds`, also `App.rounds`).  On the process whose
presenter asked, it holds the round itself (`current`, a `app.ask.round.Round`: the answers, the
tally, the CSV).  On another process of a lecture on several (`app.cluster.askbus`), it holds
what that round looks like from outside (`remote`, a `Shown`): the question, its number, open or
closed; an answer given there is checked against the question, limited in rate per browser
(`RateLimit`), remembered for its browser and handed to `forward`, which carries it to the
asking process.

Every browser's panel reads `shown()` (a `Shown`, or None for no question) and its own answer
(`mine(token)`); `version` changes whenever what `shown()` says changes (the panels redraw then),
`answers_version` whenever an answer arrives (the presenter's counts).  No viser here.
"""

from __future__ import annotations

import secrets
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from app.ask.questions import Question, question_from_dict
from app.ask.round import RateLimit, Refused, Round, Tally

__all__ = ["Rounds", "Shown"]


@dataclass(frozen=True)
class Shown:
    """What a round looks like to the browsers: `question`, its `number` (1, 2 after Vote
    again), `open` (answers taken), `revealed` (the presenter shows the true answer), `id` (a
    random name of this round, the same on every process), `answered` (answers counted so far)."""

    question: Question
    number: int
    open: bool
    revealed: bool
    id: str
    answered: int = 0


class Rounds:
    """The current round of the app (see the module docstring).  Thread-safe."""

    def __init__(self) -> None:
        self.current: Round | None = None
        self.current_id = ""
        self.remote: Shown | None = None
        self.forward: Callable[[str, str, Any], None] | None = None
        """(round id, token, value) -> None: an answer sent to the process that asked (set by the bus)."""
        self.version = 0
        self._mine: dict[str, Any] = {}  # token -> its answer to the remote round (what its browser sees)
        self._rate = RateLimit()
        self._lock = threading.RLock()

    # ------------------------------------------------------------------ the presenter's side
    def ask(self, question: Question | dict[str, Any]) -> Round:
        """Open a round of `question` (a question or its dict; ValueError if it is not one); the
        round before it ends."""
        round_ = Round(question_from_dict(question))
        with self._lock:
            if self.current is not None:
                self.current.close()
            self._start(round_)
        return round_

    def _start(self, round_: Round) -> None:
        self.current = round_
        self.current_id = secrets.token_hex(8)
        self.remote = None
        self._mine = {}
        self.version += 1

    def close_round(self) -> Round:
        """Close the current round (it keeps its answers); the round.  LookupError for none."""
        with self._lock:
            round_ = self._local()
            round_.close()
            self.version += 1
        return round_

    def vote_again(self) -> Round:
        """The same question again: the current round closes and stays beside the new one."""
        with self._lock:
            round_ = self._local().vote_again()
            self._start(round_)
        return round_

    def reveal(self, shown: bool = True) -> None:
        """Show (or hide) the true answer of the current round on the presenter's screen."""
        with self._lock:
            self._local().reveal(shown)
            self.version += 1

    def end(self) -> None:
        """No question any more (the presenter's `New question`, or the presenter left)."""
        with self._lock:
            if self.current is not None:
                self.current.close()
            self.current, self.current_id, self.remote, self._mine = None, "", None, {}
            self.version += 1

    def _local(self) -> Round:
        if self.current is None:
            raise LookupError("no question is asked on this process")
        return self.current

    def tally(self) -> Tally | None:
        """The current round's tally (None: no round here)."""
        round_ = self.current
        return None if round_ is None else round_.tally()

    def csv(self) -> str:
        """The current round's anonymous answers, with its earlier rounds (`Round.csv`; "" for none)."""
        round_ = self.current
        return "" if round_ is None else round_.csv()

    @property
    def answers_version(self) -> int:
        round_ = self.current
        return 0 if round_ is None else round_.version

    # ------------------------------------------------------------------ every browser's side
    def shown(self) -> Shown | None:
        """The round every browser is asked now (local or from another process), or None."""
        round_ = self.current
        if round_ is not None:
            return Shown(round_.question, round_.number, round_.open, round_.revealed, self.current_id, len(round_))
        return self.remote

    def answer(self, token: str, value: Any) -> Any:
        """`token`'s browser answers the round shown (here, or sent to the process that asked);
        the answer as kept.  Refused (a ValueError with the student's message) otherwise."""
        round_ = self.current
        if round_ is not None:
            return round_.answer(token, value).value
        with self._lock:
            shown, forward = self.remote, self.forward
        if shown is None:
            raise Refused("no question is asked now")
        if not shown.open:
            raise Refused("the round is closed: answers are no longer taken")
        if not self._rate.allow(token):
            raise Refused("too fast: at most 5 answers a second")
        try:
            value = shown.question.check(value)
        except ValueError as error:
            raise Refused(f"not an answer: {error}") from None
        if forward is None:
            raise Refused("the question's process cannot be reached")
        forward(shown.id, token, value)
        with self._lock:
            if self.remote is not None and self.remote.id == shown.id:
                self._mine[token] = value
        return value

    def mine(self, token: str) -> Any:
        """`token`'s answer to the round shown, or None."""
        round_ = self.current
        if round_ is not None:
            answer = round_.answer_of(token)
            return None if answer is None else answer.value
        return self._mine.get(token)

    def set_remote(self, shown: Shown | None) -> None:
        """What another process's round looks like now (the bus); None: no question there.  A
        round asked on this process is replaced by a newer one asked elsewhere."""
        with self._lock:
            if shown == self.remote:
                return
            if shown is not None and (self.remote is None or self.remote.id != shown.id):
                self._mine = {}
            if shown is not None and self.current is not None:
                self.current.close()
                self.current, self.current_id = None, ""
            self.remote = shown
            self.version += 1
