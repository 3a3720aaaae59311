"""What a browser held ends with it: a full pass of the garbage collector soon after browsers leave.

A session is a web of cycles (its GUI handles' callbacks hold the session, which holds the
handles), and so are viser's tasks for its connection (the coroutines, the exception that
closed the socket and its traceback, the compressors of its frames).  When the browser leaves,
nothing reaches them any more, but only a full pass of the collector frees them: each one
~2,000 objects and ~0.3 MiB.  Served, the collector is tuned so that full passes are rare
(`app.main.tune_collector`, for smooth frames), so departed sessions piled up between passes
and the memory they left behind came back fragmented: measured with browsers joining and
leaving every 3 s (benchmarks/soak.py), the server's RSS rose in steps of 11-23 MiB to
+98 MiB in 25 minutes, and 500 joins and leaves as fast as they come left 50 sessions of 50
waiting in cyclic garbage whatever the time.

`Sweep` gives departures their own full pass: the app calls `left()` when a browser leaves
and `run_if_due()` once a frame (from its loop, between frames); a pass runs when a browser
left since the last one and at least `max(min_interval_s, cost_factor x the last pass's
duration)` has gone by since it, so the collector takes at most 1/cost_factor of the time
(a pass over 20 rooms takes some 20 ms on the 2-core machine, one over 80 rooms ~0.3 s).

A departed object handed to `left` is watched (a weak reference): one still alive after a pass
(a thread of its own was still ending, holding it, while the pass ran) stays owed, and the next
pass comes when allowed, at most RETRIES times for it: a departure is swept after its last
holder let go, not only while the pass happened to find it free.
"""

from __future__ import annotations

import gc
import threading
import time
import weakref
from collections.abc import Callable

__all__ = ["COST_FACTOR", "MIN_INTERVAL_S", "RETRIES", "Sweep"]

MIN_INTERVAL_S = 5.0  # [s] at least this long between two sweeps
COST_FACTOR = 50.0  # ... and at least this many times the last sweep's duration (<= 2 % of the time)
RETRIES = 12  # passes owed to a departed object still alive after a pass (then it is a leak, not a race)


class Sweep:
    """Full collections owed to browsers that left (see the module docstring).

    Attributes:
        passes: sweeps run so far; seconds: their total duration [s]; longest: the longest [s].
        owed: browsers that left since the last sweep, and departed objects a pass found alive
            (each up to RETRIES passes).
    """

    def __init__(self, min_interval_s: float = MIN_INTERVAL_S, cost_factor: float = COST_FACTOR,
                 clock: Callable[[], float] = time.monotonic,
                 collect: Callable[[], object] = gc.collect) -> None:
        self.min_interval_s, self.cost_factor = min_interval_s, cost_factor
        self._clock, self._collect = clock, collect
        self._lock = threading.Lock()
        self.owed = 0
        self.passes = 0
        self.seconds = 0.0
        self.longest = 0.0
        self._last_end = -float("inf")  # [clock s] when the last sweep ended
        self._last_took = 0.0  # [s] how long it took
        self._watched: list[tuple[weakref.ref[object], int]] = []  # (departed object, passes left)

    def left(self, departed: object | None = None) -> None:
        """A browser left (any thread): its session's cycles are owed a full pass; `departed`
        (its session) is watched until a pass finds it freed."""
        with self._lock:
            self.owed += 1
            if departed is not None:
                self._watched.append((weakref.ref(departed), RETRIES))

    def due(self, now: float) -> bool:
        """Whether a sweep is owed and allowed at `now` [clock s]."""
        wait = max(self.min_interval_s, self.cost_factor * self._last_took)
        return self.owed > 0 and now - self._last_end >= wait

    def run_if_due(self) -> bool:
        """Run a full collection if `due` (the app loop's thread, between frames); whether it ran."""
        start = self._clock()
        if not self.due(start):
            return False
        with self._lock:
            self.owed = 0
            watched, self._watched = self._watched, []
        self._collect()
        alive = [(ref, left - 1) for ref, left in watched if ref() is not None and left > 1]
        with self._lock:
            self._watched.extend(alive)
            self.owed += len(alive)
        end = self._clock()
        self._last_end, self._last_took = end, end - start
        self.passes += 1
        self.seconds += self._last_took
        self.longest = max(self.longest, self._last_took)
        return True
