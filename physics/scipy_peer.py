"""The peer a user would pick: scipy.integrate.solve_ivp(method="DOP853") on the quaternion ODE.

`integrate_dop853` integrates the same y = (q, ω_b) with the same float-level right-hand side
(`physics.quaternion_ode`) as `physics.dop853.integrate_adaptive`, so the two take the same
steps; it is there to compare against.  The right-hand side raises IntegrationError on a
non-finite state or a blow-up, because solve_ivp itself keeps shrinking the step on NaN (scipy
issues 11239 and 17846) instead of stopping.
"""

from __future__ import annotations

import math
import time

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from physics._types import Array
from physics.dynamics import IntegrationError, Model, State, Trajectory
from physics.guards import omega_limit, rate_scale_function, validated_state, validated_times, validated_tolerances
from physics.quaternion import matrices_from_wxyz, wxyz_from_row_major
from physics.quaternion_ode import quaternion_rhs

__all__ = ["integrate_dop853"]


def integrate_dop853(
    model: Model, state0: State, t_eval: ArrayLike, rtol: float = 1e-12, atol: float = 1e-14
) -> Trajectory:
    """The peer: scipy.integrate.solve_ivp(method="DOP853", t_eval=t_eval) on y = (q, ω_b).

    The same (fast, float-level) right-hand side as `integrate_adaptive`; R = R(q/|q|) at
    output.  Order 8, conserves nothing exactly.  The right-hand side raises IntegrationError
    on a non-finite state or a blow-up (as `integrate_adaptive`), because solve_ivp itself keeps shrinking the
    step on NaN (scipy issues 11239, 17846) instead of stopping.

    Returns:
        Trajectory with evaluations = solve_ivp's nfev, wall_s = seconds in solve_ivp.
    """
    r, w, t0 = validated_state(state0)
    times = validated_times(t_eval, t0)
    validated_tolerances(rtol, atol)
    rhs = quaternion_rhs(model)
    isfinite = math.isfinite
    limit = omega_limit(rate_scale_function(model)(r[8], w))

    def fun(t: float, y: Array) -> tuple[float, ...]:
        values = y.tolist()
        derivative = rhs(t, *values)
        w1, w2, w3 = values[4], values[5], values[6]
        if not isfinite(sum(derivative)):
            raise IntegrationError(f"non-finite state at t = {t:.9g} s: y = {values}")
        if w1 * w1 + w2 * w2 + w3 * w3 > limit * limit:
            raise IntegrationError(f"blow-up at t = {t:.9g} s: |omega| exceeds the limit {limit:.3g} rad/s")
        return derivative

    start = time.perf_counter()
    y0 = np.array([*wxyz_from_row_major(r), *w])
    if times[-1] == t0:
        ys = np.repeat(y0[:, None], times.size, axis=1)
        evaluations = 0
    else:
        sol = solve_ivp(fun, (t0, float(times[-1])), y0, method="DOP853", t_eval=times, rtol=rtol, atol=atol)
        if sol.status != 0:
            raise IntegrationError(f"solve_ivp (DOP853) failed by t = {sol.t[-1]:.9g} s: {sol.message}")
        ys = sol.y
        evaluations = int(sol.nfev)
    R = matrices_from_wxyz(ys[:4].T)
    omega_body = ys[4:].T.copy()
    wall = time.perf_counter() - start
    return Trajectory(times, R, omega_body, evaluations, wall, "dop853")
