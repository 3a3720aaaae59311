"""The "Poinsot" scene's view: `PoinsotView` draws the torque-free body with Poinsot's construction
around it (`app.scenes.poinsot` says what is drawn and what a frame sends).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import trimesh

from app.i18n import N_, refusal_text
from app.kit.core.common import LABEL_SCALE, CameraView, SliderSpec, polyline_segments
from app.kit.draw.labels import AXES, DETAIL
from app.kit.draw.widgets import TraceLines, quantized, z_onto
from app.kit.panel.binding import BOX_DIGITS
from app.kit.panel.gui import Readout, add_slider
from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.rigid.torque_free import TorqueFreeView
from app.scenes.poinsot.readouts import poinsot_text
from app.scenes.poinsot.simulation import (
    CURVE_POINTS,
    energy_setting,
    next_flip_time,
    omega_space,
    run_energy,
    sorted_moments,
    state_at_energy,
    track_herpolhode,
)
from app.viser_internals import set_points, set_position, set_wxyz
from physics.poinsot import (
    PolhodeMotion,
    herpolhode_radii,
    invariable_plane,
    motion,
    polhode_family,
    polhode_L,
    polhode_omega,
    separatrix_L,
)
from physics.quaternion import wxyz_from_matrix

__all__ = ["ENERGY_SPEC", "PoinsotView"]

ELLIPSOID_SIZE = 1.5  # [scene units] Poinsot's ellipsoid's largest semi-axis
SPHERE_RADIUS = 1.1  # [scene units] the |L| sphere of the momentum-space picture
L_SPACE_AT = (-2.8, 0.8, 0.2)  # [scene units] centre of the momentum-space picture
PLANE_HALF = 2.0  # [scene units] half the side of the drawn invariable plane
HERPOLHODE_HEAD_EVERY = 12  # playing frames between sends of its growing chunk: at 1x each point is sent
# once, in its complete chunk; the line ends at most 0.2 s of motion behind the contact point
L_DOT_QUANTUM = 2.0**-9
"""While playing, L_b's frame in the momentum picture is sent as multiples of this (not of
POSE_QUANTUM): its dot (0.12 across) sits SPHERE_RADIUS from the frame's centre, so a step moves
it by at most ~2 x 1.1 x 2^-9 = 0.004 scene units (under 1 px); it is sent ~8 times less often."""
FAMILY_POINTS = 128
ELLIPSOID_COLOR = (120, 170, 230)
ENERGY_COLOR = (240, 170, 90)
SPHERE_COLOR = (200, 200, 215)
PLANE_COLOR = (150, 150, 150)
POLHODE_COLOR = (210, 0, 140)
HERPOLHODE_COLOR = (0, 130, 120)
FAMILY_COLOR = (120, 120, 130)
SEPARATRIX_COLOR = (220, 30, 30)
ENERGY_SPEC = SliderSpec(
    "energy", N_("Energy: x′ ← 0 → z′"), -1.0, 1.0, 0.01,
    N_("|L|²/(2T) from I_min (−1: about the smallest-moment axis) through I_mid (0: the separatrix) to "
       "I_max (+1: about the largest-moment axis); |L| and L in space are kept"),
    ((-1.0, "x′"), (0.0, N_("sep.")), (1.0, "z′")),
)


def _triple(v: np.ndarray) -> tuple[float, float, float]:
    return float(v[0]), float(v[1]), float(v[2])


def _circle(radius: float, n: int = 96) -> np.ndarray:
    s = np.linspace(0.0, 2.0 * math.pi, n + 1)
    return np.stack([radius * np.cos(s), radius * np.sin(s), np.zeros_like(s)], axis=1)


def _closed_segments(points: np.ndarray) -> np.ndarray:
    """Segments (N, 2, 3) float32 of a closed curve (N, 3)."""
    return polyline_segments(np.concatenate([points, points[:1]])).astype(np.float32)


class PoinsotView(TorqueFreeView):
    """Poinsot's construction (see the module docstring)."""

    title = N_("Poinsot")  # the scene dropdown shows it translated (app.i18n)
    simulation_parts = (omega_space,)  # the point the herpolhode follows (the room codec decodes it)
    root = "/pt"  # node names are short: every message of a frame carries its node's name
    view = CameraView(position=(2.6, -8.2, 1.9), look_at=(1.1, 0.5, -0.5))
    intro = N_(
        "### Poinsot: the ellipsoid rolls on the invariable plane\n"
        "Poinsot's ellipsoid **ω·Iω = 2T** (blue, fixed in the body) touches the plane **n·ω = 2T/|L|** "
        "(n = L/|L|, fixed in space) at **ω**: polhode (magenta) on it, herpolhode (teal) on the plane.  "
        "Left: body L-space, sphere |L| ∩ energy ellipsoid, separatrix red."
    )
    preset_file = "poinsot.json"
    grid_z = -2.2
    omega_label_at_middle = True  # the contact point at ω's tip stays clear
    arrow_lengths = (1.45, 2.2)

    def fixed_omega_scale(self) -> float | None:
        return self._poinsot_scale()

    def _poinsot_scale(self) -> float | None:
        """[scene units per rad/s] for this run: the ellipsoid's largest semi-axis is ELLIPSOID_SIZE."""
        omega = self.sim.initial_state.omega_body
        I = np.asarray(self.sim.model.inertia, dtype=float)
        T = 0.5 * float(omega @ (I * omega))
        return ELLIPSOID_SIZE / math.sqrt(2.0 * T / float(I.min())) if T > 0.0 else None

    # ------------------------------------------------------------------ building (once)
    def build_extras(self) -> None:
        scene = self.client.scene
        root = self.root
        unit = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
        vertices, faces = unit.vertices.astype(np.float32), unit.faces.astype(np.uint32)
        idle = np.zeros((1, 2, 3), dtype=np.float32)
        body = f"{self.body.node.name}/poinsot"  # under the body's frame: turned with it, nothing sent per frame
        self.ellipsoid = scene.add_mesh_simple(f"{body}/ellipsoid", vertices, faces, color=ELLIPSOID_COLOR,
                                               opacity=0.28, cast_shadow=False, receive_shadow=False)
        self.polhode = scene.add_line_segments(f"{body}/polhode", idle, POLHODE_COLOR, thickness=4.0,
                                               thickness_units="screen")
        self.plane = scene.add_frame(f"{root}/plane", show_axes=False)
        h = PLANE_HALF
        square = np.array([[-h, -h, 0.0], [h, -h, 0.0], [h, h, 0.0], [-h, h, 0.0]], dtype=np.float32)
        scene.add_mesh_simple(f"{root}/plane/square", square, np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32),
                              color=PLANE_COLOR, opacity=0.3, side="double", cast_shadow=False, receive_shadow=False)
        scene.add_line_segments(f"{root}/plane/edge", _closed_segments(square.astype(float)), (110, 110, 110),
                                thickness=1.5, thickness_units="screen")
        self.radii = scene.add_line_segments(f"{root}/plane/radii", idle, HERPOLHODE_COLOR, thickness=1.0,
                                             thickness_units="screen")
        self.plane_label = self.labels.add(
            scene.add_label(f"{root}/plane/label", self.tr.gettext("invariable plane"),
                            position=(0.8 * h, 0.8 * h, 0.0),
                            font_screen_scale=LABEL_SCALE * 0.8, anchor="bottom-center"), DETAIL)
        scene.add_frame(f"{root}/herpolhode", show_axes=False)
        self.herpolhode = TraceLines(scene, f"{root}/herpolhode", HERPOLHODE_COLOR, self.sim.traces["herpolhode"],
                                     head_every=HERPOLHODE_HEAD_EVERY)
        # The contact point is ω's tip: a child of the arrow's tip, moved with it for nothing.
        self.contact = scene.add_icosphere(f"{self.omega.tip.name}/contact", radius=0.06, color=(20, 20, 20),
                                           subdivisions=2)
        self.contact_alone = scene.add_icosphere(f"{root}/contact", radius=0.06, color=(20, 20, 20),
                                                 subdivisions=2, visible=False)  # while the ω arrow is off

        # Body angular-momentum space, beside it (body components, not turning).
        ls = f"{root}/Ls"
        self.lspace = scene.add_frame(ls, show_axes=False, position=L_SPACE_AT)
        scene.add_mesh_simple(f"{ls}/sphere", vertices * SPHERE_RADIUS, faces, color=SPHERE_COLOR, opacity=0.22,
                              cast_shadow=False, receive_shadow=False)
        self.energy_ellipsoid = scene.add_mesh_simple(f"{ls}/energy", vertices, faces, color=ENERGY_COLOR,
                                                      opacity=0.18, cast_shadow=False, receive_shadow=False)
        axes = 1.45 * SPHERE_RADIUS * np.eye(3)
        scene.add_line_segments(f"{ls}/axes", np.stack([-axes, axes], axis=1).astype(np.float32),
                                np.array([[c, c] for c in ((150, 0, 0), (0, 105, 20), (0, 30, 150))], dtype=np.uint8),
                                thickness=2.0, thickness_units="screen")
        self.axis_labels = [
            self.labels.add(scene.add_label(f"{ls}/label_{k}", name,
                                            position=tuple(1.58 * SPHERE_RADIUS * np.eye(3)[k]),
                                            font_screen_scale=LABEL_SCALE * 0.8, anchor="center-center"), AXES)
            for k, name in enumerate(("L_x′", "L_y′", "L_z′"))
        ]
        self.labels.add(scene.add_label(f"{ls}/title", self.tr.gettext("body L-space"),
                                        position=(0.0, 0.0, 1.85 * SPHERE_RADIUS), font_screen_scale=LABEL_SCALE * 0.8,
                                        anchor="bottom-center"), DETAIL)
        self.family = scene.add_line_segments(f"{ls}/family", idle, FAMILY_COLOR, thickness=1.5,
                                              thickness_units="screen")
        self.separatrix = scene.add_line_segments(f"{ls}/separatrix", idle, SEPARATRIX_COLOR, thickness=3.0,
                                                  thickness_units="screen")
        self.current = scene.add_line_segments(f"{ls}/current", idle, POLHODE_COLOR, thickness=4.5,
                                               thickness_units="screen")
        # |L| is conserved: L_b's dot stays on the sphere, at the +z of a frame turned onto L_b
        # (one orientation message when it moves, the kind the frame sends anyway).
        self.L_turn = scene.add_frame(f"{ls}/Lt", show_axes=False)
        self.L_dot = scene.add_icosphere(f"{ls}/Lt/L_b", radius=0.06, color=(120, 40, 200), subdivisions=2,
                                         position=(0.0, 0.0, SPHERE_RADIUS))
        self._drawn_family: tuple[float, ...] | None = None
        self._flip_schedule: tuple[float, float] | None = None  # (next flip, period) [s]
        self._motion: PolhodeMotion | None = None  # the run's polhode (None: a body at rest)
        self._L_scale_space = 1.0  # [scene units per kg m²/s] of the momentum picture
        self._L_turn: tuple[float, ...] = ()  # L_b's frame as sent

    def build_display_extras(self, gui: Any) -> None:
        self.gui_show_nodes.value = False  # the line of nodes would only clutter this picture
        _ = self.tr.gettext
        self.gui_show_lspace = gui.add_checkbox(_("Momentum-space picture"), True,
                                                hint=_("body L-space: the |L| sphere, the energy ellipsoid, "
                                                       "the polhodes"))
        self.gui_show_lspace.on_update(self._wrap("momentum picture", lambda _event: self._show_lspace()))

    def _show_lspace(self) -> None:
        self.lspace.visible = bool(self.gui_show_lspace.value)
        self.draw_extras(self.sim)  # L_b's dot was not moved while the picture was hidden

    def _build_gui(self) -> None:
        super()._build_gui()
        gui = self.client.gui
        with self.tabs.tab("Setup"), gui.add_folder("Poinsot", order=self.presets_row.gui_note.order + 0.01):
            energy_spec = ENERGY_SPEC.translated(self.tr)
            self.gui_energy = add_slider(gui, energy_spec)
            self.poinsot_readout = Readout(gui)
        self.bind(self.gui_energy, "energy slider", self._energy_edit, self._energy_in_force, spec=energy_spec)

    # ------------------------------------------------------------------ a new run
    def restart_extras(self) -> None:
        super().restart_extras()
        sim = self.sim
        I = np.asarray(sim.model.inertia, dtype=float)
        omega = sim.initial_state.omega_body
        R = sim.initial_state.R_space_body
        T = 0.5 * float(omega @ (I * omega))
        L_body = I * omega
        L_norm = float(np.linalg.norm(L_body))
        active = T > 0.0
        for node in (self.ellipsoid, self.polhode, self.plane, self.contact, self.energy_ellipsoid, self.current,
                     self.L_dot):
            if node.visible != active:
                node.visible = active
        if not active:
            self._flip_schedule = None
            self.show_values([self.gui_energy], [ENERGY_SPEC], [0.0])
            return
        scale = self.omega_scale
        mo = motion(I, T, L_norm)
        sign = 1.0 if L_body[mo.r] >= 0.0 else -1.0
        self.ellipsoid.scale = _triple(scale * np.sqrt(2.0 * T / I))
        set_points(self.polhode, _closed_segments(polhode_omega(I, T, L_norm, CURVE_POINTS, sign) * scale))
        normal, distance = invariable_plane(R @ L_body, T)
        frame = np.column_stack([*self._plane_axes(normal), normal])
        self.plane.position = _triple(normal * distance * scale)
        self.plane.wxyz = wxyz_from_matrix(frame)
        rho = herpolhode_radii(I, T, L_norm)
        circles = [_closed_segments(_circle(r * scale)[:-1]) for r in rho if r > 0.0]
        set_points(self.radii, np.concatenate(circles) if circles else np.zeros((1, 2, 3), dtype=np.float32))
        # The momentum-space picture: sphere radius SPHERE_RADIUS stands for |L|.
        k = SPHERE_RADIUS / L_norm
        self._L_scale_space = k
        self.energy_ellipsoid.scale = _triple(k * np.sqrt(2.0 * T * I))
        set_points(self.current, _closed_segments(polhode_L(I, T, L_norm, CURVE_POINTS, sign) * k))
        key = tuple(I.tolist())
        if key != self._drawn_family:  # depends on the moments only (drawn on the unit sphere)
            self._drawn_family = key
            curves = polhode_family(I, 1.0, 3, FAMILY_POINTS)
            set_points(self.family, np.concatenate([_closed_segments(c * SPHERE_RADIUS) for c in curves])
                       if curves else np.zeros((1, 2, 3), dtype=np.float32))
            lo, mid, hi = sorted_moments(I)
            if lo < mid < hi:
                seps = separatrix_L(I, 1.0, CURVE_POINTS)
                set_points(self.separatrix, np.concatenate([_closed_segments(c * SPHERE_RADIUS) for c in seps]))
            self.separatrix.visible = lo < mid < hi
            for j, label in enumerate(self.axis_labels):
                label.text = f"L_{'xyz'[j]}′ (I{j + 1} = {I[j]:g})"
        period = mo.flip_period
        if mo.kind == "flip":
            flips = sim.flips(0.0, period * 1.0001)
            self._flip_schedule = (float(flips[0]), period) if flips.size else None
        else:
            self._flip_schedule = None
        self._motion = mo
        self.show_values([self.gui_energy], [ENERGY_SPEC], [energy_setting(I, T, L_norm)])
        self._refresh_poinsot_readout()

    @staticmethod
    def _plane_axes(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Two unit vectors completing `normal` to a right-handed frame (x, y, normal)."""
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        x = np.cross(helper, normal)
        x /= np.linalg.norm(x)
        return x, np.cross(normal, x)

    # ------------------------------------------------------------------ per frame
    @classmethod
    def track_points(cls, sim: RigidBodySimulation) -> None:
        track_herpolhode(sim)

    def draw_extras(self, sim: RigidBodySimulation) -> None:
        if not self.contact.visible:
            self.herpolhode.hide(sim.traces["herpolhode"])
            return
        quantum = self.quantum
        alone = not self.omega.visible  # the ω arrow is off: the contact point is drawn on its own
        if self.contact_alone.visible != alone:
            self.contact_alone.visible = alone
        if alone:
            w = omega_space(sim.state) * self.omega_scale
            w_at = (float(w[0]), float(w[1]), float(w[2]))
            set_position(self.contact_alone, w_at if quantum is None else quantized(w_at, quantum))  # type: ignore[arg-type]
        self.herpolhode.sync(sim.traces["herpolhode"], self.omega_scale, lazy=quantum is not None)
        if self.lspace.visible:  # nothing sent for the hidden picture
            L = np.asarray(sim.model.inertia) * sim.state.omega_body
            norm = float(np.linalg.norm(L))
            turn = z_onto(L / norm) if norm > 0.0 else (1.0, 0.0, 0.0, 0.0)
            if quantum is not None:
                turn = quantized(turn, L_DOT_QUANTUM)  # type: ignore[assignment]
            if turn != self._L_turn:
                self._L_turn = turn
                set_wxyz(self.L_turn, turn)
        if self._flip_schedule is not None and sim.t >= self._flip_schedule[0]:
            self._refresh_poinsot_readout()

    def _next_flip(self) -> float | None:
        return next_flip_time(self._flip_schedule, self.sim.t)

    def _refresh_poinsot_readout(self) -> None:
        sim = self.sim
        self.poinsot_readout.set(poinsot_text(sim.model.inertia, run_energy(sim), self._motion, self.omega_scale,
                                              self._next_flip(), self.tr))

    def readout_extras(self, sim: RigidBodySimulation) -> str:
        return str(self.poinsot_readout.handle.content).strip("`\n")

    # ------------------------------------------------------------------ the energy slider
    def _energy_in_force(self) -> float:
        """The Energy setting of the run shown (0 for a body at rest)."""
        sim = self.sim
        I = np.asarray(sim.model.inertia, dtype=float)
        omega = sim.initial_state.omega_body
        T = 0.5 * float(omega @ (I * omega))
        if T <= 0.0:
            return 0.0
        return round(float(energy_setting(I, T, float(np.linalg.norm(I * omega)))), BOX_DIGITS)

    def set_energy(self, setting: float) -> None:
        """Move the motion to the Energy setting (−1 .. 1), same |L| and L in space; refused with
        a message where there is no such motion.  Pauses and starts a new run (t = 0)."""
        refusal = self._energy_edit(setting)
        if refusal is not None:
            self.message.show(refusal)
            self.room.refresh()

    def _energy_edit(self, setting: float) -> str | None:
        """`set_energy`'s work: the refusal text, or None once the new run started."""
        sim = self.sim
        try:
            state = state_at_energy(sim.model.inertia, sim.state, setting)
        except ValueError as error:
            return self.tr.gettext("Energy {setting} refused: {reason}.").format(
                setting=self.tr.general(setting), reason=refusal_text(error, self.tr))
        self.message.clear()
        self.room.playing = False
        sim.preset = None
        sim.restart(state)
        self.room.refresh()
        return None

