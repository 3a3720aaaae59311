"""The presenter lock and its code, for one process (`LocalGate`) or several (`RedisGate`).

**A lock nobody guesses** (the rules both gates keep, so the one-process app and `--workers N`
answer alike):

1. One presenter at a time: the holder is "<worker_id>:<client_id>".  `claim` with the right
   code takes the lock with a lease of LEASE_S; `start` confirms it when the presenter's room is
   live, the presenting worker `renew`s it about every RENEW_PERIOD from its app loop, `release`
   frees it (Stop presenting, a disconnect).  In Redis the holder is the key `rbl:presenter`
   (SET NX PX): a worker that dies stops renewing, and within LEASE_S the lock is free and
   everyone sees that the presenter left.
2. While someone presents, every code gets the same answer, BUSY, and is not evaluated: a right
   code tells a guesser nothing.
3. Wrong codes are limited over all browsers and all processes together: at most MAX_WRONG
   codes are evaluated in any sliding WINDOW_S (`Answer.WAIT` for the others, not evaluated
   either).  A code is counted before it is compared (atomically, in Redis by a Lua script), so
   no race lets more through; a right code takes its count back.  The lecture's per-browser
   limit (`app.lecture.lectern.MAX_TRIES`) comes on top.
4. So a guesser has at most MAX_WRONG * 90 evaluations in a 90-minute lecture, and against a
   random code of CODE_DIGITS digits the chance to present is at most
   `guess_chance(90)` = 60 * 90 / 1e8 = 5.4e-5 (<= 1e-4).  When the attack stops, the
   window empties within WINDOW_S: the lecturer, who has the code, gets in within a minute.
5. Codes are compared without spaces and dashes (`normalize_code`): "4821 0937", "4821-0937" and
   "48210937" are one code.  The code never goes to Redis; every worker has it (the launcher
   hands it over in the environment).

Nothing read from Redis is executed or unpickled: the holder is a string, the counts numbers.
The time of the sliding window is Redis's own clock (`TIME`, one clock for every host) unless a
gate is given a `clock` (tests).
"""

from __future__ import annotations

import collections
import enum
import math
import secrets
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from app.cluster import KEY_PREFIX, connect

__all__ = ["CODE_DIGITS", "LEASE_S", "MAX_WRONG", "RENEW_PERIOD", "WINDOW_S", "Answer", "Gate", "GateUnavailable",
           "LocalGate", "RedisGate", "Verdict", "code_matches", "guess_chance", "new_code", "normalize_code"]

CODE_DIGITS = 8  # a random code's digits, shown in groups of CODE_GROUP ("4821 0937")
CODE_GROUP = 4
MAX_WRONG = 60  # wrong codes evaluated in any sliding WINDOW_S, over all browsers and processes
WINDOW_S = 60.0  # [s]
LEASE_S = 3.0  # [s] the presenter lock lapses this long after its last renewal
RENEW_PERIOD = 1.0  # [s] the presenting worker renews the lease this often
PRESENTER_CACHE_S = 0.2  # [s] `RedisGate.presenter` answers from its last read this long (refusals shown
# to many browsers read it every FOLLOW_PERIOD); this worker's own claims and releases refresh it
PRESENTER_KEY = KEY_PREFIX + "presenter"
WRONG_KEY = KEY_PREFIX + "gate:wrong"
SEPARATORS = " \t-\u2010\u2011\u2012\u2013\u2014\u2212_."  # what a person may type between the groups


class Verdict(enum.StrEnum):
    """A claim's outcome."""

    OK = "ok"  # the right code: the caller holds the lock now
    WRONG = "wrong"  # evaluated and wrong (counted)
    BUSY = "busy"  # someone else presents: not evaluated
    WAIT = "wait"  # MAX_WRONG wrong codes in the window already: not evaluated


@dataclass(frozen=True)
class Answer:
    """A claim's verdict and, for WAIT, the seconds [s] until a code may be evaluated again."""

    verdict: Verdict
    wait_s: float = 0.0


class GateUnavailable(RuntimeError):
    """The lock cannot be reached (Redis down): nothing was decided."""


def normalize_code(code: str) -> str:
    """`code` as compared: without spaces, dashes and the like (SEPARATORS) and outer blanks."""
    return "".join(ch for ch in str(code).strip() if ch not in SEPARATORS)


def code_matches(typed: str, code: str) -> bool:
    """Whether `typed` is `code` (both normalized), in constant time."""
    return secrets.compare_digest(normalize_code(typed).encode(), normalize_code(code).encode())


def new_code(digits: int = CODE_DIGITS, group: int = CODE_GROUP) -> str:
    """A random presenter code of `digits` digits in groups of `group` ("4821 0937"): easy to read
    out and type, long enough that MAX_WRONG guesses a minute have <= 1e-4 chance in 90 minutes."""
    text = f"{secrets.randbelow(10**digits):0{digits}d}"
    return " ".join(text[i:i + group] for i in range(0, digits, group))


def guess_chance(minutes: float, code: str | None = None, max_wrong: int = MAX_WRONG) -> float:
    """The chance [0, 1] that a guesser evaluated at `max_wrong` codes a minute presents within
    `minutes`, against a random code of `code`'s length (digits; letters count 36 each) or
    CODE_DIGITS: guesses <= max_wrong * ceil(minutes), chance <= guesses / codes."""
    text = normalize_code(code) if code is not None else "0" * CODE_DIGITS
    space = 10 ** len(text) if text.isdigit() else 36 ** len(text)
    return min(1.0, max_wrong * math.ceil(minutes) / space)


class Gate(Protocol):
    """The presenter lock and the code (see the module docstring).  Holders are
    "<worker_id>:<client_id>" (`holder`)."""

    worker_id: str
    code: str  # as shown (groups); compared normalized

    def holder(self, client_id: int) -> str:
        """The holder string of this worker's browser `client_id`."""
        ...

    def claim(self, holder: str, code: str) -> Answer:
        """One try of `code` by `holder`: BUSY (someone else presents), WAIT (the hall's limit),
        WRONG (counted) or OK (the lock is `holder`'s, with a lease until `start`/`renew`)."""
        ...

    def start(self, holder: str) -> bool:
        """`holder`'s room is live: keep the lock (False if it is not `holder`'s)."""
        ...

    def renew(self, holder: str) -> bool:
        """Extend `holder`'s lease (take the lock again if it lapsed and is free); False if
        someone else holds it."""
        ...

    def release(self, holder: str) -> None:
        """Free the lock if `holder` has it."""
        ...

    def presenter(self) -> str | None:
        """The holder now, or None."""
        ...

    def close(self) -> None:
        """Free what this process holds; the gate is not used after."""
        ...


class LocalGate:
    """The gate of a one-process app: the same rules in memory.  A claimed lock waits LEASE_S for
    `start`; once started it is held until `release` (the process holds it while it runs)."""

    def __init__(self, code: str, clock: Callable[[], float] = time.monotonic, *, worker_id: str = "local",
                 max_wrong: int = MAX_WRONG, window_s: float = WINDOW_S) -> None:
        if not normalize_code(code):
            raise ValueError("the presenter code is empty")
        self.code = code
        self.worker_id = worker_id
        self.max_wrong = max_wrong
        self.window_s = window_s
        self._clock = clock
        self._lock = threading.Lock()
        self._holder: str | None = None
        self._until: float | None = None  # the lease's end [clock s]; None once started
        self._wrong: collections.deque[float] = collections.deque()  # times [clock s] of wrong codes

    def holder(self, client_id: int) -> str:
        return f"{self.worker_id}:{client_id}"

    def _current(self, now: float) -> str | None:
        if self._holder is not None and self._until is not None and now >= self._until:
            self._holder = self._until = None
        return self._holder

    def claim(self, holder: str, code: str) -> Answer:
        with self._lock:
            now = self._clock()
            current = self._current(now)
            if current is not None and current != holder:
                return Answer(Verdict.BUSY)
            while self._wrong and self._wrong[0] <= now - self.window_s:
                self._wrong.popleft()
            if len(self._wrong) >= self.max_wrong:
                oldest = self._wrong[len(self._wrong) - self.max_wrong]
                return Answer(Verdict.WAIT, max(0.0, oldest + self.window_s - now))
            if not code_matches(code, self.code):
                self._wrong.append(now)
                return Answer(Verdict.WRONG)
            if current != holder:
                self._holder, self._until = holder, now + LEASE_S
            return Answer(Verdict.OK)

    def start(self, holder: str) -> bool:
        with self._lock:
            if self._current(self._clock()) != holder:
                return False
            self._until = None
            return True

    def renew(self, holder: str) -> bool:
        with self._lock:
            current = self._current(self._clock())
            if current is None:
                self._holder, self._until = holder, None
                return True
            return current == holder

    def release(self, holder: str) -> None:
        with self._lock:
            if self._holder == holder:
                self._holder = self._until = None

    def presenter(self) -> str | None:
        with self._lock:
            return self._current(self._clock())

    def close(self) -> None:
        pass


# KEYS: presenter, wrong.  ARGV: holder, now [ms] or "" (Redis's clock), window [ms], max_wrong, member.
# Returns {0}: BUSY; {1, wait_ms}: WAIT; {2}: counted (compare the code, then `_RIGHT` or keep the count).
_COUNT = """
local current = redis.call('GET', KEYS[1])
if current and current ~= ARGV[1] then return {0} end
local now = tonumber(ARGV[2])
if not now then local t = redis.call('TIME'); now = tonumber(t[1]) * 1000 + math.floor(tonumber(t[2]) / 1000) end
local window, most = tonumber(ARGV[3]), tonumber(ARGV[4])
redis.call('ZREMRANGEBYSCORE', KEYS[2], '-inf', now - window)
local n = redis.call('ZCARD', KEYS[2])
if n >= most then
  local oldest = redis.call('ZRANGE', KEYS[2], n - most, n - most, 'WITHSCORES')
  return {1, math.max(0, tonumber(oldest[2]) + window - now)}
end
redis.call('ZADD', KEYS[2], now, ARGV[5])
redis.call('PEXPIRE', KEYS[2], window)
return {2}
"""
# KEYS: presenter, wrong.  ARGV: holder, lease [ms], member.  The right code: its count back, the lock.
_RIGHT = """
redis.call('ZREM', KEYS[2], ARGV[3])
local current = redis.call('GET', KEYS[1])
if current and current ~= ARGV[1] then return 0 end
redis.call('SET', KEYS[1], ARGV[1], 'PX', tonumber(ARGV[2]))
return 1
"""
# KEYS: presenter.  ARGV: holder, lease [ms].  Extend ours, or take it again if free.
_RENEW = """
local current = redis.call('GET', KEYS[1])
if current and current ~= ARGV[1] then return 0 end
redis.call('SET', KEYS[1], ARGV[1], 'PX', tonumber(ARGV[2]))
return 1
"""
# KEYS: presenter.  ARGV: holder.
_RELEASE = """
if redis.call('GET', KEYS[1]) == ARGV[1] then redis.call('DEL', KEYS[1]) end
return 1
"""


class RedisGate:
    """The gate of one worker among several: the lock and the wrong-code window in Redis (keys
    PRESENTER_KEY, WRONG_KEY), the code in this process.  A Redis error raises GateUnavailable."""

    def __init__(self, url: str, worker_id: str, code: str, *, clock: Callable[[], float] | None = None,
                 max_wrong: int = MAX_WRONG, window_s: float = WINDOW_S, lease_s: float = LEASE_S,
                 presenter_cache_s: float = PRESENTER_CACHE_S, client: Any = None) -> None:
        if not normalize_code(code):
            raise ValueError("the presenter code is empty")
        if not worker_id or ":" in worker_id:
            raise ValueError(f"a worker id is a name without ':', not {worker_id!r}")
        self.code = code
        self.worker_id = worker_id
        self.max_wrong = max_wrong
        self.window_s = window_s
        self.lease_ms = max(1, round(1000.0 * lease_s))
        self._clock = clock
        self._redis = client if client is not None else connect(url)
        self._scripts = {name: self._redis.register_script(text) for name, text in
                         (("count", _COUNT), ("right", _RIGHT), ("renew", _RENEW), ("release", _RELEASE))}
        self._held: set[str] = set()  # holders of this worker that may hold the lock (`close` frees them)
        self.presenter_cache_s = presenter_cache_s
        self._read: tuple[float, str | None] = (-math.inf, None)  # (monotonic time [s], holder) of the last read

    def holder(self, client_id: int) -> str:
        return f"{self.worker_id}:{client_id}"

    def _run(self, name: str, keys: list[str], args: list[Any]) -> Any:
        self._read = (-math.inf, None)  # what this worker does changes the holder: read it again
        try:
            return self._scripts[name](keys=keys, args=args)
        except Exception as error:  # noqa: BLE001 - any client error: the lock is unreachable
            raise GateUnavailable(f"the lecture's lock (Redis) does not answer: {type(error).__name__}") from error

    def claim(self, holder: str, code: str) -> Answer:
        now = "" if self._clock is None else str(round(1000.0 * self._clock()))
        member = uuid.uuid4().hex
        counted = self._run("count", [PRESENTER_KEY, WRONG_KEY],
                            [holder, now, round(1000.0 * self.window_s), self.max_wrong, member])
        kind = int(counted[0])
        if kind == 0:
            return Answer(Verdict.BUSY)
        if kind == 1:
            return Answer(Verdict.WAIT, float(counted[1]) / 1000.0)
        if not code_matches(code, self.code):
            return Answer(Verdict.WRONG)
        if int(self._run("right", [PRESENTER_KEY, WRONG_KEY], [holder, self.lease_ms, member])) == 0:
            return Answer(Verdict.BUSY)
        self._held.add(holder)
        return Answer(Verdict.OK)

    def start(self, holder: str) -> bool:
        return self.renew(holder)

    def renew(self, holder: str) -> bool:
        held = int(self._run("renew", [PRESENTER_KEY], [holder, self.lease_ms])) == 1
        if held:
            self._held.add(holder)
        return held

    def release(self, holder: str) -> None:
        self._held.discard(holder)
        self._run("release", [PRESENTER_KEY], [holder])

    def presenter(self) -> str | None:
        read_at, holder = self._read
        now = time.monotonic()
        if now - read_at < self.presenter_cache_s:
            return holder
        holder = self._get_presenter()
        self._read = (now, holder)
        return holder

    def _get_presenter(self) -> str | None:
        try:
            value = self._redis.get(PRESENTER_KEY)
        except Exception as error:  # noqa: BLE001
            raise GateUnavailable(f"the lecture's lock (Redis) does not answer: {type(error).__name__}") from error
        if value is None:
            return None
        text = value.decode("utf-8", "replace") if isinstance(value, bytes) else str(value)
        return text if ":" in text and len(text) < 200 else None  # checked before use

    def close(self) -> None:
        for holder in list(self._held):
            try:
                self.release(holder)
            except GateUnavailable:
                break
        try:
            self._redis.close()
        except Exception:  # noqa: BLE001, S110 - closing a client that may be gone
            pass
