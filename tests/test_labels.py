"""3D labels do not overlap: every scene, every preset, its first 10 s, at 1280x800.

Each label shown is projected through the scene's camera view (`app.kit.draw.screen.project`, a
pinhole checked here against hand-computed cases) and its text box estimated from viser's
label layout (`app.kit.draw.screen.label_boxes`); any two boxes must be at least MIN_GAP_PX apart at
every sampled time.  What is shown is what each view's `LabelLayer` (app.kit.draw.labels) left
visible; the layer must not get there by hiding what matters: the space axes x y z are shown
at every sample, and the KEY labels (ω, L, forces, g, ...) most of the time.  Sessions come
from a raw websocket client (`manual`); nothing is drawn.

The layer's own rules (priority, nudging, wanted visibility, the camera it looks through,
messages only for changes) are checked on a bare viser server.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
import viser

from app.kit.core.common import CameraView
from app.kit.draw.labels import DETAIL, KEY, LabelLayer
from app.kit.draw.screen import LabelBox, boxes_meet, label_boxes, overlapping, panel_box, project, project_one
from app.scenes import SCENES

WIDTH, HEIGHT = 1280, 800
MIN_GAP_PX = 4.0  # [px] between two label boxes (the boxes already include viser's 0.2 em padding)
SECONDS = 10.0  # of simulated time from the preset's start
SAMPLE_EVERY = 0.25  # [s] of simulated time between checks
DT = 1.0 / 20.0  # [s] per tick (the motion does not depend on the frame rate: tests/test_frame_rate.py)
KEY_SHOWN_SHARE = 0.6  # of the samples at which a KEY label is wanted, at least this share shows it
# (measured 2026-11: 0.69 for Moving frame 'Top frame', the most crowded; ~0.9 for most presets)


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
    # The per-label version on Python floats agrees with the vectorised one.
    for point in ([0.3, 0.6, 0.2], [1.0, -2.0, 0.5], [-3.0, 2.0, 4.0]):
        (px, py), d = project_one(view, point, 1280, 800)
        (qx, qy), e = (v[0] for v in project(view, point, 1280, 800))
        assert (px, py, d) == pytest.approx((qx, qy, e), rel=1e-12)


def test_label_boxes_follow_the_anchor() -> None:
    a = LabelBox("a", "ab", (100.0, 100.0), (100.0, 100.0, 130.0, 120.0))
    b = LabelBox("b", "cd", (135.0, 100.0), (135.0, 100.0, 165.0, 120.0))
    c = LabelBox("c", "ef", (120.0, 110.0), (120.0, 110.0, 150.0, 130.0))
    assert a.gap(b) == pytest.approx(5.0) and a.gap(c) < 0.0
    assert [(p.name, q.name) for p, q, _ in overlapping([a, b, c], MIN_GAP_PX)] == [("a", "c"), ("b", "c")]


# ---------------------------------------------------------------------- the layer's rules
TOP_VIEW = CameraView(position=(0.0, 0.0, 10.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_deg=40.0)


@pytest.fixture(scope="module")
def scene() -> Iterator[Any]:
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield server.scene
    finally:
        server.stop()


def _label(scene: Any, name: str, text: str, position: tuple[float, float, float], **kwargs: Any) -> Any:
    return scene.add_label(name, text, position=position, font_screen_scale=2.0, anchor="center-center", **kwargs)


def test_the_higher_priority_label_shows_where_two_meet(scene) -> None:
    layer = LabelLayer(None, TOP_VIEW)  # no browser camera: the fallback view at 1280x800
    low = layer.add(_label(scene, "/prio/low", "low", (0.0, 0.0, 0.0)), DETAIL, nudge=False)
    high = layer.add(_label(scene, "/prio/high", "high", (0.0, 0.0, 0.0)), KEY, nudge=False)
    layer.settle()
    assert high.visible and not low.visible
    low.position = (2.0, 0.0, 0.0)  # room for both
    layer.settle()
    assert high.visible and low.visible


def test_a_label_moves_to_another_anchor_before_it_is_hidden(scene) -> None:
    layer = LabelLayer(None, TOP_VIEW)
    first = layer.add(_label(scene, "/nudge/a", "abc", (0.0, 0.0, 0.0)), KEY)
    second = layer.add(_label(scene, "/nudge/b", "abc", (0.35, 0.0, 0.0)), KEY)  # 38 px apart; the boxes are 53 wide
    layer.settle()
    assert first.visible and second.visible
    assert first.anchor == "center-center" and second.anchor != "center-center"
    boxes = label_boxes(scene, TOP_VIEW, 1280, 800)
    assert not overlapping([b for b in boxes if b.name.startswith("/nudge/")], MIN_GAP_PX)
    second.position = (3.0, 0.0, 0.0)  # room at its own anchor: back to it
    layer.settle()
    assert second.visible and second.anchor == "center-center"


def test_wanted_visibility_hides_at_once_and_shows_at_the_next_layout(scene) -> None:
    layer = LabelLayer(None, TOP_VIEW)
    label = layer.add(_label(scene, "/want/omega", "ω", (0.0, 0.0, 0.0)), KEY)
    layer.settle()
    assert label.visible
    layer.want(label, False)
    assert not label.visible  # at once
    layer.settle()
    assert not label.visible  # the layer does not show what nobody wants
    layer.want(label, True)
    assert not label.visible  # not before the layout has checked there is room
    layer.settle()
    assert label.visible
    with pytest.raises(KeyError, match="not registered"):
        layer.want(_label(scene, "/want/stray", "?", (1.0, 1.0, 0.0)), True)


def test_a_label_under_a_hidden_node_is_hidden_and_comes_back_with_it(scene) -> None:
    layer = LabelLayer(None, TOP_VIEW)
    frame = scene.add_frame("/parent", show_axes=False, position=(1.0, 0.0, 0.0))
    label = layer.add(_label(scene, "/parent/label", "x′", (0.0, 1.0, 0.0)), KEY)
    other = layer.add(_label(scene, "/parent_other", "x′", (1.0, 1.0, 0.0)), DETAIL)  # where the child is
    layer.settle()
    assert label.visible and not other.visible  # the child's world position is (1, 1, 0): the parent moved it
    frame.visible = False
    layer.settle()
    assert not label.visible and other.visible  # a hidden child takes no room
    frame.visible = True
    layer.settle()
    assert label.visible and not other.visible


def test_the_layer_looks_through_the_browser_camera(scene) -> None:
    """Two labels one above the other meet seen from above (the fallback view) but not from the side."""
    side = SimpleNamespace(position=(10.0, 0.0, 0.0), look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0),
                           fov=math.radians(40.0), image_width=800, image_height=600)
    for camera, both in ((None, False), (side, True)):
        layer = LabelLayer(camera, TOP_VIEW)
        top = layer.add(_label(scene, "/cam/top", "top", (0.0, 0.0, 1.0)), KEY, nudge=False)
        bottom = layer.add(_label(scene, "/cam/bottom", "bottom", (0.0, 0.0, -1.0)), DETAIL, nudge=False)
        layer.settle()
        assert top.visible and bottom.visible == both


def test_the_layer_sends_only_changes(scene, monkeypatch) -> None:
    layer = LabelLayer(None, TOP_VIEW)
    a = layer.add(_label(scene, "/quiet/a", "a", (0.0, 0.0, 0.0)), KEY, nudge=False)
    b = layer.add(_label(scene, "/quiet/b", "b", (0.0, 0.0, 0.0)), DETAIL, nudge=False)
    layer.settle()
    queued: list[Any] = []
    original = scene._queue_scene_message
    monkeypatch.setattr(scene, "_queue_scene_message", lambda m: (queued.append(m), original(m))[1])
    for _ in range(3):
        layer.update(1.0)
    assert queued == [] and layer.layouts == 1  # nothing moved: no layout, no message
    b.position = (3.0, 0.0, 0.0)  # one message (the position); the layout shows b: one more
    layer.settle()
    layer.update(1.0)
    assert [type(m).__name__ for m in queued] == ["SetPositionMessage", "SetSceneNodeVisibilityMessage"]
    assert a.visible and b.visible


def test_own_rooms_share_a_budget_of_layouts_and_a_presenters_layer_keeps_its_period(monkeypatch) -> None:
    """60 own rooms drawing at 60 fps would lay out 600 times a second at PERIOD; together they
    stay within labels.BUDGET a second (+ each one's first, immediate layout).  One own room alone,
    and a presenter's shared scene (its `screens` set) beside the 60, keep every PERIOD."""
    from app.kit.draw import labels

    monkeypatch.setattr(labels, "_SHARE", labels._Share())  # no other test's layers in the count
    counts: dict[int, int] = {}

    def layer(screens: Any = None) -> LabelLayer:
        made = LabelLayer(None, TOP_VIEW, screens=screens)
        counts[id(made)] = 0

        def counted(made: LabelLayer = made) -> None:
            counts[id(made)] += 1
        made._lay_out = counted  # type: ignore[method-assign]
        return made

    def run(layers: list[LabelLayer], seconds: float, dt: float = 1.0 / 60.0) -> None:
        for _ in range(round(seconds / dt)):  # fast in wall time: all of them drew "within a second"
            for each in layers:
                each.update(dt)

    alone = layer()
    run([alone], 2.0)
    assert counts[id(alone)] == pytest.approx(2.0 / labels.PERIOD, abs=1)  # 10 Hz (the second a phase late)
    rooms = [layer() for _ in range(60)]
    presenter = layer(screens=lambda: [])
    run([*rooms, presenter], 1.0)  # the share counts the 60 layers
    for each in counts:
        counts[each] = 0
    run([*rooms, presenter], 4.0)
    total = sum(counts[id(r)] for r in rooms)
    assert 0.8 * labels.BUDGET * 4.0 <= total <= labels.BUDGET * 4.0 + len(rooms), total
    assert counts[id(presenter)] == pytest.approx(4.0 / labels.PERIOD, abs=1)


def test_every_label_of_every_scene_is_registered(manual) -> None:
    session = manual.session
    for title in SCENES:
        session.select_scene(title)
        view = session.scene
        handles = session.client.scene._handle_from_node_name
        labels = [name for name, h in handles.items()
                  if type(h).__name__ == "LabelHandle" and name.startswith(view.root + "/") and not h._impl.removed]
        assert labels, title
        assert [name for name in labels if handles[name] not in view.labels] == [], title


# ---------------------------------------------------------------------- every preset
PANEL = panel_box(WIDTH, HEIGHT)  # the floating panel's rectangle on a 1280x800 window


def _report_window(manual: Any, width: int, height: int) -> None:
    """The raw client reports a width x height canvas (what a browser of that size sends)."""
    from viser import _messages

    manual.client.send(_messages.ViewerCameraMessage(
        wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, 3.0, 3.0), fov=math.radians(50.0), near=0.01, far=100.0,
        image_height=height, image_width=width, look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))
    manual.wait(lambda: manual.session.client.camera.image_width == width)


def _cases() -> list[Any]:
    """(title, preset) of every preset of every scene."""
    return [pytest.param(title, preset.name) for title, scene in SCENES.items() for preset in scene.presets()]


def _describe(pairs: list[tuple[LabelBox, LabelBox, float]]) -> str:
    return "; ".join(f"{a.text!r} at ({a.anchor_px[0]:.0f}, {a.anchor_px[1]:.0f}) and {b.text!r} at "
                     f"({b.anchor_px[0]:.0f}, {b.anchor_px[1]:.0f}): gap {gap:.0f} px" for a, b, gap in pairs)


@pytest.mark.parametrize(("title", "preset"), _cases())
def test_labels_do_not_overlap_in_the_first_10_s(manual, title: str, preset: str) -> None:
    session = manual.session
    _report_window(manual, WIDTH, HEIGHT)  # the layout's window is the one checked here
    session.select_scene(title)
    session.reset_camera()  # the browser's camera at the scene's view (the raw client starts elsewhere)
    session.apply_preset(preset)
    view = session.scene
    session.play()
    problems: list[str] = []
    wanted: dict[str, int] = {}  # KEY label -> samples at which it was wanted / shown
    shown: dict[str, int] = {}
    t_next = 0.0
    for _ in range(round(SECONDS / DT) + 1):
        t = session.simulation.t
        if t >= t_next - 1e-9:
            t_next += SAMPLE_EVERY
            with session.lock:
                boxes = label_boxes(session.client.scene, view.view, WIDTH, HEIGHT)
                pairs = overlapping(boxes, MIN_GAP_PX)
                under = [b.text for b in boxes if boxes_meet(b.box, PANEL)]
                for entry in view.labels._entries.values():
                    text = str(entry.handle.text)
                    if entry.priority >= KEY and entry.wanted:
                        wanted[text] = wanted.get(text, 0) + 1
                        shown[text] = shown.get(text, 0) + bool(entry.handle.visible)
            if pairs:
                problems.append(f"t = {t:.2f} s: {_describe(pairs)}")
            if under:
                problems.append(f"t = {t:.2f} s: {under} under the panel")
        session.tick(DT)
    assert session.error_count == 0, session.last_error
    assert not problems, f"{title} {preset!r}: labels overlap at 1280x800:\n" + "\n".join(problems[:8])
    assert all(shown[axis] == wanted[axis] for axis in "xyz"), f"space axis labels hidden: {shown} of {wanted}"
    share = sum(shown.values()) / sum(wanted.values())
    assert share >= KEY_SHOWN_SHARE, f"{title} {preset!r}: KEY labels shown at {share:.0%}: {shown} of {wanted}"


def test_a_label_world_position_composes_its_parents_poses(scene) -> None:
    """Against scipy: a label three frames deep (a path segment with no node between) is at
    T1 T2 T3 p; hiding a parent hides it; a shared cache gives the same answer."""
    from scipy.spatial.transform import Rotation

    from app.viser_internals import world_point

    rng = np.random.default_rng(3)
    poses = [(Rotation.random(random_state=rng), rng.normal(size=3)) for _ in range(3)]
    names = ["/compose", "/compose/a/b", "/compose/a/b/c"]  # "/compose/a" is no node
    frames = [scene.add_frame(name, show_axes=False, wxyz=R.as_quat(scalar_first=True), position=t)
              for name, (R, t) in zip(names, poses)]
    p = rng.normal(size=3)
    label = _label(scene, "/compose/a/b/c/label", "q", tuple(p))
    expected = p
    for R, t in reversed(poses):
        expected = R.apply(expected) + t
    cache: dict[str, Any] = {}
    for _ in range(2):
        point, shown = world_point(label, cache)
        np.testing.assert_allclose(point, expected, atol=1e-12)
        assert shown
    frames[1].visible = False
    assert world_point(label) is not None and not world_point(label)[1]
    frames[0].remove()
