"""What the animated rigid-body scenes (free body, heavy top) share: a simulation per client.

A `SimulationScene` owns a `physics.dynamics.Model` and `State`, advances it in `tick` with
the chosen integrator (`physics.integrators.step_realtime` by default, or the closed form of
`physics.methods.exact_solution`), and draws it.  Per displayed frame it only updates a few
small properties inside one `client.atomic()`: the body pose, the line of nodes' frame, the ω
(and L) arrows and their labels (and a scene's extras, e.g. the top's trace head).  Anything
else is throttled by the wall-clock dt of the ticks: the φ θ ψ and rate sliders follow the
motion at 10 Hz, the readouts at 5 Hz, plot samples at 10 Hz and plot pushes at 4 Hz.

Sliders follow the motion without feedback: the sync sets `_syncing`, and the sliders'
`on_update` (which viser runs synchronously, with `event.client` None, when the server assigns
a value) ignores updates while it is set.  A user's edit of an angle or rate slider pauses the
motion and restarts it (t = 0) from the sliders' values: they are the initial conditions.

Bad input never stops the motion: values out of range are refused and the slider goes back;
moments that are not a body (`physics.inertia.InertiaError`) are refused with a message while
the last valid body keeps moving.  A physics failure (`IntegrationError`) pauses and says so.

Conventions as in `physics`: z-x-z Euler angles (degrees on sliders, radians inside), ω_s and
ω_b with hat(ω_s) = Ṙ Rᵀ and hat(ω_b) = Rᵀ Ṙ, L_s = R I ω_b, SI units.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import viser

from app.common import (
    BODY_AXIS_COLORS,
    GIMBAL_FADE_DEG,
    L_COLOR,
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
    fade_color,
    format_matrix,
    gimbal_note,
    wrap_deg,
    wxyz_from_matrix,
)
from app.controls import INTEGRATOR_EXACT, INTEGRATOR_REALTIME, STEP_DT, PlaybackControls
from app.plots import LivePlots, PlotSpec, SampleBuffer
from physics._types import Vec3
from physics.dynamics import IntegrationError, Model, State, angular_momentum_space, energy
from physics.euler import (
    GimbalLockError,
    euler_zxz_from_matrix,
    euler_zxz_from_matrix_near,
    matrix_from_euler_zxz,
)
from physics.inertia import InertiaError
from physics.integrators import step_realtime
from physics.lagrange import generalized_forces
from physics.methods import exact_solution
from physics.so3 import log_so3

__all__ = [
    "ANGLE_SPECS",
    "PHYSICS_LOCK",
    "Preset",
    "SimulationScene",
    "SliderSpec",
]

def kinetic_energy(model: Model, omega_body: Vec3) -> float:
    """T = ½ Σ I_k ω_bk² [J] (memo 6.4); `energy` minus the potential."""
    return 0.5 * float(np.dot(model.inertia, np.asarray(omega_body) ** 2))


PHYSICS_LOCK = threading.Lock()
"""Serialises `step_realtime` calls: it caches its last state per model, not per thread, and
the Step button runs on viser's thread pool while the loop ticks other sessions."""

SLIDER_PERIOD = 0.1  # [s] wall time between slider syncs while playing (10 Hz)
READOUT_PERIOD = 0.2  # readouts and status line (5 Hz)
SAMPLE_PERIOD = 0.1  # plot samples (10 Hz)
PLOT_PERIOD = 0.25  # plot pushes to the browser (4 Hz)
PLOT_CAPACITY = 300  # samples in the sliding window (30 s of wall time at 10 Hz)

ARROW_RANGE = (0.5, 2.6)  # [scene units] an arrow outside this at a restart is rescaled ...
NODES_HALF_LENGTH = 1.9
SPACE_AXIS_LENGTH = 2.0
LABEL_SCALE = 2.0  # font_screen_scale of the 3D labels (projector)
FADE_LEVELS = 8  # the line of nodes fades in this many steps (a colour message per step)


@dataclass(frozen=True)
class SliderSpec:
    """A slider: key, label (with unit), range, step, hint, marks ((value, text), ...)."""

    key: str
    label: str
    lo: float
    hi: float
    step: float
    hint: str = ""
    marks: tuple[tuple[float, str], ...] = ()

    def rounded(self, value: float) -> float:
        """`value` clamped to the range and rounded to the step (what the slider can show)."""
        value = min(max(value, self.lo), self.hi)
        decimals = max(0, -math.floor(math.log10(self.step)) + 1)
        return round(round(value / self.step) * self.step, decimals)


_FULL_MARKS = ((-180.0, "-180°"), (-90.0, "-90°"), (0.0, "0°"), (90.0, "90°"), (180.0, "180°"))
ANGLE_SPECS = (
    SliderSpec("phi", "φ [deg]", -180.0, 180.0, 1.0, "precession about the space z axis", _FULL_MARKS),
    SliderSpec("theta", "θ [deg]", 0.0, 180.0, 1.0, "nutation about the line of nodes",
               ((0.0, "0°"), (45.0, "45°"), (90.0, "90°"), (135.0, "135°"), (180.0, "180°"))),
    SliderSpec("psi", "ψ [deg]", -180.0, 180.0, 1.0, "spin about the body z′ axis", _FULL_MARKS),
)


@dataclass(frozen=True)
class Preset:
    """A named initial condition: parameters (in `param_specs` order), z-x-z angles [deg],
    rates (in `rate_specs` order, their units) and a note on what to watch."""

    name: str
    params: tuple[float, ...]
    angles_deg: tuple[float, float, float]
    rates: tuple[float, ...]
    note: str


class SimulationScene:
    """One client's simulated rigid body.  Subclasses fill in the class attributes and hooks.

    Public state: model, state (t = simulated time since the last restart), initial_state,
    playing, time_scale, integrator, angles (continuous z-x-z angles [rad] of the state, φ and ψ
    unwrapped), restarts (count), substeps (sub-steps of the last real-time step).
    """

    # ---- filled in by subclasses
    title = ""
    root = "/sim"
    view = CameraView((4.5, -3.6, 2.4), (0.0, 0.0, 0.0))
    intro = ""
    presets: tuple[Preset, ...] = ()
    preset_groups: tuple[tuple[str, tuple[str, ...]], ...] = ()  # (group label, preset names)
    param_specs: tuple[SliderSpec, ...] = ()
    param_folder = "Body"
    rate_specs: tuple[SliderSpec, ...] = ()
    rate_folder = "Angular velocity"
    momentum_label = "|L|"  # the conserved momentum shown in the accuracy panel
    grid_z = 0.0
    body_axis_length = 1.0
    arrow_lengths = (1.5, 1.5)  # [scene units] ω and L at a rescale (the preset's start)

    def model_from_params(self, params: Sequence[float]) -> Model:
        """The model of these parameter values; InertiaError / ValueError if they are not one."""
        raise NotImplementedError

    def omega_body_from_rates(self, angles: Vec3, rates: Sequence[float]) -> Vec3:
        """ω_b [rad/s] from the rate sliders' values at angles (φ, θ, ψ) [rad]."""
        raise NotImplementedError

    def rates_from_state(self, angles: Vec3, state: State) -> tuple[float, ...]:
        """The rate sliders' values of `state` (GimbalLockError where undefined)."""
        raise NotImplementedError

    def momentum(self, R: np.ndarray, omega_body: Vec3) -> float:
        """The conserved momentum the accuracy panel follows (default |L|)."""
        return float(np.linalg.norm(angular_momentum_space(self.model, R, omega_body)))

    def build_body(self, parent: str) -> None:
        """Add the body's shape nodes under `parent` (a frame turned by R_space_body)."""

    def build_extras(self) -> None:
        """Add scene-specific nodes (called once, after the common ones)."""

    def render_extras(self, R: np.ndarray, omega_space: Vec3, L_space: Vec3) -> None:
        """Per-frame updates of the extras (inside the frame's atomic block)."""

    def restart_extras(self) -> None:
        """Clear what depends on the history (e.g. a trace) at a restart."""

    def readout_extras(self, state: State) -> str:
        """Extra monospace lines for the readout (e.g. conserved quantities)."""
        return ""

    def shape_status(self) -> str:
        """One line describing the body drawn for the current parameters."""
        return ""

    def build_display_extras(self, gui: Any) -> None:
        """Add scene-specific toggles to the Display folder."""

    # ------------------------------------------------------------------ construction
    def __init__(self, client: viser.ClientHandle, guard: Guard) -> None:
        self.client = client
        self._guard = guard
        self.playing = False
        self.time_scale = 1.0
        self.integrator = INTEGRATOR_REALTIME
        self.restarts = 0
        self.substeps = 0
        self._syncing = False
        self._presets = {preset.name: preset for preset in self.presets}
        first = self.presets[0]
        self.params: tuple[float, ...] = tuple(first.params)
        self.model = self.model_from_params(self.params)
        self.state = State(np.eye(3), np.zeros(3), 0.0)
        self.initial_state = self.state
        self.angles = np.zeros(3)
        self.omega_scale = 0.3  # [scene units per rad/s]
        self.L_scale = 0.3  # [scene units per kg m²/s]
        self._exact: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None
        self._exact_failed: str | None = None
        self._initial_angles: np.ndarray | None = None
        self._fade_level = -1
        self._drawn_L = np.full(3, np.nan)  # L_s as last drawn (a free body's L is redrawn only if it moves)
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self._readout_throttle = Throttle(READOUT_PERIOD)
        self._sample_throttle = Throttle(SAMPLE_PERIOD)
        self._plot_throttle = Throttle(PLOT_PERIOD)
        self.samples = SampleBuffer(
            ("E", "T", "V", "L_norm", "L_z", "phi", "theta", "psi", "w1", "w2", "w3",
             "drift_E", "drift_L", "attitude_error"), PLOT_CAPACITY)
        self._max_drift = {"drift_E": 0.0, "drift_L": 0.0, "attitude_error": 0.0}
        with client.atomic():
            self._build_common_scene()
            self.build_extras()
            self._build_gui()
        self.apply_preset(first.name)
        apply_camera(client, self.view)

    def _build_common_scene(self) -> None:
        scene = self.client.scene
        root = self.root
        self._root_node = scene.add_frame(root, show_axes=False)
        scene.add_grid(
            f"{root}/grid", width=5.0, height=5.0, plane="xy", cell_size=0.5, section_size=1.0,
            cell_color=(225, 225, 225), section_color=(190, 190, 190), shadow_opacity=0.0,
            position=(0.0, 0.0, self.grid_z),
        )
        scene.add_arrows(
            f"{root}/space_axes", axis_segments(np.eye(3), SPACE_AXIS_LENGTH), np.array(SPACE_AXIS_COLORS),
            shaft_radius=0.014, head_radius=0.045, head_length=0.11,
        )
        for k, name in enumerate("xyz"):
            scene.add_label(f"{root}/space_labels/{name}", name,
                            position=tuple((SPACE_AXIS_LENGTH + 0.14) * np.eye(3)[k]),
                            font_screen_scale=LABEL_SCALE, anchor="center-center")
        self.body_node = scene.add_frame(f"{root}/body", show_axes=False)
        self._shape_name = f"{root}/body/shape"
        self._shape_node = scene.add_frame(self._shape_name, show_axes=False)
        self.build_body(self._shape_name)
        length = self.body_axis_length
        self.body_axes = scene.add_arrows(
            f"{root}/body/axes", axis_segments(np.eye(3), length), np.array(BODY_AXIS_COLORS),
            shaft_radius=0.022, head_radius=0.06, head_length=0.13,
        )
        for k, name in enumerate(("x′", "y′", "z′")):
            scene.add_label(f"{root}/body/labels/{k}", name, position=tuple((length + 0.15) * np.eye(3)[k]),
                            font_screen_scale=LABEL_SCALE, anchor="center-center")
        # Line of nodes: a frame turned by Rz(φ); the line lies along its x axis.
        self.nodes_node = scene.add_frame(f"{root}/nodes", show_axes=False)
        self.nodes_line = scene.add_line_segments(
            f"{root}/nodes/line", np.array([[[-NODES_HALF_LENGTH, 0.0, 0.0], [NODES_HALF_LENGTH, 0.0, 0.0]]]),
            NODES_COLOR, thickness=6.0, thickness_units="screen",
        )
        self.nodes_label = scene.add_label(
            f"{root}/nodes/label", "line of nodes", position=(0.8 * NODES_HALF_LENGTH, 0.0, 0.04),
            font_screen_scale=1.6, anchor="bottom-center",  # inside the line: clear of the axis labels
        )
        self.omega_arrow = scene.add_arrows(
            f"{root}/omega", np.zeros((1, 2, 3)), OMEGA_COLOR, shaft_radius=0.03, head_radius=0.08,
            head_length=0.16,
        )
        self.omega_label = scene.add_label(f"{root}/omega_label", "ω", font_screen_scale=2.4,
                                           anchor="center-center")
        self.L_arrow = scene.add_arrows(
            f"{root}/L", np.zeros((1, 2, 3)), L_COLOR, shaft_radius=0.03, head_radius=0.08, head_length=0.16,
        )
        self.L_label = scene.add_label(f"{root}/L_label", "L", font_screen_scale=2.4, anchor="center-center")

    def _build_gui(self) -> None:
        gui = self.client.gui
        guard = self._guard
        self.gui_intro = gui.add_markdown(self.intro)
        self.controls = PlaybackControls(
            gui, guard, on_toggle=self.toggle, on_step=self.step, on_reset=self.reset,
            on_time_scale=self._set_time_scale, integrators=(INTEGRATOR_REALTIME, INTEGRATOR_EXACT),
            on_integrator=self.set_integrator,
        )
        self.gui_tabs = gui.add_tab_group()
        with self.gui_tabs.add_tab("Setup", icon=viser.Icon.ADJUSTMENTS):
            self.gui_presets = []
            for label, names in self.preset_groups:
                group = gui.add_button_group(label, names)
                group.on_click(guard(f"{label} presets", self._preset_callback(group)))
                self.gui_presets.append(group)
            self.gui_preset_note = gui.add_markdown("")
            with gui.add_folder("Euler angles z-x-z [deg]"):
                self.gui_angles = [self._add_slider(gui, spec) for spec in ANGLE_SPECS]
                self.gui_gimbal_note = gui.add_markdown("", visible=False)
            with gui.add_folder(self.rate_folder):
                self.gui_rates = [self._add_slider(gui, spec) for spec in self.rate_specs]
            with gui.add_folder(self.param_folder):
                self.gui_params = [self._add_slider(gui, spec) for spec in self.param_specs]
                self.gui_param_status = gui.add_markdown("")
            with gui.add_folder("Display", expand_by_default=False):
                self.gui_show_omega = gui.add_checkbox("ω arrow", True)
                self.gui_show_L = gui.add_checkbox("L arrow", True)
                self.gui_show_nodes = gui.add_checkbox("Line of nodes", True)
                self.gui_show_body_axes = gui.add_checkbox("Body axes x′ y′ z′", True)
                self.build_display_extras(gui)
                self.gui_reset_view = gui.add_button("Reset view", icon=viser.Icon.CAMERA)
                self.gui_legend = gui.add_markdown("")
        with self.gui_tabs.add_tab("Readout", icon=viser.Icon.TABLE):
            self.gui_readout = gui.add_markdown("")
        with self.gui_tabs.add_tab("Plots", icon=viser.Icon.CHART_LINE):
            self.gui_live_plots = gui.add_checkbox("Live plots", True, hint="turn off to save CPU and bandwidth")
            self.gui_accuracy = gui.add_markdown("")
            self.plots = LivePlots(gui, self.samples, self.plot_specs())

        for index, handle in enumerate(self.gui_angles):
            handle.on_update(guard(f"{ANGLE_SPECS[index].label} slider",
                                   self._state_slider_callback(handle, ANGLE_SPECS[index])))
        for index, handle in enumerate(self.gui_rates):
            handle.on_update(guard(f"{self.rate_specs[index].label} slider",
                                   self._state_slider_callback(handle, self.rate_specs[index])))
        for index, handle in enumerate(self.gui_params):
            handle.on_update(guard(f"{self.param_specs[index].label} slider", self._param_callback(index, handle)))
        for handle in (self.gui_show_omega, self.gui_show_L, self.gui_show_nodes, self.gui_show_body_axes):
            handle.on_update(guard("display toggle", lambda _event: self.render_all()))
        self.gui_reset_view.on_click(guard("reset view", lambda _event: self.reset_view()))
        self.gui_live_plots.on_update(guard("live plots", lambda _event: self._live_plots_toggled()))
        self._gui_roots = [self.gui_intro, *self.controls.handles, self.gui_tabs]

    def _add_slider(self, gui: Any, spec: SliderSpec) -> Any:
        return gui.add_slider(spec.label, spec.lo, spec.hi, spec.step, spec.rounded(0.0),
                              marks=spec.marks or None, hint=spec.hint or None)

    def plot_specs(self) -> list[PlotSpec]:
        """The charts (subclasses may change the first two)."""
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

    # ------------------------------------------------------------------ public actions
    def play(self) -> None:
        """Start the motion (the loop's ticks advance it)."""
        self.playing = True
        self.controls.show_playing(True)
        self._refresh_status()

    def pause(self) -> None:
        """Stop the motion where it is; sliders, readouts and plots show that state."""
        self.playing = False
        self.controls.show_playing(False)
        self.render_all()

    def toggle(self) -> None:
        self.pause() if self.playing else self.play()

    def step(self) -> None:
        """Pause, and advance one display frame (STEP_DT times the time scale)."""
        if self.playing:
            self.pause()
        if self._advance(STEP_DT * self.time_scale):
            self._take_sample()
        self.render_all()

    def reset(self) -> None:
        """Pause and go back to the initial state of this run (t = 0)."""
        self.playing = False
        self.controls.show_playing(False)
        angles = euler_zxz_from_matrix(self.initial_state.R_space_body)
        self.restart(self.initial_state, angles=self._initial_angles if self._initial_angles is not None else angles)

    def apply_preset(self, name: str) -> None:
        """Load a preset's parameters and initial state (keeps playing if it was)."""
        preset = self._presets.get(name)
        if preset is None:
            self.controls.show_message(f"No preset named {name!r}.")
            return
        model = self.model_from_params(preset.params)
        self.params = tuple(preset.params)
        self.model = model
        self._sync(self.gui_params, self.param_specs, self.params)
        self._reshape_body()
        angles = np.radians(preset.angles_deg)
        omega_body = self.omega_body_from_rates(angles, preset.rates)
        self.controls.clear_message()
        self.gui_preset_note.content = f"**{preset.name}.** {preset.note}"
        self.restart(State(matrix_from_euler_zxz(*angles), omega_body, 0.0), angles=angles, rescale=True)

    def set_integrator(self, name: str) -> None:
        """'splitting4 (real time)' or 'exact' (the closed form, where the model has one)."""
        if name == INTEGRATOR_EXACT and self._exact_solution() is None:
            self.controls.show_message(f"No closed form here ({self._exact_failed}); using {INTEGRATOR_REALTIME}.")
            name = INTEGRATOR_REALTIME
        self.integrator = name
        if self.controls.gui_integrator is not None and self.controls.gui_integrator.value != name:
            self.controls.gui_integrator.value = name
        self.render_all()

    def reset_view(self) -> None:
        apply_camera(self.client, self.view)

    def remove(self) -> None:
        """Remove this scene's GUI and scene nodes from the client."""
        self.playing = False
        for handle in self._gui_roots:
            handle.remove()
        self._root_node.remove()

    # ------------------------------------------------------------------ simulation
    def restart(self, state: State, *, angles: Vec3 | None = None, rescale: bool = False) -> None:
        """Start a new run from `state` at t = 0: drift references, exact solution, plots and
        trace start afresh.  angles: the z-x-z angles [rad] to show for it (e.g. the sliders'
        values at gimbal lock, where the matrix alone does not fix φ and ψ)."""
        state = State(np.array(state.R_space_body, dtype=float), np.array(state.omega_body, dtype=float), 0.0)
        self.initial_state = self.state = state
        self._initial_angles = None if angles is None else np.array(angles, dtype=float)
        self.angles = (np.array(angles, dtype=float) if angles is not None
                       else euler_zxz_from_matrix(state.R_space_body))
        self._exact = None
        self._exact_failed = None
        self.restarts += 1
        R, omega = state.R_space_body, state.omega_body
        self._T0 = kinetic_energy(self.model, omega)
        self._E0 = energy(self.model, R, omega)
        self._energy_scale = self._T0 + abs(self.model.mgl)
        self._momentum0 = self.momentum(R, omega)
        self._momentum_scale = float(np.linalg.norm(angular_momentum_space(self.model, R, omega)))
        self._max_drift = dict.fromkeys(self._max_drift, 0.0)
        if rescale or not self._arrow_ok(omega, R):
            self._rescale_arrows(R, omega)
        self._drawn_L = np.full(3, np.nan)
        if self.integrator == INTEGRATOR_EXACT and self._exact_solution() is None:
            self.set_integrator(INTEGRATOR_REALTIME)
        self.samples.clear()
        self.restart_extras()
        self._take_sample()
        self.render_all()

    def _arrow_ok(self, omega_body: Vec3, R: np.ndarray) -> bool:
        lo, hi = ARROW_RANGE
        w = float(np.linalg.norm(omega_body)) * self.omega_scale
        L = float(np.linalg.norm(angular_momentum_space(self.model, R, omega_body))) * self.L_scale
        return (w == 0.0 or lo <= w <= hi) and (L == 0.0 or lo <= L <= hi)

    def _rescale_arrows(self, R: np.ndarray, omega_body: Vec3) -> None:
        w = float(np.linalg.norm(omega_body))
        L = float(np.linalg.norm(angular_momentum_space(self.model, R, omega_body)))
        self.omega_scale = self.arrow_lengths[0] / w if w > 0.0 else self.omega_scale
        self.L_scale = self.arrow_lengths[1] / L if L > 0.0 else self.L_scale
        self.gui_legend.content = (
            f"Arrows from the {'pivot' if self.model.mgl else 'centre of mass'}:  \n"
            f"**ω** (orange): 1 unit = {1.0 / self.omega_scale:.3g} rad/s  \n"
            f"**L** (violet): 1 unit = {1.0 / self.L_scale:.3g} kg m²/s  \n"
            "Gold: line of nodes e_n.  Red/green/blue: space x y z; dark: body x′ y′ z′."
        )

    def _exact_solution(self) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None:
        """The closed form from this run's initial state (built once per run), or None."""
        if self._exact is None and self._exact_failed is None:
            try:
                self._exact = exact_solution(self.model, self.initial_state)
            except (ValueError, ArithmeticError) as error:
                self._exact_failed = str(error)
        return self._exact

    def _advance(self, dt_sim: float) -> bool:
        """Advance the state by dt_sim [s] of simulated time; False (paused, message) on failure."""
        if not dt_sim > 0.0:
            return False
        try:
            if self.integrator == INTEGRATOR_EXACT and self._exact_solution() is not None:
                t = self.state.t + dt_sim
                R, omega = self._exact(np.array([t]))  # type: ignore[misc]
                self.state = State(R[0], omega[0], t)
                self.substeps = 0
            else:
                with PHYSICS_LOCK:
                    self.state, evaluations = step_realtime(self.model, self.state, dt_sim)
                self.substeps = evaluations // 5  # Suzuki's composition: 5 Strang stages a sub-step
        except (IntegrationError, ValueError, ArithmeticError) as error:
            self.playing = False
            self.controls.show_playing(False)
            self.controls.show_message(f"The simulation stopped: {error}")
            return False
        return True

    def tick(self, dt: float) -> None:
        """One frame of the app loop: dt [s] of wall time, times the time scale if playing."""
        if not self.playing:
            return
        with self.client.atomic():  # one flush of the client's buffer per frame
            if self._advance(dt * self.time_scale):
                self._render_frame()
            if self._sample_throttle.ready(dt):
                self._take_sample()
            if self._slider_throttle.ready(dt):
                self._sync_state_sliders()
            if self._readout_throttle.ready(dt):
                self._refresh_readout()
                self._refresh_status()
            if self._plot_throttle.ready(dt):
                self._push_plots()

    # ------------------------------------------------------------------ drawing
    def render_all(self) -> None:
        """Everything at once (after an edit, a step, a restart; never per frame)."""
        with self.client.atomic():
            self.nodes_node.visible = bool(self.gui_show_nodes.value)
            self.body_axes.visible = bool(self.gui_show_body_axes.value)
            self._render_frame()
            self._sync_state_sliders()
            self._refresh_readout()
            self._refresh_status()
            self._push_plots()

    def _render_frame(self) -> None:
        """The per-frame update: poses and arrows only, in one atomic block."""
        R = self.state.R_space_body
        omega_body = self.state.omega_body
        self.angles = euler_zxz_from_matrix_near(R, self.angles)
        phi, theta = float(self.angles[0]), float(self.angles[1])
        omega_space = R @ omega_body
        L_space = R @ (np.array(self.model.inertia) * omega_body)
        show_omega = bool(self.gui_show_omega.value)
        show_L = bool(self.gui_show_L.value)
        with self.client.atomic():
            self.body_node.wxyz = wxyz_from_matrix(R)
            self.nodes_node.wxyz = (math.cos(0.5 * phi), 0.0, 0.0, math.sin(0.5 * phi))
            distance_deg = math.degrees(min(theta, math.pi - theta))
            level = min(FADE_LEVELS, int(FADE_LEVELS * distance_deg / GIMBAL_FADE_DEG))
            if level != self._fade_level:
                self._fade_level = level
                color = fade_color(NODES_COLOR, NODES_FADED_COLOR, level / FADE_LEVELS)
                self.nodes_line.colors = np.array([[color, color]], dtype=np.uint8)
                self.nodes_label.text = "line of nodes" if gimbal_note(math.degrees(theta)) is None \
                    else "line of nodes (undefined)"
            self._draw_vector(self.omega_arrow, self.omega_label, omega_space * self.omega_scale, show_omega)
            change = float(np.max(np.abs(L_space - self._drawn_L)))  # NaN before the first frame
            if not change <= 1e-6 * (1.0 + float(np.max(np.abs(L_space)))) or show_L != self.L_arrow.visible:
                self._drawn_L = L_space
                self._draw_vector(self.L_arrow, self.L_label, L_space * self.L_scale, show_L)
            self.render_extras(R, omega_space, L_space)

    @staticmethod
    def _draw_vector(arrow: Any, label: Any, tip: np.ndarray, visible: bool) -> None:
        length = float(np.linalg.norm(tip))
        visible = visible and length > 1e-3
        if arrow.visible != visible:  # (assigning an unchanged prop still costs a comparison)
            arrow.visible = visible
            label.visible = visible
        if visible:
            arrow.points = np.array([[[0.0, 0.0, 0.0], tip]], dtype=np.float32)
            label.position = tuple(tip * (1.0 + 0.16 / length))

    def _sync(self, handles: Sequence[Any], specs: Sequence[SliderSpec], values: Sequence[float],
              skip: Any = None) -> None:
        """Show `values` on sliders without their callbacks acting (no feedback loop)."""
        self._syncing = True
        try:
            for handle, spec, value in zip(handles, specs, values):
                if handle is not skip:
                    handle.value = spec.rounded(value)
        finally:
            self._syncing = False

    def _displayed_angles_deg(self) -> tuple[float, float, float]:
        phi, theta, psi = np.degrees(self.angles)
        return wrap_deg(float(phi)), float(theta), wrap_deg(float(psi))

    def _sync_state_sliders(self, skip: Any = None) -> None:
        self._sync(self.gui_angles, ANGLE_SPECS, self._displayed_angles_deg(), skip)
        try:
            rates = self.rates_from_state(self.angles, self.state)
        except GimbalLockError:
            return  # Euler rates are undefined at the pole: the rate sliders keep their values
        self._sync(self.gui_rates, self.rate_specs, rates, skip)

    # ------------------------------------------------------------------ callbacks
    def _state_slider_callback(self, handle: Any, spec: SliderSpec) -> Callable[[Any], None]:
        """An angle or rate slider: the user sets the state from the sliders (pausing)."""

        def on_update(_event: Any) -> None:
            if self._syncing:
                return  # the server itself is showing the motion on the slider
            value = checked_value(handle.value, spec.lo, spec.hi)
            if value is None:
                self.controls.show_message(f"{spec.label} = {handle.value!r} refused: the range is "
                                           f"{spec.lo:g} to {spec.hi:g}.")
                self._sync_state_sliders()  # the slider goes back to the state's value
                return
            self.controls.clear_message()
            if self.playing:
                self.playing = False
                self.controls.show_playing(False)
            self._sync_state_sliders(skip=handle)  # the other sliders show the state paused now
            angles = np.radians([h.value for h in self.gui_angles])
            rates = [h.value for h in self.gui_rates]
            state = State(matrix_from_euler_zxz(*angles), self.omega_body_from_rates(angles, rates), 0.0)
            self.restart(state, angles=angles)

        return on_update

    def _param_callback(self, index: int, handle: Any) -> Callable[[Any], None]:
        spec = self.param_specs[index]

        def on_update(_event: Any) -> None:
            if self._syncing:
                return
            value = checked_value(handle.value, spec.lo, spec.hi)
            if value is None:
                self.controls.show_message(f"{spec.label} = {handle.value!r} refused: the range is "
                                           f"{spec.lo:g} to {spec.hi:g}.")
                self._sync([handle], [spec], [self.params[index]])
                return
            candidate = tuple(float(h.value) for h in self.gui_params)
            try:
                model = self.model_from_params(candidate)
            except (InertiaError, ValueError) as error:
                shown = ", ".join(f"{p:g}" for p in self.params)
                self.gui_param_status.content = (
                    f"**⚠ Refused:** {error}.  Each moment must be at most the sum of the other two "
                    f"(I1 + I2 ≥ I3 and cyclic) and positive.  Simulating the last valid body ({shown})."
                )
                self.controls.show_message(
                    f"Not a rigid body: {error}. Refused; the last valid body ({shown}) keeps moving.")
                return
            self.controls.clear_message()
            self.params = candidate
            self.model = model
            self._reshape_body()
            self.restart(self.state, angles=self.angles)  # same R and ω_b, new body; keeps playing

        return on_update

    def _preset_callback(self, group: Any) -> Callable[[Any], None]:
        def on_click(_event: Any) -> None:
            self.apply_preset(str(group.value))

        return on_click

    def _set_time_scale(self, value: float) -> None:
        self.time_scale = value

    def _live_plots_toggled(self) -> None:
        self.plots.set_visible(bool(self.gui_live_plots.value))
        self._push_plots()

    def _reshape_body(self) -> None:
        """Rebuild the body's shape nodes for the current parameters."""
        self._shape_node.remove()
        self._shape_node = self.client.scene.add_frame(self._shape_name, show_axes=False)
        self.build_body(self._shape_name)
        self.gui_param_status.content = self.shape_status()

    # ------------------------------------------------------------------ readouts and plots
    def _attitude_error(self) -> float | None:
        """Angle [rad] of R_exactᵀ R at the current time, or None without a closed form."""
        if self.integrator == INTEGRATOR_EXACT:
            return 0.0
        exact = self._exact_solution()
        if exact is None:
            return None
        R_exact, _ = exact(np.array([self.state.t]))
        return float(np.linalg.norm(log_so3(R_exact[0].T @ self.state.R_space_body)))

    def _take_sample(self) -> None:
        R, omega = self.state.R_space_body, self.state.omega_body
        T = kinetic_energy(self.model, omega)
        V = self.model.potential_energy(R)
        L = angular_momentum_space(self.model, R, omega)
        momentum = self.momentum(R, omega)
        drift_E = (T + V - self._E0) / self._energy_scale if self._energy_scale > 0.0 else 0.0
        drift_L = (momentum - self._momentum0) / self._momentum_scale if self._momentum_scale > 0.0 else 0.0
        error = self._attitude_error()
        phi, theta, psi = self._displayed_angles_deg()
        values = {"E": T + V, "T": T, "V": V, "L_norm": float(np.linalg.norm(L)), "L_z": float(L[2]),
                  "phi": phi, "theta": theta, "psi": psi, "w1": omega[0], "w2": omega[1], "w3": omega[2],
                  "drift_E": drift_E, "drift_L": drift_L,
                  "attitude_error": float("nan") if error is None else error}
        for key in self._max_drift:
            if math.isfinite(values[key]):
                self._max_drift[key] = max(self._max_drift[key], abs(values[key]))
        self.samples.append(self.state.t, values)

    def _push_plots(self) -> None:
        if self.gui_live_plots.value:
            self.plots.push()
        error = self.samples.last("attitude_error")
        if self.integrator == INTEGRATOR_EXACT:
            error_line = "attitude error       —  (the integrator IS the exact solution)"
        elif math.isnan(error):
            error_line = f"attitude error       —  (no closed form: {self._exact_failed})"
        else:
            error_line = f"attitude error   {error:9.2e} rad   (max {self._max_drift['attitude_error']:.2e})"
        self.gui_accuracy.content = (
            f"**Accuracy** of {self.integrator} since t = 0 (relative; exact would be 0)\n"
            "```\n"
            f"|ΔE| / E₀      {abs(self.samples.last('drift_E')):9.2e}       (max {self._max_drift['drift_E']:.2e})\n"
            f"|Δ{self.momentum_label}| / |L₀|  {abs(self.samples.last('drift_L')):9.2e}"
            f"       (max {self._max_drift['drift_L']:.2e})\n"
            f"{error_line}\n"
            "```"
        )

    def _refresh_status(self) -> None:
        state = "▶ playing" if self.playing else "paused"
        method = ("exact (closed form)" if self.integrator == INTEGRATOR_EXACT
                  else f"splitting4, {max(self.substeps, 1)} sub-step(s)/frame")
        self.controls.set_status(f"**t = {self.state.t:.2f} s** · {state} · {self.time_scale:g}× · {method}")

    def _refresh_readout(self) -> None:
        R, omega_body = self.state.R_space_body, self.state.omega_body
        phi, theta, psi = self._displayed_angles_deg()
        omega_space = R @ omega_body
        inertia = np.array(self.model.inertia)
        L_body = inertia * omega_body
        L_space = R @ L_body
        T = kinetic_energy(self.model, omega_body)
        V = self.model.potential_energy(R)
        torque = self.model.torque_space_at(self.state.t, R, omega_body)
        Q = generalized_forces(self.angles, torque)

        def row(name: str, v: np.ndarray) -> str:
            return f"{name:<13}" + "".join(f"{(0.0 if abs(x) < 5e-5 else x):9.4f}" for x in v)

        def clean(x: float) -> float:
            return 0.0 if abs(x) < 5e-5 else float(x)

        note = gimbal_note(theta)
        lines = [  # at most ~42 characters a line: the panel's width
            f"t = {self.state.t:.3f} s    (z-x-z, degrees)",
            f"φ = {phi:.2f}°  θ = {theta:.2f}°  ψ = {psi:.2f}°",
        ]
        if note is not None:
            combined = ("φ + ψ", phi + psi) if theta < 90.0 else ("φ − ψ", phi - psi)
            lines.append(f"gimbal lock: only {combined[0]} = {wrap_deg(combined[1]):.2f}°")
        lines += [
            "",
            "D = Rz(φ) Rx(θ) Rz(ψ), columns x′ y′ z′",
            format_matrix(R, 4),
            "",
            f"{'':<13}{'x | x′':>9}{'y | y′':>9}{'z | z′':>9}",
            row("ω_s [rad/s]", omega_space),
            row("ω_b [rad/s]", omega_body),
            row("L_s [kg m²/s]", L_space),
            row("L_b [kg m²/s]", L_body),
            row("M_s [N m]", torque),
            "",
            f"T = {T:.5f} J",
            f"V = {V:.5f} J",
            f"E = T + V = {T + V:.5f} J",
            f"Q_φ = M·e_z  = {clean(Q[0]):.4f} N m",
            f"Q_θ = M·e_n  = {clean(Q[1]):.4f} N m",
            f"Q_ψ = M·e_z′ = {clean(Q[2]):.4f} N m",
        ]
        extra = self.readout_extras(self.state)
        if extra:
            lines += ["", extra]
        content = ("ω_s = D ω_b: space components; ω_b: body; L_s = D I ω_b; M: torque (space); "
                   "Q: generalized forces of φ θ ψ (memo 6.10).\n```\n" + "\n".join(lines) + "\n```")
        if self.gui_readout.content != content:
            self.gui_readout.content = content
        self.gui_gimbal_note.visible = note is not None
        if note is not None and self.gui_gimbal_note.content != note:
            self.gui_gimbal_note.content = note
