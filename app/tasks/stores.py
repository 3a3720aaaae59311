"""The task store an app runs with: Redis on several processes, else SQLite in the data folder."""

from __future__ import annotations

from pathlib import Path

from app.tasks.redis_store import RedisTaskStore
from app.tasks.store import TASKS_FILE, SqliteTaskStore, TaskRules

__all__ = ["open_task_store"]


def open_task_store(data_dir: str | Path, redis_url: str | None = None) -> TaskRules:
    """Redis at `redis_url` (the redis client is imported only then), else SQLite in `data_dir`
    (`TASKS_FILE`, opened at first use)."""
    if redis_url:
        return RedisTaskStore(redis_url)
    return SqliteTaskStore(Path(data_dir) / TASKS_FILE)
