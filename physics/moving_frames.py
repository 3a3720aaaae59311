"""Moving frames (memo §1, §4): velocity, acceleration and inertial forces seen from C'.

Conventions (docs/CONVENTIONS.md):

* A particle has space coordinates x (frame C, inertial) and body coordinates x' (frame C',
  moving): ``x = a + R_space_body x'`` (1.13), ``R_space_body`` the memo's D, a [m] the
  origin of C' in C.  Vectors with suffix ``_space`` are in C, with ``_body`` in C'.
* Angular velocity with the usual sign: ``hat(omega_space) = Ṙ Rᵀ``,
  ``hat(omega_body) = Rᵀ Ṙ``, ``omega_space = R omega_body`` [rad/s].  The memo's ω of
  (1.21)-(1.28) is ``-omega_body``; its formulas (1.28), (4.5), (4.6) read with
  ω_memo = -omega_body are the ones below.
* Vectorised over particles: ``x_body`` and ``x_body_dot`` may be (3,) or (N, 3); the frame
  quantities (a, R, ω) are shared by all particles.  Results have the broadcast shape.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from physics._types import Array, Mat3, Vec3

__all__ = [
    "InertialForce",
    "acceleration_body",
    "inertial_force_body",
    "kinetic_energy_particle",
    "velocity_space",
]


def _points(x: ArrayLike, name: str) -> Array:
    """x as a float array of shape (3,) or (N, 3)."""
    arr = np.asarray(x, dtype=float)
    if arr.shape[-1:] != (3,) or arr.ndim > 2:
        raise ValueError(f"{name} must have shape (3,) or (N, 3), got {arr.shape}")
    return arr


def _vec3(x: ArrayLike, name: str) -> Vec3:
    arr = np.asarray(x, dtype=float)
    if arr.shape != (3,):
        raise ValueError(f"{name} must have shape (3,), got {arr.shape}")
    return arr


def _mat3(R: ArrayLike) -> Mat3:
    arr = np.asarray(R, dtype=float)
    if arr.shape != (3, 3):
        raise ValueError(f"R_space_body must have shape (3, 3), got {arr.shape}")
    return arr


def _masses(mass: ArrayLike, points: Array) -> Array:
    """mass as a scalar array or, for (N,) masses with (N, 3) points, a (N, 1) column."""
    m = np.asarray(mass, dtype=float)
    if m.ndim == 0:
        return m
    if m.ndim == 1 and points.ndim == 2 and m.shape[0] == points.shape[0]:
        return m[:, None]
    raise ValueError(f"mass must be a scalar or (N,) for (N, 3) points; got {m.shape}")


def velocity_space(
    a_dot: ArrayLike,
    R_space_body: ArrayLike,
    omega_space: ArrayLike,
    x_body: ArrayLike,
    x_body_dot: ArrayLike,
) -> Array:
    """Velocity of a particle in C, space components (memo 1.19): (3,) or (N, 3) [m/s].

    ``ẋ = ȧ + ω_s × (R x') + R ẋ'``.

    Args:
        a_dot: (3,) [m/s], velocity of the origin of C', space components.
        R_space_body: (3, 3), the attitude R (memo's D).
        omega_space: (3,) [rad/s], ω_s with hat(ω_s) = Ṙ Rᵀ.
        x_body: (3,) or (N, 3) [m], body coordinates x'.
        x_body_dot: (3,) or (N, 3) [m/s], ẋ', the velocity seen in C' (body components).
    """
    R = _mat3(R_space_body)
    x_space_rel = _points(x_body, "x_body") @ R.T  # R x'
    v_rel = _points(x_body_dot, "x_body_dot") @ R.T  # R ẋ'
    omega = _vec3(omega_space, "omega_space")
    return _vec3(a_dot, "a_dot") + np.cross(omega, x_space_rel) + v_rel


def acceleration_body(
    x_ddot_space: ArrayLike,
    a_ddot: ArrayLike,
    R_space_body: ArrayLike,
    omega_body: ArrayLike,
    omega_dot_body: ArrayLike,
    x_body: ArrayLike,
    x_body_dot: ArrayLike,
) -> Array:
    """Acceleration ẍ' seen in C', body components (memo 1.28): (3,) or (N, 3) [m/s²].

    ``ẍ' = Rᵀ(ẍ - ä) - ω̇_b × x' - ω_b × (ω_b × x') - 2 ω_b × ẋ'``.

    Args:
        x_ddot_space: (3,) or (N, 3) [m/s²], ẍ, acceleration in the inertial frame C.
        a_ddot: (3,) [m/s²], ä, acceleration of the origin of C' (space components).
        R_space_body: (3, 3).
        omega_body: (3,) [rad/s], ω_b with hat(ω_b) = Rᵀ Ṙ.
        omega_dot_body: (3,) [rad/s²], dω_b/dt (equal to Rᵀ dω_s/dt).
        x_body: (3,) or (N, 3) [m], x'.
        x_body_dot: (3,) or (N, 3) [m/s], ẋ'.
    """
    R = _mat3(R_space_body)
    relative = (_points(x_ddot_space, "x_ddot_space") - _vec3(a_ddot, "a_ddot")) @ R  # Rᵀ(ẍ - ä)
    w = _vec3(omega_body, "omega_body")
    w_dot = _vec3(omega_dot_body, "omega_dot_body")
    x = _points(x_body, "x_body")
    v = _points(x_body_dot, "x_body_dot")
    return (
        relative
        - np.cross(w_dot, x)
        - np.cross(w, np.cross(w, x))
        - 2.0 * np.cross(w, v)
    )


class InertialForce(NamedTuple):
    """The inertial (fictitious) forces on a particle in C', body components [N] (memo 4.6).

    Each field is (3,) or (N, 3).  Added to the real force (body components, Rᵀ F), they make
    Newton's law hold in C': ``m ẍ' = Rᵀ F + total``.
    """

    translational: Array  # -m Rᵀ ä
    euler: Array  # -m ω̇_b × x'
    centrifugal: Array  # -m ω_b × (ω_b × x')
    coriolis: Array  # -2 m ω_b × ẋ'

    @property
    def total(self) -> Array:
        """Sum of the four forces [N], (3,) or (N, 3)."""
        return self.translational + self.euler + self.centrifugal + self.coriolis


def inertial_force_body(
    mass: ArrayLike,
    a_ddot: ArrayLike,
    R_space_body: ArrayLike,
    omega_body: ArrayLike,
    omega_dot_body: ArrayLike,
    x_body: ArrayLike,
    x_body_dot: ArrayLike,
) -> InertialForce:
    """Inertial forces on particles seen in C' (memo 4.5, 4.6), body components [N].

    translational ``-m Rᵀ ä``, Euler ``-m ω̇_b × x'``, centrifugal ``-m ω_b × (ω_b × x')``,
    Coriolis ``-2m ω_b × ẋ'``.  All four fields have the broadcast shape of x_body and
    x_body_dot ((3,) or (N, 3)); the translational force is repeated for every particle.

    Args:
        mass: [kg], a scalar or (N,) (one mass per particle).
        a_ddot: (3,) [m/s²], acceleration of the origin of C', space components.
        R_space_body: (3, 3).
        omega_body: (3,) [rad/s]; omega_dot_body: (3,) [rad/s²].
        x_body: (3,) or (N, 3) [m]; x_body_dot: (3,) or (N, 3) [m/s].
    """
    R = _mat3(R_space_body)
    x = _points(x_body, "x_body")
    v = _points(x_body_dot, "x_body_dot")
    shape = np.broadcast_shapes(x.shape, v.shape)
    m = _masses(mass, np.broadcast_to(x, shape))
    w = _vec3(omega_body, "omega_body")
    w_dot = _vec3(omega_dot_body, "omega_dot_body")
    a_body = _vec3(a_ddot, "a_ddot") @ R  # Rᵀ ä
    return InertialForce(
        translational=np.broadcast_to(-m * a_body, shape).copy(),
        euler=np.broadcast_to(-m * np.cross(w_dot, x), shape).copy(),
        centrifugal=np.broadcast_to(-m * np.cross(w, np.cross(w, x)), shape).copy(),
        coriolis=np.broadcast_to(-2.0 * m * np.cross(w, v), shape).copy(),
    )


def kinetic_energy_particle(
    mass: ArrayLike,
    a_dot: ArrayLike,
    R_space_body: ArrayLike,
    omega_space: ArrayLike,
    x_body: ArrayLike,
) -> float:
    """Kinetic energy in C [J] of a particle at rest in C' (memo 1.25).

    ``T = ½ m |ȧ|² + m ȧ·(ω_s × R x') + ½ m |ω_b × x'|²``; the last term is computed as
    ``|ω_s × R x'|²``, equal because R(ω_b × x') = ω_s × R x'.

    With x_body (N, 3) (and mass a scalar or (N,)) the particles form a rigid system and the
    total T = Σ T_i is returned.

    Args:
        mass: [kg], scalar or (N,).
        a_dot: (3,) [m/s], velocity of the origin of C' (space components).
        R_space_body: (3, 3).
        omega_space: (3,) [rad/s], ω_s with hat(ω_s) = Ṙ Rᵀ.
        x_body: (3,) or (N, 3) [m].
    """
    R = _mat3(R_space_body)
    x = _points(x_body, "x_body")
    m = _masses(mass, x)
    a_dot_v = _vec3(a_dot, "a_dot")
    spin = np.cross(_vec3(omega_space, "omega_space"), x @ R.T)  # ω_s × R x'
    per_particle = (
        0.5 * float(a_dot_v @ a_dot_v)
        + spin @ a_dot_v
        + 0.5 * np.sum(spin * spin, axis=-1)
    )
    weights = m.reshape(-1) if m.ndim else m  # scalar, or (N,) per particle
    return float(np.sum(weights * per_particle))
