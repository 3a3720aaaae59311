"""End-to-end: the Euler angles scene's single rotation D = exp(Φ hat(d)) in headless Chromium.

One test (a browser test costs ~10-20 s on 2 cores), acting through the page only: the
`Single rotation` checkbox is clicked, the scene changes (clipped screenshots differ) and the
readout appears; the `half turn` preset is clicked and the θ slider dragged with the mouse
through half turns (Φ = 180° throughout) without the drawn axis flipping; `D = 1` (Φ = 0) says
the axis is undefined.  Pictures for people under $RBL_TEST_SHOTS/rotation/ (generic
mid-animation, half turn, Φ = 0).
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from conftest import TEST_SHOTS, keep_picture
from test_browser import open_app, picture_changes, slider_thumb, still_picture

from app.main import App

pytestmark = pytest.mark.browser

MIN_CHANGED_FRACTION = 0.005  # the axis, the arc and the outlines: far more than 0.5 % of pixels


def shot(page, name: str) -> None:  # type: ignore[no-untyped-def]
    """The page as `name` under $RBL_TEST_SHOTS/rotation (if set), once its picture holds still."""
    if TEST_SHOTS:
        still_picture(page)
        keep_picture(page, f"rotation/{name}", timeout=60_000)


def drawn_axis(view) -> np.ndarray:  # type: ignore[no-untyped-def]
    tail, head = np.asarray(view.single_rotation.axis.points, dtype=float)[0]
    return (head - tail) / np.linalg.norm(head - tail)


def test_single_rotation_toggle_drag_through_half_turns_and_phi_zero(wait_until, app: App, page) -> None:
    session = open_app(page, app)
    scene = session.scene
    before = still_picture(page)  # nodes faded in

    # The checkbox, clicked: the axis, the arc and the animation appear; the readout too.
    page.locator(f'[id="{scene.single_rotation.gui_toggle._impl.uuid}"]').click()
    wait_until(lambda: scene.single_rotation.gui_toggle.value and scene.single_rotation.axis.visible, timeout=10.0)
    page.get_by_text("A = Φ hat(d), D = exp(A)").first.wait_for(timeout=10_000)
    page.mouse.move(5, 5)  # away from the checkbox: its hint closes
    assert picture_changes(page, before) > MIN_CHANGED_FRACTION  # the axis, the arc, the animation (4 s)
    shot(page, "single_rotation_generic.png")
    assert "Φ = 69.55°" in scene.single_rotation.readout.handle.content  # SciPy: |rotvec| of ZXZ (30°, 50°, 20°)

    # The half turn preset, then θ dragged with the mouse: Φ stays 180°, d never flips.
    page.get_by_role("button", name="half turn").click()
    wait_until(lambda: scene.sim.angles_deg == [0.0, 60.0, 180.0], timeout=10.0)
    page.get_by_text("Φ = 180.00°").first.wait_for(timeout=10_000)
    axes = [drawn_axis(scene)]
    thumb = slider_thumb(page, scene.gui_angles[1])
    box = thumb.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 25):
        page.mouse.move(x + 3 * k, y)
        time.sleep(0.03)
        axes.append(drawn_axis(scene))
    page.mouse.up()
    wait_until(lambda: scene.sim.angles_deg[1] > 70.0, timeout=10.0)
    time.sleep(0.3)
    axes.append(drawn_axis(scene))
    theta = scene.sim.angles_deg[1]
    assert "Φ = 180.00°" in scene.single_rotation.readout.handle.content
    steps = [float(a @ b) for a, b in zip(axes[:-1], axes[1:])]
    assert min(steps) > 0.0, steps  # the sign of d is kept while θ moves through half turns
    expected = np.array([0.0, -math.sin(math.radians(theta / 2)), math.cos(math.radians(theta / 2))])
    assert abs(float(axes[-1] @ expected)) > 1.0 - 1e-6  # the half turn's axis (up to its sign)
    shot(page, "single_rotation_half_turn.png")

    # Φ = 0: no axis, and the readout says so.
    page.get_by_role("button", name="D = 1").click()
    page.get_by_text("d undefined").first.wait_for(timeout=10_000)
    wait_until(lambda: not scene.single_rotation.axis.visible, timeout=10.0)
    shot(page, "single_rotation_phi_zero.png")
    print(f"θ dragged to {theta}°")
    assert session.last_error is None, session.last_error
