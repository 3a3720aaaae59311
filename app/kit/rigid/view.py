"""The view of a rigid-body simulation (free body, heavy top) for one browser.

`RigidBodyView` draws a `RigidBodySimulation` with the kit's widgets (stage, body, line of
nodes, ω and L) and the kit's panel (transport, presets, Setup / Readout / Plots tabs), and
turns the browser's edits into calls on its room.  A scene subclasses it and fills in the
class attributes and hooks (the model of its parameters, the initial ω from its rate sliders,
its body's shape, its extras); see `app.kit.rigid.torque_free` and `app.scenes.heavy_top`.

Per frame (`frame`) the view sends only what changed: the body's pose, the line of nodes, the
ω arrow (L only when it moved), the scene's extras, at display resolution
(`app.kit.draw.widgets.POSE_QUANTUM`: what did not change at it is not sent); nothing at all while
paused.  Only for what is on screen: the sliders follow the motion (Setup tab) and the status
line at 2 Hz, the readout (Readout tab) at 10 Hz, the plots and the accuracy panel at 4 Hz
(Plots tab, live plots on).

The exact ghost (Display: "Exact ghost") is `app.kit.rigid.ghost.ExactGhost`; the texts (status,
readout, Lagrange tab, accuracy, legend) are pure functions of the simulation in
`app.kit.rigid.text`.  On the ω plot the exact solution's flips (ω along the intermediate axis
changing sign, a free body with three different moments) are vertical grey segments, at the
times `physics.poinsot.flip_times` gives.

Sliders follow the motion without feedback (`SceneView.quiet`).  A user's edit of an angle or rate
slider pauses the room and restarts the run (t = 0) from the sliders' values.  Bad input
never stops the motion: out-of-range values are refused and the slider goes back; moments
that are not a body (InertiaError) are refused with a message while the last valid body moves.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, ClassVar

import numpy as np
import viser
import viser.uplot

from app.kit.core.common import (
    GIMBAL_LOCK_DEG,
    L_COLOR,
    OMEGA_COLOR,
    SliderSpec,
    Throttle,
    Wrap,
    gimbal_note,
    wrap_deg,
)
from app.kit.core.presets import Preset
from app.kit.core.room import Room
from app.kit.draw.widgets import POSE_QUANTUM, Body, LineOfNodes, Stage, Vector, quantized
from app.kit.panel.binding import BOX_DIGITS
from app.kit.panel.gui import PresetsRow, Readout, Tabs, Transport, add_slider
from app.kit.panel.plots import LivePlots, PlotSpec
from app.kit.rigid.ghost import ExactGhost
from app.kit.rigid.hand import HandControls
from app.kit.rigid.lagrange_arrows import GeneralizedForceArrows
from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.rigid.text import (
    accuracy_text,
    integrator_hint,
    lagrange_text,
    legend_text,
    readout_text,
    status_text,
)
from app.kit.view import SceneView, nth
from app.viser_internals import set_wxyz
from physics._types import Vec3
from physics.dynamics import Model, State
from physics.euler import GimbalLockError, matrix_from_euler_zxz
from physics.inertia import InertiaError
from physics.lagrange import lagrange_terms
from physics.methods import applicable

__all__ = ["ANGLE_SPECS", "RigidBodyView", "tilt_matrix", "tilt_wxyz"]

SLIDER_PERIOD = 0.5  # [s] of wall time between slider syncs while playing (2 Hz: they show where the motion is;
# their numbers are read when paused, and a refresh writes them exactly)
READOUT_PERIOD = 0.1  # readout text (10 Hz), only while the Readout tab is shown
STATUS_PERIOD = 0.5  # status line (2 Hz: its t ticks on; the timeline below says the same once a second)
PLOT_PERIOD = 0.25  # plot pushes (4 Hz), only while the Plots tab is shown
ARROW_RANGE = (0.5, 2.6)  # [scene units] an arrow outside this at a restart is rescaled

FLIP_COLOR = "#888888"


def tilt_wxyz(phi: float, theta: float) -> tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) of the φ-θ frame Rz(φ) Rx(θ) (angles [rad]): its x axis
    is the line of nodes, its z axis the body's z′."""
    cp, sp = math.cos(0.5 * phi), math.sin(0.5 * phi)
    ct, st = math.cos(0.5 * theta), math.sin(0.5 * theta)
    return (cp * ct, cp * st, sp * st, sp * ct)


def tilt_matrix(phi: float, theta: float) -> np.ndarray:
    """Rz(φ) Rx(θ) (3, 3) (angles [rad]), the rotation of `tilt_wxyz`."""
    cp, sp, ct, st = math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta)
    return np.array([[cp, -sp * ct, sp * st], [sp, cp * ct, -cp * st], [0.0, st, ct]])


class FlipPlots(LivePlots):
    """`LivePlots` whose chart `flip_chart` has one more series: a grey line on 0 with a vertical
    segment (±max |value| of the window) at each time `flips(t_lo, t_hi)` returns."""

    def __init__(self, gui: Any, buffer: Any, specs: Sequence[PlotSpec], flip_chart: int,
                 flips: Callable[[float, float], np.ndarray]) -> None:
        self._flip_chart = -1  # plain charts while the base class builds them
        super().__init__(gui, buffer, specs)
        self._flip_chart = flip_chart
        self._flips = flips
        handle = self.handles[flip_chart]
        handle.series = (*handle.series, viser.uplot.Series(label="flip (exact)", stroke=FLIP_COLOR, width=1.5,
                                                            dash=(4.0, 3.0)))
        handle.data = self._data(self.specs[flip_chart])

    def _data(self, spec: PlotSpec, rows: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
        data = super()._data(spec, rows)
        if self._flip_chart < 0 or spec is not self.specs[self._flip_chart]:
            return data
        x = data[0]
        flips = self._flips(float(x[0]), float(x[-1])) if x.size > 1 else np.zeros(0)
        if flips.size == 0:
            return (*data, np.zeros_like(x))
        values = np.concatenate([np.abs(c[np.isfinite(c)]) for c in data[1:]] + [np.ones(1)])
        top = float(values.max())
        xs = np.concatenate([x, np.repeat(flips, 4)])
        order = np.argsort(xs, kind="stable")
        columns = [np.concatenate([c, np.repeat(np.interp(flips, x, c), 4)])[order] for c in data[1:]]
        marks = np.concatenate([np.zeros_like(x), np.tile([0.0, -top, top, 0.0], flips.size)])[order]
        return (xs[order], *columns, marks)


_FULL_MARKS = ((-180.0, "-180°"), (-90.0, "-90°"), (0.0, "0°"), (90.0, "90°"), (180.0, "180°"))
ANGLE_SPECS = (
    SliderSpec("phi", "φ [deg]", -180.0, 180.0, 1.0, "precession about the space z axis", _FULL_MARKS),
    SliderSpec("theta", "θ [deg]", 0.0, 180.0, 1.0, "nutation about the line of nodes",
               ((0.0, "0°"), (45.0, "45°"), (90.0, "90°"), (135.0, "135°"), (180.0, "180°"))),
    SliderSpec("psi", "ψ [deg]", -180.0, 180.0, 1.0, "spin about the body z′ axis", _FULL_MARKS),
)


class RigidBodyView(SceneView):
    """One browser's view of a room with a `RigidBodySimulation`.  Subclasses fill in:"""

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

    # ------------------------------------------------------------------ construction
    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: RigidBodySimulation = room.sim
        self.track_points(self.sim)
        self._drawn_version = -1
        self._drawn_restarts = -1
        self._drawn_model: Model | None = None
        self._drawn_preset: str | None = None
        self.omega_scale = 0.3  # [scene units per rad/s]
        self.L_scale = 0.3  # [scene units per kg m²/s]
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self._readout_throttle = Throttle(READOUT_PERIOD)
        self._status_throttle = Throttle(STATUS_PERIOD)
        self._plot_throttle = Throttle(PLOT_PERIOD)
        self.ghost: ExactGhost
        self._rates_shown: tuple[float, ...] | None = None
        self.build()

    def _build_scene(self) -> None:
        scene = self.client.scene
        root = self.root
        labels = self.labels
        Stage(scene, root, grid_z=self.grid_z, labels=labels)
        model = self.sim.model
        tilt = self.tilt_frame
        self._tilt_node = scene.add_frame(f"{root}/tilt", show_axes=False) if tilt else None
        self._tilt_wxyz: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)  # as sent
        parent = f"{root}/tilt" if tilt else root
        self.body = Body(scene, f"{parent}/b", lambda s, parent: self.build_shape(s, parent, model),
                         axis_length=self.body_axis_length, labels=labels)
        self._drawn_model = model
        self.nodes = LineOfNodes(scene, f"{parent}/nodes", labels=labels, riding=tilt)
        self.omega = Vector(scene, f"{parent}/w", OMEGA_COLOR, "ω", labels=labels,
                            label_at_middle=self.omega_label_at_middle)
        self.L = Vector(scene, f"{parent}/L", L_COLOR, "L", labels=labels)
        # The Lagrange tab: the torque M and its projections Q_φ e_z, Q_θ e_n, Q_ψ e_z′ (6.10).
        self.q_arrows = GeneralizedForceArrows(scene, root, labels)
        self.build_extras()

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        self.build_head(self.intro, integrators=applicable(self.sim.model), on_integrator=self.set_integrator,
                        integrator=self.sim.integrator, integrator_hint=integrator_hint(self.sim.model))
        self.tabs = Tabs(gui, wrap, ("Setup", "Readout", "Plots", "Lagrange", *self.extra_tabs),
                         on_change=lambda _name: self.refresh())
        with self.tabs.tab("Setup"):
            self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset, self.choose_own_preset)
            with gui.add_folder("Euler angles z-x-z [deg]"):
                self.gui_angles = [add_slider(gui, spec) for spec in ANGLE_SPECS]
                self.gui_gimbal_note = gui.add_markdown("", visible=False)
            with gui.add_folder(self.rate_folder):
                self.gui_rates = [add_slider(gui, spec) for spec in self.rate_specs]
            self.hand = HandControls(self, gui) if self.hand_gizmos else None
            with gui.add_folder(self.param_folder):
                params = self.params_from_model(self.sim.model)
                self.gui_params = [add_slider(gui, spec, value) for spec, value in zip(self.param_specs, params)]
                self.gui_param_status = gui.add_markdown(self.shape_status(self.sim.model))
            with gui.add_folder("Display", expand_by_default=False):
                self.gui_show_omega = gui.add_checkbox("ω arrow", True)
                self.gui_show_L = gui.add_checkbox("L arrow", True)
                self.gui_show_nodes = gui.add_checkbox("Line of nodes", True)
                self.gui_show_body_axes = gui.add_checkbox("Body axes x′ y′ z′", True)
                self.ghost = ExactGhost(gui, wrap, self.message, self.quiet, scene=self.client.scene, root=self.root,
                                        shape=self.build_shape, axis_length=self.body_axis_length, sim=self.sim,
                                        on_change=self.room.refresh, labels=self.labels)
                self.gui_ghost = self.ghost.gui_toggle  # a lesson step switches it by its label
                self.build_display_extras(gui)
                self.gui_reset_view = gui.add_button("Reset view", icon=viser.Icon.CAMERA)
                self.gui_legend = gui.add_markdown("")
        with self.tabs.tab("Readout"):
            self.readout = Readout(gui)
        with self.tabs.tab("Plots"):
            self.gui_live_plots = gui.add_checkbox("Live plots", True, hint="turn off to save CPU and bandwidth")
            self.accuracy = Readout(gui)
            specs = self.plot_specs()
            omega_chart = next(k for k, spec in enumerate(specs) if spec.columns[:1] == ("w1",))
            self.plots = FlipPlots(gui, self.sim.samples, specs, omega_chart,
                                   lambda t_lo, t_hi: self.sim.flips(t_lo, t_hi))

        with self.tabs.tab("Lagrange"):
            self.lagrange_readout = Readout(gui)
        self.build_tab_extras(gui)

        for index, (spec, handle) in enumerate(zip(ANGLE_SPECS, self.gui_angles)):
            self.bind(handle, f"{spec.label} slider", self._state_edit(handle, spec), self._angle_in_force(index),
                      spec=spec)
        for index, (spec, handle) in enumerate(zip(self.rate_specs, self.gui_rates)):
            self.bind(handle, f"{spec.label} slider", self._state_edit(handle, spec), self._rate_in_force(index),
                      spec=spec)
        for index, (spec, handle) in enumerate(zip(self.param_specs, self.gui_params)):
            self.bind(handle, f"{spec.label} slider", self._param_edit(index),
                      nth(lambda: self.params_from_model(self.sim.model), index), spec=spec)
        for handle in (self.gui_show_omega, self.gui_show_L, self.gui_show_nodes, self.gui_show_body_axes):
            handle.on_update(wrap("display toggle", lambda _event: self.refresh()))
        self.gui_reset_view.on_click(wrap("reset view", lambda _event: self.reset_view()))
        self.gui_live_plots.on_update(wrap("live plots", lambda _event: self.refresh()))
        self._gui_roots = [self.gui_intro, self.message.handle, *self.transport.handles, *self.tabs.handles]

    def plot_elements(self, tab: str) -> list[Any]:
        """Plots: the accuracy line and the charts (while `Live plots` is on); Lagrange: its table."""
        if tab == "Plots":
            return [self.accuracy.handle, *(self.plots.handles if self.gui_live_plots.value else ())]
        if tab == "Lagrange":
            return [self.lagrange_readout.handle]
        return []

    def plot_specs(self) -> list[PlotSpec]:
        return [
            PlotSpec("Energy [J]", ("E", "T", "V"), ("E = T + V", "T", "V"), ("black", "#e65a00", "#2a7ab9")),
            PlotSpec("Angular momentum [kg m²/s]", ("L_norm", "L_z"), ("|L|", "L_z"), ("#7828c8", "#2a9d8f")),
            PlotSpec("Euler angles z-x-z [deg]", ("phi", "theta", "psi"), ("φ", "θ", "ψ"),
                     ("#8c32d2", "#d70078", "#008c8c")),
            PlotSpec("ω, body components [rad/s]", ("w1", "w2", "w3"), ("ω_x′", "ω_y′", "ω_z′"),
                     ("#c00000", "#00802a", "#0030a0")),
            PlotSpec("Accuracy: log₁₀ of the errors", ("drift_E", "drift_L", "attitude_error"),
                     ("|ΔE|/E₀", f"|Δ{self.momentum_label}|/|L₀|", "attitude [rad]"),
                     ("#e65a00", "#7828c8", "black"), log=True),
        ]

    def frame(self, dt: float) -> None:
        """The per-frame update: poses and arrows if the state changed; throttled text."""
        sim = self.sim
        with self.client.atomic():
            if sim.version != self._drawn_version:
                if sim.restarts != self._drawn_restarts or sim.model != self._drawn_model:
                    self._restarted()
                self._drawn_version = sim.version
                self.quantum = POSE_QUANTUM if self.room.playing else None
                try:
                    self._draw()
                finally:
                    self.quantum = None
            self.labels.update(dt)
            if not self.room.playing:
                return
            if self._slider_throttle.ready(dt) and self.tabs.shown == "Setup":
                self._sync_state_sliders()
                self._refresh_gimbal_note()
            if self._status_throttle.ready(dt):
                self._refresh_status()
                self.ghost.refresh_note()
            if self._readout_throttle.ready(dt) and self.tabs.shown in ("Readout", "Lagrange"):
                self._refresh_readout()
            if self._plot_throttle.ready(dt) and self.tabs.shown == "Plots":
                self._push_plots()

    def refresh(self) -> None:
        """Everything at once (after an edit, a step, a restart; never per frame)."""
        sim = self.sim
        with self.client.atomic():
            if sim.restarts != self._drawn_restarts or sim.model != self._drawn_model:
                self._restarted()
            self._drawn_version = sim.version
            self.nodes.visible = bool(self.gui_show_nodes.value)
            self.body.show_axes(bool(self.gui_show_body_axes.value))
            self.omega.enabled = bool(self.gui_show_omega.value)
            self.L.enabled = bool(self.gui_show_L.value)
            self._draw()
            self._sync_state_sliders()
            self.show_values(self.gui_params, self.param_specs, self.params_from_model(sim.model))
            self.transport.show(self.room.playing, self.room.time_scale, sim.integrator)
            self._refresh_status()
            self.ghost.refresh_note()
            self._refresh_gimbal_note()
            if self.tabs.shown in ("Readout", "Lagrange"):
                self._refresh_readout()
            self.q_arrows.show(self.tabs.shown == "Lagrange")
            self.plots.set_visible(bool(self.gui_live_plots.value))
            if self.tabs.shown == "Plots":
                self._push_plots()
            if self.hand is not None:
                self.hand.refresh()
            self.labels.settle()

    # ------------------------------------------------------------------ drawing
    def _restarted(self) -> None:
        """A new run (or a new body) in the simulation: reshape, rescale, clear the history."""
        sim = self.sim
        if sim.model != self._drawn_model:
            model = sim.model
            self.body.reshape(lambda scene, parent: self.build_shape(scene, parent, model))
            self.gui_param_status.content = self.shape_status(model)
            self._drawn_model = model
            self.ghost.reshape(model)
        preset = getattr(sim, "preset", None)
        R, omega = sim.state.R_space_body, sim.state.omega_body
        if (preset is not None and preset != self._drawn_preset or not self._arrows_fit(R, omega)) \
                and not (self.hand is not None and self.hand.dragging):  # the scale holds during a drag
            self._rescale_arrows(R, omega)
        self._drawn_preset = preset
        self.presets_row.show_note(self.preset_shown())
        self._drawn_restarts = sim.restarts
        self.restart_extras()

    def _draw(self) -> None:
        """Poses and arrows of the current state: only what changed is sent."""
        sim = self.sim
        R = sim.state.R_space_body
        omega_body = sim.state.omega_body
        quantum = self.quantum
        phi, theta = float(sim.angles[0]), float(sim.angles[1])
        if self._tilt_node is not None:  # R = R_tilt R_spin: ω and L in the φ-θ frame's components
            R_tilt = tilt_matrix(phi, theta)
            wxyz = tilt_wxyz(phi, theta)
            if quantum is not None:
                wxyz = quantized(wxyz, quantum)  # type: ignore[assignment]
            if wxyz != self._tilt_wxyz:
                self._tilt_wxyz = wxyz
                set_wxyz(self._tilt_node, wxyz)
            R = R_tilt.T @ R  # R_spin: a turn about z′ (exactly, up to rounding)
        self.body.pose(R, quantum)
        self.nodes.update(phi, theta, quantum)
        self.omega.update(R @ omega_body * self.omega_scale, quantum=quantum)
        L_parent = R @ (np.asarray(sim.model.inertia) * omega_body)
        self.L.update(L_parent * self.L_scale, rtol=1e-6, quantum=quantum)
        self.ghost.draw(quantum)
        self.draw_extras(sim)

    def fit_arrows(self) -> None:
        """Rescale the arrows if the current ω or L is outside ARROW_RANGE (after a drag)."""
        R, omega = self.sim.state.R_space_body, self.sim.state.omega_body
        if not self._arrows_fit(R, omega):
            self._rescale_arrows(R, omega)

    def _arrows_fit(self, R: np.ndarray, omega_body: Vec3) -> bool:
        lo, hi = ARROW_RANGE
        fixed = self.fixed_omega_scale()
        if fixed is not None and fixed != self.omega_scale:
            return False
        w = 0.0 if fixed is not None else float(np.linalg.norm(omega_body)) * self.omega_scale
        L = float(np.linalg.norm(np.asarray(self.sim.model.inertia) * omega_body)) * self.L_scale
        return (w == 0.0 or lo <= w <= hi) and (L == 0.0 or lo <= L <= hi)

    def _rescale_arrows(self, R: np.ndarray, omega_body: Vec3) -> None:
        w = float(np.linalg.norm(omega_body))
        L = float(np.linalg.norm(np.asarray(self.sim.model.inertia) * omega_body))
        self.omega_scale = self.arrow_lengths[0] / w if w > 0.0 else self.omega_scale
        fixed = self.fixed_omega_scale()
        if fixed is not None:
            self.omega_scale = fixed
        self.L_scale = self.arrow_lengths[1] / L if L > 0.0 else self.L_scale
        self.gui_legend.content = legend_text(bool(self.sim.model.mgl), self.omega_scale, self.L_scale)

    # ------------------------------------------------------------------ sliders
    def displayed_angles_deg(self) -> tuple[float, float, float]:
        phi, theta, psi = np.degrees(self.sim.angles)
        return wrap_deg(float(phi)), float(theta), wrap_deg(float(psi))

    def _sync_state_sliders(self, skip: Any = None) -> None:
        self.show_values(self.gui_angles, ANGLE_SPECS, self.displayed_angles_deg(), skip)
        try:
            rates = self.rates_from_state(self.sim.angles, self.sim.state)
        except GimbalLockError:
            return  # Euler rates are undefined at the pole: the rate sliders keep their values
        self._rates_shown = tuple(float(r) for r in rates)
        self.show_values(self.gui_rates, self.rate_specs, rates, skip)

    def _angle_in_force(self, index: int) -> Callable[[], float]:
        return lambda: round(self.displayed_angles_deg()[index], BOX_DIGITS)

    def _rate_in_force(self, index: int) -> Callable[[], float]:
        def current() -> float:
            try:
                return round(float(self.rates_from_state(self.sim.angles, self.sim.state)[index]), BOX_DIGITS)
            except GimbalLockError:  # undefined at the pole: the slider's last value stands
                return float(self.rate_specs[index].rounded(0.0)) if self._rates_shown is None \
                    else self._rates_shown[index]

        return current

    def _state_edit(self, handle: Any, spec: SliderSpec) -> Callable[[float], None]:
        """An angle or rate slider: the user sets the initial state (pausing the room)."""

        def apply(value: float) -> None:
            self.room.playing = False
            angles_deg = [value if h is handle else float(h.value) for h in self.gui_angles]
            rates = [value if h is handle else float(h.value) for h in self.gui_rates]
            angles = np.radians(angles_deg)
            state = State(matrix_from_euler_zxz(*angles), self.omega_body_from_rates(angles, rates), 0.0)
            self.sim.preset = None
            self.sim.restart(state, angles=angles)
            self._sync_state_sliders(skip=handle)  # the others show the state it starts from
            self.room.refresh()

        return apply

    def _param_edit(self, index: int) -> Callable[[float], str | None]:
        def apply(value: float) -> str | None:
            current = self.params_from_model(self.sim.model)
            candidate = tuple(value if k == index else float(h.value) for k, h in enumerate(self.gui_params))
            try:
                model = self.model_from_params(candidate)
            except (InertiaError, ValueError) as error:
                shown = ", ".join(f"{p:g}" for p in current)
                self.gui_param_status.content = (
                    f"**⚠ Refused:** {error}.  Each moment must be at most the sum of the other two "
                    f"(I1 + I2 ≥ I3 and cyclic) and positive.  Simulating the last valid body ({shown})."
                )
                return f"Not a rigid body: {error}. Refused; the last valid body ({shown}) keeps moving."
            self.sim.mesh = None  # new moments: a handed-on mesh no longer fits
            self.sim.set_model(model)  # same R and ω_b, new body; keeps playing
            self.room.refresh()
            return None

        return apply

    # ------------------------------------------------------------------ actions
    def set_integrator(self, name: str) -> None:
        message = self.sim.set_integrator(name)
        if message is not None:
            self.message.show(message)
        self.room.refresh()

    # ------------------------------------------------------------------ text
    def _refresh_status(self) -> None:
        self.transport.set_status(status_text(self.sim, self.room.playing, self.room.time_scale))

    def _refresh_gimbal_note(self) -> None:
        note = gimbal_note(math.degrees(float(self.sim.angles[1])))
        if self.gui_gimbal_note.visible != (note is not None):
            self.gui_gimbal_note.visible = note is not None
        if note is not None and self.gui_gimbal_note.content != note:
            self.gui_gimbal_note.content = note

    def _push_plots(self) -> None:
        if self.gui_live_plots.value:
            self.plots.push()
        self.accuracy.set(accuracy_text(self.sim, self.momentum_label))

    def _refresh_readout(self) -> None:
        sim = self.sim
        if self.tabs.shown == "Lagrange":
            gimbal = math.sin(math.radians(GIMBAL_LOCK_DEG))
            try:
                terms = lagrange_terms(sim.model, sim.t, sim.state.R_space_body, sim.state.omega_body, sim.angles,
                                       min_sin_theta=gimbal)
            except GimbalLockError:
                terms = None
            self.q_arrows.draw(sim.model.torque_space_at(sim.t, sim.state.R_space_body, sim.state.omega_body), terms)
            self.lagrange_readout.set(lagrange_text(sim, terms))
            return
        self.readout.set(readout_text(sim, self.displayed_angles_deg(), self.readout_extras(sim)))
        self._refresh_gimbal_note()
