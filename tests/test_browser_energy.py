"""Setting the motion by hand and the energy picture, in Debian's Chromium, through the page only.

One test (a browser test costs ~15 s on 2 cores): the Heavy top is chosen in the Scene
dropdown and its "Cusp" preset clicked; the mouse grabs the z arrow of the gizmo at ω's tip
(projected through the browser's own camera) and drags it up: the server's ω_b is then
Rᵀ p / scale for the gizmo's position p (read back), with a larger space z component, and the
φ̇ slider has followed.  Play, then "Kick about x′" (in the "Set ω by hand" folder): ω_x′ grows by
J / I1 while the top keeps playing.  The Energy tab names the motion of the "Loop" preset.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from test_browser import choose, open_app
from test_browser_lecture import project

from app.main import App

pytestmark = pytest.mark.browser

WIDTH, HEIGHT = 1280, 800
DRAG_PX = 60  # how far the mouse drags the gizmo's z arrow up the screen
OMEGA_RTOL = 1e-9  # ω_b against Rᵀ p / scale (float32 positions travel as floats both ways)


def test_dragging_the_omega_gizmo_sets_omega_and_kick_and_energy_tab_work(wait_until, app: App, page) -> None:
    session = open_app(page, app)
    choose(page, session.gui_scene, "Heavy top")
    wait_until(lambda: session.scene.title == "Heavy top", timeout=10.0)
    view = session.scene
    page.get_by_role("button", name="Cusp", exact=True).click()
    wait_until(lambda: view.sim.preset == "Cusp", timeout=10.0)
    time.sleep(1.5)  # nodes fade in, the camera message has arrived

    # Drag: grab the gizmo's z arrow a little above its centre and pull it up.
    gizmo = view.hand.gizmos["omega"]
    assert gizmo.visible and not session.room.playing
    tip = np.asarray(gizmo.position, dtype=float)
    omega_space_before = view.sim.state.R_space_body @ view.sim.state.omega_body
    x, y = project(session.client.camera, tip + np.array([0.0, 0.0, 0.3]), WIDTH, HEIGHT)
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x, y - DRAG_PX, steps=10)
    page.mouse.up()
    wait_until(lambda: view.sim.preset is None and view.hand.dragging is None, timeout=10.0)
    time.sleep(0.5)  # the last update of the drag has been applied
    with session.lock:
        R = view.sim.state.R_space_body
        p = np.asarray(gizmo.position, dtype=float)
        omega_body = view.sim.state.omega_body.copy()
        scale = view.omega_scale
        phi_dot_slider = float(view.gui_rates[1].value)
        phi_dot = view.rates_from_state(view.sim.angles, view.sim.state)[1]
    np.testing.assert_allclose(omega_body, R.T @ p / scale, rtol=OMEGA_RTOL)
    omega_space = R @ omega_body
    assert omega_space[2] > omega_space_before[2] + 0.5  # dragged up: ω_z grew
    assert phi_dot_slider == pytest.approx(view.rate_specs[1].rounded(phi_dot), abs=0.1)  # the slider followed
    assert abs(phi_dot) > 1.0  # φ̇ was 0 in the Cusp preset

    # Play, then kick about x′ from the panel: Δω_x′ = J / I1, still playing.
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: session.room.playing and view.sim.t > 0.2, timeout=10.0)
    page.get_by_text("Set ω by hand", exact=True).first.click()
    kick = page.get_by_role("button", name="x′", exact=True)
    kick.wait_for(state="visible", timeout=5_000)
    restarts = view.sim.restarts
    kick.click()
    wait_until(lambda: view.sim.restarts > restarts, timeout=10.0)
    assert session.room.playing
    before, after = view.hand.last_change
    np.testing.assert_allclose(after - before, [view.hand.impulse / view.sim.model.inertia[0], 0.0, 0.0],
                               atol=1e-12)
    np.testing.assert_array_equal(view.sim.initial_state.omega_body, after)  # the new run starts there
    assert view.message.text == ""

    # The Energy tab names the motion of the Loop preset.
    page.get_by_role("button", name="Loop", exact=True).click()
    page.get_by_role("button", name="Energy", exact=True).click()
    page.get_by_text("Motion: loop.").first.wait_for(state="visible", timeout=10_000)
    assert view.energy_plot.picture is not None and view.energy_plot.picture.motion == "loop"
    assert session.last_error is None

