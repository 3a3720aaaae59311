"""app.wire: a frame's updates encoded once, in viser's own format, written to every recipient.

Checked against viser's public path: what a browser stand-in ends with (every node's pose and
points, every panel value) equals the server's own handles, with the wire and without it
(`Wire.attach` made to refuse); the followers' shared frame is encoded once per frame, whatever
the number of followers (the encodes are counted, nothing is timed).
"""

from __future__ import annotations

import math
import threading
import time
from typing import Any

import numpy as np
import pytest
from conftest import poll_until
from viser import _messages

from app.lecture.lectern import LIVE_ROOT
from app.wire import Wire, encode, websocket_frame
from benchmarks.ws_client import decode_frame, resolve_binary

CODE = "271828"


def _array(value: Any) -> np.ndarray:
    """A decoded value as an array (binary placeholders resolved to {"dtype", "data"})."""
    if isinstance(value, dict) and "data" in value:
        return np.frombuffer(value["data"], dtype=value["dtype"])
    return np.asarray(value, dtype=float)


def test_encode_is_viser_wire_format() -> None:
    """decode(encode(messages)) gives each message's serialisable dict, numpy buffers included."""
    points = np.arange(18, dtype=np.float32).reshape(3, 2, 3)
    sent = [_messages.SetOrientationMessage("/a", (1.0, 0.0, 0.0, 0.0)),
            _messages.SceneNodeUpdateMessage("/b", {"points": points}),
            _messages.GuiUpdateMessage("uuid-1", {"value": 1.25})]
    messages, _timestamp, buffers = decode_frame(encode(sent))
    assert [m["type"] for m in messages] == [type(m).__name__ for m in sent]
    assert messages[0]["wxyz"] == [1.0, 0.0, 0.0, 0.0]
    decoded = resolve_binary(messages[1], buffers)["updates"]["points"]
    assert np.array_equal(_array(decoded).reshape(3, 2, 3), points)
    assert messages[2]["updates"] == {"value": 1.25}


@pytest.mark.parametrize("size", [0, 125, 126, 65535, 65536])
def test_websocket_frame_header(size: int) -> None:
    """RFC 6455 §5.2: FIN + binary opcode, no mask, 7 / 7+16 / 7+64 bit lengths."""
    frame = websocket_frame(b"x" * size)
    assert frame[0] == 0x82
    if size < 126:
        assert frame[1] == size and len(frame) == 2 + size
    elif size < 65536:
        assert frame[1] == 126 and int.from_bytes(frame[2:4], "big") == size and len(frame) == 4 + size
    else:
        assert frame[1] == 127 and int.from_bytes(frame[2:10], "big") == size and len(frame) == 10 + size


class SceneMirror:
    """A browser stand-in that keeps what it is told: every node's pose and props, every panel
    value (the state a browser would draw)."""

    def __init__(self, port: int) -> None:
        import viser
        from websockets.sync.client import connect

        from benchmarks.ws_client import camera_message, encode_message

        self._ws = connect(f"ws://127.0.0.1:{port}", subprotocols=[f"viser-v{viser.__version__}"],
                           max_size=None, compression=None)
        self.nodes: dict[str, dict[str, Any]] = {}
        self.gui: dict[str, Any] = {}
        self.frames = 0
        self.lock = threading.Lock()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self._ws.send(encode_message(camera_message()))

    def _read(self) -> None:
        try:
            for data in self._ws:
                messages, _t, buffers = decode_frame(data)
                with self.lock:
                    self.frames += 1
                    for message in messages:
                        self._keep(resolve_binary(message, buffers) if buffers else message)
        except Exception:  # noqa: BLE001 - closed
            pass

    def _keep(self, message: dict[str, Any]) -> None:
        kind, name = message["type"], message.get("name")
        if kind == "RemoveSceneNodeMessage":
            self.nodes = {n: v for n, v in self.nodes.items() if n != name and not n.startswith(f"{name}/")}
        elif kind == "SetOrientationMessage":
            self.nodes.setdefault(name, {})["wxyz"] = tuple(message["wxyz"])
        elif kind == "SetPositionMessage":
            self.nodes.setdefault(name, {})["position"] = tuple(message["position"])
        elif kind == "SceneNodeUpdateMessage":
            self.nodes.setdefault(name, {}).update(message["updates"])
        elif kind == "GuiUpdateMessage" and "value" in message["updates"]:
            self.gui[message["uuid"]] = message["updates"]["value"]
        elif name is not None and isinstance(message.get("props"), dict):  # a node made
            node = self.nodes[name] = {}
            for key in ("wxyz", "position"):
                if key in message["props"]:
                    node[key] = tuple(message["props"][key])
            if "points" in message["props"]:
                node["points"] = message["props"]["points"]

    def close(self) -> None:
        self._ws.close()
        self._reader.join(timeout=5.0)


def _differences(mirror: SceneMirror, api: Any, prefix: str) -> list[str]:
    """Nodes under `prefix` whose pose or points in `mirror` differ from the server's handles."""
    found = []
    with mirror.lock:
        nodes = dict(mirror.nodes)
    for name, handle in list(api._handle_from_node_name.items()):
        if not name.startswith(prefix) or name not in nodes:
            continue
        impl, seen = handle._impl, nodes[name]
        for key, server_value in (("wxyz", impl.wxyz), ("position", impl.position)):
            if key in seen and not np.allclose(seen[key], server_value, atol=1e-6):
                found.append(f"{name}.{key}: browser {seen[key]} server {tuple(server_value)}")
        points = getattr(impl.props, "points", None)
        if "points" in seen and points is not None:
            browser = _array(seen["points"]).astype(float).ravel()
            server = np.asarray(points, dtype=float).ravel()
            if browser.size != server.size or not np.allclose(browser, server, atol=1e-6):
                found.append(f"{name}.points differ")
    return found


def _settled(mirror: SceneMirror, timeout: float = 30.0) -> None:
    """Wait until no frame has arrived for 0.3 s; AssertionError if frames still come after `timeout` [s]."""
    last, since = -1, time.monotonic()
    deadline = since + timeout
    while time.monotonic() - since < 0.3:
        assert time.monotonic() < deadline, f"frames still arriving after {timeout} s"
        with mirror.lock:
            frames = mirror.frames
        if frames != last:
            last, since = frames, time.monotonic()
        time.sleep(0.02)


@pytest.mark.parametrize("wired", [True, False], ids=["wire", "public path"])
@pytest.mark.parametrize("scene", ["Free body", "Heavy top", "Moving frame"])  # Moving frame: arrows inline
def test_own_room_ends_as_the_server(monkeypatch: pytest.MonkeyPatch, wired: bool, scene: str) -> None:
    """A room of its own plays 1 s and pauses: the browser's nodes are the server's."""
    from app.main import create_server

    if not wired:
        monkeypatch.setattr(Wire, "attach", classmethod(lambda cls, server, client=None: None))
    app = create_server("127.0.0.1", 0, verbose=False)
    mirror = SceneMirror(app.port)
    try:
        session = next(iter(app.wait_for_sessions(1).values()))
        session.select_scene(scene)
        session.play()
        time.sleep(1.0)
        if wired:  # the wire carries the frames (20 of them, however busy the machine)
            poll_until(lambda: (wire := app._wires.get(session.client.client_id)) is not None and wire.frames > 20,
                       timeout=30.0)
        else:
            assert app._wires.get(session.client.client_id) is None
        session.pause()
        _settled(mirror)
        with session.lock:
            differences = _differences(mirror, session.client.scene, "/")
        assert differences == []
        with mirror.lock:
            assert len(mirror.nodes) > 5
    finally:
        mirror.close()
        app.stop()


def test_a_browser_busy_past_the_retry_still_gets_the_last_frame(monkeypatch: pytest.MonkeyPatch) -> None:
    """The last frame before the picture stands still reaches a browser that was not caught up
    at the frame's send nor at its first retry (viser still taking a new scene's nodes on a busy
    machine): held back while one frame moves a node (no frame after it), then let through, it
    ends with the node where the server has it."""
    from app.main import create_server
    from app.wire import capturing, end_frames

    held = threading.Event()
    refused = [0]  # times the held browser was found not caught up
    caught_up = Wire._caught_up

    def not_while_held(self: Wire, client_id: int, connection: Any) -> bool:
        if held.is_set():
            refused[0] += 1
            return False
        return caught_up(self, client_id, connection)

    monkeypatch.setattr(Wire, "_caught_up", not_while_held)
    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    mirror = SceneMirror(app.port)
    try:
        session = next(iter(app.wait_for_sessions(1).values()))
        node = session.client.scene.add_frame("/probe", show_axes=False)
        poll_until(lambda: "/probe" in mirror.nodes, timeout=10.0)
        wire = app._wires.get(session.client.client_id)
        assert wire is not None
        held.set()
        with capturing():
            node.position = (1.0, 2.0, 3.0)
        end_frames([(wire, (session.client.client_id,))])
        poll_until(lambda: refused[0] >= 2)  # the frame's send, then its first retry
        with mirror.lock:
            assert mirror.nodes["/probe"].get("position", (0.0, 0.0, 0.0)) == (0.0, 0.0, 0.0)  # held back
        held.clear()
        poll_until(lambda: mirror.nodes["/probe"].get("position") == (1.0, 2.0, 3.0))
    finally:
        mirror.close()
        app.stop()


def test_followers_frame_is_encoded_once() -> None:
    """A presenter plays; four followers watch.  The shared wire encodes about once a frame (a
    catch-up for a follower that was skipped costs one more), not once per follower; every
    follower ends with the presenter's nodes."""
    from app.main import create_server

    app = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE)
    mirrors = [SceneMirror(app.port)]
    try:
        presenter = next(iter(app.wait_for_sessions(1).values()))
        presenter.present(CODE)
        presenter.select_scene("Free body")
        mirrors += [SceneMirror(app.port) for _ in range(4)]
        poll_until(lambda: len(app.lectern.followers) == 4, timeout=15.0)
        presenter.play()
        time.sleep(1.5)
        poll_until(lambda: (wire := app._wires.get(None)) is not None and wire.frames > 30, timeout=30.0)
        presenter.pause()
        for mirror in mirrors:
            _settled(mirror)
        shared = app._wires[None]
        assert shared is not None
        assert shared.encodes <= 1.25 * shared.frames, (shared.encodes, shared.frames)
        assert shared.writes >= 4 * shared.frames * 0.8  # every follower got (nearly) every frame
        for mirror in mirrors:
            assert _differences(mirror, app.server.scene, LIVE_ROOT) == []
            with mirror.lock:
                assert any(name.startswith(LIVE_ROOT) for name in mirror.nodes)
    finally:
        for mirror in mirrors:
            mirror.close()
        app.stop()


def test_pose_messages_are_serialised_as_viser_does_with_their_numbers_in_the_shortest_exact_form() -> None:
    """app.wire builds a pose message's dict itself: the same keys and values as viser's own
    `as_serializable_dict`, the numbers as integers / float32 / float64, whichever is exact."""
    import msgspec

    from app.wire import _serialise

    values = (0.0, -0.0, 1.0, -1.0, 0.5, 0.1, 1e-300, 3e38, 1e40, 2.0**31)
    for message in (_messages.SetOrientationMessage("/l/a", values[:4]),
                    _messages.SetOrientationMessage("/l/b", values[4:8]),
                    _messages.SetPositionMessage("/c", values[7:10])):
        message.owner = "7"
        ours, viser_own = _serialise(message, []), message.as_serializable_dict([])
        assert list(ours) == list(viser_own) and ours["type"] == viser_own["type"] == type(message).__name__
        decoded = msgspec.msgpack.decode(msgspec.msgpack.encode(ours))
        field = "wxyz" if "wxyz" in ours else "position"
        got, want = decoded[field], list(viser_own[field])
        assert [float(x) for x in got] == want  # exactly
        assert [math.copysign(1.0, x) for x in got] == [math.copysign(1.0, x) for x in want]  # -0.0 kept
        assert {k: v for k, v in decoded.items() if k != field} == {k: v for k, v in viser_own.items() if k != field}
    # Shorter: 0 and ±1 take a byte, a float32-exact number five, others nine.
    short = msgspec.msgpack.encode(_serialise(_messages.SetOrientationMessage("/a", (1.0, 0.0, 0.0, 0.0)), []))
    long = msgspec.msgpack.encode(_messages.SetOrientationMessage("/a", (1.0, 0.0, 0.0, 0.0)).as_serializable_dict([]))
    assert len(long) - len(short) == 4 * (9 - 1)
    message = _messages.SceneNodeUpdateMessage("/b", {"scale": 0.5})  # a uniform scale: viser's own
    assert _serialise(message, []) == message.as_serializable_dict([])
    # A node's per-axis scale (a scaled shaft, a spring) takes the shortest exact form too.
    message = _messages.SceneNodeUpdateMessage("/b", {"scale": (1.0, -0.0, 0.1)})
    ours, viser_own = _serialise(message, []), message.as_serializable_dict([])
    decoded = msgspec.msgpack.decode(msgspec.msgpack.encode(ours))
    assert [float(x) for x in decoded["updates"]["scale"]] == list(viser_own["updates"]["scale"])
    assert math.copysign(1.0, decoded["updates"]["scale"][1]) == -1.0
    assert {k: v for k, v in decoded.items() if k != "updates"} == \
        {k: v for k, v in viser_own.items() if k != "updates"}
    assert len(msgspec.msgpack.encode(viser_own)) - len(msgspec.msgpack.encode(ours)) == (9 - 1) + (9 - 5)  # 1.0, -0.0


def test_small_points_of_arrows_and_segments_go_inline_exactly() -> None:
    """A float32 `points` update of a node the wire saw made as arrows or line segments goes in
    the msgpack as an array of numbers: the same float32 values (+0.0 a one-byte 0, -0.0 kept);
    another node's, or a big array with few zeros, stays a raw buffer as viser sends it."""
    import msgspec

    from app.wire import INLINE_SLACK, _serialise

    points = np.array([[[0.0, 0.0, 0.0], [0.1, -0.0, 3e38]], [[0.0, 0.0, 0.0], [-1.5, 2.0 ** -20, 1.0]]],
                      dtype=np.float32)
    message = _messages.SceneNodeUpdateMessage("/a", {"points": points})
    buffers: list[Any] = []
    ours = _serialise(message, buffers, {"/a"})
    assert buffers == []  # no raw buffer
    decoded = msgspec.msgpack.decode(msgspec.msgpack.encode(ours))
    got = decoded["updates"]["points"]
    assert np.array_equal(np.array(got, dtype=np.float32), points.ravel())  # exactly, as float32
    assert [math.copysign(1.0, x) for x in got] == [math.copysign(1.0, float(x)) for x in points.ravel()]
    assert {k: v for k, v in decoded.items() if k != "updates"} == \
        {k: v for k, v in message.as_serializable_dict([]).items() if k != "updates"}
    assert sum(1 for x in got if type(x) is int) == 6  # the +0.0s: a byte each
    viser_own = message.as_serializable_dict(viser_buffers := [])
    assert len(msgspec.msgpack.encode(ours)) < len(msgspec.msgpack.encode(viser_own)) + viser_buffers[0].nbytes
    # Not a node of the wire's arrows or segments, too big with too few zeros, or not points
    # alone: viser's own form.
    colors = {"colors": np.zeros((2, 3), dtype=np.uint8)}
    for name, updates in (("/b", {"points": points}), ("/a", {"points": points, **colors}),
                          ("/a", {"points": np.ones((INLINE_SLACK // 6 + 1, 2, 3), dtype=np.float32)})):
        message = _messages.SceneNodeUpdateMessage(name, updates)
        ours_buffers: list[Any] = []
        viser_buffers = []
        assert _serialise(message, ours_buffers, {"/a"}) == message.as_serializable_dict(viser_buffers)
        assert [bytes(b) for b in ours_buffers] == [bytes(b) for b in viser_buffers]


def test_the_wire_inlines_points_only_for_nodes_it_saw_made_as_arrows_or_segments(server: Any) -> None:
    """The wire learns the names from the nodes' creation messages (and forgets one made again
    as another kind)."""
    wire = Wire.attach(server)
    assert wire is not None
    try:
        segments = np.zeros((1, 2, 3), dtype=np.float32)
        server.scene.add_arrows("/inline/a", segments, (255, 0, 0))
        server.scene.add_line_segments("/inline/s", segments, (0, 0, 0))
        server.scene.add_point_cloud("/inline/p", np.zeros((2, 3), dtype=np.float32), (0, 0, 0), point_size=0.1)
        assert {"/inline/a", "/inline/s"} <= wire._inline and "/inline/p" not in wire._inline
        server.scene.add_frame("/inline/a")  # the name made again as a frame
        assert "/inline/a" not in wire._inline and "/inline/s" in wire._inline
    finally:
        server._websock_server.queue_message = wire._queue  # the module's server back as it was


class _WatchedWaiters(list):
    """An event's waiter queue that records which threads walk it (asyncio.Event.set walks it)."""

    def __init__(self) -> None:
        super().__init__()
        self.walkers: set[int] = set()

    def __iter__(self):  # noqa: ANN204
        self.walkers.add(threading.get_ident())
        return super().__iter__()


def test_a_message_queued_off_the_loop_wakes_the_sender_on_the_loop_only(server: Any) -> None:
    """viser's buffer sets its asyncio.Event from the pushing thread; walking its waiters there
    races the loop ("deque mutated during iteration", a CI failure). Behind a wire, only the
    loop's thread walks them, and a waiting sender is still woken."""
    import asyncio

    from app.viser_internals import event_loop, interface_of, message_buffer

    Wire.attach(server)
    buffer = message_buffer(interface_of(server))
    loop = event_loop(server)
    loop_thread: list[int] = []
    woken = threading.Event()

    async def wait() -> None:
        loop_thread.append(threading.get_ident())
        buffer.message_event.clear()
        buffer.message_event._waiters = waiters = _WatchedWaiters()  # noqa: SLF001
        await buffer.message_event.wait()
        assert waiters.walkers == {threading.get_ident()}
        woken.set()

    asyncio.run_coroutine_threadsafe(wait(), loop)
    poll_until(lambda: loop_thread and buffer.message_event._waiters, timeout=10.0,  # noqa: SLF001
               what="a waiter on viser's loop")
    server.scene.add_frame("/off_the_loop", show_axes=False)  # pushed from this (test) thread
    assert woken.wait(10.0), "the waiting sender was not woken"
    assert threading.get_ident() not in buffer.message_event._waiters.walkers  # noqa: SLF001
