"""Backpressure for per-client scene streaming with viser 1.1: skip, don't queue.

How viser 1.1.1 sends a per-client node update (read from the installed source):

1. ``handle.wxyz = q`` (``.position``, ``.points``, any prop) runs in the caller's thread (our
   app loop).  It builds one message (``SetOrientationMessage``, ``SetPositionMessage``,
   ``SceneNodeUpdateMessage({"points": ...})``), stamps its owner and calls
   ``WebsockClientConnection.queue_message`` -> ``AsyncMessageBuffer.push`` on **that client's
   own buffer** (``client._websock_connection._state.message_buffer``).  ``wxyz``/``position``
   setters first run ``np.allclose`` against the cached value and queue nothing if unchanged.
2. ``push`` (under the buffer's ``threading.Lock``) stores the message under a new integer id in
   ``message_from_id`` and **culls** the buffered message with the same redundancy key
   (``scene:<name>:update:<prop>`` style keys: one pending orientation per node, one pending
   ``points`` per node...).  So a backlog never grows past "latest state of every node"; a
   client that is behind loses intermediate frames, never receives them late in a burst of its
   own.  Outside ``atomic()`` every push also wakes the sender with
   ``loop.call_soon_threadsafe`` (a self-pipe write: a syscall that releases the GIL).
3. ``client.atomic()`` increments the buffer's ``atomic_counter``; the sender does not take
   messages from a buffer whose counter is non-zero, and leaving the outermost block wakes the
   sender once.  It is per buffer, so it groups one client's messages into one window; it
   nests (only the outermost exit wakes).
4. The sender is viser's single asyncio thread (started by ``ViserServer()``).  For every
   connection it runs two ``_message_producer`` tasks (per-client buffer and broadcast buffer).
   Each iterates ``AsyncMessageBuffer._window_loop``: it takes up to ``max_window_size`` (128)
   messages in id order, **popping them from ``message_from_id``** (per-client buffers are not
   persistent), serialises them (``as_serializable_dict``, msgpack, zstd level 1, a 16-byte
   header plus raw numpy buffers) into **one websocket message** and ``await ws.send()``.  After
   a window, if nothing newer is queued it waits ``window_duration_sec`` (1/60 s) unless the
   buffer's ``flush_event`` is set (``client.flush()``); with nothing queued it waits on
   ``message_event`` then again up to 1/60 s.  So without a flush, a frame can sit in the buffer
   for up to one window period after it was queued.
5. ``ws.send`` writes into the asyncio transport; when the transport holds more than the
   websockets write limit (32 KiB) it awaits drain.  A client that stops reading therefore
   parks its own producer at ``send``; its buffer keeps only the latest state of each node
   (culling), and other clients are unaffected.

The failure mode this module addresses: all of that Python (roughly 0.1-0.5 ms per client frame
in viser) runs on the asyncio thread and needs the GIL, and the app loop's own node assignments
(about 25 us per property: ``np.allclose``, message construction, ``push``) need it too.  An app
loop that ticks N clients back to back at 60 Hz stops sleeping once N is large; from then on
the sender only gets the GIL in slices, and (measured with benchmarks/overload_probe.py) the
delivered rate does not degrade but collapses, bimodally: 60 clients got 35 or 16 fps in two
identical runs, 80 clients 6-14 fps with multi-second gaps.  The likely mechanism is the GIL
"convoy": each syscall the sender makes (socket send, epoll) hands the GIL to the CPU-bound loop
thread and costs the sender up to the 5 ms switch interval to get it back.

The remedy, as helpers the app loop can use (nothing here knows the app's classes):

- `pending(client)`: messages queued for that client that the sender has not yet taken
  (a few hundred ns).  Non-zero at the start of a frame means "your last frame has not
  left yet": skip drawing that client this frame (drop the frame, don't queue it).
- `FramePacer`: per-frame policy.  ``begin()`` / ``ready(client)`` / ``hold(clients)`` /
  ``end(drawn)``.  ``end`` wakes the sender for all drawn clients at once, then sleeps (GIL
  released) until their frames have been taken by the sender, at least ``idle_ratio`` times the
  time the loop worked, and at least until the next 1/rate boundary.  Under overload the
  whole loop slows down: every client loses the same frames and the sender always runs.

Internals used (viser 1.1.1), each behind a fallback:
``ClientHandle._websock_connection.get_message_buffer()`` -> ``AsyncMessageBuffer`` with
``message_from_id``, ``done``, ``flush_event``, ``event_loop``; ``ClientHandle._viser_server.
_websock_server._live_connections[client_id].transport``.  If they change, `pending` returns
0 and `internals_available()` is False: the pacer then still enforces the idle share and the
60 Hz period (time-based pacing only), and `flush_all` falls back to ``client.flush()``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from viser import ClientHandle

__all__ = [
    "FramePacer",
    "PacerStats",
    "flush_all",
    "internals_available",
    "is_closed",
    "pending",
    "unsent_bytes",
]


def _buffer(client: Any) -> Any | None:
    """The client's ``AsyncMessageBuffer`` (viser 1.1.1 internals), or None if not found."""
    try:
        return client._websock_connection.get_message_buffer()
    except AttributeError:
        return None


def internals_available(client: ClientHandle) -> bool:
    """True if `pending` can see this client's queue (viser internals as in 1.1.1)."""
    buffer = _buffer(client)
    return buffer is not None and isinstance(getattr(buffer, "message_from_id", None), dict)


def pending(client: ClientHandle) -> int:
    """Messages queued for `client` that viser's sender has not yet taken into a window.

    0 means everything queued so far has been handed to serialisation/the socket (it may still
    sit in the socket's buffers).  Cost: a few attribute lookups and ``len`` of a dict, no lock
    (``len`` of a dict is atomic under the GIL).  Returns 0 if the internals are not found
    (see `internals_available`), so callers degrade to time-based pacing, never to "skip all".
    """
    try:
        return len(client._websock_connection._state.message_buffer.message_from_id)
    except AttributeError:
        buffer = _buffer(client)
        table = getattr(buffer, "message_from_id", None)
        return len(table) if isinstance(table, dict) else 0


def is_closed(client: ClientHandle) -> bool:
    """True if the client's connection is gone (its buffer is done): draw nothing for it."""
    buffer = _buffer(client)
    return bool(getattr(buffer, "done", False))


def unsent_bytes(client: ClientHandle) -> int:
    """Bytes written to the client's socket transport and not yet accepted by the kernel
    (``transport.get_write_buffer_size()``); 0 if unknown.  A client that stopped reading shows
    up here (then in `pending`, once websockets' 32 KiB write limit parks the sender)."""
    try:
        connection = client._viser_server._websock_server._live_connections[client.client_id]
        return int(connection.transport.get_write_buffer_size())
    except (AttributeError, KeyError, TypeError):
        return 0


def flush_all(clients: Iterable[ClientHandle]) -> None:
    """Wake viser's sender for all `clients` now, skipping its 1/60 s window delay.

    One ``call_soon_threadsafe`` for the whole list (``client.flush()`` costs one self-pipe
    write, and a GIL hand-off, per client).  Falls back to ``client.flush()`` per client.
    """
    events: list[Any] = []
    loop: Any = None
    fallback: list[Any] = []
    for client in clients:
        buffer = _buffer(client)
        event = getattr(buffer, "flush_event", None)
        buffer_loop = getattr(buffer, "event_loop", None)
        if event is None or buffer_loop is None or (loop is not None and buffer_loop is not loop):
            fallback.append(client)
            continue
        loop = buffer_loop
        events.append(event)
    if events:

        def _set_all() -> None:
            for event in events:
                event.set()

        try:
            loop.call_soon_threadsafe(_set_all)
        except RuntimeError:  # loop closed: server stopping
            pass
    for client in fallback:
        with contextlib.suppress(Exception):
            client.flush()


@dataclasses.dataclass
class PacerStats:
    """Counters since the pacer was made (or since `FramePacer.reset_stats`).

    frames: loop iterations; drawn: client frames drawn; skipped: client frames dropped because
    the client's previous frame had not left; closed: draws refused for closed connections;
    work_s / wait_s: total time between begin() and end() / spent sleeping in end();
    drain_timeouts: end() calls that gave up waiting (max_wait) with frames still queued.
    """

    frames: int = 0
    drawn: int = 0
    skipped: int = 0
    closed: int = 0
    work_s: float = 0.0
    wait_s: float = 0.0
    drain_timeouts: int = 0


class FramePacer:
    """Frame pacing for a loop that draws many clients' scenes from one thread.

    Per frame::

        dt = pacer.begin()                       # wall time since the previous frame start
        with pacer.hold(clients):                # optional: sender idle while we draw
            for client in clients:
                if pacer.ready(client):          # its previous frame has left
                    draw(client)                 # inside client.atomic() as usual
                    drawn.append(client)
        pacer.end(drawn)                         # wake sender, sleep until sent / next tick

    Args:
        rate_hz: the top frame rate (the loop never starts frames faster than this).
        idle_ratio: after working w seconds, sleep at least ``idle_ratio * w`` (GIL released)
            even if the sender reports nothing pending: the sender still serialises and writes
            the last windows it took.  0.0 disables.
        max_wait: the longest a frame (begin() to the end of end()) waits for the sender to take
            the drawn frames [s]; clients still pending then are skipped next frame.
        poll: sleep granularity while waiting for the sender [s].
        drain: wait for the drawn frames to be taken (True), or only for time (False).
        max_unsent_bytes: `ready` is False while more than this many bytes sit in the client's
            socket transport (a client that reads too slowly); None disables the check.
        flush: wake the sender for all drawn clients at the end of the frame (`flush_all`).
        clock / sleep: injectable (tests); ``sleep=stop_event.wait`` lets a stop request cut
            a wait short (while the sender is still busy the wait then spins until max_wait).
    """

    def __init__(
        self,
        rate_hz: float = 60.0,
        *,
        idle_ratio: float = 0.25,
        max_wait: float = 0.25,
        poll: float = 0.001,
        drain: bool = True,
        max_unsent_bytes: int | None = 256 * 1024,
        flush: bool = True,
        clock: Callable[[], float] = time.perf_counter,
        sleep: Callable[[float], Any] = time.sleep,
    ) -> None:
        if rate_hz <= 0:
            raise ValueError(f"rate_hz must be > 0, got {rate_hz}")
        self.period = 1.0 / rate_hz
        self.idle_ratio = max(float(idle_ratio), 0.0)
        self.max_wait = float(max_wait)
        self.poll = float(poll)
        self.drain = drain
        self.max_unsent_bytes = max_unsent_bytes
        self.flush = flush
        self._clock = clock
        self._sleep = sleep
        self._frame_start: float | None = None
        self.stats = PacerStats()

    # ------------------------------------------------------------------ frame
    def begin(self) -> float:
        """Start a frame; returns the wall time since the previous frame started [s] (0 first)."""
        now = self._clock()
        dt = 0.0 if self._frame_start is None else now - self._frame_start
        self._frame_start = now
        self.stats.frames += 1
        return dt

    def ready(self, client: ClientHandle) -> bool:
        """Draw `client` this frame?  False (counted as skipped) while its previous frame is
        still queued in viser or too many bytes wait in its socket; False for a closed one."""
        if is_closed(client):
            self.stats.closed += 1
            return False
        if pending(client) > 0 or (
            self.max_unsent_bytes is not None and unsent_bytes(client) > self.max_unsent_bytes
        ):
            self.stats.skipped += 1
            return False
        self.stats.drawn += 1
        return True

    @contextlib.contextmanager
    def hold(self, clients: Iterable[ClientHandle]) -> Iterator[None]:
        """Hold every client's buffer in ``atomic()`` while the loop draws: the sender takes
        nothing (and competes for no GIL) until the block ends, then each client's frame leaves
        as one window.  Public viser API only (``ClientHandle.atomic``); nests with the views'
        own ``with client.atomic():``."""
        with contextlib.ExitStack() as stack:
            for client in clients:
                if not is_closed(client):
                    stack.enter_context(client.atomic())
            yield

    def end(self, drawn: Sequence[ClientHandle], busy: Callable[[], bool] | None = None) -> float:
        """Finish the frame: wake the sender for `drawn`, then sleep until (a) at least
        ``idle_ratio`` x the frame's work time has passed, (b) the next 1/rate boundary, and
        (c) if ``drain``, every drawn client's frame was taken by the sender and `busy()` (frames
        written by another path, `app.wire`) is False, or ``max_wait`` since begin().  Returns
        the time slept [s]."""
        clock = self._clock
        start = self._frame_start if self._frame_start is not None else clock()
        now = clock()
        work = now - start
        self.stats.work_s += work
        if self.flush and drawn:
            flush_all(drawn)
        earliest = max(now + self.idle_ratio * work, start + self.period)
        give_up = max(start + self.max_wait, earliest)
        waiting = [c for c in drawn if pending(c) > 0] if self.drain else []
        other = self.drain and busy is not None and busy()
        slept_from = now
        while True:
            now = clock()
            if waiting:
                waiting = [c for c in waiting if pending(c) > 0 and not is_closed(c)]
            if other:
                other = busy is not None and busy()
            if not (waiting or other) and now >= earliest:
                break
            if now >= give_up:
                self.stats.drain_timeouts += 1
                break
            if waiting or other:  # poll: the sender runs while we sleep (GIL released)
                self._sleep(max(min(self.poll, give_up - now), 0.0))
            else:
                self._sleep(earliest - now)
        slept = clock() - slept_from
        self.stats.wait_s += slept
        return slept

    def reset_stats(self) -> PacerStats:
        """Return the counters so far and start new ones."""
        old, self.stats = self.stats, PacerStats()
        return old
