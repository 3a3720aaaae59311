"""Tests of physics.exact_top: the exact heavy symmetric (Lagrange) top.

Independent references only:
* scipy solve_ivp (DOP853, rtol = atol = 1e-13) on Ṙ = R hat(ω_b),
  I ω̇_b + ω_b × (I ω_b) = Rᵀ M, M = -mgl (e_z' × e_z), I = diag(I1, I1, I3);
* closed forms: steady precession (Goldstein's φ̇ formula, R = Rz(φ̇ t) R0 Rz(ψ̇ t)), the free
  symmetric body R = expm(t hat(L)/I1) R0 expm(t ω3 (I1 - I3)/I1 hat(e_z)) (scipy Rotation),
  the pendulum period 4 K(sin²(α/2)) / √(mgl/I1) (scipy.special.ellipkm1), the roots of the cubic
  by numpy.roots;
* finite differences of the attitude for ω_b; invariants E, p_φ = L·e_z, p_ψ recomputed here
  from (R, ω_b); scipy.special.ellipj / mpmath for the Jacobi helper.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation
from scipy.special import ellipj, ellipkm1, elliprf

from physics.dynamics import Model, omega_body_dot
from physics.exact_top import HeavySymmetricTopExact, _sncndn_reduced, steady_precession_rate
from physics.so3 import rot_x, rot_z

ODE_TOL = 1e-13  # rtol = atol of the DOP853 reference
FINE_ODE_TOL = 2.3e-14  # the finest rtol SciPy's DOP853 takes (100 eps)
ATT_TOL = 1e-9  # [rad] attitude error against the reference over tens of seconds
CONS_TOL = 1e-12  # relative drift of E and p_φ allowed at any time, 0 <= t <= 1e4 s


def euler(phi: float, theta: float, psi: float) -> np.ndarray:
    return Rotation.from_euler("ZXZ", [phi, theta, psi]).as_matrix()


def reference_ode(I1, I3, mgl, R0, omega0, t_eval, tol=ODE_TOL):
    """DOP853 on the 12-dimensional (R, ω_b) system, at the times t_eval (increasing, from 0),
    rtol = atol = `tol`."""
    inv1, inv3, k = 1.0 / I1, 1.0 / I3, (I3 - I1)

    def rhs(_t, y):
        r00, r01, r02, r10, r11, r12, r20, r21, r22, w1, w2, w3 = y
        # Ṙ = R hat(ω): row i of R times hat(ω)
        dR = [
            r01 * w3 - r02 * w2, r02 * w1 - r00 * w3, r00 * w2 - r01 * w1,
            r11 * w3 - r12 * w2, r12 * w1 - r10 * w3, r10 * w2 - r11 * w1,
            r21 * w3 - r22 * w2, r22 * w1 - r20 * w3, r20 * w2 - r21 * w1,
        ]
        # body torque: Rᵀ(-mgl e_z' × e_z) = -mgl e3 × (Rᵀ e_z) = -mgl (-r21, r20, 0)
        m1, m2 = mgl * r21, -mgl * r20
        # I ω̇ = M - ω × Iω (I1 = I2): components 1, 2 carry (I3 - I1) w w3
        dw = [(m1 - k * w2 * w3) * inv1, (m2 + k * w1 * w3) * inv1, 0.0 * inv3]
        return dR + dw

    y0 = np.concatenate([np.asarray(R0, float).ravel(), np.asarray(omega0, float)])
    sol = solve_ivp(rhs, (0.0, float(t_eval[-1])), y0, method="DOP853", rtol=tol,
                    atol=tol, t_eval=t_eval)
    assert sol.success
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


def attitude_error(Ra: np.ndarray, Rb: np.ndarray) -> float:
    """Largest rotation angle [rad] between two stacks of attitudes (‖Ra - Rb‖_F / √2)."""
    return float(np.max(np.linalg.norm(Ra - Rb, axis=(-2, -1)))) / math.sqrt(2.0)


def invariants(I1, I3, mgl, R, omega):
    """E, p_φ = (R I ω)·e_z, p_ψ = I3 ω3 recomputed from (R, ω_b) of shape (N,3,3), (N,3)."""
    I = np.array([I1, I1, I3])
    omega = np.asarray(omega, dtype=float)
    E = 0.5 * np.sum(I * omega * omega, axis=-1) + mgl * R[..., 2, 2]
    L_space = np.einsum("...ij,...j->...i", R, I * omega)
    return E, L_space[..., 2], I3 * omega[..., 2]


# ------------------------------------------------------------------------------------------
# Against the ODE reference
# ------------------------------------------------------------------------------------------

I1, I3, MGL = 1.0, 0.5, 1.0
HANGING = np.diag([1.0, -1.0, -1.0])  # Rx(π) exactly: θ = π

ODE_CASES = {
    # name: (I1, I3, mgl, R0, ω0, t_end)
    "wave": (I1, I3, MGL, euler(0.3, 0.8, -0.2), [0.4, -0.3, 8.0], 10.0),
    "loop": (I1, I3, MGL, euler(0.3, 0.8, -0.2), [1.5, -0.3, 8.0], 10.0),
    "cusp": (I1, I3, MGL, euler(0.3, 0.8, -0.2), [0.0, 0.0, 8.0], 10.0),
    "slow_top_wide_nutation": (1.2, 0.7, 2.0, euler(0.3, 1.2, -0.2), [1.5, -0.3, 0.3], 12.0),
    "pendulum_from_rest": (I1, I3, MGL, euler(0.3, 1.2, -0.2), [0.0, 0.0, 0.0], 12.0),
    "pendulum_over_the_top": (I1, I3, MGL, rot_x(math.pi / 2), [3.0, 0.0, 0.0], 12.0),
    "start_exactly_vertical": (I1, I3, MGL, np.eye(3), [0.3, -0.2, 3.0], 12.0),
    "start_exactly_hanging": (I1, I3, MGL, HANGING, [0.3, -0.2, 3.0], 12.0),
    "hanging_no_spin": (I1, I3, MGL, HANGING, [0.3, -0.2, 0.0], 12.0),
    "near_vertical_unstable": (I1, I3, MGL, euler(0.3, 1e-3, 0.2), [0.0, 0.0, 1.0], 10.0),
    "tilted_sleeping_1e-6": (I1, I3, MGL, euler(0.3, 1e-6, 0.2), [0.0, 0.0, 5.0], 10.0),
    "oblate_heavy": (1.0, 1.8, 0.7, euler(-1.0, 2.2, 0.5), [0.9, 0.6, -4.0], 10.0),
    "spin_1000": (I1, I3, MGL, euler(0.3, 0.8, 0.2), [0.0, 0.0, 1000.0], 0.25),
}


@pytest.mark.parametrize("name", list(ODE_CASES))
def test_attitude_and_omega_match_ode(name: str) -> None:
    i1, i3, mgl, R0, w0, t_end = ODE_CASES[name]
    t = np.linspace(0.0, t_end, 121)
    top = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)
    R, w = top(t)
    R_ref, w_ref = reference_ode(i1, i3, mgl, R0, w0, t)
    assert np.all(np.isfinite(R)) and np.all(np.isfinite(w))
    assert attitude_error(R, R_ref) <= ATT_TOL
    scale = 1.0 + float(np.max(np.abs(w0)))
    np.testing.assert_allclose(w, w_ref, rtol=0.0, atol=ATT_TOL * scale)


def test_long_time_state_is_on_the_trajectory() -> None:
    """The state at t = 1e4 s (thousands of periods) continues like the ODE from there, and
    agrees with a fresh exact top started from it (whole-period bookkeeping)."""
    R0, w0 = euler(0.3, 0.8, -0.2), np.array([0.4, -0.3, 8.0])
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, w0)
    t1 = 1.0e4
    R1, w1 = top(t1)
    s = np.linspace(0.0, 5.0, 51)
    R_ref, w_ref = reference_ode(I1, I3, MGL, R1, w1, s)
    R_later, w_later = top(t1 + s)
    # t1 + s carries a rounding of ulp(1e4) ~ 2e-12 s; |ω| ~ 8 rad/s
    assert attitude_error(R_later, R_ref) <= ATT_TOL
    np.testing.assert_allclose(w_later, w_ref, atol=1e-9)
    restarted = HeavySymmetricTopExact(I1, I3, MGL, R1, w1)
    assert attitude_error(restarted.attitude(s), R_later) <= 1e-10


# ------------------------------------------------------------------------------------------
# Conservation, turning points, finite differences (hypothesis)
# ------------------------------------------------------------------------------------------


@st.composite
def tops(draw):
    """(I1, I3, mgl, R0, ω0), including exact vertical/hanging starts and zero transverse ω."""
    i1 = draw(st.floats(0.3, 3.0))
    i3 = draw(st.floats(0.1, 2.0)) * i1  # triangle inequality about the pivot: I3 <= 2 I1
    mgl = draw(st.sampled_from([0.0, 0.3, 1.0, 4.0]) | st.floats(0.0, 5.0))
    kind = draw(st.sampled_from(["random", "random", "random", "vertical", "hanging", "near_pole"]))
    if kind == "random":
        q = np.array(draw(st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4)))
        if np.linalg.norm(q) < 0.1:
            q = np.array([1.0, 0.2, -0.3, 0.1])
        R0 = Rotation.from_quat(q / np.linalg.norm(q)).as_matrix()
    elif kind == "vertical":
        R0 = rot_z(draw(st.floats(-math.pi, math.pi)))
    elif kind == "near_pole":  # θ0 = 1e-9 .. 1e-3 from the upright or the hanging position
        tilt = 10.0 ** draw(st.floats(-9.0, -3.0))
        R0 = rot_z(draw(st.floats(-math.pi, math.pi))) @ rot_x(draw(st.sampled_from([tilt, math.pi - tilt])))
    else:
        R0 = rot_z(draw(st.floats(-math.pi, math.pi))) @ HANGING
    w = draw(st.lists(st.floats(-8.0, 8.0), min_size=3, max_size=3))
    kick = draw(st.sampled_from([1.0, 1.0, 1e-6, 1e-12, 0.0]))  # transverse ω, tiny or none
    w[0] *= kick
    w[1] *= kick
    return i1, i3, mgl, R0, np.array(w)


@settings(max_examples=10, deadline=None)
@given(tops())
def test_random_tops_match_ode(case) -> None:
    """Against the reference at its finest tolerance, within ATT_TOL plus the reference's own
    error, estimated as its change from ODE_TOL to FINE_ODE_TOL: a top that falls from near the
    upright amplifies the ODE's rounding (e.g. I1 = I3 = 0.375, mgl = 4, upright, ω = (0, 1e-5,
    0): the reference moves 2.9e-9 rad between the two tolerances, while the closed form agrees
    with a 40-digit mpmath pendulum to 1.4e-11 rad)."""
    i1, i3, mgl, R0, w0 = case
    t = np.linspace(0.0, 4.0, 41)
    R, w = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)(t)
    R_ref, w_ref = reference_ode(i1, i3, mgl, R0, w0, t, tol=FINE_ODE_TOL)
    R_coarse, w_coarse = reference_ode(i1, i3, mgl, R0, w0, t)
    att_ref_err = attitude_error(R_ref, R_coarse)
    w_ref_err = float(np.max(np.abs(w_ref - w_coarse)))
    assert attitude_error(R, R_ref) <= ATT_TOL + att_ref_err
    np.testing.assert_allclose(w, w_ref, atol=ATT_TOL * (1.0 + float(np.max(np.abs(w0)))) + w_ref_err)


@settings(max_examples=80, deadline=None)
@given(tops())
def test_invariants_conserved_and_u_between_turning_points(case) -> None:
    i1, i3, mgl, R0, w0 = case
    top = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)
    t = np.concatenate([np.linspace(0.0, 40.0, 400), 1.0e4 - np.linspace(0.0, 40.0, 400)])
    R, w = top(t)
    assert np.all(np.isfinite(R)) and np.all(np.isfinite(w))
    np.testing.assert_allclose(np.einsum("nji,njk->nik", R, R), np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-14)
    E0, pphi0, ppsi0 = invariants(i1, i3, mgl, R0, w0)
    E, pphi, ppsi = invariants(i1, i3, mgl, R, w)
    e_scale = 0.5 * float(np.sum(np.array([i1, i1, i3]) * w0 * w0)) + mgl
    # |L|² <= 2 I_max (T0 + 2 mgl) and T0 <= |L0|² / (2 I_min): a bound on |L| at all times
    l0 = math.hypot(*(np.array([i1, i1, i3]) * w0))  # |L0| (hypot: no underflow)
    l_scale = l0 * math.sqrt(max(i1, i3) / min(i1, i3)) + math.sqrt(4.0 * max(i1, i3) * mgl)
    assert np.max(np.abs(E - E0)) <= CONS_TOL * max(e_scale, 1e-300)
    assert np.max(np.abs(pphi - pphi0)) <= CONS_TOL * l_scale
    assert np.max(np.abs(ppsi - ppsi0)) <= CONS_TOL * l_scale
    u = R[:, 2, 2]
    assert top.u1 <= top.u2
    assert np.all(u >= top.u1 - 1e-15) and np.all(u <= top.u2 + 1e-15)  # a few ulp
    np.testing.assert_allclose(top.cos_theta(t), u, atol=4e-15)
    theta = np.arctan2(np.hypot(R[:, 0, 2], R[:, 1, 2]), R[:, 2, 2])  # precise near 0 and π
    assert 0.0 <= top.theta_min <= top.theta_max <= math.pi
    assert np.all(theta >= top.theta_min * (1.0 - 1e-12) - 1e-15)
    assert np.all(theta <= top.theta_max * (1.0 + 1e-12) + 1e-15)


@settings(max_examples=60, deadline=None)
@given(tops(), st.floats(0.0, 30.0))
def test_omega_is_the_derivative_of_the_attitude(case, t0) -> None:
    """hat(ω_b) = Rᵀ Ṙ with Ṙ by a 4th-order central difference of `attitude`."""
    i1, i3, mgl, R0, w0 = case
    top = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)
    scale = 1.0 + float(np.max(np.abs(top.omega_body(np.linspace(0, 30, 31)))))
    h = 2e-3 / scale
    Rm2, Rm1, R, Rp1, Rp2 = top.attitude(t0 + h * np.array([-2.0, -1.0, 0.0, 1.0, 2.0]))
    Rdot = (-Rp2 + 8.0 * Rp1 - 8.0 * Rm1 + Rm2) / (12.0 * h)
    W = R.T @ Rdot
    w_fd = np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]]) / 2.0
    np.testing.assert_allclose(top.omega_body(t0), w_fd, atol=2e-8 * scale)


def cubic_roots_from_invariants(i1, i3, mgl, R0, w0):
    """Roots of u̇² = f(u) written from E, p_φ, p_ψ in the textbook form (numpy.roots)."""
    E, b, a = (float(v) for v in invariants(i1, i3, mgl, R0, w0))
    alpha = (2.0 * E - a * a / i3) / i1
    beta = 2.0 * mgl / i1
    ap, bp = a / i1, b / i1
    # f(u) = (1 - u²)(α - β u) - (b' - a' u)²
    coeffs = [beta, -(alpha + ap * ap), -beta + 2.0 * ap * bp, alpha - bp * bp]
    return np.sort(np.roots(coeffs).real)


@pytest.mark.parametrize("name", ["wave", "loop", "cusp", "slow_top_wide_nutation", "oblate_heavy"])
def test_turning_points_are_roots_of_the_cubic_and_reached(name: str) -> None:
    i1, i3, mgl, R0, w0, _ = ODE_CASES[name]
    top = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)
    r = cubic_roots_from_invariants(i1, i3, mgl, R0, w0)
    np.testing.assert_allclose([top.u1, top.u2], r[:2], atol=1e-9)
    assert r[2] >= 1.0 - 1e-12
    # the ODE's cos θ sweeps [u1, u2] over one nutation period
    t = np.linspace(0.0, top.nutation_period, 2001)
    R_ref, _ = reference_ode(i1, i3, mgl, R0, w0, t)
    u = R_ref[:, 2, 2]
    assert abs(u.min() - top.u1) < 1e-5 and abs(u.max() - top.u2) < 1e-5
    assert u.min() >= top.u1 - 1e-10 and u.max() <= top.u2 + 1e-10
    assert abs(u[-1] - u[0]) < 1e-10  # the period of u


# ------------------------------------------------------------------------------------------
# Classic special motions
# ------------------------------------------------------------------------------------------


def test_cusp_tip_stops_at_the_top_turning_points() -> None:
    """Released with φ̇ = θ̇ = 0 at θ0: u0 = u2, and at every multiple of the nutation period
    the symmetry axis is at rest again (ω_b ∥ e_z'), in the ODE reference as well."""
    R0, w0 = euler(0.3, 0.8, -0.2), np.array([0.0, 0.0, 8.0])
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, w0)
    assert top.u2 == pytest.approx(R0[2, 2], abs=1e-15)
    t = top.nutation_period * np.arange(0.0, 6.0)
    _, w_ref = reference_ode(I1, I3, MGL, R0, w0, t)
    R, w = top(t)
    assert np.max(np.hypot(w_ref[:, 0], w_ref[:, 1])) < 1e-9  # tip velocity |ω × e_z'|
    assert np.max(np.hypot(w[:, 0], w[:, 1])) < 1e-11
    np.testing.assert_allclose(R[:, 2, 2], top.u2, atol=1e-14)
    # between the cusps the tip does move
    assert np.hypot(*top.omega_body(0.5 * top.nutation_period)[:2]) > 0.1


@pytest.mark.parametrize("cos_theta, omega3, mgl", [(0.5, 10.0, 1.0), (0.3, 50.0, 2.0), (-0.4, 5.0, 1.0)])
@pytest.mark.parametrize("branch", ["slow", "fast"])
def test_steady_precession_classic_rate(cos_theta: float, omega3: float, mgl: float, branch: str) -> None:
    """φ̇ = (I3 ω3 ± √(I3² ω3² - 4 I1 mgl cos θ)) / (2 I1 cos θ) (Goldstein); θ̇ = 0."""
    i1, i3 = 1.0, 0.6
    a = i3 * omega3
    root = math.sqrt(a * a - 4.0 * i1 * mgl * cos_theta)
    # the slow rate in the form without cancellation: 2 mgl / (a + √...)
    dphi = 2.0 * mgl / (a + root) if branch == "slow" else (a + root) / (2.0 * i1 * cos_theta)
    theta = math.acos(cos_theta)
    dpsi = omega3 - dphi * cos_theta
    R0 = euler(0.2, theta, 0.7)
    w0 = np.array([dphi * math.sin(theta) * math.sin(0.7), dphi * math.sin(theta) * math.cos(0.7), omega3])
    top = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)
    assert top.u2 - top.u1 < 1e-13
    t = np.linspace(0.0, 50.0, 101)
    expected = np.array([rot_z(dphi * s) @ R0 @ rot_z(dpsi * s) for s in t])
    # rounding only: a few ulp of the phases φ̇ t, ψ̇ t
    assert attitude_error(top.attitude(t), expected) < 2e-15 * (1.0 + abs(dphi) + abs(dpsi)) * t[-1]


def test_sleeping_top_stays_vertical() -> None:
    """θ0 = 0, ω = ω3 e_z' with I3² ω3² > 4 I1 mgl: R(t) = R0 Rz(ω3 t) for ever."""
    omega3 = 5.0
    assert (I3 * omega3) ** 2 > 4.0 * I1 * MGL
    R0 = rot_z(0.4)
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, [0.0, 0.0, omega3])
    assert top.u1 == 1.0 and top.u2 == 1.0
    t = np.concatenate([np.linspace(0.0, 10.0, 51), [1.0e3, 1.0e4]])
    R = top.attitude(t)
    np.testing.assert_array_equal(R[:, 2, 2], 1.0)
    expected = np.array([R0 @ rot_z(omega3 * s) for s in t])
    assert attitude_error(R, expected) < 1e-15 * omega3 * t[-1] * 10


def test_slightly_tilted_sleeping_top_stays_in_a_small_cone() -> None:
    i1, i3, mgl, R0, w0, _ = ODE_CASES["tilted_sleeping_1e-6"]
    top = HeavySymmetricTopExact(i1, i3, mgl, R0, w0)
    theta = np.arccos(np.clip(top.attitude(np.linspace(0.0, 100.0, 2001))[:, 2, 2], -1.0, 1.0))
    assert np.max(theta) <= top.theta_max + 1e-12 and np.min(theta) >= top.theta_min - 1e-12
    # Small-angle theory (1 - u = ε ≈ θ²/2 ~ 5e-13): f(1 - ε) ≈ -(a'² - 2β)(ε - ε0)(ε - ε*),
    # ε* = ε0 a'²/(a'² - 2β), exact up to O(ε0).  A root finder working in u (absolute error
    # ~1e-16 on u) would get these tilts wrong by ~1e-4 relative.
    a2, beta = (i3 * w0[2] / i1) ** 2, 2.0 * mgl / i1
    assert top.theta_min == pytest.approx(1e-6, rel=1e-10)  # released with the tip at rest
    assert top.theta_max == pytest.approx(1e-6 * math.sqrt(a2 / (a2 - 2.0 * beta)), rel=1e-10)


def test_vertical_unstable_equilibrium_is_kept_exactly() -> None:
    """At θ = 0 with ω = ω3 e_z' too slow to sleep, the exact solution still stays there."""
    top = HeavySymmetricTopExact(I1, I3, MGL, rot_z(0.3), [0.0, 0.0, 1.0])
    assert (I3 * 1.0) ** 2 < 4.0 * I1 * MGL
    R = top.attitude(np.linspace(0.0, 50.0, 11))
    np.testing.assert_array_equal(R[:, 2, 2], 1.0)


def test_hanging_straight_down_spins_in_place() -> None:
    R0 = HANGING
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, [0.0, 0.0, 3.0])
    t = np.linspace(0.0, 20.0, 41)
    expected = np.array([R0 @ rot_z(3.0 * s) for s in t])
    assert attitude_error(top.attitude(t), expected) < 1e-13
    assert top.u1 == -1.0 and top.u2 == -1.0


def test_through_the_vertical_is_smooth() -> None:
    """p_φ = p_ψ: the axis passes through the pole (φ jumps by π); R and ω stay smooth."""
    R0, w0 = rot_x(0.6), np.array([0.7, 0.0, 2.0])
    a = I3 * w0[2] / I1
    w0[1] = a * (1.0 - math.cos(0.6)) / math.sin(0.6)  # b' = a': p_φ = p_ψ
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, w0)
    assert top.u2 == pytest.approx(1.0, abs=1e-15)
    # the passage: u reaches 1 between 0 and one nutation period; find it on a fine grid
    t = np.linspace(0.0, top.nutation_period, 20001)
    t_star = t[np.argmax(top.cos_theta(t))]
    near = t_star + np.concatenate([-np.logspace(-1, -10, 25), [0.0], np.logspace(-10, -1, 25)])
    R, w = top(near)
    assert np.all(np.isfinite(R)) and np.all(np.isfinite(w))
    R_ref, w_ref = reference_ode(I1, I3, MGL, R0, w0, np.concatenate([[0.0], near]))
    assert attitude_error(R, R_ref[1:]) < ATT_TOL
    np.testing.assert_allclose(w, w_ref[1:], atol=ATT_TOL * 3.0)
    # Lipschitz: |R(t + h) - R(t)| <= max|ω| h on a uniform grid through the pole
    grid = t_star + np.linspace(-1e-3, 1e-3, 2001)
    Rg = top.attitude(grid)
    steps = np.linalg.norm(np.diff(Rg, axis=0), axis=(-2, -1)) / math.sqrt(2.0)
    wmax = float(np.max(np.linalg.norm(top.omega_body(grid), axis=-1)))
    assert np.max(steps) <= 1.01 * wmax * (grid[1] - grid[0])


@pytest.mark.parametrize("offset", [1e-6, 1e-9, -1e-6])
def test_near_passage_of_the_vertical(offset: float) -> None:
    """b' - a' tiny: 1 - u2 ~ 1e-12 .. 1e-18; the fast φ flip near the pole matches the ODE."""
    R0, w0 = rot_x(0.6), np.array([0.7, 0.0, 2.0])
    a = I3 * w0[2] / I1
    w0[1] = (a * (1.0 - math.cos(0.6)) + offset) / math.sin(0.6)
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, w0)
    assert 0.0 < top.theta_min < 5e-6  # the pole is missed, by 1 - u2 ~ theta_min²/2
    t = np.linspace(0.0, top.nutation_period, 20001)
    t_star = t[np.argmax(top.cos_theta(t))]
    near = t_star + np.concatenate([-np.logspace(-1, -9, 17), [0.0], np.logspace(-9, -1, 17)])
    R_ref, w_ref = reference_ode(I1, I3, MGL, R0, w0, np.concatenate([[0.0], near]))
    R, w = top(near)
    assert attitude_error(R, R_ref[1:]) < ATT_TOL
    np.testing.assert_allclose(w, w_ref[1:], atol=ATT_TOL * 3.0)


def test_near_separatrix_against_high_precision_taylor_ode() -> None:
    """Spin below the sleeping threshold, released 1e-6 rad from the upright: 1 - m ~ 3e-13.
    DOP853 at 1e-13 is only good to ~1e-10 here, so the reference is mpmath's Taylor ODE
    solver at 28 digits."""
    mpmath = pytest.importorskip("mpmath")
    R0, w0 = euler(0.3, 1e-6, 0.2), np.array([0.0, 0.0, 1.0])
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, w0)

    def rhs(_t, y):
        r, (w1, w2, w3) = y[:9], y[9:]
        rows = [r[0:3], r[3:6], r[6:9]]
        dR = [v for a, b, c in rows for v in (b * w3 - c * w2, c * w1 - a * w3, a * w2 - b * w1)]
        k = I3 - I1
        return dR + [(MGL * r[7] - k * w2 * w3) / I1, (-MGL * r[6] + k * w1 * w3) / I1, 0]

    # start from the same rotation (top.R0: R0 re-orthonormalised, a 1e-16 change that the
    # near-separatrix motion would amplify ~1e6 times)
    with mpmath.workdps(32):
        y0 = [mpmath.mpf(float(v)) for v in np.concatenate([top.R0.ravel(), w0])]
        solution = mpmath.odefun(rhs, 0, y0, tol=mpmath.mpf(10) ** -28, degree=25)
        for t in (2.5, 5.0):
            R_ref = np.array([float(v) for v in solution(mpmath.mpf(t))[:9]]).reshape(1, 3, 3)
            assert attitude_error(top.attitude(np.array([t])), R_ref) < 1e-13


def test_exact_separatrix_against_ode() -> None:
    """u2 = u3 = 1: the axis creeps to the upright position in infinite time (u → 1)."""
    # initial data for which, in floating point, p_φ = p_ψ and E = mgl + p_ψ²/(2 I3) exactly
    th = 1.7070944094947509
    w0 = np.array([1.5044959758735037, -0.09080086363083872, -0.1583953176793656])
    top = HeavySymmetricTopExact(I1, I3, MGL, rot_x(th), w0)
    t = np.linspace(0.0, 6.0, 61)
    R_ref, w_ref = reference_ode(I1, I3, MGL, rot_x(th), w0, t)
    R, w = top(t)
    assert attitude_error(R, R_ref) < ATT_TOL
    np.testing.assert_allclose(w, w_ref, atol=ATT_TOL)
    assert top.nutation_period > 100.0  # inf when the separatrix is hit exactly
    assert np.all(np.diff(top.cos_theta(np.linspace(3.0, 50.0, 50))) >= 0.0)


def test_free_symmetric_body_closed_form() -> None:
    """mgl = 0: R(t) = expm(t hat(L_s)/I1) R0 expm(t ω3 (I1 - I3)/I1 hat(e_z))."""
    rng = np.random.default_rng(7)
    for _ in range(5):
        i1 = rng.uniform(0.5, 2.0)
        i3 = rng.uniform(0.1, 2.0) * i1
        R0 = Rotation.random(random_state=rng).as_matrix()
        w0 = rng.normal(size=3) * 3.0
        top = HeavySymmetricTopExact(i1, i3, 0.0, R0, w0)
        L = R0 @ (np.array([i1, i1, i3]) * w0)
        spin = w0[2] * (i1 - i3) / i1
        t = np.linspace(0.0, 30.0, 31)
        precess = Rotation.from_rotvec(np.outer(t, L / i1)).as_matrix()  # expm(t hat(L)/I1)
        spin_z = Rotation.from_rotvec(np.outer(t * spin, [0.0, 0.0, 1.0])).as_matrix()
        expected = precess @ R0 @ spin_z
        assert attitude_error(top.attitude(t), expected) < 1e-11
        # cos θ repeats once per turn of the axis about L, at the rate |L|/I1
        assert top.nutation_period == pytest.approx(2.0 * math.pi * i1 / np.linalg.norm(L), rel=1e-13)


@pytest.mark.parametrize("theta0", [1e-3, 0.7, math.pi / 2, 2.5])
def test_pendulum_from_rest_period_and_plane(theta0: float) -> None:
    """ω0 = 0: a plane pendulum through the lowest point. cos θ repeats every half period
    T/2 = 2 K(k²) / √(mgl/I1), k = sin(α/2), α = π - θ0, and the axis stays in its plane."""
    R0 = euler(0.3, theta0, -0.2)
    top = HeavySymmetricTopExact(I1, I3, MGL, R0, np.zeros(3))
    # K(k²) with 1 - k² = sin²(θ0/2) passed exactly (ellipkm1), k = sin(α/2)
    K = ellipkm1(math.sin(0.5 * theta0) ** 2)
    assert top.nutation_period == pytest.approx(2.0 * K / math.sqrt(MGL / I1), rel=1e-13)
    assert top.u1 == -1.0 and top.u2 == pytest.approx(math.cos(theta0), abs=1e-15)
    axis = top.axis_space(np.linspace(0.0, 3.0 * top.nutation_period, 301))
    normal = np.cross([0.0, 0.0, 1.0], R0[:, 2])
    assert np.max(np.abs(axis @ (normal / np.linalg.norm(normal)))) < 1e-13
    np.testing.assert_array_equal(top.omega_body(np.linspace(0, 10, 11))[:, 2], 0.0)


# ------------------------------------------------------------------------------------------
# API, helpers, input checks
# ------------------------------------------------------------------------------------------


def test_shapes_scalar_and_vector() -> None:
    top = HeavySymmetricTopExact(I1, I3, MGL, euler(0.3, 0.8, -0.2), [0.4, -0.3, 8.0])
    R, w = top(1.5)
    assert R.shape == (3, 3) and w.shape == (3,)
    Rs, ws = top(np.array([0.0, 1.5]))
    assert Rs.shape == (2, 3, 3) and ws.shape == (2, 3)
    np.testing.assert_array_equal(Rs[1], R)
    np.testing.assert_array_equal(top.attitude(1.5), R)
    np.testing.assert_array_equal(top.omega_body([1.5])[0], w)
    assert top.axis_space(1.5).shape == (3,)
    np.testing.assert_allclose(Rs[0], euler(0.3, 0.8, -0.2), atol=1e-15)
    np.testing.assert_allclose(ws[0], [0.4, -0.3, 8.0], atol=1e-14)
    assert 0.0 <= top.theta_min <= top.theta_max <= math.pi
    assert math.cos(top.theta_min) == pytest.approx(top.u2, abs=1e-15)


@pytest.mark.parametrize(
    "args",
    [
        (0.0, 1.0, 1.0, np.eye(3), [0, 0, 1]),
        (1.0, -1.0, 1.0, np.eye(3), [0, 0, 1]),
        (1.0, 1.0, -1.0, np.eye(3), [0, 0, 1]),
        (1.0, 1.0, 1.0, 2.0 * np.eye(3), [0, 0, 1]),
        (1.0, 1.0, 1.0, np.diag([1.0, 1.0, -1.0]), [0, 0, 1]),
        (1.0, 1.0, 1.0, np.eye(3), [0, np.nan, 1]),
        (1.0, 1.0, 1.0, np.eye(3), [0, 1]),
    ],
)
def test_rejects_bad_input(args) -> None:
    with pytest.raises(ValueError):
        HeavySymmetricTopExact(*args)


@pytest.mark.parametrize("m", [0.0, 0.3, 0.9, 0.999])
def test_jacobi_helper_matches_scipy(m: float) -> None:
    K = float(elliprf(0.0, 1.0 - m, 1.0))
    tau = np.linspace(-5.3 * K, 7.1 * K, 401)
    j, _, sn, cn, dn = _sncndn_reduced(tau, 0.0, m, 1.0 - m, K)
    sign = 1.0 - 2.0 * np.mod(j, 2.0)
    sn_ref, cn_ref, dn_ref, _ = ellipj(tau, m)
    np.testing.assert_allclose(sign * sn, sn_ref, atol=1e-14)
    np.testing.assert_allclose(sign * cn, cn_ref, atol=1e-14)
    np.testing.assert_allclose(dn, dn_ref, atol=1e-14)
    assert np.all(cn >= 0.0)


@pytest.mark.parametrize("m1", [1e-6, 1e-12, 1e-20])
def test_jacobi_helper_relative_precision_near_m_equal_1(m1: float) -> None:
    """With 1 - m given exactly, cn near K keeps its relative precision (mpmath, 60 digits)."""
    mpmath = pytest.importorskip("mpmath")
    K = float(elliprf(0.0, m1, 1.0))
    r = np.array([0.3, 0.4 * K, 0.5 * K, 0.8 * K, K - 1.0, K - 0.1])
    _, _, sn, cn, dn = _sncndn_reduced(r, 0.0, 1.0 - m1, m1, K)
    with mpmath.workdps(60):  # m = 1 - m1 must hold m1 to full precision
        m = 1 - mpmath.mpf(m1)
        for x, s, c, d in zip(r, sn, cn, dn):
            xm = mpmath.mpf(float(x))
            for got, kind in ((s, "sn"), (c, "cn"), (d, "dn")):
                exact = float(mpmath.ellipfun(kind, xm, m=m))
                # relative error ~K ulp, plus the rounding ulp(K) of the argument itself
                slope = float(mpmath.diff(lambda y, kind=kind: mpmath.ellipfun(kind, y, m=m), xm))
                assert abs(got - exact) <= 2e-15 * K * abs(exact) + abs(slope) * 4e-16 * K


# --- steady_precession_rate --------------------------------------------------------------------


def _theta_range_of_motion(I1: float, I3: float, mgl: float, spin: float, theta: float, phidot: float) -> float:
    """max |θ(t) - θ0| over 5 s, by solve_ivp on Ṙ = R hat(ω_b) and Euler's equations (no
    closed form, no code under test), started at ψ = 0 with θ̇ = 0:
    ω_b = (0, φ̇ sin θ, ω_z') (docs/CONVENTIONS.md, body components from Euler rates)."""
    model = Model((I1, I1, I3), mgl=mgl)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        R, w = y[:9].reshape(3, 3), y[9:]
        W = np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
        return np.concatenate([(R @ W).ravel(), omega_body_dot(model, t, R, w)])

    y0 = np.concatenate([euler(0.0, theta, 0.0).ravel(), [0.0, phidot * math.sin(theta), spin]])
    sol = solve_ivp(rhs, (0.0, 5.0), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=np.linspace(0.0, 5.0, 501))
    cos_theta = np.clip(sol.y[8], -1.0, 1.0)  # R[2, 2]
    return float(np.max(np.abs(np.arccos(cos_theta) - theta)))


@pytest.mark.parametrize(("theta", "spin"), [(1.0472, 12.0), (0.3, 20.0), (2.5, 15.0), (math.pi / 2, 8.0)])
def test_steady_precession_keeps_theta_constant(theta: float, spin: float) -> None:
    I1, I3, mgl = 1.0, 0.5, 6.0
    phidot = steady_precession_rate(I1, I3, mgl, spin, theta)
    assert _theta_range_of_motion(I1, I3, mgl, spin, theta, phidot) < 1e-8
    # a 10% different rate nods: the check above can fail
    assert _theta_range_of_motion(I1, I3, mgl, spin, theta, 0.9 * phidot) > 1e-4
    # it is the slow root of I1 cos θ φ̇² - I3 ω φ̇ + mgl = 0
    a, b = I1 * math.cos(theta), -I3 * spin
    assert a * phidot**2 + b * phidot + mgl == pytest.approx(0.0, abs=1e-12 * mgl)
    roots = np.roots([a, b, mgl]) if abs(a) > 1e-12 else np.array([phidot])
    assert abs(phidot) == pytest.approx(np.min(np.abs(roots)), rel=1e-12)


def test_steady_precession_fast_top_limit_and_no_root() -> None:
    I1, I3, mgl, theta = 1.0, 0.5, 6.0, 0.7
    for spin in (1e3, 1e5):
        rate = steady_precession_rate(I1, I3, mgl, spin, theta)
        # φ̇ = mgl/(I3 ω) (1 + O(I1 cos θ mgl / (I3 ω)²))
        assert rate == pytest.approx(mgl / (I3 * spin), rel=2 * I1 * math.cos(theta) * mgl / (I3 * spin) ** 2)
    with pytest.raises(ValueError, match="no steady precession"):
        steady_precession_rate(I1, I3, mgl, 1.0, 0.3)  # (I3 ω)² < 4 I1 cos θ mgl: too slow
    assert steady_precession_rate(I1, I3, mgl, -12.0, 1.0) == -steady_precession_rate(I1, I3, mgl, 12.0, 1.0)
