"""A bounded sliding window of a simulation's samples (no viser: simulations keep one).

`SampleBuffer` is a ring buffer (fixed capacity, so memory is bounded however long a lecture
runs) of the simulated time and named columns; `app.kit.plots.LivePlots` draws it.
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

    def __init__(self, columns: Sequence[str], capacity: int) -> None:
        self.columns = tuple(columns)
        self.capacity = capacity
        self._index = {name: k + 1 for k, name in enumerate(self.columns)}
        self._rows = np.zeros((capacity, len(self.columns) + 1))
        self._count = 0  # samples ever appended since the last clear

    def __len__(self) -> int:
        return min(self._count, self.capacity)

    def clear(self) -> None:
        self._count = 0

    def append(self, t: float, values: Mapping[str, float]) -> None:
        """Add one sample (missing columns are NaN, drawn as a gap)."""
        row = self._rows[self._count % self.capacity]
        row[0] = t
        row[1:] = np.nan
        for name, value in values.items():
            row[self._index[name]] = value
        self._count += 1

    def index(self, name: str) -> int:
        """The column's index in the rows of `ordered` (0 is the time)."""
        return self._index[name]

    def ordered(self) -> np.ndarray:
        """(n, 1 + columns) rows, oldest first: time, then the columns (a copy)."""
        return self._ordered().copy()

    def _ordered(self) -> np.ndarray:
        n = len(self)
        if self._count <= self.capacity:
            return self._rows[:n]
        start = self._count % self.capacity
        return np.concatenate([self._rows[start:], self._rows[:start]])

    def times(self) -> np.ndarray:
        """(n,) simulated times [s], oldest first."""
        return self._ordered()[:, 0].copy()

    def column(self, name: str) -> np.ndarray:
        """(n,) values of one column, oldest first."""
        return self._ordered()[:, self._index[name]].copy()

    def last(self, name: str) -> float:
        """The newest value of a column (NaN if empty)."""
        if not self._count:
            return float("nan")
        return float(self._rows[(self._count - 1) % self.capacity, self._index[name]])
