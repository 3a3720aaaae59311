"""Where a view draws: one browser, the lecture hall's shared scene, or a headless recorder.

A view (`app.kit.view.SceneView`) draws to a `DrawTarget`:

- `scene`: where its 3D goes (a browser's own `client.scene`, or `server.scene`, which every
  browser receives), under `root_prefix`;
- `gui`: where its panel goes (always one browser's, or a recorder's that nobody sees);
- `controls`: where its *interactive* handles go (transform gizmos, nodes with click
  handlers): the scene of the one browser that controls the room, or None (nobody may act on
  it: a recording).  viser routes a gizmo drag or a node click to the scope the handle lives
  in; a handle in `server.scene` answers every browser, whoever sent it (docs/VISER.md §8).
  So interactive handles never go to a shared scene: `controls` is always a single browser's.
- `camera`: the controlling browser's camera (None for a recorder).

`ClientTarget` is one browser (all four are its own).  The lecture hall's presenter target
(`app.lecture.lectern.Broadcast`) draws the 3D into the shared scene and keeps the panel and the
controls in the presenter's browser.  The exporter's recorder has no controls.
"""

from __future__ import annotations

import contextlib
from typing import Any, Protocol, runtime_checkable

import viser

from app.viser_internals import atomic_unless_captured

__all__ = ["ClientTarget", "DrawTarget", "as_target"]


@runtime_checkable
class DrawTarget(Protocol):
    """What a view draws to (see the module docstring)."""

    scene: Any  # viser SceneApi: the 3D, possibly shared
    gui: Any  # viser GuiApi: the panel of one browser (or of nobody)
    controls: Any  # viser SceneApi of the controlling browser, or None: interactive handles only
    camera: Any  # the controlling browser's CameraHandle, or None
    root_prefix: str  # prepended to the view's root node name

    def atomic(self) -> contextlib.AbstractContextManager[None]:
        """Hold the messages of a change together."""
        ...

    def add_notification(self, title: str, body: str, **kwargs: Any) -> Any:
        """A toast in the controlling browser (nothing for a recorder)."""
        ...


class ClientTarget:
    """One browser: its own scene, panel, controls and camera."""

    root_prefix = ""

    def __init__(self, client: viser.ClientHandle) -> None:
        self.client = client
        self.scene = client.scene
        self.gui = client.gui
        self.controls = client.scene
        self.camera = client.camera
        self.client_id = client.client_id

    def atomic(self) -> contextlib.AbstractContextManager[None]:
        """The browser's `atomic()`, except inside the app loop's frame when the browser's wire
        holds the frame together (`app.viser_internals.atomic_unless_captured`)."""
        return atomic_unless_captured(self.client)

    def add_notification(self, title: str, body: str, **kwargs: Any) -> Any:
        return self.client.add_notification(title, body, **kwargs)


def as_target(client: Any) -> DrawTarget:
    """`client` as a DrawTarget: a `viser.ClientHandle` becomes a `ClientTarget`; a target is
    returned as it is."""
    if isinstance(client, viser.ClientHandle):
        return ClientTarget(client)
    if not isinstance(client, DrawTarget):
        raise TypeError(f"a view draws to a viser.ClientHandle or a DrawTarget, not {type(client).__name__}")
    return client
