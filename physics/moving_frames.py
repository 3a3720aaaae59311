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
* A prescribed motion of C' (`FrameMotion`: z-x-z angles quadratic in t, the origin on a
  straight line plus a point fixed in C') gives every frame quantity at a time t (`FrameState`);
  `body_from_space`, `space_from_body`, `acceleration_space` change a particle's description
  between C and C', and `rk4_step` advances particles in C (where Newton's law is simple).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from physics._types import Array, Mat3, Vec3

__all__ = [
    "FrameMotion",
    "FrameState",
    "InertialForce",
    "acceleration_body",
    "acceleration_space",
    "body_from_space",
    "omega_dot_body_from_euler",
    "rk4_step",
    "space_from_body",
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


# ---------------------------------------------------------------------------- a prescribed frame motion
class FrameState(NamedTuple):
    """Where C' is, and how it moves, at one instant (space components unless ``_body``).

    a: (3,) [m] origin of C'; a_dot: (3,) [m/s]; a_ddot: (3,) [m/s²];
    R_space_body: (3, 3), the memo's D; omega_body: (3,) [rad/s], hat(ω_b) = Rᵀ Ṙ;
    omega_dot_body: (3,) [rad/s²], dω_b/dt; t: [s].
    """

    t: float
    a: Vec3
    a_dot: Vec3
    a_ddot: Vec3
    R_space_body: Mat3
    omega_body: Vec3
    omega_dot_body: Vec3

    @property
    def omega_space(self) -> Vec3:
        """ω_s = R ω_b (3,) [rad/s]."""
        return self.R_space_body @ self.omega_body


def _cross3(u: Vec3, v: Vec3) -> Vec3:
    """u × v for two (3,) arrays, without np.cross's generality (several times faster)."""
    u0, u1, u2 = float(u[0]), float(u[1]), float(u[2])
    v0, v1, v2 = float(v[0]), float(v[1]), float(v[2])
    return np.array([u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0])


def _cross(u: Array, v: Array) -> Array:
    """u × v: (3,) with (3,) by `_cross3`, else np.cross (broadcast over (N, 3))."""
    if u.ndim == 1 and v.ndim == 1:
        return _cross3(u, v)
    return np.cross(u, v)


def omega_dot_body_from_euler(angles: ArrayLike, rates: ArrayLike, accels: ArrayLike) -> Vec3:
    """dω_b/dt (3,) [rad/s²] from z-x-z (φ, θ, ψ) [rad], their rates [rad/s] and second
    derivatives [rad/s²]: the time derivative of
    ω_b = (φ̇ sin θ sin ψ + θ̇ cos ψ, φ̇ sin θ cos ψ − θ̇ sin ψ, φ̇ cos θ + ψ̇) (1.18).
    Defined everywhere, gimbal lock included (only the inverse map is singular there).
    """
    _, theta, psi = (float(v) for v in _vec3(angles, "angles"))
    dphi, dtheta, dpsi = (float(v) for v in _vec3(rates, "rates"))
    ddphi, ddtheta, ddpsi = (float(v) for v in _vec3(accels, "accels"))
    st, ct, ss, cs = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    return np.array([
        ddphi * st * ss + dphi * (dtheta * ct * ss + dpsi * st * cs) + ddtheta * cs - dtheta * dpsi * ss,
        ddphi * st * cs + dphi * (dtheta * ct * cs - dpsi * st * ss) - ddtheta * ss - dtheta * dpsi * cs,
        ddphi * ct - dphi * dtheta * st + ddpsi,
    ])


@dataclass(frozen=True)
class FrameMotion:
    """A prescribed motion of C' in C.

    Attitude: z-x-z angles quadratic in time for the first ``accel_seconds`` T, then linear (a
    turntable's motor speeds it up for T, then holds the speed): with τ = min(t, T),
    ``angles(t) = angles0 + rates t + accels (τ t − ½ τ²)`` (= ``½ accels t²`` while t ≤ T),
    rates ``rates + accels τ``, accelerations ``accels`` before T and 0 after;
    ``R = Rz(φ) Rx(θ) Rz(ψ)``.  Origin: ``a(t) = e s(t) + R(t) b``: a point b fixed in C'
    (``offset_body``; e.g. (0, 0, r) puts C' on the surface of a globe of radius r turning with
    it) carried along a straight line e (``line_direction``, unit) by
    ``s(t) = A (1 − cos Ω t) / Ω²`` (``line_accel`` A [m/s²], ``line_omega`` Ω [rad/s]): s starts
    at rest with s̈ = A cos Ω t, so C' first accelerates at A, then brakes and comes back with
    period 2π/Ω; at Ω = 0 it is uniform acceleration, s = A t² / 2.

    Attributes:
        angles0, rates, accels: (3,) [rad], [rad/s], [rad/s²] for (φ, θ, ψ).
        accel_seconds: [s] > 0, how long `accels` act (inf: for ever).
        offset_body: (3,) [m] b.  line_direction: (3,) e.  line_accel: [m/s²].  line_omega: [rad/s] ≥ 0.
    """

    angles0: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rates: tuple[float, float, float] = (0.0, 0.0, 0.0)
    accels: tuple[float, float, float] = (0.0, 0.0, 0.0)
    offset_body: tuple[float, float, float] = (0.0, 0.0, 0.0)
    line_direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    line_accel: float = 0.0
    line_omega: float = 0.0
    accel_seconds: float = math.inf

    def __post_init__(self) -> None:
        for name in ("angles0", "rates", "accels", "offset_body", "line_direction"):
            value = getattr(self, name)
            if len(value) != 3 or not all(math.isfinite(float(v)) for v in value):
                raise ValueError(f"FrameMotion.{name} must be three finite numbers, got {value!r}")
        for name in ("line_accel", "line_omega"):
            if not math.isfinite(float(getattr(self, name))):
                raise ValueError(f"FrameMotion.{name} must be finite, got {getattr(self, name)!r}")
        if not float(self.accel_seconds) > 0.0:  # NaN too
            raise ValueError(f"FrameMotion.accel_seconds must be > 0, got {self.accel_seconds!r}")
        if self.line_omega < 0.0:
            raise ValueError(f"FrameMotion.line_omega must be >= 0, got {self.line_omega!r}")
        if abs(float(np.linalg.norm(self.line_direction)) - 1.0) > 1e-9:
            raise ValueError(f"FrameMotion.line_direction must be a unit vector, got {self.line_direction!r}")

    def angles(self, t: float) -> Vec3:
        """(φ, θ, ψ) (3,) [rad] at time t [s] (not wrapped)."""
        tau = min(t, self.accel_seconds)
        return np.array(self.angles0) + np.array(self.rates) * t + np.array(self.accels) * (tau * t - 0.5 * tau * tau)

    def angle_rates(self, t: float) -> Vec3:
        """(φ̇, θ̇, ψ̇) (3,) [rad/s] at time t [s]."""
        return np.array(self.rates) + np.array(self.accels) * min(t, self.accel_seconds)

    def line(self, t: float) -> tuple[float, float, float]:
        """(s, ṡ, s̈) [m, m/s, m/s²] along the line at time t [s] (stable at Ω t → 0)."""
        A, W = self.line_accel, self.line_omega
        half = 0.5 * W * t
        sinc_half = math.sin(half) / half if half != 0.0 else 1.0
        s = 0.5 * A * t * t * sinc_half * sinc_half  # A (1 - cos Ωt) / Ω² = 2 A sin²(Ωt/2) / Ω²
        full = W * t
        s_dot = A * t * (math.sin(full) / full if full != 0.0 else 1.0)  # A sin(Ωt) / Ω
        return s, s_dot, A * math.cos(full)

    def at(self, t: float) -> FrameState:
        """Every frame quantity at time t [s].

        ȧ = e ṡ + R (ω_b × b), ä = e s̈ + R (ω̇_b × b + ω_b × (ω_b × b)).
        """
        (phi0, theta0, psi0), (dphi0, dtheta0, dpsi0) = self.angles0, self.rates
        ddphi, ddtheta, ddpsi = self.accels
        tau = t if t <= self.accel_seconds else self.accel_seconds
        half_t2 = tau * t - 0.5 * tau * tau  # ½ t² while the accelerations act
        phi, theta, psi = (phi0 + dphi0 * t + ddphi * half_t2, theta0 + dtheta0 * t + ddtheta * half_t2,
                           psi0 + dpsi0 * t + ddpsi * half_t2)
        dphi, dtheta, dpsi = dphi0 + ddphi * tau, dtheta0 + ddtheta * tau, dpsi0 + ddpsi * tau
        if t > self.accel_seconds:  # the speed held: no angle accelerations any more
            ddphi = ddtheta = ddpsi = 0.0
        cf, sf, ct, st, cp, sp = (math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta),
                                  math.cos(psi), math.sin(psi))
        R = np.array([  # Rz(φ) Rx(θ) Rz(ψ), written out (this runs several times a frame)
            [cf * cp - sf * ct * sp, -cf * sp - sf * ct * cp, sf * st],
            [sf * cp + cf * ct * sp, -sf * sp + cf * ct * cp, -cf * st],
            [st * sp, st * cp, ct],
        ])
        w = np.array([dphi * st * sp + dtheta * cp, dphi * st * cp - dtheta * sp, dphi * ct + dpsi])
        w_dot = np.array([  # omega_dot_body_from_euler, inlined
            ddphi * st * sp + dphi * (dtheta * ct * sp + dpsi * st * cp) + ddtheta * cp - dtheta * dpsi * sp,
            ddphi * st * cp + dphi * (dtheta * ct * cp - dpsi * st * sp) - ddtheta * sp - dtheta * dpsi * cp,
            ddphi * ct - dphi * dtheta * st + ddpsi,
        ])
        s, s_dot, s_ddot = self.line(t)
        e = np.array(self.line_direction)
        b = np.array(self.offset_body)
        wxb = _cross3(w, b)
        return FrameState(
            t=float(t),
            a=e * s + R @ b,
            a_dot=e * s_dot + R @ wxb,
            a_ddot=e * s_ddot + R @ (_cross3(w_dot, b) + _cross3(w, wxb)),
            R_space_body=R,
            omega_body=w,
            omega_dot_body=w_dot,
        )


def body_from_space(frame: FrameState, x_space: ArrayLike, x_space_dot: ArrayLike) -> tuple[Array, Array]:
    """A particle's C' description from its C one: (x', ẋ'), each (3,) or (N, 3) [m, m/s].

    ``x' = Rᵀ (x − a)``; ``ẋ' = Rᵀ (ẋ − ȧ) − ω_b × x'`` (1.19 solved for ẋ').
    """
    R = frame.R_space_body
    x_body = (_points(x_space, "x_space") - frame.a) @ R
    v_body = (_points(x_space_dot, "x_space_dot") - frame.a_dot) @ R - _cross(frame.omega_body, x_body)
    return x_body, v_body


def space_from_body(frame: FrameState, x_body: ArrayLike, x_body_dot: ArrayLike) -> tuple[Array, Array]:
    """A particle's C description from its C' one: (x, ẋ), each (3,) or (N, 3) [m, m/s].

    ``x = a + R x'`` (1.13); ``ẋ = ȧ + ω_s × (R x') + R ẋ'`` (1.19).
    """
    x = _points(x_body, "x_body")
    x_space = frame.a + x @ frame.R_space_body.T
    return x_space, velocity_space(frame.a_dot, frame.R_space_body, frame.omega_space, x, x_body_dot)


def acceleration_space(frame: FrameState, x_body: ArrayLike, x_body_dot: ArrayLike,
                       x_body_ddot: ArrayLike) -> Array:
    """ẍ in C (3,) or (N, 3) [m/s²] of a particle seen at x', ẋ', ẍ' in C' ((1.28) solved for ẍ):

    ``ẍ = ä + R (ẍ' + ω̇_b × x' + ω_b × (ω_b × x') + 2 ω_b × ẋ')``.  With ẋ' = ẍ' = 0 it is the
    acceleration of a point fixed in C' (what a force must give a particle to keep it there).
    """
    x = _points(x_body, "x_body")
    v = _points(x_body_dot, "x_body_dot")
    w, w_dot = frame.omega_body, frame.omega_dot_body
    body = (_points(x_body_ddot, "x_body_ddot") + _cross(w_dot, x) + _cross(w, _cross(w, x))
            + 2.0 * _cross(w, v))
    return frame.a_ddot + body @ frame.R_space_body.T


def rk4_step(
    acceleration: Callable[[float, Array, Array], Array], t: float, x: Array, v: Array, h: float
) -> tuple[Array, Array]:
    """One classical Runge-Kutta step (order 4) of ẍ = acceleration(t, x, ẋ) for particles in C.

    x, v: (N, 3) [m, m/s] at time t [s]; returns (x, v) at t + h.  Local error O(h⁵), global
    O(h⁴); exact for ẍ = 0 (a free particle moves on its straight line to rounding).
    """
    k1x, k1v = v, acceleration(t, x, v)
    k2x = v + 0.5 * h * k1v
    k2v = acceleration(t + 0.5 * h, x + 0.5 * h * k1x, k2x)
    k3x = v + 0.5 * h * k2v
    k3v = acceleration(t + 0.5 * h, x + 0.5 * h * k2x, k3x)
    k4x = v + h * k3v
    k4v = acceleration(t + h, x + h * k3x, k4x)
    return (x + (h / 6.0) * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            v + (h / 6.0) * (k1v + 2.0 * k2v + 2.0 * k3v + k4v))
