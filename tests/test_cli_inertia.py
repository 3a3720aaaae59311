"""`python -m physics inertia`: meshes with closed-form inertias (box, cylinder, ball, torus; the
tolerances are the tessellation's), point masses about another point, and bad input refused
with exit 2 and one line."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

ROOT = Path(__file__).resolve().parents[1]


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "physics", "inertia", *args], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)


def report(*args: str) -> dict:
    out = run(*args)
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    axes = np.array(data["principal_axes"])
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)  # right-handed columns
    np.testing.assert_allclose(axes.T @ np.array(data["inertia"]) @ axes, np.diag(data["principal_moments"]),
                               atol=1e-9 * max(data["principal_moments"]))
    assert data["principal_moments"] == sorted(data["principal_moments"])
    return data


@pytest.mark.parametrize(("name", "mesh", "mass", "expected", "rtol"), [
    ("box.stl", trimesh.creation.box(extents=(1.0, 2.0, 3.0)), 6.0,
     [6 * (4 + 9) / 12, 6 * (1 + 9) / 12, 6 * (1 + 4) / 12], 1e-6),  # exact up to float32 in STL
    ("cylinder.ply", trimesh.creation.cylinder(radius=0.5, height=2.0, sections=512), 3.0,
     [3 * (3 * 0.25 + 4) / 12, 3 * (3 * 0.25 + 4) / 12, 3 * 0.25 / 2], 1e-4),  # a 512-gon, not a circle
    ("ball.obj", trimesh.creation.icosphere(subdivisions=5, radius=1.0), 2.0, [0.8, 0.8, 0.8], 2e-3),
    ("torus.off", trimesh.creation.torus(major_radius=1.0, minor_radius=0.25, major_sections=256,
                                         minor_sections=128), 1.0,
     [1 * (0.5 + 5 / 8 * 0.0625), 1 * (0.5 + 5 / 8 * 0.0625), 1 * (1 + 3 / 4 * 0.0625)], 1e-3),
])
def test_meshes_match_their_closed_forms(tmp_path: Path, name: str, mesh: trimesh.Trimesh, mass: float,
                                         expected: list[float], rtol: float) -> None:
    path = tmp_path / name
    mesh.export(path)
    data = report(str(path), "--mass", str(mass))
    assert data["mass"] == pytest.approx(mass)
    np.testing.assert_allclose(np.diag(data["inertia"]), expected, rtol=rtol)
    np.testing.assert_allclose(data["center_of_mass"], [0, 0, 0], atol=1e-6)


def test_density_gives_the_mass_of_the_volume(tmp_path: Path) -> None:
    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=(1.0, 2.0, 3.0)).export(path)
    assert report(str(path), "--density", "500")["mass"] == pytest.approx(3000.0, rel=1e-6)


def test_point_masses_about_a_point(tmp_path: Path) -> None:
    masses, positions = [1.0, 2.0, 3.0], [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]
    path = tmp_path / "masses.json"
    path.write_text(json.dumps({"masses": masses, "positions": positions}), encoding="utf-8")
    about = np.array([0.5, -1.0, 2.0])
    data = report(str(path), "--about", *map(str, about))
    expected = sum(m * (float((x - about) @ (x - about)) * np.eye(3) - np.outer(x - about, x - about))
                   for m, x in zip(masses, np.array(positions)))
    np.testing.assert_allclose(data["inertia"], expected, atol=1e-12)
    np.testing.assert_allclose(data["center_of_mass"], np.average(positions, axis=0, weights=masses), atol=1e-12)
    assert data["mass"] == 6.0 and math.isclose(np.trace(data["inertia"]), np.trace(expected))


@pytest.mark.parametrize(("setup", "message"), [
    (lambda d: (d / "nope.stl", []), "no such file"),
    (lambda d: (d / "x.json", [], '{"masses": [1, -2], "positions": [[0,0,0],[1,0,0]]}'), "positive"),
    (lambda d: (d / "x.json", [], "{not json"), "JSON object with masses"),
    (lambda d: (d / "x.txt", [], "hello"), "a mesh"),
    (lambda d: (d / "x.stl", [], "solid junk"), "not a readable mesh"),
    (lambda d: (d / "open.stl", ["--mass", "1"], "OPEN"), "open"),
    (lambda d: (d / "box.stl", ["--mass", "-1"], "BOX"), "--mass: a positive number"),
    (lambda d: (d / "box.stl", ["--mass", "1", "--density", "2"], "BOX"), "exclude each other"),
])
def test_bad_input_exits_2_with_one_line(tmp_path: Path, setup, message: str) -> None:
    spec = setup(tmp_path)
    path, extra = spec[0], spec[1]
    if len(spec) == 3:
        content = spec[2]
        if content == "OPEN":
            box = trimesh.creation.box()
            trimesh.Trimesh(box.vertices, box.faces[:-1], process=False).export(path)
        elif content == "BOX":
            trimesh.creation.box().export(path)
        else:
            path.write_text(content, encoding="utf-8")
    out = run(str(path), *extra)
    assert out.returncode == 2 and message in out.stderr, out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and out.stdout == ""


def test_physics_imports_trimesh_only_to_read_a_mesh() -> None:
    code = "import sys, physics.__main__, physics.inertia; print('trimesh' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("path", sorted((ROOT / "assets" / "meshes").glob("*.stl")), ids=lambda p: p.name)
def test_the_shipped_meshes_are_solids_the_scene_and_the_command_agree_on(path: Path) -> None:
    from app.scenes.inertia import InertiaSystem, read_mesh

    data = report(str(path), "--mass", "1.0")
    vertices, faces = read_mesh(path.name, path.read_bytes())
    system = InertiaSystem([1.0], [[0.0, 0.0, 0.0]])
    system.set_mesh(path.name, vertices, faces, 1.0)
    np.testing.assert_allclose(system.properties()["moments"], data["principal_moments"], rtol=1e-9)
