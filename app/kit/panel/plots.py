"""Live uPlot charts of a simulation's samples (`app.kit.core.samples.SampleBuffer`).

`LivePlots` draws some of those columns in
uPlot charts (x axis = simulated time [s], `time=False` so uPlot does not print dates) and
pushes the window to the browser when asked; the scene asks at most a few times a second.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import viser
import viser.uplot

from app.kit.core.samples import SampleBuffer

__all__ = ["LOG_FLOOR", "LivePlots", "PlotSpec"]

LOG_FLOOR = 1e-17
"""A `log` chart draws log10(max(|value|, LOG_FLOOR)) (log 0 is undefined)."""


@dataclass(frozen=True)
class PlotSpec:
    """One chart: title, the buffer columns it shows, their legend labels and CSS colours."""

    title: str
    columns: tuple[str, ...]
    labels: tuple[str, ...]
    colors: tuple[str, ...]
    log: bool = False  # draw log10 |value| (drifts and errors) on a linear axis: uPlot's own
    #                    log axis labels tiny values "0", and its formatters are JavaScript


class LivePlots:
    """uPlot charts of `buffer` columns in the current GUI container.

    Attributes:
        handles: one GuiUplotHandle per spec.
        pushes: how many times the data were sent (tests check the throttling).
    """

    def __init__(self, gui: viser.GuiApi | Any, buffer: SampleBuffer, specs: Sequence[PlotSpec],
                 height: int = 190) -> None:
        self.buffer = buffer
        self.specs = tuple(specs)
        self.pushes = 0
        self.handles = []
        for spec in self.specs:
            series = (viser.uplot.Series(label="t [s]"),) + tuple(
                viser.uplot.Series(label=label, stroke=color, width=2.0)
                for label, color in zip(spec.labels, spec.colors)
            )
            self.handles.append(gui.add_uplot(
                data=self._data(spec), series=series, title=spec.title, height=height,
                scales={"x": viser.uplot.Scale(time=False, auto=True), "y": viser.uplot.Scale(auto=True)},
                legend=viser.uplot.Legend(show=True, live=True),
            ))

    def _data(self, spec: PlotSpec, rows: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
        rows = self.buffer.ordered() if rows is None else rows
        if rows.shape[0] == 0:  # uPlot wants at least one point
            return (np.zeros(1),) + tuple(np.full(1, np.nan) for _ in spec.columns)
        columns = []
        for name in spec.columns:
            values = rows[:, self.buffer.index(name)]
            if spec.log:
                values = np.log10(np.maximum(np.abs(values), LOG_FLOOR))
            columns.append(np.ascontiguousarray(values))
        return (np.ascontiguousarray(rows[:, 0]), *columns)

    def push(self) -> None:
        """Send the current window to the browser (one message per chart)."""
        rows = self.buffer.ordered()
        for spec, handle in zip(self.specs, self.handles):
            handle.data = self._data(spec, rows)
        self.pushes += 1

    def set_visible(self, visible: bool) -> None:
        for handle in self.handles:
            if handle.visible != visible:
                handle.visible = visible
