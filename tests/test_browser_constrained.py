"""The Constrained particles scene in headless Chromium, through the page only.

The scene is picked in the Scene dropdown, each preset clicked and played (the Play button);
the simulation must advance with no error, the Readout tab must show (5.13) term by term, and a
picture of each preset playing (1280×800) is kept under $RBL_TEST_SHOTS/constrained if that is set.
"""

from __future__ import annotations

import time

import pytest
from conftest import keep_picture
from test_browser import choose, open_app

from app.scenes.constrained import ConstrainedView

pytestmark = pytest.mark.browser

WIDTH, HEIGHT = 1280, 800


def test_pick_the_scene_play_every_preset(app, page) -> None:  # type: ignore[no-untyped-def]
    page.set_viewport_size({"width": WIDTH, "height": HEIGHT})
    session = open_app(page, app)
    choose(page, session.gui_scene, "Constrained particles")
    page.get_by_text("Constrained particles (memo §2, §5)").wait_for(timeout=30_000)
    for preset in ConstrainedView.presets():
        page.get_by_role("button", name=preset.name, exact=True).click()
        deadline = time.monotonic() + 20.0  # a preset's first solve on a busy machine
        while session.simulation.preset != preset.name and time.monotonic() < deadline:
            time.sleep(0.05)
        ticks = app.tick_count
        time.sleep(0.2)
        assert session.simulation.preset == preset.name, (
            f"clicked {preset.name!r}: the preset is {session.simulation.preset!r}, playing {session.room.playing}, "
            f"the app loop {'ticks' if app.tick_count > ticks else 'has stopped'}, errors {session.error_count} "
            f"(last {session.last_error!r})")
        page.get_by_role("button", name="Play", exact=True).click()
        deadline = time.monotonic() + 30.0
        while session.simulation.t < 1.2 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert session.simulation.t >= 1.2, (f"{preset.name!r} played to t = {session.simulation.t:.3f} s in 30 s, "
                                             f"errors {session.error_count} (last {session.last_error!r})")
        keep_picture(page, f"constrained/{preset.name.replace(' ', '_').replace(',', '')}.png")
        page.get_by_role("button", name="Pause", exact=True).click()
    page.get_by_role("button", name="Readout").click()
    page.get_by_text("d/dt∂T/∂q̇").first.wait_for(timeout=10_000)
    keep_picture(page, "constrained/readout.png")
    assert session.error_count == 0, session.last_error
