"""Redis and the child processes the app needs on several processes (`--workers N`, `--redis URL`).

Without `--workers` the app is one process and imports nothing from here but what is inert
without Redis.  With it:

- `app.cluster.services`: the real parts as child processes (redis-server, nginx) on free local
  ports, found on PATH, each stopped with the app; a missing one is named with the command that
  installs it.
- `app.cluster.askbus`: a question to the class across processes (the round to every worker,
  the answers back to the worker that asked).
- `app.cluster.messages`: the typed messages on Redis (msgspec), validated on decode.

The lecture across processes (`app.lecture.gate`, `app.lecture.bus`) and the launcher of the
workers behind nginx (`app.launch`) sit above and use these.
"""

from __future__ import annotations

from typing import Any

__all__ = ["KEY_PREFIX", "connect"]

KEY_PREFIX = "rbl:"  # every key and channel the app uses in Redis starts with this


def connect(url: str) -> Any:
    """A Redis client for `url` (redis://[:password@]host:port/db), answers decoded as bytes;
    imported here so that a one-process app never imports redis."""
    import redis  # noqa: PLC0415 - only the app on several processes needs it

    return redis.Redis.from_url(url, socket_timeout=5.0, socket_connect_timeout=5.0, health_check_interval=30)
