"""The Euler-angles scene's simulation (no viser): z-x-z angles advancing at constant rates, and
the box drawn for the principal moments.

The angles (φ, θ, ψ) [deg] grow linearly at the rates (φ̇, θ̇, ψ̇) [deg/s]; a θ outside
[0°, 180°] is shown as the equivalent (φ + 180°, 360° − θ, ψ + 180°) (`canonical_angles_deg`),
so the sliders wrap.  D = Rz(φ) Rx(θ) Rz(ψ) (`physics.euler`, docs/CONVENTIONS.md "Euler
angles"); degrees in the simulation's attributes, radians from `angles` on.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence

import numpy as np

from app.kit.core.common import canonical_angles_deg, wrap_deg
from app.kit.core.history import Snapshot
from physics.euler import euler_frames
from physics.inertia import box_extents_from_moments, validate_principal_moments

__all__ = ["BODY_SIZE", "GREEK", "INITIAL_ANGLES_DEG", "INITIAL_MOMENTS", "KEYS", "MIN_EDGE",
           "EulerAnglesSimulation", "box_edges"]

INITIAL_ANGLES_DEG = (30.0, 50.0, 20.0)  # the first preset's pose
INITIAL_MOMENTS = (1.0, 2.0, 2.6)  # box with edges a : b : c = 3 : 2 : 1
KEYS = ("phi", "theta", "psi")  # the angles, in the order they are applied
GREEK = {"phi": "φ", "theta": "θ", "psi": "ψ"}
BODY_SIZE = 1.25  # display length [scene units] of the body's longest edge
MIN_EDGE = 0.02  # display thickness of a flat body (a lamina: I1 + I2 = I3)


class EulerAnglesSimulation:
    """Angles advancing at constant Euler rates (no viser).

    Attributes:
        angles_deg: [φ, θ, ψ] [deg] in the principal ranges (what the sliders show).
        rates_deg: [φ̇, θ̇, ψ̇] [deg/s].  moments: (I1, I2, I3) [kg m²] of the box drawn.
        t: seconds played since the angles were last set.  version: bumped on every change.
        run: bumped at every reset (the replay's history starts afresh).
    """

    def __init__(self, angles_deg: Sequence[float], rates_deg: Sequence[float],
                 moments: Sequence[float] = INITIAL_MOMENTS) -> None:
        self.rates_deg = [float(r) for r in rates_deg]
        self.moments = tuple(float(m) for m in validate_principal_moments(moments))
        self.preset: str | None = None
        self.version = 0
        self.run = 0
        self.set_angles(angles_deg)

    def set_angles(self, angles_deg: Sequence[float]) -> None:
        """Set (φ, θ, ψ) [deg]: playing and Reset start from here (t = 0)."""
        self._initial_deg = np.array(angles_deg, dtype=float)
        self.reset()

    def set_rates(self, rates_deg: Sequence[float]) -> None:
        self.rates_deg = [float(r) for r in rates_deg]
        self.version += 1

    def set_moments(self, moments: Sequence[float]) -> None:
        """InertiaError (nothing changes) if the moments are not a body."""
        self.moments = tuple(float(m) for m in validate_principal_moments(moments))
        self.version += 1

    def reset(self) -> None:
        self._played_deg = self._initial_deg.copy()
        self.run += 1
        self.t = 0.0
        self.angles_deg = list(canonical_angles_deg(*self._played_deg))
        self.version += 1

    def advance(self, dt: float) -> None:
        played = self._played_deg + np.array(self.rates_deg) * dt
        played[[0, 2]] = [wrap_deg(a) for a in played[[0, 2]]]
        played[1] %= 360.0
        self._played_deg = played
        self.t += dt
        self.angles_deg = list(canonical_angles_deg(*played))
        self.version += 1

    # ------------------------------------------------------------------ replay (app.kit.core.history)
    def snapshot(self) -> Snapshot:
        """The moment now: t, the angles as played (3) [deg], the rates (3) [deg/s] (the angles
        shown are a function of those played)."""
        values = [self.t, *self._played_deg.tolist(), *self.rates_deg]
        return Snapshot(np.array(values, dtype=float))

    def restore(self, snapshot: Snapshot, later: float = 0.0) -> None:
        """The recorded moment back bit for bit (then `later` [s] on, for display)."""
        v = snapshot.values
        if v.shape != (7,):
            raise ValueError("this snapshot is not an Euler-angles moment")
        self.t = float(v[0])
        self._played_deg = v[1:4].copy()
        self.angles_deg = list(canonical_angles_deg(*self._played_deg))
        self.rates_deg = [float(r) for r in v[4:7]]
        if later > 0.0:
            self.advance(later)
        self.version += 1

    def truncate(self) -> None:
        """No history to cut (the scene keeps none)."""

    def fork(self) -> EulerAnglesSimulation:
        """An exact, independent copy: angles (as played and as shown), rates, moments, t, the
        angles Reset goes back to, preset and version (a deep copy: a few small arrays)."""
        return copy.deepcopy(self)

    @property
    def angles(self) -> tuple[float, float, float]:
        """(φ, θ, ψ) [rad]."""
        phi, theta, psi = (math.radians(a) for a in self.angles_deg)
        return phi, theta, psi

    @property
    def R_space_body(self) -> np.ndarray:
        return euler_frames(*self.angles).body


def box_edges(moments: Sequence[float]) -> np.ndarray:
    """The drawn box's edges (3,) [scene units] along x′ y′ z′: the uniform box of these
    principal moments [kg m²], scaled so the longest edge is BODY_SIZE (a flat lamina is drawn
    MIN_EDGE thick)."""
    edges = np.asarray(box_extents_from_moments(moments, mass=1.0), dtype=float)
    return np.maximum(BODY_SIZE * edges / edges.max(), MIN_EDGE)
