"""A frame C′ moving in the inertial frame C, and particles seen from both ("Moving frame" scene).

What it shows (memo §4, (1.28); docs/CONVENTIONS.md, "Moving frames"): C′ has its origin at
a(t) and attitude D(t) = Rz(φ) Rx(θ) Rz(ψ) with z-x-z angles quadratic in time, its origin on a
straight line plus a point fixed in C′ (`physics.moving_frames.FrameMotion`): a turntable at a
constant rate or speeding up, a cart accelerating along a line, a patch of the turning Earth,
a frame fixed to a precessing top.  Three particles of mass m live in it:

- **free**: no force at all (on a table, gravity and the normal force cancel and are not drawn);
  it is slid across C′ with a velocity given relative to C′, until the disc's rim stops it;
- **at rest in C′**: held at a fixed x′ by a real force F = m ẍ, ẍ the acceleration of that
  point of C′ (`acceleration_space` with ẋ′ = ẍ′ = 0); it is integrated like the others, so
  that it *stays* at rest is a check, not an assumption;
- **on a spring**: F = −k (x − anchor), the anchor a point fixed in C′.

The particles are integrated in C, where Newton's law is m ẍ = F (`rk4_step`: classical RK4
with steps of at most H_MAX = 1/240 s of simulated time, sub-stepping the frame; global error
O(h⁴): over 10 s the spring particle stays within 3e-8 m of scipy's DOP853 at rtol 1e-12
(1.1e-8 m measured on the top frame, ~5e-10 m on the others), the particle at rest in C′ stays
within 1e-8 m of its place, and the free particle is exact to rounding;
tests/test_moving_frame_scene.py).  Their C′
coordinates x′ = Dᵀ(x − a), ẋ′ = Dᵀ(ẋ − ȧ) − ω_b × x′ follow.  On the chosen particle the
real force Dᵀ F and the four inertial forces of (4.5, 4.6) are drawn as labelled arrows, in
body components, from `physics.moving_frames.inertial_force_body`: translational −m Dᵀä,
Euler −m ω̇_b × x′, centrifugal −m ω_b × (ω_b × x′), Coriolis −2m ω_b × ẋ′.  The readout
compares their sum with m ẍ′ obtained another way, by differentiating x′ = Dᵀ(x − a) with
Ḋ = D hat(ω_b), D̈ = D (hat(ω_b)² + hat(ω̇_b)) (no cross-product formula of (1.28)): the
residual is at rounding level.

Paths: each particle leaves a path in C (drawn in C: a straight line for the free particle)
and one in C′ (drawn in C′, carried by it: the curve a rider sees), the last PATH_SECONDS kept
by the simulation (`app.kit.core.trace.Trace`, so a view built later shows them so far) and drawn
in short chunks (`app.kit.draw.widgets.TraceLines`: a chunk of 3 segments every 0.2 s, its head resent
at most at 10 Hz while playing).

In the picture for the first minute of every preset (tests/test_in_the_picture.py: desktop,
projector, phone follower, the panel's rectangle): the camera is the inertial frame's and stays
where the scene's view puts it.  Chosen over a camera that follows C′ because a moving camera is
itself a moving frame: the inertial view is the reference the rider's view ("Ride with C′") is
compared with, and "at rest in C" must look at rest on screen.  So the motion is made to fit the
stage instead: C′'s origin moves at most 2 m (the accelerating line runs along −x, away from the
panel), a turntable that speeds up does so for `spin_up` seconds and then holds its speed (no
unbounded ω, forces or spring runaway), and the free particle, a puck on the disc, is stopped by
the disc's rim (|x′| = disc radius) and carried by it (`MovingFrameSimulation`): a straight line
in C until then, and the real force that holds it from then on is drawn.

Presets: `assets/presets/moving_frame.json` (every parameter of `simulation.PARAM_SPECS`, the frame's initial
angles; Earth's ω is exaggerated and the note says by how much).  Parameter edits restart the
run at t = 0 (the initial conditions are given at t = 0); display parameters do not.

The package: `simulation` (the setup and the run, no viser), `readouts` (the status line and
the readout as pure functions of the simulation), `view` (`MovingFrameView`: the nodes, the
panel, what a frame sends).
"""

from __future__ import annotations

from app.scenes.moving_frame.readouts import EARTH_OMEGA, readout_text, status_text
from app.scenes.moving_frame.simulation import (
    ANGLE_SPECS,
    DISPLAY_KEYS,
    H_MAX,
    KEYS,
    PARAM_SPECS,
    PARTICLES,
    ForceReport,
    MovingFrameSetup,
    MovingFrameSimulation,
)
from app.scenes.moving_frame.view import MovingFrameView

__all__ = [
    "ANGLE_SPECS",
    "DISPLAY_KEYS",
    "EARTH_OMEGA",
    "H_MAX",
    "KEYS",
    "PARAM_SPECS",
    "PARTICLES",
    "ForceReport",
    "MovingFrameSetup",
    "MovingFrameSimulation",
    "MovingFrameView",
    "readout_text",
    "status_text",
]
