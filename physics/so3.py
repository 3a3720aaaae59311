"""Rotations in SO(3) as 3x3 matrices, and the skew ("hat") map of the memo (§1).

Conventions used throughout `physics` (see docs/CONVENTIONS.md):

* Active rotations on column vectors: ``x_space = R_space_body @ x_body`` (the memo's
  x = a + D x'). ``R_space_body`` is the memo's D.
* ``hat(v) @ u == np.cross(v, u)``; ``vee`` is its inverse.  The memo's A1 = hat(e_x),
  A3 = hat(e_z).
* A rotation by the angle Φ [rad] about the unit axis d is ``exp(Φ hat(d))`` (1.2)-(1.4).
* Radians everywhere; degrees only on GUI sliders.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics._types import Mat3, Vec3

__all__ = [
    "A1",
    "A3",
    "AXIS_UNDEFINED_ANGLE",
    "HALF_TURN_BAND",
    "SingleRotation",
    "axis_angle_from_matrix",
    "exp_series",
    "exp_skew",
    "exp_so3",
    "hat",
    "log_so3",
    "project_to_so3",
    "rot_x",
    "rot_z",
    "single_rotation",
    "turn_path",
    "vee",
]

_SMALL_ANGLE = 1e-4  # below this, Taylor series of sin(x)/x and (1-cos x)/x^2 (error < 1e-17)

A1: Mat3 = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
A3: Mat3 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])


def hat(v: Vec3) -> Mat3:
    """Skew matrix of v: (3,) -> (3, 3) with ``hat(v) @ u == np.cross(v, u)``."""
    x, y, z = (float(c) for c in v)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def vee(A: Mat3) -> Vec3:
    """Inverse of `hat`: the vector (3,) of the skew part of A (3, 3), ``(A - A.T) / 2``."""
    A = np.asarray(A, dtype=float)
    return 0.5 * np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]])


def _sinc_coefficients(angle: float) -> tuple[float, float]:
    """(sin x / x, (1 - cos x) / x^2) at x = angle, accurate for every angle >= 0."""
    if angle < _SMALL_ANGLE:
        x2 = angle * angle
        return 1.0 - x2 / 6.0 + x2 * x2 / 120.0, 0.5 - x2 / 24.0 + x2 * x2 / 720.0
    # 1 - cos x = 2 sin^2(x/2) avoids the cancellation of 1 - cos x for small x.
    half = math.sin(0.5 * angle)
    return math.sin(angle) / angle, 2.0 * half * half / (angle * angle)


def exp_so3(rotvec: Vec3) -> Mat3:
    """``expm(hat(rotvec))`` in closed form (Rodrigues), (3,) -> (3, 3).

    rotvec = Φ d: angle Φ [rad] times the unit axis d (1.2, 1.3).  Equals the series (1.4)
    and ``scipy.linalg.expm`` to rounding for every angle.
    """
    rotvec = np.asarray(rotvec, dtype=float)
    K = hat(rotvec)
    a, b = _sinc_coefficients(float(np.linalg.norm(rotvec)))
    return np.eye(3) + a * K + b * (K @ K)


def exp_skew(A: Mat3) -> Mat3:
    """exp of a skew-symmetric matrix A (3, 3), in closed form: ``exp_so3(vee(A))``."""
    return exp_so3(vee(A))


def exp_series(A: Mat3, terms: int = 60) -> Mat3:
    """The memo's definition (1.4), sum_{n < terms} A^n / n!, summed term by term.

    A reference for tests and teaching; use `exp_so3` in computations.
    """
    A = np.asarray(A, dtype=float)
    total = np.eye(3)
    term = np.eye(3)
    for n in range(1, terms):
        term = term @ A / n
        total = total + term
    return total


def rot_x(angle: float) -> Mat3:
    """exp(angle A1): rotation by `angle` [rad] about the x axis."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_z(angle: float) -> Mat3:
    """exp(angle A3): rotation by `angle` [rad] about the z axis."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def axis_angle_from_matrix(R: Mat3) -> tuple[Vec3, float]:
    """Unit axis d (3,) and angle Φ in [0, π] [rad] with R = exp(Φ hat(d)) (memo 1.1-1.3).

    The memo's cos Φ = (tr R - 1)/2 loses all accuracy near Φ = 0 and Φ = π, so the angle is
    ``atan2(|vee(R)|, (tr R - 1)/2)`` with |vee(R)| = sin Φ,
    and near π the axis comes from the symmetric part R + R^T = 2 cos Φ 1 + 2(1 - cos Φ) d d^T.

    Branches: at Φ = 0 the axis is undefined and (0, 0, 1) is returned.  At Φ = π the axis is
    defined up to sign; the sign is chosen so that its largest component is positive.
    """
    R = np.asarray(R, dtype=float)
    s_vec = vee(R)  # = sin Φ d
    sin_angle = float(np.linalg.norm(s_vec))
    cos_angle = 0.5 * (float(np.trace(R)) - 1.0)
    angle = math.atan2(sin_angle, cos_angle)
    if angle < 1e-300:
        return np.array([0.0, 0.0, 1.0]), 0.0
    if cos_angle > -0.5:
        return s_vec / sin_angle, angle
    # Near π: d d^T = (R + R^T - 2 cos Φ 1) / (2 (1 - cos Φ)); take the best-conditioned column.
    B = (0.5 * (R + R.T) - cos_angle * np.eye(3)) / (1.0 - cos_angle)
    k = int(np.argmax(np.diag(B)))
    axis = B[:, k] / math.sqrt(B[k, k])
    # The sign of the axis follows sin Φ d where it is resolved (Φ < π).
    if float(axis @ s_vec) < 0.0:
        axis = -axis
    elif sin_angle == 0.0 and axis[int(np.argmax(np.abs(axis)))] < 0.0:
        axis = -axis
    return axis / np.linalg.norm(axis), angle


def log_so3(R: Mat3) -> Vec3:
    """Rotation vector Φ d (3,) with ``exp_so3(log_so3(R)) == R``; Φ in [0, π] [rad]."""
    axis, angle = axis_angle_from_matrix(R)
    return angle * axis


def project_to_so3(M: Mat3) -> Mat3:
    """The rotation nearest to M (3, 3) in the Frobenius norm (polar decomposition by SVD)."""
    U, _, Vt = np.linalg.svd(np.asarray(M, dtype=float))
    if np.linalg.det(U @ Vt) < 0.0:
        U[:, -1] = -U[:, -1]
    return U @ Vt


AXIS_UNDEFINED_ANGLE = 1e-9
"""[rad] Below this Φ the axis d of D is reported undefined (None).  D = 1 up to rounding (say
Rz(1°) Rz(-1°)) has Φ ~ 1e-16 and an axis made of rounding noise; no slider (1° steps) or typed
angle a lecture uses comes near 1e-9 rad = 6e-8°."""
HALF_TURN_BAND = 1e-10
"""[rad] Within this of Φ = π the sign of d is not fixed by D for display purposes: sin Φ d =
vee(D) is then ~1e-16 of rounding at an exact half turn (D = Rx(θ) Rz(π), any θ), so its sign is
noise.  There d is taken from the symmetric part (D + 1)/2 = d dᵀ (at Φ = π) and its sign chosen
continuously.  Flipping d there moves exp(Φ hat(d)) off D by at most 2 sin Φ ≤ 2e-10."""


@dataclass(frozen=True)
class SingleRotation:
    """D as one turn, D = exp(A), A = Φ hat(d) (memo 1.1-1.3).

    Attributes:
        angle: Φ in [0, π] [rad] (1.1).
        axis: the unit axis d (3,), or None when Φ < AXIS_UNDEFINED_ANGLE (no axis: D = 1).
        rotvec: the rotation vector Φ d (3,) [rad]; (0, 0, 0) at D = 1.
    """

    angle: float
    axis: Vec3 | None
    rotvec: Vec3

    @property
    def A(self) -> Mat3:
        """A = Φ hat(d) (3, 3), skew (1.3); exp(A) = D."""
        return hat(self.rotvec)

    @property
    def wxyz(self) -> tuple[float, float, float, float]:
        """The unit quaternion (cos Φ/2, sin(Φ/2) d), w >= 0 since Φ <= π."""
        half = 0.5 * self.angle
        # sin(Φ/2)/Φ times Φ d: well defined as Φ -> 0 (the limit is 1/2).
        k = 0.5 if self.angle < 1e-8 else math.sin(half) / self.angle
        x, y, z = (k * float(c) for c in self.rotvec)
        return (math.cos(half), x, y, z)


def single_rotation(D: Mat3, previous_axis: Vec3 | None = None) -> SingleRotation:
    """D (3, 3) as one turn by Φ in [0, π] [rad] about the unit axis d (memo 1.1-1.3).

    Outside the two bands this is `axis_angle_from_matrix` (Φ from atan2, exact near 0 and π;
    the sign of d from sin Φ d = vee(D), as SciPy's `as_rotvec`).  Branches:
    * Φ < AXIS_UNDEFINED_ANGLE: `axis` is None (every axis is one: D = 1); rotvec = vee(D).
    * π - Φ <= HALF_TURN_BAND: d from the symmetric part of D, its sign the one nearer
      `previous_axis` (the last axis drawn: sliders through a half turn do not flip it), or
      without one, the sign making d's largest component positive (so every view agrees).
    """
    axis, angle = axis_angle_from_matrix(D)
    if angle < AXIS_UNDEFINED_ANGLE:
        return SingleRotation(angle, None, angle * axis)
    if math.pi - angle <= HALF_TURN_BAND:
        reference = previous_axis
        if reference is None or float(np.dot(axis, reference)) == 0.0:
            reference = np.zeros(3)
            k = int(np.argmax(np.abs(axis)))
            reference[k] = 1.0
        if float(np.dot(axis, reference)) < 0.0:
            axis = -axis
    return SingleRotation(angle, axis, angle * axis)


def turn_path(axis: Vec3, angle: float, v: Vec3, segments: int) -> Vec3:
    """Points exp(s Φ hat(d)) v (segments + 1, 3) for s = 0 .. 1: v turned about the unit
    axis d by the growing angle s Φ [rad] (Rodrigues, 1.7-1.8)."""
    d = np.asarray(axis, dtype=float)
    v = np.asarray(v, dtype=float)
    t = np.linspace(0.0, float(angle), segments + 1)[:, None]
    along = np.dot(d, v) * d
    return along + np.cos(t) * (v - along) + np.sin(t) * np.cross(d, v)
