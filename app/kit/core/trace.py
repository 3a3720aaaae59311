"""The recent path of a moving point, kept by a simulation (no viser): `Trace`.

A trace belongs to the simulation, not to a view, so a view built later (an explorer's fork,
a late joiner, an export) draws the path so far, and a fork carries it on.  A view draws it
with `app.kit.draw.widgets.TraceLines`, which sends only the chunks that changed.

Points are stored at least `spacing` [s] of simulated time apart, in chunks of
`chunk_points` points; consecutive chunks share their end point (chunk c holds the points
c S .. c S + S, S = chunk_points - 1, counted from the last `clear`).  A complete chunk is
dropped when its newest point is older than `seconds` before the newest point, so what is
kept is a pure function of the points added: two views of one trace draw the same chunks, and
memory is bounded (`max_chunks` chunks at most, however long a lecture runs).

For the replay (`app.kit.core.history`) the ring stores `rewind_seconds` of points more than the
window: `mark()` is where the trace stands, `rewind(mark)` shows it as it was then (points are
never overwritten by a rewind, so rewinding forward gives the newer ones back), `truncate()`
forgets what came after (a branch; `generation` is bumped so views redraw).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Trace"]

SPACING_SLACK = 1e-12  # [s] a point this much early still counts as `spacing` after the last one
REWIND_SECONDS = 62.0  # [s] of simulated time stored beyond the window (the replay keeps 60 s)


class Trace:
    """A bounded, chunked history of one point (3,) in any units the owner says.

    Attributes (read them; `add` and `clear` change them):
        seconds, spacing [s] of simulated time; chunk_points: points per chunk (>= 2).
        count: points added since the last clear (the index the next point gets).
        first: index of the oldest point kept (a multiple of chunk_points - 1).
        generation: bumped by `clear` (a view redraws from scratch when it changed).
        max_chunks: the most chunks ever kept at once (a view builds this many nodes).
    """

    def __init__(self, seconds: float, spacing: float, chunk_points: int,
                 rewind_seconds: float = REWIND_SECONDS) -> None:
        if not (math.isfinite(seconds) and seconds > 0.0 and math.isfinite(spacing) and spacing > 0.0):
            raise ValueError(f"seconds and spacing must be positive and finite, got {seconds!r}, {spacing!r}")
        if chunk_points < 2:
            raise ValueError(f"chunk_points must be at least 2, got {chunk_points!r}")
        self.seconds = float(seconds)
        self.spacing = float(spacing)
        self.chunk_points = int(chunk_points)
        stride = self.chunk_points - 1
        # Complete chunks kept span >= stride * spacing each (less the slack): seconds / that + 1
        # of them, the head, and one chunk of margin.
        self.max_chunks = math.ceil(self.seconds / (stride * self.spacing)) + 3
        spare_chunks = math.ceil(max(0.0, rewind_seconds) / (stride * self.spacing))
        self._capacity = (self.max_chunks + spare_chunks) * stride + 1
        self._t = np.zeros(self._capacity)
        self._points = np.zeros((self._capacity, 3))
        self.count = 0
        self.first = 0
        self.generation = 0
        self._written = 0  # points written since the last clear: the last _capacity of them are stored

    @property
    def stride(self) -> int:
        """Points from one chunk's start to the next's (chunk_points - 1)."""
        return self.chunk_points - 1

    def __len__(self) -> int:
        """Points kept."""
        return self.count - self.first

    def clear(self) -> None:
        """Forget every point (a new run)."""
        self.count = self.first = self._written = 0
        self.generation += 1

    def last_time(self) -> float:
        """Time [s] of the newest point (-inf if there is none)."""
        return float(self._t[(self.count - 1) % self._capacity]) if self.count else -math.inf

    def add(self, t: float, point: np.ndarray) -> None:
        """The point (3,) at simulated time t [s] (non-decreasing between clears); kept only if
        it is at least `spacing` after the newest one."""
        if self.count and t - self.last_time() < self.spacing - SPACING_SLACK:
            return
        if self._written != self.count:  # after a rewind: the points after it are forgotten
            self.truncate()
        slot = self.count % self._capacity
        self._t[slot] = t
        self._points[slot] = point
        self.count += 1
        self._written = self.count
        stride = self.stride
        newest = self.count - 1
        # Drop complete chunks (not the head) whose newest point is older than `seconds`; and
        # the oldest chunk, whatever its age, if the ring is full (never with these bounds).
        while self.first + stride <= newest and (
                self._t[(self.first + stride) % self._capacity] < t - self.seconds
                or self.count - self.first > self._capacity):
            self.first += stride

    def mark(self) -> tuple[int, int]:
        """(count, first): where the trace stands, for `rewind`."""
        return self.count, self.first

    def can_rewind(self, mark: tuple[int, int]) -> bool:
        """Whether the points of `mark` are still stored (see `rewind`)."""
        count, first = mark
        return 0 <= first <= count <= self._written and first >= self._written - self._capacity

    def rewind(self, mark: tuple[int, int]) -> None:
        """Show the trace as it was at `mark` (from `mark()`); ValueError, nothing changed, if
        its points are no longer stored (older than `rewind_seconds` beyond the window)."""
        if not self.can_rewind(mark):
            raise ValueError(f"trace mark {mark} is not stored (points {self._written - self._capacity}.."
                             f"{self._written} are)")
        self.count, self.first = int(mark[0]), int(mark[1])

    def truncate(self) -> None:
        """Forget the points after `count` (a branch from a rewound moment); views redraw."""
        if self._written != self.count:
            self._written = self.count
            self.generation += 1

    def points(self, start: int, stop: int) -> np.ndarray:
        """Points (stop - start, 3) with indices start .. stop - 1 (a copy; IndexError unless
        first <= start <= stop <= count)."""
        if not self.first <= start <= stop <= self.count:
            raise IndexError(f"points {start}..{stop} asked; {self.first}..{self.count} are kept")
        slots = np.arange(start, stop) % self._capacity
        return self._points[slots]

    def times(self, start: int, stop: int) -> np.ndarray:
        """Times (stop - start,) [s] of the points start .. stop - 1 (as `points`)."""
        if not self.first <= start <= stop <= self.count:
            raise IndexError(f"times {start}..{stop} asked; {self.first}..{self.count} are kept")
        return self._t[np.arange(start, stop) % self._capacity]

    def chunk_span(self, chunk: int) -> tuple[int, int]:
        """(start, stop) point indices a view draws for `chunk`: a complete chunk whole, the
        head with an even number of points (it is redrawn on every other point, not on every
        frame); stop - start < 2 means nothing to draw."""
        start = chunk * self.stride
        available = self.count - start
        if available >= self.chunk_points:
            return start, start + self.chunk_points
        return start, start + max(0, available - available % 2)

    def chunks(self) -> range:
        """Indices of the chunks kept, oldest first (the last is the head)."""
        if self.count == 0:
            return range(0)
        return range(self.first // self.stride, (self.count - 1) // self.stride + 1)

    def copy(self) -> Trace:
        """An independent copy (its own arrays)."""
        new = Trace.__new__(Trace)
        new.__dict__.update(self.__dict__)
        new._t = self._t.copy()
        new._points = self._points.copy()
        return new
