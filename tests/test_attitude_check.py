"""The attitude check of the plots (app.kit.rigid.simulation: the integrated attitude against the closed
form, worked out for ERROR_BATCH samples at once): each sample's error equals the angle of
R_exact(t)ᵀ R(t) evaluated alone for that sample, SciPy's Rotation measuring the angle."""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from app.kit.rigid.simulation import ERROR_BATCH, SAMPLE_COLUMNS, RigidBodySimulation, turn_angles
from physics.dynamics import Model, State

DT = 1.0 / 60.0


def _free_body() -> RigidBodySimulation:
    R = Rotation.from_euler("ZXZ", [0.3, 1.1, -0.4]).as_matrix()
    return RigidBodySimulation(Model(inertia=(1.0, 2.0, 3.0)), State(R, np.array([0.05, 4.0, 0.3]), 0.0))


def test_turn_angles_match_scipy_for_small_and_large_turns() -> None:
    rng = np.random.default_rng(7)
    R_a = Rotation.random(40, random_state=1).as_matrix()
    angles = np.concatenate([10.0 ** rng.uniform(-15, -1, 20), rng.uniform(0.1, math.pi - 1e-3, 20)])
    turns = Rotation.from_rotvec(angles[:, None] * Rotation.random(40, random_state=2).as_rotvec()
                                 / np.linalg.norm(Rotation.random(40, random_state=2).as_rotvec(), axis=1)[:, None])
    R_b = R_a @ turns.as_matrix()
    reference = Rotation.from_matrix(np.swapaxes(R_a, 1, 2) @ R_b).magnitude()
    np.testing.assert_allclose(turn_angles(R_a, R_b), reference, rtol=1e-9, atol=4e-16)  # rounding of R_aᵀ R_b


def test_each_sample_gets_the_error_of_its_own_moment_and_the_maximum_follows() -> None:
    sim = _free_body()
    expected: dict[int, float] = {}  # sample number -> the error evaluated alone, at its moment
    for _ in range(20 * ERROR_BATCH + 2):  # with the restart's (number 0): 103 samples, 3 in the open batch
        for _ in range(6):
            sim.advance(DT)
        R_exact = sim.exact_attitude()
        assert R_exact is not None
        expected[sim.samples.mark()] = Rotation.from_matrix(R_exact.T @ sim.state.R_space_body).magnitude()
        sim.take_sample()
    rows = sim.samples.ordered()
    column = 1 + SAMPLE_COLUMNS.index("attitude_error")
    numbers = range(sim.samples.mark() - len(rows), sim.samples.mark())
    opened = sim.samples.mark() - sim.samples.mark() % ERROR_BATCH
    checked = [n for n in numbers if n in expected and n < opened]
    assert len(checked) == 20 * ERROR_BATCH - 1 and opened == sim.samples.mark() - 3
    for n, row in zip(numbers, rows):
        if n in checked:
            # The same closed form at the same time, in a batch or alone: equal to rounding.
            assert abs(row[column] - expected[n]) <= 1e-15 + 1e-9 * expected[n], n
    # The open batch (3 samples) is not checked yet (the accuracy text works out the error now).
    assert np.all(np.isnan(rows[-3:, column])) and not np.isnan(rows[-4, column])
    assert max(expected[n] for n in checked) > 1e-12  # a real error was measured
    assert math.isclose(sim.max_drift["attitude_error"], max(expected[n] for n in checked), rel_tol=1e-9)
