"""`physics.lagrange.lagrange_terms`: Lagrange's equations (5.13) term by term on a motion
computed without them (the closed-form solutions).  d/dt ∂T/∂q̇ is checked against central
differences of ∂T/∂q̇ = M q̇ along the motion, and the residual against Q is rounding."""

from __future__ import annotations

import numpy as np
import pytest

from physics.dynamics import Model, State
from physics.euler import euler_zxz_from_matrix, euler_zxz_from_matrix_near, matrix_from_euler_zxz
from physics.lagrange import lagrange_terms
from physics.methods import exact_solution

H = 2e-5  # [s] central-difference step: truncation ~h²|d³p/dt³|/6, rounding ~1e-16 |p|/h
CASES = {
    "heavy top": (Model(inertia=(1.0, 1.0, 0.5), mgl=6.0),
                  State(matrix_from_euler_zxz(0.0, 1.0, 0.0), np.array([0.3, 0.8, 12.0]), 0.0)),
    "free asymmetric": (Model(inertia=(0.3, 0.75, 1.0)),
                        State(matrix_from_euler_zxz(0.4, 1.1, -0.3), np.array([0.5, 3.0, 0.7]), 0.0)),
}


@pytest.mark.parametrize("case", list(CASES))
def test_lagrange_terms_agree_with_the_motion_and_balance(case: str) -> None:
    model, state0 = CASES[case]
    solution = exact_solution(model, state0)
    angles = euler_zxz_from_matrix(state0.R_space_body)
    for t in np.linspace(0.05, 2.0, 9):
        times = np.array([t - H, t, t + H])
        R, omega = solution(times)
        q = [euler_zxz_from_matrix_near(R[k], angles) for k in range(3)]
        angles = q[1]
        terms = [lagrange_terms(model, float(times[k]), R[k], omega[k], q[k]) for k in range(3)]
        middle = terms[1]
        scale = float(np.max(np.abs(middle.ddt_dT_dqdot)) + np.max(np.abs(middle.Q)) + 1.0)
        fd = (terms[2].dT_dqdot - terms[0].dT_dqdot) / (2.0 * H)  # d/dt ∂T/∂q̇ from the motion
        np.testing.assert_allclose(middle.ddt_dT_dqdot, fd, atol=1e-6 * scale)
        qddot_fd = (terms[2].qdot - terms[0].qdot) / (2.0 * H)
        np.testing.assert_allclose(middle.qddot, qddot_fd, atol=1e-6 * (1.0 + np.max(np.abs(middle.qddot))))
        assert np.max(np.abs(middle.residual)) <= 1e-10 * scale, middle.residual  # rounding
        assert middle.T == pytest.approx(0.5 * float(np.dot(model.inertia, omega[1] ** 2)), rel=1e-14)
    if model.mgl:
        assert middle.Q[0] == pytest.approx(0.0, abs=1e-12) and middle.Q[2] == pytest.approx(0.0, abs=1e-12)
        assert middle.Q[1] == pytest.approx(model.mgl * np.sin(middle.q[1]), rel=1e-12)  # M·e_n = mgl sin θ
