"""The hall's values as bus messages and back, checked beyond their types: the presenter's
camera, its open plot tab (`Plot`), a follower's kind of screen (`ScreenShape`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from app.cluster.messages import Camera, Chart, Markdown, Plot, ScreenShape
from app.kit.core.common import CameraView
from app.kit.draw.screen import Screen
from app.kit.view import PLOT_TABS
from app.lecture.room_plot import UPLOT_PROPS, ChartCopy, MarkdownCopy, is_chart

__all__ = ["camera_shot", "element_value", "plot_from_message", "plot_message", "screen_from_shape", "screen_shape"]

MAX_DEPTH = 8  # nesting of a chart's properties
MAX_PLOT_SAMPLES = 20_000  # a column's samples
MAX_PLOT_PROP_VALUES = 2_000  # the plain values in a chart's properties (its series, scales, axes ...)
PlotCopy = tuple[str, tuple[Any, ...]]
"""(tab, elements: `ChartCopy` / `MarkdownCopy`) as `app.lecture.lectern.RemoteShow.plot` holds it."""


def camera_shot(message: Camera) -> dict[str, Any]:
    """The presenter's camera as `RemoteShow.camera` holds it: position, look_at, up, fov, aspect."""
    return {"position": list(message.position), "look_at": list(message.look_at), "up": list(message.up),
            "fov": message.fov, "aspect": message.aspect}


def element_value(element: Any) -> Any:
    """What tells a plot element changed: a chart's data, a Markdown's content (viser keeps
    the object it was last given)."""
    return element.data if is_chart(element) else element.content


def plot_message(worker: str, tab: str, elements: Sequence[Any]) -> Plot:
    """The presenter's open plot tab (`Lectern.room_plot`: uPlot handles and Markdown) as a
    message: each chart's UPLOT_PROPS and its columns as float32 bytes."""
    plain: list[Markdown | Chart] = []
    for element in elements:
        if is_chart(element):
            columns = [np.ascontiguousarray(column, dtype="<f4").tobytes() for column in element.data]
            plain.append(Chart({name: getattr(element, name) for name in UPLOT_PROPS}, columns))
        else:
            plain.append(Markdown(str(element.content)))
    return Plot(worker=worker, tab=tab if elements else "", elements=plain)


def _plain_values(value: object, depth: int = 0) -> int:
    """How many plain values (None, bool, number, str of up to 200 characters, lists and dicts
    of them, str keys) `value` holds; -1 for anything else or nested deeper than MAX_DEPTH."""
    if value is None or isinstance(value, (bool, int)):
        return 1
    if isinstance(value, float):
        return 1 if np.isfinite(value) else -1
    if isinstance(value, str):
        return 1 if len(value) <= 200 else -1
    if depth >= MAX_DEPTH:
        return -1
    items: list[object]
    if isinstance(value, dict):
        items = [*value.keys(), *value.values()]
        if not all(isinstance(key, str) for key in value):
            return -1
    elif isinstance(value, list):
        items = value
    else:
        return -1
    total = 1
    for item in items:
        count = _plain_values(item, depth + 1)
        if count < 0:
            return -1
        total += count
    return total


def _chart(chart: Chart, old: object) -> ChartCopy | None:
    """A chart read from Redis (properties of UPLOT_PROPS, plain values; columns of one length);
    `old` itself when equal to it; None for anything else."""
    props, columns = chart.props, chart.columns
    if not (set(props) <= set(UPLOT_PROPS) and 0 < _plain_values(props) <= MAX_PLOT_PROP_VALUES):
        return None
    if not (all(len(c) == len(columns[0]) for c in columns)
            and len(columns[0]) % 4 == 0 and len(columns[0]) <= 4 * MAX_PLOT_SAMPLES):
        return None
    data = tuple(np.frombuffer(column, dtype="<f4") for column in columns)
    copy = ChartCopy(data, **props)
    if (isinstance(old, ChartCopy) and _shape_equal(old, copy)
            and all(np.array_equal(a, b, equal_nan=True) for a, b in zip(old.data, data))):
        return old
    return copy


def plot_from_message(message: Plot, previous: PlotCopy) -> PlotCopy | None:
    """A `Plot` read from Redis, checked (a PLOT_TABS tab with elements, or "" with none; a
    chart's properties plain values of UPLOT_PROPS only, its columns float32 of one length);
    None for anything else.  An element equal to the one at its place in `previous` is that
    object (the followers' copies are sent only when it changed)."""
    tab, items = message.tab, message.elements
    if tab == "" and not items:
        return "", ()
    if tab not in PLOT_TABS or not items:
        return None
    elements: list[Any] = []
    for index, item in enumerate(items):
        old = previous[1][index] if previous[0] == tab and index < len(previous[1]) else None
        if isinstance(item, Markdown):
            same = isinstance(old, MarkdownCopy) and old.content == item.text
            elements.append(old if same else MarkdownCopy(item.text))
            continue
        chart = _chart(item, old)
        if chart is None:
            return None
        elements.append(chart)
    return tab, tuple(elements)


def _shape_equal(a: ChartCopy, b: ChartCopy) -> bool:
    return len(a.data) == len(b.data) and all(getattr(a, name) == getattr(b, name) for name in UPLOT_PROPS)


def _vec3(v: Sequence[float]) -> tuple[float, float, float]:
    return float(v[0]), float(v[1]), float(v[2])


def screen_shape(screen: Screen) -> ScreenShape:
    """A follower's `Screen` as the message: its camera, canvas and panel."""
    view, panel = screen.view, screen.panel
    return ScreenShape(_vec3(view.position), _vec3(view.look_at), _vec3(view.up), float(view.fov_deg),
                       int(screen.width), int(screen.height),
                       None if panel is None else (float(panel[0]), float(panel[1]), float(panel[2]), float(panel[3])))


def screen_from_shape(shape: ScreenShape) -> Screen | None:
    """A `ScreenShape` read from Redis as a `Screen` (its bounds checked on decode); None for
    a camera that looks at its own position."""
    view = CameraView(shape.position, shape.look_at, shape.up, shape.fov_deg)
    if view.position == view.look_at:
        return None
    return Screen(view, shape.width, shape.height, shape.panel)
