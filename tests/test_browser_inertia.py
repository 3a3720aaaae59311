"""The body shows inside the momental ellipsoid (Inertia scene), in headless Chromium.

The ellipsoid is translucent; drawn with its front faces, it hid an uploaded compact mesh
entirely and the shipped book wherever it was inside.  Now only its back faces are drawn
(`side="back"`: the far half of the shell, behind anything inside it).  Through the page: the
scene is chosen in the dropdown, a preset and the shipped book clicked, a 0.6 m box uploaded;
then the orange (body-coloured) pixels of a patch around the body's projected centre of mass
(`app.kit.draw.screen.project` through the scene's camera view) are counted with the ellipsoid shown
and hidden: nearly as many must show through it (the old ellipsoid left 0 % of the box).
"""

from __future__ import annotations

import io

import numpy as np
import pytest
import trimesh
from PIL import Image
from test_browser import SCENE_CLIP, choose, open_app, still_picture

from app.kit.draw.screen import project
from app.scenes.inertia import InertiaView

pytestmark = pytest.mark.browser

WIDTH, HEIGHT = 1280, 800
PATCH = 40  # [px] half-width of the square sampled around the projected centre of mass
MIN_REFERENCE = 0.1  # the patch is at least this orange with the ellipsoid hidden (it is on the body)
MIN_RATIO = 0.9  # orange pixels with the ellipsoid shown / with it hidden


def _orange_fraction(png: bytes, centre: tuple[float, float]) -> float:
    """Fraction of the patch's pixels that are orange (R − B > 60 and R > G): the body's colour
    (215, 140, 70) or the masses' (230, 150, 60), shaded; the ellipsoid is blue, the grid grey."""
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)
    x, y = round(centre[0]), round(centre[1])
    patch = rgb[y - PATCH:y + PATCH + 1, x - PATCH:x + PATCH + 1]
    orange = (patch[..., 0] - patch[..., 2] > 60) & (patch[..., 0] > patch[..., 1])
    return float(np.mean(orange))


def _shot_pair(page, view) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """Orange fraction at the centre of mass with the ellipsoid shown, and hidden (the reference),
    each in a picture that holds still (the objects have faded in: on a busy page that takes
    longer than any fixed wait)."""
    (centre,), _ = project(InertiaView.view, view.sim.properties()["com"] * view.sim.display_scale(), WIDTH, HEIGHT)
    assert centre[0] + PATCH < SCENE_CLIP["width"], f"the centre of mass {centre} is not left of the panel"
    shown = _orange_fraction(still_picture(page, SCENE_CLIP, timeout=60.0), (centre[0], centre[1]))
    with view.room.lock:
        view._ellipsoid.visible = False  # the reference picture (an instrument, not a user action)
    hidden = _orange_fraction(still_picture(page, SCENE_CLIP, timeout=60.0), (centre[0], centre[1]))
    with view.room.lock:
        view._ellipsoid.visible = True
    return shown, hidden


def test_the_body_shows_inside_the_momental_ellipsoid(app, page, tmp_path) -> None:
    page.set_viewport_size({"width": WIDTH, "height": HEIGHT})
    session = open_app(page, app)
    choose(page, session.gui_scene, "Inertia")
    page.get_by_text("Inertia tensor (memo §3)").wait_for(timeout=30_000)
    view = session.scene
    results = {}
    # Point masses: "On a line" has its heaviest mass at the centre, inside the cigar.
    page.get_by_role("button", name="On a line").click()
    results["point masses"] = _shot_pair(page, view)
    page.get_by_text("Solid mesh").first.click()  # open the folder
    page.get_by_role("button", name="book", exact=True).click()
    page.get_by_text("book.stl").first.wait_for(timeout=10_000)
    results["book"] = _shot_pair(page, view)
    box = tmp_path / "box_0.6m.stl"
    trimesh.creation.box(extents=(0.6, 0.6, 0.6)).export(box)
    with page.expect_file_chooser() as chooser:  # the mesh's upload button (the Mine folder has one too)
        page.get_by_role("button", name="Upload STL / OBJ / PLY / OFF / GLB").click()
    chooser.value.set_files(str(box))
    page.get_by_text("box_0.6m.stl").first.wait_for(timeout=10_000)
    results["0.6 m box"] = _shot_pair(page, view)
    report = "; ".join(f"{k}: {s:.0%} orange with the ellipsoid, {h:.0%} without" for k, (s, h) in results.items())
    print(report)
    assert all(h >= MIN_REFERENCE for _, h in results.values()), f"the reference patch missed the body: {report}"
    assert all(s >= MIN_RATIO * h for s, h in results.values()), report
    assert session.error_count == 0, session.last_error
