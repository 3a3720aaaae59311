"""Symplectic splitting of the rigid body on T*SO(3), fixed step, order 2, 4 or 6.

The equations (docs/CONVENTIONS.md, memo §6; body axes = principal axes, R = R_space_body):
    Ṙ = R hat(ω_b),    L_b = I ω_b,    L̇_b = L_b × ω_b + Rᵀ M.
State (q, L_b): the attitude as a unit quaternion q (R = R(q), `physics.quaternion`) and the
body angular momentum.  H = T(L_b) + V(R) (+ a non-conservative torque) is split into flows
that are solved EXACTLY:

* T = T_sym + T_rem (Touma-Wisdom 1994, Dullweber-Leimkuhler-McLachlan 1997): with
  a_k = 1/(2 I_k) and a permutation (o, r, s) of the body axes,
      T = a_r |L|² + (a_s - a_r) L_s²   +   (a_o - a_r) L_o²  =  T_sym + T_rem.
  The flow of T_sym (a symmetric top) rotates R about L_b by 2 a_r |L| τ and then about e_s by
  2 (a_s - a_r) L_s τ, L_b turning back by that second angle; the flow of T_rem is a rotation
  about e_o.  r is the axis of the median moment and o the axis whose a_o is nearest a_r:
  T_rem is the smallest remainder, zero for a symmetric body, whose free motion is then exact
  at any spin rate.  At equal step this split was measured 10-400x more accurate than the
  split into three axis rotations Σ L_k²/2I_k, for ~1.3x the work.
* The torque is a kick L_b += τ Rᵀ M(t, R) with R and t frozen: exact for gravity and a
  constant space torque (one evaluation).  A hook torque may also depend on ω, so its kick is
  the explicit midpoint rule (two evaluations): exact when the hook does not depend on ω, else
  the method is 2nd order.

Strang step S(h) = T_sym(h/2) T_rem(h/2) K(h) T_rem(h/2) T_sym(h/2) (time advances in the T_sym
flows, so the kick sits at the mid time): symmetric, order 2.  Order 4 by Suzuki's 5-stage
composition (γ = 1/(4 - 4^(1/3)) four times around 1 - 4γ; ~50x smaller error than the 3-stage
triple jump at the same h), order 6 by Yoshida's 7-stage composition (solution A):
`COMPOSITIONS[order]` are the γ, `STAGES[order]` the number of Strang stages per step.
Adjacent T_sym flows are merged (they form a group).

Conserves exactly in exact arithmetic: |L| and L_s = R L_b of the free body (each flow rotates
R and turns L_b back by the same rotation); L·e_z of the heavy top (the kick changes L_b along
e_3 × γ, orthogonal to γ = Rᵀ e_z); |q| = 1.  Rounding would let them drift by ~1e-11 over 1e7
stages, so these invariants are restored every CHECK_EVERY steps (a change of ~1e-15 |L|).
Symplectic: the energy error stays bounded, O((h Ω)^order), without drift.  Cost ~1.2 µs per
Strang stage (heavy top): plain float arithmetic, no numpy in the loop.
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Callable, Sequence
from math import cos, sin, sqrt
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from physics._types import Mat3
from physics.dynamics import Model, State, Trajectory
from physics.guards import (
    check_finite,
    omega_limit,
    rate_scale,
    rate_scale_function,
    validated_state,
    validated_times,
)
from physics.quaternion import matrices_from_wxyz, row_major_from_wxyz, wxyz_from_row_major

__all__ = [
    "CHECK_EVERY",
    "COMPOSITIONS",
    "DEFAULT_STEP_ANGLE",
    "STAGES",
    "Splitting",
    "advance",
    "gammas_of",
    "integrate_splitting",
    "rate_scale",
]

DEFAULT_STEP_ANGLE = 0.05
"""`integrate_splitting` with h=None: h Ω = this [rad] (order 4).  Measured over 1e4 s:
max |ΔE/E| 7e-12 on the asymmetric heavy top (1, 1.5, 2), 2e-10 on a free body next to its
separatrix, neither with a trend; L·e_z and |L| drift < 1e-15."""

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

STAGES: dict[int, int] = {order: len(gammas) for order, gammas in COMPOSITIONS.items()}
"""order -> Strang stages per step (2: 1, 4: 5, 6: 7): the torque evaluations of one step."""

Stage = tuple[float, float, float, float, float, bool]
TorqueW = Callable[[float, float, float, float, float, float, float, float], tuple[float, float, float]]


def gammas_of(order: int) -> tuple[float, ...]:
    """COMPOSITIONS[order]; ValueError for an order without a composition."""
    if order not in COMPOSITIONS:
        raise ValueError(f"order must be one of {sorted(COMPOSITIONS)}, got {order!r}")
    return COMPOSITIONS[order]


class Splitting:
    """A model seen in the working frame of the splitting, with precomputed constants.

    Working axes (x_w, y_w, z_w) = (e_o, ±e_r, e_s): work axis j is sign[j] * body axis perm[j]
    (sign[1] = -1 when (o, r, s) is an odd permutation, to stay right-handed), so
    R_work = R_body P with P = `P_body_work()`.  a = (a_o, a_r, a_s), a_k = 1/(2 I_k).  r is the
    axis of the median moment, o the axis whose a_o is nearest a_r (smallest remainder T_rem),
    s the third (the symmetry axis of a symmetric body).
    gravity: mgl * (body e_3 in working components), or None.  torque: a callback
    (t, qw, qx, qy, qz, Lx, Ly, Lz) -> torque (3,) in working components, for a constant torque
    and/or a hook, or None.  hook: a hook is present (its kick uses the midpoint rule).

    Built per run (a few µs); `stage_tables` memoises per (h, composition) on the instance, so
    two instances on equal models never share anything.
    """

    def __init__(self, model: Model) -> None:
        inertia = model.inertia
        mgl = model.mgl
        hook = model.extra_torque
        tau = model.torque_space
        a_body = [0.5 / i for i in inertia]
        r = sorted(range(3), key=lambda k: inertia[k])[1]
        i, j = (k for k in range(3) if k != r)
        o, s = (i, j) if abs(a_body[i] - a_body[r]) <= abs(a_body[j] - a_body[r]) else (j, i)
        perm = (o, r, s)
        even = perm in ((0, 1, 2), (1, 2, 0), (2, 0, 1))
        sign = (1.0, 1.0 if even else -1.0, 1.0)
        self.model = model
        self.perm: tuple[int, int, int] = perm
        self.sign: tuple[float, float, float] = sign
        self.a: tuple[float, float, float] = (a_body[o], a_body[r], a_body[s])
        self.inertia: tuple[float, float, float] = inertia
        self.work_axis: tuple[int, int, int] = (perm.index(0), perm.index(1), perm.index(2))
        self.gravity: tuple[float, float, float] | None = None
        if mgl != 0.0:
            g = [mgl * sign[k] if perm[k] == 2 else 0.0 for k in range(3)]
            self.gravity = (g[0], g[1], g[2])
        self.hook = hook is not None
        self.torque: TorqueW | None = None
        if hook is not None or any(tau):
            self.torque = self._torque_callback(model)
        self.kicks = self.gravity is not None or self.torque is not None
        self.rate_scale: Callable[[float, Sequence[float]], float] = rate_scale_function(model)
        self.tables: dict[tuple[float, int], tuple[list[Stage], ...]] = {}
        self._plans: dict[tuple[float, ...], tuple[tuple[object, ...], dict[str, object]]] = {}
        self.inv_i_min = 1.0 / min(inertia)

    def _torque_callback(self, model: Model) -> TorqueW:
        hook = model.extra_torque
        tau = model.torque_space
        inertia_w = tuple(model.inertia[self.perm[k]] for k in range(3))
        P = self.P_body_work()

        def torque(
            t: float, qw: float, qx: float, qy: float, qz: float, lx: float, ly: float, lz: float
        ) -> tuple[float, float, float]:
            rw = row_major_from_wxyz(qw, qx, qy, qz)
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

        return torque

    def work_from_body(self, r: Sequence[float], omega_body: Sequence[float]) -> list[float]:
        """y = (qw, qx, qy, qz, Lx, Ly, Lz) in the working frame from R (9,) row-major, ω_b (3,)."""
        p0, p1, p2 = self.perm
        s1 = self.sign[1]
        q = wxyz_from_row_major(
            (r[p0], s1 * r[p1], r[p2], r[3 + p0], s1 * r[3 + p1], r[3 + p2], r[6 + p0], s1 * r[6 + p1], r[6 + p2])
        )
        i = self.inertia
        return [*q, i[p0] * omega_body[p0], s1 * i[p1] * omega_body[p1], i[p2] * omega_body[p2]]

    def body_from_work(self, y: Sequence[float]) -> tuple[list[float], list[float]]:
        """(R row-major (9,), ω_b (3,)) from the working-frame y (7,)."""
        rw = row_major_from_wxyz(y[0], y[1], y[2], y[3])
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

    def body_arrays_from_work(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(R_space_body (N, 3, 3), ω_b (N, 3) [rad/s]) from N working-frame rows y (N, 7): the
        `state_builder` formulas on arrays, element by element the same IEEE operations, so
        the same floats bit for bit (unlike `matrices_from_wxyz`, which groups differently)."""
        y = np.asarray(y, dtype=float).reshape(-1, 7)
        qw, qx, qy, qz, lx, ly, lz = y.T
        s = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz)
        work = (
            lambda: 1.0 - s * (qy * qy + qz * qz), lambda: s * (qx * qy - qw * qz), lambda: s * (qx * qz + qw * qy),
            lambda: s * (qx * qy + qw * qz), lambda: 1.0 - s * (qx * qx + qz * qz), lambda: s * (qy * qz - qw * qx),
            lambda: s * (qx * qz - qw * qy), lambda: s * (qy * qz + qw * qx), lambda: 1.0 - s * (qx * qx + qy * qy),
        )  # fmt: skip
        R = np.empty((len(y), 3, 3))
        omega = np.empty((len(y), 3))
        L = (lx, ly, lz)
        for k in range(3):
            j = self.work_axis[k]  # body axis k is sign[j] * work axis j
            negative = self.sign[j] < 0.0
            for row in range(3):
                entry = work[3 * row + j]()
                R[:, row, k] = -entry if negative else entry
            omega[:, k] = (-L[j] if negative else L[j]) / self.inertia[k]
        return R, omega

    def P_body_work(self) -> Mat3:
        """(3, 3): column j is working axis j in body components, so R_body = R_work Pᵀ."""
        P = np.zeros((3, 3))
        for j in range(3):
            P[self.perm[j], j] = self.sign[j]
        return P

    def invariant(self, y: Sequence[float]) -> tuple[float, ...] | None:
        """What the exact-arithmetic method conserves exactly, from y (7,): L_s = R L_b (3,) of a
        free body, (L·e_z,) of a heavy top; None for other torques."""
        qw, qx, qy, qz, lx, ly, lz = y
        if not self.kicks:
            r = row_major_from_wxyz(qw, qx, qy, qz)
            return (
                r[0] * lx + r[1] * ly + r[2] * lz,
                r[3] * lx + r[4] * ly + r[5] * lz,
                r[6] * lx + r[7] * ly + r[8] * lz,
            )
        if self.torque is None:
            r = row_major_from_wxyz(qw, qx, qy, qz)
            return (r[6] * lx + r[7] * ly + r[8] * lz,)
        return None

    def stage_tables(self, h: float, gammas: Sequence[float]) -> tuple[list[Stage], ...]:
        """Per-stage constants of Ψ_h = Π_i S(γ_i h), S(h) = T_sym(h/2) T_rem(h/2) K(h) T_rem(h/2) T_sym(h/2).

        Adjacent T_sym flows are merged, so a run of steps is a sequence of stages
        T_sym(δ h) T_rem(γ_i h/2) K(γ_i h) T_rem(γ_i h/2) with δ = γ_1/2 for the first stage of
        the run, (γ_{i-1} + γ_i)/2 inside a step, (γ_last + γ_1)/2 across a step boundary, and
        one closing T_sym(γ_last h/2).  A stage tuple holds (T_sym half-angle per |L|, T_sym
        half-angle per L_z, T_sym time advance, T_rem half-angle per L_x, kick τ, full): `full`
        is False for the closing T_sym.  Without a torque T_rem(γh/2) T_rem(γh/2) is one
        rotation T_rem(γh).  Returns (first step, later steps, [closing], one whole step).
        """
        key = (h, len(gammas))
        tables = self.tables.get(key)
        if tables is not None:
            return tables
        a_o, a_r, a_s = self.a
        rem_factor = 1.0 if self.kicks else 2.0

        def stage(d: float, g: float, full: bool = True) -> Stage:
            return (a_r * d * h, (a_s - a_r) * d * h, d * h, rem_factor * (a_o - a_r) * 0.5 * g * h, g * h, full)

        n = len(gammas)
        inner = [stage(0.5 * (gammas[i - 1] + gammas[i]), gammas[i]) for i in range(1, n)]
        first = [stage(0.5 * gammas[0], gammas[0]), *inner]
        later = [stage(0.5 * (gammas[-1] + gammas[0]), gammas[0]), *inner]
        closing = [stage(0.5 * gammas[-1], 0.0, False)]
        if len(self.tables) > 256:
            self.tables.clear()
        tables = (first, later, closing, first + closing)
        self.tables[key] = tables
        return tables

    def program(self, h: float, n_steps: int, gammas: Sequence[float]) -> list[Stage]:
        """The stages of n_steps (1 <= n_steps <= CHECK_EVERY) whole steps of size h, closing included."""
        first, later, closing, single = self.stage_tables(h, gammas)
        if n_steps == 1:
            return single
        return first + later * (n_steps - 1) + closing

    def run(self, program: Sequence[Stage], y: Sequence[float], t: float) -> tuple[list[float], float]:
        """Apply the stages of `program` to y (7,) at t [s]: (y, t) after them, q not renormalised.

        Plain float arithmetic: no numpy in this loop.
        """
        qw, qx, qy, qz, lx, ly, lz = y
        has_rem = self.a[0] != self.a[1]
        has_z = self.a[2] != self.a[1]
        kicks = self.kicks
        gravity = self.gravity
        gx, gy, gz = gravity if gravity is not None else (0.0, 0.0, 0.0)
        torque = self.torque
        midpoint = self.hook
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
        return [qw, qx, qy, qz, lx, ly, lz], t

    def finish(
        self, y: Sequence[float], t: float, limit: float, invariant: tuple[float, ...] | None
    ) -> list[float]:
        """After a chunk of steps: renormalise q, restore the `invariant` against rounding drift
        (L_b = Rᵀ L_s, or L_b += (L_z - γ·L_b) γ: changes of ~1e-16 |L| that would otherwise add
        up to ~1e-11 over 1e7 stages), check finiteness and the blow-up `limit` [rad/s]."""
        qw, qx, qy, qz, lx, ly, lz = y
        n = sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        qw, qx, qy, qz = qw / n, qx / n, qy / n, qz / n
        if invariant is not None:
            if len(invariant) == 3:  # free body: L_b = Rᵀ L_s
                space_x, space_y, space_z = invariant
                r = row_major_from_wxyz(qw, qx, qy, qz)
                lx = r[0] * space_x + r[3] * space_y + r[6] * space_z
                ly = r[1] * space_x + r[4] * space_y + r[7] * space_z
                lz = r[2] * space_x + r[5] * space_y + r[8] * space_z
            else:  # heavy top: restore L·e_z = γ·L_b along γ = Rᵀ e_z (|γ| = 1)
                g0 = 2.0 * (qx * qz - qw * qy)
                g1 = 2.0 * (qy * qz + qw * qx)
                g2 = 1.0 - 2.0 * (qx * qx + qy * qy)
                d = invariant[0] - (g0 * lx + g1 * ly + g2 * lz)
                lx, ly, lz = lx + d * g0, ly + d * g1, lz + d * g2
        y_new = [qw, qx, qy, qz, lx, ly, lz]
        check_finite(t, y_new, sqrt(lx * lx + ly * ly + lz * lz) * self.inv_i_min, limit)
        return y_new


    def kernel(self, h: float, gammas: Sequence[float]) -> Kernel:
        """The steps of `program` followed by `finish`, as generated straight-line code.

        Returns frame(y, t, n, fin): from y (7,) at t [s], n >= 1 whole steps of size h (the
        first T_sym(γ_1 h/2) to the closing T_sym(γ_last h/2), as `program(h, n, gammas)`), then
        q renormalised, the invariant restored and finiteness and the limit checked, with
        fin = `finish_args(limit, invariant)`; returns the new y (7,).  Equal to `run` +
        `finish` up to rounding (~1e-16 per step: τ mgl is folded into one factor, the kick
        times are t + offsets, and with gravity alone along x_w the two half remainders of a
        stage are one, `_rem_commutes_with_kick`).  Keep n <= CHECK_EVERY per call.

        Without a torque callback a kernel is a pure function of (a, mgl, h, γ), kept in a
        small module cache shared by all instances (immutable, so sharing is safe).
        """
        structure, bases = self._plan(gammas)
        key = (structure, self.a, bases["G"], h, tuple(gammas), self.inv_i_min)
        if self.torque is None:
            cached = _KERNELS.get(key)
            if cached is not None:
                return cached
        frame = cast(Kernel, _factory(structure)(h=h, **bases))
        if self.torque is None:
            if len(_KERNELS) >= _KERNELS_KEPT:
                _KERNELS.clear()
            _KERNELS[key] = frame
        return frame

    def step_kernel(self, gammas: Sequence[float]) -> StepKernel:
        """`kernel` with the step as an argument: frame(y, t, n, fin, h) equals
        `kernel(h, gammas)(y, t, n, fin)` bit for bit, for ~0.5 µs more per call instead of the
        ~5 µs of making a kernel: for steps of a size seen once (`RealtimeStepper.peek`)."""
        structure, bases = self._plan(gammas)
        return cast(StepKernel, _factory(structure, runtime_h=True)(**bases))

    def _plan(self, gammas: Sequence[float]) -> tuple[tuple[object, ...], dict[str, object]]:
        """(structure, bases) of this model's kernels for the composition `gammas`, memoised on the
        instance: the structure picks the generated code, the bases are the constants per unit h
        (`_derived_lines`) and the callbacks."""
        plan_key = tuple(gammas)
        plan = self._plans.get(plan_key)
        if plan is not None:
            return plan
        a_o, a_r, a_s = self.a
        n = len(gammas)
        gravity_axis, G = -1, 0.0
        if self.gravity is not None:
            gravity_axis = next(j for j in range(3) if self.gravity[j] != 0.0)
            G = self.gravity[gravity_axis]
        kind = "space" if not self.kicks else ("vertical" if self.torque is None else None)
        names = [str(i) for i in range(1, n + 1)] + ["wrap", "close"]
        deltas = {"1": 0.5 * gammas[0], "wrap": 0.5 * (gammas[-1] + gammas[0]), "close": 0.5 * gammas[-1]}
        for i in range(2, n + 1):
            deltas[str(i)] = 0.5 * (gammas[i - 2] + gammas[i - 1])
        distinct = list(dict.fromkeys(deltas[k] for k in names))  # the distinct δ, first seen first
        groups = tuple(distinct.index(deltas[k]) for k in names)
        has_rem = a_o != a_r
        structure = (n, has_rem, a_s != a_r, self.kicks, gravity_axis, self.torque is not None, self.hook, kind,
                     groups)  # fmt: skip
        # T_rem(γh/2) twice per stage, or once as T_rem(γh) without kicks or when it commutes with them
        merged = not self.kicks or _rem_commutes_with_kick(has_rem, gravity_axis, self.torque is not None)
        rem_factor = 2.0 if merged else 1.0
        bases: dict[str, object] = {"G": G, "inv_i_min": self.inv_i_min, "fail": check_finite, "torque": self.torque}
        for g, d in enumerate(distinct):
            bases[f"Bkag_{g}"] = a_r * d
            bases[f"Bkzg_{g}"] = (a_s - a_r) * d
        for k, d in deltas.items():
            bases[f"Bka_{k}"] = a_r * d
            bases[f"Bkz_{k}"] = (a_s - a_r) * d
        for i in range(1, n + 1):
            bases[f"del_{i}"] = deltas[str(i)]
            bases[f"gam_{i}"] = gammas[i - 1]
            bases[f"Bkx_{i}"] = rem_factor * (a_o - a_r) * 0.5 * gammas[i - 1]
        plan = (structure, bases)
        if len(self._plans) > 16:
            self._plans.clear()
        self._plans[plan_key] = plan
        return plan

    @staticmethod
    def finish_args(limit: float, invariant: tuple[float, ...] | None) -> tuple[float, ...]:
        """The `fin` argument of a kernel: (limit [rad/s], *invariant) (see `invariant`)."""
        return (limit,) if invariant is None else (limit, *invariant)

def advance(
    sp: Splitting,
    y: Sequence[float],
    t: float,
    h: float,
    n_steps: int,
    gammas: Sequence[float],
    limit: float,
    invariant: tuple[float, ...] | None = None,
) -> tuple[list[float], float]:
    """n_steps steps of size h of the composed splitting from y (7,) (working frame) at t [s].

    Returns the new (y, t).  Every CHECK_EVERY steps and at the end `Splitting.finish`
    renormalises q, restores the invariant and checks finiteness and the limit [rad/s].
    """
    if n_steps <= 0:
        return list(y), t
    first, later, closing, single = sp.stage_tables(h, gammas)
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
        y, t = sp.run(program, y, t)
        y = sp.finish(y, t, limit, invariant)
    return list(y), t


def integrate_splitting(
    model: Model, state0: State, t_eval: ArrayLike, h: float | None = None, order: int = 4
) -> Trajectory:
    """Symplectic splitting (module docstring) with a fixed step, sampled at t_eval.

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
    r, w, t0 = validated_state(state0)
    times = validated_times(t_eval, t0)
    gammas = gammas_of(order)
    sp = Splitting(model)
    rate0 = sp.rate_scale(r[8], w)
    if h is None:
        h = DEFAULT_STEP_ANGLE / max(rate0, _RATE_FLOOR)
    elif not (math.isfinite(h) and h > 0.0):
        raise ValueError(f"step h must be positive and finite, got {h}")
    start = time.perf_counter()
    y = sp.work_from_body(r, w)
    invariant = sp.invariant(y)
    limit = omega_limit(rate0)
    t = t0
    samples = np.empty((times.size, 7))
    steps = 0
    for k, t_out in enumerate(times.tolist()):
        span = t_out - t
        if span > 0.0:
            n = max(1, math.ceil(span / h - 1e-9))
            y, _ = advance(sp, y, t, span / n, n, gammas, limit, invariant)
            steps += n
        t = t_out
        samples[k] = y
    R_work = matrices_from_wxyz(samples[:, :4])
    P = sp.P_body_work()
    R = R_work @ P.T
    omega = (samples[:, 4:] @ P.T) / np.array(model.inertia)
    wall = time.perf_counter() - start
    return Trajectory(times, R, omega, steps * len(gammas), wall, f"splitting{order}")


# --- straight-line code for the hot loop ---------------------------------------------------------
#
# `Splitting.run` above interprets a list of stage tuples: readable, and the reference the
# generated code is tested against (tests/test_splitting_kernel.py).  `Splitting.kernel` returns
# the same steps as a function generated once per *structure* of the problem (kind of torque,
# which remainders exist, the gravity axis, the number of stages) and closed over the per-run
# constants (a_k, γ_i, h, mgl folded into one factor per flow): no loop over stages, no tuple of
# four floats per quaternion product, no branch on the model inside a step.

Kernel = Callable[[tuple[float, ...], float, int, tuple[float, ...]], tuple[float, ...]]
"""frame(y (7,), t [s], n, fin) -> y (7,): n whole steps (first T_sym to closing T_sym), then the
work of `finish` with fin = `Splitting.finish_args(limit, invariant)`."""

_KERNELS: dict[tuple[object, ...], Kernel] = {}
_KERNELS_KEPT = 256  # kernels (without a torque callback) kept across instances

_FACTORIES: dict[tuple[object, ...], Callable[..., Callable[..., tuple[float, ...]]]] = {}
"""Generated factories by (structure, runtime_h): immutable code shared by every Splitting; the
constants live in each kernel's closure, so steppers still share no state."""

StepKernel = Callable[[tuple[float, ...], float, int, tuple[float, ...], float], tuple[float, ...]]
"""frame(y (7,), t [s], n, fin, h [s]) -> y (7,): a `Kernel` whose step h is an argument
(`Splitting.step_kernel`): the same numbers as `Splitting.kernel(h, ...)`, bit for bit."""


def _rotation_lines(axis: str, k: str) -> list[str]:
    """R turns about work axis `axis` ('z' or 'x') by 2 (k L_axis), L_b turns back by as much."""
    lines = [f"half = {k} * l{axis}", "ch = cos(half)", "sh = sin(half)", "c = ch * ch - sh * sh", "s = 2.0 * sh * ch"]
    if axis == "z":
        lines += [
            "qw, qz = qw * ch - qz * sh, qz * ch + qw * sh",
            "qx, qy = qx * ch + qy * sh, qy * ch - qx * sh",
            "lx, ly = c * lx + s * ly, c * ly - s * lx",
        ]
    else:
        lines += [
            "qw, qx = qw * ch - qx * sh, qx * ch + qw * sh",
            "qy, qz = qy * ch + qz * sh, qz * ch - qy * sh",
            "ly, lz = c * ly + s * lz, c * lz - s * ly",
        ]
    return lines


def _rem_commutes_with_kick(has_rem: object, gravity_axis: object, torque: object) -> bool:
    """T_rem (about x_w) and the kick commute when gravity alone acts along x_w: the kick adds
    τ G (γ × e_x), turned as L_b is by a rotation about x_w, and leaves L_x (T_rem's rate) alone,
    so {L_x², γ_x} = 0.  Then T_rem(γh/2) K(γh) T_rem(γh/2) = T_rem(γh) K(γh) exactly (up to
    rounding): one remainder rotation per stage instead of two."""
    return bool(has_rem) and gravity_axis == 0 and not torque


def _derived_lines(params: Sequence[str]) -> list[str]:
    """Lines computing the kernel constants `params` from h and the per-model bases of
    `Splitting._plan` (B<name> = the constant per unit h; gam_i = γ_i; del_i = δ_i; G), written
    as the products the constants always were: (a_r δ) h, (2 (γ h)) G, ... bit for bit."""
    lines: list[str] = []
    stages = sorted({int(m) for m in re.findall(r"\b(?:tg|tG|tk|hk|ct)_(\d+)", " ".join(params))})
    for i in stages:
        lines.append(f"tau_{i} = gam_{i} * h")
    for name in params:
        kind, _, index = name.partition("_")
        if kind in ("ka", "kz", "kag", "kzg", "kx"):
            lines.append(f"{name} = B{name} * h")
        elif kind == "tg":
            lines.append(f"{name} = 2.0 * tau_{index} * G")
        elif kind == "tG":
            lines.append(f"{name} = tau_{index} * G")
        elif kind == "tk":
            lines.append(f"{name} = tau_{index}")
        elif kind == "hk":
            lines.append(f"{name} = 0.5 * tau_{index}")
    if any(name.startswith("ct_") for name in params):  # kick times: the running sum of δ_i h
        last = max(int(name[3:]) for name in params if name.startswith("ct_"))
        lines.append("ct_1 = del_1 * h")
        lines += [f"ct_{i} = ct_{i - 1} + del_{i} * h" for i in range(2, last + 1)]
    return lines


def _kernel_source(structure: tuple[object, ...], runtime_h: bool = False) -> str:
    """Python source of `_factory(**bases) -> frame` for one structure (see `Splitting.kernel`).

    runtime_h False: `_factory(h=h, **bases)` folds h into the constants once and returns
    frame(y, t, n, fin).  True: `_factory(**bases)` returns frame(y, t, n, fin, h), which
    derives the same constants from h on every call (~30 products): for steps of a size seen
    once, such as `RealtimeStepper.peek`'s, where making a kernel would cost more than the step.
    """
    n_stages, has_rem, has_z, kicks, gravity_axis, torque, midpoint, invariant, groups = structure
    assert isinstance(n_stages, int) and isinstance(groups, tuple)
    names = [str(i) for i in range(1, n_stages + 1)] + ["wrap", "close"]
    group = dict(zip(names, groups))
    # |L| is constant in a free body's step and L_z in a symmetric top's (no remainder, kicks
    # along z_w × γ): the cos/sin of their T_sym angles are computed once per call, one per
    # distinct δ (3 for Suzuki's 7 T_sym flows), instead of once per flow.
    const_nl = invariant == "space"
    const_lz = has_z and not has_rem and gravity_axis in (-1, 2) and not torque
    prelude: list[str] = []
    if const_nl:
        prelude += ["nl2 = lx * lx + ly * ly + lz * lz", "nl = sqrt(nl2) if nl2 > 0.0 else 1.0"]
        for g in sorted(set(groups)):
            prelude += [f"half = kag_{g} * nl", f"cw{g} = cos(half)", f"sf{g} = sin(half) / nl"]
    if const_lz:
        for g in sorted(set(groups)):
            prelude += [
                f"half = kzg_{g} * lz", f"chz{g} = cos(half)", f"shz{g} = sin(half)",
                f"cz{g} = chz{g} * chz{g} - shz{g} * shz{g}", f"sz{g} = 2.0 * shz{g} * chz{g}",
            ]  # fmt: skip

    def t_sym(k: str) -> list[str]:
        g = group[k]
        if const_nl:
            lines = [
                f"px = sf{g} * lx",
                f"py = sf{g} * ly",
                f"pz = sf{g} * lz",
                f"nw = qw * cw{g} - qx * px - qy * py - qz * pz",
                f"nx = qw * px + qx * cw{g} + qy * pz - qz * py",
                f"ny = qw * py - qx * pz + qy * cw{g} + qz * px",
                f"qz = qw * pz + qx * py - qy * px + qz * cw{g}",
                "qw = nw",
                "qx = nx",
                "qy = ny",
            ]
        else:
            lines = t_sym_general(k)
        if const_lz:
            return lines + [
                f"qw, qz = qw * chz{g} - qz * shz{g}, qz * chz{g} + qw * shz{g}",
                f"qx, qy = qx * chz{g} + qy * shz{g}, qy * chz{g} - qx * shz{g}",
                f"lx, ly = cz{g} * lx + sz{g} * ly, cz{g} * ly - sz{g} * lx",
            ]
        return lines + (_rotation_lines("z", f"kz_{k}") if has_z else [])

    def t_sym_general(k: str) -> list[str]:
        return [
            "nl2 = lx * lx + ly * ly + lz * lz",
            "if nl2 > 0.0:",
            "    nl = sqrt(nl2)",
            f"    half = ka_{k} * nl",
            "    cw = cos(half)",
            "    sf = sin(half) / nl",
            "    px = sf * lx",
            "    py = sf * ly",
            "    pz = sf * lz",
            "    nw = qw * cw - qx * px - qy * py - qz * pz",
            "    nx = qw * px + qx * cw + qy * pz - qz * py",
            "    ny = qw * py - qx * pz + qy * cw + qz * px",
            "    qz = qw * pz + qx * py - qy * px + qz * cw",
            "    qw = nw",
            "    qx = nx",
            "    qy = ny",
        ]

    def kick(i: int) -> list[str]:
        lines = []
        if gravity_axis == 2:  # L += τ G (γ × e_z), γ = Rᵀ e_z; tg = 2 τ G, tG = τ G
            lines += [f"lx += tg_{i} * (qy * qz + qw * qx)", f"ly -= tg_{i} * (qx * qz - qw * qy)"]
        elif gravity_axis == 1:
            lines += [f"lx -= tG_{i} - tg_{i} * (qx * qx + qy * qy)", f"lz += tg_{i} * (qx * qz - qw * qy)"]
        elif gravity_axis == 0:
            lines += [f"ly += tG_{i} - tg_{i} * (qx * qx + qy * qy)", f"lz -= tg_{i} * (qy * qz + qw * qx)"]
        if torque:
            lines.append(f"mx, my, mz = torque(ts + ct_{i}, qw, qx, qy, qz, lx, ly, lz)")
            if midpoint:
                lines.append(
                    f"mx, my, mz = torque(ts + ct_{i}, qw, qx, qy, qz, lx + hk_{i} * mx, ly + hk_{i} * my, "
                    f"lz + hk_{i} * mz)"
                )
            lines += [f"lx += tk_{i} * mx", f"ly += tk_{i} * my", f"lz += tk_{i} * mz"]
        return lines

    merged = _rem_commutes_with_kick(has_rem, gravity_axis, torque)

    def block(i: int) -> list[str]:
        rem = _rotation_lines("x", f"kx_{i}") if has_rem else []  # kx: T_rem(γh/2), or T_rem(γh) alone/merged
        if merged:
            return rem + kick(i)
        return rem + kick(i) + rem if kicks else rem

    def step(last: str) -> list[str]:
        lines: list[str] = []
        for i in range(1, n_stages + 1):
            lines += block(i) + t_sym(str(i + 1) if i < n_stages else last)
        return lines

    body = ["qw, qx, qy, qz, lx, ly, lz = y", "ts = t", *prelude]
    body += t_sym("1")
    body += ["for _ in range(n - 1):"] + ["    " + line for line in step("wrap")]
    if torque:
        body.append("    ts += h")
    body += step("close")
    body += [
        "nq = sqrt(qw * qw + qx * qx + qy * qy + qz * qz)",
        "qw, qx, qy, qz = qw / nq, qx / nq, qy / nq, qz / nq",
    ]
    if invariant == "space":  # free body: L_b = Rᵀ L_s, as v + w τ + τ × u with τ = 2 v × u, v = L_s,
        body += [  # q = (w, u) the unit q just normalised: half the products of Rᵀ from q's matrix
            "limit, space_x, space_y, space_z = fin",
            "tx = 2.0 * (space_y * qz - space_z * qy)",
            "ty = 2.0 * (space_z * qx - space_x * qz)",
            "tz = 2.0 * (space_x * qy - space_y * qx)",
            "lx = space_x + qw * tx + (ty * qz - tz * qy)",
            "ly = space_y + qw * ty + (tz * qx - tx * qz)",
            "lz = space_z + qw * tz + (tx * qy - ty * qx)",
        ]
    elif invariant == "vertical":  # heavy top: L·e_z = γ·L_b along γ = Rᵀ e_z
        body += [
            "limit, vertical = fin",
            "g0 = 2.0 * (qx * qz - qw * qy)",
            "g1 = 2.0 * (qy * qz + qw * qx)",
            "g2 = 1.0 - 2.0 * (qx * qx + qy * qy)",
            "d = vertical - (g0 * lx + g1 * ly + g2 * lz)",
            "lx, ly, lz = lx + d * g0, ly + d * g1, lz + d * g2",
        ]
    else:
        body.append("limit = fin[0]")
    body += [
        "omega = sqrt(lx * lx + ly * ly + lz * lz) * inv_i_min",
        "if not (omega <= limit and (qw + qx + qy + qz + lx + ly + lz) * 0.0 == 0.0):",
        "    fail(t + n * h, (qw, qx, qy, qz, lx, ly, lz), omega, limit)",
        "return (qw, qx, qy, qz, lx, ly, lz)",
    ]
    params = sorted(set(re.findall(r"\b(?:ka|kz|kag|kzg|kx|tg|tG|tk|hk|ct)_\w+", "\n".join(body))))
    derived = _derived_lines(params)
    bases = sorted(set(re.findall(r"\b(?:B\w+|gam_\d+|del_\d+|G)\b", "\n".join(derived))))
    bases += ["inv_i_min", "fail", "torque"]
    if runtime_h:
        src = [f"def _factory(*, {', '.join(bases)}, **_unused):", "    def frame(y, t, n, fin, h):"]
        src += ["        " + line for line in derived + body]
    else:
        src = [f"def _factory(*, h, {', '.join(bases)}, **_unused):"]
        src += ["    " + line for line in derived]
        src += ["    def frame(y, t, n, fin):"]
        src += ["        " + line for line in body]
    src += ["    return frame"]
    return "\n".join(src) + "\n"


def _factory(structure: tuple[object, ...], runtime_h: bool = False) -> Callable[..., Callable[..., tuple[float, ...]]]:
    key = (structure, runtime_h)
    factory = _FACTORIES.get(key)
    if factory is None:
        namespace: dict[str, object] = {"sqrt": sqrt, "sin": sin, "cos": cos}
        source = _kernel_source(structure, runtime_h)
        exec(compile(source, f"<physics.splitting kernel {key}>", "exec"), namespace)  # noqa: S102
        factory = cast(Callable[..., Callable[..., tuple[float, ...]]], namespace["_factory"])
        _FACTORIES[key] = factory
    return factory


StateBuilder = Callable[[tuple[float, ...], float], State]
"""state(y (7,), t [s]) -> State: R_space_body (3, 3) and ω_b (3,) in body axes, fresh arrays."""

_STATE_BUILDERS: dict[tuple[object, ...], Callable[..., StateBuilder]] = {}


def _state_source(work_axis: tuple[int, int, int], sign: tuple[float, float, float]) -> str:
    """Source of `_factory(i0, i1, i2, State, array) -> state`, `body_from_work` unrolled."""
    work = (
        "1.0 - s * (qy * qy + qz * qz)", "s * (qx * qy - qw * qz)", "s * (qx * qz + qw * qy)",
        "s * (qx * qy + qw * qz)", "1.0 - s * (qx * qx + qz * qz)", "s * (qy * qz - qw * qx)",
        "s * (qx * qz - qw * qy)", "s * (qy * qz + qw * qx)", "1.0 - s * (qx * qx + qy * qy)",
    )  # fmt: skip
    entries = []
    for row in range(3):
        for k in range(3):
            j = work_axis[k]
            entries.append(f"-({work[3 * row + j]})" if sign[j] < 0.0 else work[3 * row + j])
    for k in range(3):
        j = work_axis[k]
        entries.append(f"{'-' if sign[j] < 0.0 else ''}l{'xyz'[j]} / i{k}")
    return "\n".join([
        "def _factory(i0, i1, i2, State, array):",
        "    def state(y, t):",
        "        qw, qx, qy, qz, lx, ly, lz = y",
        "        s = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz)",
        f"        b = array(({', '.join(entries)}))  # 12 Python floats: float64, faster than fromiter",
        "        return State(b[:9].reshape(3, 3), b[9:], t)",
        "    return state",
    ]) + "\n"  # fmt: skip


def state_builder(sp: Splitting) -> StateBuilder:
    """`Splitting.body_from_work` and `State(...)` as one generated function for sp's axes.

    R and ω_b are views of one fresh (12,) array per call, so a State costs one allocation.
    """
    key = (sp.work_axis, sp.sign)
    factory = _STATE_BUILDERS.get(key)
    if factory is None:
        namespace: dict[str, object] = {}
        source = _state_source(sp.work_axis, sp.sign)
        exec(compile(source, f"<physics.splitting state {key}>", "exec"), namespace)  # noqa: S102
        factory = cast(Callable[..., StateBuilder], namespace["_factory"])
        _STATE_BUILDERS[key] = factory
    i0, i1, i2 = sp.inertia
    return factory(i0, i1, i2, State, np.array)
