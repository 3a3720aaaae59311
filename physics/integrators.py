"""Singularity-free integrators of the rigid body: no Euler angles anywhere (PHYSICS.md, memo §6).

The equations (body axes = principal axes, R = R_space_body, the memo's D):
    Ṙ = R hat(ω_b),    L_b = I ω_b,    L̇_b = L_b × ω_b + Rᵀ M,
with M the torque about the centre of mass (or the pivot of a top) in space components.

Three methods, one interface (`Model`, `State`, output times -> `Trajectory`), each counting
evaluations and wall time (time.perf_counter around the integration only):

1. `integrate_splitting` / `step_realtime`: symplectic splitting, fixed step, order 2, 4, 6.
   State (q, L_b): the attitude as a unit quaternion q (R = R(q)) and the body angular
   momentum.  H = T(L_b) + V(R) (+ a non-conservative torque) is split into flows that are
   solved EXACTLY:
   * T = T_sym + T_rem (Touma-Wisdom 1994, Dullweber-Leimkuhler-McLachlan 1997): with
     a_k = 1/(2 I_k) and a permutation (o, r, s) of the body axes,
         T = a_r |L|² + (a_s - a_r) L_s²   +   (a_o - a_r) L_o²  =  T_sym + T_rem.
     The flow of T_sym (a symmetric top) rotates R about L_b by 2 a_r |L| τ and then about
     e_s by 2 (a_s - a_r) L_s τ, L_b turning back by that second angle; the flow of T_rem is a
     rotation about e_o.  r is the axis of the median moment and o the axis whose a_o is
     nearest a_r: T_rem is the smallest remainder, zero for a symmetric body, whose free motion
     is then exact at any spin rate.  At equal step this split was measured 10-400x more
     accurate than the split into three axis rotations Σ L_k²/2I_k (heavy and free, asymmetric
     and nearly symmetric bodies), for ~1.3x the work.
   * The torque is a kick L_b += τ Rᵀ M(t, R) with R and t frozen: exact for gravity and a
     constant space torque (one evaluation).  A hook torque may also depend on ω, so its kick
     is the explicit midpoint rule (two evaluations): exact when the hook does not depend on
     ω, else the method is 2nd order (the kick is then not symmetric).
   Strang step S(h) = T_sym(h/2) T_rem(h/2) K(h) T_rem(h/2) T_sym(h/2) (time advances in the
   T_sym flows, so the kick sits at the mid time): symmetric, order 2.  Order 4 by Suzuki's
   5-stage composition (γ = 1/(4 - 4^(1/3)) four times around 1 - 4γ; ~50x smaller error
   than the 3-stage triple jump at the same h, ~6x at the same work), order 6 by Yoshida's
   7-stage composition (solution A).  Adjacent T_sym flows are merged (they form a group).
   Conserves exactly in exact arithmetic: |L| and L_s = R L_b of the free body (each flow
   rotates R and turns L_b back by the same rotation); L·e_z of the heavy top (the kick
   changes L_b along e_3 × γ, orthogonal to γ = Rᵀ e_z); |q| = 1.  Rounding would let them
   drift by ~1e-11 over 1e7 stages (sin/cos round with a bias of ~1e-18 per rotation), so
   these invariants are restored every CHECK_EVERY steps (a change of ~1e-15 |L|).
   Symplectic on T*SO(3): the energy error stays bounded, O((h Ω)^order), without drift.
   Cost ~1.4 µs per Strang stage (heavy top): plain float arithmetic, no numpy in the loop.

2. `integrate_adaptive`: Dormand-Prince 8(5,3) (the DOP853 pair, coefficients from SciPy)
   with SciPy's step-size controller and 7th-order dense output, on y = (q, ω_b) in R^7.
   Order 8, accurate to the tolerance; conserves nothing exactly.  The right-hand side is
   homogeneous of degree 0 in q (the torque uses R(q/|q|)), so the direction of q evolves as
   for a unit quaternion whatever |q| does, and q is renormalised after every accepted step
   (exactly: the q-part of f is linear in q).  Every stage and the error norm are unrolled
   into straight-line float code generated once from the tableau (`_DOP853_SOURCE`): the same
   steps as solve_ivp(method="DOP853") without its per-stage numpy overhead.

3. `integrate_dop853`: the peer a user would pick, scipy.integrate.solve_ivp(method="DOP853",
   t_eval=...) on the same (q, ω_b) ODE with the same right-hand side; R from q at output.

Guards: a non-finite or non-orthogonal initial state raises IntegrationError at once.  A
non-finite state or a blow-up (|ω| > max(OMEGA_LIMIT, OMEGA_GROWTH Ω0)) raises
IntegrationError naming t, checked every step (adaptive), in the right-hand side (the peer:
solve_ivp itself keeps shrinking the step on NaN, scipy issues 11239 and 17846) or every
CHECK_EVERY steps (splitting).  The real-time step refuses more than MAX_SUBSTEPS sub-steps.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from math import cos, sin, sqrt

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp
from scipy.integrate._ivp import dop853_coefficients as _dop853

from physics._types import Array, Mat3, Vec3
from physics.dynamics import IntegrationError, Model, State, Trajectory

__all__ = [
    "COMPOSITIONS",
    "DEFAULT_STEP_ANGLE",
    "MAX_SUBSTEPS",
    "OMEGA_GROWTH",
    "OMEGA_LIMIT",
    "REALTIME_SUBSTEP_ANGLE",
    "integrate_adaptive",
    "integrate_dop853",
    "integrate_splitting",
    "rate_scale",
    "step_realtime",
]

OMEGA_LIMIT = 1e4
OMEGA_GROWTH = 1e3
"""A run is a blow-up (IntegrationError) when |ω| exceeds max(OMEGA_LIMIT [rad/s],
OMEGA_GROWTH * Ω0), Ω0 = `rate_scale` at its start: a 1000 rad/s spin is normal, a hook that
pumps energy in is stopped before its spin makes every step tiny.  (The work of an adaptive
method grows like the angle turned, so a limit of 1e8 rad/s would take minutes to reach.)"""

ORTHOGONALITY_TOL = 1e-9
"""An initial R with max |RᵀR - 1| above this is not a rotation (as CASEFILE.md)."""

REALTIME_SUBSTEP_ANGLE = 0.25
"""Real-time sub-step bound: h Ω <= this [rad] per sub-step, Ω = `rate_scale`.

Chosen for order 4 from measurements (tests/test_integrators.py repeats the worst): the
attitude error grows like C (h Ω)^4 Ω t with C <= 1e-6 on every hard case (worst: a free
asymmetric body spinning at 1000 rad/s about a generic axis), and |ΔE/E| <= 2e-6 (h Ω)^4.  At
0.25 rad that is <= 4e-9 rad per radian turned (1e-3 rad after 2.5e5 rad, e.g. 4 min at
1000 rad/s) and |ΔE/E| <= 1e-8.  A moderate scene (Ω < 60 rad/s at 1/240 s, < 15 rad/s at
1/60 s) never sub-steps.  For order 2 pass a smaller bound: its error is C2 (h Ω)^2 Ω t with
C2 up to 1e-3."""

DEFAULT_STEP_ANGLE = 0.05
"""`integrate_splitting` with h=None: h Ω = this [rad] (order 4).  Measured over 1e4 s:
max |ΔE/E| 7e-12 on the asymmetric heavy top (1, 1.5, 2), 2e-10 on a free body next to its
separatrix, neither with a trend; L·e_z and |L| drift < 1e-15."""

MAX_SUBSTEPS = 1000
"""A real-time step needing more sub-steps than this raises IntegrationError: |ω| beyond
~1.5e4 rad/s at 1/60 s (6e4 at 1/240 s), far past anything a display can show, and a frame
must stay short (1000 sub-steps ~ 15 ms without a hook) even when a torque hook runs away."""

CHECK_EVERY = 512
"""The splitting checks finiteness and the blow-up limit at least every this many steps."""

_RATE_FLOOR = 1.0  # [rad/s]: slower rate scales are raised to this when choosing a step


def _suzuki4() -> tuple[float, ...]:
    g = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
    return (g, g, 1.0 - 4.0 * g, g, g)


def _yoshida6() -> tuple[float, ...]:
    w1, w2, w3 = -1.17767998417887, 0.235573213359357, 0.784513610477560
    w0 = 1.0 - 2.0 * (w1 + w2 + w3)
    return (w3, w2, w1, w0, w1, w2, w3)


COMPOSITIONS: dict[int, tuple[float, ...]] = {2: (1.0,), 4: _suzuki4(), 6: _yoshida6()}
"""order -> symmetric composition coefficients γ of the Strang step: Ψ_h = Π S(γ_i h)."""

# ---------------------------------------------------------------------------------------
# Quaternions (w, x, y, z) <-> rotation matrices; R(q) maps body to space, R(q ⊗ p) = R(q) R(p).
# ---------------------------------------------------------------------------------------


def _quat_from_matrix(r: Sequence[float]) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) of the rotation with row-major entries r (9,) (Shepperd)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    trace = r00 + r11 + r22
    if trace > 0.0:
        s = 2.0 * sqrt(trace + 1.0)
        q = (0.25 * s, (r21 - r12) / s, (r02 - r20) / s, (r10 - r01) / s)
    elif r00 > r11 and r00 > r22:
        s = 2.0 * sqrt(1.0 + r00 - r11 - r22)
        q = ((r21 - r12) / s, 0.25 * s, (r01 + r10) / s, (r02 + r20) / s)
    elif r11 > r22:
        s = 2.0 * sqrt(1.0 + r11 - r00 - r22)
        q = ((r02 - r20) / s, (r01 + r10) / s, 0.25 * s, (r12 + r21) / s)
    else:
        s = 2.0 * sqrt(1.0 + r22 - r00 - r11)
        q = ((r10 - r01) / s, (r02 + r20) / s, (r12 + r21) / s, 0.25 * s)
    n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def _matrix_from_quat(w: float, x: float, y: float, z: float) -> list[float]:
    """Row-major entries (9,) of R(q / |q|)."""
    s = 2.0 / (w * w + x * x + y * y + z * z)
    return [
        1.0 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),
        s * (x * y + w * z), 1.0 - s * (x * x + z * z), s * (y * z - w * x),
        s * (x * z - w * y), s * (y * z + w * x), 1.0 - s * (x * x + y * y),
    ]  # fmt: skip


def _matrices_from_quats(q: Array) -> Array:
    """R (N, 3, 3) from quaternions q (N, 4) (w, x, y, z), normalised first."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    R = np.empty((q.shape[0], 3, 3))
    R[:, 0, 0] = 1.0 - 2.0 * (y * y + z * z)
    R[:, 0, 1] = 2.0 * (x * y - w * z)
    R[:, 0, 2] = 2.0 * (x * z + w * y)
    R[:, 1, 0] = 2.0 * (x * y + w * z)
    R[:, 1, 1] = 1.0 - 2.0 * (x * x + z * z)
    R[:, 1, 2] = 2.0 * (y * z - w * x)
    R[:, 2, 0] = 2.0 * (x * z - w * y)
    R[:, 2, 1] = 2.0 * (y * z + w * x)
    R[:, 2, 2] = 1.0 - 2.0 * (x * x + y * y)
    return R


# ---------------------------------------------------------------------------------------
# Validation and guards
# ---------------------------------------------------------------------------------------


def _validated_state(state: State) -> tuple[list[float], list[float], float]:
    """(R row-major (9,), ω_b (3,), t) as floats; IntegrationError if not finite or not in SO(3)."""
    R = np.asarray(state.R_space_body, dtype=float)
    omega = np.asarray(state.omega_body, dtype=float)
    if R.shape != (3, 3) or omega.shape != (3,):
        raise IntegrationError(f"state must hold R (3, 3) and omega_body (3,), got {R.shape}, {omega.shape}")
    r = R.ravel().tolist()
    w = omega.tolist()
    t = float(state.t)
    if not math.isfinite(sum(r) + w[0] + w[1] + w[2] + t):  # NaN, ±inf (or values near overflow)
        raise IntegrationError(f"non-finite state at t = {state.t}: R = {R.tolist()}, omega_body = {w}")
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    residual = max(
        abs(r00 * r00 + r10 * r10 + r20 * r20 - 1.0),
        abs(r01 * r01 + r11 * r11 + r21 * r21 - 1.0),
        abs(r02 * r02 + r12 * r12 + r22 * r22 - 1.0),
        abs(r00 * r01 + r10 * r11 + r20 * r21),
        abs(r00 * r02 + r10 * r12 + r20 * r22),
        abs(r01 * r02 + r11 * r12 + r21 * r22),
    )
    if residual > ORTHOGONALITY_TOL:
        raise IntegrationError(
            f"R is not orthogonal at t = {t}: max |RᵀR - 1| = {residual:.3g} > {ORTHOGONALITY_TOL:g}"
        )
    det = r00 * (r11 * r22 - r12 * r21) - r01 * (r10 * r22 - r12 * r20) + r02 * (r10 * r21 - r11 * r20)
    if det < 0.0:
        raise IntegrationError(f"R is a reflection at t = {t} (det R = {det:.6g}), not a rotation")
    return r, w, t


def _omega_limit(rate0: float) -> float:
    """The blow-up threshold [rad/s] of a run that starts with rate scale rate0 [rad/s]."""
    return max(OMEGA_LIMIT, OMEGA_GROWTH * rate0)


def _validated_times(t_eval: ArrayLike, t0: float) -> Array:
    t = np.array(t_eval, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"t_eval must be a non-empty 1-D array, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError("t_eval must be finite")
    if np.any(np.diff(t) <= 0.0) or t[0] < t0:
        raise ValueError(f"t_eval must be strictly increasing and start at or after state0.t = {t0}")
    return t


def _check_finite(t: float, y: Sequence[float], omega: float, omega_limit: float) -> None:
    """IntegrationError unless y is finite and omega <= omega_limit [rad/s]."""
    if not math.isfinite(sum(y)):
        raise IntegrationError(f"non-finite state at t = {t:.9g} s: y = {list(y)}")
    if omega > omega_limit:
        raise IntegrationError(
            f"blow-up at t = {t:.9g} s: |omega| ~ {omega:.3g} rad/s exceeds the limit {omega_limit:.3g} rad/s"
        )


# ---------------------------------------------------------------------------------------
# The splitting
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Splitting:
    """A model seen in the working frame of the splitting, with precomputed constants.

    Working axes (x_w, y_w, z_w) = (e_o, ±e_r, e_s): work axis j is sign[j] * body axis
    perm[j] (sign[1] = -1 when (o, r, s) is an odd permutation, to stay right-handed), so
    R_work = R_body P with P = `P_body_work()`.  a = (a_o, a_r, a_s), a_k = 1/(2 I_k).
    gravity: mgl * (body e_3 in working components), or None.  torque: a callback
    (t, qw, qx, qy, qz, Lx, Ly, Lz) -> torque (3,) in working components, for a constant torque
    and/or a hook, or None.  hook: a hook is present (its kick uses the midpoint rule).
    """

    perm: tuple[int, int, int]
    sign: tuple[float, float, float]
    a: tuple[float, float, float]
    gravity: tuple[float, float, float] | None
    torque: Callable[[float, float, float, float, float, float, float, float], tuple[float, float, float]] | None
    inertia: tuple[float, float, float]
    hook: bool
    conservative: bool
    mgl: float
    torque_scale: float  # |mgl| + |torque_space| [N m]
    work_axis: tuple[int, int, int]  # inverse of perm
    tables: dict[tuple[float, int], tuple[list[tuple[float, ...]], ...]] = field(
        default_factory=dict, compare=False, repr=False
    )
    last: list[object] = field(default_factory=list, compare=False, repr=False)  # see step_realtime

    @property
    def kicks(self) -> bool:
        return self.gravity is not None or self.torque is not None

    def work_from_body(self, r: Sequence[float], omega_body: Sequence[float]) -> list[float]:
        """y = (qw, qx, qy, qz, Lx, Ly, Lz) in the working frame from R (9,) row-major, ω_b (3,)."""
        p0, p1, p2 = self.perm
        s1 = self.sign[1]
        q = _quat_from_matrix(
            (r[p0], s1 * r[p1], r[p2], r[3 + p0], s1 * r[3 + p1], r[3 + p2], r[6 + p0], s1 * r[6 + p1], r[6 + p2])
        )
        i = self.inertia
        return [*q, i[p0] * omega_body[p0], s1 * i[p1] * omega_body[p1], i[p2] * omega_body[p2]]

    def body_from_work(self, y: Sequence[float]) -> tuple[list[float], list[float]]:
        """(R row-major (9,), ω_b (3,)) from the working-frame y (7,)."""
        rw = _matrix_from_quat(y[0], y[1], y[2], y[3])
        inertia = self.inertia
        j0, j1, j2 = self.work_axis  # body axis k is sign[j_k] * work axis j_k
        s0, s1, s2 = self.sign[j0], self.sign[j1], self.sign[j2]
        r = [
            s0 * rw[j0], s1 * rw[j1], s2 * rw[j2],
            s0 * rw[3 + j0], s1 * rw[3 + j1], s2 * rw[3 + j2],
            s0 * rw[6 + j0], s1 * rw[6 + j1], s2 * rw[6 + j2],
        ]  # fmt: skip
        omega = [s0 * y[4 + j0] / inertia[0], s1 * y[4 + j1] / inertia[1], s2 * y[4 + j2] / inertia[2]]
        return r, omega

    def P_body_work(self) -> Mat3:
        """(3, 3): column j is working axis j in body components, so R_body = R_work Pᵀ."""
        P = np.zeros((3, 3))
        for j in range(3):
            P[self.perm[j], j] = self.sign[j]
        return P

    def rate_scale(self, r22: float, w: Sequence[float]) -> float:
        """`rate_scale` on floats: R[2, 2] and ω_b (3,)."""
        i1, i2, i3 = self.inertia
        i_min = min(i1, i2, i3)
        if self.conservative:
            kinetic = 0.5 * (i1 * w[0] * w[0] + i2 * w[1] * w[1] + i3 * w[2] * w[2])
            omega_max = sqrt(max(2.0 * (kinetic + self.mgl * r22 + abs(self.mgl)) / i_min, 0.0))
        else:
            omega_max = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
        return omega_max + sqrt(self.torque_scale / i_min)


def _splitting_for(model: Model) -> _Splitting:
    return _cached_splitting(model.inertia, model.mgl, model.torque_space, model.extra_torque)


@functools.lru_cache(maxsize=64)
def _cached_splitting(
    inertia: tuple[float, float, float],
    mgl: float,
    torque_space: tuple[float, float, float],
    hook: Callable[[float, Mat3, Vec3], Vec3] | None,
) -> _Splitting:
    """The working frame: r = axis of the median moment, o = the axis whose a_o is nearest
    a_r (smallest remainder T_rem), s = the third (the symmetry axis of a symmetric body)."""
    a_body = [0.5 / i for i in inertia]
    r = sorted(range(3), key=lambda k: inertia[k])[1]
    i, j = (k for k in range(3) if k != r)
    o, s = (i, j) if abs(a_body[i] - a_body[r]) <= abs(a_body[j] - a_body[r]) else (j, i)
    perm = (o, r, s)
    even = perm in ((0, 1, 2), (1, 2, 0), (2, 0, 1))
    sign = (1.0, 1.0 if even else -1.0, 1.0)
    a = (a_body[o], a_body[r], a_body[s])
    gravity = None
    if mgl != 0.0:
        gravity = tuple(mgl * sign[k] if perm[k] == 2 else 0.0 for k in range(3))
    P = np.zeros((3, 3))
    for k in range(3):
        P[perm[k], k] = sign[k]
    torque = None
    tau = torque_space
    if hook is not None or any(tau):
        inertia_w = tuple(inertia[perm[k]] for k in range(3))

        def torque(
            t: float, qw: float, qx: float, qy: float, qz: float, lx: float, ly: float, lz: float
        ) -> tuple[float, float, float]:
            rw = _matrix_from_quat(qw, qx, qy, qz)
            mx, my, mz = tau
            if hook is not None:
                R_work = np.array(rw).reshape(3, 3)
                omega_w = np.array([lx / inertia_w[0], ly / inertia_w[1], lz / inertia_w[2]])
                m = np.asarray(hook(t, R_work @ P.T, P @ omega_w), dtype=float)
                mx, my, mz = mx + float(m[0]), my + float(m[1]), mz + float(m[2])
            return (
                rw[0] * mx + rw[3] * my + rw[6] * mz,
                rw[1] * mx + rw[4] * my + rw[7] * mz,
                rw[2] * mx + rw[5] * my + rw[8] * mz,
            )

    conservative = hook is None and not any(tau)
    torque_scale = abs(mgl) + math.sqrt(sum(m * m for m in tau))
    work_axis = (perm.index(0), perm.index(1), perm.index(2))
    return _Splitting(
        perm, sign, a, gravity, torque, inertia,  # type: ignore[arg-type]
        hook is not None, conservative, mgl, torque_scale, work_axis,
    )  # fmt: skip


def _stage_tables(sp: _Splitting, h: float, gammas: Sequence[float]) -> tuple[list[tuple[float, ...]], ...]:
    """Per-stage constants of Ψ_h = Π_i S(γ_i h), S(h) = T_sym(h/2) T_rem(h/2) K(h) T_rem(h/2) T_sym(h/2).

    Adjacent T_sym flows are merged, so a run of steps is a sequence of stages
    T_sym(δ h) T_rem(γ_i h/2) K(γ_i h) T_rem(γ_i h/2) with δ = γ_1/2 for the first stage of
    the run, (γ_{i-1} + γ_i)/2 inside a step, (γ_last + γ_1)/2 across a step boundary, and one
    closing T_sym(γ_last h/2).  A stage tuple holds (T_sym half-angle per |L|, T_sym half-angle
    per L_z, T_sym time advance, T_rem half-angle per L_x, kick τ, full): `full` is False for
    the closing T_sym.  Without a torque T_rem(γh/2) T_rem(γh/2) is one rotation T_rem(γh).
    Returns (first step, later steps, [closing], one whole step); memoised per (h, composition)
    on `sp`.
    """
    key = (h, len(gammas))
    tables = sp.tables.get(key)
    if tables is not None:
        return tables
    a_o, a_r, a_s = sp.a
    rem_factor = 1.0 if sp.kicks else 2.0

    def stage(d: float, g: float, full: bool = True) -> tuple[float, ...]:
        return (a_r * d * h, (a_s - a_r) * d * h, d * h, rem_factor * (a_o - a_r) * 0.5 * g * h, g * h, full)

    n = len(gammas)
    inner = [stage(0.5 * (gammas[i - 1] + gammas[i]), gammas[i]) for i in range(1, n)]
    first = [stage(0.5 * gammas[0], gammas[0]), *inner]
    later = [stage(0.5 * (gammas[-1] + gammas[0]), gammas[0]), *inner]
    closing = [stage(0.5 * gammas[-1], 0.0, False)]
    if len(sp.tables) > 256:
        sp.tables.clear()
    tables = (first, later, closing, first + closing)
    sp.tables[key] = tables
    return tables


def _invariant(sp: _Splitting, y: Sequence[float]) -> tuple[float, ...] | None:
    """What the exact-arithmetic method conserves exactly, from y (7,): L_s = R L_b (3,) of a
    free body, (L·e_z,) of a heavy top; None for other torques."""
    qw, qx, qy, qz, lx, ly, lz = y
    if not sp.kicks:
        r = _matrix_from_quat(qw, qx, qy, qz)
        return (
            r[0] * lx + r[1] * ly + r[2] * lz,
            r[3] * lx + r[4] * ly + r[5] * lz,
            r[6] * lx + r[7] * ly + r[8] * lz,
        )
    if sp.torque is None:
        r = _matrix_from_quat(qw, qx, qy, qz)
        return (r[6] * lx + r[7] * ly + r[8] * lz,)
    return None


def _advance(
    sp: _Splitting,
    y: Sequence[float],
    t: float,
    h: float,
    n_steps: int,
    gammas: Sequence[float],
    omega_limit: float,
    invariant: tuple[float, ...] | None = None,
) -> tuple[list[float], float]:
    """n_steps steps of size h of the composed splitting from y (7,) (working frame) at t [s].

    Returns the new (y, t).  Every CHECK_EVERY steps and at the end: q is renormalised; the
    `invariant` (see `_invariant`), which every flow keeps exactly in exact arithmetic, is
    restored against rounding drift (L_b = Rᵀ L_s, or L_b += (L_z - γ·L_b) γ, changes of
    ~1e-16 |L| that otherwise add up to ~1e-11 over 1e7 stages); finiteness and omega_limit
    [rad/s] are checked.  Plain float arithmetic: no numpy in this loop.
    """
    qw, qx, qy, qz, lx, ly, lz = y
    if n_steps <= 0:
        return [qw, qx, qy, qz, lx, ly, lz], t
    first, later, closing, single = _stage_tables(sp, h, gammas)
    has_rem = sp.a[0] != sp.a[1]
    has_z = sp.a[2] != sp.a[1]
    kicks = sp.kicks
    gravity = sp.gravity
    gx, gy, gz = gravity if gravity is not None else (0.0, 0.0, 0.0)
    torque = sp.torque
    midpoint = sp.hook
    inv_i_min = 1.0 / min(sp.inertia)
    if invariant is not None and len(invariant) == 3:
        space_x, space_y, space_z = invariant
    elif invariant is not None:
        vertical = invariant[0]
    done = 0
    while done < n_steps:
        chunk = min(CHECK_EVERY, n_steps - done)
        if n_steps == 1:
            program = single
        else:
            program = (first if done == 0 else later) + later * (chunk - 1)
            if done + chunk == n_steps:
                program += closing
        done += chunk
        for ka, kz, dt, kx, tau, full in program:
            # --- T_sym(δh): rotation of R about L_b (L_b fixed), then about z_w (L_b turns back)
            nl2 = lx * lx + ly * ly + lz * lz
            if nl2 > 0.0:
                nl = sqrt(nl2)
                half = ka * nl
                cw = cos(half)
                sf = sin(half) / nl
                px, py, pz = sf * lx, sf * ly, sf * lz
                qw, qx, qy, qz = (
                    qw * cw - qx * px - qy * py - qz * pz,
                    qw * px + qx * cw + qy * pz - qz * py,
                    qw * py - qx * pz + qy * cw + qz * px,
                    qw * pz + qx * py - qy * px + qz * cw,
                )
            if has_z:
                half = kz * lz
                ch = cos(half)
                sh = sin(half)
                c = ch * ch - sh * sh
                s = 2.0 * sh * ch
                qw, qx, qy, qz = qw * ch - qz * sh, qx * ch + qy * sh, qy * ch - qx * sh, qz * ch + qw * sh
                lx, ly = c * lx + s * ly, c * ly - s * lx
            t += dt
            if not full:
                break
            # --- T_rem(γh/2): rotation of R about x_w by 2 kx L_x, L_b turns back
            if has_rem:
                half = kx * lx
                ch = cos(half)
                sh = sin(half)
                c = ch * ch - sh * sh
                s = 2.0 * sh * ch
                qw, qx, qy, qz = qw * ch - qx * sh, qx * ch + qw * sh, qy * ch + qz * sh, qz * ch - qy * sh
                ly, lz = c * ly + s * lz, c * lz - s * ly
            if kicks:
                # --- K(γh): L_b += τ Rᵀ M, R and t frozen (exact for M = M(t, R))
                if gravity is not None:  # Rᵀ M = mgl γ × e_3 with γ = Rᵀ e_z (third row of R)
                    g0 = 2.0 * (qx * qz - qw * qy)
                    g1 = 2.0 * (qy * qz + qw * qx)
                    g2 = 1.0 - 2.0 * (qx * qx + qy * qy)
                    lx += tau * (g1 * gz - g2 * gy)
                    ly += tau * (g2 * gx - g0 * gz)
                    lz += tau * (g0 * gy - g1 * gx)
                if torque is not None:
                    mx, my, mz = torque(t, qw, qx, qy, qz, lx, ly, lz)
                    if midpoint:  # a hook may depend on ω: explicit midpoint rule, 2nd order
                        half = 0.5 * tau
                        mx, my, mz = torque(t, qw, qx, qy, qz, lx + half * mx, ly + half * my, lz + half * mz)
                    lx += tau * mx
                    ly += tau * my
                    lz += tau * mz
                # --- T_rem(γh/2) again
                if has_rem:
                    half = kx * lx
                    ch = cos(half)
                    sh = sin(half)
                    c = ch * ch - sh * sh
                    s = 2.0 * sh * ch
                    qw, qx, qy, qz = qw * ch - qx * sh, qx * ch + qw * sh, qy * ch + qz * sh, qz * ch - qy * sh
                    ly, lz = c * ly + s * lz, c * lz - s * ly
        n = sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        qw, qx, qy, qz = qw / n, qx / n, qy / n, qz / n
        if invariant is not None:
            if len(invariant) == 3:  # free body: L_b = Rᵀ L_s
                r = _matrix_from_quat(qw, qx, qy, qz)
                lx = r[0] * space_x + r[3] * space_y + r[6] * space_z
                ly = r[1] * space_x + r[4] * space_y + r[7] * space_z
                lz = r[2] * space_x + r[5] * space_y + r[8] * space_z
            else:  # heavy top: restore L·e_z = γ·L_b along γ = Rᵀ e_z (|γ| = 1)
                g0 = 2.0 * (qx * qz - qw * qy)
                g1 = 2.0 * (qy * qz + qw * qx)
                g2 = 1.0 - 2.0 * (qx * qx + qy * qy)
                d = vertical - (g0 * lx + g1 * ly + g2 * lz)
                lx, ly, lz = lx + d * g0, ly + d * g1, lz + d * g2
        _check_finite(t, (qw, qx, qy, qz, lx, ly, lz), sqrt(lx * lx + ly * ly + lz * lz) * inv_i_min, omega_limit)
    return [qw, qx, qy, qz, lx, ly, lz], t


def rate_scale(model: Model, R_space_body: Mat3, omega_body: Vec3) -> float:
    """Ω [rad/s]: the rate the splitting's step is measured against (h Ω = angle per step).

    Ω = ω_max + sqrt((|mgl| + |torque_space|) / I_min).  ω_max = |ω_b| in general; for a
    conservative model it is the bound sqrt(2 (E + |mgl|) / I_min) that E = T + V >= T - |mgl|
    puts on |ω_b| along the whole motion, so Ω, and the number of real-time sub-steps, stay
    constant along a trajectory (the sub-stepped map is the same symplectic map every frame).
    The second term is the rate of the torque (the pendulum frequency of a top).  A hook
    torque adds nothing: its time scale is unknown.
    """
    w = np.asarray(omega_body, dtype=float).tolist()
    return _splitting_for(model).rate_scale(float(np.asarray(R_space_body, dtype=float)[2, 2]), w)


def _gammas(order: int) -> tuple[float, ...]:
    if order not in COMPOSITIONS:
        raise ValueError(f"order must be one of {sorted(COMPOSITIONS)}, got {order!r}")
    return COMPOSITIONS[order]


def integrate_splitting(
    model: Model, state0: State, t_eval: ArrayLike, h: float | None = None, order: int = 4
) -> Trajectory:
    """Symplectic splitting (module docstring, method 1) with a fixed step, sampled at t_eval.

    Args:
        model: the body and its torque.
        state0: the initial state; R must be a rotation (max |RᵀR - 1| <= 1e-9), all finite.
        t_eval: (N,) output times [s], strictly increasing, t_eval[0] >= state0.t.
        h: step [s]; None chooses h = DEFAULT_STEP_ANGLE / Ω, Ω = `rate_scale` (>= 1 rad/s).
            Each output interval Δ is split into ceil(Δ / h) equal steps, so a uniform t_eval
            gives one constant step (needed for the no-drift property).
        order: 2 (Strang), 4 (Suzuki 5-stage composition) or 6 (Yoshida 7-stage).

    Returns:
        Trajectory with evaluations = Strang stages (= torque evaluations when there is a
        torque) and wall_s = seconds spent integrating.  Error O(h^order); exact |L_s| (free
        body) and L·e_z (heavy top); bounded energy error without drift.

    Raises:
        IntegrationError: bad initial state, a non-finite state or a blow-up
            (|ω| > max(OMEGA_LIMIT, OMEGA_GROWTH Ω0)).
        ValueError: bad t_eval, h or order.
    """
    r, w, t0 = _validated_state(state0)
    times = _validated_times(t_eval, t0)
    gammas = _gammas(order)
    sp = _splitting_for(model)
    rate0 = sp.rate_scale(r[8], w)
    if h is None:
        h = DEFAULT_STEP_ANGLE / max(rate0, _RATE_FLOOR)
    elif not (math.isfinite(h) and h > 0.0):
        raise ValueError(f"step h must be positive and finite, got {h}")
    start = time.perf_counter()
    y = sp.work_from_body(r, w)
    invariant = _invariant(sp, y)
    omega_limit = _omega_limit(rate0)
    t = t0
    samples = np.empty((times.size, 7))
    steps = 0
    for k, t_out in enumerate(times.tolist()):
        span = t_out - t
        if span > 0.0:
            n = max(1, math.ceil(span / h - 1e-9))
            y, _ = _advance(sp, y, t, span / n, n, gammas, omega_limit, invariant)
            steps += n
        t = t_out
        samples[k] = y
    R_work = _matrices_from_quats(samples[:, :4])
    P = sp.P_body_work()
    R = R_work @ P.T
    omega = (samples[:, 4:] @ P.T) / np.array(model.inertia)
    wall = time.perf_counter() - start
    return Trajectory(times, R, omega, steps * len(gammas), wall, f"splitting{order}")


def step_realtime(
    model: Model,
    state: State,
    dt: float,
    max_substep_angle: float = REALTIME_SUBSTEP_ANGLE,
    order: int = 4,
) -> tuple[State, int]:
    """Advance `state` by one display step dt [s] with the splitting, sub-stepping as needed.

    n = max(1, ceil(dt Ω / max_substep_angle)) equal sub-steps, Ω = `rate_scale` (for the
    free body and the heavy top a function of the energy only, so n does not change along a
    motion).  The default bound REALTIME_SUBSTEP_ANGLE = 0.25 rad keeps the 4th-order method
    within 1e-3 rad of attitude and 1e-5 relative energy on every hard case (see its
    docstring); at 1/240 s a moderate scene (Ω < 60 rad/s) takes a single step.

    Returns (new state at t + dt, evaluations = Strang stages used).  The new state's arrays
    are read-only: when the next call gets that same State back (the app's loop) it continues
    from the exact internal quaternion and skips validating and converting R (~4 µs a frame).

    Raises:
        IntegrationError: bad or non-finite state, a blow-up, or more than MAX_SUBSTEPS
            sub-steps needed (|ω| far beyond anything a display can show).
        ValueError: dt not positive and finite, or a bad order / max_substep_angle.
    """
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"display step dt must be positive and finite, got {dt}")
    if not (math.isfinite(max_substep_angle) and max_substep_angle > 0.0):
        raise ValueError(f"max_substep_angle must be positive and finite, got {max_substep_angle}")
    gammas = _gammas(order)
    sp = _splitting_for(model)
    last = tuple(sp.last)  # one atomic copy: another thread may step an equal model meanwhile
    if last and state.R_space_body is last[0] and state.omega_body is last[1] and state.t == last[2]:
        # The state this function returned last (its read-only arrays cannot have changed):
        # continue from the exact working-frame quaternion, skipping validation and conversion.
        y, rate, t0, invariant = last[3], last[4], last[2], last[5]
    else:
        r, w, t0 = _validated_state(state)
        y, rate = sp.work_from_body(r, w), sp.rate_scale(r[8], w)
        invariant = _invariant(sp, y)
    n = max(1, math.ceil(dt * rate / max_substep_angle))
    if n > MAX_SUBSTEPS:
        raise IntegrationError(
            f"at t = {t0:.9g} s the rate scale {rate:.3g} rad/s needs {n} sub-steps per display step "
            f"of {dt:g} s, more than MAX_SUBSTEPS = {MAX_SUBSTEPS}: a blow-up, or a spin too fast for real time"
        )
    y, _ = _advance(sp, y, t0, dt / n, n, gammas, _omega_limit(rate), invariant)
    r_new, w_new = sp.body_from_work(y)
    R_new = np.array(r_new).reshape(3, 3)
    omega_new = np.array(w_new)
    R_new.flags.writeable = False
    omega_new.flags.writeable = False
    t_new = t0 + dt
    sp.last[:] = (R_new, omega_new, t_new, y, sp.rate_scale(r_new[8], w_new), invariant)
    return State(R_new, omega_new, t_new), n * len(gammas)


# ---------------------------------------------------------------------------------------
# The quaternion ODE y = (qw, qx, qy, qz, ω1, ω2, ω3): q̇ = ½ q ⊗ (0, ω_b), Euler's equations
# ---------------------------------------------------------------------------------------

Rhs = Callable[..., tuple[float, ...]]  # f(t, qw, qx, qy, qz, w1, w2, w3) -> ẏ (7,)


def _quaternion_rhs(model: Model) -> Rhs:
    """ẏ of y = (q, ω_b) for `model`, on floats, homogeneous of degree 0 in q.

    q̇ = ½ q ⊗ (0, ω_b) (so that Ṙ = R hat(ω_b)); I ω̇_b = (I ω_b) × ω_b + R(q/|q|)ᵀ M.
    Specialised for the free body and the heavy top (Rᵀ M = mgl γ × e_3, γ = Rᵀ e_z).
    """
    i1, i2, i3 = model.inertia
    k1, k2, k3 = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3
    mgl = model.mgl
    kind = model.kind

    if kind == "free":

        def rhs(
            t: float, qw: float, qx: float, qy: float, qz: float, w1: float, w2: float, w3: float
        ) -> tuple[float, ...]:
            h1, h2, h3 = 0.5 * w1, 0.5 * w2, 0.5 * w3
            return (
                -qx * h1 - qy * h2 - qz * h3,
                qw * h1 + qy * h3 - qz * h2,
                qw * h2 + qz * h1 - qx * h3,
                qw * h3 + qx * h2 - qy * h1,
                k1 * w2 * w3,
                k2 * w3 * w1,
                k3 * w1 * w2,
            )

        return rhs

    if kind == "heavy_top":
        c1, c2 = 2.0 * mgl / i1, 2.0 * mgl / i2

        def rhs(
            t: float, qw: float, qx: float, qy: float, qz: float, w1: float, w2: float, w3: float
        ) -> tuple[float, ...]:
            h1, h2, h3 = 0.5 * w1, 0.5 * w2, 0.5 * w3
            s = 1.0 / (qw * qw + qx * qx + qy * qy + qz * qz)
            return (
                -qx * h1 - qy * h2 - qz * h3,
                qw * h1 + qy * h3 - qz * h2,
                qw * h2 + qz * h1 - qx * h3,
                qw * h3 + qx * h2 - qy * h1,
                k1 * w2 * w3 + c1 * s * (qy * qz + qw * qx),
                k2 * w3 * w1 - c2 * s * (qx * qz - qw * qy),
                k3 * w1 * w2,
            )

        return rhs

    tx, ty, tz = model.torque_space
    hook = model.extra_torque

    def rhs(
        t: float, qw: float, qx: float, qy: float, qz: float, w1: float, w2: float, w3: float
    ) -> tuple[float, ...]:
        r = _matrix_from_quat(qw, qx, qy, qz)
        mx, my, mz = tx - mgl * r[5], ty + mgl * r[2], tz  # + (-mgl e_z' × e_z), e_z' = R e_3
        if hook is not None:
            m = np.asarray(hook(t, np.array(r).reshape(3, 3), np.array([w1, w2, w3])), dtype=float)
            mx, my, mz = mx + float(m[0]), my + float(m[1]), mz + float(m[2])
        h1, h2, h3 = 0.5 * w1, 0.5 * w2, 0.5 * w3
        return (
            -qx * h1 - qy * h2 - qz * h3,
            qw * h1 + qy * h3 - qz * h2,
            qw * h2 + qz * h1 - qx * h3,
            qw * h3 + qx * h2 - qy * h1,
            k1 * w2 * w3 + (r[0] * mx + r[3] * my + r[6] * mz) / i1,
            k2 * w3 * w1 + (r[1] * mx + r[4] * my + r[7] * mz) / i2,
            k3 * w1 * w2 + (r[2] * mx + r[5] * my + r[8] * mz) / i3,
        )

    return rhs


# ---------------------------------------------------------------------------------------
# DOP853 unrolled: straight-line code generated from SciPy's tableau
# ---------------------------------------------------------------------------------------

_N = 7  # dimension of y
_N_STAGES = _dop853.N_STAGES  # 12 stages per step; stage 12 = f(t + h, y_new) (FSAL)


def _dop853_source() -> str:
    """Python source of `_dop853_step` and `_dop853_dense` for y in R^7.

    _dop853_step(f, t, h, rtol, atol, *y, *f0) -> (err, y_new (7,), f_new (7,), K (13*7,)):
        one DOP853 step exactly as scipy.integrate.RK45/DOP853 `rk_step`, and SciPy's error
        norm (the 5th- and 3rd-order estimates combined, RMS, scale atol + rtol max(|y|, |y_new|)).
    _dop853_dense(f, t, h, *y, *y_new, *K) -> F (7*7,): the coefficients of SciPy's 7th-order
        dense output (three more stages), evaluated by `_dense_eval`.
    """
    A, B, C, D, E3, E5 = _dop853.A, _dop853.B, _dop853.C, _dop853.D, _dop853.E3, _dop853.E5

    def combo(coefficients: Array, stages: range, i: int) -> str:
        terms = [f"{float(coefficients[j])!r} * k{j}_{i}" for j in stages if coefficients[j] != 0.0]
        return " + ".join(terms) if terms else "0.0"

    ys = lambda p: ", ".join(f"{p}{i}" for i in range(_N))  # noqa: E731
    ks = lambda s: ", ".join(f"k{s}_{i}" for i in range(_N))  # noqa: E731
    all_k = ", ".join(ks(s) for s in range(_N_STAGES + 1))
    src = [f"def _dop853_step(f, t, h, rtol, atol, {ys('y')}, {ks(0)}):"]
    for s in range(1, _N_STAGES):
        for i in range(_N):
            src.append(f"    z{i} = y{i} + h * ({combo(A[s], range(s), i)})")
        src.append(f"    {ks(s)} = f(t + {float(C[s])!r} * h, {ys('z')})")
    for i in range(_N):
        src.append(f"    z{i} = y{i} + h * ({combo(B, range(_N_STAGES), i)})")
    src.append(f"    {ks(_N_STAGES)} = f(t + h, {ys('z')})")
    src.append("    e5 = 0.0")
    src.append("    e3 = 0.0")
    for i in range(_N):
        src.append(f"    a = y{i} if y{i} > 0.0 else -y{i}")
        src.append(f"    b = z{i} if z{i} > 0.0 else -z{i}")
        src.append("    scale = atol + rtol * (a if a > b else b)")
        src.append(f"    e = ({combo(E5, range(_N_STAGES + 1), i)}) / scale")
        src.append("    e5 += e * e")
        src.append(f"    e = ({combo(E3, range(_N_STAGES + 1), i)}) / scale")
        src.append("    e3 += e * e")
    src.append(f"    err = 0.0 if e5 == 0.0 and e3 == 0.0 else abs(h) * e5 / (((e5 + 0.01 * e3) * {_N}) ** 0.5)")
    src.append(f"    return err, ({ys('z')}), ({ks(_N_STAGES)}), ({all_k})")
    src.append("")
    src.append(f"def _dop853_dense(f, t, h, {ys('y')}, {ys('w')}, {all_k}):")
    for s in range(_N_STAGES + 1, _dop853.N_STAGES_EXTENDED):
        for i in range(_N):
            src.append(f"    z{i} = y{i} + h * ({combo(A[s], range(s), i)})")
        src.append(f"    {ks(s)} = f(t + {float(C[s])!r} * h, {ys('z')})")
    out = []
    for i in range(_N):
        src.append(f"    d{i} = w{i} - y{i}")
        out.append(f"d{i}")
        out.append(f"h * k0_{i} - d{i}")
        out.append(f"2.0 * d{i} - h * (k{_N_STAGES}_{i} + k0_{i})")
        for m in range(D.shape[0]):
            out.append(f"h * ({combo(D[m], range(_dop853.N_STAGES_EXTENDED), i)})")
    src.append("    return (" + ", ".join(out) + ")")
    return "\n".join(src) + "\n"


_DOP853_SOURCE = _dop853_source()
_dop853_namespace: dict[str, object] = {}
exec(compile(_DOP853_SOURCE, "<physics.integrators DOP853>", "exec"), _dop853_namespace)  # noqa: S102
_dop853_step: Callable[..., tuple[float, tuple[float, ...], tuple[float, ...], tuple[float, ...]]]
_dop853_step = _dop853_namespace["_dop853_step"]  # type: ignore[assignment]
_dop853_dense: Callable[..., tuple[float, ...]] = _dop853_namespace["_dop853_dense"]  # type: ignore[assignment]
_DENSE_TERMS = 3 + _dop853.D.shape[0]  # F0..F6 per component


def _dense_eval(F: Sequence[float], y_old: Sequence[float], x: float) -> list[float]:
    """SciPy's DOP853 interpolant at x = (t - t_old)/h in [0, 1]:
    y_old + x (F0 + (1-x) (F1 + x (F2 + (1-x) (F3 + x (F4 + (1-x) (F5 + x F6))))))."""
    u = 1.0 - x
    out = []
    for i in range(_N):
        f0, f1, f2, f3, f4, f5, f6 = F[_DENSE_TERMS * i : _DENSE_TERMS * (i + 1)]
        out.append(y_old[i] + x * (f0 + u * (f1 + x * (f2 + u * (f3 + x * (f4 + u * (f5 + x * f6)))))))
    return out


_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0  # SciPy's controller constants
_ERROR_EXPONENT = -1.0 / 8.0  # -1 / (error estimator order 7 + 1)


def _rms(values: Sequence[float]) -> float:
    return math.sqrt(math.fsum(v * v for v in values) / len(values))


def _initial_step(
    rhs: Rhs, t0: float, y0: Sequence[float], f0: Sequence[float], span: float, rtol: float, atol: float
) -> float:
    """SciPy's `select_initial_step` (Hairer, Nørsett, Wanner II.4) for error order 7."""
    scale = [atol + abs(v) * rtol for v in y0]
    d0 = _rms([v / s for v, s in zip(y0, scale)])
    d1 = _rms([v / s for v, s in zip(f0, scale)])
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, span)
    y1 = [v + h0 * d for v, d in zip(y0, f0)]
    f1 = rhs(t0 + h0, *y1)
    d2 = _rms([(a - b) / s for a, b, s in zip(f1, f0, scale)]) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100.0 * h0, h1, span)


def _validated_tolerances(rtol: float, atol: float) -> None:
    if not (math.isfinite(rtol) and math.isfinite(atol) and rtol > 0.0 and atol > 0.0):
        raise ValueError(f"rtol and atol must be positive and finite, got {rtol}, {atol}")


def integrate_adaptive(
    model: Model, state0: State, t_eval: ArrayLike, rtol: float = 1e-12, atol: float = 1e-14
) -> Trajectory:
    """Adaptive DOP853 on y = (q, ω_b), unrolled (module docstring, method 2).

    Same pair, controller, initial step and dense output as solve_ivp(method="DOP853"), so it
    takes the same steps to the same accuracy, in 1/3-1/5 of the wall time.  Order 8 (error
    estimate of order 7, dense output of order 7); conserves nothing exactly, the error in E,
    |L| and the attitude follows the tolerance.

    Args:
        t_eval: (N,) output times [s], strictly increasing, t_eval[0] >= state0.t.
        rtol, atol: local error tolerances on (q, ω_b) [-, rad/s].

    Returns:
        Trajectory with evaluations = right-hand-side calls, wall_s = seconds integrating.

    Raises:
        IntegrationError: bad initial state, a non-finite state (NaN torque, overflow), a
            blow-up (|ω| > max(OMEGA_LIMIT, OMEGA_GROWTH Ω0)) or a step-size underflow, at
            once, naming t.
    """
    r, w, t0 = _validated_state(state0)
    times = _validated_times(t_eval, t0)
    _validated_tolerances(rtol, atol)
    rhs = _quaternion_rhs(model)
    omega_limit = _omega_limit(_splitting_for(model).rate_scale(r[8], w))
    start = time.perf_counter()
    y: tuple[float, ...] = (*_quat_from_matrix(r), *w)
    samples = np.empty((times.size, _N))
    out = times.tolist()
    k = 0
    while k < len(out) and out[k] <= t0:
        samples[k] = y
        k += 1
    t = t0
    t_end = out[-1]
    f = rhs(t, *y)
    evaluations = 1
    if t_end > t0:
        h_abs = _initial_step(rhs, t0, y, f, t_end - t0, rtol, atol)
        evaluations += 1
    while t < t_end:
        min_step = 10.0 * abs(math.nextafter(t, math.inf) - t)
        h_abs = max(h_abs, min_step)
        rejected = False
        while True:
            if h_abs < min_step:
                raise IntegrationError(f"step size underflow at t = {t:.9g} s (h = {h_abs:.3g} s): y = {list(y)}")
            t_new = t + h_abs
            if t_new > t_end:
                t_new = t_end
            h = t_new - t
            h_abs = h
            err, z, f_new, K = _dop853_step(rhs, t, h, rtol, atol, *y, *f)
            evaluations += _N_STAGES
            if not math.isfinite(err):
                raise IntegrationError(
                    f"non-finite state at t = {t:.9g} s (trial step h = {h:.3g} s): y = {list(y)}"
                )
            if err < 1.0:
                factor = _MAX_FACTOR if err == 0.0 else min(_MAX_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(_MIN_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
            rejected = True
        if not math.isfinite(math.fsum(z)):
            raise IntegrationError(f"non-finite state at t = {t_new:.9g} s: y = {list(z)}")
        if k < len(out) and out[k] <= t_new:
            F = _dop853_dense(rhs, t, h, *y, *z, *K)
            evaluations += _dop853.N_STAGES_EXTENDED - _N_STAGES - 1
            while k < len(out) and out[k] <= t_new:
                samples[k] = z if out[k] == t_new else _dense_eval(F, y, (out[k] - t) / h)
                k += 1
        # Renormalise q; exact for the homogeneous right-hand side (f's q-part is linear in q).
        n = 1.0 / sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2] + z[3] * z[3])
        y = (z[0] * n, z[1] * n, z[2] * n, z[3] * n, z[4], z[5], z[6])
        f = (f_new[0] * n, f_new[1] * n, f_new[2] * n, f_new[3] * n, f_new[4], f_new[5], f_new[6])
        t = t_new
        omega = sqrt(y[4] * y[4] + y[5] * y[5] + y[6] * y[6])
        if omega > omega_limit:
            raise IntegrationError(
                f"blow-up at t = {t:.9g} s: |omega| = {omega:.3g} rad/s exceeds the limit {omega_limit:.3g} rad/s"
            )
    R = _matrices_from_quats(samples[:, :4])
    omega_body = samples[:, 4:].copy()
    wall = time.perf_counter() - start
    return Trajectory(times, R, omega_body, evaluations, wall, "adaptive")


def integrate_dop853(
    model: Model, state0: State, t_eval: ArrayLike, rtol: float = 1e-12, atol: float = 1e-14
) -> Trajectory:
    """The peer: scipy.integrate.solve_ivp(method="DOP853", t_eval=t_eval) on y = (q, ω_b).

    The same (fast, float-level) right-hand side as `integrate_adaptive`; R = R(q/|q|) at
    output.  Order 8, conserves nothing exactly.  The right-hand side raises IntegrationError
    on a non-finite state or a blow-up (as `integrate_adaptive`), because solve_ivp itself keeps shrinking the
    step on NaN (scipy issues 11239, 17846) instead of stopping.

    Returns:
        Trajectory with evaluations = solve_ivp's nfev, wall_s = seconds in solve_ivp.
    """
    r, w, t0 = _validated_state(state0)
    times = _validated_times(t_eval, t0)
    _validated_tolerances(rtol, atol)
    rhs = _quaternion_rhs(model)
    isfinite = math.isfinite
    omega_limit = _omega_limit(_splitting_for(model).rate_scale(r[8], w))

    def fun(t: float, y: Array) -> tuple[float, ...]:
        values = y.tolist()
        derivative = rhs(t, *values)
        w1, w2, w3 = values[4], values[5], values[6]
        if not isfinite(sum(derivative)):
            raise IntegrationError(f"non-finite state at t = {t:.9g} s: y = {values}")
        if w1 * w1 + w2 * w2 + w3 * w3 > omega_limit * omega_limit:
            raise IntegrationError(f"blow-up at t = {t:.9g} s: |omega| exceeds the limit {omega_limit:.3g} rad/s")
        return derivative

    start = time.perf_counter()
    y0 = np.array([*_quat_from_matrix(r), *w])
    if times[-1] == t0:
        ys = np.repeat(y0[:, None], times.size, axis=1)
        evaluations = 0
    else:
        sol = solve_ivp(fun, (t0, float(times[-1])), y0, method="DOP853", t_eval=times, rtol=rtol, atol=atol)
        if sol.status != 0:
            raise IntegrationError(f"solve_ivp (DOP853) failed by t = {sol.t[-1]:.9g} s: {sol.message}")
        ys = sol.y
        evaluations = int(sol.nfev)
    R = _matrices_from_quats(ys[:4].T)
    omega_body = ys[4:].T.copy()
    wall = time.perf_counter() - start
    return Trajectory(times, R, omega_body, evaluations, wall, "dop853")
