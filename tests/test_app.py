"""Server-side tests of the lecture app (no browser).

Sessions come from real websocket connections (`RawClient`, conftest), so `client.gui` /
`client.scene` are the real per-client APIs.  References are independent of the app:
SciPy's `Rotation.from_euler("ZXZ", ...)` for D, (cos φ, sin φ, 0) written out for the line
of nodes, and the forward box formula I1 = m (b² + c²) / 12 for the body's shape.
"""

from __future__ import annotations

import logging
import math
import re
import time

import numpy as np
import pytest
import viser
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import app.main as app_main
from app.explorer import INITIAL_ANGLES_DEG, INITIAL_CAMERA
from app.main import App
from app.session import Session

ATOL_POSE = 1e-6  # viser keeps poses as float32-exact numbers at worst
ATOL_READOUT = 0.6e-4  # the matrix readout has 4 decimals


def D_reference(phi_deg: float, theta_deg: float, psi_deg: float) -> np.ndarray:
    return Rotation.from_euler("ZXZ", [phi_deg, theta_deg, psi_deg], degrees=True).as_matrix()


def body_matrix(session: Session) -> np.ndarray:
    """The body node's orientation as the client receives it (wxyz), as a matrix."""
    wxyz = np.asarray(session.scene.body_node.wxyz, dtype=float)
    return Rotation.from_quat(wxyz, scalar_first=True).as_matrix()


def one_session(app: App, connect) -> Session:
    connect()
    return next(iter(app.wait_for_sessions(1).values()))


def set_angles(session: Session, phi: float, theta: float, psi: float) -> None:
    scene = session.scene
    scene.gui_phi.value, scene.gui_theta.value, scene.gui_psi.value = phi, theta, psi


# ---------------------------------------------------------------------------- sessions
def test_each_client_gets_its_own_session_gui_and_body(wait_until, app: App, connect) -> None:
    a = connect()
    (s1,) = app.wait_for_sessions(1).values()
    connect()
    (s2,) = (s for s in app.wait_for_sessions(2).values() if s is not s1)
    assert s1.client is not s2.client
    assert s1.scene.gui_theta._impl.uuid != s2.scene.gui_theta._impl.uuid

    a.set_value(s1.scene.gui_theta, 60.0)  # a browser moves ITS θ slider
    wait_until(lambda: s1.scene.angles_deg[1] == 60.0)
    time.sleep(0.1)
    phi0, theta0, psi0 = INITIAL_ANGLES_DEG
    assert s2.scene.angles_deg == [phi0, theta0, psi0]
    np.testing.assert_allclose(body_matrix(s2), D_reference(phi0, theta0, psi0), atol=ATOL_POSE)
    np.testing.assert_allclose(body_matrix(s1), D_reference(phi0, 60, psi0), atol=ATOL_POSE)

    a.close()
    remaining = app.wait_for_sessions(1)
    assert list(remaining) == [s2.client_id]
    assert s1.closed and not s2.closed


def test_sessions_are_ticked_by_a_paced_60hz_loop(app: App, connect) -> None:
    session = one_session(app, connect)
    dts: list[float] = []
    session.scene.tick = dts.append  # type: ignore[method-assign]
    time.sleep(1.0)
    # 60 Hz nominal; generous lower bound for a loaded 2-core machine, strict upper bound
    # (a busy loop would give thousands).
    assert 30 <= len(dts) <= 70, len(dts)
    assert max(dts) <= app_main.MAX_TICK_DT
    assert 1 / 75 < float(np.median(dts)) < 1 / 30


# ---------------------------------------------------------------------------- angles
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    phi=st.floats(-180.0, 180.0),
    theta=st.floats(0.0, 180.0),
    psi=st.floats(-180.0, 180.0),
)
def test_sliders_turn_body_as_scipy_zxz(app: App, connect, phi: float, theta: float, psi: float) -> None:
    session = next(iter(app.sessions.values()), None) or one_session(app, connect)
    set_angles(session, phi, theta, psi)
    np.testing.assert_allclose(body_matrix(session), D_reference(phi, theta, psi), atol=ATOL_POSE)

    # Line of nodes: the segment through the origin along (cos φ, sin φ, 0).
    start, end = np.asarray(session.scene.nodes_line.points, dtype=float)[0]
    np.testing.assert_allclose(start, -end, atol=ATOL_POSE)
    expected = np.array([math.cos(math.radians(phi)), math.sin(math.radians(phi)), 0.0])
    np.testing.assert_allclose(end / np.linalg.norm(end), expected, atol=ATOL_POSE)

    # Intermediate frames: Rz(φ) and Rz(φ) Rx(θ), again from SciPy.
    after_phi = Rotation.from_quat(np.asarray(session.scene.after_phi_node.wxyz), scalar_first=True)
    after_theta = Rotation.from_quat(np.asarray(session.scene.after_theta_node.wxyz), scalar_first=True)
    np.testing.assert_allclose(after_phi.as_matrix(), Rotation.from_euler("z", phi, degrees=True).as_matrix(),
                               atol=ATOL_POSE)
    np.testing.assert_allclose(after_theta.as_matrix(),
                               Rotation.from_euler("ZX", [phi, theta], degrees=True).as_matrix(), atol=ATOL_POSE)


def _matrices_in(markdown: str) -> list[np.ndarray]:
    """Every 3x3 block of '[ a  b  c ]' rows in the markdown."""
    rows = [[float(x) for x in row.split()] for row in re.findall(r"\[\s*([-\d.\s]+?)\s*\]", markdown)]
    return [np.array(rows[i:i + 3]) for i in range(0, len(rows), 3)]


def test_readout_shows_D_and_its_three_factors(app: App, connect) -> None:
    session = one_session(app, connect)
    phi, theta, psi = 30.0, 50.0, 20.0
    set_angles(session, phi, theta, psi)
    (D_shown,) = _matrices_in(session.scene.gui_matrix.content)
    np.testing.assert_allclose(D_shown, D_reference(phi, theta, psi), atol=ATOL_READOUT)
    factors = _matrices_in(session.scene.gui_factors.content)
    expected = [Rotation.from_euler(axis, angle, degrees=True).as_matrix()
                for axis, angle in (("z", phi), ("x", theta), ("z", psi))]
    assert len(factors) == 3
    for shown, reference in zip(factors, expected):
        np.testing.assert_allclose(shown, reference, atol=ATOL_READOUT)
    assert "-0.0000" not in session.scene.gui_matrix.content


@pytest.mark.parametrize(
    ("theta", "note"), [(0.0, "φ + ψ"), (1.0, "φ + ψ"), (180.0, "φ − ψ"), (179.5, "φ − ψ")]
)
def test_gimbal_lock_fades_line_of_nodes_and_says_what_is_defined(
    app: App, connect, theta: float, note: str
) -> None:
    session = one_session(app, connect)
    scene = session.scene
    set_angles(session, 40.0, theta, 10.0)
    assert scene.gui_gimbal_note.visible
    assert "Gimbal lock" in scene.gui_gimbal_note.content and note in scene.gui_gimbal_note.content
    assert "undefined" in scene.nodes_label.text
    faded = np.asarray(scene.nodes_line.colors).reshape(-1, 3)
    assert np.all(faded == faded[0]) and faded[0, 0] == faded[0, 1] == faded[0, 2]  # grey

    scene.gui_theta.value = 90.0
    assert not scene.gui_gimbal_note.visible
    assert scene.nodes_label.text == "line of nodes"
    colour = np.asarray(scene.nodes_line.colors).reshape(-1, 3)[0]
    assert len(set(colour.tolist())) > 1  # not grey


def test_intermediate_frames_toggle(app: App, connect) -> None:
    scene = one_session(app, connect).scene
    assert scene.after_phi_node.visible and scene.after_theta_node.visible
    scene.gui_show_frames.value = False
    assert not scene.after_phi_node.visible and not scene.after_theta_node.visible


# ---------------------------------------------------------------------------- clamping
def test_out_of_range_server_values_are_clamped(app: App, connect) -> None:
    session = one_session(app, connect)
    scene = session.scene
    scene.gui_theta.value = 500.0
    assert scene.gui_theta.value == 180.0 and scene.angles_deg[1] == 180.0
    scene.gui_phi.value = -1e9
    assert scene.gui_phi.value == -180.0
    psi0 = INITIAL_ANGLES_DEG[2]
    np.testing.assert_allclose(body_matrix(session), D_reference(-180.0, 180.0, psi0), atol=ATOL_POSE)


def test_out_of_range_and_nan_from_a_client_are_clamped(wait_until, app: App, connect) -> None:
    client = connect()
    session = next(iter(app.wait_for_sessions(1).values()))
    scene = session.scene
    client.set_value(scene.gui_theta, 1e6)  # viser itself accepts this (VISER.md pitfall 4)
    wait_until(lambda: scene.gui_theta.value == 180.0)
    assert scene.angles_deg[1] == 180.0

    client.set_value(scene.gui_psi, 33.0)
    wait_until(lambda: scene.angles_deg[2] == 33.0)
    client.set_value(scene.gui_psi, float("nan"))  # NaN: keep the last valid value
    wait_until(lambda: not math.isnan(scene.gui_psi.value) and scene.gui_psi.value == 33.0)
    assert np.all(np.isfinite(np.asarray(scene.body_node.wxyz)))

    client.set_value(scene.gui_moments[0], -3.0)
    wait_until(lambda: scene.gui_moments[0].value == 0.1)
    assert session.last_error is None


# ---------------------------------------------------------------------------- moments
def _moments_of_box(dimensions) -> np.ndarray:
    """Forward formula, independent of the app: I1 = m (b² + c²)/12 and cyclic (m = 12)."""
    a, b, c = dimensions
    return np.array([b * b + c * c, a * a + c * c, a * a + b * b])


def test_moments_reshape_the_box(app: App, connect) -> None:
    scene = one_session(app, connect).scene
    for k, value in enumerate((1.0, 1.5, 2.0)):
        scene.gui_moments[k].value = value
    moments = _moments_of_box(scene.body_box.dimensions)
    # Same shape up to scale: the drawn box has these moments for some mass.
    np.testing.assert_allclose(moments / moments.sum(), np.array([1.0, 1.5, 2.0]) / 4.5, atol=1e-6)
    assert max(scene.body_box.dimensions) == pytest.approx(1.25)
    assert "Not a rigid body" not in scene.gui_moments_status.content


def test_invalid_moments_keep_the_last_valid_body_and_say_why(app: App, connect) -> None:
    session = one_session(app, connect)
    scene = session.scene
    before = tuple(scene.body_box.dimensions)
    moments_before = scene.moments
    scene.gui_moments[2].value = 4.0  # 1 + 2 < 4: breaks I1 + I2 >= I3
    assert tuple(scene.body_box.dimensions) == before
    assert scene.moments == moments_before
    status = scene.gui_moments_status.content
    assert "Not a rigid body" in status and "I1 + I2 >= I3" in status
    assert session.last_error is None  # a refused input is not an error of the app

    scene.gui_moments[2].value = 3.0  # 1 + 2 = 3: a flat lamina, allowed
    assert scene.moments == (1.0, 2.0, 3.0)
    assert min(scene.body_box.dimensions) < 0.05
    assert "lamina" in scene.gui_moments_status.content


# ---------------------------------------------------------------------------- robustness
def test_a_raising_callback_is_shown_and_the_server_keeps_serving(
    wait_until, app: App, connect, caplog: pytest.LogCaptureFixture
) -> None:
    client = connect()
    session = next(iter(app.wait_for_sessions(1).values()))

    def broken_render() -> None:
        raise RuntimeError("boom in render")

    session.scene.render = broken_render  # type: ignore[method-assign]
    with caplog.at_level(logging.ERROR, logger="app.session"):
        client.set_value(session.scene.gui_theta, 45.0)  # runs on viser's thread pool
        wait_until(lambda: session.gui_error.visible)
        session.scene.gui_phi.value = 10.0  # server-side assignment: must not raise either
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

    s1.scene.tick = broken_tick  # type: ignore[method-assign]
    s2.scene.tick = good.append  # type: ignore[method-assign]
    wait_until(lambda: len(good) > 20)
    assert s1.gui_error.visible and "tick failed" in s1.gui_error.content
    assert s1.error_count > 1  # ticked again after failing
    assert not s2.gui_error.visible


# ---------------------------------------------------------------------------- entry point
def test_main_binds_loopback_by_default(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[tuple[str, int]] = []

    class FakeApp:
        port = 8080

        def stop(self) -> None:
            calls.append(("stopped", 0))

    def fake_create_server(host: str, port: int) -> FakeApp:
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
    position = np.asarray(app.server.initial_camera.position)
    look_at = np.asarray(app.server.initial_camera.look_at)
    assert np.linalg.norm(position - look_at) > 3.0  # the whole scene in view, not inside it
    assert position[2] > look_at[2]  # looking down on the xy plane


def test_angle_presets_from_server_and_client(wait_until, app: App, connect) -> None:
    client = connect()
    session = next(iter(app.wait_for_sessions(1).values()))
    scene = session.scene
    scene.gui_presets.value = "D = 1"
    np.testing.assert_allclose(body_matrix(session), np.eye(3), atol=ATOL_POSE)
    client.set_value(scene.gui_presets, "gimbal lock")
    wait_until(lambda: scene.angles_deg == [30.0, 0.0, 20.0])
    assert scene.gui_gimbal_note.visible
    client.set_value(scene.gui_presets, "no such preset")  # a client can send any string
    wait_until(lambda: scene.angles_deg == list(INITIAL_ANGLES_DEG))
    assert session.last_error is None


def test_reset_view_and_remove(app: App, connect) -> None:
    session = one_session(app, connect)
    session.client.camera.position = (9.0, 9.0, 9.0)
    session.scene.reset_view()
    np.testing.assert_allclose(session.client.camera.position, INITIAL_CAMERA["position"], atol=1e-9)
    session.scene.remove()  # the next issue swaps scenes; removing must work
    assert session.last_error is None
