"""The "Poinsot" scene's readout as a pure function (no viser): numbers in, Markdown out.
`PoinsotView` shows it in its Setup tab and appends it to the readout; tests/test_poinsot_readouts.py
checks it without a browser.  SI units; the ω scale in scene units per rad/s.
"""

from __future__ import annotations

from typing import Any

from app.i18n import DEFAULT_LANGUAGE, Translator, translator
from app.scenes.poinsot.simulation import sorted_moments
from physics.poinsot import PolhodeMotion

__all__ = ["poinsot_text"]


def poinsot_text(inertia: Any, T: float, mo: PolhodeMotion | None, omega_scale: float,
                 next_flip: float | None, tr: Translator | None = None) -> str:
    """The Poinsot readout (a Markdown code block): T [J] and |L| [kg m²/s], |L|²/(2T) [kg m²]
    against I_mid, the ω scale, and the motion's kind: the flip period 2K(m)/λ [s], m, λ [rad/s]
    and the next flip's time [s] (`next_flip`, None: not shown) for a flip; the circular polhode
    of a symmetric body; the separatrix; a steady rotation.  A body at rest (T = 0 or no motion
    `mo`) has no ellipsoid.  inertia: the principal moments (3,) [kg m²]."""
    _ = (tr or translator(DEFAULT_LANGUAGE)).gettext
    if T == 0.0 or mo is None:
        return _("The body is at rest: no ellipsoid.")
    L_norm = mo.L_norm
    lines = [f"T = {T:.5g} J    |L| = {L_norm:.5g} kg m²/s",
             f"|L|²/(2T) = {L_norm * L_norm / (2 * T):.5g} kg m²  (I_mid = {sorted_moments(inertia)[1]:g})",
             _("ω: 1 rad/s = {scale} scene units").format(scale=f"{omega_scale:.3g}")]
    if mo.kind == "flip":
        lines += [_("flip period 2K(m)/λ = {period} s").format(period=f"{mo.flip_period:.4f}"),
                  f"  (m = {mo.m:.6f}, λ = {mo.rate:.4g} rad/s)",
                  _("next flip at t = {t} s").format(t=f"{next_flip:.3f}") if next_flip is not None else ""]
    elif mo.kind == "symmetric":
        lines += [_("symmetric body: circular polhode, ω_⊥ turns at λ = {rate} rad/s; no flip").format(
            rate=f"{mo.rate:.4g}")]
    elif mo.kind == "separatrix":
        lines += [_("on the separatrix: flip period infinite (m = 1)")]
    else:
        lines += [_("steady rotation about a principal axis: no flip")]
    return "```\n" + "\n".join(line for line in lines if line) + "\n```"
