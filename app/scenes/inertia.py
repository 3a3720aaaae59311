"""The inertia tensor of a system of particles, or of a solid mesh ("Inertia" scene, memo §3).

What it shows (memo 3.1-3.8, docs/CONVENTIONS.md "Inertia tensor"): point masses m_i at x_i,
drawn as balls whose volume follows the mass, their centre of mass c, and a reference point O
(default c, draggable).  About O: the tensor I_O = Σ m_i (|x_i − O|² 𝟙 − (x_i − O)(x_i − O)ᵀ)
(3.5) read out, its principal moments and principal axes drawn as a right-handed frame at O, and
the momental ellipsoid ω·I_O ω = 1 (semi-axes ∝ 1/√I_k; one mesh, built once, turned and
scaled).  When O leaves c, the parallel-axis term m (|d|² 𝟙 − d dᵀ), d = c − O, is read out
beside I_cm.  The cases of (3.8) are said in words: masses on a line through O (a zero principal
moment about that line, the ellipsoid an endless cylinder, drawn cut) and equal moments (the
principal axes are not determined: the frame drawn is the eigenbasis closest to the last one,
`physics.inertia.principal_axes_near`, so it never flickers while a mass is dragged).

Masses are added, removed, weighed and moved in the panel; a click on a ball selects it, and the
selected mass is dragged with a transform gizmo (O has its own, smaller one).  A solid mesh (STL,
OBJ, PLY, OFF, GLB; `physics.meshfile` reads the file, the exact polyhedral integrals of
`physics.inertia.mesh_mass_properties` do the rest), given a mass or a density, replaces the
particles; a mesh that is open, inside out, unreadable, larger than MAX_UPLOAD_BYTES or
MAX_FACES is refused with a message saying which, and the last valid body stays.  The meshes of
assets/meshes/ load with one click.  A mesh is drawn scaled to fit the view (`display_scale`,
said in the readout); the numbers are in metres.  "Spin it" hands the body (its principal
moments, and a mesh in its principal frame) to the Free body scene.

The simulation (`InertiaSystem`, no viser) has no motion: `advance` only counts time; every edit
bumps `version`.  Presets: `assets/presets/inertia.json`, read by `load_inertia_presets` (each
entry has `masses` and `positions` instead of the kit's params/angles/rates).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
import viser

from app.data import files_in, meshes_dir
from app.kit.binding import Refused
from app.kit.common import (
    BODY_AXIS_COLORS,
    CameraView,
    SliderSpec,
    axis_segments,
    checked_value,
    fork_sharing,
    format_matrix,
)
from app.kit.gui import MessageLine, PresetsRow, Readout, Wrap, add_slider
from app.kit.labels import AXES, KEY
from app.kit.presets import PRESETS_DIR, Preset, PresetError, preset_entries
from app.kit.room import Room
from app.kit.view import SceneView
from app.kit.widgets import Stage
from physics._types import Mat3, Vec3
from physics.dynamics import Model, State
from physics.euler import matrix_from_euler_zxz
from physics.inertia import (
    InertiaError,
    MeshError,
    inertia_tensor_of_particles,
    mesh_mass_properties,
    principal_axes,
    principal_axes_near,
    validate_principal_moments,
)
from physics.meshfile import read_mesh_bytes
from physics.quaternion import wxyz_from_matrix

__all__ = ["MAX_FACES", "MAX_UPLOAD_BYTES", "MESHES_DIR", "InertiaSystem", "InertiaView", "load_inertia_presets",
           "read_mesh"]

MAX_UPLOAD_BYTES = 20 * 1024 * 1024  # 20 MiB
MAX_FACES = 500_000
MAX_MASSES = 12
MESHES_DIR = meshes_dir()  # the shipped meshes (app.data: the checkout's or the installed ones)
MESH_SUFFIXES = ("stl", "obj", "ply", "off", "glb")
EQUAL_RTOL = 1e-6  # principal moments closer than this times the largest are "equal" (3.8)
ZERO_RTOL = 1e-9  # a principal moment below this times the largest is "zero" (masses on a line)
MASS_SPEC = SliderSpec("m", "m [kg]", 0.1, 10.0, 0.1, "the selected mass")
MESH_MASS_RANGE = (1e-3, 1e4)  # [kg] a mesh's mass
MESH_DENSITY_RANGE = (1.0, 1e5)  # [kg/m³] a mesh's density (air-light foam to osmium x 4)
COORD_LIMIT = 3.0  # [m] positions and O within ±this
BALL_RADIUS = 0.12  # [m] drawn radius of a 1 kg ball (∝ m^(1/3))
ELLIPSOID_SIZE = 1.2  # [scene units] the momental ellipsoid's largest drawn semi-axis
ELLIPSOID_CUT = 4.0  # a semi-axis longer than this times the shortest is drawn cut at it
MESH_DISPLAY_SIZE = 2.4  # [scene units] a mesh is drawn about this large (display_scale)
SPIN_SCENE = "Free body"  # "Spin it" hands the body to this scene (by its title: no scene imports another)
FREE_BODY_MOMENTS = (0.05, 5.0)  # [kg m²] the Free body scene's slider range ("Spin it")
SPIN_RATE = 4.0  # [rad/s] "Spin it": about the intermediate axis e2, with a small wobble
SPIN_ANGLES_DEG = (-30.0, 60.0, 0.0)  # "Spin it": the attitude it starts from (as the Dzhanibekov preset)


def read_mesh(name: str, content: bytes) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3), faces (F, 3)) of an uploaded mesh file (`physics.meshfile`); MeshError
    saying what is wrong (too large, not a mesh type, unreadable, too many faces).  Vertices are
    merged (an STL repeats them per face), faces are kept as they are: an open or inside-out mesh
    is left for `mesh_mass_properties` to refuse, never repaired."""
    if len(content) > MAX_UPLOAD_BYTES:
        raise MeshError(f"{name}: {len(content) / 2**20:.1f} MiB is larger than {MAX_UPLOAD_BYTES / 2**20:.0f} MiB")
    kind = name.rsplit(".", 1)[-1].lower() if "." in name else ""
    if kind not in MESH_SUFFIXES:
        raise MeshError(f"{name}: not a mesh file this app reads (STL, OBJ, PLY, OFF, GLB)")
    try:
        vertices, faces = read_mesh_bytes(name, content)  # the same reader as python -m physics inertia
    except MeshError as error:
        raise MeshError(f"{name}: unreadable ({str(error).split(' (', 1)[-1].rstrip(')')})") from None
    if len(faces) > MAX_FACES:
        raise MeshError(f"{name}: {len(faces)} faces, more than {MAX_FACES}")
    return vertices, faces


def _shown(x: Any) -> tuple[float, float, float]:
    """A point [m] as a vector field shows it (4 decimals, no -0.0)."""
    a, b, c = (round(float(v), 4) + 0.0 for v in x)
    return a, b, c


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
        self.mesh = None
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
            raise ValueError(f"{'mass' if mass is not None else 'density'} {value!r} {unit}: "
                             f"a number from {lo:g} to {hi:g} wanted")
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
            notes.append("**I_O = 0**: all the mass is at O, every moment about O is zero and every axis is "
                         "principal (the frame drawn is only one choice; no ellipsoid).")
        else:
            moments, axes, equal = principal_axes_near(I_O, self._axes, rtol=EQUAL_RTOL)
            zero = [bool(moments[k] <= ZERO_RTOL * moments[2]) for k in range(3)]
            if zero[0]:
                notes.append("A principal moment is **zero**: all the mass lies on one line through O (3.8); "
                             "e1 is that line, and the momental ellipsoid is an endless cylinder about it "
                             "(drawn cut).")
            if equal == [[0, 1, 2]]:
                notes.append("**All three moments are equal**: every axis through O is principal (3.8); the "
                             "frame drawn is only one choice (it keeps its last directions).")
            elif equal and not zero[0]:
                pair = "I1 = I2" if equal[0] == [0, 1] else "I2 = I3"
                notes.append(f"**Two moments are equal** ({pair}): any axis in their plane is principal (3.8); "
                             "the frame drawn keeps its last directions there.")
            elif equal:
                notes.append("**Two moments are equal** (I2 = I3): any axis across the line is principal (3.8); "
                             "the frame drawn keeps its last directions there.")
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


def _unpack(preset: Preset) -> tuple[list[float], np.ndarray]:
    n = len(preset.params) // 4
    return list(preset.params[:n]), np.asarray(preset.params[n:], dtype=float).reshape(n, 3)


def spin_moments(moments: Vec3) -> tuple[tuple[float, float, float], float]:
    """The principal moments (ascending) handed to the Free body scene, and the factor k they
    were multiplied by so that they fit its sliders (FREE_BODY_MOMENTS; k = 1 if they do).
    Euler's equations are homogeneous in I: k changes T and L by k, never the motion.
    InertiaError if the moments are no rigid body (a zero moment: masses on a line)."""
    I = validate_principal_moments(np.asarray(moments, dtype=float))
    if float(I.min()) <= ZERO_RTOL * float(I.max()):
        raise InertiaError(f"a principal moment is zero ({float(I.min()):.3g} kg m²)")
    lo, hi = FREE_BODY_MOMENTS
    k = 1.0
    if I.min() < lo or I.max() > hi:
        k = min(2.0 / float(I.max()), hi / float(I.max()))  # the largest becomes 2 kg m²
    scaled = k * I
    return (float(scaled[0]), float(scaled[1]), float(scaled[2])), k


class _Ball:
    """A mass's ball, drawn in the view's scene; clickable only in the controlling browser.

    Where the scene is shared (a presenter's), the ball that answers clicks is a copy of the
    same name in the presenter's own scene (`controls`): viser draws a browser's own node of a
    name instead of the shared one, so the presenter sees and clicks its copy, and the shared
    ball, which every follower sees, has no click handler.  Without controls (a recording) no
    ball is clickable.
    """

    def __init__(self, scene: Any, controls: Any, name: str, vertices: np.ndarray, faces: np.ndarray) -> None:
        scopes = [scene] if controls is None or controls is scene else [scene, controls]
        self.handles = [api.add_mesh_simple(name, vertices, faces, color=(230, 150, 60)) for api in scopes]
        self.clickable = self.handles[-1] if controls is not None else None

    def on_click(self, callback: Callable[[Any], None]) -> None:
        if self.clickable is not None:
            self.clickable.on_click(callback)

    def set(self, prop: str, value: Any) -> None:
        """Set a property in every scope (only where it changes)."""
        for handle in self.handles:
            if prop == "visible" and handle.visible == value:
                continue
            setattr(handle, prop, value)

    def __getattr__(self, name: str) -> Any:  # read a property (position, scale, ...) of the drawn ball
        if name == "handles":
            raise AttributeError(name)
        return getattr(self.handles[0], name)


class InertiaView(SceneView):
    """One browser's view of an `InertiaSystem` (see the module docstring)."""

    title = "Inertia"
    root = "/inertia"
    view = CameraView(position=(5.0, -4.2, 3.2), look_at=(0.3, 0.6, 0.2))
    preset_file = "inertia.json"

    @classmethod
    def read_presets(cls) -> tuple[Preset, ...]:
        return load_inertia_presets(PRESETS_DIR / cls.preset_file)

    @classmethod
    def simulation_from_preset(cls, preset: Preset) -> InertiaSystem:
        return InertiaSystem(*_unpack(preset))

    @classmethod
    def start_preset(cls, sim: InertiaSystem, preset: Preset) -> None:
        sim.set_particles(*_unpack(preset))
        sim.reset()  # t = 0, O back to the centre of mass

    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: InertiaSystem = room.sim
        self.selected = 0
        self._drawn_version = -1
        self._balls: list[Any] = []
        self._mesh_node: Any = None
        self._mesh_drawn: Any = None
        self._ellipsoid: Any = None
        self._dragging: str | None = None  # "mass" or "O" while that gizmo's edit is drawn
        self.build()

    # ------------------------------------------------------------------ building
    def _build_scene(self) -> None:
        scene = self.client.scene
        root = self.root
        Stage(scene, root, labels=self.labels)
        ball = trimesh.creation.icosphere(subdivisions=1, radius=0.07)
        self.com_node = scene.add_mesh_simple(f"{root}/com", ball.vertices, ball.faces, color=(20, 20, 20))
        self.labels.add(scene.add_label(f"{root}/com/label", "c", position=(0.1, 0.0, -0.1), font_screen_scale=1.6,
                                        anchor="top-left"), KEY)
        self.O_frame = scene.add_frame(f"{root}/O", show_axes=False)
        scene.add_arrows(f"{root}/O/axes", axis_segments(np.eye(3), 1.0), np.array(BODY_AXIS_COLORS),
                         shaft_radius=0.02, head_radius=0.055, head_length=0.12)
        for k in range(3):
            self.labels.add(scene.add_label(f"{root}/O/labels/{k}", f"e{k + 1}", position=tuple(1.15 * np.eye(3)[k]),
                                            font_screen_scale=1.8, anchor="center-center"), AXES)
        self.O_label = self.labels.add(scene.add_label(f"{root}/O_label", "O", font_screen_scale=1.8,
                                                       anchor="bottom-right"), KEY)
        # The gizmos are interactive: only in the controlling browser's own scene (app.kit.target).
        self.gizmo: Any = None
        self.O_gizmo: Any = None
        if self.controls is not None:
            self.gizmo = self.controls.add_transform_controls(f"{root}/gizmo", scale=0.7, disable_rotations=True,
                                                              depth_test=False)
            self.gizmo.on_update(self._wrap("drag", lambda _event: self._dragged()))
            self.O_gizmo = self.controls.add_transform_controls(f"{root}/O_gizmo", scale=0.45,
                                                                disable_rotations=True, depth_test=False, opacity=0.8)
            self.O_gizmo.on_update(self._wrap("drag O", lambda _event: self._O_dragged()))

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        self.gui_intro = gui.add_markdown(
            "### Inertia tensor (memo §3)\n"
            "**I_O = Σ mᵢ (|xᵢ|² 𝟙 − xᵢ xᵢᵀ)** (3.5), xᵢ from O; principal axes e1 e2 e3 "
            "(moments ascending) at O; the momental ellipsoid has semi-axes ∝ 1/√I_k.")
        self.message = MessageLine(gui)
        self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset)
        self.folder_masses = gui.add_folder("Point masses")
        with self.folder_masses:
            self.gui_selected = gui.add_dropdown("Mass", ("1",), initial_value="1",
                                                 hint="the mass to weigh and move (or click its ball); "
                                                      "drag it with the large gizmo")
            self.gui_mass = add_slider(gui, MASS_SPEC, 1.0)
            self.gui_position = gui.add_vector3("x [m]", (0.0, 0.0, 0.0), step=0.05,
                                                min=(-COORD_LIMIT,) * 3, max=(COORD_LIMIT,) * 3)
            self.gui_add_remove = gui.add_button_group("Masses", ("Add mass", "Remove mass"))
        self.folder_O = gui.add_folder("Reference point O")
        with self.folder_O:
            self.gui_about = gui.add_vector3("O [m]", (0.0, 0.0, 0.0), step=0.05,
                                             min=(-COORD_LIMIT,) * 3, max=(COORD_LIMIT,) * 3,
                                             hint="or drag the small gizmo at O")
            self.gui_O_at_com = gui.add_button("O at the centre of mass")
        self.folder_mesh = gui.add_folder("Solid mesh", expand_by_default=False)
        with self.folder_mesh:
            self.gui_mesh_given = gui.add_dropdown("Given", ("mass [kg]", "density [kg/m³]"),
                                                initial_value="mass [kg]")
            self.gui_mesh_mass = gui.add_number("mass [kg]", 1.0, min=MESH_MASS_RANGE[0], max=MESH_DENSITY_RANGE[1],
                                                  step=0.001)
            self.gui_upload = gui.add_upload_button("Upload STL / OBJ / PLY / OFF / GLB", icon=viser.Icon.UPLOAD,
                                                    hint="a closed, outward-oriented triangle mesh, in metres; "
                                                         f"up to {MAX_UPLOAD_BYTES // 2**20} MiB and {MAX_FACES} faces")
            self.shipped = {path.name.removesuffix(".stl").replace("_", "-"): path
                            for path in files_in(MESHES_DIR, ".stl")}
            self.gui_shipped = gui.add_button_group("Shipped", tuple(self.shipped)) if self.shipped else None
        self.gui_spin = gui.add_button("Spin it", icon=viser.Icon.ROTATE_360,
                                       hint="this body, in the Free body scene")
        self.folder_readout = gui.add_folder("Readout")
        with self.folder_readout:
            self.readout = Readout(gui)
        self.gui_selected.on_update(wrap("mass selector", lambda _event: self._select(self.gui_selected.value)))
        self.bind(self.gui_mass, "mass slider", self._mass_edited, lambda: float(self.sim.masses[self.selected]),
                  spec=MASS_SPEC)
        self.bind(self.gui_position, "position", self._position_edited,
                  lambda: _shown(self.sim.positions[self.selected]), check=lambda value: self._coords(value, "x"))
        self.gui_add_remove.on_click(wrap("add/remove", lambda event: self._add_remove(str(event.target.value))))
        self.bind(self.gui_about, "O", self._set_about, lambda: _shown(self.sim.properties()["O"]),
                  check=lambda value: self._coords(value, "O"))
        self.gui_O_at_com.on_click(wrap("O at c", lambda _event: self._set_about(None)))
        self.gui_mesh_given.on_update(wrap("mesh weighed by", lambda _event: self._mesh_by_changed()))
        self.bind(self.gui_mesh_mass, "mesh mass", self._mesh_amount_edited, self._weight_shown,
                  check=self._check_weight)
        self.gui_upload.on_upload(wrap("upload", lambda _event: self._uploaded()))
        if self.gui_shipped is not None:
            self.gui_shipped.on_click(wrap("shipped mesh", lambda event: self.load_shipped(str(event.target.value))))
        self.gui_spin.on_click(wrap("spin it", lambda _event: self.spin_it()))
        self._gui_roots = [self.gui_intro, self.message.handle, *self.presets_row.groups, self.presets_row.gui_note,
                           self.folder_masses, self.folder_O, self.folder_mesh, self.gui_spin, self.folder_readout]

    # ------------------------------------------------------------------ edits
    def _coords(self, value: Any, what: str) -> np.ndarray:
        """Three finite numbers within ±COORD_LIMIT; Refused (with the message) otherwise."""
        try:
            x = np.array([float(v) for v in value])
        except (TypeError, ValueError):
            x = np.full(3, np.nan)
        if x.shape != (3,) or not np.all(np.isfinite(x)) or np.any(np.abs(x) > COORD_LIMIT):
            raise Refused(f"{what} = {value!r} refused: three numbers within ±{COORD_LIMIT:g} m.")
        return x

    def _select(self, value: Any) -> None:
        try:
            k = int(str(value)) - 1
        except ValueError:
            k = -1
        if self.sim.mesh is not None or not 0 <= k < len(self.sim.masses):
            self.message.show(f"No mass {value!r}.")
            self.quiet.write(self.gui_selected, str(self.selected + 1))
            return
        self.selected = k
        self.refresh()

    def _mass_edited(self, value: float) -> None:
        masses = self.sim.masses.copy()
        masses[self.selected] = value
        self._edit(masses, self.sim.positions)

    def _position_edited(self, x: np.ndarray) -> None:
        positions = self.sim.positions.copy()
        positions[self.selected] = x
        self._edit(self.sim.masses, positions)

    def _gizmo_point(self, handle: Any, what: str) -> np.ndarray | None:
        """Where a gizmo was dragged, in metres (clipped to ±COORD_LIMIT); None if not a point."""
        try:
            x = np.asarray(handle.position, dtype=float) / self.sim.display_scale()
        except (TypeError, ValueError):
            x = np.full(3, np.nan)
        if x.shape != (3,) or not np.all(np.isfinite(x)):
            self.message.show(f"{what} dragged to {handle.position!r}: refused, not a point.")
            return None
        return np.clip(x, -COORD_LIMIT, COORD_LIMIT)

    def _dragged(self) -> None:
        if self.sim.mesh is not None:
            return  # the gizmo is hidden with a mesh: a late event from a drag before the upload
        x = self._gizmo_point(self.gizmo, "the mass")
        if x is None:
            return
        positions = self.sim.positions.copy()
        positions[self.selected] = x
        self._edit(self.sim.masses, positions, dragging="mass")

    def _O_dragged(self) -> None:
        O = self._gizmo_point(self.O_gizmo, "O")
        if O is not None:
            self._set_about(O, dragging="O")

    def _add_remove(self, choice: str) -> None:
        masses, positions = list(self.sim.masses), list(self.sim.positions)
        if choice == "Add mass":
            if len(masses) >= MAX_MASSES:
                self.message.show(f"At most {MAX_MASSES} masses.")
                return
            masses.append(1.0)
            positions.append(np.array([0.5, 0.5, 0.5]))
            self.selected = len(masses) - 1
        elif choice == "Remove mass":
            if len(masses) <= 1:
                self.message.show("At least one mass.")
                return
            del masses[self.selected], positions[self.selected]
            self.selected = min(self.selected, len(masses) - 1)
        else:
            return  # a client can send any string
        self._edit(masses, positions)

    def _edit(self, masses: Any, positions: Any, dragging: str | None = None) -> None:
        self.message.clear()
        self.sim.set_particles(masses, np.asarray(positions, dtype=float))
        self.sim.preset = None
        self._redraw(dragging)

    def _redraw(self, dragging: str | None) -> None:
        """Every view of the room redraws; this view's gizmo being dragged is not moved back."""
        self._dragging = dragging
        try:
            self.room.refresh()
        finally:
            self._dragging = None

    def _set_about(self, O: Vec3 | None, dragging: str | None = None) -> None:
        self.message.clear()
        self.sim.set_about(O)
        self._redraw(dragging)

    # ------------------------------------------------------------------ meshes
    def _weight(self) -> dict[str, float]:
        """{"mass": …} or {"density": …} from the panel (checked by InertiaSystem)."""
        try:
            value = float(self.gui_mesh_mass.value)
        except (TypeError, ValueError):
            value = math.nan
        return {"density": value} if self._by_density() else {"mass": value}

    def _mesh_by_changed(self) -> None:
        """Mass or density: the number box shows the current mesh's (nothing changes), or a
        default (1 kg, 1000 kg/m³) while there is no mesh."""
        self.gui_mesh_mass.label = "density [kg/m³]" if self._by_density() else "mass [kg]"
        self._show_weight()

    def _by_density(self) -> bool:
        return str(self.gui_mesh_given.value).startswith("density")

    def _weight_shown(self) -> float:
        """What the mass / density box shows: the mesh's (6 significant digits), or the default."""
        sim, by_density = self.sim, self._by_density()
        if sim.mesh is None:
            return 1000.0 if by_density else 1.0
        value = sim.mesh_mass / sim.mesh_volume() if by_density else sim.mesh_mass
        return float(f"{value:.6g}")

    def _show_weight(self) -> None:
        self.quiet.write(self.gui_mesh_mass, self._weight_shown())

    def _check_weight(self, value: Any) -> float:
        """A mass [kg] or density [kg/m³] in its range (MESH_MASS_RANGE, MESH_DENSITY_RANGE)."""
        by_density = self._by_density()
        (lo, hi), what = (MESH_DENSITY_RANGE, "density") if by_density else (MESH_MASS_RANGE, "mass")
        number = checked_value(value, lo, hi)
        if number is None:
            kept = f" The mesh keeps its {self.sim.mesh_mass:.4g} kg." if self.sim.mesh is not None else ""
            unit = "kg/m³" if by_density else "kg"
            raise Refused(f"Refused: {what} {value!r} {unit}: a number from {lo:g} to {hi:g} wanted.{kept}")
        return number

    def _mesh_amount_edited(self, value: float) -> str | None:
        """A new mass or density for the mesh shown (kept for the next mesh while there is none)."""
        if self.sim.mesh is None:
            return None
        try:
            self.sim.weigh_mesh(**({"density": value} if self._by_density() else {"mass": value}))
        except ValueError as error:
            return f"Refused: {error}. The mesh keeps its {self.sim.mesh_mass:.4g} kg."
        self.room.refresh()
        return None

    def _uploaded(self) -> None:
        upload = self.gui_upload.value
        self.load_mesh(str(upload.name), bytes(upload.content))

    def load_shipped(self, name: str) -> None:
        """One of the meshes of assets/meshes/ (a button; a client can send any name)."""
        path = self.shipped.get(name)
        if path is None:
            self.message.show(f"No shipped mesh named {name!r}.")
            return
        self.load_mesh(path.name, path.read_bytes())

    def load_mesh(self, name: str, content: bytes) -> None:
        """Read, check and show a mesh file; refused with the reason, the last valid body staying."""
        try:
            vertices, faces = read_mesh(name, content)
            self.sim.set_mesh(name, vertices, faces, **self._weight())
        except (MeshError, ValueError) as error:
            text = str(error) if str(error).startswith(name) else f"{name}: {error}"
            self.message.show(f"Mesh refused: {text}. The last valid body stays.")
            return
        self.message.clear()
        self.sim.set_about(None)
        self.sim.preset = None
        self.room.refresh()

    def spin_it(self) -> None:
        """Hand this body to the Free body scene: its principal moments about the centre of mass
        (ascending, along x′ y′ z′; scaled to the scene's sliders if needed, said there) and, for
        a mesh, the mesh in its principal frame (x′ = Rᵀ (x − c))."""
        properties = self.sim.properties()
        moments, axes = principal_axes(properties["I_cm"])
        try:
            handed, k = spin_moments(moments)
        except InertiaError as error:
            self.message.show(f"Nothing to spin: {error} — masses on one line are no rigid body to spin "
                              "(add a mass off the line).")
            return
        if self.open_scene is None:
            self.message.show("This browser cannot open another scene.")
            return
        mesh = self.sim.mesh
        com = properties["com"]

        def prepare(room: Room) -> None:  # the Free body's new room, before it is shown
            sim = room.sim
            sim.model = Model(inertia=handed)
            if mesh is not None:
                sim.mesh = ((mesh[0] - com) @ axes, mesh[1])
            sim.preset = None
            angles = np.radians(SPIN_ANGLES_DEG)
            omega = np.array([0.01, 1.0, 0.01]) * SPIN_RATE  # about e2 (y′), slightly off: the flip
            sim.restart(State(matrix_from_euler_zxz(*angles), omega, 0.0), angles=angles)

        what = self.sim.mesh_name or f"{len(self.sim.masses)} point masses"
        room = self.open_scene(SPIN_SCENE, prepare)
        text = f"Spun from the Inertia scene: {what}, about its middle axis y′."
        if k != 1.0:
            text += (f" Its moments ({', '.join(f'{m:.3g}' for m in moments)} kg m²) are shown ×{k:.3g} to fit the "
                     "sliders: the motion is the same (Euler's equations are homogeneous in I), T and L are ×k.")
        room.notify(text)

    def key_numbers(self) -> list[str]:
        """For the followers' panel: the body (masses, or the mesh and its mass) and its
        principal moments about O."""
        sim, props = self.sim, self.sim.properties()
        if sim.mesh is not None:
            body = f"{sim.mesh_name}: m = {props['mass']:.4g} kg"
        else:
            body = f"{len(sim.masses)} masses [kg]: " + ", ".join(f"{m:.3g}" for m in sim.masses)
        moments = ", ".join(f"{m:.4g}" for m in props["moments"])
        return [body, f"principal moments about O: {moments} kg m²"]

    # ------------------------------------------------------------------ drawing
    def frame(self, dt: float) -> None:
        """Nothing moves: a frame draws only after an edit another view made in this room."""
        if self.sim.version != self._drawn_version:
            self.refresh()
        self.labels.update(dt)

    def refresh(self) -> None:
        sim = self.sim
        self._drawn_version = sim.version
        props = sim.properties()
        k = sim.display_scale()
        particles = sim.mesh is None
        if particles:
            self.selected = min(self.selected, len(sim.masses) - 1)  # another view may have removed masses
        with self.client.atomic():
            self._draw_bodies(k)
            O, axes, moments = props["O"], props["axes"], props["moments"]
            self.O_frame.position = tuple(k * O)
            self.O_frame.wxyz = wxyz_from_matrix(axes)
            self.O_label.position = tuple(k * O)
            self.com_node.position = tuple(k * props["com"])
            if self._dragging != "O" and self.O_gizmo is not None:
                self.O_gizmo.position = tuple(k * O)
            self._draw_ellipsoid(k * O, axes, moments, props["zero"])
            self.folder_masses.visible = particles
            if self.gizmo is not None:
                self.gizmo.visible = particles
            if particles:
                self.gui_selected.options = tuple(str(j + 1) for j in range(len(sim.masses)))
                self.quiet.write(self.gui_selected, str(self.selected + 1))
                self.show_values([self.gui_mass], [MASS_SPEC], [float(sim.masses[self.selected])])
                self.quiet.write(self.gui_position, _shown(sim.positions[self.selected]))
                if self._dragging != "mass" and self.gizmo is not None:
                    self.gizmo.position = tuple(sim.positions[self.selected])
            self.quiet.write(self.gui_about, _shown(O))
            self.presets_row.show_note(self.preset_shown())
            self._refresh_readout(props, k)
            self.labels.settle()

    def _draw_bodies(self, k: float) -> None:
        scene, sim = self.client.scene, self.sim
        if sim.mesh is not None:
            for ball in self._balls:
                ball.set("visible", False)
            if self._mesh_drawn is not sim.mesh:
                if self._mesh_node is not None:
                    self._mesh_node.remove()
                vertices, faces = sim.mesh
                self._mesh_node = scene.add_mesh_simple(f"{self.root}/mesh", vertices, faces, color=(215, 140, 70),
                                                        opacity=0.85, flat_shading=True, scale=k)
                self._mesh_drawn = sim.mesh
            return
        if self._mesh_node is not None:
            self._mesh_node.remove()
            self._mesh_node, self._mesh_drawn = None, None
        while len(self._balls) < len(sim.masses):
            index = len(self._balls)
            sphere = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
            ball = _Ball(scene, self.controls, f"{self.root}/masses/{index}", sphere.vertices, sphere.faces)
            ball.on_click(self._wrap("ball click", lambda _event, j=index: self._select(j + 1)))
            self._balls.append(ball)
        for index, ball in enumerate(self._balls):
            shown = index < len(sim.masses)
            ball.set("visible", shown)
            if shown:
                ball.set("position", tuple(sim.positions[index]))
                ball.set("scale", BALL_RADIUS * float(sim.masses[index]) ** (1.0 / 3.0))
                ball.set("color", (200, 50, 20) if index == self.selected else (230, 150, 60))

    def _draw_ellipsoid(self, O: Vec3, axes: Mat3, moments: Vec3, zero: Sequence[bool]) -> None:
        """The momental ellipsoid ω·I_O ω = 1 at O: a unit sphere built once, turned by the
        principal axes and scaled by the semi-axes 1/√I_k, all times one factor (the largest
        drawn ELLIPSOID_SIZE).  A semi-axis more than ELLIPSOID_CUT times the shortest (or
        endless: a zero moment) is drawn cut at that; with I_O = 0 there is no ellipsoid.

        Only its back faces are drawn (side="back": the far half of the shell, translucent): the
        body inside it is in front of them and shows whole.  Drawn with its front faces, it hid an
        uploaded compact mesh entirely and the book wherever it was inside (a translucent mesh
        writes depth, and three.js drew it before the body; tests/test_browser_inertia.py)."""
        if self._ellipsoid is None:
            sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
            self._ellipsoid = self.client.scene.add_mesh_simple(
                f"{self.root}/ellipsoid", sphere.vertices, sphere.faces, color=(90, 140, 230), opacity=0.25,
                side="back", cast_shadow=False, receive_shadow=False)
        if all(zero):
            if self._ellipsoid.visible:
                self._ellipsoid.visible = False
            return
        if not self._ellipsoid.visible:
            self._ellipsoid.visible = True
        semi = self.ellipsoid_semi_axes(moments, zero)
        self._ellipsoid.position = tuple(float(v) for v in O)
        self._ellipsoid.wxyz = wxyz_from_matrix(axes)
        self._ellipsoid.scale = (float(semi[0]), float(semi[1]), float(semi[2]))

    @staticmethod
    def ellipsoid_semi_axes(moments: Vec3, zero: Sequence[bool]) -> np.ndarray:
        """Drawn semi-axes (3,) along e1 e2 e3: ∝ 1/√I_k, the largest ELLIPSOID_SIZE, each at most
        ELLIPSOID_CUT times the shortest (a zero moment's endless axis is drawn that long)."""
        inverse = np.array([math.inf if zero[j] else 1.0 / math.sqrt(float(moments[j])) for j in range(3)])
        shortest = float(inverse.min())
        drawn = np.minimum(inverse, ELLIPSOID_CUT * shortest)
        return ELLIPSOID_SIZE * drawn / float(drawn.max())

    def _refresh_readout(self, props: dict[str, Any], k: float) -> None:
        sim = self.sim
        O, d = props["O"], props["d"]
        what = (f"a uniform solid **{sim.mesh_name}**, m = {props['mass']:.4g} kg" if sim.mesh is not None
                else f"**{len(sim.masses)} point masses**, m = {props['mass']:.4g} kg")
        def point(x: Vec3) -> str:  # rounding noise (1e-17 of a 0.5 m body) shown as 0
            return ", ".join(f"{0.0 if abs(v) <= 1e-12 * max(props['size'], 1e-300) else v:.4g}" for v in x)

        lines = [what, f"centre of mass c = ({point(props['com'])}) m",
                 f"O = ({point(O)}) m" + (" = c" if not np.any(d) else "")]
        if k != 1.0:
            lines.append(f"drawn ×{k:g} (its size is {props['size']:.3g} m)")
        scale = float(np.abs(props["I_O"]).max())
        decimals = 4 if scale == 0.0 else min(12, max(4, 4 - math.floor(math.log10(scale))))  # ~5 digits
        text = "  \n".join(lines) + "\n\n**I_O** [kg m²]\n```\n" + format_matrix(props["I_O"], decimals) + "\n```\n"
        if np.any(d):
            text += ("**I_O = I_cm + m(|d|²𝟙 − d dᵀ)**, d = c − O:\n```\n" + format_matrix(props["I_cm"], decimals)
                     + "\n+\n" + format_matrix(props["parallel"], decimals) + "\n```\n")
        moments = props["moments"]
        text += ("Principal moments I1 ≤ I2 ≤ I3 = " + ", ".join(f"{m:.5g}" for m in moments) + " kg m²  \n"
                 "principal axes e1 e2 e3 (columns, right-handed)\n```\n" + format_matrix(props["axes"], 4) + "\n```\n")
        for note in props["notes"]:
            text += note + "  \n"
        self.readout.set(text)
