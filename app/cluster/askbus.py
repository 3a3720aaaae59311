"""Ask the class across processes: the round's question to every worker, the answers back to
the worker that asked (`app.ask.hub.Rounds` on each side).

- The question: the worker whose presenter asked (the *source*) writes the round as it looks
  from outside (`app.ask.hub.Shown`: the question's dict, its number, open, revealed, its id, the
  count, its owner) under ROUND_KEY whenever it changes, and every REFRESH_S, each write with a
  TTL of ROUND_LIVE_S (a few REFRESH_S); every worker reads it every POLL_S and shows it to its
  browsers (`Rounds.set_remote`).  A round asked later on another worker replaces the source's own.
- **A round ends with its presenter.**  The source deletes the key when its round ends (its
  presenter stopped or left: `app.lecture.lectern.Lectern.release` ends it).  A worker that dies stops
  writing: the key lapses within ROUND_LIVE_S.  Sooner still, a worker shows another's round only
  while the round's owner holds the presenter lock (`presenter`, the gate's `presenter()`; its
  lease lapses within `app.lecture.gate.LEASE_S` of a dead worker's last renewal).  Nothing
  another worker or a browser sends renews the key: answers only go onto the answers' list.
- The answers: a browser on another worker answers there (checked against the question and
  limited in rate per browser by its `Rounds`), which pushes [token, value] onto the list
  ANSWERS_KEY + the round's id; the source pops them every POLL_S into its round, where the
  round's rules hold again (one per browser, bounded, checked).  So the tally, on the source, is
  the same whichever worker the students are on, and complete within about POLL_S of the last
  answer.
- **Earlier rounds.**  A round that ended on a worker (`Rounds.earlier`) is pushed, as its CSV
  section (`app.ask.hub.Ended.section`), onto the list EARLIER_KEY (the last MAX_EARLIER kept,
  for EARLIER_TTL_S); every worker counts the list every REFRESH_S (`Rounds.set_earlier_elsewhere`:
  its presenter's `Download earlier rounds (CSV)` shows) and reads it when that is pressed
  (`Rounds.shared_earlier`).  A worker killed before its poll pushes nothing.
- Tokens are the server's random per-browser tokens; nothing a browser sends chooses one.
  Everything read from Redis is one of `app.cluster.messages` (`ShownRound`, `SentAnswer`,
  `EarlierRound`: msgpack), decoded with its type, then checked (`question_from_dict`, the
  round's checks); a malformed entry is dropped with a log line and changes nothing.

The app loop calls `tick(dt)` once a frame; `close()` at the end.  No viser here.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable

import msgspec

from app.ask.hub import MAX_EARLIER, Rounds, Shown
from app.ask.questions import question_from_dict, question_to_dict
from app.ask.round import Refused
from app.cluster import KEY_PREFIX, connect
from app.cluster.messages import EarlierRound, SentAnswer, ShownRound, decode, encode

__all__ = ["ANSWERS_KEY", "EARLIER_KEY", "POLL_S", "REFRESH_S", "ROUND_KEY", "ROUND_LIVE_S", "AskBus"]

logger = logging.getLogger(__name__)

ROUND_KEY = KEY_PREFIX + "ask:round"  # a `ShownRound`: the source's round as every browser sees it
ANSWERS_KEY = KEY_PREFIX + "ask:answers:"  # + round id: a list of `SentAnswer` [token, value]
POLL_S = 0.1  # [s] every worker reads the round, the source pops the answers, this often
REFRESH_S = 2.0  # [s] the source rewrites the round at least this often
ROUND_LIVE_S = 3 * REFRESH_S  # [s] the round's key lapses this long after the source's last write
ANSWERS_TTL_S = 60.0  # [s] an answers' list no source pops lapses this long after its last answer
EARLIER_KEY = KEY_PREFIX + "ask:earlier"  # a list of `EarlierRound` [round id, CSV section]: the rounds that ended
EARLIER_TTL_S = 12 * 3600  # [s] the list lapses this long after its last push
MAX_SECTION_BYTES = 8 * 1024 * 1024  # a section read back longer than this is dropped
MAX_POP = 5000  # answers the source takes in one poll
MAX_ENTRY_BYTES = 8192


def encode_shown(shown: Shown, worker: str) -> bytes:
    """ROUND_KEY's bytes: `shown` as a `ShownRound` of `worker`."""
    return encode(ShownRound(worker=worker, id=shown.id, question=question_to_dict(shown.question),
                             number=shown.number, open=shown.open, revealed=shown.revealed,
                             answered=shown.answered, owner=shown.owner))


def decode_shown(data: object) -> tuple[str, Shown]:
    """(worker, Shown) from ROUND_KEY's bytes; ValueError for anything not one."""
    if not isinstance(data, bytes) or len(data) > 64 * 1024:
        raise ValueError("not a round")
    try:
        body = decode(data, ShownRound)
    except msgspec.DecodeError as error:
        raise ValueError(f"a malformed round: {error}") from None
    return body.worker, Shown(question_from_dict(body.question), body.number, body.open, body.revealed, body.id,
                              body.answered, body.owner)


class AskBus:
    """One worker's end of the questions' bus (module docstring).

    Args:
        rounds: the worker's `Rounds` (its `forward` is set here).  url: Redis.  worker_id: this worker.
        presenter: () -> the presenter lock's holder now, or None (`app.lecture.gate.Gate.presenter`);
            another worker's round is shown only while its owner holds it.  None: not checked.
    """

    def __init__(self, rounds: Rounds, url: str, worker_id: str, clock: Callable[[], float] = time.monotonic,
                 presenter: Callable[[], str | None] | None = None) -> None:
        self.rounds = rounds
        self.presenter = presenter
        self.worker_id = str(worker_id)
        self.redis = connect(url)
        self.clock = clock
        self._since = POLL_S  # the first tick polls
        # what the source last wrote (id, number, open, revealed, answered), and when
        self._written: tuple[str, int, bool, bool, int] | None = None
        self._written_at = -float("inf")
        self.taken = 0  # answers taken from other workers (the source's count)
        self._pushed: set[str] = set()  # ids of this worker's ended rounds pushed onto EARLIER_KEY
        self._counted_at = -float("inf")
        rounds.forward = self._forward
        rounds.shared_earlier = self._fetch_earlier

    def _forward(self, round_id: str, token: str, value: object) -> None:
        key = ANSWERS_KEY + round_id
        data = encode(SentAnswer(token, list(value) if isinstance(value, tuple) else value))
        pipe = self.redis.pipeline(transaction=False)
        pipe.rpush(key, data)
        pipe.expire(key, int(ANSWERS_TTL_S))
        pipe.execute()

    def tick(self, dt: float) -> None:
        """Called by the app loop every frame: every POLL_S, read the round (and, as the source,
        write it and take in the answers).  Redis trouble is logged, never raised."""
        self._since += dt
        if self._since < POLL_S:
            return
        self._since = 0.0
        try:
            self._poll()
        except Exception:  # noqa: BLE001 - the app loop must not die from Redis
            logger.warning("ask bus: poll failed", exc_info=True)

    def _poll(self) -> None:
        self._push_earlier()
        now = self.clock()
        if now - self._counted_at >= REFRESH_S:
            self._counted_at = now
            self.rounds.set_earlier_elsewhere(int(self.redis.llen(EARLIER_KEY)))
        self._poll_round()

    def _push_earlier(self) -> None:
        """This worker's rounds that ended since the last poll go onto EARLIER_KEY."""
        fresh = [one for one in list(self.rounds.earlier) if one.id not in self._pushed]
        if not fresh:
            return
        pipe = self.redis.pipeline(transaction=False)
        for one in fresh:
            pipe.rpush(EARLIER_KEY, encode(EarlierRound(one.id, one.section())))
        pipe.ltrim(EARLIER_KEY, -MAX_EARLIER, -1)
        pipe.expire(EARLIER_KEY, EARLIER_TTL_S)
        pipe.execute()
        self._pushed.update(one.id for one in fresh)

    def _fetch_earlier(self) -> list[tuple[str, str]]:
        """(round id, CSV section) of every worker's ended rounds, oldest first (bad entries dropped)."""
        found: list[tuple[str, str]] = []
        for data in self.redis.lrange(EARLIER_KEY, 0, -1):
            try:
                if not isinstance(data, bytes) or len(data) > MAX_SECTION_BYTES:
                    raise ValueError("too long")
                earlier = decode(data, EarlierRound)
                found.append((earlier.id, earlier.section))
            except (ValueError, msgspec.DecodeError) as error:
                logger.warning("ask bus: an earlier round dropped: %s", error)
        return found

    def _poll_round(self) -> None:
        rounds = self.rounds
        data = self.redis.get(ROUND_KEY)
        theirs: tuple[str, Shown] | None = None
        if data is not None:
            try:
                theirs = decode_shown(data)
            except ValueError as error:
                logger.warning("ask bus: a round dropped: %s", error)
        if rounds.current is not None:
            if theirs is not None and theirs[0] != self.worker_id and theirs[1].id != rounds.current_id \
                    and self._written is not None and self._written[0] == rounds.current_id:
                rounds.set_remote(theirs[1])  # asked later on another worker: that round is the class's
                self._written = None
                return
            self._take_answers()
            self._write()
            return
        if self._written is not None:  # this worker's round ended
            if theirs is not None and theirs[0] == self.worker_id:
                self.redis.delete(ROUND_KEY)
            self._written = None
            theirs = None
        if theirs is None or theirs[0] == self.worker_id or not self._owner_presents(theirs[1]):
            rounds.set_remote(None)
        else:
            rounds.set_remote(theirs[1])

    def _owner_presents(self, shown: Shown) -> bool:
        """The round's owner holds the presenter lock (True when either is not known: the lock
        unreachable, no `presenter`, a round without an owner)."""
        if self.presenter is None or not shown.owner:
            return True
        try:
            return self.presenter() == shown.owner
        except Exception:  # noqa: BLE001 - the gate unreachable: the key's TTL still ends the round
            logger.debug("ask bus: presenter not known", exc_info=True)
            return True

    def _write(self) -> None:
        shown = self.rounds.shown()
        if shown is None:
            return
        now = self.clock()
        key = (shown.id, shown.number, shown.open, shown.revealed, shown.answered)
        if key == self._written and now - self._written_at < REFRESH_S:
            return
        self.redis.set(ROUND_KEY, encode_shown(shown, self.worker_id), px=int(ROUND_LIVE_S * 1000))
        self._written, self._written_at = key, now

    def _take_answers(self) -> None:
        round_, rid = self.rounds.current, self.rounds.current_id
        if round_ is None:
            return
        entries = self.redis.lpop(ANSWERS_KEY + rid, MAX_POP) or []
        for data in entries:
            try:
                if not isinstance(data, bytes) or len(data) > MAX_ENTRY_BYTES:
                    raise ValueError("too long")
                answer = decode(data, SentAnswer)
                round_.answer(answer.token, answer.value)
                self.taken += 1
            except Refused:
                continue  # the round's rules: too fast, closed, full
            except (ValueError, msgspec.DecodeError) as error:
                logger.warning("ask bus: an answer dropped: %s", error)

    def close(self) -> None:
        """This worker's round leaves Redis (its browsers' questions end)."""
        try:
            if self._written is not None:
                data = self.redis.get(ROUND_KEY)
                if data is not None and decode_shown(data)[0] == self.worker_id:
                    self.redis.delete(ROUND_KEY)
            self._push_earlier()
        except Exception:  # noqa: BLE001 - Redis gone already
            logger.debug("ask bus: close", exc_info=True)
        self.rounds.forward = None
        self.rounds.shared_earlier = None
