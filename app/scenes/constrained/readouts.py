"""The "Constrained particles" scene's texts as pure functions (no viser): the status line, the
conserved-quantity note and the Readout tab's table, numbers in, Markdown out.  `ConstrainedView`
puts them into its panel at READOUT_PERIOD; tests/test_constrained_readouts.py checks them without
a browser.  q, q̇ in display units (deg and deg/s for an angle, m and m/s for a length); energies
[J], forces [N], generalized forces [N m] or [N].
"""

from __future__ import annotations

import math

from app.i18n import DEFAULT_LANGUAGE, Translator, translator
from app.kit.core.common import SliderSpec
from app.kit.core.key_number import KeyNumber
from app.scenes.constrained.simulation import ConstrainedSimulation
from physics.constrained import Evaluation, hoop_equilibrium

__all__ = ["conserved_text", "extra_line", "key_numbers_of", "on_step", "readout_text", "status_text"]

ENGLISH = translator(DEFAULT_LANGUAGE)


def status_text(t: float, playing: bool, time_scale: float, tr: Translator = ENGLISH) -> str:
    """The transport's status line: t [s], playing or paused, the time scale, the method."""
    _ = tr.gettext
    state = _("▶ playing") if playing else _("paused")
    return f"**t = {tr.decimal(t, 2)} s** · {state} · {tr.general(time_scale)}× · " + _("RK8, steps of 1/120 s")


def extra_line(sim: ConstrainedSimulation, ev: Evaluation, tr: Translator = ENGLISH) -> str:
    """A system's own reference numbers (the hoop's equilibrium, the spherical pendulum's L_z)."""
    _ = tr.gettext
    key = sim.setup.kind
    params = dict(sim.system.params)
    if key == "hoop":
        R, Omega, g = params["R"], params["Ω"], params["g"]
        eq = math.degrees(hoop_equilibrium(R, Omega, g))
        where = (_("Ω² R = {value} > g: the bottom is unstable, the bead settles about "
                   "θ∗ = ±{angle}° (cos θ∗ = g/(Ω² R))").format(value=tr.general(float(f"{Omega * Omega * R:.3g}")),
                                                               angle=tr.decimal(eq, 1))
                 if Omega * Omega * R > g
                 else _("Ω² R = {value} ≤ g = {g}: the bottom θ = 0 is stable").format(
                     value=tr.general(float(f"{Omega * Omega * R:.3g}")), g=tr.general(g)))
        return where + "."
    if key == "spherical":
        L_z = float(sim.system.masses[0] * (ev.x[0, 0] * ev.x_dot[0, 1] - ev.x[0, 1] * ev.x_dot[0, 0]))
        return _("L_z = m (x ẏ − y ẋ) = p_φ = {L_z} kg m²/s (φ is cyclic: conserved).").format(
            L_z=tr.decimal(L_z, 6))
    if key == "rod":
        return _("Q = 0 (gravity ⊥ the rod): r̈ = Ω² r, the bead flies out; C holds it up and pushes it round.")
    return ""


def conserved_text(sim: ConstrainedSimulation, ev: Evaluation, tr: Translator = ENGLISH) -> str:
    """What is conserved (Markdown): Jacobi's integral h when the constraint moves (the energy is
    not), the energy h = T + V when it is fixed, with the drift |h − h₀| / (|T| + |V|)₀; then the
    system's own line (`extra_line`).  ev: `sim.evaluation()` now."""
    drift = abs(ev.h - sim.h0) / sim.energy_scale
    _ = tr.gettext
    if sim.system.rheonomic:
        note = _("**The constraint moves (∂x/∂t ≠ 0): the energy T + V = {E} J is not conserved** "
                 "(the motor turning it does work).  Conserved: **Jacobi's integral h = T₂ − T₀ + V = "
                 "{h} J** (drift {drift}).").format(E=tr.decimal(ev.T + ev.V, 4), h=tr.decimal(ev.h, 6),
                                                    drift=f"{drift:.1e}")
    else:
        note = _("Fixed constraints (∂x/∂t = 0): T₁ = T₀ = 0 and h = T + V is the **energy, conserved: "
                 "{h} J** (drift {drift}).").format(h=tr.decimal(ev.h, 6), drift=f"{drift:.1e}")
    extra = extra_line(sim, ev, tr)
    return note + ("  \n" + extra if extra else "")


def on_step(value: float, spec: SliderSpec) -> float:
    """`value` rounded to the slider's step (as `SliderSpec.rounded`, but not clamped to its range:
    a key number says where the motion is, also beyond a slider's end); an angle on a
    (−180, 180) slider wrapped into it first."""
    if (spec.lo, spec.hi) == (-180.0, 180.0):
        value = (value + 180.0) % 360.0 - 180.0
    decimals = max(0, -math.floor(math.log10(spec.step)) + 1)
    return round(round(value / spec.step) * spec.step, decimals) + 0.0  # never -0


def key_numbers_of(sim: ConstrainedSimulation) -> list[KeyNumber]:
    """The followers' key numbers: q and q̇ now (display units, labelled as their sliders, on the
    sliders' steps) and the system's parameters."""
    kind = sim.setup.kind_spec
    numbers = [KeyNumber.made(spec.label, (on_step(value, spec),))
               for specs, values in ((kind.q_specs, sim.q_shown), (kind.rate_specs, sim.rates_shown))
               for spec, value in zip(specs, values)]
    numbers += [KeyNumber.made(spec.label, (spec.rounded(value),))
                for spec, value in zip(kind.param_specs, sim.setup.params)]
    return numbers


def _num(x: float) -> str:
    """A number in 10 columns, 4 significant digits (|x| < 5e-13 shown as 0)."""
    return f"{0.0 if abs(x) < 5e-13 else x:10.4g}"


def readout_text(sim: ConstrainedSimulation, ev: Evaluation, tr: Translator = ENGLISH) -> str:
    """The Readout tab (Markdown, a monospace table): q and q̇ (display units), T = T₂ + T₁ + T₀
    and V, the virtual work C_i·∂x_i/∂q_j per particle (and summed for two), Lagrange's
    equations (5.13) term by term with their residual, and F_i, C_i per particle.  ev:
    `sim.evaluation()` now."""
    system = sim.system
    names = system.coordinates
    units = ["N m" if a else "N" for a in system.angular]
    num = _num
    _ = tr.gettext
    lines = ["```", "q       " + "".join(f"{n:>10}" for n in names),
             "q       " + "".join(num(v) for v in sim.q_shown) + "   " + _("(deg or m)"),
             "q̇       " + "".join(num(v) for v in sim.rates_shown) + "   " + _("(deg/s or m/s)"),
             "",
             f"T = {ev.T:.4f}  T₂ = {ev.T2:.4f}  T₁ = {ev.T1:.4f}  T₀ = {ev.T0:.4f}  V = {ev.V:.4f}  [J]",
             "",
             _("(5.7) virtual work C_i·∂x_i/∂q_j") + "  [" + ", ".join(units) + "]"]
    for i in range(system.n):
        lines.append(_("particle {n}").format(n=i + 1).ljust(10) + "".join(num(w) for w in ev.virtual_work[i]))
    if system.n > 1:
        lines.append(_("sum").ljust(10) + "".join(num(w) for w in ev.virtual_work.sum(axis=0)))
    lines += ["", _("(5.13) per coordinate").ljust(21) + "  d/dt∂T/∂q̇   ∂T/∂q        Q_j   " + _("residual")]
    terms = ev.terms
    for j, name in enumerate(names):
        lines.append(f"{name:<21}" + num(terms.ddt_dT_dqdot[j]) + num(terms.dT_dq[j]) + num(terms.Q[j])
                     + f"{terms.residual[j]:11.1e}")
    lines += ["", _("forces [N]").ljust(10) + "         x         y         z"]
    for i in range(system.n):
        lines.append(f"F{i + 1}       " + "".join(num(c) for c in ev.F[i]))
        lines.append(f"C{i + 1}=mẍ−F  " + "".join(num(c) for c in ev.C[i]))
    lines.append("```")
    if system.n > 1:
        lines.append(_("On each particle of the double pendulum the middle rod's push does virtual work; on the "
                       "two together it does none (equal and opposite along the rod): the **sum** is what "
                       "(5.8)–(5.11) use."))
    return "\n".join(lines)
