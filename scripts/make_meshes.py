"""The meshes in assets/meshes/, made from trimesh primitives (nothing is downloaded).

    python3 scripts/make_meshes.py            # rewrites assets/meshes/*.stl

book.stl      a book, 0.24 × 0.17 × 0.04 m: three distinct moments (the Dzhanibekov flip)
phone.stl     a phone, 0.15 × 0.075 × 0.008 m
t_handle.stl  a T-handle like the wing nut of the Dzhanibekov films: a bar and a stem
racket.stl    a tennis racket: a ring (torus) for the head and a handle (the strings weigh ~nothing)
top.stl       a spinning top: a disc on a shaft with a point (body of revolution)

Each is a closed, outward-oriented solid (checked here with physics.inertia's own test), in
metres; upload one in the Inertia scene or run `python -m physics inertia assets/meshes/top.stl`.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import trimesh

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from physics.inertia import mesh_mass_properties  # noqa: E402

OUT = ROOT / "assets" / "meshes"


def _union(*parts: trimesh.Trimesh) -> trimesh.Trimesh:
    """The parts as one mesh; they only touch or overlap inside, and the overlap is small: the
    inertia of overlapping parts counts twice, so the shapes below keep their parts disjoint."""
    return trimesh.util.concatenate(parts)


def meshes() -> dict[str, trimesh.Trimesh]:
    book = trimesh.creation.box(extents=(0.24, 0.17, 0.04))
    phone = trimesh.creation.box(extents=(0.15, 0.075, 0.008))
    bar = trimesh.creation.cylinder(radius=0.006, height=0.08, sections=48)
    bar.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (0, 1, 0)))
    stem = trimesh.creation.cylinder(radius=0.006, height=0.05, sections=48)
    stem.apply_translation((0.0, 0.0, -0.0311))  # just below the bar: disjoint
    t_handle = _union(bar, stem)
    head = trimesh.creation.torus(major_radius=0.13, minor_radius=0.012, major_sections=96, minor_sections=24)
    head.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))
    handle = trimesh.creation.cylinder(radius=0.016, height=0.3, sections=48)
    handle.apply_translation((0.0, 0.0, -0.1421 - 0.15))  # up to just below the ring (z = -0.142)
    racket = _union(head, handle)
    disc = trimesh.creation.cylinder(radius=0.04, height=0.012, sections=96)
    shaft = trimesh.creation.cylinder(radius=0.004, height=0.05, sections=32)
    shaft.apply_translation((0.0, 0.0, 0.0311))
    point = trimesh.creation.cone(radius=0.012, height=0.02, sections=48)
    point.apply_transform(trimesh.transformations.rotation_matrix(np.pi, (1, 0, 0)))
    point.apply_translation((0.0, 0.0, -0.0061))
    top = _union(disc, shaft, point)
    return {"book": book, "phone": phone, "t_handle": t_handle, "racket": racket, "top": top}


def _check_disjoint(name: str, mesh: trimesh.Trimesh) -> None:
    """No two parts' bounding boxes overlap (a conservative test: the parts here are stacked
    along z), since overlapping solids would count twice in the inertia."""
    parts = mesh.split(only_watertight=False)
    for i, p in enumerate(parts):
        for q in parts[i + 1:]:
            if np.all(np.maximum(p.bounds[0], q.bounds[0]) < np.minimum(p.bounds[1], q.bounds[1])):
                raise SystemExit(f"{name}: the bounding boxes of two parts overlap")


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for name, mesh in meshes().items():
        properties = mesh_mass_properties(mesh.vertices, mesh.faces, density=1000.0)  # MeshError if not a solid
        _check_disjoint(name, mesh)
        path = OUT / f"{name}.stl"
        mesh.export(path)
        moments = np.round(np.linalg.eigvalsh(properties.inertia_cm), 10)
        print(f"{path.relative_to(ROOT)}: {len(mesh.faces)} faces, {properties.mass:.4g} kg at 1000 kg/m³, "
              f"principal moments {moments} kg m²")


if __name__ == "__main__":
    main()
