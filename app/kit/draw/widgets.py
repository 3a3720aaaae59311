"""3D pieces every scene shares, written once: the stage (grid, space axes x y z), the body
(a frame turned by R_space_body with its shape and axes x′ y′ z′; instantiable several times,
e.g. a solid body and a translucent ghost), the line of nodes with its gimbal-lock fade,
vector arrows with a label (ω, L), and the lines of a simulation's trace (`TraceLines`).

Per frame a widget changes only small properties of nodes built once (a pose, an arrow's two
points, a label's position), and only when they changed: a node is never rebuilt while a scene
plays.  Everything is drawn through the `scene` it is given (`client.scene`: one browser).

Their labels are registered with the view's `LabelLayer` (`labels=`, app.kit.draw.labels) at a
priority: space axes and vectors KEY, body axes and the line of nodes AXES.  The layer decides
which are shown; a widget only says whether it wants its label (`LabelLayer.want`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from app.i18n import N_
from app.kit.core.common import (
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
from app.kit.core.trace import Trace
from app.kit.draw.labels import AXES, KEY, LabelLayer
from app.viser_internals import set_points, set_position, set_scale, set_wxyz
from physics._types import Mat3, Vec3
from physics.quaternion import wxyz_from_matrix

__all__ = ["FADE_LEVELS", "NODES_LABELS", "POSE_QUANTUM", "Body", "LineOfNodes", "Stage", "TraceLines", "Vector",
           "quantized", "z_onto"]

FADE_LEVELS = 8  # the line of nodes fades in this many steps (one colour message per step)
POSE_QUANTUM = 2.0**-12
"""While playing, quaternion components and positions [scene units] are sent as multiples of
this (`quantized`): a turn of at most ~5e-4 rad, ~0.1 px at the tip of a 2-unit arrow on a
projector, and a float with 12 significant bits, whose zero bytes the frame's compression
squeezes (a pose message ~10 bytes less).  A pose that did not change at this resolution is not
sent at all.  Paused (refresh) poses are exact."""
LENGTH_RTOL = 5e-3  # while playing, an arrow's length is resent when it changed by more than this fraction
LABEL_BEYOND = 0.16  # [scene units] a vector's label sits this far beyond its tip
HEAD_EVERY = 6  # playing frames between two sends of a trace's growing head chunk (10 Hz at 60 fps)
LABEL_ASIDE = 0.06  # [scene units] ... or this far off its middle (x and y of the arrow's frame)

NODES_LABELS = (N_("line of nodes"), N_("line of nodes (undefined)"))
"""The line of nodes' 3D label, defined and near gimbal lock (`LineOfNodes`; a view passes them in
its browser's language: `text`)."""


def quantized(values: Any, quantum: float) -> tuple[float, ...]:
    """`values` (floats) rounded to multiples of `quantum` (a power of two: exact in binary)."""
    return tuple(round(float(v) / quantum) * quantum for v in values)


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
    """The grid (at height `grid_z`) and the space axes x y z with their labels, under `root`
    (the labels kept off the bodies' outlines: `LabelLayer.add(clear_of_bodies=True)`)."""

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
            handle = scene.add_label(f"{root}/space_labels/{name}", name,
                                     position=tuple((axis_length + 0.14) * np.eye(3)[k]),
                                     font_screen_scale=LABEL_SCALE, anchor="center-center")
            if labels is not None:  # an axis label never sits on a body
                labels.add(handle, KEY, clear_of_bodies=True)


class Body:
    """A body: a frame at `name` turned by R_space_body, its shape and its axes x′ y′ z′.

    build_shape(scene, parent) adds the shape's nodes under `parent`; `reshape` swaps them.
    Its shape's meshes are a body for the view's labels (`LabelLayer.avoid`).
    Two instances with different names draw two bodies (the second, say, translucent).
    """

    def __init__(self, scene: Any, name: str, build_shape: Callable[[Any, str], None], *,
                 axis_length: float = 1.0, show_axes: bool = True, labels: LabelLayer | None = None) -> None:
        self._scene = scene
        self.node = scene.add_frame(name, show_axes=False)
        self._shape_name = f"{name}/shape"
        self._shape = scene.add_frame(self._shape_name, show_axes=False)
        build_shape(scene, self._shape_name)
        if labels is not None:  # the space axes' labels keep off its outline
            labels.avoid(scene, self._shape_name)
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

    def pose(self, R_space_body: Mat3, quantum: float | None = None) -> None:
        """Turn the body to R_space_body (3, 3); sent only if it changed (at the resolution
        `quantum`, see POSE_QUANTUM; None: exact)."""
        wxyz = wxyz_from_matrix(R_space_body)
        if quantum is not None:
            wxyz = quantized(wxyz, quantum)  # type: ignore[assignment]
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
    "(undefined)" within GIMBAL_LOCK_DEG, where only φ ± ψ is defined.

    riding=True: `name` hangs from a frame whose x axis already is e_n (the φ-θ frame
    Rz(φ) Rx(θ) of `RigidBodyView.tilt_frame`): the line's own frame is never turned, only its
    fade is sent."""

    def __init__(self, scene: Any, name: str, *, half_length: float = NODES_HALF_LENGTH,
                 labels: LabelLayer | None = None, riding: bool = False,
                 text: tuple[str, str] = NODES_LABELS) -> None:
        self.riding = riding
        self._texts = text  # (defined, undefined)
        self.node = scene.add_frame(name, show_axes=False)
        self.line = scene.add_line_segments(
            f"{name}/line", np.array([[[-half_length, 0.0, 0.0], [half_length, 0.0, 0.0]]]),
            NODES_COLOR, thickness=6.0, thickness_units="screen",
        )
        self.label = _register(labels, scene.add_label(
            f"{name}/label", text[0], position=(0.8 * half_length, 0.0, 0.04),
            font_screen_scale=1.6, anchor="bottom-center",  # inside the line: clear of the axis labels
        ), AXES)
        self._level = -1
        self._wxyz: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0) if riding else ()  # as sent (riding: as built)
        self._angles = (0.0, 0.0)  # (φ, θ) [rad] last given

    @staticmethod
    def fade_level(theta: float) -> int:
        """0 (grey, at a pole) .. FADE_LEVELS (full colour) for the nutation θ [rad]."""
        distance_deg = math.degrees(min(theta, math.pi - theta))
        return max(0, min(FADE_LEVELS, int(FADE_LEVELS * distance_deg / GIMBAL_FADE_DEG)))

    def update(self, phi: float, theta: float, quantum: float | None = None) -> None:
        """Show e_n for the angles φ, θ [rad]; messages only for what changed (at the resolution
        `quantum`, see POSE_QUANTUM; None: exact), none while hidden (`visible` redraws it)."""
        self._angles = (phi, theta)
        if not self.node.visible:
            return
        wxyz = (1.0, 0.0, 0.0, 0.0) if self.riding else (math.cos(0.5 * phi), 0.0, 0.0, math.sin(0.5 * phi))
        if quantum is not None:
            wxyz = quantized(wxyz, quantum)  # type: ignore[assignment]
        if wxyz != self._wxyz:
            self._wxyz = wxyz
            set_wxyz(self.node, wxyz)
        level = self.fade_level(theta)
        if level != self._level:
            self._level = level
            color = fade_color(NODES_COLOR, NODES_FADED_COLOR, level / FADE_LEVELS)
            self.line.colors = np.array([[color, color]], dtype=np.uint8)
            locked = math.degrees(min(theta, math.pi - theta)) < GIMBAL_LOCK_DEG
            self.label.text = self._texts[1] if locked else self._texts[0]

    @property
    def visible(self) -> bool:
        return bool(self.node.visible)

    @visible.setter
    def visible(self, visible: bool) -> None:
        if self.node.visible != visible:
            self.node.visible = visible
            if visible:
                self.update(*self._angles)  # nothing was sent while it was hidden


def z_onto(direction: Vec3 | tuple[float, float, float]) -> tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) of the shortest rotation that turns +z onto the unit vector
    `direction` (3,) (about an axis in the xy-plane, so z = 0); a half turn about x for -z."""
    dx, dy, dz = float(direction[0]), float(direction[1]), float(direction[2])
    w = 1.0 + dz
    if w < 1e-12:
        return (0.0, 1.0, 0.0, 0.0)
    norm = math.sqrt(w * w + dx * dx + dy * dy)
    return (w / norm, -dy / norm, dx / norm, 0.0)


class Vector:
    """An arrow from `origin` to a tip, with a label just beyond the tip (ω, L, ...), wanted
    whenever the arrow is drawn (`show_label(False)` drops it while the arrow stays).

    Nodes (under `name`): a frame at the arrow's start turned so that its +z runs along the
    vector (`node`), the shaft `s` (a unit cylinder scaled along z), and a frame `t` at the tip
    (`tip`, at z = length) holding the head `h` and the label `l` (short names: a playing frame's
    messages carry them).  So a vector that turns costs one orientation
    message; its length is sent (the shaft's scale and the tip's position) only when it changed
    by more than LENGTH_RTOL (while playing), its start only when it moved (see `update`).  Children of `tip`
    (e.g. a dot where the arrow ends) move with it for nothing.
    """

    def __init__(self, scene: Any, name: str, color: tuple[int, int, int], text: str, *,
                 origin: tuple[float, float, float] = (0.0, 0.0, 0.0), shaft_radius: float = 0.03,
                 head_radius: float = 0.08, head_length: float = 0.16, font_scale: float = 2.4,
                 label_at_middle: bool = False, labels: LabelLayer | None = None, priority: float = KEY,
                 labelled: bool = True) -> None:
        self.origin = (float(origin[0]), float(origin[1]), float(origin[2]))
        self.node = scene.add_frame(name, show_axes=False, visible=False, position=self.origin)
        # viser's own arrows (their material, as every other arrow of the app): the shaft a unit
        # arrow with a head no wider than the shaft and vanishingly short, the head one that is all head.
        self.shaft = scene.add_arrows(f"{name}/s", np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]]), color,
                                      shaft_radius=shaft_radius, head_radius=shaft_radius, head_length=1e-6)
        self.tip = scene.add_frame(f"{name}/t", show_axes=False, position=(0.0, 0.0, 1.0))
        self.head = scene.add_arrows(f"{name}/t/h", np.array([[[0.0, 0.0, -head_length], [0.0, 0.0, 0.0]]]),
                                     color, shaft_radius=shaft_radius, head_radius=head_radius,
                                     head_length=head_length)
        self.head_length = float(head_length)
        # Just beyond the tip, a child of the tip (its length costs nothing more); or beside the
        # middle, a child of the start (moved when the length changes).
        # labelled=False: no label at all (`label` is None).
        self.label_at_middle = label_at_middle
        self.label = None if not labelled else _register(labels, scene.add_label(
            f"{name}/l" if label_at_middle else f"{name}/t/l", text, font_screen_scale=font_scale,
            anchor="center-left" if label_at_middle else "center-center", visible=False,
            position=(LABEL_ASIDE, LABEL_ASIDE, 0.5) if label_at_middle else (0.0, 0.0, LABEL_BEYOND)), priority)
        self._labels = labels
        self.enabled = True  # the user's display toggle
        self._tip: tuple[float, float, float] | None = None  # the tip as last checked (rtol)
        self._exact = False  # whether that was drawn exactly (not at a playing frame's resolution)
        self._start: tuple[float, float, float] = self.origin  # as sent
        self._wxyz: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)  # as sent
        self._length = 1.0  # [scene units] as sent
        self._head_scale = 1.0

    @property
    def visible(self) -> bool:
        return bool(self.node.visible)

    @property
    def segment(self) -> np.ndarray:
        """(start, tip) (2, 3) [scene units, in the parent's frame] of the arrow drawn (as sent)."""
        if not self.visible:
            return np.zeros((2, 3))
        return np.array([self._start, np.asarray(self._start) + _rotate(self._wxyz, self._length)])

    def show_label(self, wanted: bool) -> None:
        """Whether the label is wanted (while the arrow is drawn; e.g. not for a short arrow)."""
        if self.label is not None:
            _want(self._labels, self.label, wanted and self.visible)

    def update(self, vector: Vec3, *, start: Vec3 | None = None, rtol: float = 0.0,
               quantum: float | None = None) -> None:
        """Draw `vector` [scene units] from `start` (default: the origin given at construction);
        hidden if shorter than 1e-3 or disabled.

        rtol: skip the update if the tip moved by less than rtol times its length (a conserved
        vector, such as a free body's L, is then sent once, not every frame).
        quantum: send the orientation and start as multiples of it (`quantized`, while playing:
        what does not change at display resolution is not sent); None: exact.
        """
        ox, oy, oz = self.origin if start is None else (float(start[0]), float(start[1]), float(start[2]))
        vx, vy, vz = float(vector[0]), float(vector[1]), float(vector[2])
        tip = (ox + vx, oy + vy, oz + vz)
        length = math.sqrt(vx * vx + vy * vy + vz * vz)
        visible = self.enabled and length > 1e-3
        if self.node.visible != visible:
            self.node.visible = visible
            if self.label is not None:
                _want(self._labels, self.label, visible)
            self._tip = None
        if not visible:
            return
        if self._tip is not None and max(abs(a - b) for a, b in zip(tip, self._tip)) <= rtol * length \
                and (quantum is not None or self._exact):
            return
        self._tip = tip
        self._exact = quantum is None
        start_xyz = (ox, oy, oz) if quantum is None else quantized((ox, oy, oz), quantum)
        if start_xyz != self._start:
            self._start = start_xyz  # type: ignore[assignment]
            set_position(self.node, start_xyz)  # type: ignore[arg-type]
        wxyz = z_onto((vx / length, vy / length, vz / length))
        if quantum is not None:
            wxyz = quantized(wxyz, quantum)  # type: ignore[assignment]
        if wxyz != self._wxyz:
            self._wxyz = wxyz
            set_wxyz(self.node, wxyz)
        if quantum is None or abs(length - self._length) > LENGTH_RTOL * self._length:
            self._set_length(length)

    def _set_length(self, length: float) -> None:
        if length == self._length:
            return
        self._length = length
        head = min(1.0, length / self.head_length)  # an arrow shorter than its head: a smaller head
        self._draw_shaft(max(length - head * self.head_length, 1e-6), head)
        set_position(self.tip, (0.0, 0.0, length))
        if head != self._head_scale:
            self._head_scale = head
            self.head.scale = head
        if self.label_at_middle and self.label is not None:
            set_position(self.label, (LABEL_ASIDE, LABEL_ASIDE, 0.5 * length))

    def _draw_shaft(self, shaft: float, head: float) -> None:
        """Draw the shaft `shaft` long [scene units] under a head scaled by `head` (before the
        head's own scale is sent): the unit shaft scaled along z."""
        set_scale(self.shaft, (1.0, 1.0, shaft))


def _rotate(wxyz: tuple[float, ...], length: float) -> np.ndarray:
    """length times +z turned by the quaternion wxyz (normalized first: it may be quantized)."""
    w, x, y, z = wxyz
    norm2 = w * w + x * x + y * y + z * z
    return length / norm2 * np.array([2.0 * (x * z + w * y), 2.0 * (y * z - w * x), w * w - x * x - y * y + z * z])


class TraceLines:
    """Draws a simulation's `app.kit.core.trace.Trace` (a point's recent path) as line segments.

    One line-segment node per chunk of the trace, a ring of `trace.max_chunks` nodes built once
    (building a node costs far more than moving one): chunk c is drawn by node c mod size.
    `sync` sends only the chunks whose drawn span changed since the last call and hides the
    chunks the trace dropped: a complete
    chunk is sent once, when it completes; the growing head chunk, on a playing frame
    (`lazy=True`), at most every `head_every` frames (HEAD_EVERY by default; so a scene whose chunks complete every few
    frames sends each point once, and its trace ends at most a chunk behind the moving point),
    and at once otherwise (a refresh: a step, a pause).  A view built later draws the trace so
    far on its first `sync`, and draws exactly what every other view of the trace draws.  When
    the trace starts a new run (`Trace.clear`: a preset, a reset), the chunks of the old one are
    erased, not only hidden (`_erase`: their points put back to one idle segment), so nothing
    of a previous preset's path can reappear while the new one is drawn.
    """

    def __init__(self, scene: Any, parent: str, color: tuple[int, int, int], trace: Trace, *,
                 thickness: float = 3.5, head_every: int = HEAD_EVERY) -> None:
        self._head_every = head_every  # playing frames between two sends of the growing head chunk
        self._idle = idle = np.zeros((1, 2, 3), dtype=np.float32)
        self._nodes = [scene.add_line_segments(f"{parent}/{k}", idle, color, thickness=thickness,
                                               thickness_units="screen", visible=False)
                       for k in range(trace.max_chunks)]
        self._holding: set[int] = set()  # nodes whose points are a chunk of the trace (else idle)
        self._shown = [False] * len(self._nodes)  # each node's visibility, as last sent
        self._drawn: list[tuple[int, int] | None] = [None] * len(self._nodes)  # (chunk, stop) sent
        self._spans: dict[int, tuple[int, int, int]] = {}  # node -> (chunk, start, stop) shown
        self._chunk_points = trace.chunk_points
        self._generation = -1
        self._scale = math.nan
        self._synced: tuple[int, int, int, float] | None = None  # the trace as last synced in full
        self._head_wait = 0  # lazy syncs since the head was last sent
        self._done = 0  # chunks before this one are complete and drawn
        self._first_chunk = 0  # the oldest chunk kept at the last sync
        self._count = 0  # trace.count at the last sync (fewer now: a rewind)

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

    def hide(self, trace: Trace | None = None) -> None:
        """Hide every chunk (what is drawn on them stays, for the next `sync`, unless `trace` is
        given and has started a new run since: then it is erased, as `sync` would)."""
        if trace is not None and trace.generation != self._generation:
            self._erase()
            self._generation = trace.generation
        self._synced = None
        self._spans = {}
        self._done = 0  # the next sync looks at every chunk again
        for k, node in enumerate(self._nodes):
            if self._shown[k]:
                node.visible = self._shown[k] = False

    def _erase(self) -> None:
        """Hide every chunk and put its points back to the idle segment: a browser then holds
        nothing of the old run that a later message could show again, even for a moment."""
        for k in sorted(self._holding):
            node = self._nodes[k]
            if self._shown[k]:
                node.visible = self._shown[k] = False
            set_points(node, self._idle)
        self._holding.clear()
        self._drawn = [None] * len(self._nodes)
        self._spans = {}
        self._done = 0
        self._synced = None

    def sync(self, trace: Trace, scale: float = 1.0, *, lazy: bool = False) -> None:
        """Show `trace` (points times `scale`, in the parent node's units): send what changed.

        lazy: a playing frame: the growing head chunk waits up to `head_every` calls.  The chunks
        before the last call's head are looked at again only after a rewind or a clear."""
        synced = (trace.generation, trace.count, trace.first, scale)
        if synced == self._synced:
            return  # nothing new (paused, or no point stored since)
        size = len(self._nodes)
        chunks = trace.chunks()[-size:]
        if trace.generation != self._generation:  # a new run (a preset, a reset): the old one goes at once
            self._erase()
        if trace.generation != self._generation or scale != self._scale:
            self._generation, self._scale = trace.generation, scale
            self._drawn = [None] * len(self._nodes)
            self._done = 0
        if trace.count < self._count:  # a rewind: look at every chunk again
            self._done = 0
        self._count = trace.count
        self._head_wait += 1
        head_due = not lazy or self._head_wait >= self._head_every
        pending = False
        if self._done == 0 or chunks.start != self._first_chunk:  # after a rewind, a clear, a dropped chunk
            self._first_chunk = chunks.start
            spans = {k: span for k, span in self._spans.items() if chunks.start <= span[0] < self._done}
            changed = True
        else:  # the usual frame: the chunks before `_done` stay as they are
            spans, changed = self._spans, False
        for chunk in range(max(self._done, chunks.start), chunks.stop):
            start, stop = trace.chunk_span(chunk)
            if stop - start < 2:
                continue
            k = chunk % size
            complete = stop - start == self._chunk_points
            if self._drawn[k] != (chunk, stop):
                if complete or head_due:
                    points = trace.points(start, stop) * scale
                    set_points(self._nodes[k], polyline_segments(points).astype(np.float32))
                    self._holding.add(k)
                    self._drawn[k] = (chunk, stop)
                    self._head_wait = 0  # the trace is drawn up to here
                else:
                    pending = True
            drawn = self._drawn[k]
            if drawn is not None and drawn[0] == chunk:
                changed = changed or k not in spans
                spans[k] = (chunk, start, drawn[1])
        # Complete and drawn chunks need no second look (until a rewind or a clear).
        done = max(self._done, chunks.start)
        while done < chunks.stop and done * trace.stride + self._chunk_points <= trace.count \
                and self._drawn[done % size] == (done, done * trace.stride + self._chunk_points) \
                and done % size in spans:
            done += 1
        self._done = done
        for k, node in enumerate(self._nodes) if changed else ():
            if (k in spans) != self._shown[k]:
                node.visible = self._shown[k] = k in spans
        self._spans = spans
        self._synced = None if pending else synced
