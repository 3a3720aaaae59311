"""The heavy symmetric top on a fixed pivot ("Heavy top" scene).

Models only what it needs: `Model(inertia=(I1, I1, I3), mgl=m g ℓ)`: I1 = I2 about the pivot,
the centre of mass on the body z′ axis at ℓ from the pivot, gravity along space −z, so the
torque about the pivot is M = −mgl e_z′ × e_z and V = mgl cos θ.  Conserved: E = T + V,
L_z = L·e_z (= p_φ) and ω_z′ (p_ψ = I3 ω_z′).  The closed form (`exact`) exists for every
parameter set of this scene, since it is always symmetric (I1 = I2).

Drawn: a disc on a rod (pivot at the origin, on a stand), the disc painted in sectors so the
spin shows, and the trace of the symmetry-axis tip: the simulation follows e_z′ (`tip_axis`,
`app.kit.core.trace.Trace`: the last TRACE_SECONDS of simulated time, in chunks of CHUNK_POINTS
points, at most TRACE_SECONDS / TRACE_SPACING of them), and the view draws it ROD_LENGTH long
(`app.kit.draw.widgets.TraceLines`: a frame sends only the short newest chunk).

The Energy tab (`app.kit.rigid.energy_plot`, physics in `physics.top_energy`): U_eff(θ) of this run's
constants of motion (E, L_z = p_φ, p_ψ), the energy line, the turning points θ₁ θ₂ (from the
closed form), the current θ (moved at most twice a second while playing, and only while the tab
is shown), and the class of motion named: steady precession, wave, loop, cusp, sleeping, too slow
to sleep, through the vertical.  ω is also set by hand (`app.kit.rigid.hand`): a gizmo at ω's tip
while paused, and Kick about x′ y′ z′.

Presets (`assets/presets/heavy_top.json`): the classic patterns of the tip with θ̇(0) = 0 at
θ(0) = 60° (I1 = 1, I3 = 0.5, mgl = 6, ω_z′ = 12 rad/s): steady precession (φ̇(0) on the slow
root, `physics.exact_top.steady_precession_rate`), waves (half of it), loops (minus half) and
cusps (φ̇(0) = 0); a sleeping top (near θ = 0, ω_z′² > 4 I1 mgl / I3²) and one too slow to sleep.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import trimesh

from app.i18n import N_
from app.kit.core.common import GIMBAL_LOCK_DEG, LABEL_SCALE, CameraView, SliderSpec, striped_parts
from app.kit.draw.labels import KEY
from app.kit.draw.widgets import TraceLines
from app.kit.rigid.energy_plot import EnergyPlot
from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.rigid.view import RigidBodyView
from physics._types import Vec3
from physics.dynamics import Model, State, angular_momentum_space
from physics.euler import euler_rates_from_omega_body, omega_body_from_euler_rates
from physics.top_energy import TopEnergyPicture, energy_picture

__all__ = ["CHUNK_POINTS", "TRACE_SECONDS", "TRACE_SPACING", "HeavyTopView", "tip_axis"]

ROD_LENGTH = 1.3  # [scene units] pivot to the tip of the symmetry axis (the traced point)
DISC_CENTER = 0.85  # [scene units] along z′
DISC_THICKNESS = 0.1
STAND_HEIGHT = 1.3  # the stand's base (and the grid) at z = -STAND_HEIGHT
TRACE_SECONDS = 12.0  # [s] of simulated time kept in the trace
TRACE_SPACING = 1.0 / 30.0  # [s] of simulated time between stored trace points (~4 cm of tip at 1 rad/s)
CHUNK_POINTS = 4  # a chunk completes every 0.1 s at time scale 1: each point is sent once (TraceLines)
TRACE_COLOR = (200, 0, 120)
STRIPES = ((200, 40, 40), (250, 235, 210))
ROD_COLOR = (90, 90, 100)
_MARKS_RATE = ((-360.0, "-360"), (-180.0, "-180"), (0.0, "0"), (180.0, "180"), (360.0, "360"))


def tip_axis(state: State) -> np.ndarray:
    """The traced point: the symmetry axis e_z′ (3,) in space components (the tip is at
    ROD_LENGTH times it)."""
    return state.R_space_body[:, 2]


def _disc_on_rod(disc_radius: float) -> list[tuple[np.ndarray, np.ndarray, tuple[int, int, int]]]:
    """(vertices, faces, colour) parts of the top in body coordinates (pivot at 0, axis z′)."""
    rod = trimesh.creation.cylinder(radius=0.035, height=ROD_LENGTH, sections=24)
    rod.apply_translation((0.0, 0.0, 0.5 * ROD_LENGTH))
    knob = trimesh.creation.icosphere(subdivisions=2, radius=0.06)
    knob.apply_translation((0.0, 0.0, ROD_LENGTH))
    disc = trimesh.creation.cylinder(radius=disc_radius, height=DISC_THICKNESS, sections=64)
    disc.apply_translation((0.0, 0.0, DISC_CENTER))
    parts = [(rod.vertices, rod.faces, ROD_COLOR), (knob.vertices, knob.faces, TRACE_COLOR)]
    for (vertices, faces), color in zip(striped_parts(disc.vertices, disc.faces, 8), STRIPES):
        parts.append((vertices, faces, color))
    return parts


class HeavyTopView(RigidBodyView):
    """The heavy symmetric top (see the module docstring)."""

    title = N_("Heavy top")  # the scene dropdown shows it translated (app.i18n)
    simulation_parts = (tip_axis,)  # the point its trace follows (the room codec decodes it)
    root = "/top"
    view = CameraView(position=(5.2, -4.0, 2.4), look_at=(0.55, 0.95, -0.1))
    intro = N_(
        "### Heavy symmetric top (pivot at the origin)\n"
        "Gravity −g e_z on the centre of mass at ℓ along z′: **M = −mgℓ e_z′ × e_z**, "
        "V = mgℓ cos θ.  Conserved: E, L_z, ω_z′.  Angles in degrees (z-x-z)."
    )
    preset_file = "heavy_top.json"
    param_specs = (
        SliderSpec("I1", "I1 = I2 [kg m²]", 0.1, 5.0, 0.01, N_("transverse moment about the pivot"),
                   ((0.1, "0.1"), (1.0, "1"), (2.5, "2.5"), (5.0, "5"))),
        SliderSpec("I3", "I3 [kg m²]", 0.05, 5.0, 0.01, N_("moment about the symmetry axis z′ (≤ 2 I1)"),
                   ((0.05, "0.05"), (1.0, "1"), (2.5, "2.5"), (5.0, "5"))),
        SliderSpec("mgl", "m g ℓ [N m]", 0.0, 30.0, 0.1, N_("weight times the pivot-to-centre-of-mass distance"),
                   ((0.0, "0"), (10.0, "10"), (20.0, "20"), (30.0, "30"))),
    )
    param_folder = N_("Top: moments and gravity")
    rate_specs = (
        SliderSpec("spin", N_("spin ω_z′ [rad/s]"), -40.0, 40.0, 0.1, N_("body component of ω along z′ (conserved)"),
                   ((-40.0, "-40"), (0.0, "0"), (12.0, "12"), (40.0, "40"))),
        SliderSpec("phi_dot", "dφ/dt [deg/s]", -360.0, 360.0, 0.1, N_("precession rate"), _MARKS_RATE),
        SliderSpec("theta_dot", "dθ/dt [deg/s]", -360.0, 360.0, 0.1, N_("nutation rate"), _MARKS_RATE),
    )
    rate_folder = N_("Spin and Euler rates")
    hand_gizmos = ("omega",)
    tilt_frame = True  # steady precession: ω and L stand still in the φ-θ frame (nothing sent for them)
    momentum_kind = "z"
    momentum_label = "L_z"
    grid_z = -STAND_HEIGHT
    body_axis_length = 1.1
    arrow_lengths = (1.95, 2.45)  # beyond the disc and the tip (ROD_LENGTH), and apart

    @classmethod
    def model_from_params(cls, params: Sequence[float]) -> Model:
        I1, I3, mgl = (float(p) for p in params)
        return Model(inertia=(I1, I1, I3), mgl=mgl)

    @classmethod
    def params_from_model(cls, model: Model) -> tuple[float, ...]:
        return model.inertia[0], model.inertia[2], model.mgl

    @classmethod
    def omega_body_from_rates(cls, angles: Vec3, rates: Sequence[float]) -> Vec3:
        spin, phi_dot_deg, theta_dot_deg = (float(r) for r in rates)
        phi_dot, theta_dot = math.radians(phi_dot_deg), math.radians(theta_dot_deg)
        psi_dot = spin - phi_dot * math.cos(float(angles[1]))  # ω_z′ = φ̇ cos θ + ψ̇
        return omega_body_from_euler_rates(angles, np.array([phi_dot, theta_dot, psi_dot]))

    @classmethod
    def rates_from_state(cls, angles: Vec3, state: State) -> tuple[float, ...]:
        phi_dot, theta_dot, _ = euler_rates_from_omega_body(
            angles, state.omega_body, min_sin_theta=math.sin(math.radians(GIMBAL_LOCK_DEG)))
        return float(state.omega_body[2]), math.degrees(phi_dot), math.degrees(theta_dot)

    # ------------------------------------------------------------------ drawing
    def build_shape(self, scene: Any, parent: str, model: Model) -> None:
        I1, _, I3 = model.inertia
        radius = min(max(0.75 * math.sqrt(I3 / I1), 0.2), 0.85)  # shape only, not to scale
        for index, (vertices, faces, color) in enumerate(_disc_on_rod(radius)):
            scene.add_mesh_simple(f"{parent}/part_{index}", vertices, faces, color=color,
                                  flat_shading=index >= 2, cast_shadow=False, receive_shadow=False)

    def build_extras(self) -> None:
        scene = self.client.scene
        root = self.root
        stand = trimesh.creation.cone(radius=0.3, height=STAND_HEIGHT, sections=32)
        stand.apply_translation((0.0, 0.0, -STAND_HEIGHT))
        scene.add_mesh_simple(f"{root}/stand", stand.vertices, stand.faces, color=(150, 150, 160),
                              cast_shadow=False, receive_shadow=False)
        pivot = trimesh.creation.icosphere(subdivisions=2, radius=0.07)
        scene.add_mesh_simple(f"{root}/pivot", pivot.vertices, pivot.faces, color=(40, 40, 40))
        gravity_at = np.array([-1.6, 1.6, 1.0])
        scene.add_arrows(f"{root}/gravity", np.array([[gravity_at, gravity_at - (0.0, 0.0, 0.8)]]),
                         (60, 60, 60), shaft_radius=0.02, head_radius=0.06, head_length=0.14)
        self.labels.add(scene.add_label(f"{root}/gravity_label", "g", position=tuple(gravity_at + (0.12, 0.0, -0.3)),
                                        font_screen_scale=LABEL_SCALE, anchor="center-left"), KEY)
        self._trace_root = scene.add_frame(f"{root}/trace", show_axes=False)
        self.trace = TraceLines(scene, f"{root}/trace", TRACE_COLOR, self.sim.traces["tip"])

    def build_display_extras(self, gui: Any) -> None:
        _ = self.tr.gettext
        self.gui_show_trace = gui.add_checkbox(
            _("Tip trace"), True, hint=_("the last {seconds} s of the z′ tip").format(
            seconds=self.tr.general(TRACE_SECONDS)))
        self.gui_show_trace.on_update(self._wrap("trace toggle", lambda _event: self._show_trace()))

    def _show_trace(self) -> None:
        self._trace_root.visible = bool(self.gui_show_trace.value)

    @classmethod
    def track_points(cls, sim: RigidBodySimulation) -> None:
        sim.track("tip", tip_axis, seconds=TRACE_SECONDS, spacing=TRACE_SPACING, chunk_points=CHUNK_POINTS)

    def draw_extras(self, sim: RigidBodySimulation) -> None:
        self.trace.sync(sim.traces["tip"], ROD_LENGTH, lazy=self.quantum is not None)
        if self.tabs.shown == "Energy":
            self._draw_energy(sim)

    # ------------------------------------------------------------------ the energy picture
    extra_tabs = (N_("Energy"),)

    def build_tab_extras(self, gui: Any) -> None:
        with self.tabs.tab("Energy"):
            self.energy_plot = EnergyPlot(gui, self.tr)
        self._energy_run = -1  # the run (sim.restarts) whose picture is drawn

    def plot_elements(self, tab: str) -> list[Any]:
        """Energy: the class of motion, the U_eff(θ) chart and its readout; else the rigid body's."""
        if tab == "Energy":
            plot = self.energy_plot
            return [plot.gui_motion, plot.handle, plot.gui_readout]
        return super().plot_elements(tab)

    @staticmethod
    def energy_picture_of(sim: RigidBodySimulation) -> TopEnergyPicture:
        """The energy picture of the simulation's run (its constants of motion: the run's start);
        ValueError if there is none."""
        I1, _, I3 = sim.model.inertia
        start = sim.initial_state
        return energy_picture(I1, I3, sim.model.mgl, start.R_space_body, start.omega_body)

    def _draw_energy(self, sim: RigidBodySimulation) -> None:
        """A new run: a new picture; the same run: the current θ moves (throttled while playing)."""
        R = sim.state.R_space_body
        theta = math.atan2(math.hypot(R[0, 2], R[1, 2]), R[2, 2])  # precise near the poles
        if sim.restarts != self._energy_run:
            self._energy_run = sim.restarts
            try:
                picture: TopEnergyPicture | None = self.energy_picture_of(sim)
                failure: BaseException | str = ""
            except (ValueError, ArithmeticError) as error:
                picture, failure = None, error  # said in the viewer's language by the plot
            self.energy_plot.show(picture, theta, failure)
        else:
            self.energy_plot.mark(theta, throttled=self.room.playing)

    def shape_status(self, model: Model) -> str:
        I1, _, I3 = model.inertia
        return self.tr.gettext("I3 / I1 = {ratio} (at most 2).  Drawn as a disc on a rod; the disc's size "
                               "follows I3 / I1, not to scale.  The trace follows the tip of z′.").format(
            ratio=self.tr.decimal(I3 / I1, 2))

    def readout_extras(self, sim: RigidBodySimulation) -> str:
        R, omega = sim.state.R_space_body, sim.state.omega_body
        L = angular_momentum_space(sim.model, R, omega)
        I1, _, I3 = sim.model.inertia
        critical = 4.0 * I1 * sim.model.mgl / (I3 * I3)
        return (f"p_φ = L_z = {L[2]:.5f} kg m²/s\n"
                f"p_ψ = I3 ω_z′ = {I3 * omega[2]:.5f} kg m²/s\n"
                + self.tr.gettext("(both conserved)\n"
                                  "sleeps if ω_z′² > 4 I1 mgl / I3² = {critical}\n"
                                  "  (now ω_z′² = {now})").format(critical=f"{critical:.3g}",
                                                                  now=f"{omega[2] ** 2:.3g}"))
