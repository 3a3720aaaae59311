"""Poinsot's construction of torque-free motion: the geometry of the polhode, the herpolhode
and the flip period, as functions of the principal moments I, the kinetic energy T and |L|.

Conventions (docs/CONVENTIONS.md, the Poinsot section): body frame = principal axes, L_b = I ω_b
(body components, I the diagonal (3,) of moments [kg m²]), 2T = ω_b · I ω_b = L_b · I⁻¹ L_b,
L_s = R_space_body L_b fixed in space.  SI units, radians.

* **Two quadrics in L-space (body).**  L_b lies on the energy ellipsoid Σ L_k²/I_k = 2T and on
  the sphere Σ L_k² = |L|²; their intersection is the polhode (in L units; ω_b = L_b / I gives it
  on Poinsot's ellipsoid ω · I ω = 2T).  Let g_k = |L|² - 2T I_k.  The curve encircles the axis
  r: the largest-moment axis if g_mid > 0, the smallest if g_mid < 0; p is the other extreme
  and q the intermediate one.  With the parameter s (which is Jacobi's amplitude am u of the
  motion):
      L_p = a_p cos s,   L_q = a_q sin s,   L_r = ± sqrt(I_r [g_p cos² s/(I_r - I_p) + g_q sin² s/(I_r - I_q)]),
      a_k² = I_k g_r / (I_k - I_r)   (k = p, q),
  every term non-negative, so both quadric equations hold to rounding.  On the separatrix
  (g_mid = 0, I1 < I2 < I3) the curves are the two planes L_r = ± c cos s through ±|L| e_q.
* **Time.**  u = λ t + u0, L_p ∝ cn u, L_q ∝ sn u, L_r ∝ dn u with
      λ = sqrt((I_r - I_q) g_p / (I_p I_q I_r)),   m = (I_q - I_p) g_r / ((I_q - I_r) g_p),
      1 - m = g_q (I_r - I_p) / (g_p (I_r - I_q))   (Landau & Lifshitz, Mechanics §37).
  ω_q changes sign every 2K(m)/λ: the **flip period**, half the polhode period 4K(m)/λ.  At the
  separatrix m = 1 and the period is infinite.
* **Poinsot's ellipsoid** ω · I ω = 2T (body-fixed, semi-axes sqrt(2T/I_k)) touches the
  **invariable plane** n · x = 2T/|L|, n = L_s/|L|, at x = ω_s: the ellipsoid's normal there is
  I ω_b ∝ L.  The contact point traces the herpolhode, at distance
  ρ = sqrt(|ω|² - (2T/|L|)²) from the foot of the perpendicular; |ω|² along the polhode is
  linear in sin² s, so ρ lies between its values at s = 0 and s = π/2 (`herpolhode_radii`).

numpy and scipy only.  Tests: tests/test_poinsot.py (against the exact solution
`physics.exact_free.FreeBodyExact`, which is written independently of these formulas).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ellipk, ellipkinc, ellipkm1

from physics._types import Array, Vec3

__all__ = [
    "PolhodeMotion",
    "contact_point",
    "flip_times",
    "herpolhode_radii",
    "invariable_plane",
    "invariants",
    "motion",
    "polhode_family",
    "polhode_L",
    "polhode_omega",
    "separatrix_L",
    "time_to_next_flip",
]

DENSE = 4096  # parameter samples used to place a curve's points evenly along its length
_M1_SMALL = 0.5  # below this 1 - m, K(m) is taken from ellipkm1(1 - m) (keeps its precision)


def _moments(inertia: Vec3) -> Vec3:
    I = np.asarray(inertia, dtype=float).reshape(3)
    if not np.all(np.isfinite(I)) or np.any(I <= 0.0):
        raise ValueError(f"principal moments must be positive and finite, got {I}")
    a, b, c = np.sort(I)
    if a + b < c * (1.0 - 1e-12):
        raise ValueError(f"moments {I} break the triangle inequality I1 + I2 >= I3: not a body")
    return I


def invariants(inertia: Vec3, omega_body: Vec3) -> tuple[float, float]:
    """(T [J], |L| [kg m²/s]) of the body components ω_b (3,) [rad/s]."""
    I = _moments(inertia)
    w = np.asarray(omega_body, dtype=float).reshape(3)
    if not np.all(np.isfinite(w)):
        raise ValueError(f"omega must be finite, got {w}")
    return 0.5 * float(w @ (I * w)), float(np.linalg.norm(I * w))


@dataclass(frozen=True)
class PolhodeMotion:
    """The polhode of (I, T, |L|) and its timing.

    r, p, q: body axis indices (r encircled, p the other extreme, q the intermediate);
    g: (3,) g_k = |L|² - 2T I_k [kg² m⁴/s²]; a_p, a_q: the semi-axes of L_p, L_q [kg m²/s];
    kind: "steady" (a point: ω_b constant), "separatrix" (m = 1), "symmetric" (I_p = I_q,
    a circle: ω_⊥ turns, nothing flips) or "flip" (I1 < I2 < I3 off the separatrix);
    rate: λ [rad/s]; m, m1 = 1 - m; flip_period: 2K(m)/λ [s] (inf for "steady", "separatrix").
    """

    inertia: Vec3
    T: float
    L_norm: float
    r: int
    p: int
    q: int
    g: Vec3
    a_p: float
    a_q: float
    kind: str
    rate: float
    m: float
    m1: float
    flip_period: float

    @property
    def polhode_period(self) -> float:
        """Period of ω_b(t) [s]: 4K(m)/λ, twice the flip period."""
        return 2.0 * self.flip_period


def motion(inertia: Vec3, T: float, L_norm: float) -> PolhodeMotion:
    """The polhode of the moments `inertia` (3,) [kg m²] at energy T [J] and |L| [kg m²/s].

    ValueError unless T > 0, |L| > 0 and 2T I_min ≤ |L|² ≤ 2T I_max (rounding allowed: 1e-12
    relative), the condition for the two quadrics to meet.
    """
    I = _moments(inertia)
    T, L_norm = float(T), float(L_norm)
    if not (math.isfinite(T) and math.isfinite(L_norm) and T > 0.0 and L_norm > 0.0):
        raise ValueError(f"need T > 0 and |L| > 0, got T = {T!r}, |L| = {L_norm!r}")
    order = [int(k) for k in np.argsort(I, kind="stable")]
    lo, mid, hi = order
    L2 = L_norm * L_norm
    if not 2.0 * T * I[lo] * (1.0 - 1e-12) <= L2 <= 2.0 * T * I[hi] * (1.0 + 1e-12):
        raise ValueError(f"no motion has T = {T:g} J and |L| = {L_norm:g} kg m²/s with moments {I}: "
                         f"|L|²/(2T) = {L2 / (2.0 * T):g} must lie between {I[lo]:g} and {I[hi]:g}")
    g = L2 - 2.0 * T * I
    if I[hi] == I[mid]:  # I1 < I2 = I3 (or all equal): the curves circle the smallest axis
        r, p, q = lo, hi, mid
    elif I[lo] == I[mid] or g[mid] >= 0.0:
        r, p, q = hi, lo, mid
    else:
        r, p, q = lo, hi, mid
    if I[r] == I[p]:  # a sphere: every axis is principal
        return PolhodeMotion(I, T, L_norm, r, p, q, g, 0.0, 0.0, "steady", 0.0, 0.0, 1.0, math.inf)
    a_p = math.sqrt(max(0.0, I[p] * g[r] / (I[p] - I[r])))
    a_q = math.sqrt(max(0.0, I[q] * g[r] / (I[q] - I[r])))
    rate = math.sqrt(max(0.0, (I[r] - I[q]) * g[p] / (I[p] * I[q] * I[r])))
    separatrix = g[q] == 0.0 and I[lo] < I[mid] < I[hi]
    if a_p == 0.0 and a_q == 0.0:
        kind = "steady"
    elif separatrix:
        kind = "separatrix"
    elif I[p] == I[q]:
        kind = "symmetric"
    else:
        kind = "flip"
    if kind in ("steady", "separatrix") or rate == 0.0:
        return PolhodeMotion(I, T, L_norm, r, p, q, g, a_p, a_q, kind, rate,
                             1.0 if kind == "separatrix" else 0.0, 0.0 if kind == "separatrix" else 1.0,
                             math.inf)
    m1 = min(1.0, max(0.0, g[q] * (I[r] - I[p]) / (g[p] * (I[r] - I[q]))))
    m = min(1.0, max(0.0, (I[q] - I[p]) * g[r] / ((I[q] - I[r]) * g[p])))
    K = float(ellipkm1(m1)) if m1 < _M1_SMALL else float(ellipk(m))
    return PolhodeMotion(I, T, L_norm, r, p, q, g, a_p, a_q, kind, rate, m, m1, 2.0 * K / rate)


def _L_at(mo: PolhodeMotion, s: Array, sign: float) -> Array:
    """Points (N, 3) of the polhode (L units, body) at the parameters s (N,) [rad]."""
    I, g = mo.inertia, mo.g
    c, sn = np.cos(s), np.sin(s)
    out = np.zeros((s.shape[0], 3))
    out[:, mo.p] = mo.a_p * c
    out[:, mo.q] = mo.a_q * sn
    if mo.kind == "separatrix":
        c_r = math.sqrt(max(0.0, I[mo.r] * g[mo.p] / (I[mo.r] - I[mo.p])))
        out[:, mo.r] = sign * c_r * c
    else:
        r2 = I[mo.r] * (g[mo.p] / (I[mo.r] - I[mo.p]) * c * c + g[mo.q] / (I[mo.r] - I[mo.q]) * sn * sn)
        out[:, mo.r] = sign * np.sqrt(np.maximum(r2, 0.0))
    return out


def polhode_L(inertia: Vec3, T: float, L_norm: float, n: int = 256, sign: float = 1.0) -> Array:
    """The polhode in body L-space: n points (n, 3) [kg m²/s], evenly spaced along the closed
    curve (the last joins the first), on the side sign · L_r > 0 of the encircled axis r.

    A steady rotation gives n copies of its one point.  sign: +1 or -1.
    """
    if n < 3:
        raise ValueError(f"need at least 3 points, got {n}")
    mo = motion(inertia, T, L_norm)
    sign = 1.0 if sign >= 0.0 else -1.0
    if mo.kind == "steady":
        point = np.zeros(3)
        point[mo.r] = sign * L_norm
        return np.tile(point, (n, 1))
    dense = np.linspace(0.0, 2.0 * math.pi, DENSE + 1)
    pts = _L_at(mo, dense, sign)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    targets = np.linspace(0.0, arc[-1], n + 1)[:-1]
    s = np.interp(targets, arc, dense)  # even spacing; each point is then evaluated exactly
    return _L_at(mo, s, sign)


def polhode_omega(inertia: Vec3, T: float, L_norm: float, n: int = 256, sign: float = 1.0) -> Array:
    """The polhode on Poinsot's ellipsoid: ω_b = L_b / I, (n, 3) [rad/s] (see `polhode_L`)."""
    return polhode_L(inertia, T, L_norm, n, sign) / _moments(inertia)


def separatrix_L(inertia: Vec3, L_norm: float, n: int = 256) -> Array:
    """The separatrix on the sphere |L| = L_norm: the two planar curves (2, n, 3) [kg m²/s]
    through ±|L| e_q (q the intermediate axis), at 2T = |L|²/I_mid.  For a symmetric body
    (two equal moments) both are the circle of steady rotations.  ValueError for a sphere."""
    I = _moments(inertia)
    mid = float(np.sort(I)[1])
    if np.all(I == I[0]):
        raise ValueError("a sphere has no separatrix: every rotation is steady")
    T = L_norm * L_norm / (2.0 * mid)
    return np.stack([polhode_L(I, T, L_norm, n, sign) for sign in (1.0, -1.0)])


def polhode_family(inertia: Vec3, L_norm: float, levels: int = 3, n: int = 128) -> list[Array]:
    """Polhodes on the sphere |L| = L_norm around both extreme axes, for `levels` energies on
    each side of the separatrix (evenly spaced in |L|²/(2T) between I_min, I_mid and I_max),
    each on both ends of its axis: a list of (n, 3) curves [kg m²/s]."""
    I = _moments(inertia)
    lo, mid, hi = np.sort(I)
    curves = []
    for a, b in ((lo, mid), (mid, hi)):
        if b == a:
            continue
        for f in (np.arange(levels) + 0.5) / levels:
            effective = a + f * (b - a)  # |L|²/(2T) [kg m²]
            T = L_norm * L_norm / (2.0 * effective)
            curves += [polhode_L(I, T, L_norm, n, sign) for sign in (1.0, -1.0)]
    return curves


def invariable_plane(L_space: Vec3, T: float) -> tuple[Vec3, float]:
    """(unit normal n = L_s/|L|, distance 2T/|L| [rad/s] from the fixed point) of the plane
    n · ω = 2T/|L| on which Poinsot's ellipsoid rolls."""
    L = np.asarray(L_space, dtype=float).reshape(3)
    norm = float(np.linalg.norm(L))
    if not norm > 0.0 or not T > 0.0:
        raise ValueError("the invariable plane needs |L| > 0 and T > 0")
    return L / norm, 2.0 * float(T) / norm


def contact_point(R_space_body: Array, omega_body: Vec3) -> Vec3:
    """The point where the ellipsoid touches the invariable plane: ω_s = R ω_b [rad/s]."""
    return np.asarray(R_space_body, dtype=float) @ np.asarray(omega_body, dtype=float)


def herpolhode_radii(inertia: Vec3, T: float, L_norm: float) -> tuple[float, float]:
    """(ρ_min, ρ_max) [rad/s]: the herpolhode's distance from the foot of the perpendicular
    from the fixed point to the invariable plane stays between these."""
    mo = motion(inertia, T, L_norm)
    I = mo.inertia
    if mo.kind == "steady":
        return 0.0, 0.0
    d2 = (2.0 * T / L_norm) ** 2
    radii = []
    for s in (0.0, 0.5 * math.pi):
        w = _L_at(mo, np.array([s]), 1.0)[0] / I
        radii.append(math.sqrt(max(0.0, float(w @ w) - d2)))
    return min(radii), max(radii)


def time_to_next_flip(inertia: Vec3, omega_body: Vec3) -> float:
    """Time [s] from the state ω_b (3,) [rad/s] to the next sign change of ω_q, the body
    component along the intermediate axis (2K(m)/λ if ω_q = 0 now); inf if it never changes
    sign (steady rotation, separatrix).  From the amplitude s = am u of the current point:
    u = F(s | m) (scipy.special.ellipkinc), the next zero of sn at the next multiple of 2K."""
    I = _moments(inertia)
    T, L_norm = invariants(I, omega_body)
    if T == 0.0:
        return math.inf
    mo = motion(I, T, L_norm)
    if not math.isfinite(mo.flip_period):
        return math.inf
    L = I * np.asarray(omega_body, dtype=float)
    # u increases with time: Euler's I_q ω̇_q = ±(I_r - I_p) ω_r ω_p (+ if (p, q, r) is a cyclic
    # order of the axes, - otherwise) has, at ω_q = 0, the sign of ε L_p.
    cyclic = 1.0 if (mo.q - mo.p) % 3 == 1 else -1.0
    eps = 1.0 if cyclic * (I[mo.r] - I[mo.p]) * L[mo.r] > 0.0 else -1.0
    s = math.atan2(eps * L[mo.q] / mo.a_q, L[mo.p] / mo.a_p)
    u = float(ellipkinc(math.fmod(s + 2.0 * math.pi, math.pi), mo.m))
    half = 0.5 * mo.flip_period * mo.rate  # K(m), the same value the period was made from
    return (2.0 * half - u) / mo.rate


def flip_times(inertia: Vec3, omega_body0: Vec3, t0: float, t_lo: float, t_hi: float) -> Array:
    """The flip times (sign changes of ω_q) in [t_lo, t_hi] [s] of the motion that has ω_b0
    at time t0: t0 + time_to_next_flip + j · flip_period.  Empty if there are none."""
    I = _moments(inertia)
    first = t0 + time_to_next_flip(I, omega_body0)
    if not math.isfinite(first) or t_hi < t_lo:
        return np.zeros(0)
    period = motion(I, *invariants(I, omega_body0)).flip_period
    j_lo = max(math.ceil((t_lo - first) / period), -10**9)
    j_hi = math.floor((t_hi - first) / period)
    if j_hi < j_lo:
        return np.zeros(0)
    return first + period * np.arange(j_lo, j_hi + 1, dtype=float)
