"""The scene kit: every registered scene builds, plays and goes; one simulation, several views;
presets are data checked at start; simulations carry no viser; a frame sends only what changed.

Sessions come from real websocket connections (`RawClient`, conftest) with the app's loop not
running: the tests tick by hand.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest
from conftest import RawClient, poll_until, world_rotation
from scipy.spatial.transform import Rotation

from app.kit.core.presets import PRESETS_DIR, PresetError, load_presets
from app.kit.core.room import Room
from app.kit.draw.widgets import POSE_QUANTUM
from app.scenes import SCENES
from app.scenes.free_body import FreeBodyView
from app.scenes.heavy_top import HeavyTopView
from physics.exact_top import steady_precession_rate

DT = 1.0 / 60.0



def _is_label(name: str) -> bool:
    """A label node's name: "...label..." or an arrow's label "<arrow>/t/l" / "<arrow>/l" (draw.widgets.Vector)."""
    return "label" in name or name.endswith("/l")

def _state_vector(sim) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Every number a simulation's state holds, for a finiteness check."""
    if hasattr(sim, "state"):
        return np.concatenate([np.ravel(sim.state.R_space_body), sim.state.omega_body, [sim.t]])
    if hasattr(sim, "q_shown"):  # the constrained particles' q, q̇
        return np.array([*sim.q_shown, *sim.rates_shown, sim.t])
    if hasattr(sim, "positions"):  # the inertia scene's particles
        return np.concatenate([sim.masses, np.ravel(sim.positions), [sim.t]])
    return np.array([*sim.angles_deg, *sim.rates_deg, sim.t])


@pytest.mark.parametrize("title", list(SCENES))
def test_every_scene_builds_plays_every_preset_steps_resets_and_goes(manual, title: str) -> None:
    session = manual.session
    session.select_scene(title)
    view = session.scene
    assert view.title == title and view in session.room.views
    for preset in SCENES[title].presets():
        session.apply_preset(preset.name)
        session.play()
        manual.tick(0.5)
        assert session.room.playing, (title, preset.name, session.last_error)
        session.step()
        assert not session.room.playing
        t = session.simulation.t
        session.reset()
        assert session.simulation.t == 0.0 and t > 0.0
        assert np.all(np.isfinite(_state_vector(session.simulation))), (title, preset.name)
    assert session.error_count == 0, session.last_error
    other = next(name for name in SCENES if name != title)
    panel = list(view._gui_roots)
    session.select_scene(other)  # the scene is removed: its panel and nodes go
    assert view not in view.room.views and panel and all(h._impl.removed for h in panel)
    assert view._root_node._impl.removed


@pytest.mark.parametrize("title", list(SCENES))
def test_a_preset_starts_paused_at_its_t_0_in_every_scene(manual, title: str) -> None:
    """The one rule of `SceneView.apply_preset`: whatever the room was doing, a preset stops it
    at the preset's t = 0 and names it; a new simulation is at the first preset; the presets
    are read once per scene."""
    session = manual.session
    session.select_scene(title)
    scene = SCENES[title]
    assert scene.presets() is scene.presets()
    first, last = scene.presets()[0], scene.presets()[-1]
    assert session.simulation.preset == first.name
    session.play()
    manual.tick(0.5)
    session.apply_preset(last.name)
    assert not session.room.playing and session.simulation.t == 0.0, (title, session.last_error)
    assert session.simulation.preset == last.name and session.error_count == 0
    transport = getattr(session.scene, "transport", None)
    assert transport is None or transport.gui_play.label == "Play"
    fresh = scene.new_simulation()
    assert fresh.preset == first.name and fresh.t == 0.0


def test_a_preset_the_scene_does_not_have_is_a_clear_error_through_the_guard(manual) -> None:
    session = manual.session
    assert session.scene.title == "Euler angles"
    session.apply_preset("Disc")  # a free-body preset, asked of the Euler-angles scene
    assert session.error_count == 1
    assert "Euler angles has no preset 'Disc'" in session.last_error and "gimbal lock" in session.last_error
    assert session.scene.sim.angles_deg == [30.0, 50.0, 20.0]  # nothing changed


def test_one_simulation_drawn_by_two_views_advances_once_per_frame(manual) -> None:
    """A second browser watches the first one's room: both draw the same motion, and the
    simulation advances once per frame however many views it has."""
    second = RawClient(manual.app.port)
    try:
        sessions = manual.app.wait_for_sessions(2)
        a = manual.session
        (b,) = (s for s in sessions.values() if s is not a)
        a.select_scene("Free body")
        a.apply_preset("Dzhanibekov")
        b.watch(a.room)
        assert b.room is a.room and len(a.room.views) == 2 and b.scene is not a.scene
        assert manual.app.rooms() == [a.room]
        a.play()
        for _ in range(30):  # what the loop does: each room once
            for room in manual.app.rooms():
                room.tick(DT)
        assert a.room.ticks == 30 and a.simulation.t == pytest.approx(30 * DT)
        pose_a = Rotation.from_quat(np.asarray(a.scene.body.node.wxyz), scalar_first=True).as_matrix()
        pose_b = Rotation.from_quat(np.asarray(b.scene.body.node.wxyz), scalar_first=True).as_matrix()
        # A playing frame sends the pose at display resolution (a quaternion in multiples of POSE_QUANTUM).
        np.testing.assert_allclose(pose_a, a.simulation.state.R_space_body, atol=4 * POSE_QUANTUM)
        np.testing.assert_allclose(pose_b, pose_a, atol=1e-12)
        # The watcher's panel shows the room's transport; its Pause pauses the room for both.
        assert b.scene.transport.gui_play.label == "Pause"
        b.pause()
        assert not a.room.playing and a.scene.transport.gui_play.label == "Play"
        b.select_scene("Euler angles")  # the watcher leaves: the room keeps its first view
        assert a.room.views == [a.scene] and a.error_count == b.error_count == 0
    finally:
        second.close()


def test_a_view_can_draw_two_bodies(manual) -> None:
    """The kit's Body is instantiable twice (a solid body and, say, a ghost) on one client."""
    from app.kit.draw.widgets import Body

    session = manual.session
    session.select_scene("Free body")
    view = session.scene
    ghost = Body(session.client.scene, "/free/ghost", lambda scene, parent: view.build_shape(scene, parent,
                                                                                           view.sim.model))
    R = Rotation.from_euler("ZXZ", [10, 20, 30], degrees=True).as_matrix()
    ghost.pose(R)
    view.body.pose(np.eye(3))
    np.testing.assert_allclose(Rotation.from_quat(np.asarray(ghost.node.wxyz), scalar_first=True).as_matrix(), R,
                               atol=1e-12)
    assert tuple(view.body.node.wxyz) == (1.0, 0.0, 0.0, 0.0)


def test_a_paused_frame_sends_nothing_and_a_free_body_sends_L_once(manual, monkeypatch) -> None:
    session = manual.session
    session.select_scene("Free body")
    sent: list[tuple[str, tuple[str, ...]]] = []
    api = session.client.scene
    original = api._queue_scene_message

    def recording(message):  # type: ignore[no-untyped-def]
        updates = getattr(message, "updates", None)
        sent.append((getattr(message, "name", ""), tuple(updates) if updates else (type(message).__name__,)))
        return original(message)

    manual.tick(0.2)  # the labels' layer lays out once for the camera the session has just set
    monkeypatch.setattr(api, "_queue_scene_message", recording)
    manual.tick(0.5)
    assert sent == []  # paused: nothing at all
    session.play()
    manual.tick(0.5)
    assert [u for u in sent if u[0] == "/free/b"] == [("/free/b", ("SetOrientationMessage",))] * 30  # every frame
    assert [u for u in sent if u[0].startswith("/free/L")] == []  # L is fixed in space: never resent
    hand = [u for u in sent if u[0].startswith("/free/hand/")]  # the ω and L gizmos hide once, at Play
    assert sorted(hand) == [(f"/free/hand/{k}", ("SetSceneNodeVisibilityMessage",)) for k in ("L", "omega")]
    # Labels: shown, hidden or moved to another anchor by the view's LabelLayer, at most 10 times a second.
    layout = [u for u in sent if u[1] in (("anchor",), ("SetSceneNodeVisibilityMessage",)) and _is_label(u[0])]
    assert len(layout) <= 5 * len(session.scene.labels._entries)
    assert {name for name, _ in sent if name not in dict(hand) and (name, _) not in layout} <= {
        "/free/b", "/free/nodes", "/free/w", "/free/omega_label"}


# ---------------------------------------------------------------------------- presets
def test_every_preset_file_is_valid_and_steady_is_the_slow_root() -> None:
    for scene in SCENES.values():
        assert scene.presets()
    steady = HeavyTopView.preset("Steady")
    I1, I3, mgl = steady.params
    spin, phi_dot_deg, theta_dot_deg = steady.rates
    expected = steady_precession_rate(I1, I3, mgl, spin, math.radians(steady.angles_deg[1]))
    assert math.radians(phi_dot_deg) == pytest.approx(expected, rel=1e-12) and theta_dot_deg == 0.0
    assert HeavyTopView.preset("Wave").rates[1] == pytest.approx(0.5 * phi_dot_deg, rel=1e-12)


@pytest.mark.parametrize(("edit", "message"), [
    (lambda d: d["presets"][1]["params"].update(I3=7.0), r"presets\[1\]\.params\.I3: 7\.0 is outside \[0\.05, 5\]"),
    (lambda d: d["presets"][0]["params"].update(I3=2.0), r"presets\[0\] \(Dzhanibekov\): .*I1 \+ I2 >= I3"),
    (lambda d: d["presets"][2].pop("angles_deg"), r"presets\[2\]\.angles_deg: missing"),
    (lambda d: d["presets"][0]["rates"].update(w9=1.0), r"presets\[0\]\.rates: unknown key 'w9'"),
    (lambda d: d["presets"][3].update(name="Disc"), r"presets\[3\]\.name: 'Disc' appears twice"),
    (lambda d: d["presets"][0]["rates"].update(w1="fast"), r"presets\[0\]\.rates\.w1: 'fast' is not a number"),
    (lambda d: d.update(presets=[]), r"presets: missing or empty"),
])
def test_a_broken_preset_file_is_refused_naming_file_and_field(tmp_path: Path, edit, message: str) -> None:
    data = json.loads((PRESETS_DIR / FreeBodyView.preset_file).read_text(encoding="utf-8"))
    edit(data)
    path = tmp_path / "free_body.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(PresetError, match=str(path).replace(".", r"\.") + ": " + message):
        load_presets(path, FreeBodyView.param_specs, FreeBodyView.rate_specs,
                     check=lambda preset: FreeBodyView.initial_conditions(preset) and None)


def test_an_unreadable_preset_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "x.json"
    path.write_text("{ not json", encoding="utf-8")
    with pytest.raises(PresetError, match="not readable JSON"):
        load_presets(path)
    with pytest.raises(PresetError, match="no such file"):
        load_presets(tmp_path / "missing.json")


def test_the_app_refuses_to_start_with_a_broken_preset_file(monkeypatch: pytest.MonkeyPatch) -> None:
    import app.main as app_main

    def broken() -> None:
        raise PresetError("assets/presets/free_body.json: presets[0].params.I1: missing")

    monkeypatch.setattr(app_main, "check_presets", broken)
    with pytest.raises(PresetError, match="presets\\[0\\]"):
        app_main.create_server("127.0.0.1", 0, verbose=False, start_loop=False)


# ---------------------------------------------------------------------------- layering
def test_simulations_and_physics_import_no_viser() -> None:
    code = ("import sys, app.kit.rigid.simulation, app.kit.core.samples, app.kit.core.presets, physics.realtime; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in {'viser', 'trimesh'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[1]).stdout.strip()
    assert out == "[]"


def test_room_pauses_and_tells_every_view_when_the_simulation_fails() -> None:
    class Failing:
        t, version = 0.0, 0

        def advance(self, dt: float) -> None:
            raise ArithmeticError("non-finite state at t = 0.1 s")

        def reset(self) -> None:
            pass

    class Recorder:
        timeline = None

        def __init__(self) -> None:
            self.messages: list[str] = []
            self.frames = 0

        def frame(self, dt: float) -> None:
            self.frames += 1

        def refresh(self) -> None:
            pass

        def show_message(self, text: str) -> None:
            self.messages.append(text)

    room = Room(None, Failing())
    views = [Recorder(), Recorder()]
    for view in views:
        room.add_view(view)
    room.play()
    room.tick(DT)
    assert not room.playing and room.ticks == 0
    assert all(v.messages == ["The simulation stopped: non-finite state at t = 0.1 s"] for v in views)
    assert all(v.frames == 1 for v in views)


def test_fast_pose_and_points_writes_queue_what_the_public_setters_queue(manual, monkeypatch) -> None:
    from app import viser_internals as seam

    assert seam.FAST_SETTERS.on  # viser 1.1's internals are there (pyproject pins viser to 1.1.x)
    scene = manual.session.client.scene
    frame = scene.add_frame("/probe/frame", show_axes=False)
    label = scene.add_label("/probe/label", "x")
    arrow = scene.add_arrows("/probe/arrow", np.zeros((1, 2, 3)), (1, 2, 3))
    queued: list = []
    original = scene._queue_scene_message
    monkeypatch.setattr(scene, "_queue_scene_message", lambda m: (queued.append(m), original(m))[1])

    def wire(message) -> dict:  # type: ignore[no-untyped-def]
        out = message.as_serializable_dict()
        return {k: (np.asarray(v).tolist() if k != "type" else v) for k, v in out.items()}

    q = (math.cos(0.3), 0.0, math.sin(0.3), 0.0)
    points = np.array([[[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]]], dtype=np.float32)
    for public, fast, value in (
        (lambda v: setattr(frame, "wxyz", v), lambda v: seam.set_wxyz(frame, v), q),
        (lambda v: setattr(label, "position", v), lambda v: seam.set_position(label, v), (1.0, 2.0, 3.0)),
        (lambda v: setattr(arrow, "points", v), lambda v: seam.set_points(arrow, v), points),
    ):
        public(value)
        by_setter = wire(queued[-1])
        stored = (np.array(frame.wxyz), np.array(label.position), np.array(arrow.points))
        queued.clear()
        fast(value)  # the same value again: the public setter would skip it, the fast one sends
        assert wire(queued[-1]) == by_setter
        np.testing.assert_array_equal(np.array(frame.wxyz), stored[0])
        np.testing.assert_array_equal(np.array(label.position), stored[1])
        np.testing.assert_array_equal(np.array(arrow.points), stored[2])
    frame.remove()
    with pytest.raises(RuntimeError, match="removed"):
        seam.set_wxyz(frame, q)


def test_a_steady_top_hangs_from_its_phi_theta_frame_and_sends_no_omega_or_L(manual, monkeypatch) -> None:
    """The heavy top's body is the ψ child of the φ-θ frame; the line of nodes, ω and L hang from
    that frame: in steady precession a frame sends the two poses and nothing for ω, L or the
    nodes, and what is drawn is the state (composed poses against R_space_body; ω's and L's tips
    in space against R ω_b and R I ω_b)."""
    session = manual.session
    session.select_scene("Heavy top")
    session.apply_preset("Steady")
    view = session.scene
    sent: list[tuple[str, str]] = []
    api = session.client.scene
    original = api._queue_scene_message

    def recording(message):  # type: ignore[no-untyped-def]
        sent.append((getattr(message, "name", ""), type(message).__name__))
        return original(message)

    manual.tick(0.2)
    session.play()
    manual.tick(0.1)  # the first playing frames (the hand gizmos hide, arrows settle at the playing resolution)
    monkeypatch.setattr(api, "_queue_scene_message", recording)
    manual.tick(0.5)
    poses = [name for name, kind in sent if kind == "SetOrientationMessage"]
    assert poses.count("/top/tilt") == 30 and poses.count("/top/tilt/b") == 30  # every frame
    moved = {name for name, _ in sent if name.startswith(("/top/tilt/w", "/top/tilt/L", "/top/tilt/nodes"))
             and not _is_label(name)}
    assert moved == set(), sent
    sim = view.sim
    R = sim.state.R_space_body
    np.testing.assert_allclose(world_rotation(view.body.node), R, atol=4 * POSE_QUANTUM)
    session.pause()  # a refresh: exact poses
    R = sim.state.R_space_body
    np.testing.assert_allclose(world_rotation(view.body.node), R, atol=1e-12)
    R_tilt = world_rotation(view._tilt_node)
    np.testing.assert_allclose(R_tilt[:, 0], [math.cos(sim.angles[0]), math.sin(sim.angles[0]), 0.0], atol=1e-12)
    omega_tip = R_tilt @ view.omega.segment[1] / view.omega_scale
    L_tip = R_tilt @ view.L.segment[1] / view.L_scale
    np.testing.assert_allclose(omega_tip, R @ sim.state.omega_body, atol=1e-9)
    np.testing.assert_allclose(L_tip, R @ (np.asarray(sim.model.inertia) * sim.state.omega_body), atol=1e-9)


def test_the_loop_writing_a_slider_does_not_wait_for_a_callback_that_waits_for_the_room(manual) -> None:
    """The app loop draws under the room's lock, and a slider it writes runs its callback at once
    (viser calls it synchronously); meanwhile a callback of the same browser holds the session's
    lock and waits for the room's.  The loop's write must finish (CI once hung 300 s here: the
    loop waited for the session's lock)."""
    session = manual.session
    session.select_scene("Free body")
    room, view = session.room, session.scene
    slider = view.gui_angles[0]
    room_held, written = threading.Event(), threading.Event()
    ran: list[str] = []

    def loop() -> None:
        with room.lock:
            room_held.set()
            poll_until(lambda: not _free(session._busy))  # the callback below holds it
            view.quiet.write(slider, float(slider.value) + 1.0)  # runs the slider's guarded callback
            written.set()

    def callback() -> None:
        room_held.wait(5.0)
        session.guard("test", lambda: ran.append("callback"))()  # session lock, then the room's

    threads = [threading.Thread(target=loop, daemon=True), threading.Thread(target=callback, daemon=True)]
    for thread in threads:
        thread.start()
    assert written.wait(5.0), "the loop's slider write waited for the session's lock"
    for thread in threads:
        thread.join(5.0)
    assert ran == ["callback"] and session.error_count == 0, session.last_error


def _free(lock: threading.RLock) -> bool:
    """`lock` is not held by another thread now (taken and given back at once if free)."""
    if not lock.acquire(blocking=False):
        return False
    lock.release()
    return True
