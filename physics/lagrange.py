"""Lagrange's equations (memo §5) and the rigid body in z-x-z Euler angles (memo §6), literally.

This is the memo's formulation, kept for comparison and teaching.  The singularity-free
integrators (Ṙ = R hat(ω_b) with Euler's equations) live in `physics.integrators`.

Generic system (memo 5.1-5.13).  Generalized coordinates q (m,), kinetic energy

    T(t, q, q̇) = ½ q̇ᵀ M(q) q̇ + b(t, q)·q̇ + T0(t, q),

generalized forces Q_j = Σ_i F_i · ∂x_i/∂q_j (5.12) given as a function Q(t, q, q̇).  Lagrange's
equations d/dt ∂T/∂q̇ - ∂T/∂q = Q (5.13) in matrix form (docs/CONVENTIONS.md):

    M q̈ = Q - Ṁ q̇ + ∂T/∂q                                  (b = T0 = 0)
    M q̈ = Q - Ṁ q̇ + ½ q̇ᵀ(∂M/∂q)q̇ - (B - Bᵀ) q̇ - ∂b/∂t + ∂T0/∂q     (general)

with Ṁ = Σ_k (∂M/∂q_k) q̇_k and B_jk = ∂b_j/∂q_k.  The b and T0 terms appear when x_i depends
on t explicitly (5.1), e.g. particles described in a rotating frame (Coriolis, centrifugal).
`LagrangianSystem` takes ∂M/∂q analytically or by central finite differences.

Finite differences (documented accuracy).  Every derivative taken numerically here is the
central difference (f(x + h) - f(x - h)) / 2h with h = FD_RELATIVE_STEP · max(1, |x|),
FD_RELATIVE_STEP = ε^(1/3) ≈ 6.1e-6 (ε = 2.2e-16, the step that balances truncation h²/6 |f'''|
against rounding ε|f|/h).  For functions that vary on a scale of order 1 in x (angles [rad],
lengths in units of the system's size) the derivative is accurate to ~1e-10 relative to the
size of f; the accelerations then carry that error times the condition number of M.  Pass
`fd_step` for coordinates with other scales.

Rigid body (memo 6.3, 6.4, 6.10).  q = (φ, θ, ψ) z-x-z angles [rad] (R = Rz(φ) Rx(θ) Rz(ψ),
`physics.euler`), body axes = principal axes, I = diag(I1, I2, I3) about the centre of mass or
the fixed pivot.  With ω_b = J(θ, ψ) q̇ (`omega_body_from_euler_rates`),

    T = ½ ω_bᵀ I ω_b = ½ q̇ᵀ M q̇,   M(θ, ψ) = Jᵀ I J,   det M = I1 I2 I3 sin²θ,

and for a torque M_s (space components, about the same point) Q_φ = M_s·e_z, Q_θ = M_s·e_n,
Q_ψ = M_s·e_z' (6.10).  A potential (the heavy top's gravity) enters through its torque.

Singularity.  M is singular at sin θ = 0 (θ = 0, π: gimbal lock), where its condition number
grows like 1/sin²θ and the Euler rates of a regular motion like 1/sin θ.  The pointwise
functions raise `physics.euler.GimbalLockError` when |sin θ| < MIN_SIN_THETA = 1e-6 (condition
number >= 1e12: fewer than ~4 digits left); `integrate_euler_lagrange` stops with
`EulerLagrangeSingularityError` already where sin θ falls to SIN_THETA_STOP = 1e-3.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.linalg
from scipy.integrate import solve_ivp

from physics._types import Array, Mat3, Vec3
from physics.dynamics import IntegrationError, Model, State, Trajectory
from physics.euler import (
    GimbalLockError,
    body_z_axis,
    euler_rates_from_omega_body,
    euler_zxz_from_matrix,
    line_of_nodes,
    matrix_from_euler_zxz,
    omega_body_from_euler_rates,
)

__all__ = [
    "LagrangeTerms",
    "lagrange_terms",
    "FD_RELATIVE_STEP",
    "MIN_SIN_THETA",
    "SIN_THETA_STOP",
    "EulerLagrangeSingularityError",
    "LagrangianSystem",
    "euler_accelerations",
    "generalized_forces",
    "integrate_euler_lagrange",
    "lagrange_accelerations",
    "mass_matrix",
    "mass_matrix_derivatives",
    "mass_matrix_derivatives_fd",
    "rigid_body_system",
]

FD_RELATIVE_STEP = float(np.finfo(float).eps) ** (1.0 / 3.0)  # ≈ 6.06e-6, central differences
MIN_SIN_THETA = 1e-6  # pointwise functions refuse |sin θ| below this (cond(M) ~ 1/sin²θ)
SIN_THETA_STOP = 1e-3  # integrate_euler_lagrange stops where sin θ falls to this
METHOD_NAME = "euler_lagrange"

MatrixFn = Callable[[Array], Array]
ForceFn = Callable[[float, Array, Array], Array]


class EulerLagrangeSingularityError(IntegrationError, GimbalLockError):
    """The Euler-angle Lagrangian became singular (sin θ -> 0) during a run.

    Both an `IntegrationError` and a `GimbalLockError`.  Attributes: t [s] and theta [rad]
    where it happened.
    """

    def __init__(self, t: float, theta: float, detail: str = "") -> None:
        self.t = float(t)
        self.theta = float(theta)
        super().__init__(
            f"the Euler-angle Lagrangian is singular at θ = {self.theta:.6g} rad "
            f"(sin θ in a denominator, sin θ = {math.sin(self.theta):.3g}) reached at t = {self.t:.9g} s{detail}; "
            "use another method (e.g. 'adaptive' or 'splitting4', which have no singularity)"
        )


# --------------------------------------------------------------------------------------------
# Generic Lagrange solver (memo §5)
# --------------------------------------------------------------------------------------------


def _fd_steps(x: Array, fd_step: float | None) -> Array:
    """Central-difference steps h_k = fd_step · max(1, |x_k|) (default fd_step ε^(1/3))."""
    rel = FD_RELATIVE_STEP if fd_step is None else float(fd_step)
    return rel * np.maximum(1.0, np.abs(x))


def mass_matrix_derivatives_fd(mass_matrix_fn: MatrixFn, q: Array, fd_step: float | None = None) -> Array:
    """∂M/∂q (m, m, m) by central differences; entry [k] is ∂M/∂q_k.

    mass_matrix_fn: q (m,) -> M (m, m).  Step h_k = fd_step · max(1, |q_k|), default
    ε^(1/3) ≈ 6e-6: accurate to ~1e-10 relative to |M| when M varies on a scale ~1 in q.
    """
    q = np.asarray(q, dtype=float)
    steps = _fd_steps(q, fd_step)
    out = []
    for k, h in enumerate(steps):
        dq = np.zeros_like(q)
        dq[k] = h
        out.append((np.asarray(mass_matrix_fn(q + dq)) - np.asarray(mass_matrix_fn(q - dq))) / (2.0 * h))
    return np.array(out)


def _solve_spd(M: Array, rhs: Array) -> Array:
    """M⁻¹ rhs for a symmetric positive definite M; ValueError if M is not (T must be > 0)."""
    try:
        factor = scipy.linalg.cho_factor(M)
    except np.linalg.LinAlgError as exc:
        raise ValueError(f"the mass matrix is not positive definite: {M.tolist()}") from exc
    return scipy.linalg.cho_solve(factor, rhs)


def lagrange_accelerations(M: Array, dM_dq: Array, Q: Array, qdot: Array, extra_rhs: Array | None = None) -> Array:
    """q̈ (m,) from M q̈ = Q - Ṁ q̇ + ∂T/∂q (5.13) for T = ½ q̇ᵀ M(q) q̇.

    M: (m, m) symmetric positive definite; dM_dq: (m, m, m), [k] = ∂M/∂q_k; Q: (m,) generalized
    forces (5.12); qdot: (m,).  Ṁ = Σ_k (∂M/∂q_k) q̇_k, (∂T/∂q)_k = ½ q̇ᵀ (∂M/∂q_k) q̇.
    extra_rhs: (m,) added to the right-hand side (terms from b and T0, see the module doc).
    """
    qdot = np.asarray(qdot, dtype=float)
    M_dot = np.einsum("kij,k->ij", dM_dq, qdot)
    dT_dq = 0.5 * np.einsum("i,kij,j->k", qdot, dM_dq, qdot)
    rhs = np.asarray(Q, dtype=float) - M_dot @ qdot + dT_dq
    if extra_rhs is not None:
        rhs = rhs + extra_rhs
    M = np.asarray(M, dtype=float)
    if not (np.all(np.isfinite(rhs)) and np.all(np.isfinite(M))):
        raise ValueError(
            f"non-finite terms in Lagrange's equations: Q = {np.asarray(Q).tolist()}, q̇ = {qdot.tolist()}"
        )
    return _solve_spd(M, rhs)


@dataclass(frozen=True)
class LagrangianSystem:
    """A system with kinetic energy T = ½ q̇ᵀ M(q) q̇ + b(t, q)·q̇ + T0(t, q), forces Q(t, q, q̇).

    mass_matrix: q (m,) -> M (m, m), symmetric positive definite.
    generalized_forces: (t [s], q (m,), q̇ (m,)) -> Q (m,) (5.12); for a potential V(q),
        Q = -∂V/∂q.
    mass_matrix_derivatives: q -> (m, m, m), [k] = ∂M/∂q_k; None: central differences.
    gyroscopic: b(t, q) -> (m,), the part of T linear in q̇ (rotating frames); None: b = 0.
    kinetic_energy_0: T0(t, q) -> float, the part of T free of q̇; None: T0 = 0.
    fd_step: relative step of every finite difference (see the module doc); None: ε^(1/3).

    Example, the spherical pendulum (θ from the downward vertical, φ azimuth; m = l = 1):
        LagrangianSystem(lambda q: np.diag([1.0, math.sin(q[0]) ** 2]),
                         lambda t, q, qd: np.array([-9.81 * math.sin(q[0]), 0.0]))
    """

    mass_matrix: MatrixFn
    generalized_forces: ForceFn
    mass_matrix_derivatives: MatrixFn | None = None
    gyroscopic: Callable[[float, Array], Array] | None = None
    kinetic_energy_0: Callable[[float, Array], float] | None = None
    fd_step: float | None = None

    def kinetic_energy(self, t: float, q: Array, qdot: Array) -> float:
        """T [J] at (t, q, q̇)."""
        q, qdot = np.asarray(q, dtype=float), np.asarray(qdot, dtype=float)
        T = 0.5 * float(qdot @ np.asarray(self.mass_matrix(q)) @ qdot)
        if self.gyroscopic is not None:
            T += float(np.asarray(self.gyroscopic(t, q)) @ qdot)
        if self.kinetic_energy_0 is not None:
            T += float(self.kinetic_energy_0(t, q))
        return T

    def _extra_rhs(self, t: float, q: Array, qdot: Array) -> Array | None:
        """-(B - Bᵀ) q̇ - ∂b/∂t + ∂T0/∂q (m,) by central differences, or None."""
        if self.gyroscopic is None and self.kinetic_energy_0 is None:
            return None
        extra = np.zeros_like(q)
        steps = _fd_steps(q, self.fd_step)
        if self.gyroscopic is not None:
            b = self.gyroscopic
            B = np.empty((q.size, q.size))  # B[j, k] = ∂b_j/∂q_k
            for k, h in enumerate(steps):
                dq = np.zeros_like(q)
                dq[k] = h
                B[:, k] = (np.asarray(b(t, q + dq)) - np.asarray(b(t, q - dq))) / (2.0 * h)
            h_t = float(_fd_steps(np.array([t]), self.fd_step)[0])
            db_dt = (np.asarray(b(t + h_t, q)) - np.asarray(b(t - h_t, q))) / (2.0 * h_t)
            extra += -(B - B.T) @ qdot - db_dt
        if self.kinetic_energy_0 is not None:
            T0 = self.kinetic_energy_0
            for k, h in enumerate(steps):
                dq = np.zeros_like(q)
                dq[k] = h
                extra[k] += (float(T0(t, q + dq)) - float(T0(t, q - dq))) / (2.0 * h)
        return extra

    def accelerations(self, t: float, q: Array, qdot: Array) -> Array:
        """q̈ (m,) from Lagrange's equations (5.13) at time t [s], q (m,), q̇ (m,)."""
        q, qdot = np.asarray(q, dtype=float), np.asarray(qdot, dtype=float)
        M = np.asarray(self.mass_matrix(q), dtype=float)
        if self.mass_matrix_derivatives is not None:
            dM = np.asarray(self.mass_matrix_derivatives(q), dtype=float)
        else:
            dM = mass_matrix_derivatives_fd(self.mass_matrix, q, self.fd_step)
        Q = np.asarray(self.generalized_forces(t, q, qdot), dtype=float)
        return lagrange_accelerations(M, dM, Q, qdot, self._extra_rhs(t, q, qdot))


# --------------------------------------------------------------------------------------------
# The rigid body in z-x-z Euler angles (memo §6)
# --------------------------------------------------------------------------------------------


def _check_sin_theta(theta: float, min_sin_theta: float) -> None:
    s = math.sin(theta)
    if not abs(s) >= min_sin_theta:  # also catches NaN
        raise GimbalLockError(
            f"the Euler-angle mass matrix is singular at θ = {theta:.6g} rad (sin θ = {s:.3g} "
            f"< {min_sin_theta:g}): det M = I1 I2 I3 sin²θ; Euler rates are undefined at gimbal lock"
        )


def _jacobian(theta: float, psi: float) -> tuple[Mat3, Mat3, Mat3]:
    """J (ω_b = J q̇), ∂J/∂θ, ∂J/∂ψ, each (3, 3); J does not depend on φ."""
    st, ct, ss, cs = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    J = np.array([[st * ss, cs, 0.0], [st * cs, -ss, 0.0], [ct, 0.0, 1.0]])
    dJ_dtheta = np.array([[ct * ss, 0.0, 0.0], [ct * cs, 0.0, 0.0], [-st, 0.0, 0.0]])
    dJ_dpsi = np.array([[st * cs, -ss, 0.0], [-st * ss, -cs, 0.0], [0.0, 0.0, 0.0]])
    return J, dJ_dtheta, dJ_dpsi


def mass_matrix(angles: Vec3, inertia: Vec3, min_sin_theta: float = MIN_SIN_THETA) -> Mat3:
    """M(θ, ψ) (3, 3) [kg m²] with T = ½ q̇ᵀ M q̇ = ½ Σ I_k ω_bk² (6.4), q = (φ, θ, ψ) [rad].

    M = Jᵀ diag(I) J with ω_b = J q̇ (`omega_body_from_euler_rates`).  Written out:
    M_φφ = (I1 sψ² + I2 cψ²) sθ² + I3 cθ², M_φθ = (I1 - I2) sθ sψ cψ, M_φψ = I3 cθ,
    M_θθ = I1 cψ² + I2 sψ², M_θψ = 0, M_ψψ = I3.
    inertia: principal moments (I1, I2, I3) [kg m²].  Raises GimbalLockError where
    |sin θ| < min_sin_theta (det M = I1 I2 I3 sin²θ).
    """
    _, theta, psi = (float(a) for a in angles)
    _check_sin_theta(theta, min_sin_theta)
    J, _, _ = _jacobian(theta, psi)
    return J.T @ (np.asarray(inertia, dtype=float)[:, None] * J)


def mass_matrix_derivatives(angles: Vec3, inertia: Vec3) -> Array:
    """∂M/∂q (3, 3, 3) analytically: [0] = ∂M/∂φ = 0, [1] = ∂M/∂θ, [2] = ∂M/∂ψ [kg m²/rad].

    ∂M/∂q_k = (∂J/∂q_k)ᵀ I J + Jᵀ I (∂J/∂q_k).  Defined everywhere (no threshold).
    """
    _, theta, psi = (float(a) for a in angles)
    J, dJ_dtheta, dJ_dpsi = _jacobian(theta, psi)
    I = np.asarray(inertia, dtype=float)[:, None]
    out = np.zeros((3, 3, 3))
    for k, dJ in ((1, dJ_dtheta), (2, dJ_dpsi)):
        half = dJ.T @ (I * J)
        out[k] = half + half.T
    return out


def generalized_forces(angles: Vec3, torque_space: Vec3) -> Vec3:
    """(Q_φ, Q_θ, Q_ψ) (3,) [N m] = (M·e_z, M·e_n, M·e_z') (6.10).

    angles: (φ, θ, ψ) [rad]; torque_space: M (3,) [N m], space components, about the centre
    of mass (or the fixed pivot, with I about the pivot).  e_n = (cos φ, sin φ, 0) is the line
    of nodes, e_z' = R e_z the body z' axis (6.5).  Defined for every angle.
    """
    phi, theta, _ = (float(a) for a in angles)
    torque = np.asarray(torque_space, dtype=float)
    return np.array([torque[2], float(torque @ line_of_nodes(phi)), float(torque @ body_z_axis(phi, theta))])


def euler_accelerations(
    model: Model,
    t: float,
    angles: Vec3,
    rates: Vec3,
    *,
    min_sin_theta: float = MIN_SIN_THETA,
    derivatives: Literal["analytic", "fd"] = "analytic",
) -> Vec3:
    """(φ̈, θ̈, ψ̈) (3,) [rad/s²] from Lagrange's equations M q̈ = Q - Ṁ q̇ + ∂T/∂q (5.13).

    model: inertia (principal, about the centre of mass or pivot) and torque, the latter from
    `model.torque_space_at(t, R, ω_b)`; t [s]; angles (φ, θ, ψ) [rad]; rates (φ̇, θ̇, ψ̇)
    [rad/s].  derivatives: ∂M/∂q "analytic" (default) or "fd" (central differences).
    Raises GimbalLockError where |sin θ| < min_sin_theta.
    """
    angles = np.asarray(angles, dtype=float)
    rates = np.asarray(rates, dtype=float)
    _check_sin_theta(float(angles[1]), min_sin_theta)
    inertia = np.array(model.inertia)
    R = matrix_from_euler_zxz(*angles)
    omega_body = omega_body_from_euler_rates(angles, rates)
    Q = generalized_forces(angles, model.torque_space_at(t, R, omega_body))
    M = mass_matrix(angles, inertia, min_sin_theta)
    if derivatives == "analytic":
        dM = mass_matrix_derivatives(angles, inertia)
    elif derivatives == "fd":
        dM = mass_matrix_derivatives_fd(lambda q: mass_matrix(q, inertia, 0.0), angles)
    else:
        raise ValueError(f"derivatives must be 'analytic' or 'fd', got {derivatives!r}")
    return lagrange_accelerations(M, dM, Q, rates)


@dataclass(frozen=True)
class LagrangeTerms:
    """The terms of Lagrange's equations (5.13) for q = (φ, θ, ψ), each (3,), at one state.

    q [rad], qdot [rad/s], qddot [rad/s²] (from the motion itself, see `lagrange_terms`);
    T, V [J]; dT_dqdot = M q̇ [kg m²/s] (generalized momenta); ddt_dT_dqdot = d/dt ∂T/∂q̇ and
    dT_dq = ∂T/∂q [N m]; Q = (M·e_z, M·e_n, M·e_z') [N m] (6.10); residual = ddt_dT_dqdot -
    dT_dq - Q [N m]: zero for a motion that obeys the Newton-Euler equations.
    """

    q: Vec3
    qdot: Vec3
    qddot: Vec3
    T: float
    V: float
    dT_dqdot: Vec3
    ddt_dT_dqdot: Vec3
    dT_dq: Vec3
    Q: Vec3
    residual: Vec3


def lagrange_terms(model: Model, t: float, R_space_body: Mat3, omega_body: Vec3, angles: Vec3,
                   *, min_sin_theta: float = MIN_SIN_THETA) -> LagrangeTerms:
    """Lagrange's equations term by term, evaluated on a motion computed WITHOUT them.

    The state (R, ω_b) comes from a singularity-free method; ω̇_b from Euler's equations
    I ω̇_b = I ω_b × ω_b + Rᵀ M (`physics.dynamics.omega_body_dot`).  With ω_b = J(q) q̇:
    q̇ = J⁻¹ ω_b and q̈ = J⁻¹ (ω̇_b - J̇ q̇), J̇ = (∂J/∂θ) θ̇ + (∂J/∂ψ) ψ̇.  Then
    d/dt ∂T/∂q̇ = M q̈ + Ṁ q̇, ∂T/∂q_k = ½ q̇ᵀ (∂M/∂q_k) q̇, and the residual against Q measures
    how well the two formulations (Newton-Euler and Lagrange, memo §6) agree: rounding only.
    angles: (φ, θ, ψ) [rad] of R (continuous along a motion); GimbalLockError where
    |sin θ| < min_sin_theta (q̇ is undefined at gimbal lock).
    """
    from physics.dynamics import energy, kinetic_energy, omega_body_dot

    q = np.asarray(angles, dtype=float)
    omega = np.asarray(omega_body, dtype=float)
    _check_sin_theta(float(q[1]), min_sin_theta)
    qdot = np.asarray(euler_rates_from_omega_body(q, omega, min_sin_theta=min_sin_theta), dtype=float)
    J, dJ_dtheta, dJ_dpsi = _jacobian(float(q[1]), float(q[2]))
    Jdot = dJ_dtheta * qdot[1] + dJ_dpsi * qdot[2]
    omega_dot = omega_body_dot(model, t, R_space_body, omega)
    qddot = np.linalg.solve(J, omega_dot - Jdot @ qdot)
    inertia = np.array(model.inertia)
    M = J.T @ (inertia[:, None] * J)
    dM = mass_matrix_derivatives(q, inertia)
    Mdot = np.tensordot(qdot, dM, axes=1)
    dT_dq = 0.5 * np.einsum("i,kij,j->k", qdot, dM, qdot)
    ddt = M @ qddot + Mdot @ qdot
    Q = generalized_forces(q, model.torque_space_at(t, R_space_body, omega))
    T = kinetic_energy(model, omega)
    return LagrangeTerms(q=q, qdot=qdot, qddot=qddot, T=T, V=energy(model, R_space_body, omega) - T,
                         dT_dqdot=M @ qdot, ddt_dT_dqdot=ddt, dT_dq=dT_dq, Q=Q, residual=ddt - dT_dq - Q)


def rigid_body_system(model: Model, analytic_derivatives: bool = True) -> LagrangianSystem:
    """The rigid body of `model` as a generic `LagrangianSystem` in q = (φ, θ, ψ) [rad].

    analytic_derivatives: ∂M/∂q from `mass_matrix_derivatives`, else central differences.
    """
    inertia = np.array(model.inertia)

    def forces(t: float, q: Array, qdot: Array) -> Array:
        R = matrix_from_euler_zxz(*q)
        return generalized_forces(q, model.torque_space_at(t, R, omega_body_from_euler_rates(q, qdot)))

    return LagrangianSystem(
        mass_matrix=lambda q: mass_matrix(q, inertia),
        generalized_forces=forces,
        mass_matrix_derivatives=(lambda q: mass_matrix_derivatives(q, inertia)) if analytic_derivatives else None,
    )


# --------------------------------------------------------------------------------------------
# Integrator (1): the literal formulation
# --------------------------------------------------------------------------------------------


def integrate_euler_lagrange(
    model: Model,
    state0: State,
    t_eval: Array,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    *,
    min_sin_theta: float = SIN_THETA_STOP,
    max_evaluations: int = 5_000_000,
) -> Trajectory:
    """Integrate Lagrange's equations in z-x-z angles: y = (φ, θ, ψ, φ̇, θ̇, ψ̇).

    Scheme: scipy `solve_ivp` with DOP853 (Dormand-Prince, explicit Runge-Kutta of order 8,
    embedded error estimators of orders 5 and 3, dense output of order 7), adaptive step,
    tolerances rtol, atol on the angles [rad] and rates [rad/s].  The right-hand side is
    `euler_accelerations` with the analytic ∂M/∂q.

    Start: the angles of state0.R_space_body on the principal branch (`euler_zxz_from_matrix`)
    and the rates from state0.omega_body (`euler_rates_from_omega_body`).  Output: R =
    Rz(φ) Rx(θ) Rz(ψ) and ω_b = J(θ, ψ) q̇ at each sample; φ and ψ are integrated unwrapped.

    Conserves nothing exactly: energy, |L| (free body) and p_φ, p_ψ (symmetric top) only to
    the tolerance (relative drift ~rtol per unit time), and R stays exactly orthogonal only
    because it is rebuilt from the angles.

    Singularity: the equations are singular at sin θ = 0.  A terminal event stops the run where
    sin θ falls to `min_sin_theta` (default 1e-3, on the dense output, so t is accurate to the
    tolerance), and a guard in the right-hand side refuses |sin θ| < MIN_SIN_THETA = 1e-6 for
    trial stages; both raise `EulerLagrangeSingularityError` (an IntegrationError and a
    GimbalLockError) naming t and θ.  A start with sin θ0 < min_sin_theta (e.g. R0 = identity)
    raises it at once.  Non-finite input or state raises IntegrationError; more than
    `max_evaluations` right-hand-side calls raises IntegrationError.

    t_eval: (N,) [s], strictly increasing, t_eval[0] >= state0.t.  Returns a `Trajectory`
    with evaluations = right-hand-side calls and wall_s = seconds spent in the solver.
    """
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or t_eval.size == 0:
        raise ValueError(f"t_eval must be a non-empty 1-D array, got shape {t_eval.shape}")
    R0 = np.asarray(state0.R_space_body, dtype=float)
    omega0 = np.asarray(state0.omega_body, dtype=float)
    if R0.shape != (3, 3) or omega0.shape != (3,):
        raise ValueError(f"state0 must hold R (3, 3) and omega_body (3,), got {R0.shape}, {omega0.shape}")
    t0 = float(state0.t)
    if not (np.all(np.isfinite(R0)) and np.all(np.isfinite(omega0)) and math.isfinite(t0)):
        raise IntegrationError(
            f"non-finite initial state at t = {t0}: R0 = {R0.tolist()}, omega_body = {omega0.tolist()}"
        )
    if not np.all(np.isfinite(t_eval)):
        raise ValueError("t_eval must be finite")
    if np.any(np.diff(t_eval) <= 0.0) or t_eval[0] < t0:
        raise ValueError(f"t_eval must be strictly increasing and start at or after state0.t = {t0}")

    angles0 = euler_zxz_from_matrix(R0)
    if not abs(math.sin(angles0[1])) >= min_sin_theta:
        raise EulerLagrangeSingularityError(t0, angles0[1], " (the initial state)")
    rates0 = euler_rates_from_omega_body(angles0, omega0, min_sin_theta)

    evaluations = 0

    def rhs(t: float, y: Array) -> Array:
        nonlocal evaluations
        evaluations += 1
        if evaluations > max_evaluations:
            raise IntegrationError(f"more than {max_evaluations} right-hand-side evaluations by t = {t:.9g} s")
        if not np.all(np.isfinite(y)):
            raise IntegrationError(f"non-finite state at t = {t:.9g} s: y = {y.tolist()}")
        try:
            qddot = euler_accelerations(model, t, y[:3], y[3:])
        except GimbalLockError as exc:
            raise EulerLagrangeSingularityError(t, y[1], " (trial stage of a step)") from exc
        except ValueError as exc:
            raise IntegrationError(f"at t = {t:.9g} s, angles {y[:3].tolist()}: {exc}") from exc
        if not np.all(np.isfinite(qddot)):  # pragma: no cover - the solve above refuses these
            raise IntegrationError(f"non-finite accelerations at t = {t:.9g} s, angles {y[:3].tolist()}")
        return np.concatenate([y[3:], qddot])

    def near_pole(t: float, y: Array) -> float:
        return math.sin(y[1]) - min_sin_theta

    near_pole.terminal = True  # type: ignore[attr-defined]
    near_pole.direction = -1.0  # type: ignore[attr-defined]

    y0 = np.concatenate([angles0, rates0])
    start = time.perf_counter()
    if t_eval[-1] == t0:
        ys = y0[:, None]
    else:
        sol = solve_ivp(
            rhs, (t0, float(t_eval[-1])), y0, method="DOP853", t_eval=t_eval, events=near_pole, rtol=rtol, atol=atol
        )
        if sol.status == 1:
            assert sol.t_events is not None and sol.y_events is not None  # events were given
            t_hit, y_hit = float(sol.t_events[0][0]), sol.y_events[0][0]
            raise EulerLagrangeSingularityError(t_hit, float(y_hit[1]), f" (sin θ fell to {min_sin_theta:g})")
        if sol.status != 0:
            raise IntegrationError(f"solve_ivp (DOP853) failed by t = {sol.t[-1]:.9g} s: {sol.message}")
        ys = sol.y
    wall_s = time.perf_counter() - start

    R = np.array([matrix_from_euler_zxz(*y[:3]) for y in ys.T])
    omega = np.array([omega_body_from_euler_rates(y[:3], y[3:]) for y in ys.T])
    if not (np.all(np.isfinite(R)) and np.all(np.isfinite(omega))):
        raise IntegrationError("non-finite output state")
    return Trajectory(t_eval.copy(), R, omega, evaluations, wall_s, METHOD_NAME)
