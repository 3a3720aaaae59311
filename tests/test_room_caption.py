"""The room reads the lecture: the lesson caption and the presenter's open plot reach every
follower (app.lecture.caption, app.lecture.room_plot), the presenter's `Caption` checkbox decides for
the room, a follower's only for its own screen, and nothing a hostile follower sends on a raw
websocket changes the presenter's room, its plot tab or its caption.  The app's loop does not
run: the test ticks (`LectureHall.frames`)."""

from __future__ import annotations

import time

import numpy as np
from conftest import LectureHall, poll_until
from test_trust import attack, fingerprint

from app.lecture.caption import CAPTION_CLASS
from app.lecture.lectern import FOLLOW_PERIOD
from app.lecture.room_plot import MIRROR_PERIOD
from benchmarks.ws_client import ViserClient

CODE = "135790"
FLIP_STEP = ("§6 The free body and the heavy top", 2)  # "Watch ω_y′ change sign in the Plots tab"
FRAMES = int(round(FOLLOW_PERIOD * 60)) + 2  # one followers' refresh and a little more


def _value(handle):  # type: ignore[no-untyped-def]
    return handle.content if hasattr(handle, "content") else handle.data


def _x_end(handle) -> float:  # type: ignore[no-untyped-def]
    return float(np.asarray(handle.data[0])[-1])


def test_followers_see_the_caption_and_the_presenters_plot_read_only() -> None:
    hall = LectureHall(CODE)
    try:
        presenter = hall.join()
        presenter.present(CODE)
        title, steps = FLIP_STEP
        presenter.start_lesson(title)
        for _ in range(steps):
            presenter.next_step(1)
        assert presenter.scene.tabs.shown == "Plots" and presenter.room.playing
        follower, hostile = hall.join_with_client(lambda port: ViserClient(port, keep_messages=100_000))
        hall.frames(FRAMES)
        panel = follower.scene
        # The caption: the step's words, on the follower's screen.
        step = presenter.lesson.steps[steps]
        assert panel.caption.text == step.text and panel.caption.handle.visible
        assert CAPTION_CLASS in panel.caption.handle.content and "step 3 of 7" in panel.caption.handle.content
        # The presenter's Plots tab, copied: the same charts, the same data, following it.
        mirror = panel.plot
        sources = presenter.scene.plot_elements("Plots")
        assert mirror.tab == "Plots" and len(mirror.copies) == len(sources) and mirror.folder.visible
        assert "Plots tab (read only)" in mirror.folder.label
        chart, copy = sources[-1], mirror.copies[-1]
        assert copy.title == chart.title and copy.series == chart.series
        start = _x_end(copy)

        def moved() -> bool:
            hall.frames(FRAMES)
            return _x_end(copy) > start

        poll_until(moved, timeout=10.0 * MIRROR_PERIOD)  # the copy follows, at most every MIRROR_PERIOD
        assert len(copy.data) == len(chart.data) and _x_end(copy) <= _x_end(chart) + 1e-3

        # A hostile follower sends everything it can, at the copies and the caption too.
        hostile.state.wait_for(lambda: hostile.state.replay_done, timeout=10.0)
        copy_ids = {c._impl.uuid for c in mirror.copies} | {panel.caption.handle._impl.uuid,
                                                             panel.gui_caption._impl.uuid}
        seen = {m.get("uuid") for _, _, m in list(hostile.state.messages)}
        assert copy_ids <= seen, "the follower was not sent its copies"
        presenter.pause()
        hall.frames(2)
        sim = presenter.room.sim
        before = fingerprint(sim)
        shown = (presenter.scene.tabs.shown, presenter.lesson_step, presenter.lesson_runner.gui_caption.value,
                 presenter.room.playing, [fingerprint(_value(s)) for s in sources])
        assert attack(hostile, presenter) > 100
        time.sleep(1.0)  # viser's pool runs the callbacks
        for session in (follower, presenter):
            with session.lock:  # and the last of them has finished
                pass
        assert presenter.room.sim is sim and fingerprint(sim) == before
        assert (presenter.scene.tabs.shown, presenter.lesson_step, presenter.lesson_runner.gui_caption.value,
                presenter.room.playing, [fingerprint(_value(s)) for s in sources]) == shown
        assert presenter.mode == "presenting" and presenter.error_count == 0, presenter.last_error
    finally:
        hall.close()


def test_the_presenters_caption_checkbox_decides_for_the_room_a_followers_for_itself() -> None:
    hall = LectureHall(CODE)
    try:
        presenter = hall.join()
        presenter.present(CODE)
        presenter.start_lesson("§4 Inertial forces in a moving frame")
        first, second = hall.join(), hall.join()
        hall.frames(FRAMES)
        assert first.scene.caption.shown and second.scene.caption.shown and presenter.lesson_runner.caption.shown
        first.scene.gui_caption.value = False  # the follower's own checkbox: its screen only
        with first.lock:
            pass
        hall.frames(FRAMES)
        assert not first.scene.caption.shown and second.scene.caption.shown
        presenter.lesson_runner.gui_caption.value = False  # the presenter's: the room
        with presenter.lock:
            pass
        hall.frames(FRAMES)
        assert not second.scene.caption.shown and not presenter.lesson_runner.caption.shown
        presenter.lesson_runner.gui_caption.value = True
        with presenter.lock:
            pass
        hall.frames(FRAMES)
        assert second.scene.caption.shown and not first.scene.caption.shown
        presenter.select_scene("Heavy top")  # chosen by hand: the lesson and its caption end
        hall.frames(FRAMES)
        assert not second.scene.caption.shown and not presenter.lesson_runner.caption.shown
        assert second.scene.plot.tab == ""  # Heavy top opens on Setup: no plot to copy
        presenter.scene.show_tab("Energy")
        hall.frames(FRAMES)
        assert second.scene.plot.tab == "Energy" and len(second.scene.plot.copies) == 3
    finally:
        hall.close()
