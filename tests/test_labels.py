"""3D labels do not overlap: every scene, every preset, its first 10 s, at 1280x800.

Each label shown is projected through the scene's camera view (`app.kit.screen.project`, a
pinhole checked here against hand-computed cases) and its text box estimated from viser's
label layout (`app.kit.screen.label_boxes`); any two boxes must be at least MIN_GAP_PX apart at
every sampled time.  Sessions come from a raw websocket client (`manual`); nothing is drawn.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from app.kit.common import CameraView
from app.kit.screen import LabelBox, label_boxes, overlapping, project
from app.scenes import SCENES

WIDTH, HEIGHT = 1280, 800
MIN_GAP_PX = 4.0  # [px] between two label boxes (the boxes already include viser's 0.2 em padding)
SECONDS = 10.0  # of simulated time from the preset's start
SAMPLE_EVERY = 0.25  # [s] of simulated time between checks
DT = 1.0 / 20.0  # [s] per tick (the motion does not depend on the frame rate: tests/test_frame_rate.py)


def test_projection_of_known_points() -> None:
    """A camera on −y looking at the origin, z up, 90° vertical fov: x right, z up on screen,
    1 unit at depth 10 is a tenth of the half-height."""
    view = CameraView(position=(0.0, -10.0, 0.0), look_at=(0.0, 0.0, 0.0), fov_deg=90.0)
    pixels, depth = project(view, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0], [0.0, -20.0, 0.0]], 1280, 800)
    np.testing.assert_allclose(pixels[:3], [[640.0, 400.0], [680.0, 400.0], [640.0, 320.0]], atol=1e-9)
    np.testing.assert_allclose(depth, [10.0, 10.0, 10.0, -10.0], atol=1e-12)
    assert np.all(np.isnan(pixels[3]))  # behind the camera
    # An oblique view: the look_at point is always the centre; fov 40° → focal 400 / tan 20°.
    view = CameraView(position=(5.0, -4.2, 3.2), look_at=(0.3, 0.6, 0.2), fov_deg=40.0)
    centre, _ = project(view, [0.3, 0.6, 0.2], 1280, 800)
    np.testing.assert_allclose(centre, [[640.0, 400.0]], atol=1e-9)
    eye = np.array(view.position)
    forward = (np.array(view.look_at) - eye) / np.linalg.norm(np.array(view.look_at) - eye)
    point = np.array(view.look_at) + 1.0 * np.array([0.0, 0.0, 1.0])  # one unit above look_at
    (x, y), depth = (v[0] for v in project(view, point, 1280, 800))
    focal = 400.0 / math.tan(math.radians(20.0))
    # Straight up in space is straight up on screen (the camera has no roll), by focal · (z⊥ / depth).
    z_perp = math.sqrt(1.0 - forward[2] ** 2)
    assert x == pytest.approx(640.0, abs=1e-9)
    assert y == pytest.approx(400.0 - focal * z_perp / depth, rel=1e-12)


def test_label_boxes_follow_the_anchor() -> None:
    a = LabelBox("a", "ab", (100.0, 100.0), (100.0, 100.0, 130.0, 120.0))
    b = LabelBox("b", "cd", (135.0, 100.0), (135.0, 100.0, 165.0, 120.0))
    c = LabelBox("c", "ef", (120.0, 110.0), (120.0, 110.0, 150.0, 130.0))
    assert a.gap(b) == pytest.approx(5.0) and a.gap(c) < 0.0
    assert [(p.name, q.name) for p, q, _ in overlapping([a, b, c], MIN_GAP_PX)] == [("a", "c"), ("b", "c")]


def _cases() -> list[Any]:
    """(title, preset) of every preset of every scene."""
    return [pytest.param(title, preset.name) for title, scene in SCENES.items() for preset in scene.presets()]


def _describe(pairs: list[tuple[LabelBox, LabelBox, float]]) -> str:
    return "; ".join(f"{a.text!r} at ({a.anchor_px[0]:.0f}, {a.anchor_px[1]:.0f}) and {b.text!r} at "
                     f"({b.anchor_px[0]:.0f}, {b.anchor_px[1]:.0f}): gap {gap:.0f} px" for a, b, gap in pairs)


@pytest.mark.parametrize(("title", "preset"), _cases())
def test_labels_do_not_overlap_in_the_first_10_s(manual, title: str, preset: str) -> None:
    session = manual.session
    session.select_scene(title)
    session.apply_preset(preset)
    session.reset_camera()  # the browser's camera at the scene's view (the raw client starts elsewhere)
    view = session.scene
    session.play()
    problems: list[str] = []
    t_next = 0.0
    for _ in range(round(SECONDS / DT) + 1):
        t = session.simulation.t
        if t >= t_next - 1e-9:
            t_next += SAMPLE_EVERY
            with session.lock:
                pairs = overlapping(label_boxes(session.client.scene, view.view, WIDTH, HEIGHT), MIN_GAP_PX)
            if pairs:
                problems.append(f"t = {t:.2f} s: {_describe(pairs)}")
        session.tick(DT)
    assert session.error_count == 0, session.last_error
    assert not problems, f"{title} {preset!r}: labels overlap at 1280x800:\n" + "\n".join(problems[:8])
