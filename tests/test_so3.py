"""Tests of physics.so3: hat/vee, exp, log, rot_x/rot_z, project_to_so3.

References are independent of the code under test: np.cross, scipy.linalg.expm,
scipy.spatial.transform.Rotation, scipy.linalg.polar and closed forms of the memo (1.7), (1.8).

Tolerances (absolute on matrices whose largest entry is 1, i.e. relative in the max norm):
* EXPM_TOL = 4e-15: scipy.linalg.expm itself is only accurate to about 2.3e-15 on hat(v) with
  |v| <= π (measured against 40-digit mpmath); exp_so3 measured 4.4e-16 against mpmath.
* SERIES_TOL = 2e-15: the term-by-term series (1.4) is accurate to about 4.4e-16 here.
* ROUNDTRIP_TOL = 2e-15: exp(log(R)) == R; measured worst 1.1e-15 (near π, 5 ulp of 1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.linalg import expm, polar
from scipy.spatial.transform import Rotation

from physics.so3 import (
    A1,
    A3,
    axis_angle_from_matrix,
    exp_series,
    exp_skew,
    exp_so3,
    hat,
    log_so3,
    project_to_so3,
    rot_x,
    rot_z,
    vee,
)

EPS = np.finfo(float).eps
EXPM_TOL = 4e-15
SERIES_TOL = 2e-15
ROUNDTRIP_TOL = 2e-15
MEMO_TOL = 2e-15  # (1.7), (1.8) on unit vectors

SETTINGS = settings(max_examples=150, deadline=None)

# --- strategies --------------------------------------------------------------------------

finite = st.floats(-10.0, 10.0, allow_subnormal=False)
vectors = st.tuples(finite, finite, finite).map(np.array)


@st.composite
def unit_frames(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """A uniformly random unit axis d and a unit u ⟂ d (spherical coordinates, no rejection)."""
    z = draw(st.floats(-1.0, 1.0))
    alpha = draw(st.floats(0.0, 2.0 * math.pi))
    beta = draw(st.floats(0.0, 2.0 * math.pi))
    s = math.sqrt(1.0 - z * z)
    d = np.array([s * math.cos(alpha), s * math.sin(alpha), z])
    e_polar = np.array([z * math.cos(alpha), z * math.sin(alpha), -s])  # unit, ⟂ d
    u = e_polar * math.cos(beta) + np.cross(d, e_polar) * math.sin(beta)
    return d, u


unit_axes = unit_frames().map(lambda frame: frame[0])


def log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Floats in [lo, hi], uniform in log10."""
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: min(max(10.0**e, lo), hi))


angles_full = log_uniform(1e-12, math.pi)  # 1e-12 .. π
angles_near_zero = log_uniform(1e-12, 1e-6)
offsets_from_pi = log_uniform(1e-12, 1e-6)  # angle = π - offset


def assert_max_close(actual: np.ndarray, expected: np.ndarray, tol: float) -> None:
    """max |actual - expected| <= tol * max(1, max |expected|)."""
    scale = max(1.0, float(np.max(np.abs(expected))))
    err = float(np.max(np.abs(np.asarray(actual) - np.asarray(expected))))
    assert err <= tol * scale, f"max error {err:.3g} > {tol:.3g} * {scale:.3g}"


def assert_rotation(R: np.ndarray, tol: float = 2e-15) -> None:
    assert R.shape == (3, 3)
    assert_max_close(R.T @ R, np.eye(3), tol)
    assert abs(np.linalg.det(R) - 1.0) <= 4 * tol


# --- hat / vee ---------------------------------------------------------------------------


def test_hat_hand_checked() -> None:
    np.testing.assert_array_equal(
        hat(np.array([1.0, 2.0, 3.0])), [[0.0, -3.0, 2.0], [3.0, 0.0, -1.0], [-2.0, 1.0, 0.0]]
    )
    np.testing.assert_array_equal(A1, hat(np.array([1.0, 0.0, 0.0])))
    np.testing.assert_array_equal(A3, hat(np.array([0.0, 0.0, 1.0])))
    # e_x × e_y = e_z
    np.testing.assert_array_equal(hat(np.array([1.0, 0.0, 0.0])) @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])


@SETTINGS
@given(vectors, vectors)
def test_hat_is_cross_product(a: np.ndarray, b: np.ndarray) -> None:
    # The two sums differ only in rounding order: a few ulp of max|a| max|b| (+ underflow).
    atol = 8 * EPS * float(np.max(np.abs(a)) * np.max(np.abs(b))) + 1e-300
    np.testing.assert_allclose(hat(a) @ b, np.cross(a, b), rtol=0, atol=atol)


@SETTINGS
@given(vectors)
def test_hat_is_skew_and_vee_inverts_it_exactly(v: np.ndarray) -> None:
    K = hat(v)
    np.testing.assert_array_equal(K, -K.T)
    np.testing.assert_array_equal(vee(K), v)


@SETTINGS
@given(st.lists(finite, min_size=9, max_size=9).map(lambda x: np.array(x).reshape(3, 3)))
def test_vee_takes_the_skew_part(M: np.ndarray) -> None:
    skew = 0.5 * (M - M.T)
    np.testing.assert_allclose(vee(M), [skew[2, 1], skew[0, 2], skew[1, 0]], rtol=0, atol=1e-14)


# --- exp ---------------------------------------------------------------------------------


@SETTINGS
@given(angles_full, unit_axes)
@example(math.pi, np.array([0.0, 0.0, 1.0]))
@example(1e-12, np.array([1.0, 0.0, 0.0]))
@example(1e-4, np.array([0.0, 0.6, 0.8]))  # the Taylor-branch threshold of exp_so3
def test_exp_matches_expm_and_series(angle: float, axis: np.ndarray) -> None:
    v = angle * axis
    reference = expm(hat(v))
    R = exp_so3(v)
    assert_max_close(R, reference, EXPM_TOL)
    assert_max_close(exp_skew(hat(v)), reference, EXPM_TOL)
    assert_max_close(R, exp_series(hat(v)), SERIES_TOL)
    assert_rotation(R)


@SETTINGS
@given(angles_full, unit_axes)
def test_exp_skew_part_is_sin_angle_times_axis(angle: float, axis: np.ndarray) -> None:
    """vee(exp(Φ hat(d))) = sin Φ d, checked *relatively*, so the small-angle branch of
    exp_so3 cannot hide an error below the 1e-15 absolute level of the other tests."""
    R = exp_so3(angle * axis)
    np.testing.assert_allclose(vee(R), math.sin(angle) * axis, rtol=4e-15, atol=4 * EPS)


def test_exp_at_zero_is_exactly_identity() -> None:
    np.testing.assert_array_equal(exp_so3(np.zeros(3)), np.eye(3))
    np.testing.assert_array_equal(exp_skew(np.zeros((3, 3))), np.eye(3))
    np.testing.assert_array_equal(exp_series(np.zeros((3, 3))), np.eye(3))


def test_exp_hand_checked_quarter_turn() -> None:
    R = exp_so3(np.array([0.0, 0.0, 0.5 * math.pi]))
    np.testing.assert_allclose(R, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], rtol=0, atol=EPS)
    np.testing.assert_allclose(R @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], rtol=0, atol=EPS)


@SETTINGS
@given(angles_full, unit_frames())
@example(0.0, (np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])))
@example(math.pi, (np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])))
def test_exp_memo_1_7_and_1_8(angle: float, frame: tuple[np.ndarray, np.ndarray]) -> None:
    """(1.8) exp(A) d = d; (1.7) exp(A) u = u cos Φ + (d × u) sin Φ for a unit u ⟂ d."""
    d, u = frame
    R = exp_so3(angle * d)
    assert_max_close(R @ d, d, MEMO_TOL)
    assert_max_close(R @ u, u * math.cos(angle) + np.cross(d, u) * math.sin(angle), MEMO_TOL)


def test_exp_series_is_the_memo_definition_on_a_non_skew_matrix() -> None:
    M = np.array([[0.1, 0.2, 0.0], [-0.3, 0.05, 0.4], [0.2, 0.0, -0.1]])
    assert_max_close(exp_series(M), expm(M), 4e-15)


# --- rot_x / rot_z -----------------------------------------------------------------------


@SETTINGS
@given(st.floats(-math.pi, math.pi), st.integers(-3, 3))
def test_rot_x_and_rot_z_are_exponentials_of_A1_A3(angle: float, turns: int) -> None:
    # expm is compared on [-π, π] only: it loses digits for larger norms (3.7e-14 at 4 rad).
    assert_max_close(rot_x(angle), expm(angle * A1), EXPM_TOL)
    assert_max_close(rot_z(angle), expm(angle * A3), EXPM_TOL)
    big = angle + 2.0 * math.pi * turns
    assert_max_close(rot_x(big), Rotation.from_euler("x", big).as_matrix(), 1e-15)
    assert_max_close(rot_z(big), Rotation.from_euler("z", big).as_matrix(), 1e-15)


def test_rot_z_quarter_turn_maps_x_to_y() -> None:
    np.testing.assert_allclose(rot_z(0.5 * math.pi) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-16)
    np.testing.assert_allclose(rot_x(0.5 * math.pi) @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], atol=1e-16)


# --- log / axis-angle --------------------------------------------------------------------


def _check_log(R: np.ndarray) -> tuple[np.ndarray, float]:
    """Round trip and scipy's angle; returns (axis, angle)."""
    axis, angle = axis_angle_from_matrix(R)
    assert 0.0 <= angle <= math.pi
    assert abs(np.linalg.norm(axis) - 1.0) <= 4 * EPS
    np.testing.assert_array_equal(log_so3(R), angle * axis)
    assert_max_close(exp_so3(log_so3(R)), R, ROUNDTRIP_TOL)
    # scipy's angle (from its quaternion), to 4 ulp of the angle: relative also near 0.
    assert abs(angle - Rotation.from_matrix(R).magnitude()) <= 4 * EPS * angle
    return axis, angle


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_log_round_trip_random_rotations(seed: int) -> None:
    R = Rotation.random(random_state=seed).as_matrix()
    _check_log(R)


@SETTINGS
@given(angles_near_zero, unit_axes)
def test_log_near_zero_angle_is_relatively_accurate(angle: float, axis: np.ndarray) -> None:
    R = Rotation.from_rotvec(angle * axis).as_matrix()
    d, phi = _check_log(R)
    # Relative accuracy of the angle, against scipy and against the generating angle.
    assert abs(phi - Rotation.from_matrix(R).magnitude()) <= 4 * EPS * angle
    assert abs(phi - angle) <= 4 * EPS * angle
    np.testing.assert_allclose(d, axis, rtol=0, atol=1e-9 if angle < 1e-7 else 1e-12)


@SETTINGS
@given(offsets_from_pi, unit_axes)
def test_log_near_pi(offset: float, axis: np.ndarray) -> None:
    angle = math.pi - offset
    R = Rotation.from_rotvec(angle * axis).as_matrix()
    d, phi = _check_log(R)
    assert abs(phi - angle) <= 4 * EPS
    # Below π the axis sign is determined: it is +axis, not -axis.
    assert float(d @ axis) > 1.0 - 1e-12


@pytest.mark.parametrize(
    "R",
    [
        np.diag([1.0, -1.0, -1.0]),
        np.diag([-1.0, 1.0, -1.0]),
        np.diag([-1.0, -1.0, 1.0]),
        rot_x(math.pi),
        rot_z(math.pi),
        Rotation.from_rotvec(math.pi * np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)).as_matrix(),
        Rotation.from_rotvec(math.pi * np.array([-1.0, 1.0, 1.0]) / math.sqrt(3.0)).as_matrix(),
    ],
    ids=[
        "diag(1,-1,-1)", "diag(-1,1,-1)", "diag(-1,-1,1)", "rot_x(pi)", "rot_z(pi)",
        "rotvec(pi*123)", "rotvec(pi*-111)",
    ],  # fmt: skip
)
def test_log_exactly_pi(R: np.ndarray) -> None:
    d, phi = _check_log(R)
    assert abs(phi - math.pi) <= 4 * EPS
    # d is the axis: R d = d, and R is a half turn: R = 2 d dᵀ - 1.
    assert_max_close(R @ d, d, 2e-15)
    assert_max_close(R, 2.0 * np.outer(d, d) - np.eye(3), 2e-15)


def test_log_exactly_pi_branch_picks_positive_largest_component() -> None:
    for k in range(3):
        R = -np.eye(3)
        R[k, k] = 1.0
        d, phi = axis_angle_from_matrix(R)
        assert phi == math.pi
        np.testing.assert_array_equal(d, np.eye(3)[k])


def test_log_of_identity_is_exactly_zero() -> None:
    d, phi = axis_angle_from_matrix(np.eye(3))
    assert phi == 0.0
    np.testing.assert_array_equal(d, [0.0, 0.0, 1.0])  # documented branch
    np.testing.assert_array_equal(log_so3(np.eye(3)), np.zeros(3))


def test_bare_arccos_fails_near_zero_and_pi_but_ours_does_not() -> None:
    """The memo's (1.1) Φ = arccos((tr R - 1)/2) loses all digits near 0 and half of them
    near π; axis_angle_from_matrix stays at rounding level (relative near 0)."""
    d = np.array([2.0, -1.0, 2.0]) / 3.0
    for angle in (1e-9, 1e-7):
        R = Rotation.from_rotvec(angle * d).as_matrix()
        bare = math.acos(min(1.0, 0.5 * (np.trace(R) - 1.0)))
        assert abs(bare - angle) > 1e-3 * angle  # the motivation: >= 0.1 % wrong
        _, ours = axis_angle_from_matrix(R)
        assert abs(ours - angle) <= 4 * EPS * angle
    angle = math.pi - 1e-9
    R = Rotation.from_rotvec(angle * d).as_matrix()
    bare = math.acos(max(-1.0, 0.5 * (np.trace(R) - 1.0)))
    assert abs(bare - angle) > 1e-10
    _, ours = axis_angle_from_matrix(R)
    assert abs(ours - angle) <= 4 * EPS


# --- project_to_so3 ----------------------------------------------------------------------


@SETTINGS
@given(st.integers(0, 2**32 - 1), st.floats(1e-12, 1e-2))
def test_project_to_so3_is_the_polar_factor(seed: int, noise: float) -> None:
    rng = np.random.default_rng(seed)
    R = Rotation.random(random_state=rng).as_matrix()
    M = R + noise * rng.standard_normal((3, 3))
    P = project_to_so3(M)
    assert_rotation(P, tol=4e-15)  # as orthogonal as numpy's SVD makes it (measured 2.3e-15)
    U, _ = polar(M)  # nearest orthogonal matrix; a rotation since M is near R
    assert_max_close(P, U, 1e-14)


def test_project_to_so3_of_a_reflection_is_a_rotation_no_farther_than_neighbours() -> None:
    M = np.diag([1.0, 2.0, -3.0])  # det < 0: polar factor is not a rotation
    P = project_to_so3(M)
    assert_rotation(P, tol=4e-15)
    best = np.linalg.norm(P - M)
    rng = np.random.default_rng(0)
    for _ in range(200):
        Q = exp_so3(1e-3 * rng.standard_normal(3)) @ P
        assert np.linalg.norm(Q - M) >= best - 1e-12
    # the closed form: flip the axis of the smallest singular value
    assert_max_close(P, np.diag([-1.0, 1.0, -1.0]), 1e-15)
