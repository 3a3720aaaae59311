"""Constrained particle systems in generalized coordinates (memo §2 and §5), from x_i(q, t) alone.

A system of N particles with m degrees of freedom is given by three things and nothing derived
by hand (`System`):

* its positions x_i(q, t) (2.1)/(5.1): a function of the generalized coordinates q (m,) and the
  time t [s] returning N rows of 3 space components [m];
* its masses m_i (N,) [kg];
* its applied forces F_i(x, ẋ, t) (N, 3) [N] (gravity, springs; not the constraint forces), and,
  where they have one, their potential V(x, t) [J].

Everything else follows the memo's route.  The derivatives of x_i are exact to rounding: the
position function is evaluated once on `Jet` numbers (forward-mode hyper-dual numbers), which
carry, besides the value,

    d_k  = ∂x/∂s_k               along the directions s_k = q_1 … q_m, t   (K = m + 1 of them)
    w    = ∇x · w = ẋ            along the state's direction w = (q̇, 1) in (q, t)
    dw_k = ∂²x/∂s_k ∂w           the mixed second derivatives  (so ∂ẋ/∂q_j = d/dt ∂x/∂q_j = dw_j)
    ww   = wᵀ (∂²x) w            = Σ ∂²x/∂q_j∂q_k q̇_j q̇_k + 2 Σ ∂²x/∂q_j∂t q̇_j + ∂²x/∂t²

so one pass gives the Jacobian ∂x_i/∂q_j, ∂x_i/∂t, ẋ_i = Σ ∂x_i/∂q_j q̇_j + ∂x_i/∂t and ẍ_i =
Σ ∂x_i/∂q_j q̈_j + ww_i.  Then (`Evaluation`):

    M_jk = Σ_i m_i ∂x_i/∂q_j · ∂x_i/∂q_k                        mass matrix [kg m²] for angles
    Q_j  = Σ_i F_i · ∂x_i/∂q_j                                 (5.12)
    p_j  = ∂T/∂q̇_j = Σ_i m_i ẋ_i · ∂x_i/∂q_j
    ∂T/∂q_j = Σ_i m_i ẋ_i · ∂ẋ_i/∂q_j
    d/dt ∂T/∂q̇_j = Σ_i m_i (ẍ_i · ∂x_i/∂q_j + ẋ_i · d/dt ∂x_i/∂q_j)     ((2.3) along the motion)

Lagrange's equations (5.13), d/dt ∂T/∂q̇_j − ∂T/∂q_j = Q_j, are linear in q̈; with the identity
d/dt ∂x_i/∂q_j = ∂ẋ_i/∂q_j ((5.3), (5.4)) the ẋ·(dw) terms cancel and they read

    M q̈ = Q − Σ_i m_i (∂x_i/∂q)ᵀ ww_i                        (`accelerations`)

the right-hand side's last term being the velocity terms (Ṁq̇ − ∂T/∂q and, for a moving
constraint, the terms in ∂x/∂t).  The term-by-term readout (`Evaluation.terms`) evaluates the
four terms of (5.13) separately and their residual.

Kinetic energy T = T₂ + T₁ + T₀ with T₂ = ½ q̇ᵀ M q̇, T₁ = Σ m_i (J_i q̇)·∂x_i/∂t, T₀ = ½ Σ m_i
|∂x_i/∂t|².  When x_i and F_i do not depend on t except through a uniform turning about a fixed
axis that leaves the Lagrangian's form unchanged (the turning hoop and rod), or not at all,
Jacobi's integral h = T₂ − T₀ + V is conserved; for a scleronomic system (∂x/∂t = 0) it is the
energy T + V.

Constraint forces.  On particle i, C_i = m_i ẍ_i − F_i [N].  Its virtual work along q_j is
C_i · ∂x_i/∂q_j (5.7): zero for a single particle on a smooth constraint; for several particles
joined by a rod (the double pendulum) the rod pushes the two ends with equal and opposite
forces along itself, which do virtual work on each particle but none in total: Σ_i C_i ·
∂x_i/∂q_j = 0 is what (5.8)-(5.11) use.

Integration (`GridIntegrator`).  Fixed steps of H = 1/60 s / SUBSTEPS = 1/120 s of the 8th-order
Dormand-Prince formula (scipy's DOP853 tableau, its 12 stages, no step control) on y = (q, q̇).
The committed state moves in whole steps H from t = 0, whatever the display frames (as
`physics.realtime.GridStepper`); a time between two grid points is shown by one shorter step
from the last grid point, never committed.  Measured (tests/test_constrained.py): the conserved
quantity stays within 1e-8 relative over 60 s on every preset, and the residual of (5.13) on
the simulated motion is at rounding level (≤ 1e-9 relative).  Not symplectic: the error in h
drifts like C (H ω)⁸ ω t, far below the tolerance at the presets' rates.

Singularities.  M is singular where the coordinates are (the spherical pendulum at θ = 0, π:
φ undefined); `accelerations` raises `SingularCoordinatesError` when cond(M) > MAX_CONDITION.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import DOP853

from physics._types import Array

__all__ = [
    "MAX_CONDITION",
    "NOMINAL_STEP",
    "SUBSTEPS",
    "Evaluation",
    "GridIntegrator",
    "Jet",
    "LeftTheConstraint",
    "SingularCoordinatesError",
    "System",
    "Terms",
    "bead_on_turning_hoop",
    "bead_on_turning_rod",
    "cos",
    "derivatives",
    "double_pendulum",
    "exp",
    "hoop_equilibrium",
    "hoop_small_oscillation_rate",
    "log",
    "sin",
    "rk8_step",
    "spherical_pendulum",
    "sqrt",
]

NOMINAL_STEP = 1.0 / 60.0  # [s] the display frame the grid is laid on
SUBSTEPS = 2  # grid steps per nominal frame: H = 1/120 s
MAX_CONDITION = 1e10  # cond(M) above this: the coordinates are singular here (fewer than ~6 digits left)
MAX_GRID_STEPS = 100_000  # one advance may take at most this many grid steps


class SingularCoordinatesError(ArithmeticError):
    """The mass matrix is singular (or nearly) where the state is: the coordinates fail there."""


class LeftTheConstraint(ArithmeticError):
    """A particle reached the end of its constraint (the bead at the end of the rod)."""


# ---------------------------------------------------------------------------- jets
Scalar = Any  # float or Jet
Numbers = Sequence[float] | Array  # (m,) coordinates or velocities


class Jet:
    """A forward-mode hyper-dual number: a value and its first and second derivatives.

    v: value.  d: (K,) tuple of ∂/∂s_k.  w: the derivative along w.  dw: (K,) tuple of
    ∂²/∂s_k∂w.  ww: the second derivative along w (see the module docstring).  Arithmetic with
    floats and other Jets, and sin, cos, sqrt, exp, log (module functions, or numpy's ufuncs
    np.sin ...), follow the chain rule to second order; exact to rounding.
    """

    __slots__ = ("d", "dw", "v", "w", "ww")
    __array_priority__ = 1000  # float64 * Jet goes to Jet.__rmul__

    def __init__(self, v: float, d: tuple[float, ...], w: float, dw: tuple[float, ...], ww: float) -> None:
        self.v, self.d, self.w, self.dw, self.ww = v, d, w, dw, ww

    def __repr__(self) -> str:
        return f"Jet({self.v!r}, d={self.d}, w={self.w!r}, dw={self.dw}, ww={self.ww!r})"

    # ---- the chain rule for a function of one variable: f(v), f'(v), f''(v)
    def _apply(self, f0: float, f1: float, f2: float) -> Jet:
        w = self.w
        return Jet(f0, tuple(f1 * a for a in self.d), f1 * w,
                   tuple(f1 * b + f2 * a * w for a, b in zip(self.d, self.dw)), f1 * self.ww + f2 * w * w)

    def __add__(self, other: Scalar) -> Jet:
        if isinstance(other, Jet):
            return Jet(self.v + other.v, tuple(a + b for a, b in zip(self.d, other.d)), self.w + other.w,
                       tuple(a + b for a, b in zip(self.dw, other.dw)), self.ww + other.ww)
        return Jet(self.v + float(other), self.d, self.w, self.dw, self.ww)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet(-self.v, tuple(-a for a in self.d), -self.w, tuple(-a for a in self.dw), -self.ww)

    def __pos__(self) -> Jet:
        return self

    def __sub__(self, other: Scalar) -> Jet:
        return self + (-other)

    def __rsub__(self, other: Scalar) -> Jet:
        return (-self) + other

    def __mul__(self, other: Scalar) -> Jet:
        if isinstance(other, Jet):
            a, b = self, other
            return Jet(a.v * b.v, tuple(a.v * y + b.v * x for x, y in zip(a.d, b.d)), a.v * b.w + b.v * a.w,
                       tuple(a.v * yw + x * b.w + a.w * y + b.v * xw
                             for x, y, xw, yw in zip(a.d, b.d, a.dw, b.dw)),
                       a.v * b.ww + 2.0 * a.w * b.w + b.v * a.ww)
        c = float(other)
        return Jet(self.v * c, tuple(c * a for a in self.d), c * self.w, tuple(c * a for a in self.dw), c * self.ww)

    __rmul__ = __mul__

    def reciprocal(self) -> Jet:
        r = 1.0 / self.v
        return self._apply(r, -r * r, 2.0 * r * r * r)

    def __truediv__(self, other: Scalar) -> Jet:
        if isinstance(other, Jet):
            return self * other.reciprocal()
        return self * (1.0 / float(other))

    def __rtruediv__(self, other: Scalar) -> Jet:
        return self.reciprocal() * other

    def __pow__(self, exponent: float) -> Jet:
        p = float(exponent)
        if p == 2.0:
            return self * self
        v = self.v
        return self._apply(v**p, p * v ** (p - 1.0), p * (p - 1.0) * v ** (p - 2.0))

    def sin(self) -> Jet:
        s, c = math.sin(self.v), math.cos(self.v)
        return self._apply(s, c, -s)

    def cos(self) -> Jet:
        s, c = math.sin(self.v), math.cos(self.v)
        return self._apply(c, -s, -c)

    def sqrt(self) -> Jet:
        r = math.sqrt(self.v)
        return self._apply(r, 0.5 / r, -0.25 / (r * self.v))

    def exp(self) -> Jet:
        e = math.exp(self.v)
        return self._apply(e, e, e)

    def log(self) -> Jet:
        r = 1.0 / self.v
        return self._apply(math.log(self.v), r, -r * r)

    _UFUNCS = {"sin", "cos", "sqrt", "exp", "log", "negative", "add", "subtract", "multiply", "true_divide",
               "square"}

    def __array_ufunc__(self, ufunc: Any, method: str, *inputs: Any, **kwargs: Any) -> Any:
        """np.sin(jet) and the like (elementwise ufuncs only)."""
        if method != "__call__" or kwargs or ufunc.__name__ not in self._UFUNCS:
            return NotImplemented
        name = ufunc.__name__
        if name == "square":
            return inputs[0] * inputs[0]
        if len(inputs) == 1:
            x = inputs[0]
            return -x if name == "negative" else getattr(x, name)()
        a, b = (x if isinstance(x, Jet) else float(x) for x in inputs)
        ops: dict[str, Callable[[Any, Any], Any]] = {
            "add": lambda x, y: x + y, "subtract": lambda x, y: x - y, "multiply": lambda x, y: x * y,
            "true_divide": lambda x, y: x / y}
        return ops[name](a, b)


def _unary(name: str, fn: Callable[[float], float]) -> Callable[[Scalar], Scalar]:
    def apply(x: Scalar) -> Scalar:
        return getattr(x, name)() if isinstance(x, Jet) else fn(float(x))

    apply.__name__ = name
    apply.__doc__ = f"{name}(x) for a float or a Jet."
    return apply


sin = _unary("sin", math.sin)
cos = _unary("cos", math.cos)
sqrt = _unary("sqrt", math.sqrt)
exp = _unary("exp", math.exp)
log = _unary("log", math.log)


def _seed(q: Numbers, q_dot: Numbers, t: float) -> tuple[list[Jet], Jet]:
    """The coordinates and the time as Jets: s_k = (q_1 … q_m, t), w = (q̇, 1)."""
    m = len(q)
    K = m + 1
    zeros = (0.0,) * K

    def unit(k: int) -> tuple[float, ...]:
        return tuple(1.0 if j == k else 0.0 for j in range(K))

    qs = [Jet(float(q[j]), unit(j), float(q_dot[j]), zeros, 0.0) for j in range(m)]
    return qs, Jet(float(t), unit(m), 1.0, zeros, 0.0)


def derivatives(positions: Callable[[Sequence[Scalar], Scalar], Any], q: Numbers,
                q_dot: Numbers, t: float) -> tuple[Array, Array, Array, Array, Array, Array]:
    """x_i(q, t) and its derivatives at one state, from one evaluation on Jets.

    Returns (x (N, 3), J (N, 3, m) = ∂x_i/∂q_j, x_t (N, 3) = ∂x_i/∂t, x_dot (N, 3) = ẋ_i,
    x_dot_q (N, 3, m) = ∂ẋ_i/∂q_j = d/dt ∂x_i/∂q_j, a0 (N, 3) = ẍ_i − Σ_j ∂x_i/∂q_j q̈_j).
    Components that are plain numbers (a coordinate fixed at 0) are constants.
    """
    qs, t_jet = _seed(q, q_dot, t)
    rows = positions(qs, t_jet)
    m = len(q)
    K = m + 1
    zeros = (0.0,) * K
    flat = [c if isinstance(c, Jet) else Jet(float(c), zeros, 0.0, zeros, 0.0)
            for row in rows for c in row]
    n = len(flat) // 3
    if n * 3 != len(flat) or n == 0:
        raise ValueError(f"positions(q, t) must return N rows of 3 components, got {len(flat)} numbers")
    x = np.array([c.v for c in flat]).reshape(n, 3)
    d = np.array([c.d for c in flat]).reshape(n, 3, K)
    x_dot = np.array([c.w for c in flat]).reshape(n, 3)
    dw = np.array([c.dw for c in flat]).reshape(n, 3, K)
    a0 = np.array([c.ww for c in flat]).reshape(n, 3)
    return x, d[:, :, :m], d[:, :, m], x_dot, dw[:, :, :m], a0


# ---------------------------------------------------------------------------- systems
Positions = Callable[[Sequence[Scalar], Scalar], Any]
Forces = Callable[[Array, Array, float], Array]
Potential = Callable[[Array, float], float]


@dataclass(frozen=True)
class System:
    """A constrained particle system (see the module docstring).

    name: what it is.  coordinates: the names of q_1 … q_m ("θ", "φ").  angular: per coordinate,
    True if it is an angle [rad] (shown in degrees), False for a length [m].  masses: (N,) [kg].
    positions(q, t) -> N rows of (x, y, z) [m], written with +, −, *, /, ** and `sin`, `cos`,
    `sqrt`, `exp`, `log` (or numpy's ufuncs) so that it runs on Jets.  forces(x (N, 3), ẋ (N, 3),
    t) -> F (N, 3) [N], the applied forces.  potential(x, t) -> V [J] with F = −∂V/∂x, or None.
    params: the parameters it was built from (for display).  links: pairs (i, j) of particles
    joined by a rod, −1 the fixed pivot at the origin (drawn).  guide: for one coordinate,
    (lo, hi): the constraint curve at time t is {x_0(q, t): q in [lo, hi]} (the hoop, the rod).
    rheonomic: True if x depends on t explicitly (∂x/∂t ≠ 0: h is Jacobi's integral, not the
    energy).  limit: the largest |q_1| allowed (the rod's half length) or None.
    """

    name: str
    coordinates: tuple[str, ...]
    angular: tuple[bool, ...]
    masses: tuple[float, ...]
    positions: Positions
    forces: Forces
    potential: Potential | None = None
    params: tuple[tuple[str, float], ...] = ()
    links: tuple[tuple[int, int], ...] = ()
    guide: tuple[float, float] | None = None
    rheonomic: bool = False
    limit: float | None = None
    mass_array: Array = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if len(self.coordinates) != len(self.angular) or not self.coordinates:
            raise ValueError("a system needs at least one coordinate, each angular or not")
        masses = np.array(self.masses, dtype=float)
        if masses.ndim != 1 or not np.all(np.isfinite(masses)) or np.any(masses <= 0.0):
            raise ValueError(f"masses must be positive and finite, got {self.masses}")
        masses.flags.writeable = False
        object.__setattr__(self, "mass_array", masses)

    @property
    def m(self) -> int:
        """Degrees of freedom."""
        return len(self.coordinates)

    @property
    def n(self) -> int:
        """Particles."""
        return len(self.masses)

    def evaluate(self, q: Numbers, q_dot: Numbers, t: float) -> Evaluation:
        """Everything (5.1)-(5.13) says at the state (q, q̇, t), q̈ from Lagrange's equations."""
        return Evaluation.at(self, np.asarray(q, dtype=float), np.asarray(q_dot, dtype=float), float(t))

    def accelerations(self, q: Array, q_dot: Array, t: float) -> Array:
        """q̈ (m,) from M q̈ = Q − Σ_i m_i J_iᵀ ww_i (what the integrator calls: the same sums as
        `Evaluation.at`, in plain floats over the 3N components); SingularCoordinatesError where M
        is singular."""
        m = len(q)
        qs, t_jet = _seed(q, q_dot, t)
        rows = self.positions(qs, t_jet)
        comps = [c if isinstance(c, Jet) else None for row in rows for c in row]
        values = [c.v if c is not None else float(x) for c, x in zip(comps, (x for row in rows for x in row))]
        velocities = [c.w if c is not None else 0.0 for c in comps]
        n = len(comps) // 3
        F = np.asarray(self.forces(np.array(values).reshape(n, 3), np.array(velocities).reshape(n, 3), float(t)),
                       dtype=float).ravel().tolist()
        masses = self.masses
        M = [[0.0] * m for _ in range(m)]
        rhs = [0.0] * m
        for k, c in enumerate(comps):
            if c is None:
                continue
            mass = masses[k // 3]
            d = c.d
            force = F[k] - mass * c.ww
            for j in range(m):
                rhs[j] += force * d[j]
                md = mass * d[j]
                row = M[j]
                for i in range(j, m):
                    row[i] += md * d[i]
        for j in range(m):
            for i in range(j):
                M[j][i] = M[i][j]
        if m == 1:
            if not M[0][0] > 0.0:
                raise SingularCoordinatesError(f"the mass matrix is {M[0][0]!r} at q = {list(q)}")
            return np.array([rhs[0] / M[0][0]])
        if m == 2:
            a, b, d2 = M[0][0], M[0][1], M[1][1]
            det = a * d2 - b * b
            trace = a + d2
            # cond(M) = λmax/λmin ≈ trace²/det for a symmetric positive 2x2 with λmin ≪ λmax
            if not (det > 0.0 and trace * trace < MAX_CONDITION * det):
                _solve(np.array(M), np.array(rhs), np.asarray(q, dtype=float))  # raises with the message
            return np.array([(d2 * rhs[0] - b * rhs[1]) / det, (a * rhs[1] - b * rhs[0]) / det])
        return _solve(np.array(M), np.array(rhs), np.asarray(q, dtype=float))


def _solve(M: Array, rhs: Array, q: Array) -> Array:
    if M.shape == (1, 1):
        if not M[0, 0] > 0.0:
            raise SingularCoordinatesError(f"the mass matrix is {M[0, 0]!r} at q = {q.tolist()}")
        return rhs / M[0, 0]
    if np.linalg.cond(M) > MAX_CONDITION:
        raise SingularCoordinatesError(
            f"the mass matrix is singular at q = {np.round(q, 6).tolist()} (cond M > {MAX_CONDITION:.0e}): "
            "the coordinates fail here (a pendulum through its pole: φ undefined)")
    solution: Array = np.asarray(np.linalg.solve(M, rhs), dtype=np.float64)
    return solution


@dataclass(frozen=True)
class Terms:
    """Lagrange's equations (5.13) term by term, per coordinate, each (m,).

    ddt_dT_dqdot: d/dt ∂T/∂q̇_j.  dT_dq: ∂T/∂q_j.  Q: Q_j (5.12).  residual: the first minus the
    second minus the third (rounding).  Units: [N m] for an angle, [N] for a length.
    """

    ddt_dT_dqdot: Array
    dT_dq: Array
    Q: Array
    residual: Array


@dataclass(frozen=True)
class Evaluation:
    """A system at one state (q, q̇, t), q̈ from (5.13).  Shapes: N particles, m coordinates.

    x, x_dot, x_ddot: (N, 3) [m, m/s, m/s²].  J: (N, 3, m) ∂x_i/∂q_j (the virtual displacement
    of particle i per unit δq_j (5.6)).  x_t: (N, 3) ∂x_i/∂t.  x_dot_q: (N, 3, m) ∂ẋ_i/∂q_j.
    F: (N, 3) applied forces [N].  C: (N, 3) constraint forces m_i ẍ_i − F_i [N].  M: (m, m)
    mass matrix.  q, q_dot, q_ddot: (m,).  p: (m,) ∂T/∂q̇_j.  Q: (m,) generalized forces (5.12).
    virtual_work: (N, m) C_i · ∂x_i/∂q_j (5.7), per unit δq_j.  T, T2, T1, T0, V [J] (V NaN if
    the forces have no potential), h = T₂ − T₀ + V.
    """

    system: System
    t: float
    q: Array
    q_dot: Array
    q_ddot: Array
    x: Array
    x_dot: Array
    x_ddot: Array
    J: Array
    x_t: Array
    x_dot_q: Array
    F: Array
    C: Array
    M: Array
    p: Array
    Q: Array
    virtual_work: Array
    terms: Terms
    T: float
    T2: float
    T1: float
    T0: float
    V: float
    h: float

    @classmethod
    def at(cls, system: System, q: Array, q_dot: Array, t: float) -> Evaluation:
        x, J, x_t, x_dot, x_dot_q, a0 = derivatives(system.positions, q, q_dot, t)
        m_i = system.mass_array
        F = np.asarray(system.forces(x, x_dot, t), dtype=float)
        mJ = m_i[:, None, None] * J
        M = np.einsum("nci,ncj->ij", mJ, J)
        Q = np.einsum("nc,ncj->j", F, J)
        q_ddot = _solve(M, Q - np.einsum("nc,ncj->j", a0, mJ), q)
        x_ddot = J @ q_ddot + a0
        C = m_i[:, None] * x_ddot - F
        m_x_dot = m_i[:, None] * x_dot
        p = np.einsum("nc,ncj->j", m_x_dot, J)
        dT_dq = np.einsum("nc,ncj->j", m_x_dot, x_dot_q)
        ddt_p = np.einsum("nc,ncj->j", m_i[:, None] * x_ddot, J) + np.einsum("nc,ncj->j", m_x_dot, x_dot_q)
        terms = Terms(ddt_p, dT_dq, Q, ddt_p - dT_dq - Q)
        v_q = J @ q_dot
        T2 = 0.5 * float(q_dot @ M @ q_dot)
        T1 = float(np.sum(m_i[:, None] * v_q * x_t))
        T0 = 0.5 * float(np.sum(m_i[:, None] * x_t * x_t))
        T = 0.5 * float(np.sum(m_i[:, None] * x_dot * x_dot))
        V = float(system.potential(x, t)) if system.potential is not None else math.nan
        return cls(system, t, q.copy(), q_dot.copy(), q_ddot, x, x_dot, x_ddot, J, x_t, x_dot_q, F, C, M, p, Q,
                   np.einsum("nc,ncj->nj", C, J), terms, T, T2, T1, T0, V, T2 - T0 + V)


# ---------------------------------------------------------------------------- presets
def _gravity(masses: Sequence[float], g: float) -> tuple[Forces, Potential]:
    weights = np.array(masses, dtype=float) * g
    weights.flags.writeable = False  # shared by copies of the system (a fork copies no function)

    def forces(x: Array, x_dot: Array, t: float) -> Array:
        F = np.zeros_like(x)
        F[:, 2] = -weights
        return F

    def potential(x: Array, t: float) -> float:
        return float(weights @ x[:, 2])

    return forces, potential


def _check(**values: float) -> None:
    for name, value in values.items():
        if not math.isfinite(value):
            raise ValueError(f"{name} = {value!r} refused: not a finite number")
    for name in ("R", "L", "L1", "L2", "length", "m", "m1", "m2"):
        if name in values and not values[name] > 0.0:
            raise ValueError(f"{name} = {values[name]!r} refused: it must be > 0")
    if "g" in values and values["g"] < 0.0:
        raise ValueError(f"g = {values['g']!r} refused: it must be ≥ 0")


def bead_on_turning_hoop(R: float = 1.0, Omega: float = 4.0, m: float = 1.0, g: float = 9.81) -> System:
    """A bead on a hoop of radius R [m] turning about its vertical diameter (space z) at Ω [rad/s].

    q = (θ,): the angle from the hoop's lowest point, x = R (sin θ cos Ωt, sin θ sin Ωt, −cos θ).
    The constraint moves (∂x/∂t ≠ 0): the energy is not conserved, Jacobi's h is.
    """
    _check(R=R, Omega=Omega, m=m, g=g)

    def positions(q: Sequence[Scalar], t: Scalar) -> Any:
        theta = q[0]
        phi = Omega * t
        s = R * sin(theta)
        return [[s * cos(phi), s * sin(phi), -R * cos(theta)]]

    forces, potential = _gravity([m], g)
    return System("Bead on a turning hoop", ("θ",), (True,), (m,), positions, forces, potential,
                  (("R", R), ("Ω", Omega), ("m", m), ("g", g)), guide=(-math.pi, math.pi), rheonomic=Omega != 0.0)


def hoop_equilibrium(R: float, Omega: float, g: float) -> float:
    """The stable relative equilibrium θ* [rad] ≥ 0 of the bead on the turning hoop: 0 while
    Ω² R ≤ g, else arccos(g / (Ω² R))."""
    if Omega * Omega * R <= g:
        return 0.0
    return math.acos(g / (Omega * Omega * R))


def hoop_small_oscillation_rate(R: float, Omega: float, g: float) -> float:
    """ω [rad/s] of small oscillations about `hoop_equilibrium`: √(g/R − Ω²) below the critical
    rate, Ω sin θ* = √(Ω² − g²/(Ω² R²)) above it (0 at Ω² R = g)."""
    if Omega * Omega * R <= g:
        return math.sqrt(g / R - Omega * Omega)
    return math.sqrt(Omega * Omega - (g / (Omega * R)) ** 2)


def spherical_pendulum(L: float = 1.0, m: float = 1.0, g: float = 9.81) -> System:
    """A particle on a massless rod of length L [m] from a fixed pivot (the origin).

    q = (θ, φ): θ from the downward vertical, φ about space z; x = L (sin θ cos φ, sin θ sin φ,
    −cos θ).  Scleronomic: energy conserved; L_z = m L² sin² θ φ̇ = p_φ conserved (φ cyclic).
    Singular at θ = 0, π.
    """
    _check(L=L, m=m, g=g)

    def positions(q: Sequence[Scalar], t: Scalar) -> Any:
        theta, phi = q[0], q[1]
        s = L * sin(theta)
        return [[s * cos(phi), s * sin(phi), -L * cos(theta)]]

    forces, potential = _gravity([m], g)
    return System("Spherical pendulum", ("θ", "φ"), (True, True), (m,), positions, forces, potential,
                  (("L", L), ("m", m), ("g", g)), links=((-1, 0),))


def double_pendulum(L1: float = 1.0, L2: float = 1.0, m1: float = 1.0, m2: float = 1.0, g: float = 9.81) -> System:
    """Two particles on massless rods in the vertical xz plane: the pivot, rod L1 to particle 1,
    rod L2 to particle 2.  q = (θ₁, θ₂) from the downward vertical; x₁ = L1 (sin θ₁, 0, −cos θ₁),
    x₂ = x₁ + L2 (sin θ₂, 0, −cos θ₂).  Energy conserved; chaotic at large swings."""
    _check(L1=L1, L2=L2, m1=m1, m2=m2, g=g)

    def positions(q: Sequence[Scalar], t: Scalar) -> Any:
        a, b = q[0], q[1]
        x1, z1 = L1 * sin(a), -L1 * cos(a)
        return [[x1, 0.0, z1], [x1 + L2 * sin(b), 0.0, z1 - L2 * cos(b)]]

    forces, potential = _gravity([m1, m2], g)
    return System("Double pendulum", ("θ₁", "θ₂"), (True, True), (m1, m2), positions, forces, potential,
                  (("L₁", L1), ("L₂", L2), ("m₁", m1), ("m₂", m2), ("g", g)), links=((-1, 0), (0, 1)))


def bead_on_turning_rod(Omega: float = 1.0, length: float = 2.0, m: float = 1.0, g: float = 9.81) -> System:
    """A bead on a straight horizontal rod through the origin, turning about space z at Ω [rad/s].

    q = (r,): the bead's signed distance from the axis [m], x = (r cos Ωt, r sin Ωt, 0), the rod
    from −length to +length.  r̈ = Ω² r: the bead flies out (r = r₀ cosh Ωt from rest); it
    leaves the rod at |r| = length (`LeftTheConstraint`).  Gravity is perpendicular to the rod:
    Q = 0; the constraint force holds the bead up and pushes it round (Coriolis).  Jacobi's
    integral h = ½ m ṙ² − ½ m Ω² r² is conserved, the energy is not.
    """
    _check(Omega=Omega, length=length, m=m, g=g)

    def positions(q: Sequence[Scalar], t: Scalar) -> Any:
        r = q[0]
        phi = Omega * t
        return [[r * cos(phi), r * sin(phi), 0.0]]

    forces, potential = _gravity([m], g)
    return System("Bead on a turning rod", ("r",), (False,), (m,), positions, forces, potential,
                  (("Ω", Omega), ("ℓ", length), ("m", m), ("g", g)), guide=(-length, length),
                  rheonomic=Omega != 0.0, limit=length)


# ---------------------------------------------------------------------------- integration
_A, _B, _C = DOP853.A[: DOP853.n_stages, : DOP853.n_stages], DOP853.B, DOP853.C[: DOP853.n_stages]


def rk8_step(system: System, t: float, q: Array, q_dot: Array, h: float) -> tuple[Array, Array]:
    """One step h [s] of the 8th-order Dormand-Prince formula (DOP853's 12 stages, no error
    control) on y = (q, q̇), y' = (q̇, q̈(q, q̇, t)).  Returns (q, q̇) at t + h."""
    m = q.size
    y = np.concatenate([q, q_dot])
    K = np.empty((len(_B), 2 * m))
    for s in range(len(_B)):
        ys = y + h * (_A[s, :s] @ K[:s]) if s else y
        K[s, :m] = ys[m:]
        K[s, m:] = system.accelerations(ys[:m], ys[m:], t + _C[s] * h)
    y_new = y + h * (_B @ K)
    return y_new[:m], y_new[m:]


class GridIntegrator:
    """Frame-rate independent stepping of a `System`: whole steps H on the grid t = k H.

    The committed (grid) state moves in whole steps H = NOMINAL_STEP / SUBSTEPS from t = 0; the
    state at the time asked last, between two grid points, is one shorter `rk8_step` from the
    last grid point (shown, not committed).  Attributes (read them): q, q_dot, t (the state
    shown), steps (grid steps so far), H [s].
    """

    def __init__(self, system: System, q: Numbers, q_dot: Numbers, t: float = 0.0,
                 H: float = NOMINAL_STEP / SUBSTEPS) -> None:
        if not (math.isfinite(H) and H > 0.0):
            raise ValueError(f"the grid step H must be positive and finite, got {H!r}")
        self.system = system
        self.H = H
        self.t0 = float(t)
        self.steps = 0
        self._q_grid = np.array(q, dtype=float)
        self._q_dot_grid = np.array(q_dot, dtype=float)
        self.q, self.q_dot, self.t = self._q_grid.copy(), self._q_dot_grid.copy(), self.t0
        self._check(self.q, self.q_dot, self.t)

    @property
    def t_grid(self) -> float:
        return self.t0 + self.steps * self.H

    def snapshot(self) -> tuple[float, ...]:
        """Everything that changes as it advances, as floats: t (shown), steps, the grid state
        q, q̇ (m each) and the state shown q, q̇ (m each): 2 + 4m values."""
        return (float(self.t), float(self.steps), *self._q_grid.tolist(), *self._q_dot_grid.tolist(),
                *self.q.tolist(), *self.q_dot.tolist())

    def restore(self, values: Numbers) -> None:
        """A `snapshot` back bit for bit (ValueError, nothing changed, if it is not one of this
        integrator's: 2 + 4m finite values with a whole step count ≥ 0)."""
        m = len(self._q_grid)
        v = np.asarray(values, dtype=float)
        if v.shape != (2 + 4 * m,) or not np.all(np.isfinite(v)) or v[1] < 0 or v[1] != math.floor(v[1]):
            raise ValueError(f"not a snapshot of this integrator ({v.shape[0] if v.ndim == 1 else v.shape} "
                             f"values, {2 + 4 * m} wanted)")
        self.steps = int(v[1])
        self._q_grid, self._q_dot_grid = v[2:2 + m].copy(), v[2 + m:2 + 2 * m].copy()
        self.q, self.q_dot, self.t = v[2 + 2 * m:2 + 3 * m].copy(), v[2 + 3 * m:2 + 4 * m].copy(), float(v[0])

    def _check(self, q: Array, q_dot: Array, t: float) -> None:
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(q_dot))):
            raise ArithmeticError(f"the state is not finite at t = {t:.3f} s")
        limit = self.system.limit
        if limit is not None and abs(float(q[0])) > limit:
            raise LeftTheConstraint(f"the bead left the rod at t ≈ {t:.2f} s "
                                    f"({self.system.coordinates[0]} = {float(q[0]):.3g} m beyond ±{limit:g} m)")

    def advance(self, dt: float) -> None:
        """Advance the shown state by dt ≥ 0 [s].  On an error (ArithmeticError: singular
        coordinates, a bead off its rod, a blow-up) nothing changes: the state stays as it was."""
        if not (math.isfinite(dt) and dt >= 0.0):
            raise ValueError(f"advance: dt = {dt!r} must be finite and ≥ 0")
        target = self.t + dt
        H = self.H
        n = math.floor((target - self.t_grid) / H + 1e-9)
        if n > MAX_GRID_STEPS:
            raise ArithmeticError(f"advance by {dt:g} s needs {n} steps of {H:g} s (at most {MAX_GRID_STEPS})")
        q, q_dot, t = self._q_grid, self._q_dot_grid, self.t_grid
        steps = self.steps
        for _ in range(n):
            q, q_dot = rk8_step(self.system, t, q, q_dot, H)
            steps += 1
            t = self.t0 + steps * H
            self._check(q, q_dot, t)
        rest = target - t
        if rest > 1e-9 * H:
            q_shown, q_dot_shown = rk8_step(self.system, t, q, q_dot, rest)
            self._check(q_shown, q_dot_shown, target)
        else:
            q_shown, q_dot_shown = q.copy(), q_dot.copy()
        self._q_grid, self._q_dot_grid, self.steps = q, q_dot, steps
        self.q, self.q_dot, self.t = q_shown, q_dot_shown, target
