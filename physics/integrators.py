"""The singularity-free integrators of the rigid body, in one namespace (a public API).

No Euler angles anywhere: the state is (R_space_body, ω_b), integrated as a unit quaternion
and L_b or ω_b (docs/CONVENTIONS.md, memo §6).  Each method lives in its own module:

* `physics.splitting`: `integrate_splitting`, the symplectic splitting, fixed step, order 2,
  4, 6 (`COMPOSITIONS`, `STAGES`, `DEFAULT_STEP_ANGLE`); exact |L| (free body) and L·e_z (top).
* `physics.realtime`: `RealtimeStepper` and `step_realtime`, the app's frame-by-frame stepping
  (4th-order splitting with automatic sub-steps, `REALTIME_SUBSTEP_ANGLE`, `MAX_SUBSTEPS`).
* `physics.dop853`: `integrate_adaptive`, DOP853 unrolled into straight-line float code.
* `physics.scipy_peer`: `integrate_dop853`, scipy's solve_ivp(method="DOP853") on the same ODE.
* `physics.guards`: bad-input and blow-up checks (`OMEGA_LIMIT`, `OMEGA_GROWTH`) and
  `rate_scale`, the rate Ω the step sizes are measured against.

Every `integrate_*` takes (model, state0, t_eval) and returns a `Trajectory` counting
evaluations and wall time (time.perf_counter around the integration only).
"""

from __future__ import annotations

from physics.dop853 import integrate_adaptive
from physics.guards import OMEGA_GROWTH, OMEGA_LIMIT, ORTHOGONALITY_TOL, rate_scale
from physics.realtime import MAX_SUBSTEPS, REALTIME_SUBSTEP_ANGLE, RealtimeStepper, step_realtime
from physics.scipy_peer import integrate_dop853
from physics.splitting import CHECK_EVERY, COMPOSITIONS, DEFAULT_STEP_ANGLE, STAGES, integrate_splitting

__all__ = [
    "CHECK_EVERY",
    "COMPOSITIONS",
    "DEFAULT_STEP_ANGLE",
    "MAX_SUBSTEPS",
    "OMEGA_GROWTH",
    "OMEGA_LIMIT",
    "ORTHOGONALITY_TOL",
    "REALTIME_SUBSTEP_ANGLE",
    "STAGES",
    "RealtimeStepper",
    "integrate_adaptive",
    "integrate_dop853",
    "integrate_splitting",
    "rate_scale",
    "step_realtime",
]
