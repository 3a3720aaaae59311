"""The presenter's plot on a follower's panel: a read-only copy of the plot tab the presenter has open.

The presenter's view says which of its plot tabs is on its screen (`app.kit.view.PLOT_TABS`:
Plots, Energy, Lagrange) and which panel elements that tab shows (`SceneView.room_plot`: uPlot
charts and Markdown readouts, in order).  `PlotMirror`, in a follower's panel, keeps copies of
them: the same charts (series, scales, title, height, axes, legend) with the same data, and the
same words, sent when the presenter's change.

Read only by construction: the copies are the follower's own panel elements with no callback
(a uPlot chart and a Markdown element take no input), made from the presenter's handles by
reading them; nothing flows back.  The lectern (`app.lecture.lectern.Lectern.refresh_followers`) calls
`PlotMirror.show` every FOLLOW_PERIOD with the same source handles for every follower; a copy
is sent only when its source's value object changed (viser keeps the object it was last given,
so `is` tells), at most every MIRROR_PERIOD, as float32 (what a chart's pixels need), and only
to a follower whose panel shows it (a phone's collapsed panel does not).  A presenter on another
process: the bus carries the tab's elements as `ChartCopy` and `MarkdownCopy`, copied the same
way.  Cost: the free body's Plots tab (5 charts, 300 samples of 2-4 series) is ~24 kB a copy,
~24 kB/s for each laptop follower while the presenter's Plots tab is open and playing.
"""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import viser

__all__ = ["MIRROR_PERIOD", "UPLOT_PROPS", "ChartCopy", "MarkdownCopy", "PlotMirror", "is_chart"]

MIRROR_PERIOD = 1.0  # [s] a chart's copy is sent at most this often

UPLOT_PROPS = ("series", "scales", "title", "height", "axes", "legend")
"""The chart's properties copied with its data (what makes the copy look like the original)."""


@dataclasses.dataclass(frozen=True)
class ChartCopy:
    """A uPlot chart read from another process (`app.lecture.bus`): `PlotMirror` copies it as
    it copies a `viser.GuiUplotHandle` (the UPLOT_PROPS as attributes, `data` its columns)."""

    data: tuple[np.ndarray, ...]
    series: Any = None
    scales: Any = None
    title: Any = None
    height: Any = None
    axes: Any = None
    legend: Any = None


@dataclasses.dataclass(frozen=True)
class MarkdownCopy:
    """A Markdown element read from another process: `PlotMirror` copies its `content`."""

    content: str


def _light(data: Any) -> tuple[Any, ...]:
    """A chart's data as float32 columns (uPlot draws them the same; half the bytes)."""
    return tuple(np.asarray(column, dtype=np.float32) for column in data)


def is_chart(element: Any) -> bool:
    """`element` of a plot tab is a chart (a viser uPlot handle or a `ChartCopy`), else Markdown."""
    return isinstance(element, (viser.GuiUplotHandle, ChartCopy))


def _shape(source: Any) -> tuple[Any, ...]:
    """What a copy is built from (a change rebuilds it): its kind and, for a chart, its props."""
    if is_chart(source):
        return ("uplot", *(repr(getattr(source, name)) for name in UPLOT_PROPS))
    return ("markdown",)


class PlotMirror:
    """Read-only copies of the presenter's open plot in a follower's panel (see the module docstring).

    Args:
        gui: the follower's panel, inside the folder the copies go in.

    Attributes:
        tab: the presenter's plot tab shown ("" none).  copies: the copies' handles, in order.
        sends: how many copies' values were sent (tests check that unchanged plots send nothing).
    """

    def __init__(self, gui: Any, clock: Callable[[], float] = time.monotonic) -> None:
        self._gui = gui
        self._clock = clock
        self._sent_at = -float("inf")
        self.tab = ""
        self.folder = gui.add_folder("The presenter's plot", visible=False)
        self.copies: list[Any] = []
        self._shapes: list[tuple[Any, ...]] = []
        self._seen: list[Any] = []  # the source value each copy was last sent
        self.sends = 0
        self.shown = True
        self._lock = threading.Lock()  # the loop's refresh and a release's (a closed tab's thread) race

    def set_shown(self, shown: bool) -> None:
        """The follower's panel shows (True) or hides the copies (a collapsed phone panel)."""
        self.shown = bool(shown)
        visible = self.shown and bool(self.tab)
        if self.folder.visible != visible:
            self.folder.visible = visible

    def show(self, tab: str, sources: Sequence[Any]) -> None:
        """Copy `sources` (the presenter's open plot tab `tab`'s elements; "" and () for none)."""
        with self._lock:
            self._show(tab, sources)

    def _show(self, tab: str, sources: Sequence[Any]) -> None:
        if not tab or not sources:
            if self.tab or self.copies:
                self.tab = ""
                self._clear()
                self.set_shown(self.shown)
            return
        if tab != self.tab:
            self.tab = tab
            self.folder.label = f"The presenter's {tab} tab (read only)"
        if not self.shown:
            self.set_shown(False)
            return
        shapes = [_shape(source) for source in sources]
        now = self._clock()
        if shapes != self._shapes:
            self._rebuild(sources, shapes)
            self._sent_at = now
        elif now - self._sent_at < MIRROR_PERIOD:
            return
        self._sent_at = now
        for index, source in enumerate(sources):
            value = source.data if shapes[index][0] == "uplot" else source.content
            if value is not self._seen[index]:
                self._seen[index] = value
                copy = self.copies[index]
                if shapes[index][0] == "uplot":
                    copy.data = _light(value)
                else:
                    copy.content = value
                self.sends += 1
        self.set_shown(True)

    def _rebuild(self, sources: Sequence[Any], shapes: list[tuple[Any, ...]]) -> None:
        self._clear()
        gui = self._gui
        with self.folder:
            for source, shape in zip(sources, shapes):
                if shape[0] == "uplot":
                    props = {name: getattr(source, name) for name in UPLOT_PROPS}
                    self.copies.append(gui.add_uplot(data=_light(source.data),
                                                     **{k: v for k, v in props.items() if v is not None}))
                    self._seen.append(source.data)
                else:
                    self.copies.append(gui.add_markdown(source.content))
                    self._seen.append(source.content)
                self.sends += 1
        self._shapes = shapes

    def _clear(self) -> None:
        for copy in self.copies:
            copy.remove()
        self.copies, self._shapes, self._seen = [], [], []
