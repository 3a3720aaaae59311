"""The Inertia scene's system (no viser): point masses or one solid mesh, a reference point O,
and their inertia (memo §3: (3.5) the tensor, (3.8) its principal cases); its presets and the
check of a mesh file before it becomes the body.

Masses in kg, positions and O in metres, tensors in kg m² (space axes); principal moments
ascending, principal axes the columns of a right-handed frame (`physics.inertia`).  Nothing
moves: `advance` only counts time; every edit bumps `version`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any

import numpy as np

from app.i18n import N_
from app.kit.core.common import SliderSpec, fork_sharing
from app.kit.core.presets import Preset, PresetError, preset_entries
from physics._types import Vec3
from physics.inertia import (
    InertiaError,
    MeshError,
    inertia_tensor_of_particles,
    mesh_mass_properties,
    principal_axes_near,
    validate_principal_moments,
)
from physics.meshfile import read_mesh_bytes
from physics.refusal import Refusal

__all__ = ["COORD_LIMIT", "EQUAL_RTOL", "FREE_BODY_MOMENTS", "MASS_SPEC", "MAX_FACES", "MAX_MASSES",
           "MAX_UPLOAD_BYTES", "MESH_DENSITY_RANGE", "MESH_DISPLAY_SIZE", "MESH_MASS_RANGE", "MESH_SUFFIXES",
           "ZERO_RTOL", "InertiaSystem", "load_inertia_presets", "read_mesh", "spin_moments"]

MAX_UPLOAD_BYTES = 20 * 1024 * 1024  # 20 MiB
MAX_FACES = 500_000
MAX_MASSES = 12
MESH_SUFFIXES = ("stl", "obj", "ply", "off", "glb")
EQUAL_RTOL = 1e-6  # principal moments closer than this times the largest are "equal" (3.8)
ZERO_RTOL = 1e-9  # a principal moment below this times the largest is "zero" (masses on a line)
MASS_SPEC = SliderSpec("m", "m [kg]", 0.1, 10.0, 0.1, N_("the selected mass"))
MESH_MASS_RANGE = (1e-3, 1e4)  # [kg] a mesh's mass
MESH_DENSITY_RANGE = (1.0, 1e5)  # [kg/m³] a mesh's density (air-light foam to osmium x 4)
COORD_LIMIT = 3.0  # [m] positions and O within ±this
MESH_DISPLAY_SIZE = 2.4  # [scene units] a mesh is drawn about this large (display_scale)
FREE_BODY_MOMENTS = (0.05, 5.0)  # [kg m²] the Free body scene's slider range ("Spin it")


def read_mesh(name: str, content: bytes) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3), faces (F, 3)) of an uploaded mesh file (`physics.meshfile`); MeshError
    saying what is wrong (too large, not a mesh type, unreadable, too many faces).  Vertices are
    merged (an STL repeats them per face), faces are kept as they are: an open or inside-out mesh
    is left for `mesh_mass_properties` to refuse, never repaired."""
    if len(content) > MAX_UPLOAD_BYTES:
        raise MeshError(N_("{name}: {size} MiB is larger than {most} MiB"), name=name,
                        size=f"{len(content) / 2**20:.1f}", most=f"{MAX_UPLOAD_BYTES / 2**20:.0f}")
    kind = name.rsplit(".", 1)[-1].lower() if "." in name else ""
    if kind not in MESH_SUFFIXES:
        raise MeshError(N_("{name}: not a mesh file this app reads (STL, OBJ, PLY, OFF, GLB)"), name=name)
    try:
        vertices, faces = read_mesh_bytes(name, content)  # the same reader as python -m physics inertia
    except MeshError as error:
        raise MeshError(N_("{name}: unreadable ({reason})"), name=name,
                        reason=str(error).split(" (", 1)[-1].rstrip(")")) from None
    if len(faces) > MAX_FACES:
        raise MeshError(N_("{name}: {faces} faces, more than {most}"), name=name, faces=len(faces), most=MAX_FACES)
    return vertices, faces


class InertiaSystem:
    """Point masses (or one solid mesh) and a reference point O; their inertia (no viser).

    Attributes:
        masses: (N,) [kg]; positions: (N, 3) [m]; about: O (3,) [m] or None (the centre of mass).
        mesh: (vertices, faces) of a uniform solid of mass `mesh_mass`, or None (particles).
        version: bumped on every edit.  t: the time the room let pass (nothing moves here).
    """

    def __init__(self, masses: Sequence[float], positions: Any) -> None:
        self.t = 0.0
        self.version = 0
        self.preset: str | None = None
        self.mesh: tuple[np.ndarray, np.ndarray] | None = None
        self.mesh_name = ""
        self.mesh_mass = 1.0
        self._mesh_unit: Any = None  # the mesh's MassProperties at density 1
        self.about: np.ndarray | None = None
        self._axes = np.eye(3)  # the principal axes last drawn (kept where they are not determined)
        self._cache: tuple[int, dict[str, Any]] | None = None
        self.set_particles(masses, positions)

    def fork(self) -> InertiaSystem:
        """An exact, independent copy: masses, positions, O, mesh and its weight, the principal
        axes last drawn (kept where they are not determined), t, preset and version.  A mesh's
        arrays (up to MAX_FACES faces) are shared, made read-only; everything else is copied."""
        return fork_sharing(self, self.mesh or ())

    def advance(self, dt: float) -> None:
        """Time passes (`t`), nothing moves: a rigid system's inertia does not change."""
        self.t += dt

    def reset(self) -> None:
        """t back to 0 and O back to the centre of mass."""
        self.t = 0.0
        self.set_about(None)

    def set_particles(self, masses: Sequence[float], positions: Any) -> None:
        """Masses (N,) [kg] at positions (N, 3) [m]: the body becomes these particles.
        ValueError (nothing changes) unless 1..MAX_MASSES positive masses at finite positions."""
        m = np.asarray(masses, dtype=float)
        x = np.asarray(positions, dtype=float)
        if m.ndim != 1 or x.shape != (len(m), 3) or not 1 <= len(m) <= MAX_MASSES:
            raise ValueError(f"1 to {MAX_MASSES} masses, each with a position [x, y, z], wanted; "
                             f"got {m.shape} masses and {x.shape} positions")
        if not (np.all(np.isfinite(m)) and np.all(m > 0.0) and np.all(np.isfinite(x))):
            raise ValueError("masses must be positive and positions finite")
        self.masses, self.positions = m.copy(), x.copy()
        self.mesh, self.mesh_name = None, ""
        self.version += 1

    def set_mesh(self, name: str, vertices: np.ndarray, faces: np.ndarray, mass: float | None = None,
                 density: float | None = None) -> None:
        """A uniform solid of `mass` [kg] or `density` [kg/m³] (one of them); MeshError if it
        bounds no solid, ValueError for a bad mass or density; nothing changes then."""
        unit = mesh_mass_properties(vertices, faces, density=1.0)  # raises MeshError
        total = self._mesh_weight(unit.volume, mass, density)
        self.mesh, self.mesh_name, self.mesh_mass, self._mesh_unit = (vertices, faces), name, total, unit
        self.version += 1

    def weigh_mesh(self, *, mass: float | None = None, density: float | None = None) -> None:
        """The current mesh, now of `mass` [kg] or `density` [kg/m³]; ValueError if bad."""
        if self.mesh is None or self._mesh_unit is None:
            raise ValueError("no mesh to weigh")
        self.mesh_mass = self._mesh_weight(self._mesh_unit.volume, mass, density)
        self.version += 1

    def mesh_volume(self) -> float:
        """The mesh's volume [m³] (ValueError without a mesh)."""
        if self.mesh is None or self._mesh_unit is None:
            raise ValueError("no mesh")
        return float(self._mesh_unit.volume)

    @staticmethod
    def _mesh_weight(volume: float, mass: float | None, density: float | None) -> float:
        if (mass is None) == (density is None):
            raise ValueError("a mass or a density, not both")
        value: Any = mass if mass is not None else density
        (lo, hi), unit = (MESH_MASS_RANGE, "kg") if mass is not None else (MESH_DENSITY_RANGE, "kg/m³")
        if not (isinstance(value, (int, float)) and math.isfinite(value) and lo <= value <= hi):
            raise Refusal(N_("mass {value} {unit}: a number from {lo} to {hi} wanted") if mass is not None else
                          N_("density {value} {unit}: a number from {lo} to {hi} wanted"),
                          value=repr(value), unit=unit, lo=f"{lo:g}", hi=f"{hi:g}")
        return float(value) if mass is not None else float(value) * volume

    def set_about(self, about: Vec3 | None) -> None:
        """O [m] (3,), or None for the centre of mass."""
        self.about = None if about is None else np.asarray(about, dtype=float).copy()
        self.version += 1

    # ------------------------------------------------------------------ the inertia
    def properties(self) -> dict[str, Any]:
        """mass [kg], com (3,), I_cm (3, 3), O (3,), d = com - O, I_O, parallel (the term
        m(|d|²𝟙 − d dᵀ)), moments (3,) ascending and axes (3, 3) columns about O (the
        eigenbasis closest to the last one where moments are equal), equal (groups of equal
        moments), zero (which moments are zero), notes (the cases of (3.8) in words).
        Computed once per version (every view of the room reads the same)."""
        if self._cache is not None and self._cache[0] == self.version:
            return self._cache[1]
        if self.mesh is not None:
            unit = self._mesh_unit
            scale = self.mesh_mass / unit.mass
            mass, com, I_cm = self.mesh_mass, np.array(unit.center_of_mass), scale * np.array(unit.inertia_cm)
            size = float(np.ptp(self.mesh[0], axis=0).max())
        else:
            mass = float(self.masses.sum())
            com = (self.masses[:, None] * self.positions).sum(axis=0) / mass
            I_cm = inertia_tensor_of_particles(self.masses, self.positions, about=com)
            size = float(np.abs(self.positions - com).max())
        O = com if self.about is None else self.about
        d = com - O
        parallel = mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
        I_O = I_cm + parallel
        # I_O = 0 (all the mass at O) up to rounding: relative to m (size + |d| + 1 µm)² [kg m²].
        nothing = mass * (size + float(np.linalg.norm(d)) + 1e-6) ** 2
        notes: list[str] = []
        if float(np.abs(I_O).max()) <= 1e-12 * nothing:
            moments, axes, equal = np.zeros(3), self._axes, [[0, 1, 2]]
            zero = [True, True, True]
            notes.append(N_("**I_O = 0**: all the mass is at O, every moment about O is zero and every axis is "
                         "principal (the frame drawn is only one choice; no ellipsoid)."))
        else:
            moments, axes, equal = principal_axes_near(I_O, self._axes, rtol=EQUAL_RTOL)
            zero = [bool(moments[k] <= ZERO_RTOL * moments[2]) for k in range(3)]
            if zero[0]:
                notes.append(N_("A principal moment is **zero**: all the mass lies on one line through O (3.8); "
                             "e1 is that line, and the momental ellipsoid is an endless cylinder about it "
                             "(drawn cut)."))
            if equal == [[0, 1, 2]]:
                notes.append(N_("**All three moments are equal**: every axis through O is principal (3.8); the "
                                "frame drawn is only one choice (it keeps its last directions)."))
            elif equal and not zero[0]:
                notes.append(N_("**Two moments are equal** (I1 = I2): any axis in their plane is principal (3.8); "
                                "the frame drawn keeps its last directions there.") if equal[0] == [0, 1] else
                             N_("**Two moments are equal** (I2 = I3): any axis in their plane is principal (3.8); "
                                "the frame drawn keeps its last directions there."))
            elif equal:
                notes.append(N_("**Two moments are equal** (I2 = I3): any axis across the line is principal (3.8); "
                                "the frame drawn keeps its last directions there."))
        self._axes = axes
        result = {"mass": mass, "com": com, "I_cm": I_cm, "O": O, "d": d, "I_O": I_O, "parallel": parallel,
                  "moments": moments, "axes": axes, "equal": equal, "zero": zero, "notes": notes, "size": size}
        self._cache = (self.version, result)
        return result

    def display_scale(self) -> float:
        """Scene units per metre the body is drawn at: 1 for particles, a power of ten times 1,
        2, 4 or 5 for a mesh, so it is about MESH_DISPLAY_SIZE large."""
        if self.mesh is None:
            return 1.0
        size = float(np.ptp(self.mesh[0], axis=0).max())
        wanted = MESH_DISPLAY_SIZE / size
        exponent = math.floor(math.log10(wanted))
        mantissa = max(m for m in (1.0, 2.0, 4.0, 5.0) if m <= wanted / 10.0**exponent)
        return mantissa * 10.0**exponent


def load_inertia_presets(path: Path | Traversable) -> tuple[Preset, ...]:
    """The Inertia scene's presets: like the other scenes' files, but each preset carries
    `masses` (N,) [kg] and `positions` (N, 3) [m] (they go into `Preset.params`, masses first,
    then the positions row by row); PresetError "file: presets[i].field: message"."""
    presets: list[Preset] = []
    for place, name, entry in preset_entries(path):
        where = f"{path}: {place}"
        unknown = sorted(set(entry) - {"name", "group", "note", "masses", "positions"})
        if unknown:
            raise PresetError(f"{where}: unknown key {unknown[0]!r} (name, group, note, masses, positions)")
        masses, positions = entry.get("masses"), entry.get("positions")
        try:
            m = np.asarray(masses, dtype=float)
        except (TypeError, ValueError):
            raise PresetError(f"{where}.masses: {masses!r} is not a list of numbers") from None
        if m.ndim != 1 or not 1 <= len(m) <= MAX_MASSES:
            raise PresetError(f"{where}.masses: 1 to {MAX_MASSES} numbers wanted")
        for k, value in enumerate(m):
            if not (math.isfinite(value) and MASS_SPEC.lo <= value <= MASS_SPEC.hi):
                raise PresetError(f"{where}.masses[{k}]: {float(value):g} is outside "
                                  f"[{MASS_SPEC.lo:g}, {MASS_SPEC.hi:g}]")
        try:
            x = np.asarray(positions, dtype=float)
        except (TypeError, ValueError):
            raise PresetError(f"{where}.positions: {positions!r} is not a list of [x, y, z]") from None
        if x.shape != (len(m), 3):
            raise PresetError(f"{where}.positions: {len(m)} points [x, y, z] wanted (one per mass)")
        bad = ~(np.isfinite(x) & (np.abs(x) <= COORD_LIMIT))
        if np.any(bad):
            k, j = (int(v) for v in np.argwhere(bad)[0])
            raise PresetError(f"{where}.positions[{k}][{j}]: {float(x[k, j]):g} is outside "
                              f"[-{COORD_LIMIT:g}, {COORD_LIMIT:g}]")
        presets.append(Preset(name=name, group=str(entry.get("group", "Presets")), note=str(entry.get("note", "")),
                              params=tuple(float(v) for v in [*m, *x.ravel()]), angles_deg=(0.0, 0.0, 0.0),
                              rates=()))
    return tuple(presets)


def spin_moments(moments: Vec3) -> tuple[tuple[float, float, float], float]:
    """The principal moments (ascending) handed to the Free body scene, and the factor k they
    were multiplied by so that they fit its sliders (FREE_BODY_MOMENTS; k = 1 if they do).
    Euler's equations are homogeneous in I: k changes T and L by k, never the motion.
    InertiaError if the moments are no rigid body (a zero moment: masses on a line)."""
    I = validate_principal_moments(np.asarray(moments, dtype=float))
    if float(I.min()) <= ZERO_RTOL * float(I.max()):
        raise InertiaError(N_("a principal moment is zero ({moment} kg m²)"), moment=f"{float(I.min()):.3g}")
    lo, hi = FREE_BODY_MOMENTS
    k = 1.0
    if I.min() < lo or I.max() > hi:
        k = min(2.0 / float(I.max()), hi / float(I.max()))  # the largest becomes 2 kg m²
    scaled = k * I
    return (float(scaled[0]), float(scaled[1]), float(scaled[2])), k
