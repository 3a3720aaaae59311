"""The replay's memory: a room's last minute of motion as compact snapshots (no viser).

A simulation that moves can be replayed if it is `Replayable`: besides the `Simulation`
protocol (`app.kit.core.room`) it has

- `run`: a number that changes when a new run starts (a reset, a restart, a preset, an edit
  that starts the motion afresh); the history of the old run is then dropped;
- `snapshot() -> Snapshot`: the moment now, compact (`values`: a few dozen floats, t first;
  `refs`: objects the simulation never mutates, shared, e.g. its integrator's name), holding
  everything needed to show this moment again and to continue from it exactly: the state, the
  integrator's internal state, the maxima it keeps, and *marks* of its histories (plot samples
  `app.kit.core.samples.SampleBuffer.mark`, traces `app.kit.core.trace.Trace.mark`), not the histories;
- `restore(snapshot, later=0.0)`: the moment back, bit for bit (histories rewound to their
  marks, so plots and traces end at t; nothing is re-integrated), then, if `later` > 0, the
  state `later` [s] further on *for display only* (the histories stay at the mark): a slow
  replay shows every frame, not only the recorded ones.  `version` is bumped (views redraw),
  never restored.  ValueError, and nothing changed, if the snapshot does not fit;
- `truncate()`: forget the histories after now (a branch: the recorded future is dropped);
- `fork_with(refs)` if its snapshots' refs hold objects it mutates (a stepper): `(fork(), a
  copy of refs)` made in one pass, so the copy's refs are the fork's own objects (`fork_with_refs`).
  A room's fork carries its history this way: an explorer's copy can scrub the last minute.

Rewinding works because nothing is written into a simulation while its room shows the past:
the histories' rings still hold the newer rows, so rewinding forward (Resume) gives back the
live state exactly.  The rings hold the last HISTORY_SECONDS beyond their windows
(`app.kit.core.trace.REWIND_SECONDS`, `app.kit.rigid.simulation.PLOT_SPARE` samples).

`History` keeps snapshots at least RECORD_SPACING [s] of simulated time apart, at most
HISTORY_SECONDS of simulated time and HISTORY_BYTES of memory (`nbytes`), in one float array
that grows by doubling (a room that never plays costs almost nothing).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

__all__ = ["HISTORY_BYTES", "HISTORY_SECONDS", "RECORD_SPACING", "History", "Replayable", "Snapshot",
           "fork_with_refs", "is_replayable"]

HISTORY_SECONDS = 60.0  # [s] of simulated time kept
HISTORY_BYTES = 5_000_000  # [bytes] at most per room (the snapshots; the rings' spare rows are the simulation's)
RECORD_SPACING = 1.0 / 120.0  # [s] of simulated time between snapshots at least (every frame at 1×)
_INITIAL_ROWS = 256
_T_SLACK = 1e-9  # [s] a time this close to the recorded stretch's ends is inside it


@dataclass(frozen=True)
class Snapshot:
    """One recorded moment: `values` (n,) float64 with values[0] = t [s]; `refs`: objects the
    simulation shares with the snapshot and never mutates (names, its stepper object)."""

    values: np.ndarray
    refs: tuple[Any, ...] = ()

    @property
    def t(self) -> float:
        """Simulated time [s] of the moment."""
        return float(self.values[0])


@runtime_checkable
class Replayable(Protocol):
    """A simulation whose motion can be replayed (see the module docstring)."""

    version: int

    @property
    def t(self) -> float: ...

    @property
    def run(self) -> int: ...

    def snapshot(self) -> Snapshot: ...

    def restore(self, snapshot: Snapshot, later: float = 0.0) -> None: ...

    def truncate(self) -> None: ...


def is_replayable(sim: Any) -> bool:
    """Whether `sim` has motion to replay (the Inertia scene's system has none)."""
    return all(callable(getattr(sim, name, None)) for name in ("snapshot", "restore", "truncate")) \
        and hasattr(sim, "run")


_PLAIN = (str, int, float, bool, type(None))


def _plain(value: Any) -> bool:
    """Immutable all the way down (strings, numbers, tuples of them): safe to share with a fork."""
    return isinstance(value, _PLAIN) or (isinstance(value, tuple) and all(_plain(v) for v in value))


def fork_with_refs(sim: Any, refs: list[tuple[Any, ...]]) -> tuple[Any, dict[int, tuple[Any, ...]]] | None:
    """`sim.fork()` and, for each refs tuple of `refs` (from its snapshots), the fork's own copy
    by `id` of the original (`History.fork`); plain refs (names, numbers) are shared as they are.
    None if the refs hold objects and `sim` has no `fork_with` (its history cannot follow)."""
    if all(_plain(r) for r in refs):
        return sim.fork(), {}
    fork_with = getattr(sim, "fork_with", None)
    if fork_with is None:
        return None
    fork, copies = fork_with(tuple(refs))
    return fork, {id(old): new for old, new in zip(refs, copies)}


class History:
    """The last HISTORY_SECONDS of a run as snapshots, oldest first.

    Attributes:
        run: the simulation's `run` the snapshots belong to (None: empty).
        seconds [s], max_bytes, spacing [s]: the bounds.
    """

    def __init__(self, seconds: float = HISTORY_SECONDS, max_bytes: int = HISTORY_BYTES,
                 spacing: float = RECORD_SPACING) -> None:
        self.seconds = float(seconds)
        self.max_bytes = int(max_bytes)
        self.spacing = float(spacing)
        self.run: int | None = None
        self._values = np.zeros((0, 0))
        self._refs: list[tuple[Any, ...]] = []
        self._start = 0
        self._len = 0

    def __len__(self) -> int:
        return self._len

    def distinct_refs(self) -> list[tuple[Any, ...]]:
        """The distinct `refs` tuples of the snapshots kept (by identity; consecutive equal
        refs share one tuple, so these are few)."""
        return list({id(refs): refs for refs in self._refs}.values())

    def fork(self, refs: dict[int, tuple[Any, ...]]) -> History:
        """An independent copy (its own arrays) whose snapshots' refs are `refs[id(old refs)]`:
        the copies a simulation's fork made of the objects its snapshots refer to
        (`app.kit.core.room.Room.fork`), so restoring in the copy never touches the original."""
        copy = History(self.seconds, self.max_bytes, self.spacing)
        copy.run = self.run
        copy._values = self._values.copy()
        copy._refs = [refs.get(id(r), r) for r in self._refs]
        copy._start, copy._len = self._start, self._len
        return copy

    def clear(self) -> None:
        """Forget everything (the arrays are released)."""
        self.run = None
        self._values = np.zeros((0, 0))
        self._refs = []
        self._start = self._len = 0

    # ------------------------------------------------------------------ reading
    def _slot(self, index: int) -> int:
        return (self._start + index) % self._values.shape[0]

    def time(self, index: int) -> float:
        """t [s] of snapshot `index` (0 is the oldest)."""
        return float(self._values[self._slot(index), 1])

    def snapshot(self, index: int) -> Snapshot:
        """Snapshot `index` (0 is the oldest; its values are a copy)."""
        if not 0 <= index < self._len:
            raise IndexError(f"snapshot {index} asked; {self._len} are kept")
        slot = self._slot(index)
        return Snapshot(self._values[slot, 1:].copy(), self._refs[slot])

    def aux(self, index: int) -> float:
        """The number recorded with snapshot `index` (`record(..., aux=)`: the room's sampling phase)."""
        if not 0 <= index < self._len:
            raise IndexError(f"snapshot {index} asked; {self._len} are kept")
        return float(self._values[self._slot(index), 0])

    @property
    def t_first(self) -> float:
        """The oldest recorded time [s] (NaN if empty)."""
        return self.time(0) if self._len else math.nan

    @property
    def t_last(self) -> float:
        """The newest recorded time [s] (NaN if empty)."""
        return self.time(self._len - 1) if self._len else math.nan

    def times(self) -> np.ndarray:
        """(n,) recorded times [s], oldest first."""
        if not self._len:
            return np.zeros(0)
        slots = (self._start + np.arange(self._len)) % self._values.shape[0]
        return self._values[slots, 1].copy()

    def contains(self, t: float) -> bool:
        return bool(self._len) and self.t_first - _T_SLACK <= t <= self.t_last + _T_SLACK

    def index_at(self, t: float) -> int:
        """Index of the newest snapshot at or before t [s]; ValueError (with the stretch) if t is
        outside the recorded stretch."""
        if not (isinstance(t, int | float) and math.isfinite(t)) or not self.contains(float(t)):
            raise ValueError(self.outside_message(t))
        lo, hi = 0, self._len - 1  # the answer is in lo..hi
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if self.time(mid) <= t + _T_SLACK:
                lo = mid
            else:
                hi = mid - 1
        return lo

    def at(self, t: float) -> Snapshot:
        """The newest snapshot at or before t [s] (ValueError outside the stretch)."""
        return self.snapshot(self.index_at(t))

    def outside_message(self, t: Any) -> str:
        if not self._len:
            return f"Time {t!r} refused: nothing is recorded yet (play first)."
        return (f"Time {t!r} s refused: only {self.t_first:.2f} s to {self.t_last:.2f} s is recorded "
                f"(the last {self.seconds:g} s of this run).")

    def nbytes(self) -> int:
        """Memory held [bytes]: the float array, the list of refs and the distinct refs tuples
        (the objects they point to belong to the simulation)."""
        distinct = {id(r): r for r in self._refs}
        return int(self._values.nbytes + sys.getsizeof(self._refs)
                   + sum(sys.getsizeof(r) for r in distinct.values()))

    # ------------------------------------------------------------------ writing
    def record(self, sim: Replayable, force: bool = False, aux: float = 0.0) -> None:
        """Keep `sim.snapshot()` (and `aux` with it) if it is at least `spacing` after the newest (or `force`); a new
        run (or time going back, or a snapshot of another size) starts afresh.  Drops the
        oldest beyond `seconds` or `max_bytes`."""
        run = sim.run
        if run != self.run:
            self.clear()
            self.run = run
        snap = sim.snapshot()
        values = snap.values
        t = float(values[0])
        if self._len:
            last = self.t_last
            if t < last or values.shape[0] + 1 != self._values.shape[1]:
                self.clear()
                self.run = run
            elif t == last or (not force and t - last < self.spacing * (1.0 - 1e-9)):
                if t == last and force:
                    self._put(self._len - 1, snap, aux)
                return
        self._append(snap, aux)
        while self._len > 1 and t - self.t_first > self.seconds + _T_SLACK:
            self._drop_oldest()

    def cut_after(self, t: float) -> None:
        """Forget the snapshots after t [s] (a branch)."""
        while self._len and self.t_last > t + _T_SLACK:
            self._len -= 1

    def _put(self, index: int, snap: Snapshot, aux: float) -> None:
        """Row `index`: aux, then the snapshot's values (written in place)."""
        slot = self._slot(index)
        row = self._values[slot]
        row[0] = aux
        row[1:] = snap.values
        previous = self._refs[self._slot(index - 1)] if index > 0 else None
        # Equal refs share one tuple (a pointer per row, not a tuple per row).
        same = previous is not None and len(previous) == len(snap.refs) and all(
            a is b or a == b for a, b in zip(previous, snap.refs))
        self._refs[slot] = previous if same and previous is not None else snap.refs

    def _max_rows(self, width: int) -> int:
        """Rows that fit max_bytes (the float row and its refs pointer; a margin for the tuples)."""
        return max(2, self.max_bytes // (8 * width + 8) - 8)

    def _append(self, snap: Snapshot, aux: float) -> None:
        width = snap.values.shape[0] + 1  # aux, then the values
        rows = self._values.shape[0]
        if self._len == rows:
            limit = self._max_rows(width)
            if rows >= limit:
                self._drop_oldest()
            else:
                self._grow(min(limit, max(_INITIAL_ROWS, 2 * rows)), width)
        self._len += 1
        self._put(self._len - 1, snap, aux)

    def _grow(self, rows: int, width: int) -> None:
        values = np.zeros((rows, width))
        refs: list[tuple[Any, ...]] = [()] * rows
        for k in range(self._len):
            slot = self._slot(k)
            values[k] = self._values[slot]
            refs[k] = self._refs[slot]
        self._values, self._refs, self._start = values, refs, 0

    def _drop_oldest(self) -> None:
        self._refs[self._start] = ()
        self._start = (self._start + 1) % self._values.shape[0]
        self._len -= 1
