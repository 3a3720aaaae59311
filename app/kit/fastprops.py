"""Per-frame writes of a scene node's pose and points without viser's per-assignment checks.

viser's public setters (`handle.wxyz = ...`, `.position`, `.points`) cast the value and
compare it with the stored one (`np.allclose` for poses, ~70 µs a call here, most of it numpy's
error-state context), then queue one message.  The widgets already send only what changed, so
per frame they use these functions instead: they store the value where the handle keeps it and
queue the very message the setter would (`SetOrientationMessage`, `SetPositionMessage`,
`SceneNodeUpdateMessage`), for ~5 µs.  Everything else (building nodes, colours, visibility,
text) goes through the public API.

They rely on viser 1.1's handle internals (`handle._impl.wxyz`, `._impl.position`,
`._impl.props`, `._impl.api._queue_scene_message`); `pyproject.toml` pins viser to 1.1.x,
`tests/test_scene_kit.py` checks that a client receives the same as with the public setters,
and if the internals are not there (`FAST` is False) these fall back to the setters.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from viser import _messages

__all__ = ["FAST", "set_points", "set_position", "set_scale", "set_wxyz"]


def _has_internals() -> bool:
    return all(hasattr(_messages, name) for name in
               ("SetOrientationMessage", "SetPositionMessage", "SceneNodeUpdateMessage"))


FAST = _has_internals()


def _queue(handle: Any, message: Any) -> None:
    impl = handle._impl
    if impl.removed:
        raise RuntimeError(f"Cannot update the removed scene node {impl.name!r}.")
    impl.api._queue_scene_message(message)


def set_wxyz(handle: Any, wxyz: tuple[float, float, float, float]) -> None:
    """handle.wxyz = wxyz (a unit quaternion, w x y z, Python floats), unconditionally."""
    if not FAST:
        handle.wxyz = wxyz
        return
    _queue(handle, _messages.SetOrientationMessage(handle._impl.name, wxyz))
    handle._impl.wxyz[:] = wxyz


def set_position(handle: Any, xyz: tuple[float, float, float]) -> None:
    """handle.position = xyz (Python floats), unconditionally."""
    if not FAST:
        handle.position = xyz
        return
    _queue(handle, _messages.SetPositionMessage(handle._impl.name, xyz))
    handle._impl.position[:] = xyz


def set_points(handle: Any, points: np.ndarray) -> None:
    """handle.points = points, a float32 array of the node's points shape, unconditionally."""
    if not FAST:
        handle.points = points
        return
    _queue(handle, _messages.SceneNodeUpdateMessage(handle._impl.name, {"points": points.copy()}))
    current = handle._impl.props.points
    if current.shape == points.shape:
        current[:] = points
    else:
        handle._impl.props.points = points.copy()


def set_scale(handle: Any, scale: tuple[float, float, float]) -> None:
    """handle.scale = scale (per-axis, Python floats), unconditionally."""
    if not FAST:
        handle.scale = scale
        return
    _queue(handle, _messages.SceneNodeUpdateMessage(handle._impl.name, {"scale": scale}))
    handle._impl.props.scale = scale
