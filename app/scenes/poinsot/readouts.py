"""The "Poinsot" scene's readout as a pure function (no viser): numbers in, Markdown out.
`PoinsotView` shows it in its Setup tab and appends it to the readout; tests/test_poinsot_readouts.py
checks it without a browser.  SI units; the ω scale in scene units per rad/s.
"""

from __future__ import annotations

from typing import Any

from app.scenes.poinsot.simulation import sorted_moments
from physics.poinsot import PolhodeMotion

__all__ = ["poinsot_text"]


def poinsot_text(inertia: Any, T: float, mo: PolhodeMotion | None, omega_scale: float,
                 next_flip: float | None) -> str:
    """The Poinsot readout (a Markdown code block): T [J] and |L| [kg m²/s], |L|²/(2T) [kg m²]
    against I_mid, the ω scale, and the motion's kind: the flip period 2K(m)/λ [s], m, λ [rad/s]
    and the next flip's time [s] (`next_flip`, None: not shown) for a flip; the circular polhode
    of a symmetric body; the separatrix; a steady rotation.  A body at rest (T = 0 or no motion
    `mo`) has no ellipsoid.  inertia: the principal moments (3,) [kg m²]."""
    if T == 0.0 or mo is None:
        return "The body is at rest: no ellipsoid."
    L_norm = mo.L_norm
    lines = [f"T = {T:.5g} J    |L| = {L_norm:.5g} kg m²/s",
             f"|L|²/(2T) = {L_norm * L_norm / (2 * T):.5g} kg m²  (I_mid = {sorted_moments(inertia)[1]:g})",
             f"ω: 1 rad/s = {omega_scale:.3g} scene units"]
    if mo.kind == "flip":
        lines += [f"flip period 2K(m)/λ = {mo.flip_period:.4f} s",
                  f"  (m = {mo.m:.6f}, λ = {mo.rate:.4g} rad/s)",
                  f"next flip at t = {next_flip:.3f} s" if next_flip is not None else ""]
    elif mo.kind == "symmetric":
        lines += [f"symmetric body: circular polhode, ω_⊥ turns at λ = {mo.rate:.4g} rad/s; no flip"]
    elif mo.kind == "separatrix":
        lines += ["on the separatrix: flip period infinite (m = 1)"]
    else:
        lines += ["steady rotation about a principal axis: no flip"]
    return "```\n" + "\n".join(line for line in lines if line) + "\n```"
