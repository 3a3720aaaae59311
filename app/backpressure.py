"""Backpressure for per-client scene streaming with viser 1.1: skip, don't queue.

How viser 1.1 sends a per-client node update:

1. ``handle.wxyz = q`` (``.position``, ``.points``, any prop) runs in the caller's thread (our
   app loop).  It builds one message (``SetOrientationMessage``, ``SetPositionMessage``,
   ``SceneNodeUpdateMessage({"points": ...})``), stamps its owner and pushes it into **that
   client's own send buffer**.  ``wxyz``/``position`` setters first run ``np.allclose`` against
   the cached value and queue nothing if unchanged.
2. The push (under the buffer's lock) stores the message under a new id and **culls** the
   buffered message with the same redundancy key (one pending orientation per node, one
   pending ``points`` per node...).  So a backlog never grows past "latest state of every
   node"; a client that is behind loses intermediate frames, never receives them late in a
   burst of its own.  Outside ``atomic()`` every push also wakes the sender (a self-pipe
   write: a syscall that releases the GIL).
3. ``client.atomic()`` holds the client's buffer: the sender takes nothing from it until the
   outermost block ends, which wakes the sender once; so it groups one client's messages into
   one window.
4. The sender is viser's single asyncio thread.  For every connection it takes windows of up to
   128 messages in id order from the client's buffer and from the broadcast buffer, serialises
   each (msgpack, zstd, raw numpy buffers) into **one websocket message** and sends it.  After a
   window it waits one window period (1/60 s) unless the buffer is flushed
   (``client.flush()``), so without a flush a frame can sit in the buffer that long.
5. The send writes into the asyncio transport; when the transport holds more than websockets'
   write limit it awaits drain.  A client that stops reading therefore parks its own sender;
   its buffer keeps only the latest state of each node (culling), and other clients are
   unaffected.

The failure mode this module addresses: all of that Python runs on the asyncio thread and needs
the GIL, and the app loop's own node assignments (``np.allclose``, message construction, the
push) need it too.  An app loop that ticks N clients back to back at 60 Hz stops sleeping once
N is large; from then on the sender only gets the GIL in slices, and the delivered rate does
not degrade but collapses (docs/VISER.md, "How a frame leaves"; benchmarks/overload_probe.py).
The likely mechanism is the GIL "convoy": each syscall the sender makes (socket send, epoll)
hands the GIL to the CPU-bound loop thread and costs the sender up to the switch interval to
get it back.

The remedy, as helpers the app loop can use (nothing here knows the app's classes):

- `pending(client)`: messages queued for that client that the sender has not yet taken
  (a dict's length).  Non-zero at the start of a frame means "your last frame has not
  left yet": skip drawing that client this frame (drop the frame, don't queue it).
- `FramePacer`: per-frame policy.  ``begin()`` / ``ready(client)`` / ``hold(clients)`` /
  ``end(drawn)``.  ``end`` wakes the sender for all drawn clients at once, then sleeps (GIL
  released) until their frames have been taken by the sender, at least ``idle_ratio`` times the
  time the loop worked, and at least until the next 1/rate boundary.  Under overload the
  whole loop slows down: every client loses the same frames and the sender always runs.

What viser keeps private (the send buffers, the transports) is read through
`app.viser_internals` (its SEND_QUEUE).  When that is off `pending` returns 0 and
`internals_available()` is False: the pacer then still enforces the idle share and the 60 Hz
period (time-based pacing only), and `flush_all` falls back to ``client.flush()``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

from app.viser_internals import connection_closed, pending_messages
from app.viser_internals import flush_all as _flush_all
from app.viser_internals import unsent_bytes as _unsent_bytes

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


def internals_available(client: ClientHandle) -> bool:
    """True if `pending` can see this client's queue (`app.viser_internals.SEND_QUEUE`)."""
    return pending_messages(client) is not None


def pending(client: ClientHandle) -> int:
    """Messages queued for `client` that viser's sender has not yet taken into a window.

    0 means everything queued so far has been handed to serialisation/the socket (it may still
    sit in the socket's buffers).  Returns 0 if the queue is not found (see
    `internals_available`), so callers degrade to time-based pacing, never to "skip all".
    """
    return pending_messages(client) or 0


def is_closed(client: ClientHandle) -> bool:
    """True if the client's connection is gone (its buffer is done): draw nothing for it."""
    return connection_closed(client)


def unsent_bytes(client: ClientHandle) -> int:
    """Bytes written to the client's socket transport and not yet accepted by the kernel
    (``transport.get_write_buffer_size()``); 0 if unknown.  A client that stopped reading shows
    up here (then in `pending`, once websockets' write limit parks the sender)."""
    return _unsent_bytes(client)


def flush_all(clients: Iterable[ClientHandle]) -> None:
    """Wake viser's sender for all `clients` now, skipping its window delay: one call on its
    event loop for the whole list, else ``client.flush()`` per client."""
    _flush_all(clients)


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
        wake: set by a source of work the loop should take at once (the cluster bus: a
            presenter's frame from another process): the wait for the next 1/rate boundary then
            ends, though not before half a period from the frame's start (so the loop runs in
            step with that source, never above twice the rate); `begin` clears it.  The wait
            then sleeps in `wake.wait` (set it also to stop).
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
        wake: threading.Event | None = None,
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
        self._wake = wake
        self._frame_start: float | None = None
        self.stats = PacerStats()

    # ------------------------------------------------------------------ frame
    def begin(self) -> float:
        """Start a frame; returns the wall time since the previous frame started [s] (0 first)."""
        now = self._clock()
        dt = 0.0 if self._frame_start is None else now - self._frame_start
        self._frame_start = now
        self.stats.frames += 1
        if self._wake is not None:
            self._wake.clear()
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
        early = max(now + self.idle_ratio * work, start + 0.5 * self.period)  # when woken (`wake`)
        wake = self._wake
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
            if not (waiting or other) and (now >= earliest or (
                    wake is not None and wake.is_set() and now >= early)):
                break
            if now >= give_up:
                self.stats.drain_timeouts += 1
                break
            if waiting or other:  # poll: the sender runs while we sleep (GIL released)
                self._sleep(max(min(self.poll, give_up - now), 0.0))
            elif wake is not None and not wake.is_set():
                wake.wait(earliest - now)  # until the boundary, or woken
            else:
                self._sleep((early if wake is not None else earliest) - now)
        slept = clock() - slept_from
        self.stats.wait_s += slept
        return slept

    def reset_stats(self) -> PacerStats:
        """Return the counters so far and start new ones."""
        old, self.stats = self.stats, PacerStats()
        return old
