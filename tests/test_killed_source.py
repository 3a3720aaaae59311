"""A lecture survives its presenter's worker (issue 34, "State has an owner and ends with it"):
the room on the shared screen belongs to the lecture, not to the process that drew it.

- Worker A (a real `python -m app` process) presents Heavy top, playing; B's browsers follow.
  A is SIGKILLed.  A follower on B presses Explore: it gets a room of the scene at the last state
  B drew (the body's drawn orientation within TURN_TOLERANCE_RAD of what B's browser displayed),
  paused, with a line saying the presenter's worker is gone; another follower on B presses
  Present (with the code, once A's lock has lapsed with its lease) and presents that state.
  On the old code both failed ("the presenter's process did not answer").
- The room a lecture left in Redis (kept LAST_TTL_S) is offered only to that lecture: after a
  stopped lecture on Heavy top, a later lecture on Free body whose worker dies, a newcomer's
  `Open the last lecture's room` on B opens Free body, not the older Heavy top.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from conftest import WorkerProcess, lecturer_presenting, poll_until
from test_bus import Workers, workers_fixture

CODE = "97531864"
TURN_TOLERANCE_RAD = 5e-3
"""The copy's body against the body B's browser displayed last: the drawn poses are quantized
(`app.kit.draw.widgets.POSE_QUANTUM`, ~5e-4 rad) and the kept copy (at most a second old) is
advanced to the last time drawn in frames of 1/60 s, not the presenter's own frames."""
BODY = ("/top/tilt", "/top/tilt/b")  # Heavy top's body: the tilt frame, then the body's spin about its axis
workers = workers_fixture(CODE)  # in-process workers on one redis-server for the module (`redis_url`)


def _wait(predicate: Callable[[], Any], what: str, seen: Callable[[], Any], timeout: float = 30.0) -> Any:
    """Poll `predicate` until truthy (its value); AssertionError naming `what` and what was `seen`."""
    return poll_until(predicate, timeout, 0.02, what=what, seen=seen)


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _body_wxyz(mirror: Any, prefix: str) -> np.ndarray | None:
    """The body's orientation (wxyz, unit) as the browser stand-in `mirror` has it drawn, its
    nodes under `prefix` ("/l": the shared scene; "": the browser's own room); None if not drawn."""
    with mirror.lock:
        poses = [mirror.nodes.get(prefix + name, {}).get("wxyz") for name in BODY]
    if any(pose is None for pose in poses):
        return None
    q = _quat_mul(np.asarray(poses[0], float), np.asarray(poses[1], float))
    return q / np.linalg.norm(q)


def _turn_rad(a: np.ndarray, b: np.ndarray) -> float:
    """The angle [rad] of the rotation between unit quaternions a and b."""
    return float(2.0 * np.arccos(min(1.0, abs(float(np.dot(a, b))))))


def test_explore_and_present_on_b_after_the_presenters_worker_is_killed(workers: Workers) -> None:
    from test_wire import SceneMirror

    from app.lecture.follower import Hall
    from app.lecture.gate import LEASE_S

    with WorkerProcess(workers.url, CODE, "w1") as w1:
        b = workers.start("w2")
        follower, mirror = workers.connect("w2", SceneMirror)
        successor, _ = workers.connect("w2", SceneMirror)
        lecturer = lecturer_presenting(w1.port, CODE, scene="Heavy top")
        workers.clients.append(lecturer)
        lecturer.click("Play")
        _wait(lambda: follower.mode == "following" and successor.mode == "following" and b.lectern.hall is Hall.LIVE
              and b.lectern.live_title() == "Heavy top",
              "B's browsers following A's Heavy top", lambda: (follower.mode, successor.mode, b.lectern.hall,
                                                               b.lectern.live_title()))
        drawn: list[np.ndarray] = []

        def moving() -> bool:
            pose = _body_wxyz(mirror, "/l")
            if pose is not None and (not drawn or _turn_rad(pose, drawn[-1]) > 1e-3):
                drawn.append(pose)
            return len(drawn) >= 3

        _wait(moving, "the top turning on B's browser", lambda: len(drawn), 60.0)
        seen = b.bus.following
        _wait(lambda: (seen.seen_t or 0.0) > 1.5, "B drawing 1.5 s of the top's motion", lambda: seen.seen_t, 60.0)
        _wait(lambda: seen.kept is not None, "a kept copy of A's room on B", lambda: seen.kept, 20.0)
        w1.kill()
        _wait(lambda: b.lectern.hall is Hall.LEFT, "B taking it that A's presenter left", lambda: b.lectern.hall,
              LEASE_S + 10.0)
        displayed = _body_wxyz(mirror, "/l")
        assert displayed is not None
        shown_t = b.bus.following.seen_t
        assert shown_t is not None

        follower.guard("test", follower.explore)()
        assert follower.mode == "own" and follower.error_count == 0, follower.last_error
        room = follower.room
        assert room.scene.title == "Heavy top" and not room.playing
        note = follower.scene.message.text
        assert "presenter's worker is gone" in note and "last state" in note, note
        assert abs(room.shown_t - shown_t) < 1e-6, (room.shown_t, shown_t)  # the time B drew last
        _wait(lambda: _body_wxyz(mirror, "") is not None, "the explored room's body on the browser",
                       lambda: sorted(n for n in mirror.nodes if n.startswith("/top/tilt")), 20.0)
        copied = _body_wxyz(mirror, "")
        assert copied is not None
        turn = _turn_rad(copied, displayed)
        print(f"explored after the kill: t = {room.shown_t:.3f} s, body {turn:.2e} rad from what B displayed")
        assert turn < TURN_TOLERANCE_RAD, f"the copy's body is {turn:.3g} rad from what B's browser displayed"

        _wait(lambda: b.lectern.gate.presenter() is None, "A's presenter lock lapsing with its lease",
              b.lectern.gate.presenter, 3 * LEASE_S + 10.0)
        successor.guard("test", successor.present)(CODE)
        assert successor.mode == "presenting" and successor.error_count == 0, successor.last_error
        assert b.lectern.presenter is successor and b.lectern.hall is Hall.LIVE
        assert b.lectern.live_room is successor.room and successor.room.scene.title == "Heavy top"
        assert abs(successor.room.shown_t - shown_t) < 1e-6
        assert "presenter's worker is gone" in successor.scene.message.text


def test_only_the_last_lectures_room_is_offered_after_its_worker_died(workers: Workers) -> None:
    from conftest import RawClient
    from test_bus import _present

    from app.lecture.bus import LAST_KEY
    from app.lecture.follower import Hall

    a, b = workers.start("a"), workers.start("b")
    first = _present(workers, "a", "Heavy top")
    _wait(lambda: b.lectern.hall is Hall.LIVE and b.lectern.live_title() == "Heavy top",
          "B showing the first lecture", lambda: (b.lectern.hall, b.lectern.live_title()))
    first.guard("test", first.stop_presenting)()
    _wait(lambda: b.lectern.hall is Hall.STOPPED, "B hearing the first lecture stop", lambda: b.lectern.hall)
    _wait(lambda: a.bus.redis.get(LAST_KEY) is not None, "the first lecture's room kept in Redis",
          lambda: None, 10.0)
    second = _present(workers, "a", "Free body")
    _wait(lambda: b.lectern.hall is Hall.LIVE and b.lectern.live_title() == "Free body",
          "B showing the second lecture", lambda: (b.lectern.hall, b.lectern.live_title()))
    assert second.mode == "presenting"
    a.bus.source = False  # as if killed: no "left" said, no room kept in Redis
    a.stop()
    del workers.apps["a"]
    _wait(lambda: b.lectern.hall is Hall.LEFT, "B taking it that the second presenter left",
          lambda: b.lectern.hall, 15.0)
    newcomer, _ = workers.connect("b", RawClient)
    assert newcomer.came_after_lecture and newcomer.mode == "own"
    assert newcomer.lecture.gui_ended.visible and "Free body" in newcomer.lecture.gui_ended.content
    newcomer.guard("test", newcomer.select_scene)("Poinsot")
    newcomer.guard("test", newcomer.open_last_lecture)()
    assert newcomer.error_count == 0, newcomer.last_error
    assert newcomer.room.scene.title == "Free body", \
        f"the last lecture was on Free body; opened {newcomer.room.scene.title} (an older lecture's room)"
    assert "presenter's worker is gone" in newcomer.scene.message.text, newcomer.scene.message.text


def test_with_nothing_of_the_room_kept_explore_gives_a_fresh_room_of_the_scene(
        monkeypatch: pytest.MonkeyPatch, workers: Workers) -> None:
    """The last resort: a killed source whose room never reached B (no copy kept, none in Redis):
    Explore on B still leaves the frozen screen, with a fresh room of the same scene and a line
    saying only the scene could be kept."""
    from test_bus import _present

    from app.lecture.bus.source import Publisher
    from app.lecture.follower import Hall

    monkeypatch.setattr(Publisher, "_send_keep", lambda self: None)  # no copy of the room ever published
    a, b = workers.start("a"), workers.start("b")
    _present(workers, "a", "Poinsot")
    follower, _ = workers.connect("b")
    _wait(lambda: follower.mode == "following" and b.lectern.live_title() == "Poinsot",
          "B's browser following the Poinsot lecture", lambda: (follower.mode, b.lectern.live_title()))
    a.bus.source = False  # as if killed
    a.stop()
    del workers.apps["a"]
    _wait(lambda: b.lectern.hall is Hall.LEFT, "B taking it that the presenter left", lambda: b.lectern.hall, 15.0)
    follower.guard("test", follower.explore)()
    assert follower.mode == "own" and follower.error_count == 0, follower.last_error
    assert follower.room.scene.title == "Poinsot" and follower.room.shown_t == 0.0
    note = follower.scene.message.text
    assert "presenter's worker is gone" in note and "only the scene" in note, note
