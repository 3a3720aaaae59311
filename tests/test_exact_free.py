"""Tests of physics.exact_free: Jacobi functions, the third-kind integral, FreeBodyExact.

Every reference is independent of the code under test:
* scipy.special (ellipj where it is accurate, m <= 0.9; ellipk, ellipkm1, ellipkinc, elliprf),
  identities, finite differences, and the small-m / small-(1-m) expansions of Abramowitz &
  Stegun 16.13, 16.15;
* scipy.integrate.quad for the third-kind integral;
* solve_ivp DOP853 (rtol = atol = 1e-13) on  Ṙ = R hat(ω_b),  I ω̇_b = (I ω_b) × ω_b;
* a Taylor-series integrator of the same equations in 80-bit long double (order 28), ~1e-18
  accurate, for the cases where DOP853 is not accurate enough (near the separatrix an error
  ε in the state is amplified by ~1/|δ|, δ = (|L|² - 2T I2)/|L|²: DOP853 and its own
  tighter/looser runs differ by ~5e-16/|δ|, so its tolerance below is written that way);
* closed forms: symmetric top (docs/CONVENTIONS.md), steady rotation R0 expm(t hat(ω)), the textbook
  flip half-period 2K(m)/λ (Landau & Lifshitz §37).

Figures measured when these tests were written (2-core machine): attitude error vs DOP853
<= 1.1e-12 rad over 20 s (DOP853's own error); vs the long-double reference <= 3e-15 rad;
at t = 1e4 s, 2.3e-12 rad; E and L_space conserved to ~1e-15 relative; 1e4 sample times
in ~5 ms (R and ω_b) or ~1 ms (ω_b only).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp
from scipy.linalg import expm
from scipy.spatial.transform import Rotation
from scipy.special import ellipj, ellipk, ellipkinc, ellipkm1, elliprf

from physics.euler import matrix_from_euler_zxz
from physics.exact_free import (
    FreeBodyExact,
    elliptic_k,
    jacobi_amplitude,
    jacobi_sn_cn_dn,
    jacobi_third_kind,
)

SETTINGS = settings(max_examples=100, deadline=None)
LD = np.longdouble
HAVE_LONG_DOUBLE = np.finfo(LD).eps < 1e-18  # x86-64: 80-bit; elsewhere long double may be double
needs_long_double = pytest.mark.skipif(not HAVE_LONG_DOUBLE, reason="needs 80-bit long double")

# --- references and helpers ----------------------------------------------------------------------


def hat(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def rotation_angle(Ra: np.ndarray, Rb: np.ndarray) -> np.ndarray:
    """Angle [rad] of Raᵀ Rb, (N,3,3) x (N,3,3) -> (N,) (accurate for small angles)."""
    Ra, Rb = np.asarray(Ra, dtype=float), np.asarray(Rb, dtype=float)
    rel = np.swapaxes(Ra, -1, -2) @ Rb
    return np.linalg.norm(Rotation.from_matrix(rel.reshape(-1, 3, 3)).as_rotvec(), axis=-1)


def dop853(I, R0, w0, t_eval, rtol=1e-13):
    """(R (N,3,3), ω_b (N,3)) from solve_ivp DOP853 at rtol = atol."""
    I = np.asarray(I, dtype=float)

    def f(_t, y):
        R, w = y[:9].reshape(3, 3), y[9:]
        return np.concatenate([(R @ hat(w)).ravel(), np.cross(I * w, w) / I])

    sol = solve_ivp(
        f,
        (t_eval[0], t_eval[-1]),
        np.concatenate([np.ravel(R0), w0]),
        method="DOP853",
        rtol=rtol,
        atol=rtol,
        t_eval=t_eval,
    )
    assert sol.success
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


def taylor_long_double(I, R0, w0, t_samples, h_max=0.2, order=28):
    """Taylor-series integration of Euler's equations and Ṙ = R hat(ω) in long double.

    Both right-hand sides are bilinear, so the Taylor coefficients follow from Cauchy products.
    Returns long-double arrays R (N,3,3), ω (N,3) at t_samples (increasing, t_samples[0] = 0)."""
    I = np.asarray(I, dtype=LD)
    c = np.array([(I[1] - I[2]) / I[0], (I[2] - I[0]) / I[1], (I[0] - I[1]) / I[2]], dtype=LD)
    R, w = np.asarray(R0, dtype=LD), np.asarray(w0, dtype=LD)
    out_R, out_w, t = [R.copy()], [w.copy()], 0.0
    for t_next in t_samples[1:]:
        n = max(1, int(np.ceil((t_next - t) / h_max)))
        h = (LD(t_next) - LD(t)) / n
        for _ in range(n):
            W = np.zeros((order + 1, 3), dtype=LD)
            Rc = np.zeros((order + 1, 3, 3), dtype=LD)
            W[0], Rc[0] = w, R
            for k in range(order):
                a, b = W[: k + 1], W[k::-1]
                W[k + 1] = (
                    c
                    * np.array([a[:, 1] @ b[:, 2], a[:, 2] @ b[:, 0], a[:, 0] @ b[:, 1]])
                    / (k + 1)
                )
                H = np.zeros((k + 1, 3, 3), dtype=LD)
                H[:, 0, 1], H[:, 0, 2], H[:, 1, 2] = -b[:, 2], b[:, 1], -b[:, 0]
                H[:, 1, 0], H[:, 2, 0], H[:, 2, 1] = b[:, 2], -b[:, 1], b[:, 0]
                Rc[k + 1] = np.einsum("iab,ibc->ac", Rc[: k + 1], H) / (k + 1)
            w, R = W[order].copy(), Rc[order].copy()
            for k in range(order - 1, -1, -1):
                w, R = w * h + W[k], R * h + Rc[k]
        t = t_next
        out_R.append(R.copy())
        out_w.append(w.copy())
    return np.array(out_R), np.array(out_w)


def random_rotation(seed: int) -> np.ndarray:
    return Rotation.random(random_state=seed).as_matrix()


def textbook_constants(I_sorted, w):
    """Landau & Lifshitz §37 for I1 < I2 < I3 (given in that order) and |L|² > 2T I2, or the
    mirrored formulas for |L|² < 2T I2: (m, 1 - m, λ) with ω2 = A2 sn(λ t + ...)."""
    I1, I2, I3 = I_sorted
    G, E2 = (
        float(np.sum((np.asarray(I_sorted) * w) ** 2)),
        float(np.sum(np.asarray(I_sorted) * w**2)),
    )
    # |L|² - 2T I2 = I1 (I1 - I2) ω1² + I3 (I3 - I2) ω3², summed exactly (it is a small
    # difference near the separatrix, and 1 - m is proportional to it)
    D = float(
        sum(
            Fraction(float(i))
            * (Fraction(float(i)) - Fraction(float(I2)))
            * Fraction(float(x)) ** 2
            for i, x in ((I1, w[0]), (I3, w[2]))
        )
    )
    if D > 0:
        lam = math.sqrt((I3 - I2) * (G - E2 * I1) / (I1 * I2 * I3))
        m = (I2 - I1) * (E2 * I3 - G) / ((I3 - I2) * (G - E2 * I1))
        m1 = (I3 - I1) * D / ((I3 - I2) * (G - E2 * I1))
    else:
        lam = math.sqrt((I2 - I1) * (E2 * I3 - G) / (I1 * I2 * I3))
        m = (I3 - I2) * (G - E2 * I1) / ((I2 - I1) * (E2 * I3 - G))
        m1 = (I3 - I1) * D / ((I2 - I1) * (G - E2 * I3))
    return m, m1, lam


# --- Jacobi elliptic functions -------------------------------------------------------------------


@pytest.mark.parametrize("m", [0.0, 1e-6, 0.1, 0.5, 0.75, 0.9])
def test_jacobi_matches_scipy_where_scipy_is_accurate(m):
    u = np.random.default_rng(0).uniform(-10.0, 10.0, 2000)
    sn, cn, dn = jacobi_sn_cn_dn(u, m)
    S, C, D, PH = ellipj(u, m)
    np.testing.assert_allclose(sn, S, rtol=0, atol=2e-14)
    np.testing.assert_allclose(cn, C, rtol=0, atol=2e-14)
    np.testing.assert_allclose(dn, D, rtol=0, atol=2e-14)
    np.testing.assert_allclose(jacobi_amplitude(u, m), PH, rtol=0, atol=2e-14)


@SETTINGS
@given(log_m1=st.floats(-300.0, 0.0), u=st.floats(-60.0, 60.0))
def test_jacobi_identities_hold_for_every_parameter(log_m1, u):
    """sn² + cn² = 1, dn² + m sn² = 1, and dn² = m1 + m cn² RELATIVE to dn² (that is where
    the relative accuracy of cn, dn near m = 1 shows)."""
    m1 = 10.0**log_m1
    m = 1.0 - m1
    sn, cn, dn = (float(x) for x in jacobi_sn_cn_dn(u, m, m1=m1))
    assert abs(sn * sn + cn * cn - 1.0) <= 8e-16  # 4 ulp of 1
    assert abs(dn * dn + m * sn * sn - 1.0) <= 8e-16
    assert abs(dn * dn - (m1 + m * cn * cn)) <= 4e-15 * dn * dn  # measured <= 2.2e-15


@pytest.mark.parametrize("m1", [0.9, 0.5, 1e-3, 1e-8, 1e-12])
def test_jacobi_derivatives_by_finite_differences(m1):
    """d sn/du = cn dn, d cn/du = -sn dn, d ln dn/du = -m sn cn/dn (4th-order differences)."""
    m = 1.0 - m1
    K = float(ellipkm1(m1))
    u = np.linspace(-2.2 * K, 2.2 * K, 401)
    h = 1e-3

    def d(f):
        return (-f(u + 2 * h) + 8 * f(u + h) - 8 * f(u - h) + f(u - 2 * h)) / (12 * h)

    sn, cn, dn = jacobi_sn_cn_dn(u, m, m1=m1)
    np.testing.assert_allclose(d(lambda x: jacobi_sn_cn_dn(x, m, m1=m1)[0]), cn * dn, atol=2e-10)
    np.testing.assert_allclose(d(lambda x: jacobi_sn_cn_dn(x, m, m1=m1)[1]), -sn * dn, atol=2e-10)
    # logarithmic derivative of dn: a relative check where dn is as small as sqrt(m1)
    dlog = d(lambda x: np.log(jacobi_sn_cn_dn(x, m, m1=m1)[2]))
    np.testing.assert_allclose(dlog, -m * sn * cn / dn, atol=1e-8)


def test_jacobi_small_m_limit():
    u = np.linspace(-5.0, 5.0, 101)
    sn, cn, dn = jacobi_sn_cn_dn(u, 0.0)
    np.testing.assert_allclose(sn, np.sin(u), atol=1e-15)
    np.testing.assert_allclose(cn, np.cos(u), atol=1e-15)
    np.testing.assert_array_equal(dn, 1.0)
    # A&S 16.13: first order in m; the neglected O(m²) is ~1e-16 here
    m = 1e-8
    s, c = np.sin(u), np.cos(u)
    g = 0.25 * m * (u - s * c)
    sn, cn, dn = jacobi_sn_cn_dn(u, m)
    np.testing.assert_allclose(sn, s - g * c, atol=1e-15)
    np.testing.assert_allclose(cn, c + g * s, atol=1e-15)
    np.testing.assert_allclose(dn, 1.0 - 0.5 * m * s * s, atol=1e-15)


def test_jacobi_m_near_one_limit():
    u = np.linspace(-3.0, 3.0, 61)
    th, sech = np.tanh(u), 1.0 / np.cosh(u)
    sn, cn, dn = jacobi_sn_cn_dn(u, 1.0)  # the separatrix: exact hyperbolic functions
    np.testing.assert_allclose(sn, th, rtol=0, atol=1e-16)
    np.testing.assert_allclose(cn, sech, rtol=1e-15)
    np.testing.assert_allclose(dn, sech, rtol=1e-15)
    # A&S 16.15: first order in m1 = 1 - m (O(m1² e^{4|u|}) ~ 1e-15 neglected)
    m1 = 1e-10
    g = 0.25 * m1 * (np.sinh(u) * np.cosh(u) - u)
    g2 = 0.25 * m1 * (np.sinh(u) * np.cosh(u) + u)
    sn, cn, dn = jacobi_sn_cn_dn(u, 0.0, m1=m1)
    np.testing.assert_allclose(sn, th + g * sech**2, rtol=0, atol=1e-15)
    np.testing.assert_allclose(cn, sech - g * th * sech, rtol=1e-14)
    np.testing.assert_allclose(dn, sech + g2 * th * sech, rtol=1e-14)


@pytest.mark.parametrize("m1", [1e-4, 1e-12, 1e-40, 1e-100, 1e-200, 1e-300])
def test_jacobi_relative_accuracy_at_half_period_near_separatrix(m1):
    """sn(K/2) = 1/√(1+k'), cn(K/2) = √(k'/(1+k')), dn(K/2) = √k' (k' = √m1): cn and dn are as
    small as m1^{1/4} and must keep ~14 digits.  K from scipy.special.ellipkm1; the rounding
    of K/2 alone allows a relative error ~ 1e-16 K."""
    K = float(ellipkm1(m1))
    kp = math.sqrt(m1)
    sn, cn, dn = (float(x) for x in jacobi_sn_cn_dn(0.5 * K, 0.0, m1=m1))
    rtol = 1e-14 + 2e-16 * K
    assert sn == pytest.approx(1.0 / math.sqrt(1.0 + kp), rel=rtol)
    assert cn == pytest.approx(math.sqrt(kp / (1.0 + kp)), rel=rtol)
    assert dn == pytest.approx(math.sqrt(kp), rel=rtol)


@pytest.mark.parametrize("m1", [1.0, 0.5, 0.1, 1e-3, 1e-9, 1e-16, 1e-100, 1e-300])
def test_elliptic_k_matches_scipy(m1):
    assert elliptic_k(1.0 - m1, m1=m1) == pytest.approx(float(ellipkm1(m1)), rel=2e-15)
    if m1 >= 0.1:
        assert elliptic_k(1.0 - m1) == pytest.approx(float(ellipk(1.0 - m1)), rel=2e-15)


@pytest.mark.parametrize("m1", [0.7, 0.2, 1e-6, 1e-12])
def test_jacobi_quasi_periodicity_and_amplitude(m1):
    m = 1.0 - m1
    K = float(ellipkm1(m1))
    u = np.linspace(-3 * K, 3 * K, 301)
    sn, cn, dn = jacobi_sn_cn_dn(u, m, m1=m1)
    sn2, cn2, dn2 = jacobi_sn_cn_dn(u + 2 * K, m, m1=m1)
    np.testing.assert_allclose(sn2, -sn, atol=1e-13)
    np.testing.assert_allclose(cn2, -cn, atol=1e-13)
    np.testing.assert_allclose(dn2, dn, atol=1e-13)
    am = jacobi_amplitude(u, m, m1=m1)
    np.testing.assert_allclose(jacobi_amplitude(u + 2 * K, m, m1=m1), am + math.pi, atol=1e-13)
    np.testing.assert_allclose(np.sin(am), sn, atol=1e-15)
    assert np.all(np.diff(am) > 0)  # continuous and increasing
    if m <= 0.9:  # F(am u | m) = u with scipy's incomplete integral of the first kind
        np.testing.assert_allclose(ellipkinc(am, m), u, atol=1e-13)


@pytest.mark.parametrize("m1", [1e-3, 1e-12, 1e-100])
def test_jacobi_inverse_by_carlson_near_separatrix(m1):
    """u = sn R_F(cn², dn², 1) on [0, K] (DLMF 19.25.5): the right side is sensitive to the
    relative accuracy of cn and dn where both are tiny (u → K)."""
    K = float(ellipkm1(m1))
    u = np.linspace(0.0, K, 201)
    sn, cn, dn = jacobi_sn_cn_dn(u, 0.0, m1=m1)
    np.testing.assert_allclose(
        sn * elliprf(cn**2, dn**2, 1.0), u, rtol=1e-14 + 1e-16 * K, atol=1e-300
    )


def _quad_third_kind(u, nu, m, m1):
    """∫_0^u du'/(1 - ν sn²u') by adaptive quadrature, split at the peaks sn = 0."""
    K = float(ellipkm1(m1))
    if m <= 0.9:
        f = lambda x: 1.0 / (1.0 - nu * ellipj(x, m)[0] ** 2)  # noqa: E731
    else:  # scipy.special.ellipj is not accurate near m = 1 (scipy issue 8480)
        f = lambda x: 1.0 / (1.0 - nu * float(jacobi_sn_cn_dn(x, m, m1=m1)[0]) ** 2)  # noqa: E731
    pts = [2 * k * K for k in range(-6, 7) if 0 < 2 * k * K < u]
    edges = [0.0, *pts, u]
    total = 0.0
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        total += quad(f, a, b, epsabs=1e-16, epsrel=2e-14, limit=400)[0]
    return total


@pytest.mark.parametrize("m1", [1.0, 0.5, 0.1, 1e-8, 1e-200])
@pytest.mark.parametrize("nu", [0.0, -1e-7, -0.4, -30.0, -1e4])
def test_third_kind_matches_quadrature(m1, nu):
    m = 1.0 - m1
    K = float(ellipkm1(m1))
    us = np.array([0.3, 0.5 * K, 0.9 * K, K, 1.7 * K, 4.6 * K])
    got = jacobi_third_kind(us, nu, m, m1=m1)
    ref = np.array([_quad_third_kind(u, nu, m, m1) for u in us])
    np.testing.assert_allclose(got, ref, rtol=1e-12)
    np.testing.assert_allclose(jacobi_third_kind(-us, nu, m, m1=m1), -got, rtol=1e-15)


def test_third_kind_on_separatrix_matches_quadrature():
    for nu in (0.0, -0.5, -50.0):
        for u in (0.4, 3.0, 30.0):
            ref = quad(lambda x, nu=nu: 1.0 / (1.0 - nu * math.tanh(x) ** 2), 0.0, u, epsrel=1e-14)[
                0
            ]
            assert float(jacobi_third_kind(u, nu, 1.0)) == pytest.approx(ref, rel=1e-13)


def test_jacobi_rejects_bad_parameters():
    with pytest.raises(ValueError):
        jacobi_sn_cn_dn(0.3, 1.5)
    with pytest.raises(ValueError):
        jacobi_sn_cn_dn(0.3, -0.1)
    with pytest.raises(ValueError):
        jacobi_third_kind(0.3, 0.5, 0.2)


# --- the free rigid body against DOP853 ----------------------------------------------------------

DOP_CASES = [
    # (inertia, omega0_body): generic, both sides of the separatrix, unsorted axes, symmetric
    # (oblate, prolate, unique axis x), nearly symmetric, lamina, near a principal axis
    ((1.0, 2.0, 3.0), (0.3, 1.0, 0.2)),
    ((1.0, 2.0, 3.0), (1.0, 0.2, 0.1)),
    ((3.0, 1.0, 2.0), (0.4, -0.3, 1.0)),
    ((2.0, 1.5, 1.0), (-0.2, 0.7, -1.1)),
    ((1.0, 1.0, 2.0), (0.5, 0.2, 1.0)),
    ((2.0, 2.0, 1.2), (0.5, 0.2, 1.0)),
    ((2.0, 1.0, 1.0), (0.5, 0.2, 1.0)),
    ((1.0, 1.0 + 1e-9, 2.0), (1.0, 0.3, 0.5)),
    ((1.0, 2.0 - 1e-9, 2.0), (1e-3, 0.3, 1.0)),
    ((2.0, 3.0, 4.0), (-1e-3, 1.0, 2e-3)),
    ((1.0, 2.0, 3.0), (1e-7, 1e-7, 2.0)),
]


@pytest.mark.parametrize(("inertia", "omega0"), DOP_CASES)
def test_matches_dop853(inertia, omega0):
    I, w0 = np.array(inertia), np.array(omega0)
    R0 = random_rotation(12)
    t = np.linspace(0.0, 20.0, 201)
    R_ref, w_ref = dop853(I, R0, w0, t)
    R, w = FreeBodyExact(I, R0, w0)(t)
    assert rotation_angle(R, R_ref).max() <= 1e-10
    assert np.abs(w - w_ref).max() <= 1e-10 * np.linalg.norm(w0)


def test_negative_times_match_dop853_backwards():
    I, w0, R0 = np.array([1.0, 2.0, 3.0]), np.array([0.3, 1.0, 0.2]), random_rotation(11)
    t = np.linspace(0.0, -15.0, 151)
    R_ref, w_ref = dop853(I, R0, w0, t)
    R, w = FreeBodyExact(I, R0, w0)(t)
    assert rotation_angle(R, R_ref).max() <= 1e-10
    assert np.abs(w - w_ref).max() <= 1e-10


LONG_DOUBLE_CASES = [
    ((1.0, 2.0, 3.0), (0.3, 1.0, 0.2)),
    ((5.0, 3.0, 2.5), (0.1, -0.2, -3.0)),
    ((1.0, 2.0 - 1e-9, 2.0), (1e-5, 0.3, 1.0)),  # |ν| ~ 1e9: slow ω, third kind by n -> m/n
    ((1.0, 1.0 + 1e-9, 2.0), (1.0, 1.0, 1e-6)),  # same, on the other side
    ((1.0, 1.0 + 1e-12, 2.0), (1.0, 0.5, 0.3)),  # m ~ 1e-12
    ((1.0, 2.0, 3.0), (3e-6, 1e-5, 2e-6)),  # tiny rates
    ((1.0, 2.0, 3.0), (3e3, 1e4, 2e3)),  # large rates
    ((1.0, 2.0, 3.0), (1e-100, 1.0, 1e-100)),  # |D|/|L|² ~ 1e-200: still no NaN, still exact
]


@needs_long_double
@pytest.mark.parametrize(("inertia", "omega0"), LONG_DOUBLE_CASES)
def test_matches_long_double_taylor_reference(inertia, omega0):
    I, w0 = np.array(inertia), np.array(omega0)
    R0 = random_rotation(7)
    speed = float(np.linalg.norm(w0))
    t = np.linspace(0.0, 10.0 / speed, 21)
    R_ref, w_ref = taylor_long_double(I, R0, w0, t, h_max=0.2 / speed)
    R, w = FreeBodyExact(I, R0, w0)(t)
    assert rotation_angle(R, R_ref.astype(float)).max() <= 5e-14  # measured <= 3e-15
    assert np.abs(w - w_ref.astype(float)).max() <= 1e-14 * speed


# --- conservation, Euler's equations, kinematics (property tests) --------------------------------


@st.composite
def bodies(draw):
    """(inertia (3,), R0, ω0): physical moments in any order (laminae included), any attitude,
    rates over six decades."""
    i1 = draw(st.floats(0.2, 3.0))
    i2 = draw(st.floats(0.2, 3.0))
    lam = draw(st.floats(0.0, 1.0))
    lo = max(abs(i1 - i2), 0.05)
    i3 = lo + lam * (i1 + i2 - lo)  # triangle inequality; lamina at lam = 1
    perm = draw(st.permutations([0, 1, 2]))
    inertia = np.array([i1, i2, i3])[list(perm)]
    q = np.array(draw(st.tuples(*[st.floats(-1.0, 1.0)] * 4)))
    if np.linalg.norm(q) < 1e-3:
        q = np.array([0.0, 0.0, 0.0, 1.0])
    R0 = Rotation.from_quat(q).as_matrix()
    direction = np.array(draw(st.tuples(*[st.floats(-1.0, 1.0)] * 3)))
    if np.linalg.norm(direction) < 1e-6:
        direction = np.array([0.0, 1.0, 0.0])
    speed = 10.0 ** draw(st.floats(-3.0, 3.0))
    return inertia, R0, speed * direction / np.linalg.norm(direction)


@SETTINGS
@given(body=bodies(), log_t=st.floats(-2.0, 4.0))
def test_energy_and_angular_momentum_are_conserved(body, log_t):
    I, R0, w0 = body
    exact = FreeBodyExact(I, R0, w0)
    speed = float(np.linalg.norm(w0))
    t = np.array([0.0, 0.37, 1.0, 3.3]) * 10.0**log_t / speed
    R, w = exact(t)
    L = np.einsum("nij,nj->ni", R, I * w)
    L0 = R0 @ (I * w0)
    energy = 0.5 * np.sum(I * w * w, axis=1)
    # measured <= 1.1e-15 relative over 3000 examples; the brief asks for 1e-13
    assert np.abs(L - L0).max() <= 1e-14 * np.linalg.norm(L0)
    assert np.abs(energy - exact.energy).max() <= 1e-14 * exact.energy
    assert np.abs(np.swapaxes(R, 1, 2) @ R - np.eye(3)).max() <= 4e-15  # measured <= 1.9e-15
    assert np.all(np.abs(np.linalg.det(R) - 1.0) <= 5e-15)  # det itself rounds; measured 2.4e-15
    np.testing.assert_allclose(exact(0.0)[0], R0, atol=2e-15)
    np.testing.assert_allclose(exact(0.0)[1], w0, atol=2e-15 * speed)


@SETTINGS
@given(body=bodies(), t0=st.floats(0.0, 50.0))
def test_euler_equations_and_kinematics_by_finite_differences(body, t0):
    """I ω̇ = (I ω) × ω and Rᵀ Ṙ = hat(ω), with 4th-order central differences (h = 1e-3/|ω|)."""
    I, R0, w0 = body
    exact = FreeBodyExact(I, R0, w0)
    speed = float(np.linalg.norm(w0))
    t0 = t0 / speed
    h = 1e-3 / speed
    ts = t0 + h * np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    R, w = exact(ts)
    stencil = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / (12.0 * h)
    w_dot = np.tensordot(stencil, w, axes=1)
    R_dot = np.tensordot(stencil, R, axes=1)
    np.testing.assert_allclose(w_dot, np.cross(I * w[2], w[2]) / I, atol=1e-8 * speed**2)
    np.testing.assert_allclose(R[2].T @ R_dot, hat(w[2]), atol=1e-8 * speed)


# --- closed forms --------------------------------------------------------------------------------


def symmetric_closed_form(I, R0, w0, axis, t):
    """docs/CONVENTIONS.md: I_⊥ = the two equal moments, e the symmetry axis.  In space the body turns
    about L at |L|/I_⊥; in the body ω turns about e at Ω = (I_e - I_⊥) ω_e / I_⊥:
    R(t) = exp(|L| t/I_⊥ hat(l)) R0 exp(-Ω t hat(e)),  ω_b(t) = exp(Ω t hat(e)) ω0."""
    I_perp, I_e = I[(axis + 1) % 3], I[axis]
    omega = (I_e - I_perp) * w0[axis] / I_perp
    L = R0 @ (I * w0)
    rate = np.linalg.norm(L) / I_perp
    e = np.eye(3)[axis]

    def rot(unit, angle):
        return Rotation.from_rotvec(math.remainder(angle, 2 * math.pi) * unit).as_matrix()

    R = np.array([rot(L / np.linalg.norm(L), rate * s) @ R0 @ rot(e, -omega * s) for s in t])
    w = np.array([rot(e, omega * s) @ w0 for s in t])
    return R, w


SYMMETRIC_CASES = [
    ((1.0, 1.0, 2.0), (0.5, 0.2, 1.0), 2),  # oblate, lamina
    ((2.0, 2.0, 1.0), (0.5, -0.2, 1.0), 2),  # prolate
    ((2.0, 1.0, 1.0), (0.5, 0.2, 1.0), 0),  # symmetry axis x
    ((1.0, 2.0, 2.0), (-0.5, 0.2, 1.0), 0),
    ((1.5, 0.7, 1.5), (0.1, 2.0, -0.3), 1),
]


@pytest.mark.parametrize(("inertia", "omega0", "axis"), SYMMETRIC_CASES)
def test_symmetric_body_matches_closed_form(inertia, omega0, axis):
    I, w0, R0 = np.array(inertia), np.array(omega0), random_rotation(3)
    t = np.array([0.0, 0.5, 3.0, 10.0, 100.0, 1000.0])
    R_ref, w_ref = symmetric_closed_form(I, R0, w0, axis, t)
    R, w = FreeBodyExact(I, R0, w0)(t)
    assert rotation_angle(R, R_ref).max() <= 2e-12
    assert np.abs(w - w_ref).max() <= 2e-12


@pytest.mark.parametrize("omega0", [(1.0, 0.3, 0.5), (1.0, 1.0, 1e-6), (0.2, -0.1, -2.0)])
def test_nearly_symmetric_degrades_smoothly_to_symmetric(omega0):
    """I = (1, 1 + ε, 2): the distance to the symmetric solution (ε = 0) is O(ε t), with no
    special case for equal moments, and ε = 1e-9 agrees to ~1e-8 over 10 s."""
    w0, R0 = np.array(omega0), random_rotation(4)
    t = np.linspace(0.0, 10.0, 41)
    R_sym, w_sym = symmetric_closed_form(np.array([1.0, 1.0, 2.0]), R0, w0, 2, t)
    for eps in (1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13, 0.0):
        R, w = FreeBodyExact(np.array([1.0, 1.0 + eps, 2.0]), R0, w0)(t)
        err = max(rotation_angle(R, R_sym).max(), np.abs(w - w_sym).max())
        assert err <= 20.0 * eps * t[-1] + 1e-12, eps
        if eps == 1e-9:
            assert err <= 1e-7


STEADY_CASES = [
    ((1.0, 2.0, 3.0), (0.0, 2.0, 0.0)),  # intermediate axis: steady (unstable)
    ((1.0, 2.0, 3.0), (-1.5, 0.0, 0.0)),
    ((3.0, 1.0, 2.0), (0.0, 0.0, 0.7)),
    ((1.0, 1.0, 2.0), (1.0, 2.0, 0.0)),  # symmetric, spin in the equatorial plane
    ((2.0, 1.0, 2.0), (1.0, 0.0, -2.0)),
    ((1.0, 1.0, 1.0), (1.0, 2.0, 3.0)),  # sphere
    ((1.0, 2.0, 3.0), (0.0, 0.0, 0.0)),  # at rest
]


@pytest.mark.parametrize(("inertia", "omega0"), STEADY_CASES)
def test_rotation_about_a_principal_axis_is_steady(inertia, omega0):
    I, w0, R0 = np.array(inertia), np.array(omega0), random_rotation(5)
    t = np.array([0.0, 0.3, 2.0, 50.0, 1234.5])
    R, w = FreeBodyExact(I, R0, w0)(t)
    np.testing.assert_array_equal(w, np.broadcast_to(w0, w.shape))
    speed = np.linalg.norm(w0)
    for Rk, s in zip(R, t, strict=True):
        angle = math.remainder(speed * s, 2 * math.pi)
        axis = w0 / speed if speed > 0 else w0
        np.testing.assert_allclose(Rk, R0 @ expm(angle * hat(axis)), atol=2e-14)


# --- the intermediate axis (Dzhanibekov) and the separatrix --------------------------------------


def test_dzhanibekov_flip_half_period():
    """I = (1, 2, 3), spin near y: ω_y flips sign every 2K(m)/λ.  Reference: the zero crossings
    of ω_y found by DOP853 event location, and the textbook formula with scipy's K."""
    I, w0 = np.array([1.0, 2.0, 3.0]), np.array([1e-3, 1.0, 2e-3])
    exact = FreeBodyExact(I, np.eye(3), w0)
    m, m1, lam = textbook_constants(I, w0)
    half = 2.0 * float(ellipkm1(m1)) / lam
    assert exact.m == pytest.approx(m, rel=1e-12)
    assert exact.omega_period / 2 == pytest.approx(half, rel=1e-12)

    def f(_t, w):
        return np.cross(I * w, w) / I

    def flip(_t, w):
        return w[1]

    sol = solve_ivp(f, (0.0, 3.3 * half), w0, method="DOP853", rtol=1e-13, atol=1e-13, events=flip)
    crossings = sol.t_events[0]
    assert len(crossings) == 3
    np.testing.assert_allclose(np.diff(crossings), half, rtol=1e-9)
    assert np.abs(exact.omega_body(crossings)[:, 1]).max() <= 1e-9
    # between crossings ω_y keeps one sign and reaches ∓|ω_y(0)|-ish values
    w = exact.omega_body(np.linspace(0.0, crossings[0], 50)[:-1])
    assert np.all(w[:, 1] > 0)


def near_separatrix_state(delta):
    """I = (1, 2, 3), ω at ω_y = 0 (far from the saddle) with (|L|² - 2T I2)/|L|² = δ."""
    w1 = math.sqrt((3.0 - 9.0 * delta) / (1.0 + delta))
    return np.array([1.0, 2.0, 3.0]), np.array([w1, 0.0, 1.0])


SEPARATRIX_DELTAS = [1e-2, -1e-2, 1e-4, -1e-6, 1e-8, -1e-10, 1e-12, -1e-12]


@pytest.mark.parametrize("delta", SEPARATRIX_DELTAS)
def test_near_separatrix_matches_dop853(delta):
    """Over one full flip and back (2.2 half periods).  The tolerance is DOP853's own: its
    rtol 1e-13 and 1e-12 runs differ by ~5e-16/|δ| (ill-conditioning near the saddle)."""
    I, w0 = near_separatrix_state(delta)
    R0 = random_rotation(6)
    exact = FreeBodyExact(I, R0, w0)
    G, E2 = np.sum((I * w0) ** 2), np.sum(I * w0**2)
    assert (G - E2 * I[1]) / G == pytest.approx(delta, rel=1e-6)
    t = np.linspace(0.0, 1.1 * exact.omega_period, 120)
    R_ref, w_ref = dop853(I, R0, w0, t)
    R, w = exact(t)
    tol = 1e-10 + 5e-15 / abs(delta)
    assert rotation_angle(R, R_ref).max() <= tol
    assert np.abs(w - w_ref).max() <= tol


@needs_long_double
@pytest.mark.parametrize("delta", SEPARATRIX_DELTAS)
def test_near_separatrix_matches_long_double_reference(delta):
    """The same, against the ~1e-19 long-double reference: agreement to 1e-12 + 1e-18/|δ|
    (the reference's own amplified rounding; measured ~8e-20/|δ|)."""
    I, w0 = near_separatrix_state(delta)
    R0 = random_rotation(6)
    exact = FreeBodyExact(I, R0, w0)
    t = np.linspace(0.0, 1.1 * exact.omega_period, 40)
    R_ref, w_ref = taylor_long_double(I, R0, w0, t)
    R, w = exact(t)
    tol = 1e-12 + 1e-18 / abs(delta)
    assert rotation_angle(R, R_ref.astype(float)).max() <= tol
    assert np.abs(w - w_ref.astype(float)).max() <= tol


# |L|² = 2T I2 exactly in binary floating point: I_a (I_b - I_a) ω_a² = I_c (I_c - I_b) ω_c²
SEPARATRIX_CASES = [
    ((3.0, 4.0, 6.0), (2.0, 0.3, 1.0)),
    ((3.0, 4.0, 6.0), (-2.0, 0.3, 1.0)),
    ((6.0, 3.0, 4.0), (1.0, -2.0, 0.3)),
    ((3.0, 6.0, 4.0), (2.0, -1.0, 0.0)),  # starts ON the separatrix with ω_b = 0
]


@needs_long_double
@pytest.mark.parametrize(("inertia", "omega0"), SEPARATRIX_CASES)
def test_exactly_on_separatrix(inertia, omega0):
    I, w0, R0 = np.array(inertia), np.array(omega0), random_rotation(8)
    exact = FreeBodyExact(I, R0, w0)
    assert exact.m == 1.0 and exact.omega_period == math.inf
    t = np.linspace(0.0, 12.0, 25)
    R_ref, w_ref = taylor_long_double(I, R0, w0, t)
    R, w = exact(t)
    assert rotation_angle(R, R_ref.astype(float)).max() <= 1e-13
    assert np.abs(w - w_ref.astype(float)).max() <= 1e-13
    R_far, w_far = exact(np.array([-1e4, 1e3, 1e4]))  # creeps to the intermediate axis, no NaN
    assert np.all(np.isfinite(R_far)) and np.all(np.isfinite(w_far))
    np.testing.assert_allclose(
        np.einsum("nij,nj->ni", R_far, I * w_far),
        np.broadcast_to(exact.L_space, (3, 3)),
        rtol=0,
        atol=1e-13 * np.linalg.norm(exact.L_space),
    )


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_separatrix_is_the_limit_of_both_sides(sign):
    """Continuity across the separatrix: δ = ±1e-15 agrees with δ = 0 for t ≤ 4 s (the two
    motions part only after the time ~ ln(1/δ)/λ it takes to reach the saddle)."""
    I, w0, R0 = np.array([3.0, 4.0, 6.0]), np.array([2.0, 0.3, 1.0]), random_rotation(9)
    t = np.linspace(0.0, 4.0, 41)
    R_sep, w_sep = FreeBodyExact(I, R0, w0)(t)
    w_near = w0 * np.array([1.0, 1.0, 1.0 + sign * 1e-15])
    near = FreeBodyExact(I, R0, w_near)
    assert 0.0 < 1.0 - near.m < 1e-13
    R, w = near(t)
    assert rotation_angle(R, R_sep).max() <= 1e-11
    assert np.abs(w - w_sep).max() <= 1e-11


# --- long times ----------------------------------------------------------------------------------


@needs_long_double
@pytest.mark.parametrize(
    ("inertia", "omega0"), [((1.0, 2.0, 3.0), (0.6, 0.8, 0.5)), ((2.5, 1.0, 2.0), (0.9, -0.3, 0.4))]
)
def test_long_times_against_monodromy(inertia, omega0):
    """t ~ 1e4 s.  ω_b has period T = 4K(m)/λ (textbook, scipy's K), so R(nT + τ) =
    exp(nΔ hat(l)) R(τ) with l = L/|L| and Δ the precession per period.  Δ and R(τ) come from
    the long-double reference over a single period, so the reference is ~1e-13 good at 1e4 s."""
    I, w0, R0 = np.array(inertia), np.array(omega0), random_rotation(10)
    order = np.argsort(I)
    m, m1, lam = textbook_constants(I[order], w0[order])
    T = 4.0 * float(ellipkm1(m1)) / lam
    exact = FreeBodyExact(I, R0, w0)
    assert exact.omega_period == pytest.approx(T, rel=1e-13)
    taus = np.array([0.0, 0.31 * T, 0.77 * T, T])
    R_tau, w_tau = taylor_long_double(I, R0, w0, taus)
    assert np.abs(w_tau[-1].astype(float) - w0).max() <= 1e-15  # T is the period
    l_unit = (R0 @ (I * w0)).astype(LD)
    l_unit /= np.sqrt(np.sum(l_unit * l_unit))
    M = R_tau[-1] @ R0.T.astype(LD)  # monodromy: rotation about l by Δ
    sin_d = 0.5 * (
        l_unit[0] * (M[2, 1] - M[1, 2])
        + l_unit[1] * (M[0, 2] - M[2, 0])
        + l_unit[2] * (M[1, 0] - M[0, 1])
    )
    cos_d = 0.5 * (M[0, 0] + M[1, 1] + M[2, 2] - 1)
    delta = np.arctan2(sin_d, cos_d)
    Kl = np.array(
        [[0, -l_unit[2], l_unit[1]], [l_unit[2], 0, -l_unit[0]], [-l_unit[1], l_unit[0], 0]],
        dtype=LD,
    )
    n = math.floor(1e4 / T)
    times, refs = [], []
    for k, tau in enumerate(taus[:3]):
        ang = np.remainder(LD(n - k) * delta, LD(2) * LD(math.pi))
        expo = np.eye(3, dtype=LD) + np.sin(ang) * Kl + (1 - np.cos(ang)) * (Kl @ Kl)
        times.append((n - k) * T + tau)
        refs.append((expo @ R_tau[k]).astype(float))
    R, w = exact(np.array(times))
    err = rotation_angle(R, np.array(refs))
    assert err.max() <= 2e-11  # the brief asks for 1e-10; measured 2.3e-12
    np.testing.assert_allclose(w, w_tau[:3].astype(float), atol=1e-12)


# --- API, shapes, speed, validation --------------------------------------------------------------


def test_shapes_and_call_consistency():
    exact = FreeBodyExact([1.0, 2.0, 3.0], np.eye(3), [0.3, 1.0, 0.2])
    R, w = exact(1.5)
    assert R.shape == (3, 3) and w.shape == (3,)
    t = np.linspace(0.0, 5.0, 7)
    R, w = exact(t)
    assert R.shape == (7, 3, 3) and w.shape == (7, 3)
    np.testing.assert_array_equal(exact.attitude(t), R)
    np.testing.assert_array_equal(exact.omega_body(t), w)
    np.testing.assert_allclose(exact.attitude(t[3]), R[3], atol=1e-15)
    steady = FreeBodyExact([1.0, 2.0, 3.0], np.eye(3), [0.0, 1.0, 0.0])
    assert steady.attitude(2.0).shape == (3, 3) and steady.omega_body(t).shape == (7, 3)


def test_euler_part_is_zxz_matrix():
    """The vectorised z-x-z product equals physics.euler.matrix_from_euler_zxz."""
    from physics.exact_free import _matrix_zxz

    rng = np.random.default_rng(1)
    phi, theta, psi = rng.uniform(-3, 3, 5), rng.uniform(0, 3, 5), rng.uniform(-3, 3, 5)
    M = _matrix_zxz(phi, np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi))
    for k in range(5):
        np.testing.assert_allclose(
            M[k], matrix_from_euler_zxz(phi[k], theta[k], psi[k]), atol=1e-15
        )


def test_ten_thousand_samples_at_once():
    """One vectorised call for 1e4 samples (its speed: benchmarks/physics_timings.py)."""
    exact = FreeBodyExact([1.0, 2.0, 3.0], random_rotation(1), [0.3, 1.0, 0.2])
    t = np.linspace(0.0, 1e4, 10_000)
    R, w = exact(t)
    assert R.shape == (10_000, 3, 3) and w.shape == (10_000, 3)
    assert np.all(np.isfinite(R)) and np.all(np.isfinite(w))
    R_last, w_last = exact(t[-1:])
    np.testing.assert_array_equal(R[-1:], R_last)


@pytest.mark.parametrize(
    ("inertia", "R0"),
    [
        ((0.0, 1.0, 1.0), np.eye(3)),
        ((1.0, 1.0, 3.0), np.eye(3)),
        ((1.0, 2.0, 3.0), np.diag([1.0, 1.0, -1.0])),
        ((1.0, 2.0, 3.0), 2.0 * np.eye(3)),
    ],
)
def test_rejects_bad_input(inertia, R0):
    with pytest.raises(ValueError):
        FreeBodyExact(inertia, R0, [1.0, 0.0, 0.0])
