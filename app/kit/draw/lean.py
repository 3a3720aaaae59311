"""Lean frames: send a node only when it moved visibly, many arrows in one message.

A playing frame is one websocket window: a header, zstd(msgpack) and raw numpy buffers; each
pose message adds to it, and the frame budget (`tests/test_frame_budget.py`; figures in
docs/VISER.md, "Smaller frames") allows only a few small messages a frame.  So a scene sends

- while playing, poses at display resolution: snapped to a grid on which a step moves the
  node's farthest drawn point by `TOLERANCE` [scene units] (~1 px), and sent only when the
  snapped value changed (`Pose`): a slow turn is sent every other frame, a still one never.
  What is drawn is then a function of the state alone (not of what was sent before), so a view
  built later, a fork's view and every follower draw exactly the same; paused (`exact=True`,
  after an edit, a step, a reset) everything is drawn exactly;
- floats rounded to float32 (`f32`): `app.wire` sends a float32-exact pose number as a 5-byte
  float32 instead of a 9-byte float64 (viser's client draws in float32 anyway);
- many arrows of one style in one `add_arrows` node (`Arrows`): one `points` message for all;
- text only when it changed, at a reader's rate (the scenes' throttles).

Nothing here knows physics; the views give points in the parent node's frame [scene units].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from app.kit.draw.widgets import quantized, z_onto
from app.viser_internals import set_points, set_position, set_wxyz, world_pose

__all__ = ["TOLERANCE", "ArcPieces", "Arrows", "FrameArrow", "Pose", "f32", "quaternion_turn", "snap",
           "turn_z_onto", "world_pose"]

TOLERANCE = 0.006  # [scene units] a point that moved less is not resent: ~1 px at the default views (110-160 px/unit)


def f32(value: float) -> float:
    """`value` rounded to the nearest float32, as a Python float (compresses on the wire)."""
    return float(np.float32(value))


def quaternion_turn(a: Sequence[float], b: Sequence[float]) -> float:
    """The angle [rad] of the turn between two unit quaternions (w, x, y, z) (q and -q are one turn)."""
    dot = abs(sum(float(x) * float(y) for x, y in zip(a, b)))
    return 2.0 * math.acos(min(1.0, dot))


def snap(value: float, step: float) -> float:
    """`value` rounded to the nearest multiple of `step` (> 0), as a float32-exact float."""
    return f32(round(value / step) * step)


class Pose:
    """A node's pose (T_parent_local) drawn at display resolution while playing.

    reach: the distance [scene units] of the node's farthest drawn point from its origin (a
    change dq of a quaternion component turns it by about 2 dq, moving that point by 2 reach dq).
    `set(wxyz, position, exact)`: with exact=False the quaternion's components are snapped to
    the grid tolerance / (2 reach) (then normalized) and the position to the grid tolerance;
    a message goes only when what is drawn changed.  turn_quantum (a power of two): the
    components are snapped to this grid instead and not renormalized (a float64 on it ends in
    zero bytes, which compress; the browser draws the slightly non-unit quaternion as a turn
    within ~turn_quantum of it).
    """

    def __init__(self, handle: Any, reach: float = 1.0, tolerance: float = TOLERANCE,
                 turn_quantum: float | None = None) -> None:
        self.handle = handle
        self.reach = float(reach)
        self.tolerance = float(tolerance)
        self.turn_quantum = turn_quantum
        self._wxyz: tuple[float, float, float, float] | None = None
        self._position: tuple[float, float, float] | None = None
        self.sent = 0  # messages sent (tests)

    @property
    def wxyz(self) -> tuple[float, float, float, float] | None:
        """The orientation as last sent (None before the first)."""
        return self._wxyz

    @property
    def position(self) -> tuple[float, float, float] | None:
        """The position as last sent (None before the first)."""
        return self._position

    def forget(self) -> None:
        """The next `set` sends."""
        self._wxyz = self._position = None

    def set(self, wxyz: Sequence[float] | None = None, position: Sequence[float] | np.ndarray | None = None,
            exact: bool = True) -> None:
        """Turn the node to `wxyz` (unit quaternion) and move it to `position` (3,) [scene units]
        in its parent's frame: exactly, or snapped (exact=False, while playing)."""
        if wxyz is not None:
            if exact:
                q = tuple(f32(c) for c in wxyz)
            elif self.turn_quantum is not None:
                q = quantized(wxyz, self.turn_quantum)
            else:
                step = self.tolerance / (2.0 * max(self.reach, 1e-9))
                snapped = [round(float(c) / step) * step for c in wxyz]
                norm = math.sqrt(sum(c * c for c in snapped)) or 1.0
                q = tuple(f32(c / norm) for c in snapped)
            if q != self._wxyz:
                set_wxyz(self.handle, q)  # type: ignore[arg-type]
                self._wxyz = q  # type: ignore[assignment]
                self.sent += 1
        if position is not None:
            if exact:
                p = (f32(position[0]), f32(position[1]), f32(position[2]))
            else:
                p = (snap(position[0], self.tolerance), snap(position[1], self.tolerance),
                     snap(position[2], self.tolerance))
            if p != self._position:
                set_position(self.handle, p)
                self._position = p
                self.sent += 1


class Arrows:
    """Arrows of one style in one viser `add_arrows` node: one `points` message moves them all.

    `set(segments)` takes (N, 2, 3) start/end points [scene units] in the parent's frame, N fixed
    at construction, with `shown` (N,) saying which are drawn (hidden ones, and any shorter than
    MIN_LENGTH, are left out of the node; a change of which are drawn also sends their colours).
    Snapped to the grid `tolerance` unless `exact`; sent only when what is drawn changed.
    """

    MIN_LENGTH = 1e-3  # [scene units] a shorter arrow is not drawn

    def __init__(self, scene: Any, name: str, colors: Sequence[Sequence[int]], *, shaft_radius: float,
                 head_radius: float, head_length: float, tolerance: float = TOLERANCE) -> None:
        self.colors = np.asarray(colors, dtype=np.uint8).reshape(-1, 3)
        self.node = scene.add_arrows(name, np.zeros((1, 2, 3), dtype=np.float32), self.colors[:1],
                                     shaft_radius=shaft_radius, head_radius=head_radius,
                                     head_length=head_length, visible=False)
        self.tolerance = tolerance
        self._drawn: np.ndarray | None = None  # the segments (k, 2, 3) sent
        self._which: tuple[int, ...] | None = None  # which arrows they are

    @property
    def count(self) -> int:
        return len(self.colors)

    def set(self, segments: np.ndarray, shown: Sequence[bool] | None = None, exact: bool = True) -> None:
        segments = np.asarray(segments, dtype=float).reshape(-1, 2, 3)
        if not exact:
            segments = np.round(segments / self.tolerance) * self.tolerance
        segments = segments.astype(np.float32)
        lengths = np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1)
        keep = lengths > self.MIN_LENGTH
        if shown is not None:
            keep &= np.asarray(shown, dtype=bool)
        which = tuple(int(k) for k in np.flatnonzero(keep))
        if not which:
            if self.node.visible:
                self.node.visible = False
            self._which, self._drawn = which, None
            return
        drawn = segments[list(which)]
        if which != self._which:
            self.node.colors = self.colors[list(which)]
        if self._drawn is None or drawn.shape != self._drawn.shape or not np.array_equal(drawn, self._drawn):
            set_points(self.node, drawn)
            self._drawn = drawn
        self._which = which
        if not self.node.visible:
            self.node.visible = True

    def segment(self, k: int) -> np.ndarray | None:
        """The segment (2, 3) drawn for arrow k (parent frame), or None if it is not drawn."""
        if self._which is None or k not in self._which or self._drawn is None:
            return None
        return np.asarray(self._drawn[self._which.index(k)], dtype=float)


class ArcPieces:
    """An arc from angle 0 to angle a about an axis, moved with no message while a changes.

    The arc is drawn in two frames: `fixed` (where the angle is measured from) and `moving`
    (the frame turned by a about the same axis, e.g. the after-φ frame for φ).  Fixed pieces of
    `width` [rad] cover [0, k width] (shown one by one as |a| grows: one visibility message per
    piece), and a tail piece of the same width hangs in the moving frame just behind its x axis,
    covering [a - width, a]: the union is exactly [0, a], and the tail turns with its frame.
    Below one width a short arc in the fixed frame is sent as points instead (few segments).

    point_at(t) -> (3,): the arc's point at angle t [rad] in the fixed frame (radius included);
    in the moving frame the point at angle a + u is point_at(u).  signed: whether a may be
    negative (φ, ψ) or not (θ).
    """

    SEGMENTS = 6  # per piece
    SHORT_SEGMENTS = 4
    MIN_ANGLE = math.radians(0.5)  # smaller arcs are not drawn

    def __init__(self, scene: Any, fixed: str, moving: str, name: str, point_at: Any, color: tuple[int, int, int],
                 *, signed: bool = True, width: float = math.radians(20.0), thickness: float = 4.0) -> None:
        self.point_at = point_at
        self.width = width
        self.fixed_group = scene.add_frame(f"{fixed}/{name}", show_axes=False, visible=False)
        self.moving_group = scene.add_frame(f"{moving}/{name}", show_axes=False, visible=False)
        signs = (1, -1) if signed else (1,)
        count = math.ceil(math.pi / width - 1e-9)
        style = {"thickness": thickness, "thickness_units": "screen"}

        def polyline(lo: float, hi: float, segments: int) -> np.ndarray:
            points = np.array([point_at(t) for t in np.linspace(lo, hi, segments + 1)], dtype=np.float32)
            return np.stack([points[:-1], points[1:]], axis=1)

        self.pieces = {(sign, k): scene.add_line_segments(
            f"{fixed}/{name}/{'p' if sign > 0 else 'n'}{k}",
            polyline(sign * k * width, sign * min((k + 1) * width, math.pi), self.SEGMENTS), color,
            visible=False, **style) for sign in signs for k in range(count)}
        self.tails = {sign: scene.add_line_segments(
            f"{moving}/{name}/{'p' if sign > 0 else 'n'}", polyline(-sign * width, 0.0, self.SEGMENTS), color,
            visible=False, **style) for sign in signs}
        self.short = scene.add_line_segments(f"{fixed}/{name}/short", polyline(0.0, width, self.SHORT_SEGMENTS),
                                             color, visible=False, **style)
        self._polyline = polyline
        self._short_angle = math.nan
        self._shown: dict[Any, bool] = {}

    def _show(self, node: Any, visible: bool) -> None:
        if self._shown.get(id(node), bool(node.visible)) != visible:
            node.visible = visible
        self._shown[id(node)] = visible

    def show(self, angle: float, visible: bool = True, exact: bool = True, tolerance: float = TOLERANCE) -> None:
        """Draw the arc for `angle` [rad] (hidden if not `visible` or shorter than MIN_ANGLE); a
        short arc's end is snapped to display resolution unless `exact`."""
        drawn = visible and abs(angle) >= self.MIN_ANGLE
        self._show(self.fixed_group, drawn)
        self._show(self.moving_group, drawn)
        if not drawn:
            return
        sign = 1 if angle >= 0.0 else -1
        whole = int(abs(angle) // self.width)
        for (s, k), node in self.pieces.items():
            self._show(node, s == sign and k < whole)
        for s, node in self.tails.items():
            self._show(node, s == sign and whole >= 1)
        short = whole == 0
        if short:
            end = angle if exact else snap(angle, tolerance / float(np.linalg.norm(self.point_at(0.0))))
            if end != self._short_angle:
                set_points(self.short, self._polyline(0.0, end, self.SHORT_SEGMENTS))
                self._short_angle = end
        self._show(self.short, short)

    def label_point(self, angle: float, out: float = 1.18) -> tuple[float, float, float]:
        """Where the arc's label goes, in the moving frame: `out` times the arc's middle point
        while the arc is short, else the tail piece's middle (fixed in the moving frame)."""
        sign = 1.0 if angle >= 0.0 else -1.0
        u = -0.5 * angle if abs(angle) < self.width else -sign * 0.5 * self.width
        x, y, z = (out * float(c) for c in self.point_at(u))
        return x, y, z


def turn_z_onto(vector: Sequence[float] | np.ndarray) -> tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) of the shortest turn taking +z onto the direction of
    `vector` (3,) (nonzero): `app.kit.draw.widgets.z_onto` of its unit vector."""
    x, y, z = (float(c) for c in vector)
    n = math.sqrt(x * x + y * y + z * z)
    return z_onto((x / n, y / n, z / n))


class FrameArrow:
    """An arrow as a frame turned so that its +z points along the vector, holding an arrow
    along +z: while the vector turns, one small orientation message (sent when its tip moved
    visibly); a visible change of length is sent as the child's z scale (a small message),
    and as new points (the head keeps its size) when the scale would leave 1 ± RESCALE.

    `node` is the frame (its position is the arrow's start, set with `set(start=...)`),
    `arrow` the child `add_arrows` node.  Hidden below MIN_LENGTH or when not `shown`.
    """

    MIN_LENGTH = 1e-3
    RESCALE = 0.05  # the head may grow or shrink by this fraction before the points are resent

    def __init__(self, scene: Any, name: str, color: tuple[int, int, int], *, shaft_radius: float,
                 head_radius: float, head_length: float, tolerance: float = TOLERANCE) -> None:
        self.node = scene.add_frame(name, show_axes=False, visible=False)
        self.arrow = scene.add_arrows(f"{name}/arrow", np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]], dtype=np.float32),
                                      color, shaft_radius=shaft_radius, head_radius=head_radius,
                                      head_length=head_length)
        self.pose = Pose(self.node, reach=1.0, tolerance=tolerance)
        self.tolerance = tolerance
        self.length = math.nan  # drawn [scene units]
        self._base = math.nan  # the length of the child's points (drawn at z scale length / base)

    def set(self, vector: Sequence[float] | np.ndarray, start: Sequence[float] | np.ndarray | None = None,
            shown: bool = True, exact: bool = True) -> None:
        """Draw `vector` (3,) [scene units, parent frame] from `start` (default: where it is),
        snapped to display resolution unless `exact`."""
        length = math.sqrt(sum(float(c) * float(c) for c in vector))
        visible = shown and length > self.MIN_LENGTH
        if self.node.visible != visible:
            self.node.visible = visible
        if not visible:
            return
        self.pose.reach = 2.0  # a fixed grid (a function of the state alone), ~1 px at the tip of a 2-unit arrow
        self.pose.set(turn_z_onto(vector), start, exact=exact)
        if not exact:
            length = snap(length, self.tolerance)
        if length != self.length:
            # The child's length: exact when paused; while playing the nearest of a geometric grid
            # (steps of 2 RESCALE), so the head is within RESCALE of its size and the grid point
            # changes rarely (new points then), the z scale carries the rest.
            grid = 2.0 * self.RESCALE
            base = length if exact else f32(math.exp(grid * round(math.log(length) / grid)))
            if base != self._base:
                set_points(self.arrow, np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, base]]], dtype=np.float32))
                self._base = base
            scale = (1.0, 1.0, f32(length / base))
            if _scale3(self.arrow.scale) != scale:
                self.arrow.scale = scale
            self.length = length

    @property
    def visible(self) -> bool:
        return bool(self.node.visible)

    def world_segment(self) -> np.ndarray:
        """(2, 3) start and tip as drawn, world coordinates."""
        R, p = world_pose(self.arrow)
        segment = np.asarray(self.arrow.points, dtype=float)[0] * np.asarray(_scale3(self.arrow.scale))
        return segment @ R.T + p


def _scale3(scale: Any) -> tuple[float, float, float]:
    """A node's `scale` (a float or a 3-tuple) as a 3-tuple."""
    if isinstance(scale, (int, float)):
        return float(scale), float(scale), float(scale)
    x, y, z = (float(c) for c in scale)
    return x, y, z
