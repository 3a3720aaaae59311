"""The z-x-z Euler-angle explorer ("Euler angles" scene), drawn for one client.

What it shows (PHYSICS.md, "Euler angles", "Angular velocity"): the space axes x y z, a box
whose proportions follow its principal moments, its body axes x′ y′ z′, the line of nodes
e_n = (cos φ, sin φ, 0), the two intermediate frames of D = Rz(φ) Rx(θ) Rz(ψ) (after φ:
ξηζ = Rz(φ); after θ: ξ′η′ζ′ = Rz(φ) Rx(θ)), arcs for φ, θ, ψ, and the angular velocity
ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′ (1.17) drawn head to tail: φ̇ e_z from the origin, θ̇ e_n from its
tip, ψ̇ e_z′ from that one, and the resultant ω from the origin to the end.  Readouts: D, its
three factors, and ω with its space (ω_s) and body (ω_b) components.

Play advances the angles at the set rates (φ, θ, ψ grow linearly; a θ outside [0°, 180°]
is shown as the equivalent (φ + 180°, 360° − θ, ψ + 180°), so the sliders wrap).  Near θ = 0°
or 180° the line of nodes fades and the panel says that only φ + ψ (or φ − ψ) is defined.

Every formula comes from `physics` (euler_frames, line_of_nodes, body_z_axis,
omega_space_from_euler_rates, omega_body_from_euler_rates, rot_x, rot_z and the inertia
checks); this module only turns matrices into drawing commands.  Degrees on the sliders,
radians everywhere else.  Values a client sends out of range are refused with a message.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import viser

from app.common import (
    BODY_AXIS_COLORS,
    GIMBAL_FADE_DEG,
    NODES_COLOR,
    NODES_FADED_COLOR,
    OMEGA_COLOR,
    SPACE_AXIS_COLORS,
    CameraView,
    Guard,
    Throttle,
    apply_camera,
    axis_segments,
    checked_value,
    clamp_finite,
    fade_color,
    format_matrix,
    format_vector,
    gimbal_note,
    polyline_segments,
    wrap_deg,
    wxyz_from_matrix,
)
from app.controls import PlaybackControls, STEP_DT
from physics._types import Mat3
from physics.euler import (
    body_z_axis,
    euler_frames,
    line_of_nodes,
    omega_body_from_euler_rates,
    omega_space_from_euler_rates,
)
from physics.inertia import InertiaError, box_extents_from_moments, validate_principal_moments
from physics.so3 import rot_x, rot_z

__all__ = [
    "ANGLE_RANGES_DEG",
    "GIMBAL_LOCK_DEG",
    "INITIAL_ANGLES_DEG",
    "INITIAL_CAMERA",
    "INITIAL_FOV_DEG",
    "INITIAL_RATES_DEG",
    "PRESETS_DEG",
    "RATE_RANGE_DEG",
    "VIEW",
    "ExplorerScene",
    "canonical_angles_deg",
    "clamp_finite",
    "format_matrix",
    "wxyz_from_matrix",
]

# Slider ranges [deg]: φ, ψ in [-180, 180], θ in [0, 180] (PHYSICS.md principal ranges).
ANGLE_RANGES_DEG: dict[str, tuple[float, float]] = {
    "phi": (-180.0, 180.0),
    "theta": (0.0, 180.0),
    "psi": (-180.0, 180.0),
}
RATE_RANGE_DEG = (-180.0, 180.0)  # [deg/s] each Euler rate
INITIAL_ANGLES_DEG = (30.0, 50.0, 20.0)  # a generic pose: every element of the picture visible
INITIAL_RATES_DEG = (20.0, 10.0, 45.0)  # [deg/s] φ̇, θ̇, ψ̇
PRESETS_DEG: dict[str, tuple[float, float, float]] = {  # button label -> (φ, θ, ψ) [deg]
    "30°, 50°, 20°": INITIAL_ANGLES_DEG,
    "D = 1": (0.0, 0.0, 0.0),
    "gimbal lock": (30.0, 0.0, 20.0),
}
GIMBAL_LOCK_DEG = 2.0  # within this of θ = 0° or 180° the line of nodes is shown undefined
MOMENT_RANGE = (0.1, 5.0)  # [kg m²] slider range of each principal moment
MOMENT_STEP = 0.05
INITIAL_MOMENTS = (1.0, 2.0, 2.6)  # box with edges a : b : c = 3 : 2 : 1
BODY_SIZE = 1.25  # display length [scene units] of the body's longest edge
MIN_EDGE = 0.02  # display thickness of a flat body (a lamina: I1 + I2 = I3)

# Lengths [scene units].
SPACE_AXIS_LENGTH = 1.9
BODY_AXIS_LENGTH = 1.35
FRAME_AXIS_LENGTH = 1.1
NODES_HALF_LENGTH = 1.75
ARC_RADII = {"phi": 1.2, "theta": 1.05, "psi": 0.95}
ARC_SEGMENTS = 48
RATE_ARROW_SCALE = 1.0 / 30.0  # [scene units per deg/s]: 30°/s is one unit long

# Colours (RGB 0-255).
SPACE_COLORS = SPACE_AXIS_COLORS
BODY_COLORS = BODY_AXIS_COLORS
FRAME_COLORS = ((240, 160, 160), (150, 215, 160), (160, 180, 245))
BODY_COLOR = (235, 170, 70)
BODY_OPACITY = 0.7
ARC_COLORS = {"phi": (140, 50, 210), "theta": (215, 0, 120), "psi": (0, 140, 140)}
GREEK = {"phi": "φ", "theta": "θ", "psi": "ψ"}
RATE_LABELS = {"phi": "dφ/dt", "theta": "dθ/dt", "psi": "dψ/dt"}  # along e_z, e_n, e_z′

# The view this scene is framed for (z up); also the server's initial camera.
# Seen from x > 0, y < 0 so that x, y, the line of nodes and x′ are all visible for typical
# angles (φ ≈ 30°), with the origin left of centre to clear the GUI panel on the right.
VIEW = CameraView(position=(5.9, -2.0, 3.3), look_at=(0.5, 1.15, 0.25), fov_deg=40.0)
INITIAL_CAMERA: dict[str, tuple[float, float, float]] = {
    "position": VIEW.position,
    "look_at": VIEW.look_at,
    "up": VIEW.up,
}
INITIAL_FOV_DEG = VIEW.fov_deg

ARC_PERIOD = 1.0 / 20.0  # [s] arcs and their labels while playing (20 Hz)
SLIDER_PERIOD = 0.1  # sliders follow at 10 Hz
READOUT_PERIOD = 0.2  # readouts at 5 Hz


def canonical_angles_deg(phi: float, theta: float, psi: float) -> tuple[float, float, float]:
    """The same rotation with θ in [0, 180] and φ, ψ in (-180, 180] [deg].

    Rz(φ) Rx(θ) Rz(ψ) = Rz(φ + 180°) Rx(−θ) Rz(ψ + 180°), so a θ in (180°, 360°) becomes
    360° − θ with φ and ψ turned by 180°.
    """
    theta = theta % 360.0
    if theta > 180.0:
        theta, phi, psi = 360.0 - theta, phi + 180.0, psi + 180.0
    return wrap_deg(phi), theta, wrap_deg(psi)


class ExplorerScene:
    """The Euler-angle explorer for one client: its GUI, its scene nodes and its state.

    Public state (read by tests and the session):
        angles_deg: [φ, θ, ψ] [deg] shown (principal ranges: what the sliders show).
        rates_deg: [φ̇, θ̇, ψ̇] [deg/s].
        playing, time_scale, t (seconds played since the last edit).
        moments: (I1, I2, I3) [kg m²] of the body drawn (the last valid triple).
        R_space_body: D (3, 3) as drawn.
    """

    title = "Euler angles"
    view = VIEW

    def __init__(self, client: viser.ClientHandle, guard: Guard) -> None:
        self.client = client
        self._guard = guard
        self.angles_deg: list[float] = list(INITIAL_ANGLES_DEG)
        self.rates_deg: list[float] = list(INITIAL_RATES_DEG)
        self._played_deg = np.array(INITIAL_ANGLES_DEG)  # φ, θ, ψ advanced by play (any range)
        self._initial_deg = np.array(INITIAL_ANGLES_DEG)  # what Reset goes back to
        self.moments: tuple[float, float, float] = INITIAL_MOMENTS
        self.R_space_body: Mat3 = np.eye(3)
        self.playing = False
        self.time_scale = 1.0
        self.t = 0.0
        self._syncing = False
        self._fade_level = -1
        self._arc_throttle = Throttle(ARC_PERIOD)
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self._readout_throttle = Throttle(READOUT_PERIOD)
        with client.atomic():
            self._build_scene()
            self._build_gui()
            self._reshape_body(validate_principal_moments(INITIAL_MOMENTS))
            self.render()

    # ------------------------------------------------------------------ building
    def _build_scene(self) -> None:
        scene = self.client.scene
        root = "/explorer"
        self._root_node = scene.add_frame(root, show_axes=False)
        scene.add_grid(
            f"{root}/grid", width=4.0, height=4.0, plane="xy", cell_size=0.5, section_size=1.0,
            cell_color=(225, 225, 225), section_color=(190, 190, 190), shadow_opacity=0.0,
        )
        # Space axes x y z (red, green, blue), fixed.
        scene.add_arrows(
            f"{root}/space_axes", axis_segments(np.eye(3), SPACE_AXIS_LENGTH),
            np.array(SPACE_COLORS), shaft_radius=0.016, head_radius=0.05, head_length=0.12,
        )
        for k, name in enumerate("xyz"):
            scene.add_label(
                f"{root}/space_labels/{name}", name,
                position=tuple((SPACE_AXIS_LENGTH + 0.12) * np.eye(3)[k]),
                font_screen_scale=2.0, anchor="center-center",
            )

        # The body: a frame node whose orientation is D; the box, axes, labels are children.
        self.body_node = scene.add_frame(f"{root}/body", show_axes=False)
        self.body_box = scene.add_box(
            f"{root}/body/box", color=BODY_COLOR, dimensions=(1.0, 1.0, 1.0),
            opacity=BODY_OPACITY, flat_shading=True, cast_shadow=False, receive_shadow=False,
        )
        scene.add_arrows(
            f"{root}/body/axes", axis_segments(np.eye(3), BODY_AXIS_LENGTH),
            np.array(BODY_COLORS), shaft_radius=0.028, head_radius=0.07, head_length=0.14,
        )
        for k, name in enumerate(("x′", "y′", "z′")):
            scene.add_label(
                f"{root}/body/labels/{k}", name,
                position=tuple((BODY_AXIS_LENGTH + 0.14) * np.eye(3)[k]),
                font_screen_scale=2.0, anchor="center-center",
            )

        # Intermediate frames of the decomposition: thin, faint, toggleable.
        self.after_phi_node = scene.add_frame(f"{root}/after_phi", show_axes=False)
        self.after_theta_node = scene.add_frame(f"{root}/after_theta", show_axes=False)
        for node, prime in ((self.after_phi_node, ""), (self.after_theta_node, "′")):
            scene.add_line_segments(
                f"{node.name}/axes", axis_segments(np.eye(3), FRAME_AXIS_LENGTH),
                np.repeat(np.array(FRAME_COLORS, dtype=np.uint8)[:, None, :], 2, axis=1),
                thickness=2.5, thickness_units="screen",
            )
            scene.add_label(
                f"{node.name}/label", f"η{prime}",
                position=(0.0, FRAME_AXIS_LENGTH + 0.08, 0.0),
                font_screen_scale=1.3, anchor="center-center",
            )

        # Line of nodes e_n, through the origin.
        self.nodes_line = scene.add_line_segments(
            f"{root}/line_of_nodes", np.zeros((1, 2, 3)), NODES_COLOR,
            thickness=6.0, thickness_units="screen",
        )
        self.nodes_label = scene.add_label(
            f"{root}/line_of_nodes_label", "line of nodes", font_screen_scale=1.7,
            anchor="center-left",
        )

        # Arcs for φ (xy plane), θ (plane ⟂ e_n) and ψ (x′y′ plane), with labels.
        self.arcs: dict[str, Any] = {}
        self.arc_labels: dict[str, Any] = {}
        for key in ("phi", "theta", "psi"):
            self.arcs[key] = scene.add_line_segments(
                f"{root}/arcs/{key}", np.zeros((1, 2, 3)), ARC_COLORS[key],
                thickness=4.0, thickness_units="screen",
            )
            self.arc_labels[key] = scene.add_label(
                f"{root}/arc_labels/{key}", GREEK[key], font_screen_scale=1.6,
                anchor="center-center",
            )

        # ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′, head to tail, and the resultant (orange, thick).
        self.rate_arrows: dict[str, Any] = {}
        self.rate_labels: dict[str, Any] = {}
        for key in ("phi", "theta", "psi"):
            self.rate_arrows[key] = scene.add_arrows(
                f"{root}/omega/{key}", np.zeros((1, 2, 3)), ARC_COLORS[key],
                shaft_radius=0.018, head_radius=0.05, head_length=0.1,
            )
            self.rate_labels[key] = scene.add_label(
                f"{root}/omega/{key}_label", RATE_LABELS[key], font_screen_scale=1.4, anchor="center-left",
            )
        self.omega_arrow = scene.add_arrows(
            f"{root}/omega/resultant", np.zeros((1, 2, 3)), OMEGA_COLOR,
            shaft_radius=0.032, head_radius=0.085, head_length=0.16,
        )
        self.omega_label = scene.add_label(
            f"{root}/omega/resultant_label", "ω", font_screen_scale=2.4, anchor="center-center",
        )

    def _build_gui(self) -> None:
        gui = self.client.gui
        guard = self._guard
        self.gui_intro = gui.add_markdown(
            "### Euler angles, z-x-z convention\n"
            "**D = Rz(φ) Rx(θ) Rz(ψ)**, body → space (x = D x′).  \n"
            "φ: precession about z · θ: nutation about the line of nodes · "
            "ψ: spin about z′.  Angles in **degrees**.  \n"
            "**ω = (dφ/dt) e_z + (dθ/dt) e_n + (dψ/dt) e_z′** (orange, head to tail)."
        )
        self.controls = PlaybackControls(
            gui, guard, on_toggle=self.toggle, on_step=self.step, on_reset=self.reset,
            on_time_scale=self._set_time_scale,
        )
        self.folder_angles = gui.add_folder("Euler angles z-x-z [deg]")
        with self.folder_angles:
            marks_full = ((-180.0, "-180°"), (-90.0, "-90°"), (0.0, "0°"), (90.0, "90°"), (180.0, "180°"))
            self.gui_phi = gui.add_slider(
                "φ [deg]", *ANGLE_RANGES_DEG["phi"], 1.0, INITIAL_ANGLES_DEG[0], marks=marks_full,
                hint="precession about the space z axis (applied first)",
            )
            self.gui_theta = gui.add_slider(
                "θ [deg]", *ANGLE_RANGES_DEG["theta"], 1.0, INITIAL_ANGLES_DEG[1],
                marks=((0.0, "0°"), (45.0, "45°"), (90.0, "90°"), (135.0, "135°"), (180.0, "180°")),
                hint="nutation about the line of nodes (applied second)",
            )
            self.gui_psi = gui.add_slider(
                "ψ [deg]", *ANGLE_RANGES_DEG["psi"], 1.0, INITIAL_ANGLES_DEG[2], marks=marks_full,
                hint="spin about the body z′ axis (applied last)",
            )
            self.gui_gimbal_note = gui.add_markdown("", visible=False)
            self.gui_presets = gui.add_button_group("Set φ θ ψ", tuple(PRESETS_DEG))
        self.gui_angles = (self.gui_phi, self.gui_theta, self.gui_psi)
        for index, (key, handle) in enumerate(zip(("phi", "theta", "psi"), self.gui_angles)):
            handle.on_update(guard(f"{GREEK[key]} slider", self._angle_callback(index, key, handle)))
        self.gui_presets.on_click(guard("angle presets", lambda event: self._preset(event.target.value)))

        self.folder_rates = gui.add_folder("Euler rates [deg/s]")
        with self.folder_rates:
            lo, hi = RATE_RANGE_DEG
            marks = ((-180.0, "-180"), (-90.0, "-90"), (0.0, "0"), (90.0, "90"), (180.0, "180"))
            self.gui_rates = tuple(
                gui.add_slider(f"d{GREEK[key]}/dt [deg/s]", lo, hi, 1.0, INITIAL_RATES_DEG[k], marks=marks,
                               hint=f"d{GREEK[key]}/dt: Play advances {GREEK[key]} at this rate")
                for k, key in enumerate(("phi", "theta", "psi"))
            )
        for index, handle in enumerate(self.gui_rates):
            handle.on_update(guard("rate slider", self._rate_callback(index, handle)))

        self.folder_matrix = gui.add_folder("Readout")
        with self.folder_matrix:
            tabs = gui.add_tab_group()
            with tabs.add_tab("D"):
                self.gui_matrix = gui.add_markdown("")
            with tabs.add_tab("Factors"):
                self.gui_factors = gui.add_markdown("")
            with tabs.add_tab("ω"):
                self.gui_omega = gui.add_markdown("")

        self.folder_body = gui.add_folder("Body: principal moments [kg m²]", expand_by_default=False)
        with self.folder_body:
            lo, hi = MOMENT_RANGE
            self.gui_moments = tuple(
                gui.add_slider(f"I{k + 1} [kg m²]", lo, hi, MOMENT_STEP, INITIAL_MOMENTS[k],
                               hint=f"principal moment about the body {'xyz'[k]}′ axis")
                for k in range(3)
            )
            self.gui_moments_status = gui.add_markdown("")
        for k, handle in enumerate(self.gui_moments):
            handle.on_update(guard(f"I{k + 1} slider", self._moment_callback(k, handle)))

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
        for handle in (self.gui_show_frames, self.gui_show_arcs, self.gui_show_omega):
            handle.on_update(guard("display toggle", lambda _event: self.render()))
        self.gui_reset_view.on_click(guard("reset view", lambda _event: self.reset_view()))
        self._gui_roots = [self.gui_intro, *self.controls.handles, self.folder_angles, self.folder_rates,
                           self.folder_matrix, self.folder_body, self.folder_display]

    # ------------------------------------------------------------------ callbacks
    def _refuse(self, what: str, raw: Any, lo: float, hi: float, handle: Any, last: float) -> None:
        self.controls.show_message(f"{what} = {raw!r} refused: the range is {lo:g} to {hi:g}.")
        self._syncing = True
        try:
            handle.value = last
        finally:
            self._syncing = False

    def _angle_callback(self, index: int, key: str, handle: Any) -> Callable[[Any], None]:
        lo, hi = ANGLE_RANGES_DEG[key]

        def on_update(_event: Any) -> None:
            if self._syncing:
                return  # the server itself is showing the motion on the slider
            value = checked_value(handle.value, lo, hi)
            if value is None:
                self._refuse(f"{GREEK[key]}", handle.value, lo, hi, handle, self.angles_deg[index])
                return
            self.controls.clear_message()
            if self.playing:
                self.pause()
            self.angles_deg[index] = value
            self._set_start(self.angles_deg)
            self.render()

        return on_update

    def _rate_callback(self, index: int, handle: Any) -> Callable[[Any], None]:
        lo, hi = RATE_RANGE_DEG

        def on_update(_event: Any) -> None:
            value = checked_value(handle.value, lo, hi)
            if value is None:
                self._refuse("rate", handle.value, lo, hi, handle, self.rates_deg[index])
                return
            self.controls.clear_message()
            self.rates_deg[index] = value
            self.render()

        return on_update

    def _moment_callback(self, k: int, handle: Any) -> Callable[[Any], None]:
        lo, hi = MOMENT_RANGE

        def on_update(_event: Any) -> None:
            value = checked_value(handle.value, lo, hi)
            if value is None:
                self._refuse(f"I{k + 1}", handle.value, lo, hi, handle, self.moments[k])
                return
            candidate = tuple(float(h.value) for h in self.gui_moments)
            try:
                moments = validate_principal_moments(candidate)
            except InertiaError as error:
                self.gui_moments_status.content = (
                    f"**⚠ Not a rigid body:** {error}  \n"
                    "Each moment must be at most the sum of the other two "
                    "(I1 + I2 ≥ I3 and cyclic).  Showing the last valid body, "
                    f"I = ({', '.join(f'{m:.2f}' for m in self.moments)}) kg m²."
                )
                return
            self._reshape_body(moments)

        return on_update

    def _preset(self, name: Any) -> None:
        if self.playing:
            self.pause()
        self.set_angles_deg(*PRESETS_DEG.get(str(name), INITIAL_ANGLES_DEG))

    def _set_time_scale(self, value: float) -> None:
        self.time_scale = value

    # ------------------------------------------------------------------ actions
    def set_angles_deg(self, phi: float, theta: float, psi: float) -> None:
        """Move the sliders (and so the body) to (φ, θ, ψ) [deg]."""
        with self.client.atomic():
            for handle, value in zip(self.gui_angles, (phi, theta, psi)):
                handle.value = float(value)
        self._set_start((phi, theta, psi))

    def _set_start(self, angles_deg: Any) -> None:
        """The user set the angles: playing and Reset start from here."""
        self._played_deg = np.array(angles_deg, dtype=float)
        self._initial_deg = self._played_deg.copy()
        self.t = 0.0

    def play(self) -> None:
        self.playing = True
        self.controls.show_playing(True)
        self._refresh_status()

    def pause(self) -> None:
        self.playing = False
        self.controls.show_playing(False)
        self._sync_sliders()
        self.render()

    def toggle(self) -> None:
        self.pause() if self.playing else self.play()

    def step(self) -> None:
        """Pause and advance the angles by one frame (STEP_DT times the time scale)."""
        if self.playing:
            self.pause()
        self._advance(STEP_DT * self.time_scale)
        self._sync_sliders()
        self.render()

    def reset(self) -> None:
        """Pause and go back to the angles last set by the user."""
        self.playing = False
        self.controls.show_playing(False)
        self._played_deg = self._initial_deg.copy()
        self.t = 0.0
        self.angles_deg = list(canonical_angles_deg(*self._played_deg))
        self._sync_sliders()
        self.render()

    def reset_view(self) -> None:
        """Put this client's camera back to the scene's view."""
        apply_camera(self.client, VIEW)

    def _advance(self, dt: float) -> None:
        self._played_deg = self._played_deg + np.array(self.rates_deg) * dt
        self._played_deg[[0, 2]] = [wrap_deg(a) for a in self._played_deg[[0, 2]]]
        self._played_deg[1] %= 360.0
        self.t += dt
        self.angles_deg = list(canonical_angles_deg(*self._played_deg))

    def tick(self, dt: float) -> None:
        """Advance the angles by their rates (dt [s] of wall time times the time scale)."""
        if not self.playing:
            return
        self._advance(dt * self.time_scale)
        with self.client.atomic():
            self.render_pose()
            if self._arc_throttle.ready(dt):
                self.render_arcs()
            if self._slider_throttle.ready(dt):
                self._sync_sliders()
            if self._readout_throttle.ready(dt):
                self.render_readout()
                self._refresh_status()

    def _sync_sliders(self) -> None:
        """Show the angles on the sliders without their callbacks acting (no feedback)."""
        self._syncing = True
        try:
            for handle, value in zip(self.gui_angles, self.angles_deg):
                handle.value = round(float(value))
        finally:
            self._syncing = False

    def _refresh_status(self) -> None:
        state = "▶ playing" if self.playing else "paused"
        self.controls.set_status(f"**t = {self.t:.2f} s** · {state} · {self.time_scale:g}×")

    def _reshape_body(self, moments: Any) -> None:
        """Box with edges proportional to the box of these moments; the longest is BODY_SIZE."""
        edges = np.asarray(box_extents_from_moments(moments, mass=1.0), dtype=float)
        ratio = edges / edges.max()  # shape only: the moments fix the box up to its mass
        self.moments = (float(moments[0]), float(moments[1]), float(moments[2]))
        self.body_box.dimensions = tuple(float(d) for d in np.maximum(BODY_SIZE * ratio, MIN_EDGE))
        flat = ratio.min() < 1e-3
        shown = ratio if flat else ratio / ratio.min()  # smallest edge 1, unless it is 0
        status = f"Uniform box with edges along x′, y′, z′ in the ratio **{', '.join(f'{r:.2f}' for r in shown)}**."
        if flat:
            status += "  \nA flat lamina: one triangle inequality holds with equality."
        self.gui_moments_status.content = status

    def remove(self) -> None:
        """Remove this scene's GUI elements and scene nodes from the client."""
        self.playing = False
        for handle in self._gui_roots:
            handle.remove()
        self._root_node.remove()  # removes its descendants, the whole scene

    # ------------------------------------------------------------------ drawing
    def render(self) -> None:
        """Redraw everything from `angles_deg` and `rates_deg` (all formulas from `physics`)."""
        with self.client.atomic():
            self.render_pose()
            self.render_arcs()
            self.render_readout()
            self._refresh_status()

    def _frames(self) -> tuple[Any, float, float, float]:
        phi, theta, psi = (math.radians(a) for a in self.angles_deg)
        return euler_frames(phi, theta, psi), phi, theta, psi

    def render_pose(self) -> None:
        """The per-frame part: body, intermediate frames, line of nodes, ω arrows."""
        frames, phi, theta, _ = self._frames()
        R = frames.body
        self.R_space_body = R
        e_n = line_of_nodes(phi)
        theta_deg = self.angles_deg[1]
        show_frames = bool(self.gui_show_frames.value)
        self.body_node.wxyz = wxyz_from_matrix(R)
        self.after_phi_node.wxyz = wxyz_from_matrix(frames.after_phi)
        self.after_theta_node.wxyz = wxyz_from_matrix(frames.after_theta)
        self.after_phi_node.visible = show_frames
        self.after_theta_node.visible = show_frames

        self.nodes_line.points = np.array([[-NODES_HALF_LENGTH * e_n, NODES_HALF_LENGTH * e_n]])
        self.nodes_label.position = tuple((NODES_HALF_LENGTH + 0.05) * e_n)
        distance = min(theta_deg, 180.0 - theta_deg)
        level = min(8, int(8 * distance / GIMBAL_FADE_DEG))
        if level != self._fade_level:
            self._fade_level = level
            locked = distance < GIMBAL_LOCK_DEG
            color = NODES_FADED_COLOR if locked else fade_color(NODES_COLOR, NODES_FADED_COLOR, level / 8)
            self.nodes_line.colors = np.array([[color, color]], dtype=np.uint8)
            self.nodes_label.text = "line of nodes\n(undefined)" if locked else "line of nodes"

        # ω head to tail: φ̇ e_z, then θ̇ e_n, then ψ̇ e_z′ (each scaled to scene units).
        dphi, dtheta, dpsi = (RATE_ARROW_SCALE * r for r in self.rates_deg)
        components = {"phi": dphi * np.array([0.0, 0.0, 1.0]), "theta": dtheta * e_n,
                      "psi": dpsi * body_z_axis(phi, theta)}
        show = bool(self.gui_show_omega.value)
        start = np.zeros(3)
        for key in ("phi", "theta", "psi"):
            end = start + components[key]
            visible = show and float(np.linalg.norm(components[key])) > 1e-3
            self.rate_arrows[key].visible = visible
            self.rate_labels[key].visible = visible
            if visible:
                self.rate_arrows[key].points = np.array([[start, end]])
                self.rate_labels[key].position = tuple(0.5 * (start + end) + 0.06)
            start = end
        visible = show and float(np.linalg.norm(start)) > 1e-3
        self.omega_arrow.visible = visible
        self.omega_label.visible = visible
        if visible:
            self.omega_arrow.points = np.array([[np.zeros(3), start]])
            self.omega_label.position = tuple(start * (1.0 + 0.15 / float(np.linalg.norm(start))))

    def render_arcs(self) -> None:
        """Arcs for φ, θ, ψ and their labels."""
        frames, phi, theta, psi = self._frames()
        show_arcs = bool(self.gui_show_arcs.value)
        arcs = {
            "phi": [rot_z(t) @ np.array([ARC_RADII["phi"], 0.0, 0.0])
                    for t in np.linspace(0.0, phi, ARC_SEGMENTS + 1)],
            "theta": [frames.after_phi @ rot_x(t) @ np.array([0.0, 0.0, ARC_RADII["theta"]])
                      for t in np.linspace(0.0, theta, ARC_SEGMENTS + 1)],
            "psi": [frames.after_theta @ rot_z(t) @ np.array([ARC_RADII["psi"], 0.0, 0.0])
                    for t in np.linspace(0.0, psi, ARC_SEGMENTS + 1)],
        }
        for key, angle_deg in zip(("phi", "theta", "psi"), self.angles_deg):
            points = np.array(arcs[key])
            visible = show_arcs and abs(angle_deg) >= 0.5
            self.arcs[key].points = polyline_segments(points)
            self.arcs[key].visible = visible
            middle = points[ARC_SEGMENTS // 2]
            self.arc_labels[key].position = tuple(1.18 * middle)
            self.arc_labels[key].text = f"{GREEK[key]} = {angle_deg:.0f}°"
            self.arc_labels[key].visible = visible

    def render_readout(self) -> None:
        """D, its factors, ω (space and body components) and the gimbal-lock note."""
        frames, phi, theta, psi = self._frames()
        R = frames.body
        e_n = line_of_nodes(phi)
        e_z_body = body_z_axis(phi, theta)
        note = gimbal_note(self.angles_deg[1])
        self.gui_gimbal_note.visible = note is not None
        if note is not None:
            self.gui_gimbal_note.content = note
        self.gui_matrix.content = (
            "D = Rz(φ) Rx(θ) Rz(ψ), columns = x′ y′ z′ in space components\n"
            f"```\n{format_matrix(R, 4)}\n```\n"
            f"e_n = (cos φ, sin φ, 0) = {format_vector(e_n)}  \n"
            f"e_z′ = D e_z = {format_vector(e_z_body)}"
        )
        factors = ((f"Rz(φ), φ = {self.angles_deg[0]:g}°", rot_z(phi)),
                   (f"Rx(θ), θ = {self.angles_deg[1]:g}°", rot_x(theta)),
                   (f"Rz(ψ), ψ = {self.angles_deg[2]:g}°", rot_z(psi)))
        self.gui_factors.content = "\n".join(
            f"{title}\n```\n{format_matrix(M, 4)}\n```" for title, M in factors
        )
        angles = (phi, theta, psi)
        rates = tuple(math.radians(r) for r in self.rates_deg)
        omega_space = np.degrees(omega_space_from_euler_rates(angles, rates))
        omega_body = np.degrees(omega_body_from_euler_rates(angles, rates))
        dphi, dtheta, dpsi = self.rates_deg

        def row(name: str, v: Any) -> str:
            return f"{name:<14}" + "".join(f"{(0.0 if abs(x) < 5e-4 else x):10.3f}" for x in v)

        self.gui_omega.content = (
            "ω = (dφ/dt) e_z + (dθ/dt) e_n + (dψ/dt) e_z′ [deg/s]; ω_s = D ω_b\n```\n"
            f"dφ/dt = {dphi:g}   dθ/dt = {dtheta:g}   dψ/dt = {dpsi:g}   [deg/s]\n\n"
            f"{'':<14}{'x | x′':>10}{'y | y′':>10}{'z | z′':>10}\n"
            f"{row('(dφ/dt) e_z', (0.0, 0.0, dphi))}\n"
            f"{row('(dθ/dt) e_n', dtheta * e_n)}\n"
            f"{row('(dψ/dt) e_z′', dpsi * e_z_body)}\n"
            f"{row('ω_s (space)', omega_space)}\n"
            f"{row('ω_b (body)', omega_body)}\n"
            f"|ω| = {float(np.linalg.norm(omega_space)):.3f} deg/s\n```"
        )
