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

import numpy as np

from physics._types import Mat3, Vec3

__all__ = [
    "A1",
    "A3",
    "axis_angle_from_matrix",
    "exp_series",
    "exp_skew",
    "exp_so3",
    "hat",
    "log_so3",
    "project_to_so3",
    "rot_x",
    "rot_z",
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
