"""The inertia tensor of a system of particles, or of a solid mesh ("Inertia" scene, memo §3).

- `simulation`: the masses or mesh, O, their inertia, the presets and the mesh-file check (no viser);
- `readouts`: the panel's texts as pure functions of numbers (no viser);
- `mesh_panel`: the "Solid mesh" folder (upload, shipped meshes, mass or density);
- `view`: `InertiaView`, the scene (nodes, panel, drawing, "Spin it").

The names other modules and the tests use are re-exported here.
"""

from __future__ import annotations

from app.scenes.inertia.mesh_panel import MESHES_DIR
from app.scenes.inertia.simulation import (
    MAX_FACES,
    MAX_UPLOAD_BYTES,
    InertiaSystem,
    load_inertia_presets,
    read_mesh,
)
from app.scenes.inertia.view import BALL_RADIUS, ELLIPSOID_CUT, ELLIPSOID_SIZE, InertiaView

__all__ = ["BALL_RADIUS", "ELLIPSOID_CUT", "ELLIPSOID_SIZE", "MAX_FACES", "MAX_UPLOAD_BYTES", "MESHES_DIR",
           "InertiaSystem", "InertiaView", "load_inertia_presets", "read_mesh"]
