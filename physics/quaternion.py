"""Unit quaternions q = (w, x, y, z), scalar first ("wxyz"), and rotation matrices.

Conventions (docs/CONVENTIONS.md): R(q) is the active rotation with R(q) v = q v q̄, so for the
attitude quaternion of a body R(q) = R_space_body (body components -> space components) and
R(q ⊗ p) = R(q) R(p).  q and -q are the same rotation; every `*_from_matrix` here returns the
one with w >= 0, normalised.  SciPy's `Rotation.as_quat(scalar_first=True)` uses the same
order and sign of rotation (its canonical form also picks w >= 0); viser's `wxyz` is this order.

Two flavours of each conversion:
* on Python floats, for the integrators' inner loops and the app's per-frame poses
  (`wxyz_from_matrix`, `wxyz_from_row_major`, `row_major_from_wxyz`): no numpy in the arithmetic;
* vectorised over leading axes (`wxyz_from_matrices`, `matrices_from_wxyz`).

Matrix -> quaternion is Shepperd's method: of 4 w², 4 x², 4 y², 4 z² (= 1 + tr R, 1 + 2 R_kk - tr R)
take the largest, so the square root is of a number >= 1 and the division is well conditioned.
"""

from __future__ import annotations

from collections.abc import Sequence
from math import sqrt
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from physics._types import Array, Mat3

__all__ = [
    "matrices_from_wxyz",
    "matrix_from_wxyz",
    "row_major_from_wxyz",
    "wxyz_from_matrices",
    "wxyz_from_matrix",
    "wxyz_from_row_major",
]

Wxyz = tuple[float, float, float, float]


def wxyz_from_row_major(r: Sequence[float]) -> Wxyz:
    """Unit quaternion (w, x, y, z), w >= 0, of the rotation with row-major entries r (9,).

    Shepperd's method on Python floats (~1 µs).  r should be a rotation; the result is
    normalised whatever the small non-orthogonality of r.
    """
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    trace = r00 + r11 + r22
    if trace >= r00 and trace >= r11 and trace >= r22:
        s = 2.0 * sqrt(max(1.0 + trace, 0.0))  # s = 4 |w| >= 2
        w, x, y, z = 0.25 * s, (r21 - r12) / s, (r02 - r20) / s, (r10 - r01) / s
    elif r00 >= r11 and r00 >= r22:
        s = 2.0 * sqrt(max(1.0 + r00 - r11 - r22, 0.0))  # 4 |x|
        w, x, y, z = (r21 - r12) / s, 0.25 * s, (r01 + r10) / s, (r02 + r20) / s
    elif r11 >= r22:
        s = 2.0 * sqrt(max(1.0 + r11 - r00 - r22, 0.0))  # 4 |y|
        w, x, y, z = (r02 - r20) / s, (r01 + r10) / s, 0.25 * s, (r12 + r21) / s
    else:
        s = 2.0 * sqrt(max(1.0 + r22 - r00 - r11, 0.0))  # 4 |z|
        w, x, y, z = (r10 - r01) / s, (r02 + r20) / s, (r12 + r21) / s, 0.25 * s
    n = sqrt(w * w + x * x + y * y + z * z)
    if w < 0.0:
        n = -n
    return (w / n, x / n, y / n, z / n)


def wxyz_from_matrix(R_space_body: ArrayLike) -> Wxyz:
    """Unit quaternion (w, x, y, z), w >= 0, of the rotation matrix R (3, 3), as Python floats.

    The scalar conversion for per-frame use (a viser node's `wxyz`): a few µs, no numpy
    arithmetic.  Accepts a (3, 3) ndarray or nested sequences.
    """
    if isinstance(R_space_body, np.ndarray):
        return wxyz_from_row_major(R_space_body.ravel().tolist())
    rows = cast(Sequence[Sequence[float]], R_space_body)
    return wxyz_from_row_major([float(v) for row in rows for v in row])


def row_major_from_wxyz(w: float, x: float, y: float, z: float) -> list[float]:
    """Row-major entries (9,) of R(q / |q|), on Python floats (q need not be normalised)."""
    s = 2.0 / (w * w + x * x + y * y + z * z)
    return [
        1.0 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),
        s * (x * y + w * z), 1.0 - s * (x * x + z * z), s * (y * z - w * x),
        s * (x * z - w * y), s * (y * z + w * x), 1.0 - s * (x * x + y * y),
    ]  # fmt: skip


def matrices_from_wxyz(q: ArrayLike) -> Array:
    """R (..., 3, 3) of quaternions q (..., 4) (w, x, y, z), each normalised first."""
    q = np.asarray(q, dtype=float)
    n = np.sqrt(np.sum(q * q, axis=-1))
    w, x, y, z = (q[..., k] / n for k in range(4))
    R = np.empty(q.shape[:-1] + (3, 3))
    R[..., 0, 0] = 1.0 - 2.0 * (y * y + z * z)
    R[..., 0, 1] = 2.0 * (x * y - w * z)
    R[..., 0, 2] = 2.0 * (x * z + w * y)
    R[..., 1, 0] = 2.0 * (x * y + w * z)
    R[..., 1, 1] = 1.0 - 2.0 * (x * x + z * z)
    R[..., 1, 2] = 2.0 * (y * z - w * x)
    R[..., 2, 0] = 2.0 * (x * z - w * y)
    R[..., 2, 1] = 2.0 * (y * z + w * x)
    R[..., 2, 2] = 1.0 - 2.0 * (x * x + y * y)
    return R


def matrix_from_wxyz(q: ArrayLike) -> Mat3:
    """R (3, 3) of one quaternion q (4,) (w, x, y, z), normalised first."""
    return matrices_from_wxyz(np.asarray(q, dtype=float).reshape(4))


def wxyz_from_matrices(R: ArrayLike) -> Array:
    """Unit quaternions (..., 4) (w, x, y, z), w >= 0, of rotation matrices R (..., 3, 3) (Shepperd)."""
    R = np.asarray(R, dtype=float)
    r00, r11, r22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    trace = r00 + r11 + r22
    candidates = np.stack([trace, r00, r11, r22], axis=-1)  # the largest picks the largest of 4 w², 4 x², ...
    k = np.argmax(candidates, axis=-1)
    d21, d02, d10 = R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]
    s01, s02, s12 = R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0], R[..., 1, 2] + R[..., 2, 1]
    big = np.sqrt(np.maximum(1.0 + np.choose(k, [trace, 2 * r00 - trace, 2 * r11 - trace, 2 * r22 - trace]), 0.0))
    s = 2.0 * big  # 4 |q_k|
    q = np.empty(R.shape[:-2] + (4,))
    q[..., 0] = np.choose(k, [0.25 * s, d21 / s, d02 / s, d10 / s])
    q[..., 1] = np.choose(k, [d21 / s, 0.25 * s, s01 / s, s02 / s])
    q[..., 2] = np.choose(k, [d02 / s, s01 / s, 0.25 * s, s12 / s])
    q[..., 3] = np.choose(k, [d10 / s, s02 / s, s12 / s, 0.25 * s])
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    q *= np.where(q[..., :1] < 0.0, -1.0, 1.0)
    return q
