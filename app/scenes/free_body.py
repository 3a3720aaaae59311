"""The "Free body" scene: a torque-free rigid body (Euler's equations with M = 0).

Models only what it needs: `Model(inertia=(I1, I2, I3))`, no torque.  L_s = D I ω_b is fixed
in space (drawn violet), E = T is conserved, ω (orange) wanders in space and in the body.  The
body, its sliders and readout are `app.kit.rigid.torque_free.TorqueFreeView`'s (shared with Poinsot);
presets: `assets/presets/free_body.json`.  ω is also set by hand
(`app.kit.rigid.hand`): gizmos at the tips of ω and L while paused, and Kick about x′ y′ z′ (kick
about the largest, smallest and middle axes to see which spins are stable).
"""

from __future__ import annotations

from app.i18n import N_
from app.kit.core.common import CameraView
from app.kit.rigid.torque_free import TorqueFreeView

__all__ = ["FreeBodyView"]


class FreeBodyView(TorqueFreeView):
    """The free body (see the module docstring)."""

    title = N_("Free body")  # the scene dropdown shows it translated (app.i18n)
    root = "/free"
    view = CameraView(position=(4.6, -3.9, 2.5), look_at=(0.25, 0.55, 0.1))
    intro = N_(
        "### Free body (no torque)\n"
        "I ω̇_b + ω_b × (I ω_b) = 0.  **L = D I ω_b** is fixed in space, **E = T** is conserved.  "
        "SI units; angles in degrees (z-x-z)."
    )
    preset_file = "free_body.json"
