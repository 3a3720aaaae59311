"""The z-x-z Euler-angle explorer: one scene of the lecture app, drawn for one client.

What it shows (PHYSICS.md, "Euler angles"): the space axes x y z, a box-shaped body whose
proportions follow its principal moments, its body axes x′ y′ z′, the line of nodes
e_n = (cos φ, sin φ, 0), the two intermediate frames of D = Rz(φ) Rx(θ) Rz(ψ)
(after φ: ξηζ = Rz(φ); after θ: ξ′η′ζ′ = Rz(φ) Rx(θ)), arcs for φ, θ, ψ, and a readout
of D and its three factors.

Every formula comes from `physics` (euler_frames, line_of_nodes, body_z_axis, rot_x,
rot_z, and the inertia checks); this module only turns matrices into drawing commands.
Angles are in degrees on the sliders and in radians everywhere else.  Client values are
clamped in the callbacks: viser does not validate what a browser sends.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import viser
from scipy.spatial.transform import Rotation

from physics._types import Mat3, Vec3
from physics.euler import body_z_axis, euler_frames, line_of_nodes
from physics.inertia import InertiaError, box_extents_from_moments, validate_principal_moments
from physics.so3 import rot_x, rot_z

__all__ = [
    "ANGLE_RANGES_DEG",
    "GIMBAL_LOCK_DEG",
    "INITIAL_ANGLES_DEG",
    "PRESETS_DEG",
    "INITIAL_CAMERA",
    "INITIAL_FOV_DEG",
    "ExplorerScene",
    "clamp_finite",
    "format_matrix",
    "wxyz_from_matrix",
]

Guard = Callable[[str, Callable[..., Any]], Callable[..., Any]]

# Slider ranges [deg]: φ, ψ in [-180, 180], θ in [0, 180] (PHYSICS.md principal ranges).
ANGLE_RANGES_DEG: dict[str, tuple[float, float]] = {
    "phi": (-180.0, 180.0),
    "theta": (0.0, 180.0),
    "psi": (-180.0, 180.0),
}
INITIAL_ANGLES_DEG = (30.0, 50.0, 20.0)  # a generic pose: every element of the picture visible
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

# Colours (RGB 0-255).
SPACE_COLORS = ((225, 35, 35), (30, 160, 45), (35, 75, 230))
BODY_COLORS = ((150, 0, 0), (0, 105, 20), (0, 30, 150))
FRAME_COLORS = ((240, 160, 160), (150, 215, 160), (160, 180, 245))
NODES_COLOR = (235, 180, 0)  # gold
NODES_FADED_COLOR = (205, 205, 205)
BODY_COLOR = (235, 170, 70)
BODY_OPACITY = 0.7
ARC_COLORS = {"phi": (140, 50, 210), "theta": (215, 0, 120), "psi": (0, 140, 140)}
GREEK = {"phi": "φ", "theta": "θ", "psi": "ψ"}

# The view this scene is framed for (z up); also the server's initial camera.
# Seen from x > 0, y < 0 so that x, y, the line of nodes and x′ are all visible for typical
# angles (φ ≈ 30°), with the origin left of centre to clear the GUI panel on the right.
INITIAL_CAMERA: dict[str, tuple[float, float, float]] = {
    "position": (5.9, -2.0, 3.3),
    "look_at": (0.5, 1.15, 0.25),
    "up": (0.0, 0.0, 1.0),
}
INITIAL_FOV_DEG = 40.0  # vertical field of view; three.js' 75° distorts the axes


def wxyz_from_matrix(R: Mat3) -> np.ndarray:
    """Quaternion (w, x, y, z) (4,) of the rotation matrix R (3, 3), for viser only."""
    return Rotation.from_matrix(R).as_quat(scalar_first=True)


def clamp_finite(value: float, lo: float, hi: float, fallback: float) -> float:
    """`value` clamped to [lo, hi]; `fallback` if it is NaN (viser passes NaN through)."""
    value = float(value)
    if math.isnan(value):
        return fallback
    return min(max(value, lo), hi)


def format_matrix(M: Mat3, decimals: int = 4) -> str:
    """A 3x3 matrix as three aligned text rows (no '-0.0000')."""
    width = decimals + 3
    rows = []
    for row in np.asarray(M, dtype=float):
        cells = [f"{(0.0 if abs(x) < 0.5 * 10**-decimals else x):{width}.{decimals}f}" for x in row]
        rows.append("[ " + "  ".join(cells) + " ]")
    return "\n".join(rows)


def format_vector(v: Vec3, decimals: int = 3) -> str:
    """A 3-vector as '(a, b, c)' with no '-0.000'."""
    return "(" + ", ".join(f"{(0.0 if abs(x) < 0.5 * 10**-decimals else x):.{decimals}f}" for x in v) + ")"


def _axis_segments(R: Mat3, length: float) -> np.ndarray:
    """Line segments (3, 2, 3) from the origin along the columns of R, `length` long."""
    return np.stack([np.zeros((3, 3)), length * np.asarray(R).T], axis=1)


def _polyline_segments(points: np.ndarray) -> np.ndarray:
    """Consecutive pairs (N-1, 2, 3) of a polyline's points (N, 3)."""
    return np.stack([points[:-1], points[1:]], axis=1)


class ExplorerScene:
    """The Euler-angle explorer for one client: its GUI, its scene nodes and its state.

    Public state (read by tests and, later, by the multi-scene session):
        angles_deg: [φ, θ, ψ] [deg], the last valid slider values.
        moments: (I1, I2, I3) [kg m²] of the body drawn (the last valid triple).
        R_space_body: D (3, 3) as drawn.
    Handles: gui_phi, gui_theta, gui_psi, gui_moments, gui_show_frames, gui_show_arcs,
    gui_gimbal_note, gui_moments_status, gui_matrix, gui_factors; nodes body_node, body_box,
    nodes_line, nodes_label, after_phi_node, after_theta_node.
    """

    title = "Euler angles"

    def __init__(self, client: viser.ClientHandle, guard: Guard) -> None:
        self.client = client
        self._guard = guard
        self.angles_deg: list[float] = list(INITIAL_ANGLES_DEG)
        self.moments: tuple[float, float, float] = INITIAL_MOMENTS
        self.R_space_body: Mat3 = np.eye(3)
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
            f"{root}/space_axes", _axis_segments(np.eye(3), SPACE_AXIS_LENGTH),
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
            f"{root}/body/axes", _axis_segments(np.eye(3), BODY_AXIS_LENGTH),
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
                f"{node.name}/axes", _axis_segments(np.eye(3), FRAME_AXIS_LENGTH),
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

    def _build_gui(self) -> None:
        gui = self.client.gui
        guard = self._guard
        self.gui_intro = gui.add_markdown(
            "### Euler angles, z-x-z convention\n"
            "**D = Rz(φ) Rx(θ) Rz(ψ)**, body → space (x = D x′).  \n"
            "φ: precession about z · θ: nutation about the line of nodes · "
            "ψ: spin about z′.  Angles in **degrees**."
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
        for index, (key, handle) in enumerate(
            (("phi", self.gui_phi), ("theta", self.gui_theta), ("psi", self.gui_psi))
        ):
            handle.on_update(guard(f"{GREEK[key]} slider", self._angle_callback(index, key, handle)))
        self.gui_presets.on_click(guard("angle presets", lambda event: self.set_angles_deg(
            *PRESETS_DEG.get(event.target.value, INITIAL_ANGLES_DEG))))

        self.folder_matrix = gui.add_folder("Rotation matrix")
        with self.folder_matrix:
            tabs = gui.add_tab_group()
            with tabs.add_tab("D"):
                self.gui_matrix = gui.add_markdown("")
            with tabs.add_tab("Factors"):
                self.gui_factors = gui.add_markdown("")

        self.folder_body = gui.add_folder("Body: principal moments [kg m²]")
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
            self.gui_reset_view = gui.add_button("Reset view", icon=viser.Icon.CAMERA)
            gui.add_markdown(
                "Thin red/green/blue arrows: space axes x y z.  \n"
                "Dark arrows: body axes x′ y′ z′ (the columns of D).  \n"
                "Gold: line of nodes e_n = (cos φ, sin φ, 0).  \n"
                "Faint: intermediate frames (η after φ, η′ after θ)."
            )
        self.gui_show_frames.on_update(guard("frames toggle", lambda _event: self.render()))
        self.gui_show_arcs.on_update(guard("arcs toggle", lambda _event: self.render()))
        self.gui_reset_view.on_click(guard("reset view", lambda _event: self.reset_view()))
        self._gui_roots = [self.gui_intro, self.folder_angles, self.folder_matrix,
                           self.folder_body, self.folder_display]

    # ------------------------------------------------------------------ callbacks
    def _angle_callback(self, index: int, key: str, handle: Any) -> Callable[[Any], None]:
        lo, hi = ANGLE_RANGES_DEG[key]

        def on_update(_event: Any) -> None:
            raw = handle.value
            value = clamp_finite(raw, lo, hi, self.angles_deg[index])
            if value != raw or math.isnan(raw):
                handle.value = value  # runs this callback again (synchronously) with `value`
                return
            self.angles_deg[index] = value
            self.render()

        return on_update

    def _moment_callback(self, k: int, handle: Any) -> Callable[[Any], None]:
        lo, hi = MOMENT_RANGE

        def on_update(_event: Any) -> None:
            raw = handle.value
            value = clamp_finite(raw, lo, hi, self.moments[k])
            if value != raw or math.isnan(raw):
                handle.value = value
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

    # ------------------------------------------------------------------ actions
    def set_angles_deg(self, phi: float, theta: float, psi: float) -> None:
        """Move the sliders (and so the body) to (φ, θ, ψ) [deg]."""
        with self.client.atomic():
            for handle, value in zip((self.gui_phi, self.gui_theta, self.gui_psi), (phi, theta, psi)):
                handle.value = float(value)

    def reset_view(self) -> None:
        """Put this client's camera back to the app's initial view."""
        camera = self.client.camera
        camera.up_direction = INITIAL_CAMERA["up"]
        camera.position = INITIAL_CAMERA["position"]
        camera.look_at = INITIAL_CAMERA["look_at"]
        camera.fov = math.radians(INITIAL_FOV_DEG)

    def _reshape_body(self, moments: Vec3) -> None:
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

    def tick(self, dt: float) -> None:
        """The explorer has no dynamics: nothing moves unless a slider does."""

    def remove(self) -> None:
        """Remove this scene's GUI elements and scene nodes from the client."""
        for handle in self._gui_roots:
            handle.remove()
        self._root_node.remove()  # removes its descendants, the whole scene

    # ------------------------------------------------------------------ drawing
    def render(self) -> None:
        """Redraw everything from `angles_deg` (all formulas from `physics`)."""
        phi, theta, psi = (math.radians(a) for a in self.angles_deg)
        frames = euler_frames(phi, theta, psi)
        R = frames.body
        e_n = line_of_nodes(phi)
        e_z_body = body_z_axis(phi, theta)
        theta_deg = self.angles_deg[1]
        locked = min(theta_deg, 180.0 - theta_deg) < GIMBAL_LOCK_DEG
        show_frames = bool(self.gui_show_frames.value)
        show_arcs = bool(self.gui_show_arcs.value)
        self.R_space_body = R

        with self.client.atomic():
            self.body_node.wxyz = wxyz_from_matrix(R)
            self.after_phi_node.wxyz = wxyz_from_matrix(frames.after_phi)
            self.after_theta_node.wxyz = wxyz_from_matrix(frames.after_theta)
            self.after_phi_node.visible = show_frames
            self.after_theta_node.visible = show_frames

            self.nodes_line.points = np.array([[-NODES_HALF_LENGTH * e_n, NODES_HALF_LENGTH * e_n]])
            self.nodes_line.colors = np.array([[NODES_FADED_COLOR if locked else NODES_COLOR] * 2],
                                              dtype=np.uint8)
            self.nodes_label.position = tuple((NODES_HALF_LENGTH + 0.05) * e_n)
            self.nodes_label.text = "line of nodes\n(undefined)" if locked else "line of nodes"

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
                self.arcs[key].points = _polyline_segments(points)
                self.arcs[key].visible = visible
                middle = points[ARC_SEGMENTS // 2]
                self.arc_labels[key].position = tuple(1.18 * middle)
                self.arc_labels[key].text = f"{GREEK[key]} = {angle_deg:g}°"
                self.arc_labels[key].visible = visible

            if locked:
                pole, defined = ("0°", "φ + ψ") if theta_deg < 90.0 else ("180°", "φ − ψ")
                self.gui_gimbal_note.content = (
                    f"**⚠ Gimbal lock** (θ ≈ {pole}): the line of nodes is undefined; "
                    f"only {defined} is defined."
                )
            self.gui_gimbal_note.visible = locked

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
