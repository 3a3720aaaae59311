"""The torque-free rigid body ("Free body" scene): Euler's equations with M = 0.

Models only what it needs: `Model(inertia=(I1, I2, I3))`, no torque.  L_s = D I ω_b is fixed
in space (drawn violet), E = T is conserved, ω (orange) wanders in space and in the body.
The body is drawn as the uniform solid with exactly these principal moments: a ball when
I1 = I2 = I3, a cylinder about z′ when I1 = I2 (its sides striped so that the spin shows),
else a box (`physics.inertia.box_extents_from_moments`) with its faces tinted by the axis they
face (x′ red, y′ green, z′ blue) so that the Dzhanibekov flip is easy to see.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import trimesh

from app.common import CameraView, striped_parts
from app.simulation import Preset, SimulationScene, SliderSpec
from physics._types import Vec3
from physics.dynamics import Model, State, angular_momentum_space, energy
from physics.inertia import box_extents_from_moments

__all__ = ["FreeBodyScene", "PRESETS"]

BODY_SIZE = 1.4  # [scene units] the drawn body's largest dimension
MIN_THICKNESS = 0.03  # a flat lamina is drawn this thick
FACE_TINTS = ((245, 165, 150), (165, 220, 165), (165, 185, 245))  # faces normal to x′, y′, z′
STRIPES = ((240, 170, 70), (250, 240, 215))  # a body of revolution: alternating sectors
SYMMETRY_RTOL = 1e-9

PRESETS = (
    Preset("Dzhanibekov", (0.3, 0.75, 1.0), (-30.0, 60.0, 0.0), (0.05, 5.0, 0.05),
           "A book (edges 1.2 : 0.74 : 0.22) spun about its intermediate axis y′, "
           "with a tiny wobble: the spin is unstable and the book flips over every ~3 s, while "
           "L (violet) stays fixed.  Watch ω_y′ change sign in the Plots tab."),
    Preset("Disc", (1.0, 1.0, 2.0), (0.0, 30.0, 0.0), (1.0, 0.0, 4.0),
           "A thin disc (I3 = 2 I1): ω_b turns about z′ at (I3 − I1)/I1 ω_z′ = ω_z′, and z′ cones "
           "about the fixed L at |L|/I1 — Feynman's wobbling plate."),
    Preset("Rod", (1.0, 1.0, 0.05), (0.0, 80.0, 0.0), (2.0, 0.0, 6.0),
           "A long rod (along z′) thrown tumbling with a spin about its own axis: the rod "
           "sweeps a cone about L while ω swings around it."),
    Preset("Sphere", (1.0, 1.0, 1.0), (20.0, 40.0, 0.0), (1.0, 2.0, 3.0),
           "A ball (I1 = I2 = I3): L = I ω, so ω is parallel to L and fixed: a steady rotation "
           "about one axis."),
)
_MOMENT_MARKS = ((0.05, "0.05"), (1.0, "1"), (2.0, "2"), (3.0, "3"), (4.0, "4"), (5.0, "5"))


class FreeBodyScene(SimulationScene):
    """The free body of one client (see the module docstring)."""

    title = "Free body"
    root = "/free"
    view = CameraView(position=(4.6, -3.9, 2.5), look_at=(0.25, 0.55, 0.1))
    intro = (
        "### Free body (no torque)\n"
        "I ω̇_b + ω_b × (I ω_b) = 0.  **L = D I ω_b** is fixed in space, **E = T** is conserved.  "
        "SI units; angles in degrees (z-x-z)."
    )
    presets = PRESETS
    preset_groups = (("Presets", tuple(p.name for p in PRESETS)),)
    param_specs = tuple(
        SliderSpec(f"I{k + 1}", f"I{k + 1} [kg m²]", 0.05, 5.0, 0.01,
                   f"principal moment about the body {'xyz'[k]}′ axis", _MOMENT_MARKS)
        for k in range(3)
    )
    param_folder = "Body: principal moments [kg m²]"
    rate_specs = tuple(
        SliderSpec(f"w{k + 1}", f"ω_{'xyz'[k]}′ [rad/s]", -10.0, 10.0, 0.01,
                   f"body component of ω along {'xyz'[k]}′ (initial condition)",
                   ((-10.0, "-10"), (-5.0, "-5"), (0.0, "0"), (5.0, "5"), (10.0, "10")))
        for k in range(3)
    )
    rate_folder = "Angular velocity ω_b, body axes [rad/s]"
    momentum_label = "|L|"
    body_axis_length = 1.15

    def model_from_params(self, params: Sequence[float]) -> Model:
        return Model(inertia=(float(params[0]), float(params[1]), float(params[2])))

    def omega_body_from_rates(self, angles: Vec3, rates: Sequence[float]) -> Vec3:
        return np.array([float(r) for r in rates])

    def rates_from_state(self, angles: Vec3, state: State) -> tuple[float, ...]:
        return tuple(float(w) for w in state.omega_body)

    # ------------------------------------------------------------------ drawing
    def _shape_kind(self) -> str:
        I1, I2, I3 = self.model.inertia
        if math.isclose(I1, I2, rel_tol=SYMMETRY_RTOL) and math.isclose(I2, I3, rel_tol=SYMMETRY_RTOL):
            return "ball"
        if math.isclose(I1, I2, rel_tol=SYMMETRY_RTOL):
            return "cylinder"
        return "box"

    def build_body(self, parent: str) -> None:
        scene = self.client.scene
        I1, I2, I3 = self.model.inertia
        kind = self._shape_kind()
        if kind == "box":
            extents = np.asarray(box_extents_from_moments((I1, I2, I3), mass=1.0), dtype=float)
            extents = np.maximum(BODY_SIZE * extents / extents.max(), MIN_THICKNESS)
            self._dimensions = tuple(float(e) for e in extents)
            mesh = trimesh.creation.box(extents=extents)
            axis_of_face = np.argmax(np.abs(mesh.face_normals), axis=1)
            for k in range(3):
                scene.add_mesh_simple(f"{parent}/faces_{'xyz'[k]}", mesh.vertices, mesh.faces[axis_of_face == k],
                                      color=FACE_TINTS[k], flat_shading=True, opacity=0.92,
                                      cast_shadow=False, receive_shadow=False)
            return
        if kind == "ball":
            radius = 0.5 * BODY_SIZE
            self._dimensions = (2 * radius,) * 3
            mesh = trimesh.creation.icosphere(subdivisions=3, radius=radius)
        else:
            # Uniform cylinder about z′ (mass 1): I3 = r²/2, I1 = (3 r² + h²)/12.
            radius = math.sqrt(2.0 * I3)
            height = math.sqrt(max(12.0 * I1 - 6.0 * I3, 0.0))
            scale = BODY_SIZE / max(2.0 * radius, height)
            radius, height = radius * scale, max(height * scale, MIN_THICKNESS)
            self._dimensions = (2 * radius, 2 * radius, height)
            mesh = trimesh.creation.cylinder(radius=radius, height=height, sections=64)
        for index, (vertices, faces) in enumerate(striped_parts(mesh.vertices, mesh.faces, 8)):
            scene.add_mesh_simple(f"{parent}/stripes_{index}", vertices, faces, color=STRIPES[index],
                                  flat_shading=kind == "cylinder", cast_shadow=False, receive_shadow=False)

    def shape_status(self) -> str:
        kind = self._shape_kind()
        a, b, c = self._dimensions
        if kind == "ball":
            return "Drawn as a uniform **ball** (I1 = I2 = I3), painted in sectors so its spin shows."
        if kind == "cylinder":
            return (f"Drawn as the uniform **cylinder** about z′ with these moments: diameter : length "
                    f"= {a / c if c > 0 else math.inf:.2f} : 1.")
        smallest = min(a, b, c)
        return (f"Drawn as the uniform **box** with these moments: edges along x′ y′ z′ "
                f"in the ratio {a / smallest:.2f} : {b / smallest:.2f} : {c / smallest:.2f}.")

    def readout_extras(self, state: State) -> str:
        R, omega = state.R_space_body, state.omega_body
        L = float(np.linalg.norm(angular_momentum_space(self.model, R, omega)))
        T = energy(self.model, R, omega)
        lines = ["conserved: E = T, L_s (fixed in space)", f"|L| = {L:.5f} kg m²/s"]
        if T > 0.0:
            lines.append(f"|L|²/(2T) = {L * L / (2.0 * T):.4f} kg m²")
            lines.append("  (= I2, the middle moment, on the")
            lines.append("   separatrix of the Dzhanibekov flip)")
        return "\n".join(lines)
