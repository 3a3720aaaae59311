"""The rigid body's model and state, and the quantities every integrator shares (memo §6).

Equations (docs/CONVENTIONS.md), body axes = principal axes, no Euler angles:
    Ṙ = R hat(ω_b),    I ω̇_b + ω_b × (I ω_b) = Rᵀ M,
with R = R_space_body (the memo's D), ω_b the body components of ω (usual sign), I = diag(I1,
I2, I3) about the centre of mass (or about the fixed pivot of a top) and M the torque in space
components about the same point.

Models (each models only what a scene needs):
* free body: M = 0.
* heavy top: centre of mass on the body +z' axis at distance ℓ from a fixed pivot, gravity along
  space -z: M = -mgl (e_z' × e_z), V = mgl e_z'·e_z = mgl R[2, 2].
* constant torque fixed in space: M = torque_space (no potential: the energy is not conserved).
* a hook: `extra_torque(t, R_space_body, omega_body) -> M_space` that the app adds.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from physics._types import Mat3, Vec3
from physics.inertia import validate_principal_moments

__all__ = [
    "IntegrationError",
    "Model",
    "State",
    "TorqueHook",
    "Trajectory",
    "angular_momentum_space",
    "energy",
    "kinetic_energy",
    "omega_body_dot",
]

TorqueHook = Callable[[float, Mat3, Vec3], Vec3]
"""extra_torque(t [s], R_space_body (3, 3), omega_body (3,) [rad/s]) -> torque, space [N m]."""


@dataclass(frozen=True)
class Model:
    """A rigid body and the torque acting on it.

    inertia: principal moments (I1, I2, I3) [kg m^2] about the body axes x', y', z', taken
        about the centre of mass, or about the pivot when mgl != 0.  Validated on creation
        (positive, finite, triangle inequalities; the flat lamina is allowed).
    mgl: m g ℓ [N m] of a heavy top (centre of mass at +ℓ on z', gravity along space -z).
    torque_space: a constant torque (3,) in space components [N m].
    extra_torque: optional hook adding a torque (space components) that depends on t, R, ω_b.
    """

    inertia: tuple[float, float, float]
    mgl: float = 0.0
    torque_space: tuple[float, float, float] = (0.0, 0.0, 0.0)
    extra_torque: TorqueHook | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        moments = validate_principal_moments(self.inertia)
        object.__setattr__(self, "inertia", tuple(float(m) for m in moments))
        torque = np.asarray(self.torque_space, dtype=float)
        if torque.shape != (3,) or not np.all(np.isfinite(torque)) or not np.isfinite(self.mgl):
            raise ValueError(f"mgl and torque_space must be finite, got {self.mgl}, {self.torque_space}")
        object.__setattr__(self, "mgl", float(self.mgl))
        object.__setattr__(self, "torque_space", tuple(float(m) for m in torque))

    @property
    def kind(self) -> str:
        """'free', 'heavy_top', 'const_torque' or 'custom' (anything combined or hooked)."""
        has_torque = any(self.torque_space)
        if self.extra_torque is not None or (self.mgl != 0.0 and has_torque):
            return "custom"
        if self.mgl != 0.0:
            return "heavy_top"
        return "const_torque" if has_torque else "free"

    @property
    def is_symmetric_top(self) -> bool:
        """I1 == I2 and only gravity acts: the Lagrange top (closed form exists)."""
        return self.kind in ("free", "heavy_top") and self.inertia[0] == self.inertia[1]

    @property
    def conservative(self) -> bool:
        """True when E = T + V is conserved (free body, heavy top)."""
        return self.kind in ("free", "heavy_top")

    def torque_space_at(self, t: float, R_space_body: Mat3, omega_body: Vec3) -> Vec3:
        """Total torque M (3,) [N m], space components, about the centre of mass or pivot."""
        M = np.array(self.torque_space)
        if self.mgl != 0.0:
            e_z_body = R_space_body[:, 2]
            M += -self.mgl * np.array([e_z_body[1], -e_z_body[0], 0.0])  # -mgl e_z' × e_z
        if self.extra_torque is not None:
            M += np.asarray(self.extra_torque(t, R_space_body, omega_body), dtype=float)
        return M

    def potential_energy(self, R_space_body: Mat3) -> float:
        """V [J] = mgl cos θ = mgl R[2, 2]; 0 without gravity."""
        return self.mgl * float(R_space_body[2, 2])


@dataclass(frozen=True)
class State:
    """R_space_body: (3, 3) attitude (x = R x'); omega_body: (3,) [rad/s]; t: time [s]."""

    R_space_body: Mat3
    omega_body: Vec3
    t: float = 0.0

    @property
    def euler_zxz(self) -> Vec3:
        """(φ, θ, ψ) [rad] on the principal branch, for display; never integrated."""
        from physics.euler import euler_zxz_from_matrix

        return euler_zxz_from_matrix(self.R_space_body)


@dataclass(frozen=True)
class Trajectory:
    """Samples of a motion.

    t: (N,) [s]; R_space_body: (N, 3, 3); omega_body: (N, 3) [rad/s]; evaluations: number of
    torque / right-hand-side evaluations used; wall_s: wall-clock seconds spent integrating;
    method: the method's registry name.
    """

    t: np.ndarray
    R_space_body: np.ndarray
    omega_body: np.ndarray
    evaluations: int
    wall_s: float
    method: str


class IntegrationError(RuntimeError):
    """A run met a non-finite state or a singularity; the message says when and why."""


def omega_body_dot(model: Model, t: float, R_space_body: Mat3, omega_body: Vec3) -> Vec3:
    """ω̇_b (3,) [rad/s^2] from Euler's equations I ω̇_b = (I ω_b) × ω_b + Rᵀ M."""
    inertia = np.array(model.inertia)
    M_body = R_space_body.T @ model.torque_space_at(t, R_space_body, omega_body)
    return (np.cross(inertia * omega_body, omega_body) + M_body) / inertia


def energy(model: Model, R_space_body: Mat3, omega_body: Vec3) -> float:
    """T + V [J]: T = ½ Σ I_k ω_bk² (6.4), V = mgl R[2, 2]."""
    inertia = np.array(model.inertia)
    return 0.5 * float(np.sum(inertia * omega_body**2)) + model.potential_energy(R_space_body)


def kinetic_energy(model: Model, omega_body: Vec3) -> float:
    """T = ½ Σ I_k ω_bk² [J] (memo 6.4), ω_b (3,) [rad/s]: `energy` without the potential."""
    i1, i2, i3 = model.inertia
    w1, w2, w3 = (float(w) for w in omega_body)
    return 0.5 * (i1 * w1 * w1 + i2 * w2 * w2 + i3 * w3 * w3)


def angular_momentum_space(model: Model, R_space_body: Mat3, omega_body: Vec3) -> Vec3:
    """L_s = R I ω_b (3,) [kg m^2/s], about the centre of mass or pivot, space components."""
    return R_space_body @ (np.array(model.inertia) * omega_body)
