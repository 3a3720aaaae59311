"""The Inertia scene's "Solid mesh" folder (`MeshPanel`, owned by the view): a mesh file uploaded
or one of assets/meshes/ (MESHES_DIR) picked, given a mass [kg] or a density [kg/m³], becomes the
system's body.

A file is read and checked by `app.scenes.inertia.simulation.read_mesh` (size, type, readable,
faces) and `InertiaSystem.set_mesh` (a closed, outward-oriented solid, its mass or density in
range); a refused one is named with its reason in the view's message line and the last valid
body stays.  The number box shows the mesh's mass or density (6 significant digits), or a
default (1 kg, 1000 kg/m³) while there is no mesh; a value typed there reweighs the mesh shown.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import viser

from app.data import files_in, meshes_dir
from app.i18n import N_, Said, Translator, refusal_text
from app.kit.core.common import Wrap, checked_value
from app.kit.panel.binding import Refused
from app.kit.view import SceneView
from app.scenes.inertia.simulation import (
    MAX_FACES,
    MAX_UPLOAD_BYTES,
    MESH_DENSITY_RANGE,
    MESH_MASS_RANGE,
    InertiaSystem,
    read_mesh,
)
from physics.inertia import MeshError

__all__ = ["MESHES_DIR", "MeshPanel"]

MESHES_DIR = meshes_dir()  # the shipped meshes (app.data: the checkout's or the installed ones)
SHIPPED_NAMES = (N_("book"), N_("phone"), N_("racket"), N_("t-handle"), N_("top"))
"""The shipped meshes' names (their files' stems), marked: a button shows its name translated."""
MASS_LABEL, DENSITY_LABEL = N_("mass [kg]"), N_("density [kg/m³]")


class MeshPanel:
    """The "Solid mesh" folder of one Inertia view: `build` adds it to the view's panel (where
    the view calls it), `connect` binds its controls; edits go to `sim` and refresh the room."""

    def __init__(self, view: SceneView, sim: InertiaSystem) -> None:
        self.view = view
        self.sim = sim

    def build(self) -> Any:
        """The folder (collapsed): given mass or density, the number box, the upload button and
        one button per shipped mesh; returns the folder."""
        gui = self.view.client.gui
        tr = self.view.tr
        _ = tr.gettext
        self.mass_label, self.density_label = _(MASS_LABEL), _(DENSITY_LABEL)
        self.folder = gui.add_folder(_("Solid mesh"), expand_by_default=False)
        with self.folder:
            self.gui_given = gui.add_dropdown(_("Given"), (self.mass_label, self.density_label),
                                              initial_value=self.mass_label)
            self.gui_amount = gui.add_number(self.mass_label, 1.0, min=MESH_MASS_RANGE[0], max=MESH_DENSITY_RANGE[1],
                                             step=0.001)
            self.gui_upload = gui.add_upload_button(_("Upload STL / OBJ / PLY / OFF / GLB"), icon=viser.Icon.UPLOAD,
                                                    hint=_("a closed, outward-oriented triangle mesh, in metres; "
                                                           "up to {mib} MiB and {faces} faces").format(
                                                        mib=MAX_UPLOAD_BYTES // 2**20, faces=MAX_FACES))
            self.shipped = {path.name.removesuffix(".stl").replace("_", "-"): path
                            for path in files_in(MESHES_DIR, ".stl")}
            self.shipped_labels = {_(name): name for name in self.shipped}  # a button's label -> the mesh's name
            self.gui_shipped = gui.add_button_group(_("Shipped"), tuple(self.shipped_labels)) if self.shipped \
                else None
        return self.folder

    def connect(self, wrap: Wrap) -> None:
        """The controls' callbacks, each through the session's guard `wrap`."""
        self.gui_given.on_update(wrap("mesh weighed by", lambda _event: self._given_changed()))
        self.view.bind(self.gui_amount, "mesh mass", self._amount_edited, self._amount_shown,
                       check=self._check_amount)
        self.gui_upload.on_upload(wrap("upload", lambda _event: self._uploaded()))
        if self.gui_shipped is not None:
            self.gui_shipped.on_click(wrap("shipped mesh", lambda event: self.load_shipped(
                self.shipped_labels.get(str(event.target.value), str(event.target.value)))))

    # ------------------------------------------------------------------ mass or density
    def _weight(self) -> dict[str, float]:
        """{"mass": …} or {"density": …} from the panel (checked by InertiaSystem)."""
        try:
            value = float(self.gui_amount.value)
        except (TypeError, ValueError):
            value = math.nan
        return {"density": value} if self._by_density() else {"mass": value}

    def _given_changed(self) -> None:
        """Mass or density: the number box shows the current mesh's (nothing changes), or a
        default (1 kg, 1000 kg/m³) while there is no mesh."""
        self.gui_amount.label = self.density_label if self._by_density() else self.mass_label
        self.view.quiet.write(self.gui_amount, self._amount_shown())

    def _by_density(self) -> bool:
        return str(self.gui_given.value) in (self.density_label, DENSITY_LABEL)

    def _amount_shown(self) -> float:
        """What the mass / density box shows: the mesh's (6 significant digits), or the default."""
        sim, by_density = self.sim, self._by_density()
        if sim.mesh is None:
            return 1000.0 if by_density else 1.0
        value = sim.mesh_mass / sim.mesh_volume() if by_density else sim.mesh_mass
        return float(f"{value:.6g}")

    def _check_amount(self, value: Any) -> float:
        """A mass [kg] or density [kg/m³] in its range (MESH_MASS_RANGE, MESH_DENSITY_RANGE)."""
        by_density = self._by_density()
        _ = self.view.tr.gettext
        (lo, hi), what = (MESH_DENSITY_RANGE, _("density")) if by_density else (MESH_MASS_RANGE, _("mass"))
        number = checked_value(value, lo, hi)
        if number is None:
            kept = (" " + _("The mesh keeps its {mass} kg.").format(mass=f"{self.sim.mesh_mass:.4g}")
                    if self.sim.mesh is not None else "")
            unit = "kg/m³" if by_density else "kg"
            raise Refused(_("Refused: {what} {value} {unit}: a number from {lo} to {hi} wanted.").format(
                what=what, value=repr(value), unit=unit, lo=self.view.tr.general(lo), hi=self.view.tr.general(hi))
                + kept)
        return number

    def _amount_edited(self, value: float) -> str | None:
        """A new mass or density for the mesh shown (kept for the next mesh while there is none)."""
        if self.sim.mesh is None:
            return None
        try:
            self.sim.weigh_mesh(**({"density": value} if self._by_density() else {"mass": value}))
        except ValueError as error:
            return self.view.tr.gettext("Refused: {reason}. The mesh keeps its {mass} kg.").format(
                reason=refusal_text(error, self.view.tr), mass=f"{self.sim.mesh_mass:.4g}")
        self.view.room.refresh()
        return None

    # ------------------------------------------------------------------ files
    def _uploaded(self) -> None:
        upload = self.gui_upload.value
        self.load_mesh(str(upload.name), bytes(upload.content))

    def load_shipped(self, name: str) -> None:
        """One of the meshes of assets/meshes/ (a button; a client can send any name)."""
        path = self.shipped.get(name)
        if path is None:
            self.view.message.show(Said(N_("No shipped mesh named {name}."), name=repr(name)))
            return
        self.load_mesh(path.name, path.read_bytes())

    def load_mesh(self, name: str, content: bytes) -> None:
        """Read, check and show a mesh file; refused with the reason, the last valid body staying."""
        message = self.view.message
        try:
            vertices, faces = read_mesh(name, content)
            self.sim.set_mesh(name, vertices, faces, **self._weight())
        except (MeshError, ValueError) as error:
            message.show(functools.partial(mesh_refused, name, error))
            return
        message.clear()
        self.sim.set_about(None)
        self.sim.preset = None
        self.view.room.refresh()


def mesh_refused(name: str, error: Exception, tr: Translator) -> str:
    """The message on a refused mesh file `name` in `tr`'s language: `error`'s reason, named by the file."""
    words = refusal_text(error, tr)
    text = words if words.startswith(name) else f"{name}: {words}"
    return tr.gettext(N_("Mesh refused: {reason}. The last valid body stays.")).format(reason=text)
