"""z-x-z Euler angles (memo §1): attitude, its geometry, and angular velocity.

Conventions (docs/CONVENTIONS.md):

* ``R_space_body = exp(φ A3) exp(θ A1) exp(ψ A3) = Rz(φ) Rx(θ) Rz(ψ)`` (1.13), the memo's D;
  equal to ``Rotation.from_euler("ZXZ", [φ, θ, ψ]).as_matrix()`` (upper case: intrinsic).
  φ: precession about the space z axis, applied first; θ: nutation about the line of nodes,
  applied second; ψ: spin about the body z' axis, applied last.  Radians.
* Principal ranges φ, ψ in (-π, π], θ in [0, π].
* Gimbal lock: at θ = 0 only φ + ψ is defined, at θ = π only φ - ψ, and the line of nodes
  is undefined.  `euler_zxz_from_matrix` then returns the documented branch ψ = 0.
* Angular velocity with the usual sign: ``hat(ω_s) = Ṙ Rᵀ``, ``hat(ω_b) = Rᵀ Ṙ``.  The memo's
  ω of (1.21) is -ω_b (see `memo_omega_from_euler_rates`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from physics._types import Mat3, Vec3
from physics.so3 import rot_x, rot_z

__all__ = [
    "EulerFrames",
    "GimbalLockError",
    "body_z_axis",
    "euler_rates_from_omega_body",
    "euler_zxz_from_matrix",
    "euler_zxz_from_matrix_near",
    "euler_frames",
    "line_of_nodes",
    "matrix_from_euler_zxz",
    "memo_omega_from_euler_rates",
    "omega_body_from_euler_rates",
    "omega_space_from_euler_rates",
    "wrap_angle",
]

TWO_PI = 2.0 * math.pi


class GimbalLockError(ValueError):
    """Euler rates are asked for where sin θ = 0 (θ = 0 or π): they are not defined there."""


def wrap_angle(angle: float) -> float:
    """`angle` [rad] mapped to (-π, π]."""
    wrapped = math.remainder(angle, TWO_PI)  # in [-π, π]
    return math.pi if wrapped == -math.pi else wrapped


def matrix_from_euler_zxz(phi: float, theta: float, psi: float) -> Mat3:
    """R_space_body (3, 3) = Rz(φ) Rx(θ) Rz(ψ) from z-x-z angles [rad] (memo 1.13)."""
    return rot_z(phi) @ rot_x(theta) @ rot_z(psi)


def _sum_and_difference(R: Mat3) -> tuple[float, float]:
    """(φ + ψ, φ - ψ) [rad] from the upper-left block of R, each to full precision where its
    weight 1 ± cos θ is not small:
    R00 + R11 = (1 + cos θ) cos(φ + ψ),  R10 - R01 = (1 + cos θ) sin(φ + ψ),
    R00 - R11 = (1 - cos θ) cos(φ - ψ),  R10 + R01 = (1 - cos θ) sin(φ - ψ)."""
    sigma = math.atan2(R[1, 0] - R[0, 1], R[0, 0] + R[1, 1])
    delta = math.atan2(R[1, 0] + R[0, 1], R[0, 0] - R[1, 1])
    return sigma, delta


def _theta_and_phi(R: Mat3) -> tuple[float, float | None]:
    """θ in [0, π] and φ (None where sin θ == 0) from the third column and row of R."""
    s_col = math.hypot(R[0, 2], R[1, 2])  # sin θ from e_z' = (sφ sθ, -cφ sθ, cθ)
    s_row = math.hypot(R[2, 0], R[2, 1])  # sin θ from the third row (sθ sψ, sθ cψ, cθ)
    theta = math.atan2(0.5 * (s_col + s_row), R[2, 2])
    phi = math.atan2(R[0, 2], -R[1, 2]) if s_col > 0.0 else None
    return theta, phi


def euler_zxz_from_matrix(R: Mat3) -> Vec3:
    """(φ, θ, ψ) [rad] (3,) with ``matrix_from_euler_zxz(φ, θ, ψ) == R`` for any rotation R.

    θ = atan2(sin θ, cos θ) in [0, π] is accurate everywhere, the poles included.  Where
    cos θ >= 0 the sum φ + ψ is taken from the well-conditioned block (1 + cos θ) e^{i(φ+ψ)},
    φ from the column e_z', and ψ = (φ + ψ) - φ; where cos θ < 0 likewise with φ - ψ.  So R is
    recovered to rounding (~1e-15) also within 1e-12 of the poles, where φ and ψ alone are
    ill-conditioned but do not matter.

    Branch at gimbal lock (sin θ == 0 exactly): ψ = 0, so φ = φ + ψ at θ = 0 and φ = φ - ψ
    at θ = π.  φ and ψ are in (-π, π].
    """
    R = np.asarray(R, dtype=float)
    theta, phi = _theta_and_phi(R)
    sigma, delta = _sum_and_difference(R)
    upper = R[2, 2] >= 0.0
    if phi is None:
        phi = sigma if upper else delta
    psi = sigma - phi if upper else phi - delta
    return np.array([wrap_angle(phi), theta, wrap_angle(psi)])


def _nearest(angle: float, reference: float) -> float:
    """angle + 2πk nearest to `reference`."""
    return reference + math.remainder(angle - reference, TWO_PI)


def euler_zxz_from_matrix_near(R: Mat3, previous: Vec3) -> Vec3:
    """(φ, θ, ψ) [rad] of R on the branch nearest the previous angles, for trajectories.

    φ and ψ are unwrapped (not reduced to (-π, π]) so they are continuous in time; θ is in
    [0, π].  φ + ψ (upper hemisphere, cos θ >= 0) or φ - ψ (lower) is taken nearest its
    previous value, so it never jumps when the body axis passes through a pole: φ and ψ alone
    flip by π there, as the line of nodes does.  Exactly at a pole (sin θ == 0) φ keeps its
    previous value.  R is recovered to rounding as by `euler_zxz_from_matrix`.

    previous: (3,) the angles returned for the preceding sample.
    """
    R = np.asarray(R, dtype=float)
    phi_prev, _, psi_prev = (float(a) for a in previous)
    theta, phi = _theta_and_phi(R)
    sigma, delta = _sum_and_difference(R)
    phi = phi_prev if phi is None else _nearest(phi, phi_prev)
    if R[2, 2] >= 0.0:
        psi = _nearest(sigma, phi_prev + psi_prev) - phi
    else:
        psi = phi - _nearest(delta, phi_prev - psi_prev)
    return np.array([phi, theta, psi])


def line_of_nodes(phi: float) -> Vec3:
    """e_n = (cos φ, sin φ, 0) (3,), space components: the axis of the θ rotation.

    Undefined at gimbal lock (θ = 0, π); this returns the axis of the documented branch.
    """
    return np.array([math.cos(phi), math.sin(phi), 0.0])


def body_z_axis(phi: float, theta: float) -> Vec3:
    """e_z' = R e_z = (sin φ sin θ, -cos φ sin θ, cos θ) (3,), space components (6.5)."""
    return np.array([math.sin(phi) * math.sin(theta), -math.cos(phi) * math.sin(theta), math.cos(theta)])


class EulerFrames(NamedTuple):
    """The frames of the z-x-z decomposition (memo §1), each R_space_frame (3, 3).

    space: the space frame C (identity).  after_phi: the ξηζ frame, Rz(φ); its x axis is
    the line of nodes.  after_theta: the ξ'η'ζ' frame, Rz(φ) Rx(θ); its z axis is the body
    z' axis.  body: C', Rz(φ) Rx(θ) Rz(ψ).
    """

    space: Mat3
    after_phi: Mat3
    after_theta: Mat3
    body: Mat3


def euler_frames(phi: float, theta: float, psi: float) -> EulerFrames:
    """The four frames of the decomposition at angles (φ, θ, ψ) [rad], for drawing."""
    after_phi = rot_z(phi)
    after_theta = after_phi @ rot_x(theta)
    return EulerFrames(np.eye(3), after_phi, after_theta, after_theta @ rot_z(psi))


def omega_space_from_euler_rates(angles: Vec3, rates: Vec3) -> Vec3:
    """ω_s (3,) [rad/s], space components, from (φ, θ, ψ) [rad] and their rates [rad/s].

    ω_s = φ̇ e_z + θ̇ e_n + ψ̇ e_z' (1.17, 1.18), hat(ω_s) = Ṙ Rᵀ.
    """
    phi, theta, _ = angles
    dphi, dtheta, dpsi = rates
    sp, cp, st, ct = math.sin(phi), math.cos(phi), math.sin(theta), math.cos(theta)
    return np.array([dtheta * cp + dpsi * st * sp, dtheta * sp - dpsi * st * cp, dphi + dpsi * ct])


def omega_body_from_euler_rates(angles: Vec3, rates: Vec3) -> Vec3:
    """ω_b (3,) [rad/s], body components, from (φ, θ, ψ) [rad] and rates; hat(ω_b) = Rᵀ Ṙ."""
    _, theta, psi = angles
    dphi, dtheta, dpsi = rates
    st, ct, ss, cs = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    return np.array([dphi * st * ss + dtheta * cs, dphi * st * cs - dtheta * ss, dphi * ct + dpsi])


def euler_rates_from_omega_body(angles: Vec3, omega_body: Vec3, min_sin_theta: float = 1e-9) -> Vec3:
    """(φ̇, θ̇, ψ̇) (3,) [rad/s] from ω_b [rad/s] at (φ, θ, ψ) [rad].

    The map from rates to ω has determinant sin θ, so the rates are undefined at gimbal lock;
    where |sin θ| < min_sin_theta this raises `GimbalLockError` instead of returning huge or
    non-finite numbers.
    """
    _, theta, psi = angles
    w1, w2, w3 = omega_body
    st = math.sin(theta)
    if not abs(st) >= min_sin_theta:
        raise GimbalLockError(
            f"Euler rates are undefined at θ = {theta:.3g} rad (sin θ = {st:.3g}): only "
            f"{'φ + ψ' if math.cos(theta) > 0 else 'φ - ψ'} is defined at gimbal lock"
        )
    ss, cs = math.sin(psi), math.cos(psi)
    dphi = (w1 * ss + w2 * cs) / st
    return np.array([dphi, w1 * cs - w2 * ss, w3 - dphi * math.cos(theta)])


def memo_omega_from_euler_rates(angles: Vec3, rates: Vec3) -> Vec3:
    """The memo's ω (1.21) (3,): defined by hat(ω) = (R⁻¹)˙ R = -Rᵀ Ṙ, so ω_memo = -ω_b.

    Written out as in the memo: ω_x' = -φ̇ sin θ sin ψ - θ̇ cos ψ, ω_y' = -φ̇ sin θ cos ψ
    + θ̇ sin ψ, ω_z' = -φ̇ cos θ - ψ̇.  Its (1.23) R⁻¹ ω' = -ω relates it to ω' = ω_s.
    """
    _, theta, psi = angles
    dphi, dtheta, dpsi = rates
    st, ct, ss, cs = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    return np.array([-dphi * st * ss - dtheta * cs, -dphi * st * cs + dtheta * ss, -dphi * ct - dpsi])
