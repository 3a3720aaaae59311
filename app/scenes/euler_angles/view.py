"""The z-x-z Euler-angle explorer's view ("Euler angles" scene): nodes, panel and drawing.

What it shows (docs/CONVENTIONS.md, "Euler angles", "Angular velocity"): the space axes x y z,
a box whose proportions follow its principal moments, its body axes x′ y′ z′, the line of nodes
e_n = (cos φ, sin φ, 0), the two intermediate frames of D = Rz(φ) Rx(θ) Rz(ψ) (after φ:
ξηζ = Rz(φ); after θ: ξ′η′ζ′ = Rz(φ) Rx(θ)), arcs for φ, θ, ψ, and the angular velocity
ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′ (memo 1.17) drawn head to tail: φ̇ e_z from the origin, θ̇ e_n
from its tip, ψ̇ e_z′ from that one, and the resultant ω from the origin to the end.
Readouts (`app.scenes.euler_angles.readouts`): D, its three factors, and ω with its space (ω_s)
and body (ω_b) components.  The single rotation D = exp(Φ hat(d)) (the toggle `Single rotation`,
off by default) is `app.scenes.euler_angles.single_rotation`.

The simulation (`app.scenes.euler_angles.simulation.EulerAnglesSimulation`, no viser) advances
the angles at the set rates, so the sliders wrap.  Near θ = 0° or 180° the line of nodes fades
and the panel says that only φ + ψ (or φ − ψ) is defined.  Every formula comes from `physics`;
degrees on the sliders, radians everywhere else.  Presets: `assets/presets/euler_angles.json`.

**What a playing frame sends** (the frame budget, tests/test_frame_budget.py; the first
preset, φ̇ θ̇ ψ̇ = 20, 10, 45 °/s).  The decomposition is a chain of frames, each turned by one
angle about one of its own axes: after φ (`/e/p`), after θ (`/e/p/t`), the body (`/e/p/t/s`);
everything else rides on the frame it is fixed in (the line of nodes and the fixed arc pieces
on the after-φ frame, η′ and the ψ arc on the after-θ frame, the box and its axes on the body).
While playing each angle is snapped so that a step moves its frame's farthest point by ~1 px
(`app.kit.draw.lean.Pose`), and a frame's turn is sent only when its snapped angle changed: φ and ψ
one orientation message every frame, θ about three frames in four.  ω's components are fixed
in frames that are sent anyway: φ̇ e_z in space, θ̇ e_n in the after-φ frame (no message while
the rates are constant), ψ̇ e_z′ (with ω's label) in a frame at θ̇ e_n's tip turned by the same
Rx(θ) as the after-θ frame, so its orientation message repeats the after-θ frame's values in
the same window (~5 B compressed).  The resultant ω depends on θ (and the rates) only: it
lives in the after-φ frame as an `app.kit.draw.lean.FrameArrow`, an orientation message at each
θ step that moves its tip and a z-scale message when its length moved by ~1 px (about one
frame in five).  Labels: anchors and visibility only when the view's `LabelLayer` changes
them (10 Hz), the arcs' readings at 2 Hz; the sliders, the status line and the readout tab
shown at 2 Hz (the readouts' fixed headings are markdowns of their own, sent once).  Node
names are short (`/e`, `/e/p`, ...): every message carries its node's name.  Measured
(2026-11-25, four seconds): 224 / 222 B/frame own / follower, 5.1 scene messages a frame (4.3 of
them orientations).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import viser

from app.i18n import N_
from app.kit.core.common import (
    OMEGA_COLOR,
    CameraView,
    SliderSpec,
    Throttle,
    Wrap,
    axis_segments,
    gimbal_note,
)
from app.kit.core.presets import Preset
from app.kit.core.room import Room
from app.kit.draw.labels import DETAIL, KEY, LabelLayer
from app.kit.draw.lean import TOLERANCE, ArcPieces, FrameArrow, Pose, snap, world_pose
from app.kit.draw.widgets import NODES_LABELS, Body, LineOfNodes, Stage
from app.kit.panel.gui import PresetsRow, Readout, Tabs, Transport, add_slider
from app.kit.view import SceneView, nth
from app.scenes.euler_angles import readouts
from app.scenes.euler_angles.simulation import GREEK, KEYS, EulerAnglesSimulation, box_edges
from app.scenes.euler_angles.single_rotation import SingleRotationPart
from app.viser_internals import set_points, set_position
from physics._types import Vec3
from physics.inertia import InertiaError

__all__ = [
    "ANGLE_SPECS",
    "INITIAL_CAMERA",
    "INITIAL_FOV_DEG",
    "MOMENT_SPECS",
    "RATE_ARROW_SCALE",
    "RATE_SPECS",
    "VIEW",
    "EulerAnglesView",
]

_FULL_MARKS = ((-180.0, "-180°"), (-90.0, "-90°"), (0.0, "0°"), (90.0, "90°"), (180.0, "180°"))
# Labels and hints in English, marked for the catalogs (app.i18n): a view shows them translated
# (`SliderSpec.translated`).  Unit symbols and formulas stay.
ANGLE_SPECS = (
    SliderSpec("phi", N_("φ [deg]"), -180.0, 180.0, 1.0, N_("precession about the space z axis (applied first)"),
               _FULL_MARKS),
    SliderSpec("theta", N_("θ [deg]"), 0.0, 180.0, 1.0, N_("nutation about the line of nodes (applied second)"),
               ((0.0, "0°"), (45.0, "45°"), (90.0, "90°"), (135.0, "135°"), (180.0, "180°"))),
    SliderSpec("psi", N_("ψ [deg]"), -180.0, 180.0, 1.0, N_("spin about the body z′ axis (applied last)"),
               _FULL_MARKS),
)
_RATE_MARKS = ((-180.0, "-180"), (-90.0, "-90"), (0.0, "0"), (90.0, "90"), (180.0, "180"))
RATE_SPECS = (
    SliderSpec("phi_dot", N_("dφ/dt [deg/s]"), -180.0, 180.0, 1.0, N_("dφ/dt: Play advances φ at this rate"),
               _RATE_MARKS),
    SliderSpec("theta_dot", N_("dθ/dt [deg/s]"), -180.0, 180.0, 1.0, N_("dθ/dt: Play advances θ at this rate"),
               _RATE_MARKS),
    SliderSpec("psi_dot", N_("dψ/dt [deg/s]"), -180.0, 180.0, 1.0, N_("dψ/dt: Play advances ψ at this rate"),
               _RATE_MARKS),
)
MOMENT_SPECS = (
    SliderSpec("I1", "I1 [kg m²]", 0.1, 5.0, 0.05, N_("principal moment about the body x′ axis")),
    SliderSpec("I2", "I2 [kg m²]", 0.1, 5.0, 0.05, N_("principal moment about the body y′ axis")),
    SliderSpec("I3", "I3 [kg m²]", 0.1, 5.0, 0.05, N_("principal moment about the body z′ axis")),
)
INTRO = N_(
    "### Euler angles, z-x-z convention\n"
    "**D = Rz(φ) Rx(θ) Rz(ψ)**, body → space (x = D x′).  \n"
    "φ: precession about z · θ: nutation about the line of nodes · "
    "ψ: spin about z′.  Angles in **degrees**.  \n"
    "**ω = (dφ/dt) e_z + (dθ/dt) e_n + (dψ/dt) e_z′** (orange, head to tail)."
)
LEGEND = N_(
    "Thin red/green/blue arrows: space axes x y z.  \n"
    "Dark arrows: body axes x′ y′ z′ (the columns of D).  \n"
    "Gold: line of nodes e_n = (cos φ, sin φ, 0).  \n"
    "Faint: intermediate frames (η after φ, η′ after θ).  \n"
    "ω arrows: 1 unit = {scale}°/s."
)
READOUT_TABS = ("D", N_("Factors"), "ω")
BODY_AXIS_LENGTH = 1.35
FRAME_AXIS_LENGTH = 1.1
ARC_RADII = {"phi": 1.2, "theta": 1.05, "psi": 0.95}
RATE_ARROW_SCALE = 1.0 / 30.0  # [scene units per deg/s]: 30°/s is one unit long
FRAME_COLORS = ((240, 160, 160), (150, 215, 160), (160, 180, 245))
BODY_COLOR = (235, 170, 70)
BODY_OPACITY = 0.7
ARC_COLORS = {"phi": (140, 50, 210), "theta": (215, 0, 120), "psi": (0, 140, 140)}
SHORT = {"phi": "p", "theta": "t", "psi": "s"}  # in node names (every message carries its node's name)

# Seen from x > 0, y < 0 so that x, y, the line of nodes and x′ are all visible for typical
# angles (φ ≈ 30°), with the origin left of centre to clear the GUI panel on the right.
VIEW = CameraView(position=(5.9, -2.0, 3.3), look_at=(0.5, 1.15, 0.25), fov_deg=40.0)
INITIAL_CAMERA = {"position": VIEW.position, "look_at": VIEW.look_at, "up": VIEW.up}
INITIAL_FOV_DEG = VIEW.fov_deg

ARC_PERIOD = 1.0 / 20.0  # [s] the single rotation's axis and arc while playing (20 Hz)
ARC_TEXT_PERIOD = 0.5  # [s] the arcs' readings ("φ = 31°") while playing (2 Hz; exact when paused)
SLIDER_PERIOD = 0.5  # sliders follow at 2 Hz while playing (read when paused: a refresh writes them exactly)
# How far the drawn points of each frame reach from the origin [scene units]: a turn is sent when
# it moves them by more than app.kit.draw.lean.TOLERANCE (the ω arrows are at most ~2 long at 30°/s per unit).
PHI_REACH = 2.2  # the line of nodes (1.9), ω's components
THETA_REACH = 1.6  # the body under the after-θ frame (axes 1.35 and labels), ψ̇ e_z′ (≤ 1.5 at 45°/s) turning ω's tip
PSI_REACH = 1.6  # the body's axes (1.35) and their labels
READOUT_PERIOD = 0.5  # the readout tab shown and the status line, while playing (2 Hz; exact when paused)


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

    title = N_("Euler angles")  # the scene dropdown shows it translated (app.i18n)
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

    @classmethod
    def moment_preset(cls, room: Room, name: str) -> Preset:
        """The angles shown and the rates [deg/s] as a preset (the sliders' values now)."""
        sim: EulerAnglesSimulation = room.sim
        phi, theta, psi = (float(a) for a in sim.angles_deg)
        note = f"Saved at t = {sim.t:.2f} s" + (f" of {sim.preset}" if getattr(sim, "preset", None) else "") + "."
        return Preset(name, "Mine", note, (), (phi, theta, psi), tuple(float(r) for r in sim.rates_deg))

    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: EulerAnglesSimulation = room.sim
        self._drawn_version = -1
        self._drawn_moments: tuple[float, ...] = ()
        self._arc_throttle = Throttle(ARC_PERIOD)
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self._readout_throttle = Throttle(READOUT_PERIOD)
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
        # (app.kit.draw.lean.Pose): a steady precession sends one small message a frame, not four.
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
        defined, undefined = (self.tr.gettext(text) for text in NODES_LABELS)
        self.nodes = LineOfNodes(scene, f"{root}/p/n", labels=labels, text=(defined, undefined))
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
        # The single rotation D = exp(Φ hat(d)): axis, arc (with its two spokes), two animated outlines;
        # its folder comes between the rates and the readout.
        self.single_rotation = SingleRotationPart(self.client, root, labels, self.sim,
                                                  tuple(ARC_COLORS[key] for key in KEYS), 0.6 * BODY_AXIS_LENGTH)

    def _build_box(self, scene: Any, parent: str) -> None:
        self.body_box = scene.add_box(
            f"{parent}/box", color=BODY_COLOR, dimensions=tuple(float(e) for e in box_edges(self.sim.moments)),
            opacity=BODY_OPACITY, flat_shading=True, cast_shadow=False, receive_shadow=False,
        )
        self._drawn_moments = self.sim.moments

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        tr = self.tr
        _ = tr.gettext
        angle_specs = [spec.translated(tr) for spec in ANGLE_SPECS]
        rate_specs = [spec.translated(tr) for spec in RATE_SPECS]
        moment_specs = [spec.translated(tr) for spec in MOMENT_SPECS]
        self.build_head(_(INTRO))
        self.folder_angles = gui.add_folder(_("Euler angles z-x-z [deg]"))
        with self.folder_angles:
            self.gui_angles = [add_slider(gui, spec, value) for spec, value in zip(angle_specs, self.sim.angles_deg)]
            self.gui_gimbal_note = gui.add_markdown("", visible=False)
            self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset, self.choose_own_preset,
                                          tr=tr)
        self.folder_rates = gui.add_folder(_("Euler rates [deg/s]"))
        with self.folder_rates:
            self.gui_rates = [add_slider(gui, spec, value) for spec, value in zip(rate_specs, self.sim.rates_deg)]
        self.folder_single = self.single_rotation.build_gui(tr)
        self.folder_readout = gui.add_folder(_("Readout"))
        with self.folder_readout:
            # Three texts, one shown at a time (the server knows which: only that one is sent while playing).
            self.readout_tabs = Tabs(gui, wrap, READOUT_TABS, on_change=lambda _name: self.render_readout(), tr=tr)
            # Each tab's fixed heading is a markdown of its own, sent once: only the numbers go at 2 Hz.
            with self.readout_tabs.tab("D"):
                gui.add_markdown(_("D = Rz(φ) Rx(θ) Rz(ψ), columns = x′ y′ z′ in space components; "
                                   "e_n = (cos φ, sin φ, 0), e_z′ = D e_z"))
                self.readout_matrix = Readout(gui)
            with self.readout_tabs.tab("Factors"):
                self.readout_factors = Readout(gui)
            with self.readout_tabs.tab("ω"):
                gui.add_markdown(_("ω = (dφ/dt) e_z + (dθ/dt) e_n + (dψ/dt) e_z′ [deg/s]; ω_s = D ω_b"))
                self.readout_omega = Readout(gui)
        self.folder_body = gui.add_folder(_("Body: principal moments [kg m²]"), expand_by_default=False)
        with self.folder_body:
            self.gui_moments = [add_slider(gui, spec, value) for spec, value in zip(moment_specs, self.sim.moments)]
            self.gui_moments_status = gui.add_markdown("")
        self.folder_display = gui.add_folder(_("Display"), expand_by_default=False)
        with self.folder_display:
            self.gui_show_frames = gui.add_checkbox(_("Intermediate frames"), True,
                                                    hint=_("ξηζ = Rz(φ) and ξ′η′ζ′ = Rz(φ) Rx(θ)"))
            self.gui_show_arcs = gui.add_checkbox(_("Angle arcs"), True)
            self.gui_show_omega = gui.add_checkbox(_("ω and its components"), True)
            self.gui_reset_view = gui.add_button(_("Reset view"), icon=viser.Icon.CAMERA)
            gui.add_markdown(_(LEGEND).format(scale=tr.general(1.0 / RATE_ARROW_SCALE)))
        for index, handle in enumerate(self.gui_angles):
            self.bind(handle, f"{GREEK[KEYS[index]]} slider", self._angle_edit(index),
                      nth(lambda: self.sim.angles_deg, index), spec=angle_specs[index])
        for index, handle in enumerate(self.gui_rates):
            self.bind(handle, "rate slider", self._rate_edit(index), nth(lambda: self.sim.rates_deg, index),
                      spec=rate_specs[index])
        for index, handle in enumerate(self.gui_moments):
            self.bind(handle, f"I{index + 1} slider", self._moment_edit(index),
                      nth(lambda: self.sim.moments, index), spec=moment_specs[index])
        for handle in (self.gui_show_frames, self.gui_show_arcs, self.gui_show_omega):
            handle.on_update(wrap("display toggle", lambda _event: self.refresh()))
        self.gui_reset_view.on_click(wrap("reset view", lambda _event: self.reset_view()))
        self.single_rotation.connect(wrap, self.refresh)
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
                self.gui_moments_status.content = readouts.moments_refused_text(error, self.sim.moments, self.tr)
                return readouts.moments_refused_message(index, value, error, self.sim.moments, self.tr)
            self.room.refresh()
            return None

        return apply

    def set_angles_deg(self, phi: float, theta: float, psi: float) -> None:
        """Set (φ, θ, ψ) [deg], as dragging the three sliders does."""
        self.room.playing = False
        self.sim.set_angles((phi, theta, psi))
        self.room.refresh()

    def frame(self, dt: float) -> None:
        """The per-frame update while the angles move (and while the single rotation animates);
        arcs, sliders and text throttled."""
        self.single_rotation.advance(dt)
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
                self.single_rotation.render()
            self.labels.update(dt)
            if self._slider_throttle.ready(dt):
                self._sync_sliders()
            if self._readout_throttle.ready(dt):
                self.render_readout(only_shown=True)
                self.single_rotation.render_readout()
                self._refresh_status()

    def refresh(self) -> None:
        """Redraw everything from the simulation (all formulas from `physics`)."""
        self._drawn_version = self.sim.version
        with self.client.atomic():
            if self.sim.moments != self._drawn_moments:
                self.body.reshape(self._build_box)
            self.single_rotation.reshape()
            self._refresh_moments_status()
            self.transport.show(self.room.playing, self.room.time_scale)
            self.presets_row.show_note(self.preset_shown())
            self._sync_sliders()
            exact = not self.room.playing  # a view built while playing draws what the others draw
            self.render_pose(exact)
            self.render_arcs(exact)
            self.render_arc_text()
            self.single_rotation.render()
            self.single_rotation.draw_animation()
            self.render_readout()
            self.single_rotation.render_readout()
            self._refresh_status()
            self.labels.settle()

    # ------------------------------------------------------------------ drawing
    def _sync_sliders(self) -> None:
        self.show_values(self.gui_angles, ANGLE_SPECS, self.sim.angles_deg)
        self.show_values(self.gui_rates, RATE_SPECS, self.sim.rates_deg)
        self.show_values(self.gui_moments, MOMENT_SPECS, self.sim.moments)

    def _refresh_status(self) -> None:
        self.transport.set_status(readouts.status_text(self.sim.t, self.room.playing, self.room.time_scale, self.tr))

    def _refresh_moments_status(self) -> None:
        status = readouts.body_text(self.sim.moments, self.tr)
        if self.gui_moments_status.content != status:
            self.gui_moments_status.content = status

    def render_pose(self, exact: bool = True) -> None:
        """The per-frame part: the chain of frames (after φ, after θ, body), the line of nodes'
        fade, the ω arrows.  While playing (exact=False) each angle is drawn at display
        resolution (app.kit.draw.lean: a step moves the frame's farthest point by ~1 px) and a
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
            text = readouts.arc_text(key, angle_deg)
            if self.arc_labels[key].text != text:
                self.arc_labels[key].text = text

    def render_readout(self, only_shown: bool = False) -> None:
        """D, its factors, ω (space and body components) and the gimbal-lock note; while
        playing (`only_shown`) only the readout tab on screen (each under its fixed heading,
        built in _build_gui)."""
        shown = self.readout_tabs.shown if only_shown else None
        angles_deg = self.sim.angles_deg
        note = gimbal_note(angles_deg[1])
        if note is not None:
            note = self.tr.gettext(note)
        if self.gui_gimbal_note.visible != (note is not None):
            self.gui_gimbal_note.visible = note is not None
        if note is not None and self.gui_gimbal_note.content != note:
            self.gui_gimbal_note.content = note
        if shown in (None, "D"):
            self.readout_matrix.set(readouts.matrix_text(angles_deg))
        if shown in (None, "Factors"):
            self.readout_factors.set(readouts.factors_text(angles_deg))
        if shown in (None, "ω"):
            self.readout_omega.set(readouts.omega_text(angles_deg, self.sim.rates_deg, self.tr))
