"""3D pieces every scene shares, written once: the stage (grid, space axes x y z), the body
(a frame turned by R_space_body with its shape and axes x′ y′ z′; instantiable several times,
e.g. a solid body and a translucent ghost), the line of nodes with its gimbal-lock fade,
vector arrows with a label (ω, L), and the lines of a simulation's trace (`TraceLines`).

Per frame a widget changes only small properties of nodes built once (a pose, an arrow's two
points, a label's position), and only when they changed: a node is never rebuilt while a scene
plays.  Everything is drawn through the `scene` it is given (`client.scene`: one browser).

Their labels are registered with the view's `LabelLayer` (`labels=`, app.kit.labels) at a
priority: space axes and vectors KEY, body axes and the line of nodes AXES.  The layer decides
which are shown; a widget only says whether it wants its label (`LabelLayer.want`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from app.kit.common import (
    BODY_AXIS_COLORS,
    GIMBAL_FADE_DEG,
    GIMBAL_LOCK_DEG,
    LABEL_SCALE,
    NODES_COLOR,
    NODES_FADED_COLOR,
    NODES_HALF_LENGTH,
    SPACE_AXIS_COLORS,
    SPACE_AXIS_LENGTH,
    axis_segments,
    fade_color,
    polyline_segments,
)
from app.kit.fastprops import set_points, set_position, set_wxyz
from app.kit.labels import AXES, KEY, LabelLayer
from app.kit.trace import Trace
from physics._types import Mat3, Vec3
from physics.quaternion import wxyz_from_matrix

__all__ = ["FADE_LEVELS", "Body", "LineOfNodes", "Stage", "TraceLines", "Vector"]

FADE_LEVELS = 8  # the line of nodes fades in this many steps (one colour message per step)


def _register(labels: LabelLayer | None, handle: Any, priority: float) -> Any:
    """Register a label with the view's layer (if the widget was given one); returns it."""
    if labels is not None:
        labels.add(handle, priority)
    return handle


def _want(labels: LabelLayer | None, handle: Any, visible: bool) -> None:
    """Whether a label should be shown: through the layer if it has one, else directly."""
    if labels is not None:
        labels.want(handle, visible)
    elif handle.visible != visible:
        handle.visible = visible


class Stage:
    """The grid (at height `grid_z`) and the space axes x y z with their labels, under `root`."""

    def __init__(self, scene: Any, root: str, *, grid_z: float = 0.0, size: float = 5.0,
                 axis_length: float = SPACE_AXIS_LENGTH, labels: LabelLayer | None = None) -> None:
        scene.add_grid(
            f"{root}/grid", width=size, height=size, plane="xy", cell_size=0.5, section_size=1.0,
            cell_color=(225, 225, 225), section_color=(190, 190, 190), shadow_opacity=0.0,
            position=(0.0, 0.0, grid_z),
        )
        scene.add_arrows(
            f"{root}/space_axes", axis_segments(np.eye(3), axis_length), np.array(SPACE_AXIS_COLORS),
            shaft_radius=0.014, head_radius=0.045, head_length=0.11,
        )
        for k, name in enumerate("xyz"):
            _register(labels, scene.add_label(f"{root}/space_labels/{name}", name,
                                              position=tuple((axis_length + 0.14) * np.eye(3)[k]),
                                              font_screen_scale=LABEL_SCALE, anchor="center-center"), KEY)


class Body:
    """A body: a frame at `name` turned by R_space_body, its shape and its axes x′ y′ z′.

    build_shape(scene, parent) adds the shape's nodes under `parent`; `reshape` swaps them.
    Two instances with different names draw two bodies (the second, say, translucent).
    """

    def __init__(self, scene: Any, name: str, build_shape: Callable[[Any, str], None], *,
                 axis_length: float = 1.0, show_axes: bool = True, labels: LabelLayer | None = None) -> None:
        self._scene = scene
        self.node = scene.add_frame(name, show_axes=False)
        self._shape_name = f"{name}/shape"
        self._shape = scene.add_frame(self._shape_name, show_axes=False)
        build_shape(scene, self._shape_name)
        self.axes = scene.add_frame(f"{name}/axes", show_axes=False, visible=show_axes)
        scene.add_arrows(
            f"{name}/axes/arrows", axis_segments(np.eye(3), axis_length), np.array(BODY_AXIS_COLORS),
            shaft_radius=0.022, head_radius=0.06, head_length=0.13,
        )
        for k, label in enumerate(("x′", "y′", "z′")):
            _register(labels, scene.add_label(f"{name}/axes/labels/{k}", label,
                                              position=tuple((axis_length + 0.15) * np.eye(3)[k]),
                                              font_screen_scale=LABEL_SCALE, anchor="center-center"), AXES)
        self._wxyz: tuple[float, ...] = ()

    def pose(self, R_space_body: Mat3) -> None:
        """Turn the body to R_space_body (3, 3); sent only if it changed."""
        wxyz = wxyz_from_matrix(R_space_body)
        if wxyz != self._wxyz:
            self._wxyz = wxyz
            set_wxyz(self.node, wxyz)

    def reshape(self, build_shape: Callable[[Any, str], None]) -> None:
        """Replace the shape (after its parameters changed; never per frame)."""
        self._shape.remove()
        self._shape = self._scene.add_frame(self._shape_name, show_axes=False)
        build_shape(self._scene, self._shape_name)

    def show_axes(self, visible: bool) -> None:
        if self.axes.visible != visible:
            self.axes.visible = visible


class LineOfNodes:
    """The line of nodes e_n = (cos φ, sin φ, 0): a frame turned by Rz(φ) with the line along
    its x axis, fading to grey within GIMBAL_FADE_DEG of θ = 0° or 180° and labelled
    "(undefined)" within GIMBAL_LOCK_DEG, where only φ ± ψ is defined."""

    def __init__(self, scene: Any, name: str, *, half_length: float = NODES_HALF_LENGTH,
                 labels: LabelLayer | None = None) -> None:
        self.node = scene.add_frame(name, show_axes=False)
        self.line = scene.add_line_segments(
            f"{name}/line", np.array([[[-half_length, 0.0, 0.0], [half_length, 0.0, 0.0]]]),
            NODES_COLOR, thickness=6.0, thickness_units="screen",
        )
        self.label = _register(labels, scene.add_label(
            f"{name}/label", "line of nodes", position=(0.8 * half_length, 0.0, 0.04),
            font_screen_scale=1.6, anchor="bottom-center",  # inside the line: clear of the axis labels
        ), AXES)
        self._level = -1
        self._phi = math.nan

    @staticmethod
    def fade_level(theta: float) -> int:
        """0 (grey, at a pole) .. FADE_LEVELS (full colour) for the nutation θ [rad]."""
        distance_deg = math.degrees(min(theta, math.pi - theta))
        return max(0, min(FADE_LEVELS, int(FADE_LEVELS * distance_deg / GIMBAL_FADE_DEG)))

    def update(self, phi: float, theta: float) -> None:
        """Show e_n for the angles φ, θ [rad]; messages only for what changed."""
        if phi != self._phi:
            self._phi = phi
            set_wxyz(self.node, (math.cos(0.5 * phi), 0.0, 0.0, math.sin(0.5 * phi)))
        level = self.fade_level(theta)
        if level != self._level:
            self._level = level
            color = fade_color(NODES_COLOR, NODES_FADED_COLOR, level / FADE_LEVELS)
            self.line.colors = np.array([[color, color]], dtype=np.uint8)
            locked = math.degrees(min(theta, math.pi - theta)) < GIMBAL_LOCK_DEG
            self.label.text = "line of nodes (undefined)" if locked else "line of nodes"

    @property
    def visible(self) -> bool:
        return bool(self.node.visible)

    @visible.setter
    def visible(self, visible: bool) -> None:
        if self.node.visible != visible:
            self.node.visible = visible


class Vector:
    """An arrow from `origin` to a tip, with a label just beyond the tip (ω, L, ...), wanted
    whenever the arrow is drawn (`show_label(False)` drops it while the arrow stays)."""

    def __init__(self, scene: Any, name: str, color: tuple[int, int, int], text: str, *,
                 origin: tuple[float, float, float] = (0.0, 0.0, 0.0), shaft_radius: float = 0.03,
                 head_radius: float = 0.08, head_length: float = 0.16, font_scale: float = 2.4,
                 label_at_middle: bool = False, labels: LabelLayer | None = None, priority: float = KEY) -> None:
        self.arrow = scene.add_arrows(name, np.zeros((1, 2, 3)), color, shaft_radius=shaft_radius,
                                      head_radius=head_radius, head_length=head_length, visible=False)
        self.label = _register(labels, scene.add_label(
            f"{name}_label", text, font_screen_scale=font_scale,
            anchor="center-left" if label_at_middle else "center-center", visible=False), priority)
        self._labels = labels
        self.origin = (float(origin[0]), float(origin[1]), float(origin[2]))
        self.label_at_middle = label_at_middle  # else just beyond the tip
        self.enabled = True  # the user's display toggle
        self._tip: tuple[float, float, float] | None = None

    @property
    def visible(self) -> bool:
        return bool(self.arrow.visible)

    def show_label(self, wanted: bool) -> None:
        """Whether the label is wanted (while the arrow is drawn; e.g. not for a short arrow)."""
        _want(self._labels, self.label, wanted and self.visible)

    def update(self, vector: Vec3, *, start: Vec3 | None = None, rtol: float = 0.0) -> None:
        """Draw `vector` [scene units] from `start` (default: the origin given at construction);
        hidden if shorter than 1e-3 or disabled.

        rtol: skip the update if the tip moved by less than rtol times its length (a conserved
        vector, such as a free body's L, is then sent once, not every frame).
        """
        ox, oy, oz = self.origin if start is None else start
        vx, vy, vz = float(vector[0]), float(vector[1]), float(vector[2])
        tip = (ox + vx, oy + vy, oz + vz)
        length = math.sqrt(vx * vx + vy * vy + vz * vz)
        visible = self.enabled and length > 1e-3
        if self.arrow.visible != visible:
            self.arrow.visible = visible
            _want(self._labels, self.label, visible)
            self._tip = None
        if not visible:
            return
        if self._tip is not None and max(abs(a - b) for a, b in zip(tip, self._tip)) <= rtol * length:
            return
        self._tip = tip
        set_points(self.arrow, np.array([[(ox, oy, oz), tip]], dtype=np.float32))
        if self.label_at_middle:
            set_position(self.label, (0.5 * (ox + tip[0]) + 0.06, 0.5 * (oy + tip[1]) + 0.06,
                                      0.5 * (oz + tip[2]) + 0.06))
        else:
            k = 1.0 + 0.16 / length
            set_position(self.label, (ox + k * vx, oy + k * vy, oz + k * vz))


class TraceLines:
    """Draws a simulation's `app.kit.trace.Trace` (a point's recent path) as line segments.

    One line-segment node per chunk of the trace, a ring of `trace.max_chunks` nodes built once
    (creating a node costs viser ~2 ms): chunk c is drawn by node c mod size.  `sync` sends
    only the chunks whose drawn span changed since the last call (per frame: the head, on every
    other stored point) and hides the chunks the trace dropped; a view built later draws the
    trace so far on its first `sync`, and draws exactly what every other view of the trace draws.
    """

    def __init__(self, scene: Any, parent: str, color: tuple[int, int, int], trace: Trace, *,
                 thickness: float = 3.5) -> None:
        idle = np.zeros((1, 2, 3), dtype=np.float32)
        self._nodes = [scene.add_line_segments(f"{parent}/{k}", idle, color, thickness=thickness,
                                               thickness_units="screen", visible=False)
                       for k in range(trace.max_chunks)]
        self._shown = [False] * len(self._nodes)  # each node's visibility, as last sent
        self._drawn: list[tuple[int, int] | None] = [None] * len(self._nodes)  # (chunk, stop) sent
        self._spans: dict[int, tuple[int, int, int]] = {}  # node -> (chunk, start, stop) shown
        self._chunk_points = trace.chunk_points
        self._generation = -1
        self._scale = math.nan
        self._synced: tuple[int, int, int, float] | None = None  # the trace as last synced

    @property
    def point_count(self) -> int:
        """Distinct trace points shown (consecutive chunks share their end point)."""
        spans = [stop - start for k, (_c, start, stop) in self._spans.items() if self._shown[k]]
        return sum(spans) - max(0, len(spans) - 1)

    @property
    def chunk_count(self) -> int:
        """Complete chunks shown."""
        return sum(1 for k, (_c, start, stop) in self._spans.items()
                   if self._shown[k] and stop - start == self._chunk_points)

    def shown_segments(self) -> np.ndarray:
        """The segments (N, 2, 3) shown, oldest chunk first (what the client was sent)."""
        keys = sorted((span[0], k) for k, span in self._spans.items() if self._shown[k])
        parts = [np.asarray(self._nodes[k].points) for _c, k in keys]
        return np.concatenate(parts) if parts else np.zeros((0, 2, 3), dtype=np.float32)

    def hide(self) -> None:
        """Hide every chunk (what is drawn on them stays, for the next `sync`)."""
        self._synced = None
        for k, node in enumerate(self._nodes):
            if self._shown[k]:
                node.visible = self._shown[k] = False

    def sync(self, trace: Trace, scale: float = 1.0) -> None:
        """Show `trace` (points times `scale`, in the parent node's units): send what changed."""
        synced = (trace.generation, trace.count, trace.first, scale)
        if synced == self._synced:
            return  # nothing new (paused, or no point stored since)
        self._synced = synced
        if trace.generation != self._generation or scale != self._scale:
            self._generation, self._scale = trace.generation, scale
            self._drawn = [None] * len(self._nodes)
        size = len(self._nodes)
        spans: dict[int, tuple[int, int, int]] = {}
        for chunk in trace.chunks()[-size:]:
            start, stop = trace.chunk_span(chunk)
            if stop - start >= 2:
                spans[chunk % size] = (chunk, start, stop)
        for k, node in enumerate(self._nodes):
            span = spans.get(k)
            if span is None:
                if self._shown[k]:
                    node.visible = self._shown[k] = False
                continue
            chunk, start, stop = span
            if self._drawn[k] != (chunk, stop):
                points = trace.points(start, stop) * scale
                set_points(node, polyline_segments(points).astype(np.float32))
                self._drawn[k] = (chunk, stop)
            if not self._shown[k]:
                node.visible = self._shown[k] = True
        self._spans = spans
