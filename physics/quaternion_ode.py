"""The quaternion ODE of the rigid body that the adaptive methods integrate (`physics.dop853`,
`physics.scipy_peer`): y = (qw, qx, qy, qz, ω1, ω2, ω3) in R^7,

    q̇ = ½ q ⊗ (0, ω_b)   (so that Ṙ = R hat(ω_b), R = R(q / |q|) = R_space_body),
    I ω̇_b = (I ω_b) × ω_b + R(q / |q|)ᵀ M          (Euler's equations, docs/CONVENTIONS.md).

The right-hand side is homogeneous of degree 0 in q (the torque uses R(q/|q|)), so the direction
of q evolves as for a unit quaternion whatever |q| does; the q-part is linear in q.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from physics.dynamics import Model
from physics.quaternion import row_major_from_wxyz

__all__ = ["Rhs", "quaternion_rhs"]

Rhs = Callable[..., tuple[float, ...]]  # f(t, qw, qx, qy, qz, w1, w2, w3) -> ẏ (7,)


def quaternion_rhs(model: Model) -> Rhs:
    """ẏ of y = (q, ω_b) for `model`, on floats, homogeneous of degree 0 in q.

    q̇ = ½ q ⊗ (0, ω_b) (so that Ṙ = R hat(ω_b)); I ω̇_b = (I ω_b) × ω_b + R(q/|q|)ᵀ M.
    Specialised for the free body and the heavy top (Rᵀ M = mgl γ × e_3, γ = Rᵀ e_z).
    """
    i1, i2, i3 = model.inertia
    k1, k2, k3 = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3
    mgl = model.mgl
    kind = model.kind

    if kind == "free":

        def rhs_free(
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

        return rhs_free

    if kind == "heavy_top":
        c1, c2 = 2.0 * mgl / i1, 2.0 * mgl / i2

        def rhs_top(
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

        return rhs_top

    tx, ty, tz = model.torque_space
    hook = model.extra_torque

    def rhs(
        t: float, qw: float, qx: float, qy: float, qz: float, w1: float, w2: float, w3: float
    ) -> tuple[float, ...]:
        r = row_major_from_wxyz(qw, qx, qy, qz)
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
