"""`RigidBodyPanel`: the panel of a rigid-body view (`app.kit.rigid.view.RigidBodyView`): the
transport and the Setup / Readout / Plots / Lagrange tabs (presets, the angle, rate and
parameter sliders, Display, the readouts, the live plots with the exact solution's flips), the
edits of the sliders turned into calls on the room, and the panel's texts at their rates.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import viser
import viser.uplot

from app.i18n import N_, refusal_text
from app.kit.core.common import GIMBAL_LOCK_DEG, SliderSpec, gimbal_note, wrap_deg
from app.kit.panel.binding import BOX_DIGITS
from app.kit.panel.gui import PresetsRow, Readout, Tabs, add_slider
from app.kit.panel.plots import LivePlots, PlotSpec
from app.kit.rigid.ghost import ExactGhost
from app.kit.rigid.hand import HandControls
from app.kit.rigid.lagrange_arrows import GeneralizedForceArrows
from app.kit.rigid.scene import RigidBodyScene
from app.kit.rigid.text import accuracy_text, integrator_hint, lagrange_text, readout_text, status_text
from app.kit.run_words import METHOD_REFUSALS
from app.kit.view import nth
from physics.dynamics import State
from physics.euler import GimbalLockError, matrix_from_euler_zxz
from physics.inertia import InertiaError
from physics.lagrange import lagrange_terms
from physics.methods import applicable

__all__ = ["ANGLE_SPECS", "PLOT_PERIOD", "READOUT_PERIOD", "SLIDER_PERIOD", "STATUS_PERIOD", "FlipPlots",
           "RigidBodyPanel"]

SLIDER_PERIOD = 0.5  # [s] of wall time between slider syncs while playing (2 Hz: they show where the motion is;
# their numbers are read when paused, and a refresh writes them exactly)
READOUT_PERIOD = 0.1  # readout text (10 Hz), only while the Readout tab is shown
STATUS_PERIOD = 0.5  # status line (2 Hz: its t ticks on; the timeline below says the same once a second)
PLOT_PERIOD = 0.25  # plot pushes (4 Hz), only while the Plots tab is shown

FLIP_COLOR = "#888888"


class FlipPlots(LivePlots):
    """`LivePlots` whose chart `flip_chart` has one more series: a grey line on 0 with a vertical
    segment (±max |value| of the window) at each time `flips(t_lo, t_hi)` returns."""

    def __init__(self, gui: Any, buffer: Any, specs: Sequence[PlotSpec], flip_chart: int,
                 flips: Callable[[float, float], np.ndarray], flip_label: str = "flip (exact)") -> None:
        self._flip_chart = -1  # plain charts while the base class builds them
        super().__init__(gui, buffer, specs)
        self._flip_chart = flip_chart
        self._flips = flips
        handle = self.handles[flip_chart]
        handle.series = (*handle.series, viser.uplot.Series(label=flip_label, stroke=FLIP_COLOR, width=1.5,
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
    SliderSpec("phi", N_("φ [deg]"), -180.0, 180.0, 1.0, N_("precession about the space z axis"), _FULL_MARKS),
    SliderSpec("theta", N_("θ [deg]"), 0.0, 180.0, 1.0, N_("nutation about the line of nodes"),
               ((0.0, "0°"), (45.0, "45°"), (90.0, "90°"), (135.0, "135°"), (180.0, "180°"))),
    SliderSpec("psi", N_("ψ [deg]"), -180.0, 180.0, 1.0, N_("spin about the body z′ axis"), _FULL_MARKS),
)


class RigidBodyPanel(RigidBodyScene):
    """The rigid-body view's panel (see the module docstring); the drawing is `RigidBodyView`'s."""

    _rates_shown: tuple[float, ...] | None = None  # the rate sliders' values last shown (kept at gimbal lock)
    # The drawing's (`RigidBodyView`), read here: the arrows' scales (the hand's gizmos) and the
    # Lagrange tab's arrows (drawn with its table).
    omega_scale: float  # [scene units per rad/s]
    L_scale: float  # [scene units per kg m²/s]
    q_arrows: GeneralizedForceArrows

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        tr = self.tr
        _ = tr.gettext
        # The widgets' specs in the browser's language (the class's, English, read the presets).
        angle_specs = [spec.translated(tr) for spec in ANGLE_SPECS]
        rate_specs = [spec.translated(tr) for spec in self.rate_specs]
        param_specs = [spec.translated(tr) for spec in self.param_specs]
        self.build_head(_(self.intro), integrators=applicable(self.sim.model), on_integrator=self.set_integrator,
                        integrator=self.sim.integrator, integrator_hint=integrator_hint(self.sim.model, tr))
        self.tabs = Tabs(gui, wrap, (N_("Setup"), N_("Readout"), N_("Plots"), N_("Lagrange"), *self.extra_tabs),
                         on_change=lambda _name: self.refresh(), tr=tr)
        with self.tabs.tab("Setup"):
            self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset, self.choose_own_preset,
                                          tr=tr)
            with gui.add_folder(_("Euler angles z-x-z [deg]")):
                self.gui_angles = [add_slider(gui, spec) for spec in angle_specs]
                self.gui_gimbal_note = gui.add_markdown("", visible=False)
            with gui.add_folder(_(self.rate_folder)):
                self.gui_rates = [add_slider(gui, spec) for spec in rate_specs]
            self.hand = HandControls(self, gui) if self.hand_gizmos else None
            with gui.add_folder(_(self.param_folder)):
                params = self.params_from_model(self.sim.model)
                self.gui_params = [add_slider(gui, spec, value) for spec, value in zip(param_specs, params)]
                self.gui_param_status = gui.add_markdown(self.shape_status(self.sim.model))
            with gui.add_folder(_("Display"), expand_by_default=False):
                self.gui_show_omega = gui.add_checkbox(_("ω arrow"), True)
                self.gui_show_L = gui.add_checkbox(_("L arrow"), True)
                self.gui_show_nodes = gui.add_checkbox(_("Line of nodes"), True)
                self.gui_show_body_axes = gui.add_checkbox(_("Body axes x′ y′ z′"), True)
                self.ghost = ExactGhost(gui, wrap, self.message, self.quiet, scene=self.client.scene, root=self.root,
                                        shape=self.build_shape, axis_length=self.body_axis_length, sim=self.sim,
                                        on_change=self.room.refresh, labels=self.labels, tr=tr)
                self.gui_ghost = self.ghost.gui_toggle  # a lesson step switches it by its label
                self.build_display_extras(gui)
                self.gui_reset_view = gui.add_button(_("Reset view"), icon=viser.Icon.CAMERA)
                self.gui_legend = gui.add_markdown("")
        with self.tabs.tab("Readout"):
            self.readout = Readout(gui)
        with self.tabs.tab("Plots"):
            self.gui_live_plots = gui.add_checkbox(_("Live plots"), True, hint=_("turn off to save CPU and bandwidth"))
            self.accuracy = Readout(gui)
            specs = self.plot_specs()
            omega_chart = next(k for k, spec in enumerate(specs) if spec.columns[:1] == ("w1",))
            self.plots = FlipPlots(gui, self.sim.samples, specs, omega_chart,
                                   lambda t_lo, t_hi: self.sim.flips(t_lo, t_hi), _("flip (exact)"))

        with self.tabs.tab("Lagrange"):
            self.lagrange_readout = Readout(gui)
        self.build_tab_extras(gui)

        for index, (spec, handle) in enumerate(zip(angle_specs, self.gui_angles)):
            self.bind(handle, f"{spec.label} slider", self._state_edit(handle, spec), self._angle_in_force(index),
                      spec=spec)
        for index, (spec, handle) in enumerate(zip(rate_specs, self.gui_rates)):
            self.bind(handle, f"{spec.label} slider", self._state_edit(handle, spec), self._rate_in_force(index),
                      spec=spec)
        for index, (spec, handle) in enumerate(zip(param_specs, self.gui_params)):
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
        _ = self.tr.gettext
        return [
            PlotSpec(_("Energy [J]"), ("E", "T", "V"), ("E = T + V", "T", "V"), ("black", "#e65a00", "#2a7ab9")),
            PlotSpec(_("Angular momentum [kg m²/s]"), ("L_norm", "L_z"), ("|L|", "L_z"), ("#7828c8", "#2a9d8f")),
            PlotSpec(_("Euler angles z-x-z [deg]"), ("phi", "theta", "psi"), ("φ", "θ", "ψ"),
                     ("#8c32d2", "#d70078", "#008c8c")),
            PlotSpec(_("ω, body components [rad/s]"), ("w1", "w2", "w3"), ("ω_x′", "ω_y′", "ω_z′"),
                     ("#c00000", "#00802a", "#0030a0")),
            PlotSpec(_("Accuracy: log₁₀ of the errors"), ("drift_E", "drift_L", "attitude_error"),
                     ("|ΔE|/E₀", f"|Δ{self.momentum_label}|/|L₀|", _("attitude [rad]")),
                     ("#e65a00", "#7828c8", "black"), log=True),
        ]


    def fit_arrows(self) -> None:
        """Rescale the arrows if ω or L is outside their range (after a drag; `RigidBodyView` draws)."""
        raise NotImplementedError

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
                tr = self.tr
                shown = "; ".join(tr.general(p) for p in current) if tr.language != "en" \
                    else ", ".join(f"{p:g}" for p in current)
                reason = refusal_text(error, tr)
                self.gui_param_status.content = tr.gettext(
                    "**⚠ Refused:** {reason}.  Each moment must be at most the sum of the other two "
                    "(I1 + I2 ≥ I3 and cyclic) and positive.  Simulating the last valid body ({shown})."
                ).format(reason=reason, shown=shown)
                return tr.gettext("Not a rigid body: {reason}. Refused; the last valid body ({shown}) keeps moving."
                                  ).format(reason=reason, shown=shown)
            self.sim.mesh = None  # new moments: a handed-on mesh no longer fits
            self.sim.set_model(model)  # same R and ω_b, new body; keeps playing
            self.room.refresh()
            return None

        return apply

    # ------------------------------------------------------------------ actions
    def set_integrator(self, name: str) -> None:
        message = self.sim.set_integrator(name)
        if message is not None:  # the simulation's English words, in this browser's language
            self.message.show(functools.partial(METHOD_REFUSALS.in_language, message))
        self.room.refresh()

    # ------------------------------------------------------------------ text
    def _refresh_status(self) -> None:
        self.transport.set_status(status_text(self.sim, self.room.playing, self.room.time_scale, self.tr))

    def _refresh_gimbal_note(self) -> None:
        note = gimbal_note(math.degrees(float(self.sim.angles[1])))
        if self.gui_gimbal_note.visible != (note is not None):
            self.gui_gimbal_note.visible = note is not None
        if note is not None:
            note = self.tr.gettext(note)
        if note is not None and self.gui_gimbal_note.content != note:
            self.gui_gimbal_note.content = note

    def _push_plots(self) -> None:
        if self.gui_live_plots.value:
            self.plots.push()
        self.accuracy.set(accuracy_text(self.sim, self.momentum_label, self.tr))

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
            self.lagrange_readout.set(lagrange_text(sim, terms, self.tr))
            return
        self.readout.set(readout_text(sim, self.displayed_angles_deg(), self.readout_extras(sim), self.tr))
        self._refresh_gimbal_note()
