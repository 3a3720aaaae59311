"""`RemoteRooms`: Explore on this process while the presenter is on another: its room asked of
its process, else the room its lecture left (LAST_KEY), else the copy kept here or its scene."""

from __future__ import annotations

import secrets
import threading
import time

import msgspec

from app.cluster.messages import Explore, LastRoom, RoomAnswer, decode
from app.kit.core.room import LIVE, Room
from app.lecture.bus.follow import Following
from app.lecture.bus.link import (
    ASK,
    CATCH_UP_FRAME_S,
    EXPLORE_TIMEOUT_S,
    LAST_KEY,
    MAX_CATCH_UP_S,
    ROOM_KEY,
    Link,
    logger,
)
from app.lecture.bus.wire import DecodeRoom, codec
from app.lecture.follower import Hall
from app.lecture.lectern import Lectern
from app.scenes import SCENES

__all__ = ["RemoteRooms"]


class _Waiting:
    """An Explore request's answer, awaited: `done` set with `key` (the room's) or `error`."""

    def __init__(self) -> None:
        self.done = threading.Event()
        self.key = ""
        self.error = ""


class RemoteRooms:
    """Copies of the remote presenter's room (Explore on this process), from what `following` kept."""

    def __init__(self, link: Link, lectern: Lectern, following: Following) -> None:
        self.link = link
        self.lectern = lectern
        self.following = following
        self._waiting: dict[str, _Waiting] = {}  # explore request id -> its answer

    def answered(self, message: RoomAnswer) -> None:
        """The source's answer to Explore requests (the reader thread: the asking thread waits for it)."""
        for request in message.requests:
            waiting = self._waiting.get(request)
            if waiting is not None:
                if message.error or message.number is None:
                    waiting.error = str(message.error)
                else:
                    waiting.key = f"{ROOM_KEY}{message.number}"
                waiting.done.set()

    def fetch_noted(self) -> tuple[Room, str]:
        """(a copy of the remote presenter's room, a note: "" for an exact copy).

        The best to be had: the room asked of its process and decoded here, bit for bit (while
        it presents); once that presenter has stopped or left, or its process does not answer,
        the room the lecture left (LAST_KEY of this lecture, exact); else the last copy this
        process kept (`Kept`, brought to the last frame drawn here, paused) or a fresh room of
        the same scene, each with a note saying so.  RuntimeError when the source answered with
        an error, or nothing of the lecture is known here (not even its scene)."""
        _, decode_room = codec()
        remote = self.lectern.remote
        if remote is None or remote.hall is Hall.LIVE:
            asked = self._ask_source(decode_room)
            if asked is not None:
                return asked, ""
        last = self._last_of_this_lecture(decode_room)
        if last is not None:
            return last, ""
        return self._orphan_copy(decode_room)

    def _ask_source(self, decode_room: DecodeRoom) -> Room | None:
        """The live room, asked of the source; None when it does not answer within
        EXPLORE_TIMEOUT_S or its presenter stops or leaves meanwhile (killed: after LEASE_S)."""
        request = secrets.token_hex(8)
        waiting = self._waiting[request] = _Waiting()
        try:
            self.link.publish(ASK, Explore(worker=self.link.worker_id, request=request))
            deadline = time.monotonic() + EXPLORE_TIMEOUT_S
            while not waiting.done.wait(0.05):  # the answer, or the presenter leaving meanwhile
                remote = self.lectern.remote
                if time.monotonic() > deadline or remote is None or remote.hall is not Hall.LIVE:
                    break
            if not waiting.done.is_set():
                return None
            if waiting.error:
                raise RuntimeError(f"the presenter's process could not send its room: {waiting.error}")
            data = self.link.redis.get(waiting.key)
            if data is None:
                raise RuntimeError("the presenter's room expired before it was read")
            return decode_room(data)
        finally:
            self._waiting.pop(request, None)

    def _last_of_this_lecture(self, decode_room: DecodeRoom) -> Room | None:
        """The room kept in LAST_KEY if the lecture shown here left it (an older lecture's: None)."""
        data = self.link.redis.get(LAST_KEY)
        if data is None or not self.following.remote_lecture:
            return None
        try:
            last = decode(data, LastRoom)
        except msgspec.DecodeError as error:
            logger.warning("bus: a malformed last room ignored: %s", error)
            return None
        if last.lecture != self.following.remote_lecture:
            return None
        return decode_room(last.data)

    def _orphan_copy(self, decode_room: DecodeRoom) -> tuple[Room, str]:
        """The presenter's process is gone (or silent) and left nothing in Redis: the last copy
        kept here, brought to the last frame drawn here and paused, else a fresh room of the
        scene; with the note saying which."""
        remote = self.lectern.remote
        gone = "is gone" if remote is None or remote.hall is not Hall.LIVE else "does not answer"
        kept, seen_t = self.following.kept, self.following.seen_t
        if kept is not None and kept.lecture == self.following.remote_lecture:
            try:
                room = decode_room(kept.data)
            except Exception:  # noqa: BLE001 - then the scene alone
                logger.warning("bus: the kept copy of the presenter's room could not be read", exc_info=True)
            else:
                if kept.running and seen_t is not None:
                    catch_up(room, min(seen_t, kept.t + MAX_CATCH_UP_S))
                room.playing = False
                return room, (f"The presenter's worker {gone}: this is the last state of its room that this "
                              f"server saw (t = {room.shown_t:.2f} s), paused.")
        title = remote.title if remote is not None else ""
        scene = SCENES.get(title)
        if scene is None:
            raise RuntimeError(f"the presenter's process {gone} and nothing of its room reached this one")
        return Room(scene, scene.new_simulation()), (
            f"The presenter's worker {gone} and none of its room reached this server: only the scene "
            f"({title}) could be kept, in a fresh room.")


def catch_up(room: Room, t_s: float) -> None:
    """Advance a playing live `room` in frames of CATCH_UP_FRAME_S (times its time scale) until
    its time reaches `t_s` [s] (a kept copy brought to the last frame drawn)."""
    scale = room.time_scale
    if not scale > 0:
        return
    with room.lock:
        for _ in range(int(MAX_CATCH_UP_S / CATCH_UP_FRAME_S / min(max(scale, 0.1), 1.0)) + 2):
            left_s = t_s - room.shown_t
            if not room.playing or room.mode != LIVE or left_s <= 1e-12:
                return
            room.advance(min(CATCH_UP_FRAME_S, left_s / scale))
