"""The recent path of a moving point, kept by a simulation (no viser): `Trace`.

A trace belongs to the simulation, not to a view, so a view built later (an explorer's fork,
a late joiner, an export) draws the path so far, and a fork carries it on.  A view draws it
with `app.kit.widgets.TraceLines`, which sends only the chunks that changed.

Points are stored at least `spacing` [s] of simulated time apart, in chunks of
`chunk_points` points; consecutive chunks share their end point (chunk c holds the points
c S .. c S + S, S = chunk_points - 1, counted from the last `clear`).  A complete chunk is
dropped when its newest point is older than `seconds` before the newest point, so what is
kept is a pure function of the points added: two views of one trace draw the same chunks, and
memory is bounded (`max_chunks` chunks at most, however long a lecture runs).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Trace"]

SPACING_SLACK = 1e-12  # [s] a point this much early still counts as `spacing` after the last one


class Trace:
    """A bounded, chunked history of one point (3,) in any units the owner says.

    Attributes (read them; `add` and `clear` change them):
        seconds, spacing [s] of simulated time; chunk_points: points per chunk (>= 2).
        count: points added since the last clear (the index the next point gets).
        first: index of the oldest point kept (a multiple of chunk_points - 1).
        generation: bumped by `clear` (a view redraws from scratch when it changed).
        max_chunks: the most chunks ever kept at once (a view builds this many nodes).
    """

    def __init__(self, seconds: float, spacing: float, chunk_points: int) -> None:
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
        self._capacity = self.max_chunks * stride + 1
        self._t = np.zeros(self._capacity)
        self._points = np.zeros((self._capacity, 3))
        self.count = 0
        self.first = 0
        self.generation = 0

    @property
    def stride(self) -> int:
        """Points from one chunk's start to the next's (chunk_points - 1)."""
        return self.chunk_points - 1

    def __len__(self) -> int:
        """Points kept."""
        return self.count - self.first

    def clear(self) -> None:
        """Forget every point (a new run)."""
        self.count = 0
        self.first = 0
        self.generation += 1

    def last_time(self) -> float:
        """Time [s] of the newest point (-inf if there is none)."""
        return float(self._t[(self.count - 1) % self._capacity]) if self.count else -math.inf

    def add(self, t: float, point: np.ndarray) -> None:
        """The point (3,) at simulated time t [s] (non-decreasing between clears); kept only if
        it is at least `spacing` after the newest one."""
        if self.count and t - self.last_time() < self.spacing - SPACING_SLACK:
            return
        slot = self.count % self._capacity
        self._t[slot] = t
        self._points[slot] = point
        self.count += 1
        stride = self.stride
        newest = self.count - 1
        # Drop complete chunks (not the head) whose newest point is older than `seconds`; and
        # the oldest chunk, whatever its age, if the ring is full (never with these bounds).
        while self.first + stride <= newest and (
                self._t[(self.first + stride) % self._capacity] < t - self.seconds
                or self.count - self.first > self._capacity):
            self.first += stride

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
