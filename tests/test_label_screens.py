"""3D labels on every screen that shows them (app.kit.draw.labels, app.kit.draw.screen), server side.

1. The layer alone, on a bare viser server: a box body with the space axes' labels and a
   crowd of labels round it, seen from sampled camera poses on three screens (a 1280x800
   desktop with its floating panel, a 390x844 phone at device scale 2 with its bottom sheet, a
   1024x768 projector whose docked panel leaves a 764x768 canvas), each alone and all three at
   once (the presenter's shared labels): on every screen no two labels shown overlap, none
   covers the panel's rectangle or runs off the window, and no space axis label sits on the
   body's projected outline.
2. The lecture hall (raw clients, the loop ticked by hand): a phone follower of a presenter
   showing Euler angles sees no two labels overlap, paused and playing (the shared labels are
   laid out for its screen too: it sees the picture from farther away).
3. The presenter points at "g" with a label: the pointer's label shows, and g makes room.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
import trimesh
import viser
from conftest import LectureHall

from app.kit.core.common import CameraView
from app.kit.draw.labels import AXES, DETAIL, KEY, LabelLayer
from app.kit.draw.screen import (
    LabelBox,
    Screen,
    boxes_meet,
    convex_hull,
    label_boxes,
    overlapping,
    panel_box,
    polygon_meets_box,
    project,
)

CODE = "135791"
DT = 1.0 / 60.0
DESKTOP, PHONE, PROJECTOR = (1280, 800, False), (780, 1688, False), (764, 768, True)  # canvas [px], docked
POSES = 10  # sampled camera poses


def _screen(view: CameraView, size: tuple[int, int, bool]) -> Screen:
    width, height, docked = size
    return Screen(view, width, height, panel_box(width, height, docked))


def _shown(scene: Any, screen: Screen, prefix: str) -> list[LabelBox]:
    return [b for b in label_boxes(scene, screen.view, screen.width, screen.height) if b.name.startswith(prefix)]


def _problems(boxes: list[LabelBox], screen: Screen, body: np.ndarray | None = None,
              axes: tuple[str, ...] = ()) -> list[str]:
    """What is wrong with the labels shown on `screen`: overlaps, the panel, the window's edges,
    the space axes' labels (`axes`, by name) on the body's outline (convex polygon [px])."""
    found = [f"{a.text!r} meets {b.text!r} ({gap:.1f} px)" for a, b, gap in overlapping(boxes, 0.0)]
    for box in boxes:
        if screen.panel is not None and boxes_meet(box.box, screen.panel):
            found.append(f"{box.text!r} on the panel")
        x0, y0, x1, y1 = box.box
        if x0 < 0.0 or y0 < 0.0 or x1 > screen.width or y1 > screen.height:
            found.append(f"{box.text!r} cut at the window's edge")
        if body is not None and box.name in axes and polygon_meets_box(body, box.box):
            found.append(f"the axis label {box.text!r} on the body")
    return found


@pytest.fixture(scope="module")
def scene() -> Iterator[Any]:
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield server.scene
    finally:
        server.stop()


def test_no_label_overlaps_another_the_panel_or_the_body_on_any_screen(scene) -> None:
    rng = np.random.default_rng(24)
    root = "/screens"
    box = trimesh.creation.box(extents=(1.6, 1.1, 0.35))  # a book, as big as Poinsot's
    scene.add_mesh_simple(f"{root}/body/shape/mesh", box.vertices, box.faces)
    axes = tuple(f"{root}/space/{name}" for name in "xyz")
    texts = ["ω", "L", "x′", "y′", "z′", "line of nodes", "θ = 50°", "dψ/dt", "centrifugal", "Coriolis", "η′"]
    crowd = [(text, tuple(rng.uniform(-1.4, 1.4, 3)), (KEY, AXES, DETAIL)[i % 3]) for i, text in enumerate(texts)]
    seen = 0
    for pose in range(POSES):
        direction = rng.normal(size=3)
        direction[2] = abs(direction[2]) + 0.3  # from above the floor, as the scenes look
        view = CameraView(tuple(rng.uniform(5.0, 8.0) * direction / np.linalg.norm(direction)),  # type: ignore[arg-type]
                          tuple(rng.uniform(-0.4, 0.4, 3)), fov_deg=40.0)  # type: ignore[arg-type]
        body = np.asarray(box.vertices, dtype=float)
        for sizes in ((DESKTOP,), (PHONE,), (PROJECTOR,), (DESKTOP, PHONE, PROJECTOR)):
            screens = [_screen(view, size) for size in sizes]
            layer = LabelLayer(None, view, lambda screens=screens: screens)
            layer.avoid(scene, f"{root}/body/shape")
            prefix = f"{root}/case{pose}_{len(sizes)}{sizes[0][0]}"
            for k, name in enumerate("xyz"):  # re-added per case: a slid label comes back home
                layer.add(scene.add_label(f"{root}/space/{name}", name, position=tuple(1.45 * np.eye(3)[k]),
                                          font_screen_scale=1.8, anchor="center-center"), KEY, clear_of_bodies=True)
            for i, (text, at, priority) in enumerate(crowd):
                layer.add(scene.add_label(f"{prefix}/{i}", text, position=at, font_screen_scale=1.8,
                                          anchor="center-center"), priority)
            layer.settle()
            for screen in screens:
                shown = _shown(scene, screen, f"{root}/space/") + _shown(scene, screen, prefix + "/")
                seen += len(shown)
                outline = convex_hull(project(view, body, screen.width, screen.height)[0])
                problems = _problems(shown, screen, outline, axes)
                assert not problems, f"pose {pose}, screens {sizes}, on {screen.width}x{screen.height}: {problems}"
            for name, handle in list(scene._handle_from_node_name.items()):
                if name.startswith(prefix + "/"):
                    handle.remove()
    assert seen > POSES * 4 * 8  # the layer did not get there by hiding everything


# ---------------------------------------------------------------------- the lecture hall
def _window(client: Any, width: int, height: int) -> None:
    """What a browser of that canvas size reports."""
    from viser import _messages

    client.send(_messages.ViewerCameraMessage(
        wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, 3.0, 3.0), fov=math.radians(50.0), near=0.01, far=100.0,
        image_height=height, image_width=width, look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))


def _screen_of_session(session: Any) -> Screen:
    from app.kit.draw.screen import screen_of

    screen = screen_of(session.client.camera, docked=session.projector)
    assert screen is not None
    return screen


@pytest.fixture
def hall() -> Iterator[LectureHall]:
    running = LectureHall(CODE)
    try:
        yield running
    finally:
        running.close()


def test_a_phone_follower_sees_no_two_labels_overlap(hall: LectureHall) -> None:
    from conftest import poll_until

    from app.lecture.follower import view_aspect
    from app.lecture.lectern import fitted_camera

    presenter, presenter_client = hall.join_with_client()
    _window(presenter_client, *DESKTOP[:2])
    poll_until(lambda: presenter.client.camera.image_width == DESKTOP[0])
    presenter.reset_camera()
    presenter.present(CODE)
    phone, phone_client = hall.join_with_client()
    _window(phone_client, *PHONE[:2])
    poll_until(lambda: phone.client.camera.image_width == PHONE[0])
    hall.frames(1)
    poll_until(lambda: phone.mode == "following" and phone.scene.narrow)  # its panel fitted to its view

    def fitted() -> bool:  # the lectern has put the phone's camera where the presenter's is, fitted
        source, camera = presenter.client.camera, phone.client.camera
        position, _ = fitted_camera(source.position, source.look_at, view_aspect(source), view_aspect(camera),
                                    float(source.fov), source.up_direction)
        return bool(np.allclose(camera.position, position, atol=1e-9))

    poll_until(fitted)
    scene = hall.app.server.scene
    live = presenter.scene.root + "/"

    def counts() -> list[int]:
        return [len(_shown(scene, _screen_of_session(session), live)) for session in (presenter, phone)]

    layer = presenter.scene.labels

    def laid_out() -> bool:  # the layer's last layout was for the phone's fitted screen (PERIOD apart, wall time)
        hall.frames(1)
        phone_screen = _screen_of_session(phone)
        return min(counts()) >= 6 and any(
            (s.view, s.width, s.height) == (phone_screen.view, phone_screen.width, phone_screen.height)
            for s in layer._last_screens or ())

    poll_until(laid_out, timeout=30.0, interval=0.02, what="the labels laid out for the phone's fitted screen",
               seen=lambda: (counts(), layer.layouts))
    for moment in range(8):
        for session in (presenter, phone):
            screen = _screen_of_session(session)
            shown = _shown(scene, screen, live)
            problems = _problems(shown, screen)
            assert not problems, f"{moment}: on {screen.width}x{screen.height}: {problems}"
            assert len(shown) >= 6, [b.text for b in shown]
        if moment == 0:
            presenter.play()
        hall.frames(7)


def test_the_phones_screen_moves_with_the_camera_the_lectern_sends_it(hall: LectureHall) -> None:
    """The follower screens the shared labels are laid out for are kept for a while
    (`Lectern.follower_screens`); a camera the lectern sends a follower ends that at once."""
    from conftest import poll_until
    from viser import _messages

    presenter, presenter_client = hall.join_with_client()
    _window(presenter_client, *DESKTOP[:2])
    poll_until(lambda: presenter.client.camera.image_width == DESKTOP[0])
    presenter.present(CODE)
    phone, phone_client = hall.join_with_client()
    _window(phone_client, *PHONE[:2])
    poll_until(lambda: phone.client.camera.image_width == PHONE[0])
    hall.frames(1)
    poll_until(lambda: phone.mode == "following")
    hall.frames(2)
    before = hall.app.lectern.follower_screens()[0].view.position
    presenter_client.send(_messages.ViewerCameraMessage(  # the presenter turns the view
        wxyz=(1.0, 0.0, 0.0, 0.0), position=(-4.0, 2.0, 1.5), fov=math.radians(50.0), near=0.01, far=100.0,
        image_height=DESKTOP[1], image_width=DESKTOP[0], look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))
    poll_until(lambda: presenter.client.camera.position[0] == -4.0)
    moved = lambda: not np.allclose(phone.client.camera.position, before)  # noqa: E731

    def sent() -> bool:
        """A frame of the loop, then whether the phone's camera moved: the lectern hears the turn
        on viser's callback thread (`app.lecture.lectern.followers.Followers._camera_moved`), maybe only
        after many frames on a busy machine, and then sends it at its next CAMERA_PERIOD of frames."""
        hall.frames(1)
        return moved()

    try:
        poll_until(sent, timeout=20.0, interval=0.005)
    except AssertionError:
        turned, stayed = tuple(presenter.client.camera.position), tuple(phone.client.camera.position)
        raise AssertionError(f"the lectern did not send the presenter's camera {turned} to the phone "
                             f"within 20 s: it stayed at {stayed}") from None
    kept = lambda: hall.app.lectern.follower_screens()[0].view.position  # noqa: E731 - the screen the labels use
    poll_until(lambda: np.allclose(kept(), phone.client.camera.position, atol=1e-9), timeout=20.0,
               what="the phone's kept screen at the camera sent to it",
               seen=lambda: (kept(), tuple(phone.client.camera.position), before))


def test_the_pointers_label_shows_and_g_makes_room(hall: LectureHall) -> None:
    from conftest import poll_until

    presenter, client = hall.join_with_client()
    _window(client, *DESKTOP[:2])
    poll_until(lambda: presenter.client.camera.image_width == DESKTOP[0])
    presenter.select_scene("Heavy top")
    presenter.reset_camera()
    presenter.present(CODE)
    hall.frames(3)
    live = presenter.scene
    g = next(e.handle for e in live.labels._entries.values() if str(e.handle.text) == "g")
    camera = presenter.client.camera
    eye = np.asarray(camera.position, dtype=float)
    from app.viser_internals import world_point

    at = np.asarray(world_point(g)[0])  # type: ignore[index]
    with presenter.lock:
        hall.app.lectern.point(presenter, tuple(eye), tuple(at - eye), "gravity here")
    hall.frames(8)
    screen = _screen_of_session(presenter)
    shown = _shown(hall.app.server.scene, screen, "/l/")
    assert "gravity here" in [b.text for b in shown]
    assert not _problems(shown, screen)
