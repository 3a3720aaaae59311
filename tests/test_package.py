"""The wheel carries the app's data, and the app reads it through importlib.resources.

The wheel is built once (from a copy of the sources, as `scripts/smoke_wheel.py` does, with this
venv's pip; setuptools comes from the package index) and unzipped: that folder is what
`pip install` puts in site-packages, so the app is run from it in a subprocess, away from the
checkout.  The full install-and-serve smoke test is `scripts/smoke_wheel.py` (in `.ci/run`).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from scripts.smoke_wheel import copy_sources

ROOT = Path(__file__).resolve().parents[1]
DATA_FOLDERS = ("presets", "lessons", "meshes")

pytestmark = pytest.mark.slow  # builds a wheel: about 5 s


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    temp = tmp_path_factory.mktemp("wheel")
    src = copy_sources(temp)
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(temp / "dist"), str(src)],
                   check=True, capture_output=True, timeout=600)
    (found,) = (temp / "dist").glob("*.whl")
    return found


@pytest.fixture(scope="module")
def site(wheel: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wheel unzipped: the layout `pip install` gives site-packages."""
    folder = tmp_path_factory.mktemp("site")
    with zipfile.ZipFile(wheel) as archive:
        archive.extractall(folder)
    return folder


def _names(wheel: Path) -> set[str]:
    with zipfile.ZipFile(wheel) as archive:
        return set(archive.namelist())


def test_the_wheel_holds_every_data_file_under_app_assets(wheel: Path) -> None:
    names = _names(wheel)
    shipped = [path for folder in DATA_FOLDERS for path in sorted((ROOT / "assets" / folder).iterdir())
               if path.is_file()]
    assert len(shipped) >= 15  # 6 presets, 5 lessons, 5 meshes when this was written
    missing = [str(path.relative_to(ROOT)) for path in shipped
               if f"app/assets/{path.relative_to(ROOT / 'assets').as_posix()}" not in names]
    assert missing == []
    assert not any(name.startswith("assets/") for name in names)  # never a top-level "assets" package


def test_the_wheel_holds_every_module_and_the_command(wheel: Path) -> None:
    names = _names(wheel)
    modules = sorted(path.relative_to(ROOT).as_posix() for package in ("app", "physics")
                     for path in (ROOT / package).rglob("*.py") if "__pycache__" not in path.parts)
    assert [m for m in modules if m not in names] == []  # a new subpackage must be listed in pyproject.toml
    (entry_points,) = [n for n in names if n.endswith(".dist-info/entry_points.txt")]
    with zipfile.ZipFile(wheel) as archive:
        assert "rigid-body-lab = app.main:main" in archive.read(entry_points).decode()


_INSTALLED_CHECK = """
import sys
sys.path.insert(0, sys.argv[1])
import app, app.data
from app.lessons import lessons
from app.scenes import SCENES
from app.scenes.inertia import MESHES_DIR
from app.data import files_in
print(app.__file__)
print(app.data.assets_root())
print(sum(len(view.presets()) for view in SCENES.values()), len(lessons()), len(files_in(MESHES_DIR, ".stl")))
"""


def test_the_installed_layout_reads_its_own_data_from_any_folder(site: Path, tmp_path: Path) -> None:
    """Run from an empty folder with only the unzipped wheel on the path (-I: no cwd, no PYTHONPATH)."""
    out = subprocess.run([sys.executable, "-I", "-c", _INSTALLED_CHECK, str(site)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    app_file, root, counts = out.stdout.strip().splitlines()
    assert Path(app_file) == site / "app" / "__init__.py"
    assert Path(root) == site / "app" / "assets"
    n_presets, n_lessons, n_meshes = map(int, counts.split())
    assert n_presets >= 6 and n_lessons == len(list((ROOT / "assets" / "lessons").glob("*.json")))
    assert n_meshes == len(list((ROOT / "assets" / "meshes").glob("*.stl")))


def test_a_broken_installed_preset_is_named_by_its_installed_path(site: Path, tmp_path: Path) -> None:
    copy = tmp_path / "site"
    shutil.copytree(site, copy)
    broken = copy / "app" / "assets" / "presets" / "free_body.json"
    broken.write_text("{", encoding="utf-8")
    script = ("import sys; sys.path.insert(0, sys.argv[1])\n"
              "from app.kit.core.presets import PresetError\nfrom app.scenes.free_body import FreeBodyView\n"
              "try:\n    FreeBodyView.presets()\nexcept PresetError as error:\n    print(error)\n")
    out = subprocess.run([sys.executable, "-I", "-c", script, str(copy)], cwd=tmp_path, capture_output=True,
                         text=True, timeout=120)
    assert out.stdout.startswith(f"{broken}: not readable JSON"), out.stdout + out.stderr


def test_the_checkout_reads_its_own_assets_folder() -> None:
    from app.data import assets_root, files_in, presets_dir

    assert Path(str(assets_root())) == ROOT / "assets"
    assert [p.name for p in files_in(presets_dir(), ".json")] == sorted(
        p.name for p in (ROOT / "assets" / "presets").glob("*.json"))


def test_no_module_finds_its_data_through_its_own_file() -> None:
    """Data is read through importlib.resources (app/data.py), never Path(__file__)/../assets,
    which pointed at site-packages/assets in an installed wheel."""
    users = sorted(str(path.relative_to(ROOT)) for package in ("app", "physics")
                   for path in (ROOT / package).rglob("*.py") if "__file__" in path.read_text(encoding="utf-8"))
    assert users == []
    assert "resources.files(" in (ROOT / "app" / "data.py").read_text(encoding="utf-8")


def test_the_wheel_carries_every_catalog_compiled_and_the_installed_app_reads_it(wheel: Path, site: Path,
                                                                                 tmp_path: Path) -> None:
    """setup.py's build compiles each app/locale/<lang>/LC_MESSAGES/messages.po (the copy has no
    .mo: `copy_sources`), and the installed app reads the .mo (no .po there) through importlib.resources."""
    catalogs = sorted(p.relative_to(ROOT).with_suffix(".mo").as_posix()
                      for p in (ROOT / "app" / "locale").glob("*/LC_MESSAGES/messages.po"))
    assert len(catalogs) >= 2  # nl, de
    names = _names(wheel)
    assert [c for c in catalogs if c not in names] == []
    assert not any(name.endswith(".po") for name in names)
    script = ("import sys; sys.path.insert(0, sys.argv[1])\n"
              "from app.i18n import translator, locale_dir\n"
              "print(locale_dir())\n"
              "print(translator('nl').gettext('Scene'), translator('de').gettext('Scene'))\n")
    out = subprocess.run([sys.executable, "-I", "-c", script, str(site)], cwd=tmp_path, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    folder, words = out.stdout.strip().splitlines()
    assert Path(folder) == site / "app" / "locale"
    assert words == "Scène Szene"
