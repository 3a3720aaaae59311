"""app.kit.screen.Projector: one view's projection worked out once, the same pixels as project_one."""

from __future__ import annotations

import math

import pytest

from app.kit.common import CameraView
from app.kit.screen import Projector, project_one

VIEWS = [
    (CameraView(position=(0.0, -10.0, 0.0), look_at=(0.0, 0.0, 0.0), fov_deg=90.0), 1280, 800),
    (CameraView(position=(5.0, -4.2, 3.2), look_at=(0.3, 0.6, 0.2), fov_deg=40.0), 1280, 800),
    (CameraView(position=(-2.5, 7.0, -1.0), look_at=(1.0, -0.5, 0.75), up=(0.1, 0.2, 0.97), fov_deg=62.5), 1919, 1037),
    (CameraView(position=(0.0, 0.0, 12.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_deg=20.0), 640, 480),
]
POINTS = [(0.0, 0.0, 0.0), (1.0, -2.0, 0.5), (-3.0, 2.0, 4.0), (0.3, 0.6, 0.2), (12.5, -7.25, 3.0), (1e-3, 2e-3, -4e-3)]


@pytest.mark.parametrize(("view", "width", "height"), VIEWS)
def test_the_projector_gives_project_ones_pixels(view: CameraView, width: int, height: int) -> None:
    project = Projector(view, width, height)
    for point in POINTS:
        (x, y), depth = project(*point)
        (x1, y1), depth1 = project_one(view, point, width, height)
        assert depth == pytest.approx(depth1, abs=1e-12)
        if math.isnan(x1):  # behind the camera: NaN pixels both
            assert math.isnan(x) and math.isnan(y) and math.isnan(y1)
        else:
            assert abs(x - x1) <= 1e-9 and abs(y - y1) <= 1e-9


def test_the_projector_hides_what_is_behind_the_camera() -> None:
    view, width, height = VIEWS[0]
    (x, y), depth = Projector(view, width, height)(0.0, -20.0, 0.0)
    assert depth == pytest.approx(-10.0) and math.isnan(x) and math.isnan(y)
