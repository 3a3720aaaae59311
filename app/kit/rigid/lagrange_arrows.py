"""The Lagrange tab's drawing for the rigid-body scenes: the torque M and its projections
Q_φ e_z, Q_θ e_n, Q_ψ e_z′ (memo 6.10) as arrows from the pivot, head to tail, so that the three
projections add up to what the generalized forces say about M."""

from __future__ import annotations

from typing import Any

import numpy as np

from app.kit.draw.labels import DETAIL, LabelLayer
from app.kit.draw.widgets import Vector
from physics.euler import body_z_axis, line_of_nodes
from physics.lagrange import LagrangeTerms

__all__ = ["GeneralizedForceArrows"]

LENGTH = 1.2  # [scene units] of M's arrow (the projections in the same scale)
ARROWS = (("M", (60, 60, 60), "M"), ("phi", (140, 50, 210), "Q_φ e_z"), ("theta", (215, 0, 120), "Q_θ e_n"),
          ("psi", (0, 140, 140), "Q_ψ e_z′"))


class GeneralizedForceArrows:
    """Four arrows under `{root}/lagrange`, hidden until the Lagrange tab shows them."""

    def __init__(self, scene: Any, root: str, labels: LabelLayer | None = None) -> None:
        self.vectors = {
            key: Vector(scene, f"{root}/lagrange/{key}", color, label, shaft_radius=0.02, head_radius=0.06,
                        head_length=0.12, font_scale=1.6, label_at_middle=key != "M", labels=labels, priority=DETAIL)
            for key, color, label in ARROWS
        }
        self.show(False)

    def show(self, on: bool) -> None:
        """Shown on the Lagrange tab only; hidden arrows send a message only if they were shown."""
        for vector in self.vectors.values():
            vector.enabled = bool(on)
            if not on:
                vector.update(np.zeros(3))

    def draw(self, torque_space: np.ndarray, terms: LagrangeTerms | None) -> None:
        """M [N m] (space components) and Q_φ e_z, Q_θ e_n, Q_ψ e_z′ at the angles of `terms`
        (none drawn where the terms are undefined: θ at a pole)."""
        if terms is None:
            for vector in self.vectors.values():
                vector.update(np.zeros(3))
            return
        torque = np.asarray(torque_space, dtype=float)
        scale = LENGTH / max(float(np.linalg.norm(torque)), 1e-300) if np.any(torque) else 0.0
        phi, theta = float(terms.q[0]), float(terms.q[1])
        axes = (np.array([0.0, 0.0, 1.0]), line_of_nodes(phi), body_z_axis(phi, theta))
        self.vectors["M"].update(torque * scale)
        start = np.zeros(3)
        for key, Q, axis in zip(("phi", "theta", "psi"), terms.Q, axes):
            self.vectors[key].update(Q * scale * axis, start=start)
            start = start + Q * scale * axis
