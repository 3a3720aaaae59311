"""Exact torque-free motion of a rigid body: the reference ("ghost") for every integrator.

Conventions (docs/CONVENTIONS.md): ``x_space = R_space_body @ x_body``; ``hat(ω_b) = Rᵀ Ṙ``;
Euler's equations ``I ω̇_b = (I ω_b) × ω_b``; ``L_space = R I ω_b`` and ``2T = ω_b · I ω_b``
are conserved.  Times in [s], rates in [rad/s], moments in [kg m^2].

Method (the approach of Celledoni, Fassò, Säfström, Zanna, SIAM J. Sci. Comput. 30 (2008)
2084; every sign re-derived here and checked by tests/test_exact_free.py):

1. Body axes are relabelled (p, q, r) so that the elliptic parameter m is in [0, 1]: with
   D = |L|² - 2T I_mid (summed exactly, in rationals), r is the largest axis if D > 0 and the
   smallest if D < 0; p is the other extreme and q the intermediate axis.  The right-handed
   body frame B = [s_p e_p, ±e_q, s_r e_r] makes ω_z > 0 and ω_x(0) ≥ 0.  In B,
       ω = (A_p cn u, σ A_q sn u, A_r dn u),   u = λ t + u0,
   σ = +1 if r is the largest axis, -1 if it is the smallest.
2. The attitude is written with z-x-z angles about the fixed direction of L_space:
       R(t) = S · Rz(φ(t)) Rx(θ(t)) Rz(ψ(t)) · Bᵀ,    S = R0 B (Rx(θ0) Rz(ψ0))ᵀ,
   where θ, ψ give the direction of L in the body (algebraic in sn, cn, dn) and the angle of
   precession about L obeys
       φ̇ = |L| (I_p ω_x² + I_q ω_y²) / (L_x² + L_y²)
         = |L|/I_r + |L| (I_r - I_p)/(I_r I_p) / (1 - ν sn²u),
       ν = I_r (I_q - I_p) / (I_p (I_q - I_r)) ≤ 0,
   i.e. an incomplete elliptic integral of the third kind ∫ du/(1 - ν sn²u), evaluated with
   Carlson's R_J in forms free of cancellation (`_ThirdKind`).
3. Long times: u is reduced to r = u - 2jK in [-K, K] (j whole half periods of ω_b); each
   whole half period adds the same precession (accumulated as j Δφ mod 2π), and the growing
   part of φ is reduced mod 2π, so the phases never lose precision.
   On the separatrix (m = 1 exactly) the functions are tanh/sech and ∫ is elementary.
   Steady rotations (ω_b an eigenvector of I, or 0) are R0 exp(t hat(ω_b)).

Jacobi's sn, cn, dn (`jacobi_sn_cn_dn`) use the descending Landen (Gauss) transformation
written in the ratios sc = sn/cn and cs = cn/sn, with the complementary parameter m1 = 1 - m
as input: cn and dn keep their relative accuracy for m → 1, where ``scipy.special.ellipj``
does not (scipy issue 8480).

Known limits: when λ is tiny compared with |L|/I (ω_b nearly frozen, e.g. nearly symmetric
bodies spinning near the degenerate plane) the attitude error grows to ~1e-16 |L|/(I λ) rad.
Components of ω_b(0) below 1e-145 |ω_b(0)| are treated as 0 and |D|/|L|² below ~1e-290 as
exactly on the separatrix: near the intermediate axis this changes the motion only after
~330/λ seconds, the time such a perturbation needs to grow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from scipy.special import elliprf, elliprj

from physics._types import Array, Mat3, Vec3

__all__ = [
    "FreeBodyExact",
    "elliptic_k",
    "jacobi_amplitude",
    "jacobi_sn_cn_dn",
    "jacobi_third_kind",
]

# Stop the Landen descent when k < 1e-9: then m < 1e-18 and sn = sin, cn = cos to rounding.
_LANDEN_STOP = 1e-9
_MAX_LANDEN_LEVELS = 64


# ----------------------------------------------------------------------------------------------
# Jacobi elliptic functions
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Landen:
    """Descending Landen sequence for one parameter m = k² (0 ≤ m < 1).

    levels[i] = (k_i, 1 - k_i, 1 + k_i) for i = 1..N, with k_{i+1} = (1 - k_i')/(1 + k_i');
    scale = Π (1 + k_i) so that K(m) = (π/2) · scale (to O(k_N²) < 1e-18); m_last = k_N².
    """

    levels: tuple[tuple[float, float, float], ...]
    scale: float
    m_last: float
    K: float


def _landen(m: float, m1: float) -> _Landen:
    """Landen sequence from m and m1 = 1 - m (both given so that m → 1 keeps its precision)."""
    if not (0.0 <= m <= 1.0 and 0.0 < m1 <= 1.0):
        raise ValueError(f"need 0 <= m < 1 with m1 = 1 - m > 0, got m={m!r}, m1={m1!r}")
    k, kp = math.sqrt(m), math.sqrt(m1)
    levels: list[tuple[float, float, float]] = []
    scale = 1.0
    while k > _LANDEN_STOP:
        if len(levels) >= _MAX_LANDEN_LEVELS:  # pragma: no cover - cannot happen for m1 > 0
            raise RuntimeError("Landen descent did not converge")
        # k_next = (1 - k')/(1 + k') written without the cancellation in 1 - k'.
        k_next = (k / (1.0 + kp)) ** 2
        one_minus = 2.0 * kp / (1.0 + kp)
        one_plus = 2.0 / (1.0 + kp)
        kp = 2.0 * math.sqrt(kp) / (1.0 + kp)
        k = k_next
        levels.append((k_next, one_minus, one_plus))
        scale *= one_plus
    m_last = k * k
    K = 0.5 * math.pi * scale * (1.0 + 0.25 * m_last)
    return _Landen(tuple(levels), scale, m_last, K)


def _parameters(m: float, m1: float | None) -> tuple[float, float]:
    """(m, m1) with m1 = 1 - m; m1 (if given) is the accurate one."""
    if m1 is None:
        m = float(m)
        m1 = 1.0 - m
    else:
        m1 = float(m1)
        m = 1.0 - m1
    if not (0.0 <= m <= 1.0) or m1 < 0.0:
        raise ValueError(f"Jacobi parameter m must be in [0, 1], got m={m!r}, m1={m1!r}")
    return m, m1


def elliptic_k(m: float, m1: float | None = None) -> float:
    """Complete elliptic integral K(m) (parameter m = k², 0 ≤ m < 1) by the Landen/AGM product.

    Give ``m1 = 1 - m`` instead of m when m is close to 1 (then m is ignored).
    """
    m, m1 = _parameters(m, m1)
    if m1 == 0.0:
        return math.inf
    return _landen(m, m1).K


def _sn_cn_dn_half(u: Array, K_minus_u: Array, ld: _Landen) -> tuple[Array, Array, Array]:
    """sn, cn, dn for 0 ≤ u ≤ K.  ``K_minus_u`` = K - u, given separately so that cn keeps its
    precision near u = K.  Gauss/Landen recursion in sc = sn/cn (u ≤ K/2) and cs = cn/sn
    (u > K/2): only products, quotients and sums of positive terms, hence cn and dn are
    accurate relative to themselves for every m < 1."""
    low = u <= K_minus_u  # u <= K/2
    u_N = np.where(low, u, K_minus_u) / ld.scale  # argument at the bottom level, in [0, π/4]
    x = np.tan(u_N)  # sc (low) or cs (high) at the bottom level, where sn = sin, cn = cos
    s_N2 = np.where(low, np.sin(u_N) ** 2, np.cos(u_N) ** 2)  # sn² at the bottom level
    d = 1.0 - 0.5 * ld.m_last * s_N2
    for _k_i, one_minus, one_plus in reversed(ld.levels):
        x2 = x * x
        # sc(z,k) = (1+k1) sc1/dn1,  dn = (1 + (1-k1) sc1²)/(1 + (1+k1) sc1²)
        x_low = one_plus * x / d
        d_low = (1.0 + one_minus * x2) / (1.0 + one_plus * x2)
        # cs(z,k) = cs1 dn1/(1+k1),  dn = (cs1² + (1-k1))/(cs1² + (1+k1))
        x_high = x * d / one_plus
        d_high = (x2 + one_minus) / (x2 + one_plus)
        x = np.where(low, x_low, x_high)
        d = np.where(low, d_low, d_high)
    inv = 1.0 / np.hypot(1.0, x)
    sn = np.where(low, x * inv, inv)
    cn = np.where(low, inv, x * inv)
    return sn, cn, d


def _sech(u: Array) -> Array:
    """1/cosh(u) without overflow."""
    e = np.exp(-np.abs(u))
    return 2.0 * e / (1.0 + e * e)


def _jacobi_reduced(
    u: Array, m: float, m1: float, ld: _Landen | None
) -> tuple[Array, Array, Array, Array]:
    """(sn, cn, dn, j) with u = r + 2jK, |r| ≤ K; sn, cn returned for u (signs included)."""
    u = np.asarray(u, dtype=float)
    if ld is None:  # m = 1: no period
        return np.tanh(u), _sech(u), _sech(u), np.zeros_like(u)
    K = ld.K
    j = np.round(u / (2.0 * K))
    r = u - j * (2.0 * K)
    a = np.abs(r)
    sn, cn, dn = _sn_cn_dn_half(a, K - a, ld)
    parity = 1.0 - 2.0 * np.mod(j, 2.0)  # (-1)^j
    return np.sign(r) * sn * parity, cn * parity, dn, j


def jacobi_sn_cn_dn(
    u: float | Array, m: float, m1: float | None = None
) -> tuple[Array, Array, Array]:
    """Jacobi elliptic functions sn(u|m), cn(u|m), dn(u|m) for real u, 0 ≤ m ≤ 1.

    Args:
        u: argument, any shape.
        m: parameter m = k² (scipy's convention).
        m1: complementary parameter 1 - m; give it (instead of m) near m = 1, where m itself
            cannot hold the distance to 1.  If given, m is ignored.
    Returns:
        (sn, cn, dn), each of u's shape.  Absolute error ~1e-16; cn and dn also keep their
        relative accuracy where they are small (m → 1, u → K).  m = 1: tanh, sech, sech.
    """
    m, m1 = _parameters(m, m1)
    ld = None if m1 == 0.0 else _landen(m, m1)
    sn, cn, dn, _ = _jacobi_reduced(np.asarray(u, dtype=float), m, m1, ld)
    return sn, cn, dn


def jacobi_amplitude(u: float | Array, m: float, m1: float | None = None) -> Array:
    """Amplitude am(u|m) [rad], continuous in u: sn = sin am, cn = cos am, am(u + 2K) = am(u) + π.

    m = 1: the Gudermannian gd(u) = 2 atan(tanh(u/2)).  Arguments as `jacobi_sn_cn_dn`.
    """
    m, m1 = _parameters(m, m1)
    u = np.asarray(u, dtype=float)
    if m1 == 0.0:
        return 2.0 * np.arctan(np.tanh(0.5 * u))
    ld = _landen(m, m1)
    sn, cn, _, j = _jacobi_reduced(u, m, m1, ld)
    parity = 1.0 - 2.0 * np.mod(j, 2.0)
    return np.arctan2(sn * parity, cn * parity) + j * math.pi


# ----------------------------------------------------------------------------------------------
# The incomplete elliptic integral of the third kind, in Jacobi's argument u
# ----------------------------------------------------------------------------------------------


_TINY_COMPONENT = 1e-145  # relative size of ω_b components treated as zero
_M1_SEPARATRIX = 1e-290  # below this 1 - m, the free body is taken to be on the separatrix
_SHIFT_BELOW_M1 = 1e-100  # below this m1, P(u > K/2) is evaluated at v = K - u (see _ThirdKind)


class _ThirdKind:
    """P(u) = ∫_0^u du' / (1 - ν sn²(u'|m)) for ν ≤ 0, 0 ≤ u ≤ K, written P = lin·u + rest.

    Forms without cancellation (R_J: Carlson's integral, scipy.special.elliprj):
    * |ν| ≤ √m (direct):        P = u + (ν/3) sn³ R_J(cn², dn², 1, 1 - ν sn²).
    * |ν| > √m (n ↔ m/n):       with n' = m/ν, q = √((1-ν)(1-n')),
          1/(1-ν sn²) + 1/(1-n' sn²) - 1 = d/du [atan(q sn/(cn dn))/q], so
          P = -(n'/3) sn³ R_J(cn², dn², 1, 1 - n' sn²) + atan2(q sn, cn dn)/q   (lin = 0).
      Both are sums of terms of one sign; the second keeps P's relative accuracy when |ν| ≫ 1
      (then P ≪ u and the direct form would cancel).
    * m1 < 1e-100 and u > K/2: scipy's R_J fails when two arguments are < ~1e-155, and cn², dn²
      are ~m1 near u = K.  With v = K - u, sn(K - v) = cd v and μ = -ν:
          P = P_c - [v + μ m1 S/(3(1+μ))]/(1+μ),  S = sn³v R_J(cn²v, dn²v, 1, cn²v + m1 sn²v/(1+μ)),
      whose R_J arguments stay ≥ √m1/2.
    Splitting off lin·u lets a caller form P(u) - P(u0) = lin (u - u0) + ... without losing
    the small difference u - u0 = λ t when λ is tiny.
    """

    def __init__(self, nu: float, m: float, m1: float, ld: _Landen) -> None:
        if nu > 0.0:
            raise ValueError(f"characteristic nu must be <= 0, got {nu}")
        self.nu, self.m, self.m1, self.K = nu, m, m1, ld.K
        self.reciprocal = nu != 0.0 and -nu > math.sqrt(m)
        # complete = P(K); excess_low/high = P(K) - lin K in each branch (computed without
        # cancellation), the part of the complete integral not carried by lin·u.
        if nu == 0.0:
            self.complete, self.excess_low = ld.K, 0.0
        elif self.reciprocal:
            n_r = m / nu
            self.n_r, self.q = n_r, math.sqrt((1.0 - nu) * (1.0 - n_r))
            rj = float(elliprj(0.0, m1, 1.0, 1.0 - n_r))
            self.complete = -n_r / 3.0 * rj + 0.5 * math.pi / self.q
            self.excess_low = self.complete
        else:
            self.excess_low = nu / 3.0 * float(elliprj(0.0, m1, 1.0, 1.0 - nu))
            self.complete = ld.K + self.excess_low
        self.shift = nu != 0.0 and m1 < _SHIFT_BELOW_M1
        self.excess_high = self.complete - ld.K / (1.0 - nu)

    def parts(
        self, a: Array, K_minus_a: Array, sn: Array, cn: Array, dn: Array
    ) -> tuple[Array, Array, Array]:
        """(lin, rest, excess) with P(a) = lin·a + rest and excess = P(K) - lin·K, for
        0 ≤ a ≤ K, given K - a and the Jacobi functions at a (all (N,))."""
        nu = self.nu
        if nu == 0.0:
            return np.ones_like(a), np.zeros_like(a), np.zeros_like(a)
        low = a <= K_minus_a if self.shift else np.ones(a.shape, dtype=bool)
        lin, rest = np.empty_like(a), np.empty_like(a)
        excess = np.where(low, self.excess_low, self.excess_high)
        if np.any(low):
            s, c, d = sn[low], cn[low], dn[low]
            s2 = s * s
            if self.reciprocal:
                rj = elliprj(c * c, d * d, 1.0, 1.0 - self.n_r * s2)
                lin[low] = 0.0
                rest[low] = -self.n_r / 3.0 * s2 * s * rj + np.arctan2(self.q * s, c * d) / self.q
            else:
                lin[low] = 1.0
                rest[low] = nu / 3.0 * s2 * s * elliprj(c * c, d * d, 1.0, 1.0 - nu * s2)
        high = ~low
        if np.any(high):
            s, c, d = sn[high], cn[high], dn[high]
            kp = math.sqrt(self.m1)
            sv, cv, dv = c / d, kp * s / d, kp / d  # sn, cn, dn at v = K - a
            mu = -nu
            S = sv**3 * elliprj(cv * cv, dv * dv, 1.0, cv * cv + self.m1 * sv * sv / (1.0 + mu))
            lin[high] = 1.0 / (1.0 + mu)
            rest[high] = self.excess_high - mu * self.m1 * S / (3.0 * (1.0 + mu) ** 2)
        return lin, rest, excess

    def __call__(self, a: Array, K_minus_a: Array, sn: Array, cn: Array, dn: Array) -> Array:
        """P(a) for 0 ≤ a ≤ K."""
        lin, rest, _ = self.parts(a, K_minus_a, sn, cn, dn)
        return lin * a + rest


def _pi_separatrix_parts(u: Array, nu: float) -> tuple[float, Array]:
    """m = 1: ∫_0^u du'/(1 - ν tanh²u') = (u + √μ atan(√μ tanh u))/(1 + μ), μ = -ν ≥ 0,
    returned as (lin, rest) with the integral = lin·u + rest."""
    mu = -nu
    rt = math.sqrt(mu)
    return 1.0 / (1.0 + mu), rt * np.arctan(rt * np.tanh(u)) / (1.0 + mu)


def _pi_separatrix(u: Array, nu: float) -> Array:
    lin, rest = _pi_separatrix_parts(u, nu)
    return lin * u + rest


def jacobi_third_kind(u: float | Array, nu: float, m: float, m1: float | None = None) -> Array:
    """∫_0^u du' / (1 - ν sn²(u'|m)) for real u and ν ≤ 0, i.e. Legendre's Π(ν; am u | m).

    Quasi-periodic: value(u + 2K) = value(u) + 2 value(K).  Arguments m, m1 as
    `jacobi_sn_cn_dn`; m = 1 uses the elementary closed form.
    """
    m, m1 = _parameters(m, m1)
    u = np.asarray(u, dtype=float)
    if nu > 0.0:
        raise ValueError(f"characteristic nu must be <= 0, got {nu}")
    if m1 == 0.0:
        return _pi_separatrix(u, nu)
    ld = _landen(m, m1)
    P3 = _ThirdKind(nu, m, m1, ld)
    flat = u.reshape(-1)
    j = np.round(flat / (2.0 * ld.K))
    r = flat - j * (2.0 * ld.K)
    a = np.abs(r)
    sn, cn, dn = _sn_cn_dn_half(a, ld.K - a, ld)
    P = np.sign(r) * P3(a, ld.K - a, sn, cn, dn) + 2.0 * j * P3.complete
    return P.reshape(u.shape)


# ----------------------------------------------------------------------------------------------
# The free rigid body
# ----------------------------------------------------------------------------------------------


def _matrix_zxz(phi: Array, c2: Array, s2: Array, c3: Array, s3: Array) -> Array:
    """Rz(φ) Rx(θ) Rz(ψ), vectorised: φ (N,), (cos θ, sin θ, cos ψ, sin ψ) (N,) -> (N, 3, 3).

    Same matrix as `physics.euler.matrix_from_euler_zxz` (docs/CONVENTIONS.md (1.13))."""
    c1, s1 = np.cos(phi), np.sin(phi)
    M = np.empty(phi.shape + (3, 3))
    M[..., 0, 0] = c1 * c3 - s1 * c2 * s3
    M[..., 0, 1] = -c1 * s3 - s1 * c2 * c3
    M[..., 0, 2] = s1 * s2
    M[..., 1, 0] = s1 * c3 + c1 * c2 * s3
    M[..., 1, 1] = -s1 * s3 + c1 * c2 * c3
    M[..., 1, 2] = -c1 * s2
    M[..., 2, 0] = s2 * s3
    M[..., 2, 1] = s2 * c3
    M[..., 2, 2] = c2
    return M


def _sandwich(S: Mat3, M: Array, T: Mat3) -> Array:
    """S @ M[n] @ T for every n: (3, 3), (N, 3, 3), (3, 3) -> (N, 3, 3), as two BLAS products."""
    n = M.shape[0]
    MT = (M.reshape(n * 3, 3) @ T).reshape(n, 3, 3)
    return (S @ MT.transpose(1, 0, 2).reshape(3, n * 3)).reshape(3, n, 3).transpose(1, 0, 2)


def _rotation_about(axis: Vec3, angle: Array) -> Array:
    """exp(angle hat(axis)) for a unit axis (3,) and angles (N,) [rad] -> (N, 3, 3) (Rodrigues)."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s = np.sin(angle)[..., None, None]
    h = np.sin(0.5 * angle)[..., None, None]
    R: Array = np.eye(3) + s * K + (2.0 * h * h) * (K @ K)
    return R


class FreeBodyExact:
    """Exact torque-free motion.

    inertia: principal moments (3,) [kg m^2] in body axes x', y', z' (any order, any of them may
    be equal; flat lamina allowed); R0: (3, 3) R_space_body at t = 0; omega0_body: (3,) [rad/s].

    ``omega_body(t)``, ``attitude(t)`` and ``__call__(t)`` take t [s] as a float (-> (3,),
    (3, 3)) or an array of shape (N,) (-> (N, 3), (N, 3, 3)); negative times are allowed.

    Attributes (read-only, for display and tests):
        m: elliptic parameter in [0, 1] (0 for steady rotation; 1 on the separatrix).
        omega_period: period [s] of ω_b(t) (inf on the separatrix, 0 when ω_b is constant).
        L_space: (3,) conserved angular momentum in space [kg m^2/s].
        energy: conserved kinetic energy T [J].
    """

    def __init__(self, inertia: Vec3, R0: Mat3, omega0_body: Vec3) -> None:
        inertia = np.asarray(inertia, dtype=float).reshape(3)
        R0 = np.asarray(R0, dtype=float).reshape(3, 3)
        omega0 = np.asarray(omega0_body, dtype=float).reshape(3)
        if not np.all(np.isfinite(inertia)) or np.any(inertia <= 0.0):
            raise ValueError(f"principal moments must be positive and finite, got {inertia}")
        Ia, Ib, Ic = np.sort(inertia)
        if Ia + Ib < Ic * (1.0 - 1e-12):
            raise ValueError(
                f"moments {inertia} break the triangle inequality I1 + I2 >= I3: not a body"
            )
        if not np.all(np.isfinite(R0)) or not np.all(np.isfinite(omega0)):
            raise ValueError("R0 and omega0_body must be finite")
        if np.max(np.abs(R0.T @ R0 - np.eye(3))) > 1e-9 or np.linalg.det(R0) < 0.0:
            raise ValueError("R0 must be a rotation matrix (orthogonal, det +1)")

        self.inertia: Vec3 = inertia
        self.R0: Mat3 = R0
        self.omega0_body: Vec3 = omega0
        self.L_space: Vec3 = R0 @ (inertia * omega0)
        self.energy: float = 0.5 * float(omega0 @ (inertia * omega0))

        order = np.argsort(inertia, kind="stable")
        a, b, c = (int(i) for i in order)
        I = inertia
        # Components below 1e-145 |ω| are dropped: they would matter only after ~330/λ s (near
        # the intermediate axis) and their squares leave the floating-point range.
        w = np.where(np.abs(omega0) < _TINY_COMPONENT * np.max(np.abs(omega0)), 0.0, omega0)
        # D = |L|² - 2T I_b (the b term is exactly zero), in exact rational arithmetic on the
        # given floats: near the separatrix D is a small difference and m1 = 1 - m ∝ D.
        Fa, Fb, Fc = (Fraction(float(x)) for x in (I[a], I[b], I[c]))
        D_exact = (
            Fa * (Fa - Fb) * Fraction(float(w[a])) ** 2
            + Fc * (Fc - Fb) * Fraction(float(w[c])) ** 2
        )
        separatrix = D_exact == 0 and I[a] < I[b] < I[c] and w[a] != 0.0 and w[c] != 0.0
        self._steady = bool(D_exact == 0 and not separatrix) or not np.any(w != 0.0)
        if self._steady:
            self._init_steady()
            return

        if D_exact >= 0:
            r, p, q, sigma = c, a, b, 1.0
        else:
            r, p, q, sigma = a, c, b, -1.0

        # Work with ω scaled to O(1); rates are multiplied back by `scale`.
        scale = float(np.max(np.abs(w)))
        ws = w / scale
        Ip, Iq, Ir = I[p], I[q], I[r]

        def G_minus_2T(Ik: float) -> float:
            """|L|² - 2T I_k = Σ I_i (I_i - I_k) ω_i² (no cancellation when I_k is extreme)."""
            return float(np.sum(I * (I - Ik) * ws**2))

        g_r, g_p = G_minus_2T(Ir), G_minus_2T(Ip)
        g_q = float(D_exact / Fraction(scale) ** 2)
        A_p = math.sqrt(g_r / (Ip * (Ip - Ir)))
        A_q = math.sqrt(g_r / (Iq * (Iq - Ir)))
        A_r = math.sqrt(g_p / (Ir * (Ir - Ip)))
        lam = math.sqrt((Ir - Iq) * g_p / (Ip * Iq * Ir))
        if lam == 0.0:
            # Only when the deviation from a steady rotation underflows (e.g. ω = (0, 1, 1e-285)
            # on a symmetric body): ω_b changes at a rate below 1e-300 rad/s², treat as steady.
            self._steady = True
            self._init_steady()
            return
        m1 = min(1.0, max(0.0, g_q * (Ir - Ip) / ((Ir - Iq) * g_p)))
        m = min(1.0, max(0.0, (Iq - Ip) * g_r / ((Iq - Ir) * g_p)))
        # m + m1 = 1; keep whichever is small as computed (it carries the relative accuracy)
        m, m1 = (m, 1.0 - m) if m < 0.5 else (1.0 - m1, m1)
        if separatrix or m1 < _M1_SEPARATRIX:
            # m1 < 1e-290 (|D|/|L|² below ~1e-290, beyond scipy's R_J and near underflow) is
            # taken as the separatrix: the two motions differ only after ~330/λ seconds.  If it
            # starts at the saddle itself (cn0 = 0 below), the rotation is taken as steady.
            m, m1 = 1.0, 0.0
        nu = Ir * (Iq - Ip) / (Ip * (Iq - Ir))
        kappa = math.sqrt(Iq * (Ip - Ir) / (Ip * (Iq - Ir)))  # = sqrt(1 - ν) = I_q A_q/(I_p A_p)
        L_norm = math.sqrt(float(np.sum((I * ws) ** 2)))

        # Right-handed body frame B = [b1 b2 b3] (columns, body components).
        s_r = 1.0 if w[r] > 0.0 else -1.0
        s_p = 1.0 if w[p] >= 0.0 else -1.0
        e = np.eye(3)
        b3, b1 = s_r * e[r], s_p * e[p]
        B = np.column_stack([b1, np.cross(b3, b1), b3])
        wB = B.T @ ws  # (ω_x ≥ 0, ω_y, ω_z > 0)

        # Initial phase: (sn u0, cn u0) ∝ (σ ω_y/A_q, ω_x/A_p) = (σ ω_y A_p, ω_x A_q)/(A_p A_q).
        y0, x0 = sigma * wB[1] * A_p, wB[0] * A_q
        h = math.hypot(y0, x0)
        sn0, cn0 = (y0 / h, x0 / h) if h > 0.0 else (0.0, 1.0)
        if m1 == 0.0 and cn0 == 0.0:
            self._steady = True
            self._init_steady()
            return
        if m1 == 0.0:  # sn = tanh u, cn = sech u
            u0 = math.asinh(sn0 / cn0)
        else:  # F(am u0 | m), |am u0| ≤ π/2
            dn0 = math.sqrt(m1 + m * cn0 * cn0)
            u0 = sn0 * float(elliprf(cn0 * cn0, dn0 * dn0, 1.0))

        self.m = m
        self._m1 = m1
        self._ld = None if m1 == 0.0 else _landen(m, m1)
        if self._ld is not None:  # |u0| ≤ K (R_F and the Landen product may differ by an ulp)
            u0 = min(max(u0, -self._ld.K), self._ld.K)
        self._B = B
        self._amp = np.array([A_p, sigma * A_q, A_r]) * scale  # ω_B = amp * (cn, sn, dn)
        self._Ipqr = np.array([Ip, Iq, Ir])
        self._lam = lam * scale
        self._u0 = u0
        self._nu = nu
        self._kappa = kappa
        self._sigma = sigma
        # φ̇ = a_phi + c_phi / (1 - ν sn²u)  (a_phi + c_phi = |L|/I_p).
        self._a_phi = L_norm / Ir * scale
        self._c_phi = L_norm * (Ir - Ip) / (Ir * Ip) * scale
        if self._ld is None:  # separatrix: no period
            self.omega_period = math.inf
        else:
            self._P3 = _ThirdKind(nu, m, m1, self._ld)
            self.omega_period = 4.0 * self._ld.K / self._lam  # ω_z has half this period
        # The Jacobi functions and P at u0, computed exactly as at later times, so that
        # R(0) = R0 and φ(0) = 0 to rounding.
        self._lin0, self._rest0 = 0.0, 0.0
        jac0 = self._jacobi_and_pi(np.zeros(1), want_pi=True)
        self._lin0, self._rest0 = float(jac0[4][0]), float(jac0[5][0])

        # Fixed frame S = R0 B (Rx(θ0) Rz(ψ0))ᵀ, so that φ(0) = 0.
        E0 = self._euler_part(np.zeros(1), jac0[0], jac0[1], jac0[2])[0]
        self._S = R0 @ B @ E0.T

    def _init_steady(self) -> None:
        """ω_b is an eigenvector of I (or zero): ω_b constant, R = R0 exp(t hat(ω_b))."""
        w = self.omega0_body
        self.m = 0.0
        self.omega_period = 0.0
        speed = float(np.linalg.norm(w))
        self._spin_rate = speed
        self._spin_axis = w / speed if speed > 0.0 else np.array([0.0, 0.0, 1.0])

    # --- pieces -------------------------------------------------------------------------------

    def _jacobi_and_pi(self, t: Array, want_pi: bool) -> tuple[Array, ...]:
        """At times t (N,): (sn, cn, dn) of u = λ t + u0, the half-period count j with
        u = r + 2jK, |r| ≤ K, and the parts (lin, rest, excess) of P(r) = lin·r + rest (signed;
        zeros unless `want_pi`)."""
        lam = self._lam
        zeros = np.zeros_like(t)
        if self._ld is None:  # separatrix: no reduction
            u = self._u0 + lam * t
            sn, cn, dn = np.tanh(u), _sech(u), _sech(u)
            lin, rest = zeros, zeros
            if want_pi:
                lin_s, rest = _pi_separatrix_parts(u, self._nu)
                lin = np.full_like(u, lin_s)
            return sn, cn, dn, zeros, lin, rest, zeros
        K = self._ld.K
        # Reduction in u (absolute error ~ulp(u)), never in t: T_half = 2K/λ can be huge.
        u = self._u0 + lam * t
        j = np.round(u / (2.0 * K))
        r = u - j * (2.0 * K)
        a = np.minimum(np.abs(r), K)
        K_minus_a = K - a
        sn_a, cn_r, dn = _sn_cn_dn_half(a, K_minus_a, self._ld)
        sign_r = np.where(r < 0.0, -1.0, 1.0)
        parity = 1.0 - 2.0 * np.mod(j, 2.0)  # sn, cn change sign every half period
        sn, cn = sign_r * sn_a * parity, cn_r * parity
        lin, rest, excess = zeros, zeros, zeros
        if want_pi:
            lin, rest, excess = self._P3.parts(a, K_minus_a, sn_a, cn_r, dn)
            rest = sign_r * rest
        return sn, cn, dn, j, lin, rest, excess

    def _phases(self, t: Array, want_phi: bool = True) -> tuple[Array, Array, Array, Array]:
        """(sn, cn, dn, φ) at times t (N,): Jacobi functions of u = λ t + u0 and the precession
        angle φ [rad] about L (reduced mod 2π; zeros unless `want_phi`).

        φ = a_φ t + (c_φ/λ)(P(u) - P(u0)) with P(u) = P(r) + 2j P(K), P(r) = lin·r + rest and
        r = u - 2jK, i.e.
            φ = (a_φ + c_φ lin) t + j (2c_φ/λ) excess + (c_φ/λ) [(lin - lin0) u0 + rest - rest0],
        excess = P(K) - lin K.  The first two terms grow with t and are reduced modulo 2π; the
        last is bounded and, unlike u - u0, never a difference of nearly equal large numbers
        divided by a small λ."""
        sn, cn, dn, j, lin, rest, excess = self._jacobi_and_pi(t, want_phi)
        if not want_phi:
            return sn, cn, dn, np.zeros_like(t)
        two_pi = 2.0 * math.pi
        c_over_lam = self._c_phi / self._lam
        phi = (
            np.remainder((self._a_phi + self._c_phi * lin) * t, two_pi)
            + np.remainder(j * (2.0 * c_over_lam * excess), two_pi)
            + c_over_lam * ((lin - self._lin0) * self._u0 + (rest - self._rest0))
        )
        return sn, cn, dn, phi

    def _euler_part(self, phi: Array, sn: Array, cn: Array, dn: Array) -> Array:
        """Rz(φ) Rx(θ) Rz(ψ) (N, 3, 3), with θ, ψ the direction of L in the frame B:
        L_B/|L| = (sin θ sin ψ, sin θ cos ψ, cos θ)."""
        Ip, Ir = self._Ipqr[0], self._Ipqr[2]
        A_p, A_r = abs(self._amp[0]), self._amp[2]
        rho = np.hypot(cn, self._kappa * sn)  # L_⊥ = I_p A_p ρ
        s3, c3 = cn / rho, self._sigma * self._kappa * sn / rho
        L_perp, L_z = Ip * A_p * rho, Ir * A_r * dn
        hyp = np.hypot(L_perp, L_z)
        s2, c2 = L_perp / hyp, L_z / hyp
        return _matrix_zxz(phi, c2, s2, c3, s3)

    # --- public -------------------------------------------------------------------------------

    def _evaluate(self, t: float | Array, want_R: bool) -> tuple[Array | None, Array]:
        t_arr = np.asarray(t, dtype=float)
        shape = t_arr.shape
        tt = t_arr.reshape(-1)
        if self._steady:
            omega = np.broadcast_to(self.omega0_body, tt.shape + (3,)).copy()
            R = None
            if want_R:
                angle = np.remainder(self._spin_rate * tt, 2.0 * math.pi)
                R = self.R0 @ _rotation_about(self._spin_axis, angle)
        else:
            sn, cn, dn, phi = self._phases(tt, want_phi=want_R)
            omega_B = self._amp * np.stack([cn, sn, dn], axis=-1)
            omega = omega_B @ self._B.T
            R = None
            if want_R:
                R = _sandwich(self._S, self._euler_part(phi, sn, cn, dn), self._B.T)
        omega = omega.reshape(shape + (3,))
        if R is not None:
            R = R.reshape(shape + (3, 3))
        return R, omega

    def omega_body(self, t: float | Array) -> Array:
        """ω_b(t) [rad/s]: t float -> (3,), t (N,) -> (N, 3)."""
        return self._evaluate(t, want_R=False)[1]

    def attitude(self, t: float | Array) -> Array:
        """R_space_body(t): t float -> (3, 3), t (N,) -> (N, 3, 3)."""
        R, _ = self._evaluate(t, want_R=True)
        assert R is not None
        return R

    def __call__(self, t: float | Array) -> tuple[Array, Array]:
        """(R_space_body(t), ω_b(t)): shapes as `attitude` and `omega_body`."""
        R, omega = self._evaluate(t, want_R=True)
        assert R is not None
        return R, omega
