"""Small pieces every scene shares: colours, lengths, formatting, throttles, slider specs and
value checks, camera views.

No physics formulas live here (they come from `physics`); this module only turns arrays into
what viser draws and text a projector can show.  No viser import either: the camera is moved
through the client handle it is given.
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from app.i18n import N_
from physics._types import Mat3, Vec3

__all__ = [
    "RunEnded",
    "Wrap",
    "show_if_changed",
    "write_if_changed",
    "BODY_AXIS_COLORS",
    "GIMBAL_FADE_DEG",
    "format_deg",
    "keep_phase",
    "staggered",
    "GIMBAL_LOCK_DEG",
    "L_COLOR",
    "NODES_COLOR",
    "NODES_FADED_COLOR",
    "OMEGA_COLOR",
    "LABEL_SCALE",
    "NODES_HALF_LENGTH",
    "SPACE_AXIS_COLORS",
    "SPACE_AXIS_LENGTH",
    "SliderSpec",
    "CameraView",
    "Throttle",
    "apply_camera",
    "axis_segments",
    "canonical_angles_deg",
    "checked_value",
    "fade_color",
    "format_matrix",
    "format_vector",
    "fork_sharing",
    "gimbal_note",
    "polyline_segments",
    "striped_parts",
    "wrap_deg",
]

Wrap = Callable[[str, Callable[..., Any]], Callable[..., Any]]
"""The session's guard: `wrap(where, fn)` is `fn` run under the room's lock, an error shown, never raised."""


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

LABEL_SCALE = 2.0  # font_screen_scale of the 3D axis labels (readable on a projector)
SPACE_AXIS_LENGTH = 2.0  # [scene units]
NODES_HALF_LENGTH = 1.9  # [scene units] the line of nodes is drawn from -this to +this along e_n


REFUSAL = N_("{label} = {value} refused: the range is {lo} to {hi}.")
"""A slider's refusal (`SliderSpec.refusal`), for translation; the English one is written in place."""


@dataclass(frozen=True)
class SliderSpec:
    """A slider: key, label (with unit), range, step, hint, marks ((value, text), ...)."""

    key: str
    label: str
    lo: float
    hi: float
    step: float
    hint: str = ""
    marks: tuple[tuple[float, str], ...] = ()
    words: Any = field(default=None, compare=False, repr=False)
    """The `app.i18n.Translator` its texts are in (`translated`); None: English."""

    def rounded(self, value: float) -> float:
        """`value` clamped to the range and rounded to the step (what the slider can show)."""
        value = min(max(value, self.lo), self.hi)
        decimals = max(0, -math.floor(math.log10(self.step)) + 1)
        return round(round(value / self.step) * self.step, decimals)

    def check(self, value: Any) -> float | None:
        """`value` as a float if finite and in range, else None (refuse it)."""
        return checked_value(value, self.lo, self.hi)

    def refusal(self, value: Any) -> str:
        """The message for a refused value (in the spec's language, `translated`)."""
        if self.words is None:
            return f"{self.label} = {value!r} refused: the range is {self.lo:g} to {self.hi:g}."
        tr = self.words
        return tr.gettext(REFUSAL).format(label=self.label, value=repr(value), lo=tr.general(self.lo),
                                          hi=tr.general(self.hi))

    def translated(self, tr: Any) -> SliderSpec:
        """This spec with its label, hint and marks in the language of `tr` (an
        `app.i18n.Translator`; its refusals too); range and step unchanged."""
        marks = tuple((value, tr.gettext(text)) for value, text in self.marks)
        return replace(self, label=tr.gettext(self.label), hint=tr.gettext(self.hint), marks=marks, words=tr)


def checked_value(value: Any, lo: float, hi: float) -> float | None:
    """`value` as a float if it is finite and within [lo, hi]; None (refuse it) otherwise.

    viser does not validate what a browser sends: a slider with range [0, 10] accepts 1e6
    or NaN from a hand-written client (docs/VISER.md pitfall 4).
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


def format_deg(angle_deg: float, decimals: int = 2) -> str:
    """An angle [deg] as text in (-180, 180] at `decimals` places: wrapped after rounding, so
    -179.999 reads 180.00, never -180.00 (and -0.001 reads 0.00)."""
    shown = wrap_deg(round(wrap_deg(angle_deg), decimals))
    return f"{0.0 if shown == 0.0 else shown:.{decimals}f}"


def canonical_angles_deg(phi: float, theta: float, psi: float) -> tuple[float, float, float]:
    """The same rotation with θ in [0, 180] and φ, ψ in (-180, 180] [deg].

    Rz(φ) Rx(θ) Rz(ψ) = Rz(φ + 180°) Rx(−θ) Rz(ψ + 180°), so a θ in (180°, 360°) becomes
    360° − θ with φ and ψ turned by 180°.
    """
    theta = theta % 360.0
    if theta > 180.0:
        theta, phi, psi = 360.0 - theta, phi + 180.0, psi + 180.0
    return wrap_deg(phi), theta, wrap_deg(psi)


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
        return N_("**⚠ Gimbal lock** (θ ≈ 0°): the line of nodes is undefined; "
                  "only **φ + ψ** is defined here, not φ and ψ separately.")
    if theta_deg > 180.0 - GIMBAL_LOCK_DEG:
        return N_("**⚠ Gimbal lock** (θ ≈ 180°): the line of nodes is undefined; "
                  "only **φ − ψ** is defined here, not φ and ψ separately.")
    return None


def keep_phase(elapsed: float, period: float) -> float:
    """What is left of `elapsed` [s] after a periodic task ran (elapsed >= period): the time it
    ran late, modulo the period.  Not 0: after a long frame every view (every room) of the app
    would run its periodic work in the same later frames (their phases snapped together); 60
    rooms laying out their labels and sampling their plots in one frame out of six made that
    frame several times longer than the others."""
    late = max(0.0, elapsed - period)
    return 0.0 if math.isinf(late) else late % period


_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
_TURNS = itertools.count()


def staggered(period: float) -> Throttle:
    """A Throttle whose phase is frac(k φ) of its period for the k-th one made (φ the golden
    ratio: any number of them spread evenly): the periodic work of many browsers' views (label
    layouts, panel text) then falls into different frames, not all into the same one."""
    return Throttle(period, phase=period * (next(_TURNS) * _GOLDEN % 1.0))


class Throttle:
    """True at most once per `period` [s] of the time fed to `ready` (the tick's dt).

    Fed with the loop's wall-clock dt, not time.time(), so a test that ticks by hand gets
    the same schedule as the running app.
    """

    def __init__(self, period: float, phase: float = 0.0) -> None:
        """phase [s] in [0, period): after the first (immediate) time, the next comes period +
        phase later (throttles of many views made in the same frame so take turns; never sooner
        than a period)."""
        self.period = period
        self.phase = phase % period if period > 0.0 else 0.0
        self._elapsed = math.inf  # the first call is ready

    def ready(self, dt: float) -> bool:
        self._elapsed += dt
        if self._elapsed >= self.period * (1.0 - 1e-9):  # 6 x (1/60) s is 0.1 s, not 0.0999...
            first = math.isinf(self._elapsed)
            self._elapsed = -self.phase if first else keep_phase(self._elapsed, self.period)
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


def apply_camera(client: Any, view: CameraView) -> None:
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


def fork_sharing(obj: Any, shared: Any = ()) -> Any:
    """A deep copy of `obj` (a simulation's `fork`) that shares the arrays in `shared` instead
    of copying them (a mesh of up to half a million faces); they are made read-only first, so
    neither copy can change what both see."""
    memo: dict[int, Any] = {}
    for array in shared:
        array.flags.writeable = False
        memo[id(array)] = array
    return copy.deepcopy(obj, memo)


class RunEnded(Exception):  # noqa: N818 - not an error: the motion's natural end
    """Raised by a simulation's `advance` when its motion reaches its natural end (a bead that
    flies off the end of its rod): not an error.  The state stays at the last moment of the run;
    the room pauses and says `str(self)`, plain words for a student, without a warning sign."""


def show_if_changed(handle: Any, visible: bool) -> None:
    """Set a GUI or scene handle's `visible` only when it differs (a write is a message to the browser)."""
    if handle.visible != visible:
        handle.visible = visible


def write_if_changed(handle: Any, content: str) -> None:
    """Set a markdown handle's `content` only when it differs (a write is a message to the browser)."""
    if handle.content != content:
        handle.content = content
