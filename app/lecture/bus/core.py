"""`Bus`: one process's end of the lecture bus (the package docstring), its roles wired together."""

from __future__ import annotations

import collections
import contextlib
import threading
import time

import msgspec
import viser

from app.cluster.messages import ASK_DECODER, LIVE_DECODER, Ask, Explore, Live, Resync, RoomAnswer, SceneBatch
from app.kit.core.room import Room
from app.lecture.bus.audience import AudienceBoard
from app.lecture.bus.follow import Following
from app.lecture.bus.link import ASK, CHANNEL, MAX_MESSAGE_BYTES, Link, logger
from app.lecture.bus.rooms import RemoteRooms
from app.lecture.bus.shared import SharedScene
from app.lecture.bus.source import Publisher
from app.lecture.bus.wire import BusError, SceneMessage, tappable
from app.lecture.lectern import Lectern
from app.viser_internals import divert_queue, interface_of

__all__ = ["Bus"]


class Bus:
    """One process's end of the lecture bus (see the package docstring).

    The app loop calls `take_in()` at the start of each frame (inside `app.wire.capturing()`),
    `apply_frame()` inside it and `send_out(dt)` after the frame's end; a reader thread receives
    from Redis.  Its roles: `publisher` (this process's presenter's room, published), `following`
    (a presenter on another process, followed), `shared` (that presenter's nodes in this
    process's shared scene), `rooms` (Explore here of that presenter's room), `audience`.

    Counters: `published_bytes` / `published_batches` (scene batches sent), `delays` (recent bus
    delays [s], source's publish to this process's frame, scene batches), `resyncs` (full states
    applied).
    """

    def __init__(self, server: viser.ViserServer, lectern: Lectern, url: str, worker_id: str) -> None:
        self.server = server
        self.lectern = lectern
        self.link = Link(url, worker_id)
        self.worker_id = self.link.worker_id
        self.redis = self.link.redis
        self._pubsub = self.redis.pubsub(ignore_subscribe_messages=True)
        self._pubsub.subscribe(CHANNEL, ASK)
        self._inbox: collections.deque[Live | Ask] = collections.deque()
        self._tapped: list[SceneMessage] = []
        self._tap_lock = threading.Lock()
        self._events: collections.deque[str] = collections.deque()
        self.wake: threading.Event | None = None
        """Set when a scene batch arrives (the app's loop then starts its next frame at once:
        followers here get the presenter's frame about when a follower of its process does)."""
        self._queue = divert_queue(interface_of(server), self._tap)  # the app's wire (or viser's) behind the tap
        self.publisher = Publisher(self.link, lectern)
        self.shared = SharedScene(self._queue)
        self.following = Following(self.link, lectern, self.shared, self._yield_source)
        self.rooms = RemoteRooms(self.link, lectern, self.following)
        self.audience = AudienceBoard(self.link, lectern)
        lectern.events.append(self._events.append)
        lectern.remote_audience = lambda: self.audience.remote_audience
        lectern.remote_screens = lambda: self.audience.remote_screens
        lectern.fetch_remote = self.fetch_room
        lectern.fetch_remote_noted = self.fetch_room_noted
        lectern.clear_shared = self._clear_shared
        self._stop = threading.Event()
        self._reader = threading.Thread(target=self._read, name=f"bus-{self.worker_id}", daemon=True)
        self._reader.start()

    # ------------------------------------------------------------------ what others read
    @property
    def source(self) -> bool:
        """This process's presenter's scene is the lecture's."""
        return self.publisher.active

    @source.setter
    def source(self, active: bool) -> None:
        self.publisher.active = active

    @property
    def lecture_id(self) -> str:
        """This process's presenter's lecture (a new id at each start), in its batches and LAST_KEY."""
        return self.publisher.lecture_id

    @property
    def published_bytes(self) -> int:
        return self.publisher.published_bytes

    @property
    def published_batches(self) -> int:
        return self.publisher.published_batches

    @property
    def resyncs(self) -> int:
        return self.shared.resyncs

    @property
    def delays(self) -> collections.deque[float]:
        return self.following.delays

    def _yield_source(self) -> None:
        self.publisher.active = False

    # ------------------------------------------------------------------ in
    def _tap(self, message: SceneMessage) -> None:
        if tappable(message):
            with self._tap_lock:
                self._tapped.append(message)
        self._queue(message)

    def _read(self) -> None:
        while not self._stop.is_set():
            try:
                item = self._pubsub.get_message(timeout=0.2)
            except Exception:  # noqa: BLE001 - Redis gone for a moment: try again
                if self._stop.is_set():
                    return
                logger.warning("bus: Redis read failed", exc_info=True)
                time.sleep(0.5)
                continue
            if item is not None and item.get("type") == "message":
                self._received(item["channel"], item["data"])

    def _received(self, channel: bytes | str, data: object) -> None:
        """One message from Redis, decoded with its channel's type (a malformed one is dropped
        with a log line); an answer to an Explore goes to the thread that waits for it, the rest
        to the inbox (`take_in`)."""
        name = channel.decode() if isinstance(channel, bytes) else str(channel)
        if not isinstance(data, bytes) or len(data) > MAX_MESSAGE_BYTES:
            logger.warning("bus: a message on %s of %s dropped", name, type(data).__name__)
            return
        try:
            message: Live | Ask = (ASK_DECODER if name == ASK else LIVE_DECODER).decode(data)
        except msgspec.DecodeError as error:
            logger.warning("bus: a malformed message on %s dropped: %s", name, error)
            return
        if message.worker == self.worker_id:
            return
        if isinstance(message, RoomAnswer):
            self.rooms.answered(message)
            return
        self._inbox.append(message)
        if isinstance(message, SceneBatch) and self.wake is not None:
            self.wake.set()

    def take_in(self) -> None:
        """Take what came from the other processes (the app loop, before its frame): the hall's
        state into the lectern, requests noted, a whole state (resync) into the shared scene at
        once through viser (its persistent buffer then serves late browsers exactly), scene
        batches kept for `apply_frame`."""
        while self._inbox:
            message = self._inbox.popleft()
            try:
                if isinstance(message, (Resync, Explore)):
                    self.publisher.asked(message)
                else:
                    self.following.heard(message)
            except (BusError, KeyError, TypeError, ValueError) as error:
                logger.warning("bus: a message from %s dropped: %s", message.worker, error)
                self.following.expected = None  # the next batch asks for the whole state
            except Exception:  # noqa: BLE001 - the app loop must not die from a message
                logger.exception("bus: a message from %s failed", message.worker)
                self.following.expected = None
        self.following.check_lease()

    def apply_frame(self) -> None:
        """Queue the scene batches taken in into the shared scene (the app loop, inside its frame:
        the wire encodes them once for every follower)."""
        self.shared.apply_frame()

    def _clear_shared(self) -> None:
        """Remove another process's nodes from the shared scene (this process presents now)."""
        self.following.forget()
        self.shared.clear()

    # ------------------------------------------------------------------ out
    def send_out(self, dt: float) -> None:
        """After the app loop's frame: publish this frame's scene batch (a source), the hall's
        state and camera at their periods, answer Explore requests (one encode for all), write
        this process's audience."""
        with self._tap_lock:
            batch, self._tapped = self._tapped, []
        while self._events:
            event = self._events.popleft()
            if event == "start":
                self.following.remote_worker = None
            self.publisher.event(event)
        self.publisher.send_out(batch, dt)
        self.audience.tick(dt)

    # ------------------------------------------------------------------ Explore on this process
    def fetch_room(self) -> Room:
        """A copy of the remote presenter's room (`fetch_room_noted` without its note)."""
        return self.fetch_room_noted()[0]

    def fetch_room_noted(self) -> tuple[Room, str]:
        """(a copy of the remote presenter's room, a note: "" for an exact copy): see
        `RemoteRooms.fetch_noted`."""
        return self.rooms.fetch_noted()

    def close(self) -> None:
        """Say "left" if this process's presenter is still on (its room kept for Explore
        elsewhere), and stop reading."""
        if self.publisher.active:
            self.publisher.store_last()
            if self.lectern.presenter is not None:
                with contextlib.suppress(Exception):
                    self.publisher.say_left()
        self.audience.remove()
        self._stop.set()
        self._reader.join(timeout=2.0)
        with contextlib.suppress(Exception):
            self._pubsub.close()
        with contextlib.suppress(Exception):
            self.redis.close()
