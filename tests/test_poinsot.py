"""Poinsot's construction (physics.poinsot) and the "Poinsot" scene.

References, independent of the formulas under test: the two quadric equations themselves;
`physics.exact_free.FreeBodyExact` (Jacobi functions by Landen, written separately and tested
against mpmath in test_exact_free.py) for the motion, whose flips are found as sign changes of
ω_y by root bracketing; scipy's solve_ivp for the scene's motion.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

from physics import poinsot
from physics.euler import matrix_from_euler_zxz
from physics.exact_free import FreeBodyExact

QUADRIC_RTOL = 1e-9  # the brief's bound for points on the energy ellipsoid and the |L| sphere

BODIES = {  # (moments, ω_b(0)): every kind of body and both sides of the separatrix
    "dzhanibekov": ((0.3, 0.75, 1.0), (0.05, 5.0, 0.05)),
    "near separatrix, below": ((0.3, 0.75, 1.0), (0.01, 5.0, -0.0105)),
    "stable largest": ((0.3, 0.75, 1.0), (0.8, 0.8, 4.0)),
    "stable smallest": ((0.3, 0.75, 1.0), (5.0, 0.6, 0.6)),
    "disc": ((1.0, 1.0, 2.0), (1.5, 0.0, 4.0)),
    "nearly symmetric": ((1.0, 1.0 + 1e-6, 2.0), (1.5, 0.2, 4.0)),
    "flat lamina": ((0.4, 1.0, 1.4), (0.3, 4.0, 0.3)),
    "rod, I2 = I3": ((0.05, 1.0, 1.0), (3.0, 2.0, 1.0)),
    "axes in another order": ((1.0, 0.3, 0.75), (0.05, 0.2, 5.0)),
}


def _quadric_residuals(I: np.ndarray, T: float, L_norm: float, L: np.ndarray) -> tuple[float, float]:
    energy = np.sum(L * L / I, axis=-1)
    sphere = np.sum(L * L, axis=-1)
    return (float(np.max(np.abs(energy - 2.0 * T)) / (2.0 * T)),
            float(np.max(np.abs(sphere - L_norm**2)) / L_norm**2))


@pytest.mark.parametrize("name", list(BODIES))
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_polhode_points_lie_on_both_quadrics(name: str, sign: float) -> None:
    I, w = (np.array(x) for x in BODIES[name])
    T, L_norm = poinsot.invariants(I, w)
    L = poinsot.polhode_L(I, T, L_norm, 512, sign)
    assert L.shape == (512, 3)
    e, s = _quadric_residuals(I, T, L_norm, L)
    assert e < QUADRIC_RTOL and s < QUADRIC_RTOL, (name, e, s)
    omega = poinsot.polhode_omega(I, T, L_norm, 512, sign)  # on Poinsot's ellipsoid ω·Iω = 2T
    assert np.max(np.abs(np.sum(I * omega * omega, axis=1) - 2 * T)) / (2 * T) < QUADRIC_RTOL
    # The curve is the one the body follows: the exact solution's L_b comes within a point spacing.
    L_exact = I * FreeBodyExact(I, np.eye(3), w).omega_body(np.linspace(0.0, 3.0, 50))
    spacing = np.max(np.linalg.norm(np.diff(L, axis=0), axis=1))
    candidates = np.concatenate([L, poinsot.polhode_L(I, T, L_norm, 512, -sign)])  # one of the two is its side
    distance = np.min(np.linalg.norm(L_exact[:, None, :] - candidates[None], axis=2), axis=1)
    assert np.all(distance < spacing), name


def test_polhode_points_are_evenly_spaced_so_the_curve_is_smooth() -> None:
    I, w = (np.array(x) for x in BODIES["dzhanibekov"])
    L = poinsot.polhode_L(I, *poinsot.invariants(I, w), 256)
    steps = np.linalg.norm(np.diff(np.concatenate([L, L[:1]]), axis=0), axis=1)
    assert steps.max() < 1.05 * steps.mean()  # (chords of a dense arc-length sampling)


def test_the_separatrix_passes_through_plus_and_minus_L_on_the_intermediate_axis() -> None:
    I = np.array([0.3, 0.75, 1.0])
    L_norm = 3.0
    curves = poinsot.separatrix_L(I, L_norm, 400)
    T = L_norm**2 / (2 * I[1])
    for curve in curves:
        e, s = _quadric_residuals(I, T, L_norm, curve)
        assert e < QUADRIC_RTOL and s < QUADRIC_RTOL
        spacing = np.max(np.linalg.norm(np.diff(curve, axis=0), axis=1))
        for end in (np.array([0.0, L_norm, 0.0]), np.array([0.0, -L_norm, 0.0])):
            assert np.min(np.linalg.norm(curve - end, axis=1)) < 0.5 * spacing + 1e-12
        # Each separatrix curve is planar, through the intermediate axis: L_z / L_x constant.
        ratio = curve[:, 2] / curve[:, 0]
        big = np.abs(curve[:, 0]) > 0.1 * L_norm
        assert np.ptp(ratio[big]) < 1e-9
    # Two polhodes just either side of the separatrix circle different axes.
    above = poinsot.motion(I, T * (1 - 1e-6), L_norm)
    below = poinsot.motion(I, T * (1 + 1e-6), L_norm)
    assert (above.r, below.r) == (2, 0) and above.kind == below.kind == "flip"
    assert poinsot.motion(I, T, L_norm).kind == "separatrix"
    assert math.isinf(poinsot.motion(I, T, L_norm).flip_period)


def _contact_checks(I: np.ndarray, R: np.ndarray, w: np.ndarray, T: float, L_space: np.ndarray) -> None:
    normal, distance = poinsot.invariable_plane(L_space, T)
    point = poinsot.contact_point(R, w)
    assert normal @ point == pytest.approx(distance, rel=1e-12)  # on the invariable plane
    w_body = R.T @ point
    assert w_body @ (I * w_body) == pytest.approx(2 * T, rel=1e-12)  # on Poinsot's ellipsoid
    surface_normal = R @ (I * w_body)  # gradient of ω·Iω/2: the ellipsoid is tangent to the plane
    assert np.linalg.norm(np.cross(surface_normal / np.linalg.norm(surface_normal), normal)) < 1e-12
    np.testing.assert_allclose(point, R @ w, rtol=1e-15)  # ω (from the centre) ends at the point


@pytest.mark.parametrize("name", ["dzhanibekov", "flat lamina", "nearly symmetric", "stable smallest"])
def test_the_contact_point_is_omega_on_the_plane_and_on_the_ellipsoid(name: str) -> None:
    I, w0 = (np.array(x) for x in BODIES[name])
    R0 = matrix_from_euler_zxz(0.3, 1.1, -0.4)
    exact = FreeBodyExact(I, R0, w0)
    R, w = exact(np.linspace(0.0, 20.0, 41))
    for k in range(R.shape[0]):
        _contact_checks(I, R[k], w[k], exact.energy, exact.L_space)


@pytest.mark.parametrize("name", ["dzhanibekov", "near separatrix, below", "flat lamina", "nearly symmetric",
                                  "stable largest", "disc", "rod, I2 = I3"])
def test_the_herpolhode_stays_between_its_two_radii_and_reaches_both(name: str) -> None:
    I, w0 = (np.array(x) for x in BODIES[name])
    exact = FreeBodyExact(I, matrix_from_euler_zxz(0.3, 1.1, -0.4), w0)
    T, L_norm = exact.energy, float(np.linalg.norm(exact.L_space))
    rho_min, rho_max = poinsot.herpolhode_radii(I, T, L_norm)
    period = poinsot.motion(I, T, L_norm).polhode_period
    t = np.linspace(0.0, 3.0 * period, 20001)
    R, w = exact(t)
    normal, distance = poinsot.invariable_plane(exact.L_space, T)
    points = np.einsum("nij,nj->ni", R, w)
    rho = np.linalg.norm(points - distance * normal, axis=1)
    tol = 1e-9 * max(rho_max, 1e-300)
    assert np.all(rho >= rho_min - tol) and np.all(rho <= rho_max + tol), (rho.min(), rho_min, rho.max(), rho_max)
    assert rho.max() == pytest.approx(rho_max, rel=1e-3) and rho.min() == pytest.approx(rho_min, rel=1e-3, abs=1e-9)


def _flips_of(exact: FreeBodyExact, axis: int, t_end: float, dt: float = 0.01) -> np.ndarray:
    """Sign changes of ω_axis of the exact solution in (0, t_end), each bracketed on a grid of
    step dt and refined by brentq to 1e-13 s (no use of any period formula)."""
    t = np.arange(0.0, t_end, dt)
    w = exact.omega_body(t)[:, axis]
    roots = []
    for k in np.nonzero(np.sign(w[:-1]) * np.sign(w[1:]) < 0)[0]:
        roots.append(brentq(lambda s: float(exact.omega_body(s)[axis]), t[k], t[k + 1], xtol=1e-13, rtol=1e-15))
    return np.array(roots)


@pytest.mark.parametrize("name", ["dzhanibekov", "near separatrix, below", "flat lamina", "stable largest",
                                  "stable smallest", "axes in another order"])
def test_the_flip_period_is_the_exact_solutions_flip_interval_over_many_flips(name: str) -> None:
    I, w0 = (np.array(x) for x in BODIES[name])
    exact = FreeBodyExact(I, matrix_from_euler_zxz(0.2, 0.9, 0.1), w0)
    T, L_norm = poinsot.invariants(I, w0)
    mo = poinsot.motion(I, T, L_norm)
    q = int(np.argsort(I)[1])  # the intermediate axis
    assert mo.q == q and mo.kind == "flip"
    flips = _flips_of(exact, q, 25.0 * mo.flip_period + 0.5)
    assert len(flips) >= 25
    intervals = np.diff(flips)
    np.testing.assert_allclose(intervals, mo.flip_period, rtol=1e-9)
    # The next flip from the state at t = 0 and at later times, and the schedule of flip_times.
    assert poinsot.time_to_next_flip(I, w0) == pytest.approx(flips[0], rel=1e-9, abs=1e-10)
    for t in (0.37 * mo.flip_period, 3.5 * mo.flip_period):
        upcoming = flips[flips > t][0]
        assert t + poinsot.time_to_next_flip(I, exact.omega_body(t)) == pytest.approx(upcoming, rel=1e-9)
    np.testing.assert_allclose(poinsot.flip_times(I, w0, 0.0, 0.0, flips[-1] + 1e-6), flips, rtol=1e-9)


def test_no_flips_for_steady_rotation_and_the_separatrix_and_circles_for_a_symmetric_body() -> None:
    I = np.array([0.3, 0.75, 1.0])
    assert math.isinf(poinsot.time_to_next_flip(I, np.array([0.0, 0.0, 3.0])))
    assert poinsot.motion(I, *poinsot.invariants(I, np.array([0.0, 0.0, 3.0]))).kind == "steady"
    disc = poinsot.motion(np.array([1.0, 1.0, 2.0]), *poinsot.invariants(np.array([1.0, 1.0, 2.0]),
                                                                         np.array([1.5, 0.0, 4.0])))
    assert disc.kind == "symmetric" and disc.m == 0.0
    assert disc.flip_period == pytest.approx(math.pi / ((2.0 - 1.0) / 1.0 * 4.0), rel=1e-12)  # π/λ, λ = ΔI/I1 ω3
    L = poinsot.polhode_L(np.array([1.0, 1.0, 2.0]), disc.T, disc.L_norm, 64)
    np.testing.assert_allclose(np.hypot(L[:, 0], L[:, 1]), 1.5, rtol=1e-12)  # a circle about z′
    assert poinsot.herpolhode_radii(np.array([1.0, 1.0, 2.0]), disc.T, disc.L_norm)[0] == pytest.approx(
        poinsot.herpolhode_radii(np.array([1.0, 1.0, 2.0]), disc.T, disc.L_norm)[1], rel=1e-12)


@pytest.mark.parametrize(("args", "message"), [
    (((0.3, 0.75, 1.0), 1.0, 10.0), "must lie between"),
    (((0.3, 0.75, 1.0), -1.0, 1.0), "T > 0"),
    (((0.3, 0.75, 1.0), 1.0, math.nan), "T > 0"),
    (((0.3, 0.3, 1.0), 1.0, 1.0), "triangle inequality"),
    (((0.0, 0.75, 1.0), 1.0, 1.0), "positive"),
])
def test_bad_input_is_refused_with_a_message(args, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        poinsot.motion(np.array(args[0]), args[1], args[2])


# ---------------------------------------------------------------------------- the scene
def _pose(handle) -> np.ndarray:  # type: ignore[no-untyped-def]
    return Rotation.from_quat(np.asarray(handle.wxyz), scalar_first=True).as_matrix()


def test_the_scene_draws_omega_to_the_contact_point_on_the_plane_and_the_ellipsoid(manual) -> None:
    from app.scenes.poinsot import PoinsotView

    session = manual.session
    session.select_scene("Poinsot")
    view = session.scene
    assert isinstance(view, PoinsotView) and view.title == "Poinsot"
    for preset in PoinsotView.presets():
        session.apply_preset(preset.name)
        session.play()
        manual.tick(0.7)
        session.pause()  # a refresh draws exactly (a playing frame at display resolution)
        sim = view.sim
        R = _pose(view.body.node)
        np.testing.assert_allclose(R, sim.state.R_space_body, atol=1e-6)
        start, contact = view.omega.segment  # the contact point hangs at ω's tip: ω runs from the centre to it
        assert view.contact._impl.name == f"{view.root}/w/t/contact" and view.contact.visible
        scale = view.omega_scale
        np.testing.assert_allclose(contact, R @ sim.state.omega_body * scale, atol=1e-5)
        np.testing.assert_allclose(start, 0.0, atol=1e-6)
        semi = np.asarray(view.ellipsoid.scale, dtype=float)  # the unit sphere's scale: the semi-axes
        local = R.T @ contact  # the ellipsoid is a child of the body's frame
        assert np.sum((local / semi) ** 2) == pytest.approx(1.0, abs=1e-5), preset.name
        n = _pose(view.plane)[:, 2]
        assert n @ (contact - np.asarray(view.plane.position)) == pytest.approx(0.0, abs=1e-5)
        assert np.allclose(n, [0.0, 0.0, -1.0], atol=1e-6)  # presets put L along −z: a table below
    assert session.error_count == 0, session.last_error


def test_the_readout_gives_the_flip_period_and_the_next_flip(manual) -> None:
    session = manual.session
    session.select_scene("Poinsot")
    session.apply_preset("Dzhanibekov")
    view = session.scene
    I = np.array(view.sim.model.inertia)
    w0 = view.sim.initial_state.omega_body
    exact = FreeBodyExact(I, view.sim.initial_state.R_space_body, w0)
    flips = _flips_of(exact, 1, 12.0)
    text = view.poinsot_readout.handle.content
    assert f"flip period 2K(m)/λ = {np.diff(flips).mean():.4f} s" in text
    assert f"next flip at t = {flips[0]:.3f} s" in text
    session.play()
    manual.tick(flips[0] + 0.3)  # past the first flip: the readout moves to the second
    assert f"next flip at t = {flips[1]:.3f} s" in view.poinsot_readout.handle.content


def test_the_energy_slider_crosses_the_separatrix_keeping_L_and_refuses_what_is_no_motion(manual) -> None:
    session = manual.session
    session.select_scene("Poinsot")
    session.apply_preset("Dzhanibekov")
    view = session.scene
    sim = view.sim
    I = np.array(sim.model.inertia)
    L_space = sim.state.R_space_body @ (I * sim.state.omega_body)
    for setting, axis in ((-0.5, 0), (0.5, 2)):
        manual.client.set_value(view.gui_energy, setting)
        manual.wait(lambda s=setting: sim.restarts and view.gui_energy.value == s and sim.t == 0.0
                    and abs(poinsot.invariants(I, sim.state.omega_body)[1] ** 2 / (2 * poinsot.invariants(
                        I, sim.state.omega_body)[0]) - (0.75 + s * (0.45 if s < 0 else 0.25))) < 1e-9)
        T, L_norm = poinsot.invariants(I, sim.state.omega_body)
        assert poinsot.motion(I, T, L_norm).r == axis  # now circling x′ (−) or z′ (+)
        np.testing.assert_allclose(sim.state.R_space_body @ (I * sim.state.omega_body), L_space, rtol=1e-9,
                                   atol=1e-9)  # the same L in space
    manual.client.set_value(view.gui_energy, 7.0)
    manual.wait(lambda: "refused" in view.message.text)
    session.apply_preset("Symmetric disc")
    view.set_energy(-0.5)
    assert "two equal moments" in view.message.text
