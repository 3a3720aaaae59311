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


SECTIONS = 64  # the cylinder's polygon: its exact prism and the circle's closed form differ by ~(π/n)²


def _prism_moments(mass: float, R: float, h: float, n: int) -> list[float]:
    """A right prism on the regular n-gon of circumradius R, height h, about its centre, from the
    polygon's second moment J = Σ (xᵢyᵢ₊₁ − xᵢ₊₁yᵢ)(xᵢ² + xᵢxᵢ₊₁ + xᵢ₊₁² + yᵢ² + yᵢyᵢ₊₁ + yᵢ₊₁²)/12
    = n R⁴ sin(2π/n) (2 + cos(2π/n))/12 and its area A = n R² sin(2π/n)/2:
    I_z = m J/A = m R² (2 + cos(2π/n))/6, I_x = I_y = I_z/2 + m h²/12."""
    I_z = mass * R * R * (2.0 + math.cos(2.0 * math.pi / n)) / 6.0
    return [I_z / 2.0 + mass * h * h / 12.0, I_z / 2.0 + mass * h * h / 12.0, I_z]


@pytest.mark.parametrize(("name", "mesh", "mass", "expected", "rtol"), [
    ("box.stl", trimesh.creation.box(extents=(1.0, 2.0, 3.0)), 6.0,
     [6 * (4 + 9) / 12, 6 * (1 + 9) / 12, 6 * (1 + 4) / 12], 1e-6),  # exact up to float32 in STL
    ("prism.ply", trimesh.creation.cylinder(radius=0.5, height=2.0, sections=SECTIONS), 3.0,
     _prism_moments(3.0, 0.5, 2.0, SECTIONS), 1e-7),  # the polyhedron's own closed form: exact (PLY digits)
    ("cylinder.glb", trimesh.creation.cylinder(radius=0.5, height=2.0, sections=SECTIONS), 3.0,
     [3 * (3 * 0.25 + 4) / 12, 3 * (3 * 0.25 + 4) / 12, 3 * 0.25 / 2],
     (math.pi / SECTIONS) ** 2),  # the circle's: 1 − (2 + cos(2π/n))/3 ≈ (2π/n)²/6 < (π/n)² relative
    ("torus.off", trimesh.creation.torus(major_radius=1.0, minor_radius=0.25, major_sections=256,
                                         minor_sections=128), 1.0,
     [1 * (0.5 + 5 / 8 * 0.0625), 1 * (0.5 + 5 / 8 * 0.0625), 1 * (1 + 3 / 4 * 0.0625)],
     2 * (math.pi / 128) ** 2),  # polygons of 128 (tube) and 256 (ring) sides: O((π/128)²)
])
def test_meshes_match_their_closed_forms(tmp_path: Path, name: str, mesh: trimesh.Trimesh, mass: float,
                                         expected: list[float], rtol: float) -> None:
    path = tmp_path / name
    mesh.export(path)
    data = report(str(path), "--mass", str(mass))
    assert data["mass"] == pytest.approx(mass)
    np.testing.assert_allclose(np.diag(data["inertia"]), expected, rtol=rtol)
    np.testing.assert_allclose(data["center_of_mass"], [0, 0, 0], atol=1e-6)


def test_a_tessellated_ball_lies_between_the_bounds_of_its_spheres(tmp_path: Path) -> None:
    """An icosphere lies between its inscribed ball (radius a, the nearest face plane) and its
    circumscribed one (b, the vertices).  A uniform solid K with B(a) ⊂ K ⊂ B(b) has a mean |x|²
    between 3a²/5 and (3a²/5 (a/b)³ + b² (1 − (a/b)³)) (the most mass it can have outside a is
    B(b) − B(a), all at b), and trace(I) = 2 m ⟨|x|²⟩."""
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    path = tmp_path / "ball.obj"
    mesh.export(path)
    data = report(str(path), "--mass", "2.0")
    normals = np.cross(mesh.vertices[mesh.faces[:, 1]] - mesh.vertices[mesh.faces[:, 0]],
                       mesh.vertices[mesh.faces[:, 2]] - mesh.vertices[mesh.faces[:, 0]])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    a = float(np.min(np.abs(np.einsum("ij,ij->i", normals, mesh.vertices[mesh.faces[:, 0]]))))
    b = float(np.linalg.norm(mesh.vertices, axis=1).max())
    m = 2.0
    lower = 2.0 / 3.0 * m * 0.6 * a * a  # the mean moment trace(I)/3 = (2/3) m ⟨|x|²⟩, bounded
    upper = 2.0 / 3.0 * m * (0.6 * a * a * (a / b) ** 3 + b * b * (1.0 - (a / b) ** 3))
    mean_moment = np.trace(data["inertia"]) / 3.0
    assert lower <= mean_moment <= upper, (lower, mean_moment, upper)
    assert (upper - lower) / mean_moment < 2e-2  # the bounds are tight enough to mean something
    moments = data["principal_moments"]
    assert moments[2] - moments[0] <= upper - lower  # nearly isotropic, within the same gap


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
    (lambda d: (d / "box.stl", ["--mass", "abc"], "BOX"), "invalid float value: 'abc'"),
    (lambda d: (d / "box.stl", ["--density", "nan"], "BOX"), "--density: a positive number"),
    (lambda d: (d / "box.stl", ["--about", "1", "2"], "BOX"), "--about: expected 3 arguments"),
    (lambda d: (d / "box.stl", ["--about", "1", "inf", "0"], "BOX"), "--about: three finite numbers"),
    (lambda d: (d / "inside.off", [], "INSIDE"), "inside out"),
    (lambda d: (d / "x.json", ["--mass", "2"], '{"masses": [1], "positions": [[0, 0, 0]]}'), "for meshes"),
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
        elif content == "INSIDE":
            box = trimesh.creation.box()
            trimesh.Trimesh(box.vertices, box.faces[:, ::-1], process=False).export(path)
        else:
            path.write_text(content, encoding="utf-8")
    out = run(str(path), *extra)
    assert out.returncode == 2 and message in out.stderr, out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and out.stdout == ""


def test_physics_never_imports_trimesh_or_viser_even_to_read_a_mesh() -> None:
    mesh = ROOT / "assets" / "meshes" / "book.stl"
    code = ("import sys, contextlib, io, physics.__main__ as cli\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            f"    assert cli.main(['inertia', {str(mesh)!r}, '--mass', '1']) == 0\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in {'trimesh', 'viser'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("path", sorted((ROOT / "assets" / "meshes").glob("*.stl")), ids=lambda p: p.name)
def test_the_shipped_meshes_are_solids_the_scene_and_the_command_agree_on(path: Path) -> None:
    from app.scenes.inertia import InertiaSystem, read_mesh

    data = report(str(path), "--mass", "1.0")
    vertices, faces = read_mesh(path.name, path.read_bytes())
    system = InertiaSystem([1.0], [[0.0, 0.0, 0.0]])
    system.set_mesh(path.name, vertices, faces, 1.0)
    np.testing.assert_allclose(system.properties()["moments"], data["principal_moments"], rtol=1e-9)
