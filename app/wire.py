"""A frame's scene and panel updates, encoded once and written straight to the websockets.

viser 1.1 sends every queued message through a per-connection buffer: one producer task per
browser takes a window, serialises it (msgpack + zstd) and sends it.  For the presenter's shared
scene that means the same frame encoded once per follower (500 followers, 500 encodes a frame),
and every `atomic()` block wakes every follower's producer.  Inside `capturing()` (the app loop's
frame, `app.main.App.frame`) a `Wire` holds what is queued to its interface instead: the
*updates* (poses, props, visibility, panel values) it encodes once at the frame's end (`end_frames`), in viser's
own wire format, frames once as a websocket message (a server's frames are not masked: the
bytes are the same for every browser) and writes to each recipient's transport in one callback
on viser's event loop; everything else (nodes and panel elements made or removed, camera moves,
notifications) it hands to viser in one atomic block.  Outside a frame, or from another thread,
messages go through viser as before.

Order and late joiners.  A recipient gets a frame only when viser has already taken everything
queued for it before (its own buffer is empty, its cursor in the shared buffer has caught up:
`_caught_up`); the producer writes what it takes at once, so a frame never overtakes the message
that made its node.  A recipient that is not caught up, slow (more than MAX_UNSENT_BYTES waiting
in its socket), new, or skipped for any reason is *behind*: it is tried again (`_retry`, at
doubling intervals) until it is ready or a newer frame goes out, and then it gets one catch-up
frame with the latest value of everything the wire sent since the last frame it got
(`latest`, keyed as viser culls: one value per node and property).  A node made or removed
drops its entries from `latest` (a removed node's descendants too), and so does a value viser
sent outside a frame (viser brings that newer value to every browser itself).  Such a newer
value also beats the frame that captured an older one before it (a callback, on another thread,
drawing between the loop's capture and the frame's end: a preset erasing the last run's traces):
what is captured and what viser is handed carry one sequence, and a frame drops what was
overtaken (`_not_overtaken`) instead of bringing the older value back after viser's.

Counters: `encodes` (payloads built), `frames` (frames ended with something to send), `writes`
(transport writes) and `bytes_written`; tests count encodes to show one encode per frame.

viser's internals it uses (its interfaces' queues and buffers, the browsers' connections, the
event loop, the window envelope) come from `app.viser_internals`, the app's one seam to them:
when its FRAME_CAPTURE is off `Wire.attach` returns None and the app sends through viser's
public path; `tests/test_wire.py` checks that a browser stand-in ends with the same scene
either way.
"""

from __future__ import annotations

import itertools
import logging
import math
import struct
import threading
import time
from collections.abc import Container, Iterable
from contextlib import AbstractContextManager
from typing import Any

import msgspec.msgpack
import numpy as np
import zstandard

from app.viser_internals import (
    FRAME_CAPTURE,
    client_buffer,
    divert_queue,
    event_loop,
    frame_capture,
    in_frame_capture,
    interface_of,
    live_connections,
    message_buffer,
    pack_window,
)

__all__ = ["MAX_UNSENT_BYTES", "ZSTD_LEVEL", "Wire", "capturing", "encode", "end_frames",
           "websocket_frame"]

logger = logging.getLogger(__name__)

MAX_UNSENT_BYTES = 64 * 1024  # a browser with more than this waiting in its socket skips frames
RETRY_S = 0.002  # [s] a recipient viser had not caught up is tried again this much later ...
RETRY_MAX_S = 0.1  # [s] ... and then at doubling intervals up to this, until it has caught up or left
# zstd level of a frame's msgpack (viser's own producer uses 1).  A frame is a few hundred bytes
# and compressed alone, so every name and key is new in each: a higher level finds more of the
# repeats within a frame; beyond 6 the gain is small for many times the time (docs/VISER.md,
# "Smaller frames").
ZSTD_LEVEL = 6
CAPTURED_PHASES = ("update_simple", "update_dict")
_ZSTD = threading.local()


def capturing() -> AbstractContextManager[None]:
    """A frame of the app loop (`app.viser_internals.frame_capture`): within it, what this
    thread queues to any interface with a wire is held by that wire until `end_frames`
    (updates to be encoded once, everything else to be handed to viser in one atomic block)."""
    return frame_capture()


def encode(messages: Iterable[Any], inline: Container[str] = ()) -> bytes:
    """One window of viser messages in viser 1.1's wire format (as its `_message_producer`):
    sizes (2 x 8 bytes), zstd(msgpack({messages, timestampSec, binaryBufferLengths})), the raw
    numpy buffers 8-byte aligned; binaryBufferLengths is left out when there are none, which
    viser's client reads the same way (`WebsocketClientWorker.ts`: "If no binary buffers").
    inline: names of nodes whose small `points` updates go in the msgpack (`_serialise`)."""
    compressor = getattr(_ZSTD, "compressor", None)
    if compressor is None:
        compressor = _ZSTD.compressor = zstandard.ZstdCompressor(level=ZSTD_LEVEL)
    buffers: list[memoryview] = []
    serialised = tuple(_serialise(message, buffers, inline) for message in messages)
    envelope: dict[str, Any] = {"messages": serialised, "timestampSec": time.perf_counter()}
    if buffers:  # viser's client reads a missing list as none (21 bytes a frame saved)
        envelope["binaryBufferLengths"] = tuple(b.nbytes for b in buffers)
    inner = msgspec.msgpack.encode(envelope)
    return pack_window(inner, compressor.compress(inner), buffers)


_F32 = struct.Struct(">f")
_POSE_FIELDS = {"SetOrientationMessage": "wxyz", "SetPositionMessage": "position"}
# Nodes whose client reads `points` by index and length only, so a JavaScript array of numbers
# draws as the Float32Array would (viser 1.1: Arrows.tsx indexes it; Line.tsx hands it to three's
# LineSegmentsGeometry.setPositions, which takes an Array too).
INLINE_NODES = frozenset({"ArrowMessage", "LineSegmentsMessage"})
# A float32 `points` update goes in the msgpack when (values - 4 zeros) is at most this.  A raw
# buffer costs 4 B a value, never compressed, plus alignment, a placeholder and a length; inline
# a value costs 5 B (1 for +0.0) before the frame's compression, which squeezes the zero low
# bytes of values on the power-of-two grids (the traces' chunks of up to 10 segments go inline;
# docs/VISER.md, "Smaller frames").
INLINE_SLACK = 64


def _serialise(message: Any, buffers: list[memoryview], inline: Container[str] = ()) -> dict[str, Any]:
    """`message.as_serializable_dict(buffers)`, a pose message's numbers in their shortest exact
    msgpack form: a whole number (not -0.0) as an integer (1 byte for 0, ±1), a float32-exact one
    (the poses snapped while playing, `app.kit.draw.lean`) as float32 (5 bytes), others as float64 (9).
    Lossless: viser's client reads every msgpack number as a JavaScript number (a float64), so
    it gets the same values.  A node's per-axis scale (a `SceneNodeUpdateMessage`'s "scale") is
    sent the same way (a shaft scaled along its arrow, a spring: (1, 1, length) takes 2 bytes, not 18,
    for its ones).  A pose message's dict is built here (its three fields and its type,
    as viser builds it, `tests/test_wire.py`), faster than viser's generic serialiser.
    A small float32 `points` update of a node named in `inline` goes in the msgpack as an array
    of numbers (`_inline_points`) rather than as a raw buffer: its zeros take a byte and the
    frame's compression reaches it (a force arrow drawn from its origin: half its numbers are 0)."""
    kind = type(message).__name__
    field = _POSE_FIELDS.get(kind)
    if field is None:
        points = _inline_points(message, inline) if kind == "SceneNodeUpdateMessage" else None
        if points is not None:  # as viser builds it (`tests/test_wire.py`)
            return {"name": message.name, "updates": {"points": points}, "owner": message.owner, "type": kind}
        serialised = message.as_serializable_dict(buffers)
        if kind == "SceneNodeUpdateMessage" and isinstance(serialised["updates"].get("scale"), (tuple, list)):
            serialised["updates"]["scale"] = tuple(_number(float(x)) for x in serialised["updates"]["scale"])
        return serialised
    return {"name": message.name, field: tuple(_number(float(x)) for x in getattr(message, field)),
            "owner": message.owner, "type": kind}


def _inline_points(message: Any, inline: Container[str]) -> msgspec.Raw | None:
    """The message's `points` as one msgpack array (+0.0 as the integer 0, every other value as
    a float32: lossless, they are float32), or None if it does not go inline (only an update of
    `points` alone does, as `app.viser_internals.set_points` sends it)."""
    points = message.updates.get("points")
    if message.name not in inline or len(message.updates) != 1 or not isinstance(points, np.ndarray) \
            or points.dtype != np.float32 or points.size >= 1 << 16:
        return None
    pack = _F32.pack
    parts = [b"\x00" if x == 0.0 and math.copysign(1.0, x) > 0.0 else b"\xca" + pack(x)
             for x in points.ravel().tolist()]
    n = len(parts)
    if n - 4 * parts.count(b"\x00") > INLINE_SLACK:
        return None
    header = bytes((0x90 | n,)) if n < 16 else b"\xdc" + n.to_bytes(2, "big")
    return msgspec.Raw(header + b"".join(parts))


def _number(x: float) -> Any:
    if x.is_integer() and abs(x) < 2**31 and (x != 0.0 or math.copysign(1.0, x) > 0.0):
        return int(x)
    try:
        packed = _F32.pack(x)
    except OverflowError:
        return x
    return msgspec.Raw(b"\xca" + packed) if _F32.unpack(packed)[0] == x else x


def websocket_frame(payload: bytes) -> bytes:
    """`payload` as one unmasked, unfragmented binary websocket frame (RFC 6455 §5.2), the
    form a server sends."""
    size = len(payload)
    if size < 126:
        header = bytes((0x82, size))
    elif size < 1 << 16:
        header = bytes((0x82, 126)) + size.to_bytes(2, "big")
    else:
        header = bytes((0x82, 127)) + size.to_bytes(8, "big")
    return header + payload


def end_frames(frames: Iterable[tuple[Wire, Iterable[int]]]) -> None:
    """End the frame of each wire: hand what it held to viser, then send its updates to its
    recipients (client ids), once encoded, on viser's event loop (recipients that are behind get
    their catch-up first); one wake-up of the loop (a self-pipe write) for all the wires."""
    deliveries = [d for d in (wire._close_frame(recipients) for wire, recipients in frames) if d is not None]
    if not deliveries:
        return

    def deliver_all() -> None:
        for wire, messages, ops, recipients in deliveries:
            try:
                wire._deliver(messages, ops, recipients)
            except Exception:  # noqa: BLE001 - one browser's failure must not stop the others' frames
                logger.exception("a frame could not be delivered")

    try:
        deliveries[0][0]._loop.call_soon_threadsafe(deliver_all)
    except RuntimeError:  # the loop is closed: the server stops
        for wire, *_ in deliveries:
            wire._scheduled -= 1


def _entity(message: Any) -> tuple[str, str] | None:
    """(entity type, id) of a node or panel element message, or None."""
    kind, field = getattr(message, "entity_type", None), getattr(message, "entity_id_field", None)
    if kind is None or field is None:
        return None
    return kind, str(getattr(message, field, ""))


def _not_overtaken(captured: list[tuple[int, Any]], ops: list[tuple[Any, ...]]) -> list[Any]:
    """The messages of a frame, (sequence number, message) as captured, that nothing in `ops`
    (what viser was handed outside frames up to the frame's end) overtook: a value for the same
    node and property handed to viser later (a callback that drew between the frame's capture
    and its end, e.g. a preset hiding and erasing the last run's traces), or their node made
    or removed later.  viser delivers those first; sending the older captured value after them
    would leave the browser with it (a previous preset's trace shown again)."""
    newer: dict[str, int] = {}
    purges = []
    for op in ops:
        if op[0] == "set":
            key = op[1].redundancy_key()
            newer[key] = max(newer.get(key, -1), op[-1])
        else:
            purges.append(op)
    kept = []
    for seq, message in captured:
        key = message.redundancy_key()
        if newer.get(key, -1) > seq or any(seq < purge[-1] and (key.startswith(purge[1]) or (
                purge[2] is not None and key.startswith(purge[2]))) for purge in purges):
            continue
        kept.append(message)
    return kept


class Wire:
    """The messages one viser interface (the shared scene, or one browser's connection) is given
    inside `capturing()` (the app loop's frame), sent by `end_frames` to recipients.

    Made with `Wire.attach`."""

    def __init__(self, server: Any, interface: Any, buffer: Any) -> None:
        self._server = server
        self._loop = event_loop(server)
        self._interface = interface
        self._buffer = buffer
        self._shared = buffer is message_buffer(interface_of(server))
        self._frame: list[tuple[int, Any]] = []  # updates captured this frame: (sequence number, message)
        self._held: list[Any] = []  # anything else queued this frame (for viser, at its end)
        self._lock = threading.Lock()
        self._ops: list[tuple[Any, ...]] = []  # ("set", message, seq) / ("purge", key prefix, descendants' prefix, seq)
        self._sequence = itertools.count()  # orders what is captured and what viser is handed (`_not_overtaken`)
        self._scheduled = 0  # frames ended whose delivery has not run yet
        self._count = 0  # frames delivered so far (delivery thread)
        self._latest: dict[str, tuple[int, Any]] = {}  # redundancy key -> (frame, message)
        self._delivered: dict[int, int] = {}  # client id -> last frame it got
        self._payloads: dict[int, Any] = {}  # this frame's: since -> bytes (or messages not yet encoded)
        self._inline: set[str] = set()  # nodes made by an INLINE_NODES message (`encode`)
        self.encodes = self.frames = self.writes = self.bytes_written = 0
        self._queue = divert_queue(interface, self._take)  # viser's own queue_message

    @classmethod
    def attach(cls, server: Any, client: Any | None = None) -> Wire | None:
        """A wire for the shared scene (`client` None) or for one browser's own messages; None
        if `app.viser_internals.FRAME_CAPTURE` is off or viser's objects are not as expected
        (then nothing changes)."""
        if not FRAME_CAPTURE.on:
            return None
        try:
            interface = interface_of(server, client)
            buffer = message_buffer(interface)
            if not (isinstance(buffer.message_from_id, dict) and isinstance(buffer.generator_cursors, dict)
                    and isinstance(live_connections(server), dict) and event_loop(server) is not None
                    and callable(interface.queue_message)):
                return None
            return cls(server, interface, buffer)
        except AttributeError:
            return None

    # ------------------------------------------------------------------ the app loop's side
    def _take(self, message: Any) -> None:
        entity = _entity(message)
        phase = getattr(message, "lifecycle_phase", None)
        inside = in_frame_capture()
        seq = next(self._sequence)
        if entity is not None and phase in CAPTURED_PHASES:
            if inside:
                self._frame.append((seq, message))
                return
            op: tuple[Any, ...] | None = ("set", message, seq)  # viser sends it: a catch-up must not undo it
        elif entity is not None and phase in ("create", "remove"):  # its latest values go
            if phase == "create":
                (self._inline.add if type(message).__name__ in INLINE_NODES else self._inline.discard)(entity[1])
            op = ("purge", f"{entity[0]}:{entity[1]}:", f"{entity[0]}:{entity[1]}/" if phase == "remove" else None,
                  seq)
        else:
            op = None
        if inside:
            self._held.append(message)  # to viser at the frame's end, in order, in one atomic block
        else:
            self._queue(message)
        if op is not None:
            with self._lock:
                self._ops.append(op)

    def busy(self) -> bool:
        """A frame was ended and its delivery has not run yet."""
        return self._scheduled > 0

    def _close_frame(self, recipients: Iterable[int]) -> tuple[Any, ...] | None:
        """The app loop's part of ending a frame (`end_frames`): the held messages to viser, in
        one atomic block; the delivery's arguments, or None when there is nothing to deliver."""
        if self._held:
            held, self._held = self._held, []
            with self._interface.atomic():
                for message in held:
                    self._queue(message)
        if not (self._frame or self._ops):
            return None
        messages, self._frame = self._frame, []
        with self._lock:
            ops, self._ops = self._ops, []
        self._scheduled += 1
        return self, messages, ops, tuple(recipients)

    # ------------------------------------------------------------------ viser's event loop
    def _caught_up(self, client_id: int, connection: Any) -> bool:
        """Viser has taken everything queued for this browser before, and its socket keeps up."""
        own = client_buffer(self._server, client_id)
        if own is None or own.message_from_id:
            return False
        cursor = self._buffer.generator_cursors.get(client_id) if self._shared else None
        if self._shared and (cursor is None or cursor < self._buffer.message_counter - 1):
            return False
        transport = connection.transport
        return (getattr(connection.protocol.state, "name", "") == "OPEN" and not transport.is_closing()
                and transport.get_write_buffer_size() <= MAX_UNSENT_BYTES)

    def _deliver(self, messages: list[tuple[int, Any]], ops: list[tuple[Any, ...]], recipients: tuple[int, ...]
                 ) -> None:
        try:
            self._apply(messages, ops, recipients)
        finally:
            self._scheduled -= 1

    def _apply(self, captured: list[tuple[int, Any]], ops: list[tuple[Any, ...]], recipients: tuple[int, ...]
               ) -> None:
        latest = self._latest
        messages = _not_overtaken(captured, ops)
        self._forget(ops)
        if not messages:
            return
        self._count += 1
        frame = self._count
        unique = {message.redundancy_key(): message for message in messages}  # viser culls so too
        messages = list(unique.values())
        for key, message in unique.items():
            latest[key] = (frame, message)
        self.frames += 1
        overtaken = self._drop_overtaken()
        # since -> what to send (encoded on first use); from `latest` when viser overtook a value
        self._payloads = {} if overtaken else {frame - 1: messages}
        late = self._send(frame, recipients)
        if late:  # viser has not yet taken what this frame handed it: again, a little later
            self._loop.call_later(RETRY_S, self._retry, frame, late, RETRY_S)
        connections, delivered = live_connections(self._server), self._delivered
        if len(delivered) > 2 * len(connections) + 16:  # browsers that left
            for client_id in [c for c in delivered if c not in connections]:
                del delivered[client_id]

    def _retry(self, frame: int, recipients: tuple[int, ...], wait: float) -> None:
        """Frame `frame` to the recipients that were late for it, once they have caught up: tried
        again after `wait` [s], then after twice as long (up to RETRY_MAX_S) while any is still
        late and connected.  A frame may be the last for a long time (the picture stands still
        after a new scene: its labels' last layout), so a browser that was busy taking the new
        scene's nodes must still get it.  Stops when a newer frame went out (its catch-up serves
        them, and its own retries follow them)."""
        if frame != self._count:
            return
        if self._drop_overtaken():
            self._payloads = {}  # each late browser: what is left of the frames it missed
        late = self._send(frame, recipients)
        if late:
            wait = min(2.0 * wait, RETRY_MAX_S)
            self._loop.call_later(wait, self._retry, frame, late, wait)

    def _drop_overtaken(self) -> bool:
        """Forget the values of `latest` that viser was handed a newer value for, or whose node
        went, after the last frame closed (ops not yet applied: they stay for the next frame's
        `_apply`), so that no frame written later brings a browser an older value back; whether
        any went."""
        with self._lock:
            pending = list(self._ops)
        return self._forget(pending)

    def _forget(self, ops: list[tuple[Any, ...]]) -> bool:
        """Drop from `latest` what `ops` name: a value viser itself brings to every browser
        ("set"), a node made or removed and, for a removal, what hangs under it ("purge");
        whether anything went."""
        latest, before = self._latest, len(self._latest)
        for op in ops:
            if op[0] == "set":
                latest.pop(op[1].redundancy_key(), None)
                continue
            _, prefix, under, _seq = op
            for key in [k for k in latest if k.startswith(prefix) or (under and k.startswith(under))]:
                del latest[key]
        return len(latest) < before

    def _send(self, frame: int, recipients: Iterable[int]) -> tuple[int, ...]:
        """Write frame `frame` to the recipients that are caught up (the shared payload to those
        that got the previous frame, a catch-up to the others); the ones that are not."""
        connections, delivered, payloads = live_connections(self._server), self._delivered, self._payloads
        late = []
        for client_id in recipients:
            connection = connections.get(client_id)
            if connection is None or delivered.get(client_id, 0) == frame:
                continue
            if not self._caught_up(client_id, connection):
                late.append(client_id)
                continue
            since = delivered.get(client_id, 0)
            data = payloads.get(since)
            if not isinstance(data, bytes):  # behind: what changed after the last frame it got
                data = payloads[since] = self._payload(
                    data if data is not None else [m for f, m in self._latest.values() if f > since])
            connection.transport.write(data)
            delivered[client_id] = frame
            self.writes += 1
            self.bytes_written += len(data)
        return tuple(late)

    def _payload(self, messages: list[Any]) -> bytes:
        self.encodes += 1
        return websocket_frame(encode(messages, self._inline))
