"""The z-x-z Euler-angle explorer ("Euler angles" scene).

What it shows (docs/CONVENTIONS.md, "Euler angles", "Angular velocity"): the space axes x y z,
a box whose proportions follow its principal moments, its body axes x′ y′ z′, the line of nodes
e_n = (cos φ, sin φ, 0), the two intermediate frames of D = Rz(φ) Rx(θ) Rz(ψ) (after φ:
ξηζ = Rz(φ); after θ: ξ′η′ζ′ = Rz(φ) Rx(θ)), arcs for φ, θ, ψ, and the angular velocity
ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′ (memo 1.17) drawn head to tail: φ̇ e_z from the origin, θ̇ e_n
from its tip, ψ̇ e_z′ from that one, and the resultant ω from the origin to the end.
Readouts: D, its three factors, and ω with its space (ω_s) and body (ω_b) components.

The single rotation (memo 1.1-1.3; the toggle `Single rotation`, off by default): the same D as
one turn, D = exp(A), A = Φ hat(d).  Drawn: the axis d (a near-black line through the origin,
both ways, its head at +d) and the angle Φ (an arc about d, in the plane through the origin
perpendicular to d, from the projection of the space axis e_k most perpendicular to d to D of
it, which is the projection of the body axis e_k′; the two spokes in the colours of e_k and
e_k′).  Read out: Φ, d, A = Φ hat(d), the rotation vector Φ d and the quaternion.  At Φ = 0
(below `physics.so3.AXIS_UNDEFINED_ANGLE`) no axis is drawn and the readout says the axis is
undefined; within `HALF_TURN_BAND` of Φ = π the axis comes from (D + 1)/2 = d dᵀ with the sign
nearer the last axis drawn (`physics.so3.single_rotation`), so sliders through half turns do not
flip it.  The animation: switching the toggle on, or the `Animate` button, turns two outlines of
the box from the space axes to D over ANIMATION_SECONDS: a dark one by exp(s Φ hat(d)), s = 0 →
1 (the single turn), and beside it a coloured one through the three Euler steps z-x-z (purple
while φ turns about z, pink for θ about the line of nodes, teal for ψ about z′); both end on the
body, stay ANIMATION_HOLD seconds and go.  The animation is this view's (a presenter's is seen by
the followers); it follows D if the angles move meanwhile.

The simulation (`EulerAnglesSimulation`, no viser) advances the angles at the set rates
(φ, θ, ψ grow linearly; a θ outside [0°, 180°] is shown as the equivalent
(φ + 180°, 360° − θ, ψ + 180°), so the sliders wrap).  Near θ = 0° or 180° the line of nodes
fades and the panel says that only φ + ψ (or φ − ψ) is defined.  Every formula comes from
`physics`; degrees on the sliders, radians everywhere else.  Presets:
`assets/presets/euler_angles.json`.

**What a playing frame sends** (the frame budget, tests/test_frame_budget.py; the first
preset, φ̇ θ̇ ψ̇ = 20, 10, 45 °/s).  The decomposition is a chain of frames, each turned by one
angle about one of its own axes: after φ (`/e/p`), after θ (`/e/p/t`), the body (`/e/p/t/s`);
everything else rides on the frame it is fixed in (the line of nodes and the fixed arc pieces
on the after-φ frame, η′ and the ψ arc on the after-θ frame, the box and its axes on the body).
While playing each angle is snapped so that a step moves its frame's farthest point by ~1 px
(`app.kit.lean.Pose`), and a frame's turn is sent only when its snapped angle changed: φ and ψ
one orientation message every frame, θ about three frames in four.  ω's components are fixed
in frames that are sent anyway: φ̇ e_z in space, θ̇ e_n in the after-φ frame (no message while
the rates are constant), ψ̇ e_z′ (with ω's label) in a frame at θ̇ e_n's tip turned by the same
Rx(θ) as the after-θ frame, so its orientation message repeats the after-θ frame's values in
the same window (~5 B compressed).  The resultant ω depends on θ (and the rates) only: it
lives in the after-φ frame as an `app.kit.lean.FrameArrow`, an orientation message at each
θ step that moves its tip and a z-scale message when its length moved by ~1 px (about one
frame in five).  Labels: anchors and visibility only when the view's `LabelLayer` changes
them (10 Hz), the arcs' readings at 2 Hz; the sliders, the status line and the readout tab
shown at 2 Hz (the readouts' fixed headings are markdowns of their own, sent once).  Node
names are short (`/e`, `/e/p`, ...): every message carries its node's name.  Measured
(2026-11-25, four seconds): 224 / 222 B/frame own / follower, 5.1 scene messages a frame (4.3 of
them orientations).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import viser

from app.kit.common import (
    BODY_AXIS_COLORS,
    OMEGA_COLOR,
    SPACE_AXIS_COLORS,
    CameraView,
    SliderSpec,
    Throttle,
    axis_segments,
    canonical_angles_deg,
    format_deg,
    format_matrix,
    format_vector,
    gimbal_note,
    polyline_segments,
    wrap_deg,
)
from app.kit.fastprops import set_points, set_position, set_wxyz
from app.kit.gui import PresetsRow, Readout, Tabs, Transport, Wrap, add_slider
from app.kit.history import Snapshot
from app.kit.labels import AXES, DETAIL, KEY, LabelLayer
from app.kit.lean import TOLERANCE, ArcPieces, FrameArrow, Pose, snap, world_pose
from app.kit.presets import Preset
from app.kit.room import Room
from app.kit.view import SceneView, nth
from app.kit.widgets import Body, LineOfNodes, Stage
from physics._types import Vec3
from physics.euler import (
    body_z_axis,
    euler_frames,
    line_of_nodes,
    omega_body_from_euler_rates,
    omega_space_from_euler_rates,
)
from physics.inertia import InertiaError, box_extents_from_moments, validate_principal_moments
from physics.quaternion import wxyz_from_matrix
from physics.so3 import HALF_TURN_BAND, SingleRotation, exp_so3, rot_x, rot_z, single_rotation, turn_path

__all__ = [
    "ANGLE_SPECS",
    "INITIAL_ANGLES_DEG",
    "INITIAL_CAMERA",
    "INITIAL_FOV_DEG",
    "RATE_ARROW_SCALE",
    "VIEW",
    "EulerAnglesSimulation",
    "EulerAnglesView",
    "arc_reference_axis",
    "box_outline_segments",
    "canonical_angles_deg",
]

_FULL_MARKS = ((-180.0, "-180°"), (-90.0, "-90°"), (0.0, "0°"), (90.0, "90°"), (180.0, "180°"))
ANGLE_SPECS = (
    SliderSpec("phi", "φ [deg]", -180.0, 180.0, 1.0, "precession about the space z axis (applied first)",
               _FULL_MARKS),
    SliderSpec("theta", "θ [deg]", 0.0, 180.0, 1.0, "nutation about the line of nodes (applied second)",
               ((0.0, "0°"), (45.0, "45°"), (90.0, "90°"), (135.0, "135°"), (180.0, "180°"))),
    SliderSpec("psi", "ψ [deg]", -180.0, 180.0, 1.0, "spin about the body z′ axis (applied last)", _FULL_MARKS),
)
_RATE_MARKS = ((-180.0, "-180"), (-90.0, "-90"), (0.0, "0"), (90.0, "90"), (180.0, "180"))
RATE_SPECS = tuple(
    SliderSpec(f"{key}_dot", f"d{greek}/dt [deg/s]", -180.0, 180.0, 1.0,
               f"d{greek}/dt: Play advances {greek} at this rate", _RATE_MARKS)
    for key, greek in (("phi", "φ"), ("theta", "θ"), ("psi", "ψ"))
)
MOMENT_SPECS = tuple(
    SliderSpec(f"I{k + 1}", f"I{k + 1} [kg m²]", 0.1, 5.0, 0.05, f"principal moment about the body {'xyz'[k]}′ axis")
    for k in range(3)
)
INITIAL_ANGLES_DEG = (30.0, 50.0, 20.0)  # the first preset's pose
INITIAL_MOMENTS = (1.0, 2.0, 2.6)  # box with edges a : b : c = 3 : 2 : 1
BODY_SIZE = 1.25  # display length [scene units] of the body's longest edge
MIN_EDGE = 0.02  # display thickness of a flat body (a lamina: I1 + I2 = I3)
BODY_AXIS_LENGTH = 1.35
FRAME_AXIS_LENGTH = 1.1
ARC_RADII = {"phi": 1.2, "theta": 1.05, "psi": 0.95}
ARC_SEGMENTS = 48
RATE_ARROW_SCALE = 1.0 / 30.0  # [scene units per deg/s]: 30°/s is one unit long
FRAME_COLORS = ((240, 160, 160), (150, 215, 160), (160, 180, 245))
BODY_COLOR = (235, 170, 70)
BODY_OPACITY = 0.7
ARC_COLORS = {"phi": (140, 50, 210), "theta": (215, 0, 120), "psi": (0, 140, 140)}
GREEK = {"phi": "φ", "theta": "θ", "psi": "ψ"}
KEYS = ("phi", "theta", "psi")
SHORT = {"phi": "p", "theta": "t", "psi": "s"}  # in node names (every message carries its node's name)

# Seen from x > 0, y < 0 so that x, y, the line of nodes and x′ are all visible for typical
# angles (φ ≈ 30°), with the origin left of centre to clear the GUI panel on the right.
VIEW = CameraView(position=(5.9, -2.0, 3.3), look_at=(0.5, 1.15, 0.25), fov_deg=40.0)
INITIAL_CAMERA = {"position": VIEW.position, "look_at": VIEW.look_at, "up": VIEW.up}
INITIAL_FOV_DEG = VIEW.fov_deg

# The single rotation D = exp(Φ hat(d)).
SINGLE_COLOR = (40, 40, 40)  # the axis d, the arc Φ and the single-turn outline: near black
SINGLE_AXIS_HALF_LENGTH = 2.3  # [scene units] d is drawn from -this to +this, past the space axes
SINGLE_ARC_RADIUS = 1.6  # [scene units] outside the φ θ ψ arcs (at most 1.2)
ARC_HYSTERESIS = 0.25  # the Φ arc keeps its space axis e_k until another is this much more perpendicular to d
ANIMATION_SECONDS = 4.0  # [s] of wall time: the outlines turn from 1 to D
ANIMATION_HOLD = 1.5  # [s] they then stay on the body, and go
ZXZ_KEYS = KEYS  # the three-step outline's colour is ARC_COLORS of the step it is in

ARC_PERIOD = 1.0 / 20.0  # [s] the single rotation's axis and arc while playing (20 Hz)
ARC_TEXT_PERIOD = 0.5  # [s] the arcs' readings ("φ = 31°") while playing (2 Hz; exact when paused)
SLIDER_PERIOD = 0.5  # sliders follow at 2 Hz while playing (read when paused: a refresh writes them exactly)
# How far the drawn points of each frame reach from the origin [scene units]: a turn is sent when
# it moves them by more than app.kit.lean.TOLERANCE (the ω arrows are at most ~2 long at 30°/s per unit).
PHI_REACH = 2.2  # the line of nodes (1.9), ω's components
THETA_REACH = 1.6  # the body under the after-θ frame (axes 1.35 and labels), ψ̇ e_z′ (≤ 1.5 at 45°/s) turning ω's tip
PSI_REACH = 1.6  # the body's axes (1.35) and their labels
READOUT_PERIOD = 0.5  # the readout tab shown and the status line, while playing (2 Hz; exact when paused)


class EulerAnglesSimulation:
    """Angles advancing at constant Euler rates (no viser).

    Attributes:
        angles_deg: [φ, θ, ψ] [deg] in the principal ranges (what the sliders show).
        rates_deg: [φ̇, θ̇, ψ̇] [deg/s].  moments: (I1, I2, I3) [kg m²] of the box drawn.
        t: seconds played since the angles were last set.  version: bumped on every change.
        run: bumped at every reset (the replay's history starts afresh).
    """

    def __init__(self, angles_deg: Sequence[float], rates_deg: Sequence[float],
                 moments: Sequence[float] = INITIAL_MOMENTS) -> None:
        self.rates_deg = [float(r) for r in rates_deg]
        self.moments = tuple(float(m) for m in validate_principal_moments(moments))
        self.preset: str | None = None
        self.version = 0
        self.run = 0
        self.set_angles(angles_deg)

    def set_angles(self, angles_deg: Sequence[float]) -> None:
        """Set (φ, θ, ψ) [deg]: playing and Reset start from here (t = 0)."""
        self._initial_deg = np.array(angles_deg, dtype=float)
        self.reset()

    def set_rates(self, rates_deg: Sequence[float]) -> None:
        self.rates_deg = [float(r) for r in rates_deg]
        self.version += 1

    def set_moments(self, moments: Sequence[float]) -> None:
        """InertiaError (nothing changes) if the moments are not a body."""
        self.moments = tuple(float(m) for m in validate_principal_moments(moments))
        self.version += 1

    def reset(self) -> None:
        self._played_deg = self._initial_deg.copy()
        self.run += 1
        self.t = 0.0
        self.angles_deg = list(canonical_angles_deg(*self._played_deg))
        self.version += 1

    def advance(self, dt: float) -> None:
        played = self._played_deg + np.array(self.rates_deg) * dt
        played[[0, 2]] = [wrap_deg(a) for a in played[[0, 2]]]
        played[1] %= 360.0
        self._played_deg = played
        self.t += dt
        self.angles_deg = list(canonical_angles_deg(*played))
        self.version += 1

    # ------------------------------------------------------------------ replay (app.kit.history)
    def snapshot(self) -> Snapshot:
        """The moment now: t, the angles as played (3) [deg], the rates (3) [deg/s] (the angles
        shown are a function of those played)."""
        values = [self.t, *self._played_deg.tolist(), *self.rates_deg]
        return Snapshot(np.array(values, dtype=float))

    def restore(self, snapshot: Snapshot, later: float = 0.0) -> None:
        """The recorded moment back bit for bit (then `later` [s] on, for display)."""
        v = snapshot.values
        if v.shape != (7,):
            raise ValueError("this snapshot is not an Euler-angles moment")
        self.t = float(v[0])
        self._played_deg = v[1:4].copy()
        self.angles_deg = list(canonical_angles_deg(*self._played_deg))
        self.rates_deg = [float(r) for r in v[4:7]]
        if later > 0.0:
            self.advance(later)
        self.version += 1

    def truncate(self) -> None:
        """No history to cut (the scene keeps none)."""

    def fork(self) -> EulerAnglesSimulation:
        """An exact, independent copy: angles (as played and as shown), rates, moments, t, the
        angles Reset goes back to, preset and version (a deep copy: a few small arrays)."""
        return copy.deepcopy(self)

    @property
    def angles(self) -> tuple[float, float, float]:
        """(φ, θ, ψ) [rad]."""
        phi, theta, psi = (math.radians(a) for a in self.angles_deg)
        return phi, theta, psi

    @property
    def R_space_body(self) -> np.ndarray:
        return euler_frames(*self.angles).body


def arc_reference_axis(axis: np.ndarray, previous: int | None = None) -> int:
    """Index k of the space axis e_k the Φ arc starts from: the one most perpendicular to the
    unit axis d (3,) (smallest |d_k|), except that `previous` is kept while it is within
    ARC_HYSTERESIS of the best (near a tie, as for d = (1, 1, 1)/√3, the arc does not jump)."""
    magnitudes = np.abs(np.asarray(axis, dtype=float))
    best = int(np.argmin(magnitudes))
    if previous is not None and magnitudes[previous] <= magnitudes[best] + ARC_HYSTERESIS:
        return previous
    return best


def box_outline_segments(edges: Sequence[float] | np.ndarray, axis_length: float) -> np.ndarray:
    """The 12 edges of a box centred at the origin with edge lengths `edges` (3,) along x y z,
    then its three axes from the origin, `axis_length` long: segments (15, 2, 3)."""
    half = 0.5 * np.asarray(edges, dtype=float)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float) * half
    lines = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    box = np.array([[corners[a], corners[b]] for a, b in lines])
    return np.concatenate([box, axis_segments(np.eye(3), axis_length)])


def _outline_colors(color: tuple[int, int, int]) -> np.ndarray:
    """Colours (15, 2, 3) of `box_outline_segments`: the box in `color`, the axes x′ y′ z′."""
    colors = np.empty((15, 2, 3), dtype=np.uint8)
    colors[:12] = color
    colors[12:] = np.array(BODY_AXIS_COLORS, dtype=np.uint8)[:, None, :]
    return colors


def _box_edges(moments: Sequence[float]) -> np.ndarray:
    """The drawn box's edges (3,) [scene units]: the uniform box of these moments, scaled so the
    longest edge is BODY_SIZE (a flat lamina is drawn MIN_EDGE thick)."""
    edges = np.asarray(box_extents_from_moments(moments, mass=1.0), dtype=float)
    return np.maximum(BODY_SIZE * edges / edges.max(), MIN_EDGE)


def _arc_point(key: str) -> Callable[[float], np.ndarray]:
    """The arc of angle `key` at angle t [rad], in the frame the angle is measured in: φ about z
    from x, θ about x (the line of nodes) from z, ψ about z′ from the line of nodes."""
    radius = ARC_RADII[key]
    if key == "theta":
        return lambda t: np.array([0.0, -radius * math.sin(t), radius * math.cos(t)])
    return lambda t: np.array([radius * math.cos(t), radius * math.sin(t), 0.0])


class RateArrow:
    """One component of ω (an arrow with its label at the middle) in a frame where it stands still
    while the rates are constant: `update` sends only when start or end changed."""

    def __init__(self, scene: Any, name: str, color: tuple[int, int, int], text: str, labels: LabelLayer) -> None:
        self.arrow = scene.add_arrows(name, np.zeros((1, 2, 3), dtype=np.float32), color, shaft_radius=0.018,
                                      head_radius=0.05, head_length=0.1, visible=False)
        self.label = labels.add(scene.add_label(f"{name}l", text, font_screen_scale=1.4, anchor="center-left",
                                                visible=False), DETAIL)
        self._labels = labels
        self._drawn: tuple[tuple[float, ...], bool] | None = None

    def update(self, start: Vec3, end: Vec3, enabled: bool) -> None:
        """Draw the arrow from `start` to `end` (3,) [scene units, parent frame] if `enabled` and
        longer than 1e-3."""
        segment = tuple(float(c) for c in (*start, *end))
        visible = enabled and math.dist(segment[:3], segment[3:]) > 1e-3
        if self._drawn == (segment, visible):
            return
        self._drawn = (segment, visible)
        if self.arrow.visible != visible:
            self.arrow.visible = visible
        self._labels.want(self.label, visible)
        if visible:
            set_points(self.arrow, np.array([[segment[:3], segment[3:]]], dtype=np.float32))
            mid = [0.5 * (a + b) + 0.06 for a, b in zip(segment[:3], segment[3:])]
            set_position(self.label, (mid[0], mid[1], mid[2]))

    def segment(self) -> np.ndarray:
        """(2, 3) start and end as drawn (parent frame)."""
        return np.asarray(self.arrow.points, dtype=float)[0]


class EulerAnglesView(SceneView):
    """One browser's view of a room with an `EulerAnglesSimulation`."""

    transport: Transport  # built by build_head

    title = "Euler angles"
    root = "/e"  # node names are short: every message of a frame carries its node's name
    view = VIEW
    preset_file = "euler_angles.json"
    rate_specs = RATE_SPECS

    @classmethod
    def simulation_from_preset(cls, preset: Preset) -> EulerAnglesSimulation:
        return EulerAnglesSimulation(preset.angles_deg, preset.rates)

    @classmethod
    def start_preset(cls, sim: EulerAnglesSimulation, preset: Preset) -> None:
        sim.set_rates(preset.rates)
        sim.set_angles(preset.angles_deg)

    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: EulerAnglesSimulation = room.sim
        self._drawn_version = -1
        self._drawn_moments: tuple[float, ...] = ()
        self._arc_throttle = Throttle(ARC_PERIOD)
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self._readout_throttle = Throttle(READOUT_PERIOD)
        self._single: tuple[int, SingleRotation] | None = None  # (sim version, D as one turn)
        self._last_axis: np.ndarray | None = None  # the axis d last drawn (its sign is kept near Φ = π)
        self._arc_axis: int | None = None  # k of the space axis e_k the Φ arc starts from
        self.animation_time: float | None = None  # [s] into the animation; None: not animating
        self._zxz_step = -1
        self._outline_moments: tuple[float, ...] = ()
        self.build()

    # ------------------------------------------------------------------ building
    def _build_scene(self) -> None:
        scene = self.client.scene
        root = self.root
        labels = self.labels
        Stage(scene, root, size=4.0, labels=labels)
        # The decomposition as a chain of frames, each turned by one angle about one of its own
        # axes (T_parent_local): after φ = Rz(φ) under the root, after θ = Rx(θ) under it, the
        # body = Rz(ψ) under that.  A frame's message is sent only when its angle moved visibly
        # (app.kit.lean.Pose): a steady precession sends one small message a frame, not four.
        self.after_phi_node = scene.add_frame(f"{root}/p", show_axes=False)
        self.after_theta_node = scene.add_frame(f"{root}/p/t", show_axes=False)
        self.frame_axes = []
        for node, prime in ((self.after_phi_node, ""), (self.after_theta_node, "′")):
            axes = scene.add_frame(f"{node.name}/x", show_axes=False)  # thin, faint, toggleable
            scene.add_line_segments(
                f"{axes.name}/l", axis_segments(np.eye(3), FRAME_AXIS_LENGTH),
                np.repeat(np.array(FRAME_COLORS, dtype=np.uint8)[:, None, :], 2, axis=1),
                thickness=2.5, thickness_units="screen",
            )
            labels.add(scene.add_label(f"{axes.name}/eta", f"η{prime}", position=(0.0, FRAME_AXIS_LENGTH + 0.08, 0.0),
                                       font_screen_scale=1.3, anchor="center-center"), DETAIL)
            self.frame_axes.append(axes)
        self.body = Body(scene, f"{root}/p/t/s", self._build_box, axis_length=BODY_AXIS_LENGTH, labels=labels)
        self.poses = {"phi": Pose(self.after_phi_node, reach=PHI_REACH),
                      "theta": Pose(self.after_theta_node, reach=THETA_REACH),
                      "psi": Pose(self.body.node, reach=PSI_REACH)}
        # The line of nodes is the after-φ frame's x axis: it rides on that frame (no message of its own).
        self.nodes = LineOfNodes(scene, f"{root}/p/n", labels=labels)
        # Arcs: fixed pieces in the frame the angle is measured in, a tail piece in the frame it turns.
        frames = {"phi": (root, f"{root}/p"), "theta": (f"{root}/p", f"{root}/p/t"),
                  "psi": (f"{root}/p/t", f"{root}/p/t/s")}
        self.arcs: dict[str, ArcPieces] = {}
        self.arc_labels: dict[str, Any] = {}
        for key in KEYS:
            fixed, moving = frames[key]
            self.arcs[key] = ArcPieces(scene, fixed, moving, f"a{SHORT[key]}", _arc_point(key), ARC_COLORS[key],
                                       signed=key != "theta")
            self.arc_labels[key] = labels.add(scene.add_label(f"{moving}/l{SHORT[key]}", GREEK[key],
                                                              font_screen_scale=1.6, anchor="center-center"), DETAIL)
        self._arc_text_throttle = Throttle(ARC_TEXT_PERIOD)
        self._arc_label_at: dict[str, tuple[float, float, float] | None] = dict.fromkeys(KEYS)
        # ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′, head to tail, and the resultant (orange, thick).  φ̇ e_z is
        # fixed in space, θ̇ e_n in the after-φ frame; ψ̇ e_z′ hangs in a frame at the tip of θ̇ e_n
        # turned by Rx(θ) like the after-θ frame, and carries ω's label at the common tip; the
        # resultant is drawn in the after-φ frame (it depends on θ only there).  ψ̇ e_z′'s frame costs
        # ~5 B a θ step: its orientation repeats the after-θ frame's in the same window (hung under
        # the after-θ frame instead, its position would change with θ: a position message, ~38 B).
        self.omega_node = scene.add_frame(f"{root}/w", show_axes=False)
        self.omega_phi_node = scene.add_frame(f"{root}/p/w", show_axes=False)
        self.omega_psi_node = scene.add_frame(f"{root}/p/w/s", show_axes=False)
        self.omega_psi_pose = Pose(self.omega_psi_node, reach=THETA_REACH)
        self.rate_vectors = {
            "phi": RateArrow(scene, f"{root}/w/p", ARC_COLORS["phi"], "dφ/dt", labels),
            "theta": RateArrow(scene, f"{root}/p/w/t", ARC_COLORS["theta"], "dθ/dt", labels),
            "psi": RateArrow(scene, f"{root}/p/w/s/a", ARC_COLORS["psi"], "dψ/dt", labels),
        }
        self.omega = FrameArrow(scene, f"{root}/p/w/r", OMEGA_COLOR, shaft_radius=0.032,
                                head_radius=0.085, head_length=0.16)
        self.omega_label = labels.add(scene.add_label(f"{root}/p/w/s/l", "ω", font_screen_scale=2.4,
                                                      anchor="center-center", visible=False), KEY)
        self._omega_drawn: tuple[float, ...] | None = None  # (rates, shown) the constant arrows were drawn for
        # The single rotation D = exp(Φ hat(d)): axis, arc (with its two spokes), two animated outlines.
        single = f"{root}/d"
        self.single_node = scene.add_frame(single, show_axes=False, visible=False)
        self.single_axis = scene.add_arrows(f"{single}/d", np.zeros((1, 2, 3)), SINGLE_COLOR, shaft_radius=0.014,
                                            head_radius=0.06, head_length=0.14)
        self.single_axis_label = labels.add(scene.add_label(f"{single}/dl", "d", font_screen_scale=1.8,
                                                            anchor="center-center"), AXES)
        self.single_arc = scene.add_line_segments(f"{single}/a", np.zeros((ARC_SEGMENTS + 2, 2, 3)),
                                                  np.zeros((ARC_SEGMENTS + 2, 2, 3), dtype=np.uint8),
                                                  thickness=4.0, thickness_units="screen")
        self.single_arc_label = labels.add(scene.add_label(f"{single}/al", "Φ", font_screen_scale=1.6,
                                                           anchor="center-center"), AXES)
        self.ghost_turn = scene.add_frame(f"{single}/g1", show_axes=False, visible=False)
        self.ghost_zxz = scene.add_frame(f"{single}/g3", show_axes=False, visible=False)
        outline = box_outline_segments(_box_edges(self.sim.moments), 0.6 * BODY_AXIS_LENGTH)
        self.ghost_turn_lines = scene.add_line_segments(f"{single}/g1/l", outline,
                                                        _outline_colors(SINGLE_COLOR), thickness=3.0,
                                                        thickness_units="screen")
        self.ghost_zxz_lines = scene.add_line_segments(f"{single}/g3/l", outline,
                                                       _outline_colors(ARC_COLORS["phi"]), thickness=3.0,
                                                       thickness_units="screen")
        self._outline_moments = self.sim.moments

    def _build_box(self, scene: Any, parent: str) -> None:
        self.body_box = scene.add_box(
            f"{parent}/box", color=BODY_COLOR, dimensions=tuple(float(e) for e in _box_edges(self.sim.moments)),
            opacity=BODY_OPACITY, flat_shading=True, cast_shadow=False, receive_shadow=False,
        )
        self._drawn_moments = self.sim.moments

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        self.build_head(
            "### Euler angles, z-x-z convention\n"
            "**D = Rz(φ) Rx(θ) Rz(ψ)**, body → space (x = D x′).  \n"
            "φ: precession about z · θ: nutation about the line of nodes · "
            "ψ: spin about z′.  Angles in **degrees**.  \n"
            "**ω = (dφ/dt) e_z + (dθ/dt) e_n + (dψ/dt) e_z′** (orange, head to tail)."
        )
        self.folder_angles = gui.add_folder("Euler angles z-x-z [deg]")
        with self.folder_angles:
            self.gui_angles = [add_slider(gui, spec, value) for spec, value in zip(ANGLE_SPECS, self.sim.angles_deg)]
            self.gui_gimbal_note = gui.add_markdown("", visible=False)
            self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset)
        self.folder_rates = gui.add_folder("Euler rates [deg/s]")
        with self.folder_rates:
            self.gui_rates = [add_slider(gui, spec, value) for spec, value in zip(RATE_SPECS, self.sim.rates_deg)]
        self.folder_single = gui.add_folder("Single rotation D = exp(Φ hat d)")
        with self.folder_single:
            self.gui_single_rotation = gui.add_checkbox(
                "Single rotation", False,
                hint="D as one turn by Φ about the unit axis d (memo 1.1-1.3); switching it on animates once")
            self.gui_animate = gui.add_button(
                "Animate", icon=viser.Icon.PLAYER_PLAY,
                hint="two outlines turn from the space axes to D: dark, by sΦ about d (s = 0 → 1); "
                     "coloured, z-x-z in three steps (φ purple, θ pink, ψ teal)")
            self.readout_single = Readout(gui)
            self.readout_single.handle.visible = False
        self.folder_readout = gui.add_folder("Readout")
        with self.folder_readout:
            # Three texts, one shown at a time (the server knows which: only that one is sent while playing).
            self.readout_tabs = Tabs(gui, wrap, ("D", "Factors", "ω"), on_change=lambda _name: self.render_readout())
            # Each tab's fixed heading is a markdown of its own, sent once: only the numbers go at 2 Hz.
            with self.readout_tabs.tab("D"):
                gui.add_markdown("D = Rz(φ) Rx(θ) Rz(ψ), columns = x′ y′ z′ in space components; "
                                 "e_n = (cos φ, sin φ, 0), e_z′ = D e_z")
                self.readout_matrix = Readout(gui)
            with self.readout_tabs.tab("Factors"):
                self.readout_factors = Readout(gui)
            with self.readout_tabs.tab("ω"):
                gui.add_markdown("ω = (dφ/dt) e_z + (dθ/dt) e_n + (dψ/dt) e_z′ [deg/s]; ω_s = D ω_b")
                self.readout_omega = Readout(gui)
        self.folder_body = gui.add_folder("Body: principal moments [kg m²]", expand_by_default=False)
        with self.folder_body:
            self.gui_moments = [add_slider(gui, spec, value) for spec, value in zip(MOMENT_SPECS, self.sim.moments)]
            self.gui_moments_status = gui.add_markdown("")
        self.folder_display = gui.add_folder("Display", expand_by_default=False)
        with self.folder_display:
            self.gui_show_frames = gui.add_checkbox("Intermediate frames", True,
                                                    hint="ξηζ = Rz(φ) and ξ′η′ζ′ = Rz(φ) Rx(θ)")
            self.gui_show_arcs = gui.add_checkbox("Angle arcs", True)
            self.gui_show_omega = gui.add_checkbox("ω and its components", True)
            self.gui_reset_view = gui.add_button("Reset view", icon=viser.Icon.CAMERA)
            gui.add_markdown(
                "Thin red/green/blue arrows: space axes x y z.  \n"
                "Dark arrows: body axes x′ y′ z′ (the columns of D).  \n"
                "Gold: line of nodes e_n = (cos φ, sin φ, 0).  \n"
                "Faint: intermediate frames (η after φ, η′ after θ).  \n"
                f"ω arrows: 1 unit = {1.0 / RATE_ARROW_SCALE:g}°/s."
            )
        for index, handle in enumerate(self.gui_angles):
            self.bind(handle, f"{GREEK[KEYS[index]]} slider", self._angle_edit(index),
                      nth(lambda: self.sim.angles_deg, index), spec=ANGLE_SPECS[index])
        for index, handle in enumerate(self.gui_rates):
            self.bind(handle, "rate slider", self._rate_edit(index), nth(lambda: self.sim.rates_deg, index),
                      spec=RATE_SPECS[index])
        for index, handle in enumerate(self.gui_moments):
            self.bind(handle, f"I{index + 1} slider", self._moment_edit(index),
                      nth(lambda: self.sim.moments, index), spec=MOMENT_SPECS[index])
        for handle in (self.gui_show_frames, self.gui_show_arcs, self.gui_show_omega):
            handle.on_update(wrap("display toggle", lambda _event: self.refresh()))
        self.gui_reset_view.on_click(wrap("reset view", lambda _event: self.reset_view()))
        self.gui_single_rotation.on_update(wrap("single rotation", lambda _event: self._single_toggled()))
        self.gui_animate.on_click(wrap("animate", lambda _event: self.animate()))
        self._gui_roots = [self.gui_intro, self.message.handle, *self.transport.handles, self.folder_angles,
                           self.folder_rates, self.folder_single, self.folder_readout, self.folder_body,
                           self.folder_display]

    # ------------------------------------------------------------------ callbacks
    def _angle_edit(self, index: int) -> Callable[[float], None]:
        def apply(value: float) -> None:
            self.room.playing = False
            angles = list(self.sim.angles_deg)
            angles[index] = value
            self.sim.preset = None
            self.sim.set_angles(angles)
            self.room.refresh()

        return apply

    def _rate_edit(self, index: int) -> Callable[[float], None]:
        def apply(value: float) -> None:
            rates = list(self.sim.rates_deg)
            rates[index] = value
            self.sim.set_rates(rates)
            self.room.refresh()

        return apply

    def _moment_edit(self, index: int) -> Callable[[float], str | None]:
        def apply(value: float) -> str | None:
            moments = list(self.sim.moments)
            moments[index] = value
            try:
                self.sim.set_moments(moments)
            except InertiaError as error:
                shown = ", ".join(f"{m:.2f}" for m in self.sim.moments)
                self.gui_moments_status.content = (
                    f"**⚠ Not a rigid body:** {error}  \n"
                    "Each moment must be at most the sum of the other two "
                    f"(I1 + I2 ≥ I3 and cyclic).  Showing the last valid body, I = ({shown}) kg m²."
                )
                return (f"I{index + 1} = {value:g} refused: not a rigid body ({error}); "
                        f"the body stays I = ({shown}) kg m².")
            self.room.refresh()
            return None

        return apply

    def _single_toggled(self) -> None:
        if self.gui_single_rotation.value:
            self.animate()
        else:
            self._stop_animation()
        self.refresh()

    def animate(self) -> None:
        """Run the animation from s = 0 (switching `Single rotation` on if it is off, which
        starts it)."""
        if not self.gui_single_rotation.value:
            self.gui_single_rotation.value = True  # its callback comes back here
            return
        self.animation_time = 0.0
        self._zxz_step = -1
        self._draw_animation()

    def _stop_animation(self) -> None:
        self.animation_time = None
        for node in (self.ghost_turn, self.ghost_zxz):
            if node.visible:
                node.visible = False

    def _draw_animation(self) -> None:
        """The two outlines at the animation's time: exp(s Φ hat(d)) and the z-x-z turn, where
        s = time / ANIMATION_SECONDS (at most 1); gone after ANIMATION_HOLD more seconds."""
        time = self.animation_time
        if time is None:
            return
        if time >= ANIMATION_SECONDS + ANIMATION_HOLD or not self.gui_single_rotation.value:
            self._stop_animation()
            return
        s = min(time / ANIMATION_SECONDS, 1.0)
        rotation = self.single()
        phi, theta, psi = self.sim.angles
        steps = [min(max(3.0 * s - k, 0.0), 1.0) for k in range(3)]  # φ, then θ, then ψ
        R_zxz = rot_z(steps[0] * phi) @ rot_x(steps[1] * theta) @ rot_z(steps[2] * psi)
        step = min(int(3.0 * s), 2)
        if step != self._zxz_step:
            self._zxz_step = step
            self.ghost_zxz_lines.colors = _outline_colors(ARC_COLORS[ZXZ_KEYS[step]])
        set_wxyz(self.ghost_turn, wxyz_from_matrix(exp_so3(s * rotation.rotvec)))
        set_wxyz(self.ghost_zxz, wxyz_from_matrix(R_zxz))
        for node in (self.ghost_turn, self.ghost_zxz):
            if not node.visible:
                node.visible = True

    def set_angles_deg(self, phi: float, theta: float, psi: float) -> None:
        """Set (φ, θ, ψ) [deg], as dragging the three sliders does."""
        self.room.playing = False
        self.sim.set_angles((phi, theta, psi))
        self.room.refresh()

    def frame(self, dt: float) -> None:
        """The per-frame update while the angles move (and while the single rotation animates);
        arcs, sliders and text throttled."""
        if self.animation_time is not None:
            self.animation_time += dt
            with self.client.atomic():
                self._draw_animation()
        if self.sim.version == self._drawn_version:
            self.labels.update(dt)  # the camera may have moved
            return
        self._drawn_version = self.sim.version
        with self.client.atomic():
            self.render_pose(exact=not self.room.playing)
            self.render_arcs(exact=not self.room.playing)
            if self._arc_text_throttle.ready(dt):
                self.render_arc_text()
            if self._arc_throttle.ready(dt):
                self.render_single_rotation()
            self.labels.update(dt)
            if self._slider_throttle.ready(dt):
                self._sync_sliders()
            if self._readout_throttle.ready(dt):
                self.render_readout(only_shown=True)
                self.render_single_readout()
                self._refresh_status()

    def refresh(self) -> None:
        """Redraw everything from the simulation (all formulas from `physics`)."""
        self._drawn_version = self.sim.version
        with self.client.atomic():
            if self.sim.moments != self._drawn_moments:
                self.body.reshape(self._build_box)
            if self.sim.moments != self._outline_moments:
                outline = box_outline_segments(_box_edges(self.sim.moments), 0.6 * BODY_AXIS_LENGTH)
                self.ghost_turn_lines.points = outline
                self.ghost_zxz_lines.points = outline
                self._outline_moments = self.sim.moments
            self._refresh_moments_status()
            self.transport.show(self.room.playing, self.room.time_scale)
            self.presets_row.show_note(self.preset_shown())
            self._sync_sliders()
            exact = not self.room.playing  # a view built while playing draws what the others draw
            self.render_pose(exact)
            self.render_arcs(exact)
            self.render_arc_text()
            self.render_single_rotation()
            self._draw_animation()
            self.render_readout()
            self.render_single_readout()
            self._refresh_status()
            self.labels.settle()

    # ------------------------------------------------------------------ drawing
    def _sync_sliders(self) -> None:
        self.show_values(self.gui_angles, ANGLE_SPECS, self.sim.angles_deg)
        self.show_values(self.gui_rates, RATE_SPECS, self.sim.rates_deg)
        self.show_values(self.gui_moments, MOMENT_SPECS, self.sim.moments)

    def _refresh_status(self) -> None:
        state = "▶ playing" if self.room.playing else "paused"
        self.transport.set_status(f"**t = {self.sim.t:.2f} s** · {state} · {self.room.time_scale:g}×")

    def _refresh_moments_status(self) -> None:
        edges = _box_edges(self.sim.moments)
        flat = edges.min() <= MIN_EDGE
        shown = edges / edges.min()
        status = f"Uniform box with edges along x′, y′, z′ in the ratio **{', '.join(f'{r:.2f}' for r in shown)}**."
        if flat:
            status += "  \nA flat lamina: one triangle inequality holds with equality."
        if self.gui_moments_status.content != status:
            self.gui_moments_status.content = status

    def render_pose(self, exact: bool = True) -> None:
        """The per-frame part: the chain of frames (after φ, after θ, body), the line of nodes'
        fade, the ω arrows.  While playing (exact=False) each angle is drawn at display
        resolution (app.kit.lean: a step moves the frame's farthest point by ~1 px) and a
        message goes only when what is drawn changed."""
        phi, theta, psi = self.sim.angles
        if not exact:  # everything θ turns is drawn from the same snapped θ: sent in the same frames
            phi = snap(phi, TOLERANCE / PHI_REACH)
            theta = snap(theta, TOLERANCE / THETA_REACH)
            psi = snap(psi, TOLERANCE / PSI_REACH)
        self.poses["phi"].set((math.cos(0.5 * phi), 0.0, 0.0, math.sin(0.5 * phi)))
        turn_theta = (math.cos(0.5 * theta), math.sin(0.5 * theta), 0.0, 0.0)
        self.poses["theta"].set(turn_theta)
        self.poses["psi"].set((math.cos(0.5 * psi), 0.0, 0.0, math.sin(0.5 * psi)))
        show_frames = bool(self.gui_show_frames.value)
        for axes in self.frame_axes:
            if axes.visible != show_frames:
                axes.visible = show_frames
        self.nodes.update(0.0, theta)  # its frame rides on the after-φ frame: only the fade changes
        # ω head to tail: φ̇ e_z, then θ̇ e_n, then ψ̇ e_z′ (each scaled to scene units).
        dphi, dtheta, dpsi = (RATE_ARROW_SCALE * r for r in self.sim.rates_deg)
        show = bool(self.gui_show_omega.value)
        zero = np.zeros(3)
        a_phi = np.array([0.0, 0.0, dphi])  # tip of φ̇ e_z (space = after-φ coordinates on the z axis)
        a_theta = np.array([dtheta, 0.0, dphi])  # tip of θ̇ e_n, after-φ coordinates
        self.rate_vectors["phi"].update(zero, a_phi, show)
        self.rate_vectors["theta"].update(a_phi, a_theta, show)
        self.rate_vectors["psi"].update(zero, np.array([0.0, 0.0, dpsi]), show)  # in its frame at a_theta
        self.omega_psi_pose.set(turn_theta, tuple(a_theta))
        tip = a_theta + dpsi * np.array([0.0, -math.sin(theta), math.cos(theta)])  # ω, after-φ coordinates
        self.omega.set(tip, zero, shown=show, exact=exact)
        omega_label = (0.0, 0.0, dpsi + math.copysign(0.16, dpsi))  # beyond the common tip, along e_z′
        if tuple(self.omega_label.position) != omega_label:
            set_position(self.omega_label, omega_label)
        self.labels.want(self.omega_label, show and self.omega.visible)

    def omega_chain(self) -> list[np.ndarray]:
        """The ω arrows as drawn, in space coordinates: [(2, 3) for φ̇ e_z, θ̇ e_n, ψ̇ e_z′, ω]
        (each composed through the frames it hangs in; for tests and the export)."""
        chain = []
        for node_segment, handle in ((self.rate_vectors["phi"].segment(), self.rate_vectors["phi"].arrow),
                                     (self.rate_vectors["theta"].segment(), self.rate_vectors["theta"].arrow),
                                     (self.rate_vectors["psi"].segment(), self.rate_vectors["psi"].arrow),
                                     ):
            R, p = world_pose(handle)
            chain.append(node_segment @ R.T + p)
        return [*chain, self.omega.world_segment()]

    def render_arcs(self, exact: bool = True) -> None:
        """Arcs for φ, θ, ψ (pieces riding on the frames: messages only when a piece appears or
        goes) and their labels; the readings' text throttled by the caller."""
        show_arcs = bool(self.gui_show_arcs.value)
        for key, angle in zip(KEYS, self.sim.angles):
            arc = self.arcs[key]
            arc.show(angle, show_arcs, exact=exact)
            visible = show_arcs and abs(angle) >= arc.MIN_ANGLE
            where = arc.label_point(angle)
            if where != self._arc_label_at[key]:
                self._arc_label_at[key] = where
                set_position(self.arc_labels[key], where)
            self.labels.want(self.arc_labels[key], visible)

    def render_arc_text(self) -> None:
        for key, angle_deg in zip(KEYS, self.sim.angles_deg):
            text = f"{GREEK[key]} = {format_deg(angle_deg, 0)}°"
            if self.arc_labels[key].text != text:
                self.arc_labels[key].text = text

    def render_readout(self, only_shown: bool = False) -> None:
        """D, its factors, ω (space and body components) and the gimbal-lock note; while
        playing (`only_shown`) only the readout tab on screen."""
        shown = self.readout_tabs.shown if only_shown else None
        phi, theta, psi = self.sim.angles
        R = euler_frames(phi, theta, psi).body
        e_n = line_of_nodes(phi)
        e_z_body = body_z_axis(phi, theta)
        angles_deg = self.sim.angles_deg
        note = gimbal_note(angles_deg[1])
        if self.gui_gimbal_note.visible != (note is not None):
            self.gui_gimbal_note.visible = note is not None
        if note is not None and self.gui_gimbal_note.content != note:
            self.gui_gimbal_note.content = note
        if shown in (None, "D"):
            self.readout_matrix.set(  # under its fixed heading (built in _build_gui)
                f"```\n{format_matrix(R, 4)}\n```\n"
                f"e_n = {format_vector(e_n)}  \n"
                f"e_z′ = {format_vector(e_z_body)}"
            )
        factors = ((f"Rz(φ), φ = {format_deg(angles_deg[0])}°", rot_z(phi)),
                   (f"Rx(θ), θ = {angles_deg[1]:.2f}°", rot_x(theta)),
                   (f"Rz(ψ), ψ = {format_deg(angles_deg[2])}°", rot_z(psi)))
        if shown in (None, "Factors"):
            self.readout_factors.set("\n".join(f"{title}\n```\n{format_matrix(M, 4)}\n```" for title, M in factors))
        if shown not in (None, "ω"):
            return
        angles, rates = np.array([phi, theta, psi]), np.radians(self.sim.rates_deg)
        omega_space = np.degrees(omega_space_from_euler_rates(angles, rates))
        omega_body = np.degrees(omega_body_from_euler_rates(angles, rates))
        dphi, dtheta, dpsi = self.sim.rates_deg

        def row(name: str, v: Any) -> str:
            return f"{name:<14}" + "".join(f"{(0.0 if abs(x) < 5e-4 else x):10.3f}" for x in v)

        self.readout_omega.set(
            "```\n"  # under its fixed heading (built in _build_gui)
            f"dφ/dt = {dphi:g}   dθ/dt = {dtheta:g}   dψ/dt = {dpsi:g}   [deg/s]\n\n"
            f"{'':<14}{'x | x′':>10}{'y | y′':>10}{'z | z′':>10}\n"
            f"{row('(dφ/dt) e_z', (0.0, 0.0, dphi))}\n"
            f"{row('(dθ/dt) e_n', dtheta * e_n)}\n"
            f"{row('(dψ/dt) e_z′', dpsi * e_z_body)}\n"
            f"{row('ω_s (space)', omega_space)}\n"
            f"{row('ω_b (body)', omega_body)}\n"
            f"|ω| = {float(np.linalg.norm(omega_space)):.3f} deg/s\n```"
        )

    # ------------------------------------------------------------------ the single rotation
    def single(self) -> SingleRotation:
        """D as one turn (`physics.so3.single_rotation`), computed once per simulation version,
        the sign of d near Φ = π the one nearer the axis last drawn."""
        if self._single is None or self._single[0] != self.sim.version:
            rotation = single_rotation(self.sim.R_space_body, self._last_axis)
            if rotation.axis is not None:
                self._last_axis = rotation.axis
            self._single = (self.sim.version, rotation)
        return self._single[1]

    def render_single_rotation(self) -> None:
        """The axis d (both ways from the origin) and the arc Φ about it, if the toggle is on and
        D has an axis (Φ > 0)."""
        on = bool(self.gui_single_rotation.value)
        rotation = self.single() if on else None
        shown = rotation is not None and rotation.axis is not None
        if self.single_node.visible != on:
            self.single_node.visible = on
        for node in (self.single_axis, self.single_arc):
            if node.visible != shown:
                node.visible = shown
        for label in (self.single_axis_label, self.single_arc_label):
            self.labels.want(label, shown)  # the view's LabelLayer shows it where there is room
        if rotation is None or rotation.axis is None:
            return
        d = rotation.axis
        set_points(self.single_axis, np.array([[-SINGLE_AXIS_HALF_LENGTH * d, SINGLE_AXIS_HALF_LENGTH * d]],
                                              dtype=np.float32))
        tip = (SINGLE_AXIS_HALF_LENGTH + 0.25) * d
        set_position(self.single_axis_label, (float(tip[0]), float(tip[1]), float(tip[2])))
        k = arc_reference_axis(d, self._arc_axis)
        if k != self._arc_axis:
            self._arc_axis = k
            colors = np.empty((ARC_SEGMENTS + 2, 2, 3), dtype=np.uint8)
            colors[:ARC_SEGMENTS] = SINGLE_COLOR
            colors[ARC_SEGMENTS] = SPACE_AXIS_COLORS[k]
            colors[ARC_SEGMENTS + 1] = BODY_AXIS_COLORS[k]
            self.single_arc.colors = colors
        e_k = np.eye(3)[k]
        u = e_k - float(d @ e_k) * d  # e_k projected on the plane ⟂ d
        u *= SINGLE_ARC_RADIUS / float(np.linalg.norm(u))
        points = turn_path(d, rotation.angle, u, ARC_SEGMENTS)  # u, ..., D u
        spokes = np.array([[np.zeros(3), points[0]], [np.zeros(3), points[-1]]])
        set_points(self.single_arc, np.concatenate([polyline_segments(points), spokes]).astype(np.float32))
        middle = 0.8 * points[ARC_SEGMENTS // 2]  # inside the arc: clear of the d label at the axis tip
        set_position(self.single_arc_label, (float(middle[0]), float(middle[1]), float(middle[2])))
        text = f"Φ = {math.degrees(rotation.angle):.1f}°"
        if self.single_arc_label.text != text:
            self.single_arc_label.text = text

    def render_single_readout(self) -> None:
        """Φ, d, A = Φ hat(d), the rotation vector and the quaternion (shown with the toggle)."""
        on = bool(self.gui_single_rotation.value)
        if self.readout_single.handle.visible != on:
            self.readout_single.handle.visible = on
        if not on:
            return
        rotation = self.single()
        D = self.sim.R_space_body
        angle_deg = math.degrees(rotation.angle)
        lines = [f"**Φ = {angle_deg:.2f}°** = {rotation.angle:.4f} rad;  "
                 f"cos Φ = (tr D − 1)/2 = {0.5 * (float(np.trace(D)) - 1.0):.4f} (1.1)  "]
        if rotation.axis is None:
            lines.append("**d undefined**: Φ = 0, D = 1 — a turn by 0 about any axis.  ")
        else:
            lines.append(f"**d = {format_vector(rotation.axis, 4)}** (D d = d)  ")
            if math.pi - rotation.angle <= HALF_TURN_BAND:
                lines.append("Half turn: d and −d give the same D; d from (D + 1)/2 = d dᵀ, "
                             "its sign kept from the axis drawn before.  ")
        w, x, y, z = rotation.wxyz
        lines.append(
            "```\n"
            f"A = Φ hat(d), D = exp(A) (1.2, 1.3)\n{format_matrix(rotation.A, 4)}\n"
            f"Φ d = {format_vector(rotation.rotvec, 4)} rad\n"
            f"q = (cos Φ/2, sin Φ/2 d)\n  = {format_vector(np.array([w, x, y, z]), 4)}\n```"
        )
        self.readout_single.set("\n".join(lines))
