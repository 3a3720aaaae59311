"""app.kit.draw.screen.Projector (and project_one, built on it): the same pixels as the vectorised project."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.kit.core.common import CameraView
from app.kit.draw.screen import Projector, project, project_one

VIEWS = [
    (CameraView(position=(0.0, -10.0, 0.0), look_at=(0.0, 0.0, 0.0), fov_deg=90.0), 1280, 800),
    (CameraView(position=(5.0, -4.2, 3.2), look_at=(0.3, 0.6, 0.2), fov_deg=40.0), 1280, 800),
    (CameraView(position=(-2.5, 7.0, -1.0), look_at=(1.0, -0.5, 0.75), up=(0.1, 0.2, 0.97), fov_deg=62.5), 1919, 1037),
    (CameraView(position=(0.0, 0.0, 12.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_deg=20.0), 640, 480),
]
POINTS = [(0.0, 0.0, 0.0), (1.0, -2.0, 0.5), (-3.0, 2.0, 4.0), (0.3, 0.6, 0.2), (12.5, -7.25, 3.0), (1e-3, 2e-3, -4e-3)]


@pytest.mark.parametrize(("view", "width", "height"), VIEWS)
def test_the_projector_gives_the_pixels_of_the_vectorised_projection(view: CameraView, width: int,
                                                                     height: int) -> None:
    """Projector's plain-float arithmetic against `project`'s numpy (cross products, matmuls):
    the same pixels within 1e-9 px, the same depths within 1e-12, NaN behind the camera."""
    pixels, depths = project(view, np.array(POINTS), width, height)
    project_many = Projector(view, width, height)
    for point, (x_ref, y_ref), depth_ref in zip(POINTS, pixels, depths):
        for (x, y), depth in (project_many(*point), project_one(view, point, width, height)):
            assert depth == pytest.approx(depth_ref, abs=1e-12)
            if math.isnan(x_ref):  # behind the camera: NaN pixels both
                assert math.isnan(x) and math.isnan(y) and math.isnan(y_ref)
            else:
                assert abs(x - x_ref) <= 1e-9 and abs(y - y_ref) <= 1e-9


def test_the_projector_hides_what_is_behind_the_camera() -> None:
    view, width, height = VIEWS[0]
    (x, y), depth = Projector(view, width, height)(0.0, -20.0, 0.0)
    assert depth == pytest.approx(-10.0) and math.isnan(x) and math.isnan(y)


@pytest.mark.parametrize(("view", "width", "height"), VIEWS)
def test_the_projector_projects_a_posed_point_set_as_project_does(view: CameraView, width: int, height: int) -> None:
    """Projector.pixels (a frame's points, the frame's pose and the camera composed first)
    against `project` of the same points moved to the world by hand."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(7)
    local = rng.normal(size=(20, 3))
    rotation = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    offset = (0.4, -0.2, 0.9)
    expected, _ = project(view, local @ rotation.T + np.array(offset), width, height)
    got = np.array(Projector(view, width, height).pixels(local, rotation, offset))
    np.testing.assert_allclose(got, expected, atol=1e-7)


def test_an_outline_meets_the_boxes_the_numpy_polygon_test_says() -> None:
    """Outline (the hull on Python floats, its separating axes worked out once) against
    `polygon_meets_box` on `convex_hull`: the same polygon and the same answer for many boxes."""
    from app.kit.draw.screen import Outline, convex_hull, hull_chain, polygon_meets_box

    rng = np.random.default_rng(3)
    for _ in range(20):
        points = rng.uniform(100.0, 400.0, size=(int(rng.integers(1, 30)), 2))
        chain = hull_chain(points.tolist())
        np.testing.assert_array_equal(np.array(chain).reshape(-1, 2), convex_hull(points))
        outline = Outline(points.tolist())
        assert outline.vertices == chain
        polygon = convex_hull(points)
        for _ in range(50):
            x0, y0 = rng.uniform(0.0, 450.0, size=2)
            box = (x0, y0, x0 + rng.uniform(1.0, 120.0), y0 + rng.uniform(1.0, 60.0))
            assert outline.meets(box) == polygon_meets_box(polygon, box)


def test_a_narrow_view_centres_the_body_above_the_bottom_sheet() -> None:
    """`narrow_view`: every scene's camera view, for a 390x844 phone, keeps its viewing direction
    and fov, is farther back, and shows the body's middle (`body_centre`) horizontally centred in
    the middle of the part the bottom sheet (PHONE_PANEL_SHARE) leaves."""
    import numpy as np

    from app.kit.draw.screen import PHONE_PANEL_SHARE, body_centre, narrow_view
    from app.scenes import SCENES

    for title, scene in SCENES.items():
        view = scene.view
        phone = narrow_view(view, 390 / 844)
        (x, y), depth = project_one(phone, body_centre(view), 390, 844)
        assert abs(x - 195.0) < 1e-6 and abs(y - (1.0 - PHONE_PANEL_SHARE) * 844 / 2) < 1e-6, (title, x, y)
        sight, wide_sight = np.subtract(phone.position, phone.look_at), np.subtract(view.position, view.look_at)
        np.testing.assert_allclose(sight / np.linalg.norm(sight), wide_sight / np.linalg.norm(wide_sight), atol=1e-12)
        assert np.linalg.norm(sight) > 2.0 * np.linalg.norm(wide_sight) and phone.fov_deg == view.fov_deg, title
