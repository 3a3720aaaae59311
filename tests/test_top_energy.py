"""Tests of physics.top_energy: U_eff(θ), the turning points and the class of motion.

Independent references:
* the energy E = ½ ω_b·I ω_b + mgl cos θ (`physics.dynamics.energy`) of states built here from
  z-x-z angles and rates (scipy Rotation), against ½ I1 θ̇² + U_eff(θ);
* the turning points as zeros of E − U_eff found by scipy's brentq, and as the extremes of the
  exact solution's θ(t) = atan2(|e_z′ × e_z|, e_z′·e_z) over a nutation period (sampled, then
  refined by scipy's minimize_scalar);
* the presets' names (assets/presets/heavy_top.json) for the classes of motion.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq, minimize_scalar
from scipy.spatial.transform import Rotation

from app.scenes.heavy_top import HeavyTopView
from physics.dynamics import Model, energy
from physics.euler import omega_body_from_euler_rates
from physics.exact_top import HeavySymmetricTopExact
from physics.top_energy import (
    CUSP,
    LOOP,
    MOTION_CLASSES,
    SLEEPING,
    STEADY,
    THROUGH_VERTICAL,
    TOO_SLOW,
    WAVE,
    classify,
    effective_potential,
    energy_picture,
)

TURNING_TOL = 1e-9  # [rad] the tolerance on the turning points
ENERGY_RTOL = 1e-12  # ½ I1 θ̇² + U_eff(θ) against E, relative


def state(phi: float, theta: float, psi: float, phi_dot: float, theta_dot: float, spin: float):
    """(R_space_body, ω_b) from z-x-z angles [rad], φ̇, θ̇ [rad/s] and ω_z′ [rad/s]."""
    R = Rotation.from_euler("ZXZ", [phi, theta, psi]).as_matrix()
    psi_dot = spin - phi_dot * math.cos(theta)
    return R, omega_body_from_euler_rates(np.array([phi, theta, psi]), np.array([phi_dot, theta_dot, psi_dot]))


def preset_states():
    for preset in HeavyTopView.presets():
        model, start, _ = HeavyTopView.initial_conditions(preset)
        yield preset.name, model, start.R_space_body, start.omega_body


def theta_range_of_exact(top: HeavySymmetricTopExact) -> tuple[float, float]:
    """min and max of θ(t) over a nutation period, sampled and then refined."""
    period = top.nutation_period if math.isfinite(top.nutation_period) else 10.0

    def theta(t: float) -> float:
        x, y, z = top.axis_space(t)
        return math.atan2(math.hypot(x, y), z)

    ts = np.linspace(0.0, period, 4001)
    thetas = np.array([theta(t) for t in ts])
    dt = ts[1] - ts[0]
    found = []
    for sign in (1.0, -1.0):
        k = int(np.argmin(sign * thetas))
        result = minimize_scalar(lambda t, sign=sign: sign * theta(t), bounds=(ts[k] - dt, ts[k] + dt),
                                 method="bounded", options={"xatol": 1e-13})
        found.append(min(sign * result.fun, sign * thetas[k]) * sign)
    return found[0], found[1]


def brentq_turning_points(picture) -> tuple[float, float]:
    """The zeros of E − U_eff on either side of U_eff's minimum (a pole where U_eff < E there)."""
    grid = np.linspace(1e-9, math.pi - 1e-9, 20001)
    k = int(np.argmin(picture.U_eff(grid)))
    theta_min_U = float(grid[k])

    def gap(theta: float) -> float:
        return float(picture.energy - picture.U_eff(theta))

    def zero(pole: float, near_pole: float) -> float:
        """The zero between U_eff's minimum and `pole`; the pole itself where E − U_eff has no sign
        change a float can show (a top nearly at rest: the zero is within 1e-16 rad of the pole)."""
        if gap(pole) >= 0.0 or gap(near_pole) >= 0.0:
            return pole
        a, b = sorted((theta_min_U, near_pole))
        return float(brentq(gap, a, b, xtol=1e-15, rtol=1e-15))

    return zero(0.0, 1e-300), zero(math.pi, math.pi * (1 - 1e-16))


# ---------------------------------------------------------------------------- U_eff
@settings(max_examples=60, deadline=None)
@given(st.floats(0.2, 3.0), st.floats(0.1, 1.0), st.floats(0.0, 20.0), st.floats(0.05, math.pi - 0.05),
       st.floats(-5.0, 5.0), st.floats(-5.0, 5.0), st.floats(-30.0, 30.0), st.floats(-3.0, 3.0))
def test_energy_is_kinetic_theta_plus_effective_potential(I1, ratio, mgl, theta, phi_dot, theta_dot, spin, psi):
    I3 = 2.0 * I1 * ratio
    R, omega = state(0.3, theta, psi, phi_dot, theta_dot, spin)
    picture = energy_picture(I1, I3, mgl, R, omega)
    E = energy(Model(inertia=(I1, I1, I3), mgl=mgl), R, omega)
    expected = 0.5 * I1 * theta_dot**2 + float(picture.U_eff(theta))
    assert picture.energy == pytest.approx(E, rel=ENERGY_RTOL, abs=1e-12)
    assert expected == pytest.approx(E, rel=ENERGY_RTOL, abs=1e-12)


def test_effective_potential_at_a_reachable_pole_is_its_limit():
    I1, I3, mgl, p = 1.0, 0.5, 6.0, 6.0
    near = effective_potential(I1, I3, mgl, p, p, np.array([1e-7, 0.0]))
    assert near[1] == pytest.approx(p * p / (2 * I3) + mgl, rel=1e-15)
    assert near[0] == pytest.approx(near[1], rel=1e-12)
    bottom = effective_potential(I1, I3, mgl, -p, p, np.array([math.pi - 1e-7, math.pi]))
    assert bottom[1] == pytest.approx(p * p / (2 * I3) - mgl, rel=1e-15)
    assert bottom[0] == pytest.approx(bottom[1], rel=1e-12)
    assert effective_potential(I1, I3, mgl, 3.0, p, 0.0) == math.inf  # p_φ ≠ p_ψ: a barrier


# ---------------------------------------------------------------------------- turning points
@pytest.mark.parametrize("name", [p.name for p in HeavyTopView.presets()])
def test_turning_points_are_the_exact_theta_range_and_the_zeros_of_E_minus_U_eff(name):
    _, model, R, omega = next(s for s in preset_states() if s[0] == name)
    I1, _, I3 = model.inertia
    picture = energy_picture(I1, I3, model.mgl, R, omega)
    top = HeavySymmetricTopExact(I1, I3, model.mgl, R, omega)
    lo, hi = theta_range_of_exact(top)
    assert picture.theta_1 == pytest.approx(lo, abs=TURNING_TOL)
    assert picture.theta_2 == pytest.approx(hi, abs=TURNING_TOL)
    if picture.motion != STEADY:
        b_lo, b_hi = brentq_turning_points(picture)
        assert picture.theta_1 == pytest.approx(b_lo, abs=TURNING_TOL)
        assert picture.theta_2 == pytest.approx(b_hi, abs=TURNING_TOL)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.3, 3.0), st.floats(0.1, 1.0), st.floats(0.5, 20.0), st.floats(0.2, math.pi - 0.2),
       st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(-30.0, 30.0))
def test_turning_points_are_zeros_of_E_minus_U_eff(I1, ratio, mgl, theta, phi_dot, theta_dot, spin):
    I3 = 2.0 * I1 * ratio
    R, omega = state(0.0, theta, 0.0, phi_dot, theta_dot, spin)
    picture = energy_picture(I1, I3, mgl, R, omega)
    if picture.theta_2 - picture.theta_1 < 1e-4:
        return  # too near steady precession for a bracketing root finder
    b_lo, b_hi = brentq_turning_points(picture)
    assert picture.theta_1 == pytest.approx(b_lo, abs=TURNING_TOL)
    assert picture.theta_2 == pytest.approx(b_hi, abs=TURNING_TOL)
    assert picture.theta_1 - 1e-12 <= theta <= picture.theta_2 + 1e-12


# ---------------------------------------------------------------------------- classes
PRESET_CLASSES = {"Steady": STEADY, "Wave": WAVE, "Loop": LOOP, "Cusp": CUSP, "Sleeping": SLEEPING,
                  "Too slow": TOO_SLOW, "Through the vertical": THROUGH_VERTICAL}


def test_every_preset_is_listed():
    assert {p.name for p in HeavyTopView.presets()} == set(PRESET_CLASSES)
    assert set(PRESET_CLASSES.values()) == set(MOTION_CLASSES)


@pytest.mark.parametrize("name", list(PRESET_CLASSES))
def test_the_class_of_each_preset_matches_its_name(name):
    _, model, R, omega = next(s for s in preset_states() if s[0] == name)
    I1, _, I3 = model.inertia
    picture = energy_picture(I1, I3, model.mgl, R, omega)
    assert picture.motion == PRESET_CLASSES[name]
    assert picture.motion.startswith(name.lower())


def test_wave_and_loop_follow_the_sign_of_phi_dot_at_the_turning_points():
    I1, mgl, p_psi = 1.0, 6.0, 6.0
    t1, t2 = math.radians(40.0), math.radians(70.0)
    # φ̇ ∝ p_φ − p_ψ cos θ: at 40° cos = 0.766, at 70° 0.342
    assert classify(I1, mgl, 5.0, p_psi, t1, t2) == WAVE  # > 0 at both
    assert classify(I1, mgl, 1.0, p_psi, t1, t2) == WAVE  # < 0 at both
    assert classify(I1, mgl, 3.0, p_psi, t1, t2) == LOOP  # changes sign
    assert classify(I1, mgl, p_psi * math.cos(t1), p_psi, t1, t2) == CUSP
    assert classify(I1, 0.0, 3.0, p_psi, t1, t1) == STEADY  # no gravity: regular precession


def test_a_top_started_upright_and_nudged_sleeps_if_fast_and_falls_if_slow():
    I1, I3, mgl = 1.0, 0.5, 6.0  # sleeps if ω_z′² > 4 I1 mgl / I3² = 96
    fast = energy_picture(I1, I3, mgl, *state(0.0, 0.0, 0.0, 0.0, 0.05, 12.0))
    slow = energy_picture(I1, I3, mgl, *state(0.0, 0.0, 0.0, 0.0, 0.05, 6.0))
    assert fast.motion == SLEEPING and fast.vertical_stable
    assert slow.motion == THROUGH_VERTICAL and not slow.vertical_stable  # p_φ = p_ψ at θ = 0
    tilted_slow = energy_picture(I1, I3, mgl, *state(0.0, 0.05, 0.0, 0.0, 0.0, 6.0))
    assert tilted_slow.motion == TOO_SLOW


def test_bad_input_is_refused():
    with pytest.raises(ValueError):
        energy_picture(1.0, 0.5, math.nan, np.eye(3), np.zeros(3))
    with pytest.raises(ValueError):
        energy_picture(1.0, 0.5, 6.0, np.eye(3), np.array([math.nan, 0.0, 0.0]))
