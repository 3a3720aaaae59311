"""The app's one seam to viser's internals (`app.viser_internals`).

- With the installed viser every private name the app uses is there (`check()` is empty; a
  failure names each missing attribute), and the version is the one the seam is written for.
- `check()` names what a viser without one of them lacks, `configure()` turns that feature off
  and `report()` says so once in the log.
- No module of `app/` but the seam names a private viser attribute or module.
- With a feature off the app still serves frames, and a browser ends with the server's scene.
"""

from __future__ import annotations

import dataclasses
import logging
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import viser
from conftest import poll_until

from app import viser_internals as seam

ROOT = Path(__file__).resolve().parents[1]
SEAM = ROOT / "app" / "viser_internals.py"

# What counts as naming viser's internals outside the seam: its private modules, and the private
# attributes the seam holds (an attribute access or a string, as in getattr(x, "_impl")).
PRIVATE_MODULES = re.compile(r"\bviser\s*\.\s*(infra\b|_\w+)|from\s+viser\s+import\s+(\(\s*)?_\w+"
                             r"|from\s+viser\.(infra|_\w+)")
PRIVATE_ATTRIBUTES = sorted({need.attribute for need in seam.NEEDS if need.attribute.startswith("_")}
                            | {"_impl", "_state", "_viser_server", "_children_from_node_name", "_node_lifecycle_lock"})
PRIVATE_PREFIXES = ("_queue_", "_websock", "_gui_input_handle", "_handle_from", "_container_handle")
# `.name` or "name" (not the app's own `self.name` / `cls.name`): a whole name, or one of the prefixes
PRIVATE_ACCESS = re.compile(r"""(?<!self)(?<!cls)(\.|["'])(""" + "|".join(
    [re.escape(a) + r"\b" for a in PRIVATE_ATTRIBUTES] + [re.escape(p) + r"\w*" for p in PRIVATE_PREFIXES]) + ")")


@pytest.fixture
def restore(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Put every feature back as the installed viser allows after the test (after putting back
    what the test took away)."""
    yield
    monkeypatch.undo()
    seam.configure()


def test_the_installed_viser_has_every_internal_the_app_uses() -> None:
    missing = seam.check()
    assert not missing, "the installed viser lacks:\n" + "\n".join(missing)
    assert seam.VERSION.startswith(seam.SUPPORTED), f"viser {seam.VERSION}: the seam is for {seam.SUPPORTED}x"
    off = [f"{feature.name}: {feature.why}" for feature in seam.FEATURES if not feature.on]
    assert not off, off


def test_every_need_names_a_feature_and_says_what_it_is_for() -> None:
    assert all(need.feature in seam.FEATURES and need.purpose for need in seam.NEEDS)
    assert {need.feature.name for need in seam.NEEDS} == {feature.name for feature in seam.FEATURES}


def test_a_missing_module_attribute_is_named_and_turns_its_feature_off(monkeypatch, caplog, restore) -> None:
    import viser.infra._infra

    monkeypatch.delattr(viser.infra._infra, "_append_aligned_buffers")
    missing = seam.check()
    assert any(line.startswith("viser.infra._infra._append_aligned_buffers ") for line in missing), missing
    seam.configure()
    assert not seam.FRAME_CAPTURE.on and "_append_aligned_buffers" in seam.FRAME_CAPTURE.why
    assert all(feature.on for feature in seam.FEATURES if feature is not seam.FRAME_CAPTURE)
    with caplog.at_level(logging.WARNING, logger=seam.__name__):
        seam.report()
        seam.report()  # once
    lines = [r.getMessage() for r in caplog.records if r.name == seam.__name__]
    assert len(lines) == 1 and "frame capture off" in lines[0] and "_append_aligned_buffers" in lines[0], lines


def test_a_missing_class_attribute_or_field_is_named(monkeypatch, restore) -> None:
    """Methods, dataclass fields, annotations and attributes a constructor sets are found; one
    taken away is named."""
    from viser import _scene_api

    assert seam.check() == []
    monkeypatch.delattr(_scene_api.SceneApi, "_queue_scene_message")
    assert seam.check() == [f"viser._scene_api.SceneApi._queue_scene_message ({seam.FAST_SETTERS.name}: "
                            "queue a node's message in its scope)"]
    seam.configure()
    assert not seam.FAST_SETTERS.on and seam.SCENE_NODES.on

    class Made:
        def __init__(self) -> None:
            self._registry: dict[str, int] = {}

    monkeypatch.setattr(_scene_api, "Made", Made, raising=False)
    needs = [seam.Need(seam.SCENE_NODES, "viser._scene_api.Made", name, "a test") for name in ("_registry", "_gone")]
    assert seam.check(needs) == ["viser._scene_api.Made._gone (scene nodes: a test)"]
    assert seam.check([seam.Need(seam.SCENE_NODES, "viser._no_such_module", "x", "a test")]) == [
        "viser._no_such_module.x (scene nodes: a test)"]


def test_another_viser_release_turns_the_wire_off(restore) -> None:
    seam.configure(version="1.2.0")
    assert not seam.FRAME_CAPTURE.on and "1.2.0" in seam.FRAME_CAPTURE.why
    assert seam.FAST_SETTERS.on


def _app_sources() -> list[Path]:
    return sorted(path for path in (ROOT / "app").rglob("*.py") if path != SEAM)


def test_no_module_of_the_app_but_the_seam_names_a_private_viser_name() -> None:
    found = []
    for path in _app_sources():
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if PRIVATE_MODULES.search(line) or PRIVATE_ACCESS.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "private viser names outside app/viser_internals.py:\n" + "\n".join(found)


def test_the_scan_sees_what_it_looks_for() -> None:
    for line in ("x = handle._impl.wxyz", "api._queue_scene_message(m)", "client._websock_connection",
                 "gui._gui_input_handle_from_uuid", "from viser.infra._infra import f", "from viser import _messages",
                 "import viser._messages", 'getattr(scene, "_handle_from_node_name", {})', "viser.infra.x"):
        assert PRIVATE_MODULES.search(line) or PRIVATE_ACCESS.search(line), line
    for line in ("self._wrap(x)", "self._root_node.remove()", "import viser", "viser.GuiCheckboxHandle",
                 "from physics._types import Vec3", "self._messages = []", "self._state_edit(handle)",
                 "self._impl = 1"):
        assert not (PRIVATE_MODULES.search(line) or PRIVATE_ACCESS.search(line)), line


# ---------------------------------------------------------------------- the app with a feature off
def _plays_as_the_server(wired: bool) -> None:
    """Euler angles (labels, arcs, frames) plays until 21 frames are served and pauses: frames go out (by a wire or by
    viser's path, as `wired` says) and the browser's nodes are the server's."""
    from app.main import create_server
    from tests.test_wire import SceneMirror, _differences, _settled

    app = create_server("127.0.0.1", 0, verbose=False)
    mirror = SceneMirror(app.port)
    try:
        session = next(iter(app.wait_for_sessions(1).values()))
        session.select_scene("Euler angles")
        with mirror.lock:
            before = mirror.frames
        session.play()
        served = lambda: mirror.frames - before  # noqa: E731
        poll_until(lambda: served() > 20, 60.0, 0.05, what="21 frames served while playing", seen=served)
        session.pause()
        _settled(mirror)
        assert (app._wires.get(session.client.client_id) is not None) == wired
        with session.lock:
            differences = _differences(mirror, session.client.scene, "/")
        assert differences == []
    finally:
        mirror.close()
        app.stop()


@pytest.mark.parametrize("feature", [f.name for f in seam.FEATURES])
def test_with_a_feature_off_a_browser_ends_with_the_servers_scene(feature: str, restore) -> None:
    (off,) = (f for f in seam.FEATURES if f.name == feature)
    off.on, off.why = False, "switched off by the test"
    _plays_as_the_server(wired=off is not seam.FRAME_CAPTURE)


def test_when_viser_renames_the_buffer_helper_the_app_serves_frames_through_viser(restore) -> None:
    """A viser whose `_append_aligned_buffers` (the wire's envelope) has another name (the name
    the seam looks for is renamed here: viser itself still needs its own): no wire, viser's
    own frames."""
    needs = [dataclasses.replace(need, attribute="_append_aligned_buffers_renamed")
             if need.attribute == "_append_aligned_buffers" else need for need in seam.NEEDS]
    assert seam.configure(needs) == ["viser.infra._infra._append_aligned_buffers_renamed"]
    assert not seam.FRAME_CAPTURE.on and all(f.on for f in seam.FEATURES if f is not seam.FRAME_CAPTURE)
    _plays_as_the_server(wired=False)


def test_without_visers_panel_registry_a_view_finds_the_same_checkboxes(manual, restore) -> None:
    from app.scenes import SCENES

    session = manual.session
    for title in SCENES:
        with session.lock:
            session.select_scene(title)
            seam.PANEL_INPUTS.on = True
            by_registry = session.scene.checkboxes()
            seam.PANEL_INPUTS.on = False
            by_attributes = session.scene.checkboxes()
        assert by_attributes == by_registry, title


def test_panel_inputs_holds_the_checkboxes_and_is_none_without_the_registry(manual, restore) -> None:
    view = manual.session.scene
    with manual.session.lock:
        inputs = seam.panel_inputs(view.client.gui, view._gui_roots)
        assert inputs is not None and set(map(id, seam.panel_checkboxes(view.client.gui, view._gui_roots) or [])) \
            <= set(map(id, inputs))
        assert any(isinstance(h, viser.GuiButtonHandle) for h in inputs)
        seam.PANEL_INPUTS.on = False
        assert seam.panel_inputs(view.client.gui, view._gui_roots) is None and view.panel_controls() == []


def test_without_visers_scene_registry_controls_are_removed_and_labels_shown(manual, restore) -> None:
    scene = manual.session.client.scene
    nodes = [scene.add_frame(name, show_axes=False) for name in ("/probe", "/probe/a", "/probe/a/b", "/kept")]
    seam.SCENE_NODES.on = False
    assert seam.scene_nodes(scene) == {}
    with pytest.raises(RuntimeError, match="scene registry"):
        seam.world_pose(nodes[2])
    with pytest.raises(RuntimeError, match="scene registry"):
        seam.node_pose(nodes[2], {})
    seam.remove_under(scene, "/probe")
    seam.SCENE_NODES.on = True
    left = set(seam.scene_nodes(scene))
    assert "/probe/a" not in left and "/probe/a/b" not in left and "/kept" in left

    from app.kit.core.common import CameraView
    from app.kit.draw.labels import KEY, LabelLayer

    layer = LabelLayer(None, CameraView((0.0, -5.0, 0.0), (0.0, 0.0, 0.0)))
    labels = [layer.add(scene.add_label(f"/kept/l{i}", "same place", visible=False), KEY, wanted=True)
              for i in range(3)]
    layer.settle()
    assert sum(bool(label.visible) for label in labels) == 1  # the layout hides the overlapping ones
    seam.SCENE_NODES.on = False
    layer.settle()
    assert all(bool(label.visible) for label in labels)  # no layout: every wanted label is shown


def test_the_fast_setters_fall_back_to_the_public_ones(manual, monkeypatch, restore) -> None:
    scene = manual.session.client.scene
    frame = scene.add_frame("/probe_fast", show_axes=False)
    queued: list[Any] = []
    original = scene._queue_scene_message
    monkeypatch.setattr(scene, "_queue_scene_message", lambda m: (queued.append(m), original(m))[1])
    seam.FAST_SETTERS.on = False
    q = (0.0, 1.0, 0.0, 0.0)
    seam.set_wxyz(frame, q)
    seam.set_position(frame, (1.0, 2.0, 3.0))
    assert tuple(frame.wxyz) == q and tuple(frame.position) == (1.0, 2.0, 3.0)
    assert [type(m).__name__ for m in queued] == ["SetOrientationMessage", "SetPositionMessage"]
    queued.clear()
    seam.set_wxyz(frame, q)  # the public setter skips an unchanged value
    assert queued == []


def test_message_from_dict_rebuilds_only_allowed_messages_with_their_props() -> None:
    from viser import _messages

    made = _messages.LabelMessage("/l/x", _messages.LabelProps("hi", "screen", 1.0, 0.1, False, "top-left"))
    again = seam.message_from_dict(made.as_serializable_dict(), {"LabelMessage"})
    assert again == made and isinstance(again.props, _messages.LabelProps)
    for mapping, allowed in (({"type": "LabelMessage", "name": "/l/x"}, set()),  # not allowed
                             ({"type": "NoSuchMessage"}, {"NoSuchMessage"}),
                             ({**made.as_serializable_dict(), "extra": 1}, {"LabelMessage"})):
        with pytest.raises(ValueError):
            seam.message_from_dict(mapping, allowed)
