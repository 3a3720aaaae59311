"""The heavy top's energy picture in the panel: U_eff(θ), the energy line, θ₁ θ₂, the current θ.

`EnergyPlot` is one uPlot chart and a Markdown readout, drawn from a
`physics.top_energy.TopEnergyPicture` (the physics lives there: U_eff, the turning points from
the closed form, the class of motion).  The chart's x axis is θ [deg] around [θ₁, θ₂], its y axis
U_eff [J], on a fixed window around the well (`plot_window`) (U_eff grows without bound at a pole the motion
cannot reach; values beyond the range are cut off before they are sent).  Vertical marks are
drawn as one series each that runs below the range and spikes through it at the marked θ, so
that only the spikes show (uPlot's gaps need `null`, which a numpy array cannot carry).

Cost: `show` sends ~200 points × 5 columns (~8 kB); the scene calls it when the run changes
(a slider, a preset, a kick), and `mark` (the same message with the current θ moved) at most
MARK_PERIOD apart while playing, only while the chart's tab is on screen.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import viser.uplot

from app.i18n import DEFAULT_LANGUAGE, Translator, refusal_text, translator
from physics.top_energy import TopEnergyPicture

ENGLISH = translator(DEFAULT_LANGUAGE)

__all__ = ["GRID_POINTS", "MARK_PERIOD", "EnergyPlot", "Window", "energy_plot_data", "plot_window"]

GRID_POINTS = 201  # U_eff samples across the window
MARGIN_DEG = 8.0  # [deg] at least this much of θ shown either side of the turning points
MARK_PERIOD = 0.5  # [s] of wall time between moves of the current-θ mark while playing
U_COLOR, E_COLOR, TURN_COLOR, NOW_COLOR = "#222222", "#e65a00", "#2a7ab9", "#c80078"


Window = tuple[float, float, float, float]
"""(θ_lo, θ_hi) [deg], (U_lo, U_hi) [J]: what the chart shows."""


def plot_window(picture: TopEnergyPicture) -> Window:
    """The chart's window: θ from θ₁ to θ₂ with 60 % (at least MARGIN_DEG) either side, within
    [0°, 180°]; U_eff from below the bottom of the well to well above E, at least 0.1 mgl (or
    1e-3 |E|) tall, so that a steady precession (E at the bottom) still shows its well."""
    theta_1, theta_2 = math.degrees(picture.theta_1), math.degrees(picture.theta_2)
    margin = max(0.6 * (theta_2 - theta_1), MARGIN_DEG)
    x_lo, x_hi = max(theta_1 - margin, 0.0), min(theta_2 + margin, 180.0)
    U = picture.U_eff(np.radians(np.linspace(x_lo, x_hi, GRID_POINTS)))
    finite = U[np.isfinite(U)]
    U_min = min(float(finite.min()) if finite.size else picture.energy, picture.energy)
    span = max(picture.energy - U_min, 0.1 * picture.mgl, 1e-3 * abs(picture.energy), 1e-9)
    return x_lo, x_hi, U_min - 0.15 * span, picture.energy + 0.85 * span


def energy_plot_data(picture: TopEnergyPicture, theta_now: float, window: Window) -> tuple[np.ndarray, ...]:
    """(θ [deg], U_eff, E, turning-point marks, current-θ mark) for uPlot, x ascending.

    theta_now [rad]; window (`plot_window`): U_eff is sampled across it and clipped to just
    above it (a finite value for the infinite barrier at a pole), the marks run from below it
    to above it."""
    x_lo, x_hi, y_lo, y_hi = window
    height = y_hi - y_lo
    below, above = y_lo - height, y_hi + height
    grid = np.linspace(x_lo, x_hi, GRID_POINTS)
    turning = np.degrees([picture.theta_1, picture.theta_2])
    now = np.array([math.degrees(theta_now)])
    marks = np.concatenate([np.repeat(turning, 3), np.repeat(now, 3)])
    x = np.concatenate([grid, marks])
    order = np.argsort(x, kind="stable")
    U = np.nan_to_num(picture.U_eff(np.radians(x)), nan=above, posinf=above)
    U = np.minimum(U, above)
    spike = np.array([below, above, below])
    turning_marks = np.concatenate([np.full(grid.size, below), np.tile(spike, 2), np.full(3, below)])
    now_marks = np.concatenate([np.full(grid.size, below), np.full(6, below), spike])
    return (x[order], U[order], np.full(x.size, picture.energy), turning_marks[order], now_marks[order])


def _deg(theta: float) -> str:
    return f"{math.degrees(theta):.2f}°"


def _rate(phi_dot: float) -> str:
    return "—" if math.isnan(phi_dot) else f"{math.degrees(phi_dot):.1f}°/s"


class EnergyPlot:
    """The U_eff(θ) chart and its readout in the current GUI container (see the module docstring).

    Attributes:
        picture: the picture shown (None before the first `show`, or when there is none).
        sends: how many times the chart's data were sent (tests check the throttling).
    """

    def __init__(self, gui: Any, tr: Translator = ENGLISH) -> None:
        self.tr = tr
        _ = tr.gettext
        self.picture: TopEnergyPicture | None = None
        self.sends = 0
        self.window: Window = (0.0, 180.0, 0.0, 1.0)
        self._theta_now = 0.0
        self._marked_at = -math.inf
        self.gui_motion = gui.add_markdown("")
        series = (
            viser.uplot.Series(label="θ [deg]"),
            viser.uplot.Series(label="U_eff(θ)", stroke=U_COLOR, width=2.0),
            viser.uplot.Series(label="E", stroke=E_COLOR, width=2.0, dash=(6.0, 4.0)),
            viser.uplot.Series(label="θ₁ θ₂", stroke=TURN_COLOR, width=1.5, dash=(3.0, 3.0)),
            viser.uplot.Series(label=_("θ now"), stroke=NOW_COLOR, width=2.0),
        )
        self.handle = gui.add_uplot(
            data=(np.zeros(1),) + tuple(np.zeros(1) for _ in range(4)), series=series,
            title=_("Effective potential U_eff(θ) [J]"), height=230,
            scales=self._scales(), legend=viser.uplot.Legend(show=True, live=False),
            axes=(viser.uplot.Axis(label="θ [deg]"), viser.uplot.Axis()),
        )
        self.gui_readout = gui.add_markdown("")

    def _scales(self) -> dict[str, Any]:
        x_lo, x_hi, y_lo, y_hi = self.window
        return {"x": viser.uplot.Scale(time=False, auto=False, range=(x_lo, x_hi)),
                "y": viser.uplot.Scale(auto=False, range=(y_lo, y_hi))}

    def show(self, picture: TopEnergyPicture | None, theta_now: float, failure: BaseException | str = "") -> None:
        """Draw `picture` with the current θ [rad] marked; None: say `failure` instead (an error
        that made none: a refusal from physics said in this plot's language, `app.i18n.refusal_text`,
        another error's own words; or a reason already written)."""
        self.picture = picture
        _ = self.tr.gettext
        if picture is None:
            reason = failure if isinstance(failure, str) else refusal_text(failure, self.tr)
            self.gui_motion.content = _("**No energy picture:** {reason}").format(reason=reason)
            self.gui_readout.content = ""
            return
        window = plot_window(picture)
        if window != self.window:
            self.window = window
            self.handle.scales = self._scales()
        # The motion's name and description are physics' (`physics.top_energy`, marked there).
        self.gui_motion.content = _("**Motion: {motion}.** {description}").format(
            motion=_(picture.motion), description=_(picture.description))
        pole = _(" (the pole: the axis passes through it)")
        self.gui_readout.content = _(
            "θ₁ = {theta_1}{pole_1}, θ₂ = {theta_2}{pole_2}; dφ/dt there: {rate_1}, {rate_2}.  \n"
            "E = {energy} J, L_z = p_φ = {p_phi} kg m²/s, p_ψ = I3 ω_z′ = {p_psi} kg m²/s (all conserved).  \n"
            "E = ½ I1 θ̇² + U_eff(θ), U_eff = (p_φ − p_ψ cos θ)² / (2 I1 sin²θ) + p_ψ² / (2 I3) + mgl cos θ: "
            "θ moves where U_eff ≤ E, between the turning points θ₁ and θ₂ where U_eff = E."
        ).format(theta_1=_deg(picture.theta_1), pole_1=pole if picture.theta_1 == 0.0 else "",
                 theta_2=_deg(picture.theta_2), pole_2=pole if picture.theta_2 == math.pi else "",
                 rate_1=_rate(picture.phi_dot_1), rate_2=_rate(picture.phi_dot_2), energy=f"{picture.energy:.4f}",
                 p_phi=f"{picture.p_phi:.4f}", p_psi=f"{picture.p_psi:.4f}")
        self._send(theta_now)

    def mark(self, theta_now: float, *, throttled: bool = True) -> None:
        """Move the current-θ mark to theta_now [rad] (at most every MARK_PERIOD s if throttled)."""
        if self.picture is None:
            return
        now = time.monotonic()
        if throttled and now - self._marked_at < MARK_PERIOD:
            return
        if theta_now != self._theta_now:
            self._send(theta_now)

    def _send(self, theta_now: float) -> None:
        assert self.picture is not None
        self._theta_now = theta_now
        self._marked_at = time.monotonic()
        self.handle.data = energy_plot_data(self.picture, theta_now, self.window)
        self.sends += 1
