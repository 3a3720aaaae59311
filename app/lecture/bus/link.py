"""The bus's channels, keys and periods, and `Link`: one process's Redis connection and its worker id."""

from __future__ import annotations

import logging
from typing import Any

from app.cluster import KEY_PREFIX, connect
from app.cluster.messages import Message, encode

__all__ = ["ASK", "AUDIENCE_KEY", "CHANNEL", "LAST_KEY", "LEASE_S", "Link"]

logger = logging.getLogger("app.lecture.bus")

CHANNEL = KEY_PREFIX + "live"  # the source to every process: scene batches, the hall, camera, call back, rooms
ASK = KEY_PREFIX + "ask"  # any process to the source: "resync", "explore"
AUDIENCE_KEY = KEY_PREFIX + "audience"  # hash: worker id -> msgpack `Audience`
ROOM_KEY = KEY_PREFIX + "room:"  # + number: an encoded room (Explore on another process)
ROOM_TTL_MS = 20_000
LAST_KEY = KEY_PREFIX + "last"  # the room a presenter left on the shared screen, a `LastRoom` (Explore after it ended)
LAST_TTL_S = 6 * 3600  # [s] kept this long (a lecture's length and more)
KEEP_PERIOD_S = 1.0  # [s] the source publishes its room (no history) this often when it changed
KEEP_RESEND_S = 5.0  # [s] ... and this often unchanged (a worker that came late)
MAX_CATCH_UP_S = 2 * KEEP_PERIOD_S + 1.0  # [s] a kept copy is advanced at most this far to the last frame drawn
CATCH_UP_FRAME_S = 1.0 / 60.0  # [s] of wall time per frame of that advance
LEASE_S = 3.0  # [s] a live source heard nothing from this long: its presenter has left
EXPLORE_TIMEOUT_S = 10.0  # [s] an Explore on another process waits this long for the source's room
RESYNC_PERIOD_S = 1.0  # [s] a process out of step asks again after this long
MAX_MESSAGE_BYTES = 64 << 20  # a bus message larger than this is refused
PLOT_RESEND_S = 5.0  # [s] the presenter's open plot is sent again this often unchanged (a worker that came late)


class Link:
    """One process's end of Redis for the bus: `redis` (the client), `worker_id`, `publish`."""

    def __init__(self, url: str, worker_id: str) -> None:
        self.worker_id = str(worker_id)
        self.redis: Any = connect(url)  # redis.Redis (imported only with --workers)

    def publish(self, channel: str, message: Message) -> int:
        """Publish `message` on `channel` (Redis trouble logged: the followers resync later);
        its size [bytes]."""
        data = encode(message)
        try:
            self.redis.publish(channel, data)
        except Exception:  # noqa: BLE001 - Redis gone for a moment: the followers resync later
            logger.warning("bus: publish failed", exc_info=True)
        return len(data)
