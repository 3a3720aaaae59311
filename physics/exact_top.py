"""Exact solution of the heavy symmetric (Lagrange) top on a fixed pivot.

The reference every heavy-top integrator is measured against, and the app's exact "ghost".

Conventions (docs/CONVENTIONS.md, docs/CASEFILE.md):

* ``R_space_body`` maps body components to space components, ``x = R x'`` (the memo's D).
  z-x-z Euler angles: ``R = Rz(φ) Rx(θ) Rz(ψ)``.
* Principal moments about the PIVOT: I1 = I2 (transverse), I3 (symmetry axis z').  The centre
  of mass sits on the body +z' axis at distance ℓ; gravity points along space -z, so
  ``V = mgl cos θ = mgl R[2, 2]`` and the torque about the pivot is ``-mgl (e_z' × e_z)``.
* ``omega_body`` is ω_b with ``hat(ω_b) = Rᵀ Ṙ`` (usual sign).
* Conserved: E = ½ ω_b·I ω_b + mgl cos θ, p_φ = L·e_z = I1 φ̇ sin²θ + I3 ω3 cos θ and
  p_ψ = I3 ω3 (ω3 = ω_b[2] is constant).

Method.  u = cos θ obeys u̇² = f(u) = (1 - u²)(α - βu) - (b' - a'u)², a cubic with roots
u1 ≤ u2 ≤ 1 ≤ u3 (β = 2 mgl / I1, a' = p_ψ / I1, b' = p_φ / I1); u oscillates in [u1, u2]:

    u = u1 + (u2 - u1) sn²(τ | m),  τ = λ t + τ0,  m = (u2 - u1) / (u3 - u1),
    λ = √(β (u3 - u1)) / 2.

The attitude is never built from φ and ψ (undefined at θ = 0, π).  It is the unit quaternion
(Cayley-Klein parameters)

    q = (c cos A, s cos B, s sin B, c sin A),  c = cos(θ/2), s = sin(θ/2),
    A = (φ + ψ)/2,  B = (φ - ψ)/2,

whose phases have the regular rates

    2 Ȧ = ω3 - a' + (b' + a') / (1 + u),   2 Ḃ = a' - ω3 + (b' - a') / (1 - u).

(b' + a') vanishes when the axis reaches θ = π, (b' - a') when it reaches θ = 0; then the
phase rate is constant and c (or s) is continued with a sign, c ∝ sn τ (s ∝ cn τ), so a top
passing through the vertical moves smoothly where φ jumps by π.)  The time integrals of
1/(1 ± u) are incomplete elliptic integrals of the third kind, evaluated with Carlson's
R_F, R_J (`scipy.special.elliprf`, `elliprj`) in forms with only positive terms; the integral
of 1/(1 + u) is taken in the variable τ - K so that its characteristic stays in [m, 1].  Time
is reduced modulo the nutation period and whole periods add the complete integrals.

All the small distances that matter, 1 - u2, 1 + u1, u2 - u0, u0 - u1 (and u3 - u2 through
Vieta), are found as roots of the cubic written in the shifted variables ε = 1 - u, δ = 1 + u,
x = u - u0, whose coefficients are computed from the initial state without cancellation, and
the Jacobi functions take the complementary parameter 1 - m, so near-sleeping, near-vertical
and near-separatrix tops keep full relative precision.

Special cases handled exactly: steady precession (u1 = u2, including the sleeping top and a
top hanging straight down), a top started exactly at θ = 0 or π, passage through θ = 0 or π,
mgl = 0 (the free symmetric body), and the separatrix u2 = u3 = 1 (infinite period).

Accuracy (tests/test_exact_top.py): attitude and ω_b within ~1e-14 of a 28-digit Taylor
integration over 5-20 s (also near the separatrix and near a pole); E and p_φ recomputed from
the output drift < 1e-14 relative up to t = 1e4 s.  At large t the error grows like
1e-16 × (accumulated rotation angle |ω| t), the conditioning of the phases themselves:
~1e-11 at 8 rad/s and ~2e-9 at 1000 rad/s after 1e4 s.

Below double-precision scales the model is changed, each time by far less than the rounding of
the data: an axis within 2e-60 rad of a pole starts on it; a pole missed by 1 - u2 < 1e-60 is
passed through; 0 < 1 - m < 1e-60 is raised to 1e-60 (so R_J's arguments stay >= ~1e-121).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import elliprf, elliprj

from physics._types import Array, Mat3, Vec3
from physics.quaternion import matrices_from_wxyz, wxyz_from_matrix
from physics.refusal import N_, Refusal

__all__ = ["HeavySymmetricTopExact", "steady_precession_rate"]

_ORTHO_TOL = 1e-9  # ‖R0ᵀ R0 - 1‖ allowed before R0 is refused (docs/CASEFILE.md)
_LANDEN_MAX_LEVELS = 40
# Below these scales the model is changed by far less than the rounding of the data, so that
# every argument of Carlson's R_J stays >= ~1e-121, where SciPy's elliprj is exact to rounding:
_POLE_PASSAGE = 1e-60  # 1 - u2 (or 1 + u1) below this, p_φ ≠ ±p_ψ: a passage through the pole
_M1_FLOOR = 1e-60  # 0 < 1 - m below this is raised to it (energy moved by ~1e-60 of its scale)
_SNAP_TO_POLE = 1e-60  # sin(θ0/2) (or cos(θ0/2)) below this: the start is put on the pole
_NEAR_POLE = 1e-25  # |sin(θ/2)| (or |cos(θ/2)|) below this: initial phase from the velocity


def steady_precession_rate(I1: float, I3: float, mgl: float, spin: float, theta: float) -> float:
    """The slow steady-precession rate φ̇ [rad/s] of the heavy symmetric top at nutation θ [rad].

    I1 about the pivot, I3 about the symmetry axis [kg m²], mgl [N m], spin = ω_z' = ω_b[2]
    [rad/s] (= φ̇ cos θ + ψ̇).  Steady precession (θ̇ = θ̈ = 0) needs, from Lagrange's equation of
    θ, mgl = φ̇ (I3 ω_z' - I1 φ̇ cos θ), i.e.

        I1 cos θ φ̇² - I3 ω_z' φ̇ + mgl = 0;

    this returns the root that tends to mgl / (I3 ω_z') for a fast top (the slow precession),
    computed without cancellation; at cos θ = 0 the equation is linear.  Started with this φ̇,
    θ̇ = 0 and this spin, the top keeps θ constant.

    Raises:
        ValueError: no real root (the spin is too slow for steady precession at this θ), or a
            non-finite argument, or spin = 0 with cos θ = 0.
    """
    a, b, c = I1 * math.cos(theta), I3 * spin, mgl
    if not all(math.isfinite(v) for v in (a, b, c)):
        raise ValueError(f"arguments must be finite, got I1 = {I1}, I3 = {I3}, mgl = {mgl}, spin = {spin}, θ = {theta}")
    if a == 0.0:
        if b == 0.0:
            raise ValueError(f"no steady precession at θ = {math.degrees(theta):g}° without spin")
        return c / b
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        raise ValueError(f"no steady precession at θ = {math.degrees(theta):g}° with ω_z′ = {spin:g} rad/s")
    q = b + math.copysign(math.sqrt(disc), b)
    if q == 0.0:  # b = 0 and disc = 0: c = 0, the top with no gravity and no spin
        return 0.0
    return 2.0 * c / q  # the small root c/(a x_large) = 2c / (b + sign(b) sqrt(disc))


# --------------------------------------------------------------------------------------------
# Polynomial roots by bisection in a shifted variable (relative precision near the anchor).
# --------------------------------------------------------------------------------------------


def _horner(coeffs: tuple[float, float, float, float]) -> Callable[[float], float]:
    """p(x) = c0 + c1 x + c2 x² + c3 x³ for coeffs = (c0, c1, c2, c3)."""
    c0, c1, c2, c3 = coeffs

    def p(x: float) -> float:
        return c0 + x * (c1 + x * (c2 + x * c3))

    return p


def _sign_right_of_zero(coeffs: tuple[float, float, float, float]) -> float:
    """Sign of the polynomial just right of x = 0: the sign of its first non-zero coefficient."""
    for c in coeffs:
        if c != 0.0:
            return math.copysign(1.0, c)
    return 0.0


def _bisect(p: Callable[[float], float], hi: float, sign_lo: float) -> float:
    """Root of p in (0, hi] where p has sign `sign_lo` just right of 0 and not at hi.

    Plain bisection to the last bit: the root keeps the relative precision with which p can
    be evaluated near it, however close it is to 0 (the anchor of the shifted variable).
    """
    lo = 0.0
    for _ in range(2200):
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            break
        val = p(mid)
        if val == 0.0:
            return mid
        if math.copysign(1.0, val) == sign_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _root_between(
    near: tuple[float, float, float, float], far: tuple[float, float, float, float], width: float
) -> tuple[float, float]:
    """The root of a cubic on [anchor_near, anchor_far], |anchor_far - anchor_near| = width.

    `near` are the coefficients in the variable y measured from the near anchor towards the far
    one (the cubic is ≥ 0 just beyond y = 0 unless the root is the anchor itself); `far` in the
    variable z measured from the far anchor back towards the near one (the cubic is ≤ 0 at
    z = 0).  Returns (y, z) = distances of the root from both anchors, each to full relative
    precision (the smaller one is solved for directly).
    """
    if width == 0.0:
        return 0.0, 0.0
    if _sign_right_of_zero(near) < 0.0:
        return 0.0, width
    half = 0.5 * width
    p_near = _horner(near)
    if p_near(half) <= 0.0:
        y = _bisect(p_near, half, 1.0)
        return y, width - y
    s_far = _sign_right_of_zero(far)
    if s_far > 0.0:  # the cubic vanishes at the far anchor and is positive before it
        return width, 0.0
    p_far = _horner(far)
    if p_far(half) < 0.0:  # rounding disagreement: the root is at the midpoint
        return half, half
    z = _bisect(p_far, half, -1.0)
    return width - z, z


# --------------------------------------------------------------------------------------------
# Jacobi elliptic functions with the complementary parameter m1 = 1 - m given exactly.
# --------------------------------------------------------------------------------------------


def _sncndn_small(u: Array, m: float, m1: float) -> tuple[Array, Array, Array]:
    """sn, cn, dn (u | m) for |u| ≤ K/2, with m1 = 1 - m given exactly.

    Descending Landen transformation applied to the function values (Abramowitz & Stegun
    16.12.2-4), with k = √μ of each level and 1 - k carried separately:

        sn(u|m) = (1 + k) sn(v|μ) / (1 + k sn²),  cn(u|m) = cn(v|μ) dn(v|μ) / (1 + k sn²),
        dn(u|m) = (cn² + (1 - k) sn²) / (1 + k sn²),  v = u / (1 + k),

    down to μ < 1e-18 (sin, cos plus the first-order term of A&S 16.13).  Every step is a
    product or a sum of positive terms, so sn, cn, dn keep their relative precision (about
    K · 1e-16) for any m, also m → 1 where cn(K/2) = √(k'/(1 + k')) is tiny.
    """
    u = np.asarray(u, dtype=float)
    if m == 0.0:
        return np.sin(u), np.cos(u), np.ones_like(u)
    kp = math.sqrt(m1)  # k' of the current level
    m_cur = m
    levels: list[tuple[float, float]] = []  # (k, 1 - k) of the successive levels
    scale = 1.0
    for _ in range(_LANDEN_MAX_LEVELS):
        k_new = m_cur / (1.0 + kp) ** 2  # (1 - k') / (1 + k')
        levels.append((k_new, 2.0 * kp / (1.0 + kp)))
        scale *= 1.0 + k_new
        kp = 2.0 * math.sqrt(kp) / (1.0 + kp)
        m_cur = k_new * k_new
        if k_new < 1e-9:
            break
    v = u / scale
    sn, cn = np.sin(v), np.cos(v)
    corr = 0.25 * m_cur * (v - sn * cn)
    sn, cn = sn - corr * cn, cn + corr * sn
    dn = 1.0 - 0.5 * m_cur * sn * sn
    for k, one_minus_k in reversed(levels):
        s2 = sn * sn
        den = 1.0 + k * s2
        sn, cn, dn = (1.0 + k) * sn / den, cn * dn / den, (cn * cn + one_minus_k * s2) / den
    return sn, cn, dn


def _sncndn_reduced(
    tau_shifted: Array, n0: float, m: float, m1: float, K: float
) -> tuple[Array, Array, Array, Array, Array]:
    """Jacobi functions at τ = n0 K + tau_shifted, reduced to r = τ - 2 K j in [-K, K].

    τ is split as q K + ρ with q an integer and |ρ| ≤ K/2 computed as tau_shifted - (q - n0) K,
    so ρ keeps the relative precision of tau_shifted near the multiple n0 K (a top started
    within a hair of a turning point).  For odd q the shift theorem
    sn(K + ρ) = cn ρ/dn ρ, cn(K + ρ) = -k' sn ρ/dn ρ, dn(K + ρ) = k'/dn ρ is used, so cn r is
    relatively precise near r = ±K as well.

    Returns (j, r_nonneg, sn r, cn r ≥ 0, dn r); sn τ = (-1)^j sn r, cn τ = (-1)^j cn r.
    """
    shift = np.rint(tau_shifted / K)
    rho = tau_shifted - shift * K
    q = shift + n0
    S, C, Dn = _sncndn_small(rho, m, m1)
    odd = np.mod(q, 2.0) == 1.0
    kp = math.sqrt(m1)
    rho_pos = rho > 0.0
    half = np.floor(0.5 * q)
    j = np.where(odd, half + rho_pos, half)
    r_nonneg = np.where(odd, ~rho_pos, rho >= 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        sn_r = np.where(odd, np.where(rho_pos, -C, C) / Dn, S)
        cn_r = np.where(odd, kp * np.abs(S) / Dn, C)
        dn_r = np.where(odd, kp / Dn, Dn)
    return j, r_nonneg, sn_r, cn_r, dn_r


def _carlson_pi(s: Array, c: Array, dn: Array, n: float, p: Array) -> Array:
    """Π(n; φ | m) for |φ| ≤ π/2 from s = sin φ, c = cos φ ≥ 0, dn = √(1 - m s²), p = 1 - n s².

    Π = s R_F(c², dn², 1) + (n/3) s³ R_J(c², dn², 1, p): all terms share the sign of s.
    """
    c2, d2 = c * c, dn * dn
    out = s * elliprf(c2, d2, 1.0)
    if n != 0.0:
        out = out + (n / 3.0) * s**3 * elliprj(c2, d2, 1.0, p)
    return out


# --------------------------------------------------------------------------------------------
# The top.
# --------------------------------------------------------------------------------------------


class HeavySymmetricTopExact:
    """Exact motion of the heavy symmetric top on a fixed pivot (Lagrange top).

    Args:
        I1: transverse principal moment about the pivot (I1 = I2) [kg m^2], > 0.
        I3: principal moment about the symmetry axis z' [kg m^2], > 0.
        mgl: m g ℓ [N m] ≥ 0; mgl = 0 is the free symmetric body (about the pivot).
        R0: (3, 3) R_space_body at t = 0 (orthogonal to 1e-9; it is re-orthonormalised, and
            `self.R0` holds the rotation actually used).
        omega0_body: (3,) ω_b at t = 0 [rad/s], usual sign (hat(ω_b) = Rᵀ Ṙ).

    Raises:
        Refusal (a ValueError, `physics.refusal`): input no top has (its msgid and fields).

    Evaluation is vectorised over times: `attitude(t)`, `omega_body(t)`, `self(t)` (both),
    `cos_theta(t)`, `axis_space(t)` take a scalar or an (N,) array of times [s] (any sign, any
    size; about 2.5 µs per time, construction about 1 ms).

    Attributes for drawing:
        u1, u2: turning points u1 ≤ cos θ(t) ≤ u2.
        theta_min, theta_max: the nutation range [rad], θ_min = arccos u2.
        nutation_period: period of θ(t) [s] (inf on the separatrix; for steady precession
            the small-oscillation limit 2π/√(β (u3 - u1))).
        energy [J], p_phi [kg m^2/s] (= L·e_z), p_psi (= I3 ω3), omega3 [rad/s].
        steady: True when u is constant (steady precession, sleeping or hanging top).
    """

    def __init__(self, I1: float, I3: float, mgl: float, R0: ArrayLike, omega0_body: ArrayLike) -> None:
        I1, I3, mgl = float(I1), float(I3), float(mgl)
        R0a = np.asarray(R0, dtype=float)
        om = np.asarray(omega0_body, dtype=float)
        if not (math.isfinite(I1) and math.isfinite(I3) and I1 > 0.0 and I3 > 0.0):
            raise Refusal(N_("moments must be finite and positive, got I1={I1}, I3={I3}"), I1=I1, I3=I3)
        if not (math.isfinite(mgl) and mgl >= 0.0):
            raise Refusal(N_("mgl must be finite and >= 0, got {mgl}"), mgl=mgl)
        if R0a.shape != (3, 3) or not np.all(np.isfinite(R0a)):
            raise Refusal(N_("R0 must be a finite (3, 3) matrix"))
        if np.linalg.norm(R0a.T @ R0a - np.eye(3)) > _ORTHO_TOL or np.linalg.det(R0a) < 0.0:
            raise Refusal(N_("R0 is not a rotation (orthogonal with det +1 to 1e-9)"))
        if om.shape != (3,) or not np.all(np.isfinite(om)):
            raise Refusal(N_("omega0_body must be a finite (3,) vector"))

        self.I1, self.I3, self.mgl = I1, I3, mgl
        w0, x0, y0, z0 = wxyz_from_matrix(R0a)
        # An axis within 2e-60 rad of a pole is put on it (squares of such tilts underflow).
        if math.hypot(x0, y0) < _SNAP_TO_POLE:
            w0, x0, y0, z0 = w0 / math.hypot(w0, z0), 0.0, 0.0, z0 / math.hypot(w0, z0)
        elif math.hypot(w0, z0) < _SNAP_TO_POLE:
            w0, x0, y0, z0 = 0.0, x0 / math.hypot(x0, y0), y0 / math.hypot(x0, y0), 0.0
        self.R0: Mat3 = matrices_from_wxyz(np.array([w0, x0, y0, z0]))
        self.omega0_body: Vec3 = om.copy()
        om1, om2, om3 = (float(v) for v in om)

        # ---- invariants, in 1/s^2-type units, without cancellation -------------------------
        c0 = math.hypot(w0, z0)  # cos(θ0/2)
        s0 = math.hypot(x0, y0)  # sin(θ0/2)
        eps0 = 2.0 * s0 * s0  # 1 - u0
        del0 = 2.0 * c0 * c0  # 1 + u0
        u0 = (c0 - s0) * (c0 + s0)
        g1 = 2.0 * (x0 * z0 - w0 * y0)  # R[2, 0] = sin θ sin ψ
        g2 = 2.0 * (y0 * z0 + w0 * x0)  # R[2, 1] = sin θ cos ψ
        beta = 2.0 * mgl / I1
        ap = I3 * om3 / I1  # a' = p_ψ / I1
        kperp = om1 * om1 + om2 * om2  # θ̇² + φ̇² sin²θ
        wv = om1 * g1 + om2 * g2  # b' - a' u0 = φ̇ sin²θ
        v0 = g1 * om2 - g2 * om1  # u̇0
        bma = wv - ap * eps0  # b' - a'
        bpa = wv + ap * del0  # b' + a'
        h_top = kperp - beta * eps0  # α - β
        h_bot = kperp + beta * del0  # α + β

        self.omega3 = om3
        self.p_psi = I3 * om3
        self.p_phi = I1 * wv + I3 * om3 * u0
        self.energy = 0.5 * (I1 * kperp + I3 * om3 * om3) + mgl * u0

        # f(u0 + x) = f0 + f1 x + f2 x² + β x³ ; f(1 - ε) ; f(-1 + δ)
        f0 = v0 * v0
        f1 = -2.0 * u0 * kperp - beta * eps0 * del0 + 2.0 * ap * wv
        f2 = -kperp + 2.0 * u0 * beta - ap * ap
        p_mid_up = (f0, f1, f2, beta)
        p_mid_down = (f0, -f1, f2, -beta)  # f(u0 - y)
        p_top = (-bma * bma, 2.0 * (h_top - ap * bma), 2.0 * beta - h_top - ap * ap, -beta)
        p_bot = (-bpa * bpa, 2.0 * (h_bot + ap * bpa), -2.0 * beta - h_bot - ap * ap, beta)

        if f0 == 0.0 and f1 == 0.0:  # u̇0 = ü0 = 0: u ≡ u0 (steady precession / equilibrium)
            x2, e2, y1, e1 = 0.0, eps0, 0.0, del0
        else:
            x2, e2 = _root_between(p_mid_up, p_top, eps0)
            y1, e1 = _root_between(p_mid_down, p_bot, del0)
        d = x2 + y1  # u2 - u1

        # g = β (u3 - u1), g3 = β (u3 - u2) (Vieta on f(1 - ε), no cancellation near u3 = u2)
        if d > 0.0 and e2 + d > 0.0:
            c1 = p_top[1]
            bq3 = (c1 + beta * e2 * (e2 + d)) / (2.0 * e2 + d)  # β (u3 - 1)
            bq3 = max(bq3, 0.0)
            g3 = bq3 + beta * e2
            g = bq3 + beta * (e2 + d)
        else:
            g = max(-f2, 0.0)  # β (u3 - u0) with u1 = u2 = u0
            g3 = g
        if d > 0.0 and g > 0.0 and g3 / g == 0.0 and x2 == 0.0:
            # on the separatrix at its end u = 1 (a kick whose square underflows): the upright
            # equilibrium, which the axis would take infinitely long to leave
            x2, y1, d, e2, e1 = 0.0, 0.0, 0.0, eps0, del0
            g = g3 = max(-f2, 0.0)

        # A pole missed by 1 - u2 < 1e-60 (p_φ ≠ p_ψ) is taken as a passage through it: the
        # error is ~ √(1 - u2) = 1e-30, and Carlson's R_J stays clear of underflow.
        if e2 == 0.0 or (bma != 0.0 and e2 < _POLE_PASSAGE):
            e2, bma = 0.0, 0.0  # the axis reaches θ = 0: s is continued with a sign
        if e1 == 0.0 or (bpa != 0.0 and e1 < _POLE_PASSAGE):
            e1, bpa = 0.0, 0.0  # the axis reaches θ = π: c is continued with a sign
        D = e2 + d  # 1 - u1
        E = e1 + d  # 1 + u2
        # each turning point from its nearest anchor (-1, u0 or +1)
        self.u1 = -1.0 + e1 if e1 < y1 else u0 - y1
        self.u2 = max(self.u1, 1.0 - e2 if e2 < x2 else u0 + x2)
        # θ = 2 atan2(√(1 - u), √(1 + u)): full relative precision near 0 and near π
        self.theta_min = 2.0 * math.atan2(math.sqrt(e2), math.sqrt(e1 + d))
        self.theta_max = 2.0 * math.atan2(math.sqrt(e2 + d), math.sqrt(e1))
        self.steady = d == 0.0

        self._e1, self._e2, self._d, self._D, self._E = e1, e2, d, D, E
        self._bma, self._bpa, self._ap = bma, bpa, ap
        self._signed_c = e1 == 0.0
        self._signed_s = e2 == 0.0

        # ---- elliptic parameters ----------------------------------------------------------
        if d > 0.0 and g > 0.0:
            self._lam = 0.5 * math.sqrt(g)
            self._mu = beta / g  # m = μ d
            m = min(1.0, beta * d / g)
            m1 = max(0.0, min(1.0, g3 / g))
            if m1 == 0.0:
                m = 1.0  # exactly on the separatrix u2 = u3 = 1
            elif m1 < _M1_FLOOR:
                m1 = _M1_FLOOR  # the first return, after ~140/λ s, comes too early
        else:  # steady: any λ > 0 gives the same answer with m = 0
            self._lam, self._mu, m, m1 = 1.0, 0.0, 0.0, 1.0
        self._m, self._m1 = m, m1
        self._separatrix = m1 == 0.0
        if self.steady:
            self.nutation_period = 2.0 * math.pi / math.sqrt(g) if g > 0.0 else math.inf
        elif self._separatrix:
            self.nutation_period = math.inf
        else:
            self._K = float(elliprf(0.0, m1, 1.0))
            self.nutation_period = 2.0 * self._K / self._lam

        # ---- initial phase τ0 of u = u1 + d sn²(τ) -----------------------------------------
        # τ0 = n0 K + δ0 with n0 in {-1, 0, 1}: δ0 keeps its relative precision when the top
        # starts within a hair of a turning point (where the phases of a near-polar passage
        # change on a scale far below ulp(K)).
        sgn_v = 1.0 if v0 >= 0.0 else -1.0
        n0, delta0 = 0.0, 0.0
        if self.steady:
            pass
        elif self._separatrix:  # sn = tanh: sinh² τ0 = (u0 - u1) / (u2 - u0)
            # (x2 > 0: u0 = 1 on the separatrix is the equilibrium, caught above as f0 = f1 = 0)
            delta0 = sgn_v * math.asinh(math.sqrt(y1 / x2))
        else:
            sn2, cn2 = y1 / d, x2 / d
            dn2 = m1 + m * cn2
            if cn2 >= math.sqrt(m1) * sn2:  # |τ0| ≤ K/2 (sn² ≤ 1/(1 + k')): τ0 = F(arcsin √sn2)
                delta0 = sgn_v * math.sqrt(sn2) * float(elliprf(cn2, dn2, 1.0))
            else:  # K - |τ0| = F(arcsin(cn/dn))
                sv = math.sqrt(cn2 / dn2)
                v = sv * float(elliprf(m1 * sn2 / dn2, m1 / dn2, 1.0))
                n0, delta0 = sgn_v, -sgn_v * v
        self._n0, self._delta0 = n0, delta0

        # ---- initial phases A0, B0 ---------------------------------------------------------
        q0dot = 0.5 * np.array([  # q̇ = ½ q ⊗ (0, ω_b)
            -x0 * om1 - y0 * om2 - z0 * om3,
            w0 * om1 + y0 * om3 - z0 * om2,
            w0 * om2 + z0 * om1 - x0 * om3,
            w0 * om3 + x0 * om2 - y0 * om1,
        ])
        self._B_rate = 0.5 * (ap - om3)
        self._A_rate = 0.5 * (om3 - ap)
        self._kB = 0.0
        self._kA = 0.0
        if not self.steady and not self._separatrix:
            K, lam = self._K, self._lam
            if bma != 0.0:
                self._nB = d / D
                self._PicB = K + (self._nB / 3.0) * float(elliprj(0.0, m1, 1.0, e2 / D))
                self._kB = bma / (2.0 * lam * D)
            if bpa != 0.0:
                self._nA = (e1 * m + d) / E
                self._PicA = K + (self._nA / 3.0) * float(elliprj(0.0, m1, 1.0, e1 * m1 / E))
                self._kA = bpa * m1 / (2.0 * lam * E * (1.0 + self._mu * e1))
                self._A_rate += 0.5 * bpa * self._mu / (1.0 + self._mu * e1)
        elif self._separatrix and bpa != 0.0:
            self._kA = bpa / (2.0 * self._lam)
        elif self.steady:  # u ≡ u0: 1 + u = e1, 1 - u = e2
            if bpa != 0.0:
                self._A_rate += 0.5 * bpa / e1
            if bma != 0.0:
                self._B_rate += 0.5 * bma / e2
        self._A0 = 0.0
        self._B0 = 0.0
        self._PhiA0 = 0.0
        self._PhiB0 = 0.0
        st0 = self._state(np.array([0.0]))
        c_f, s_f, cdot_f, sdot_f = st0["c"][0], st0["s"][0], st0["cdot"][0], st0["sdot"][0]
        self._PhiA0 = float(st0["PhiA"][0])
        self._PhiB0 = float(st0["PhiB"][0])
        # The phase from the position (x, y) = s (cos B, sin B); for a signed s within 1e-25 of
        # the pole, from the velocity (ẋ, ẏ) ≈ ṡ (cos B, sin B) instead: there a pole missed by
        # < 1e-50 and taken as a passage leaves its miss distance in the position only.
        if c_f != 0.0 and (not self._signed_c or abs(c_f) >= _NEAR_POLE):
            sg = math.copysign(1.0, c_f)
            self._A0 = math.atan2(sg * z0, sg * w0)
        elif cdot_f != 0.0:
            sg = math.copysign(1.0, cdot_f)
            self._A0 = math.atan2(sg * q0dot[3], sg * q0dot[0])
        if s_f != 0.0 and (not self._signed_s or abs(s_f) >= _NEAR_POLE):
            sg = math.copysign(1.0, s_f)
            self._B0 = math.atan2(sg * y0, sg * x0)
        elif sdot_f != 0.0:
            sg = math.copysign(1.0, sdot_f)
            self._B0 = math.atan2(sg * q0dot[2], sg * q0dot[1])

    # ----------------------------------------------------------------------------------------

    def _state(self, t: Array) -> dict[str, Array]:
        """c, s (cos, sin θ/2, signed where continued), their rates, u, and the phase integrals."""
        lam, d, e1, e2 = self._lam, self._d, self._e1, self._e2
        m, m1 = self._m, self._m1
        tau_shifted = lam * t + self._delta0  # τ - n0 K
        zero = np.zeros_like(t)
        if self.steady:
            sn, cn, dn = zero, np.ones_like(t), np.ones_like(t)
            PhiA, PhiB = zero, zero
        elif self._separatrix:
            tau = tau_shifted
            ex = np.exp(-2.0 * np.abs(tau))  # sech τ without overflow for large |τ|
            sn, cn = np.tanh(tau), 2.0 * np.sqrt(ex) / (1.0 + ex)
            dn = cn
            PhiB = zero
            if self._kA != 0.0:
                rho = math.sqrt(d / e1)
                PhiA = (tau + rho * np.arctan(rho * sn)) / (e1 + d)
            else:
                PhiA = zero
        else:
            j, r_pos, sn_r, cn_r, dn = _sncndn_reduced(tau_shifted, self._n0, m, m1, self._K)
            parity = 1.0 - 2.0 * np.mod(j, 2.0)
            sn, cn = parity * sn_r, parity * cn_r
            if self._kB != 0.0:
                pB = (e2 + d * cn_r * cn_r) / self._D
                PhiB = 2.0 * j * self._PicB + _carlson_pi(sn_r, cn_r, dn, self._nB, pB)
            else:
                PhiB = zero
            if self._kA != 0.0:
                # σ = τ - K: sn σ = -sgn(r) cn r/dn r, cn σ = k'|sn r|/dn r, dn σ = k'/dn r
                kp = math.sqrt(m1)
                jA = np.where(r_pos, j, j - 1.0)
                sA = np.where(r_pos, -cn_r, cn_r) / dn
                cA = kp * np.abs(sn_r) / dn
                dA = kp / dn
                pA = (e1 * dA * dA + d * cA * cA) / self._E
                PhiA = 2.0 * jA * self._PicA + _carlson_pi(sA, cA, dA, self._nA, pA)
            else:
                PhiA = zero
        lam_d = lam * d
        half_d = math.sqrt(0.5 * d)
        snd = sn * cn * dn
        if self._signed_c:
            c = half_d * sn
            cdot = half_d * lam * cn * dn
        else:
            c = np.sqrt(0.5 * (e1 + d * sn * sn))
            cdot = lam_d * snd / (2.0 * c)
        if self._signed_s:
            s = half_d * cn
            sdot = -half_d * lam * sn * dn
        else:
            s = np.sqrt(0.5 * (e2 + d * cn * cn))
            sdot = -lam_d * snd / (2.0 * s)
        return {"c": c, "s": s, "cdot": cdot, "sdot": sdot, "PhiA": PhiA, "PhiB": PhiB,
                "sn2": sn * sn, "cn2": cn * cn}

    def _quaternion(self, t: Array) -> tuple[Array, Array, Array, Array, dict[str, Array]]:
        st = self._state(t)
        A = self._A0 + self._A_rate * t + self._kA * (st["PhiA"] - self._PhiA0)
        B = self._B0 + self._B_rate * t + self._kB * (st["PhiB"] - self._PhiB0)
        cA, sA, cB, sB = np.cos(A), np.sin(A), np.cos(B), np.sin(B)
        c, s = st["c"], st["s"]
        st["cosA"], st["sinA"], st["cosB"], st["sinB"] = cA, sA, cB, sB
        return c * cA, s * cB, s * sB, c * sA, st

    @staticmethod
    def _times(t: ArrayLike) -> tuple[Array, bool]:
        ta = np.asarray(t, dtype=float)
        if ta.ndim > 1:
            raise ValueError("t must be a scalar or a 1-D array of times [s]")
        return np.atleast_1d(ta), ta.ndim == 0

    def cos_theta(self, t: ArrayLike) -> Array:
        """u = cos θ = R[2, 2] at time(s) t [s]: scalar or (N,); in [u1, u2]."""
        ta, scalar = self._times(t)
        st = self._state(ta)
        one_minus = self._e2 + self._d * st["cn2"]
        one_plus = self._e1 + self._d * st["sn2"]
        u = np.where(one_minus < one_plus, 1.0 - one_minus, one_plus - 1.0)
        return u[0] if scalar else u

    def attitude(self, t: ArrayLike) -> Array:
        """R_space_body at time(s) t [s]: (3, 3) for scalar t, (N, 3, 3) for t of shape (N,)."""
        ta, scalar = self._times(t)
        w, x, y, z, _ = self._quaternion(ta)
        R = matrices_from_wxyz(np.stack([w, x, y, z], axis=-1))
        return R[0] if scalar else R

    def omega_body(self, t: ArrayLike) -> Array:
        """ω_b [rad/s] (usual sign) at time(s) t [s]: (3,) or (N, 3)."""
        return self(t)[1]

    def axis_space(self, t: ArrayLike) -> Array:
        """Symmetry axis e_z' in space components (the tip path on the unit sphere): (3,) or (N, 3)."""
        R = self.attitude(t)
        return R[..., :, 2]

    def __call__(self, t: ArrayLike) -> tuple[Array, Array]:
        """(R_space_body, ω_b) at time(s) t [s]: ((3, 3), (3,)) or ((N, 3, 3), (N, 3))."""
        ta, scalar = self._times(t)
        w, x, y, z, st = self._quaternion(ta)
        c, s = st["c"], st["s"]
        cA, sA, cB, sB = st["cosA"], st["sinA"], st["cosB"], st["sinB"]
        # c Ȧ and s Ḃ written so that nothing divides by a vanishing c or s
        half_w = 0.5 * (self.omega3 - self._ap)
        c_safe = np.where(c == 0.0, 1.0, c)
        s_safe = np.where(s == 0.0, 1.0, s)
        cAdot = half_w * c + (0.0 if self._bpa == 0.0 else 0.25 * self._bpa / c_safe)
        sBdot = -half_w * s + (0.0 if self._bma == 0.0 else 0.25 * self._bma / s_safe)
        cdot, sdot = st["cdot"], st["sdot"]
        wd = cdot * cA - cAdot * sA
        zd = cdot * sA + cAdot * cA
        xd = sdot * cB - sBdot * sB
        yd = sdot * sB + sBdot * cB
        # ω_b = 2 vec(q̄ ⊗ q̇) / |q|²
        n2 = w * w + x * x + y * y + z * z
        o1 = 2.0 * (w * xd - wd * x - (y * zd - z * yd)) / n2
        o2 = 2.0 * (w * yd - wd * y - (z * xd - x * zd)) / n2
        omega = np.stack([o1, o2, np.full_like(o1, self.omega3)], axis=-1)
        R = matrices_from_wxyz(np.stack([w, x, y, z], axis=-1))
        if scalar:
            return R[0], omega[0]
        return R, omega
