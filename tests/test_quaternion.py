"""physics.quaternion against SciPy's Rotation (as_quat(scalar_first=True): the same order,
the same rotation, and the canonical sign w >= 0)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from physics.quaternion import (
    matrices_from_wxyz,
    matrix_from_wxyz,
    row_major_from_wxyz,
    wxyz_from_matrices,
    wxyz_from_matrix,
    wxyz_from_row_major,
)
from physics.so3 import rot_x

quaternions = st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(lambda q: np.linalg.norm(q) > 1e-3)

HALF_TURNS_AND_IDENTITY = [
    np.eye(3), rot_x(math.pi), np.diag([-1.0, -1.0, 1.0]), np.diag([-1.0, 1.0, -1.0]),
    Rotation.from_rotvec(math.pi * np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)).as_matrix(),
]  # fmt: skip


def same_rotation_sign(q: np.ndarray, expected: np.ndarray) -> None:
    """q equals the canonical scipy quaternion (w >= 0); at w == 0 q and -q both qualify."""
    if abs(expected[0]) < 1e-12:
        assert abs(abs(float(np.dot(q, expected))) - 1.0) < 1e-13
    else:
        np.testing.assert_allclose(q, expected, atol=1e-14)


@settings(max_examples=200, deadline=None)
@given(quaternions)
def test_round_trip_matches_scipy(q: list[float]) -> None:
    qn = np.array(q) / np.linalg.norm(q)
    R_expected = Rotation.from_quat(qn, scalar_first=True).as_matrix()
    np.testing.assert_allclose(np.array(row_major_from_wxyz(*q)).reshape(3, 3), R_expected, atol=1e-14)
    np.testing.assert_allclose(matrix_from_wxyz(q), R_expected, atol=1e-14)
    expected = Rotation.from_matrix(R_expected).as_quat(canonical=True, scalar_first=True)
    for ours in (wxyz_from_matrix(R_expected), wxyz_from_row_major(R_expected.ravel().tolist())):
        assert all(type(c) is float for c in ours)
        assert ours[0] >= 0.0
        assert abs(math.fsum(c * c for c in ours) - 1.0) <= 1e-15
        same_rotation_sign(np.array(ours), expected)


@pytest.mark.parametrize("R", HALF_TURNS_AND_IDENTITY)
def test_identity_and_half_turns(R: np.ndarray) -> None:
    q = wxyz_from_matrix(R)
    assert q[0] >= 0.0
    np.testing.assert_allclose(matrix_from_wxyz(q), R, atol=1e-15)
    same_rotation_sign(np.array(q), Rotation.from_matrix(R).as_quat(canonical=True, scalar_first=True))


def test_nested_lists_and_unnormalised_input() -> None:
    R = Rotation.from_euler("ZXZ", [0.3, 2.9, -1.2]).as_matrix()
    assert wxyz_from_matrix(R.tolist()) == wxyz_from_matrix(R)
    q = np.array(wxyz_from_matrix(R))
    np.testing.assert_allclose(matrix_from_wxyz(3.0 * q), R, atol=1e-15)  # normalised first


def test_vectorised_variants_match_the_scalar_ones() -> None:
    rotations = Rotation.random(200, random_state=7)
    R = np.concatenate([rotations.as_matrix(), np.array(HALF_TURNS_AND_IDENTITY)])
    q = wxyz_from_matrices(R)
    assert q.shape == (len(R), 4)
    assert np.all(q[:, 0] >= 0.0)
    for Rk, qk in zip(R, q):
        np.testing.assert_allclose(qk, wxyz_from_matrix(Rk), atol=2e-16)
    np.testing.assert_allclose(matrices_from_wxyz(q), R, atol=1e-15)
    np.testing.assert_allclose(
        matrices_from_wxyz(q[:200]), Rotation.from_quat(q[:200], scalar_first=True).as_matrix(), atol=1e-15
    )
    grid = q[:12].reshape(3, 4, 4)  # any leading shape
    assert matrices_from_wxyz(grid).shape == (3, 4, 3, 3)
    assert wxyz_from_matrices(R[:12].reshape(3, 4, 3, 3)).shape == (3, 4, 4)
