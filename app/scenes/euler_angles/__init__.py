"""The z-x-z Euler-angle explorer ("Euler angles" scene): D = Rz(φ) Rx(θ) Rz(ψ), its
intermediate frames, the angular velocity ω = φ̇ e_z + θ̇ e_n + ψ̇ e_z′ head to tail, and D as a
single rotation exp(Φ hat(d)) (memo 1.1-1.3, 1.17).

- `simulation`: the angles advancing at constant rates, and the box drawn (no viser);
- `readouts`: the panel's texts as pure functions of numbers (no viser);
- `single_rotation`: the single rotation's nodes, folder, readout and animation;
- `view`: `EulerAnglesView`, the scene (nodes, panel, drawing).

The names other modules and the tests use are re-exported here.
"""

from __future__ import annotations

from app.kit.core.common import canonical_angles_deg
from app.scenes.euler_angles.simulation import INITIAL_ANGLES_DEG, EulerAnglesSimulation
from app.scenes.euler_angles.single_rotation import (
    ANIMATION_HOLD,
    ANIMATION_SECONDS,
    ARC_SEGMENTS,
    SINGLE_ARC_RADIUS,
    arc_reference_axis,
    box_outline_segments,
)
from app.scenes.euler_angles.view import (
    ANGLE_SPECS,
    INITIAL_CAMERA,
    INITIAL_FOV_DEG,
    RATE_ARROW_SCALE,
    SLIDER_PERIOD,
    THETA_REACH,
    VIEW,
    EulerAnglesView,
)

__all__ = [
    "ANGLE_SPECS",
    "ANIMATION_HOLD",
    "ANIMATION_SECONDS",
    "ARC_SEGMENTS",
    "INITIAL_ANGLES_DEG",
    "INITIAL_CAMERA",
    "INITIAL_FOV_DEG",
    "RATE_ARROW_SCALE",
    "SINGLE_ARC_RADIUS",
    "SLIDER_PERIOD",
    "THETA_REACH",
    "VIEW",
    "EulerAnglesSimulation",
    "EulerAnglesView",
    "arc_reference_axis",
    "box_outline_segments",
    "canonical_angles_deg",
]
