"""End-to-end replay: a lecturer plays the Dzhanibekov flip, pauses, drags the Timeline back,
replays it at 0.1×, resumes, drags back again and branches, all through the page (Playwright,
Debian's Chromium); the state is read back on the server.  ~20 s on 2 cores.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from conftest import DESK, TEST_SHOTS, keep_picture
from test_browser import choose

from app.kit.core.room import LIVE, REPLAYING, SCRUBBING
from app.main import App
from tests.test_browser import open_app, slider_thumb, wait_for_gui

pytestmark = pytest.mark.browser
PAGE = DESK  # the `page` fixture: no assertion here reads the page's size




def drag_thumb(page, handle, dx: float) -> None:
    """Drag a slider's thumb dx [px] sideways with the mouse, in small moves."""
    box = slider_thumb(page, handle).bounding_box()
    assert box is not None
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(x + dx * k / 10, y)
        time.sleep(0.03)
    page.mouse.up()


def test_stop_at_a_flip_scrub_back_replay_slowly_resume_and_branch(wait_until, app: App, page) -> None:
    session = open_app(page, app, wait=False)
    wait_for_gui(page)
    choose(page, session.gui_scene, "Free body")
    wait_until(lambda: session.scene.title == "Free body", timeout=10.0)
    page.get_by_role("button", name="Dzhanibekov").click()
    scene = session.scene
    room = scene.room
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: room.playing and room.sim.t > 6.0, timeout=30.0)
    page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not room.playing, timeout=10.0)
    t_live = room.sim.t
    live = room.sim.snapshot().values

    # Drag the Timeline back: the room shows a recorded moment, paused; the live one is set aside.
    timeline = scene.timeline
    assert timeline is not None
    thumb = slider_thumb(page, timeline.gui_slider)
    wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - t_live) < 0.02, timeout=10.0)
    drag_thumb(page, timeline.gui_slider, -0.3 * page.locator(f'[id="{timeline.gui_slider._impl.uuid}"]')
               .bounding_box()["width"])
    wait_until(lambda: room.mode == SCRUBBING and room.shown_t < t_live - 1.0, timeout=10.0)
    wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - room.shown_t) < 0.011, timeout=10.0)
    shown = room.shown_t
    history = room.history
    assert history is not None and history.t_first == 0.0 and room.live_t == t_live
    page.get_by_text("Showing t = ").first.wait_for(timeout=5_000)
    if TEST_SHOTS:
        time.sleep(1.0)  # the nodes fade in (a picture for people)
        keep_picture(page, "replay/flip.png")

    # Slow motion, then Replay: the recording plays at 0.1× from the moment shown.
    scale = slider_thumb(page, scene.transport.gui_time_scale)
    scale.focus()
    page.keyboard.press("Home")
    wait_until(lambda: room.time_scale == 0.1, timeout=10.0)
    page.get_by_role("button", name="Replay", exact=True).click()
    wait_until(lambda: room.mode == REPLAYING and room.shown_t > shown + 0.02, timeout=10.0)
    page.get_by_text("Replaying t = ").first.wait_for(timeout=5_000)
    assert room.shown_t < shown + 0.5  # 0.1×: a tenth of the wall time
    keep_picture(page, "replay/flip_replaying.png")

    # Resume: the live moment back, bit for bit, paused as it was.
    page.get_by_role("button", name="Resume").click()
    wait_until(lambda: room.mode == LIVE, timeout=10.0)
    assert not room.playing and room.sim.t == t_live
    np.testing.assert_array_equal(room.sim.snapshot().values, live)

    # Back again, and Branch here: the motion goes on from the moment shown.
    drag_thumb(page, timeline.gui_slider, -0.5 * page.locator(f'[id="{timeline.gui_slider._impl.uuid}"]')
               .bounding_box()["width"])
    wait_until(lambda: room.mode == SCRUBBING and room.shown_t < t_live - 1.0, timeout=10.0)
    time.sleep(0.5)  # the drag's last value applied
    branch_t = room.shown_t
    page.get_by_role("button", name="Branch here").click()
    wait_until(lambda: room.mode == LIVE and room.playing and room.sim.t > branch_t, timeout=10.0)
    assert room.sim.t < t_live and history.t_last <= room.sim.t
    assert session.last_error is None


def test_constrained_particles_scrub_back_resume_and_branch(wait_until, app: App, page) -> None:
    """The double pendulum: play, pause, drag the Timeline back (the recorded moment, its plot
    and paths rewound), Resume (the live moment bit for bit), back again and Branch here."""
    session = open_app(page, app, wait=False)
    wait_for_gui(page)
    choose(page, session.gui_scene, "Constrained particles")
    wait_until(lambda: session.scene.title == "Constrained particles", timeout=30.0)
    page.get_by_role("button", name="Double pendulum, chaotic").click()
    scene = session.scene
    room = scene.room
    wait_until(lambda: room.sim.setup.kind == "double", timeout=30.0)
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: room.playing and room.sim.t > 3.0, timeout=30.0)
    page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not room.playing, timeout=30.0)
    t_live = room.sim.t
    live = room.sim.snapshot().values
    timeline = scene.timeline
    assert timeline is not None
    width = page.locator(f'[id="{timeline.gui_slider._impl.uuid}"]').bounding_box()["width"]
    thumb = slider_thumb(page, timeline.gui_slider)
    wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - t_live) < 0.02, timeout=30.0)
    drag_thumb(page, timeline.gui_slider, -0.4 * width)
    wait_until(lambda: room.mode == SCRUBBING and room.shown_t < t_live - 0.5, timeout=30.0)
    history = room.history
    assert history is not None
    wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - room.shown_t) < 0.011, timeout=30.0)
    index = history.index_at(room.shown_t)
    if history.time(index) == room.sim.t:
        np.testing.assert_array_equal(room.sim.snapshot().values, history.snapshot(index).values)
    assert room.sim.samples.mark() <= history.snapshot(history.index_at(t_live)).values[-1 - 2 * len(room.sim.paths)]
    page.get_by_text("Showing t = ").first.wait_for(timeout=5_000)
    keep_picture(page, "replay/flip_constrained.png")

    page.get_by_role("button", name="Resume").click()
    wait_until(lambda: room.mode == LIVE, timeout=30.0)
    assert not room.playing and room.sim.t == t_live
    np.testing.assert_array_equal(room.sim.snapshot().values, live)

    wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - t_live) < 0.02, timeout=30.0)  # back live
    drag_thumb(page, timeline.gui_slider, -0.5 * width)
    wait_until(lambda: room.mode == SCRUBBING and room.shown_t < t_live - 0.5, timeout=30.0)
    wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - room.shown_t) < 0.011, timeout=30.0)
    branch_t = room.shown_t
    page.get_by_role("button", name="Branch here").click()
    wait_until(lambda: room.mode == LIVE and room.playing and room.sim.t > branch_t, timeout=30.0)
    assert room.sim.t < t_live + 1.0 and history.t_last <= room.sim.t
    assert session.last_error is None and session.error_count == 0
