"""The "Moving frame" scene: its physics against references that do not use the code under test,
its refusals, its rider's view, and (marked `browser`) the camera toggle in Chromium.

References: the frame's motion is rebuilt here from the preset's numbers with SciPy's
`Rotation.from_euler("ZXZ")` and the closed form of the line, never from
`physics.moving_frames`; velocities and accelerations come from 5-point central differences;
the spring particle's reference path from scipy's DOP853 at rtol 1e-12.  Tolerances are
written next to each check.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation
from test_browser import choose

from app.kit.core.presets import PresetError, load_presets
from app.kit.draw.lean import TOLERANCE
from app.scenes.moving_frame import (
    KEYS,
    PARAM_SPECS,
    PARTICLES,
    MovingFrameSetup,
    MovingFrameSimulation,
    MovingFrameView,
)
from physics.moving_frames import FrameMotion, omega_dot_body_from_euler

DT = 1.0 / 60.0
PRESETS = {preset.name: preset for preset in MovingFrameView.presets()}
FREE, REST, SPRING = range(3)


# ---------------------------------------------------------------------------- an independent reference
class Reference:
    """C′'s motion rebuilt from a preset's numbers (SciPy rotations, no physics.moving_frames)."""

    def __init__(self, params: tuple[float, ...], angles_deg: tuple[float, float, float]) -> None:
        self.p = dict(zip(KEYS, params))
        self.angles0 = np.radians(angles_deg)

    def R(self, t: float) -> np.ndarray:
        p = self.p
        rates = np.radians([p["phi_dot"], p["theta_dot"], p["psi_dot"]])
        accels = np.radians([p["phi_ddot"], 0.0, 0.0])
        tau = min(t, p["spin_up"])  # the speeding up stops after spin_up seconds
        return Rotation.from_euler("ZXZ", self.angles0 + rates * t + accels * (tau * t - 0.5 * tau * tau)).as_matrix()

    def a(self, t: float) -> np.ndarray:
        A, W = self.p["line_accel"], self.p["line_omega"]
        s = A * (1.0 - math.cos(W * t)) / W**2 if W > 0 else 0.5 * A * t * t
        return np.array([s, 0.0, 0.0]) + self.R(t) @ np.array([0.0, 0.0, self.p["offset"]])

    def to_space(self, t: float, x_body: np.ndarray) -> np.ndarray:
        return self.a(t) + self.R(t) @ x_body

    def to_body(self, t: float, x: np.ndarray) -> np.ndarray:
        return self.R(t).T @ (x - self.a(t))


def d1(f, t: float, h: float = 1e-3) -> np.ndarray:  # type: ignore[no-untyped-def]
    """5-point first derivative: error ~h⁴ f⁽⁵⁾/30 + eps/h ≈ 1e-12 here."""
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h)


def d2(f, t: float, h: float = 2e-3) -> np.ndarray:  # type: ignore[no-untyped-def]
    """5-point second derivative: error ~h⁴ f⁽⁶⁾/90 + 16 eps |f| / (12 h²) ≈ 1e-10 here."""
    return (-f(t - 2 * h) + 16 * f(t - h) - 30 * f(t) + 16 * f(t + h) - f(t + 2 * h)) / (12 * h * h)


def initial_space_state(ref: Reference, x_body: np.ndarray, v_body: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """x, ẋ in C at t = 0 of a particle at x′ with velocity ẋ′ relative to C′ (by differences)."""
    R0 = ref.R(0.0)
    return ref.to_space(0.0, x_body), d1(lambda t: ref.to_space(t, x_body), 0.0) + R0 @ v_body


def spring_reference(ref: Reference, t_eval: np.ndarray) -> np.ndarray:
    """The spring particle's path in C (N, 3) by DOP853 at rtol 1e-12, F = −k (x − anchor(t))."""
    p = ref.p
    anchor = np.array([p["anchor_x"], p["anchor_y"], 0.0])
    start = anchor + np.array([p["stretch_x"], p["stretch_y"], 0.0])
    x0, v0 = initial_space_state(ref, start, np.zeros(3))

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([y[3:], -p["k"] / p["mass"] * (y[:3] - ref.to_space(t, anchor))])

    sol = solve_ivp(rhs, (0.0, float(t_eval[-1])), np.concatenate([x0, v0]), method="DOP853",
                    rtol=1e-12, atol=1e-12, t_eval=t_eval)
    assert sol.success
    return sol.y[:3].T


def simulation(name: str) -> MovingFrameSimulation:
    preset = PRESETS[name]
    return MovingFrameSimulation(MovingFrameSetup(preset.params, preset.angles_deg))


def play(sim: MovingFrameSimulation, seconds: float, dt: float = DT) -> None:
    for _ in range(int(round(seconds / dt))):
        sim.advance(dt)


# ---------------------------------------------------------------------------- physics
@pytest.mark.parametrize("name", ["Earth, 45° N", "Top frame", "Speeding up", "Accelerating line"])
@pytest.mark.parametrize("particle", [FREE, SPRING])
def test_real_plus_inertial_forces_equal_m_x_ddot_from_differences_of_the_path_in_C_prime(
    name: str, particle: int
) -> None:
    """(1.28): Dᵀ F + the four inertial forces = m ẍ′, with ẍ′ the second difference of the
    reference path x′(t) = Dᵀ(t) (x(t) − a(t)) (free: x(t) a straight line, or at rest in C′
    where the rim stopped it; spring: DOP853)."""
    preset = PRESETS[name]
    ref = Reference(preset.params, preset.angles_deg)
    sim = simulation(name)
    mass = ref.p["mass"]
    h = 2e-3
    for t in (1.0, 2.5):
        play(sim, t - sim.t, dt=t - sim.t)  # one call: sub-stepped at H_MAX inside
        stencil = t + h * np.arange(-2, 3)
        if particle == FREE and sim.caught_at is not None:  # stopped by the rim: at rest in C′ there
            path = {float(s): ref.to_space(float(s), sim.caught_at) for s in stencil}
        elif particle == FREE:
            x0, v0 = initial_space_state(ref, np.array([ref.p["free_x"], ref.p["free_y"], 0.0]),
                                         np.array([ref.p["free_vx"], ref.p["free_vy"], 0.0]))
            path = {float(s): x0 + v0 * s for s in stencil}
        else:
            path = dict(zip((float(s) for s in stencil), spring_reference(ref, stencil)))
        x_body = {s: ref.to_body(s, x) for s, x in path.items()}
        expected = mass * d2(lambda s, xb=x_body: xb[float(s)], t, h)
        report = sim.forces()
        got = report.real[particle] + report.inertial.total[particle]
        scale = max(1.0, float(np.max(np.abs(expected))))
        # FD truncation ~1e-10, rounding 16 eps |x′| / (12 h²) ~ 1e-9, DOP853 vs RK4 ~1e-9 m x k/m.
        np.testing.assert_allclose(got, expected, atol=1e-6 * scale, err_msg=f"{name}, t = {t}")
        # and the readout's own m ẍ′ (matrix route) agrees with the sum to rounding
        np.testing.assert_allclose(report.m_x_ddot_body, report.real + report.inertial.total, atol=1e-12 * scale)
        assert np.max(np.abs(report.residual)) < 1e-12 * scale


@pytest.mark.parametrize("name", list(PRESETS))
def test_the_free_particle_moves_on_a_straight_line_in_C_at_constant_velocity(name: str) -> None:
    """Until the disc's rim stops it: a uniform straight line in C (curved in a turning C′); from
    then on at rest in C′ where it stopped, at the rim's distance."""
    sim = simulation(name)
    x0, v0 = sim.x[FREE].copy(), sim.v[FREE].copy()
    ts, xs, xs_body, caught = [], [], [], []
    for _ in range(6 * 60):
        sim.advance(DT)
        if sim.caught_at is not None:
            caught.append(sim.body_coordinates()[0][FREE])
            continue
        ts.append(sim.t)
        xs.append(sim.x[FREE].copy())
        xs_body.append(sim.body_coordinates()[0][FREE])
    assert len(ts) >= 30, "it slides for half a second at least"
    xs_arr = np.array(xs)
    # RK4 is exact for ẍ = 0: the uniform straight line x0 + v0 t to rounding (|x| < 20 m).
    np.testing.assert_allclose(xs_arr, x0 + np.outer(ts, v0), atol=1e-12)
    # Independently of v0: every point lies on the line through the first and last (to 1e-12 m);
    # on the accelerating line the free particle starts at rest in C and the "line" is a point.
    length = float(np.linalg.norm(xs_arr[-1] - xs_arr[0]))
    if length < 1e-9:
        assert np.max(np.abs(xs_arr - xs_arr[0])) < 1e-12
    else:
        chord = (xs_arr[-1] - xs_arr[0]) / length
        offsets = (xs_arr - xs_arr[0]) - np.outer((xs_arr - xs_arr[0]) @ chord, chord)
        assert np.max(np.linalg.norm(offsets, axis=1)) < 1e-12
    # ... while in a turning C′ the rider sees it curve (by decimetres, not rounding).
    if name in ("Turntable", "Speeding up", "Earth, 45° N", "Top frame"):
        body = np.array(xs_body)
        chord_b = (body[-1] - body[0]) / np.linalg.norm(body[-1] - body[0])
        bent = (body - body[0]) - np.outer((body - body[0]) @ chord_b, chord_b)
        assert np.max(np.linalg.norm(bent, axis=1)) > 0.1
    if caught:  # stopped at the rim's distance, and held at rest in C′ there (as the rider is)
        assert sim.caught_at is not None
        assert float(np.linalg.norm(sim.caught_at)) == pytest.approx(sim.setup.value("disc_radius"), rel=1e-12)
        assert np.max(np.abs(np.array(caught) - sim.caught_at)) < 1e-8


def test_the_free_particle_starts_with_the_velocity_given_relative_to_C_prime() -> None:
    """x(0), ẋ(0) = what the reference makes of x′₀, ẋ′₀ (ȧ and ω from differences)."""
    for name, preset in PRESETS.items():
        ref = Reference(preset.params, preset.angles_deg)
        sim = simulation(name)
        x0, v0 = initial_space_state(ref, np.array([ref.p["free_x"], ref.p["free_y"], 0.0]),
                                     np.array([ref.p["free_vx"], ref.p["free_vy"], 0.0]))
        np.testing.assert_allclose(sim.x[FREE], x0, atol=1e-12, err_msg=name)
        np.testing.assert_allclose(sim.v[FREE], v0, atol=1e-9, err_msg=name)  # 5-point FD, h = 1e-3


@pytest.mark.parametrize("name", list(PRESETS))
def test_a_particle_held_at_rest_in_C_prime_stays_at_rest(name: str) -> None:
    """Integrated in C under F = m × (the acceleration of its point of C′): over 10 s it stays
    within 1e-8 m of its place and its ẋ′ below 1e-8 m/s (RK4 at h = 1/240 s)."""
    sim = simulation(name)
    start = np.array([sim.setup.value("rider_x"), sim.setup.value("rider_y"), 0.0])
    ref = Reference(sim.setup.params, sim.setup.angles_deg)
    worst_x = worst_v = 0.0
    for _ in range(10 * 60):
        sim.advance(DT)
        x_body, v_body = sim.body_coordinates()
        worst_x = max(worst_x, float(np.max(np.abs(x_body[REST] - start))))
        worst_v = max(worst_v, float(np.max(np.abs(v_body[REST]))))
    assert worst_x < 1e-8 and worst_v < 1e-8, (worst_x, worst_v)
    # checked against the reference frame too, not only the code's own x′
    np.testing.assert_allclose(ref.to_body(sim.t, sim.x[REST]), start, atol=1e-8)


@pytest.mark.parametrize("name", ["Earth, 45° N", "Top frame", "Turntable"])
def test_rk4_follows_dop853_for_the_spring_particle(name: str) -> None:
    """The accuracy the module docstring states: within 3e-8 m of DOP853 (rtol 1e-12) over 10 s
    (measured: 1.1e-8 m on the top frame, k = 20 N/m in a fast frame; ~5e-10 m on the others)."""
    preset = PRESETS[name]
    ref = Reference(preset.params, preset.angles_deg)
    sim = simulation(name)
    times = np.arange(1, 11, dtype=float)
    expected = spring_reference(ref, times)
    for k, t in enumerate(times):
        play(sim, t - sim.t)
        assert np.max(np.abs(sim.x[SPRING] - expected[k])) < 3e-8, (name, t)


@pytest.mark.parametrize("seed", range(5))
def test_frame_motion_matches_the_reference_and_its_differences(seed: int) -> None:
    """FrameMotion.at: R and a against SciPy; ȧ, ä, ω_b = vee(Rᵀ Ṙ), ω̇_b against differences."""
    rng = np.random.default_rng(seed)
    angles0, rates, accels = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3), rng.uniform(-1, 1, 3)
    b = rng.uniform(-1, 1, 3)
    A, W = rng.uniform(-1, 1), rng.uniform(0.1, 2)
    motion = FrameMotion(tuple(angles0), tuple(rates), tuple(accels), tuple(b), (1.0, 0.0, 0.0), A, W)

    def R(t: float) -> np.ndarray:
        return Rotation.from_euler("ZXZ", angles0 + rates * t + 0.5 * accels * t * t).as_matrix()

    def a(t: float) -> np.ndarray:
        return np.array([A * (1 - math.cos(W * t)) / W**2, 0.0, 0.0]) + R(t) @ b

    def omega_body(t: float) -> np.ndarray:
        W_hat = R(t).T @ d1(R, t)
        return np.array([W_hat[2, 1], W_hat[0, 2], W_hat[1, 0]])

    t = float(rng.uniform(0, 3))
    state = motion.at(t)
    np.testing.assert_allclose(state.R_space_body, R(t), atol=1e-14)
    np.testing.assert_allclose(state.a, a(t), atol=1e-12)
    np.testing.assert_allclose(state.a_dot, d1(a, t), atol=1e-9)
    np.testing.assert_allclose(state.a_ddot, d2(a, t), atol=1e-7)
    np.testing.assert_allclose(state.omega_body, omega_body(t), atol=1e-9)
    np.testing.assert_allclose(state.omega_dot_body, d1(omega_body, t, h=1e-2), atol=1e-6)
    np.testing.assert_allclose(
        omega_dot_body_from_euler(motion.angles(t), motion.angle_rates(t), accels), state.omega_dot_body,
        atol=1e-15)


def test_uniform_acceleration_is_the_limit_of_the_line() -> None:
    s, s_dot, s_ddot = FrameMotion(line_accel=0.7, line_omega=0.0).line(2.0)
    assert (s, s_dot, s_ddot) == pytest.approx((0.5 * 0.7 * 4.0, 1.4, 0.7), rel=1e-15)
    s, s_dot, _ = FrameMotion(line_accel=0.7, line_omega=1e-9).line(2.0)
    assert s == pytest.approx(1.4, rel=1e-12) and s_dot == pytest.approx(1.4, rel=1e-12)


# ---------------------------------------------------------------------------- bad input
def test_bad_setups_are_refused_with_a_message() -> None:
    good = PRESETS["Turntable"]
    params = list(good.params)
    params[KEYS.index("k")] = -1.0
    with pytest.raises(ValueError, match=r"spring constant k \[N/m\] = -1\.0 refused: the range is 0 to 40"):
        MovingFrameSetup(tuple(params), good.angles_deg)
    params[KEYS.index("k")] = math.nan
    with pytest.raises(ValueError, match="refused"):
        MovingFrameSetup(tuple(params), good.angles_deg)
    with pytest.raises(ValueError, match="θ₀"):
        MovingFrameSetup(good.params, (0.0, 200.0, 0.0))
    with pytest.raises(ValueError, match="must be >= 0"):
        FrameMotion(line_omega=-1.0)
    sim = simulation("Turntable")
    with pytest.raises(ValueError, match="finite"):
        sim.advance(math.inf)
    assert sim.t == 0.0


def test_a_broken_preset_is_refused_naming_the_field(tmp_path) -> None:  # type: ignore[no-untyped-def]
    import json

    from app.kit.core.presets import PRESETS_DIR

    data = json.loads((PRESETS_DIR / "moving_frame.json").read_text(encoding="utf-8"))
    data["presets"][1]["params"]["forces_on"] = 2.5
    path = tmp_path / "moving_frame.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(PresetError, match=r"presets\[1\] \(Speeding up\): forces on particle = 2\.5 refused"):
        load_presets(path, PARAM_SPECS, check=MovingFrameView.check_preset)


# ---------------------------------------------------------------------------- the view
def _open(manual):  # type: ignore[no-untyped-def]
    session = manual.session
    session.select_scene("Moving frame")
    view = session.scene
    assert view.title == "Moving frame" and "Moving frame" in session.gui_scene.options
    return session, view


def _pose(node) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    R = Rotation.from_quat(np.asarray(node.wxyz), scalar_first=True).as_matrix()
    return R, np.asarray(node.position, dtype=float)


def test_riding_turns_the_world_so_that_C_prime_stands_still(manual) -> None:  # type: ignore[no-untyped-def]
    session, view = _open(manual)
    session.apply_preset("Earth, 45° N")
    session.play()
    manual.tick(0.5)
    frame = view.sim.frame
    R_w, p_w = _pose(view.world)
    np.testing.assert_allclose(R_w, np.eye(3), atol=1e-12)  # inertial view: the world is C
    R_f, p_f = _pose(view.body.node)
    # Playing: drawn at display resolution (app.kit.draw.lean.Pose: ~1 px at the disc's rim, 2.2 m)
    np.testing.assert_allclose(R_f, frame.R_space_body, atol=TOLERANCE / 2.2)
    np.testing.assert_allclose(p_f, frame.a, atol=TOLERANCE)
    view.set_riding(True)
    for _ in range(2):
        manual.tick(0.25)
        R_w, p_w = _pose(view.world)
        R_f, p_f = _pose(view.body.node)
        # world ∘ frame = identity: C′ sits on the screen's axes while the world turns past
        np.testing.assert_allclose(R_w @ R_f, np.eye(3), atol=1e-6)  # float32 poses
        np.testing.assert_allclose(R_w @ p_f + p_w, np.zeros(3), atol=1e-6)
    assert "riding with C′" in view.transport.gui_status.content
    view.set_riding(False)
    np.testing.assert_allclose(_pose(view.world)[0], np.eye(3), atol=1e-12)
    assert session.error_count == 0, session.last_error


def test_a_paused_frame_sends_nothing_and_a_playing_one_only_moving_nodes(manual, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    session, view = _open(manual)
    manual.tick(0.2)  # the labels' layer lays out once for the camera the session has just set
    sent: list[str] = []
    api = session.client.scene
    original = api._queue_scene_message
    monkeypatch.setattr(api, "_queue_scene_message", lambda m: (sent.append(getattr(m, "name", "")), original(m))[1])
    manual.tick(0.5)
    assert sent == []
    session.play()
    manual.tick(1.0)
    root = view.root + "/w"  # the world; C′ is f, its particles p, spring s, paths t, forces a; paths in C tc
    allowed = (f"{root}/f", f"{root}/f/p/", f"{root}/f/s", f"{root}/tc/", f"{root}/f/t/", f"{root}/f/a")
    assert sent and all(name == f"{root}/f" or name.startswith(allowed) for name in sent), set(sent) - {""}
    assert not any(name.startswith(f"{root}/grid") or name == root for name in sent)  # not riding: world still
    per_frame = len(sent) / 60
    assert per_frame < 30, per_frame  # poses, 3 particles, 6 arrows and labels, a path chunk now and then


def test_refused_input_changes_nothing(manual) -> None:  # type: ignore[no-untyped-def]
    session, view = _open(manual)
    before = view.sim.setup
    k_slider = view.gui_params[view._param_keys.index("k")]
    for bad in (1e6, float("nan"), -3.0):  # (a string never gets past viser's own float conversion)
        manual.client.set_value(k_slider, bad)
        manual.wait(lambda: "refused" in view.message.text)
        assert view.sim.setup == before
        view.message.clear()
    manual.client.set_value(view.gui_forces_on, "the moon")
    manual.wait(lambda: "refused" in view.message.text)
    assert view.sim.setup == before and view.gui_forces_on.value == PARTICLES[before.focus]
    manual.client.set_value(k_slider, 9.5)  # a good value restarts the run with it
    manual.wait(lambda: view.sim.setup.k == 9.5)
    assert view.sim.t == 0.0 and session.error_count == 0, session.last_error


# ---------------------------------------------------------------------------- in a browser
@pytest.mark.browser
def test_browser_opens_the_scene_and_the_camera_toggle_makes_C_prime_stand_still(wait_until, app, page) -> None:  # type: ignore[no-untyped-def]
    from test_browser import SCENE_CLIP, changed_fraction, open_app

    session = open_app(page, app)
    choose(page, session.gui_scene, "Moving frame")
    wait_until(lambda: session.scene.title == "Moving frame", timeout=10.0)
    page.get_by_text("Moving frame C′").first.wait_for(timeout=10_000)
    view = session.scene
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: view.room.playing and view.sim.t > 1.5, timeout=10.0)  # C′ turned by > 45°
    page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not view.room.playing, timeout=10.0)
    time.sleep(1.0)
    inertial = page.screenshot(clip=SCENE_CLIP)
    time.sleep(0.5)
    still = changed_fraction(inertial, page.screenshot(clip=SCENE_CLIP))
    assert still < 0.001  # control: paused, nothing moves on screen
    page.get_by_label("Ride with C′").check()  # paused: only the toggle can change the picture
    wait_until(lambda: view.riding, timeout=10.0)
    page.get_by_text("riding with C′").first.wait_for(timeout=10_000)
    time.sleep(1.0)
    riding = page.screenshot(clip=SCENE_CLIP)
    turned = changed_fraction(inertial, riding)
    assert turned > 0.005  # the world (grid, space axes) turned under the rider
    page.get_by_label("Ride with C′").uncheck()
    wait_until(lambda: not view.riding, timeout=10.0)
    back = 1.0
    deadline = time.monotonic() + 8.0  # the software renderer may take a few frames under load
    while back >= 0.001 and time.monotonic() < deadline:
        time.sleep(0.5)
        back = changed_fraction(inertial, page.screenshot(clip=SCENE_CLIP))
    assert back < 0.001, back  # the inertial view again, as it was
    print(f"changed pixels: still {still:.4%}, riding {turned:.2%}, back {back:.4%}")
    assert session.last_error is None


def test_snapped_while_playing_exact_when_paused_and_the_rider_sends_nothing(manual, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Turntable: while it plays, the particle at rest in C′ (a child of C′) sends no message and
    every drawn particle is within TOLERANCE of its C′ coordinates; paused, all are exact (float32)."""
    session, view = _open(manual)
    session.apply_preset("Turntable")
    manual.tick(0.2)
    sent: list[str] = []
    api = session.client.scene
    original = api._queue_scene_message
    monkeypatch.setattr(api, "_queue_scene_message", lambda m: (sent.append(getattr(m, "name", "")), original(m))[1])
    session.play()
    manual.tick(1.0)
    rider = view.particles[1]._impl.name
    assert sent and rider not in sent
    x_body, _ = view.sim.body_coordinates()
    for k in range(3):
        np.testing.assert_allclose(view.particle_drawn(k), x_body[k], atol=0.5 * TOLERANCE * math.sqrt(3) + 1e-6)
    session.pause()
    x_body, _ = view.sim.body_coordinates()
    for k in range(3):
        np.testing.assert_allclose(view.particle_drawn(k), x_body[k].astype(np.float32), atol=1e-6)
    assert not view.particles[0].visible and view.focus_ball.visible  # the free one: drawn by the ball
    assert session.error_count == 0, session.last_error
