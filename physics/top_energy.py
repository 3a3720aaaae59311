"""The heavy symmetric top's energy picture: U_eff(θ), the turning points, the class of motion.

Conventions as in `physics.exact_top` (docs/CONVENTIONS.md): z-x-z Euler angles, I1 = I2 and
I3 about the pivot [kg m²], the centre of mass on +z′ at ℓ, gravity along space −z, V = mgl cos θ.

With the two conserved momenta p_φ = L·e_z and p_ψ = I3 ω_z′ [kg m²/s], the energy separates as

    E = ½ I1 θ̇² + U_eff(θ),
    U_eff(θ) = (p_φ − p_ψ cos θ)² / (2 I1 sin²θ) + p_ψ² / (2 I3) + mgl cos θ   [J],

so θ moves where U_eff(θ) ≤ E, between the turning points θ₁ ≤ θ₂ where U_eff = E.  Those are
taken from the closed form (`physics.exact_top.HeavySymmetricTopExact`: u₂ = cos θ₁,
u₁ = cos θ₂, roots of its u-cubic), never recomputed here.  The precession rate is

    φ̇ = (p_φ − p_ψ cos θ) / (I1 sin²θ),

linear in u = cos θ in its numerator, so the sign of φ̇ at θ₁ and θ₂ names the motion
(`classify`, checked against the presets of `assets/presets/heavy_top.json`):

* **sleeping**: the whole motion within UPRIGHT_DEG of the vertical and the vertical stable
  (I3² ω_z′² > 4 I1 mgl, mgl > 0);
* **through the vertical**: the axis passes through θ = 0 (or θ = 180°) each nod: p_φ = ±p_ψ,
  θ₁ = 0 (θ₂ = 180°) within POLE_TOL_RAD; θ then runs through the pole and the z-x-z θ
  reflects (θ₁ = 0 is the pole, not a zero of E − U_eff);
* **too slow to sleep**: starts near the vertical (θ₁ < UPRIGHT_DEG) whose stability it lacks
  (I3² ω_z′² < 4 I1 mgl): it falls away from it;
* **steady precession**: θ₂ − θ₁ ≤ STEADY_TOL_RAD;
* **cusp**: φ̇ = 0 at a turning point (|p_φ − p_ψ cos θ_k| ≤ CUSP_RTOL (|p_φ| + |p_ψ|));
* **wave**: φ̇ keeps its sign between θ₁ and θ₂ (the tip draws waves);
* **loop**: φ̇ changes sign between them (the tip draws loops).

The tolerances decide classes only at their borders (a preset typed to 16 digits, a slider at
0): all motions near a border look alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from physics._types import Array
from physics.exact_top import HeavySymmetricTopExact
from physics.refusal import N_  # the motion's names and descriptions: an app translates them

__all__ = [
    "CUSP",
    "CUSP_RTOL",
    "LOOP",
    "MOTION_CLASSES",
    "POLE_TOL_RAD",
    "SLEEPING",
    "STEADY",
    "STEADY_TOL_RAD",
    "THROUGH_VERTICAL",
    "TOO_SLOW",
    "UPRIGHT_DEG",
    "WAVE",
    "TopEnergyPicture",
    "classify",
    "effective_potential",
    "energy_picture",
]

STEADY = N_("steady precession")
WAVE = N_("wave")
LOOP = N_("loop")
CUSP = N_("cusp")
SLEEPING = N_("sleeping")
TOO_SLOW = N_("too slow to sleep")
THROUGH_VERTICAL = N_("through the vertical")
MOTION_CLASSES = (STEADY, WAVE, LOOP, CUSP, SLEEPING, TOO_SLOW, THROUGH_VERTICAL)

STEADY_TOL_RAD = 1e-6  # θ₂ − θ₁ at most this [rad]: steady precession (1e-6 rad = 6e-5°)
POLE_TOL_RAD = 1e-6  # θ₁ (π − θ₂) at most this [rad]: the axis reaches the pole
CUSP_RTOL = 1e-9  # |p_φ − p_ψ cos θ_k| at most this times |p_φ| + |p_ψ|: φ̇ = 0 at θ_k
UPRIGHT_DEG = 10.0  # [deg] "near the vertical" for sleeping and too-slow tops

_DESCRIPTIONS = {
    STEADY: N_("θ stays put (θ₁ = θ₂): the tip draws a circle."),
    WAVE: N_("θ nods between θ₁ and θ₂ and φ̇ keeps its sign: the tip draws waves."),
    LOOP: N_("φ̇ changes sign between θ₁ and θ₂: the tip draws loops."),
    CUSP: N_("φ̇ = 0 at a turning point: the tip stops there every nod and draws cusps."),
    SLEEPING: N_("the vertical is stable (I3² ω_z′² > 4 I1 mgl) and the axis stays near it."),
    TOO_SLOW: N_("near the vertical, but I3² ω_z′² < 4 I1 mgl: the vertical is unstable and the top falls."),
    THROUGH_VERTICAL: N_("p_φ = ±p_ψ: the axis swings through the vertical (θ = 0 or 180°) every nod."),
}


def effective_potential(I1: float, I3: float, mgl: float, p_phi: float, p_psi: float, theta: ArrayLike) -> Array:
    """U_eff(θ) [J] (module docstring) at θ [rad], scalar or any shape.

    I1, I3 [kg m²] about the pivot, mgl [N m], p_φ = L·e_z and p_ψ = I3 ω_z′ [kg m²/s].  Written
    with s = sin(θ/2), c = cos(θ/2): p_φ − p_ψ cos θ = (p_φ − p_ψ) + 2 p_ψ s² and sin θ = 2 s c, so
    that U_eff stays finite to full precision near a pole that p_φ = ±p_ψ lets the axis reach;
    +inf at a pole it cannot reach.
    """
    theta = np.asarray(theta, dtype=float)
    s, c = np.sin(0.5 * theta), np.cos(0.5 * theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        near_top = ((p_phi - p_psi) / (2.0 * s * c) + p_psi * s / c)  # (p_φ − p_ψ cos θ) / sin θ
        near_bottom = ((p_phi + p_psi) / (2.0 * s * c) - p_psi * c / s)  # the same, from cos θ = 2c² − 1
        ratio = np.where(theta <= 0.5 * np.pi, near_top, near_bottom)
    ratio = np.where(np.isnan(ratio), np.inf, ratio)  # 0/0 at a pole: only where it cannot be reached
    at_top = theta == 0.0
    at_bottom = theta == np.pi
    ratio = np.where(at_top & (p_phi == p_psi), 0.0, ratio)
    ratio = np.where(at_bottom & (p_phi == -p_psi), 0.0, ratio)
    with np.errstate(over="ignore"):  # next to a barrier pole: +inf
        out: Array = 0.5 * ratio * ratio / I1 + 0.5 * p_psi * p_psi / I3 + mgl * np.cos(theta)
    return out


@dataclass(frozen=True)
class TopEnergyPicture:
    """The energy picture of one motion of the heavy symmetric top.

    I1, I3 [kg m²], mgl [N m]; p_phi = L·e_z, p_psi = I3 ω_z′ [kg m²/s]; energy E [J].
    theta_1 ≤ theta_2: the turning points [rad] (the closed form's θ range);
    phi_dot_1, phi_dot_2: φ̇ at them [rad/s] (nan at a pole, where φ̇ is undefined);
    motion: one of MOTION_CLASSES; description: one sentence about it.
    """

    I1: float
    I3: float
    mgl: float
    p_phi: float
    p_psi: float
    energy: float
    theta_1: float
    theta_2: float
    phi_dot_1: float
    phi_dot_2: float
    motion: str
    description: str

    def U_eff(self, theta: ArrayLike) -> Array:
        """U_eff(θ) [J] at θ [rad] (`effective_potential` with this motion's constants)."""
        return effective_potential(self.I1, self.I3, self.mgl, self.p_phi, self.p_psi, theta)

    @property
    def vertical_stable(self) -> bool:
        """The sleeping-top condition I3² ω_z′² = p_ψ² > 4 I1 mgl (with gravity)."""
        return self.mgl > 0.0 and self.p_psi * self.p_psi > 4.0 * self.I1 * self.mgl


def _phi_dot(I1: float, p_phi: float, p_psi: float, theta: float) -> float:
    """φ̇ [rad/s] at θ [rad]; nan at a pole."""
    sin_theta = math.sin(theta)
    if sin_theta == 0.0:
        return math.nan
    return (p_phi - p_psi * math.cos(theta)) / (I1 * sin_theta * sin_theta)


def classify(I1: float, mgl: float, p_phi: float, p_psi: float, theta_1: float, theta_2: float) -> str:
    """The class of motion (one of MOTION_CLASSES; rules and tolerances in the module docstring)
    of a top with these constants whose θ runs in [θ₁, θ₂] [rad]."""
    upright = math.radians(UPRIGHT_DEG)
    stable = mgl > 0.0 and p_psi * p_psi > 4.0 * I1 * mgl
    steady = theta_2 - theta_1 <= STEADY_TOL_RAD
    if mgl > 0.0 and stable and theta_2 < upright:
        return SLEEPING
    if not steady and (theta_1 <= POLE_TOL_RAD or theta_2 >= math.pi - POLE_TOL_RAD):
        return THROUGH_VERTICAL
    if mgl > 0.0 and not stable and theta_1 < upright:
        return TOO_SLOW
    if steady:
        return STEADY
    scale = CUSP_RTOL * (abs(p_phi) + abs(p_psi))
    g1 = p_phi - p_psi * math.cos(theta_1)  # the sign of φ̇ at θ₁ (I1 sin²θ > 0)
    g2 = p_phi - p_psi * math.cos(theta_2)
    if abs(g1) <= scale or abs(g2) <= scale:
        return CUSP
    return WAVE if (g1 > 0.0) == (g2 > 0.0) else LOOP


def energy_picture(I1: float, I3: float, mgl: float, R_space_body: ArrayLike,
                   omega_body: ArrayLike) -> TopEnergyPicture:
    """The energy picture of the motion started at (R_space_body (3, 3), ω_b (3,) [rad/s]).

    The constants and the turning points come from `HeavySymmetricTopExact` (ValueError for
    non-physical input, as there).
    """
    top = HeavySymmetricTopExact(I1, I3, mgl, R_space_body, omega_body)
    theta_1, theta_2 = top.theta_min, top.theta_max
    motion = classify(I1, mgl, top.p_phi, top.p_psi, theta_1, theta_2)
    return TopEnergyPicture(
        I1=I1, I3=I3, mgl=mgl, p_phi=top.p_phi, p_psi=top.p_psi, energy=top.energy,
        theta_1=theta_1, theta_2=theta_2,
        phi_dot_1=_phi_dot(I1, top.p_phi, top.p_psi, theta_1),
        phi_dot_2=_phi_dot(I1, top.p_phi, top.p_psi, theta_2),
        motion=motion, description=_DESCRIPTIONS[motion],
    )
