"""Labels that never overlap: a view's 3D labels shown by priority, on every screen that shows them.

Each view has one `LabelLayer` (`SceneView.labels`).  Every 3D label the view adds is
registered with it once, with a priority (`add(handle, priority)`); who wants it shown says so
through the layer (`want(handle, visible)`), never by writing `handle.visible`, so the layer
and the widgets do not fight.  After the view draws (`update(dt)`, at most every PERIOD of
wall time, and at once on `refresh()` through `settle()`), the layer projects the wanted
labels onto its screens (`app.kit.draw.screen.Screen`: a camera, a canvas, the panel's
rectangle), estimates their text boxes (`app.kit.draw.screen`), and places them greedily,
highest priority first (ties: the order of registration): a label goes at its own anchor, else
at the first of NUDGE_ANCHORS that is free, else it is hidden until there is room.  Free means,
on every screen where its anchor is in the window: inside the window (not cut at its edge), off
the panel's rectangle, clear of the labels placed before it, and, for a label registered
`clear_of_bodies` (the space axes' x y z), off the bodies' outlines (`avoid`: the convex hull of
a body's projected mesh vertices).  Only the label goes: an arrow keeps its colour.

The screens (`screens_now`): the controlling browser's (`target.camera`, its panel docked or not:
`docked`, set by the projector layout); for a presenter's view, drawn once into the shared scene,
the presenter's and its followers' (`screens`, set by the lectern: a phone follower sees the
presenter's picture from farther away, its labels closer together); the scene's `CameraView`
in a 1280x800 window with no panel when there is none (a recording).

A moving label's box is swept from where it is to where it will be at the next layout (its
screen motion since the last layout, Δ, once more), grown on every side by TURN_MARGIN times
how much that motion changed since the layout before (a label going round a circle turns away
from the straight line by exactly that much per layout) plus SLIP_MARGIN times |Δ| (speeding up,
uneven layouts).  So labels do not run into each other between two layouts.  A label's motion
is followed while it is off the window or under a hidden node; one that appears while the
picture moves, its motion not known yet, waits hidden for the next layout.  After a
refresh (an edit, a reset: labels jump) and when a camera moved (a browser orbits, the
view is reset, a follower comes or goes), the labels' motion starts afresh.  (A body axis label
that whizzes round with a fast spin gets a large box and is mostly hidden: it could not be read.)
Only changes are sent: a visibility or an anchor message when it changed, nothing when the
picture stood still.

What a layout cannot move: viser's client places each label from its parent node's world
matrix as of the frame drawn before (its label manager runs before three.js updates the
matrices), so a label riding on a moving frame trails its arrow by one drawn frame: 1/60 s on a
GPU, but at the few frames a second (under load, fewer than one) of headless software WebGL
it sits well behind its arrow while playing, and catches up when the picture stops.  The
layout itself runs every PERIOD while the view draws, on the cameras the browsers report.

World positions come from the app's one walker of world poses (`app.viser_internals.world_point`);
when it is off (SCENE_NODES) every wanted label is shown at its own anchor, with no layout.

Priorities (higher is shown first): POINTER (the presenter's pointer label), KEY (space axes
x y z, the body's vectors ω and L, forces, g), AXES (body axes x′ y′ z′, the line of nodes),
DETAIL (arc readings, titles, intermediate frames, component arrows).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial import ConvexHull

from app.kit.core.common import CameraView, staggered
from app.kit.draw.screen import (
    ANCHOR_SHIFT,
    REFERENCE_HEIGHT_PX,
    SCREEN_EM_PX,
    Box,
    Outline,
    Projector,
    Screen,
    boxes_meet,
    screen_of,
    text_size,
)
from app.viser_internals import (
    SCENE_NODES,
    label_props,
    node_pose,
    node_removed,
    scene_nodes,
    set_position,
    world_point,
)

__all__ = ["AXES", "DETAIL", "KEY", "NUDGE_ANCHORS", "PERIOD", "POINTER", "LabelLayer", "Screen"]

POINTER = 4  # the presenter's pointer label: what the lecturer points at now
KEY = 3  # space axes, ω, L, forces, gravity: what a lecture talks about
AXES = 2  # body axes x′ y′ z′, the line of nodes
DETAIL = 1  # readings on arcs, titles, intermediate frames, component arrows

PERIOD = 0.1  # [s] of wall time between two layouts while the view draws (10 Hz); the layers take
# turns (`staggered`): many browsers' layouts fall into different frames
BUDGET = 150.0  # layouts a second shared by every own room's layer of the process (a layout of a
# free body's labels costs ~0.6 ms: at most ~10 % of a core); a presenter's shared scene is not in it
FALLBACK_SIZE_PX = (1280, 800)  # the window assumed when the view has no browser camera
MIN_GAP_FRACTION = 6.0 / 800.0  # two boxes keep this share of the window height apart (6 px at 800)
TURN_MARGIN = 1.5  # times |Δ now − Δ before| [px]: the bend of the path over the next layout interval
SLIP_MARGIN = 0.25  # times |Δ| [px]: a label speeding up, a layout coming late
SLIDE_FACTORS = (1.0, 1.3, 1.6, 2.0)  # a label kept off the bodies may slide this far out from its parent's origin
HULL_POINTS = 64  # a body's outline is the projected hull of at most this many vertices per pose of its meshes
NUDGE_ANCHORS = ("bottom-left", "top-left", "bottom-right", "top-right", "center-left", "center-right",
                 "bottom-center", "top-center")  # tried in this order when a label's own anchor is taken


@dataclass
class _Entry:
    handle: Any
    priority: float
    order: int
    anchor: str  # the label's own anchor (as built)
    nudge: bool
    wanted: bool
    clear_of_bodies: bool = False  # kept off the bodies' outlines (`LabelLayer.avoid`); it may slide out
    home: tuple[float, float, float] = (0.0, 0.0, 0.0)  # its position as built, in its parent's frame
    slid: float = 1.0  # its position now is `home` times this (SLIDE_FACTORS)
    # Per screen of the last layout: where it was then [px] and how it moved before that layout [px]
    # (None where it was off that screen or its motion is not known yet).
    last_px: list[tuple[float, float] | None] | None = field(default=None)
    last_step: list[tuple[float, float] | None] | None = field(default=None)
    # Fixed at registration, for the layout's hot loop: the parent node's name, the anchors tried
    # in order (its own first) with their box shifts, the sort rank.
    parent: str = ""
    tries: tuple[tuple[str, float, float], ...] = ()
    rank: tuple[float, int] = (0.0, 0)
    # The text block's size [em] for the text it was last worked out for.
    size_of: str | None = field(default=None)
    size: tuple[float, float] = (0.0, 0.0)
    blank: bool = False  # that text is only white space

    def __post_init__(self) -> None:
        self.parent = str(self.handle.name).rsplit("/", 1)[0]
        anchors = (self.anchor, *(a for a in NUDGE_ANCHORS if a != self.anchor)) if self.nudge else (self.anchor,)
        self.tries = tuple((a, *ANCHOR_SHIFT[a]) for a in anchors)
        self.rank = (-self.priority, self.order)


def _clear(box: Box, placed: list[Box], gap: float) -> bool:
    """Whether `box` keeps at least `gap` [px] from every placed box (their distance, or minus
    their overlap when they overlap)."""
    # Plain comparisons (the hot loop of a layout); gap > 0.  dx, dy: the boxes' distance apart
    # along x and along y (negative: they overlap along that axis).  Far enough apart along one
    # axis: clear of that box.  Else, overlapping or apart along one axis only (their distance is
    # then that one, < gap): too close; apart along both: their corners' distance decides.
    x0, y0, x1, y1 = box
    for b0, c0, b1, c1 in placed:
        dx = b0 - x1
        t = x0 - b1
        if t > dx:
            dx = t
        if dx >= gap:
            continue
        dy = c0 - y1
        t = y0 - c1
        if t > dy:
            dy = t
        if dy >= gap:
            continue
        if dx <= 0.0 or dy <= 0.0 or math.hypot(dx, dy) < gap:
            return False
    return True


_STILL = (0.0, 0.0, 0.0)  # a sweep (dx, dy, margin) [px] of a label whose motion is not known

Spot = tuple[float, float, float, float, bool]  # a label's anchor x, y and block w, h [px] on a screen; in its window


def _xyz(v: Any) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _swept_box(where: Spot, fh: float, fv: float,
               sweep: tuple[float, float, float]) -> Box:
    """A label's block at (x, y) [px] of size (w, h) [px] (`where`) with its anchor's shift (fh,
    fv), swept by (dx, dy) and grown by `margin` [px] on every side (`sweep`)."""
    x, y, w, h, _inside = where
    dx, dy, margin = sweep
    x0, y0 = x + fh * w, y + fv * h
    x1, y1 = x0 + w, y0 + h
    if dx < 0.0:
        x0 += dx
    else:
        x1 += dx
    if dy < 0.0:
        y0 += dy
    else:
        y1 += dy
    return (x0 - margin, y0 - margin, x1 + margin, y1 + margin)


_MESH_TYPES: dict[type, bool] = {}  # node handle type -> whether it has vertices (a mesh)


def _is_mesh(handle: Any) -> bool:
    kind = type(handle)
    known = _MESH_TYPES.get(kind)
    if known is None:
        known = _MESH_TYPES[kind] = hasattr(handle, "vertices")
    return known


def _matrix(wxyz: tuple[float, float, float, float]) -> np.ndarray:
    """The rotation matrix (3, 3) of the quaternion (w, x, y, z) (normalised here)."""
    w, x, y, z = wxyz
    n = 2.0 / (w * w + x * x + y * y + z * z)
    return np.array(((1.0 - n * (y * y + z * z), n * (x * y - w * z), n * (x * z + w * y)),
                     (n * (x * y + w * z), 1.0 - n * (x * x + z * z), n * (y * z - w * x)),
                     (n * (x * z - w * y), n * (y * z + w * x), 1.0 - n * (x * x + y * y))))


def _key(screens: list[Screen], seen: list[tuple[int, str, list[Spot | None]]]) -> list[Any]:
    """What a layout saw, to tell whether anything changed since the last: the screens and per
    label its order, text and per screen its anchor's pixel rounded to 0.1 px."""
    return [screens, *((order, text, tuple(None if w is None else (round(w[0], 1), round(w[1], 1)) for w in where))
                       for order, text, where in seen)]


class _Share:
    """The own rooms' layers that drew in the last second of wall time: their layouts share
    BUDGET, each at most every max(PERIOD, layers / BUDGET) [s] (80 rooms of one process: 0.53 s)."""

    def __init__(self) -> None:
        self._seen: dict[int, float] = {}  # id(layer) -> when it last drew (time.monotonic)
        self._counted_at = -math.inf
        self._layers = 0

    def period(self, layer: object) -> float:
        now = time.monotonic()
        self._seen[id(layer)] = now
        if len(self._seen) > self._layers or now - self._counted_at >= 0.5:  # a new one; the gone ones
            self._counted_at = now
            self._seen = {k: t for k, t in self._seen.items() if now - t < 1.0}
            self._layers = len(self._seen)
        return max(PERIOD, self._layers / BUDGET)


_SHARE = _Share()


def _rank(candidate: tuple[Any, ...]) -> tuple[float, int]:
    """The placing order: priority, highest first, then the order of registration."""
    return candidate[0].rank


class LabelLayer:
    """One view's labels, shown by priority so that none overlap (see the module docstring).

    Args:
        camera: the controlling browser's camera (viser `CameraHandle`), or None.
        fallback: the view used when there is no camera (or it has not reported yet), seen in a
            FALLBACK_SIZE_PX window.
    """

    def __init__(self, camera: Any, fallback: CameraView,
                 screens: Callable[[], Sequence[Screen | None]] | None = None) -> None:
        self.camera = camera
        self.fallback = fallback
        self.screens = screens
        """The screens to lay out for (a presenter's shared scene: its own and its followers'), or
        None: the controlling browser's (`camera`)."""
        self.docked: Callable[[], bool] = lambda: False
        """Whether the controlling browser's panel is docked beside its canvas (the projector
        layout sets it): nothing then covers the canvas."""
        self._bodies: list[tuple[Any, str]] = []  # (scene, root): meshes under root are bodies
        # by the ids of meshes at one pose: (their vertex arrays, hull points in their frame)
        self._hulls: dict[tuple[int, ...], tuple[tuple[Any, ...], np.ndarray | None]] = {}
        self._last_screens: list[Screen] | None = None
        self._projectors: list[Projector] = []  # one per screen of `_last_screens`
        self._entries: dict[int, _Entry] = {}  # by id(handle)
        self._throttle = staggered(PERIOD)
        self._last_key: Any = None  # what the last layout saw (camera, boxes, wants)
        self._moving = False  # the last layout grew some box for its label's motion
        self._settling = False  # a layout after a refresh: every label placed at once
        self.layouts = 0  # layouts computed (tests)

    # ------------------------------------------------------------------ registration
    def add(self, handle: Any, priority: float, *, wanted: bool | None = None, nudge: bool = True,
            clear_of_bodies: bool = False) -> Any:
        """Register a label (a viser LabelHandle) with its priority (POINTER, KEY, AXES, DETAIL or
        any number: higher is shown first); returns the handle.

        wanted: whether it should be shown when there is room (default: its visibility now).
        nudge: whether it may move to another anchor (NUDGE_ANCHORS) before it is hidden.
        clear_of_bodies: kept off the bodies' outlines (`avoid`): a space axis label, which
            says nothing about the body it would sit on.
        """
        anchor = str(handle.anchor)
        self._entries[id(handle)] = _Entry(handle, float(priority), len(self._entries), anchor, nudge,
                                           bool(handle.visible) if wanted is None else bool(wanted),
                                           bool(clear_of_bodies), _xyz(handle.position))
        self._last_key = None
        return handle

    def avoid(self, scene: Any, root: str) -> None:
        """The meshes under the node `root` of `scene` are a body: labels registered with
        clear_of_bodies stay off its outline on the screen (the convex hull of its projected
        vertices)."""
        self._bodies.append((scene, root))
        self._last_key = None

    def __contains__(self, handle: Any) -> bool:
        return id(handle) in self._entries

    def want(self, handle: Any, visible: bool) -> None:
        """Whether the label should be shown when there is room.  Hidden at once; shown at the
        next layout (which checks it has room).  KeyError for a label never registered."""
        entry = self._entries.get(id(handle))
        if entry is None:
            raise KeyError(f"the label {handle.name!r} is not registered with the view's LabelLayer")
        visible = bool(visible)
        if entry.wanted == visible:
            return
        entry.wanted = visible
        self._last_key = None
        if not visible:
            self._show(entry, False)

    def wanted(self, handle: Any) -> bool:
        return self._entries[id(handle)].wanted

    # ------------------------------------------------------------------ layout
    def update(self, dt: float) -> None:
        """After the view drew a frame (dt [s] of wall time): lay the labels out, at most every
        PERIOD (an own room's layer: longer when the process's rooms would lay out more than
        BUDGET times a second together), if anything moved since the last layout."""
        if self.screens is None:
            self._throttle.period = _SHARE.period(self)
        if self._throttle.ready(dt):
            self._lay_out()

    def settle(self) -> None:
        """Lay the labels out now, after a refresh (an edit, a step, a reset, a new preset): the
        labels may have jumped, so their motion so far says nothing about the next frames."""
        self._forget_motion()
        self._settling = True
        try:
            self._lay_out()
        finally:
            self._settling = False

    def _forget_motion(self) -> None:
        for entry in self._entries.values():
            entry.last_px = entry.last_step = None
        self._last_key = None

    def _lay_out(self) -> None:
        if not SCENE_NODES.on:  # no walker of world poses (app.viser_internals): no layout
            for entry in self._entries.values():
                self._show(entry, entry.wanted)
            return
        screens = self.screens_now()
        if screens != self._last_screens:
            if self._last_screens is None or len(screens) != len(self._last_screens) or any(
                    (a.view, a.width, a.height) != (b.view, b.width, b.height)
                    for a, b in zip(screens, self._last_screens)):
                self._forget_motion()  # a camera moved (an orbit, a reset, a follower): the labels jumped
            self._last_screens = screens
            self._projectors = [Projector(s.view, s.width, s.height) for s in screens]
        n = len(screens)
        projectors = self._projectors
        em_per_scale = [SCREEN_EM_PX * s.height / REFERENCE_HEIGHT_PX for s in screens]
        gaps = [MIN_GAP_FRACTION * s.height for s in screens]

        def spot(point: Any, entry: _Entry, font_scale: float) -> list[Spot | None]:
            """Per screen, a label's anchor (x, y) and block size (w, h) [px] at the world `point`
            and whether the anchor is in the window (elsewhere it takes no room, but its motion
            is followed); None where it is behind the camera."""
            where: list[Spot | None] = []
            for k in range(n):
                (x, y), depth = projectors[k](*point)
                if not depth > 0.0 or not (math.isfinite(x) and math.isfinite(y)):
                    where.append(None)
                    continue
                screen = screens[k]
                em = em_per_scale[k] * font_scale
                where.append((x, y, entry.size[0] * em, entry.size[1] * em,
                              0.0 <= x <= screen.width and 0.0 <= y <= screen.height))
            return where

        # entry, per screen where it is at its own place (`spot`), and for a label that may slide
        # out (`clear_of_bodies`): its parent's origin and its own place in the world, its font scale.
        candidates: list[tuple[_Entry, list[Spot | None], tuple[Any, Any, float] | None]] = []
        seen: list[tuple[int, str, list[Spot | None]]] = []  # what this layout sees: the key below
        poses: dict[str, Any] = {}  # the parents' world poses, shared by the labels of this layout
        for entry in list(self._entries.values()):
            handle = entry.handle
            if node_removed(handle):  # removed with its view or a rebuilt part
                del self._entries[id(handle)]
                continue
            if not entry.wanted:  # no pose to work out
                self._show(entry, False)
                entry.last_px = entry.last_step = None
                continue
            placed_at = world_point(handle, poses, entry.parent)
            if placed_at is None:  # removed meanwhile
                continue
            point, shown = placed_at
            text, font_scale, _anchor, _visible = label_props(handle)
            text = str(text)
            if entry.size_of != text:  # the text changed: its block's size per em anew
                entry.size_of, entry.size, entry.blank = text, text_size(text, 1.0), not text.strip()
            if entry.blank:
                self._show(entry, False)
                entry.last_px = entry.last_step = None
                continue
            slide = None
            if entry.clear_of_bodies and entry.parent in poses:  # its place as built, in the world
                origin = poses[entry.parent][1]
                point = tuple(o + (p - o) / entry.slid for p, o in zip(point, origin))
                slide = (origin, point, float(font_scale))
            where = spot(point, entry, float(font_scale))
            if not shown:  # under a hidden node (an arrow too short to draw): followed, not shown
                where = [None if w is None else (*w[:4], False) for w in where]
            if all(w is None for w in where):  # behind every camera
                self._show(entry, False)
                entry.last_px = entry.last_step = None
                continue
            candidates.append((entry, where, slide))
            seen.append((entry.order, text, where))
        key = None
        if not self._moving:  # (a moving picture is laid out anyway: no key needed)
            key = _key(screens, seen)
            if key == self._last_key:
                return  # nothing moved since a layout that had nothing moving either
        was_moving, self._moving = self._moving, False
        self.layouts += 1
        placed: list[list[Box]] = [[] for _ in range(n)]
        bodies = self._body_outlines(projectors, poses) if any(c[0].clear_of_bodies for c in candidates) else None
        candidates.sort(key=_rank)
        for entry, where, slide in candidates:
            # Where it will be at the next layout, and how far it may stray from the straight way there.
            last_px, last_step = entry.last_px, entry.last_step
            if last_px is not None and len(last_px) != n:
                last_px = None
            if last_step is not None and len(last_step) != n:
                last_step = None
            sweeps: list[tuple[float, float, float]] = []  # per screen: dx, dy, margin [px]
            now_px: list[tuple[float, float] | None] = []
            now_step: list[tuple[float, float] | None] = []
            known = inside = False  # it was somewhere at the last layout; its anchor is in a window now
            for k in range(n):
                now, before = where[k], (last_px[k] if last_px is not None else None)
                if before is not None:
                    known = True
                if now is None:
                    sweeps.append(_STILL)
                    now_px.append(None)
                    now_step.append(None)
                    continue
                if now[4]:
                    inside = True
                now_px.append((now[0], now[1]))
                if before is None:
                    sweeps.append(_STILL)
                    now_step.append(None)
                    continue
                dx, dy = now[0] - before[0], now[1] - before[1]
                step = last_step[k] if last_step is not None else None
                bend = math.hypot(dx - step[0], dy - step[1]) if step is not None else 0.0
                margin = TURN_MARGIN * bend + SLIP_MARGIN * math.hypot(dx, dy)
                if margin > 0.0:
                    self._moving = True
                sweeps.append((dx, dy, margin))
                now_step.append((dx, dy))
            # Its step is known only from its second layout on: a label that just appeared (or
            # just started moving) is not taken to have turned from standing still.
            entry.last_px, entry.last_step = now_px, now_step
            if not inside:  # off every window or hidden: followed
                self._show(entry, False)
                continue
            if not known and was_moving and not self._settling:
                # It (re)appears in a moving picture: its motion is known at the next layout, and
                # only then is its box swept; till then (PERIOD) it waits, hidden.
                self._show(entry, False)
                self._moving = True
                continue
            # Its own place, then (a label that may slide) farther out from its parent's origin
            # along the same line (an axis label beyond a body over the axis' tip); at each, its
            # own anchor, then the others in a fixed order: the same picture for the same positions.
            for factor in (SLIDE_FACTORS if slide is not None else (1.0,)):
                if factor == 1.0 or slide is None:
                    here = where
                else:
                    origin, home, font_scale = slide
                    here = spot(tuple(o + factor * (h - o) for h, o in zip(home, origin)), entry, font_scale)
                anchor = self._first_free(entry, here, sweeps, screens, placed, gaps,
                                          bodies if entry.clear_of_bodies else None)
                if anchor is not None:
                    break
            if anchor is None:
                self._show(entry, False)
                continue
            if slide is not None and factor != entry.slid:
                entry.slid = factor
                home_local = entry.home
                set_position(entry.handle, (factor * home_local[0], factor * home_local[1], factor * home_local[2]))
            if label_props(entry.handle)[2] != anchor:
                entry.handle.anchor = anchor
            self._show(entry, True)

        # The next layout compares what it sees with this one's only if nothing moved here.
        self._last_key = None if self._moving else (key if key is not None else _key(screens, seen))

    def _first_free(self, entry: _Entry, where: list[Spot | None],
                    sweeps: list[tuple[float, float, float]], screens: Sequence[Screen], placed: list[list[Box]],
                    gaps: list[float], bodies: list[list[Outline]] | None) -> str | None:
        """The first of the label's anchors (`entry.tries`) at which its swept boxes fit on every
        screen where it is (`_room_for`), those boxes then taken (`placed`); None if none does."""
        if not any(w is not None and w[4] for w in where):
            return None
        for anchor, fh, fv in entry.tries:
            boxes: list[Box | None] = []
            for k, at in enumerate(where):
                box = _swept_box(at, fh, fv, sweeps[k]) if at is not None and at[4] else None
                if box is not None and not self._room_for(box, screens[k], placed[k], gaps[k],
                                                          bodies[k] if bodies else ()):
                    break
                boxes.append(box)
            else:
                for k, box in enumerate(boxes):
                    if box is not None:
                        placed[k].append(box)
                return anchor
        return None

    @staticmethod
    def _room_for(box: Box, screen: Screen, placed: list[Box], gap: float, bodies: Sequence[Outline]) -> bool:
        """Whether a label's box fits on `screen`: inside its window, off its panel, clear of the
        labels placed there and of the bodies' outlines `bodies` (convex polygons [px])."""
        if box[0] < 0.0 or box[1] < 0.0 or box[2] > screen.width or box[3] > screen.height:
            return False  # it would be cut at the window's edge
        panel = screen.panel
        if panel is not None and boxes_meet(box, (panel[0] - gap, panel[1] - gap, panel[2] + gap, panel[3] + gap)):
            return False  # on the panel, or closer to it than to another label
        if any(outline.meets(box) for outline in bodies):
            return False
        return _clear(box, placed, gap)

    def _body_outlines(self, projectors: Sequence[Projector], poses: dict[str, Any]) -> list[list[Outline]]:
        """Per screen (its `Projector`), the outlines (convex polygons [px]) of the bodies
        (`avoid`): a body's is the convex hull of its shown meshes' hull points (`_body_points`)
        projected onto that screen.  poses: the world poses of this layout (`node_pose`), shared
        with the labels'."""
        outlines: list[list[Outline]] = [[] for _ in projectors]
        for scene, root in list(self._bodies):
            for points, rotation, offset in self._body_points(scene, root, poses):
                for k, projector in enumerate(projectors):
                    outline = Outline(projector.pixels(points, rotation, offset))
                    if outline:
                        outlines[k].append(outline)
        return outlines

    def _body_points(self, scene: Any, root: str, poses: dict[str, Any]) -> list[tuple[np.ndarray, np.ndarray, Any]]:
        """The points whose projected hull is the outline of the body under `root`: per pose of
        its shown meshes, their hull points (N, 3) in that frame (`_hull_points`: the meshes at
        one pose taken together, a box's three face meshes are its 8 corners once), and that
        frame's rotation (3, 3) and position (3,) [scene units] in the world."""
        groups: dict[tuple[Any, Any], list[Any]] = {}
        prefix = root + "/"
        for name, handle in scene_nodes(scene).items():
            if not name.startswith(prefix) or not _is_mesh(handle):
                continue
            pose = node_pose(handle, poses)
            if pose is None or not pose[2]:  # removed, or it or a node above it hidden
                continue
            groups.setdefault((pose[0], pose[1]), []).append(handle)
        parts = []
        for (wxyz, at), handles in groups.items():
            points = self._hull_points(handles)
            if points is not None:
                parts.append((points, _matrix(wxyz), at))
        return parts

    def _hull_points(self, handles: list[Any]) -> np.ndarray | None:
        """At most HULL_POINTS of the mesh nodes' vertices (N, 3) in their (common) frame, on the
        convex hull of them all (worked out once per set of vertex arrays); None if they are empty."""
        key = tuple(id(h) for h in handles)
        arrays = tuple(h.vertices for h in handles)
        cached = self._hulls.get(key)
        if cached is not None and len(cached[0]) == len(arrays) and all(
                a is b for a, b in zip(cached[0], arrays)):
            return cached[1]
        points = np.concatenate([np.asarray(v, dtype=float).reshape(-1, 3) for v in arrays])
        if len(points) == 0:
            self._hulls[key] = (arrays, None)
            return None
        points = np.unique(points, axis=0)
        if len(points) > 4:
            try:
                points = points[ConvexHull(points).vertices]
            except Exception:  # noqa: BLE001 - flat or degenerate: all its points
                pass
        if len(points) > HULL_POINTS:
            points = points[np.linspace(0, len(points) - 1, HULL_POINTS).astype(int)]
        self._hulls[key] = (arrays, points)
        return points

    def screens_now(self) -> list[Screen]:
        """The screens the labels are laid out for now: `screens()` if set (a presenter's shared
        scene: its own and its followers'), else the controlling browser's (`camera`, its panel
        `docked()` or not); the fallback view in a FALLBACK_SIZE_PX window with no panel when
        there is none (a recording, a browser that has not reported its camera)."""
        screens: list[Screen] = []
        if self.screens is not None:
            screens = [s for s in self.screens() if s is not None]
        elif self.camera is not None:
            own = screen_of(self.camera, docked=bool(self.docked()))
            if own is not None:
                screens = [own]
        return screens or [Screen(self.fallback, *FALLBACK_SIZE_PX)]

    @staticmethod
    def _show(entry: _Entry, visible: bool) -> None:
        if bool(label_props(entry.handle)[3]) != visible:
            entry.handle.visible = visible
