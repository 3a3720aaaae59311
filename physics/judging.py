"""Judging an answer by its physics: how far an attitude is from a target, the class of a heavy
top's motion, whether a kicked body's axis stays.  Pure functions of numbers (no app).

Conventions as in `physics` (docs/CONVENTIONS.md): R = R_space_body maps body components to space
components (x = R x′), z-x-z Euler angles R = Rz(φ) Rx(θ) Rz(ψ), ω_b the body components of ω,
moments [kg m²] about the centre of mass (a free body) or the pivot (a heavy top), SI units.

* `attitude_error_rad(R_answer, R_target)`: the angle [rad] of the turn R_targetᵀ R_answer, in
  [0, π], accurate to rounding for small and large turns (atan2 of its sine and cosine).
* `top_motion(I1, I3, mgl, R, ω_b)`: the class of motion of the heavy symmetric top from its
  energy picture (`physics.top_energy`: the turning points θ₁ ≤ θ₂ are roots of the u-cubic
  f(u) = (1 − u²)(α − βu) − (b′ − a′u)², u = cos θ, and the sign of φ̇ ∝ p_φ − p_ψ cos θ at
  them decides wave, loop or cusp), with the looser tolerances a person's start needs: steady
  precession when θ₂ − θ₁ ≤ `steady_tol_rad`, a cusp when φ̇ at a turning point is at most
  `cusp_rtol` times the larger |φ̇| of the two turning points.
* `axis_stays(inertia, R, ω_b, axis, within_rad, seconds)`: the torque-free body started at
  (R, ω_b), integrated (`physics.methods.simulate`, its default method: the closed form); the
  body axis `axis` (0, 1, 2 for x′, y′, z′) stays when its direction in space keeps within
  `within_rad` of where it started over [0, seconds].  Spin about the largest or the smallest
  axis stays (the axis circles L on a small cone); about the middle one it flips
  (the intermediate-axis theorem).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from physics.dynamics import Model, State
from physics.top_energy import CUSP, LOOP, STEADY, WAVE, TopEnergyPicture, energy_picture

__all__ = [
    "AXIS_SAMPLES_PER_RAD",
    "CUSP_RTOL",
    "STEADY_TOL_RAD",
    "AxisRun",
    "TopMotion",
    "attitude_error_rad",
    "axis_stays",
    "top_motion",
]

STEADY_TOL_RAD = math.radians(0.5)  # θ₂ − θ₁ at most this [rad]: steady precession for a person's start
CUSP_RTOL = 0.01  # |φ̇| at a turning point at most this times the larger of the two: a cusp
AXIS_SAMPLES_PER_RAD = 8.0  # samples of the axis run per radian the body turns (|ω| t)
_AXIS_MIN_SAMPLES = 200
_AXIS_MAX_SAMPLES = 20_000


def attitude_error_rad(R_answer: ArrayLike, R_target: ArrayLike) -> float:
    """The angle [rad] in [0, π] of the turn R_targetᵀ R_answer between two attitudes (3, 3):
    atan2(|vee(M − Mᵀ)| / 2, (tr M − 1) / 2) for M = R_targetᵀ R_answer."""
    M = np.asarray(R_target, dtype=float).T @ np.asarray(R_answer, dtype=float)
    sine = 0.5 * math.sqrt((M[2, 1] - M[1, 2]) ** 2 + (M[0, 2] - M[2, 0]) ** 2 + (M[1, 0] - M[0, 1]) ** 2)
    cosine = 0.5 * (float(np.trace(M)) - 1.0)
    return math.atan2(sine, cosine)


@dataclass(frozen=True)
class TopMotion:
    """The judged class of a heavy top's motion: `motion` (one of `physics.top_energy`'s
    MOTION_CLASSES) and the energy picture it was read from (turning points, φ̇ at them)."""

    motion: str
    picture: TopEnergyPicture


def top_motion(I1: float, I3: float, mgl: float, R_space_body: ArrayLike, omega_body: ArrayLike,
               steady_tol_rad: float = STEADY_TOL_RAD, cusp_rtol: float = CUSP_RTOL) -> TopMotion:
    """The class of motion of the heavy symmetric top (I1 = I2, I3 [kg m²] about the pivot, mgl
    [N m]) started at (R (3, 3), ω_b (3,) [rad/s]) (module docstring); ValueError for a state the
    closed form refuses (not a rotation, non-finite)."""
    picture = energy_picture(I1, I3, mgl, np.asarray(R_space_body, dtype=float),
                             np.asarray(omega_body, dtype=float))
    motion = picture.motion
    if motion in (WAVE, LOOP, CUSP):
        if picture.theta_2 - picture.theta_1 <= steady_tol_rad:
            motion = STEADY
        else:
            rate_1, rate_2 = abs(picture.phi_dot_1), abs(picture.phi_dot_2)
            if min(rate_1, rate_2) <= cusp_rtol * max(rate_1, rate_2):
                motion = CUSP
    return TopMotion(motion, picture)


@dataclass(frozen=True)
class AxisRun:
    """How far a body axis went: `stays` (it kept within the angle), `max_angle_rad` (the largest
    angle from where it started), `left_at_s` (the first sampled time [s] beyond the angle, or
    None), `axis` (0, 1, 2), `seconds` (the span [s] looked at)."""

    stays: bool
    max_angle_rad: float
    left_at_s: float | None
    axis: int
    seconds: float


def axis_stays(inertia: ArrayLike, R_space_body: ArrayLike, omega_body: ArrayLike, axis: int | None = None,
               within_rad: float = math.radians(20.0), seconds: float = 10.0) -> AxisRun:
    """Whether the body axis `axis` of the torque-free body (principal moments `inertia` (3,)
    [kg m²]) started at (R (3, 3), ω_b (3,) [rad/s]) stays within `within_rad` of its starting
    direction over [0, seconds] (module docstring).  axis None: the body axis ω_b lies closest
    to.  Sampled AXIS_SAMPLES_PER_RAD times per radian turned (at least 200, at most 20,000
    samples)."""
    from physics.methods import simulate

    moments = tuple(float(m) for m in np.asarray(inertia, dtype=float))
    R0 = np.asarray(R_space_body, dtype=float)
    omega0 = np.asarray(omega_body, dtype=float)
    if not (math.isfinite(seconds) and seconds > 0.0):
        raise ValueError(f"the span must be a positive number of seconds, got {seconds!r}")
    if axis is None:
        axis = int(np.argmax(np.abs(omega0)))
    if axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1 or 2 (x′, y′, z′), got {axis!r}")
    model = Model(inertia=(moments[0], moments[1], moments[2]))
    turned = float(np.linalg.norm(omega0)) * seconds
    n = int(min(max(AXIS_SAMPLES_PER_RAD * turned, _AXIS_MIN_SAMPLES), _AXIS_MAX_SAMPLES))
    t = np.linspace(0.0, seconds, n + 1)
    run = simulate(model, State(R0, omega0, 0.0), t)
    start = R0[:, axis]
    now = run.R_space_body[:, :, axis]  # (N, 3) the axis in space
    sines = np.linalg.norm(np.cross(now, start), axis=1)
    angles = np.arctan2(sines, now @ start)
    beyond = np.nonzero(angles > within_rad)[0]
    left_at = float(t[beyond[0]]) if beyond.size else None
    return AxisRun(stays=left_at is None, max_angle_rad=float(angles.max()), left_at_s=left_at,
                   axis=axis, seconds=float(seconds))
