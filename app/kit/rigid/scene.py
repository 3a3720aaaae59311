"""`RigidBodyScene`: what a rigid-body scene declares (its class attributes and hooks: the
model of its parameters, the initial ω from its rate sliders, its body's shape, its extras) and
its simulation from a preset.  The base of `app.kit.rigid.panel.RigidBodyPanel` and
`app.kit.rigid.view.RigidBodyView`, which a scene subclasses; no drawing, no panel here.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from app.kit.core.common import wrap_deg
from app.kit.core.presets import Preset
from app.kit.core.room import Room
from app.kit.panel.gui import Tabs, Transport
from app.kit.rigid.hand import HandControls
from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.view import SceneView
from physics._types import Vec3
from physics.dynamics import Model, State
from physics.euler import GimbalLockError, matrix_from_euler_zxz

__all__ = ["RigidBodyScene"]


class RigidBodyScene(SceneView):
    """A rigid-body scene's declarations and its simulation from presets.  Subclasses fill in:"""

    sim: RigidBodySimulation  # the room's (set by the view)
    transport: Transport  # built by build_head

    intro: ClassVar[str] = ""
    tabs: Tabs
    param_folder: ClassVar[str] = "Body"
    rate_folder: ClassVar[str] = "Angular velocity"
    momentum_kind: ClassVar[str] = "norm"  # "norm": |L| is conserved; "z": L_z
    momentum_label: ClassVar[str] = "|L|"
    grid_z: ClassVar[float] = 0.0
    body_axis_length: ClassVar[float] = 1.0
    arrow_lengths: ClassVar[tuple[float, float]] = (1.5, 1.5)  # ω and L [scene units] at a rescale
    omega_label_at_middle: ClassVar[bool] = False  # ω's label beside its middle (else beyond its tip)
    tilt_frame: ClassVar[bool] = False
    """True: the body hangs from the φ-θ frame `{root}/tilt` (turned by Rz(φ) Rx(θ), its x axis
    the line of nodes, its z axis the body's z′) as its ψ child (`{root}/tilt/b`, turned by
    Rz(ψ)), and the line of nodes, ω and L hang from the φ-θ frame too (their components in it).
    A symmetric top then sends per frame the φ-θ frame and a spin about z′; ω and L only when
    the nutation changes them (in steady precession: never).  False: the body, nodes, ω and L
    are children of the root, posed in space."""
    quantum: float | None = None
    """While a playing frame draws: POSE_QUANTUM (poses at display resolution, `app.kit.draw.widgets`);
    None while a refresh draws (exact)."""

    def fixed_omega_scale(self) -> float | None:
        """[scene units per rad/s] if the scene fixes the ω arrow's scale (Poinsot: ω must end on
        the ellipsoid drawn at that scale); None: rescaled to `arrow_lengths` at a new run."""
        return None

    # ------------------------------------------------------------------ scene hooks
    @classmethod
    def model_from_params(cls, params: Sequence[float]) -> Model:
        """The model of these parameter values; InertiaError / ValueError if they are not one."""
        raise NotImplementedError

    @classmethod
    def params_from_model(cls, model: Model) -> tuple[float, ...]:
        """The parameter sliders' values of a model."""
        raise NotImplementedError

    @classmethod
    def omega_body_from_rates(cls, angles: Vec3, rates: Sequence[float]) -> Vec3:
        """ω_b [rad/s] from the rate sliders' values at angles (φ, θ, ψ) [rad]."""
        raise NotImplementedError

    @classmethod
    def rates_from_state(cls, angles: Vec3, state: State) -> tuple[float, ...]:
        """The rate sliders' values of `state` (GimbalLockError where undefined)."""
        raise NotImplementedError

    def build_shape(self, scene: Any, parent: str, model: Model) -> None:
        """Add the body's shape nodes under `parent` (a frame turned by R_space_body)."""

    def shape_status(self, model: Model) -> str:
        """One line describing the body drawn for this model."""
        return ""

    def build_extras(self) -> None:
        """Add scene-specific nodes (once, after the common ones)."""

    hand_gizmos: ClassVar[tuple[str, ...]] = ()
    """"omega" and/or "L": the scene sets ω by hand (gizmos at those arrows' tips, and Kick:
    `app.kit.rigid.hand`); () for neither."""
    hand: HandControls | None = None

    def gizmo_handles(self) -> list[Any]:
        """The ω (and L) drag gizmos (`app.kit.rigid.hand`)."""
        return [] if self.hand is None else list(self.hand.gizmos.values())

    extra_tabs: ClassVar[tuple[str, ...]] = ()
    """The scene's own panel tabs after Setup / Readout / Plots / Lagrange (filled by `build_tab_extras`)."""

    def build_tab_extras(self, gui: Any) -> None:
        """Fill the scene's own tabs (`with self.tabs.tab(name):`); `refresh` and `draw_extras`
        draw them (`self.tabs.shown` says which tab is on screen)."""

    def build_display_extras(self, gui: Any) -> None:
        """Add scene-specific toggles to the Display folder."""

    def draw_extras(self, sim: RigidBodySimulation) -> None:
        """Per-frame updates of the extras (e.g. the top's trace)."""

    def restart_extras(self) -> None:
        """Redraw what depends on the run (a new run or a new body)."""

    @classmethod
    def track_points(cls, sim: RigidBodySimulation) -> None:
        """Ask the simulation to follow the points whose paths the scene draws
        (`RigidBodySimulation.track`; the traces live in the simulation, so a view built later
        and a fork have them).  Called for every new simulation and every view; none by default."""

    def readout_extras(self, sim: RigidBodySimulation) -> str:
        """Extra monospace lines for the readout (e.g. conserved quantities)."""
        return ""

    # ------------------------------------------------------------------ the scene's simulation
    @classmethod
    def check_preset(cls, preset: Preset) -> None:
        cls.initial_conditions(preset)

    @classmethod
    def initial_conditions(cls, preset: Preset) -> tuple[Model, State, np.ndarray]:
        """(model, state at t = 0, angles [rad]) of a preset (InertiaError, ValueError)."""
        model = cls.model_from_params(preset.params)
        angles = np.radians(preset.angles_deg)
        state = State(matrix_from_euler_zxz(*angles), cls.omega_body_from_rates(angles, preset.rates), 0.0)
        return model, state, angles

    @classmethod
    def moment_preset(cls, room: Room, name: str) -> Preset:
        """The room's moment as a preset: the model's parameters, the angles shown and the rate
        sliders' values of the state now (ValueError at gimbal lock, where the rates are undefined)."""
        sim: RigidBodySimulation = room.sim
        angles = np.array(sim.angles, dtype=float)
        try:
            rates = cls.rates_from_state(angles, sim.state)
        except GimbalLockError as error:
            raise ValueError(f"at gimbal lock the rates are undefined ({error}): step on a little") from None
        phi, theta, psi = (float(a) for a in np.degrees(angles))
        angles_deg = (wrap_deg(phi), min(max(theta, 0.0), 180.0), wrap_deg(psi))
        note = f"Saved at t = {sim.t:.2f} s" + (f" of {sim.preset}" if sim.preset else "") + "."
        return Preset(name, "Mine", note, tuple(float(v) for v in cls.params_from_model(sim.model)),
                      angles_deg, tuple(float(r) for r in rates))

    @classmethod
    def simulation_from_preset(cls, preset: Preset) -> RigidBodySimulation:
        model, state, angles = cls.initial_conditions(preset)
        sim = RigidBodySimulation(model, state, angles=angles, momentum_kind=cls.momentum_kind)
        cls.track_points(sim)
        return sim

    @classmethod
    def start_preset(cls, sim: RigidBodySimulation, preset: Preset) -> None:
        model, state, angles = cls.initial_conditions(preset)
        sim.model = model
        sim.mesh = None  # a body handed on ("Spin it") gives way to the preset
        sim.restart(state, angles=angles)
