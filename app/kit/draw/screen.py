"""Where a client's 3D labels land on the screen: a pinhole projection and label text boxes.

For checks (tests/test_labels.py) and layout decisions, not for drawing.  A scene's camera is
its `CameraView` (position, look_at, up, vertical fov); the canvas is the whole browser window
(viser's panel floats over it).  A label's world position composes the poses of the nodes
above it (viser names are paths: "/a/b" is a child of "/a"), through the app's one walker of
world poses (`app.viser_internals.node_world`, over the nodes of the client's scene).

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

__all__ = ["ANCHOR_SHIFT", "LabelBox", "Projector", "box_at", "label_boxes", "overlapping", "project", "project_one",
           "text_box", "text_size"]

REFERENCE_HEIGHT_PX = 800.0  # viser sizes screen labels relative to an 800 px tall viewport
SCREEN_EM_PX = 12.0  # [px] a screen label's em at font_screen_scale 1, at REFERENCE_HEIGHT_PX
CHAR_WIDTH_EM = 0.6  # mean advance of a character of viser's sans font (DejaVu-like) [em]
LINE_HEIGHT_EM = 1.2  # ascent + descent [em]
PADDING_EM = 0.2  # viser's BACKGROUND_PADDING_FRACTION
NEAR = 1e-3  # [scene units] a point this close to the camera plane, or behind it, is not drawn


def project(view: CameraView, points: Any, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Pixel coordinates (N, 2) (x right, y down, origin top-left) and depths (N,) [scene units
    along the view direction] of world points (N, 3) seen by `view` in a width x height window.

    A pinhole camera at view.position looking at view.look_at, `up` projected to the screen's
    up, vertical field of view view.fov_deg (three.js' PerspectiveCamera).  Points with depth
    <= NEAR get NaN pixels.
    """
    p = np.atleast_2d(np.asarray(points, dtype=float))
    eye = np.asarray(view.position, dtype=float)
    forward = np.asarray(view.look_at, dtype=float) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.asarray(view.up, dtype=float))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = p - eye
    depth = d @ forward
    focal = 0.5 * height / math.tan(0.5 * math.radians(view.fov_deg))  # [px]
    with np.errstate(divide="ignore", invalid="ignore"):
        x = 0.5 * width + focal * (d @ right) / depth
        y = 0.5 * height - focal * (d @ up) / depth
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
