"""The app's questions to the class: the current round, and what every browser is asked.

`Rounds` is one per app (`app.lecture.lectern.Lectern.rounds`, also `App.rounds`).  On the process whose
presenter asked, it holds the round itself (`current`, a `app.ask.round.Round`: the answers, the
tally, the CSV).  On another process of a lecture on several (`app.cluster.askbus`), it holds
what that round looks like from outside (`remote`, a `Shown`): the question, its number, open or
closed; an answer given there is checked against the question, limited in rate per browser
(`RateLimit`), remembered for its browser and handed to `forward`, which carries it to the
asking process.

Every browser's panel reads `shown()` (a `Shown`, or None for no question) and its own answer
(`mine(token)`); `version` changes whenever what `shown()` says changes (the panels redraw then),
`answers_version` whenever an answer arrives (the presenter's counts).

**A round belongs to the presenter who asked it** (`owner`, the gate's holder string
"<worker>:<client>", set by `app.lecture.lectern.Lectern` through `begin`).  When that presenter stops
or leaves, the lectern calls `end`: the round closes and leaves every panel, and is kept, with
its answers, in `earlier` (`Ended`: the lecture it belonged to, why it ended), which the next
presenter may download (`earlier_csv`), never shown to anyone.  A round seen from another
process carries its owner (`Shown.owner`): `app.cluster.askbus` shows it only while that owner
holds the presenter lock.  No viser here.
"""

from __future__ import annotations

import secrets
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from app.ask.questions import Question, question_from_dict
from app.ask.round import RateLimit, Refused, Round, Tally

__all__ = ["MAX_EARLIER", "Ended", "Rounds", "Shown"]

MAX_EARLIER = 50  # ended rounds kept for `earlier_csv` (the oldest go)


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
    owner: str = ""  # the presenter who asked it (the gate's holder string; "" when not known)


@dataclass(frozen=True)
class Ended:
    """A round that ended: `round_` (its answers kept, closed), the `lecture` it was asked in
    (1, 2, ... on this process: a lecture is one presenter's time presenting), `owner` (who asked
    it), `why` ("new question", "the presenter stopped", "the presenter left") and `id` (the
    round's id, `Shown.id`)."""

    round_: Round
    lecture: int
    owner: str
    why: str
    id: str = ""

    def section(self) -> str:
        """This round's part of `Rounds.earlier_csv`: a comment line naming the lecture, the
        presenter and why it ended, then `Round.csv` (its question, its rounds' anonymous answers)."""
        who = f" · presenter {self.owner}" if self.owner else ""
        return (f"# lecture {self.lecture}{who} · round {self.round_.number} · ended: {self.why}\n"
                f"{self.round_.csv()}")


class Rounds:
    """The current round of the app (see the module docstring).  Thread-safe."""

    def __init__(self) -> None:
        self.current: Round | None = None
        self.current_id = ""
        self.remote: Shown | None = None
        self.forward: Callable[[str, str, Any], None] | None = None
        """(round id, token, value) -> None: an answer sent to the process that asked (set by the bus)."""
        self.version = 0
        self.owner = ""
        """The presenter a new round belongs to (`begin`), "" between lectures."""
        self.lecture = 0  # counts `begin`
        self.earlier: list[Ended] = []
        """Rounds that ended on this process, oldest first, at most MAX_EARLIER (`earlier_csv`)."""
        self.shared_earlier: Callable[[], list[tuple[str, str]]] | None = None
        """() -> (id, `Ended.section`) of the rounds that ended on every process, oldest first
        (set by the bus, `app.cluster.askbus`; None on one process)."""
        self.earlier_elsewhere = 0  # how many the bus last counted (`set_earlier_elsewhere`)
        self._mine: dict[str, Any] = {}  # token -> its answer to the remote round (what its browser sees)
        self._rate = RateLimit()
        self._lock = threading.RLock()

    # ------------------------------------------------------------------ the presenter's side
    def begin(self, owner: str) -> None:
        """A presenter (`owner`, the gate's holder string) starts: a round left from before ends
        (kept in `earlier`), the next rounds are `owner`'s."""
        with self._lock:
            self.end("a new presenter started")
            self.owner = str(owner)
            self.lecture += 1
            self.version += 1

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

    def end(self, why: str = "new question") -> None:
        """No question any more (the presenter's `New question`; the presenter stopped or left:
        `app.lecture.lectern.Lectern.release`): the round closes, leaves every panel and is kept, with its
        answers, in `earlier`.  `why` is said in `earlier_csv`."""
        with self._lock:
            round_ = self.current
            if round_ is not None:
                round_.close()
                self.earlier.append(Ended(round_, self.lecture, self.owner, str(why), self.current_id))
                del self.earlier[:-MAX_EARLIER]
            self.current, self.current_id, self.remote, self._mine = None, "", None, {}
            self.version += 1

    def end_lecture(self, why: str) -> None:
        """The presenter stopped or left (`why`): its round ends (`end`), no one owns the next."""
        with self._lock:
            self.end(why)
            self.owner = ""

    @property
    def has_earlier(self) -> bool:
        """A round has ended, here or (the bus counted) on another process."""
        return bool(self.earlier) or self.earlier_elsewhere > 0

    def set_earlier_elsewhere(self, count: int) -> None:
        """The bus counted `count` ended rounds over every process."""
        with self._lock:
            if count != self.earlier_elsewhere:
                self.earlier_elsewhere = count
                self.version += 1

    def earlier_csv(self) -> str:
        """The rounds that ended (every process's through `shared_earlier`, then this process's
        not there yet), each its `Ended.section`; "" for none."""
        with self._lock:
            local = [(one.id, one.section()) for one in self.earlier]
            fetch = self.shared_earlier
        sections = fetch() if fetch is not None else []
        ids = {rid for rid, _ in sections}
        sections += [(rid, text) for rid, text in local if rid not in ids]
        return "\n".join(text for _, text in sections)

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
            return Shown(round_.question, round_.number, round_.open, round_.revealed, self.current_id, len(round_),
                         self.owner)
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
                self.end("asked later on another process")
            self.remote = shown
            self.version += 1
