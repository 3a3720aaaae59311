"""The presenter's room is the presenter's (app.lectern's rule), tried with a hostile follower on
a raw websocket, in every scene; Explore copies what the presenter shows, exactly; the follower
panel stays current; a phone follower's camera is framed for its aspect.

The hostile follower (benchmarks.ws_client.ViserClient, which decodes every frame it is sent):
- sends an update for every GUI id it has seen (numbers far out of range, NaN, strings, True),
  presses every button and triggers every command it has seen;
- drags every transform gizmo and clicks and drags every scene node it was sent, addressed to
  the shared scope and, guessing, to the presenter's scope (its client id as owner) and to the
  names the presenter's own gizmos and balls have;
- uploads a mesh to every upload button it has seen;
- and, as if it had learned them, sends updates, clicks and uploads to the uuids of the
  presenter's own panel (known here from the server side).
The app's loop does not run (the test ticks), so the presenter's simulation can only change if
something the hostile sent changed it: its fingerprint must stay bit-identical.
"""

from __future__ import annotations

import dataclasses
import math
import time
import uuid as uuidlib
from typing import Any

import numpy as np
import pytest
from conftest import LectureHall, RawClient, hall_fixture, poll_until

from app.kit.draw.screen import project_one, screen_of
from app.lecture.lectern import BODY_WIDTH_SHARE, NARROW_MARGIN, fitted_camera
from app.scenes import SCENES
from benchmarks.ws_client import ViserClient

DT = 1.0 / 60.0
CODE = "135790"
BOX_STL = b"""solid box
facet normal 0 0 -1
outer loop
vertex 0 0 0
vertex 1 1 0
vertex 1 0 0
endloop
endfacet
endsolid box
"""


def fingerprint(obj: Any, depth: int = 0) -> Any:
    """Everything a simulation holds, as comparable plain values (arrays as dtype, shape, bytes)."""
    if isinstance(obj, np.ndarray):
        return ("array", obj.dtype.str, obj.shape, obj.tobytes())
    if isinstance(obj, (bool, int, str, bytes, type(None))):
        return obj
    if isinstance(obj, float):
        return ("float", obj.hex())
    if isinstance(obj, (list, tuple)):
        return tuple(fingerprint(v, depth + 1) for v in obj)
    if isinstance(obj, dict):
        return tuple(sorted((str(k), fingerprint(v, depth + 1)) for k, v in obj.items()))
    if callable(obj) or depth > 4:
        return type(obj).__name__
    fields = getattr(obj, "__dict__", None)
    if fields is None:
        slots = getattr(type(obj), "__slots__", ())
        fields = {name: getattr(obj, name) for name in slots if hasattr(obj, name)}
    return (type(obj).__name__, tuple(sorted((k, fingerprint(v, depth + 1)) for k, v in fields.items()
                                             if not k.startswith("_cache"))))


class Hall(LectureHall):
    """The lecture hall; `join` gives (session, client)."""

    def join(self, client_factory: Any = RawClient) -> Any:  # type: ignore[override]
        return self.join_with_client(client_factory)


hall = hall_fixture(CODE, Hall)


def _messages_seen(client: ViserClient) -> list[dict[str, Any]]:
    with client.state.lock:
        return [message for _, _, message in client.state.messages]


def _hostile_values(message: dict[str, Any]) -> list[Any]:
    value = message.get("value")
    if isinstance(value, bool):
        return [not value, True]
    if isinstance(value, (int, float)):
        return [1e9, -5.0, math.nan, "x", 0]
    if isinstance(value, (list, tuple)):
        return [[1e9] * len(value), [math.nan] * len(value), "x"]
    if isinstance(value, str):
        return ["nonsense", "Free body", "Euler angles", "000000"]
    return [True]  # buttons and the like: a click


def attack(hostile: ViserClient, presenter_session: Any) -> int:
    """Everything a hostile follower can send; the number of messages sent."""
    from viser import _messages

    sent = 0

    def send(message: Any) -> None:
        nonlocal sent
        hostile.send(message)
        sent += 1

    seen = _messages_seen(hostile)
    gui_ids = {m["uuid"]: m for m in seen if m.get("type", "").startswith("Gui") and "uuid" in m
               and "props" in m}
    node_names = {m["name"] for m in seen if isinstance(m.get("name"), str) and m.get("type", "").endswith("Message")}
    gizmo_names = {m["name"] for m in seen if m.get("type") == "TransformControlsMessage"}
    uploads = [u for u, m in gui_ids.items() if m.get("type") == "GuiUploadButtonMessage"]
    commands = {m["uuid"] for m in seen if m.get("type") == "RegisterCommandMessage" and "uuid" in m}
    # What it could only guess: the presenter's own panel, its gizmos and balls, its client id.
    presenter_gui = presenter_session.client.gui
    known = dict(presenter_gui._gui_input_handle_from_uuid)
    guessed_nodes = {name for name in presenter_session.client.scene._handle_from_node_name}
    owners = ["", str(presenter_session.client_id)]

    for uid, message in gui_ids.items():
        for value in _hostile_values(message):
            send(_messages.GuiUpdateMessage(uid, {"value": value}))
        send(_messages.GuiButtonHoldMessage(uid, 10.0))
    for uid in known:
        for value in (1e9, True, "x"):
            send(_messages.GuiUpdateMessage(uid, {"value": value}))
    for uid in commands | set(presenter_gui._command_handle_from_uuid):
        send(_messages.CommandTriggerMessage(uid))
    for name in sorted(node_names | gizmo_names | guessed_nodes):
        for owner in owners:
            send(_messages.SceneNodeClickMessage(name, None, (0.0, 0.0, 5.0), (0.0, 0.0, -1.0), (0.5, 0.5), None,
                                                 owner=owner))
            send(_messages.SceneNodeClickMessage(name, 0, (0.0, 0.0, 5.0), (0.0, 0.0, -1.0), (0.5, 0.5), None,
                                                 owner=owner))
            send(_messages.TransformControlsDragStartMessage(name, owner=owner))
            send(_messages.TransformControlsUpdateMessage(name, (1.0, 0.0, 0.0, 0.0), (0.7, -0.9, 0.79),
                                                          owner=owner))
            send(_messages.TransformControlsDragEndMessage(name, owner=owner))
    upload_targets = uploads + [u for u, h in known.items() if type(h).__name__ == "GuiUploadButtonHandle"]
    for uid in upload_targets:
        transfer = str(uuidlib.uuid4())
        send(_messages.FileTransferStartUpload(uid, transfer, "box.stl", "model/stl", 1, len(BOX_STL)))
        send(_messages.FileTransferPart(uid, transfer, 0, BOX_STL))
    return sent


def _presenter_for(hall: Hall, title: str) -> Any:
    presenter, _ = hall.join()
    presenter.select_scene(title)
    if title == "Inertia":  # a state of its own: three masses, O moved
        view = presenter.scene
        view._add_remove("Add mass")
        view.sim.set_about((0.1, 0.2, 0.3))
        presenter.room.refresh()
    presenter.present(CODE)
    hall.frames(1)
    presenter.play()
    hall.frames(30)
    return presenter


@pytest.mark.parametrize("title", list(SCENES))
def test_a_hostile_follower_cannot_change_the_presenters_room(hall: Hall, title: str) -> None:
    presenter = _presenter_for(hall, title)
    follower, hostile = hall.join(lambda port: ViserClient(port, keep_messages=100_000))
    assert follower.mode == "following"
    hall.frames(2)
    hostile.state.wait_for(lambda: hostile.state.replay_done, timeout=10.0)
    time.sleep(0.3)  # the shared scene and the follower panel have arrived
    sim = presenter.room.sim
    before = fingerprint(sim)
    room_before = (presenter.room.playing, presenter.room.time_scale, presenter.room.scene)
    errors_before = presenter.error_count
    sent = attack(hostile, presenter)
    assert sent > 100
    time.sleep(1.0)  # viser's pool runs the callbacks
    with follower.lock:  # and the last of them has finished
        pass
    with presenter.lock:
        pass
    assert presenter.room.sim is sim and fingerprint(sim) == before, f"{title}: the presenter's simulation changed"
    assert (presenter.room.playing, presenter.room.time_scale, presenter.room.scene) == room_before
    assert presenter.mode == "presenting" and presenter.error_count == errors_before
    assert hall.app.lectern.presenter is presenter


def test_the_shared_scene_has_no_handle_that_answers_a_browser(hall: Hall) -> None:
    """By design: every interactive handle (gizmo, click, drag) of a presenter's view lives in
    the presenter's own scene, none in the shared one."""
    for title in SCENES:
        presenter = _presenter_for(hall, title) if hall.app.lectern.presenter is None else hall.app.lectern.presenter
        presenter.select_scene(title)
        shared = hall.app.server.scene._handle_from_node_name
        for name, handle in shared.items():
            impl = handle._impl
            assert not impl.click_cb, f"{title}: {name} is clickable in the shared scene"
            assert not getattr(impl, "drag_cb", None), f"{title}: {name} is draggable in the shared scene"
            assert not getattr(handle, "_impl_aux", None) or not handle._impl_aux.update_cb, \
                f"{title}: the gizmo {name} is in the shared scene"
        if title == "Inertia":
            own = presenter.client.scene._handle_from_node_name
            assert any(type(h).__name__ == "TransformControlsHandle" for h in own.values())
            assert sum(1 for h in own.values() if h._impl.click_cb) == len(presenter.scene.sim.masses)


@pytest.mark.parametrize("title", list(SCENES))
def test_explore_copies_exactly_what_the_presenter_shows(hall: Hall, title: str) -> None:
    presenter = _presenter_for(hall, title)
    follower, _ = hall.join()
    hall.frames(3)
    follower.explore()
    assert follower.mode == "own" and follower.scene.title == title
    assert follower.room is not presenter.room and follower.room.sim is not presenter.room.sim
    assert fingerprint(follower.room.sim) == fingerprint(presenter.room.sim), title
    assert follower.room.playing == presenter.room.playing and follower.room.time_scale == presenter.room.time_scale
    hall.frames(20)  # both go on alike, each in its own room
    assert fingerprint(follower.room.sim) == fingerprint(presenter.room.sim), title
    assert follower.error_count == 0, follower.last_error


def test_the_follower_panel_says_what_is_shown_now(hall: Hall) -> None:
    presenter = _presenter_for(hall, "Inertia")
    follower, _ = hall.join()
    hall.frames(40)
    status = follower.scene.gui_status.content
    assert "Inertia" in status and "masses [kg] = 1, 1, 1" in status and "principal moments" in status
    presenter.start_lesson("§1 Euler angles and ω")  # a lesson step reaches the followers
    hall.frames(40)
    assert "§1 Euler angles" in follower.scene.gui_status.content
    presenter.select_scene("Heavy top")  # chosen by hand: the lesson and its text go
    hall.frames(40)
    status = follower.scene.gui_status.content
    assert "Heavy top" in status and "§1" not in status and presenter.lesson is None
    presenter.stop_presenting()
    hall.frames(40)
    status = follower.scene.gui_status.content
    assert "stopped presenting" in status and "paused" not in status
    assert not presenter.gui_follow.visible


def test_a_narrow_follower_sees_one_line_and_its_camera_is_fitted(hall: Hall) -> None:
    from benchmarks.ws_client import camera_message

    _presenter_for(hall, "Heavy top")
    follower, client = hall.join()
    client.send(camera_message(width=780, height=1688))  # a phone, portrait, device pixels
    panel = poll_until(lambda: follower.scene if follower.scene.narrow else None)
    with follower.lock:  # the layout callback that set `narrow` has finished
        pass
    assert not panel.expanded and panel.gui_line.visible and not panel.gui_status.visible
    assert not follower.gui_projector.visible and not follower.lecture_folder.visible
    panel.set_expanded(True)
    assert panel.gui_status.visible and follower.lecture_folder.visible


def test_fitted_camera_keeps_the_horizontal_extent() -> None:
    fov = math.radians(40.0)
    position, look_at = fitted_camera((4.0, -3.0, 2.0), (0.0, 0.0, 0.0), 1.6, 0.4)
    assert look_at == (0.0, 0.0, 0.0)
    distance = float(np.linalg.norm(position))
    # Horizontal half-width at the target: d tan(h/2), tan(h/2) = aspect tan(fov/2); the phone
    # keeps BODY_WIDTH_SHARE of the presenter's, and a margin.
    np.testing.assert_allclose(distance * 0.4 * math.tan(fov / 2),
                               NARROW_MARGIN * BODY_WIDTH_SHARE * math.sqrt(29.0) * 1.6 * math.tan(fov / 2), rtol=1e-12)
    np.testing.assert_allclose(np.asarray(position) / distance, np.array([4.0, -3.0, 2.0]) / math.sqrt(29.0),
                               rtol=1e-12)
    assert fitted_camera((4.0, -3.0, 2.0), (0.0, 0.0, 0.0), 1.6, 1.2)[0] == (4.0, -3.0, 2.0)


def _ndc_x(eye: np.ndarray, target: np.ndarray, up: np.ndarray, fov: float, aspect: float, point: np.ndarray) -> float:
    """A pinhole camera's horizontal normalised device coordinate of `point` (-1 left edge, +1 right)."""
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    rel = point - eye
    return float((rel @ right) / (rel @ forward) / (aspect * math.tan(fov / 2)))


def test_fitted_camera_puts_the_presenters_body_share_across_a_phone() -> None:
    """With the fov, the left BODY_WIDTH_SHARE of the presenter's width (where the scenes frame the
    body) spans the phone's width less its margin: its left edge, middle and right edge at the
    phone's -1, 0, +1 over NARROW_MARGIN."""
    eye, target, up = np.array([4.0, -3.0, 2.0]), np.array([0.2, 0.1, -0.3]), np.array([0.0, 0.0, 1.0])
    fov, wide, narrow = math.radians(50.0), 1280 / 800, 390 / 844
    position, look_at = fitted_camera(eye, target, wide, narrow, fov, up)
    forward = (target - eye) / np.linalg.norm(target - eye)
    np.testing.assert_allclose((np.asarray(look_at) - np.asarray(position)) / np.linalg.norm(
        np.asarray(look_at) - np.asarray(position)), forward, rtol=1e-12)  # the same viewing direction
    right = np.cross(forward, up) / np.linalg.norm(np.cross(forward, up))
    half_width = np.linalg.norm(target - eye) * wide * math.tan(fov / 2)  # at the target's depth
    edge = 1.0 / NARROW_MARGIN
    for x_wide, x_phone in ((-1.0, -edge), (BODY_WIDTH_SHARE - 1.0, 0.0), (2 * BODY_WIDTH_SHARE - 1.0, edge)):
        point = target + x_wide * half_width * right
        assert _ndc_x(eye, target, up, fov, wide, point) == pytest.approx(x_wide, abs=1e-12)
        assert _ndc_x(np.asarray(position), np.asarray(look_at), up, fov, narrow, point) == pytest.approx(
            x_phone, abs=1e-9)


def test_dataclass_messages_used_here_exist() -> None:
    from viser import _messages

    for name in ("SceneNodeClickMessage", "TransformControlsUpdateMessage", "FileTransferStartUpload",
                 "CommandTriggerMessage", "GuiButtonHoldMessage"):
        assert dataclasses.is_dataclass(getattr(_messages, name))


def test_followers_read_that_the_presenter_looks_back_or_replays(hall: Hall) -> None:
    presenter = _presenter_for(hall, "Free body")
    follower, _ = hall.join()
    hall.frames(60)
    room = presenter.room
    first, live = room.stretch()  # type: ignore[misc]
    room.pause()
    room.scrub(0.5 * (first + live))
    hall.frames(40)
    status = follower.scene.gui_status.content
    assert "looking back at t = " in status and f"(live: {room.live_t:.1f} s)" in status
    assert "⟲" in hall.app.lectern.status_line()
    room.resume()
    hall.frames(40)
    assert "looking back" not in follower.scene.gui_status.content


def test_a_hostile_browser_cannot_press_the_presenters_lecture_buttons(hall: Hall) -> None:
    """The live bar's presenter-only buttons (Stop presenting, Pointer, Call everyone back) answer
    the presenter only: a hostile explorer on a raw websocket that presses every button of its
    own panel and sends the presenter's uuids calls nobody back, stops nobody, moves no explorer;
    its own Stay and Follow presenter move only itself."""
    presenter = _presenter_for(hall, "Heavy top")
    bystander, _ = hall.join()
    hostile_session, hostile = hall.join(lambda port: ViserClient(port, keep_messages=100_000))
    hall.frames(2)
    bystander.explore()
    hostile_session.explore()  # its panel now has the explorer's bar (Follow presenter, Stay) of its own
    hall.frames(40)
    hostile.state.wait_for(lambda: hostile.state.replay_done, timeout=10.0)
    time.sleep(0.3)
    lectern = hall.app.lectern
    assert "0 following · 2 exploring" in presenter.gui_badge.content
    errors_before = hostile_session.error_count
    attack(hostile, presenter)
    time.sleep(1.0)
    for session in (hostile_session, bystander, presenter):
        with session.lock:
            pass
    hall.frames(40)
    assert lectern.presenter is presenter and presenter.mode == "presenting"
    assert lectern.call_back_left(bystander) is None and bystander.mode == "own"
    from viser import _messages  # its own (hidden) Call everyone back, pressed: refused in its own panel

    hostile.send(_messages.GuiUpdateMessage(hostile_session.gui_call_back._impl.uuid, {"value": True}))
    poll_until(lambda: "only the presenter can call everyone back" in str(hostile_session.last_error))
    assert hostile_session.error_count > errors_before and lectern.call_back_left(bystander) is None
    # The presenter's button does call back, and counts change with it.
    presenter.call_back()
    hall.frames(2)
    assert lectern.call_back_left(bystander) is not None


def test_call_back_brings_back_every_explorer_but_the_one_who_stays(hall: Hall, monkeypatch: Any) -> None:
    from app.lecture.lectern import CALL_BACK_SECONDS

    presenter = _presenter_for(hall, "Free body")
    leaver, _ = hall.join()
    stayer, _ = hall.join()
    hall.frames(2)
    leaver.explore()
    stayer.explore()
    hall.frames(31)
    assert "0 following · 2 exploring" in presenter.gui_badge.content
    assert "Lecture on" in leaver.lecture.gui_lecture_on.content and leaver.gui_follow.visible
    now = [100.0]
    monkeypatch.setattr(hall.app.lectern, "_clock", lambda: now[0])
    presenter.call_back()
    hall.frames(2)
    for explorer in (leaver, stayer):
        assert "following again in 10 s" in explorer.lecture.gui_lecture_on.content and explorer.gui_stay.visible
    stayer.lecture.stay()  # what its Stay button does
    assert not stayer.gui_stay.visible and "Lecture on" in stayer.lecture.gui_lecture_on.content
    now[0] += CALL_BACK_SECONDS - 0.1
    hall.frames(2)
    assert leaver.mode == "own"
    now[0] += 0.1
    hall.frames(31)
    assert leaver.mode == "following" and stayer.mode == "own"
    assert "1 following · 1 exploring" in presenter.gui_badge.content
    assert leaver.error_count == stayer.error_count == 0, (leaver.last_error, stayer.last_error)


def test_a_narrow_explorer_keeps_one_line_and_its_camera(hall: Hall) -> None:
    from benchmarks.ws_client import camera_message

    _presenter_for(hall, "Heavy top")
    explorer, client = hall.join()
    client.send(camera_message(width=780, height=1688))  # a phone, portrait, device pixels
    poll_until(lambda: explorer.scene if explorer.scene.narrow else None)
    with explorer.lock:
        pass
    hall.frames(31)  # the lectern fits the follower's camera to the phone (every CAMERA_PERIOD): then look
    camera = explorer.client.camera
    sight = np.subtract(camera.position, camera.look_at)  # from where it looks at, to the eye
    explorer.explore()
    hall.frames(31)
    narrow = explorer.narrow
    assert narrow.on and narrow.gui_line.visible and narrow.gui_details.visible
    assert "Your copy" in narrow.gui_line.content and explorer.gui_follow.visible
    folded = [explorer.gui_scene, *explorer.scene.gui_roots]
    assert not any(handle.visible for handle in folded)
    # The camera it had, fitted to the phone (direction and distance), moved sideways onto the body.
    np.testing.assert_allclose(np.subtract(camera.position, camera.look_at), sight, atol=1e-9)
    screen = screen_of(camera)
    assert screen is not None
    (pivot_x, _), _ = project_one(screen.view, (0.0, 0.0, 0.0), screen.width, screen.height)
    assert abs(pivot_x - 390) < 0.08 * 780, f"the top's pivot is at x = {pivot_x:.0f} of 780 px: not centred"
    narrow.set_expanded(True)  # Details
    assert explorer.gui_scene.visible and explorer.scene.transport.gui_play.visible and not narrow.gui_line.visible
    narrow.set_expanded(False)
    explorer.follow()  # back: the follower's own narrow panel, nothing left folded or shown twice
    assert explorer.mode == "following" and not narrow.on and not narrow.gui_details.visible


def test_a_hostile_student_is_counted_once_and_changes_nothing_else(hall: Hall) -> None:
    """Ask the class (issue 26): a hostile follower on a raw websocket sends 10,000 answers in a
    second (its option buttons, over and over), answers on the buttons of another browser's
    question (its uuids, known here from the server), malformed values to every control of its
    question, and the whole attack above: it is counted once, the honest student's answer stays,
    the presenter's room is bit-identical."""
    from viser import _messages

    presenter = _presenter_for(hall, "Free body")
    honest, _ = hall.join()
    hostile_session, hostile = hall.join(lambda port: ViserClient(port, keep_messages=100_000))
    presenter.ask({"kind": "choice", "prompt": "Which axis is stable?", "options": ["x′", "y′", "z′"]})
    hall.app.frame(DT)  # the round reaches every panel
    asked = hall.app.rounds.current
    honest.answer(0)
    hostile.state.wait_for(lambda: hostile.state.find_gui("3. z′") is not None, timeout=10.0)
    sim = presenter.room.sim
    before = fingerprint(sim)
    errors_before = presenter.error_count
    buttons = [hostile.state.find_gui(f"{k + 1}. {o}") for k, o in enumerate(("x′", "y′", "z′"))]
    own = hostile_session.question
    honest_ids = [button._impl.uuid for button in honest.question.gui_options]
    start = time.monotonic()
    for k in range(10_000):
        hostile.send(_messages.GuiUpdateMessage(buttons[k % 3].uuid, {"value": True}))  # type: ignore[union-attr]
    sent_in = time.monotonic() - start
    for uid in honest_ids:  # another browser's buttons: viser hands them to nobody
        hostile.send(_messages.GuiUpdateMessage(uid, {"value": True}))
    for handle in (*own.gui_options, own.gui_azimuth, own.gui_elevation, own.gui_send_direction, own.gui_send_state,
                   own.gui_from_copy, own.gui_change):
        for value in (math.nan, 1e9, "x", [1, 2, 3], None, {"t": 1.0}):
            hostile.send(_messages.GuiUpdateMessage(handle._impl.uuid, {"value": value}))
    attack(hostile, presenter)

    def settled() -> bool:
        time.sleep(0.5)
        with hostile_session.lock, presenter.lock:  # the pool has run what arrived before
            return True

    poll_until(lambda: settled() and hall.app.rounds.tally().answered == 2, timeout=30.0)
    time.sleep(1.0)
    with hostile_session.lock, presenter.lock:
        pass
    assert hall.app.rounds.current is asked  # its hidden Ask the class folder asked nothing, closed nothing
    tally = hall.app.rounds.tally()
    assert tally.open and sent_in < 5.0, f"10,000 answers took {sent_in:.1f} s to send"
    assert tally.answered == 2 and sum(tally.counts) == 2, tally  # the hostile once, the honest once
    assert hall.app.rounds.mine(honest.answer_token) == 0  # the honest answer stands
    assert hall.app.rounds.mine(hostile_session.answer_token) in (0, 1, 2)
    assert hostile_session.error_count > 100  # its refusals were said in its own panel
    assert presenter.room.sim is sim and fingerprint(sim) == before
    assert presenter.mode == "presenting" and presenter.error_count == errors_before
    assert honest.error_count == 0, honest.last_error
