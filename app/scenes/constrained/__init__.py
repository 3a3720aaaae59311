"""Particles held by constraints, in generalized coordinates ("Constrained particles" scene).

What it shows (memo §2 and §5): a system of N particles with m degrees of freedom, positions
x_i(q_1 … q_m, t) (2.1)/(5.1), given by nothing else than that function, the masses and the
applied forces (`physics.constrained`).  Per particle it draws

- the virtual displacements ∂x_i/∂q_j δq_j (5.6) (teal for q₁, violet for q₂; drawn for
  δq = DELTA_Q rad or m): the ways the constraints let the particle move *at frozen t*;
- the applied force F_i (black) and the constraint force C_i = m_i ẍ_i − F_i (red): on a
  smooth single-particle constraint C_i is perpendicular to every virtual displacement (5.7);

and reads out (Readout tab) the virtual work C_i · ∂x_i/∂q_j (per particle and summed: on the
double pendulum the middle rod pushes the two particles with equal and opposite forces that
do virtual work on each, none in total), the generalized forces Q_j (5.12), Lagrange's
equations (5.13) term by term and their residual, T = T₂ + T₁ + T₀, V, and the conserved
quantity: the energy T + V when the constraints are fixed, Jacobi's integral h = T₂ − T₀ + V
when they move (the turning hoop and rod: the motor turning them does work, the energy changes;
the panel says so).

Presets (`assets/presets/constrained.json`): each names a system (`system`: hoop, spherical,
double, rod), its parameters and the initial q, q̇.  The Setup tab's sliders are the chosen
system's: its parameters (an edit keeps the state and restarts the run at t = 0) and its q, q̇
(setting the state, also from t = 0).  Bad values (lengths ≤ 0, NaN, a rate out of range, a bead
placed off its rod) are refused with a message and the state kept.

The simulation (`ConstrainedSimulation`, no viser) integrates with
`physics.constrained.GridIntegrator` (8th order, fixed grid of 1/120 s), keeps the plot samples
(q, h, T + V, the drift of h) and each particle's path (`app.kit.core.trace.Trace`), so a view built
later shows them; `fork()` is a deep copy; `snapshot` / `restore` / `truncate` give the replay
(`Timeline`, Replay, Resume, Branch here: `app.kit.core.history`).  Nothing in the 3D is interactive.

The package: `simulation` (the systems, the setup, the run and the presets, no viser), `readouts`
(the status line and the Readout tab as pure functions of the simulation), `view`
(`ConstrainedView`: the nodes, the panel, what a frame sends).
"""

from __future__ import annotations

from app.scenes.constrained.readouts import conserved_text, extra_line, readout_text, status_text
from app.scenes.constrained.simulation import (
    KINDS,
    ConstrainedSetup,
    ConstrainedSimulation,
    Kind,
    load_constrained_presets,
    setup_of,
)
from app.scenes.constrained.view import DELTA_Q, ConstrainedView

__all__ = [
    "DELTA_Q",
    "KINDS",
    "ConstrainedSetup",
    "ConstrainedSimulation",
    "ConstrainedView",
    "Kind",
    "conserved_text",
    "extra_line",
    "load_constrained_presets",
    "readout_text",
    "setup_of",
    "status_text",
]
