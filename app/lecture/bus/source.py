"""`Publisher`: this process's presenter's room, published for the other processes (the source):
its shared scene's batches once a frame (a whole state when asked), the hall, camera and plot
tab at their periods, its room for Explore elsewhere ("room", "keep", LAST_KEY)."""

from __future__ import annotations

import secrets
import time
from typing import Any, Literal

from app.cluster.messages import (
    Ask,
    CallBack,
    Camera,
    Explore,
    HallState,
    Keep,
    LastRoom,
    Resync,
    RoomAnswer,
    SceneBatch,
    encode,
)
from app.kit.core.room import LIVE, Room
from app.lecture.bus.link import (
    CHANNEL,
    KEEP_PERIOD_S,
    KEEP_RESEND_S,
    LAST_KEY,
    LAST_TTL_S,
    PLOT_RESEND_S,
    ROOM_KEY,
    ROOM_TTL_MS,
    Link,
    logger,
)
from app.lecture.bus.values import element_value, plot_message
from app.lecture.bus.wire import Replica, SceneMessage, codec, cull, encode_batch
from app.lecture.follower import Hall, view_aspect
from app.lecture.lectern import CAMERA_PERIOD, FOLLOW_PERIOD, Lectern
from app.lecture.room_plot import MIRROR_PERIOD

__all__ = ["Publisher", "hall_message"]


def hall_message(worker: str, lectern: Lectern, hall: Hall, said: bool = True) -> HallState:
    """The hall's state as the source says it: the followers' status as data
    (`Lectern.follower_status`; none when not `said`), the caption, the title."""
    return HallState(worker=worker, hall=hall.value, title=lectern.live_title(),
                     status=lectern.follower_status().to_dict() if said else {},
                     caption=lectern.caption() if said else ("", ""))


def room_mark(room: Room | None) -> tuple[object, ...]:
    """What a kept copy must be sent again at once when it changes (else a copy advanced to the
    last frame drawn would run from the wrong start): the room, its simulation and its run (a
    restart: a preset, an edit), playing, time scale, live or in the past.  (Not `version`: it
    counts every step.)"""
    if room is None:
        return ()
    sim = room.sim
    return (id(room), id(sim), getattr(sim, "run", None), room.playing, room.time_scale, room.mode)


class Publisher:
    """The source's side of the bus (`active`: this process's presenter's scene is the lecture's).

    Counters: `published_bytes` / `published_batches` (scene batches sent).  `lecture_id`: this
    process's presenter's lecture (a new id at each start), in its batches and LAST_KEY.
    """

    def __init__(self, link: Link, lectern: Lectern) -> None:
        self.link = link
        self.lectern = lectern
        self.active = False
        self.lecture_id = ""
        self.replica = Replica()  # this process's own shared scene (what it publishes as a source)
        self.resync_for: set[str] = set()  # workers that asked for the whole state ("*": everyone)
        self.published_bytes = self.published_batches = 0
        self._seq = 0
        self._hall_due = False
        self._since_hall = self._since_camera = self._since_plot = self._plot_sent_at = self._since_keep = 0.0
        self._camera_sent: Camera | None = None
        self._plot_sent: tuple[str, list[Any]] | None = None  # (tab, its elements' values) last published
        self._room_requests: list[str] = []
        self._room_count = 0
        self._keep_sent: tuple[bytes, float] | None = None  # (data, when) last published as "keep"
        self._keep_mark: tuple[object, ...] = ()  # `room_mark` of the room last kept

    def event(self, event: str) -> None:
        """A lectern's event: "start" (a new lecture), "stopped", "left", "call_back"."""
        if event == "start":
            self.active = True
            self.lecture_id = secrets.token_hex(8)
            self._keep_sent = None
            self._since_keep = KEEP_PERIOD_S  # the first copy with the first frame
            self.resync_for = {"*"}
            self._hall_due = True
        elif event in ("stopped", "left"):
            self._hall_due = True
            self._keep_sent = None  # the lecture's last room goes to LAST_KEY instead
            if self.active:
                self.store_last()
        elif event == "call_back" and self.active:
            self.link.publish(CHANNEL, CallBack(worker=self.link.worker_id))

    def asked(self, message: Ask) -> None:
        """A request on ASK (a source only): a resync, an Explore."""
        if not self.active:
            return
        if isinstance(message, Resync):
            self.resync_for.add(message.worker)
        elif isinstance(message, Explore):
            self._room_requests.append(message.request)

    def send_out(self, batch: list[SceneMessage], dt: float) -> None:
        """After the app loop's frame: keep this frame's batch; a source publishes it, the hall's
        state, camera, plot and kept room at their periods and answers Explore requests."""
        for message in batch:
            self.replica.add(message)
        if not self.active:
            return
        presenting = self.lectern.presenter is not None
        if self.resync_for:
            self._plot_sent = None  # a worker out of step gets the plot too,
            self._camera_sent = None  # and the camera (sent only when it moved): its followers' view
        self._send_scene(batch)
        self._since_plot += dt
        if presenting and self._since_plot >= MIRROR_PERIOD:
            self._send_plot()
        self._since_hall += dt
        if self._hall_due or (presenting and self._since_hall >= FOLLOW_PERIOD):
            self._hall_due = False
            self._since_hall = 0.0
            self.link.publish(CHANNEL, hall_message(self.link.worker_id, self.lectern, self.lectern.hall))
        self._since_camera += dt
        if presenting and self._since_camera >= CAMERA_PERIOD:
            self._since_camera = 0.0
            self._send_camera()
        if self._room_requests:
            self._send_room()
        self._since_keep += dt
        if presenting and (self._since_keep >= KEEP_PERIOD_S or room_mark(self.lectern.live_room) != self._keep_mark):
            self._since_keep = 0.0
            self._send_keep()

    def _send_scene(self, batch: list[SceneMessage]) -> None:
        full: Literal["*"] | list[str] | None = None
        if self.resync_for:
            full = "*" if "*" in self.resync_for else sorted(self.resync_for)
            self.resync_for = set()
            messages = self.replica.messages()
        else:
            messages = cull(batch)
            if not messages:
                return
        dicts, buffers, shapes = encode_batch(messages)
        self._seq += 1
        room = self.lectern.live_room
        message = SceneBatch(worker=self.link.worker_id, seq=self._seq, full=full, messages=dicts, buffers=buffers,
                             shapes=shapes, sent_at=time.time(), title=self.lectern.live_title(),
                             lecture=self.lecture_id, shown_t=None if room is None else float(room.shown_t))
        self.published_bytes += self.link.publish(CHANNEL, message)
        self.published_batches += 1

    def _send_plot(self) -> None:
        """The presenter's open plot tab, when a value changed (viser keeps the object it was last
        given: `is` tells) or PLOT_RESEND_S passed."""
        self._since_plot = 0.0  # looked at once a MIRROR_PERIOD, not every frame
        tab, elements = self.lectern.room_plot()
        values = [element_value(element) for element in elements]
        sent, now = self._plot_sent, time.monotonic()
        if (sent is not None and sent[0] == tab and len(sent[1]) == len(values)
                and all(a is b for a, b in zip(sent[1], values)) and now - self._plot_sent_at < PLOT_RESEND_S):
            return
        self._plot_sent, self._plot_sent_at = (tab, values), now
        try:
            self.link.publish(CHANNEL, plot_message(self.link.worker_id, tab, elements))
        except Exception:  # noqa: BLE001 - a chart property msgpack cannot carry: the followers elsewhere miss it
            logger.warning("bus: the presenter's plot not sent", exc_info=True)

    def _send_camera(self) -> None:
        presenter = self.lectern.presenter
        if presenter is None:
            return
        try:
            camera = presenter.client.camera
            x, y, z = (float(v) for v in camera.position)
            ax, ay, az = (float(v) for v in camera.look_at)
            ux, uy, uz = (float(v) for v in camera.up_direction)
            shot = Camera(worker=self.link.worker_id, position=(x, y, z), look_at=(ax, ay, az), up=(ux, uy, uz),
                          fov=float(camera.fov), aspect=float(view_aspect(camera)))
        except Exception:  # noqa: BLE001 - the presenter's camera is not known yet
            return
        if shot == self._camera_sent:
            return
        self._camera_sent = shot
        self.link.publish(CHANNEL, shot)

    def _send_room(self) -> None:
        """Answer this frame's Explore requests with one encoded copy of the live room."""
        requests, self._room_requests = self._room_requests, []
        answer = RoomAnswer(worker=self.link.worker_id, requests=requests)
        room = self.lectern.live_room
        try:
            if room is None:
                raise RuntimeError("the presenter's process has nothing on the shared screen")
            encode_room, _ = codec()
            with room.lock:
                data = encode_room(room)
            self._room_count += 1
            self.link.redis.set(f"{ROOM_KEY}{self._room_count}", data, px=ROOM_TTL_MS)
            answer.number = self._room_count
        except Exception as error:  # noqa: BLE001 - the asker shows the reason
            logger.warning("bus: the live room could not be sent", exc_info=True)
            answer.error = f"{type(error).__name__}: {error}"
        self.link.publish(CHANNEL, answer)

    def _send_keep(self) -> None:
        """Publish the live room without its history ("keep"): what the other processes copy
        if this one dies (sent when it changed, or KEEP_RESEND_S passed)."""
        room = self.lectern.live_room
        self._keep_mark = room_mark(room)
        if room is None:
            return
        try:
            encode_room, _ = codec()
            with room.lock:
                data = encode_room(room, history=False)
                t, running = float(room.shown_t), bool(room.playing and room.mode == LIVE)
        except Exception:  # noqa: BLE001 - the others keep the last copy they had
            logger.warning("bus: the live room could not be kept elsewhere", exc_info=True)
            return
        now, sent = time.monotonic(), self._keep_sent
        if sent is not None and sent[0] == data and now - sent[1] < KEEP_RESEND_S:
            return
        self._keep_sent = (data, now)
        self.link.publish(CHANNEL, Keep(worker=self.link.worker_id, lecture=self.lecture_id, room=data, shown_t=t,
                                        running=running))

    def store_last(self) -> None:
        """Keep the room on this process's shared screen in Redis (LAST_KEY): what another
        process's Explore copies once this process's presenter has stopped, left or ended."""
        room = self.lectern.live_room
        if room is None:
            return
        try:
            encode_room, _ = codec()
            with room.lock:
                data = encode_room(room)
            self.link.redis.set(LAST_KEY, encode(LastRoom(self.lecture_id, data)), ex=LAST_TTL_S)
        except Exception:  # noqa: BLE001 - then Explore elsewhere says the presenter's process is gone
            logger.warning("bus: the last room could not be kept", exc_info=True)

    def say_left(self) -> None:
        """This process ends while its presenter presents: "left" (the others keep the last state)."""
        self.link.publish(CHANNEL, hall_message(self.link.worker_id, self.lectern, Hall.LEFT, said=False))
