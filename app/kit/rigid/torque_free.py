"""The torque-free rigid body, the base of the "Free body" and "Poinsot" scenes: Euler's
equations with M = 0.

Models only what it needs: `Model(inertia=(I1, I2, I3))`, no torque.  L_s = D I ω_b is fixed
in space (drawn violet), E = T is conserved, ω (orange) wanders in space and in the body.
The body is drawn as the uniform solid with exactly these principal moments: a ball when
I1 = I2 = I3, a cylinder about z′ when I1 = I2 (`physics.inertia.cylinder_dimensions_from_moments`,
its sides striped so that the spin shows), else a box (`physics.inertia.box_extents_from_moments`)
with its faces tinted by the axis they face (x′ red, y′ green, z′ blue) so that the
Dzhanibekov flip is easy to see.  Presets: `assets/presets/free_body.json`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np
import trimesh

from app.i18n import N_
from app.kit.core.common import SliderSpec, striped_parts
from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.rigid.view import RigidBodyView
from physics._types import Vec3
from physics.dynamics import Model, State, kinetic_energy
from physics.inertia import box_extents_from_moments, cylinder_dimensions_from_moments

__all__ = ["BODY_SIZE", "TorqueFreeView", "shape_of"]

BODY_SIZE = 1.4  # [scene units] the drawn body's largest dimension
MIN_THICKNESS = 0.03  # a flat lamina is drawn this thick
FACE_TINTS = ((245, 165, 150), (165, 220, 165), (165, 185, 245))  # faces normal to x′, y′, z′
STRIPES = ((240, 170, 70), (250, 240, 215))  # a body of revolution: alternating sectors
SYMMETRY_RTOL = 1e-9
_MOMENT_MARKS = ((0.05, "0.05"), (1.0, "1"), (2.0, "2"), (3.0, "3"), (4.0, "4"), (5.0, "5"))


def shape_of(model: Model) -> tuple[str, tuple[float, float, float]]:
    """("ball" | "cylinder" | "box", its dimensions along x′ y′ z′ [scene units]) for a model."""
    I1, I2, I3 = model.inertia
    if math.isclose(I1, I2, rel_tol=SYMMETRY_RTOL) and math.isclose(I2, I3, rel_tol=SYMMETRY_RTOL):
        return "ball", (BODY_SIZE,) * 3
    if math.isclose(I1, I2, rel_tol=SYMMETRY_RTOL):
        radius, height = cylinder_dimensions_from_moments(I1, I3)
        scale = BODY_SIZE / max(2.0 * radius, height)
        diameter = 2.0 * radius * scale
        return "cylinder", (diameter, diameter, max(height * scale, MIN_THICKNESS))
    extents = np.asarray(box_extents_from_moments((I1, I2, I3), mass=1.0), dtype=float)
    extents = np.maximum(BODY_SIZE * extents / extents.max(), MIN_THICKNESS)
    return "box", (float(extents[0]), float(extents[1]), float(extents[2]))


class TorqueFreeView(RigidBodyView):
    """A torque-free body (see the module docstring): its parameters (I1, I2, I3), rates (ω_b),
    shape and readout.  A scene subclasses it with its title, root, camera view, intro and
    preset file (`app/scenes/free_body.py`, `app/scenes/poinsot/`)."""

    param_specs = (
        SliderSpec("I1", "I1 [kg m²]", 0.05, 5.0, 0.01, N_("principal moment about the body x′ axis"), _MOMENT_MARKS),
        SliderSpec("I2", "I2 [kg m²]", 0.05, 5.0, 0.01, N_("principal moment about the body y′ axis"), _MOMENT_MARKS),
        SliderSpec("I3", "I3 [kg m²]", 0.05, 5.0, 0.01, N_("principal moment about the body z′ axis"), _MOMENT_MARKS),
    )
    param_folder = N_("Body: principal moments [kg m²]")
    rate_specs = tuple(
        SliderSpec(f"w{k + 1}", label, -10.0, 10.0, 0.01, hint,
                   ((-10.0, "-10"), (-5.0, "-5"), (0.0, "0"), (5.0, "5"), (10.0, "10")))
        for k, (label, hint) in enumerate((
            (N_("ω_x′ [rad/s]"), N_("body component of ω along x′ (initial condition)")),
            (N_("ω_y′ [rad/s]"), N_("body component of ω along y′ (initial condition)")),
            (N_("ω_z′ [rad/s]"), N_("body component of ω along z′ (initial condition)"))))
    )
    rate_folder = N_("Angular velocity ω_b, body axes [rad/s]")
    hand_gizmos = ("omega", "L")  # ω and L set by dragging their tips (app.kit.rigid.hand)
    body_axis_length: ClassVar[float] = 1.15
    arrow_lengths = (1.45, 2.0)  # ω and L start nearly parallel (L = I ω): different lengths keep their labels apart

    @classmethod
    def model_from_params(cls, params: Sequence[float]) -> Model:
        return Model(inertia=(float(params[0]), float(params[1]), float(params[2])))

    @classmethod
    def params_from_model(cls, model: Model) -> tuple[float, ...]:
        return tuple(model.inertia)

    @classmethod
    def omega_body_from_rates(cls, angles: Vec3, rates: Sequence[float]) -> Vec3:
        return np.array([float(r) for r in rates])

    @classmethod
    def rates_from_state(cls, angles: Vec3, state: State) -> tuple[float, ...]:
        return tuple(float(w) for w in state.omega_body)

    # ------------------------------------------------------------------ drawing
    def build_shape(self, scene: Any, parent: str, model: Model) -> None:
        mesh = getattr(self.sim, "mesh", None)  # a body handed on by the Inertia scene ("Spin it")
        if mesh is not None:
            vertices, faces = mesh
            size = float(np.ptp(vertices, axis=0).max()) or 1.0
            scene.add_mesh_simple(f"{parent}/mesh", np.asarray(vertices) * (BODY_SIZE / size), faces,
                                  color=(150, 170, 210), flat_shading=True, cast_shadow=False, receive_shadow=False)
            return
        kind, dimensions = shape_of(model)
        if kind == "box":
            mesh = trimesh.creation.box(extents=dimensions)
            axis_of_face = np.argmax(np.abs(mesh.face_normals), axis=1)
            for k in range(3):
                scene.add_mesh_simple(f"{parent}/faces_{'xyz'[k]}", mesh.vertices, mesh.faces[axis_of_face == k],
                                      color=FACE_TINTS[k], flat_shading=True, opacity=0.92,
                                      cast_shadow=False, receive_shadow=False)
            return
        if kind == "ball":
            mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.5 * BODY_SIZE)
        else:
            mesh = trimesh.creation.cylinder(radius=0.5 * dimensions[0], height=dimensions[2], sections=64)
        for index, (vertices, faces) in enumerate(striped_parts(mesh.vertices, mesh.faces, 8)):
            scene.add_mesh_simple(f"{parent}/stripes_{index}", vertices, faces, color=STRIPES[index],
                                  flat_shading=kind == "cylinder", cast_shadow=False, receive_shadow=False)

    def shape_status(self, model: Model) -> str:
        tr = self.tr
        _ = tr.gettext
        if getattr(self.sim, "mesh", None) is not None:
            return _("Drawn as the mesh handed on from the Inertia scene, in its principal frame (scaled to fit).")
        kind, (a, b, c) = shape_of(model)
        if kind == "ball":
            return _("Drawn as a uniform **ball** (I1 = I2 = I3), painted in sectors so its spin shows.")
        if kind == "cylinder":
            return _("Drawn as the uniform **cylinder** about z′ with these moments: diameter : length "
                     "= {ratio} : 1.").format(ratio=tr.decimal(a / c, 2))
        smallest = min(a, b, c)
        return _("Drawn as the uniform **box** with these moments: edges along x′ y′ z′ "
                 "in the ratio {a} : {b} : {c}.").format(a=tr.decimal(a / smallest, 2), b=tr.decimal(b / smallest, 2),
                                                        c=tr.decimal(c / smallest, 2))

    def readout_extras(self, sim: RigidBodySimulation) -> str:
        R, omega = sim.state.R_space_body, sim.state.omega_body
        L = sim.momentum(R, omega)
        T = kinetic_energy(sim.model, omega)
        _ = self.tr.gettext
        lines = [_("conserved: E = T, L_s (fixed in space)"), f"|L| = {L:.5f} kg m²/s"]
        if T > 0.0:
            lines.append(f"|L|²/(2T) = {L * L / (2.0 * T):.4f} kg m²")
            lines.append(_("  (= I2, the middle moment, on the"))
            lines.append(_("   separatrix of the Dzhanibekov flip)"))
        return "\n".join(lines)
