"""The gallery of a State question: every submitted body drawn faint at once, or one at a time,
and the one chosen played in the presenter's room.  Anonymous: answers are numbered 1, 2, ... in
the order they first arrived, never named.

* `Gallery(scene)` draws into a scene (the lecture hall's shared scene, `server.scene`: the
  presenter, the followers and the projector see it; drawings only, no handle a browser could
  move).  All the bodies are ONE batched mesh node (`add_batched_meshes_simple`: one message
  for N attitudes, one draw call in the browser), superposed where the scene's body stands
  (the origin: the top's pivot, the free body's centre of mass), so the spread of the answers
  is what the eye reads.  Its arrays change only when answers change or another is chosen,
  at most every REDRAW_PERIOD (`tick`): nothing is sent per frame.
* Modes: ALL (every body faint, ALL_OPACITY) and ONE (the chosen one in CHOSEN_COLOR, the others
  fainter still, ONE_OTHERS_OPACITY); `next` / `previous` walk the answers (and switch to ONE),
  `show_all` goes back.  `words()` is the panel's line ("Answer 3 of 12: loops").
* The glyph is the scene's body in outline: the heavy top a rod and a disc from the pivot
  (TOP_ROD, TOP_DISC_*), a body with moments of inertia the box of uniform density that has them
  (`box_extents`), otherwise a 1.2 × 0.8 × 0.4 box.
* `play_answer(room, answer)` restarts the room's simulation from the answer (its model's moments
  and mgl, attitude, ω_b) at t = 0 and plays: the projector shows it moving.  A body the scene's
  sliders could not set (a parameter outside its range, I1 ≠ I2 for the heavy top) is refused
  with a message and changes nothing.

`GalleryPanel(gui, gallery, play)` is the presenter's folder: the line, one row `Previous`
`Next` `All`, and `Play this answer`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

from app.ask.judges import AnswerState
from app.ask.verdict_words import verdict_in_language
from app.i18n import N_, Labels, Translator, for_gui, translator
from physics.dynamics import Model, State
from physics.euler import euler_zxz_from_matrix

__all__ = ["ALL", "GALLERY_ROOT", "ONE", "Gallery", "GalleryEntry", "GalleryPanel", "box_extents", "play_answer"]

GALLERY_ROOT = "/ask_gallery"
ALL, ONE = "all", "one"
ALL_OPACITY = 0.28  # each body's opacity when all are shown
ONE_OTHERS_OPACITY = 0.06  # the others' while one is chosen
CHOSEN_OPACITY = 0.95
FAINT_COLOR = (70, 120, 230)
CHOSEN_COLOR = (245, 140, 20)
REDRAW_PERIOD = 0.25  # [s] of wall time: the gallery's arrays are sent at most this often
TOP_ROD = (0.03, 1.3)  # the top glyph's rod: radius, length along z′ from the pivot [scene units]
TOP_DISC_RADIUS, TOP_DISC_CENTER, TOP_DISC_THICKNESS = 0.45, 0.85, 0.1
DEFAULT_BOX = (1.2, 0.8, 0.4)


@dataclasses.dataclass(frozen=True)
class GalleryEntry:
    """One anonymous answer: number (1, 2, ... in arrival order), the body, the judged value and
    the verdict ("" where the question has no judge)."""

    number: int
    answer: AnswerState
    value: float | str | None = None
    verdict: str = ""


def _signature(entry: GalleryEntry) -> tuple[Any, ...]:
    """An entry as plain comparable values (its arrays as bytes)."""
    answer = entry.answer
    return (entry.number, entry.value, entry.verdict, answer.scene, answer.R_space_body.tobytes(),
            answer.omega_body.tobytes(), answer.inertia, answer.mgl)


def box_extents(inertia: Sequence[float], size: float = 1.2) -> tuple[float, float, float]:
    """Edge lengths (a, b, c) of the uniform box whose principal moments have the ratios of
    `inertia` (I1 ∝ b² + c², ...), scaled so the longest edge is `size`; a moment set no box has
    (a flat lamina's limit) gets a thin edge of 2 % of `size`."""
    I1, I2, I3 = (float(m) for m in inertia)
    squares = np.array([I2 + I3 - I1, I1 + I3 - I2, I1 + I2 - I3])  # ∝ a², b², c²
    edges = np.sqrt(np.maximum(squares, 0.0))
    if not np.all(np.isfinite(edges)) or edges.max() <= 0.0:
        return DEFAULT_BOX
    edges = np.maximum(edges / edges.max(), 0.02) * size
    return float(edges[0]), float(edges[1]), float(edges[2])


def _glyph(answer: AnswerState) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3) float32, faces (F, 3) uint32) of the answer's body in body coordinates."""
    if answer.mgl != 0.0:
        rod = trimesh.creation.cylinder(radius=TOP_ROD[0], height=TOP_ROD[1], sections=8)
        rod.apply_translation((0.0, 0.0, 0.5 * TOP_ROD[1]))
        disc = trimesh.creation.cylinder(radius=TOP_DISC_RADIUS, height=TOP_DISC_THICKNESS, sections=24)
        disc.apply_translation((0.0, 0.0, TOP_DISC_CENTER))
        vertices = np.concatenate([rod.vertices, disc.vertices])
        faces = np.concatenate([rod.faces, disc.faces + len(rod.vertices)])
    else:
        extents = box_extents(answer.inertia) if answer.inertia is not None else DEFAULT_BOX
        box = trimesh.creation.box(extents=extents)
        vertices, faces = box.vertices, box.faces
    return np.asarray(vertices, dtype=np.float32), np.asarray(faces, dtype=np.uint32)


class Gallery:
    """The submitted bodies in one scene (module docstring).  Its one node is made when the
    gallery is (hidden): a node made inside the app loop's frame holds back that frame's panel
    updates for the browser (`app.wire`), so drawing only sets the node's arrays and shows it.
    Not thread-safe on its own: the caller holds the lock of the round it draws."""

    def __init__(self, scene: Any, root: str = GALLERY_ROOT, clock: Callable[[], float] = time.monotonic) -> None:
        self.scene = scene
        self.root = root
        self.clock = clock
        self.entries: tuple[GalleryEntry, ...] = ()
        self._signature: tuple[tuple[Any, ...], ...] = ()  # what `entries` holds, comparable
        self.mode = ALL
        self.index = 0
        self.visible = True
        self._glyph_key: tuple[Any, ...] = ("top",)
        vertices, faces = _glyph(AnswerState("", np.eye(3), np.zeros(3), (1.0, 1.0, 0.5), 1.0))
        self._node: Any = scene.add_batched_meshes_simple(
            f"{root}/bodies", vertices, faces, batched_wxyzs=np.array([[1.0, 0.0, 0.0, 0.0]], np.float32),
            batched_positions=np.zeros((1, 3), np.float32), batched_colors=np.array([FAINT_COLOR], np.uint8),
            batched_opacities=np.array([ALL_OPACITY], np.float32), opacity=1.0, lod="off", cast_shadow=False,
            receive_shadow=False, flat_shading=True, visible=False)
        self._shown = False
        self._dirty = False
        self._drawn_at = -math.inf
        self.sends = 0  # how many times the node's arrays went out (for tests and measurements)

    # ------------------------------------------------------------------ what is shown
    def set_entries(self, entries: Sequence[GalleryEntry]) -> None:
        """The answers now (drawn at the next `tick`); the chosen answer stays chosen by its number."""
        entries = tuple(entries)
        signature = tuple(_signature(entry) for entry in entries)
        if signature == self._signature:
            return
        chosen = self.chosen
        self.entries = entries
        self._signature = signature
        if chosen is not None:
            numbers = [entry.number for entry in self.entries]
            self.index = numbers.index(chosen.number) if chosen.number in numbers else 0
        self.index = min(self.index, max(len(self.entries) - 1, 0))
        self._dirty = True

    @property
    def chosen(self) -> GalleryEntry | None:
        """The answer shown alone (ONE), or None (ALL, or no answers)."""
        if self.mode != ONE or not self.entries:
            return None
        return self.entries[self.index]

    def show_all(self) -> None:
        self.mode = ALL
        self.visible = True
        self.draw()

    def show_one(self, index: int) -> None:
        """Show the answer at `index` (0-based, taken modulo the count) alone."""
        if not self.entries:
            self.mode = ALL
            return
        self.mode = ONE
        self.visible = True
        self.index = index % len(self.entries)
        self.draw()

    def next(self) -> None:
        self.show_one(self.index + 1 if self.mode == ONE else 0)

    def previous(self) -> None:
        self.show_one(self.index - 1 if self.mode == ONE else -1)

    def hide(self) -> None:
        self.visible = False
        self.draw()

    def words(self, tr: Translator | None = None) -> str:
        """The panel's line about what is shown, in `tr`'s language (English by default; a
        judge's class and verdict written in it too)."""
        tr = tr or translator("en")
        count = len(self.entries)
        if count == 0:
            return tr.gettext("No answers yet.")
        chosen = self.chosen
        if chosen is None:
            return tr.ngettext("{count} answer drawn faint at once.", "{count} answers drawn faint at once.",
                               count).format(count=count)
        value = chosen.value
        judged = tr.gettext(value) if isinstance(value, str) else verdict_in_language(chosen.verdict, tr)
        said = f": {judged}" if chosen.verdict else ""
        return tr.gettext("Answer {number} of {count}").format(number=chosen.number, count=count) + said

    # ------------------------------------------------------------------ drawing
    def tick(self) -> None:
        """Send what changed, at most every REDRAW_PERIOD (call it from the app loop)."""
        if self._dirty and self.clock() - self._drawn_at >= REDRAW_PERIOD:
            self.draw()

    def draw(self) -> None:
        """Send the node's arrays now (one batched mesh: attitudes, colours, opacities), or hide it."""
        self._dirty = False
        self._drawn_at = self.clock()
        node = self._node
        if node is None:
            return
        if not self.entries or not self.visible:
            if self._shown:
                node.visible = False
                self._shown = False
            return
        first = self.entries[0].answer
        key = ("top",) if first.mgl != 0.0 else ("box", first.inertia)
        count = len(self.entries)
        wxyzs = Rotation.from_matrix(np.stack([e.answer.R_space_body for e in self.entries])).as_quat(scalar_first=True)
        colors = np.tile(np.array(FAINT_COLOR, dtype=np.uint8), (count, 1))
        opacities = np.full(count, ALL_OPACITY, dtype=np.float32)
        if self.chosen is not None:
            opacities[:] = ONE_OTHERS_OPACITY
            opacities[self.index] = CHOSEN_OPACITY
            colors[self.index] = CHOSEN_COLOR
        if key != self._glyph_key:
            vertices, faces = _glyph(first)
            node.vertices = vertices
            node.faces = faces
            self._glyph_key = key
        if len(node.batched_positions) != count:
            node.batched_positions = np.zeros((count, 3), dtype=np.float32)
        node.batched_wxyzs = wxyzs.astype(np.float32)
        node.batched_colors = colors
        node.batched_opacities = opacities
        if not self._shown:
            node.visible = True
            self._shown = True
        self.sends += 1

    def clear(self) -> None:
        """No answers: the drawing is hidden (the round is over or not a State question)."""
        self.entries = self._signature = ()
        self.mode = ALL
        self.draw()

    def remove(self) -> None:
        """Take the node away (its panel goes)."""
        self.entries = self._signature = ()
        if self._node is not None:
            self._node.remove()
            self._node = None


def _check_showable(scene: Any, model: Model) -> None:
    """ValueError unless the scene's sliders can show `model` (each parameter in its slider's
    range, and the scene's own model of those parameters is this one): a student's body is
    played only if the presenter could have set it."""
    to_params = getattr(scene, "params_from_model", None)
    specs = getattr(scene, "param_specs", ())
    if to_params is None or not specs:
        return
    params = tuple(float(p) for p in to_params(model))
    for spec, value in zip(specs, params, strict=False):
        if not spec.lo <= value <= spec.hi:
            raise ValueError(f"this answer's {spec.label} = {value:g} is outside [{spec.lo:g}, {spec.hi:g}]")
    rebuilt = scene.model_from_params(params)
    if rebuilt.inertia != model.inertia or rebuilt.mgl != model.mgl:
        raise ValueError(f"this answer's body is not one the {scene.title} scene can show")


def play_answer(room: Any, answer: AnswerState) -> None:
    """Restart `room`'s simulation from `answer` at t = 0 and play (module docstring); ValueError
    with the message to show for an answer of another scene."""
    title = str(getattr(room.scene, "title", "?"))
    if answer.scene != title:
        raise ValueError(f"this answer is a {answer.scene} body; the room shows {title}")
    with room.lock:
        sim = room.sim
        model = getattr(sim, "model", None)
        if isinstance(model, Model) and hasattr(sim, "restart"):
            if answer.inertia is not None:
                new_model = dataclasses.replace(model, inertia=answer.inertia, mgl=answer.mgl)
                _check_showable(room.scene, new_model)
                if new_model != model:
                    sim.model = new_model
                    sim.mesh = None  # a body of its own gives way to the answer's moments
            sim.restart(State(answer.R_space_body.copy(), answer.omega_body.copy(), 0.0))
            sim.preset = None
        elif hasattr(sim, "set_angles"):
            sim.set_angles(np.degrees(euler_zxz_from_matrix(answer.R_space_body)))
        else:
            raise ValueError(f"{title} cannot play an answer")
        room.play()


class GalleryPanel:
    """The presenter's Gallery folder (module docstring): one row `Previous` `Next` `All` and
    `Play this answer`; `play(entry)` is called with the chosen answer (the caller loads it into
    its room and says what happened)."""

    WALK = {N_("Previous"): "previous", N_("Next"): "next", N_("All"): "show_all"}

    def __init__(self, gui: Any, gallery: Gallery, play: Callable[[GalleryEntry], None],
                 guard: Callable[[str, Callable[..., Any]], Callable[..., Any]] | None = None) -> None:
        self.gallery = gallery
        self.play = play
        wrap = guard or (lambda _where, fn: fn)
        self.gui = gui
        self.folder = gui.add_folder(N_("Gallery"))
        with self.folder:
            self.line = gui.add_markdown(gallery.words(for_gui(gui)))
            self.walk = gui.add_button_group(N_("Answers"), tuple(self.WALK))
            self.play_button = gui.add_button(N_("Play this answer"), disabled=True,
                                              hint=N_("the chosen answer in the room, on every screen"))
        self.words = Labels(gui)
        self.words.take(self.folder, self.play_button)
        self.words.take(self.walk, options=True)
        self.walk.on_click(wrap("gallery", lambda event: self._walk(event.target.value)))
        self.play_button.on_click(wrap("gallery play", lambda _event: self._play()))

    def _walk(self, option: Any) -> None:
        name = self.WALK.get(self.words.english(option)) if isinstance(option, str) else None
        if name is None:  # a client can send anything
            return
        getattr(self.gallery, name)()
        self.refresh()

    def _play(self) -> None:
        chosen = self.gallery.chosen
        if chosen is None:
            self.line.content = for_gui(self.gui).gettext("Choose an answer first (Next or Previous).")
            return
        self.play(chosen)

    def refresh(self) -> None:
        """Write the line and the buttons' state from the gallery."""
        words = self.gallery.words(for_gui(self.gui))
        if self.line.content != words:
            self.line.content = words
        self.play_button.disabled = self.gallery.chosen is None
        shown = bool(self.gallery.entries)  # (viser's button groups cannot be disabled)
        if self.walk.visible != shown:
            self.walk.visible = shown

    def relabel(self, tr: Translator) -> None:
        """The folder's words in `tr`'s language (the browser chose another)."""
        self.words.relabel(tr)
        self.refresh()

    def remove(self) -> None:
        self.folder.remove()
