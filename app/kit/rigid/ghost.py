"""The exact ghost of a rigid-body view: a translucent second body at the exact solution.

Display: "Exact ghost" (off by default) builds, the first time, a second `Body` of the same
shape drawn translucent (`Translucent`), posed at the exact solution's attitude while the
chosen integrator turns the solid one; "Exaggerate error ×k" draws it at
R_ghost = R_exact exp(k log(R_exactᵀ R)) (`app.kit.rigid.simulation.magnified_attitude`): k = 0 is the exact
solution, k = 1 lies on the solid body, k = 10⁶ turns a 1e-7 rad drift into 0.1 rad.  Off, it
costs nothing: neither evaluated nor sent.  Its note (`app.kit.rigid.text.ghost_note`) reads the
attitude error out.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from app.i18n import DEFAULT_LANGUAGE, N_, Said, Translator, translator
from app.kit.core.common import Wrap
from app.kit.draw.labels import LabelLayer
from app.kit.draw.widgets import Body
from app.kit.panel.gui import MessageLine, Quiet
from app.kit.rigid.simulation import RigidBodySimulation, magnified_attitude
from app.kit.rigid.text import ghost_note
from physics.dynamics import Model

ENGLISH = translator(DEFAULT_LANGUAGE)

__all__ = ["GHOST_K_OPTIONS", "GHOST_OPACITY", "ExactGhost", "Translucent"]

GHOST_OPACITY = 0.3
GHOST_K_OPTIONS = {N_("0 (exact)"): 0.0, N_("1 (= solid)"): 1.0, "10": 10.0, "100": 100.0, "10³": 1e3, "10⁴": 1e4,
                   "10⁵": 1e5, "10⁶": 1e6}
"""The ghost's error magnifications k (English dropdown label -> k; shown translated)."""

Shape = Callable[[Any, str, Model], None]
"""build_shape(scene, parent, model): add a body's shape nodes under `parent`."""


class Translucent:
    """A scene API whose meshes are drawn translucent (the ghost's shape, built by the same
    `build_shape` as the solid body's)."""

    def __init__(self, scene: Any, opacity: float) -> None:
        self._scene = scene
        self._opacity = opacity

    def __getattr__(self, name: str) -> Any:
        return getattr(self._scene, name)

    def _translucent(self, kwargs: dict[str, Any]) -> dict[str, Any]:
        return {**kwargs, "opacity": min(float(kwargs.get("opacity", 1.0)), self._opacity)}

    def add_mesh_simple(self, *args: Any, **kwargs: Any) -> Any:
        return self._scene.add_mesh_simple(*args, **self._translucent(kwargs))

    def add_icosphere(self, *args: Any, **kwargs: Any) -> Any:
        return self._scene.add_icosphere(*args, **self._translucent(kwargs))

    def add_box(self, *args: Any, **kwargs: Any) -> Any:
        return self._scene.add_box(*args, **self._translucent(kwargs))

    def add_mesh_trimesh(self, name: str, mesh: Any, **kwargs: Any) -> Any:
        mesh = mesh.copy()
        mesh.visual.face_colors = (*mesh.visual.face_colors[0, :3], int(255 * self._opacity))
        return self._scene.add_mesh_trimesh(name, mesh, **kwargs)


class ExactGhost:
    """The ghost's panel (a checkbox, the ×k dropdown, a note) and its body (built on first use).

    scene, root: where the body goes (`{root}/ghost`); shape: the scene's `build_shape`;
    sim: the simulation; on_change: redraw the room (after the toggle or k changed).
    """

    def __init__(self, gui: Any, wrap: Wrap, message: MessageLine, quiet: Quiet, *, scene: Any, root: str,
                 shape: Shape, axis_length: float, sim: RigidBodySimulation,
                 on_change: Callable[[], None], labels: LabelLayer | None = None,
                 tr: Translator = ENGLISH) -> None:
        self._scene, self._root, self._shape, self._axis_length = scene, root, shape, axis_length
        self._labels = labels  # the view's LabelLayer (the ghost's axis labels stay hidden with its axes)
        self.sim = sim
        self._message, self._quiet, self._on_change = message, quiet, on_change
        self.body: Body | None = None
        self._model: Model | None = None
        self.k = 0.0
        self._tr = tr
        _ = tr.gettext
        self._options = {_(name): value for name, value in GHOST_K_OPTIONS.items()}  # shown label -> k
        self.gui_toggle = gui.add_checkbox(_("Exact ghost"), False,
                                           hint=_("a translucent copy at the exact solution's attitude"))
        self.gui_k = gui.add_dropdown(
            _("Exaggerate error ×k"), tuple(self._options), initial_value=next(iter(self._options)),
            visible=False, hint=_("ghost at R_exact·exp(k·log(R_exactᵀR)): k = 0 exact, k = 1 on the solid body"))
        self.gui_note = gui.add_markdown("", visible=False)
        self.gui_toggle.on_update(wrap("exact ghost", self._toggled))
        self.gui_k.on_update(wrap("ghost magnification", self._k_chosen))

    @property
    def shown(self) -> bool:
        return bool(self.gui_toggle.value)

    def set(self, on: bool) -> None:
        """Show or hide the ghost (what the checkbox does)."""
        if on and self.body is None:
            model = self.sim.model
            self.body = Body(Translucent(self._scene, GHOST_OPACITY), f"{self._root}/ghost",
                             lambda scene, parent: self._shape(scene, parent, model),
                             axis_length=self._axis_length, show_axes=False, labels=self._labels)
            self._model = model
        self._quiet.write(self.gui_toggle, bool(on))
        self.gui_k.visible = bool(on)
        if self.body is not None:
            self.body.node.visible = bool(on)
        self._on_change()

    def set_k(self, k: float) -> None:
        """The error magnification k (one of GHOST_K_OPTIONS' values; ValueError otherwise)."""
        label = next((name for name, value in self._options.items() if value == k), None)
        if label is None:
            raise ValueError(f"k = {k!r} is not one of {sorted(GHOST_K_OPTIONS.values())}")
        self.k = float(k)
        self._quiet.write(self.gui_k, label)
        self._on_change()

    def _toggled(self, _event: Any) -> None:
        if self._quiet.active:
            return
        value = self.gui_toggle.value
        if not isinstance(value, bool):  # a client can send anything
            self._message.show(Said(N_("Exact ghost = {value} refused: on or off."), value=repr(value)))
            self._quiet.write(self.gui_toggle, self.body is not None and bool(self.body.node.visible))
            return
        self.set(value)

    def _k_chosen(self, _event: Any) -> None:
        if self._quiet.active:
            return
        label = self.gui_k.value
        if label not in self._options:
            self._message.show(Said(N_("Magnification {label} refused: choose one of {options}."),
                                    label=repr(label), options=", ".join(self._options)))
            self.set_k(self.k)
            return
        self.set_k(self._options[label])

    def reshape(self, model: Model) -> None:
        """A new body: the ghost takes its shape (if it was built)."""
        if self.body is not None and model != self._model:
            self.body.reshape(lambda scene, parent: self._shape(scene, parent, model))
            self._model = model

    def draw(self, quantum: float | None = None) -> None:
        """Pose the ghost at the exact attitude, turned by k times the error (hidden without a
        closed form), at the resolution `quantum` (`app.kit.draw.widgets.POSE_QUANTUM`; None:
        exact); nothing while it is off."""
        if not self.shown or self.body is None:
            return
        R_exact = self.sim.exact_attitude()
        visible = R_exact is not None
        if bool(self.body.node.visible) != visible:
            self.body.node.visible = visible
        if R_exact is not None:
            R = self.sim.state.R_space_body
            self.body.pose(R_exact if self.k == 0.0 else magnified_attitude(R_exact, R, self.k), quantum)

    def refresh_note(self) -> None:
        shown = self.shown
        if self.gui_note.visible != shown:
            self.gui_note.visible = shown
        if not shown:
            return
        label = next(name for name, value in self._options.items() if value == self.k)
        text = ghost_note(self.sim, self.k, label, self._tr)
        if self.gui_note.content != text:
            self.gui_note.content = text
