"""D as one turn, D = exp(A), A = Φ hat(d) (memo 1.1-1.3): physics.so3.single_rotation.

References are independent of the code under test: SciPy's `Rotation.as_rotvec`, `as_quat`,
`magnitude` and `scipy.linalg.expm`.

Tolerances (absolute on matrices and vectors whose entries are at most π):
* ROTVEC_TOL = 4e-15: rotation vectors against SciPy's, a few ulp of π (measured 1.8e-15).
* EXPM_TOL = 4e-15: scipy.linalg.expm is itself accurate to ~2.3e-15 on hat(v), |v| <= π.
* Within HALF_TURN_BAND of π the sign of d is a choice, not a datum: there exp(Φ hat(d)) may
  differ from D by up to 2 sin Φ (the documented price of a sign that does not flicker).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from physics.so3 import (
    AXIS_UNDEFINED_ANGLE,
    HALF_TURN_BAND,
    exp_so3,
    hat,
    rot_x,
    rot_z,
    single_rotation,
    turn_path,
)

ROTVEC_TOL = 4e-15
EXPM_TOL = 4e-15
RNG_SEED = 17


def random_axes(n: int, seed: int = RNG_SEED) -> np.ndarray:
    v = np.random.default_rng(seed).standard_normal((n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def check_against_scipy(D: np.ndarray) -> None:
    """(1.1)-(1.3) against SciPy, away from the half turn."""
    ours = single_rotation(D)
    reference = Rotation.from_matrix(D)
    assert 0.0 <= ours.angle <= math.pi
    assert abs(ours.angle - reference.magnitude()) <= 4 * np.finfo(float).eps * max(ours.angle, 1e-300) + 1e-300
    np.testing.assert_allclose(ours.rotvec, reference.as_rotvec(), rtol=0, atol=ROTVEC_TOL)
    np.testing.assert_allclose(ours.wxyz, reference.as_quat(canonical=True, scalar_first=True), rtol=0,
                               atol=ROTVEC_TOL)
    np.testing.assert_array_equal(ours.A, hat(ours.rotvec))  # (1.3)
    np.testing.assert_allclose(expm(ours.A), D, rtol=0, atol=EXPM_TOL)  # (1.2)
    if ours.axis is not None:
        assert abs(np.linalg.norm(ours.axis) - 1.0) <= 4e-16
        np.testing.assert_allclose(D @ ours.axis, ours.axis, rtol=0, atol=4e-15)  # d is D's eigenvector, eigenvalue 1
        # (1.1) as the memo writes it, where arccos is well conditioned (away from 0 and π).
        if 1e-3 < ours.angle < math.pi - 1e-3:
            assert abs(ours.angle - math.acos(0.5 * (np.trace(D) - 1.0))) <= 1e-12


@pytest.mark.parametrize("seed", range(40))
def test_random_rotations_match_scipy_rotvec_and_quat(seed: int) -> None:
    check_against_scipy(Rotation.random(random_state=seed).as_matrix())


@pytest.mark.parametrize("angle", [1e-6, 1e-8, 2e-9, 1e-12, 5e-13, 1e-15, 0.0])
def test_near_zero_the_rotation_vector_matches_and_the_axis_is_undefined_below_the_threshold(angle: float) -> None:
    for d in random_axes(5):
        D = Rotation.from_rotvec(angle * d).as_matrix()
        check_against_scipy(D)
        ours = single_rotation(D)
        if angle < AXIS_UNDEFINED_ANGLE:
            assert ours.axis is None  # D = 1 to within rounding: no axis is drawn
        else:
            assert ours.axis is not None
            np.testing.assert_allclose(ours.axis, d, rtol=0, atol=1e-6 if angle < 1e-7 else 1e-9)


def test_identity_and_rounding_noise_have_no_axis() -> None:
    for D in (np.eye(3), rot_z(math.radians(1.0)) @ rot_z(math.radians(-1.0)),
              rot_z(math.radians(30.0)) @ rot_x(0.0) @ rot_z(math.radians(-30.0))):
        ours = single_rotation(D)
        assert ours.axis is None and ours.angle < 1e-15
        assert ours.wxyz[0] == pytest.approx(1.0, abs=1e-16)


HALF_TURNS = [
    np.diag([1.0, -1.0, -1.0]), np.diag([-1.0, 1.0, -1.0]), np.diag([-1.0, -1.0, 1.0]),
    rot_x(math.pi), rot_z(math.pi), rot_x(math.radians(60.0)) @ rot_z(math.pi),
    Rotation.from_rotvec(math.pi * np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)).as_matrix(),
    Rotation.from_rotvec(math.pi * np.array([-1.0, 1.0, 1.0]) / math.sqrt(3.0)).as_matrix(),
    *(Rotation.from_rotvec(math.pi * d).as_matrix() for d in random_axes(8)),
]


@pytest.mark.parametrize("D", HALF_TURNS)
def test_exactly_pi_the_axis_is_from_the_symmetric_part_with_a_fixed_sign(D: np.ndarray) -> None:
    ours = single_rotation(D)
    assert abs(ours.angle - math.pi) <= 4 * np.finfo(float).eps
    d = ours.axis
    assert d is not None
    np.testing.assert_allclose(0.5 * (D + np.eye(3)), np.outer(d, d), rtol=0, atol=4e-15)  # (D + 1)/2 = d dᵀ
    assert d[int(np.argmax(np.abs(d)))] > 0.0  # no previous axis: the largest component positive
    # SciPy's rotvec is ±π d (both are D); the quaternion is ±(0, d).
    reference = Rotation.from_matrix(D)
    sign = 1.0 if float(reference.as_rotvec() @ d) > 0.0 else -1.0
    np.testing.assert_allclose(ours.rotvec, sign * reference.as_rotvec(), rtol=0, atol=ROTVEC_TOL)
    quat = reference.as_quat(scalar_first=True)  # w is rounding noise of either sign: compare ±q
    quat = quat if float(quat[1:] @ d) > 0.0 else -quat
    np.testing.assert_allclose(ours.wxyz, quat, rtol=0, atol=ROTVEC_TOL)
    np.testing.assert_allclose(expm(ours.A), D, rtol=0, atol=EXPM_TOL)
    # The other sign when the last axis drawn pointed the other way.
    flipped = single_rotation(D, previous_axis=-d)
    assert flipped.axis is not None
    np.testing.assert_array_equal(flipped.axis, -d)
    np.testing.assert_allclose(expm(flipped.A), D, rtol=0, atol=EXPM_TOL)


@pytest.mark.parametrize("offset", [1e-12, 5e-13, 1e-14, 5e-11])
def test_within_the_half_turn_band_the_sign_follows_the_previous_axis(offset: float) -> None:
    assert offset <= HALF_TURN_BAND
    for d in random_axes(6, seed=3):
        D = Rotation.from_rotvec((math.pi - offset) * d).as_matrix()
        reference = Rotation.from_matrix(D).as_rotvec()
        for previous in (d, -d):
            ours = single_rotation(D, previous_axis=previous)
            assert ours.axis is not None and float(ours.axis @ previous) > 0.999
            assert abs(ours.angle - (math.pi - offset)) <= 4 * np.finfo(float).eps
            # D itself to within the band's documented error, 2 sin Φ.
            np.testing.assert_allclose(exp_so3(ours.rotvec), D, rtol=0, atol=2.0 * offset + EXPM_TOL)
            if previous is d:  # the sign SciPy reads from sin Φ d: the same rotation vector
                np.testing.assert_allclose(ours.rotvec, reference, rtol=0, atol=1e-9)


@pytest.mark.parametrize("offset", [1e-9, 1e-6, 1e-3])
def test_outside_the_band_the_sign_is_the_data_not_the_previous_axis(offset: float) -> None:
    for d in random_axes(6, seed=4):
        D = Rotation.from_rotvec((math.pi - offset) * d).as_matrix()
        ours = single_rotation(D, previous_axis=-d)
        assert ours.axis is not None and float(ours.axis @ d) > 1.0 - 1e-9
        np.testing.assert_allclose(ours.rotvec, Rotation.from_matrix(D).as_rotvec(), rtol=0, atol=1e-9)


def test_a_slider_sweep_through_half_turns_never_flips_the_axis() -> None:
    """D = Rx(θ) Rz(180°) is a half turn about (0, -sin θ/2, cos θ/2) for every θ, and so is
    Rz(φ) Rx(θ) Rz(180° - φ) (the same turned by Rz(φ)).  The axis drawn moves continuously as θ,
    then φ, move in 1° steps: each axis is within 1.5° of the last (no flip to -d)."""
    sweeps = ([rot_x(math.radians(theta_deg)) @ rot_z(math.pi) for theta_deg in range(0, 181)],
              [rot_z(math.radians(phi_deg)) @ rot_x(math.radians(60.0)) @ rot_z(math.radians(180.0 - phi_deg))
               for phi_deg in range(-180, 181)])
    for sweep in sweeps:
        previous = None
        axes = []
        for D in sweep:
            rotation = single_rotation(D, previous)
            assert abs(rotation.angle - math.pi) < 1e-15
            assert rotation.axis is not None
            axes.append(rotation.axis)
            previous = rotation.axis
        steps = np.einsum("ij,ij->i", np.array(axes[:-1]), np.array(axes[1:]))
        assert steps.min() > math.cos(math.radians(1.5))  # each 1° of θ turns d by 0.5°, of φ by ≤ 1°


def test_turn_path_goes_from_v_to_D_v_about_d() -> None:
    d = np.array([1.0, 2.0, 2.0]) / 3.0
    angle = 2.0
    v = np.array([0.3, -0.4, 1.2])
    points = turn_path(d, angle, v, 16)
    assert points.shape == (17, 3)
    np.testing.assert_allclose(points[0], v, atol=1e-15)
    np.testing.assert_allclose(points[-1], exp_so3(angle * d) @ v, atol=1e-15)
    for s, point in zip(np.linspace(0.0, 1.0, 17), points):
        np.testing.assert_allclose(point, expm(s * angle * hat(d)) @ v, atol=1e-14)
