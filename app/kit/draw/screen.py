"""Where a client's 3D labels land on the screen: a pinhole projection and label text boxes.

For checks (tests/test_labels.py) and layout decisions, not for drawing.  A scene's camera is
its `CameraView` (position, look_at, up, vertical fov); the canvas is the whole browser window
(viser's panel floats over it).  A label's world position composes the poses of the nodes
above it (viser names are paths: "/a/b" is a child of "/a"), through the app's one walker of
world poses (`app.viser_internals.node_world`, over the nodes of the client's scene).

A browser's `Screen` is what a label layout needs of it: its camera view, its canvas [px, as the
browser reports them: device pixels] and the rectangle its panel covers there (`panel_box`):
a wide view's floating panel on the right (PANEL_WIDTH_SHARE of the width), a narrow view's
(a phone's: `narrow_size`) bottom sheet (PHONE_PANEL_SHARE of the height), nothing when the panel
is docked beside the canvas (the projector layout: the canvas the browser reports ends where the
panel starts).  `screen_of(camera)` reads one from a viser camera.

Text boxes follow viser 1.1's label renderer (client/src/label/LabelRenderer.tsx and
labelLayout.ts): a "screen" label's em is 12 CSS px times `font_screen_scale` in an 800 px tall
viewport (proportional to the height), its block is padded by 0.2 em, and `anchor` says which
point of the padded block sits at the projected position.  The text width is an estimate
(CHAR_WIDTH_EM per character); "scene"-sized labels are not estimated (none in the app).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from app.kit.core.common import CameraView
from app.viser_internals import node_world, scene_nodes

__all__ = ["ANCHOR_SHIFT", "BODY_CENTRE_SHARE", "BODY_WIDTH_SHARE", "NARROW_ASPECT", "NARROW_MARGIN", "NARROW_PX",
           "PANEL_WIDTH_SHARE", "PHONE_PANEL_SHARE", "WIDE_ASPECT", "Box",
           "LabelBox", "Outline", "Projector", "Screen", "body_centre", "box_at", "boxes_meet", "centred_view",
           "convex_hull", "hull_chain", "label_boxes", "narrow_size", "narrow_view",
           "overlapping", "panel_box", "polygon_meets_box", "project", "project_one", "screen_of", "text_box",
           "text_size"]

REFERENCE_HEIGHT_PX = 800.0  # viser sizes screen labels relative to an 800 px tall viewport
SCREEN_EM_PX = 12.0  # [px] a screen label's em at font_screen_scale 1, at REFERENCE_HEIGHT_PX
CHAR_WIDTH_EM = 0.6  # mean advance of a character of viser's sans font (DejaVu-like) [em]
LINE_HEIGHT_EM = 1.2  # ascent + descent [em]
PADDING_EM = 0.2  # viser's BACKGROUND_PADDING_FRACTION
NEAR = 1e-3  # [scene units] a point this close to the camera plane, or behind it, is not drawn
NARROW_PX = 500  # a view at most this wide [px] is narrow (a phone) ...
NARROW_ASPECT = 0.8  # ... and so is a portrait one (width / height below this)
PANEL_WIDTH_SHARE = 0.31  # a wide view's floating panel: the right 31 % (viser's ~400 px panel of 1280)
PHONE_PANEL_SHARE = 0.28  # a narrow view's bottom sheet (one status line, `Details`): the lowest 28 %
WIDE_ASPECT = 1.6  # the width / height of the wide window a scene's camera view is made for (1280 x 800)
BODY_WIDTH_SHARE = 0.6  # the share of a wide view's width a scene's body is framed in (left of the floating panel)
NARROW_MARGIN = 1.25  # a narrow view is that much farther back than the share's width needs
BODY_CENTRE_SHARE = 0.3  # a scene's body lies this share of the way from the origin to its view's look_at

Box = tuple[float, float, float, float]  # (x0, y0, x1, y1) [px], y down


def narrow_size(width: float, height: float) -> bool:
    """A phone-like view of width x height [px]: at most NARROW_PX wide, or portrait (aspect below
    NARROW_ASPECT).  (viser reports a view's size in device pixels; a phone's CSS width of ~400
    px is 800-1200 of them, which the portrait test catches.)"""
    return (0.0 < width <= NARROW_PX) or (width > 0.0 and height > 0.0 and width / height < NARROW_ASPECT)


def body_centre(view: CameraView) -> tuple[float, float, float]:
    """Where a scene's body is seen, from the scene's camera `view` [scene units]: the scenes put
    their body at the origin and look at a point beside it (framing it left of the floating
    panel), so the body's middle is taken BODY_CENTRE_SHARE of the way from the origin to look_at
    (where the projector layout looks too, `app.hall.projector.projector_view`)."""
    return (BODY_CENTRE_SHARE * view.look_at[0], BODY_CENTRE_SHARE * view.look_at[1],
            BODY_CENTRE_SHARE * view.look_at[2])


def centred_view(view: CameraView, centre: Any, distance: float, panel_share: float = PHONE_PANEL_SHARE) -> CameraView:
    """`view`'s viewing direction, up and fov from `distance` [scene units], aimed so that the world
    point `centre` (3,) projects to the middle of what a narrow window's bottom sheet leaves of it
    (the top 1 - panel_share of its height, horizontally centred): the look-at point lies
    panel_share tan(fov/2) distance below `centre` along the screen's up."""
    eye, target = np.asarray(view.position, dtype=float), np.asarray(view.look_at, dtype=float)
    back = (eye - target) / np.linalg.norm(eye - target)  # from the look-at point to the eye
    up = np.asarray(view.up, dtype=float)
    screen_up = up - (up @ back) * back
    norm = float(np.linalg.norm(screen_up))
    screen_up = screen_up / norm if norm > 1e-9 else np.zeros(3)  # looking along `up`: no lift
    lift = panel_share * math.tan(0.5 * math.radians(view.fov_deg)) * distance
    look_at = np.asarray(centre, dtype=float) - lift * screen_up
    position = look_at + distance * back
    return CameraView(tuple(float(c) for c in position), tuple(float(c) for c in look_at),  # type: ignore[arg-type]
                      view.up, view.fov_deg)


def narrow_view(view: CameraView, aspect: float) -> CameraView:
    """A scene's camera `view` (made for a WIDE_ASPECT window, the body in the left BODY_WIDTH_SHARE
    of its width) for a narrow window of width / height `aspect`: the same direction and fov, the
    body (`body_centre`) in the middle of what the bottom sheet leaves (`centred_view`), from
    BODY_WIDTH_SHARE WIDE_ASPECT / aspect NARROW_MARGIN times the view's distance (so that share's
    width fits the narrow width; never nearer than the view)."""
    distance = float(np.linalg.norm(np.subtract(view.position, view.look_at)))
    factor = BODY_WIDTH_SHARE * WIDE_ASPECT / aspect * NARROW_MARGIN if aspect > 0.0 else 1.0
    return centred_view(view, body_centre(view), distance * max(1.0, factor))


def panel_box(width: int, height: int, docked: bool = False) -> Box | None:
    """The rectangle [px] the panel covers on a width x height canvas: none when it is docked
    beside the canvas (the projector layout), a narrow view's bottom sheet, or a wide view's
    floating panel on the right (see the module docstring)."""
    if docked:
        return None
    if narrow_size(width, height):
        return (0.0, (1.0 - PHONE_PANEL_SHARE) * height, float(width), float(height))
    return ((1.0 - PANEL_WIDTH_SHARE) * width, 0.0, float(width), float(height))


@dataclass(frozen=True)
class Screen:
    """One browser's 3D view as a label layout sees it: the camera `view`, the canvas width x
    height [px] and the `panel`'s rectangle over it [px] (None: nothing covers the canvas)."""

    view: CameraView
    width: int
    height: int
    panel: Box | None = None


def screen_of(camera: Any, docked: bool = False) -> Screen | None:
    """The `Screen` of a browser whose viser camera is `camera` (its panel docked or not); None
    before the browser has reported its camera, or for a degenerate one."""
    try:
        width, height = int(camera.image_width), int(camera.image_height)
        view = CameraView(tuple(float(c) for c in camera.position),  # type: ignore[arg-type]
                          tuple(float(c) for c in camera.look_at),  # type: ignore[arg-type]
                          tuple(float(c) for c in camera.up_direction),  # type: ignore[arg-type]
                          math.degrees(float(camera.fov)))
    except (AssertionError, AttributeError, TypeError, ValueError):  # viser: not reported yet
        return None
    if width <= 0 or height <= 0 or not 0.0 < view.fov_deg < 180.0 or view.position == view.look_at:
        return None
    return Screen(view, width, height, panel_box(width, height, docked))


def boxes_meet(a: Box, b: Box) -> bool:
    """Whether two boxes overlap (touching edges do not)."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def convex_hull(points: Any) -> np.ndarray:
    """The convex hull (M, 2) of points (N, 2) [px], counter-clockwise in (x, y) (Andrew's
    monotone chain); NaN points are dropped."""
    return np.array(hull_chain(np.asarray(points, dtype=float).reshape(-1, 2).tolist()), dtype=float).reshape(-1, 2)


def hull_chain(points: list[list[float]] | list[tuple[float, float]]) -> list[tuple[float, float]]:
    """`convex_hull` on Python floats: the hull's vertices (x, y) [px], counter-clockwise in (x,
    y), of the points (x, y) [px]; non-finite points are dropped (the layout's few points: plain
    arithmetic is cheaper than NumPy's per-call overhead)."""
    pts = sorted({(x, y) for x, y in points if math.isfinite(x) and math.isfinite(y)})
    if len(pts) < 3:
        return pts

    def half(sequence: list[tuple[float, float]]) -> list[tuple[float, float]]:
        chain: list[tuple[float, float]] = []
        for q in sequence:
            while len(chain) >= 2 and ((chain[-1][0] - chain[-2][0]) * (q[1] - chain[-2][1])
                                       - (chain[-1][1] - chain[-2][1]) * (q[0] - chain[-2][0])) <= 0.0:
                chain.pop()
            chain.append(q)
        return chain

    lower, upper = half(pts), half(pts[::-1])
    return lower[:-1] + upper[:-1]


class Outline:
    """The convex hull of points (x, y) [px] (a body's outline on a screen), ready for many box
    tests (`meets`): their bounding box at once; the hull (`hull_chain`) and, per hull edge, its
    normal and the hull's extent along it only when a box first meets the bounding box (most
    labels are far from a body).  Non-finite points are left out."""

    __slots__ = ("_points", "_axes", "bounds")

    def __init__(self, points: list[tuple[float, float]]) -> None:
        finite = [(x, y) for x, y in points if math.isfinite(x) and math.isfinite(y)]
        self._points = finite
        self._axes: list[tuple[float, float, float, float]] | None = None
        xs = [p[0] for p in finite]
        ys = [p[1] for p in finite]
        self.bounds: Box | None = (min(xs), min(ys), max(xs), max(ys)) if finite else None
        """the points' bounding box (x0, y0, x1, y1) [px]; None when there is none"""

    def __bool__(self) -> bool:
        return self.bounds is not None

    @property
    def vertices(self) -> list[tuple[float, float]]:
        """The hull's vertices (x, y) [px], counter-clockwise in (x, y)."""
        return hull_chain(self._points)

    def _edge_axes(self) -> list[tuple[float, float, float, float]]:
        if self._axes is None:
            hull = hull_chain(self._points)
            axes = []
            if len(hull) >= 3:
                for (ax, ay), (bx, by) in zip(hull, hull[1:] + hull[:1]):
                    nx, ny = by - ay, ax - bx
                    along = [nx * x + ny * y for x, y in hull]
                    axes.append((nx, ny, min(along), max(along)))
            self._axes = axes
        return self._axes

    def meets(self, box: Box) -> bool:
        """Whether the hull and the box overlap (separating axes: the box's two, then the hull's
        edge normals); `polygon_meets_box` on Python floats."""
        bounds = self.bounds
        if bounds is None:
            return False
        x0, y0, x1, y1 = box
        b0, c0, b1, c1 = bounds
        if b1 <= x0 or b0 >= x1 or c1 <= y0 or c0 >= y1:
            return False
        for nx, ny, low, high in self._edge_axes():
            lx, hx = (nx * x0, nx * x1) if nx >= 0.0 else (nx * x1, nx * x0)
            ly, hy = (ny * y0, ny * y1) if ny >= 0.0 else (ny * y1, ny * y0)
            if hx + hy <= low or lx + ly >= high:
                return False
        return True


def polygon_meets_box(polygon: np.ndarray, box: Box) -> bool:
    """Whether a convex polygon (M, 2) [px] and a box overlap (separating axes: the box's two
    axes and the polygon's edge normals)."""
    if len(polygon) == 0:
        return False
    x0, y0, x1, y1 = box
    xs, ys = polygon[:, 0], polygon[:, 1]
    if xs.max() <= x0 or xs.min() >= x1 or ys.max() <= y0 or ys.min() >= y1:
        return False
    if len(polygon) < 3:
        return True
    corners = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
    edges = np.roll(polygon, -1, axis=0) - polygon
    normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1)  # one per edge
    on_poly = polygon @ normals.T  # (M, E)
    on_box = corners @ normals.T  # (4, E)
    separated = (on_box.max(axis=0) <= on_poly.min(axis=0)) | (on_box.min(axis=0) >= on_poly.max(axis=0))
    return not bool(np.any(separated))


def project(view: CameraView, points: Any, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Pixel coordinates (N, 2) (x right, y down, origin top-left) and depths (N,) [scene units
    along the view direction] of world points (N, 3) seen by `view` in a width x height window.

    A pinhole camera at view.position looking at view.look_at, `up` projected to the screen's
    up, vertical field of view view.fov_deg (three.js' PerspectiveCamera).  Points with depth
    <= NEAR get NaN pixels.
    """
    p = np.atleast_2d(np.asarray(points, dtype=float))
    camera = Projector(view, width, height)  # the basis on floats: cheaper than NumPy on 3-vectors
    d = p - camera._eye
    basis = np.array((camera._right, camera._up, camera._forward)).T  # (3, 3): columns right, up, forward
    along = d @ basis
    depth = along[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        x = camera._cx + camera._focal * along[:, 0] / depth
        y = camera._cy - camera._focal * along[:, 1] / depth
    pixels = np.stack([x, y], axis=-1)
    pixels[depth <= NEAR] = np.nan
    return pixels, depth


def project_one(view: CameraView, point: Any, width: int, height: int) -> tuple[tuple[float, float], float]:
    """`project` for one point (3,) on Python floats (cheap enough for per-frame layout): its pixel
    (x, y) and depth [scene units]; NaN pixels if depth <= NEAR.  Many points through one view:
    `Projector`."""
    return Projector(view, width, height)(float(point[0]), float(point[1]), float(point[2]))


class Projector:
    """`project` on Python floats for many points seen by one view: the camera basis and the
    focal length are worked out once (a layout projects every label through the same camera);
    `(x, y, z)` gives that world point's pixel and depth (tests/test_screen.py checks
    it against the vectorised `project`)."""

    __slots__ = ("_eye", "_forward", "_right", "_up", "_focal", "_cx", "_cy")

    def __init__(self, view: CameraView, width: int, height: int) -> None:
        ex, ey, ez = view.position
        fx, fy, fz = view.look_at[0] - ex, view.look_at[1] - ey, view.look_at[2] - ez
        norm = math.sqrt(fx * fx + fy * fy + fz * fz)
        fx, fy, fz = fx / norm, fy / norm, fz / norm
        ux, uy, uz = view.up
        rx, ry, rz = fy * uz - fz * uy, fz * ux - fx * uz, fx * uy - fy * ux
        norm = math.sqrt(rx * rx + ry * ry + rz * rz)
        rx, ry, rz = rx / norm, ry / norm, rz / norm
        self._eye = (ex, ey, ez)
        self._forward = (fx, fy, fz)
        self._right = (rx, ry, rz)
        self._up = (ry * fz - rz * fy, rz * fx - rx * fz, rx * fy - ry * fx)  # screen up = right x forward
        self._focal = 0.5 * height / math.tan(0.5 * math.radians(view.fov_deg))  # [px]
        self._cx, self._cy = 0.5 * width, 0.5 * height

    def pixels(self, points: np.ndarray, rotation: np.ndarray | None = None,
               offset: Any = (0.0, 0.0, 0.0)) -> list[tuple[float, float]]:
        """The pixels (x, y) of many points (N, 3) given in a frame whose pose in the world is
        `rotation` (3, 3) and `offset` (3,) [scene units] (world = rotation p + offset; default:
        the world itself), the camera and the pose composed first (one small matmul for all);
        NaN pixels for points with depth <= NEAR."""
        basis = np.array((self._right, self._up, self._forward))  # rows: the camera's axes in the world
        eye = np.asarray(offset, dtype=float) - np.asarray(self._eye)
        shift = basis @ eye
        along = points @ (basis if rotation is None else basis @ rotation).T + shift  # (N, 3): right, up, depth
        focal, cx, cy = self._focal, self._cx, self._cy
        return [(cx + focal * a / d, cy - focal * b / d) if d > NEAR else (math.nan, math.nan)
                for a, b, d in along.tolist()]

    def __call__(self, x: float, y: float, z: float) -> tuple[tuple[float, float], float]:
        """The pixel (x, y) and depth [scene units] of the world point (x, y, z); NaN pixels if
        depth <= NEAR."""
        ex, ey, ez = self._eye
        fx, fy, fz = self._forward
        dx, dy, dz = x - ex, y - ey, z - ez
        depth = dx * fx + dy * fy + dz * fz
        if depth <= NEAR:
            return (math.nan, math.nan), depth
        rx, ry, rz = self._right
        sx, sy, sz = self._up
        focal = self._focal
        return (self._cx + focal * (dx * rx + dy * ry + dz * rz) / depth,
                self._cy - focal * (dx * sx + dy * sy + dz * sz) / depth), depth


@dataclass(frozen=True)
class LabelBox:
    """A label on the screen: name, text, anchor point (x, y) [px], box (x0, y0, x1, y1) [px]."""

    name: str
    text: str
    anchor_px: tuple[float, float]
    box: tuple[float, float, float, float]

    def gap(self, other: LabelBox) -> float:
        """The distance [px] between the two boxes (0 when they touch or overlap), minus overlap
        depth when they overlap (negative)."""
        ax0, ay0, ax1, ay1 = self.box
        bx0, by0, bx1, by1 = other.box
        dx = max(bx0 - ax1, ax0 - bx1)
        dy = max(by0 - ay1, ay0 - by1)
        if dx < 0.0 and dy < 0.0:
            return max(dx, dy)
        return math.hypot(max(dx, 0.0), max(dy, 0.0))


def text_size(text: str, em: float) -> tuple[float, float]:
    """(width, height) [px] of a label's padded text block; em [px] is its font size."""
    lines = text.split("\n")
    w = max(len(line) for line in lines) * CHAR_WIDTH_EM * em + 2.0 * PADDING_EM * em
    h = len(lines) * LINE_HEIGHT_EM * em + 2.0 * PADDING_EM * em
    return w, h


# A label's anchor -> (fx, fy): its block's top-left corner is (x + fx w, y + fy h) for the anchor at (x, y).
ANCHOR_SHIFT = {f"{v}-{h}": (fh, fv) for v, fv in (("top", 0.0), ("center", -0.5), ("bottom", -1.0))
                for h, fh in (("left", 0.0), ("center", -0.5), ("right", -1.0))}


def box_at(anchor: str, x: float, y: float, w: float, h: float) -> tuple[float, float, float, float]:
    """The block (x0, y0, x1, y1) [px] of size (w, h) [px] whose `anchor` ("top-left", ...,
    "center-center", "bottom-right") sits at (x, y) [px]."""
    fh, fv = ANCHOR_SHIFT[anchor]
    x0, y0 = x + fh * w, y + fv * h
    return (x0, y0, x0 + w, y0 + h)


def text_box(anchor: str, x: float, y: float, text: str, em: float) -> tuple[float, float, float, float]:
    """The padded text block (x0, y0, x1, y1) [px] of a label whose `anchor` ("top-left", ...,
    "center-center", "bottom-right") sits at (x, y) [px]; em [px] is its font size."""
    return box_at(anchor, x, y, *text_size(text, em))


def label_boxes(scene: Any, view: CameraView, width: int, height: int) -> list[LabelBox]:
    """The boxes of every label of a client's scene (`client.scene`) that is shown (it and its
    ancestors visible, non-empty text, in front of the camera and inside the window)."""
    handles = scene_nodes(scene)
    poses: dict[str, Any] = {}
    labels = [(name, h) for name, h in handles.items() if type(h).__name__ == "LabelHandle"]
    boxes = []
    for name, handle in labels:
        _, p_world, shown = node_world(name, handles, poses)
        text = str(handle.text)
        if not shown or not text.strip():
            continue
        (x, y), _depth = (v[0] for v in project(view, p_world, width, height))
        if not (0.0 <= x <= width and 0.0 <= y <= height):  # NaN too: behind the camera
            continue
        em = SCREEN_EM_PX * float(handle.font_screen_scale) * height / REFERENCE_HEIGHT_PX
        box = text_box(str(handle.anchor), float(x), float(y), text, em)
        boxes.append(LabelBox(name, text, (float(x), float(y)), box))
    return boxes


def overlapping(boxes: list[LabelBox], min_gap_px: float) -> list[tuple[LabelBox, LabelBox, float]]:
    """Pairs of boxes closer than min_gap_px [px] (overlapping ones have a negative gap)."""
    pairs = []
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            gap = a.gap(b)
            if gap < min_gap_px:
                pairs.append((a, b, gap))
    return pairs
