"""A visitor after the lecture (issue 34 row 9): a browser that connects once the presenter stopped
presenting or closed its tab lands in its own room (the Scene dropdown, its own simulation, not
the frozen last state), told that the lecture ended; `Open the last lecture's room` gives it an
exact copy of the room the presenter left.  The browsers that were following keep the last state.
Real websocket clients (`RawClient`), the app's loop not running: the tests tick the rooms."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from conftest import LectureHall as Hall
from conftest import RawClient, hall_fixture, poll_until
from test_bus import Workers, _present, workers  # noqa: F401 - the fixtures across workers

from app.hall.lecture_panel import LAST_ROOM_LABEL
from app.lecture.follower import Follower
from app.lecture.lectern import Mode
from app.scenes import DEFAULT_SCENE

CODE = "313131"


hall = hall_fixture(CODE)


def _state(room: Any) -> tuple[float, np.ndarray, np.ndarray]:
    """(t [s], R_space_body (3, 3), omega_body (3,) [rad/s]) of a room's simulation, copied."""
    sim = room.sim
    return float(sim.t), sim.state.R_space_body.copy(), np.asarray(sim.state.omega_body).copy()


def _lecture_ends(hall: Hall, how: str) -> tuple[Any, Any, tuple[float, np.ndarray, np.ndarray]]:
    """A presenter plays Heavy top · Loop, a browser follows; then the presenter stops (`how`
    "stopped") or closes its tab ("left").  (the follower, the last room, its state then)."""
    presenter, follower = hall.join(), hall.join()
    presenter.select_scene("Heavy top")
    presenter.apply_preset("Loop")
    presenter.present(CODE)
    hall.frames(1)
    assert follower.mode == Mode.FOLLOWING
    presenter.play()
    hall.frames(40)
    if how == "stopped":
        presenter.stop_presenting()
    else:
        hall.clients[0].close()
        poll_until(lambda: len(hall.app.sessions) == 1, timeout=10.0)
    lectern = hall.app.lectern
    assert lectern.presenter is None and lectern.live
    hall.frames(40)  # the lectern refreshes every panel; the last room stays paused
    last = lectern.live_room
    assert last is not None and not last.playing and last.sim.t > 0.5
    return follower, last, _state(last)


@pytest.mark.parametrize("how", ["stopped", "left"])
def test_a_newcomer_after_the_lecture_has_its_own_room_and_the_last_one_a_click_away(hall: Hall,
                                                                                    how: str) -> None:
    follower, last, (t_last, R_last, w_last) = _lecture_ends(hall, how)
    newcomer, client = hall.join_with_client()
    # Its own room: not the frozen last state, the Scene dropdown shown, a simulation of its own.
    assert newcomer.mode == Mode.OWN and not isinstance(newcomer.scene, Follower)
    assert hall.app.lectern.followers.keys() == {follower.client_id}
    assert newcomer.room is not last and newcomer.room.scene.title == DEFAULT_SCENE
    assert newcomer.gui_scene.visible and newcomer.gui_scene.value == DEFAULT_SCENE
    assert newcomer.showing.shadow is not None  # the shared (last) scene is hidden in this browser
    assert newcomer.room.sim.t == 0.0
    newcomer.play()
    hall.frames(10)
    assert newcomer.room.sim.t > 0.0 and last.sim.t == t_last  # it drives its own simulation
    # The line saying the lecture ended, and the button.
    panel = newcomer.lecture
    word = "stopped presenting" if how == "stopped" else "has left"
    assert panel.gui_ended.visible and "lecture has ended" in panel.gui_ended.content
    assert word in panel.gui_ended.content and "Heavy top" in panel.gui_ended.content
    assert panel.gui_last_room.visible and panel.gui_last_room.label == LAST_ROOM_LABEL
    assert not panel.gui_follow.visible  # nobody presents: nothing to follow
    # The follower keeps today's view: the last state, the note, Explore.
    assert follower.mode == Mode.FOLLOWING and isinstance(follower.scene, Follower)
    assert ("stopped presenting" if how == "stopped" else "The presenter has left") in follower.scene.gui_status.content
    assert not follower.lecture.gui_ended.visible
    # One click (through the wire, as the browser's button sends it): a copy of the last room.
    client.set_value(panel.gui_last_room, True)
    poll_until(lambda: newcomer.room.scene.title == "Heavy top", timeout=10.0)
    with newcomer.lock:
        pass  # the click's callback has finished
    copy = newcomer.room
    assert copy is not last and newcomer.mode == Mode.OWN and newcomer.error_count == 0, newcomer.last_error
    t, R, w = _state(copy)
    assert t == t_last and np.array_equal(R, R_last) and np.array_equal(w, w_last)
    assert copy.sim.preset == "Loop" and not copy.playing and newcomer.gui_scene.value == "Heavy top"
    assert len(copy.sim.traces["tip"]) == len(last.sim.traces["tip"]) > 1
    # Its copy is its own: playing it leaves the last room (the followers' last state) alone.
    newcomer.play()
    hall.frames(10)
    assert copy.sim.t > t_last and last.sim.t == t_last and np.array_equal(last.sim.state.R_space_body, R_last)
    # A new presenter pulls the newcomer along like any browser in its own room; the line goes.
    follower.present(CODE)
    hall.frames(1)
    assert newcomer.mode == Mode.FOLLOWING and not newcomer.came_after_lecture
    assert not panel.gui_ended.visible and not panel.gui_last_room.visible


def test_a_browser_that_came_before_any_lecture_is_not_told_one_ended(hall: Hall) -> None:
    first = hall.join()
    assert first.mode == Mode.OWN and not first.came_after_lecture
    assert not first.lecture.gui_ended.visible and not first.lecture.gui_last_room.visible
    room = first.room
    first.guard("last room", first.open_last_lecture)()  # nothing to open: said in its panel
    assert first.room is room and first.error_count == 1 and "no lecture" in (first.last_error or "")


def test_the_last_room_is_refused_while_someone_presents(hall: Hall) -> None:
    presenter, follower = hall.join(), hall.join()
    presenter.present(CODE)
    hall.frames(1)
    presenter.stop_presenting()
    hall.frames(1)
    late = hall.join()
    assert late.came_after_lecture and late.mode == Mode.OWN
    presenter.present(CODE)
    hall.frames(1)
    assert late.mode == Mode.FOLLOWING and not late.came_after_lecture
    late.guard("test", late.explore)()
    before = late.room
    late.guard("last room", late.open_last_lecture)()
    assert late.room is before and "a lecture is on" in (late.last_error or "")
    assert follower.mode == Mode.FOLLOWING


# ---------------------------------------------------------------------- across workers (app.lecture.bus)
@pytest.mark.parametrize("how", ["stopped", "left"])
def test_a_newcomer_on_another_worker_after_the_lecture_has_its_own_room(workers: Workers, how: str  # noqa: F811
                                                                          ) -> None:
    """A presenter on worker A plays Heavy top and stops (or closes its tab); a browser that
    connects to worker B afterwards lands in its own room with the ended line, and the button
    gives it the room A's presenter left, bit for bit (through Redis, `Lectern.fetch_remote`)."""
    pytest.importorskip("app.codec")
    from test_codec import assert_rooms_equal

    from app.lecture.follower import Hall as HallState

    a, b = workers.start("a"), workers.start("b")
    presenter = _present(workers, "a", "Heavy top")
    presenter.guard("test", presenter.apply_preset)("Loop")
    presenter.guard("test", presenter.play)()
    follower_b, _ = workers.connect("b")
    poll_until(lambda: follower_b.mode == Mode.FOLLOWING and b.lectern.hall is HallState.LIVE, timeout=20.0)
    poll_until(lambda: presenter.room.sim.t > 0.5, timeout=20.0)
    ended = HallState.STOPPED if how == "stopped" else HallState.LEFT
    if how == "stopped":
        presenter.guard("test", presenter.stop_presenting)()
    else:
        workers.clients[0].close()  # the presenter's tab
        poll_until(lambda: not any(s is presenter for s in a.sessions.values()), timeout=20.0)
    poll_until(lambda: b.lectern.hall is ended, timeout=20.0)
    last = a.lectern.live_room
    assert last is not None and not last.playing
    newcomer, client = workers.connect("b", RawClient)
    assert newcomer.mode == Mode.OWN and not isinstance(newcomer.scene, Follower), newcomer.mode
    assert newcomer.room.scene.title == DEFAULT_SCENE and newcomer.gui_scene.visible
    assert follower_b.mode == Mode.FOLLOWING  # the follower keeps the last state
    panel = newcomer.lecture
    poll_until(lambda: panel.gui_ended.visible and panel.gui_last_room.visible, timeout=10.0)
    assert "lecture has ended" in panel.gui_ended.content and "Heavy top" in panel.gui_ended.content
    client.set_value(panel.gui_last_room, True)
    poll_until(lambda: newcomer.room.scene.title == "Heavy top", timeout=20.0)
    with newcomer.lock:
        pass
    assert newcomer.error_count == 0, newcomer.last_error
    with newcomer.room.lock:
        copy = newcomer.room.fork()
    with last.lock:
        original = last.fork()
    assert copy.sim.t == original.sim.t > 0.5
    assert_rooms_equal(copy, original, "the last lecture's room on B")
