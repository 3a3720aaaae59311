"""Checks shared by the integrators: bad input, blow-ups, and the rate scale Ω of a motion.

* A non-finite or non-orthogonal initial state raises IntegrationError at once
  (`validated_state`); bad output times or tolerances raise ValueError.
* A run is a blow-up (IntegrationError naming t) when |ω| exceeds
  max(OMEGA_LIMIT, OMEGA_GROWTH Ω0), Ω0 = `rate_scale` at its start (`omega_limit`,
  `check_finite`).
* `rate_scale` is the rate Ω [rad/s] the splitting measures its step against (h Ω = angle per
  step); the adaptive methods use it only for the blow-up limit.

Everything here works on Python floats: R as its row-major entries (9,), ω_b as (3,).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from math import sqrt

import numpy as np
from numpy.typing import ArrayLike

from physics._types import Array, Mat3, Vec3
from physics.dynamics import IntegrationError, Model, State

__all__ = [
    "OMEGA_GROWTH",
    "OMEGA_LIMIT",
    "ORTHOGONALITY_TOL",
    "check_finite",
    "omega_limit",
    "rate_scale",
    "rate_scale_function",
    "validated_state",
    "validated_times",
    "validated_tolerances",
]

OMEGA_LIMIT = 1e4
OMEGA_GROWTH = 1e3
"""A run is a blow-up (IntegrationError) when |ω| exceeds max(OMEGA_LIMIT [rad/s],
OMEGA_GROWTH * Ω0), Ω0 = `rate_scale` at its start: a 1000 rad/s spin is normal, a hook that
pumps energy in is stopped before its spin makes every step tiny.  (The work of an adaptive
method grows like the angle turned, so a limit of 1e8 rad/s would take minutes to reach.)"""

ORTHOGONALITY_TOL = 1e-9
"""An initial R with max |RᵀR - 1| above this is not a rotation (as docs/CASEFILE.md)."""


def validated_state(state: State) -> tuple[list[float], list[float], float]:
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


def validated_times(t_eval: ArrayLike, t0: float) -> Array:
    """t_eval as a float array (N,); ValueError unless 1-D, finite, strictly increasing, >= t0."""
    t = np.array(t_eval, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"t_eval must be a non-empty 1-D array, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError("t_eval must be finite")
    if np.any(np.diff(t) <= 0.0) or t[0] < t0:
        raise ValueError(f"t_eval must be strictly increasing and start at or after state0.t = {t0}")
    return t


def validated_tolerances(rtol: float, atol: float) -> None:
    """ValueError unless rtol and atol are positive and finite."""
    if not (math.isfinite(rtol) and math.isfinite(atol) and rtol > 0.0 and atol > 0.0):
        raise ValueError(f"rtol and atol must be positive and finite, got {rtol}, {atol}")


def omega_limit(rate0: float) -> float:
    """The blow-up threshold [rad/s] of a run that starts with rate scale rate0 [rad/s]."""
    return max(OMEGA_LIMIT, OMEGA_GROWTH * rate0)


def check_finite(t: float, y: Sequence[float], omega: float, limit: float) -> None:
    """IntegrationError unless y is finite and omega <= limit [rad/s]."""
    if not math.isfinite(sum(y)):
        raise IntegrationError(f"non-finite state at t = {t:.9g} s: y = {list(y)}")
    if omega > limit:
        raise IntegrationError(
            f"blow-up at t = {t:.9g} s: |omega| ~ {omega:.3g} rad/s exceeds the limit {limit:.3g} rad/s"
        )


def rate_scale_function(model: Model) -> Callable[[float, Sequence[float]], float]:
    """`rate_scale` of `model` on floats: f(R[2, 2], ω_b (3,)) -> Ω [rad/s], constants bound once."""
    i1, i2, i3 = model.inertia
    i_min = min(i1, i2, i3)
    mgl = model.mgl
    torque_scale = abs(mgl) + math.sqrt(sum(m * m for m in model.torque_space))
    torque_rate = sqrt(torque_scale / i_min)
    if model.conservative:

        def conservative(r22: float, w: Sequence[float]) -> float:
            kinetic = 0.5 * (i1 * w[0] * w[0] + i2 * w[1] * w[1] + i3 * w[2] * w[2])
            return sqrt(max(2.0 * (kinetic + mgl * r22 + abs(mgl)) / i_min, 0.0)) + torque_rate

        return conservative

    def general(r22: float, w: Sequence[float]) -> float:
        return sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) + torque_rate

    return general


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
    return rate_scale_function(model)(float(np.asarray(R_space_body, dtype=float)[2, 2]), w)
