"""The frame budget: what one playing browser receives per frame, counted (never timed).

For every scene of the dropdown, its default preset playing, in its own room and as a follower
of a presenter, the app's loop NOT running: the test runs the loop's frame (`App.frame`: the
frames go out through `app.wire` as in the running app) one at a time and, after each
tick, waits until everything that tick sent has reached a decoding websocket client
(`benchmarks.ws_client.ViserClient`), so that one tick is one frame, whatever the machine's
speed.  How it waits (`_sync`): the server's window generators of that client (its own buffer
and the broadcast buffer) have taken every message queued so far, then a sync marker is queued
on the client's own buffer; it travels in a window of its own, behind the tick's windows on the
same connection, and the client counts it nowhere.

Asserted per scene and per way of watching (each measured once, `_measured`):
- mean scene messages per frame (created, moved, updated, shown, hidden or removed scene nodes,
  `benchmarks.ws_client.message_category`) <= that scene's limit in BUDGETS;
- mean wire bytes per frame <= that scene's byte budget at 60 frames a second: 15 kB/s (250 B a
  frame), and 25 kB/s (≈ 417 B a frame) for Moving frame, which keeps its picture (its springs,
  forces and paths: the project's decision on lean frames).

Each failure message gives the measured figures (run with -s to see them all).  The budget benchmark,
timed and in a subprocess, is benchmarks/frame_budget.py.
"""

from __future__ import annotations

import collections
import dataclasses
import functools
from typing import Any

import pytest
from conftest import LectureHall, RawClient, poll_until, scenes_without_an_entry

from app.scenes import SCENES
from benchmarks.ws_client import ViserClient, sync_marker_message

DT = 1.0 / 60.0  # [s] one frame of the app's loop
FRAMES_PER_SECOND = 60.0
BUDGET_BYTES_PER_SECOND = 15_000.0  # [B/s] what one playing browser may receive (a scene's default)
WARMUP_FRAMES = 12  # ticked and synced as the counted ones, not counted: the scene's first frames after
# Play, a follower's replay, and the one catch-up frame (app.wire) that brings a browser the values of
# frames it was not ready for (Play's own panel messages go through viser, and a frame waits for them)
MEASURED_FRAMES = 240  # four seconds of frames (the panel's 1-2 Hz refreshes come in 4-8 times)
SYNC_TIMEOUT = 10.0  # [s] for one frame to reach the client (a loaded 2-core machine)
CODE = "271828"  # presenter code of the lecture-hall runs


@dataclasses.dataclass(frozen=True)
class Budget:
    """One scene's limits: mean scene messages per frame in its own room and as a follower
    (None: the scene has no Play, it is skipped), and the wire bytes a second [B/s] one playing
    browser may receive."""

    scene_messages_own: float | None
    scene_messages_follower: float | None
    bytes_per_second: float = BUDGET_BYTES_PER_SECOND

    @property
    def bytes_per_frame(self) -> float:
        return self.bytes_per_second / FRAMES_PER_SECOND


# The measured figures of every scene are in docs/performance.md ("App performance").
BUDGETS: dict[str, Budget] = {
    "Euler angles": Budget(5.5, 5.5),
    "Inertia": Budget(None, None),  # edited, never played: no Play button
    "Free body": Budget(4.0, 4.0),
    "Heavy top": Budget(3.0, 3.0),
    "Poinsot": Budget(4.5, 4.5),  # 3.8 -> 4.0 when its labels began to keep off the book (bytes unchanged)
    "Moving frame": Budget(9.0, 9.0, bytes_per_second=25_000.0),  # it keeps its picture
    "Constrained particles": Budget(4.5, 4.5),
}
HOW = ("own", "follower")  # the browser plays in its own room / follows a presenter who plays


@dataclasses.dataclass(frozen=True)
class FrameCount:
    """What the client received over `frames` ticks: wire bytes, scene and GUI messages,
    websocket frames (windows)."""

    frames: int
    bytes: int
    scene_messages: int
    gui_messages: int
    windows: int

    @property
    def bytes_per_frame(self) -> float:
        return self.bytes / self.frames

    @property
    def scene_messages_per_frame(self) -> float:
        return self.scene_messages / self.frames

    def describe(self, scene: str, how: str, kinds: dict[str, int]) -> str:
        busiest = ", ".join(f"{kind} {n / self.frames:.1f}" for kind, n in
                            sorted(kinds.items(), key=lambda item: -item[1])[:6])
        return (f"{scene} ({how}), {self.frames} frames: {self.bytes_per_frame:.0f} B/frame "
                f"(budget {BUDGETS[scene].bytes_per_frame:.0f}; "
                f"{self.bytes_per_frame * FRAMES_PER_SECOND / 1e3:.1f} kB/s "
                f"at 60 fps), {self.scene_messages_per_frame:.2f} scene msgs/frame, "
                f"{self.gui_messages / self.frames:.2f} GUI msgs/frame, {self.windows / self.frames:.2f} "
                f"windows/frame; messages per frame by type: {busiest}")


class Synced:
    """A decoding client of `app` and the way to wait until a tick's messages have reached it."""

    def __init__(self, app: Any, client: ViserClient, client_id: int) -> None:
        self.app, self.client, self.client_id = app, client, client_id
        self._markers = 0

    def _buffers(self) -> list[Any]:
        websock = self.app.server._websock_server  # viser internals: the broadcast buffer ...
        own = self.app.server.get_clients()[self.client_id]._websock_connection.get_message_buffer()
        return [own, websock.get_message_buffer()]  # ... and this client's own

    def sync(self) -> None:
        """Return once everything queued so far for this client has been ingested by it."""
        poll_until(self.app.frames_sent, SYNC_TIMEOUT, 0.001)  # app.wire: written to the socket
        buffers = self._buffers()
        targets = [buffer.message_counter - 1 for buffer in buffers]
        poll_until(lambda: all(buffer.generator_cursors.get(self.client_id, -1) >= target
                               for buffer, target in zip(buffers, targets)), SYNC_TIMEOUT, 0.001)
        # Every message queued so far is in a window handed to the socket: a marker queued now
        # leaves in a window of its own, after them, on the same connection.
        self._markers += 1
        number = self._markers
        connection = self.app.server.get_clients()[self.client_id]._websock_connection
        connection.queue_message(sync_marker_message(number))
        buffers[0].flush()  # no windowing delay for the marker
        state = self.client.state
        state.wait_for(lambda: state.marker >= number, SYNC_TIMEOUT)

    def snapshot(self) -> tuple[int, int, int, int, dict[str, int]]:
        state = self.client.state
        with state.lock:
            return (state.bytes_received, state.category_counts["scene"], state.category_counts["gui"],
                    state.frames, dict(state.message_counts))


def _count(synced: Synced, tick: Any, frames: int) -> tuple[FrameCount, dict[str, int]]:
    """Tick `frames` frames, one at a time, each synced; what the client received."""
    synced.sync()
    bytes0, scene0, gui0, windows0, kinds0 = synced.snapshot()
    for _ in range(frames):
        tick()
        synced.sync()
    bytes1, scene1, gui1, windows1, kinds1 = synced.snapshot()
    kinds = {kind: n - kinds0.get(kind, 0) for kind, n in kinds1.items() if n > kinds0.get(kind, 0)}
    return FrameCount(frames, bytes1 - bytes0, scene1 - scene0, gui1 - gui0, windows1 - windows0), kinds


def _own_room(scene: str) -> tuple[FrameCount, dict[str, int]]:
    from app.main import create_server

    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    client = None
    try:
        client = ViserClient(app.port, keep_messages=100)
        ((client_id, session),) = app.wait_for_sessions(1).items()
        synced = Synced(app, client, client_id)
        session.select_scene(scene)  # a new room at the scene's first preset
        session.play()
        assert session.room.playing and session.last_error is None, session.last_error
        _count(synced, lambda: app.frame(DT), WARMUP_FRAMES)
        return _count(synced, lambda: app.frame(DT), MEASURED_FRAMES)
    finally:
        if client is not None:
            client.close()
        app.stop()


def _follower(scene: str) -> tuple[FrameCount, dict[str, int]]:
    hall = LectureHall(CODE)
    try:
        presenter, _ = hall.join_with_client(RawClient)
        presenter.select_scene(scene)
        presenter.present(CODE)
        presenter.play()
        assert presenter.mode == "presenting" and presenter.room.playing, presenter.last_error
        before = set(hall.app.sessions)
        follower, client = hall.join_with_client(lambda port: ViserClient(port, keep_messages=100))
        (client_id,) = set(hall.app.sessions) - before
        hall.app.frame(DT)
        assert follower.mode == "following" and follower.room is presenter.room
        client.state.wait_for(lambda: client.state.replay_done, SYNC_TIMEOUT)
        synced = Synced(hall.app, client, client_id)
        _count(synced, lambda: hall.app.frame(DT), WARMUP_FRAMES)
        return _count(synced, lambda: hall.app.frame(DT), MEASURED_FRAMES)
    finally:
        # The follower leaves first, so the presenter's panel ("N following") is not written
        # after the presenter's connection closed.
        for staying, leaving in reversed(list(enumerate(hall.clients))):
            leaving.close()
            poll_until(lambda staying=staying: len(hall.app.sessions) <= staying, SYNC_TIMEOUT)
        hall.clients.clear()
        hall.close()


@functools.cache
def _measured(scene: str, how: str) -> tuple[FrameCount, str]:
    """(the count, its description) for `scene` watched `how`; measured once per test run."""
    count, kinds = _own_room(scene) if how == "own" else _follower(scene)
    return count, count.describe(scene, how, kinds)


def _limit(scene: str, how: str) -> float:
    budget = BUDGETS[scene]
    limit = budget.scene_messages_own if how == "own" else budget.scene_messages_follower
    if limit is None:
        pytest.skip(f"{scene} does not play")
    return limit


def _cases() -> list[Any]:
    return [pytest.param(scene, how, id=f"{scene}-{how}") for scene in SCENES for how in HOW]


def test_the_counting_client_sorts_what_a_plain_server_sent_and_skips_its_markers() -> None:
    """Independent of the app: what a bare viser server queued for one client (recorded on the
    server side, sorted by the message classes) is what the client counted after the sync, in
    one window, and the marker's frame is in no count."""
    import viser
    from viser import _messages

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    client = None
    try:
        client = ViserClient(server.get_port(), keep_messages=100)
        (client_id,) = poll_until(server.get_clients)  # registered after its camera message
        bare = type("Bare", (), {"server": server, "frames_sent": staticmethod(lambda: True)})()  # no wires
        synced = Synced(bare, client, client_id)
        synced.sync()  # the first panel, the replay
        bytes0, scene0, gui0, windows0, kinds0 = synced.snapshot()
        handle = server.get_clients()[client_id]
        connection = handle._websock_connection
        queued: list[Any] = []
        send = connection.queue_message
        connection.queue_message = lambda message: (queued.append(message), send(message))[1]
        with handle.atomic():
            frame = handle.scene.add_frame("/probe", show_axes=False)
            frame.wxyz = (0.0, 1.0, 0.0, 0.0)
            frame.position = (1.0, 2.0, 3.0)
            handle.gui.add_markdown("probe")
        connection.queue_message = send
        synced.sync()
        bytes1, scene1, gui1, windows1, kinds1 = synced.snapshot()
        node_updates = (_messages._CreateSceneNodeMessage, _messages.SetOrientationMessage,
                        _messages.SetPositionMessage, _messages.SetSceneNodeVisibilityMessage)
        scene_sent = sum(isinstance(m, node_updates) for m in queued)
        assert scene_sent >= 3 and len(queued) - scene_sent >= 1  # the node, its pose; the markdown
        assert (scene1 - scene0, gui1 - gui0, windows1 - windows0) == (scene_sent, len(queued) - scene_sent, 1)
        assert {k: n - kinds0.get(k, 0) for k, n in kinds1.items() if n != kinds0.get(k, 0)} == \
            collections.Counter(type(m).__name__ for m in queued)
        assert bytes1 - bytes0 > 16  # one frame: its 16-byte header and more
        assert client.state.marker == 2 and not client.state.errors
        assert client.state.message_counts["RunJavascriptMessage"] == 0  # markers are counted nowhere
    finally:
        if client is not None:
            client.close()
        server.stop()


def test_every_scene_has_a_budget() -> None:
    problems = scenes_without_an_entry(BUDGETS, "BUDGETS of tests/test_frame_budget.py (its scene messages per frame)")
    assert not problems, problems


@pytest.mark.parametrize(("scene", "how"), _cases())
def test_a_playing_scene_sends_at_most_its_scene_messages_per_frame(scene: str, how: str) -> None:
    limit = _limit(scene, how)
    count, figures = _measured(scene, how)
    print(figures)
    assert count.scene_messages > 0, f"nothing moved: {figures}"  # it really played
    assert count.scene_messages_per_frame <= limit, f"more than {limit:g} scene msgs/frame: {figures}"


@pytest.mark.parametrize(("scene", "how"), _cases())
def test_a_playing_scene_stays_within_the_byte_budget(scene: str, how: str) -> None:
    _limit(scene, how)
    budget = BUDGETS[scene].bytes_per_frame
    count, figures = _measured(scene, how)
    assert count.bytes_per_frame <= budget, f"over the byte budget of {budget:.0f} B/frame: {figures}"


def test_the_frame_budget_benchmark_runs_and_counts() -> None:
    """benchmarks/frame_budget.py on one scene, briefly: the app in a subprocess, a browser in
    its own room and a follower both receive drawn frames with scene messages (no figure is
    checked against a threshold: that is the counted tests' job)."""
    from benchmarks.frame_budget import Figures, format_table, measure_tree

    results = measure_tree(("Free body",), warmup=0.3, seconds=1.0)
    for how in ("own", "follower"):
        figures = results["Free body", how]
        assert isinstance(figures, Figures), figures
        assert figures.drawn_frames > 0 and figures.scene_messages >= figures.drawn_frames
        assert figures.bytes > 16 * figures.frames  # every frame has its 16-byte header and more
    assert "| Free body | " in format_table(("Free body",), [results])
