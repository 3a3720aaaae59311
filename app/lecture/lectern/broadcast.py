"""The shared scene's drawing: the presenter's draw target into it (`Broadcast`), the pointer's
markers (`Pointer`, `pointed_at`) and the presenter's camera made for another screen
(`fitted_camera`)."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import viser

from app.kit.draw.labels import POINTER, Screen
from app.kit.draw.screen import BODY_WIDTH_SHARE, NARROW_MARGIN
from app.viser_internals import atomic_unless_captured

__all__ = ["LIVE_ROOT", "POINTER_LABEL_CHARS", "POINTER_ROOT", "POINTER_SECONDS", "Broadcast", "Pointer",
           "fitted_camera", "pointed_at"]

LIVE_ROOT = "/l"  # the presenter's 3D in the shared scene hangs under this node (every follower message
# carries its node's name: short)
POINTER_ROOT = LIVE_ROOT + "/pointer"  # the pointer's markers (`Pointer`), under the live root
POINTER_SECONDS = 4.0  # [s] a pointer marker stays this long, fading
POINTER_MARKERS = 4  # at most this many at once (the oldest goes)
POINTER_COLOR = (235, 0, 140)
POINTER_RADIUS = 0.22  # [scene units] of the ring
POINTER_LABEL_CHARS = 40


class Broadcast:
    """The presenter's draw target (`app.kit.core.target.DrawTarget`): the 3D into the shared scene
    under LIVE_ROOT, the panel, the interactive handles and the camera in the presenter's browser."""

    root_prefix = LIVE_ROOT

    def __init__(self, server: viser.ViserServer, client: viser.ClientHandle,
                 screens: Callable[[], list[Screen]] | None = None) -> None:
        self.server = server
        self.presenter = client
        self.scene = server.scene
        self.gui = client.gui
        self.controls = client.scene  # gizmos and clickable nodes: the presenter's only
        self.camera = client.camera
        self.client_id = client.client_id
        self.screens = screens  # the screens the shared labels are laid out for (`Lectern.label_screens`)

    def atomic(self) -> contextlib.AbstractContextManager[None]:
        """The shared scene's and the presenter's `atomic()`, except inside the app loop's frame
        for those a wire holds together (`app.viser_internals.atomic_unless_captured`)."""
        return atomic_unless_captured(self.server, self.presenter)

    def add_notification(self, title: str, body: str, **kwargs: Any) -> Any:
        return self.presenter.add_notification(title, body, **kwargs)


def fitted_camera(position: Any, look_at: Any, aspect_from: float, aspect_to: float, fov: float | None = None,
                  up: Any = (0.0, 0.0, 1.0)) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The presenter's camera (position, look_at [scene units], aspect, vertical `fov` [rad])
    made for a narrower view of aspect `aspect_to`, with the same fov and viewing direction.

    The scenes frame their body in the left BODY_WIDTH_SHARE of a wide view (the panel floats on
    the right), so only that share of the presenter's width is kept, with a margin: the distance
    grows by NARROW_MARGIN BODY_WIDTH_SHARE aspect_from / aspect_to (tan(h/2) = aspect tan(fov/2),
    h the horizontal angle), and with `fov` given both points move sideways (along the view's right, from `up`)
    by (BODY_WIDTH_SHARE - 1) d aspect_from tan(fov/2), d = |position - look_at|, so that share's
    middle is the narrow view's middle.  A view at least that wide keeps the presenter's camera."""
    eye, target = np.asarray(position, dtype=float), np.asarray(look_at, dtype=float)
    factor = BODY_WIDTH_SHARE * aspect_from / aspect_to if aspect_to > 0.0 else 1.0
    if factor > 1.0:
        factor *= NARROW_MARGIN
        offset = eye - target
        if fov is not None:
            forward = -offset / np.linalg.norm(offset)
            right = np.cross(forward, np.asarray(up, dtype=float))
            if np.linalg.norm(right) > 1e-9:  # looking along `up` has no sideways
                shift = (BODY_WIDTH_SHARE - 1.0) * np.linalg.norm(offset) * aspect_from * math.tan(fov / 2.0)
                target = target + shift * right / np.linalg.norm(right)
        eye = target + factor * offset
    return (float(eye[0]), float(eye[1]), float(eye[2])), (float(target[0]), float(target[1]), float(target[2]))


def pointed_at(ray_origin: Any, ray_direction: Any, look_at: Any) -> np.ndarray:
    """Where a click points in 3D: the point of the click's ray nearest the camera's look-at
    point (a click on the body lands near the body; the scene has no depth to read back).
    ValueError for a ray that is not finite or has no direction."""
    origin, direction = np.asarray(ray_origin, dtype=float), np.asarray(ray_direction, dtype=float)
    target = np.asarray(look_at, dtype=float)
    length = float(np.linalg.norm(direction))
    if origin.shape != (3,) or direction.shape != (3,) or not (np.all(np.isfinite(origin))
                                                              and np.all(np.isfinite(direction)) and length > 0.0):
        raise ValueError(f"a click's ray {ray_origin!r} + s {ray_direction!r} is not a ray")
    direction = direction / length
    s = max(float((target - origin) @ direction), 0.0)
    return origin + s * direction


class Pointer:
    """The presenter's markers in the shared scene (under LIVE_ROOT, so a browser exploring on
    its own, which hides LIVE_ROOT, does not see them): a ring facing the camera, a dot and an
    optional label each, fading over POINTER_SECONDS."""

    def __init__(self, scene: Any) -> None:
        self.scene = scene
        self.markers: list[tuple[float, list[Any]]] = []  # (age [s], handles)
        self.count = 0

    def add(self, point: np.ndarray, facing: np.ndarray, label: str, labels: Any = None) -> None:
        """A marker at `point` [scene units], its ring perpendicular to `facing`; its label is
        registered with `labels` (the live view's `LabelLayer`), if given, above every other
        (POINTER): the others make room for it."""
        if len(self.markers) >= POINTER_MARKERS:
            self._remove(self.markers.pop(0)[1])
        facing = facing / float(np.linalg.norm(facing))
        helper = np.array([0.0, 0.0, 1.0]) if abs(facing[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        u = np.cross(facing, helper)
        u /= float(np.linalg.norm(u))
        v = np.cross(facing, u)
        angles = np.linspace(0.0, 2.0 * np.pi, 49)
        ring = POINTER_RADIUS * (np.cos(angles)[:, None] * u + np.sin(angles)[:, None] * v)
        segments = np.stack([ring[:-1], ring[1:]], axis=1).astype(np.float32)
        name = f"{POINTER_ROOT}/{self.count}"
        self.count += 1
        frame = self.scene.add_frame(name, show_axes=False, position=tuple(float(x) for x in point))
        handles = [frame,
                   self.scene.add_line_segments(f"{name}/ring", segments, POINTER_COLOR, thickness=7.0,
                                                thickness_units="screen"),
                   self.scene.add_icosphere(f"{name}/dot", radius=0.05, color=POINTER_COLOR, subdivisions=2)]
        if label:
            handle = self.scene.add_label(f"{name}/label", label, position=tuple(1.3 * POINTER_RADIUS * u),
                                          font_screen_scale=1.6, anchor="bottom-left")
            handles.append(handle)
            if labels is not None:
                labels.add(handle, POINTER)
                labels.settle()
        self.markers.append((0.0, handles))

    def tick(self, dt: float) -> None:
        """Age the markers: each shrinks to nothing over POINTER_SECONDS, then goes."""
        kept = []
        for age, handles in self.markers:
            age += dt
            if age >= POINTER_SECONDS:
                self._remove(handles)
                continue
            shrink = round(1.0 - (age / POINTER_SECONDS) ** 3, 2)  # stays large, then goes quickly
            if handles[0].scale != shrink:
                handles[0].scale = shrink
            kept.append((age, handles))
        self.markers = kept

    def clear(self) -> None:
        for _, handles in self.markers:
            self._remove(handles)
        self.markers = []

    @staticmethod
    def _remove(handles: list[Any]) -> None:
        with contextlib.suppress(Exception):  # gone already
            handles[0].remove()
