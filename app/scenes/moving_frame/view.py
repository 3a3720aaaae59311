"""The "Moving frame" scene's view: `MovingFrameView` draws a `MovingFrameSimulation` for one
browser (`app.scenes.moving_frame`).

**What a playing frame sends** (the frame budget, tests/test_frame_budget.py; Turntable, the
default: ~470 B and ~8.5 scene messages a frame, own room or following, 2026-11-25).  What
moves with C′ hangs under C′'s node in C′ coordinates: the particles, the anchor, the spring,
the paths in C′ and the forces, so C′'s turn is one message (~45 B: four float64s) and a
particle at rest in C′ sends none.  The forces hang under one group at the chosen particle,
which also holds that particle's ball (its own node hidden): one position message moves both;
the five forces are one `add_arrows` node and the sum another, thinner (`app.kit.draw.lean.Arrows`:
one `points` message each, raw float32, 24 B an arrow: ~72 B of the frame, the largest part);
their labels move in steps of LABEL_TOLERANCE (~4 px).  The spring's group sits at its anchor:
the spring particle hangs in it at d = x′ − anchor and the spring is a unit segment (0 → (1, 1,
1)) scaled by d, so the two messages carry the same three numbers (the second compresses to a
few bytes) and no points are sent.  The paths: a new chunk or head every few frames (~45 B a
frame); a path that is one point (the particle at rest in C′, seen in C′) is not drawn.  While
playing every pose, point and label is snapped (`app.kit.draw.lean.Pose`; C′ to ~1 px, particles
and the spring to GRID = 1/256 m, a power of two, so their float64s end in zero bytes that
compress) and sent only when what is drawn changed; paused, all is exact.  Node names are
short (each message carries its node's name); each message type a frame holds costs its name
once (~20-30 B; SetOrientation, SetPosition, SceneNodeUpdate), which no node layout avoids.
The readout and the status line are rewritten at 2 Hz (READOUT_PERIOD).

**The rider's view.**  "Ride with C′" does not move the camera.  Everything is drawn under
one node `world` (space coordinates) and C′'s contents under `world/frame` (posed by a, D);
riding turns `world` by the inverse pose, (Dᵀ, −Dᵀa), so C′ stands still on screen and the
inertial grid and axes turn and slide past.  Chosen over moving `client.camera` each frame
because (1) the camera would reach the browser in its own messages, out of step with the
nodes (judder), and would fight the user's orbit controls, while a root pose is one more
pose message in the same atomic frame and the user keeps orbiting *within* C′; (2) it works
unchanged for a presenter's view drawn into the shared scene for many followers, whose
cameras are theirs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import viser

from app.i18n import N_, Said
from app.kit.core.common import CameraView, Throttle, Wrap
from app.kit.core.presets import Preset
from app.kit.core.room import Room
from app.kit.core.trace import Trace
from app.kit.draw.labels import KEY
from app.kit.draw.lean import TOLERANCE, Arrows, Pose, f32, snap, turn_z_onto
from app.kit.draw.widgets import Body, Stage, TraceLines
from app.kit.panel.gui import PresetsRow, Readout, Transport, add_slider
from app.kit.view import SceneView, nth
from app.scenes.moving_frame.readouts import readout_text, status_text
from app.scenes.moving_frame.simulation import (
    ANGLE_SPECS,
    DISPLAY_KEYS,
    FRAME_KEYS,
    KEYS,
    PARAM_SPECS,
    PARTICLE_KEYS,
    PARTICLES,
    ForceReport,
    MovingFrameSetup,
    MovingFrameSimulation,
)
from app.viser_internals import set_scale
from physics._types import Array
from physics.quaternion import wxyz_from_matrix

__all__ = ["VIEW", "MovingFrameView"]

PARTICLE_COLORS = ((20, 120, 230), (30, 150, 60), (200, 60, 160))
PARTICLE_RADIUS = 0.07
FORCE_KEYS = ("real", "translational", "euler", "centrifugal", "coriolis")
FORCE_LABELS = {"real": N_("F (real)"), "translational": "−m Dᵀä", "euler": N_("Euler"),
                "centrifugal": N_("centrifugal"), "coriolis": N_("Coriolis")}
FORCE_COLORS = {"real": (30, 30, 30), "translational": (120, 120, 0), "euler": (0, 150, 150),
                "centrifugal": (230, 90, 0), "coriolis": (150, 40, 220)}
DISC_COLOR = (210, 205, 190)
DISC_STRIPE_COLOR = (150, 140, 120)
LABEL_MIN_LENGTH = 0.25  # [m] a force arrow shorter than this is drawn without its label
READOUT_PERIOD = 0.5  # [s] of wall time (2 Hz): the readout and the status line
FRAME_REACH = 2.2  # [m] the farthest drawn point of C′ (disc rim, axis labels): its pose's snapping grid
GRID = 1.0 / 256.0  # [m] while playing, particles and the spring are snapped to this (~0.6 px): a power of two,
# so a snapped coordinate has few significant bits and its float64 ends in zero bytes (they compress)
LABEL_TOLERANCE = 1.0 / 32.0  # [m] while playing, a force's label moves in steps of this (~4 px; a power of 2)
LABEL_BEYOND = 0.16  # [m] a force's label sits this far beyond its tip
LABEL_ASIDE = 0.06  # [m] ... the sum's this far beside its middle
LABEL_FONT = 1.5

VIEW = CameraView(position=(5.2, -5.6, 4.4), look_at=(0.3, 0.2, 0.0), fov_deg=45.0)


def _disc(scene: Any, parent: str, radius: float) -> None:
    """A thin disc in the x′y′ plane with four dark spokes, so that its turning shows."""
    if radius <= 0.0:
        return
    scene.add_cylinder(f"{parent}/disc", radius=radius, height=0.02, color=DISC_COLOR, opacity=0.55,
                       position=(0.0, 0.0, -0.02), cast_shadow=False, receive_shadow=False)
    spokes = np.array([[[0.0, 0.0, 0.0], [radius * math.cos(a), radius * math.sin(a), 0.0]]
                       for a in np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False)])
    scene.add_line_segments(f"{parent}/spokes", spokes, DISC_STRIPE_COLOR, thickness=2.0,
                            thickness_units="screen")
    circle = np.array([[radius * math.cos(a), radius * math.sin(a), 0.0] for a in np.linspace(0, 2 * math.pi, 97)])
    scene.add_line_segments(f"{parent}/rim", np.stack([circle[:-1], circle[1:]], axis=1), DISC_STRIPE_COLOR,
                            thickness=2.5, thickness_units="screen")


class _Spread:
    """Whether a path's points lie farther than TOLERANCE from its oldest one, looking only at the
    points added since the last call (a playing frame adds one at most): the same answer as
    scanning the whole path, without scanning it every frame."""

    def __init__(self) -> None:
        self._seen: dict[int, tuple[Trace, int, int, bool]] = {}  # id -> (trace, first, checked up to, wide)

    def wide(self, trace: Trace) -> bool:
        seen, first, checked, wide = self._seen.get(id(trace), (None, -1, 0, False))
        if seen is not trace or first != trace.first or checked > trace.count:  # new, older points dropped, rewound
            first, checked, wide = trace.first, trace.first, False
        if not wide and checked < trace.count and trace.count - first >= 2:
            origin = trace.points(first, first + 1)[0]
            wide = float(np.max(np.abs(trace.points(checked, trace.count) - origin))) > TOLERANCE
            checked = trace.count
        self._seen[id(trace)] = (trace, first, checked, wide)
        return wide


def _matrix_of(wxyz: Sequence[float]) -> Array:
    """The rotation matrix (3, 3) of a unit quaternion (w, x, y, z)."""
    w, x, y, z = (float(c) for c in wxyz)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _lighter(color: tuple[int, int, int], weight: float = 0.55) -> tuple[int, int, int]:
    r, g, b = (int(round(c + weight * (255 - c))) for c in color)
    return r, g, b


class MovingFrameView(SceneView):
    """One browser's view of a room with a `MovingFrameSimulation`."""

    transport: Transport  # built by build_head

    title = N_("Moving frame")  # the scene dropdown shows it translated (app.i18n)
    root = "/mf"  # node names are short: every message of a frame carries its node's name
    view = VIEW
    preset_file = "moving_frame.json"
    param_specs = PARAM_SPECS

    @classmethod
    def check_preset(cls, preset: Preset) -> None:
        MovingFrameSetup(preset.params, preset.angles_deg)

    @classmethod
    def simulation_from_preset(cls, preset: Preset) -> MovingFrameSimulation:
        return MovingFrameSimulation(MovingFrameSetup(preset.params, preset.angles_deg))

    @classmethod
    def start_preset(cls, sim: MovingFrameSimulation, preset: Preset) -> None:
        sim.set_setup(MovingFrameSetup(preset.params, preset.angles_deg))

    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: MovingFrameSimulation = room.sim
        self._drawn_version = -1
        self._drawn_disc = math.nan
        self._spring_drawn: tuple[float, ...] | None = None  # the spring's scale (its vector d) as sent
        self._spread = _Spread()  # which paths are more than one point (only those are drawn)
        self._readout_throttle = Throttle(READOUT_PERIOD)
        self.build()

    # ------------------------------------------------------------------ building
    def _build_scene(self) -> None:
        # Everything that moves with C′ hangs under it, in C′ coordinates: a particle at rest in
        # C′, the anchor, a path in C′ cost no message while C′ turns; the force arrows hang
        # under one group at the chosen particle (one position message) and only turn.
        scene = self.client.scene
        world = f"{self.root}/w"
        self.world = scene.add_frame(world, show_axes=False)
        self.world_pose = Pose(self.world, reach=FRAME_REACH)
        Stage(scene, world, size=8.0, labels=self.labels)
        self.paths_space = [TraceLines(scene, f"{world}/tc/{k}", _lighter(PARTICLE_COLORS[k]),
                                       self.sim.paths_space[k])
                            for k in range(len(PARTICLES))]
        self.body = Body(scene, f"{world}/f", self._build_disc, axis_length=1.0, labels=self.labels)
        self.frame_pose = Pose(self.body.node, reach=FRAME_REACH)
        frame = f"{world}/f"
        # The spring's group sits at its anchor (fixed in C′): its particle hangs in it at d = x′ − anchor
        # and the spring is a segment from (0, 0, 0) to (1, 1, 1) scaled by d, so that both messages
        # of a frame carry the same three numbers (they compress) and no points are sent.
        self.spring_group = scene.add_frame(f"{frame}/s", show_axes=False)
        self.particles = [
            scene.add_icosphere(f"{frame}/p/{k}" if k < 2 else f"{frame}/s/p", radius=PARTICLE_RADIUS,
                                color=PARTICLE_COLORS[k], subdivisions=2, cast_shadow=False, receive_shadow=False)
            for k in range(len(PARTICLES))
        ]
        self.particle_poses = [Pose(node, reach=PARTICLE_RADIUS, tolerance=GRID) for node in self.particles]
        self.radius_rod = scene.add_line_segments(f"{frame}/rod", np.zeros((1, 2, 3)), (110, 110, 120),
                                                  thickness=3.0, thickness_units="screen", visible=False)
        self.anchor = scene.add_icosphere(f"{frame}/s/o", radius=0.035, color=(90, 90, 90), subdivisions=1,
                                          cast_shadow=False, receive_shadow=False)
        self.spring = scene.add_line_segments(f"{frame}/s/l", np.array([[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]]),
                                              PARTICLE_COLORS[2], thickness=1.5, thickness_units="screen")
        self.paths_body = [TraceLines(scene, f"{frame}/t/{k}", PARTICLE_COLORS[k], self.sim.paths_body[k])
                           for k in range(len(PARTICLES))]
        self.forces_group = scene.add_frame(f"{frame}/a", show_axes=False)
        self.forces_pose = Pose(self.forces_group, reach=PARTICLE_RADIUS, tolerance=GRID)
        # The chosen particle is drawn by a ball in the group (its own node hidden): one message
        # moves the particle and its forces.
        self.focus_ball = scene.add_icosphere(f"{frame}/a/b", radius=PARTICLE_RADIUS, color=PARTICLE_COLORS[0],
                                              subdivisions=2, cast_shadow=False, receive_shadow=False)
        self._ball_focus = 0
        # All five forces in one node (one `points` message moves them), the sum in another (thinner).
        self.force_arrows = Arrows(scene, f"{frame}/a/a", [FORCE_COLORS[key] for key in FORCE_KEYS],
                                   shaft_radius=0.018, head_radius=0.05, head_length=0.1)
        self.sum_arrow = Arrows(scene, f"{frame}/a/s", [(200, 0, 0)], shaft_radius=0.01,
                                head_radius=0.035, head_length=0.08)
        texts = {**{key: self.tr.gettext(text) for key, text in FORCE_LABELS.items()}, "sum": "m ẍ′"}
        self.force_labels = {key: self.labels.add(scene.add_label(
            f"{frame}/a/l/{key}", text, font_screen_scale=LABEL_FONT, visible=False,
            anchor="center-left" if key == "sum" else "center-center"), KEY, wanted=False)
            for key, text in texts.items()}
        self.force_label_poses = {key: Pose(label, tolerance=LABEL_TOLERANCE)
                                  for key, label in self.force_labels.items()}

    def _build_disc(self, scene: Any, parent: str) -> None:
        radius = self.sim.setup.value("disc_radius")
        _disc(scene, parent, radius)
        self._drawn_disc = radius

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        tr = self.tr
        _ = tr.gettext
        self.param_specs_shown = [spec.translated(tr) for spec in PARAM_SPECS]
        angle_specs = [spec.translated(tr) for spec in ANGLE_SPECS]
        self.particles_shown = tr.all(PARTICLES)
        self.build_head(_(
            "### Moving frame C′ (memo §4, (1.28))\n"
            "x = a + D x′, D = Rz(φ) Rx(θ) Rz(ψ).  In C′: **m ẍ′ = Dᵀ F − m Dᵀä − m ω̇ × x′ "
            "− m ω × (ω × x′) − 2m ω × ẋ′** (ω = ω_b, body components).  Particles: blue free, "
            "green at rest in C′, magenta on a spring; pale paths in C, dark paths in C′."
        ))
        self.gui_ride = gui.add_checkbox(_("Ride with C′"), False,
                                         hint=_("on: the rider's view (C′ stands still); off: the inertial view (C)"))
        self.gui_forces_on = gui.add_dropdown(_("Forces on"), self.particles_shown,
                                              initial_value=self.particles_shown[self.sim.setup.focus],
                                              hint=_("the particle whose real and inertial forces are drawn"))
        self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset, self.choose_own_preset, tr=tr)
        self.folder_readout = gui.add_folder(_("Readout"))
        with self.folder_readout:
            self.readout = Readout(gui)
        self.folder_frame = gui.add_folder(_("Frame C′ (restarts at t = 0)"), expand_by_default=False)
        with self.folder_frame:
            self.gui_angles = [add_slider(gui, spec, value)
                               for spec, value in zip(angle_specs, self.sim.setup.angles_deg)]
            frame_sliders = [self._slider(gui, key) for key in FRAME_KEYS]
        self.folder_particles = gui.add_folder(_("Particles (restarts at t = 0)"), expand_by_default=False)
        with self.folder_particles:
            particle_sliders = [self._slider(gui, key) for key in PARTICLE_KEYS]
        self.folder_display = gui.add_folder(_("Display"), expand_by_default=False)
        with self.folder_display:
            self.gui_show_paths = gui.add_checkbox(_("Paths"), True,
                                                   hint=_("pale: in C; dark: in C′ (what a rider sees)"))
            self.gui_show_forces = gui.add_checkbox(_("Force arrows"), True)
            display_sliders = [self._slider(gui, key) for key in DISPLAY_KEYS[:1]]
            self.gui_reset_view = gui.add_button(_("Reset view"), icon=viser.Icon.CAMERA)
            self.gui_legend = gui.add_markdown("")
        self.gui_params = [*frame_sliders, *particle_sliders, *display_sliders]
        self._param_keys = [*FRAME_KEYS, *PARTICLE_KEYS, *DISPLAY_KEYS[:1]]
        for handle, key in zip(self.gui_params, self._param_keys):
            index = KEYS.index(key)
            self.bind(handle, f"{key} slider", self._param_edit(key), nth(lambda: self.sim.setup.params, index),
                      spec=self.param_specs_shown[index])
        for index, handle in enumerate(self.gui_angles):
            self.bind(handle, f"{ANGLE_SPECS[index].key} slider", self._angle_edit(index),
                      nth(lambda: self.sim.setup.angles_deg, index), spec=angle_specs[index])
        self.gui_ride.on_update(wrap("ride toggle", lambda _event: self.refresh()))
        self.gui_forces_on.on_update(wrap("forces-on dropdown", self._forces_on_chosen))
        for handle in (self.gui_show_paths, self.gui_show_forces):
            handle.on_update(wrap("display toggle", lambda _event: self.refresh()))
        self.gui_reset_view.on_click(wrap("reset view", lambda _event: self.reset_view()))
        self._gui_roots = [self.gui_intro, self.message.handle, *self.transport.handles, self.gui_ride,
                           self.gui_forces_on, *self.presets_row.groups, self.presets_row.gui_note,
                           self.folder_readout, self.folder_frame, self.folder_particles, self.folder_display]

    def _slider(self, gui: Any, key: str) -> Any:
        spec = self.param_specs_shown[KEYS.index(key)]
        return add_slider(gui, spec, self.sim.setup.value(key))

    # ------------------------------------------------------------------ callbacks
    def _edit(self, params: Sequence[float], angles_deg: Sequence[float], display_only: bool) -> str | None:
        """Apply an edit to the simulation; the refusal text, or None if it was applied."""
        try:
            setup = MovingFrameSetup(tuple(float(p) for p in params),
                                     (float(angles_deg[0]), float(angles_deg[1]), float(angles_deg[2])))
        except ValueError as error:
            return str(error)
        self.message.clear()
        if display_only:
            self.sim.set_display(setup)
        else:
            self.sim.preset = None
            self.sim.set_setup(setup)
        self.room.refresh()
        return None

    def _param_edit(self, key: str) -> Callable[[float], str | None]:
        index = KEYS.index(key)

        def apply(value: float) -> str | None:
            params = list(self.sim.setup.params)
            params[index] = value
            return self._edit(params, self.sim.setup.angles_deg, key in DISPLAY_KEYS)

        return apply

    def _angle_edit(self, index: int) -> Callable[[float], str | None]:
        def apply(value: float) -> str | None:
            angles = list(self.sim.setup.angles_deg)
            angles[index] = value
            return self._edit(self.sim.setup.params, angles, False)

        return apply

    def _forces_on_chosen(self, _event: Any) -> None:
        if self.quiet.active:
            return
        choice = self.gui_forces_on.value
        if choice not in self.particles_shown:  # a client can send any string
            self.message.show(Said(N_("Forces on {choice} refused: choose one of {options}."),
                                   choice=repr(choice), options=", ".join(self.particles_shown)))
            self.quiet.write(self.gui_forces_on, self.particles_shown[self.sim.setup.focus])
            return
        params = list(self.sim.setup.params)
        params[KEYS.index("forces_on")] = float(self.particles_shown.index(choice) + 1)
        self._edit(params, self.sim.setup.angles_deg, True)

    def set_riding(self, on: bool) -> None:
        """The camera toggle, as clicking it does."""
        self.gui_ride.value = bool(on)  # viser's setter; runs its callback: refresh

    @property
    def riding(self) -> bool:
        return bool(self.gui_ride.value)

    # ------------------------------------------------------------------ the view protocol
    def frame(self, dt: float) -> None:
        """The per-frame update: poses, particles, paths, arrows; readout and sliders throttled."""
        with self.client.atomic():
            if self.sim.version != self._drawn_version:
                self._draw(dt)
            self.labels.update(dt)

    def refresh(self) -> None:
        """Redraw everything from the simulation."""
        with self.client.atomic():
            setup = self.sim.setup
            if setup.value("disc_radius") != self._drawn_disc:
                self.body.reshape(self._build_disc)
            self.transport.show(self.room.playing, self.room.time_scale)
            self.presets_row.show_note(self.preset_shown())
            self.show_values(self.gui_params, [PARAM_SPECS[KEYS.index(k)] for k in self._param_keys],
                             [setup.value(k) for k in self._param_keys])
            self.show_values(self.gui_angles, ANGLE_SPECS, setup.angles_deg)
            self.quiet.write(self.gui_forces_on, self.particles_shown[setup.focus])
            self.gui_legend.content = self.tr.gettext(
                "Arrows: 1 m = {newtons} N, drawn in C′ at the particle "
                "(body components, turned by D for display).  \n"
                "Black: the real force Dᵀ F; olive −m Dᵀä; teal Euler; orange centrifugal; violet "
                "Coriolis; thin red: m ẍ′ (their sum).  Thin grey rod: from C′'s origin back along −z′ by h."
            ).format(newtons=self.tr.general(float(f"{1.0 / setup.value('force_scale'):.3g}")))
            self._readout_throttle.trigger()
            self._draw(0.0)
            self.labels.settle()

    def _draw(self, dt: float) -> None:
        """Draw the simulation now: exactly when paused, at display resolution while playing
        (`app.kit.draw.lean.Pose`: ~1 px, sent only when what is drawn changed)."""
        sim = self.sim
        self._drawn_version = sim.version
        exact = not self.room.playing
        frame = sim.frame
        R, a = frame.R_space_body, frame.a
        # Poses: C′ in C; while riding, the world turned by the inverse of C′'s pose as drawn
        # (so that C′ stands still on screen to rounding).
        self.frame_pose.set(wxyz_from_matrix(R), a, exact=exact)
        if self.riding:
            q = self.frame_pose.wxyz or (1.0, 0.0, 0.0, 0.0)
            p = np.asarray(self.frame_pose.position or (0.0, 0.0, 0.0), dtype=float)
            R_drawn = _matrix_of(q)
            back = -(p @ R_drawn)  # −Dᵀ a, as drawn
            self.world_pose.set((q[0], -q[1], -q[2], -q[3]), back, exact=True)
        else:
            self.world_pose.set((1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), exact=True)
        h = sim.setup.value("offset")
        rod_visible = h > 0.0
        if self.radius_rod.visible != rod_visible:
            self.radius_rod.visible = rod_visible
        if rod_visible and float(self.radius_rod.points[0, 1, 2]) != -h:
            self.radius_rod.points = np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, -h]]], dtype=np.float32)
        ax, ay, az = (float(c) for c in sim.setup.anchor_body)
        anchor = (f32(ax), f32(ay), f32(az))
        if tuple(self.spring_group.position) != anchor:
            self.spring_group.position = anchor
        # Particles and the spring, in C′ (the spring particle and the spring from the anchor).
        x_body, _ = sim.body_coordinates()
        d = x_body[2] - np.array(anchor)
        stretch = (tuple(f32(c) for c in d) if exact else tuple(snap(float(c), GRID) for c in d))
        focus = sim.setup.focus
        for k, pose in enumerate(self.particle_poses):
            own = k != focus  # else drawn by the ball of the forces' group
            if self.particles[k].visible != own:
                self.particles[k].visible = own
            if own and k == 1:  # snapped about its place in C′: at rest there, it is drawn there and sends nothing
                place = sim.setup.rider_body
                pose.set(position=x_body[1] if exact else place + [snap(float(c), GRID) for c in x_body[1] - place])
            elif own:
                pose.set(position=stretch if k == 2 else x_body[k], exact=exact)
        if self._ball_focus != focus:
            self.focus_ball.color = PARTICLE_COLORS[focus]
            self._ball_focus = focus
        if stretch != self._spring_drawn:
            set_scale(self.spring, stretch)  # type: ignore[arg-type]
            self._spring_drawn = stretch
        self._draw_paths(bool(self.gui_show_paths.value), lazy=not exact)
        # Forces on the chosen particle, body components, drawn in C′ from its centre (the
        # group sits where that particle is drawn).
        report = sim.forces()
        scale = sim.setup.value("force_scale")
        show = bool(self.gui_show_forces.value)
        self.forces_pose.set(position=x_body[focus], exact=exact)
        vectors = {"real": report.real[focus], "translational": report.inertial.translational[focus],
                   "euler": report.inertial.euler[focus], "centrifugal": report.inertial.centrifugal[focus],
                   "coriolis": report.inertial.coriolis[focus]}
        vectors["sum"] = report.m_x_ddot_body[focus]
        drawn = {key: scale * np.asarray(vector, dtype=float) for key, vector in vectors.items()}
        origin = np.zeros(3)
        self.force_arrows.set(np.array([[origin, drawn[key]] for key in FORCE_KEYS]), [show] * len(FORCE_KEYS),
                              exact=exact)
        self.sum_arrow.set(np.array([[origin, drawn["sum"]]]), [show], exact=exact)
        for key, vector in drawn.items():
            length = float(np.linalg.norm(vector))
            # A short arrow keeps its colour but loses its label: labels of short arrows pile up.
            wanted = show and length >= LABEL_MIN_LENGTH
            self.labels.want(self.force_labels[key], wanted)
            if not wanted:
                continue
            if key == "sum":  # beside its middle, as if turned with the arrow
                w, x, y, z = turn_z_onto(vector)
                aside = _matrix_of((w, x, y, z)) @ np.array([LABEL_ASIDE, LABEL_ASIDE, 0.0])
                where = 0.5 * vector + aside
            else:
                where = vector * (1.0 + LABEL_BEYOND / length)
            self.force_label_poses[key].set(position=where, exact=exact)
        if self._readout_throttle.ready(dt):
            self._render_readout(report, x_body)
            self._refresh_status()

    def particle_drawn(self, k: int) -> tuple[float, float, float]:
        """Where particle k is drawn, C′ coordinates [m] (the chosen one: by the forces' group)."""
        node = self.forces_group if k == self.sim.setup.focus else self.particles[k]
        x, y, z = (float(c) for c in node.position)
        if node is self.particles[2]:  # in the spring's group, at the anchor
            ax, ay, az = (float(c) for c in self.spring_group.position)
            x, y, z = x + ax, y + ay, z + az
        return x, y, z

    def _draw_paths(self, visible: bool, lazy: bool = False) -> None:
        """The paths so far (only what is new is sent; lazy: a playing frame, the growing head
        at most at 10 Hz), or none."""
        sim = self.sim
        for lines, trace in zip((*self.paths_space, *self.paths_body), (*sim.paths_space, *sim.paths_body)):
            if visible and self._spread.wide(trace):
                lines.sync(trace, lazy=lazy)
            else:  # hidden, or a path that is one point (the particle at rest in C′, seen in C′): nothing to draw
                lines.hide(trace)

    def _refresh_status(self) -> None:
        self.transport.set_status(status_text(self.sim.t, self.room.playing, self.room.time_scale, self.riding,
                                              self.tr))

    def _render_readout(self, report: ForceReport, x_body: Array) -> None:
        self.readout.set(readout_text(self.sim, report, x_body, self.tr))
