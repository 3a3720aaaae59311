"""The Inertia scene's view: the inertia tensor of a system of particles, or of a solid mesh (memo §3).

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

The simulation (`app.scenes.inertia.simulation.InertiaSystem`, no viser) has no motion:
`advance` only counts time; every edit bumps `version`.  The readout's texts are
`app.scenes.inertia.readouts`, the "Solid mesh" folder `app.scenes.inertia.mesh_panel`.
Presets: `assets/presets/inertia.json`, read by `load_inertia_presets` (each entry has `masses`
and `positions` instead of the kit's params/angles/rates).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import trimesh
import viser

from app.i18n import N_, Said, Translator, refusal_text
from app.kit.core.common import BODY_AXIS_COLORS, CameraView, Wrap, axis_segments
from app.kit.core.key_number import KeyNumber
from app.kit.core.presets import PRESETS_DIR, Preset
from app.kit.core.room import Room
from app.kit.draw.labels import AXES, KEY
from app.kit.draw.widgets import Stage
from app.kit.panel.binding import Refused
from app.kit.panel.gui import MessageLine, PresetsRow, Readout, add_slider
from app.kit.view import SceneView
from app.scenes.inertia import readouts
from app.scenes.inertia.mesh_panel import MeshPanel
from app.scenes.inertia.simulation import (
    COORD_LIMIT,
    MASS_SPEC,
    MAX_MASSES,
    InertiaSystem,
    load_inertia_presets,
    spin_moments,
)
from physics._types import Mat3, Vec3
from physics.dynamics import Model, State
from physics.euler import matrix_from_euler_zxz
from physics.inertia import InertiaError, principal_axes
from physics.quaternion import wxyz_from_matrix

__all__ = ["BALL_RADIUS", "ELLIPSOID_CUT", "ELLIPSOID_SIZE", "InertiaView"]

BALL_RADIUS = 0.12  # [m] drawn radius of a 1 kg ball (∝ m^(1/3))
ELLIPSOID_SIZE = 1.2  # [scene units] the momental ellipsoid's largest drawn semi-axis
ELLIPSOID_CUT = 4.0  # a semi-axis longer than this times the shortest is drawn cut at it
SPIN_SCENE = "Free body"  # "Spin it" hands the body to this scene (by its title: no scene imports another)
SPIN_RATE = 4.0  # [rad/s] "Spin it": about the intermediate axis e2, with a small wobble
SPIN_ANGLES_DEG = (-30.0, 60.0, 0.0)  # "Spin it": the attitude it starts from (as the Dzhanibekov preset)


def _shown(x: Any) -> tuple[float, float, float]:
    """A point [m] as a vector field shows it (4 decimals, no -0.0)."""
    a, b, c = (round(float(v), 4) + 0.0 for v in x)
    return a, b, c


def _unpack(preset: Preset) -> tuple[list[float], np.ndarray]:
    n = len(preset.params) // 4
    return list(preset.params[:n]), np.asarray(preset.params[n:], dtype=float).reshape(n, 3)


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

    title = N_("Inertia")  # the scene dropdown shows it translated (app.i18n)
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
        self.mesh_panel = MeshPanel(self, self.sim)  # the "Solid mesh" folder, built with the panel
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
        # The gizmos are interactive: only in the controlling browser's own scene (app.kit.core.target).
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
        tr = self.tr
        _ = tr.gettext
        self.mass_spec = MASS_SPEC.translated(tr)
        self.gui_intro = gui.add_markdown(_(
            "### Inertia tensor (memo §3)\n"
            "**I_O = Σ mᵢ (|xᵢ|² 𝟙 − xᵢ xᵢᵀ)** (3.5), xᵢ from O; principal axes e1 e2 e3 "
            "(moments ascending) at O; the momental ellipsoid has semi-axes ∝ 1/√I_k."))
        self.message = MessageLine(gui)
        self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset, self.choose_own_preset, tr=tr)
        self.folder_masses = gui.add_folder(_("Point masses"))
        with self.folder_masses:
            self.gui_selected = gui.add_dropdown(_("Mass"), ("1",), initial_value="1",
                                                 hint=_("the mass to weigh and move (or click its ball); "
                                                        "drag it with the large gizmo"))
            self.gui_mass = add_slider(gui, self.mass_spec, 1.0)
            self.gui_position = gui.add_vector3("x [m]", (0.0, 0.0, 0.0), step=0.05,
                                                min=(-COORD_LIMIT,) * 3, max=(COORD_LIMIT,) * 3)
            self.gui_add_remove = gui.add_button_group(_("Masses"), (_("Add mass"), _("Remove mass")))
        self.folder_O = gui.add_folder(_("Reference point O"))
        with self.folder_O:
            self.gui_about = gui.add_vector3("O [m]", (0.0, 0.0, 0.0), step=0.05,
                                             min=(-COORD_LIMIT,) * 3, max=(COORD_LIMIT,) * 3,
                                             hint=_("or drag the small gizmo at O"))
            self.gui_O_at_com = gui.add_button(_("O at the centre of mass"))
        self.folder_mesh = self.mesh_panel.build()
        self.gui_spin = gui.add_button(_("Spin it"), icon=viser.Icon.ROTATE_360,
                                       hint=_("this body, in the Free body scene"))
        self.folder_readout = gui.add_folder(_("Readout"))
        with self.folder_readout:
            self.readout = Readout(gui)
        self.gui_selected.on_update(wrap("mass selector", lambda _event: self._select(self.gui_selected.value)))
        self.bind(self.gui_mass, "mass slider", self._mass_edited, lambda: float(self.sim.masses[self.selected]),
                  spec=self.mass_spec)
        self.bind(self.gui_position, "position", self._position_edited,
                  lambda: _shown(self.sim.positions[self.selected]), check=lambda value: self._coords(value, "x"))
        self.gui_add_remove.on_click(wrap("add/remove",
                                          lambda event: self._add_remove(
                                              tr.english(str(event.target.value), ("Add mass", "Remove mass")))))
        self.bind(self.gui_about, "O", self._set_about, lambda: _shown(self.sim.properties()["O"]),
                  check=lambda value: self._coords(value, "O"))
        self.gui_O_at_com.on_click(wrap("O at c", lambda _event: self._set_about(None)))
        self.mesh_panel.connect(wrap)
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
            raise Refused(self.tr.gettext("{what} = {value} refused: three numbers within ±{limit} m.").format(
                what=what, value=repr(value), limit=self.tr.general(COORD_LIMIT)))
        return x

    def _select(self, value: Any) -> None:
        try:
            k = int(str(value)) - 1
        except ValueError:
            k = -1
        if self.sim.mesh is not None or not 0 <= k < len(self.sim.masses):
            self.message.show(Said(N_("No mass {value}."), value=repr(value)))
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
            self.message.show(Said(N_("{what} dragged to {position}: refused, not a point."),
                                   what=what, position=repr(handle.position)))
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
                self.message.show(Said(N_("At most {n} masses."), n=MAX_MASSES))
                return
            masses.append(1.0)
            positions.append(np.array([0.5, 0.5, 0.5]))
            self.selected = len(masses) - 1
        elif choice == "Remove mass":
            if len(masses) <= 1:
                self.message.show(Said(N_("At least one mass.")))
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

    def spin_it(self) -> None:
        """Hand this body to the Free body scene: its principal moments about the centre of mass
        (ascending, along x′ y′ z′; scaled to the scene's sliders if needed, said there) and, for
        a mesh, the mesh in its principal frame (x′ = Rᵀ (x − c))."""
        properties = self.sim.properties()
        moments, axes = principal_axes(properties["I_cm"])
        try:
            handed, k = spin_moments(moments)
        except InertiaError as error:
            def nothing_to_spin(tr: Translator, error: InertiaError = error) -> str:
                """The refusal in `tr`'s language (said again when the browser changes language)."""
                return tr.gettext(N_("Nothing to spin: {reason} — masses on one line are no rigid body "
                                     "to spin (add a mass off the line).")).format(reason=refusal_text(error, tr))

            self.message.show(nothing_to_spin)
            return
        if self.open_scene is None:
            self.message.show(Said(N_("This browser cannot open another scene.")))
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
        room.notify(readouts.spin_text(what, moments, k))

    def key_numbers(self) -> list[KeyNumber]:
        """For the followers' panel: the body (masses, or the mesh and its mass) and its
        principal moments about O."""
        sim = self.sim
        if sim.mesh is not None:
            return readouts.key_numbers_of(sim.properties(), mesh_name=sim.mesh_name)
        return readouts.key_numbers_of(sim.properties(), masses=sim.masses)

    def gizmo_handles(self) -> list[Any]:
        """The mass's and O's drag gizmos (only in the controlling browser)."""
        return [g for g in (self.gizmo, self.O_gizmo) if g is not None]

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
                self.gizmo.visible = particles and not self.gizmos_hidden
            if self.O_gizmo is not None and self.O_gizmo.visible == self.gizmos_hidden:
                self.O_gizmo.visible = not self.gizmos_hidden
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
        if sim.mesh is not None:
            self.readout.set(readouts.readout_text(props, k, mesh_name=sim.mesh_name, tr=self.tr))
        else:
            self.readout.set(readouts.readout_text(props, k, masses=len(sim.masses), tr=self.tr))
