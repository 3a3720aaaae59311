"""End-to-end: the explorer in headless Chromium (SwiftShader WebGL), driven by Playwright.

One test (~10 s): the page loads, the θ slider is moved with the keyboard on its Mantine
thumb, the server sees the new value, and the rendered scene changes (clipped screenshots
before and after differ).  Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import io
import re
import time

import numpy as np
import pytest
from PIL import Image

from app.main import App

pytestmark = pytest.mark.browser

SCENE_CLIP = {"x": 0, "y": 0, "width": 860, "height": 800}  # left of the GUI panel
MIN_CHANGED_FRACTION = 0.005  # θ 50° -> 179° turns the body over: far more than 0.5 % of pixels


def changed_fraction(png_a: bytes, png_b: bytes) -> float:
    """Fraction of pixels whose RGB differs by more than 8/255 in any channel."""
    a = np.asarray(Image.open(io.BytesIO(png_a)).convert("RGB"), dtype=np.int16)
    b = np.asarray(Image.open(io.BytesIO(png_b)).convert("RGB"), dtype=np.int16)
    return float(np.mean(np.any(np.abs(a - b) > 8, axis=-1)))


def test_theta_slider_in_the_browser_moves_the_body(wait_until, app: App, page) -> None:
    page.goto(f"http://127.0.0.1:{app.port}")
    (session,) = app.wait_for_sessions(1, timeout=30.0).values()
    page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    toasts = page.locator(".mantine-Notification-closeButton")  # "software WebGL" notice
    for i in range(toasts.count()):
        toasts.nth(i).click(force=True)
    time.sleep(1.5)  # nodes fade in
    before = page.screenshot(clip=SCENE_CLIP)
    time.sleep(0.5)
    unchanged = changed_fraction(before, page.screenshot(clip=SCENE_CLIP))
    assert unchanged < MIN_CHANGED_FRACTION / 5  # control: a still scene renders the same

    # The slider root's id is the GUI uuid; its <label for=...> carries the text.
    uuid = page.locator("label", has_text=re.compile(r"^θ")).first.get_attribute("for")
    assert uuid == session.scene.gui_theta._impl.uuid
    thumb = page.locator(f'[id="{uuid}"] [role="slider"]')
    thumb.focus()
    page.keyboard.press("End")
    wait_until(lambda: session.scene.angles_deg[1] == 180.0, timeout=10.0)
    assert thumb.get_attribute("aria-valuenow") == "180"
    page.get_by_text("Gimbal lock").wait_for(timeout=5_000)  # θ = 180°: the GUI says so

    page.keyboard.press("ArrowLeft")  # one step: 179°
    wait_until(lambda: session.scene.angles_deg[1] == 179.0, timeout=10.0)
    time.sleep(1.0)
    after = page.screenshot(clip=SCENE_CLIP)
    changed = changed_fraction(before, after)
    print(f"changed pixels: still {unchanged:.4%}, after θ 50° -> 179° {changed:.2%}")
    assert changed > MIN_CHANGED_FRACTION
    assert session.last_error is None
