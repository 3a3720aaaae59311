"""One lecture across processes: what followers on another process see, through Redis.

**The design, and why.**  The presenting process (the *source*) already draws its presenter's
room once per frame into viser's shared scene (`server.scene`, under LIVE_ROOT, the pointer
too).  The bus taps the messages queued to that shared interface (`divert_queue`, in front of
the app's `Wire`) and publishes them once per frame, as msgpack of viser's own message dicts
(`Message.as_serializable_dict`, numpy arrays as raw buffers), culled as viser culls (one value
per node and property).  Every other process decodes them into viser message objects of an
allowlisted set of scene types (`ALLOWED`; names under LIVE_ROOT only;
`app.viser_internals.message_from_dict` takes the class from viser's own registry: nothing is
imported, executed or unpickled) and queues them into *its* shared scene inside its app loop's
frame, so its `Wire` encodes each frame once for all its followers and viser's persistent buffer
serves its late joiners exactly as on one process.  Sending the scene's messages, not simulation
snapshots, keeps one simulation and one drawing per lecture (the other processes do no physics
for the lecture) and makes a remote follower's scene the same messages a local follower gets.

- Order and gaps: the scene batches carry a sequence number; a process that joins late or sees
  a gap asks (`ASK`, "resync") and the source publishes its shared scene's whole state (`Replica`:
  the last create and the last value of every node under LIVE_ROOT, kept from the same tap);
  the one that asked removes the nodes the state no longer has and applies it.
- The hall's state (the followers' status as data, `FollowerStatus`; the caption, the title)
  goes as a small dict every FOLLOW_PERIOD, the presenter's camera (with its aspect, so each
  follower's view is framed for its screen as on one process) at most every CAMERA_PERIOD when it
  moved, and again after a resync (a process that came late has never heard it); a "call_back"
  when the presenter calls everyone back.  Another process shows it as a
  `app.lectern.RemoteShow` (its `Lectern` then has a live show without a local room).
- The presenter's open plot tab (`Lectern.room_plot`: uPlot charts as float32 columns and their
  properties, Markdown) goes when it changed, at most every MIRROR_PERIOD and at least every
  PLOT_RESEND_S; another process's followers see it copied as on one process (`RemoteShow.plot`).
- Stopped and left: the source says "stopped" or "left" when its presenter stops or leaves (or
  its process stops); a process that hears nothing from a live source for LEASE_S takes it that
  the presenter has left (its process ended).  The last state stays on the followers' screens.
- Explore on another process: it asks the source ("explore", with a request id); the source
  encodes its live room ONCE for all the requests of a frame (`encode_room`, the kit's codec),
  stores the bytes under ROOM_KEY + n for ROOM_TTL_MS and answers with n; the asker decodes it
  (`decode_room`: checked, bit for bit the presenter's state).
- A lecture survives its source's death.  Each presenter's start is a new lecture (`lecture_id`,
  carried in its scene batches); its room left on the shared screen is kept in Redis (LAST_KEY)
  with that id, so only that lecture's followers copy it (an older lecture's room, kept
  LAST_TTL_S, is never offered for a newer one).  While it presents, the source also publishes
  its room without history ("keep", `encode_room(history=False)`, under 0.5 ms, up to ~280 kB:
  ~250 kB/s for Heavy top playing) at once when its run or transport changes (`_room_mark`),
  else every KEEP_PERIOD_S when it changed; every process keeps the last one of the lecture it shows
  (`Kept`), and each scene batch says the room's time ("st").  Explore when the source does not
  answer (killed: SIGKILL says nothing) gives, the best first: the room the lecture left in Redis
  (exact: stored when its presenter stopped or left, after the last keep), else the kept copy
  advanced to the time of the last batch this process drew (at most MAX_CATCH_UP_S; the same
  integrator, frames of 1/60 s) and paused, else a fresh room of the same scene; the last two
  with a note saying so (`fetch_room_noted`).
- Audience: each process writes its (following, exploring) into the hash AUDIENCE_KEY every
  FOLLOW_PERIOD with the time and its followers' kinds of screen (`Lectern.follower_screens`);
  the presenter's badge adds the others' fresh counts, and its shared labels are laid out for
  their screens too (`Lectern.remote_screens`: a phone on another process sees no overlap).

Channels and keys start with `app.cluster.KEY_PREFIX`.  Everything read from Redis is msgpack of
plain values, checked (types, sizes, names) before use; a bad message is logged and dropped.
The bus is made only with `create_server(redis_url=...)`: a one-process app has none.
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import logging
import math
import secrets
import threading
import time
from collections.abc import Iterable
from typing import Any

import msgspec.msgpack
import numpy as np

from app.cluster import KEY_PREFIX, connect
from app.hall.follower import FollowerStatus, Hall, view_aspect
from app.hall.room_plot import MIRROR_PERIOD, UPLOT_PROPS, ChartCopy, MarkdownCopy, is_chart
from app.kit.core.common import CameraView
from app.kit.core.room import LIVE, Room
from app.kit.draw.screen import Screen
from app.kit.view import PLOT_TABS
from app.lectern import CAMERA_PERIOD, FOLLOW_PERIOD, LIVE_ROOT, MAX_LABEL_SCREENS, POINTER_ROOT, Lectern, RemoteShow
from app.scenes import SCENES
from app.viser_internals import divert_queue, interface_of, message_from_dict

__all__ = ["ALLOWED", "ASK", "AUDIENCE_KEY", "CHANNEL", "LAST_KEY", "LEASE_S", "Bus", "BusError", "Kept", "Replica",
           "cull", "decode_batch", "encode_batch"]

logger = logging.getLogger(__name__)

CHANNEL = KEY_PREFIX + "live"  # the source to every process: scene batches, the hall, camera, call back, rooms
ASK = KEY_PREFIX + "ask"  # any process to the source: "resync", "explore"
AUDIENCE_KEY = KEY_PREFIX + "audience"  # hash: worker id -> msgpack [following, exploring, time [s], screens]
ROOM_KEY = KEY_PREFIX + "room:"  # + number: an encoded room (Explore on another process)
ROOM_TTL_MS = 20_000
LAST_KEY = KEY_PREFIX + "last"  # the room a presenter left on the shared screen, encoded (Explore after it ended)
LAST_TTL_S = 6 * 3600  # [s] kept this long (a lecture's length and more)
KEEP_PERIOD_S = 1.0  # [s] the source publishes its room (no history) this often when it changed
KEEP_RESEND_S = 5.0  # [s] ... and this often unchanged (a worker that came late)
MAX_CATCH_UP_S = 2 * KEEP_PERIOD_S + 1.0  # [s] a kept copy is advanced at most this far to the last frame drawn
CATCH_UP_FRAME_S = 1.0 / 60.0  # [s] of wall time per frame of that advance
MAX_LECTURE_ID = 64  # characters of a lecture id read from Redis
LEASE_S = 3.0  # [s] a live source heard nothing from this long: its presenter has left
EXPLORE_TIMEOUT_S = 10.0  # [s] an Explore on another process waits this long for the source's room
RESYNC_PERIOD_S = 1.0  # [s] a process out of step asks again after this long
MAX_MESSAGE_BYTES = 64 << 20  # a bus message larger than this is refused
MAX_DEPTH = 8  # nesting of a message dict
PLOT_RESEND_S = 5.0  # [s] the presenter's open plot is sent again this often unchanged (a worker that came late)
MAX_PLOT_ELEMENTS = 16  # a plot tab's elements, carried
MAX_PLOT_COLUMNS = 16  # a chart's columns (x and its series)
MAX_PLOT_SAMPLES = 20_000  # a column's samples
MAX_PLOT_PROP_VALUES = 2_000  # the plain values in a chart's properties (its series, scales, axes ...)
ALLOWED = frozenset({
    "FrameMessage", "BatchedAxesMessage", "GridMessage", "LabelMessage", "PointCloudMessage", "MeshMessage",
    "BoxMessage", "IcosphereMessage", "CylinderMessage", "GlbMessage", "BatchedMeshesMessage", "BatchedGlbMessage",
    "LineSegmentsMessage", "ArrowMessage", "CatmullRomSplineMessage", "CubicBezierSplineMessage", "ImageMessage",
    "RemoveSceneNodeMessage", "SetOrientationMessage", "SetPositionMessage", "SetSceneNodeVisibilityMessage",
    "SceneNodeUpdateMessage"})
"""The viser message types the bus carries: drawings of the shared scene (no gizmo, no panel)."""
DTYPES = frozenset({"<f4", "<f8", "|u1", "<u2", "<u4", "<i4", "|i1", "<i2", "<i8", "<u8", "|b1"})


class BusError(ValueError):
    """A bus message that is not what the bus sends (dropped, logged)."""


@dataclasses.dataclass(frozen=True)
class Kept:
    """The last copy of the remote presenter's room this process received ("keep").

    Attributes:
        lecture: the lecture id it belongs to.  data: `encode_room(room, history=False)`.
        t: the room's shown time [s] when encoded.  running: it was live and playing (a copy
            may then be advanced to the time last drawn here).
    """

    lecture: str
    data: bytes
    t: float
    running: bool


def _live_name(name: Any) -> bool:
    return isinstance(name, str) and (name == LIVE_ROOT or name.startswith(LIVE_ROOT + "/"))


def _tappable(message: Any) -> bool:
    return type(message).__name__ in ALLOWED and _live_name(getattr(message, "name", None))


# ---------------------------------------------------------------------- messages as bytes
def encode_batch(messages: Iterable[Any]) -> tuple[list[Any], list[bytes], list[list[int]]]:
    """viser messages as (dicts, buffers, shapes): each `as_serializable_dict` with its numpy
    arrays as placeholders {"__binary_index": i, "dtype": ...} into `buffers` (raw bytes), each
    array's shape in `shapes`."""
    views: list[memoryview] = []
    dicts = [message.as_serializable_dict(views) for message in messages]
    return dicts, [bytes(view) for view in views], [list(view.shape or ()) for view in views]


def _restore(value: Any, buffers: list[bytes], shapes: list[Any], depth: int = 0) -> Any:
    """`value` with every buffer placeholder replaced by a flat numpy array (checked dtype)."""
    if depth > MAX_DEPTH:
        raise BusError("too deeply nested")
    if isinstance(value, dict):
        if "__binary_index" in value:
            index, dtype = value.get("__binary_index"), value.get("dtype")
            if not isinstance(index, int) or not 0 <= index < len(buffers) or dtype not in DTYPES:
                raise BusError(f"bad buffer placeholder {value!r}"[:200])
            data, shape = buffers[index], shapes[index]
            if not (isinstance(shape, list) and len(shape) <= 4 and all(isinstance(n, int) and n >= 0 for n in shape)
                    and int(np.prod(shape)) * np.dtype(dtype).itemsize == len(data)):
                raise BusError("a buffer's size does not fit its dtype and shape")
            return np.frombuffer(data, dtype=dtype).reshape(shape)
        return {key: _restore(item, buffers, shapes, depth + 1) for key, item in value.items()
                if isinstance(key, str)}
    if isinstance(value, list):
        return [_restore(item, buffers, shapes, depth + 1) for item in value]
    if isinstance(value, (str, int, float, bool, bytes)) or value is None:
        return value
    raise BusError(f"unexpected value of type {type(value).__name__}")


def decode_batch(dicts: Any, buffers: Any, shapes: Any) -> list[Any]:
    """viser message objects from `encode_batch`'s output, read from Redis: only ALLOWED types,
    only nodes under LIVE_ROOT; BusError (nothing built) for anything else."""
    if not isinstance(dicts, list) or not isinstance(buffers, list) or not all(isinstance(b, bytes) for b in buffers) \
            or not isinstance(shapes, list) or len(shapes) != len(buffers):
        raise BusError("a scene batch is a list of messages, one of buffers and one of their shapes")
    out = []
    for mapping in dicts:
        if not isinstance(mapping, dict) or not _live_name(mapping.get("name")):
            raise BusError(f"not a message under {LIVE_ROOT}: {str(mapping)[:120]}")
        try:
            out.append(message_from_dict(_restore(mapping, buffers, shapes), ALLOWED))
        except ValueError as error:
            raise BusError(str(error)) from None
    return out


def cull(messages: list[Any]) -> list[Any]:
    """`messages` without the updates a later update of the same node and property supersedes
    (as viser's buffer culls; safe across a node's removal or re-creation in between: the
    earlier value belonged to the node that went)."""
    seen: set[str] = set()
    kept = []
    for message in reversed(messages):
        if getattr(message, "lifecycle_phase", None) in ("update_simple", "update_dict"):
            key = message.redundancy_key()
            if key in seen:
                continue
            seen.add(key)
        kept.append(message)
    kept.reverse()
    return kept


class Replica:
    """The shared scene's state under LIVE_ROOT, kept from its messages: each node's last create
    and the last value of each of its properties, in order (a late process's resync)."""

    def __init__(self) -> None:
        self.entries: dict[tuple[str, str], Any] = {}

    def _drop(self, name: str, subtree: bool) -> None:
        under = name + "/"
        for key in [k for k, m in self.entries.items()
                    if m.name == name or (subtree and m.name.startswith(under))]:
            del self.entries[key]

    def add(self, message: Any) -> None:
        phase, name = getattr(message, "lifecycle_phase", None), message.name
        if phase == "remove":
            self._drop(name, subtree=True)
        elif phase == "create":
            self._drop(name, subtree=False)
            self.entries[("c", name)] = message
        else:
            key = ("u", message.redundancy_key())
            if ("c", name) in self.entries or name == LIVE_ROOT:
                self.entries[key] = message

    def nodes(self) -> set[str]:
        return {name for kind, name in self.entries if kind == "c"}

    def messages(self) -> list[Any]:
        return list(self.entries.values())


# ---------------------------------------------------------------------- the bus
class Bus:
    """One process's end of the lecture bus (see the module docstring).

    The app loop calls `take_in()` at the start of each frame (inside `app.wire.capturing()`)
    and `send_out(dt)` after the frame's end; a reader thread receives from Redis.

    Counters: `published_bytes` / `published_batches` (scene batches sent), `delays` (recent bus
    delays [s], source's publish to this process's frame, scene batches), `resyncs` (full states
    applied).
    """

    def __init__(self, server: Any, lectern: Lectern, url: str, worker_id: str) -> None:
        self.server = server
        self.lectern = lectern
        self.worker_id = str(worker_id)
        self.redis = connect(url)
        self._pubsub = self.redis.pubsub(ignore_subscribe_messages=True)
        self._pubsub.subscribe(CHANNEL, ASK)
        self._inbox: collections.deque[tuple[str, dict[str, Any]]] = collections.deque()
        self._tapped: list[Any] = []
        self._pending: list[Any] = []  # scene messages taken in, for this frame (`apply_frame`)
        self._tap_lock = threading.Lock()
        self._replica = Replica()  # this process's own shared scene (what it publishes as a source)
        self._applied = Replica()  # what it applied of another's (nodes to drop on a resync)
        self.source = False  # this process's presenter's scene is the lecture's
        self._seq = 0
        self._remote_worker: str | None = None
        self._expected: int | None = None
        self._asked_at = -float("inf")
        self._heard_at = time.monotonic()
        self._resync_for: set[str] = set()  # workers that asked for the whole state ("*": everyone)
        self._hall_due = False
        self._since_hall = self._since_camera = self._since_audience = 0.0
        self._camera_sent: Any = None
        self._since_plot = self._plot_sent_at = 0.0
        self._plot_sent: tuple[str, list[Any]] | None = None  # (tab, its elements' values) last published
        self._room_requests: list[str] = []
        self.lecture_id = ""
        """This process's presenter's lecture (a new id at each start), in its batches and LAST_KEY."""
        self._since_keep = 0.0
        self._keep_sent: tuple[bytes, float] | None = None  # (data, when) last published as "keep"
        self._keep_mark: tuple[Any, ...] = ()  # `_room_mark` of the room last kept
        self._remote_lecture = ""  # the lecture of the remote presenter shown here
        self._kept: Kept | None = None  # its room's last copy received
        self._seen_t: float | None = None  # its room's time [s] in the last scene batch drawn here
        self._room_count = 0
        self._waiting: dict[str, list[Any]] = {}  # explore request id -> [Event, room key or error]
        self._events: collections.deque[str] = collections.deque()
        self._remote_audience = (0, 0)
        self._remote_screens: list[Screen] = []
        self.published_bytes = self.published_batches = self.resyncs = 0
        self.delays: collections.deque[float] = collections.deque(maxlen=2000)
        self.wake: threading.Event | None = None
        """Set when a scene batch arrives (the app's loop then starts its next frame at once:
        followers here get the presenter's frame about when a follower of its process does)."""
        self._queue = divert_queue(interface_of(server), self._tap)  # the app's wire (or viser's) behind the tap
        lectern.events.append(self._events.append)
        lectern.remote_audience = lambda: self._remote_audience
        lectern.remote_screens = lambda: self._remote_screens
        lectern.fetch_remote = self.fetch_room
        lectern.fetch_remote_noted = self.fetch_room_noted
        lectern.clear_shared = self._clear_shared
        self._stop = threading.Event()
        self._reader = threading.Thread(target=self._read, name=f"bus-{self.worker_id}", daemon=True)
        self._reader.start()

    # ------------------------------------------------------------------ in
    def _tap(self, message: Any) -> None:
        if _tappable(message):
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
            if item is None or item.get("type") != "message":
                continue
            channel = item["channel"].decode() if isinstance(item["channel"], bytes) else str(item["channel"])
            data = item["data"]
            if not isinstance(data, bytes) or len(data) > MAX_MESSAGE_BYTES:
                continue
            try:
                body = msgspec.msgpack.decode(data)
            except msgspec.DecodeError:
                logger.warning("bus: undecodable message on %s dropped", channel)
                continue
            if not isinstance(body, dict) or body.get("w") == self.worker_id:
                continue
            if body.get("k") == "room":  # an answer to an Explore: the asking thread waits for it
                self._answered(body)
                continue
            self._inbox.append((channel, body))
            if body.get("k") == "scene" and self.wake is not None:
                self.wake.set()

    def _answered(self, body: dict[str, Any]) -> None:
        number, error = body.get("n"), body.get("error")
        for request in body.get("for", []) if isinstance(body.get("for"), list) else []:
            waiting = self._waiting.get(request) if isinstance(request, str) else None
            if waiting is not None:
                waiting[1] = ("error", str(error)) if error or not isinstance(number, int) \
                    else ("key", f"{ROOM_KEY}{number}")
                waiting[0].set()

    def take_in(self) -> None:
        """Take what came from the other processes (the app loop, before its frame): the hall's
        state into the lectern, requests noted, a whole state (resync) into the shared scene at
        once through viser (its persistent buffer then serves late browsers exactly), scene
        batches kept for `apply_frame`."""
        lectern = self.lectern
        while self._inbox:
            channel, body = self._inbox.popleft()
            try:
                if channel == ASK:
                    self._asked(body)
                else:
                    self._heard(body)
            except (BusError, KeyError, TypeError, ValueError) as error:
                logger.warning("bus: a message from %s dropped: %s", body.get("w"), error)
                self._expected = None  # the next batch asks for the whole state
            except Exception:  # noqa: BLE001 - the app loop must not die from a message
                logger.exception("bus: a message from %s failed", body.get("w"))
                self._expected = None
        remote = lectern.remote
        if (remote is not None and remote.hall is Hall.LIVE and self._remote_worker is not None
                and time.monotonic() - self._heard_at > LEASE_S):
            lectern.remote_ended(left=True)
            self._drop_pointer()

    def _drop_pointer(self) -> None:
        """The pointer's markers of a source that went silent (killed: it never removes them) go
        from the shared scene; the rest stays, the last state it showed."""
        markers = [name for name in self._applied.nodes() if name.startswith(POINTER_ROOT + "/")
                   and "/" not in name[len(POINTER_ROOT) + 1:]]
        for name in sorted(markers):
            message = message_from_dict({"type": "RemoveSceneNodeMessage", "name": name}, ALLOWED)
            self._queue(message)
            self._applied.add(message)

    def _asked(self, body: dict[str, Any]) -> None:
        if not self.source:
            return
        kind, worker = body.get("k"), str(body.get("w"))
        if kind == "resync":
            self._resync_for.add(worker)
        elif kind == "explore" and isinstance(body.get("r"), str):
            self._room_requests.append(body["r"][:64])

    def _heard(self, body: dict[str, Any]) -> None:
        worker, kind = str(body.get("w")), body.get("k")
        lectern = self.lectern
        if kind == "scene":
            full = body.get("full")
            mine = full == "*" or (isinstance(full, list) and self.worker_id in full)
            if full == "*" or (mine and (self._remote_worker != worker or lectern.remote is None)):
                self.source = False  # a presenter elsewhere: this process's scene is no longer the lecture's
                self._remote_worker = worker
                lectern.show_remote(RemoteShow(worker=worker, title=str(body.get("title", ""))[:200]))
            if worker != self._remote_worker:
                return
            self._heard_at = time.monotonic()
            self._lecture_heard(body.get("lid"))
            seq = int(body["s"])
            if mine or (full is not None and seq != self._expected):  # also another's resync, if out of step
                self._apply_full(decode_batch(body["m"], body["b"], body["sh"]))
                self._expected = seq + 1
                self._seen(body.get("st"))
            elif full is not None or seq == self._expected:
                if full is None:
                    self._apply(decode_batch(body["m"], body["b"], body["sh"]))
                self._expected = seq + 1
                self._seen(body.get("st"))
            else:
                self._expected = None
                self._ask_resync()
            sent = body.get("t")
            if isinstance(sent, float):
                self.delays.append(time.time() - sent)
            return
        if worker != self._remote_worker:
            if kind == "hall" and body.get("hall") == Hall.LIVE.value and self._remote_worker is None:
                self._ask_resync(worker)  # a lecture already on: this process came late
            return
        self._heard_at = time.monotonic()
        remote = lectern.remote
        if remote is None:
            return
        if kind == "hall":
            hall = body.get("hall")
            status = FollowerStatus.from_dict(body.get("status"))  # checked: ValueError drops the message
            remote.title = str(body.get("title", ""))[:200]
            remote.status = status
            caption = body.get("caption")
            remote.caption = ((str(caption[0])[:400], str(caption[1])[:4000])
                              if isinstance(caption, list) and len(caption) == 2 else ("", ""))
            if hall in (Hall.STOPPED.value, Hall.LEFT.value):
                lectern.remote_ended(left=hall == Hall.LEFT.value)
        elif kind == "camera":
            remote.camera = _camera(body)
            for follower in list(lectern.followers.values()):
                lectern.send_camera(follower)
        elif kind == "plot":
            plot = _plot_from_plain(body, remote.plot)
            if plot is None:
                logger.warning("bus: a plot message from %s refused", worker)
            else:
                remote.plot = plot
        elif kind == "call_back" and remote.hall is Hall.LIVE:
            lectern.remote_call_back()
        elif kind == "keep":
            data, lecture, t = body.get("room"), body.get("lid"), body.get("st")
            if (isinstance(data, bytes) and isinstance(lecture, str) and lecture == self._remote_lecture
                    and isinstance(t, float) and math.isfinite(t)):
                self._kept = Kept(lecture, data, t, body.get("run") is True)

    def _lecture_heard(self, lecture: Any) -> None:
        """The remote presenter's lecture id (a new lecture: what was kept of the last one goes)."""
        lecture = lecture if isinstance(lecture, str) and len(lecture) <= MAX_LECTURE_ID else ""
        if lecture != self._remote_lecture:
            self._remote_lecture = lecture
            self._kept = None
            self._seen_t = None

    def _seen(self, t: Any) -> None:
        if isinstance(t, float) and math.isfinite(t):
            self._seen_t = t

    def _ask_resync(self, worker: str | None = None) -> None:
        now = time.monotonic()
        if now - self._asked_at < RESYNC_PERIOD_S:
            return
        self._asked_at = now
        self._publish(ASK, {"k": "resync", "w": self.worker_id, "to": worker or self._remote_worker})

    def apply_frame(self) -> None:
        """Queue the scene batches taken in into the shared scene (the app loop, inside its frame:
        the wire encodes them once for every follower)."""
        pending, self._pending = self._pending, []
        for message in pending:
            self._queue(message)

    def _apply(self, messages: list[Any]) -> None:
        for message in messages:
            self._applied.add(message)
        self._pending.extend(messages)

    def _apply_full(self, messages: list[Any]) -> None:
        """The source's whole state: the nodes it no longer has go, then everything is applied
        (what was kept for this frame is older: dropped)."""
        self._pending = []
        state = Replica()
        for message in messages:
            state.add(message)
        gone = self._applied.nodes() - state.nodes()
        for name in sorted(gone, key=len):
            if not any(name.startswith(other + "/") for other in gone):
                self._queue(message_from_dict({"type": "RemoveSceneNodeMessage", "name": name}, ALLOWED))
        self._applied = state
        for message in messages:
            self._queue(message)
        self.resyncs += 1

    def _clear_shared(self) -> None:
        """Remove another process's nodes from the shared scene (this process presents now): each
        node by name, the deepest first.  (One removal of LIVE_ROOT is not enough: the new view's
        first node of that name supersedes it in viser's buffers, and the old nodes under it
        stayed on this process's followers' screens, and in what a late browser is sent.)"""
        self._remote_worker = None
        self._expected = None
        self._lecture_heard("")  # what was kept of the other's lecture goes with it
        names = self._applied.nodes()
        for name in sorted(names, key=lambda n: (-n.count("/"), n)):
            self._queue(message_from_dict({"type": "RemoveSceneNodeMessage", "name": name}, ALLOWED))
        if names:
            self._queue(message_from_dict({"type": "RemoveSceneNodeMessage", "name": LIVE_ROOT}, ALLOWED))
        self._applied = Replica()

    # ------------------------------------------------------------------ out
    def send_out(self, dt: float) -> None:
        """After the app loop's frame: publish this frame's scene batch (a source), the hall's
        state and camera at their periods, answer Explore requests (one encode for all), write
        this process's audience."""
        lectern = self.lectern
        with self._tap_lock:
            batch, self._tapped = self._tapped, []
        for message in batch:
            self._replica.add(message)
        while self._events:
            event = self._events.popleft()
            if event == "start":
                self.source = True
                self.lecture_id = secrets.token_hex(8)
                self._keep_sent = None
                self._since_keep = KEEP_PERIOD_S  # the first copy with the first frame
                self._remote_worker = None
                self._resync_for = {"*"}
                self._hall_due = True
            elif event in ("stopped", "left"):
                self._hall_due = True
                self._keep_sent = None  # the lecture's last room goes to LAST_KEY instead
                if self.source:
                    self._store_last()
            elif event == "call_back" and self.source:
                self._publish(CHANNEL, {"k": "call_back", "w": self.worker_id})
        if self.source:
            if self._resync_for:
                self._plot_sent = None  # a worker out of step gets the plot too,
                self._camera_sent = None  # and the camera (sent only when it moved): its followers' view
            self._send_scene(batch)
            self._since_plot += dt
            if lectern.presenter is not None and self._since_plot >= MIRROR_PERIOD:
                self._send_plot()
            self._since_hall += dt
            if self._hall_due or (lectern.presenter is not None and self._since_hall >= FOLLOW_PERIOD):
                self._hall_due = False
                self._since_hall = 0.0
                self._send_hall()
            self._since_camera += dt
            if lectern.presenter is not None and self._since_camera >= CAMERA_PERIOD:
                self._since_camera = 0.0
                self._send_camera()
            if self._room_requests:
                self._send_room()
            self._since_keep += dt
            if lectern.presenter is not None and (self._since_keep >= KEEP_PERIOD_S
                                                  or _room_mark(lectern.live_room) != self._keep_mark):
                self._since_keep = 0.0
                self._send_keep()
        self._since_audience += dt
        if self._since_audience >= FOLLOW_PERIOD:
            self._since_audience = 0.0
            self._audience()

    def _publish(self, channel: str, body: dict[str, Any]) -> int:
        data = msgspec.msgpack.encode(body)
        try:
            self.redis.publish(channel, data)
        except Exception:  # noqa: BLE001 - Redis gone for a moment: the followers resync later
            logger.warning("bus: publish failed", exc_info=True)
        return len(data)

    def _send_scene(self, batch: list[Any]) -> None:
        full: Any = None
        if self._resync_for:
            full = "*" if "*" in self._resync_for else sorted(self._resync_for)
            self._resync_for = set()
            messages = self._replica.messages()
        else:
            messages = cull(batch)
            if not messages:
                return
        dicts, buffers, shapes = encode_batch(messages)
        self._seq += 1
        room = self.lectern.live_room
        body = {"k": "scene", "w": self.worker_id, "s": self._seq, "full": full, "m": dicts, "b": buffers, "sh": shapes,
                "t": time.time(), "title": self.lectern.live_title(), "lid": self.lecture_id,
                "st": None if room is None else float(room.shown_t)}
        self.published_bytes += self._publish(CHANNEL, body)
        self.published_batches += 1

    def _send_hall(self) -> None:
        lectern = self.lectern
        hall = lectern.hall
        self._publish(CHANNEL, {"k": "hall", "w": self.worker_id, "hall": hall.value, "title": lectern.live_title(),
                                "status": lectern.follower_status().to_dict(),
                                "caption": list(lectern.caption())})

    def _send_plot(self) -> None:
        """The presenter's open plot tab, when a value changed (viser keeps the object it was last
        given: `is` tells) or PLOT_RESEND_S passed."""
        self._since_plot = 0.0  # looked at once a MIRROR_PERIOD, not every frame
        tab, elements = self.lectern.room_plot()
        values = [_element_value(element) for element in elements]
        sent, now = self._plot_sent, time.monotonic()
        if (sent is not None and sent[0] == tab and len(sent[1]) == len(values)
                and all(a is b for a, b in zip(sent[1], values)) and now - self._plot_sent_at < PLOT_RESEND_S):
            return
        self._plot_sent, self._plot_sent_at = (tab, values), now
        try:
            body = {"k": "plot", "w": self.worker_id, **_plot_to_plain(tab, elements)}
            self._publish(CHANNEL, body)
        except Exception:  # noqa: BLE001 - a chart property msgpack cannot carry: the followers elsewhere miss it
            logger.warning("bus: the presenter's plot not sent", exc_info=True)

    def _send_camera(self) -> None:
        presenter = self.lectern.presenter
        if presenter is None:
            return
        try:
            source = presenter.client.camera
            shot = {"position": [float(x) for x in source.position], "look_at": [float(x) for x in source.look_at],
                    "up": [float(x) for x in source.up_direction], "fov": float(source.fov),
                    "aspect": float(view_aspect(source))}
        except Exception:  # noqa: BLE001 - the presenter's camera is not known yet
            return
        if shot == self._camera_sent:
            return
        self._camera_sent = shot
        self._publish(CHANNEL, {"k": "camera", "w": self.worker_id, **shot})

    def _send_room(self) -> None:
        """Answer this frame's Explore requests with one encoded copy of the live room."""
        requests, self._room_requests = self._room_requests, []
        answer: dict[str, Any] = {"k": "room", "w": self.worker_id, "for": requests}
        room = self.lectern.live_room
        try:
            if room is None:
                raise RuntimeError("the presenter's process has nothing on the shared screen")
            encode_room, _ = _codec()
            with room.lock:
                data = encode_room(room)
            self._room_count += 1
            self.redis.set(f"{ROOM_KEY}{self._room_count}", data, px=ROOM_TTL_MS)
            answer["n"] = self._room_count
        except Exception as error:  # noqa: BLE001 - the asker shows the reason
            logger.warning("bus: the live room could not be sent", exc_info=True)
            answer["error"] = f"{type(error).__name__}: {error}"
        self._publish(CHANNEL, answer)

    def _send_keep(self) -> None:
        """Publish the live room without its history ("keep"): what the other processes copy
        if this one dies (sent when it changed, or KEEP_RESEND_S passed)."""
        room = self.lectern.live_room
        self._keep_mark = _room_mark(room)
        if room is None:
            return
        try:
            encode_room, _ = _codec()
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
        self._publish(CHANNEL, {"k": "keep", "w": self.worker_id, "lid": self.lecture_id, "room": data, "st": t,
                                "run": running})

    def _store_last(self) -> None:
        """Keep the room on this process's shared screen in Redis (LAST_KEY): what another
        process's Explore copies once this process's presenter has stopped, left or ended."""
        room = self.lectern.live_room
        if room is None:
            return
        try:
            encode_room, _ = _codec()
            with room.lock:
                data = encode_room(room)
            self.redis.set(LAST_KEY, msgspec.msgpack.encode([self.lecture_id, data]), ex=LAST_TTL_S)
        except Exception:  # noqa: BLE001 - then Explore elsewhere says the presenter's process is gone
            logger.warning("bus: the last room could not be kept", exc_info=True)

    def _audience(self) -> None:
        lectern = self.lectern
        following, exploring = lectern.audience()
        now = time.time()
        screens = [_screen_to_list(screen) for screen in lectern.follower_screens()] if following else []
        try:
            self.redis.hset(AUDIENCE_KEY, self.worker_id, msgspec.msgpack.encode([following, exploring, now, screens]))
            if lectern.presenter is not None:
                total = [0, 0]
                remote: list[Screen] = []
                for worker, value in self.redis.hgetall(AUDIENCE_KEY).items():
                    entry = msgspec.msgpack.decode(value)
                    if worker.decode() == self.worker_id or not isinstance(entry, list) or len(entry) != 4:
                        continue
                    if now - float(entry[2]) <= LEASE_S:
                        total[0] += int(entry[0])
                        total[1] += int(entry[1])
                        for item in entry[3][:MAX_LABEL_SCREENS] if isinstance(entry[3], list) else ():
                            screen = _screen_from_list(item)
                            if screen is not None and screen not in remote:
                                remote.append(screen)
                self._remote_audience = (total[0], total[1])
                self._remote_screens = remote[:MAX_LABEL_SCREENS]
        except Exception:  # noqa: BLE001 - the badge keeps its last figures
            logger.debug("bus: audience not written", exc_info=True)

    # ------------------------------------------------------------------ Explore on this process
    def fetch_room(self) -> Room:
        """A copy of the remote presenter's room (`fetch_room_noted` without its note)."""
        return self.fetch_room_noted()[0]

    def fetch_room_noted(self) -> tuple[Room, str]:
        """(a copy of the remote presenter's room, a note: "" for an exact copy).

        The best to be had: the room asked of its process and decoded here, bit for bit (while
        it presents); once that presenter has stopped or left, or its process does not answer,
        the room the lecture left (LAST_KEY of this lecture, exact); else the last copy this
        process kept (`Kept`, brought to the last frame drawn here, paused) or a fresh room of
        the same scene, each with a note saying so.  RuntimeError when the source answered with
        an error, or nothing of the lecture is known here (not even its scene)."""
        _, decode_room = _codec()
        remote = self.lectern.remote
        if remote is None or remote.hall is Hall.LIVE:
            asked = self._ask_source(decode_room)
            if asked is not None:
                return asked, ""
        last = self._last_of_this_lecture(decode_room)
        if last is not None:
            return last, ""
        return self._orphan_copy(decode_room)

    def _ask_source(self, decode_room: Any) -> Room | None:
        """The live room, asked of the source; None when it does not answer within
        EXPLORE_TIMEOUT_S or its presenter stops or leaves meanwhile (killed: after LEASE_S)."""
        request = secrets.token_hex(8)
        waiting: list[Any] = [threading.Event(), None]
        self._waiting[request] = waiting
        try:
            self._publish(ASK, {"k": "explore", "w": self.worker_id, "r": request})
            deadline = time.monotonic() + EXPLORE_TIMEOUT_S
            while not waiting[0].wait(0.05):  # the answer, or the presenter leaving meanwhile
                remote = self.lectern.remote
                if time.monotonic() > deadline or remote is None or remote.hall is not Hall.LIVE:
                    break
            if not waiting[0].is_set():
                return None
            kind, value = waiting[1]
            if kind == "error":
                raise RuntimeError(f"the presenter's process could not send its room: {value}")
            data = self.redis.get(value)
            if data is None:
                raise RuntimeError("the presenter's room expired before it was read")
            room: Room = decode_room(data)
            return room
        finally:
            self._waiting.pop(request, None)

    def _last_of_this_lecture(self, decode_room: Any) -> Room | None:
        """The room kept in LAST_KEY if the lecture shown here left it (an older lecture's: None)."""
        data = self.redis.get(LAST_KEY)
        if data is None or not self._remote_lecture:
            return None
        try:
            kept = msgspec.msgpack.decode(data)
        except msgspec.DecodeError:
            logger.warning("bus: an undecodable last room ignored")
            return None
        if not (isinstance(kept, list) and len(kept) == 2 and kept[0] == self._remote_lecture
                and isinstance(kept[1], bytes)):
            return None
        room: Room = decode_room(kept[1])
        return room

    def _orphan_copy(self, decode_room: Any) -> tuple[Room, str]:
        """The presenter's process is gone (or silent) and left nothing in Redis: the last copy
        kept here, brought to the last frame drawn here and paused, else a fresh room of the
        scene; with the note saying which."""
        remote = self.lectern.remote
        gone = "is gone" if remote is None or remote.hall is not Hall.LIVE else "does not answer"
        kept, seen_t = self._kept, self._seen_t
        if kept is not None and kept.lecture == self._remote_lecture:
            try:
                room: Room = decode_room(kept.data)
            except Exception:  # noqa: BLE001 - then the scene alone
                logger.warning("bus: the kept copy of the presenter's room could not be read", exc_info=True)
            else:
                if kept.running and seen_t is not None:
                    _catch_up(room, min(seen_t, kept.t + MAX_CATCH_UP_S))
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

    def close(self) -> None:
        """Say "left" if this process's presenter is still on (its room kept for Explore
        elsewhere), and stop reading."""
        if self.source:
            self._store_last()
        if self.source and self.lectern.presenter is not None:
            with contextlib.suppress(Exception):
                self._publish(CHANNEL, {"k": "hall", "w": self.worker_id, "hall": Hall.LEFT.value,
                                        "title": self.lectern.live_title(),
                                        "status": self.lectern.follower_status().ended(Hall.LEFT).to_dict(),
                                        "caption": ["", ""]})
        with contextlib.suppress(Exception):
            self.redis.hdel(AUDIENCE_KEY, self.worker_id)
        self._stop.set()
        self._reader.join(timeout=2.0)
        with contextlib.suppress(Exception):
            self._pubsub.close()
        with contextlib.suppress(Exception):
            self.redis.close()


def _camera(body: dict[str, Any]) -> dict[str, Any] | None:
    """A camera message's shot, checked: three finite 3-vectors, fov and aspect positive."""
    try:
        shot = {key: [float(x) for x in body[key]] for key in ("position", "look_at", "up")}
        fov, aspect = float(body["fov"]), float(body["aspect"])
    except (KeyError, TypeError, ValueError):
        return None
    if any(len(v) != 3 or not np.all(np.isfinite(v)) for v in shot.values()) \
            or not (0 < fov < 3.2 and 0 < aspect < 100):
        return None
    return {**shot, "fov": fov, "aspect": aspect}


def _element_value(element: Any) -> Any:
    return element.data if is_chart(element) else element.content


def _plot_to_plain(tab: str, elements: list[Any]) -> dict[str, Any]:
    """The presenter's open plot tab as plain values: {"tab", "el"}, each element ["uplot",
    {property: value} (UPLOT_PROPS), [float32 column bytes]] or ["markdown", text]."""
    plain: list[Any] = []
    for element in elements:
        if is_chart(element):
            columns = [np.ascontiguousarray(column, dtype="<f4").tobytes() for column in element.data]
            plain.append(["uplot", {name: getattr(element, name) for name in UPLOT_PROPS}, columns])
        else:
            plain.append(["markdown", str(element.content)])
    return {"tab": tab if elements else "", "el": plain}


def _plain_values(value: Any, depth: int = 0) -> int:
    """How many plain values (None, bool, number, str of up to 200 characters, lists and dicts
    of them, str keys) `value` holds; -1 for anything else or nested deeper than MAX_DEPTH."""
    if value is None or isinstance(value, (bool, int)):
        return 1
    if isinstance(value, float):
        return 1 if np.isfinite(value) else -1
    if isinstance(value, str):
        return 1 if len(value) <= 200 else -1
    if depth >= MAX_DEPTH:
        return -1
    if isinstance(value, dict):
        items = [*value.keys(), *value.values()]
        if not all(isinstance(key, str) for key in value):
            return -1
    elif isinstance(value, list):
        items = value
    else:
        return -1
    total = 1
    for item in items:
        count = _plain_values(item, depth + 1)
        if count < 0:
            return -1
        total += count
    return total


def _plot_from_plain(body: dict[str, Any], previous: tuple[str, tuple[Any, ...]]) -> tuple[str, tuple[Any, ...]] | None:
    """`_plot_to_plain` read back from Redis, checked (a PLOT_TABS tab, at most MAX_PLOT_ELEMENTS
    elements; a chart's properties plain values of UPLOT_PROPS only, its columns float32 of one
    length); None for anything else.  An element equal to the one at its place in `previous` is
    that object (the followers' copies are sent only when it changed)."""
    tab, items = body.get("tab"), body.get("el")
    if tab == "" and items == []:
        return "", ()
    if tab not in PLOT_TABS or not isinstance(items, list) or not 0 < len(items) <= MAX_PLOT_ELEMENTS:
        return None
    elements: list[Any] = []
    for index, item in enumerate(items):
        if not isinstance(item, list) or not item:
            return None
        old = previous[1][index] if previous[0] == tab and index < len(previous[1]) else None
        if item[0] == "markdown" and len(item) == 2 and isinstance(item[1], str) and len(item[1]) <= 20_000:
            elements.append(old if isinstance(old, MarkdownCopy) and old.content == item[1] else MarkdownCopy(item[1]))
            continue
        if item[0] != "uplot" or len(item) != 3:
            return None
        props, columns = item[1], item[2]
        if not (isinstance(props, dict) and set(props) <= set(UPLOT_PROPS)
                and 0 < _plain_values(props) <= MAX_PLOT_PROP_VALUES):
            return None
        if not (isinstance(columns, list) and 0 < len(columns) <= MAX_PLOT_COLUMNS
                and all(isinstance(c, bytes) and len(c) == len(columns[0]) for c in columns)
                and len(columns[0]) % 4 == 0 and len(columns[0]) <= 4 * MAX_PLOT_SAMPLES):
            return None
        data = tuple(np.frombuffer(column, dtype="<f4") for column in columns)
        chart = ChartCopy(data, **props)
        if (isinstance(old, ChartCopy) and _shape_equal(old, chart)
                and all(np.array_equal(a, b, equal_nan=True) for a, b in zip(old.data, data))):
            chart = old
        elements.append(chart)
    return tab, tuple(elements)


def _shape_equal(a: ChartCopy, b: ChartCopy) -> bool:
    return len(a.data) == len(b.data) and all(getattr(a, name) == getattr(b, name) for name in UPLOT_PROPS)


def _screen_to_list(screen: Screen) -> list[Any]:
    """A follower's `Screen` as plain values: the camera's position, look_at, up (9), its fov
    [deg], the canvas width and height [px], the panel's rectangle [px] or None."""
    view = screen.view
    return [*view.position, *view.look_at, *view.up, view.fov_deg, screen.width, screen.height,
            None if screen.panel is None else list(screen.panel)]


def _screen_from_list(item: Any) -> Screen | None:
    """`_screen_to_list` read back from Redis, checked (finite numbers, a canvas of 1..16384 px,
    a fov in (0°, 180°)); None for anything else."""
    if not isinstance(item, list) or len(item) != 13:
        return None
    numbers, width, height, panel = item[:10], item[10], item[11], item[12]
    if not all(isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x) for x in numbers):
        return None
    if not (isinstance(width, int) and isinstance(height, int) and 0 < width <= 16384 and 0 < height <= 16384
            and 0.0 < numbers[9] < 180.0):
        return None
    if panel is not None and not (isinstance(panel, list) and len(panel) == 4 and all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x) for x in panel)):
        return None
    x = [float(v) for v in numbers]
    view = CameraView((x[0], x[1], x[2]), (x[3], x[4], x[5]), (x[6], x[7], x[8]), x[9])
    if view.position == view.look_at:
        return None
    return Screen(view, width, height, None if panel is None else tuple(float(v) for v in panel))  # type: ignore[arg-type]


def _room_mark(room: Room | None) -> tuple[Any, ...]:
    """What a kept copy must be sent again at once when it changes (else a copy advanced to the
    last frame drawn would run from the wrong start): the room, its simulation and its run (a
    restart: a preset, an edit), playing, time scale, live or in the past.  (Not `version`: it
    counts every step.)"""
    if room is None:
        return ()
    sim = room.sim
    return (id(room), id(sim), getattr(sim, "run", None), room.playing, room.time_scale, room.mode)


def _catch_up(room: Room, t_s: float) -> None:
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


def _codec() -> tuple[Any, Any]:
    """(encode_room, decode_room) of the kit's codec; RuntimeError naming what is missing."""
    try:
        from app.codec import decode_room, encode_room  # noqa: PLC0415 - only Explore across processes
    except ImportError as error:
        raise RuntimeError(f"Explore on another process needs the room codec (app.codec): {error}") from None
    return encode_room, decode_room
