"""The "Moving frame" scene's simulation (no viser): C′'s prescribed motion and three particles
integrated in C (`app.scenes.moving_frame` says what it shows and how exactly).
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from app.i18n import N_
from app.kit.core.common import SliderSpec, canonical_angles_deg, wrap_deg
from app.kit.core.history import Snapshot
from app.kit.core.trace import Trace
from physics._types import Array, Vec3
from physics.moving_frames import (
    FrameMotion,
    FrameState,
    InertialForce,
    acceleration_space,
    body_from_space,
    inertial_force_body,
    rk4_step,
    space_from_body,
)
from physics.so3 import hat

__all__ = [
    "ANGLE_SPECS",
    "DISPLAY_KEYS",
    "FRAME_KEYS",
    "H_MAX",
    "KEYS",
    "PARAM_SPECS",
    "PARTICLES",
    "PARTICLE_KEYS",
    "ForceReport",
    "MovingFrameSetup",
    "MovingFrameSimulation",
]

H_MAX = 1.0 / 240.0  # [s] the longest RK4 step (simulated time); a frame is sub-stepped
PARTICLES = (N_("free"), N_("at rest in C′"), N_("on a spring"))  # English: the API's; shown translated
PATH_SECONDS = 10.0  # [s] of simulated time kept in each path
PATH_SPACING = 1.0 / 15.0  # [s] between stored path points (2° of the turntable's turn)
PATH_CHUNK = 4  # points: a chunk completes every 0.2 s; its head is resent at most at 10 Hz

_DEG = ((-360.0, "-360"), (0.0, "0"), (360.0, "360"))
PARAM_SPECS = (
    # The frame C′ (an edit restarts the run at t = 0).
    SliderSpec("phi_dot", N_("dφ/dt [deg/s]"), -360.0, 360.0, 1.0, N_("precession rate of C′ about space z at t = 0"),
               _DEG),
    SliderSpec("theta_dot", N_("dθ/dt [deg/s]"), -180.0, 180.0, 1.0, N_("nutation rate of C′ (constant)")),
    SliderSpec("psi_dot", N_("dψ/dt [deg/s]"), -720.0, 720.0, 1.0, N_("spin rate of C′ about its own z′ (constant)")),
    SliderSpec("phi_ddot", N_("d²φ/dt² [deg/s²]"), -30.0, 30.0, 0.5,
               N_("angular acceleration of φ (a turntable speeding up)")),
    SliderSpec("spin_up", N_("speeds up for [s]"), 1.0, 600.0, 1.0,
               N_("d²φ/dt² acts this long, then dφ/dt holds (a motor that speeds the turntable up, "
                  "then keeps the speed)")),
    SliderSpec("offset", N_("origin offset h [m]"), 0.0, 3.0, 0.05,
               N_("C′'s origin is D (0, 0, h) from the line: on a globe of radius h, or up a top's axis")),
    SliderSpec("line_accel", N_("line acceleration A [m/s²]"), -2.0, 2.0, 0.05,
               N_("C′ is carried along space x with ä = A cos(Ω t) at t = 0 starting from rest")),
    SliderSpec("line_omega", N_("line Ω [rad/s]"), 0.0, 3.0, 0.05,
               N_("0: uniform acceleration; else C′ brakes and comes back with period 2π/Ω")),
    # The particles (an edit restarts the run).
    SliderSpec("mass", N_("mass m [kg]"), 0.1, 5.0, 0.1, N_("the mass of each particle")),
    SliderSpec("k", N_("spring constant k [N/m]"), 0.0, 40.0, 0.5, N_("the spring particle: F = −k (x − anchor)")),
    SliderSpec("free_x", N_("free: x′₀ [m]"), -3.0, 3.0, 0.05, N_("the free particle's start in C′")),
    SliderSpec("free_y", N_("free: y′₀ [m]"), -3.0, 3.0, 0.05, N_("the free particle's start in C′")),
    SliderSpec("free_vx", N_("free: ẋ′₀ [m/s]"), -3.0, 3.0, 0.05, N_("its velocity relative to C′ at t = 0")),
    SliderSpec("free_vy", N_("free: ẏ′₀ [m/s]"), -3.0, 3.0, 0.05, N_("its velocity relative to C′ at t = 0")),
    SliderSpec("rider_x", N_("at rest: x′ [m]"), -3.0, 3.0, 0.05, N_("where the particle at rest sits in C′")),
    SliderSpec("rider_y", N_("at rest: y′ [m]"), -3.0, 3.0, 0.05, N_("where the particle at rest sits in C′")),
    SliderSpec("anchor_x", N_("spring anchor x′ [m]"), -3.0, 3.0, 0.05, N_("the spring's anchor, fixed in C′")),
    SliderSpec("anchor_y", N_("spring anchor y′ [m]"), -3.0, 3.0, 0.05, N_("the spring's anchor, fixed in C′")),
    SliderSpec("stretch_x", N_("spring stretch x′ [m]"), -2.0, 2.0, 0.05,
               N_("the particle starts here from the anchor, "
                  "at rest in C′")),
    SliderSpec("stretch_y", N_("spring stretch y′ [m]"), -2.0, 2.0, 0.05,
               N_("the particle starts here from the anchor, "
                  "at rest in C′")),
    SliderSpec("disc_radius", N_("disc radius [m]"), 0.0, 3.0, 0.05,
               N_("the disc in C′'s x′y′ plane; its rim stops the free particle and carries it (0: no disc)")),
    # Display (no restart).
    SliderSpec("force_scale", N_("arrow scale [m/N]"), 0.01, 3.0, 0.01, N_("length of a force arrow per newton")),
    SliderSpec("forces_on", N_("forces on particle"), 1.0, 3.0, 1.0, N_("1 free, 2 at rest in C′, 3 on a spring")),
)
KEYS = tuple(spec.key for spec in PARAM_SPECS)
DISPLAY_KEYS = ("force_scale", "forces_on")
FRAME_KEYS = (*KEYS[:KEYS.index("mass")], "disc_radius")
PARTICLE_KEYS = KEYS[KEYS.index("mass"):KEYS.index("disc_radius")]
ANGLE_SPECS = (
    SliderSpec("phi0", N_("φ₀ [deg]"), -180.0, 180.0, 1.0, N_("C′'s precession angle at t = 0")),
    SliderSpec("theta0", N_("θ₀ [deg]"), 0.0, 180.0, 1.0, N_("C′'s nutation at t = 0 (Earth: 90° − latitude)")),
    SliderSpec("psi0", N_("ψ₀ [deg]"), -180.0, 180.0, 1.0, N_("C′'s spin angle at t = 0")),
)


@dataclass(frozen=True)
class MovingFrameSetup:
    """Everything a run starts from: the frame's motion and the particles' initial conditions.

    params: the values of PARAM_SPECS in order; angles_deg: C′'s z-x-z angles at t = 0 [deg].
    """

    params: tuple[float, ...]
    angles_deg: tuple[float, float, float]

    def __post_init__(self) -> None:
        if len(self.params) != len(PARAM_SPECS):
            raise ValueError(f"{len(PARAM_SPECS)} parameters expected, got {len(self.params)}")
        for spec, value in zip(PARAM_SPECS, self.params):
            if spec.check(value) is None:
                raise ValueError(spec.refusal(value))
        for spec, value in zip(ANGLE_SPECS, self.angles_deg):
            if spec.check(value) is None:
                raise ValueError(spec.refusal(value))
        if self.value("forces_on") not in (1.0, 2.0, 3.0):
            raise ValueError(f"forces on particle = {self.value('forces_on')!r} refused: 1, 2 or 3")

    def value(self, key: str) -> float:
        return float(self.params[KEYS.index(key)])

    @property
    def motion(self) -> FrameMotion:
        v = self.value
        rates = (math.radians(v("phi_dot")), math.radians(v("theta_dot")), math.radians(v("psi_dot")))
        angles = (math.radians(self.angles_deg[0]), math.radians(self.angles_deg[1]),
                  math.radians(self.angles_deg[2]))
        return FrameMotion(angles0=angles, rates=rates, accels=(math.radians(v("phi_ddot")), 0.0, 0.0),
                           accel_seconds=v("spin_up"),
                           offset_body=(0.0, 0.0, v("offset")), line_direction=(1.0, 0.0, 0.0),
                           line_accel=v("line_accel"), line_omega=v("line_omega"))

    @property
    def mass(self) -> float:
        return self.value("mass")

    @property
    def k(self) -> float:
        return self.value("k")

    @property
    def focus(self) -> int:
        """Index into PARTICLES of the particle whose forces are drawn."""
        return int(self.value("forces_on")) - 1

    def initial_body(self) -> tuple[Array, Array]:
        """(x′, ẋ′) (3, 3) of the particles (free, at rest, spring) at t = 0 [m, m/s]."""
        v = self.value
        x = np.array([[v("free_x"), v("free_y"), 0.0], [v("rider_x"), v("rider_y"), 0.0],
                      [v("anchor_x") + v("stretch_x"), v("anchor_y") + v("stretch_y"), 0.0]])
        x_dot = np.array([[v("free_vx"), v("free_vy"), 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        return x, x_dot

    @property
    def rider_body(self) -> Vec3:
        return np.array([self.value("rider_x"), self.value("rider_y"), 0.0])

    @property
    def anchor_body(self) -> Vec3:
        return np.array([self.value("anchor_x"), self.value("anchor_y"), 0.0])


@dataclass(frozen=True)
class ForceReport:
    """The forces on every particle at one instant, body components (C′) [N], each (3, 3).

    real: Dᵀ F.  inertial: the four forces of (4.6).  m_x_ddot_body: m ẍ′ from differentiating
    x′ = Dᵀ(x − a) with matrices.  residual: m ẍ′ − (Dᵀ F + Σ inertial), (3, 3).
    """

    real: Array
    inertial: InertialForce
    m_x_ddot_body: Array
    residual: Array


class MovingFrameSimulation:
    """C′'s prescribed motion and three particles integrated in C (no viser).

    Attributes:
        setup: the run's initial conditions.  t: [s] since the run started.  version: bumped on
        every change.  run: bumped on every reset.  x, v: (3, 3) space positions and velocities
        of (free, at rest, spring) [m, m/s].  paths_space, paths_body: per particle, the `Trace`
        of its position in C (x) and in C′ (x′) [m], cleared at every reset.  caught_at: where
        the disc's rim stopped the free particle, x′ (3,) [m], or None while it slides.

    The rim: a free particle that starts on the disc (|x′| below `disc_radius`) and slides to
    its edge (|x′| = disc_radius: on a flat frame the rim, on the Earth's patch, whose ground
    curves away under a free particle, where it has risen to) is stopped there and carried
    along (an inelastic stop: after the RK4 step in which it got there, it is at rest in C′
    where its straight line crossed that distance); from then on the rim's real force m ẍ holds it
    as the particle at rest in C′ is held.  So it stays on the picture, and the real force that
    now makes it go round shows.  Before that it is free: a straight line in C.
    """

    def __init__(self, setup: MovingFrameSetup) -> None:
        self.preset: str | None = None
        self.version = 0
        self.run = 0
        self.setup = setup
        self.paths_space = [Trace(PATH_SECONDS, PATH_SPACING, PATH_CHUNK) for _ in PARTICLES]
        self.paths_body = [Trace(PATH_SECONDS, PATH_SPACING, PATH_CHUNK) for _ in PARTICLES]
        self.reset()

    # ------------------------------------------------------------------ the Simulation protocol
    def reset(self) -> None:
        self._motion = motion = self.setup.motion
        # The same motion once the speeding up is over (t ≥ T): rates held, no accelerations.
        T = motion.accel_seconds
        self._held = (motion if not math.isfinite(T) else dataclasses.replace(
            motion, accel_seconds=math.inf, accels=(0.0, 0.0, 0.0),
            angles0=tuple(a - 0.5 * c * T * T for a, c in zip(motion.angles0, motion.accels)),  # type: ignore[arg-type]
            rates=tuple(r + c * T for r, c in zip(motion.rates, motion.accels))))  # type: ignore[arg-type]
        self._stepping = motion  # the motion the RK4 steps see (`_move`)
        self._mass, self._k = self.setup.mass, self.setup.k
        self._rider, self._anchor, self._zeros = self.setup.rider_body, self.setup.anchor_body, np.zeros(3)
        self.t = 0.0
        self._frame = self._motion.at(0.0)
        x_body, x_body_dot = self.setup.initial_body()
        self.x, self.v = space_from_body(self._frame, x_body, x_body_dot)
        self._rim = self.setup.value("disc_radius")
        self._on_disc = float(np.linalg.norm(x_body[0])) < self._rim
        self.caught_at: Vec3 | None = None
        for path in (*self.paths_space, *self.paths_body):
            path.clear()
        self._record_paths()
        self.run += 1
        self.version += 1

    def _record_paths(self) -> None:
        x_body, _ = self.body_coordinates()
        for k in range(len(PARTICLES)):
            self.paths_space[k].add(self.t, self.x[k])
            self.paths_body[k].add(self.t, x_body[k])

    def advance(self, dt: float) -> None:
        """RK4 in C in ceil(dt / H_MAX) equal steps; ArithmeticError (state kept) if it blows up."""
        if not (math.isfinite(dt) and dt >= 0.0):
            raise ValueError(f"advance: dt = {dt!r} must be finite and >= 0")
        if dt == 0.0:
            return
        self._move(dt)
        self._record_paths()
        self.version += 1

    def _move(self, dt: float) -> None:
        """x, v, t and C′ dt [s] on (no paths).  No RK4 step straddles the end of the speeding up
        (`FrameMotion.accel_seconds`, where the frame's ω̇ jumps): a step ends there."""
        x, v, t = self.x, self.v, self.t
        kink = self._motion.accel_seconds
        spans = [kink - self.t, self.t + dt - kink] if self.t < kink < self.t + dt else [dt]
        for span in spans:
            # the steps before the kink see its left limit (t ≤ T: still speeding up), those after
            # it the motion at the held speed (its right limit at t = T)
            self._stepping = self._motion if t < kink else self._held
            n = max(1, math.ceil(span / H_MAX - 1e-9))
            h = span / n
            for _ in range(n):
                x_before, v_before, t_before = x, v, t
                x, v = rk4_step(self._acceleration, t, x, v, h)
                t += h
                if self._on_disc and self.caught_at is None:
                    x, v = self._catch(t_before, x_before[0], v_before[0], t, x, v)
            if len(spans) > 1:
                t = kink
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            raise ArithmeticError(f"non-finite particle state at t = {t:.3f} s")
        self.x, self.v, self.t = x, v, self.t + dt
        self._frame = self._motion.at(self.t)

    def _x_body_free(self, t: float, x0: Vec3, v0: Vec3, t0: float) -> Vec3:
        """x′ (3,) [m] at time t [s] of the free particle on its straight line x0 + v0 (t − t0)."""
        frame = self._motion.at(t)
        return (x0 + (t - t0) * v0 - frame.a) @ frame.R_space_body

    def _catch(self, t0: float, x0: Vec3, v0: Vec3, t: float, x: Array, v: Array) -> tuple[Array, Array]:
        """(x, v) at time t [s], with the free particle stopped if it reached the rim since t0,
        where it was at x0 with velocity v0 (free: a straight line).  Where it stops is where its
        line crosses |x′| = rim (found to 1e-13 s, so it does not depend on how time was cut into
        steps); at t it is there at rest in C′."""
        rim = self._rim
        if float(np.linalg.norm(self._x_body_free(t, x0, v0, t0))) < rim:
            return x, v
        t_rim = brentq(lambda s: float(np.linalg.norm(self._x_body_free(s, x0, v0, t0))) - rim, t0, t, xtol=1e-13)
        place = self._x_body_free(t_rim, x0, v0, t0)
        self.caught_at = place = place * (rim / float(np.linalg.norm(place)))
        x_at, v_at = space_from_body(self._motion.at(t), place, self._zeros)
        x, v = x.copy(), v.copy()
        x[0], v[0] = x_at, v_at
        return x, v

    # ------------------------------------------------------------------ replay (app.kit.core.history)
    def snapshot(self) -> Snapshot:
        """The moment now: t, x (9) and v (9) [m, m/s], each path's (count, first), then whether
        the rim holds the free particle and where (4) (C′ is a function of t)."""
        marks = [float(m) for path in (*self.paths_space, *self.paths_body) for m in path.mark()]
        caught = [0.0, 0.0, 0.0, 0.0] if self.caught_at is None else [1.0, *self.caught_at.tolist()]
        values = [self.t, *self.x.ravel().tolist(), *self.v.ravel().tolist(), *marks, *caught]
        return Snapshot(np.array(values, dtype=float))

    def restore(self, snapshot: Snapshot, later: float = 0.0) -> None:
        """The recorded moment back bit for bit, paths rewound to it; then `later` [s] on for
        display (RK4 from the recorded state; the paths stay).  ValueError, nothing changed,
        if the snapshot is not one of this run's."""
        v = snapshot.values
        paths = (*self.paths_space, *self.paths_body)
        if v.shape != (23 + 2 * len(paths),):
            raise ValueError("this snapshot is not a moving-frame moment")
        marks = [(int(v[19 + 2 * k]), int(v[20 + 2 * k])) for k in range(len(paths))]
        if not all(path.can_rewind(mark) for path, mark in zip(paths, marks)):
            raise ValueError("this snapshot is not one of this run's moments")
        self.t = float(v[0])
        self.x, self.v = v[1:10].reshape(3, 3).copy(), v[10:19].reshape(3, 3).copy()
        self.caught_at = v[-3:].copy() if v[-4] == 1.0 else None
        self._frame = self._motion.at(self.t)
        for path, mark in zip(paths, marks):
            path.rewind(mark)
        if later > 0.0:
            try:
                self._move(later)
            except ArithmeticError:  # shown as recorded
                pass
        self.version += 1

    def truncate(self) -> None:
        """Forget the paths after now (a branch)."""
        for path in (*self.paths_space, *self.paths_body):
            path.truncate()

    # ------------------------------------------------------------------ edits
    def set_setup(self, setup: MovingFrameSetup) -> None:
        """New initial conditions; the run restarts at t = 0."""
        self.setup = setup
        self.reset()

    def set_display(self, setup: MovingFrameSetup) -> None:
        """New display parameters only (no restart); ValueError if anything else differs."""
        changed = [k for k, a, b in zip(KEYS, self.setup.params, setup.params) if a != b]
        if any(k not in DISPLAY_KEYS for k in changed) or setup.angles_deg != self.setup.angles_deg:
            raise ValueError("set_display changes display parameters only")
        self.setup = setup
        self.version += 1

    def fork(self) -> MovingFrameSimulation:
        """An exact, independent copy of the run at its current time: setup, t, the particles'
        x and v bit for bit, C′ now (its motion is a function of t), the paths so far, preset,
        run and version (a deep copy: small arrays and frozen dataclasses)."""
        return copy.deepcopy(self)

    # ------------------------------------------------------------------ physics
    def real_force(self, t: float, frame: FrameState, x: Array) -> Array:
        """F (3, 3) [N], space components, on (free, at rest, spring) at time t (on the free
        particle: none, or the rim's once it is caught)."""
        hold = self._mass * acceleration_space(frame, self._rider, self._zeros, self._zeros)
        spring = -self._k * (x[2] - frame.a - frame.R_space_body @ self._anchor)
        rim = (self._zeros if self.caught_at is None
               else self._mass * acceleration_space(frame, self.caught_at, self._zeros, self._zeros))
        return np.array([rim, hold, spring])

    def _acceleration(self, t: float, x: Array, v: Array) -> Array:
        return self.real_force(t, self._stepping.at(t), x) / self.setup.mass

    @property
    def frame(self) -> FrameState:
        """C′ now."""
        return self._frame

    def body_coordinates(self) -> tuple[Array, Array]:
        """(x′, ẋ′) (3, 3) of the particles now [m, m/s]."""
        return body_from_space(self._frame, self.x, self.v)

    def forces(self) -> ForceReport:
        """The real and inertial forces now (body components), and m ẍ′ found without (1.28)."""
        frame = self._frame
        m = self.setup.mass
        R = frame.R_space_body
        x_body, v_body = self.body_coordinates()
        F = self.real_force(self.t, frame, self.x)
        real = F @ R  # Dᵀ F, row-wise
        inertial = inertial_force_body(m, frame.a_ddot, R, frame.omega_body, frame.omega_dot_body, x_body, v_body)
        # x′ = Dᵀ (x − a): ẍ′ = D̈ᵀ (x − a) + 2 Ḋᵀ (ẋ − ȧ) + Dᵀ (ẍ − ä), with Ḋ = D W, D̈ = D (W² + Ẇ).
        W, W_dot = hat(frame.omega_body), hat(frame.omega_dot_body)
        R_dot, R_ddot = R @ W, R @ (W @ W + W_dot)
        x_ddot = F / m
        m_x_ddot_body = m * ((self.x - frame.a) @ R_ddot + 2.0 * (self.v - frame.a_dot) @ R_dot
                             + (x_ddot - frame.a_ddot) @ R)
        return ForceReport(real, inertial, m_x_ddot_body, m_x_ddot_body - (real + inertial.total))

    # ------------------------------------------------------------------ what the scene kit reads
    @property
    def angles_deg(self) -> list[float]:
        """C′'s z-x-z angles now [deg], θ in [0, 180], φ, ψ in (−180, 180]."""
        phi, theta, psi = (math.degrees(a) for a in self._motion.angles(self.t))
        return list(canonical_angles_deg(wrap_deg(phi), theta, wrap_deg(psi)))

    @property
    def rates_deg(self) -> list[float]:
        """C′'s Euler rates now [deg/s]."""
        return [math.degrees(r) for r in self._motion.angle_rates(self.t)]

