"""`app.backpressure.FramePacer` with stand-in clients and a fake clock: a client whose last frame
is still queued is skipped, the loop sleeps to the frame boundary and at least `idle_ratio` of
its work, waits for the sender to take the drawn frames (up to `max_wait`), and without viser's
internals falls back to pacing by time alone."""

from __future__ import annotations

import contextlib
import threading
import time
import types
from collections.abc import Iterator

from app.backpressure import FramePacer, internals_available, pending


class _Buffer:
    def __init__(self) -> None:
        self.message_from_id: dict[int, str] = {}
        self.done = False
        self.flush_event = None
        self.event_loop = None


class _Client:
    """What FramePacer reads of a viser ClientHandle: its message buffer, flush and atomic."""

    def __init__(self, client_id: int) -> None:
        self.client_id = client_id
        self.buffer = _Buffer()
        self._websock_connection = types.SimpleNamespace(
            _state=types.SimpleNamespace(message_buffer=self.buffer),
            get_message_buffer=lambda: self.buffer)
        self.flushed = 0
        self.atomics = 0

    def flush(self) -> None:
        self.flushed += 1

    @contextlib.contextmanager
    def atomic(self) -> Iterator[None]:
        self.atomics += 1
        yield


class _Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t

    def sleep(self, seconds: float) -> None:
        self.t += max(seconds, 1e-4)


def test_a_client_whose_last_frame_is_queued_is_skipped_and_the_loop_sleeps_to_the_period() -> None:
    clock, a, b = _Clock(), _Client(0), _Client(1)
    pacer = FramePacer(60.0, clock=clock, sleep=clock.sleep, max_unsent_bytes=None)
    assert internals_available(a) and pending(a) == 0
    b.buffer.message_from_id[1] = "the last frame, not yet sent"
    pacer.begin()
    with pacer.hold([a, b]):
        drawn = [c for c in (a, b) if pacer.ready(c)]  # type: ignore[arg-type]
    assert drawn == [a] and pacer.stats.skipped == 1 and a.atomics == 1
    clock.t += 0.002  # 2 ms of drawing
    pacer.end(drawn)  # type: ignore[arg-type]
    assert abs(clock.t - 1 / 60) < 1e-3  # slept to the frame boundary
    assert a.flushed == 1


def test_the_loop_waits_for_the_sender_then_gives_up_at_max_wait() -> None:
    clock, a = _Clock(), _Client(0)
    pacer = FramePacer(60.0, clock=clock, sleep=clock.sleep, max_wait=0.1, max_unsent_bytes=None)
    pacer.begin()
    clock.t += 0.01
    a.buffer.message_from_id[1] = "drawn, never taken by the sender"
    pacer.end([a])  # type: ignore[list-item]
    assert abs(clock.t - 0.1) < 2e-3 and pacer.stats.drain_timeouts == 1


def test_the_loop_leaves_the_sender_a_share_of_the_time_under_overload() -> None:
    clock, a = _Clock(), _Client(0)
    pacer = FramePacer(60.0, clock=clock, sleep=clock.sleep, idle_ratio=0.5, max_unsent_bytes=None)
    pacer.begin()
    clock.t += 0.04  # 40 ms of work: longer than a frame
    pacer.end([a])  # type: ignore[list-item]
    assert abs(clock.t - 0.06) < 1e-3  # and then 20 ms asleep (GIL released)


def test_a_wake_ends_the_wait_for_the_boundary_but_not_before_half_a_period() -> None:
    clock, a, wake = _Clock(), _Client(0), threading.Event()
    pacer = FramePacer(60.0, clock=clock, sleep=clock.sleep, wake=wake, max_unsent_bytes=None)
    pacer.begin()
    clock.t += 0.002
    wake.set()  # a presenter's frame came from another process while this one drew
    pacer.end([a])  # type: ignore[list-item]
    assert abs(clock.t - 0.5 / 60) < 1e-3  # half a period from the start, not the whole
    pacer.begin()
    assert not wake.is_set()  # the next frame takes it in


def test_a_wake_during_the_wait_starts_the_next_frame_then() -> None:
    """Real time, a slow rate (0.2 Hz: a boundary 5 s after the start): woken at 0.3 s, the wait
    ends after the wake and long before the boundary (a busy machine may wake the timer late,
    never 4 s late)."""
    wake = threading.Event()
    pacer = FramePacer(0.2, wake=wake, max_unsent_bytes=None)
    woken_at: list[float] = []

    def set_wake() -> None:
        woken_at.append(time.perf_counter())
        wake.set()

    start = time.perf_counter()
    pacer.begin()
    timer = threading.Timer(0.3, set_wake)
    timer.start()
    pacer.end([])
    ended = time.perf_counter()
    timer.join()
    assert woken_at and woken_at[0] <= ended, (woken_at, ended)
    assert ended - start < 4.0, ended - start


def test_without_visers_internals_pending_is_zero_and_pacing_is_by_time() -> None:
    stranger = types.SimpleNamespace(client_id=3)
    assert pending(stranger) == 0 and not internals_available(stranger)  # type: ignore[arg-type]
