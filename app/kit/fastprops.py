"""Per-frame writes of a scene node's pose, points and scale without viser's per-assignment checks.

viser's public setters (`handle.wxyz = ...`, `.position`, `.points`, `.scale`) cast the value
and compare it with the stored one (`np.allclose` for poses), then queue one message.  The
widgets already send only what changed, so per frame they use these functions instead: they
store the value where the handle keeps it and queue the very message the setter would.
Everything else (building nodes, colours, visibility, text) goes through the public API.

They live in `app.viser_internals` (the app's one seam to viser's private names); when its
FAST_SETTERS is off (`FAST` False) they are the public setters.
`tests/test_scene_kit.py` checks that a client receives the same as with the public setters.
"""

from __future__ import annotations

from app.viser_internals import FAST_SETTERS, set_points, set_position, set_scale, set_wxyz

__all__ = ["FAST", "set_points", "set_position", "set_scale", "set_wxyz"]

FAST = FAST_SETTERS.on  # at import: viser's internals the fast setters need are there
