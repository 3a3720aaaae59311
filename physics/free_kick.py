"""Torqued rigid bodies by the exact free-body flow composed with torque kicks (`free_kick`).

H = T(L_b) + V(R) (+ a constant space torque) is split into the torque-free body, whose flow
is exact (the drift, `FreeDrift`: Jacobi's elliptic functions, as `physics.exact_free`), and
the torque with the attitude frozen (the kick L_b += τ Rᵀ M(R), exact).  T is quadratic in
L_b and M depends on R only, so [B, [B, [B, A]]] = 0 and the compositions built for
Runge-Kutta-Nyström problems apply (Celledoni, Fassò, Säfström & Zanna, SIAM J. Sci. Comput.
30 (2008); Algorithm 903, ACM TOMS): `SCHEMES[name]` are symmetric kick-drift-kick
compositions, (kick coefficients b (s + 1), drift coefficients a (s)); one step is
K(b_0 h) D(a_0 h) K(b_1 h) ... D(a_{s-1} h) K(b_s h), the last kick merged with the next
step's first.  Symplectic and time-reversible: the energy error stays bounded (no drift);
|L| is conserved by every drift, L·e_z of the heavy top by every kick and drift.

The drift over τ from (R, L_b), in plain floats and `math` (no NumPy on 3-vectors):
* the invariants |L|², 2T give the elliptic parameter m, the rate λ and the amplitudes of
  ω in a body frame B = [e_p, ±e_q, s_r e_r] (r: the largest axis when |L|² > 2T I_mid, else
  the smallest): ω_B = (A_p cn u, σ A_q sn u, A_r dn u), u = λ t + u0;
* sn, cn, dn at u0 + λτ by the addition theorem from their values now (read off ω: no
  elliptic integral for u0) and at λτ/2 (the descending Landen transformation, a few levels);
* the attitude R(τ) = R B E0ᵀ Rz(Δφ) E1 Bᵀ, with E = Rx(θ) Rz(ψ) the z-x-z angles of L's
  direction in B and Δφ = ∫ φ̇ dt, φ̇ = |L| (I_p ω_x² + I_q ω_y²)/(L_x² + L_y²), by a 4-, 6- or
  8-point Gauss-Legendre rule about the middle of the drift (the integrand is analytic; the
  number of points grows with λτ, `_NODE_LIMITS`, and a drift with λτ/2 > `_MAX_HALF` is cut in
  two: the limits keep the drift within ~1e-14 rad of `FreeBodyExact` on random bodies);
* the end phase is put back on sn² + cn² = 1 and L_b scaled to |L| now: the roundings of the
  amplitudes would otherwise shrink |L| by ~2e-17 a drift, which over 1e4 drifts is a phase
  error of ~1e-12 rad;
* near the separatrix (1 - m < `SEPARATRIX_M1`), where the Landen descent needs many levels and
  the addition theorem cancels, the drift is `physics.exact_free.FreeBodyExact` (exact, slower).

What bounds its speed: the torque in body axes (gravity's Rᵀ e_z) turns with the body, so the
kicks must resolve the body's rotation, h Ω ≲ 1 (Ω = `rate_scale`), as any integrator's steps
must; the exact drift only makes the error constant small (it carries the torque's strength,
not the free motion's).  A drift costs several right-hand-side evaluations of straight-line
float code and the 6th-order composition 11 drifts a step, so per unit of accuracy it is not
cheaper than `physics.dop853.integrate_adaptive` on the bodies measured
(benchmarks/work_precision.py: docs/performance.md, "Speed against error").

`integrate_free_kick(model, state0, t_eval, tol=..., h=None, scheme="bm6")`: fixed steps of h
[s] (default: from `tol`, `step_for`), cut so every output time is a step end.  Applies to a
body with no torque hook (`applies`): free, heavy top, constant torque, gravity with a
constant torque.
"""

from __future__ import annotations

import math
import time
from math import cos, hypot, sin, sqrt

import numpy as np

from physics.dynamics import IntegrationError, Model, State, Trajectory
from physics.guards import rate_scale, validated_state, validated_times

__all__ = ["DEFAULT_TOL", "ORDERS", "SCHEMES", "SEPARATRIX_M1", "STEP_ANGLE", "STEP_TOL", "FreeDrift", "applies",
           "free_kick_step", "integrate_free_kick", "step_for"]

DEFAULT_TOL = 1e-12
"""[rad]: the attitude error `integrate_free_kick` aims at over a run of ~20 s by default."""

SEPARATRIX_M1 = 1e-6
"""Below this 1 - m the drift is `FreeBodyExact` (near the separatrix)."""

_GAUSS = (  # Gauss-Legendre (node, weight) on [-1, 1], the positive half: 4, 6 and 8 points
    ((0.8611363115940526, 0.34785484513745357), (0.33998104358485626, 0.6521451548625464)),
    ((0.9324695142031519, 0.17132449237917027), (0.6612093864662645, 0.3607615730481387),
     (0.2386191860831969, 0.46791393457269104)),
    ((0.9602898564975362, 0.10122853629037706), (0.7966664774136267, 0.22238103445337443),
     (0.525532409916329, 0.3137066458778869), (0.18343464249564978, 0.36268378337836166)),
)
_NODE_LIMITS = (0.015, 0.045)  # [u]: 4 Gauss points below the first, 6 below the second, else 8
_MAX_HALF = 0.09  # [u]: a longer drift is cut in two (worst body measured: 4e-14 rad at 0.5)
_LANDEN_STOP = 1e-9


def _bm_srkn11b() -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Blanes & Moan (J. Comput. Appl. Math. 142, 2002), SRKN_11^b: order 6, 11 kicks a step."""
    b = (0.0414649985182624, 0.198128671918067, -0.0400061921041533, 0.0752539843015807,
         -0.0115113874206879, 0.2366699247869311)
    a = (0.123229775946271, 0.290553797799558, -0.127049212625417, -0.246331761062075,
         0.357208872795928)
    a_mid = 1.0 - 2.0 * sum(a)
    b_full = (*b[:-1], 0.5 - sum(b[:-1]), 0.5 - sum(b[:-1]), *reversed(b[:-1]))
    return b_full, (*a, a_mid, *reversed(a))


def _bm_srkn6b() -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Blanes & Moan (2002), SRKN_6^b: order 4, 6 drifts and 7 kicks a step."""
    b = (0.0829844064174052, 0.396309801498368, -0.0390563049223486)
    a = (0.245298957184271, 0.604872665711080)
    a_full = (*a, 0.5 - sum(a), 0.5 - sum(a), *reversed(a))
    return (*b, 1.0 - 2.0 * sum(b), *reversed(b)), a_full


def _strang_composition(gammas: tuple[float, ...]) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Π Strang(γ_i h) with Strang = K(h/2) D(h) K(h/2), adjacent kicks merged."""
    b = [0.5 * gammas[0]]
    for g0, g1 in zip(gammas, gammas[1:]):
        b.append(0.5 * (g0 + g1))
    b.append(0.5 * gammas[-1])
    return tuple(b), tuple(gammas)


def _yoshida6() -> tuple[float, ...]:
    w1, w2, w3 = -1.17767998417887, 0.235573213359357, 0.784513610477560
    return (w3, w2, w1, 1.0 - 2.0 * (w1 + w2 + w3), w1, w2, w3)


def _suzuki4() -> tuple[float, ...]:
    g = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
    return (g, g, 1.0 - 4.0 * g, g, g)


SCHEMES: dict[str, tuple[tuple[float, ...], tuple[float, ...]]] = {
    "strang": _strang_composition((1.0,)),
    "suzuki4": _strang_composition(_suzuki4()),
    "yoshida6": _strang_composition(_yoshida6()),
    "bm4": _bm_srkn6b(),
    "bm6": _bm_srkn11b(),
}
"""name -> (kick coefficients b (s + 1), drift coefficients a (s)), symmetric, Σa = Σb = 1."""

ORDERS = {"strang": 2, "suzuki4": 4, "yoshida6": 6, "bm4": 4, "bm6": 6}
"""name -> order of `SCHEMES[name]`."""


def applies(model: Model) -> bool:
    """The torque depends on the attitude only: no hook (free, heavy top, constant torque)."""
    return model.extra_torque is None


# ----------------------------------------------------------------------------------------------
# The drift: the exact free flow, scalar
# ----------------------------------------------------------------------------------------------


def _landen(m: float, m1: float) -> tuple[tuple[tuple[float, float], ...], float, float]:
    """Descending Landen levels ((1 - k_i, 1 + k_i), ...), scale Π(1 + k_i), m_last (as
    `physics.exact_free._landen`, scalar)."""
    k, kp = sqrt(m), sqrt(m1)
    levels = []
    scale = 1.0
    while k > _LANDEN_STOP:
        k_next = (k / (1.0 + kp)) ** 2
        one_minus = 2.0 * kp / (1.0 + kp)
        one_plus = 2.0 / (1.0 + kp)
        kp = 2.0 * sqrt(kp) / (1.0 + kp)
        k = k_next
        levels.append((one_minus, one_plus))
        scale *= one_plus
    return tuple(reversed(levels)), scale, k * k


def _sn_cn_dn(x: float, levels: tuple[tuple[float, float], ...], scale: float, m_last: float,
              K: float) -> tuple[float, float, float]:
    """sn, cn, dn (x | m) for |x| ≤ K (Gauss/Landen recursion in sc or cs, scalar)."""
    a = abs(x)
    low = a <= K - a
    u_n = (a if low else K - a) / scale
    y = math.tan(u_n)
    s2 = sin(u_n) ** 2 if low else cos(u_n) ** 2
    d = 1.0 - 0.5 * m_last * s2
    if low:
        for one_minus, one_plus in levels:
            y2 = y * y
            y, d = one_plus * y / d, (1.0 + one_minus * y2) / (1.0 + one_plus * y2)
        inv = 1.0 / hypot(1.0, y)
        sn, cn = y * inv, inv
    else:
        for one_minus, one_plus in levels:
            y2 = y * y
            y, d = y * d / one_plus, (y2 + one_minus) / (y2 + one_plus)
        inv = 1.0 / hypot(1.0, y)
        sn, cn = inv, y * inv
    return (sn if x >= 0.0 else -sn), cn, d


_PERM_SIGN = {perm: (1.0 if perm in ((0, 1, 2), (1, 2, 0), (2, 0, 1)) else -1.0)
              for perm in ((0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1), (2, 1, 0), (1, 0, 2))}


R9 = tuple[float, float, float, float, float, float, float, float, float]


def _matmul(A: R9 | list[float], B: R9 | list[float]) -> list[float]:
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = A
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = B
    return [a0 * b0 + a1 * b3 + a2 * b6, a0 * b1 + a1 * b4 + a2 * b7, a0 * b2 + a1 * b5 + a2 * b8,
            a3 * b0 + a4 * b3 + a5 * b6, a3 * b1 + a4 * b4 + a5 * b7, a3 * b2 + a4 * b5 + a5 * b8,
            a6 * b0 + a7 * b3 + a8 * b6, a6 * b1 + a7 * b4 + a8 * b7, a6 * b2 + a7 * b5 + a8 * b8]


def _rotation(axis: tuple[float, float, float], angle: float) -> list[float]:
    """exp(angle hat(axis)) row-major for a unit axis (Rodrigues)."""
    x, y, z = axis
    s, c1 = sin(angle), 2.0 * sin(0.5 * angle) ** 2
    return [1.0 - c1 * (y * y + z * z), -s * z + c1 * x * y, s * y + c1 * x * z,
            s * z + c1 * x * y, 1.0 - c1 * (x * x + z * z), -s * x + c1 * y * z,
            -s * y + c1 * x * z, s * x + c1 * y * z, 1.0 - c1 * (x * x + y * y)]


def _euler(lx: float, ly: float, lz: float) -> tuple[tuple[float, float], tuple[float, float, float],
                                                     tuple[float, float, float]]:
    """The rows of Rx(θ) Rz(ψ) with (sin θ sin ψ, sin θ cos ψ, cos θ) ∝ (lx, ly, lz) (the first
    row's third entry, 0, left out)."""
    st = hypot(lx, ly)
    n = 1.0 / hypot(st, lz)
    if st == 0.0:
        sp, cp = 0.0, 1.0
    else:
        sp, cp = lx / st, ly / st
    ct, st = lz * n, st * n
    return (cp, -sp), (ct * sp, ct * cp, -st), (st * sp, st * cp, ct)


class FreeDrift:
    """The exact torque-free flow of a body with principal moments `inertia` (3,) [kg m²]:
    `flow(R, L, tau)` -> (R, L) tau [s] later; R row-major (9 floats), L_b (3 floats)
    [kg m²/s].  See the module docstring for the method."""

    def __init__(self, inertia: tuple[float, float, float]) -> None:
        self.I = tuple(float(i) for i in inertia)
        self.order = tuple(sorted(range(3), key=lambda k: self.I[k]))
        self.slow_drifts = 0

    def flow(self, R: list[float], L: list[float], tau: float) -> tuple[list[float], list[float]]:
        I0, I1, I2 = I = self.I
        w0, w1, w2 = L[0] / I0, L[1] / I1, L[2] / I2
        scale = max(abs(w0), abs(w1), abs(w2))
        if scale == 0.0 or tau == 0.0:
            return R, L
        inv = 1.0 / scale
        ws = (w0 * inv, w1 * inv, w2 * inv)
        a, b, c = self.order
        Ia, Ib, Ic = I[a], I[b], I[c]
        D = Ia * (Ia - Ib) * ws[a] ** 2 + Ic * (Ic - Ib) * ws[c] ** 2
        if D >= 0.0:
            r, p, q, sigma = c, a, b, 1.0
        else:
            r, p, q, sigma = a, c, b, -1.0
        Ip, Iq, Ir = I[p], I[q], I[r]
        s0, s1, s2 = ws[0] * ws[0], ws[1] * ws[1], ws[2] * ws[2]
        g_r = I0 * (I0 - Ir) * s0 + I1 * (I1 - Ir) * s1 + I2 * (I2 - Ir) * s2
        g_p = I0 * (I0 - Ip) * s0 + I1 * (I1 - Ip) * s1 + I2 * (I2 - Ip) * s2
        if Ip == Ir or g_p == 0.0 or g_r == 0.0 or Iq == Ir:
            return self._steady(R, L, [w0, w1, w2], tau)
        A_p = sqrt(g_r / (Ip * (Ip - Ir)))
        A_q = sqrt(g_r / (Iq * (Iq - Ir)))
        A_r = sqrt(g_p / (Ir * (Ir - Ip)))
        lam = sqrt((Ir - Iq) * g_p / (Ip * Iq * Ir)) * scale
        m = min(1.0, max(0.0, (Iq - Ip) * g_r / ((Iq - Ir) * g_p)))
        if m > 0.5:
            m1 = min(1.0, max(0.0, D * (Ir - Ip) / ((Ir - Iq) * g_p)))
            m = 1.0 - m1
        else:
            m1 = 1.0 - m
        if m1 < SEPARATRIX_M1 or lam == 0.0:
            return self._exact(R, L, tau)
        s_r = 1.0 if ws[r] > 0.0 else -1.0
        y_sign = s_r * _PERM_SIGN[r, p, q]  # b2 = b3 × b1 = s_r (e_r × e_p) = y_sign e_q
        # the phase now: (sn, cn) ∝ (σ y / A_q, x / A_p)
        ys, xs = sigma * y_sign * ws[q] * A_p, ws[p] * A_q
        hh = hypot(ys, xs)
        if hh == 0.0:
            return self._steady(R, L, [w0, w1, w2], tau)
        sn0, cn0 = ys / hh, xs / hh
        dn0 = sqrt(m1 + m * cn0 * cn0)
        levels, lscale, m_last = _landen(m, m1)
        K = 0.5 * math.pi * lscale * (1.0 + 0.25 * m_last)
        half = 0.5 * lam * tau
        if abs(half) > _MAX_HALF:  # a long drift: two shorter ones (the quadrature's reach)
            R, L = self.flow(R, L, 0.5 * tau)
            return self.flow(R, L, 0.5 * tau)
        sh, ch, dh = _sn_cn_dn(half, levels, lscale, m_last, K)
        # the middle and the end of the step by the addition theorem
        den = 1.0 / (1.0 - m * sn0 * sn0 * sh * sh)
        sm, cm, dm = ((sn0 * ch * dh + sh * cn0 * dn0) * den, (cn0 * ch - sn0 * sh * dn0 * dh) * den,
                      (dn0 * dh - m * sn0 * sh * cn0 * ch) * den)
        den = 1.0 / (1.0 - m * sm * sm * sh * sh)
        sn1, cn1 = (sm * ch * dh + sh * cm * dm) * den, (cm * ch - sm * sh * dm * dh) * den
        norm = 1.0 / hypot(sn1, cn1)  # back on sn² + cn² = 1, dn² + m sn² = 1: |L| and T kept to rounding
        sn1, cn1 = sn1 * norm, cn1 * norm
        dn1 = sqrt(m1 + m * cn1 * cn1)
        # Δφ = ∫ φ̇ dt, φ̇ = |L| (P2 cn² + Q2 sn²)/(P3 cn² + Q3 sn²), Gauss-Legendre about the middle
        P2, Q2 = Ip * A_p * A_p, Iq * A_q * A_q
        P3, Q3 = Ip * P2, Iq * Q2
        ah = abs(half)
        nodes = _GAUSS[0] if ah < _NODE_LIMITS[0] else _GAUSS[1] if ah < _NODE_LIMITS[1] else _GAUSS[2]
        total = 0.0
        msm2, cmd, smd = m * sm * sm, cm * dm, sm * dm
        for xg, wg in nodes:  # sn, cn at mid ± x from their values at mid and x
            sg, cg, dg = _sn_cn_dn(half * xg, levels, lscale, m_last, K)
            den = 1.0 / (1.0 - msm2 * sg * sg)
            a1, a2 = sm * cg * dg, sg * cmd
            b1, b2 = cm * cg, sg * smd * dg
            sp, cp = (a1 + a2) * den, (b1 - b2) * den
            sq, cq = (a1 - a2) * den, (b1 + b2) * den
            c2, q2 = cp * cp, sp * sp
            c3, q3 = cq * cq, sq * sq
            total += wg * ((P2 * c2 + Q2 * q2) / (P3 * c2 + Q3 * q2) + (P2 * c3 + Q2 * q3) / (P3 * c3 + Q3 * q3))
        Lnorm = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2])
        dphi = Lnorm * 0.5 * tau * total
        # E = Rx(θ) Rz(ψ) from L's direction in B at both ends: l_B ∝ (I_p A_p cn, σ I_q A_q sn, I_r A_r dn)
        u0, v0, z0 = _euler(Ip * A_p * cn0, sigma * Iq * A_q * sn0, Ir * A_r * dn0)
        u1, v1, z1 = _euler(Ip * A_p * cn1, sigma * Iq * A_q * sn1, Ir * A_r * dn1)
        # M = E0ᵀ Rz(Δφ) E1 with E = [[cψ, -sψ, 0], [cθ sψ, cθ cψ, -sθ], [sθ sψ, sθ cψ, cθ]]
        cf, sf = cos(dphi), sin(dphi)
        # F = Rz(Δφ) E1
        e10, e11 = u1
        e20, e21, e22 = v1
        e30, e31, e32 = z1
        f00, f01, f02 = cf * e10 - sf * e20, cf * e11 - sf * e21, -sf * e22
        f10, f11, f12 = sf * e10 + cf * e20, sf * e11 + cf * e21, cf * e22
        f20, f21, f22 = e30, e31, e32
        # M = E0ᵀ F: M[i][j] = Σ_k E0[k][i] F[k][j]
        (g00, g01), (g10, g11, g12), (g20, g21, g22) = u0, v0, z0
        M = (g00 * f00 + g10 * f10 + g20 * f20, g00 * f01 + g10 * f11 + g20 * f21, g00 * f02 + g10 * f12 + g20 * f22,
             g01 * f00 + g11 * f10 + g21 * f20, g01 * f01 + g11 * f11 + g21 * f21, g01 * f02 + g11 * f12 + g21 * f22,
             g12 * f10 + g22 * f20, g12 * f11 + g22 * f21, g12 * f12 + g22 * f22)
        # R_new = R B M Bᵀ; B's columns: e_p, y_sign e_q, s_r e_r
        cols, sgn = (p, q, r), (1.0, y_sign, s_r)
        RB = [0.0] * 9
        for row in (0, 3, 6):
            RB[row], RB[row + 1], RB[row + 2] = R[row + p], y_sign * R[row + q], s_r * R[row + r]
        R_new = [0.0] * 9
        for row in (0, 3, 6):
            x0, x1, x2 = RB[row], RB[row + 1], RB[row + 2]
            for j in range(3):
                R_new[row + cols[j]] = sgn[j] * (x0 * M[j] + x1 * M[3 + j] + x2 * M[6 + j])
        # L_B = (I_p A_p cn, σ I_q A_q sn, I_r A_r dn) scale, scaled to |L| now (the amplitudes'
        # roundings would otherwise shrink |L| by ~2e-17 a drift, a drift of the phase)
        lp, lq, lr = Ip * A_p * cn1, y_sign * sigma * Iq * A_q * sn1, s_r * Ir * A_r * dn1
        f = Lnorm / sqrt(lp * lp + lq * lq + lr * lr)
        L_new = [0.0, 0.0, 0.0]
        L_new[p], L_new[q], L_new[r] = lp * f, lq * f, lr * f
        return R_new, L_new

    def _steady(self, R: list[float], L: list[float], w: list[float], tau: float) -> tuple[list[float], list[float]]:
        speed = sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
        if speed == 0.0:
            return R, L
        axis = (w[0] / speed, w[1] / speed, w[2] / speed)
        return _matmul(R, _rotation(axis, speed * tau)), list(L)

    def _exact(self, R: list[float], L: list[float], tau: float) -> tuple[list[float], list[float]]:
        from physics.exact_free import FreeBodyExact

        self.slow_drifts += 1
        I = self.I
        omega = np.array([L[0] / I[0], L[1] / I[1], L[2] / I[2]])
        R1, w1 = FreeBodyExact(np.array(I), np.array(R).reshape(3, 3), omega)(float(tau))
        return [float(x) for x in np.asarray(R1).ravel()], [float(I[k] * w1[k]) for k in range(3)]


# ----------------------------------------------------------------------------------------------
# Kicks and the composition
# ----------------------------------------------------------------------------------------------


def _torque_body(mgl: float, torque_space: tuple[float, float, float], R: list[float]) -> tuple[float, float, float]:
    """Rᵀ M (3) [N m]: M = -mgl (e_z' × e_z) + torque_space (`Model.torque_space_at`)."""
    Mx, My, Mz = torque_space
    if mgl != 0.0:
        Mx -= mgl * R[5]
        My += mgl * R[2]
    return (R[0] * Mx + R[3] * My + R[6] * Mz, R[1] * Mx + R[4] * My + R[7] * Mz,
            R[2] * Mx + R[5] * My + R[8] * Mz)


def free_kick_step(drift: FreeDrift, mgl: float, torque_space: tuple[float, float, float],
                   R: list[float], L: list[float], h: float, scheme: str = "bm6") -> tuple[list[float], list[float]]:
    """One step of h [s] of the composition `SCHEMES[scheme]` from (R row-major (9), L_b (3))."""
    b, a = SCHEMES[scheme]
    torque = mgl != 0.0 or any(torque_space)
    for k, ak in enumerate(a):
        if torque:
            tx, ty, tz = _torque_body(mgl, torque_space, R)
            f = b[k] * h
            L = [L[0] + f * tx, L[1] + f * ty, L[2] + f * tz]
        R, L = drift.flow(R, L, ak * h)
    if torque:
        tx, ty, tz = _torque_body(mgl, torque_space, R)
        f = b[-1] * h
        L = [L[0] + f * tx, L[1] + f * ty, L[2] + f * tz]
    return R, L


STEP_ANGLE = 0.6
"""h Ω [rad] of `step_for` at tol = STEP_TOL (Ω = `physics.guards.rate_scale`): measured on the
asymmetric heavy top (1, 1.4, 0.6), mgl 2, spin 12 rad/s, 4 s: attitude error 1.4e-11 rad."""
STEP_TOL = 5e-11


def step_for(model: Model, state: State, tol: float, scheme: str = "bm6") -> float:
    """The step h [s] for an attitude error ~tol [rad] over ~20 s: h Ω = STEP_ANGLE (tol /
    STEP_TOL)^(1/order), Ω = `rate_scale` (the spin and the torque's own rate); inf without a
    torque (the drift is exact: one step per output interval)."""
    if model.mgl == 0.0 and not any(model.torque_space):
        return math.inf
    Omega = max(rate_scale(model, state.R_space_body, state.omega_body), 1e-300)
    return STEP_ANGLE * (tol / STEP_TOL) ** (1.0 / ORDERS[scheme]) / Omega


def integrate_free_kick(model: Model, state0: State, t_eval: np.ndarray, tol: float = DEFAULT_TOL,
                        h: float | None = None, scheme: str = "bm6") -> Trajectory:
    """The motion sampled at t_eval (N,) [s] (t_eval[0] >= state0.t) by fixed steps of at most h
    [s] (default `step_for(tol)`), each output interval cut into equal steps; without a torque,
    the drift over the whole run (`physics.exact_free.FreeBodyExact`).  ValueError for
    a model with a torque hook or bad input; IntegrationError on a non-finite state."""
    if not applies(model):
        raise ValueError("free_kick needs a torque that depends on the attitude only (no torque hook)")
    if scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {', '.join(SCHEMES)}, got {scheme!r}")
    R_rows, omega_list, t0 = validated_state(state0)
    t_eval = validated_times(t_eval, t0)
    step = step_for(model, state0, tol, scheme) if h is None else float(h)
    if not step > 0.0:
        raise ValueError(f"step h must be positive, got {h}")
    start = time.perf_counter()
    if model.mgl == 0.0 and not any(model.torque_space):  # no kicks: the drift over the whole run
        from physics.exact_free import FreeBodyExact

        R_all, omega_all = FreeBodyExact(np.array(model.inertia), np.array(R_rows).reshape(3, 3),
                                         np.array(omega_list))(t_eval - t0)
        return Trajectory(t_eval, R_all, omega_all, 0, time.perf_counter() - start, "free_kick")
    drift = FreeDrift(model.inertia)
    mgl, torque_space = model.mgl, model.torque_space
    I = model.inertia
    R = list(R_rows)
    L = [I[k] * omega_list[k] for k in range(3)]
    n_out = len(t_eval)
    R_out = np.empty((n_out, 3, 3))
    omega_out = np.empty((n_out, 3))
    t = t0
    kicks = 0
    n_kicks = len(SCHEMES[scheme][1])
    for i, t_next in enumerate(t_eval):
        span = float(t_next) - t
        if span > 0.0:
            n = max(1, math.ceil(span / step * (1.0 - 1e-12))) if math.isfinite(step) else 1
            hk = span / n
            for _ in range(n):
                R, L = free_kick_step(drift, mgl, torque_space, R, L, hk, scheme)
            kicks += n * n_kicks
            if not all(math.isfinite(x) for x in (*R, *L)):
                raise IntegrationError(f"free_kick: the state is not finite at t = {t_next:.6g} s")
        t = float(t_next)
        R_out[i] = np.array(R).reshape(3, 3)
        omega_out[i] = (L[0] / I[0], L[1] / I[1], L[2] / I[2])
    wall = time.perf_counter() - start
    return Trajectory(t_eval, R_out, omega_out, kicks, wall, "free_kick")
