"""The heavy symmetric top on a fixed pivot ("Heavy top" scene).

Models only what it needs: `Model(inertia=(I1, I1, I3), mgl=m g ℓ)`: I1 = I2 about the pivot,
the centre of mass on the body z′ axis at ℓ from the pivot, gravity along space −z, so the
torque about the pivot is M = −mgl e_z′ × e_z and V = mgl cos θ.  Conserved: E = T + V,
L_z = L·e_z (= p_φ) and ω_z′ (p_ψ = I3 ω_z′).  The closed form (`exact`) exists for every
parameter set of this scene, since it is always symmetric (I1 = I2).

Drawn: a disc on a rod (pivot at the origin, on a stand), the disc painted in sectors so the
spin shows, and the trace of the symmetry-axis tip: a polyline of the last TRACE_SECONDS of
simulated time, stored in chunks of CHUNK_POINTS points so that a frame only sends the short
newest chunk (bounded memory: at most TRACE_SECONDS / TRACE_SPACING points).

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

from app.kit.common import GIMBAL_LOCK_DEG, LABEL_SCALE, CameraView, SliderSpec, polyline_segments, striped_parts
from app.kit.fastprops import set_points
from app.kit.labels import KEY
from app.kit.rigid import RigidBodySimulation
from app.kit.rigid_view import RigidBodyView
from physics._types import Vec3
from physics.dynamics import Model, State, angular_momentum_space
from physics.euler import euler_rates_from_omega_body, omega_body_from_euler_rates

__all__ = ["CHUNK_POINTS", "TRACE_SECONDS", "TRACE_SPACING", "HeavyTopView", "TipTrace"]

ROD_LENGTH = 1.3  # [scene units] pivot to the tip of the symmetry axis (the traced point)
DISC_CENTER = 0.85  # [scene units] along z′
DISC_THICKNESS = 0.1
STAND_HEIGHT = 1.3  # the stand's base (and the grid) at z = -STAND_HEIGHT
TRACE_SECONDS = 12.0  # [s] of simulated time kept in the trace
TRACE_SPACING = 1.0 / 60.0  # [s] of simulated time between stored trace points
CHUNK_POINTS = 30
TRACE_COLOR = (200, 0, 120)
STRIPES = ((200, 40, 40), (250, 235, 210))
ROD_COLOR = (90, 90, 100)
_MARKS_RATE = ((-360.0, "-360"), (-180.0, "-180"), (0.0, "0"), (180.0, "180"), (360.0, "360"))


class TipTrace:
    """A bounded polyline of the last `seconds` of a moving point, sent in small chunks.

    The chunks are a ring of line-segment nodes built once (creating a node costs viser ~2 ms):
    only the newest (head) chunk changes, redrawn on every other stored point; when it is full
    the next node of the ring becomes the head, and chunks older than `seconds` are hidden.
    Points are stored at least `spacing` [s] of simulated time apart, so a chunk spans at least
    chunk_points * spacing and the ring never needs more than seconds / that + 2 nodes.
    """

    def __init__(self, scene: Any, parent: str, color: tuple[int, int, int], *,
                 seconds: float = TRACE_SECONDS, spacing: float = TRACE_SPACING,
                 chunk_points: int = CHUNK_POINTS) -> None:
        self.seconds = seconds
        self.spacing = spacing
        self.chunk_points = chunk_points
        size = math.ceil(seconds / (chunk_points * spacing)) + 2
        idle = np.zeros((1, 2, 3), dtype=np.float32)
        self._nodes = [scene.add_line_segments(f"{parent}/{k}", idle, color, thickness=3.5,
                                               thickness_units="screen", visible=False)
                       for k in range(size)]
        self._newest = [-math.inf] * size  # the newest time in each node
        self._shown = [False] * size  # each node's visibility, as last sent
        self._head = 0
        self._head_points: list[np.ndarray] = []
        self._last_t = -math.inf

    @property
    def point_count(self) -> int:
        """Points shown (full chunks and head), for tests of the bound."""
        return self.chunk_count * self.chunk_points + len(self._head_points)

    @property
    def chunk_count(self) -> int:
        """Full chunks shown."""
        return sum(1 for k, shown in enumerate(self._shown) if shown and k != self._head)

    def clear(self) -> None:
        for k, node in enumerate(self._nodes):
            if self._shown[k]:
                node.visible = self._shown[k] = False
        self._newest = [-math.inf] * len(self._nodes)
        self._head_points = []
        self._last_t = -math.inf

    def add(self, t: float, point: np.ndarray) -> None:
        """The point at simulated time t [s] (non-decreasing between clears)."""
        if t - self._last_t < self.spacing - 1e-12 and self._head_points:
            return
        self._head_points.append(np.array(point, dtype=np.float32))
        self._last_t = t
        points = self._head_points
        head = self._nodes[self._head]
        self._newest[self._head] = t
        # Redrawn on every other stored point, not every frame: with many clients each message
        # per frame counts, and the head then trails the tip by one point at most.
        if len(points) >= 2 and (len(points) % 2 == 0 or len(points) >= self.chunk_points):
            set_points(head, polyline_segments(np.array(points)))
            if not self._shown[self._head]:
                head.visible = self._shown[self._head] = True
        if len(points) >= self.chunk_points:
            self._head = (self._head + 1) % len(self._nodes)
            self._head_points = [points[-1]]  # the next chunk starts where this one ends
        size = len(self._nodes)
        for step in range(1, size):  # from the oldest chunk on: they leave in the order they came
            k = (self._head + step) % size
            if not self._shown[k]:
                continue
            if self._newest[k] >= t - self.seconds:
                break
            self._nodes[k].visible = self._shown[k] = False


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

    title = "Heavy top"
    root = "/top"
    view = CameraView(position=(5.2, -4.0, 2.4), look_at=(0.55, 0.95, -0.1))
    intro = (
        "### Heavy symmetric top (pivot at the origin)\n"
        "Gravity −g e_z on the centre of mass at ℓ along z′: **M = −mgℓ e_z′ × e_z**, "
        "V = mgℓ cos θ.  Conserved: E, L_z, ω_z′.  Angles in degrees (z-x-z)."
    )
    preset_file = "heavy_top.json"
    param_specs = (
        SliderSpec("I1", "I1 = I2 [kg m²]", 0.1, 5.0, 0.01, "transverse moment about the pivot",
                   ((0.1, "0.1"), (1.0, "1"), (2.5, "2.5"), (5.0, "5"))),
        SliderSpec("I3", "I3 [kg m²]", 0.05, 5.0, 0.01, "moment about the symmetry axis z′ (≤ 2 I1)",
                   ((0.05, "0.05"), (1.0, "1"), (2.5, "2.5"), (5.0, "5"))),
        SliderSpec("mgl", "m g ℓ [N m]", 0.0, 30.0, 0.1, "weight times the pivot-to-centre-of-mass distance",
                   ((0.0, "0"), (10.0, "10"), (20.0, "20"), (30.0, "30"))),
    )
    param_folder = "Top: moments and gravity"
    rate_specs = (
        SliderSpec("spin", "spin ω_z′ [rad/s]", -40.0, 40.0, 0.1, "body component of ω along z′ (conserved)",
                   ((-40.0, "-40"), (0.0, "0"), (12.0, "12"), (40.0, "40"))),
        SliderSpec("phi_dot", "dφ/dt [deg/s]", -360.0, 360.0, 0.1, "precession rate", _MARKS_RATE),
        SliderSpec("theta_dot", "dθ/dt [deg/s]", -360.0, 360.0, 0.1, "nutation rate", _MARKS_RATE),
    )
    rate_folder = "Spin and Euler rates"
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
        self.trace = TipTrace(scene, f"{root}/trace", TRACE_COLOR)

    def build_display_extras(self, gui: Any) -> None:
        self.gui_show_trace = gui.add_checkbox("Tip trace", True, hint=f"the last {TRACE_SECONDS:g} s of the z′ tip")
        self.gui_show_trace.on_update(self._wrap("trace toggle", lambda _event: self._show_trace()))

    def _show_trace(self) -> None:
        self._trace_root.visible = bool(self.gui_show_trace.value)

    def draw_extras(self, sim: RigidBodySimulation) -> None:
        self.trace.add(sim.t, ROD_LENGTH * np.asarray(sim.state.R_space_body)[:, 2])

    def restart_extras(self) -> None:
        self.trace.clear()

    def shape_status(self, model: Model) -> str:
        I1, _, I3 = model.inertia
        return (f"I3 / I1 = {I3 / I1:.2f} (at most 2).  Drawn as a disc on a rod; the disc's size "
                "follows I3 / I1, not to scale.  The trace follows the tip of z′.")

    def readout_extras(self, sim: RigidBodySimulation) -> str:
        R, omega = sim.state.R_space_body, sim.state.omega_body
        L = angular_momentum_space(sim.model, R, omega)
        I1, _, I3 = sim.model.inertia
        critical = 4.0 * I1 * sim.model.mgl / (I3 * I3)
        return (f"p_φ = L_z = {L[2]:.5f} kg m²/s\n"
                f"p_ψ = I3 ω_z′ = {I3 * omega[2]:.5f} kg m²/s\n"
                "(both conserved)\n"
                f"sleeps if ω_z′² > 4 I1 mgl / I3² = {critical:.3g}\n"
                f"  (now ω_z′² = {omega[2] ** 2:.3g})")
