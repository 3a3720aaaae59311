"""The app's data files (presets, lessons, meshes), read through `importlib.resources`.

The repository keeps them in `assets/` (`presets/*.json`, `lessons/*.json`, `meshes/*.stl`);
pyproject.toml maps that folder into the wheel as the package `app.assets`
(`[tool.setuptools] package-dir`), so an installed app (a wheel, `pip install .`, `pipx
install .`) reads them from `site-packages/app/assets/`, wherever it is started from.

Which copy is read, in order:

1. a source tree: when the imported `app` package sits in a checkout (its folder has
   `pyproject.toml` and `assets/__init__.py` beside `app/`), that checkout's `assets/`.  This
   covers `pip install -e .`, `python -m app` from the checkout and the tests' `pythonpath`, and
   keeps a second checkout (a worktree) from reading the files of the one installed in editable
   mode;
2. otherwise the installed resource package `app.assets`.

Every place returned is a `Traversable` (`read_text`, `read_bytes`, `iterdir`, `name`, `/`);
on a normal install or checkout it is a `pathlib.Path`, so `str()` of it (used in the
PresetError / LessonError messages) is a real, readable path.  Nothing here is cached but the
root, and nothing writes.
"""

from __future__ import annotations

import functools
from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path

__all__ = ["assets_root", "files_in", "lessons_dir", "meshes_dir", "presets_dir"]

ASSETS_PACKAGE = "app.assets"  # the package pyproject.toml maps assets/ to


@functools.cache
def assets_root() -> Traversable:
    """The folder that holds presets/, lessons/ and meshes/ (see the module docstring)."""
    app_dir = resources.files("app")
    if isinstance(app_dir, Path):  # a folder on disk, not a zip: perhaps a checkout
        tree = app_dir.parent
        if (tree / "pyproject.toml").is_file() and (tree / "assets" / "__init__.py").is_file():
            return tree / "assets"
    return resources.files(ASSETS_PACKAGE)


def presets_dir() -> Traversable:
    """presets/: one JSON file per scene (format in `app.kit.core.presets`)."""
    return assets_root() / "presets"


def lessons_dir() -> Traversable:
    """lessons/: one JSON file per lesson (format in `app.lessons`)."""
    return assets_root() / "lessons"


def meshes_dir() -> Traversable:
    """meshes/: the solid meshes the Inertia scene offers with one click (`scripts/make_meshes.py`)."""
    return assets_root() / "meshes"


def files_in(directory: Traversable, suffix: str) -> list[Traversable]:
    """The files of `directory` whose name ends in `suffix` (e.g. ".json"), sorted by name;
    [] if the directory is missing."""
    if not directory.is_dir():
        return []
    return sorted((entry for entry in directory.iterdir() if entry.is_file() and entry.name.endswith(suffix)),
                  key=lambda entry: entry.name)
