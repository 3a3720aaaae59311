"""The registry of scenes: the Scene dropdown lists them in this order (the first is the default).

A new scene is one new file (a big one: a package) in this folder and one line here (see `app.kit`
for the recipe).
"""

from __future__ import annotations

from app.kit.core.room import Scene
from app.scenes.constrained import ConstrainedView
from app.scenes.euler_angles import EulerAnglesView
from app.scenes.free_body import FreeBodyView
from app.scenes.heavy_top import HeavyTopView
from app.scenes.inertia import InertiaView
from app.scenes.moving_frame import MovingFrameView
from app.scenes.poinsot import PoinsotView

__all__ = ["DEFAULT_SCENE", "SCENES", "check_presets"]

SCENES: dict[str, Scene] = {
    scene.title: scene
    for scene in (
        EulerAnglesView,
        InertiaView,
        FreeBodyView,
        HeavyTopView,
        PoinsotView,
        MovingFrameView,
        ConstrainedView,
    )
}
"""Scene title (the dropdown option) -> scene (a view class with `new_simulation`, `presets`)."""
DEFAULT_SCENE = next(iter(SCENES))


def check_presets() -> None:
    """Read and check every scene's preset file now (PresetError naming file and field)."""
    for scene in SCENES.values():
        scene.presets()
