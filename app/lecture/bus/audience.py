"""`AudienceBoard`: each process's audience in Redis (AUDIENCE_KEY), the others' read back for
the presenter's badge and its shared labels' layout."""

from __future__ import annotations

import contextlib
import time

import msgspec

from app.cluster.messages import Audience, decode, encode
from app.kit.draw.screen import Screen
from app.lecture.bus.link import AUDIENCE_KEY, LEASE_S, Link, logger
from app.lecture.bus.values import screen_from_shape, screen_shape
from app.lecture.lectern import FOLLOW_PERIOD, MAX_LABEL_SCREENS, Lectern

__all__ = ["AudienceBoard"]


class AudienceBoard:
    """Every FOLLOW_PERIOD: this process's (following, exploring) and its followers' kinds of
    screen written; with a presenter here, the other processes' fresh entries summed
    (`remote_audience`) and their screens gathered (`remote_screens`)."""

    def __init__(self, link: Link, lectern: Lectern) -> None:
        self.link = link
        self.lectern = lectern
        self.remote_audience = (0, 0)
        self.remote_screens: list[Screen] = []
        self._since = 0.0

    def tick(self, dt: float) -> None:
        self._since += dt
        if self._since >= FOLLOW_PERIOD:
            self._since = 0.0
            try:
                self._write_and_read()
            except Exception:  # noqa: BLE001 - the badge keeps its last figures
                logger.debug("bus: audience not written", exc_info=True)

    def _write_and_read(self) -> None:
        lectern, redis = self.lectern, self.link.redis
        following, exploring = lectern.audience()
        now = time.time()
        screens = [screen_shape(screen) for screen in lectern.follower_screens()] if following else []
        redis.hset(AUDIENCE_KEY, self.link.worker_id, encode(Audience(following, exploring, now, screens)))
        if lectern.presenter is None:
            return
        total = [0, 0]
        remote: list[Screen] = []
        for worker, value in redis.hgetall(AUDIENCE_KEY).items():
            if worker.decode() == self.link.worker_id:
                continue
            try:
                entry = decode(value, Audience)
            except msgspec.DecodeError as error:
                logger.warning("bus: a malformed audience of %s ignored: %s", worker, error)
                continue
            if now - entry.time_s <= LEASE_S:
                total[0] += entry.following
                total[1] += entry.exploring
                for shape in entry.screens[:MAX_LABEL_SCREENS]:
                    screen = screen_from_shape(shape)
                    if screen is not None and screen not in remote:
                        remote.append(screen)
        self.remote_audience = (total[0], total[1])
        self.remote_screens = remote[:MAX_LABEL_SCREENS]

    def remove(self) -> None:
        """This process's entry goes (it ends)."""
        with contextlib.suppress(Exception):
            self.link.redis.hdel(AUDIENCE_KEY, self.link.worker_id)
