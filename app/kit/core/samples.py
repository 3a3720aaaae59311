"""A bounded sliding window of a simulation's samples (no viser: simulations keep one).

`SampleBuffer` is a ring buffer (fixed capacity, so memory is bounded however long a lecture
runs) of the simulated time and named columns; `app.kit.panel.plots.LivePlots` draws it.  For the
replay (`app.kit.core.history`) it stores `spare` rows more than it shows and can be rewound: `mark()`
is where it stands, `rewind(mark)` shows the window as it was then (rows are never overwritten
by a rewind, so rewinding forward again gives back the newer rows), `truncate()` forgets what
came after (a branch).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

__all__ = ["SampleBuffer"]


class SampleBuffer:
    """Ring buffer of (t, columns...) samples; `capacity` rows at most.

    Attributes:
        columns: the column names (besides the time).
    """

    def __init__(self, columns: Sequence[str], capacity: int, spare: int = 0) -> None:
        """capacity: rows shown (the window); spare: rows stored beyond it, for a rewind."""
        self.columns = tuple(columns)
        self.capacity = capacity
        self._size = capacity + max(0, int(spare))  # rows stored
        self._index = {name: k + 1 for k, name in enumerate(self.columns)}
        self._rows = np.zeros((self._size, len(self.columns) + 1))
        self._count = 0  # the window ends before sample number _count (counted since the last clear)
        self._written = 0  # samples written since the last clear: the last _size of them are stored

    def _first(self) -> int:
        """Number of the oldest sample in the window."""
        return max(0, self._count - self.capacity, self._written - self._size)

    def __len__(self) -> int:
        return max(0, self._count - self._first())

    def clear(self) -> None:
        self._count = self._written = 0

    def append(self, t: float, values: Mapping[str, float]) -> None:
        """Add one sample (missing columns are NaN, drawn as a gap); after a rewind it replaces
        the samples that came after (they are forgotten)."""
        row = self._rows[self._count % self._size]
        row[0] = t
        row[1:] = np.nan
        for name, value in values.items():
            row[self._index[name]] = value
        self._count += 1
        self._written = self._count

    @property
    def written(self) -> int:
        """Samples written since the last clear (a mark up to this can be rewound to)."""
        return self._written

    def mark(self) -> int:
        """Where the buffer stands (samples appended since the last clear), for `rewind`."""
        return self._count

    def rewind(self, mark: int) -> None:
        """Show the window as it was at `mark` (from `mark()`; ValueError beyond what was
        written).  Rows older than the storage are gone: the window then starts later."""
        if not 0 <= mark <= self._written:
            raise ValueError(f"sample mark {mark} is not in 0..{self._written}")
        self._count = int(mark)

    def truncate(self) -> None:
        """Forget the samples after the window's end (a branch from a rewound moment)."""
        self._written = self._count

    def index(self, name: str) -> int:
        """The column's index in the rows of `ordered` (0 is the time)."""
        return self._index[name]

    def ordered(self) -> np.ndarray:
        """(n, 1 + columns) rows, oldest first: time, then the columns (a copy)."""
        return self._ordered().copy()

    def _ordered(self) -> np.ndarray:
        first = self._first()
        if self._count <= self._size:
            return self._rows[first:max(first, self._count)]
        return self._rows[np.arange(first, self._count) % self._size]

    def times(self) -> np.ndarray:
        """(n,) simulated times [s], oldest first."""
        return self._ordered()[:, 0].copy()

    def column(self, name: str) -> np.ndarray:
        """(n,) values of one column, oldest first."""
        return self._ordered()[:, self._index[name]].copy()

    @property
    def oldest(self) -> int:
        """Number of the oldest sample stored (counted since the last clear)."""
        return max(0, self._written - self._size)

    def rows(self, first: int, stop: int) -> np.ndarray:
        """(stop - first, 1 + columns) rows of the samples numbered first .. stop - 1 (counted since
        the last clear; all stored: ValueError otherwise), as in `ordered` (a copy)."""
        if not (self.oldest <= first <= stop <= self._written):
            raise ValueError(f"samples {first}..{stop - 1} are not stored")
        return self._rows[np.arange(first, stop) % self._size].copy()

    def put(self, number: int, name: str, value: float) -> None:
        """Set one column of the stored sample `number` (counted since the last clear)."""
        if not self.oldest <= number < self._written:
            raise ValueError(f"sample {number} is not stored")
        self._rows[number % self._size, self._index[name]] = value

    def last(self, name: str) -> float:
        """The newest value of a column (NaN if empty)."""
        if not len(self):
            return float("nan")
        return float(self._rows[(self._count - 1) % self._size, self._index[name]])
