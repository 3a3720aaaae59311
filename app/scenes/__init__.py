"""The registry of scenes: the Scene dropdown lists them in this order (the first is the default).

A new scene is one new file (a big one: a package, `moving_frame/` is the template) in this folder
and one line here (see `app.kit` for the recipe).  What the room codec may decode of each scene is
derived from it here (`simulation_parts`); the tests' per-scene tables are checked against `SCENES`.
"""

from __future__ import annotations

import inspect
import sys
import types
from collections.abc import Callable
from typing import Any

from app.kit.core.room import Scene
from app.scenes.constrained import ConstrainedView
from app.scenes.euler_angles import EulerAnglesView
from app.scenes.free_body import FreeBodyView
from app.scenes.heavy_top import HeavyTopView
from app.scenes.inertia import InertiaView
from app.scenes.moving_frame import MovingFrameView
from app.scenes.poinsot import PoinsotView

__all__ = ["DEFAULT_SCENE", "SCENES", "check_presets", "simulation_class", "simulation_parts"]

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


_SIMULATION_CLASSES: dict[str, type] = {}


def simulation_class(scene: Scene) -> type:
    """The class of the simulation the scene makes (its first preset's, built once per scene)."""
    found = _SIMULATION_CLASSES.get(scene.title)
    if found is None:
        found = _SIMULATION_CLASSES[scene.title] = type(scene.new_simulation())
    return found


def simulation_parts(scene: Scene) -> tuple[type | Callable[..., Any], ...]:
    """What the scene's simulation may be made of (the room codec decodes nothing else of it):
    derived, every class defined in the module of its simulation class and of each of its bases
    (`simulation_class`); declared, the scene's own `simulation_parts` (functions a trace follows,
    classes of other modules).  The kit's core and `physics` are the codec's own (`app.codec`)."""
    classes: dict[type | Callable[..., Any], None] = {}
    for base in simulation_class(scene).__mro__:
        module = sys.modules.get(base.__module__)
        if module is None or base is object:
            continue
        for value in vars(module).values():
            if inspect.isclass(value) and value.__module__ == module.__name__:
                classes[value] = None
    for part in scene.simulation_parts:
        if not isinstance(part, type | types.FunctionType):
            raise TypeError(f"{scene.title}: simulation_parts holds {part!r}, not a class or a function")
        classes[part] = None
    return tuple(classes)
