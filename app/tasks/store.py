"""Where tasks and submissions are kept, and the rules every submission passes (no viser).

`TaskRules` is the rules (the task's code opens it, it is open, the name is checked and bound
to one browser once per task, the answer is checked, the attempts allowed, the browser's rate,
the verdict and the receipt); a store gives it a few primitives.  Two stores, as for share
codes (`app.sharestore`):

- `SqliteTaskStore(path)`: an SQLite file in the app's data folder (`TASKS_FILE`), one process;
  it survives a restart; the file is opened at first use.
- `RedisTaskStore(url)` (`app.tasks.redis_store`): Redis, for an app on several processes.

`app.tasks.stores.open_task_store` opens the one the app runs with.

A browser is known by its session's anonymous token (`app.session.Session.answer_token`, never
sent to a browser); only its hash is kept.  What a browser can read of a task is its own
submissions (`mine`); `submissions`, `close` and `extend` are the lecturer's (the panel checks
the presenter code first).  Every refusal is a `TaskRefused` or `TaskCodeError` whose message is
for the person who acted, and changes nothing.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import sqlite3
import threading
import time
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from app.ask.round import RateLimit
from app.i18n import N_
from app.sharestore import format_code, new_code
from app.tasks.model import (
    DEFAULT_EXPIRE_AFTER_S,
    Student,
    Submission,
    Task,
    TaskCodeError,
    TaskRefused,
    check_student,
    make_task,
    normalize_task_code,
    verdict,
)

__all__ = ["RATE", "RATE_WINDOW_S", "TASKS_FILE", "SqliteTaskStore", "TaskRules", "already_answering", "token_hash"]

TASKS_FILE = "tasks.sqlite3"  # the SQLite store's file in the data folder
RATE = 5  # submissions a browser may make ...
LECTURER_CODES = 20  # lecturer's codes compared a minute, all browsers of a process together
RATE_WINDOW_S = 10.0  # [s] ... in any window this long (more are refused, not counted)


def token_hash(token: str) -> str:
    """What is kept of a browser's token (its SHA-256, hex)."""
    return hashlib.sha256(str(token).encode("utf-8")).hexdigest()


def already_answering(student: Student) -> TaskRefused:
    """The refusal of a second browser answering as `student` without a receipt of theirs."""
    return TaskRefused(N_("{who} already answers this task from another browser: go on there, or type a receipt "
                          "of yours in Your receipt."), who=student.number or student.name)


class TaskRules:
    """The rules of tasks over a store's primitives (`_insert_task`, `_load_task`, `_save_task`,
    `_bind`, `_attempts`, `_append`, `_all`, `_receipt`); `clock` the wall clock [s since the
    epoch], `listeners` called with a task's code after it changed (in this process)."""

    clock: Callable[[], float]

    def __init__(self, clock: Callable[[], float] = time.time, rate: RateLimit | None = None) -> None:
        self.clock = clock
        self.rate = rate or RateLimit(RATE, RATE_WINDOW_S, clock=time.monotonic)
        self.listeners: list[Callable[[str], None]] = []
        self.lecturer_codes = RateLimit(LECTURER_CODES, 60.0, clock=time.monotonic)
        self.receipt_tries = RateLimit(LECTURER_CODES, 60.0, clock=time.monotonic)  # receipts shown to go on
        """Lecturer's codes (the presenter code, `app.tasks.panel`) this process compares in any minute."""
        self._lock = threading.RLock()

    # -------------------------------------------------------------- primitives (a store's)
    def _insert_task(self, task: Task) -> bool:
        raise NotImplementedError

    def _load_task(self, code: str) -> Task | None:
        raise NotImplementedError

    def _save_task(self, task: Task) -> None:
        raise NotImplementedError

    def _student(self, code: str, token: str) -> Student | None:
        raise NotImplementedError

    def _bind(self, code: str, token: str, student: Student) -> Student:
        """The student `token` answers `code` as (binding `student` to it if it has none);
        TaskRefused if the token has another or the student another token."""
        raise NotImplementedError

    def _bind_more(self, code: str, token: str, student: Student) -> None:
        """One more browser (`token`) answers `code` as `student` (who showed a receipt)."""
        raise NotImplementedError

    def _attempts(self, code: str, key: str, question: int) -> int:
        raise NotImplementedError

    def _append(self, submission: Submission) -> bool:
        """Keep `submission`; False if its (student, question, attempt) or receipt is taken."""
        raise NotImplementedError

    def _all(self, code: str) -> list[Submission]:
        raise NotImplementedError

    def _receipt(self, receipt: str) -> Submission | None:
        raise NotImplementedError

    def close(self) -> None:
        """Let go of the store (its file or connection)."""

    # -------------------------------------------------------------- the rules
    def _changed(self, code: str) -> None:
        for listener in list(self.listeners):
            try:
                listener(code)
            except Exception:  # noqa: BLE001, S110 - a listener's panel is gone; the store carries on
                pass

    def create(self, questions: Any, *, due: float, attempts: int | None = 1, counts: str = "best",
               scene: str | None = None, preset: str | None = None, words: str = "",
               expire_after_s: float = DEFAULT_EXPIRE_AFTER_S, places: Any = ()) -> Task:
        """A new task (model.make_task's checks) under a new code."""
        now = self.clock()
        while True:
            task = make_task(new_code(), questions, due=due, now=now, attempts=attempts, counts=counts, scene=scene,
                             preset=preset, words=words, expire_after_s=expire_after_s, places=places)
            if self._insert_task(task):
                return task

    def task(self, text: Any) -> Task:
        """The task of the code typed in `text`; TaskCodeError if malformed, unknown or expired."""
        code = normalize_task_code(text)
        task = self._load_task(code)
        if task is None:
            raise TaskCodeError(N_("No task has the code {code}: check it with your lecturer."), code=format_code(code))
        if self.clock() >= task.expires:
            day = datetime.fromtimestamp(task.expires, UTC).strftime("%Y-%m-%d")
            raise TaskCodeError(N_("The task {code} expired on {day}: ask your lecturer."), code=format_code(code),
                                day=day)
        return task

    def student(self, text: Any, token: str) -> Student | None:
        """Who the browser of `token` answers the task as (None: nobody yet)."""
        return self._student(self.task(text).code, token)

    def submit(self, text: Any, token: str, name: Any, number: Any, question: Any, value: Any,
               receipt: Any = None) -> Submission:
        """Keep a student's answer to question `question` (0-based) of the task with code `text`,
        from the browser of `token`: its submission (with its verdict and receipt).  A browser
        new to the task answers as `name` / `number`, or, showing a `receipt` of this task, as
        the student it belongs to (who goes on from another browser).  TaskRefused or
        TaskCodeError with the reason otherwise (nothing is kept)."""
        task = self.task(text)
        task.check_open(self.clock())
        if not isinstance(token, str) or not token:
            raise TaskRefused(N_("this browser has no token"))
        bound = self._student(task.code, token)
        if bound is None and isinstance(receipt, str) and receipt.strip():
            bound = self._continue_with(task, token, receipt)
        student = check_student(name, number) if bound is None else bound
        if isinstance(question, bool) or not isinstance(question, int) or not 0 <= question < len(task.questions):
            raise TaskRefused(N_("question: 1 to {count} wanted"), count=len(task.questions))
        asked = task.questions[question]
        try:
            checked = asked.check(value)
        except ValueError as error:
            raise TaskRefused(N_("Not an answer: {error}"), error=error) from None
        allowed = task.policy.attempts
        if allowed is not None and self._attempts(task.code, student.key, question) >= allowed:
            raise self._used_up(allowed, question, len(task.questions))
        if not self.rate.allow(token_hash(token)):
            raise TaskRefused(N_("Too many submissions from this browser: at most {rate} in {seconds} s. "
                                 "Wait a moment and submit again."), rate=RATE, seconds=f"{RATE_WINDOW_S:g}")
        try:
            score, words = verdict(asked, checked)
        except ValueError as error:  # a judge that cannot judge this state (another scene's body)
            raise TaskRefused(N_("Not judged: {error}"), error=error) from None
        with self._lock:
            student = self._bind(task.code, token, student)
            while True:
                attempt = self._attempts(task.code, student.key, question) + 1
                if allowed is not None and attempt > allowed:
                    raise self._used_up(allowed, question, len(task.questions))
                submission = Submission(receipt=new_code(), task=task.code, student=student, question=question,
                                        attempt=attempt, value=checked, score=score, words=words, at=self.clock())
                if self._append(submission):
                    break
        self._changed(task.code)
        return submission

    def _continue_with(self, task: Task, token: str, receipt: str) -> Student:
        """The student a receipt of `task` belongs to, now answering from `token`'s browser too;
        TaskRefused for another task's receipt, none, or too many tried on this process."""
        if not self.receipt_tries.allow("hall"):
            raise TaskRefused(N_("Too many receipts were tried on this app: wait a minute."))
        try:
            found = self._receipt(normalize_task_code(receipt))
        except TaskCodeError:
            found = None
        if found is None or found.task != task.code:
            raise TaskRefused(N_("That receipt is not one of this task's: check it (or give your name)."))
        with self._lock:
            self._bind_more(task.code, token, found.student)
        return found.student

    @staticmethod
    def _used_up(allowed: int, question: int, questions: int) -> TaskRefused:
        if questions > 1:
            template = (N_("You have used your {count} attempt at question {question}: this task allows no more.")
                        if allowed == 1 else
                        N_("You have used your {count} attempts at question {question}: this task allows no more."))
            return TaskRefused(template, count=allowed, question=question + 1)
        template = (N_("You have used your {count} attempt: this task allows no more.") if allowed == 1 else
                    N_("You have used your {count} attempts: this task allows no more."))
        return TaskRefused(template, count=allowed)

    def mine(self, text: Any, token: str) -> list[Submission]:
        """The submissions of the student the browser of `token` answers as (nobody else's)."""
        task = self.task(text)
        student = self._student(task.code, token)
        if student is None:
            return []
        return [s for s in self._all(task.code) if s.student.key == student.key]

    def submissions(self, text: Any) -> list[Submission]:
        """Every submission of the task (the lecturer's: the panel checks the presenter code)."""
        return self._all(self.task(text).code)

    def receipt(self, text: Any) -> Submission:
        """The submission of a receipt code; TaskCodeError if none."""
        try:
            code = normalize_task_code(text)
        except TaskCodeError:
            raise TaskCodeError(N_("That is not a receipt code: a code is 8 letters and digits.")) from None
        found = self._receipt(code)
        if found is None:
            raise TaskCodeError(N_("No submission has the receipt {code}."), code=format_code(code))
        return found

    def close_task(self, text: Any) -> Task:
        """No more submissions (the lecturer's)."""
        task = self.task(text)
        closed = dataclasses.replace(task, closed=True)
        self._save_task(closed)
        self._changed(task.code)
        return closed

    def extend(self, text: Any, due: float) -> Task:
        """A new due time (later than now), the task open again (the lecturer's)."""
        task = self.task(text)
        now = self.clock()
        if due <= now:
            raise TaskRefused(N_("the new due time has passed already"))
        extended = dataclasses.replace(task, due=float(due), closed=False)
        self._save_task(extended)
        self._changed(task.code)
        return extended


class SqliteTaskStore(TaskRules):
    """Tasks, students and submissions in an SQLite file (opened at first use), as JSON rows."""

    def __init__(self, path: str | Path, clock: Callable[[], float] = time.time, rate: RateLimit | None = None) -> None:
        super().__init__(clock, rate)
        self.path = Path(path)
        self._connection: sqlite3.Connection | None = None

    def _db(self) -> sqlite3.Connection:
        if self._connection is None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            db = sqlite3.connect(self.path, check_same_thread=False, timeout=10.0)
            db.executescript(
                "CREATE TABLE IF NOT EXISTS tasks (code TEXT PRIMARY KEY, body TEXT NOT NULL, expires REAL NOT NULL);"
                "CREATE TABLE IF NOT EXISTS students (task TEXT NOT NULL, key TEXT NOT NULL, token TEXT NOT NULL,"
                " name TEXT NOT NULL, number TEXT NOT NULL, PRIMARY KEY (task, key), UNIQUE (task, token));"
                "CREATE TABLE IF NOT EXISTS submissions (receipt TEXT PRIMARY KEY, task TEXT NOT NULL,"
                " key TEXT NOT NULL, question INTEGER NOT NULL, attempt INTEGER NOT NULL, body TEXT NOT NULL,"
                " UNIQUE (task, key, question, attempt));"
                "CREATE TABLE IF NOT EXISTS more_tokens (task TEXT NOT NULL, token TEXT NOT NULL, key TEXT NOT NULL,"
                " PRIMARY KEY (task, token));")
            db.commit()
            self._connection = db
        return self._connection

    def _insert_task(self, task: Task) -> bool:
        with self._lock:
            db = self._db()
            for (code,) in db.execute("SELECT code FROM tasks WHERE expires <= ?", (self.clock(),)).fetchall():
                for table in ("submissions", "students", "more_tokens"):
                    db.execute(f"DELETE FROM {table} WHERE task = ?", (code,))  # noqa: S608 - fixed names
                db.execute("DELETE FROM tasks WHERE code = ?", (code,))
            try:
                db.execute("INSERT INTO tasks VALUES (?, ?, ?)", (task.code, json.dumps(task.to_dict()), task.expires))
            except sqlite3.IntegrityError:
                return False
            db.commit()
            return True

    def _load_task(self, code: str) -> Task | None:
        with self._lock:
            row = self._db().execute("SELECT body FROM tasks WHERE code = ?", (code,)).fetchone()
        return None if row is None else Task.from_dict(json.loads(row[0]))

    def _save_task(self, task: Task) -> None:
        with self._lock:
            db = self._db()
            db.execute("UPDATE tasks SET body = ?, expires = ? WHERE code = ?",
                       (json.dumps(task.to_dict()), task.expires, task.code))
            db.commit()

    def _student(self, code: str, token: str) -> Student | None:
        with self._lock:
            db = self._db()
            row = db.execute("SELECT key, name, number FROM students WHERE task = ? AND token = ?",
                             (code, token_hash(token))).fetchone()
            if row is None:
                row = db.execute("SELECT s.key, s.name, s.number FROM more_tokens t JOIN students s ON s.task = t.task "
                                 "AND s.key = t.key WHERE t.task = ? AND t.token = ?",
                                 (code, token_hash(token))).fetchone()
        return None if row is None else Student(*row)

    def _bind(self, code: str, token: str, student: Student) -> Student:
        with self._lock:
            db = self._db()
            mine = self._student(code, token)
            if mine is not None:
                return mine
            other = db.execute("SELECT 1 FROM students WHERE task = ? AND key = ?", (code, student.key)).fetchone()
            if other is not None:
                raise already_answering(student)
            db.execute("INSERT INTO students VALUES (?, ?, ?, ?, ?)",
                       (code, student.key, token_hash(token), student.name, student.number))
            db.commit()
            return student

    def _bind_more(self, code: str, token: str, student: Student) -> None:
        with self._lock:
            db = self._db()
            db.execute("INSERT OR IGNORE INTO more_tokens VALUES (?, ?, ?)", (code, token_hash(token), student.key))
            db.commit()

    def _attempts(self, code: str, key: str, question: int) -> int:
        with self._lock:
            row = self._db().execute("SELECT COUNT(*) FROM submissions WHERE task = ? AND key = ? AND question = ?",
                                     (code, key, question)).fetchone()
        return int(row[0])

    def _append(self, submission: Submission) -> bool:
        s = submission
        with self._lock:
            db = self._db()
            try:
                db.execute("INSERT INTO submissions VALUES (?, ?, ?, ?, ?, ?)",
                           (s.receipt, s.task, s.student.key, s.question, s.attempt, json.dumps(s.to_dict())))
            except sqlite3.IntegrityError:
                return False
            db.commit()
            return True

    def _all(self, code: str) -> list[Submission]:
        with self._lock:
            rows = self._db().execute("SELECT body FROM submissions WHERE task = ? ORDER BY rowid", (code,)).fetchall()
        return [Submission.from_dict(json.loads(body)) for (body,) in rows]

    def _receipt(self, receipt: str) -> Submission | None:
        with self._lock:
            row = self._db().execute("SELECT body FROM submissions WHERE receipt = ?", (receipt,)).fetchone()
        return None if row is None else Submission.from_dict(json.loads(row[0]))

    def close(self) -> None:
        with self._lock:
            if self._connection is not None:
                self._connection.close()
                self._connection = None
