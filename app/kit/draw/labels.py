"""Labels that never overlap: a view's 3D labels shown by priority, through the view's camera.

Each view has one `LabelLayer` (`SceneView.labels`).  Every 3D label the view adds is
registered with it once, with a priority (`add(handle, priority)`); who wants it shown says so
through the layer (`want(handle, visible)`), never by writing `handle.visible`, so the layer
and the widgets do not fight.  After the view draws (`update(dt)`, at most every PERIOD of
wall time, and at once on `refresh()` through `settle()`), the layer projects the wanted
labels through the camera of the browser that controls the view (`target.camera`; the scene's
`CameraView` at 1280x800 when there is none, e.g. a recording), estimates their text boxes
(`app.kit.draw.screen`), and places them greedily, highest priority first (ties: the order of
registration): a label goes at its own anchor, else at the first of NUDGE_ANCHORS that is free,
else it is hidden until there is room.  Only the label goes: an arrow keeps its colour.

A moving label's box is swept from where it is to where it will be at the next layout (its
screen motion since the last layout, Δ, once more), grown on every side by TURN_MARGIN times
how much that motion changed since the layout before (a label going round a circle turns away
from the straight line by exactly that much per layout) plus SLIP_MARGIN times |Δ| (speeding up,
uneven layouts).  So labels do not run into each other between two layouts.  After a
refresh (an edit, a reset: labels jump) and when the camera moved (the browser orbits, the
view is reset), the labels' motion starts afresh.  (A body axis label
that whizzes round with a fast spin gets a large box and is mostly hidden: it could not be read.)
Only changes are sent: a visibility or an anchor message when it changed, nothing when the
picture stood still.

World positions come from the app's one walker of world poses (`app.viser_internals.world_point`);
when it is off (SCENE_NODES) every wanted label is shown at its own anchor, with no layout.

Priorities (higher is shown first): KEY (space axes x y z, the body's vectors ω and L, forces,
g), AXES (body axes x′ y′ z′, the line of nodes), DETAIL (arc readings, titles, intermediate
frames, component arrows).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from app.kit.core.common import CameraView, staggered
from app.kit.draw.screen import ANCHOR_SHIFT, REFERENCE_HEIGHT_PX, SCREEN_EM_PX, Projector, text_size
from app.viser_internals import SCENE_NODES, label_props, node_removed, world_point

__all__ = ["AXES", "DETAIL", "KEY", "NUDGE_ANCHORS", "PERIOD", "LabelLayer"]

KEY = 3  # space axes, ω, L, forces, gravity: what a lecture talks about
AXES = 2  # body axes x′ y′ z′, the line of nodes
DETAIL = 1  # readings on arcs, titles, intermediate frames, component arrows

PERIOD = 0.1  # [s] of wall time between two layouts while the view draws (10 Hz); the layers take
# turns (`staggered`): many browsers' layouts fall into different frames
FALLBACK_SIZE_PX = (1280, 800)  # the window assumed when the view has no browser camera
MIN_GAP_FRACTION = 6.0 / 800.0  # two boxes keep this share of the window height apart (6 px at 800)
TURN_MARGIN = 1.5  # times |Δ now − Δ before| [px]: the bend of the path over the next layout interval
SLIP_MARGIN = 0.25  # times |Δ| [px]: a label speeding up, a layout coming late
NUDGE_ANCHORS = ("bottom-left", "top-left", "bottom-right", "top-right", "center-left", "center-right",
                 "bottom-center", "top-center")  # tried in this order when a label's own anchor is taken

Box = tuple[float, float, float, float]  # (x0, y0, x1, y1) [px], y down


@dataclass
class _Entry:
    handle: Any
    priority: float
    order: int
    anchor: str  # the label's own anchor (as built)
    nudge: bool
    wanted: bool
    last_px: tuple[float, float] | None = field(default=None)  # where it was at the last layout
    last_step: tuple[float, float] | None = field(default=None)  # how it moved before that layout [px]
    # Fixed at registration, for the layout's hot loop: the parent node's name, the anchors tried
    # in order (its own first) with their box shifts, the sort rank.
    parent: str = ""
    tries: tuple[tuple[str, float, float], ...] = ()
    rank: tuple[float, int] = (0.0, 0)
    # The text block's size [px] for the text and em it was last worked out for.
    size_of: tuple[str, float] | None = field(default=None)
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


def _rank(candidate: tuple[_Entry, float, float, float, float]) -> tuple[float, int]:
    """The placing order: priority, highest first, then the order of registration."""
    return candidate[0].rank


class LabelLayer:
    """One view's labels, shown by priority so that none overlap (see the module docstring).

    Args:
        camera: the controlling browser's camera (viser `CameraHandle`), or None.
        fallback: the view used when there is no camera (or it has not reported yet), seen in a
            FALLBACK_SIZE_PX window.
    """

    def __init__(self, camera: Any, fallback: CameraView) -> None:
        self.camera = camera
        self.fallback = fallback
        self._entries: dict[int, _Entry] = {}  # by id(handle)
        self._throttle = staggered(PERIOD)
        self._last_key: Any = None  # what the last layout saw (camera, boxes, wants)
        self._moving = False  # the last layout grew some box for its label's motion
        self._last_view: tuple[CameraView, int, int] | None = None
        self.layouts = 0  # layouts computed (tests)

    # ------------------------------------------------------------------ registration
    def add(self, handle: Any, priority: float, *, wanted: bool | None = None, nudge: bool = True) -> Any:
        """Register a label (a viser LabelHandle) with its priority (KEY, AXES, DETAIL or any
        number: higher is shown first); returns the handle.

        wanted: whether it should be shown when there is room (default: its visibility now).
        nudge: whether it may move to another anchor (NUDGE_ANCHORS) before it is hidden.
        """
        anchor = str(handle.anchor)
        self._entries[id(handle)] = _Entry(handle, float(priority), len(self._entries), anchor, nudge,
                                           bool(handle.visible) if wanted is None else bool(wanted))
        self._last_key = None
        return handle

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
        PERIOD, if anything moved since the last layout."""
        if self._throttle.ready(dt):
            self._lay_out()

    def settle(self) -> None:
        """Lay the labels out now, after a refresh (an edit, a step, a reset, a new preset): the
        labels may have jumped, so their motion so far says nothing about the next frames."""
        self._forget_motion()
        self._lay_out()

    def _forget_motion(self) -> None:
        for entry in self._entries.values():
            entry.last_px = entry.last_step = None
        self._last_key = None

    def _lay_out(self) -> None:
        if not SCENE_NODES.on:  # no walker of world poses (app.viser_internals): no layout
            for entry in self._entries.values():
                self._show(entry, entry.wanted)
            return
        view, width, height = self._view()
        if (view, width, height) != self._last_view:
            self._last_view = (view, width, height)
            self._forget_motion()  # the camera moved (an orbit, a reset): the labels jumped on the screen
        em_per_scale = SCREEN_EM_PX * height / REFERENCE_HEIGHT_PX
        gap = MIN_GAP_FRACTION * height
        project = Projector(view, width, height)
        candidates: list[tuple[_Entry, float, float, float, float]] = []  # entry, x, y, w, h [px]
        key: list[Any] = [view, width, height]
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
            em = em_per_scale * float(font_scale)
            if entry.size_of != (text, em):  # the text or the window changed: its block's size anew
                entry.size_of, entry.size, entry.blank = (text, em), text_size(text, em), not text.strip()
            if not shown or entry.blank:
                self._show(entry, False)
                entry.last_px = entry.last_step = None
                continue
            (x, y), depth = project(*point)
            if not depth > 0.0 or not (math.isfinite(x) and math.isfinite(y)):
                self._show(entry, False)  # behind the camera
                entry.last_px = entry.last_step = None
                continue
            w, h = entry.size
            candidates.append((entry, x, y, w, h))
            key.append((entry.order, round(x, 1), round(y, 1), text))
        if key == self._last_key and not self._moving:
            return  # nothing moved since a layout that had nothing moving either
        self._last_key = key
        self._moving = False
        self.layouts += 1
        placed: list[Box] = []
        candidates.sort(key=_rank)
        for entry, x, y, w, h in candidates:
            # Where it will be at the next layout, and how far it may stray from the straight way there.
            last_px, last_step = entry.last_px, entry.last_step
            dx, dy = (x - last_px[0], y - last_px[1]) if last_px is not None else (0.0, 0.0)
            bend = math.hypot(dx - last_step[0], dy - last_step[1]) if last_step is not None else 0.0
            margin = TURN_MARGIN * bend + SLIP_MARGIN * math.hypot(dx, dy)
            # Its step is known only from its second layout on: a label that just appeared (or
            # just started moving) is not taken to have turned from standing still.
            entry.last_px, entry.last_step = (x, y), ((dx, dy) if last_px is not None else None)
            if margin > 0.0:
                self._moving = True
            # Its own anchor, then the others in a fixed order: the same picture for the same positions.
            for anchor, fh, fv in entry.tries:
                # box_at's block, swept by (dx, dy): (min(x0, x0 + dx), ..., max(x1, x1 + dx), ...)
                # grown by the margin (the branch picks the same float as min/max).
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
                box = (x0 - margin, y0 - margin, x1 + margin, y1 + margin)
                if _clear(box, placed, gap):
                    placed.append(box)
                    if label_props(entry.handle)[2] != anchor:
                        entry.handle.anchor = anchor
                    self._show(entry, True)
                    break
            else:
                self._show(entry, False)

    def _view(self) -> tuple[CameraView, int, int]:
        """The camera the labels are seen through and its window [px]."""
        camera = self.camera
        if camera is not None:
            try:
                width, height = int(camera.image_width), int(camera.image_height)
                view = CameraView(tuple(float(c) for c in camera.position),  # type: ignore[arg-type]
                                  tuple(float(c) for c in camera.look_at),  # type: ignore[arg-type]
                                  tuple(float(c) for c in camera.up_direction),  # type: ignore[arg-type]
                                  math.degrees(float(camera.fov)))
            except AssertionError:  # viser: the browser has not sent its camera yet
                pass
            else:
                if width > 0 and height > 0 and 0.0 < view.fov_deg < 180.0 and view.position != view.look_at:
                    return view, width, height
        return self.fallback, *FALLBACK_SIZE_PX

    @staticmethod
    def _show(entry: _Entry, visible: bool) -> None:
        if bool(entry.handle.visible) != visible:
            entry.handle.visible = visible
