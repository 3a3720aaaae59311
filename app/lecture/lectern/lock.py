"""The presenter lock as a browser meets it: the code, the refusals and their words, the lease.

`PresenterLock` asks the gate (`app.lecture.gate`: `LocalGate` in one process, `RedisGate`
across `--workers`; one set of rules) who presents and whether a code is right, limits a
browser's wrong codes (MAX_TRIES in TRIES_WINDOW), keeps each browser's last refusal true while
it is shown (`refusal_now`, `watch_refusal`) and renews the presenter's lease from the app loop
(`tick`).  Who presents is the lectern's (`Stage.presenter`); this part only reads it.
"""

from __future__ import annotations

import collections
import contextlib
import logging
import math
import threading
from collections.abc import Callable
from typing import Any

from app.lecture.gate import RENEW_PERIOD, Gate, GateUnavailable, Verdict
from app.lecture.lectern.seat import FOLLOW_PERIOD, Seat, Stage

__all__ = ["DOWN_NOTE_SECONDS", "MAX_TRIES", "TRIES_WINDOW", "PresenterLock"]

logger = logging.getLogger(__name__)

MAX_TRIES = 5  # wrong codes a browser may try ...
TRIES_WINDOW = 60.0  # ... per this many seconds
DOWN_NOTE_SECONDS = 10.0  # [s] "the presenter lock does not answer" stays this long (then try again)


class PresenterLock:
    """Who may present: the gate's lock and code, each browser's refusals, the presenter's lease.

    Args:
        gate: the presenter lock and the code (`app.lecture.gate`).
        stage: the lectern (who presents now).
        clock: the lectern's clock [s] (read at each call: a test moves it).
        lock: the lectern's lock (the refusals change under it).
    """

    def __init__(self, gate: Gate, stage: Stage, clock: Callable[[], float], lock: threading.RLock) -> None:
        self.gate = gate
        self._stage = stage
        self._clock = clock
        self._lock = lock
        self._tries: dict[int, collections.deque[float]] = collections.defaultdict(collections.deque)
        self._refused: dict[int, str] = {}  # client id -> "wrong", "wait", "hall", "busy" or "down": its last refusal
        self._hall_wait: dict[int, float] = {}  # client id -> when [clock s] the hall's limit lets it try
        self._refusal_watchers: dict[int, tuple[Seat, Callable[[], None]]] = {}  # `watch_refusal`
        self._since_refusals = 0.0
        self._since_renew = 0.0

    def holder(self, seat: Any) -> str:
        """`seat`'s name in the gate (`Gate.holder`)."""
        return self.gate.holder(seat.client_id)

    def _recent_tries(self, seat: Any) -> collections.deque[float]:
        """`seat`'s wrong codes within the last TRIES_WINDOW (older ones dropped)."""
        now = self._clock()
        tries = self._tries[seat.client_id]
        while tries and tries[0] < now - TRIES_WINDOW:
            tries.popleft()
        return tries

    def _wait_words(self, tries: collections.deque[float], head: str = "Too many wrong codes") -> str:
        wait = max(1, math.ceil(TRIES_WINDOW - (self._clock() - tries[0])))
        return f"{head}: wait {wait} s before trying again."

    def _someone_else(self, seat: Any) -> bool:
        """Someone other than `seat` presents (here or, through the gate, on another process)."""
        presenter = self._stage.presenter
        if presenter is not None and presenter is not seat:
            return True
        try:
            holder = self.gate.presenter()
        except GateUnavailable:
            return False
        return holder is not None and holder != self.holder(seat)

    def try_code(self, seat: Any, code: str) -> str | None:
        """None if `seat` may present with `code` (the gate's lock is then `seat`'s, for `start`),
        else the refusal: someone else presents (every code, not evaluated), the browser's or
        the hall's limit of wrong codes (not evaluated), a wrong code, or the lock unreachable.
        The refusal's words as they are now come from `refusal_now`."""
        with self._lock:
            cid = seat.client_id
            presenter = self._stage.presenter
            if presenter is not None and presenter is not seat:
                self._refused[cid] = "busy"
                return self.refusal_now(seat)
            tries = self._recent_tries(seat)
            if len(tries) >= MAX_TRIES:
                self._refused[cid] = "wait"
                return self._wait_words(tries)
            try:
                answer = self.gate.claim(self.holder(seat), str(code))
            except GateUnavailable as error:
                logger.warning("presenter code not checked: %s", error)
                self._hall_wait[cid] = self._clock() + DOWN_NOTE_SECONDS
                self._refused[cid] = "down"
                return self.refusal_now(seat)
            if answer.verdict is Verdict.OK:
                self._refused.pop(cid, None)
                return None
            if answer.verdict is Verdict.WRONG:
                tries.append(self._clock())
                self._refused[cid] = "wrong"
            elif answer.verdict is Verdict.WAIT:
                self._hall_wait[cid] = self._clock() + answer.wait_s
                self._refused[cid] = "hall"
            else:
                self._refused[cid] = "busy"
            return self.refusal_now(seat)

    def refusal_now(self, seat: Any) -> str | None:
        """`seat`'s last refusal (`try_code`) in the words true now, or None once it no longer
        holds: the wait counts down and ends, the tries left grow back as the minute passes,
        "someone else is presenting" ends when they stop or leave."""
        with self._lock:
            cid = seat.client_id
            kind = self._refused.get(cid)
            tries = self._recent_tries(seat)
            words: str | None = None
            if kind in ("wait", "wrong") and len(tries) >= MAX_TRIES:
                words = self._wait_words(tries, "Too many wrong codes" if kind == "wait" else
                                         "Wrong presenter code, no tries left")
            elif kind == "wrong" and tries:
                left = MAX_TRIES - len(tries)
                words = f"Wrong presenter code ({left} {'try' if left == 1 else 'tries'} left this minute)."
            elif kind == "hall" and self._hall_wait.get(cid, 0.0) > self._clock():
                wait = max(1, math.ceil(self._hall_wait[cid] - self._clock()))
                words = (f"Too many wrong codes in this lecture hall (someone may be guessing): wait {wait} s "
                         "before trying again.")
            elif kind == "busy" and self._someone_else(seat):
                words = "Someone else is presenting; they must stop first."
            elif kind == "down" and self._hall_wait.get(cid, 0.0) > self._clock():
                words = "The presenter lock does not answer (the lecture's Redis); try again in a moment."
            if words is None:
                self._refused.pop(cid, None)
                self._hall_wait.pop(cid, None)
            return words

    def watch_refusal(self, seat: Any, show: Callable[[], None] | None) -> None:
        """Call `show()` (in `seat`'s guard) every FOLLOW_PERIOD while `seat` has a refusal on
        screen, so its words stay true (`refusal_now`); None: stop."""
        with self._lock:
            if show is None:
                self._refusal_watchers.pop(seat.client_id, None)
            else:
                self._refusal_watchers[seat.client_id] = (seat, show)

    def start(self, seat: Seat) -> None:
        """`seat` starts presenting: the gate's lock (claimed by `try_code`) is confirmed as its."""
        try:
            self.gate.start(self.holder(seat))  # a lock lost meanwhile: `tick` stops the presenter
        except GateUnavailable as error:
            logger.warning("presenter lock not confirmed: %s", error)
        self._since_renew = 0.0

    def release(self, seat: Seat) -> None:
        """`seat` stops presenting (or never did): the gate's lock is freed if it is `seat`'s."""
        try:
            self.gate.release(self.holder(seat))
        except GateUnavailable as error:  # the lease lapses by itself
            logger.warning("presenter lock not released: %s", error)

    def tick(self, dt: float) -> None:
        """From the app loop: renew the presenter's lease every RENEW_PERIOD, rewrite the refusals
        on screen every FOLLOW_PERIOD."""
        self._since_renew += dt
        if self._since_renew >= RENEW_PERIOD and self._stage.presenter is not None:
            self._since_renew = 0.0
            self._renew()
        self._since_refusals += dt
        if self._since_refusals >= FOLLOW_PERIOD and self._refusal_watchers:
            self._since_refusals = 0.0
            with self._lock:
                watchers = list(self._refusal_watchers.items())
            for client_id, (seat, show) in watchers:
                if seat.closed:
                    self._refusal_watchers.pop(client_id, None)
                else:
                    seat.guard("presenter code note", show)()

    def _renew(self) -> None:
        """Renew the presenter's lease in the gate (from the loop: a process that stalls or dies
        lets it lapse); a presenter whose lock someone else took meanwhile stops presenting."""
        seat = self._stage.presenter
        if seat is None:
            return
        try:
            held = self.gate.renew(self.holder(seat))
        except GateUnavailable as error:
            logger.warning("presenter lock not renewed: %s", error)
            return
        if not held and not seat.closed:
            logger.warning("client %d: the presenter lock went to someone else", seat.client_id)
            seat.guard("presenter lock", seat.stop_presenting)()
            seat.report_error("presenter lock", RuntimeError("the presenter lock lapsed and someone else "
                                                             "took it; you no longer present"))

    def forget(self, client_id: int) -> None:
        """The browser `client_id` left: its wrong codes, refusal and refusal note go."""
        with self._lock:
            self._tries.pop(client_id, None)
            self._refused.pop(client_id, None)
            self._hall_wait.pop(client_id, None)
            self._refusal_watchers.pop(client_id, None)

    def close(self) -> None:
        """Free what this process holds in the gate (the app stops)."""
        with contextlib.suppress(Exception):
            self.gate.close()
