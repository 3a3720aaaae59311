"""Small pieces every scene of the lecture app shares: drawing helpers, formatting, colours,
throttles, slider-value checks and camera views.

No physics formulas live here (they come from `physics`); this module only turns arrays into
what viser draws and text a projector can show.  Quaternions (w, x, y, z) exist only here and
where a scene hands an orientation to viser.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import viser

from physics._types import Mat3, Vec3

__all__ = [
    "BODY_AXIS_COLORS",
    "GIMBAL_FADE_DEG",
    "GIMBAL_LOCK_DEG",
    "Guard",
    "L_COLOR",
    "NODES_COLOR",
    "NODES_FADED_COLOR",
    "OMEGA_COLOR",
    "SPACE_AXIS_COLORS",
    "CameraView",
    "Throttle",
    "apply_camera",
    "axis_segments",
    "checked_value",
    "clamp_finite",
    "fade_color",
    "format_matrix",
    "format_vector",
    "gimbal_note",
    "polyline_segments",
    "striped_parts",
    "wrap_deg",
    "wxyz_from_matrix",
]

Guard = Callable[[str, Callable[..., Any]], Callable[..., Any]]
"""Session.guard: (where, fn) -> fn run under the session lock, exceptions shown, not raised."""

# Colours (RGB 0-255), the same in every scene.
SPACE_AXIS_COLORS = ((225, 35, 35), (30, 160, 45), (35, 75, 230))  # x y z: red green blue
BODY_AXIS_COLORS = ((150, 0, 0), (0, 105, 20), (0, 30, 150))  # x′ y′ z′: darker
NODES_COLOR = (235, 180, 0)  # gold
NODES_FADED_COLOR = (215, 215, 215)  # the line of nodes near gimbal lock
OMEGA_COLOR = (230, 90, 0)  # ω: orange
L_COLOR = (120, 40, 200)  # L: violet

GIMBAL_LOCK_DEG = 2.0
"""Within this of θ = 0° or 180° the app says that φ and ψ are not separately defined."""
GIMBAL_FADE_DEG = 15.0
"""The line of nodes fades from full colour at this distance from a pole to grey at the pole."""


def wxyz_from_matrix(R: Mat3) -> np.ndarray:
    """Unit quaternion (w, x, y, z) (4,) of the rotation matrix R (3, 3), w >= 0, for viser.

    Shepperd's method on Python floats (a few µs: it runs for every pose of every frame).
    """
    r00, r01, r02 = float(R[0][0]), float(R[0][1]), float(R[0][2])
    r10, r11, r12 = float(R[1][0]), float(R[1][1]), float(R[1][2])
    r20, r21, r22 = float(R[2][0]), float(R[2][1]), float(R[2][2])
    trace = r00 + r11 + r22
    if trace >= max(r00, r11, r22):
        s = 2.0 * math.sqrt(max(1.0 + trace, 0.0))
        q = (0.25 * s, (r21 - r12) / s, (r02 - r20) / s, (r10 - r01) / s)
    elif r00 >= r11 and r00 >= r22:
        s = 2.0 * math.sqrt(max(1.0 + r00 - r11 - r22, 0.0))
        q = ((r21 - r12) / s, 0.25 * s, (r01 + r10) / s, (r02 + r20) / s)
    elif r11 >= r22:
        s = 2.0 * math.sqrt(max(1.0 + r11 - r00 - r22, 0.0))
        q = ((r02 - r20) / s, (r01 + r10) / s, 0.25 * s, (r12 + r21) / s)
    else:
        s = 2.0 * math.sqrt(max(1.0 + r22 - r00 - r11, 0.0))
        q = ((r10 - r01) / s, (r02 + r20) / s, (r12 + r21) / s, 0.25 * s)
    norm = math.sqrt(sum(c * c for c in q))
    sign = 1.0 if q[0] >= 0.0 else -1.0
    return np.array([sign * c / norm for c in q])


def clamp_finite(value: float, lo: float, hi: float, fallback: float) -> float:
    """`value` clamped to [lo, hi]; `fallback` if it is NaN (viser passes NaN through)."""
    value = float(value)
    if math.isnan(value):
        return fallback
    return min(max(value, lo), hi)


def checked_value(value: Any, lo: float, hi: float) -> float | None:
    """`value` as a float if it is finite and within [lo, hi]; None (refuse it) otherwise.

    viser does not validate what a browser sends: a slider with range [0, 10] accepts 1e6
    or NaN from a hand-written client (VISER.md pitfall 4).
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    if not math.isfinite(number) or number < lo or number > hi:
        return None
    return number


def wrap_deg(angle_deg: float) -> float:
    """An angle [deg] mapped to (-180, 180]."""
    wrapped = math.remainder(angle_deg, 360.0)
    return 180.0 if wrapped == -180.0 else wrapped


def _clean(x: float, decimals: int) -> float:
    return 0.0 if abs(x) < 0.5 * 10.0**-decimals else float(x)


def format_matrix(M: Mat3, decimals: int = 4) -> str:
    """A 3x3 matrix as three aligned text rows '[ a  b  c ]' (no '-0.0000')."""
    width = decimals + 4
    rows = []
    for row in np.asarray(M, dtype=float):
        rows.append("[ " + "  ".join(f"{_clean(x, decimals):{width}.{decimals}f}" for x in row) + " ]")
    return "\n".join(rows)


def format_vector(v: Vec3, decimals: int = 3) -> str:
    """A 3-vector as '(a, b, c)' with no '-0.000'."""
    return "(" + ", ".join(f"{_clean(x, decimals):.{decimals}f}" for x in v) + ")"


def axis_segments(R: Mat3, length: float) -> np.ndarray:
    """Segments (3, 2, 3) from the origin along the columns of R, `length` long."""
    return np.stack([np.zeros((3, 3)), length * np.asarray(R, dtype=float).T], axis=1)


def polyline_segments(points: np.ndarray) -> np.ndarray:
    """Consecutive pairs (N-1, 2, 3) of a polyline's points (N, 3)."""
    return np.stack([points[:-1], points[1:]], axis=1)


def fade_color(color: Sequence[int], faded: Sequence[int], weight: float) -> tuple[int, int, int]:
    """`color` blended towards `faded`: weight 1 gives `color`, 0 gives `faded`."""
    w = min(max(weight, 0.0), 1.0)
    return tuple(int(round(f + w * (c - f))) for c, f in zip(color, faded))  # type: ignore[return-value]


def gimbal_note(theta_deg: float) -> str | None:
    """The gimbal-lock message near θ = 0° or 180° (within GIMBAL_LOCK_DEG), else None."""
    if theta_deg < GIMBAL_LOCK_DEG:
        return ("**⚠ Gimbal lock** (θ ≈ 0°): the line of nodes is undefined; "
                "only **φ + ψ** is defined here, not φ and ψ separately.")
    if theta_deg > 180.0 - GIMBAL_LOCK_DEG:
        return ("**⚠ Gimbal lock** (θ ≈ 180°): the line of nodes is undefined; "
                "only **φ − ψ** is defined here, not φ and ψ separately.")
    return None


class Throttle:
    """True at most once per `period` [s] of the time fed to `ready` (the tick's dt).

    Fed with the loop's wall-clock dt, not time.time(), so a test that ticks by hand gets
    the same schedule as the running app.
    """

    def __init__(self, period: float) -> None:
        self.period = period
        self._elapsed = math.inf  # the first call is ready

    def ready(self, dt: float) -> bool:
        self._elapsed += dt
        if self._elapsed >= self.period * (1.0 - 1e-9):  # 6 x (1/60) s is 0.1 s, not 0.0999...
            self._elapsed = 0.0
            return True
        return False

    def trigger(self) -> None:
        """Make the next `ready` call return True."""
        self._elapsed = math.inf


@dataclass(frozen=True)
class CameraView:
    """A camera view (z up): position and look_at [scene units], vertical fov [deg]."""

    position: tuple[float, float, float]
    look_at: tuple[float, float, float]
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    fov_deg: float = 40.0  # three.js' default 75° distorts the axes


def apply_camera(client: viser.ClientHandle, view: CameraView) -> None:
    """Move `client`'s camera to `view`."""
    camera = client.camera
    camera.up_direction = view.up
    camera.position = view.position
    camera.look_at = view.look_at
    camera.fov = math.radians(view.fov_deg)


def striped_parts(
    vertices: np.ndarray, faces: np.ndarray, sectors: int
) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """Split a mesh symmetric about z into two meshes of alternating azimuth sectors.

    A spinning body of revolution painted in one colour looks still; painted in `sectors`
    alternating sectors (by the azimuth of each face's centroid) its spin is visible.
    Returns ((vertices, faces) of the even sectors, (vertices, faces) of the odd ones).
    """
    centroids = vertices[faces].mean(axis=1)
    azimuth = np.arctan2(centroids[:, 1], centroids[:, 0]) % (2.0 * np.pi)
    odd = (np.floor(azimuth / (2.0 * np.pi / sectors)).astype(int) % 2).astype(bool)
    return (vertices, faces[~odd]), (vertices, faces[odd])
