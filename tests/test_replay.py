"""Replay (app.kit.core.history, Room.scrub / replay / resume / branch), without a browser.

For every scene with motion: play 20 s with a view drawing it, taking forks (`Room.fork`, an
exact copy: tests/test_fork.py) at a few moments; then scrubbing to each of those moments must
give the fork's simulation bit for bit (state, integrator state, samples and traces as they
were), and the view must draw what a view of the fork draws.  Resume gives back the live
simulation bit for bit; a branch goes on exactly as the fork taken at that moment; a replay at
0.1× passes the recorded trajectory; a time outside the stretch is refused and nothing
changes; ten minutes of play keep the history at 60 s and under 5 MB.
"""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest
import viser

from app.kit.core.history import HISTORY_BYTES, HISTORY_SECONDS, RECORD_SPACING, History
from app.kit.core.room import LIVE, REPLAYING, SCRUBBING, Room
from app.kit.core.samples import SampleBuffer
from app.kit.core.trace import Trace
from app.kit.panel.timeline import BRANCH_LABEL, REPLAY_LABEL, RESUME_LABEL, timeline_text
from app.scenes import SCENES
from physics.dynamics import State
from tests.test_fork import assert_equal_values, assert_same, build_view, picture

DT = 1.0 / 60.0
MOVING = {"Euler angles": None, "Free body": "Dzhanibekov", "Heavy top": None, "Poinsot": None,
          "Moving frame": None, "Constrained particles": None}  # scene -> preset (None: its first)
PLAY_FRAMES = 1200  # 20 s at 1×
FORK_FRAMES = (150, 601, 1000)  # forks taken after these frames
IGNORED = {"version", "_exact_at", "_evaluation"}  # a redraw counter (bumped by a restore), caches of
# R_exact(t) and of a constrained system's evaluation at its state


def _content(value: Any) -> Any:
    """What a history shows (a rewound ring's stale rows beyond its end are not part of it)."""
    if isinstance(value, SampleBuffer):
        return ("samples", value.ordered(), len(value))
    if isinstance(value, Trace):
        return ("trace", value.count, value.first, value.points(value.first, value.count),
                value.times(value.first, value.count))
    if isinstance(value, list):
        return [_content(v) for v in value]
    if isinstance(value, dict):
        return {k: _content(v) for k, v in value.items()}
    return value


def moment(sim: Any) -> dict[str, Any]:
    """Every field of a simulation, histories by their contents, the stepper by its state."""
    fields = {}
    for name, value in vars(copy.deepcopy(sim)).items():
        if name in IGNORED:
            continue
        if name == "_stepper":
            value = value.snapshot()
        fields[name] = _content(value)
    return fields


def assert_same_moment(a: Any, b: Any, where: str) -> None:
    assert_same(moment(a), moment(b), where)
    np.testing.assert_array_equal(a.snapshot().values, b.snapshot().values, err_msg=where)


def played(title: str, frames: int = PLAY_FRAMES, time_scale: float = 1.0,
           fork_frames: tuple[int, ...] = ()) -> tuple[Room, dict[int, Room]]:
    scene = SCENES[title]
    room = Room(scene, scene.new_simulation())
    if MOVING[title] is not None:
        scene.apply_preset(room, MOVING[title])
    room.set_time_scale(time_scale)
    room.play()
    forks = {}
    for frame in range(1, frames + 1):
        room.tick(DT)
        if frame in fork_frames:
            forks[frame] = room.fork()
    return room, forks


@pytest.mark.parametrize("title", list(MOVING))
def test_scrub_shows_the_recorded_moment_and_resume_the_live_one(server: viser.ViserServer, title: str) -> None:
    room, forks = played(title, fork_frames=FORK_FRAMES)
    view = build_view(server, room)
    live = room.fork()
    t_live = room.sim.t
    assert room.history is not None and room.stretch() == (0.0, t_live)
    for frame in (601, 150, 1000, 601):  # back, further back, forward, back: any order
        fork = forks[frame]
        room.scrub(fork.sim.t)
        assert room.mode == SCRUBBING and not room.playing and room.shown_t == fork.sim.t
        assert_same_moment(room.sim, fork.sim, f"{title} scrubbed to frame {frame}")
        fork.playing = False  # shown paused, as the scrubbed room is (a playing view may draw at display resolution)
        forked_view = build_view(server, fork)
        assert_equal_values(picture(view), picture(forked_view), f"{title}: the view at frame {frame}")
        forked_view.remove()
        assert "Showing t = " in timeline_text(room)
    room.resume()
    assert room.mode == LIVE and room.playing and room.sim.t == t_live
    assert_same_moment(room.sim, live.sim, f"{title} resumed")
    live_view = build_view(server, live)
    assert_equal_values(picture(view), picture(live_view), f"{title}: the view after Resume")
    # And it plays on as the live copy does.
    for r in (room, live):
        for _ in range(30):
            r.tick(DT)
    assert_same_moment(room.sim, live.sim, f"{title} resumed and played on")
    for v in (view, live_view):
        v.remove()


@pytest.mark.parametrize("title", list(MOVING))
def test_a_branch_goes_on_as_the_run_did_and_two_branches_agree(title: str) -> None:
    room, forks = played(title, fork_frames=(601,))
    twin, _ = played(title)
    assert_same_moment(room.sim, twin.sim, f"{title}: two rooms played alike")
    fork = forks[601]
    for r in (room, twin):
        r.scrub(fork.sim.t)
        r.branch()
        assert r.mode == LIVE and r.playing and r.sim.t == fork.sim.t
        assert r.history is not None and r.history.t_last == fork.sim.t
    dts = [DT * (1.0 + 0.3 * math.sin(k)) for k in range(240)]  # jittered frames
    for r in (room, twin, fork):
        for dt in dts:
            r.tick(dt)
    assert_same_moment(room.sim, twin.sim, f"{title}: two branches")
    assert_same_moment(room.sim, fork.sim, f"{title}: the branch and the run it left")


@pytest.mark.parametrize("title", list(MOVING))
def test_a_slow_replay_passes_the_recorded_states_and_ends_live(title: str) -> None:
    room, forks = played(title, frames=240, fork_frames=(120,))
    live = room.fork()
    history = room.history
    assert history is not None
    room.set_time_scale(0.1)
    start = forks[120].sim.t
    room.pause()  # the lecturer stops at the flip, then replays it slowly
    room.replay(start)
    assert room.mode == REPLAYING and room.playing
    assert_same_moment(room.sim, forks[120].sim, f"{title} replay start")
    reference = forks[120]  # the run itself from there, frame by frame at 0.1×
    reference.set_time_scale(0.1)
    passed = set()
    for _ in range(60):  # 0.1 s of the recording in 1 s
        room.tick(DT)
        reference.tick(DT)
        assert room.mode == REPLAYING
        index = history.index_at(room.sim.t)
        passed.add(index)
        if history.time(index) == room.sim.t:  # on a recorded frame: that snapshot exactly
            np.testing.assert_array_equal(room.sim.snapshot().values, history.snapshot(index).values)
        assert abs(room.sim.t - reference.sim.t) < 1e-12
        shown, run = _pose(room.sim), _pose(reference.sim)
        np.testing.assert_allclose(shown, run, rtol=0, atol=1e-9, err_msg=f"{title} at t = {room.sim.t}")
    assert len(passed) >= 6  # every recorded frame of that 0.1 s (6 of them at 1×)
    assert "Replaying t = " in timeline_text(room) and "(0.1×)" in timeline_text(room)
    room.set_time_scale(4.0)  # to the end: back to the live moment, exactly
    for _ in range(200):
        room.tick(DT)
    assert room.mode == LIVE and not room.playing  # paused, as it was when the replay started
    assert_same_moment(room.sim, live.sim, f"{title} after the replay")


def _pose(sim: Any) -> np.ndarray:
    """What the scene shows moving, as numbers: R and ω, the particles, q and q̇, or the angles."""
    if hasattr(sim, "state"):
        return np.concatenate([sim.state.R_space_body.ravel(), sim.state.omega_body])
    if hasattr(sim, "x"):
        return np.concatenate([sim.x.ravel(), sim.v.ravel()])
    if hasattr(sim, "integrator"):  # constrained particles: q, q̇
        return np.concatenate([sim.integrator.q, sim.integrator.q_dot])
    return np.array(sim.angles_deg)


@pytest.mark.parametrize("title", ["Free body", "Moving frame"])
def test_a_time_outside_the_stretch_is_refused_and_nothing_changes(title: str) -> None:
    room, _ = played(title, frames=300)
    kept = room.fork()
    version = room.sim.version
    for t in (-1.0, room.sim.t + 0.5, math.nan, math.inf, "abc", None):
        with pytest.raises(ValueError, match="refused"):
            room.scrub(t)
        assert room.mode == LIVE and room.playing and room.sim.version == version
        assert_same(room.sim, kept.sim, f"{title} after refusing {t!r}")
    with pytest.raises(ValueError, match="Timeline back"):
        room.branch()
    room.scrub(2.0)  # and from the past, too
    shown = room.sim.fork()
    with pytest.raises(ValueError, match="refused"):
        room.scrub(room.live_t + 1.0)
    assert room.mode == SCRUBBING
    assert_same_moment(room.sim, shown, f"{title} scrubbed, after a refusal")


def test_a_new_run_while_scrubbing_drops_the_past() -> None:
    room, _ = played("Free body", frames=300)
    room.scrub(1.0)
    SCENES["Free body"].apply_preset(room, "Disc")
    room.refresh()
    assert room.mode == LIVE and room.sim.t == 0.0 and room.stretch() is None
    room.play()
    for _ in range(60):
        room.tick(DT)
    stretch = room.stretch()
    assert stretch is not None and stretch[0] == 0.0 and stretch[1] == room.sim.t
    room.reset()
    assert room.mode == LIVE and room.stretch() == (0.0, 0.0)


def test_play_right_after_a_new_run_while_scrubbing_plays_the_new_run_live() -> None:
    """A new run and play in one step while the past is shown (the gallery's `Play this answer`
    restarts and plays under the room's lock): the new run plays, live, from its start."""
    room, _ = played("Free body", frames=300)
    room.scrub(1.0)
    start = room.sim.initial_state
    with room.lock:
        room.sim.restart(State(start.R_space_body.copy(), -start.omega_body, 0.0))
        room.play()
    assert room.playing and room.mode == LIVE
    for _ in range(10):
        room.tick(DT)
    assert room.playing and room.mode == LIVE and room.sim.t == pytest.approx(10 * DT * room.time_scale, rel=1e-9)


def test_inertia_has_no_motion_and_no_timeline(server: viser.ViserServer) -> None:
    scene = SCENES["Inertia"]
    room = Room(scene, scene.new_simulation())
    view = build_view(server, room)
    assert room.history is None and view.timeline is None
    with pytest.raises(ValueError, match="no motion"):
        room.scrub(0.0)
    view.remove()


@pytest.mark.parametrize(("title", "time_scale", "seconds"), [
    ("Free body", 1.0, 600.0), ("Euler angles", 1.0, 600.0),  # ten minutes
    ("Heavy top", 0.1, 65.0),  # slow motion: a snapshot every 1/120 s, the densest history (~4 s of CPU)
    ("Moving frame", 4.0, 65.0),  # its RK4 costs per simulated second: past the 60 s window, as the top's
])
def test_ten_minutes_of_play_keep_the_last_minute_under_the_memory_bound(title: str, time_scale: float,
                                                                       seconds: float) -> None:
    frames = round(seconds / (DT * time_scale))
    scene = SCENES[title]
    room = Room(scene, scene.new_simulation())
    room.set_time_scale(time_scale)
    room.playing = True
    for _ in range(frames):
        room.advance(DT)
    history = room.history
    assert history is not None
    span = history.t_last - history.t_first
    rows = len(history)
    print(f"\n{title} at {time_scale:g}×: t = {room.sim.t:.1f} s, history {span:.2f} s in {rows} snapshots "
          f"of {history.snapshot(0).values.nbytes} B, {history.nbytes() / 1e6:.2f} MB held")
    assert history.nbytes() <= HISTORY_BYTES
    assert HISTORY_SECONDS - 0.1 <= span <= HISTORY_SECONDS + 1e-9
    assert history.t_first > 0.0  # the window has moved on: the oldest snapshots were dropped
    assert rows <= HISTORY_SECONDS / RECORD_SPACING + 2
    assert 0.0 <= room.sim.t - history.t_last < RECORD_SPACING
    room.scrub(history.t_first)  # the oldest moment is still whole (its trace points are stored)
    room.resume()


def test_a_constrained_minute_fits_the_memory_bound() -> None:
    """Constrained particles (its RK8 grid costs ~0.2 s of CPU per simulated second, so a
    minute is not played here): the double pendulum's snapshot, the largest of its systems,
    times the most snapshots a history keeps, is under HISTORY_BYTES."""
    scene = SCENES["Constrained particles"]
    room = Room(scene, scene.new_simulation())
    scene.apply_preset(room, "Double pendulum, chaotic")
    room.play()
    for _ in range(30):
        room.tick(DT)
    assert room.history is not None and len(room.history) > 0
    most = (HISTORY_SECONDS / RECORD_SPACING + 2) * room.history.snapshot(0).values.nbytes
    assert most <= HISTORY_BYTES / 5


def test_history_refuses_outside_and_finds_the_moment_at_or_before() -> None:
    history = History(seconds=1.0, spacing=0.1)

    class Counter:
        run, version = 1, 0

        def __init__(self) -> None:
            self.t = 0.0

        def snapshot(self) -> Any:
            from app.kit.core.history import Snapshot
            return Snapshot(np.array([self.t, 2.0 * self.t]))

    sim = Counter()
    for k in range(25):
        sim.t = 0.05 * k
        history.record(sim)  # type: ignore[arg-type]
    times = history.times()
    assert np.all(np.diff(times) >= 0.1 - 1e-12) and times[-1] - times[0] <= 1.0 + 1e-9
    assert history.at(times[3] + 0.01).t == times[3] and history.at(times[3]).t == times[3]
    with pytest.raises(ValueError, match="recorded"):
        history.at(times[0] - 0.01)
    history.cut_after(times[2])
    assert history.t_last == times[2]


def test_the_timeline_buttons_drive_the_room(server: viser.ViserServer) -> None:
    room, _ = played("Free body", frames=300)
    view = build_view(server, room)
    timeline = view.timeline
    assert timeline is not None

    def click(label: str) -> None:
        group = timeline.gui_buttons
        for callback in group._impl.update_cb:
            callback(type("Event", (), {"target": type("T", (), {"value": label})(), "client": None})())

    room.pause()
    timeline.gui_slider.value = 2.0  # the server's own write applies at once (app.kit.panel.binding)
    assert room.mode == SCRUBBING and room.shown_t == 2.0
    click(REPLAY_LABEL)
    assert room.mode == REPLAYING
    click(RESUME_LABEL)
    assert room.mode == LIVE and room.sim.t == room.live_t
    click(BRANCH_LABEL)
    assert "Timeline back" in view.message.text
    timeline.gui_slider.value = 3.0
    click(BRANCH_LABEL)
    assert room.mode == LIVE and room.playing and room.sim.t == 3.0
    view.remove()


def test_resume_right_after_a_drag_brings_the_thumb_back_to_the_live_time(server: viser.ViserServer) -> None:
    """The Timeline's thumb follows the room once the user's hand has left it: at once when they
    press Resume within HANDS_OFF_S of their last drag update (the button ends the edit), and
    after HANDS_OFF_S when the room went live otherwise, though the room stands still."""
    from app.kit.panel.binding import HANDS_OFF_S, ManualClock

    room, _ = played("Free body", frames=300)
    view = build_view(server, room)
    timeline = view.timeline
    assert timeline is not None
    clock = timeline.binding.clock = ManualClock()
    slider = timeline.gui_slider
    browser = type("Client", (), {})()

    def drag_to(value: float) -> None:  # the server's write applies it; then the browser's update marks the edit
        slider.value = value
        for callback in slider._impl.update_cb:
            callback(type("Event", (), {"target": slider, "client": browser})())

    def click(label: str) -> None:
        for callback in timeline.gui_buttons._impl.update_cb:
            callback(type("Event", (), {"target": type("T", (), {"value": label})(), "client": browser})())

    room.pause()
    t_live = room.sim.t
    drag_to(2.0)
    assert room.mode == SCRUBBING and timeline.binding.editing()
    click(RESUME_LABEL)
    assert room.mode == LIVE and abs(slider.value - t_live) < 0.011, (slider.value, t_live)
    drag_to(3.0)
    room.resume()  # live again, not by the Timeline's button: the hand may still be on the thumb
    assert slider.value == 3.0
    timeline.frame(DT)
    assert slider.value == 3.0  # still within HANDS_OFF_S of the drag
    clock.advance(HANDS_OFF_S)
    timeline.frame(DT)  # the room stands still (paused): the thumb comes back all the same
    assert abs(slider.value - t_live) < 0.011, (slider.value, t_live)
    view.remove()
