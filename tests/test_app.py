"""Server-side tests of the lecture app (no browser).

Sessions come from real websocket connections (`RawClient`, conftest), so `client.gui` /
`client.scene` are the real per-client APIs.  Most tests use the `manual` fixture: the app
with its 60 Hz loop NOT running, so the test ticks the session itself (deterministic).

References are independent of the app: SciPy's `Rotation` for D and for the z-x-z angles of a
pose, finite differences of `Rotation.from_euler("ZXZ", ...)` for ω, SciPy `solve_ivp` at
tight tolerance on Euler's equations (Ṙ = R hat(ω_b), I ω̇_b = (I ω_b) × ω_b) for the free
body, numpy cross products for L and the top's torque, and closed forms (T = ½ ω·Iω,
V = mgl cos θ, Q_θ = mgl sin θ, box moments m (b² + c²)/12).
"""

from __future__ import annotations

import logging
import math
import re
import time

import numpy as np
import pytest
import viser
from conftest import poll_until, world_rotation
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import app.kit.rigid.simulation as rigid
import app.main as app_main
from app.kit.core.common import NODES_FADED_COLOR
from app.kit.draw.lean import TOLERANCE
from app.kit.rigid.view import SLIDER_PERIOD as RIGID_SLIDER_PERIOD
from app.main import App
from app.scenes.euler_angles import INITIAL_ANGLES_DEG, INITIAL_CAMERA, RATE_ARROW_SCALE, THETA_REACH
from app.scenes.euler_angles import SLIDER_PERIOD as EULER_SLIDER_PERIOD
from app.scenes.free_body import FreeBodyView
from app.scenes.heavy_top import CHUNK_POINTS, TRACE_SECONDS, TRACE_SPACING, HeavyTopView
from app.session import Session
from physics.dynamics import IntegrationError

ATOL_POSE = 1e-6  # viser keeps poses as float32-exact numbers at worst
ATOL_READOUT = 0.6e-4  # the matrix and vector readouts have 4 decimals
DT = 1.0 / 60.0


def D_reference(phi_deg: float, theta_deg: float, psi_deg: float) -> np.ndarray:
    return Rotation.from_euler("ZXZ", [phi_deg, theta_deg, psi_deg], degrees=True).as_matrix()


def body_matrix(session: Session) -> np.ndarray:
    """The body node's orientation in the world as the client composes it (each node's wxyz is
    T_parent_local; the Euler explorer hangs the body under the after-θ frame), as a matrix."""
    return world_rotation(session.scene.body.node)


def one_session(app: App, connect) -> Session:
    connect()
    return next(iter(app.wait_for_sessions(1).values()))


def set_angles(session: Session, phi: float, theta: float, psi: float) -> None:
    """Set the explorer's angles [deg] as a drag of the three sliders does (the sliders show
    them rounded to 1°, so assigning the sliders could find an unchanged value)."""
    session.scene.set_angles_deg(phi, theta, psi)


def _matrices_in(markdown: str) -> list[np.ndarray]:
    """Every 3x3 block of '[ a  b  c ]' rows in the markdown."""
    rows = [[float(x) for x in row.split()] for row in re.findall(r"\[\s*([-\d.\s]+?)\s*\]", markdown)]
    return [np.array(rows[i:i + 3]) for i in range(0, len(rows), 3)]


_NUMBER = r"(-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)"


def _row(content: str, name: str) -> np.ndarray:
    match = re.search(re.escape(name) + r"\s+" + r"\s*".join([_NUMBER] * 3), content)
    assert match, f"no row {name!r} in\n{content}"
    return np.array([float(x) for x in match.groups()])


def parse_readout(content: str) -> dict[str, np.ndarray | float]:
    """The simulation readout's numbers, read back from its text."""
    out: dict[str, np.ndarray | float] = {"D": _matrices_in(content)[0]}
    for name in ("ω_s [rad/s]", "ω_b [rad/s]", "L_s [kg m²/s]", "L_b [kg m²/s]", "M_s [N m]"):
        out[name.split()[0]] = _row(content, name)
    energies = re.search(rf"T = {_NUMBER} J\s+V = {_NUMBER} J\s+E = T \+ V = {_NUMBER} J", content)
    forces = re.search(rf"Q_φ = M·e_z\s*= {_NUMBER} N m\s+Q_θ = M·e_n\s*= {_NUMBER} N m\s+"
                       rf"Q_ψ = M·e_z′\s*= {_NUMBER} N m", content)
    angles = re.search(rf"φ =\s*{_NUMBER}°\s+θ =\s*{_NUMBER}°\s+ψ =\s*{_NUMBER}°", content)
    assert energies and forces and angles, content
    out["T"], out["V"], out["E"] = (float(x) for x in energies.groups())
    out["Q"] = np.array([float(x) for x in forces.groups()])
    out["angles"] = np.array([float(x) for x in angles.groups()])
    return out


def free_body_reference(inertia, R0, omega0, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(R, ω_b) at t from solve_ivp (DOP853, rtol = atol = 1e-12) on Ṙ = R hat(ω_b),
    I ω̇_b = (I ω_b) × ω_b: independent of `physics`."""
    inertia = np.asarray(inertia, dtype=float)

    def rhs(_t, y):
        R, w = y[:9].reshape(3, 3), y[9:]
        W = np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
        return np.concatenate([(R @ W).ravel(), np.cross(inertia * w, w) / inertia])

    y0 = np.concatenate([np.asarray(R0, dtype=float).ravel(), np.asarray(omega0, dtype=float)])
    solution = solve_ivp(rhs, (0.0, t), y0, method="DOP853", rtol=1e-12, atol=1e-12)
    return solution.y[:9, -1].reshape(3, 3), solution.y[9:, -1]


def rotation_angle(A: np.ndarray, B: np.ndarray) -> float:
    """The angle [rad] of the rotation Aᵀ B (SciPy)."""
    return float(Rotation.from_matrix(A.T @ B).magnitude())


def start_free_body(manual, preset: str = "Dzhanibekov") -> FreeBodyView:
    manual.session.select_scene("Free body")
    manual.session.apply_preset(preset)
    scene = manual.session.scene
    assert isinstance(scene, FreeBodyView)
    return scene


# ---------------------------------------------------------------------------- sessions
def test_each_client_gets_its_own_session_gui_and_body(wait_until, app: App, connect) -> None:
    a = connect()
    (s1,) = app.wait_for_sessions(1).values()
    connect()
    (s2,) = (s for s in app.wait_for_sessions(2).values() if s is not s1)
    assert s1.client is not s2.client
    assert s1.scene.gui_angles[1]._impl.uuid != s2.scene.gui_angles[1]._impl.uuid

    a.set_value(s1.scene.gui_angles[1], 60.0)  # a browser moves ITS θ slider
    wait_until(lambda: s1.scene.sim.angles_deg[1] == 60.0)
    time.sleep(0.1)
    phi0, theta0, psi0 = INITIAL_ANGLES_DEG
    assert s2.scene.sim.angles_deg == [phi0, theta0, psi0]
    np.testing.assert_allclose(body_matrix(s2), D_reference(phi0, theta0, psi0), atol=ATOL_POSE)
    np.testing.assert_allclose(body_matrix(s1), D_reference(phi0, 60, psi0), atol=ATOL_POSE)

    # One client plays a free body; the other's scene does not change or move.
    s1.select_scene("Free body")
    s1.play()
    wait_until(lambda: s1.scene.sim.state.t > 0.2)
    assert s2.scene.title == "Euler angles" and not s2.scene.room.playing
    assert s2.scene.sim.angles_deg == [phi0, theta0, psi0]

    a.close()
    remaining = app.wait_for_sessions(1)
    assert list(remaining) == [s2.client_id]
    assert s1.closed and not s2.closed


def test_sessions_are_ticked_by_a_paced_60hz_loop(app: App, connect) -> None:
    session = one_session(app, connect)
    dts: list[float] = []
    started = time.monotonic()
    session.room.advance = dts.append  # type: ignore[method-assign]
    poll_until(lambda: len(dts) >= 30, 30.0, what="30 ticks", seen=lambda: len(dts))
    ticks, seconds = len(dts), time.monotonic() - started
    # 60 Hz nominal: never faster (a busy loop would give thousands a second); a loaded machine
    # may give fewer, so the count is awaited, not timed.
    assert ticks / seconds <= 70, (ticks, seconds)
    assert max(dts) <= app_main.MAX_TICK_DT
    assert float(np.median(dts)) > 1 / 75, dts  # paced at 60 Hz at most: slower only on a busy machine
    assert sum(dts) <= seconds + app_main.MAX_TICK_DT, (sum(dts), seconds)  # each tick: the wall time since the last


# ---------------------------------------------------------------------------- Euler angles
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    phi=st.floats(-180.0, 180.0),
    theta=st.floats(0.0, 180.0),
    psi=st.floats(-180.0, 180.0),
)
def test_angles_turn_body_as_scipy_zxz(manual, phi: float, theta: float, psi: float) -> None:
    session = manual.session
    set_angles(session, phi, theta, psi)
    np.testing.assert_allclose(body_matrix(session), D_reference(phi, theta, psi), atol=ATOL_POSE)

    # Line of nodes: a segment through the origin along the x axis of a frame turned to
    # (cos φ, sin φ, 0).
    start, end = np.asarray(session.scene.nodes.line.points, dtype=float)[0]
    np.testing.assert_allclose(start, -end, atol=ATOL_POSE)
    frame = world_rotation(session.scene.nodes.node)
    expected = np.array([math.cos(math.radians(phi)), math.sin(math.radians(phi)), 0.0])
    np.testing.assert_allclose(frame @ (end / np.linalg.norm(end)), expected, atol=ATOL_POSE)

    # Intermediate frames: Rz(φ) and Rz(φ) Rx(θ), again from SciPy.
    after_phi = world_rotation(session.scene.after_phi_node)
    after_theta = world_rotation(session.scene.after_theta_node)
    np.testing.assert_allclose(after_phi, Rotation.from_euler("z", phi, degrees=True).as_matrix(),
                               atol=ATOL_POSE)
    np.testing.assert_allclose(after_theta,
                               Rotation.from_euler("ZX", [phi, theta], degrees=True).as_matrix(), atol=ATOL_POSE)


def test_readout_shows_D_and_its_three_factors(manual) -> None:
    session = manual.session
    phi, theta, psi = 30.0, 50.0, 20.0
    set_angles(session, phi, theta, psi)
    (D_shown,) = _matrices_in(session.scene.readout_matrix.handle.content)
    np.testing.assert_allclose(D_shown, D_reference(phi, theta, psi), atol=ATOL_READOUT)
    factors = _matrices_in(session.scene.readout_factors.handle.content)
    expected = [Rotation.from_euler(axis, angle, degrees=True).as_matrix()
                for axis, angle in (("z", phi), ("x", theta), ("z", psi))]
    assert len(factors) == 3
    for shown, reference in zip(factors, expected):
        np.testing.assert_allclose(shown, reference, atol=ATOL_READOUT)
    assert "-0.0000" not in session.scene.readout_matrix.handle.content


def _omega_by_finite_differences(angles_deg, rates_deg, h: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """(ω_s, ω_b) [deg/s] from hat(ω_s) = Ṙ Rᵀ, hat(ω_b) = Rᵀ Ṙ, Ṙ by central differences."""
    angles, rates = np.asarray(angles_deg, dtype=float), np.asarray(rates_deg, dtype=float)
    R = D_reference(*angles)
    R_dot = (D_reference(*(angles + h * rates)) - D_reference(*(angles - h * rates))) / (2 * h)
    W_s, W_b = R_dot @ R.T, R.T @ R_dot
    vee = lambda W: np.array([W[2, 1], W[0, 2], W[1, 0]])  # noqa: E731
    return np.degrees(vee(W_s)), np.degrees(vee(W_b))


def test_euler_rates_draw_omega_head_to_tail_and_read_out(manual) -> None:
    scene = manual.session.scene
    angles, rates = (40.0, 65.0, -25.0), (30.0, -20.0, 50.0)
    set_angles(manual.session, *angles)
    for handle, rate in zip(scene.gui_rates, rates):
        handle.value = rate
    omega_s, omega_b = _omega_by_finite_differences(angles, rates)

    # Head to tail: each component starts where the previous ended; the resultant is ω_s.
    *chain, resultant = scene.omega_chain()  # space coordinates, composed through the frames they ride on
    np.testing.assert_allclose(chain[0][0], 0.0, atol=ATOL_POSE)
    np.testing.assert_allclose(chain[1][0], chain[0][1], atol=ATOL_POSE)
    np.testing.assert_allclose(chain[2][0], chain[1][1], atol=ATOL_POSE)
    np.testing.assert_allclose(resultant[1], chain[2][1], atol=ATOL_POSE)
    np.testing.assert_allclose(resultant[1] / RATE_ARROW_SCALE, omega_s, atol=1e-3)
    np.testing.assert_allclose(chain[0][1] / RATE_ARROW_SCALE, [0.0, 0.0, rates[0]], atol=1e-3)  # φ̇ e_z

    content = scene.readout_omega.handle.content
    np.testing.assert_allclose(_row(content, "ω_s (space)"), omega_s, atol=2e-3)
    np.testing.assert_allclose(_row(content, "ω_b (body)"), omega_b, atol=2e-3)


def test_euler_play_advances_angles_and_sliders_follow_without_feedback(manual) -> None:
    session, scene = manual.session, manual.session.scene
    set_angles(session, 10.0, 60.0, 20.0)
    for handle, rate in zip(scene.gui_rates, (20.0, 0.0, 45.0)):
        handle.value = rate
    session.play()
    manual.tick(1.0)
    # Exactly initial + rate t: the sliders' 5 Hz sync (whole degrees) did not feed back.
    assert scene.sim.angles_deg == pytest.approx([30.0, 60.0, 65.0], abs=1e-9)
    assert [h.value for h in scene.gui_angles] == pytest.approx([30.0, 60.0, 65.0], abs=0.5 + EULER_SLIDER_PERIOD * 45)
    assert scene.room.playing and session.last_error is None

    scene.transport.gui_time_scale.value = 0.5  # slow motion: half the angle per wall second
    manual.tick(1.0)
    assert scene.sim.angles_deg == pytest.approx([40.0, 60.0, 87.5], abs=1e-9)

    # θ through 180°: the sliders wrap (θ back below 180, φ and ψ turned by 180°) and the
    # body passes without a jump: D equals Rz(φ) Rx(θ) Rz(ψ) of the unwrapped angles.
    session.pause()
    set_angles(session, 10.0, 170.0, 20.0)
    for handle, rate in zip(scene.gui_rates, (0.0, 20.0, 0.0)):
        handle.value = rate
    scene.transport.gui_time_scale.value = 1.0
    session.play()
    poses = []
    for _ in range(60):
        session.tick(DT)
        poses.append(body_matrix(session))
    assert scene.sim.angles_deg == pytest.approx([-170.0, 170.0, -160.0], abs=1e-6)
    # Playing, θ is drawn at display resolution (app.kit.draw.lean): within half a step of the
    # snapping grid, a step moving the body's farthest point (THETA_REACH) by TOLERANCE.
    theta_step = TOLERANCE / THETA_REACH  # [rad]
    np.testing.assert_allclose(poses[-1], D_reference(10.0, 190.0, 20.0), atol=0.5 * theta_step + 1e-6)
    steps = [rotation_angle(a, b) for a, b in zip(poses, poses[1:])]
    assert max(steps) < math.radians(20.0 / 60.0) * 1.01 + theta_step + 1e-6  # one frame's turn, no jump
    session.pause()  # paused: drawn exactly
    np.testing.assert_allclose(body_matrix(session), D_reference(10.0, 190.0, 20.0), atol=ATOL_POSE)
    session.play()
    note = scene.gui_gimbal_note
    session.step()  # θ = 170 - 1/3: not locked
    assert not scene.room.playing and not note.visible


def test_user_drag_while_playing_pauses_and_sets_the_angle(manual) -> None:
    scene = manual.session.scene
    manual.session.play()
    manual.tick(0.5)
    manual.client.set_value(scene.gui_angles[1], 100.0)  # what a browser sends when dragging
    manual.wait(lambda: scene.sim.angles_deg[1] == 100.0)
    assert not scene.room.playing
    phi, _, psi = scene.sim.angles_deg
    np.testing.assert_allclose(body_matrix(manual.session), D_reference(phi, 100.0, psi), atol=ATOL_POSE)
    manual.session.play()
    manual.tick(0.2)
    assert scene.sim.angles_deg[1] != 100.0  # plays on from the dragged pose (θ̇ = 10°/s)
    manual.session.reset()
    assert scene.sim.angles_deg == pytest.approx([phi, 100.0, psi], abs=1e-9) and not scene.room.playing


@pytest.mark.parametrize(
    ("theta", "note"), [(0.0, "φ + ψ"), (1.0, "φ + ψ"), (180.0, "φ − ψ"), (179.5, "φ − ψ")]
)
def test_gimbal_lock_fades_line_of_nodes_and_says_what_is_defined(manual, theta: float, note: str) -> None:
    scene = manual.session.scene
    set_angles(manual.session, 40.0, theta, 10.0)
    assert scene.gui_gimbal_note.visible
    assert "Gimbal lock" in scene.gui_gimbal_note.content and note in scene.gui_gimbal_note.content
    assert "undefined" in scene.nodes.label.text
    faded = np.asarray(scene.nodes.line.colors).reshape(-1, 3)
    assert np.all(faded == NODES_FADED_COLOR)  # grey

    scene.gui_angles[1].value = 90.0
    assert not scene.gui_gimbal_note.visible
    assert scene.nodes.label.text == "line of nodes"
    colour = np.asarray(scene.nodes.line.colors).reshape(-1, 3)[0]
    assert len(set(colour.tolist())) > 1  # not grey


def test_intermediate_frames_toggle(manual) -> None:
    scene = manual.session.scene
    assert all(axes.visible for axes in scene.frame_axes)
    scene.gui_show_frames.value = False
    assert not any(axes.visible for axes in scene.frame_axes)
    assert scene.after_phi_node.visible and scene.nodes.visible  # the line of nodes rides on the after-φ frame


# ---------------------------------------------------------------------------- bad input
def test_out_of_range_and_nan_are_refused_with_a_message(manual) -> None:
    client, session = manual.client, manual.session
    scene = session.scene
    scene.gui_angles[1].value = 500.0  # server side
    assert scene.gui_angles[1].value == 50.0 and scene.sim.angles_deg[1] == 50.0
    assert "refused" in scene.message.text
    # The page says it once, under the box (its note), the top line hidden:
    assert any("refused" in b.refusal for b in scene._bindings) and not scene.message.handle.visible

    client.set_value(scene.gui_angles[1], 1e6)  # viser itself accepts this (docs/VISER.md pitfall 4)
    manual.wait(lambda: "1000000.0 refused" in scene.message.text)
    assert scene.gui_angles[1].value == 50.0 and scene.sim.angles_deg[1] == 50.0
    client.set_value(scene.gui_angles[2], 33.0)
    manual.wait(lambda: scene.sim.angles_deg[2] == 33.0)
    assert not scene.message.text  # a valid value clears the message
    client.set_value(scene.gui_angles[2], float("nan"))  # NaN: keep the last valid value
    manual.wait(lambda: "nan refused" in scene.message.text)
    assert scene.gui_angles[2].value == 33.0 and scene.sim.angles_deg[2] == 33.0
    assert np.all(np.isfinite(np.asarray(scene.body.node.wxyz)))
    client.set_value(scene.gui_moments[0], -3.0)
    manual.wait(lambda: "-3.0 refused" in scene.message.text)
    assert scene.gui_moments[0].value == 1.0 and scene.sim.moments[0] == 1.0
    client.set_value(scene.transport.gui_time_scale, 100.0)
    manual.wait(lambda: "Time scale" in scene.message.text)
    assert scene.room.time_scale == 1.0 and scene.transport.gui_time_scale.value == 1.0
    sent = time.time()
    client.set_value(session.gui_scene, "no such scene")  # a client can send any string
    manual.wait(lambda: session.gui_scene.update_timestamp > sent and session.gui_scene.value == "Euler angles")
    assert session.last_error is None


def _moments_of_box(dimensions) -> np.ndarray:
    """Forward formula, independent of the app: I1 = m (b² + c²)/12 and cyclic (m = 12)."""
    a, b, c = dimensions
    return np.array([b * b + c * c, a * a + c * c, a * a + b * b])


def test_moments_reshape_the_box_and_invalid_ones_are_refused(manual) -> None:
    session = manual.session
    scene = session.scene
    for k, value in reversed(list(enumerate((1.0, 1.5, 2.0)))):  # each step a body: from (1, 2, 2.6)
        scene.gui_moments[k].value = value
    moments = _moments_of_box(scene.body_box.dimensions)
    # Same shape up to scale: the drawn box has these moments for some mass.
    np.testing.assert_allclose(moments / moments.sum(), np.array([1.0, 1.5, 2.0]) / 4.5, atol=1e-6)
    assert max(scene.body_box.dimensions) == pytest.approx(1.25)

    before = tuple(scene.body_box.dimensions)
    scene.gui_moments[2].value = 4.0  # 1 + 1.5 < 4: breaks I1 + I2 >= I3
    assert tuple(scene.body_box.dimensions) == before and scene.sim.moments == (1.0, 1.5, 2.0)
    assert scene.gui_moments[2].value == 2.0  # the box shows the moment in force again
    assert "I3 = 4 refused" in scene.message.text
    status = scene.gui_moments_status.content
    assert "Not a rigid body" in status and "I1 + I2 >= I3" in status
    assert session.last_error is None  # a refused input is not an error of the app
    scene.gui_moments[2].value = 2.5  # 1 + 1.5 = 2.5: a flat lamina, allowed
    assert scene.sim.moments == (1.0, 1.5, 2.5) and min(scene.body_box.dimensions) < 0.05


def test_angle_presets_from_server_and_client(manual) -> None:
    client, session = manual.client, manual.session
    scene = session.scene
    scene.presets_row.groups[0].value = "D = 1"
    np.testing.assert_allclose(body_matrix(session), np.eye(3), atol=ATOL_POSE)
    client.set_value(scene.presets_row.groups[0], "gimbal lock")
    manual.wait(lambda: scene.sim.angles_deg == [30.0, 0.0, 20.0])
    assert scene.gui_gimbal_note.visible
    client.set_value(scene.presets_row.groups[0], "no such preset")  # a client can send any string
    manual.wait(lambda: "No preset named 'no such preset'" in scene.message.text)
    assert scene.sim.angles_deg == [30.0, 0.0, 20.0] and session.last_error is None


# ---------------------------------------------------------------------------- scenes
def test_scene_switching_builds_each_scene_with_its_view_and_removes_the_old(manual) -> None:
    session = manual.session
    euler = session.scene
    euler_handles = [euler.gui_angles[1], euler.transport.gui_play]
    session.select_scene("Free body")
    assert isinstance(session.scene, FreeBodyView)
    assert all(handle._impl.removed for handle in euler_handles)
    np.testing.assert_allclose(session.client.camera.position, FreeBodyView.view.position, atol=1e-9)
    np.testing.assert_allclose(session.client.camera.look_at, FreeBodyView.view.look_at, atol=1e-9)

    manual.client.set_value(session.gui_scene, "Heavy top")  # the dropdown, from a browser
    manual.wait(lambda: isinstance(session.scene, HeavyTopView))
    top = session.scene
    np.testing.assert_allclose(session.client.camera.position, HeavyTopView.view.position, atol=1e-9)
    session.play()
    manual.tick(0.5)
    assert top.sim.state.t == pytest.approx(0.5)
    session.select_scene("Euler angles")
    assert session.scene.title == "Euler angles" and top.transport.gui_play._impl.removed
    np.testing.assert_allclose(session.client.camera.position, INITIAL_CAMERA["position"], atol=1e-9)
    manual.tick(0.2)  # the removed top is not ticked, and nothing raises
    assert top.sim.state.t == pytest.approx(0.5) and session.last_error is None
    with pytest.raises(ValueError, match="unknown scene"):
        session.select_scene("Nope")


def test_each_scene_loads_with_its_body_in_view(manual) -> None:
    """The camera looks at the origin region from outside it, and the origin (the body's
    centre or the pivot) projects inside the left part of the view (the GUI is on the right)."""
    for title in ("Euler angles", "Free body", "Heavy top"):
        manual.session.select_scene(title)
        view = manual.session.scene.view
        position, look_at = np.array(view.position), np.array(view.look_at)
        forward = (look_at - position) / np.linalg.norm(look_at - position)
        assert 4.0 < np.linalg.norm(position - look_at) < 9.0
        to_origin = -position / np.linalg.norm(position)
        assert math.degrees(math.acos(float(forward @ to_origin))) < 0.5 * view.fov_deg, title


# ---------------------------------------------------------------------------- free body
def test_dzhanibekov_preset_flips_and_matches_an_independent_solution(manual) -> None:
    scene = start_free_body(manual)
    I = np.array(scene.sim.model.inertia)
    assert I[0] < I[1] < I[2]  # spun about the intermediate axis y′
    R0, omega0 = scene.sim.state.R_space_body.copy(), scene.sim.state.omega_body.copy()
    assert abs(omega0[1]) > 20 * max(abs(omega0[0]), abs(omega0[2]))
    manual.session.play()
    flipped_at = None
    for _ in range(int(4.0 / DT)):
        manual.session.tick(DT)
        if flipped_at is None and np.sign(scene.sim.state.omega_body[1]) != np.sign(omega0[1]):
            flipped_at = scene.sim.state.t
    assert flipped_at is not None and flipped_at < 3.0, flipped_at  # visibly, within a few seconds
    R_ref, omega_ref = free_body_reference(I, R0, omega0, scene.sim.state.t)
    np.testing.assert_allclose(scene.sim.state.omega_body, omega_ref, atol=1e-5)
    assert rotation_angle(scene.sim.state.R_space_body, R_ref) < 1e-5
    assert manual.session.last_error is None


def test_free_body_readout_matches_independent_formulas(manual) -> None:
    scene = start_free_body(manual, "Rod")
    scene.tabs.show("Readout")
    manual.session.play()
    manual.tick(0.7)
    manual.session.pause()  # the readout shows the paused state
    shown = parse_readout(scene.readout.handle.content)
    I = np.array(scene.sim.model.inertia)
    D = shown["D"]
    np.testing.assert_allclose(D, scene.sim.state.R_space_body, atol=ATOL_READOUT)
    np.testing.assert_allclose(D, body_matrix(manual.session), atol=ATOL_READOUT)
    np.testing.assert_allclose(D, D_reference(*shown["angles"]), atol=1e-3)  # angles: 2 decimals
    w_b = shown["ω_b"]
    np.testing.assert_allclose(shown["ω_s"], D @ w_b, atol=2e-3)  # D and ω_b rounded to 1e-4
    np.testing.assert_allclose(shown["L_b"], I * w_b, atol=1e-3)
    np.testing.assert_allclose(shown["L_s"], D @ (I * w_b), atol=2e-3)
    assert shown["T"] == pytest.approx(0.5 * float(w_b @ (I * w_b)), rel=1e-3)
    assert shown["V"] == 0.0 and shown["E"] == shown["T"]
    np.testing.assert_allclose(shown["Q"], 0.0, atol=1e-12)
    np.testing.assert_allclose(shown["M_s"], 0.0, atol=1e-12)
    # L is fixed in space: the arrow drawn now is the arrow drawn at t = 0.
    L0 = scene.sim.initial_state.R_space_body @ (I * scene.sim.initial_state.omega_body)
    tip = scene.L.segment[1]
    np.testing.assert_allclose(tip / np.linalg.norm(tip), L0 / np.linalg.norm(L0), atol=1e-6)
    np.testing.assert_allclose(shown["L_s"], L0, atol=2e-4)


def test_play_pause_step_reset_and_time_scale(manual) -> None:
    scene = start_free_body(manual, "Disc")
    R0 = scene.sim.state.R_space_body.copy()
    manual.session.step()
    assert scene.sim.state.t == pytest.approx(DT) and not scene.room.playing
    manual.client.set_value(scene.transport.gui_time_scale, 2.0)  # from a browser
    manual.wait(lambda: scene.room.time_scale == 2.0)
    manual.session.step()
    assert scene.sim.state.t == pytest.approx(3 * DT)
    manual.session.play()
    manual.tick(0.5)
    assert scene.sim.state.t == pytest.approx(3 * DT + 1.0)
    assert scene.transport.gui_play.label == "Pause"  # the toggle now offers Pause
    manual.session.pause()
    manual.tick(0.5)
    assert scene.sim.state.t == pytest.approx(3 * DT + 1.0)
    assert "t = 1.05 s" in scene.transport.gui_status.content and scene.transport.gui_play.label == "Play"
    manual.session.reset()
    assert scene.sim.state.t == 0.0 and not scene.room.playing
    np.testing.assert_array_equal(scene.sim.state.R_space_body, R0)
    manual.client.set_value(scene.transport.gui_play, True)  # the Play button, from a browser
    manual.wait(lambda: scene.room.playing)
    assert manual.session.last_error is None


def test_sliders_follow_the_motion_without_feedback_and_a_drag_sets_the_state(manual) -> None:
    scene = start_free_body(manual)
    I = np.array(scene.sim.model.inertia)
    R0, omega0 = scene.sim.state.R_space_body.copy(), scene.sim.state.omega_body.copy()
    restarts = scene.sim.restarts
    manual.session.play()

    def check_sliders(slack_deg: float, slack_rate: float) -> None:
        """The sliders show the state: angles from SciPy, ω_b, within the given slack."""
        angles = Rotation.from_matrix(scene.sim.state.R_space_body).as_euler("ZXZ", degrees=True)
        for value, reference in zip([h.value for h in scene.gui_angles], angles):
            assert abs((value - reference + 180.0) % 360.0 - 180.0) <= slack_deg, (value, reference)
        np.testing.assert_allclose([h.value for h in scene.gui_rates], scene.sim.state.omega_body, atol=slack_rate)

    motion = []
    for _ in range(int(1.2 / DT)):
        manual.session.tick(DT)
        motion.append(np.array([h.value for h in scene.gui_angles]))
        # At most SLIDER_PERIOD (0.5 s, 2 Hz) behind: |ω| that long in degrees, plus the 1° step of the slider.
        check_sliders(0.5 + RIGID_SLIDER_PERIOD * math.degrees(float(np.linalg.norm(scene.sim.state.omega_body))),
                      0.005 + 1.0)
    assert len({tuple(m) for m in motion}) >= round(1.2 / RIGID_SLIDER_PERIOD)  # they moved, once a SLIDER_PERIOD
    assert scene.sim.restarts == restarts and scene.sim.state.t == pytest.approx(1.2)
    # Not disturbed by the sliders' (rounded) values: still the independent solution.
    R_ref, omega_ref = free_body_reference(I, R0, omega0, scene.sim.state.t)
    np.testing.assert_allclose(scene.sim.state.omega_body, omega_ref, atol=1e-6)
    manual.session.pause()
    check_sliders(0.5 + 1e-9, 0.005 + 1e-9)  # paused: exactly the state, to the slider step

    manual.session.play()
    manual.tick(0.2)
    manual.client.set_value(scene.gui_angles[1], 45.0)  # a browser drags θ while playing
    manual.wait(lambda: not scene.room.playing and scene.sim.state.t == 0.0)
    phi_s, theta_s, psi_s = (h.value for h in scene.gui_angles)
    assert theta_s == 45.0
    np.testing.assert_allclose(scene.sim.state.R_space_body, D_reference(phi_s, 45.0, psi_s), atol=1e-12)
    np.testing.assert_allclose(scene.sim.state.omega_body, [h.value for h in scene.gui_rates], atol=1e-12)


def test_invalid_moments_while_playing_show_a_message_and_the_body_keeps_moving(manual) -> None:
    scene = start_free_body(manual)
    model = scene.sim.model
    manual.session.play()
    manual.tick(0.3)
    manual.client.set_value(scene.gui_params[2], 4.9)  # 0.3 + 0.75 < 4.9: not a body
    manual.wait(lambda: bool(scene.message.text))
    assert "Not a rigid body" in scene.message.text
    assert "I1 + I2 >= I3" in scene.message.text
    assert "Refused" in scene.gui_param_status.content
    assert scene.sim.model is model and scene.room.playing
    t, R = scene.sim.state.t, scene.sim.state.R_space_body.copy()
    manual.tick(0.5)
    assert scene.room.playing and scene.sim.state.t == pytest.approx(t + 0.5)
    assert rotation_angle(R, scene.sim.state.R_space_body) > 0.1  # still turning

    manual.client.set_value(scene.gui_params[0], -1.0)  # out of range: refused, slider goes back
    manual.wait(lambda: "-1.0 refused" in scene.message.text)
    assert scene.gui_params[0].value == 0.3 and scene.room.playing
    manual.client.set_value(scene.gui_params[2], 1.05)  # valid again: a new body, still playing
    manual.wait(lambda: scene.sim.model.inertia == (0.3, 0.75, 1.05))
    assert scene.room.playing and not scene.message.text
    assert manual.session.last_error is None


def test_exact_integrator_and_the_accuracy_readout(manual) -> None:
    scene = start_free_body(manual)
    I = np.array(scene.sim.model.inertia)
    R0, omega0 = scene.sim.state.R_space_body.copy(), scene.sim.state.omega_body.copy()
    assert scene.sim.integrator == "splitting4"
    scene.tabs.show("Plots")
    manual.session.play()
    manual.tick(2.0)
    manual.session.step()  # pauses and samples the current state for the accuracy panel
    R_ref, _ = free_body_reference(I, R0, omega0, scene.sim.state.t)
    independent = rotation_angle(R_ref, scene.sim.state.R_space_body)
    reported = float(re.search(rf"attitude \[rad\]\s+{_NUMBER}", scene.accuracy.handle.content).group(1))
    assert reported < 1e-6 and abs(reported - independent) < 1e-9, (reported, independent)
    E = lambda w: 0.5 * float(w @ (I * w))  # noqa: E731
    drift = float(re.search(rf"\|ΔE\|/E₀\s+{_NUMBER}", scene.accuracy.handle.content).group(1))
    expected = abs(E(scene.sim.state.omega_body) - E(omega0)) / E(omega0)
    assert drift == pytest.approx(expected, rel=0.05, abs=1e-15)

    scene.transport.gui_integrator.value = "exact"
    assert scene.sim.integrator == "exact"
    manual.session.play()
    manual.tick(1.0)
    R_ref, omega_ref = free_body_reference(I, R0, omega0, scene.sim.state.t)
    assert rotation_angle(R_ref, scene.sim.state.R_space_body) < 1e-8
    np.testing.assert_allclose(scene.sim.state.omega_body, omega_ref, atol=1e-8)
    manual.session.step()
    assert "IS the exact solution" in scene.accuracy.handle.content


def test_plots_are_throttled_bounded_and_closed_tabs_cost_nothing(manual) -> None:
    scene = start_free_body(manual, "Sphere")
    readouts = []
    original = scene._refresh_readout
    scene._refresh_readout = lambda: (readouts.append(1), original())[1]  # type: ignore[method-assign]
    scene.tabs.show("Plots")
    pushes = scene.plots.pushes
    manual.session.play()
    manual.tick(1.0)
    assert scene.plots.pushes - pushes <= 5  # 4 Hz
    assert readouts == []  # the Readout tab is closed: not computed, not sent
    assert len(scene.sim.samples) <= 12  # 10 Hz, plus the one at t = 0
    scene.tabs.show("Readout")
    pushes = scene.plots.pushes
    readout = scene.readout.handle.content
    manual.tick(1.0)
    assert scene.plots.pushes == pushes and 5 <= len(readouts) <= 12  # 10 Hz
    assert scene.readout.handle.content != readout
    scene.tabs.show("Plots")
    manual.tick(40.0)
    assert len(scene.sim.samples) == rigid.PLOT_CAPACITY  # a sliding window, bounded
    for handle in scene.plots.handles:
        t, *series = handle.data
        assert len(t) == rigid.PLOT_CAPACITY and np.all(np.diff(t) > 0)
        assert all(len(s) == len(t) for s in series)
    energy = scene.plots.handles[0].data[1]  # E = T for the free ball: constant
    np.testing.assert_allclose(energy, 0.5 * (1 + 4 + 9), rtol=1e-9)
    scene.gui_live_plots.value = False
    pushes = scene.plots.pushes
    manual.tick(1.0)
    assert scene.plots.pushes == pushes and not scene.plots.handles[0].visible


def test_a_physics_failure_pauses_with_a_message(monkeypatch: pytest.MonkeyPatch, manual) -> None:
    scene = start_free_body(manual)
    manual.session.play()
    manual.tick(0.1)

    def failing(*_args, **_kwargs):
        raise IntegrationError("non-finite state at t = 0.1 s")

    class Failing:
        step = staticmethod(failing)

    monkeypatch.setattr(scene.sim, "_stepper", Failing())
    manual.tick(0.1)
    assert not scene.room.playing
    assert "non-finite state" in scene.message.text and bool(scene.message.text)
    assert manual.session.last_error is None  # a stopped simulation, not a crash


# ---------------------------------------------------------------------------- heavy top
def _run_top(manual, preset: str, seconds: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, HeavyTopView]:
    """(t, θ [deg], φ̇ [deg/s]) of a preset played for `seconds`: angles from SciPy's ZXZ of
    each frame's pose, φ̇ by central differences of the unwrapped φ."""
    manual.session.select_scene("Heavy top")
    manual.session.apply_preset(preset)
    scene = manual.session.scene
    manual.session.play()
    times, angles = [0.0], [Rotation.from_matrix(scene.sim.state.R_space_body).as_euler("ZXZ")]
    for _ in range(int(seconds / DT)):
        manual.session.tick(DT)
        times.append(scene.sim.state.t)
        angles.append(Rotation.from_matrix(scene.sim.state.R_space_body).as_euler("ZXZ"))
    angles = np.array(angles)
    t = np.array(times)
    phi_dot = np.gradient(np.unwrap(angles[:, 0]), t)
    return t, np.degrees(angles[:, 1]), np.degrees(phi_dot), scene


def test_heavy_top_presets_draw_steady_wave_loop_and_cusp(manual) -> None:
    _, theta, phi_dot, _ = _run_top(manual, "Steady", 2.0)
    assert np.ptp(theta) < 0.1 and np.ptp(phi_dot[1:-1]) < 0.5  # a circle at constant rate

    _, theta, phi_dot, _ = _run_top(manual, "Wave", 2.0)
    assert np.ptp(theta) > 5.0 and phi_dot[1:-1].min() > 5.0  # nods, φ̇ keeps its sign

    _, theta, phi_dot, _ = _run_top(manual, "Loop", 2.0)
    assert phi_dot[1:-1].min() < -10.0 and phi_dot[1:-1].max() > 10.0  # φ̇ changes sign: loops

    t, theta, phi_dot, scene = _run_top(manual, "Cusp", 3.0)
    # The top turning points (θ minima, θ̇ = 0): the tip is at rest there, φ̇ ≈ 0 (cusps).
    inner = np.arange(1, len(theta) - 1)
    minima = inner[(theta[inner] <= theta[inner - 1]) & (theta[inner] < theta[inner + 1])]
    assert len(minima) >= 2, theta
    assert np.all(np.abs(phi_dot[minima]) < 0.05 * np.abs(phi_dot).max()), phi_dot[minima]
    assert theta[minima] == pytest.approx(60.0, abs=0.1)  # back to the release height
    assert manual.session.last_error is None


def test_heavy_top_readout_torque_and_generalized_forces(manual) -> None:
    manual.session.select_scene("Heavy top")
    manual.session.apply_preset("Loop")
    scene = manual.session.scene
    scene.tabs.show("Readout")
    manual.session.play()
    manual.tick(0.8)
    manual.session.pause()
    shown = parse_readout(scene.readout.handle.content)
    D = shown["D"]
    I1, _, I3 = scene.sim.model.inertia
    mgl = scene.sim.model.mgl
    e_z_body = D[:, 2]
    cos_theta = e_z_body[2]
    sin_theta = math.hypot(e_z_body[0], e_z_body[1])
    assert shown["V"] == pytest.approx(mgl * cos_theta, abs=1e-3)  # V = mgl cos θ
    np.testing.assert_allclose(shown["M_s"], -mgl * np.cross(e_z_body, [0.0, 0.0, 1.0]), atol=2e-3)
    np.testing.assert_allclose(shown["Q"], [0.0, mgl * sin_theta, 0.0], atol=2e-3)  # (M·e_z, M·e_n, M·e_z′)
    w_b = shown["ω_b"]
    assert shown["T"] == pytest.approx(0.5 * (I1 * (w_b[0] ** 2 + w_b[1] ** 2) + I3 * w_b[2] ** 2), rel=1e-3)
    # Conserved by the motion: E, L_z (= p_φ) and ω_z′ against their initial values.
    R0, w0 = scene.sim.initial_state.R_space_body, scene.sim.initial_state.omega_body
    L0 = R0 @ (np.array([I1, I1, I3]) * w0)
    E0 = 0.5 * float(w0 @ (np.array([I1, I1, I3]) * w0)) + mgl * R0[2, 2]
    assert shown["E"] == pytest.approx(E0, abs=1e-4)
    assert shown["L_s"][2] == pytest.approx(L0[2], abs=1e-4) and w_b[2] == pytest.approx(w0[2], abs=1e-4)


def test_heavy_top_trace_is_bounded_and_invalid_moments_are_refused(manual) -> None:
    manual.session.select_scene("Heavy top")
    scene = manual.session.scene
    scene.transport.gui_time_scale.value = 4.0
    manual.session.play()
    manual.tick(6.0)  # 360 frames, 24 s of simulated time at 4x: one trace point a frame
    # Only the last TRACE_SECONDS of simulated time are kept (in chunks): 12 s / (4/60 s).
    kept = TRACE_SECONDS / (4.0 * DT)
    assert kept - CHUNK_POINTS <= scene.trace.point_count <= kept + 2 * CHUNK_POINTS < 360
    assert scene.trace.chunk_count <= kept / (CHUNK_POINTS - 1) + 1  # consecutive chunks share a point
    assert TRACE_SECONDS / TRACE_SPACING == pytest.approx(360)  # the bound at 1x or slower
    manual.client.set_value(scene.gui_params[1], 2.5)  # I3 = 2.5 > 2 I1 = 2: not a body
    manual.wait(lambda: bool(scene.message.text))
    assert "I1 + I2 >= I3" in scene.message.text and scene.room.playing
    t = scene.sim.state.t
    manual.tick(0.25)
    assert scene.sim.state.t == pytest.approx(t + 1.0) and scene.sim.model.inertia[2] == 0.5
    manual.session.reset()
    assert scene.trace.point_count <= 1 and scene.sim.state.t == 0.0


def test_top_falling_out_of_gimbal_lock_shows_it_and_passes_without_a_jump(manual) -> None:
    manual.session.select_scene("Heavy top")
    manual.session.apply_preset("Too slow")  # θ = 1.5°, too slow to sleep: it falls
    scene = manual.session.scene
    assert scene.gui_gimbal_note.visible and "only **φ + ψ** is defined" in scene.gui_gimbal_note.content
    assert "undefined" in scene.nodes.label.text
    assert np.all(np.asarray(scene.nodes.line.colors).reshape(-1, 3) == NODES_FADED_COLOR)
    manual.session.play()
    sums, poses = [], []
    for _ in range(int(2.5 / DT)):
        manual.session.tick(DT)
        phi, _, psi = scene.sim.angles
        sums.append(phi + psi)  # the defined combination near θ = 0
        poses.append(scene.sim.state.R_space_body)
    steps = [rotation_angle(a, b) for a, b in zip(poses, poses[1:])]
    # φ + ψ turns by at most what the body turns in a frame (plus its tilt), never by 2π.
    assert np.max(np.abs(np.diff(sums))) < 2.0 * max(steps) + 1e-9
    assert math.degrees(scene.sim.angles[1]) > 20.0  # fallen
    manual.session.pause()
    assert not scene.gui_gimbal_note.visible and scene.nodes.label.text == "line of nodes"
    colour = np.asarray(scene.nodes.line.colors).reshape(-1, 3)[0]
    assert len(set(colour.tolist())) > 1  # gold again


# ---------------------------------------------------------------------------- robustness
def test_a_raising_callback_is_shown_and_the_server_keeps_serving(
    wait_until, app: App, connect, caplog: pytest.LogCaptureFixture
) -> None:
    client = connect()
    session = next(iter(app.wait_for_sessions(1).values()))

    def broken_render() -> None:
        raise RuntimeError("boom in render")

    session.scene.refresh = broken_render  # type: ignore[method-assign]
    with caplog.at_level(logging.ERROR, logger="app.session"):
        client.set_value(session.scene.gui_angles[1], 45.0)  # runs on viser's thread pool
        wait_until(lambda: session.gui_error.visible)
        session.scene.gui_angles[0].value = 10.0  # server-side assignment: must not raise either
    assert "boom in render" in session.gui_error.content
    assert any("boom in render" in str(r.exc_info[1]) for r in caplog.records if r.exc_info)

    # The server still accepts clients and builds sessions; the loop still ticks.
    ticks = app.tick_count
    connect()
    app.wait_for_sessions(2)
    wait_until(lambda: app.tick_count > ticks + 5)


def test_a_raising_tick_does_not_stop_the_loop_or_other_sessions(wait_until, app: App, connect) -> None:
    connect(), connect()
    s1, s2 = app.wait_for_sessions(2).values()
    good: list[float] = []

    def broken_tick(dt: float) -> None:
        raise ValueError("tick failed")

    s1.scene.frame = broken_tick  # type: ignore[method-assign]
    s2.scene.frame = good.append  # type: ignore[method-assign]
    wait_until(lambda: len(good) > 20)
    assert s1.gui_error.visible and "tick failed" in s1.gui_error.content
    assert s1.error_count > 1  # ticked again after failing
    assert not s2.gui_error.visible


# ---------------------------------------------------------------------------- entry point
def test_main_binds_loopback_by_default(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[tuple[str, int]] = []

    class FakeApp:
        port = 8080
        lectern = type("Lectern", (), {"code": "123456"})()

        def stop(self) -> None:
            calls.append(("stopped", 0))

    def fake_create_server(host: str, port: int, **_options: object) -> FakeApp:
        calls.append((host, port))
        return FakeApp()

    def interrupt(_seconds: float) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(app_main, "create_server", fake_create_server)
    monkeypatch.setattr(app_main.time, "sleep", interrupt)
    app_main.main([])
    assert calls == [("127.0.0.1", 8080), ("stopped", 0)]
    calls.clear()
    app_main.main(["--host", "0.0.0.0", "--port", "9000"])
    assert calls[0] == ("0.0.0.0", 9000)


def test_create_server_hides_share_button_and_sets_camera(monkeypatch: pytest.MonkeyPatch) -> None:
    themes: list[dict] = []
    original = viser.GuiApi.configure_theme

    def recording(self, **kwargs):  # type: ignore[no-untyped-def]
        themes.append(kwargs)
        return original(self, **kwargs)

    monkeypatch.setattr(viser.GuiApi, "configure_theme", recording)
    app = app_main.create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    try:
        assert app.server.get_host() == "127.0.0.1"
        assert themes and themes[-1]["show_share_button"] is False
        position = np.asarray(app.server.initial_camera.position)
        look_at = np.asarray(app.server.initial_camera.look_at)
    finally:
        app.stop()
    assert np.linalg.norm(position - look_at) > 3.0  # the whole scene in view, not inside it
    assert position[2] > look_at[2]  # looking down on the xy plane


# ---------------------------------------------------------------------------- Lagrange's equations live
def test_the_lagrange_tab_balances_at_rounding_and_draws_Q_as_projections_of_M(manual) -> None:
    manual.session.select_scene("Heavy top")
    manual.session.apply_preset("Loop")
    scene = manual.session.scene
    scene.transport.gui_integrator.value = "exact"
    scene.tabs.show("Lagrange")
    manual.session.play()
    manual.tick(0.7)
    manual.session.pause()
    content = scene.lagrange_readout.handle.content
    residual = [float(x) for x in re.search(r"residual = .*:\n\s+(\S+)\s+(\S+)\s+(\S+)", content).groups()]
    assert max(abs(r) for r in residual) < 1e-9, content
    mgl, theta = scene.sim.model.mgl, scene.sim.angles[1]
    q_theta = scene.q_arrows.vectors["theta"].segment
    torque = scene.q_arrows.vectors["M"].segment[1]
    scale = 1.2 / (mgl * math.sin(theta))  # |M| = mgl sin θ is drawn 1.2 units long
    np.testing.assert_allclose(np.linalg.norm(q_theta[1] - q_theta[0]), mgl * math.sin(theta) * scale, rtol=1e-5)
    assert np.linalg.norm(torque) == pytest.approx(1.2, rel=1e-5)
    scene.tabs.show("Setup")  # the Q arrows belong to the Lagrange tab
    assert not scene.q_arrows.vectors["M"].visible


def test_the_euler_angle_lagrangian_stops_at_the_vertical_and_offers_the_splitting(manual) -> None:
    manual.session.select_scene("Heavy top")
    manual.session.apply_preset("Through the vertical")
    scene = manual.session.scene
    scene.transport.gui_integrator.value = "euler_lagrange"
    assert scene.sim.integrator == "euler_lagrange"
    manual.session.play()
    manual.tick(1.0)  # θ reaches the vertical at t ≈ 0.59 s
    assert not scene.room.playing and 0.4 < scene.sim.t < 0.7
    assert "singular" in scene.message.text and "sin θ in a denominator" in scene.message.text
    assert scene.sim.integrator == "splitting4" and scene.transport.gui_integrator.value == "splitting4"
    manual.session.play()  # goes on with the splitting, through the vertical
    manual.tick(1.0)
    assert scene.room.playing and scene.sim.t > 1.4 and manual.session.last_error is None
