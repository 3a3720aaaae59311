"""The lecture hall: the presenter lock, followers who see and cannot change, explore and follow
back, a presenter who leaves.  Real websocket clients (`RawClient`), the app's loop not running:
the tests tick the rooms by hand."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import LectureHall as Hall
from conftest import hall_fixture, poll_until
from scipy.spatial.transform import Rotation

from app.kit.draw.widgets import POSE_QUANTUM
from app.lecture.follower import Follower
from app.lecture.lectern import LIVE_ROOT, MAX_TRIES, Lectern
from app.main import App

DT = 1.0 / 60.0
CODE = "424242"


hall = hall_fixture(CODE)


def _pose(node) -> np.ndarray:  # type: ignore[no-untyped-def]
    return Rotation.from_quat(np.asarray(node.wxyz), scalar_first=True).as_matrix()


def test_a_wrong_code_is_refused_and_tries_are_limited_per_minute() -> None:
    clock = [0.0]
    lectern = Lectern(server=None, code=CODE, clock=lambda: clock[0])  # type: ignore[arg-type]
    browser = type("S", (), {"client_id": 7})()
    for _ in range(MAX_TRIES):
        refusal = lectern.try_code(browser, "000000")  # type: ignore[arg-type]
        assert refusal is not None and refusal.startswith("Wrong presenter code")
    refusal = lectern.try_code(browser, CODE)  # type: ignore[arg-type]
    assert refusal is not None and "Too many wrong codes" in refusal  # even the right one, for now
    clock[0] = 61.0
    assert lectern.try_code(browser, CODE) is None  # type: ignore[arg-type]
    other = type("S", (), {"client_id": 8})()
    # The right code took the lock for browser 7: every code of another browser gets one answer.
    assert lectern.try_code(other, "000000") == lectern.try_code(other, CODE) == (  # type: ignore[arg-type]
        "Someone else is presenting; they must stop first.")
    lectern.release(browser, disconnected=True)  # type: ignore[arg-type]
    assert lectern.try_code(other, "000000") is not None and lectern.try_code(other, CODE) is None  # type: ignore[arg-type]


def test_followers_see_the_presenters_motion_and_cannot_change_it(hall: Hall) -> None:
    presenter, follower = hall.join(), hall.join()
    assert presenter.mode == follower.mode == "own"  # nobody presents: everyone explores alone
    presenter.select_scene("Free body")
    presenter.apply_preset("Dzhanibekov")
    presenter.present("wrong")
    assert presenter.mode == "own" and "Wrong presenter code" in presenter.gui_lecture_note.content
    presenter.present(CODE)
    hall.frames(1)  # the loop moves the other browsers
    assert presenter.mode == "presenting" and follower.mode == "following"
    assert isinstance(follower.scene, Follower) and follower.room is presenter.room
    live = presenter.scene
    assert live.root == LIVE_ROOT + "/free" and live.client.scene is hall.app.server.scene
    presenter.play()
    hall.frames(30)
    assert presenter.room.ticks == 30  # one simulation, advanced once a frame
    # While playing, poses are snapped to POSE_QUANTUM per quaternion component (widgets.quantized):
    # a rotation-matrix entry moves by at most ~4 quanta.
    np.testing.assert_allclose(_pose(live.body.node), presenter.simulation.state.R_space_body,
                               atol=4 * POSE_QUANTUM)
    assert "Free body" in follower.scene.gui_status.content and "Dzhanibekov" in follower.scene.gui_status.content
    # A follower's actions are refused; the presenter's room does not change.
    t = presenter.simulation.t
    follower.pause()
    follower.apply_preset("Disc")
    assert follower.error_count == 2 and "follows the presenter" in follower.last_error
    assert presenter.room.playing and presenter.simulation.t == t and presenter.simulation.preset == "Dzhanibekov"
    # A hand-made browser sends an update for the presenter's time-scale slider: not its handle.
    hall.clients[1].set_value(live.transport.gui_time_scale, 4.0)
    hall.clients[1].set_value(follower.scene.gui_follow_camera, False)  # its own handle: sent after
    poll_until(lambda: follower.scene.gui_follow_camera.value is False)
    with presenter.room.lock:
        assert presenter.room.time_scale == 1.0 and live.transport.gui_time_scale.value == 1.0
    # A second browser with the code cannot take over while someone presents.
    third = hall.join()
    assert third.mode == "following"  # joined during the presentation: follows at once
    third.present(CODE)
    assert third.mode != "presenting" and "Someone else is presenting" in third.gui_lecture_note.content


def test_explore_on_my_own_forks_the_state_and_follow_presenter_comes_back(hall: Hall) -> None:
    presenter, student = hall.join(), hall.join()
    presenter.select_scene("Heavy top")
    presenter.apply_preset("Loop")
    presenter.present(CODE)
    hall.frames(1)
    presenter.play()
    hall.frames(20)
    R_live = presenter.simulation.state.R_space_body.copy()
    t_live = presenter.simulation.t
    student.explore()
    assert student.mode == "own" and student.room is not presenter.room
    # An exact copy, playing as the presenter's plays, at the same time (not a restart at t = 0).
    assert np.array_equal(student.simulation.state.R_space_body, R_live)
    assert student.simulation.t == t_live > 0.0 and student.scene.title == "Heavy top"
    assert student.room.playing and student.simulation.preset == "Loop"
    assert len(student.simulation.traces["tip"]) == len(presenter.simulation.traces["tip"]) > 1
    assert student.showing.shadow is not None  # the shared scene is hidden in this browser
    hall.frames(10)
    assert student.simulation.t > t_live and presenter.room.ticks == 30
    np.testing.assert_array_equal(student.simulation.state.R_space_body, presenter.simulation.state.R_space_body)
    presenter.select_scene("Euler angles")  # a new scene goes live; the explorer stays put
    assert student.mode == "own" and student.scene.title == "Heavy top"
    student.follow()
    assert student.mode == "following" and student.room is presenter.room and student.showing.shadow is None
    hall.frames(40)
    assert "Euler angles" in student.scene.gui_status.content
    student.explore()  # the live scene now, never the student's earlier room
    assert student.scene.title == "Euler angles" and student.room is not presenter.room


def test_a_presenter_who_leaves_leaves_the_last_state_and_a_new_one_takes_over(hall: Hall) -> None:
    presenter, follower = hall.join(), hall.join()
    presenter.select_scene("Free body")
    presenter.present(CODE)
    hall.frames(1)
    presenter.play()
    hall.frames(10)
    live = presenter.scene
    hall.clients[0].close()  # the presenter's browser goes away
    poll_until(lambda: len(hall.app.sessions) == 1)
    assert hall.app.lectern.presenter is None and not live.body.node._impl.removed  # the last state stays
    hall.frames(40)  # the lectern refreshes the followers' panels
    assert "The presenter has left" in follower.scene.gui_status.content
    follower.present(CODE)  # a new presenter takes over with the code, from what is on screen
    assert follower.mode == "presenting" and live.body.node._impl.removed
    assert follower.scene.root == LIVE_ROOT + "/free"


def test_the_followers_change_only_through_the_lectern(hall: Hall) -> None:
    """Follow, explore and leave go through `add_follower` / `remove_follower`; the followers
    the lectern shows are a read-only view."""
    presenter, follower, leaver = hall.join(), hall.join(), hall.join()
    presenter.present(CODE)
    hall.frames(1)
    lectern = hall.app.lectern
    assert set(lectern.followers) == {follower.client_id, leaver.client_id}
    with pytest.raises(TypeError):
        lectern.followers[presenter.client_id] = lectern.followers[follower.client_id]  # type: ignore[index]
    follower.explore()
    assert set(lectern.followers) == {leaver.client_id} and follower.lecture_folder.visible
    hall.clients[2].close()  # the leaver's browser goes away
    poll_until(lambda: len(hall.app.sessions) == 2)
    assert not lectern.followers
    hall.frames(40)  # nothing is written to a browser that left
    assert presenter.error_count == follower.error_count == 0, (presenter.last_error, follower.last_error)


def test_stop_presenting_keeps_the_room_in_the_presenters_browser(hall: Hall) -> None:
    presenter, follower = hall.join(), hall.join()
    presenter.present(CODE)
    hall.frames(1)
    presenter.stop_presenting()
    assert presenter.mode == "own" and hall.app.lectern.presenter is None
    assert presenter.scene.root == "/e" and presenter.showing.shadow is not None
    assert follower.mode == "following"  # the last state stays on the followers' screens
    assert presenter.gui_present.visible and not presenter.gui_stop.visible
    assert not presenter.gui_follow.visible  # nobody presents: nothing to follow
    hall.frames(40)
    assert "stopped presenting" in follower.scene.gui_status.content
    assert "paused" not in follower.scene.gui_status.content


def test_the_app_prints_the_presenter_code_and_takes_it_from_the_command_line(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import app.main as app_main

    seen: list[object] = []

    class FakeApp:
        port = 8080
        lectern = type("L", (), {"code": "777777"})()

        def stop(self) -> None:
            pass

    def fake_create_server(host: str, port: int, **options: object) -> FakeApp:
        seen.append(options.get("presenter_code"))
        return FakeApp()

    def interrupt(_seconds: float) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(app_main, "create_server", fake_create_server)
    monkeypatch.setattr(app_main.time, "sleep", interrupt)
    app_main.main(["--presenter-code", "777777"])
    assert seen == ["777777"] and "presenter code: 777777" in capsys.readouterr().out
    app_main.main([])
    assert seen[-1] is None  # the app makes a random code


def test_random_codes_differ() -> None:
    codes = {Lectern(server=None).code for _ in range(20)}  # type: ignore[arg-type]
    # eight digits in two groups of four: 1e8 codes (app.lecture.gate.guess_chance)
    assert len(codes) > 15 and all(len(c) == 9 and c[4] == " " and (c[:4] + c[5:]).isdigit() for c in codes)


def test_app_api_is_unchanged() -> None:
    assert {"port", "stop", "wait_for_sessions"} <= set(dir(App))


# ---------------------------------------------------------------------------- keys and projector
def _commands(session) -> dict[str, object]:  # type: ignore[no-untyped-def]
    return {h._impl.props.label: h for h in session.client.gui._command_handle_from_uuid.values()}


def test_keys_drive_play_step_reset_and_presets_are_commands(hall: Hall) -> None:
    from viser import _messages

    session = hall.join()
    session.select_scene("Free body")
    commands = _commands(session)
    assert commands["Play / pause"]._impl.props.hotkey == "space"  # type: ignore[attr-defined]
    assert commands["Step"]._impl.props.hotkey == "S" and commands["Reset"]._impl.props.hotkey == "R"  # type: ignore[attr-defined]
    assert {f"Preset: {p.name}" for p in session.room.scene.presets()} <= set(commands)
    client = hall.clients[0]
    client.send(_messages.CommandTriggerMessage(commands["Play / pause"]._impl.uuid))  # type: ignore[attr-defined]
    poll_until(lambda: session.room.playing)
    hall.frames(10)
    client.send(_messages.CommandTriggerMessage(commands["Preset: Disc"]._impl.uuid))  # type: ignore[attr-defined]
    poll_until(lambda: session.simulation.preset == "Disc")
    client.send(_messages.CommandTriggerMessage(commands["Step"]._impl.uuid))  # type: ignore[attr-defined]
    poll_until(lambda: not session.room.playing and session.simulation.t > 0.0)
    client.send(_messages.CommandTriggerMessage(commands["Reset"]._impl.uuid))  # type: ignore[attr-defined]
    poll_until(lambda: session.simulation.t == 0.0)
    session.select_scene("Heavy top")  # the preset commands follow the scene
    assert "Preset: Loop" in _commands(session) and "Preset: Disc" not in _commands(session)
    assert session.error_count == 0, session.last_error


def test_projector_layout_styles_the_panel_and_enlarges_the_3d_labels(hall: Hall) -> None:
    session = hall.join()
    label = session.scene.nodes.label
    before = float(label.font_screen_scale)
    session.gui_projector.value = True  # the panel's toggle
    assert session.projector and session.projector_layout.style is not None
    assert "font-size: 19px" in session.projector_layout.style.content
    assert float(label.font_screen_scale) == pytest.approx(1.4 * before)
    session.select_scene("Heavy top")  # a new scene is built large too
    assert float(session.scene.nodes.label.font_screen_scale) == pytest.approx(1.4 * before)
    session.set_projector(False)
    assert session.projector_layout.style is None
    assert float(session.scene.nodes.label.font_screen_scale) == pytest.approx(before)


def test_a_refusal_stays_true_the_wait_counts_down_and_tries_agree_in_number() -> None:
    clock = [0.0]
    lectern = Lectern(server=None, code=CODE, clock=lambda: clock[0])  # type: ignore[arg-type]
    browser = type("S", (), {"client_id": 7})()
    for _ in range(MAX_TRIES - 1):
        lectern.try_code(browser, "000000")  # type: ignore[arg-type]
    assert lectern.refusal_now(browser) == "Wrong presenter code (1 try left this minute)."
    lectern.try_code(browser, "000000")  # type: ignore[arg-type]
    assert "wait 60 s" in str(lectern.refusal_now(browser))
    clock[0] = 15.5
    assert "wait 45 s" in str(lectern.refusal_now(browser))  # counts down
    clock[0] = 60.5
    assert lectern.refusal_now(browser) is None  # the wait is over: nothing to say
    presenter = type("S", (), {"client_id": 9})()
    lectern.presenter = presenter  # type: ignore[assignment]
    assert "Someone else" in str(lectern.try_code(browser, CODE))  # type: ignore[arg-type]
    assert "Someone else" in str(lectern.refusal_now(browser))
    lectern.presenter = None
    assert lectern.refusal_now(browser) is None  # they stopped


def test_a_followers_status_says_one_time_while_the_presenter_replays() -> None:
    from types import SimpleNamespace

    from app.kit.core.room import LIVE, REPLAYING
    from app.lecture.follower import FollowerStatus, Hall

    sim = SimpleNamespace(t=5.86, preset=None)
    room = SimpleNamespace(mode=REPLAYING, shown_t=6.01, live_t=9.5, time_scale=1.0, playing=True, sim=sim,
                           scene=SimpleNamespace(title="Free body"))
    text = FollowerStatus.of_room(room, Hall.LIVE).markdown()  # type: ignore[arg-type]
    assert text.count("t = ") == 1 and "replaying t = 6.0 s" in text
    room.mode = LIVE
    assert FollowerStatus.of_room(room, Hall.LIVE).markdown().count("t = ") == 1  # type: ignore[arg-type]
