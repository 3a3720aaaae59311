"""Tasks in Redis, for an app on several processes (`--workers`): every worker opens every task
and sees every submission; the rules are `app.tasks.store.TaskRules`'.

Keys (all under `rigid-body-lab:task:`, each expiring with its task, `expires` after the due time):

- `<code>`: the task (JSON);
- `<code>:tokens` (hash: a browser's token hash -> the student's key) and `<code>:students` (hash:
  key -> the student, JSON): one name per browser and one browser per name, bound with HSETNX;
- `<code>:attempts` (hash: "key|question|attempt" -> receipt): an attempt is taken once, by
  HSETNX, whatever process tries it; `<code>:counts` (hash: "key|question" -> attempts made);
- `<code>:log` (list): the submissions in the order made, appended only (RPUSH), never changed;
- `rigid-body-lab:receipt:<receipt>`: a submission by its receipt code.

Redis keeps them across a restart when it writes its append-only file (`appendonly yes`: the
app's own redis-server does, `app.cluster.services.start_redis`, as `deploy/redis-rigid-body-lab.conf`).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from typing import Any

from app.ask.round import RateLimit
from app.i18n import N_
from app.tasks.model import Student, Submission, Task, TaskRefused
from app.tasks.store import TaskRules, already_answering, token_hash

__all__ = ["RedisTaskStore"]


class RedisTaskStore(TaskRules):
    """Tasks in Redis at `url` (`redis.Redis.from_url`; the client is imported here only)."""

    PREFIX = "rigid-body-lab:task:"
    RECEIPTS = "rigid-body-lab:receipt:"

    def __init__(self, url: str, clock: Callable[[], float] = time.time, rate: RateLimit | None = None) -> None:
        import redis  # noqa: PLC0415 - only an app on several processes needs it

        super().__init__(clock, rate)
        self.url = url
        self._redis: Any = redis.Redis.from_url(url, decode_responses=True)

    def _key(self, code: str, part: str = "") -> str:
        return f"{self.PREFIX}{code}{':' + part if part else ''}"

    def _ttl_ms(self, task_expires: float) -> int:
        """[ms] until a task expires, by the store's clock (at least a second)."""
        return max(1000, int((task_expires - self.clock()) * 1000.0))

    def _expire_all(self, code: str, expires: float) -> None:
        ttl = self._ttl_ms(expires)
        pipe = self._redis.pipeline()
        for part in ("tokens", "students", "attempts", "counts", "log"):
            pipe.pexpire(self._key(code, part), ttl)
        pipe.execute()

    def _insert_task(self, task: Task) -> bool:
        return bool(self._redis.set(self._key(task.code), json.dumps(task.to_dict()), nx=True,
                                    px=self._ttl_ms(task.expires)))

    def _load_task(self, code: str) -> Task | None:
        body = self._redis.get(self._key(code))
        return None if body is None else Task.from_dict(json.loads(body))

    def _save_task(self, task: Task) -> None:
        self._redis.set(self._key(task.code), json.dumps(task.to_dict()), xx=True, px=self._ttl_ms(task.expires))
        self._expire_all(task.code, task.expires)

    def _student(self, code: str, token: str) -> Student | None:
        key = self._redis.hget(self._key(code, "tokens"), token_hash(token))
        if key is None:
            return None
        body = self._redis.hget(self._key(code, "students"), key)
        return None if body is None else Student(**json.loads(body))

    def _bind(self, code: str, token: str, student: Student) -> Student:
        mine = self._student(code, token)
        if mine is not None:
            return mine
        body = json.dumps({"key": student.key, "name": student.name, "number": student.number})
        if not self._redis.hsetnx(self._key(code, "students"), student.key, body):
            raise already_answering(student)
        if not self._redis.hsetnx(self._key(code, "tokens"), token_hash(token), student.key):
            self._redis.hdel(self._key(code, "students"), student.key)  # this browser bound itself meanwhile
            found = self._student(code, token)
            if found is None:
                raise TaskRefused(N_("this browser's name could not be kept: submit again"))
            return found
        task = self._load_task(code)
        if task is not None:
            self._expire_all(code, task.expires)
        return student

    def _bind_more(self, code: str, token: str, student: Student) -> None:
        self._redis.hsetnx(self._key(code, "tokens"), token_hash(token), student.key)

    def _attempts(self, code: str, key: str, question: int) -> int:
        return int(self._redis.hget(self._key(code, "counts"), f"{key}|{question}") or 0)

    def _append(self, submission: Submission) -> bool:
        s = submission
        slot = f"{s.student.key}|{s.question}|{s.attempt}"
        if not self._redis.hsetnx(self._key(s.task, "attempts"), slot, s.receipt):
            return False  # taken by another process a moment ago: the next attempt number
        body = json.dumps(s.to_dict())
        task = self._load_task(s.task)
        ttl = self._ttl_ms(task.expires if task is not None else self.clock() + 86400.0)
        if not self._redis.set(self.RECEIPTS + s.receipt, body, nx=True, px=ttl):
            self._redis.hdel(self._key(s.task, "attempts"), slot)
            return False  # a receipt code taken (one chance in 2^40): another
        pipe = self._redis.pipeline()
        pipe.rpush(self._key(s.task, "log"), body)
        pipe.hincrby(self._key(s.task, "counts"), f"{s.student.key}|{s.question}", 1)
        pipe.execute()
        if task is not None:
            self._expire_all(s.task, task.expires)
        return True

    def _all(self, code: str) -> list[Submission]:
        return [Submission.from_dict(json.loads(body)) for body in self._redis.lrange(self._key(code, "log"), 0, -1)]

    def _receipt(self, receipt: str) -> Submission | None:
        body = self._redis.get(self.RECEIPTS + receipt)
        return None if body is None else Submission.from_dict(json.loads(body))

    def close(self) -> None:
        self._redis.close()
