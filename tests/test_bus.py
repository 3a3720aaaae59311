"""One lecture across processes (app.lecture.bus), with a real redis-server and two (or three)
in-process workers, each a whole app (`create_server(redis_url=..., worker_id=...)`, its loop
running): a presenter on worker A, followers on A and on B.

- The followers on B receive the same scene as those on A: their decoded scene trees (browser
  stand-ins that keep every node's pose and props) are equal at a paused moment, also on a
  worker that joined after the lecture began (a resync); their panels say the same.
- The hostile follower of tests/test_trust.py, on B, leaves the presenter's room on A
  bit-identical.
- Stop presenting on A is "stopped" on B; A ending is "the presenter has left" on B (said, or,
  when A dies without a word, after the lease); B ending leaves A's presenter and followers
  working.
- The bus's messages: what is not an allowlisted scene message under LIVE_ROOT is refused;
  a culled batch keeps the last value of each property.
- Explore on B equals the presenter's room bit for bit (needs the room codec,
  `app.codec`; skipped without it).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterator
from typing import Any

import msgspec
import numpy as np
import pytest
from conftest import join, poll_until
from test_trust import attack, fingerprint
from test_wire import SceneMirror, _array, _settled

from app.kit.draw.screen import screen_of
from app.lecture.bus import BusError, cull, decode_batch, encode_batch
from app.lecture.follower import Hall
from app.lecture.lectern import LIVE_ROOT
from app.main import App, create_server
from benchmarks.ws_client import ViserClient

CODE = "97531864"


class SharedMirror(SceneMirror):
    """A browser stand-in that keeps the shared scene only (the nodes of owner ""): a browser's
    own nodes of the same name (a hidden shadow of LIVE_ROOT) are another layer."""

    def _keep(self, message: dict[str, Any]) -> None:
        if message.get("owner") not in ("", None):
            return
        if message["type"] == "SetSceneNodeVisibilityMessage":
            self.nodes.setdefault(message["name"], {})["visible"] = message["visible"]
        elif message["type"] == "LabelMessage":
            super()._keep(message)
            self.nodes[message["name"]]["text"] = message["props"]["text"]
        else:
            super()._keep(message)


class Workers:
    """Apps on one Redis (flushed: a fresh lecture), each a worker with presenter code `code`;
    browser stand-ins connected to them; all closed at the end."""

    def __init__(self, url: str, code: str = CODE) -> None:
        self.url = url
        self.code = code
        self.apps: dict[str, App] = {}
        self.clients: list[Any] = []
        import redis

        redis.Redis.from_url(url).flushall()  # a fresh lecture (the lock, the audience)

    def start(self, worker: str) -> App:
        app = create_server("127.0.0.1", 0, verbose=False, presenter_code=self.code, redis_url=self.url,
                            worker_id=worker)
        self.apps[worker] = app
        return app

    def connect(self, worker: str, factory: Any = SharedMirror) -> tuple[Any, Any]:
        """A browser stand-in on `worker`: (its session, the client)."""
        return join(self.apps[worker], self.clients, factory, timeout=60.0)  # a websocket handshake on a busy machine

    def close(self) -> None:
        for client in self.clients:
            client.close()
        for app in self.apps.values():
            app.stop()


def workers_fixture(code: str = CODE) -> Any:
    """A pytest fixture, to assign to the name the tests ask for (`workers = workers_fixture(CODE)`;
    it needs the `redis_url` fixture imported beside it): fresh `Workers` with presenter code
    `code` for each test, closed after it."""

    @pytest.fixture
    def fresh_workers(redis_url: str) -> Iterator[Workers]:
        with contextlib.closing(Workers(redis_url, code)) as running:
            yield running

    return fresh_workers


workers = workers_fixture(CODE)


def _present(workers: Workers, worker: str, title: str = "Free body") -> Any:
    presenter, _ = workers.connect(worker)
    presenter.guard("test", presenter.select_scene)(title)
    presenter.guard("test", presenter.present)(workers.code)
    assert presenter.mode == "presenting", presenter.last_error
    return presenter


def _live_nodes(mirror: SceneMirror) -> dict[str, dict[str, Any]]:
    with mirror.lock:
        return {name: dict(node) for name, node in mirror.nodes.items() if name.startswith(LIVE_ROOT)}


def _same(a: Any, b: Any) -> bool:
    """Equal as a browser reads them: numbers by value (0 and 0.0 alike), arrays element by element."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return False
        return all(np.array_equal(_array(a[k]).astype(float).ravel(), _array(b[k]).astype(float).ravel())
                   if k == "points" else _same(a[k], b[k]) for k in a)  # points inline or as a buffer alike
    if isinstance(a, (bytes, memoryview)) or isinstance(b, (bytes, memoryview)):
        return bytes(a) == bytes(b)
    if isinstance(a, (list, tuple, np.ndarray)) and isinstance(b, (list, tuple, np.ndarray)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return bool(a == b)


def _wait_for_cameras(presenter: Any, followers: dict[str, Any], timeout: float = 30.0) -> None:
    """Wait until every follower's camera (by its worker) looks at what the presenter's does (the
    lectern's `send_camera`, through the bus on another worker); the failure names who does not."""
    look_at = np.asarray(presenter.client.camera.look_at, float)
    away = lambda: [(worker, [float(x) for x in f.client.camera.look_at]) for worker, f in followers.items()  # noqa: E731
                    if not np.allclose(f.client.camera.look_at, look_at, atol=1e-6)]
    _poll(lambda: not away(), lambda: f"every follower's camera looking at the presenter's {look_at.tolist()}; "
          f"not: {away()}", timeout)


def _poll(predicate: Any, message: Any, timeout: float = 30.0) -> None:
    """poll_until, its failure saying `message()`: what it waited for and what it saw."""
    try:
        poll_until(predicate, timeout=timeout, interval=0.05)
    except AssertionError:
        raise AssertionError(f"after {timeout} s: {message()}") from None


def _scene_differences(a: SceneMirror, b: SceneMirror) -> list[str]:
    _settled(a)
    _settled(b)
    nodes_a, nodes_b = _live_nodes(a), _live_nodes(b)
    found = [f"only one side has {name}" for name in sorted(set(nodes_a) ^ set(nodes_b))]
    found += [f"{name}: {str(nodes_a[name])[:160]} != {str(nodes_b[name])[:160]}"
              for name in sorted(set(nodes_a) & set(nodes_b)) if not _same(nodes_a[name], nodes_b[name])]
    return found


def test_followers_on_other_workers_see_the_presenters_scene(workers: Workers) -> None:
    a, b = workers.start("a"), workers.start("b")
    presenter = _present(workers, "a")
    follower_a, mirror_a = workers.connect("a")
    follower_b, mirror_b = workers.connect("b")
    poll_until(lambda: follower_a.mode == "following" and follower_b.mode == "following", timeout=10.0)
    presenter.guard("test", presenter.play)()
    poll_until(lambda: presenter.room.sim.t > 0.5, timeout=10.0)
    poll_until(lambda: b.lectern.status() == a.lectern.status() and "playing" in b.lectern.status(), timeout=10.0)
    presenter.guard("test", presenter.pause)()
    c = workers.start("c")  # a worker that joins late: it asks for the whole scene
    follower_c, mirror_c = workers.connect("c")
    poll_until(lambda: follower_c.mode == "following" and follower_c.scene is not None, timeout=10.0)
    poll_until(lambda: not _scene_differences(mirror_a, mirror_b), timeout=10.0, interval=0.1)
    try:
        poll_until(lambda: not _scene_differences(mirror_a, mirror_c), timeout=10.0, interval=0.1)
    except AssertionError:
        raise AssertionError(_scene_differences(mirror_a, mirror_c)[:8]) from None
    assert len(_live_nodes(mirror_b)) > 20  # the body, its axes, ω, L, the labels ...
    # Their panels say the same; the presenter's badge counts every worker's followers.
    poll_until(lambda: b.lectern.status() == a.lectern.status() == c.lectern.status(), timeout=10.0)
    assert "Free body" in b.lectern.status() and b.lectern.hall is Hall.LIVE
    poll_until(lambda: a.lectern.total_audience() == (3, 0), timeout=10.0)
    # The camera: the presenter's view reaches every follower, also C's (a worker that came after
    # it was last sent), and the shared labels are then laid out for that view only.
    _wait_for_cameras(presenter, {"A": follower_a, "B": follower_b, "C": follower_c})
    views = lambda: {s.view for s in a.lectern.label_screens()}  # noqa: E731
    _poll(lambda: views() == {screen_of(presenter.client.camera).view},
          lambda: f"the shared labels laid out for the presenter's view only; they are for {views()}")
    _poll(lambda: not _scene_differences(mirror_a, mirror_b),
          lambda: f"B's scene equal to A's; differences: {_scene_differences(mirror_a, mirror_b)[:8]}", 30.0)
    shown = lambda: [node.get("text") for node in _live_nodes(mirror_b).values()  # noqa: E731
                     if node.get("visible") and "text" in node]
    _poll(lambda: "ω" in shown() and "L" in shown(), lambda: f"ω and L shown on B's follower; shown: {shown()}")
    # The bus: a scene batch once a frame, small, and fast enough.
    assert a.bus.published_batches > 10 and a.bus.published_bytes / a.bus.published_batches < 20_000
    assert b.bus.delays and float(np.median(b.bus.delays)) < 0.25


def test_the_shared_labels_are_laid_out_for_a_phone_on_another_worker(workers: Workers) -> None:
    """A phone follows on B: A's shared labels are laid out for its screen too (B writes its
    followers' kinds of screen with its audience; A adds them to `label_screens`)."""
    from test_label_screens import PHONE, _window

    a, b = workers.start("a"), workers.start("b")
    presenter = _present(workers, "a")
    phone, phone_client = workers.connect("b", ViserClient)
    _window(phone_client, *PHONE[:2])
    poll_until(lambda: phone.mode == "following" and phone.client.camera.image_width == PHONE[0], timeout=10.0)
    poll_until(b.lectern.follower_screens, timeout=10.0, what="B's follower screens (kept up to a period)")
    assert all(s.width != PHONE[0] for s in a.lectern.follower_screens())
    poll_until(lambda: any((s.width, s.height) == PHONE[:2] for s in a.lectern.label_screens()), timeout=10.0)
    (remote,) = [s for s in a.lectern.label_screens() if (s.width, s.height) == PHONE[:2]]
    assert remote.panel == b.lectern.follower_screens()[0].panel  # the phone's bottom sheet, through Redis
    assert presenter.mode == "presenting"


def _screen_read(plain: Any) -> Any:
    """`plain` as another worker reads it from the audience: a `Screen`, or None (refused)."""
    from app.cluster.messages import ScreenShape, decode
    from app.lecture.bus.values import screen_from_shape

    try:
        return screen_from_shape(decode(msgspec.msgpack.encode(plain), ScreenShape))
    except msgspec.DecodeError:
        return None


def test_a_screen_from_redis_is_checked() -> None:
    from app.cluster.messages import encode
    from app.kit.core.common import CameraView
    from app.kit.draw.screen import Screen
    from app.lecture.bus.values import screen_shape

    view = CameraView((3.0, 3.0, 3.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 50.0)
    screen = Screen(view, 780, 1688, (0.0, 1000.0, 780.0, 1688.0))
    good = msgspec.msgpack.decode(encode(screen_shape(screen)))
    assert _screen_read(good) == screen
    assert _screen_read([*good[:6], None]) == Screen(view, 780, 1688, None)
    for bad in (None, "x", good[:6], [*good[:3], 0.0, *good[4:]], [*good[:3], 180.0, *good[4:]],
                [*good[:4], 0, *good[5:]], [*good[:4], 1 << 20, *good[5:]], [[float("nan"), 3.0, 3.0], *good[1:]],
                [*good[:6], [0.0, 0.0, "1", 1.0]], [[True, 3.0, 3.0], *good[1:]], [good[0], good[0], *good[2:]],
                [*good[:4], 780.5, *good[5:]]):
        assert _screen_read(bad) is None, bad


def test_a_follower_on_another_worker_sees_the_presenters_plot_tab(workers: Workers) -> None:
    """The presenter on A opens Plots and plays: B's follower has the same charts (titles,
    series, column count) whose data follow the presenter's (float32 of the same samples)."""
    workers.start("a")
    workers.start("b")
    presenter = _present(workers, "a")
    follower, _ = workers.connect("b")
    poll_until(lambda: follower.mode == "following" and follower.scene is not None, timeout=10.0)
    presenter.guard("test", presenter.scene.tabs.show)("Plots")
    presenter.guard("test", presenter.play)()
    sources = presenter.scene.plot_elements("Plots")
    mirror = follower.scene.plot
    poll_until(lambda: mirror.tab == "Plots" and len(mirror.copies) == len(sources), timeout=10.0)
    assert "Plots tab (read only)" in mirror.folder.label and mirror.folder.visible
    charts = [(s, c) for s, c in zip(sources, mirror.copies) if hasattr(s, "series")]
    assert charts
    for source, copy in charts:
        assert copy.title == source.title and len(copy.series) == len(source.series)
        assert [x.get("label") for x in copy.series] == [x.get("label") for x in source.series]
    source, copy = charts[-1]
    start = float(np.asarray(copy.data[0])[-1])
    poll_until(lambda: float(np.asarray(copy.data[0])[-1]) > start, timeout=10.0)  # it follows
    presenter.guard("test", presenter.pause)()
    time.sleep(0.3)
    x_source = np.asarray(source.data[0], dtype=np.float32)
    poll_until(lambda: np.array_equal(np.asarray(copy.data[0]), x_source), timeout=10.0)  # paused: the same samples
    for column_source, column_copy in zip(source.data, copy.data):
        np.testing.assert_array_equal(np.asarray(column_copy), np.asarray(column_source, dtype=np.float32))
    presenter.guard("test", presenter.stop_presenting)()
    poll_until(lambda: mirror.tab == "", timeout=10.0)  # stopped: the copy goes, as on one process


def _plot_read(plain: Any, previous: Any) -> Any:
    """`plain` (a plot message's dict) as another worker reads it from the bus: (tab, elements), or None (refused)."""
    from app.cluster.messages import LIVE_DECODER, Plot
    from app.lecture.bus.values import plot_from_message

    try:
        message = LIVE_DECODER.decode(msgspec.msgpack.encode({"k": "plot", "w": "a", **plain}))
    except msgspec.DecodeError:
        return None
    assert isinstance(message, Plot)
    return plot_from_message(message, previous)


def test_a_plot_from_redis_is_checked() -> None:
    from app.cluster.messages import encode
    from app.lecture.bus.values import plot_message
    from app.lecture.room_plot import ChartCopy, MarkdownCopy

    x = np.linspace(0.0, 1.0, 5)
    chart = ChartCopy((x, np.sin(x)), series=[{"label": "t"}, {"label": "ω_x", "stroke": "red"}], title="ω")
    plain = msgspec.msgpack.decode(encode(plot_message("a", "Plots", [chart, MarkdownCopy("**E** = 1")])))
    tab, (got, words) = _plot_read(plain, ("", ()))
    assert tab == "Plots" and words == MarkdownCopy("**E** = 1") and got.title == "ω" and got.series == chart.series
    np.testing.assert_array_equal(got.data[1], np.sin(x).astype(np.float32))
    again = _plot_read(plain, (tab, (got, words)))  # unchanged: the same objects (nothing re-sent)
    assert again is not None and again[1][0] is got and again[1][1] is words
    assert _plot_read({"tab": "", "el": []}, (tab, (got, words))) == ("", ())
    uplot = plain["el"][0]
    for bad in ({"tab": "Setup", "el": plain["el"]}, {"tab": "Plots", "el": []}, {"tab": "Plots", "el": "x"},
                {"tab": "Plots", "el": [["uplot", {"onclick": "alert(1)"}, uplot[2]]]},
                {"tab": "Plots", "el": [["uplot", uplot[1], [uplot[2][0], uplot[2][1][:-4]]]]},
                {"tab": "Plots", "el": [["uplot", uplot[1], [b"abc"]]]},
                {"tab": "Plots", "el": [["uplot", uplot[1], [b"\0" * 4 * 20_004]]]},
                {"tab": "Plots", "el": [["uplot", uplot[1], []]]},
                {"tab": "Plots", "el": [["uplot", {"title": float("nan")}, uplot[2]]]},
                {"tab": "Plots", "el": [["uplot", {"series": [{"label": "x" * 201}]}, uplot[2]]]},
                {"tab": "Plots", "el": [["uplot", {"series": [[[[[[[[[[]]]]]]]]]]}, uplot[2]]]},
                {"tab": "Plots", "el": [["markdown", 3]]}, {"tab": "Plots", "el": [["script", "x"]]},
                {"tab": "Plots", "el": [["markdown", "x"]] * 17}, {"tab": 3, "el": []}):
        assert _plot_read(bad, ("", ())) is None, str(bad)[:120]


def test_a_hostile_follower_on_another_worker_changes_nothing(workers: Workers) -> None:
    workers.start("a")
    b = workers.start("b")
    presenter = _present(workers, "a", "Heavy top")
    presenter.guard("test", presenter.play)()
    poll_until(lambda: presenter.room.sim.t > 0.3, timeout=10.0)
    presenter.guard("test", presenter.pause)()
    hostile_session, hostile = workers.connect("b", ViserClient)
    poll_until(lambda: hostile_session.mode == "following" and hostile_session.scene is not None, timeout=10.0)
    poll_until(lambda: len([m for m in hostile.state.messages if str(m[2].get("name", "")).startswith(LIVE_ROOT)])
               > 10, timeout=10.0)
    before = fingerprint(presenter.room.sim)
    sent = attack(hostile, presenter)
    assert sent > 50
    time.sleep(0.5)  # what it sent arrives (B's loop keeps running)
    assert fingerprint(presenter.room.sim) == before
    assert presenter.mode == "presenting" and b.lectern.hall is Hall.LIVE


def test_stopped_left_and_a_worker_ending(workers: Workers) -> None:
    a, b = workers.start("a"), workers.start("b")
    presenter = _present(workers, "a")
    follower_a, mirror_a = workers.connect("a")
    follower_b, _ = workers.connect("b")
    try:
        poll_until(lambda: follower_b.mode == "following" and b.lectern.hall is Hall.LIVE, timeout=10.0)
    except AssertionError:
        raise AssertionError((follower_b.mode, b.lectern.hall, b.lectern.remote, b.bus.following.remote_worker,
                              b.bus.following.expected, a.bus.source, a.bus.published_batches,
                              presenter.mode)) from None
    presenter.guard("test", presenter.stop_presenting)()
    poll_until(lambda: b.lectern.hall is Hall.STOPPED, timeout=10.0)
    assert "stopped" in b.lectern.status().lower()
    presenter.guard("test", presenter.present)(CODE)
    poll_until(lambda: b.lectern.hall is Hall.LIVE, timeout=10.0)
    # B ends: A's presenter and followers go on.
    b.stop()
    del workers.apps["b"]
    presenter.guard("test", presenter.play)()
    with mirror_a.lock:
        frames = mirror_a.frames
    t = presenter.room.sim.t
    poll_until(lambda: presenter.room.sim.t > t + 0.5 and mirror_a.frames > frames + 10, timeout=10.0)
    # A worker that dies without a word: the others take it that the presenter left, after the lease.
    c = workers.start("c")
    follower_c, _ = workers.connect("c")
    try:
        poll_until(lambda: follower_c.mode == "following" and c.lectern.hall is Hall.LIVE, timeout=10.0)
    except AssertionError:
        raise AssertionError((follower_c.mode, c.lectern.hall, c.lectern.remote, c.bus.following.remote_worker,
                              c.bus.following.expected, a.bus.source, a.bus.published_batches, presenter.mode,
                              a.bus.publisher.resync_for, c.bus.following.asked_at, c.bus.resyncs)) from None
    a.bus.source = False  # as if killed: no "left" said
    a.stop()
    del workers.apps["a"]
    poll_until(lambda: c.lectern.hall is Hall.LEFT, timeout=10.0)
    assert "left" in c.lectern.status().lower()


def test_a_presenter_on_b_takes_over_from_a_stopped_presenter_on_a(workers: Workers) -> None:
    pytest.importorskip("app.codec")  # a follower that presents explores first: a copy of the room
    a, b = workers.start("a"), workers.start("b")
    first = _present(workers, "a", "Heavy top")
    follower_a, mirror_a = workers.connect("a")
    follower_b, mirror_b = workers.connect("b")
    poll_until(lambda: follower_b.mode == "following" and follower_b.scene is not None, timeout=10.0)
    first.guard("test", first.stop_presenting)()
    poll_until(lambda: b.lectern.hall is Hall.STOPPED, timeout=10.0)
    second, _ = workers.connect("b")  # it lands in its own room (the lecture ended), presents it, picks a scene
    second.guard("test", second.present)(CODE)
    second.guard("test", second.select_scene)("Poinsot")
    poll_until(lambda: a.lectern.hall is Hall.LIVE and a.lectern.remote is not None, timeout=10.0)
    poll_until(lambda: "Poinsot" in a.lectern.status(), timeout=10.0)
    assert second.mode == "presenting"
    try:
        poll_until(lambda: not _scene_differences(mirror_a, mirror_b), timeout=10.0, interval=0.1)
    except AssertionError:
        raise AssertionError(_scene_differences(mirror_a, mirror_b)[:6]) from None
    assert any("/poinsot" in name or "/p" in name for name in _live_nodes(mirror_a))


def _through_redis(batch: tuple[list[Any], list[bytes], list[list[int]]]) -> tuple[Any, ...]:
    """A batch as another process reads it (msgpack there and back)."""
    return tuple(msgspec.msgpack.decode(msgspec.msgpack.encode(part)) for part in batch)


def test_bus_messages_are_checked() -> None:
    from viser import _messages

    good = [_messages.SetPositionMessage(f"{LIVE_ROOT}/x", (1.0, 2.0, 3.0)),
            _messages.SetPositionMessage(f"{LIVE_ROOT}/x", (4.0, 5.0, 6.0))]
    dicts, buffers, shapes = _through_redis(encode_batch(cull(good)))
    (message,) = decode_batch(dicts, buffers, shapes)
    assert message.position == (4.0, 5.0, 6.0)
    for bad in ([{"type": "GuiUpdateMessage", "name": f"{LIVE_ROOT}/x", "uuid": "u", "updates": {}}],
                [{"type": "SetPositionMessage", "name": "/elsewhere", "position": [0, 0, 0]}],
                [{"type": "TransformControlsMessage", "name": f"{LIVE_ROOT}/g", "props": {}}],
                [{"type": "SetPositionMessage", "name": f"{LIVE_ROOT}/x", "position": [0, 0, 0], "evil": 1}],
                [{"type": "SceneNodeUpdateMessage", "name": f"{LIVE_ROOT}/x",
                  "updates": {"points": {"__binary_index": 0, "dtype": "O"}}}]):
        with pytest.raises(BusError):
            decode_batch(bad, [b"\0" * 8], [[8]])
    arrows = [_messages.ArrowMessage(f"{LIVE_ROOT}/a", _messages.ArrowProps(
        points=np.ones((2, 2, 3), np.float32), colors=np.zeros((2, 3), np.uint8), shaft_radius=0.1,
        head_radius=0.2, head_length=0.3, scale=1.0))]
    dicts, buffers, shapes = _through_redis(encode_batch(arrows))
    (message,) = decode_batch(dicts, buffers, shapes)
    assert message.props.points.shape == (2, 2, 3) and np.array_equal(message.props.points, arrows[0].props.points)
    with pytest.raises(BusError):
        decode_batch(dicts, [buffers[0][:-4], buffers[1]], shapes)  # a buffer that does not fit its shape


def test_explore_on_another_worker_is_the_presenters_room_bit_for_bit(workers: Workers,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("app.codec")
    import app.lecture.lectern

    monkeypatch.setattr(app.lecture.lectern, "CALL_BACK_SECONDS", 0.5)  # the countdown's length is not the claim
    workers.start("a")
    b = workers.start("b")
    presenter = _present(workers, "a", "Free body")
    presenter.guard("test", presenter.play)()
    follower_b, _ = workers.connect("b")
    poll_until(lambda: follower_b.mode == "following" and b.lectern.hall is Hall.LIVE, timeout=10.0)
    presenter.guard("test", presenter.pause)()
    follower_b.guard("test", follower_b.explore)()
    assert follower_b.mode == "own", follower_b.last_error
    from test_codec import advance, assert_rooms_equal

    with presenter.room.lock:
        original = presenter.room.fork()  # the presenter's room as it was copied (A's loop goes on with its own)
    with follower_b.room.lock:
        copy = follower_b.room.fork()
    assert_rooms_equal(copy, original, "explored on B")  # state, time, traces, samples, history: bit for bit
    copy.play()
    original.play()
    t = copy.sim.t
    advance(copy, 30)
    advance(original, 30)
    assert copy.sim.t > t
    assert_rooms_equal(copy, original, "30 frames on")
    presenter.guard("test", presenter.call_back)()
    poll_until(lambda: follower_b.mode == "following" and follower_b.scene is not None, timeout=20.0)


# ---------------------------------------------------------------------- malformed messages (app.cluster.messages)
def test_the_hall_names_on_the_bus_are_the_halls() -> None:
    from typing import get_args

    from app.cluster.messages import HallName

    assert set(get_args(HallName)) == {hall.value for hall in Hall}


def _remote_seen(show: Any) -> tuple[Any, ...]:
    return (show.worker, show.hall, show.title, show.status, show.caption, show.plot)


def test_a_malformed_message_on_the_bus_is_dropped_and_changes_nothing(workers: Workers,
                                                                       caplog: pytest.LogCaptureFixture) -> None:
    """The test plays a source (worker "s", its messages put on the channel by hand) that B
    follows.  Garbage, JSON and wrong-typed messages in its name (a hall "stopped" with a number
    for a title, a hall whose followers' status is not one, a camera at NaN, a scene numbered
    "x", a plot with a script, an unknown kind) and on the requests' channel change nothing on B:
    its remote show and camera stay; the valid message after them is applied; B's browser goes
    on following and a newcomer follows.  Each one dropped is said in B's log."""
    import logging

    import redis

    from app.cluster.messages import Camera, HallState, Message, SceneBatch, encode
    from app.lecture.bus import ASK, CHANNEL

    b = workers.start("b")
    follower, _ = workers.connect("b")
    client = redis.Redis.from_url(workers.url)

    def say(message: Message) -> None:
        client.publish(CHANNEL, encode(message))

    from app.lecture.follower import FollowerStatus

    status = FollowerStatus(hall=Hall.LIVE, title="Free body", lesson="marked")
    hall = HallState(worker="s", hall="live", title="Free body", status=status.to_dict(), caption=("Head", "words"))

    def heard() -> bool:  # also the source's heartbeat: B's lease on it does not lapse meanwhile
        say(hall)
        remote = b.lectern.remote
        return remote is not None and remote.status == status and remote.camera is not None

    say(SceneBatch(worker="s", seq=1, full="*", messages=[], buffers=[], shapes=[], title="Free body"))
    say(Camera(worker="s", position=(3.0, 3.0, 3.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0), fov=0.8,
               aspect=1.5))
    _poll(heard, lambda: f"B following the test's source; its remote show: {b.lectern.remote}")
    _poll(lambda: follower.mode == "following", lambda: f"B's browser following; its mode: {follower.mode}")
    remote = b.lectern.remote
    before, camera = _remote_seen(remote), dict(remote.camera)
    pack = msgspec.msgpack.encode
    caplog.set_level(logging.WARNING, logger="app.lecture.bus")
    garbage = (b"\xc1", b"not msgpack", b'{"k": "hall", "w": "s", "hall": "stopped"}',
                 pack({"k": "hall", "w": "s", "hall": "stopped", "title": 5, "status": ["evil"], "line": "x"}),
                 pack({"k": "hall", "w": "s", "hall": "sideways", "title": "Evil"}),
                 pack({"k": "camera", "w": "s", "position": [float("nan"), 0.0, 0.0], "look_at": [0.0, 0.0, 0.0],
                       "up": [0.0, 0.0, 1.0], "fov": 0.8, "aspect": 1.5}),
                 pack({"k": "scene", "w": "s", "s": "x", "m": [], "b": [], "sh": []}),
                 pack({"k": "plot", "w": "s", "tab": "Plots", "el": [["script", "alert(1)"]]}),
                 pack({"k": "keep", "w": "s", "lid": "", "room": "not bytes", "st": 1.0}),
                 pack({"k": "evil", "w": "s"}), pack({"k": "call_back"}), pack([1, 2, 3]), pack("hall"))
    asks = (b"\xc1", pack({"k": "explore", "w": "x", "r": 5}), pack({"k": "resync"}))
    for data in garbage:
        client.publish(CHANNEL, data)
    for data in asks:
        client.publish(ASK, data)
    wrong_status = pack({"k": "hall", "w": "s", "hall": "stopped", "title": "Evil",  # a hall, not a status in it
                         "status": {"hall": "left", "title": 5}})
    client.publish(CHANNEL, wrong_status)
    say(Camera(worker="s", position=(4.0, 4.0, 4.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0), fov=0.8,
               aspect=1.5))
    _poll(lambda: remote.camera is not None and remote.camera["position"] == [4.0, 4.0, 4.0],
          lambda: f"the valid camera after the garbage applied on B; its camera: {remote.camera}")
    assert b.lectern.remote is remote and _remote_seen(remote) == before, (_remote_seen(remote), before)
    assert {key: value for key, value in remote.camera.items() if key != "position"} == \
        {key: value for key, value in camera.items() if key != "position"}
    assert b.lectern.hall is Hall.LIVE and follower.mode == "following"
    dropped = [r.getMessage() for r in caplog.records if "malformed message" in r.getMessage()]
    assert len(dropped) == len(garbage) + len(asks), dropped
    refused = [r.getMessage() for r in caplog.records if "a message from s dropped" in r.getMessage()]
    assert len(refused) == 1 and "title" in refused[0], refused  # the status's check said what it refused
    newcomer, _ = workers.connect("b")
    _poll(lambda: heard() and newcomer.mode == "following", lambda: f"a newcomer on B following: {newcomer.mode}")


def test_malformed_values_under_the_keys_are_dropped(workers: Workers) -> None:
    """Garbage and wrong-typed entries in the audience hash, the last room's key and the
    questions' keys are dropped: A's badge still counts B's follower, a question asked on A
    still reaches B and B's answer is still counted on A."""
    import redis

    from app.cluster.askbus import ANSWERS_KEY, EARLIER_KEY, ROUND_KEY
    from app.lecture.bus import AUDIENCE_KEY, LAST_KEY

    a, b = workers.start("a"), workers.start("b")
    client = redis.Redis.from_url(workers.url)
    pack = msgspec.msgpack.encode
    client.hset(AUDIENCE_KEY, "z1", b"\xc1")  # before B's entry: read first
    client.hset(AUDIENCE_KEY, "z2", pack([1, "x", time.time(), []]))
    client.hset(AUDIENCE_KEY, "z3", pack([5, 0, time.time(), [["not a screen"]]]))
    client.set(LAST_KEY, b"\xc1")
    client.set(ROUND_KEY, pack({"w": "z", "id": "r", "q": {"kind": "choice"}, "n": "one", "open": True}))
    client.rpush(EARLIER_KEY, b"\xc1", pack([1, 2]))
    presenter = _present(workers, "a")
    student, _ = workers.connect("b")
    _poll(lambda: student.mode == "following", lambda: f"B's browser following: {student.mode}")
    _poll(lambda: a.lectern.remote_audience() == (1, 0),
          lambda: f"A's badge counting B's follower and nothing else: {a.lectern.remote_audience()}")
    presenter.guard("test", presenter.ask)({"kind": "choice", "prompt": "Which axis?", "options": ["1", "2", "3"]})
    _poll(lambda: student.question.folder.visible, lambda: "the question shown on B")
    round_id = a.lectern.rounds.current_id
    client.rpush(ANSWERS_KEY + round_id, b"\xc1", pack(["token"]), pack([5, 1]), pack({"token": "t", "value": 1}))
    student.answer(2)
    _poll(lambda: a.lectern.rounds.tally().answered == 1,
          lambda: f"B's answer counted on A: {a.lectern.rounds.tally()}")
    assert a.lectern.rounds.tally().counts == (0, 0, 1)
    assert b.ask_bus._fetch_earlier() == []  # the two malformed entries dropped
    assert presenter.error_count == 0 and student.error_count == 0, (presenter.last_error, student.last_error)
