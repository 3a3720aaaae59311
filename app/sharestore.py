"""Where shared moments are kept: short codes -> bytes, for a set time (no viser, no codec).

`ShareStore` is what the app needs: `save(payload) -> code` and `load(code) -> payload`.  Two
stores implement it:

- `SqliteShareStore(path)`: an SQLite file in the app's data folder (`app.userdata`), the one-process
  default; it survives a restart; the file is opened at the first save or load.
- `RedisShareStore(url)`: Redis, for an app on several processes (`--workers`); the key
  `rigid-body-lab:share:<code>` expires with the moment (Redis drops it itself).

A code is CODE_LENGTH characters of Crockford's base-32 alphabet (digits and capitals without
I, L, O, U: 40 bits), shown as two groups of four, `K7M2-QX9P`; typing it is forgiving
(`normalize_code`: case, spaces, dashes, O for 0, I and L for 1).  A code that is malformed,
unknown or expired raises `ShareCodeError` whose message says which, for the panel to show;
nothing else changes.  Moments expire after `DEFAULT_TTL_S` (30 days) unless the store is
told otherwise.
"""

from __future__ import annotations

import secrets
import sqlite3
import threading
import time
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Protocol

from app.i18n import N_
from physics.refusal import Refusal

__all__ = ["ALPHABET", "CODE_LENGTH", "DEFAULT_TTL_S", "MAX_PAYLOAD", "SHARES_FILE", "RedisShareStore",
           "ShareCodeError", "ShareStore", "SqliteShareStore", "format_code", "normalize_code",
           "open_share_store"]

ALPHABET = "0123456789ABCDEFGHJKMNPQRSTVWXYZ"  # Crockford's base 32
CODE_LENGTH = 8  # characters: 40 bits
DEFAULT_TTL_S = 30 * 24 * 3600.0  # [s] a moment is kept 30 days
MAX_PAYLOAD = 32 * 1024 * 1024  # [bytes] the largest moment kept (a room with a big mesh is ~10 MB)
_TYPOS = str.maketrans({"O": "0", "I": "1", "L": "1"})
EXAMPLE = "K7M2-QX9P"
SHARES_FILE = "shares.sqlite3"  # the SQLite store's file in the data folder


class ShareCodeError(Refusal):
    """A code that opens nothing: malformed, unknown or expired (the message says which: English,
    its `template` a msgid and its `fields` for a panel to say it in a browser's language)."""


def normalize_code(text: Any) -> str:
    """The code in `text` as stored (8 characters of ALPHABET); ShareCodeError if it is not one."""
    if not isinstance(text, str) or len(text) > 64:
        raise ShareCodeError(N_("That is not a share code: a code is {length} letters and digits, like {example}."),
                             length=CODE_LENGTH, example=EXAMPLE)
    code = "".join(text.split()).replace("-", "").upper().translate(_TYPOS)
    if len(code) != CODE_LENGTH or any(c not in ALPHABET for c in code):
        shown = text.strip()[:20]
        raise ShareCodeError(N_("{shown} is not a share code: a code is {length} letters and digits, like {example}."),
                             shown=repr(shown), length=CODE_LENGTH, example=EXAMPLE)
    return code


def format_code(code: str) -> str:
    """`K7M2QX9P` -> `K7M2-QX9P`."""
    return f"{code[:4]}-{code[4:]}"


def new_code() -> str:
    """A random code (CODE_LENGTH characters of ALPHABET, from `secrets`)."""
    return "".join(secrets.choice(ALPHABET) for _ in range(CODE_LENGTH))


def _unknown(code: str) -> ShareCodeError:
    return ShareCodeError(N_("No shared moment has the code {code}: check it, or ask for a new one "
                             "(a moment is kept 30 days)."), code=format_code(code))


def _check_payload(payload: bytes) -> None:
    if not isinstance(payload, bytes) or not payload:
        raise ValueError("a shared moment is non-empty bytes")
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(f"this moment takes {len(payload) / 1e6:.1f} MB, more than the "
                         f"{MAX_PAYLOAD / 1e6:.0f} MB a share may keep")


def open_share_store(data_dir: str | Path, redis_url: str | None = None, ttl_s: float = DEFAULT_TTL_S) -> ShareStore:
    """The app's store: Redis at `redis_url` when the app runs on several processes (every process
    opens every code), else SQLite in `data_dir` (`SHARES_FILE`, opened at first use)."""
    if redis_url:
        return RedisShareStore(redis_url, ttl_s=ttl_s)
    return SqliteShareStore(Path(data_dir) / SHARES_FILE, ttl_s=ttl_s)


class ShareStore(Protocol):
    """Codes -> moments (bytes), kept `ttl_s` seconds."""

    ttl_s: float

    def save(self, payload: bytes) -> str:
        """Keep `payload`; its new code (CODE_LENGTH characters of ALPHABET)."""
        ...

    def load(self, code: str) -> bytes:
        """The payload saved under `code` (typed as a person types it: `normalize_code`);
        ShareCodeError if the code is malformed, unknown or expired."""
        ...


class SqliteShareStore:
    """Moments in an SQLite file (table `shares`: code, payload, created, expires [s since the epoch]).

    clock: time.time, or a test's clock.  Expired rows are deleted when a moment is saved."""

    def __init__(self, path: str | Path, ttl_s: float = DEFAULT_TTL_S, clock: Callable[[], float] = time.time) -> None:
        self.path = Path(path)
        self.ttl_s = float(ttl_s)
        self.clock = clock
        self._lock = threading.Lock()
        self._connection: sqlite3.Connection | None = None

    def _db(self) -> sqlite3.Connection:
        if self._connection is None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            connection = sqlite3.connect(self.path, check_same_thread=False, timeout=10.0)
            connection.execute("CREATE TABLE IF NOT EXISTS shares (code TEXT PRIMARY KEY, payload BLOB NOT NULL, "
                               "created REAL NOT NULL, expires REAL NOT NULL)")
            connection.commit()
            self._connection = connection
        return self._connection

    def save(self, payload: bytes) -> str:
        _check_payload(payload)
        now = self.clock()
        with self._lock:
            db = self._db()
            db.execute("DELETE FROM shares WHERE expires <= ?", (now,))
            while True:
                code = new_code()
                try:
                    db.execute("INSERT INTO shares VALUES (?, ?, ?, ?)", (code, payload, now, now + self.ttl_s))
                except sqlite3.IntegrityError:
                    continue  # taken (one chance in 2^40 per moment kept): another
                db.commit()
                return code

    def load(self, code: str) -> bytes:
        code = normalize_code(code)
        with self._lock:
            row = self._db().execute("SELECT payload, expires FROM shares WHERE code = ?", (code,)).fetchone()
        if row is None:
            raise _unknown(code)
        payload, expires = row
        if expires <= self.clock():
            day = datetime.fromtimestamp(expires, UTC).strftime("%Y-%m-%d")
            raise ShareCodeError(N_("The shared moment {code} expired on {day} (moments are kept {days} days): "
                                    "ask for a new code."), code=format_code(code), day=day,
                                 days=f"{self.ttl_s / 86400:g}")
        return bytes(payload)

    def close(self) -> None:
        with self._lock:
            if self._connection is not None:
                self._connection.close()
                self._connection = None


class RedisShareStore:
    """Moments in Redis under `rigid-body-lab:share:<code>`, expiring with the moment (SET ... PX, NX).

    url: `redis://host:port/db` (`redis.Redis.from_url`; the `redis` client is imported here only)."""

    PREFIX = "rigid-body-lab:share:"

    def __init__(self, url: str, ttl_s: float = DEFAULT_TTL_S) -> None:
        import redis  # noqa: PLC0415 - only an app on several processes needs it

        self.url = url
        self.ttl_s = float(ttl_s)
        self._redis = redis.Redis.from_url(url)

    def save(self, payload: bytes) -> str:
        _check_payload(payload)
        ttl_ms = max(1, int(self.ttl_s * 1000))
        while True:
            code = new_code()
            if self._redis.set(self.PREFIX + code, payload, px=ttl_ms, nx=True):
                return code

    def load(self, code: str) -> bytes:
        code = normalize_code(code)
        payload = self._redis.get(self.PREFIX + code)
        if payload is None:
            raise _unknown(code)
        return bytes(payload)  # type: ignore[arg-type]

    def close(self) -> None:
        self._redis.close()
