"""The rigid-body scenes' texts as pure functions of the simulation (no viser): the status line,
the readout, the Lagrange tab, the accuracy panel, the ghost's note and the arrows' legend.

Each takes a `RigidBodySimulation` (and what the view chose: the angles shown, the tab's extras)
and returns Markdown; `app.kit.rigid.view.RigidBodyView` puts them into the panel at the rates
it chooses.  Tested without a browser in tests/test_rigid_text.py.  Angles in degrees, wrapped
to (−180°, 180°] (`format_deg`); SI units otherwise.
"""

from __future__ import annotations

import math

import numpy as np

from app.i18n import DEFAULT_LANGUAGE, N_, Translator, translator
from app.kit.core.common import format_deg, format_matrix, gimbal_note
from app.kit.rigid.simulation import RigidBodySimulation
from physics.dynamics import Model, kinetic_energy
from physics.lagrange import LagrangeTerms, generalized_forces
from physics.methods import applicable, methods

__all__ = ["READOUT_HEAD", "accuracy_text", "ghost_note", "integrator_hint", "lagrange_text", "legend_text",
           "readout_text", "status_text"]

READOUT_HEAD = N_("ω_s = D ω_b: space components; ω_b: body; L_s = D I ω_b; M: torque (space); "
                   "Q: generalized forces of φ θ ψ (memo 6.10).")
ENGLISH = translator(DEFAULT_LANGUAGE)


def status_text(sim: RigidBodySimulation, playing: bool, time_scale: float, tr: Translator = ENGLISH) -> str:
    """The transport's status line: time, playing or paused, time scale, method (with its
    sub-steps in the last frame, if it takes any; "closed form" for the reference), in the
    language of `tr` (the method's name is `physics.methods`', as the CLI's)."""
    _ = tr.gettext
    state = _("▶ playing") if playing else _("paused")
    method = (_("{method} (closed form)").format(method=sim.integrator) if sim.method.reference
              else _("{method}, {n} sub-step(s)/frame").format(method=sim.integrator, n=sim.substeps)
              if sim.substeps else sim.integrator)
    return f"**t = {tr.decimal(sim.t, 2)} s** · {state} · {tr.general(time_scale)}× · {method}"


def integrator_hint(model: Model, tr: Translator = ENGLISH) -> str:
    """The integrator menu's hint, a line or two: the menu's names are `physics.methods`' (the
    CLI's, whose `methods` command says what each does), and which of those that apply to
    `model` keep up with real time."""
    registry = methods()
    realtime = [name for name in applicable(model) if registry[name].realtime]
    return tr.gettext("how the motion is computed (python -m physics methods describes each); "
                      "{names} keep up with real time, the others are for comparison").format(
        names=(" " + tr.gettext("and") + " ").join(realtime))


def accuracy_text(sim: RigidBodySimulation, momentum_label: str, tr: Translator = ENGLISH) -> str:
    """The accuracy panel: energy and momentum drift and the attitude error, now and at most, in
    columns narrow enough for the panel (34 characters of monospace; the projector's narrower panel
    wraps each row after its label)."""
    error = sim.attitude_error()  # now (the samples' are checked in batches: app.kit.rigid.simulation.ERROR_BATCH)
    if sim.method.reference:
        error_row, after = "—", "\n\n" + tr.gettext("The integrator IS the exact solution.")
    elif error is None:
        error_row, after = "—", "\n\n" + tr.gettext("No attitude error: no closed form ({reason}).").format(
            reason=sim.exact_failed)
    else:
        error_row, after = f"{error:.2e}  {max(error, sim.max_drift['attitude_error']):.2e}", ""
    rows = (
        ("|ΔE|/E₀", f"{abs(sim.samples.last('drift_E')):.2e}  {sim.max_drift['drift_E']:.2e}"),
        (f"|Δ{momentum_label}|/|L₀|", f"{abs(sim.samples.last('drift_L')):.2e}  {sim.max_drift['drift_L']:.2e}"),
        (tr.gettext("attitude [rad]"), error_row),
    )
    table = "\n".join(f"{label:<16}{values}" for label, values in rows)
    head = tr.gettext("**Accuracy** of {method} since t = 0, now and at most (relative; exact would be 0)").format(
        method=sim.integrator)
    return f"{head}\n```\n{table}\n```{after}"


def _clean(x: float) -> float:
    return 0.0 if abs(x) < 5e-5 else float(x)


def readout_text(sim: RigidBodySimulation, angles_deg: tuple[float, float, float], extras: str = "",
                 tr: Translator = ENGLISH) -> str:
    """The Readout tab: t, the angles (φ θ ψ [deg] as shown), D, ω, L and M in space and body
    components, T, V, E and the generalized forces Q (6.10); `extras` (monospace lines) below."""
    R, omega_body = sim.state.R_space_body, sim.state.omega_body
    phi, theta, psi = angles_deg
    L_body = np.array(sim.model.inertia) * omega_body
    T = kinetic_energy(sim.model, omega_body)
    V = sim.model.potential_energy(R)
    torque = sim.model.torque_space_at(sim.t, R, omega_body)
    Q = generalized_forces(sim.angles, torque)

    def row(name: str, v: np.ndarray) -> str:
        return f"{name:<13}" + "".join(f"{_clean(x):9.4f}" for x in v)

    lines = [  # at most ~42 characters a line: the panel's width
        "t = {t} s    ({words})".format(t=f"{sim.t:.3f}", words=tr.gettext("z-x-z, degrees")),
        f"φ = {format_deg(phi)}°  θ = {theta:.2f}°  ψ = {format_deg(psi)}°",
    ]
    if gimbal_note(theta) is not None:
        combined = ("φ + ψ", phi + psi) if theta < 90.0 else ("φ − ψ", phi - psi)
        lines.append(tr.gettext("gimbal lock: only {angle} = {value}°").format(angle=combined[0],
                                                                             value=format_deg(combined[1])))
    lines += [
        "",
        tr.gettext("D = Rz(φ) Rx(θ) Rz(ψ), columns x′ y′ z′"),
        format_matrix(R, 4),
        "",
        f"{'':<13}{'x | x′':>9}{'y | y′':>9}{'z | z′':>9}",
        row("ω_s [rad/s]", R @ omega_body),
        row("ω_b [rad/s]", omega_body),
        row("L_s [kg m²/s]", R @ L_body),
        row("L_b [kg m²/s]", L_body),
        row("M_s [N m]", torque),
        "",
        f"T = {T:.5f} J",
        f"V = {V:.5f} J",
        f"E = T + V = {T + V:.5f} J",
        f"Q_φ = M·e_z  = {_clean(Q[0]):.4f} N m",
        f"Q_θ = M·e_n  = {_clean(Q[1]):.4f} N m",
        f"Q_ψ = M·e_z′ = {_clean(Q[2]):.4f} N m",
    ]
    if extras:
        lines += ["", extras]
    return tr.gettext(READOUT_HEAD) + "\n```\n" + "\n".join(lines) + "\n```"


def lagrange_text(sim: RigidBodySimulation, terms: LagrangeTerms | None, tr: Translator = ENGLISH) -> str:
    """The Lagrange tab: q, q̇, T (6.4), V and the terms of (5.13) for φ θ ψ on the simulated
    motion (`physics.lagrange.lagrange_terms`), or why they are undefined (terms None: θ at a pole)."""
    _ = tr.gettext
    head = _("Lagrange's equations in q = (φ, θ, ψ) (memo 5.13, 6.4, 6.10), evaluated on the "
             "motion computed by **{method}**.").format(method=sim.integrator)
    if terms is None:
        return (head + "\n\n" + _("**θ is within 2° of 0° or 180°**: the Euler rates q̇ are undefined there "
                                   "(det M = I1 I2 I3 sin²θ): the equations in φ θ ψ are singular; "
                                   "the motion itself is not."))

    def row(name: str, v: np.ndarray, scale: float = 1.0) -> str:
        return f"{name:<15}" + "".join(f"{(0.0 if abs(x) < 5e-9 else x) * scale:11.5f}" for x in v)

    # q in degrees: φ and ψ are the simulation's continuous angles (unwrapped, thousands of
    # degrees after a long run), shown in (-180°, 180°]; θ is in [0°, 180°].
    q_deg = np.degrees(terms.q)
    q_row = f"{'q [deg]':<15}" + "".join(f"{text:>11}" for text in (
        format_deg(q_deg[0], 5), f"{q_deg[1]:.5f}", format_deg(q_deg[2], 5)))
    lines = [
        f"t = {sim.t:.3f} s   T = {terms.T:.5f} J   V = {terms.V:.5f} J",
        "",
        f"{'':<15}{'φ':>11}{'θ':>11}{'ψ':>11}",
        q_row,
        row("q̇ [deg/s]", terms.qdot, 180.0 / math.pi),
        row("∂T/∂q̇", terms.dT_dqdot),
        row("d/dt ∂T/∂q̇", terms.ddt_dT_dqdot),
        row("− ∂T/∂q", -terms.dT_dq),
        row("− Q", -terms.Q),
        "",
        _("residual = d/dt ∂T/∂q̇ − ∂T/∂q − Q [N m]:"),
        "  " + "  ".join(f"{x:.1e}" for x in terms.residual),
        "",
        "Q_φ = M·e_z, Q_θ = M·e_n, Q_ψ = M·e_z′ [N m]",
    ]
    return (head + "\n```\n" + "\n".join(lines) + "\n```\n"
            + _("∂T/∂q̇ in kg m²/s, the other rows in N m.  q̈ comes from Euler's "
                "equations, not from (5.13): the residual shows that the two agree."))


def ghost_note(sim: RigidBodySimulation, k: float, k_label: str, tr: Translator = ENGLISH) -> str:
    """The exact ghost's note: the attitude error and how it is drawn at magnification k."""
    _ = tr.gettext
    error = sim.attitude_error()
    if error is None:
        return _("**Ghost:** no closed form here ({reason}).").format(reason=sim.exact_failed)
    return (_("**Ghost** (translucent) = R_exact·exp(k·log(R_exactᵀR)): k = 0 is the exact solution, "
              "k = 1 lies on the solid body.  Attitude error **{error} rad**; k = {k}, drawn as {drawn} rad").format(
                error=f"{error:.2e}", k=k_label.split(" ")[0], drawn=f"{k * error:.2e}")
            + (_(" (beyond π it wraps).") if k * error > math.pi else "."))


def legend_text(from_pivot: bool, omega_scale: float, L_scale: float, tr: Translator = ENGLISH) -> str:
    """What the arrows mean and their scales [scene units per rad/s, per kg m²/s]."""
    _ = tr.gettext
    head = _("Arrows from the pivot:") if from_pivot else _("Arrows from the centre of mass:")
    return head + "  \n" + _(
        "**ω** (orange): 1 unit = {omega} rad/s  \n"
        "**L** (violet): 1 unit = {L} kg m²/s  \n"
        "Gold: line of nodes e_n.  Red/green/blue: space x y z; dark: body x′ y′ z′."
    ).format(omega=_general(1.0 / omega_scale, tr), L=_general(1.0 / L_scale, tr))


def _general(value: float, tr: Translator) -> str:
    """`value` to 3 significant digits (`:.3g`), with the decimal separator of `tr`."""
    text = f"{value:.3g}"
    return text if tr.language == DEFAULT_LANGUAGE else text.replace(".", tr.decimal(0.5, 1)[1])
