"""A browser stand-in for viser 1.1 servers: pure Python, no browser, for load tests and benchmarks.

It speaks viser's websocket protocol (docs/VISER.md §3):

- connects with the subprotocol ``viser-v<viser.__version__>`` (a mismatch is closed with 1002);
- sends a ``ViewerCameraMessage`` first (until then the server does not register the client and
  fires no GUI callbacks for it);
- decodes every server frame ``[u64 inner_len][u64 comp_len][zstd msgpack][8-aligned buffers]``,
  where the msgpack is ``{"messages": [...], "timestampSec": float, "binaryBufferLengths": [...]}``;
- keeps a table of the GUI elements it was sent (uuid, type, label, value, props), so that it can
  send the ``GuiUpdateMessage`` a browser would send to the element with a given label (slider
  moved, dropdown changed, button clicked).

Every decoded message is also counted by category (`message_category`): "scene" (scene nodes
created, moved, updated, shown, hidden, removed) or "gui" (everything else: the panel,
notifications, commands, the camera); a frame with at least one scene message is a "scene
frame" (one drawn frame of a view).  A test that drives the server in its own process can put a
sync marker (`sync_marker_message(n)`) behind what it sent: the frame carrying it is not counted,
and `ClientState.marker` becomes n once everything sent before it has been ingested.

Memory is bounded: pose messages (``SetOrientationMessage``, ``SetPositionMessage``) are counted
per scene node, never stored; other messages go to a ring buffer of ``keep_messages`` entries
(time of arrival, server timestamp, message dict with its binary buffers as bytes).

Two front ends share the bookkeeping (`ClientState`):

    client = ViserClient(port)            # threads (websockets.sync); for tests and scripts
    client.wait_for_label("θ [deg]")
    client.set_value("θ [deg]", 90.0)
    client.click("Play")
    client.close()

    client = await AsyncViserClient.connect(port)   # asyncio; many clients in one process
    ...
    await client.close()

Loopback by default (host 127.0.0.1).  Times are `time.monotonic()` seconds.
"""

from __future__ import annotations

import asyncio
import collections
import dataclasses
import math
import threading
import time
from collections.abc import Callable
from typing import Any

import msgspec.msgpack
import zstandard

__all__ = [
    "POSE_MESSAGE_TYPES",
    "SCENE_UPDATE_MESSAGE_TYPES",
    "SYNC_MARKER_PREFIX",
    "AsyncViserClient",
    "ClientState",
    "GuiElement",
    "NodePoseStats",
    "ViserClient",
    "camera_message",
    "decode_frame",
    "encode_message",
    "gui_update_message",
    "message_category",
    "subprotocol",
    "sync_marker_message",
]

POSE_MESSAGE_TYPES = frozenset({"SetOrientationMessage", "SetPositionMessage"})
SCENE_UPDATE_MESSAGE_TYPES = frozenset({
    "SetOrientationMessage", "SetPositionMessage", "SceneNodeUpdateMessage", "SetSceneNodeVisibilityMessage",
    "RemoveSceneNodeMessage", "SetBoneOrientationMessage", "SetBonePositionMessage",
    "SetSceneNodeClickBindingsMessage", "SetSceneNodeDragBindingsMessage",
})
"""Messages that change an existing scene node (besides the creation messages of scene nodes)."""
SYNC_MARKER_PREFIX = "/* ws_client sync marker "
_CATEGORY: dict[str, str] = {}
_HEADER_BYTES = 16


def subprotocol() -> str:
    """The websocket subprotocol the installed viser server accepts, ``viser-v<version>``."""
    import viser

    return f"viser-v{viser.__version__}"


def decode_frame(data: bytes) -> tuple[list[dict[str, Any]], float, list[memoryview]]:
    """One server frame -> (messages as dicts, server timestampSec, binary buffers).

    Layout: [u64 LE msgpack length][u64 LE compressed length][zstd msgpack][padding to 8]
    [buffers, each 8-aligned, lengths in ``binaryBufferLengths``].  Placeholders
    ``{"__binary_index": i, "dtype": ...}`` are left in the messages (see `resolve_binary`).

    Raises:
        ValueError: a truncated or inconsistent frame.
    """
    if len(data) < _HEADER_BYTES:
        raise ValueError(f"frame of {len(data)} bytes is shorter than its 16-byte header")
    inner_len = int.from_bytes(data[0:8], "little")
    comp_len = int.from_bytes(data[8:16], "little")
    end = _HEADER_BYTES + comp_len
    if end > len(data):
        raise ValueError(f"frame says {comp_len} compressed bytes, has {len(data) - _HEADER_BYTES}")
    inner = zstandard.ZstdDecompressor().decompress(data[_HEADER_BYTES:end], max_output_size=inner_len)
    if len(inner) != inner_len:
        raise ValueError(f"msgpack payload is {len(inner)} bytes, header says {inner_len}")
    payload = msgspec.msgpack.decode(inner)
    buffers: list[memoryview] = []
    view = memoryview(data)
    offset = end
    for length in payload.get("binaryBufferLengths", ()):
        offset += (8 - offset % 8) % 8
        if offset + length > len(data):
            raise ValueError("binary buffer runs past the end of the frame")
        buffers.append(view[offset:offset + length])
        offset += length
    return payload["messages"], float(payload.get("timestampSec", math.nan)), buffers


def message_category(kind: str) -> str:
    """"scene" for a message type that creates or changes a scene node (a viser
    ``_CreateSceneNodeMessage`` or one of SCENE_UPDATE_MESSAGE_TYPES), "gui" for any other
    (the panel, notifications, commands, the camera, plotly's script)."""
    category = _CATEGORY.get(kind)
    if category is None:
        from viser import _messages

        cls = getattr(_messages, kind, None)
        creates_node = isinstance(cls, type) and issubclass(cls, _messages._CreateSceneNodeMessage)
        category = _CATEGORY[kind] = "scene" if creates_node or kind in SCENE_UPDATE_MESSAGE_TYPES else "gui"
    return category


def sync_marker_message(number: int) -> Any:
    """A message a client ignores but recognises (`ClientState.marker`): queue it on a client's
    connection in the server's process behind what that client must have received first.  A
    viser ``RunJavascriptMessage`` holding only a comment (a browser runs nothing); never culled."""
    from viser import _messages

    return _messages.RunJavascriptMessage(source=f"{SYNC_MARKER_PREFIX}{int(number)} */")


def _marker_number(messages: list[dict[str, Any]]) -> int | None:
    """n if `messages` is exactly one sync marker n, else None."""
    if len(messages) != 1 or messages[0].get("type") != "RunJavascriptMessage":
        return None
    source = str(messages[0].get("source", ""))
    if not source.startswith(SYNC_MARKER_PREFIX):
        return None
    return int(source[len(SYNC_MARKER_PREFIX):].split()[0])


def resolve_binary(value: Any, buffers: list[memoryview]) -> Any:
    """`value` with every binary placeholder replaced by {"dtype": str, "data": bytes}."""
    if isinstance(value, dict):
        if "__binary_index" in value and "dtype" in value:
            return {"dtype": value["dtype"], "data": bytes(buffers[value["__binary_index"]])}
        return {k: resolve_binary(v, buffers) for k, v in value.items()}
    if isinstance(value, list):
        return [resolve_binary(v, buffers) for v in value]
    return value


def encode_message(message: Any) -> bytes:
    """A viser `_messages.Message` (client -> server) as the msgpack bytes a browser sends."""
    return msgspec.msgpack.encode(message.as_serializable_dict())


def camera_message(
    position: tuple[float, float, float] = (5.0, -2.0, 3.0),
    look_at: tuple[float, float, float] = (0.0, 0.0, 0.0),
    width: int = 1280,
    height: int = 800,
) -> Any:
    """The first message of every viser client: a ViewerCameraMessage (fov 40°, z up)."""
    from viser import _messages

    return _messages.ViewerCameraMessage(
        wxyz=(1.0, 0.0, 0.0, 0.0), position=position, fov=math.radians(40.0), near=0.01,
        far=100.0, image_height=height, image_width=width, look_at=look_at,
        up_direction=(0.0, 0.0, 1.0),
    )


def gui_update_message(uuid: str, value: Any) -> Any:
    """What a browser sends when the user sets the GUI element `uuid` to `value`
    (buttons: value True on each click)."""
    from viser import _messages

    return _messages.GuiUpdateMessage(uuid, {"value": value})


@dataclasses.dataclass
class GuiElement:
    """A GUI element as this client knows it: creation message type (e.g. 'GuiSliderMessage'),
    label, current value (None for folders, markdown...), props dict, container uuid."""

    uuid: str
    type: str
    label: str
    value: Any
    props: dict[str, Any]
    container_uuid: str | None


@dataclasses.dataclass
class NodePoseStats:
    """Pose messages received for one scene node since the last `reset_pose_stats`.

    orientations / positions: message counts; first_time, last_time: arrival of the first and
    last orientation message [s, monotonic]; max_gap: the longest time between two consecutive
    orientation messages [s] (a stutter shows up here, not in the mean rate).
    """

    orientations: int = 0
    positions: int = 0
    first_time: float = math.nan
    last_time: float = math.nan
    max_gap: float = 0.0
    last_wxyz: tuple[float, ...] | None = None


class ClientState:
    """Everything a client learns from the frames it receives; thread-safe.

    Attributes:
        frames: websocket frames received; bytes_received: their total size [B].
        message_counts: messages received, by type (a Counter).
        category_counts: messages received by `message_category` ("scene", "gui"; a Counter).
        scene_frames: frames with at least one scene message (drawn frames of a view).
        marker: the number of the last sync marker received (-1: none); the marker's frame
            is counted nowhere else.
        pose: {node name: NodePoseStats}, pose messages counted, not stored.
        messages: ring buffer of (arrival time [s], server timestampSec, message dict) for
            all non-pose messages, at most `keep_messages` of them.
        gui: {uuid: GuiElement}, every GUI element created and not removed.
        replay_done: the server has replayed its shared scene (ReplayDoneMessage seen).
        errors: decoding errors (strings), at most 100.
    """

    def __init__(self, keep_messages: int = 2000) -> None:
        self.lock = threading.Lock()
        self.changed = threading.Condition(self.lock)
        self.frames = 0
        self.bytes_received = 0
        self.message_counts: collections.Counter[str] = collections.Counter()
        self.category_counts: collections.Counter[str] = collections.Counter()
        self.scene_frames = 0
        self.marker = -1
        self.pose: dict[str, NodePoseStats] = {}
        self.messages: collections.deque[tuple[float, float, dict[str, Any]]] = collections.deque(
            maxlen=keep_messages)
        self.gui: dict[str, GuiElement] = {}
        self.replay_done = False
        self.errors: collections.deque[str] = collections.deque(maxlen=100)
        self.count_only = False  # True: frames are counted, not decoded (load tests)
        self.max_frame_gap = 0.0  # [s] longest time between two frames since `count_only` was set
        self.first_frame_time = math.nan
        self.last_frame_time = math.nan

    # ------------------------------------------------------------------ ingest
    def ingest(self, data: bytes | str, now: float | None = None) -> None:
        """Decode one server frame and update the tables (errors are recorded, not raised)."""
        now = time.monotonic() if now is None else now
        if self.count_only:  # a load client that has pressed what it needs: count, do not decode
            with self.lock:
                self.frames += 1
                self.bytes_received += len(data)
                if self.last_frame_time == self.last_frame_time:  # not NaN
                    self.max_frame_gap = max(self.max_frame_gap, now - self.last_frame_time)
                self.last_frame_time = now
            return
        if isinstance(data, str):
            data = data.encode()
        try:
            messages, server_time, buffers = decode_frame(data)
        except Exception as error:  # noqa: BLE001 - a load client must not die on one frame
            with self.lock:
                self.errors.append(f"{type(error).__name__}: {error}")
            return
        marker = _marker_number(messages)
        with self.changed:
            if marker is not None:
                self.marker = marker
                self.changed.notify_all()
                return
            self.frames += 1
            self.bytes_received += len(data)
            if self.frames == 1:
                self.first_frame_time = now
            self.last_frame_time = now
            scene_messages = 0
            for message in messages:
                kind = message.get("type", "?")
                self.message_counts[kind] += 1
                category = message_category(kind)
                self.category_counts[category] += 1
                scene_messages += category == "scene"
                if kind in POSE_MESSAGE_TYPES:
                    self._count_pose(kind, message, now)
                    continue
                if buffers:
                    message = resolve_binary(message, buffers)
                self.messages.append((now, server_time, message))
                self._track_gui(kind, message)
                if kind == "ReplayDoneMessage":
                    self.replay_done = True
            self.scene_frames += scene_messages > 0
            self.changed.notify_all()

    def _count_pose(self, kind: str, message: dict[str, Any], now: float) -> None:
        stats = self.pose.get(message["name"])
        if stats is None:
            stats = self.pose[message["name"]] = NodePoseStats()
        if kind == "SetPositionMessage":
            stats.positions += 1
            return
        if stats.orientations == 0:
            stats.first_time = now
        else:
            stats.max_gap = max(stats.max_gap, now - stats.last_time)
        stats.orientations += 1
        stats.last_time = now
        stats.last_wxyz = tuple(message["wxyz"])

    def _track_gui(self, kind: str, message: dict[str, Any]) -> None:
        if kind.startswith("Gui") and kind.endswith("Message") and "props" in message \
                and "uuid" in message and isinstance(message["props"], dict):
            props = message["props"]
            self.gui[message["uuid"]] = GuiElement(
                uuid=message["uuid"], type=kind, label=str(props.get("label", "")),
                value=message.get("value"), props=dict(props),
                container_uuid=message.get("container_uuid"),
            )
        elif kind == "GuiUpdateMessage":
            element = self.gui.get(message.get("uuid", ""))
            if element is not None:
                for key, value in message.get("updates", {}).items():
                    if key == "value":
                        element.value = value
                    else:
                        element.props[key] = value
                        if key == "label":
                            element.label = str(value)
        elif kind == "GuiRemoveMessage":
            self.gui.pop(message.get("uuid", ""), None)
        elif kind == "ResetGuiMessage":
            self.gui.clear()

    # ------------------------------------------------------------------ queries
    def find_gui(self, label: str, type_contains: str | None = None) -> GuiElement | None:
        """The GUI element whose label is `label` (exact), optionally whose message type contains
        `type_contains` (e.g. 'Dropdown', 'Button'); the most recently created one if several."""
        with self.lock:
            found = [e for e in self.gui.values() if e.label == label
                     and (type_contains is None or type_contains in e.type)]
        return found[-1] if found else None

    def labels(self) -> list[str]:
        """Labels of all known GUI elements, in creation order."""
        with self.lock:
            return [e.label for e in self.gui.values()]

    def wait_for(self, predicate: Callable[[], Any], timeout: float = 30.0) -> Any:
        """Block until `predicate()` (called without the lock held) is truthy; its value.

        Raises:
            TimeoutError: not within `timeout` seconds.
        """
        deadline = time.monotonic() + timeout
        while True:
            value = predicate()
            if value:
                return value
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError(f"condition not met within {timeout} s")
            with self.changed:
                self.changed.wait(min(remaining, 0.05))

    def reset_pose_stats(self) -> None:
        """Forget the pose counts (start of a measurement window)."""
        with self.lock:
            self.pose.clear()

    def pose_snapshot(self) -> dict[str, NodePoseStats]:
        """A copy of the pose counts, {node name: NodePoseStats}."""
        with self.lock:
            return {name: dataclasses.replace(stats) for name, stats in self.pose.items()}

    def busiest_node(self) -> tuple[str, NodePoseStats] | None:
        """The node with the most orientation messages (the moving body, in a physics scene)."""
        snapshot = self.pose_snapshot()
        if not snapshot:
            return None
        name = max(snapshot, key=lambda n: snapshot[n].orientations)
        return name, snapshot[name]


class _GuiSender:
    """`set_value` / `click` for both front ends: find the element, build the message."""

    state: ClientState

    def _gui_message(self, label: str, value: Any, type_contains: str | None) -> Any:
        element = self.state.find_gui(label, type_contains)
        if element is None:
            raise KeyError(f"no GUI element labelled {label!r}; known: {self.state.labels()}")
        if "Dropdown" in element.type:
            options = tuple(element.props.get("options", ()))
            if options and value not in options:
                raise ValueError(f"{value!r} is not an option of {label!r}: {options}")
        return gui_update_message(element.uuid, value)


class ViserClient(_GuiSender):
    """A synchronous viser client: a reader thread feeds `state`; `send` is thread-safe.

    port: the server's port on `host` (127.0.0.1).  keep_messages: size of the ring buffer of
    non-pose messages.  The ViewerCameraMessage is sent on connect.
    """

    def __init__(self, port: int, host: str = "127.0.0.1", *, keep_messages: int = 2000,
                 open_timeout: float = 30.0) -> None:
        from websockets.sync.client import connect

        self.state = ClientState(keep_messages)
        self._ws = connect(f"ws://{host}:{port}", subprotocols=[subprotocol()], max_size=None,
                           open_timeout=open_timeout, compression=None)
        self._send_lock = threading.Lock()
        self.closed = False
        self._reader = threading.Thread(target=self._read, name=f"viser-client-{port}", daemon=True)
        self._reader.start()
        self.send(camera_message())

    def _read(self) -> None:
        try:
            for data in self._ws:
                self.state.ingest(data)
        except Exception:  # noqa: BLE001 - connection closed
            pass
        finally:
            self.closed = True
            with self.state.changed:
                self.state.changed.notify_all()

    def send(self, message: Any) -> None:
        """Send a viser `_messages.Message` (client -> server)."""
        data = encode_message(message)
        with self._send_lock:
            self._ws.send(data)

    def wait_for_label(self, label: str, timeout: float = 30.0, type_contains: str | None = None
                       ) -> GuiElement:
        """Block until a GUI element labelled `label` exists; that element."""
        return self.state.wait_for(lambda: self.state.find_gui(label, type_contains), timeout)

    def set_value(self, label: str, value: Any, type_contains: str | None = None) -> None:
        """Set the GUI element labelled `label` to `value`, as a browser would (no echo to us:
        the local table is updated here)."""
        self.send(self._gui_message(label, value, type_contains))
        element = self.state.find_gui(label, type_contains)
        if element is not None and "Button" not in element.type:
            element.value = value

    def click(self, label: str) -> None:
        """Click the button labelled `label`."""
        self.send(self._gui_message(label, True, "Button"))

    def close(self) -> None:
        """Close the connection and join the reader thread."""
        self._ws.close()
        self._reader.join(timeout=5.0)

    def __enter__(self) -> ViserClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class AsyncViserClient(_GuiSender):
    """An asyncio viser client: create with ``await AsyncViserClient.connect(port)``."""

    def __init__(self, ws: Any, keep_messages: int) -> None:
        self.state = ClientState(keep_messages)
        self._ws = ws
        self.closed = False
        self._reader: asyncio.Task[None] | None = None

    @classmethod
    async def connect(cls, port: int, host: str = "127.0.0.1", *, keep_messages: int = 2000,
                      open_timeout: float = 30.0) -> AsyncViserClient:
        """Connect, start the reader task, send the ViewerCameraMessage."""
        from websockets.asyncio.client import connect

        ws = await connect(f"ws://{host}:{port}", subprotocols=[subprotocol()], max_size=None,
                           open_timeout=open_timeout, compression=None)
        client = cls(ws, keep_messages)
        client._reader = asyncio.create_task(client._read())
        await client.send(camera_message())
        return client

    async def _read(self) -> None:
        try:
            async for data in self._ws:
                self.state.ingest(data)
        except Exception:  # noqa: BLE001 - connection closed
            pass
        finally:
            self.closed = True

    async def send(self, message: Any) -> None:
        """Send a viser `_messages.Message` (client -> server)."""
        await self._ws.send(encode_message(message))

    async def wait_for(self, predicate: Callable[[], Any], timeout: float = 30.0) -> Any:
        """Poll `predicate()` every 10 ms until truthy; its value.  TimeoutError if not."""
        deadline = time.monotonic() + timeout
        while True:
            value = predicate()
            if value:
                return value
            if time.monotonic() > deadline:
                raise TimeoutError(f"condition not met within {timeout} s")
            await asyncio.sleep(0.01)

    async def wait_for_label(self, label: str, timeout: float = 30.0,
                             type_contains: str | None = None) -> GuiElement:
        """Wait until a GUI element labelled `label` exists; that element."""
        return await self.wait_for(lambda: self.state.find_gui(label, type_contains), timeout)

    async def set_value(self, label: str, value: Any, type_contains: str | None = None) -> None:
        """Set the GUI element labelled `label` to `value`, as a browser would."""
        await self.send(self._gui_message(label, value, type_contains))
        element = self.state.find_gui(label, type_contains)
        if element is not None and "Button" not in element.type:
            element.value = value

    async def click(self, label: str) -> None:
        """Click the button labelled `label`."""
        await self.send(self._gui_message(label, True, "Button"))

    async def close(self) -> None:
        """Close the connection and wait for the reader task."""
        await self._ws.close()
        if self._reader is not None:
            try:
                await asyncio.wait_for(self._reader, 5.0)
            except (TimeoutError, asyncio.CancelledError):
                self._reader.cancel()
