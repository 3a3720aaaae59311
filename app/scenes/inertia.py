"""The inertia tensor of a system of particles, or of a solid mesh ("Inertia" scene, memo §3).

What it shows (memo 3.1-3.8, docs/CONVENTIONS.md "Inertia tensor"): point masses m_i at x_i,
drawn as balls whose volume follows the mass, their centre of mass c, and a reference point O
(default c).  About O: the tensor I_O = Σ m_i (|x_i − O|² 𝟙 − (x_i − O)(x_i − O)ᵀ) (3.5) read
out, its principal moments and principal axes drawn as a right-handed frame at O, and the
momental ellipsoid (semi-axes ∝ 1/√I_k).  When O leaves c, the parallel-axis term
m (|d|² 𝟙 − d dᵀ), d = c − O, is read out beside I_cm.  The cases of (3.8) are said in words:
masses on a line through O (a zero principal moment about that line) and equal moments (the
principal axes are not determined: the frame drawn keeps its last axes, so it never flickers).

Masses are added, removed, weighed and moved in the panel (the selected mass also with a
transform gizmo); O is typed in or dragged with its own, smaller gizmo.  A solid mesh of a
given mass or density (STL, OBJ, PLY, OFF, GLB; trimesh reads the file, the exact polyhedral
integrals of `physics.inertia.mesh_mass_properties` do the rest) replaces the
particles; a mesh that is open, inside out, unreadable, larger than MAX_UPLOAD_BYTES or
MAX_FACES is refused with a message saying which, and the last valid body stays.  "Spin it"
hands the body (its principal moments, and a mesh in its principal frame) to the Free body scene.

The simulation (`InertiaSystem`, no viser) has no motion: `advance` does nothing; every edit
bumps `version`.  Presets: `assets/presets/inertia.json` (`params` hold the masses and
positions, see `PARAM_KEYS`).
"""

from __future__ import annotations

import io
import json
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import trimesh
import viser

from app.kit.common import BODY_AXIS_COLORS, CameraView, SliderSpec, axis_segments, format_matrix
from app.kit.gui import MessageLine, PresetsRow, Readout, Wrap, add_slider
from app.kit.presets import PRESETS_DIR, Preset, PresetError
from app.kit.room import Room
from app.kit.view import SceneView
from app.kit.widgets import Stage
from physics._types import Mat3, Vec3
from physics.dynamics import Model, State
from physics.inertia import (
    MeshError,
    inertia_tensor_of_particles,
    mesh_mass_properties,
    parallel_axis,
    principal_axes,
)
from physics.quaternion import wxyz_from_matrix

__all__ = ["MAX_FACES", "MAX_UPLOAD_BYTES", "InertiaSystem", "InertiaView", "read_mesh"]

MAX_UPLOAD_BYTES = 20 * 1024 * 1024
MAX_FACES = 500_000
MAX_MASSES = 12
EQUAL_RTOL = 1e-6  # principal moments closer than this (relative) are "equal"
ZERO_RTOL = 1e-9  # a principal moment below this times the largest is "zero" (collinear masses)
MASS_SPEC = SliderSpec("m", "m [kg]", 0.1, 10.0, 0.1, "the selected mass")
COORD_LIMIT = 3.0  # [m] positions and O within ±this
BALL_RADIUS = 0.12  # [m] drawn radius of a 1 kg ball (∝ m^(1/3))
ELLIPSOID_SIZE = 1.2  # [scene units] the momental ellipsoid's largest semi-axis


def read_mesh(name: str, content: bytes) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3), faces (F, 3)) of an uploaded mesh file; MeshError saying what is wrong."""
    if len(content) > MAX_UPLOAD_BYTES:
        raise MeshError(f"{name}: {len(content) / 2**20:.1f} MiB is larger than {MAX_UPLOAD_BYTES / 2**20:.0f} MiB")
    kind = name.rsplit(".", 1)[-1].lower() if "." in name else ""
    if kind not in ("stl", "obj", "ply", "off", "glb"):
        raise MeshError(f"{name}: not a mesh file this app reads (STL, OBJ, PLY, OFF, GLB)")
    try:
        mesh = trimesh.load(io.BytesIO(content), file_type=kind, force="mesh", process=False)
    except Exception as error:  # noqa: BLE001 - trimesh raises many kinds for a bad file
        raise MeshError(f"{name}: unreadable ({type(error).__name__}: {error})") from None
    faces = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), dtype=np.int64)
    if faces.size == 0:
        raise MeshError(f"{name}: unreadable (no triangles in it)")
    if len(faces) > MAX_FACES:
        raise MeshError(f"{name}: {len(faces)} faces, more than {MAX_FACES}")
    vertices = np.asarray(getattr(mesh, "vertices"), dtype=float)  # noqa: B009 - trimesh's loose types
    merged = trimesh.Trimesh(vertices, faces, process=True)
    return np.asarray(merged.vertices, dtype=float), np.asarray(merged.faces, dtype=np.int64)


class InertiaSystem:
    """Point masses (or one solid mesh) and a reference point O; their inertia (no viser).

    Attributes:
        masses: (N,) [kg]; positions: (N, 3) [m]; about: O (3,) [m] or None (the centre of mass).
        mesh: (vertices, faces) of a uniform solid of mass `mesh_mass`, or None (particles).
        version: bumped on every edit.  t: always 0 (nothing moves here).
    """

    def __init__(self, masses: Sequence[float], positions: Any) -> None:
        self.t = 0.0
        self.version = 0
        self.preset: str | None = None
        self.mesh: tuple[np.ndarray, np.ndarray] | None = None
        self.mesh_name = ""
        self.mesh_mass = 1.0
        self.about: np.ndarray | None = None
        self._axes = np.eye(3)  # the principal axes last drawn (kept where they are not determined)
        self.set_particles(masses, positions)

    def advance(self, dt: float) -> None:
        """Time passes (`t`), nothing moves: a rigid system's inertia does not change."""
        self.t += dt

    def reset(self) -> None:
        """t back to 0 and O back to the centre of mass."""
        self.t = 0.0
        self.set_about(None)

    def set_particles(self, masses: Sequence[float], positions: Any) -> None:
        """Masses (N,) [kg] at positions (N, 3) [m]: the body becomes these particles."""
        m = np.asarray(masses, dtype=float)
        x = np.asarray(positions, dtype=float).reshape(-1, 3)
        if len(m) != len(x) or not 1 <= len(m) <= MAX_MASSES:
            raise ValueError(f"1 to {MAX_MASSES} masses, each with a position, wanted")
        if not (np.all(np.isfinite(m)) and np.all(m > 0.0) and np.all(np.isfinite(x))):
            raise ValueError("masses must be positive and positions finite")
        self.masses, self.positions = m, x
        self.mesh = None
        self.version += 1

    def set_mesh(self, name: str, vertices: np.ndarray, faces: np.ndarray, mass: float | None = None,
                 density: float | None = None) -> None:
        """A uniform solid of `mass` [kg], or of `density` [kg/m³]; MeshError (nothing changes)
        if it bounds no solid, ValueError for a non-positive mass or density."""
        unit = mesh_mass_properties(vertices, faces, density=1.0)  # raises MeshError
        given = mass if density is None else density
        if given is None or not (math.isfinite(given) and given > 0.0):
            raise ValueError(f"{'density' if density is not None else 'mass'} {given!r}: positive wanted")
        total = float(given) if density is None else float(density) * unit.volume
        self.mesh, self.mesh_name, self.mesh_mass = (vertices, faces), name, total
        self.version += 1

    def set_about(self, about: Vec3 | None) -> None:
        self.about = None if about is None else np.asarray(about, dtype=float)
        self.version += 1

    # ------------------------------------------------------------------ the inertia
    def properties(self) -> dict[str, Any]:
        """mass [kg], com (3,), I_cm (3, 3), O (3,), d = com - O, I_O, parallel (the term
        m(|d|²𝟙 − d dᵀ)), moments (3,) ascending and axes (3, 3) columns about O, notes."""
        if self.mesh is not None:
            vertices, faces = self.mesh
            unit = mesh_mass_properties(vertices, faces, density=1.0)
            scale = self.mesh_mass / unit.mass
            mass, com, I_cm = self.mesh_mass, np.asarray(unit.center_of_mass), scale * np.asarray(unit.inertia_cm)
        else:
            mass = float(self.masses.sum())
            com = (self.masses[:, None] * self.positions).sum(axis=0) / mass
            I_cm = inertia_tensor_of_particles(self.masses, self.positions, about=com)
        O = com if self.about is None else self.about
        d = com - O
        parallel = mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
        I_O = parallel_axis(I_cm, mass, d) if np.any(d) else np.array(I_cm)
        moments, axes = principal_axes(I_O)
        axes, notes = self._stable_axes(moments, axes)
        return {"mass": mass, "com": com, "I_cm": I_cm, "O": O, "d": d, "I_O": I_O, "parallel": parallel,
                "moments": moments, "axes": axes, "notes": notes}

    def _stable_axes(self, moments: Vec3, axes: Mat3) -> tuple[Mat3, list[str]]:
        """Principal axes that do not jump: where two or three moments are equal, the eigenbasis
        is any basis of the eigenspace, so the last drawn axes are kept projected on it."""
        notes = []
        largest = max(float(moments[2]), 1e-300)
        if float(moments[0]) <= ZERO_RTOL * largest:
            notes.append("A principal moment is **zero**: all masses lie on one line through O (3.8), "
                         "the axis along that line.")
        equal = [abs(float(moments[k + 1] - moments[k])) <= EQUAL_RTOL * largest for k in range(2)]
        if all(equal):
            notes.append("**All three moments are equal**: every axis through O is principal; "
                         "the frame drawn is only one choice.")
            return self._axes, notes
        if any(equal):
            k = 0 if equal[0] else 1  # the axes k, k+1 span a degenerate plane
            notes.append("**Two moments are equal**: any axis in their plane is principal (the frame "
                         "drawn keeps its last direction there).")
            distinct = axes[:, 2 if k == 0 else 0]
            previous = self._axes[:, k]
            in_plane = previous - (previous @ distinct) * distinct
            if float(np.linalg.norm(in_plane)) > 1e-6:
                first = in_plane / np.linalg.norm(in_plane)
                second = np.cross(distinct, first) if k == 0 else np.cross(first, distinct)
                columns = [first, second, distinct] if k == 0 else [distinct, first, second]
                if k == 1:
                    columns = [distinct, first, np.cross(distinct, first)]
                axes = np.column_stack(columns)
        # Signs: closest to the last axes drawn, still right-handed.
        for j in range(3):
            if float(axes[:, j] @ self._axes[:, j]) < 0.0:
                axes[:, j] = -axes[:, j]
        if np.linalg.det(axes) < 0.0:
            axes[:, 2] = -axes[:, 2]
        self._axes = axes
        return axes, notes


PARAM_KEYS = ()  # the masses are not sliders: their presets carry them in "masses"/"positions"


def _load_presets() -> tuple[Preset, ...]:
    """assets/presets/inertia.json: like the other scenes' files, each preset with `masses` (N,)
    [kg] and `positions` (N, 3) [m]; PresetError naming the file and the field."""
    path = PRESETS_DIR / "inertia.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as error:
        raise PresetError(f"{path}: not readable JSON: {error}") from None
    presets = []
    for k, entry in enumerate(data.get("presets", [])):
        where = f"{path}: presets[{k}]"
        try:
            system = InertiaSystem(entry["masses"], entry["positions"])
        except (KeyError, TypeError, ValueError) as error:
            raise PresetError(f"{where}: masses/positions: {error}") from None
        if np.any(np.abs(system.positions) > COORD_LIMIT) or np.any(system.masses > MASS_SPEC.hi):
            raise PresetError(f"{where}: positions within ±{COORD_LIMIT:g} m and masses up to {MASS_SPEC.hi:g} kg")
        presets.append(Preset(name=str(entry["name"]), group=str(entry.get("group", "Presets")),
                              note=str(entry.get("note", "")),
                              params=tuple(float(v) for v in [*system.masses, *system.positions.ravel()]),
                              angles_deg=(0.0, 0.0, 0.0), rates=()))
    if not presets:
        raise PresetError(f"{path}: presets: missing or empty")
    return tuple(presets)


def _unpack(preset: Preset) -> tuple[list[float], np.ndarray]:
    n = len(preset.params) // 4
    return list(preset.params[:n]), np.asarray(preset.params[n:], dtype=float).reshape(n, 3)


class InertiaView(SceneView):
    """One browser's view of an `InertiaSystem` (see the module docstring)."""

    title = "Inertia"
    root = "/inertia"
    view = CameraView(position=(5.0, -4.2, 3.2), look_at=(0.3, 0.6, 0.2))
    preset_file = "inertia.json"
    _presets: tuple[Preset, ...] | None = None

    @classmethod
    def presets(cls) -> tuple[Preset, ...]:
        if cls._presets is None:
            cls._presets = _load_presets()
        return cls._presets

    @classmethod
    def new_simulation(cls) -> InertiaSystem:
        first = cls.presets()[0]
        system = InertiaSystem(*_unpack(first))
        system.preset = first.name
        return system

    @classmethod
    def apply_preset(cls, room: Room, name: str) -> None:
        preset = cls.preset(name)
        system: InertiaSystem = room.sim
        system.set_particles(*_unpack(preset))
        system.set_about(None)
        system.preset = name
        room.refresh()

    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: InertiaSystem = room.sim
        self.selected = 0
        self._drawn_version = -1
        self._balls: list[Any] = []
        self._mesh_node: Any = None
        self._ellipsoid: Any = None
        self.build()

    # ------------------------------------------------------------------ building
    def _build_scene(self) -> None:
        scene = self.client.scene
        root = self.root
        Stage(scene, root)
        ball = trimesh.creation.icosphere(subdivisions=1, radius=0.1)
        self.com_node = scene.add_mesh_simple(f"{root}/com", ball.vertices, ball.faces, color=(20, 20, 20))
        scene.add_label(f"{root}/com/label", "c", position=(0.13, 0.0, 0.13), font_screen_scale=1.6)
        self.O_frame = scene.add_frame(f"{root}/O", show_axes=False)
        scene.add_arrows(f"{root}/O/axes", axis_segments(np.eye(3), 1.0), np.array(BODY_AXIS_COLORS),
                         shaft_radius=0.02, head_radius=0.055, head_length=0.12)
        for k in range(3):
            scene.add_label(f"{root}/O/labels/{k}", f"e{k + 1}", position=tuple(1.15 * np.eye(3)[k]),
                            font_screen_scale=1.8, anchor="center-center")
        self.O_label = scene.add_label(f"{root}/O_label", "O", font_screen_scale=1.8, anchor="bottom-right")
        self.gizmo = scene.add_transform_controls(f"{root}/gizmo", scale=0.6, disable_rotations=True)
        self.gizmo.on_update(self._wrap("drag", lambda _event: self._dragged()))
        self.O_gizmo = scene.add_transform_controls(f"{root}/O_gizmo", scale=0.45, disable_rotations=True,
                                                    opacity=0.7)
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
            self.gui_selected = gui.add_dropdown("Mass", ("1",), initial_value="1", hint="the mass to edit and drag")
            self.gui_mass = add_slider(gui, MASS_SPEC, 1.0)
            self.gui_position = gui.add_vector3("x [m]", (0.0, 0.0, 0.0), step=0.05,
                                                min=(-COORD_LIMIT,) * 3, max=(COORD_LIMIT,) * 3)
            self.gui_add_remove = gui.add_button_group("Masses", ("Add mass", "Remove mass"))
        self.folder_O = gui.add_folder("Reference point O")
        with self.folder_O:
            self.gui_about = gui.add_vector3("O [m]", (0.0, 0.0, 0.0), step=0.05,
                                             min=(-COORD_LIMIT,) * 3, max=(COORD_LIMIT,) * 3)
            self.gui_O_at_com = gui.add_button("O at the centre of mass")
        self.folder_mesh = gui.add_folder("Solid mesh", expand_by_default=False)
        with self.folder_mesh:
            self.gui_mesh_given = gui.add_dropdown("Given", ("mass [kg]", "density [kg/m³]"),
                                                   initial_value="mass [kg]")
            self.gui_mesh_mass = gui.add_number("value", 1.0, min=0.001, max=1e5, step=0.1,
                                                hint="the mesh's mass, or its density (a uniform solid)")
            self.gui_upload = gui.add_upload_button("Upload STL / OBJ / PLY / OFF / GLB", icon=viser.Icon.UPLOAD)
        self.gui_spin = gui.add_button("Spin it", icon=viser.Icon.ROTATE_360,
                                       hint="this body, in the Free body scene")
        self.readout = Readout(gui)
        self.gui_selected.on_update(wrap("mass selector", lambda _event: self._select()))
        self.gui_mass.on_update(wrap("mass slider", lambda _event: self._mass_edited()))
        self.gui_position.on_update(wrap("position", lambda _event: self._position_edited()))
        self.gui_add_remove.on_click(wrap("add/remove", lambda event: self._add_remove(str(event.target.value))))
        self.gui_about.on_update(wrap("O", lambda _event: self._about_edited()))
        self.gui_O_at_com.on_click(wrap("O at c", lambda _event: self._set_about(None)))
        self.gui_upload.on_upload(wrap("upload", lambda _event: self._uploaded()))
        self.gui_spin.on_click(wrap("spin it", lambda _event: self.spin_it()))
        self._gui_roots = [self.gui_intro, self.message.handle, *self.presets_row.groups, self.presets_row.gui_note,
                           self.folder_masses, self.folder_O, self.folder_mesh, self.gui_spin, self.readout.handle]

    # ------------------------------------------------------------------ edits
    def _coords(self, value: Any, what: str) -> np.ndarray | None:
        try:
            x = np.array([float(v) for v in value])
        except (TypeError, ValueError):
            x = np.full(3, np.nan)
        if x.shape != (3,) or not np.all(np.isfinite(x)) or np.any(np.abs(x) > COORD_LIMIT):
            self.message.show(f"{what} = {value!r} refused: three numbers within ±{COORD_LIMIT:g} m.")
            return None
        return x

    def _select(self) -> None:
        try:
            k = int(str(self.gui_selected.value)) - 1
        except ValueError:
            k = -1
        if not 0 <= k < len(self.sim.masses):
            self.message.show(f"No mass {self.gui_selected.value!r}.")
            return
        self.selected = k
        self.refresh()

    def _mass_edited(self) -> None:
        if self.quiet.active:
            return
        value = MASS_SPEC.check(self.gui_mass.value)
        if value is None:
            self.refuse(MASS_SPEC, self.gui_mass, float(self.sim.masses[self.selected]))
            return
        masses = self.sim.masses.copy()
        masses[self.selected] = value
        self._edit(masses, self.sim.positions)

    def _position_edited(self) -> None:
        if self.quiet.active:
            return
        x = self._coords(self.gui_position.value, "x")
        if x is None:
            self.quiet.write(self.gui_position, tuple(self.sim.positions[self.selected]))
            return
        positions = self.sim.positions.copy()
        positions[self.selected] = x
        self._edit(self.sim.masses, positions)

    def _dragged(self) -> None:
        x = np.clip(np.asarray(self.gizmo.position, dtype=float), -COORD_LIMIT, COORD_LIMIT)
        positions = self.sim.positions.copy()
        positions[self.selected] = x
        self._edit(self.sim.masses, positions, from_gizmo=True)

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
        self._edit(masses, positions)

    def _edit(self, masses: Any, positions: Any, from_gizmo: bool = False) -> None:
        self.message.clear()
        self.sim.set_particles(masses, positions)
        self.sim.preset = None
        self._from_gizmo = from_gizmo
        self.room.refresh()
        self._from_gizmo = False

    def _about_edited(self) -> None:
        if self.quiet.active:
            return
        O = self._coords(self.gui_about.value, "O")
        if O is None:
            self.quiet.write(self.gui_about, tuple(self.sim.properties()["O"]))
            return
        self._set_about(O)

    def _O_dragged(self) -> None:
        O = np.clip(np.asarray(self.O_gizmo.position, dtype=float), -COORD_LIMIT, COORD_LIMIT)
        self._O_from_gizmo = True
        try:
            self._set_about(O)
        finally:
            self._O_from_gizmo = False

    def _set_about(self, O: Vec3 | None) -> None:
        self.message.clear()
        self.sim.set_about(O)
        self.room.refresh()

    def _uploaded(self) -> None:
        upload = self.gui_upload.value
        value = float(self.gui_mesh_mass.value)
        by_density = str(self.gui_mesh_given.value).startswith("density")
        try:
            vertices, faces = read_mesh(str(upload.name), bytes(upload.content))
            if by_density:
                self.sim.set_mesh(str(upload.name), vertices, faces, density=value)
            else:
                self.sim.set_mesh(str(upload.name), vertices, faces, mass=value)
        except (MeshError, ValueError) as error:
            self.message.show(f"Mesh refused: {error}. The last valid body stays.")
            return
        self.message.clear()
        self.sim.preset = None
        self.room.refresh()

    def spin_it(self) -> None:
        """Hand this body to the Free body scene: its principal moments about the centre of mass
        (ascending, along x′ y′ z′) and, for a mesh, the mesh in its principal frame."""
        from app.scenes.free_body import FreeBodyView

        properties = self.sim.properties()
        moments, axes = principal_axes(properties["I_cm"])
        scale = max(float(moments[2]), 1e-300)
        sim = FreeBodyView.new_simulation()
        sim.model = Model(inertia=(float(moments[0]), float(moments[1]), float(moments[2])))
        if self.sim.mesh is not None:
            vertices, faces = self.sim.mesh
            sim.mesh = ((vertices - properties["com"]) @ axes, faces)
        omega = np.array([0.05, 2.0 * math.sqrt(1.0 / scale) * min(1.0, scale), 0.05])  # about e2
        sim.preset = None
        sim.restart(State(np.eye(3), omega, 0.0))
        if self.open_room is None:
            raise RuntimeError("this view cannot open another scene")
        self.open_room(Room(FreeBodyView, sim))

    # ------------------------------------------------------------------ drawing
    def frame(self, dt: float) -> None:
        """Nothing moves: a frame draws only after an edit (that `refresh` already drew)."""
        if self.sim.version != self._drawn_version:
            self.refresh()

    def refresh(self) -> None:
        sim = self.sim
        self._drawn_version = sim.version
        props = sim.properties()
        with self.client.atomic():
            self._draw_bodies(props)
            O, axes, moments = props["O"], props["axes"], props["moments"]
            self.O_frame.position = tuple(O)
            self.O_frame.wxyz = wxyz_from_matrix(axes)
            self.O_label.position = tuple(O)
            self.com_node.position = tuple(props["com"])
            self._draw_ellipsoid(O, axes, moments)
            n = len(sim.masses)
            particles = sim.mesh is None
            self.folder_masses.visible = particles
            if particles:
                self.gui_selected.options = tuple(str(k + 1) for k in range(n))
                self.quiet.write(self.gui_selected, str(self.selected + 1))
                self.quiet.write(self.gui_mass, MASS_SPEC.rounded(float(sim.masses[self.selected])))
                self.quiet.write(self.gui_position, tuple(round(float(v), 4) for v in sim.positions[self.selected]))
                if not getattr(self, "_from_gizmo", False):
                    self.gizmo.position = tuple(sim.positions[self.selected])
            self.gizmo.visible = particles
            self.quiet.write(self.gui_about, tuple(round(float(v), 4) for v in O))
            if not getattr(self, "_O_from_gizmo", False):
                self.O_gizmo.position = (float(O[0]), float(O[1]), float(O[2]))
            self.presets_row.show_note(self.preset_shown())
            self._refresh_readout(props)

    def _draw_bodies(self, props: dict[str, Any]) -> None:
        scene, sim = self.client.scene, self.sim
        if sim.mesh is not None:
            for ball in self._balls:
                ball.visible = False
            if self._mesh_node is None or getattr(self, "_mesh_drawn", None) is not sim.mesh:
                if self._mesh_node is not None:
                    self._mesh_node.remove()
                vertices, faces = sim.mesh
                self._mesh_node = scene.add_mesh_simple(f"{self.root}/mesh", vertices, faces, color=(150, 170, 210),
                                                        opacity=0.6, flat_shading=True)
                self._mesh_drawn = sim.mesh
            return
        if self._mesh_node is not None:
            self._mesh_node.remove()
            self._mesh_node = None
        while len(self._balls) < len(sim.masses):
            k = len(self._balls)
            sphere = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
            self._balls.append(scene.add_mesh_simple(f"{self.root}/masses/{k}", sphere.vertices, sphere.faces,
                                                     color=(230, 120, 40)))
        for k, ball in enumerate(self._balls):
            shown = k < len(sim.masses)
            if ball.visible != shown:
                ball.visible = shown
            if shown:
                ball.position = tuple(sim.positions[k])
                ball.scale = BALL_RADIUS * float(sim.masses[k]) ** (1.0 / 3.0)
                ball.color = (200, 60, 20) if k == self.selected else (230, 150, 60)

    def _draw_ellipsoid(self, O: Vec3, axes: Mat3, moments: Vec3) -> None:
        """The momental ellipsoid at O: a unit sphere built once, posed by the principal axes and
        scaled by the semi-axes ∝ 1/√I_k (the largest ELLIPSOID_SIZE)."""
        if self._ellipsoid is None:
            sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
            self._ellipsoid = self.client.scene.add_mesh_simple(
                f"{self.root}/ellipsoid", sphere.vertices, sphere.faces, color=(90, 140, 230), opacity=0.25,
                cast_shadow=False, receive_shadow=False)
        positive = np.maximum(np.asarray(moments, dtype=float), 1e-12 * max(float(moments[2]), 1e-300))
        semi = 1.0 / np.sqrt(positive)
        semi = np.maximum(ELLIPSOID_SIZE * semi / semi.max(), 0.01)
        self._ellipsoid.position = tuple(float(v) for v in O)
        self._ellipsoid.wxyz = wxyz_from_matrix(axes)
        self._ellipsoid.scale = (float(semi[0]), float(semi[1]), float(semi[2]))

    def _refresh_readout(self, props: dict[str, Any]) -> None:
        sim = self.sim
        O, d = props["O"], props["d"]
        what = (f"a uniform solid **{sim.mesh_name}**, m = {props['mass']:.4g} kg" if sim.mesh is not None
                else f"**{len(sim.masses)} point masses**, m = {props['mass']:.4g} kg")
        lines = [what + f", centre of mass c = ({', '.join(f'{v:.3f}' for v in props['com'])}) m"]
        lines.append(f"O = ({', '.join(f'{v:.3f}' for v in O)}) m"
                     + (" = c" if not np.any(d) else ""))
        text = "  \n".join(lines) + "\n\n**I_O** [kg m²]\n```\n" + format_matrix(props["I_O"], 4) + "\n```\n"
        if np.any(d):
            text += ("**I_cm** [kg m²] + **m(|d|²𝟙 − d dᵀ)**, d = c − O\n```\n" + format_matrix(props["I_cm"], 4)
                     + "\n+\n" + format_matrix(props["parallel"], 4) + "\n```\n")
        moments = props["moments"]
        text += ("Principal moments I1 ≤ I2 ≤ I3 = " + ", ".join(f"{m:.5g}" for m in moments) + " kg m²  \n"
                 "axes e1 e2 e3 (columns, right-handed)\n```\n" + format_matrix(props["axes"], 4) + "\n```\n")
        for note in props["notes"]:
            text += note + "  \n"
        self.readout.set(text)
