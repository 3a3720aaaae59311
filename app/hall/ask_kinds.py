"""Each question kind's part of the panels, registered once by kind name in `PANELS`.

A kind's data (check, dict, tally, CSV, words) is its class in `app.ask.questions`; here is what
it shows: `form` the presenter's form fields (made hidden in the `Ask the class` folder, shown
while the kind is chosen; `question` reads them, `fill` writes a lesson's question into them)
and `widget` the student's controls (made hidden in the `Question` folder; `show` shows them
for a round of its kind while the student may answer).  Adding a kind: its class in
`app.ask.questions.KINDS`, a form and a widget here, one line in `PANELS`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import viser

from app.ask import JUDGES, Question, State, question_from_dict
from app.ask.judges import MOTION_WORDS
from app.ask.questions import MAX_OPTION_CHARS, MAX_OPTIONS, QuestionRefused
from app.i18n import N_, Translator, for_gui
from app.kit.core.common import Wrap, show_if_changed

__all__ = ["ARROW_COLOR", "ARROW_LENGTH", "ASK_ROOT", "DIRECTION_LABEL", "FROM_COPY_LABEL", "NUMBER_LABEL", "PANELS",
           "STATE_LABEL", "KindForm", "KindPanels", "KindWidget", "Student", "angles_of", "direction_of",
           "quaternion_to", "rotated_z", "target_of"]

DIRECTION_LABEL = N_("Send my direction")
FROM_COPY_LABEL = N_("Answer from my copy")
STATE_LABEL = N_("Send my state")
NUMBER_LABEL = N_("Send my number")
AZIMUTH_LABEL, AZIMUTH_HINT = N_("Azimuth"), N_("[deg] from x towards y, about the vertical z")
ELEVATION_LABEL, ELEVATION_HINT = N_("Elevation"), N_("[deg] above the horizontal x-y plane")
DIRECTION_HINT = N_("or turn the arrow in the 3D view first")
FROM_COPY_HINT = N_("an exact copy of the presenter's scene, yours to change")
STATE_HINT = N_("your copy's state as it is now")
ANSWER_LABEL, ANSWER_HINT = N_("Your answer"), N_("a number in the question's unit")
NUMBER_HINT = N_("the number in the box")
NONE = N_("none")  # a form dropdown's "nothing chosen" (the right option, the judge)
TARGET = N_("Target")  # the State form's target field (a refusal names it)
ARROW_LENGTH = 2.2  # [scene units] a student's arrow (out of the scenes' bodies)
ARROW_COLOR = (0, 150, 150)  # teal: no axis, vector or pointer of the scenes has it
ASK_ROOT = "/ask"  # the presenter's sphere and a student's arrow, each in its own browser's scene


class Student(Protocol):
    """What a student's question panel drives: a browser's session (`app.session.Session` is one)."""

    client: viser.ClientHandle

    def answer(self, value: Any) -> Any:
        """Answer the round shown (the session's anonymous token); Refused is shown in the panel."""
        ...

    def my_answer(self) -> Any:
        """This browser's answer to the round shown, or None."""
        ...

    def answer_from_copy(self) -> None:
        """Leave the presenter with an exact copy of the room (a State question)."""
        ...

    def state_answer(self) -> Any:
        """The state of this browser's own room, as a State question takes it."""
        ...

    def folded_for_question(self, folded: bool) -> None:
        """Fold (or unfold) the follower's panel while the question waits for an answer."""
        ...


# ---------------------------------------------------------------------- pure helpers
def target_of(judge_name: str, text: str) -> dict[str, Any] | None:
    """A State question's target typed in the form (None when empty): the attitude judge takes
    "φ, θ, ψ" [deg], the top's a class of motion ("loops"), the axis judge "stays" or "flips".
    ValueError naming what is wrong."""
    text = text.strip()
    if not text:
        return None
    if judge_name == "attitude":
        try:
            angles = [float(part) for part in text.replace("(", "").replace(")", "").replace(";", ",").split(",")]
        except ValueError:
            raise QuestionRefused(N_("{where}: φ, θ, ψ in degrees wanted, got {got}"), where=TARGET,
                                  got=repr(text)) from None
        if len(angles) != 3:
            raise QuestionRefused(N_("{where}: three angles φ, θ, ψ [deg] wanted, got {count}"), where=TARGET,
                                  count=len(angles))
        return {"angles_deg": angles}
    if judge_name == "top_motion":
        if text not in MOTION_WORDS.values():
            raise QuestionRefused(N_("{where}: one of {choices}, got {got}"), where=TARGET,
                                  choices=", ".join(MOTION_WORDS.values()), got=repr(text))
        return {"motion": text}
    if judge_name == "axis_stays":
        if text not in ("stays", "flips"):
            raise QuestionRefused(N_("{where}: stays or flips, got {got}"), where=TARGET, got=repr(text))
        return {"stays": text == "stays"}
    raise QuestionRefused(N_("{where}: choose a judge first"), where=TARGET)


def direction_of(azimuth_deg: float, elevation_deg: float) -> tuple[float, float, float]:
    """The unit vector (space frame, z up) at azimuth [deg] from x towards y and elevation [deg] above the x-y plane."""
    a, e = math.radians(azimuth_deg), math.radians(elevation_deg)
    return math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)


def angles_of(direction: Sequence[float]) -> tuple[float, float]:
    """(azimuth, elevation) [deg] of a unit vector (`direction_of`'s inverse)."""
    x, y, z = direction
    return math.degrees(math.atan2(y, x)), math.degrees(math.asin(max(-1.0, min(1.0, z))))


def quaternion_to(direction: Sequence[float]) -> tuple[float, float, float, float]:
    """wxyz of the shortest rotation taking +z to the unit vector `direction`."""
    x, y, z = (float(c) for c in direction)
    w, v = 1.0 + z, (-y, x, 0.0)  # (1 + ez·d, ez × d), normalized below
    if w < 1e-9:
        return 0.0, 1.0, 0.0, 0.0  # straight down: half a turn about x
    norm = math.sqrt(w * w + v[0] * v[0] + v[1] * v[1])
    return w / norm, v[0] / norm, v[1] / norm, 0.0


def rotated_z(wxyz: Any) -> tuple[float, float, float]:
    """R(q) e_z for a unit quaternion `wxyz`: where a gizmo turned its arrow."""
    w, x, y, z = (float(c) for c in wxyz)
    return 2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)


def _float_or_none(text: str, where: str) -> float | None:
    """A number typed in a form field (None when empty); ValueError naming the field."""
    text = text.strip()
    if not text:
        return None
    try:
        return float(text)
    except ValueError:
        raise QuestionRefused(N_("{where}: a number wanted, got {got}"), where=where, got=repr(text)) from None


# ---------------------------------------------------------------------- the protocols
class KindForm(Protocol):
    """A kind's fields in the presenter's form (made hidden, in the folder being built)."""

    handles: tuple[Any, ...]  # shown while this kind is chosen
    with_options: tuple[Any, ...]  # those of them whose options are words (translated, `app.i18n.Labels`)

    def question(self, prompt: str) -> Question:
        """The question the fields describe with `prompt`; ValueError naming what is wrong."""
        ...

    def fill(self, question: Any) -> None:
        """Write `question` (of this kind) into the fields."""
        ...


def relabel(handle: Any, tr: Translator, label: str, hint: str | None = None) -> None:
    """`handle`'s label (and hint), msgids, in `tr`'s language; unchanged ones are not sent."""
    if handle.label != (text := tr.gettext(label)):
        handle.label = text
    if hint is not None and handle.hint != (text := tr.gettext(hint)):
        handle.hint = text


class KindWidget(Protocol):
    """A kind's controls in a student's `Question` folder (made hidden, in the folder being built;
    `show` writes their words in the language of the browser whose panel they are in)."""

    def show(self, question: Question | None, controls: bool) -> None:
        """Show the controls for `question` (of this kind) while `controls`; hide them for None."""
        ...

    def remove(self) -> None:
        """Remove what it made outside the folder (scene nodes)."""
        ...


@dataclass(frozen=True)
class KindPanels:
    """A kind's label in the form's Kind dropdown, its form fields and its student widget."""

    label: str
    form: Callable[..., KindForm]  # (gui, scene_title) -> KindForm
    widget: Callable[..., KindWidget]  # (gui, guard, student, send, redraw) -> KindWidget


# ---------------------------------------------------------------------- the presenter's form fields
class ChoiceForm:
    def __init__(self, gui: Any, scene_title: Callable[[], str]) -> None:
        self.gui = gui
        self.gui_options = gui.add_text(N_("Options"), "", hint=N_("2 to 6 options, separated by |"))
        self.gui_correct = gui.add_dropdown(N_("Right option"), (NONE, *map(str, range(1, MAX_OPTIONS + 1))),
                                            initial_value=NONE, hint=N_("revealed on demand"))
        self.handles = (self.gui_options, self.gui_correct)
        self.with_options = (self.gui_correct,)  # dropdowns whose options are words (translated)

    def question(self, prompt: str) -> Question:
        options = [o.strip() for o in str(self.gui_options.value).split("|") if o.strip()]
        for number, option in enumerate(options, start=1):
            if len(option) > MAX_OPTION_CHARS:
                raise QuestionRefused(N_("{where}: option {number} is longer than {most} characters"),
                                      where=N_("Options"), number=number, most=MAX_OPTION_CHARS)
        chosen = for_gui(self.gui).english(str(self.gui_correct.value), (NONE,))
        correct = None if chosen == NONE else int(chosen) - 1
        if correct is not None and correct >= len(options):
            raise QuestionRefused(N_("{where}: option {number} is not one of the {count} options"),
                                  where=N_("Right option"), number=correct + 1, count=len(options))
        return question_from_dict({"kind": "choice", "prompt": prompt, "options": options, "correct": correct})

    def fill(self, question: Any) -> None:
        self.gui_options.value = " | ".join(question.options)
        self.gui_correct.value = (for_gui(self.gui).gettext(NONE) if question.correct is None
                                  else str(question.correct + 1))


class DirectionForm:
    def __init__(self, gui: Any, scene_title: Callable[[], str]) -> None:
        self.gui_truth = gui.add_text(N_("True direction"), "", visible=False,
                                      hint=N_("x, y, z in the space frame (z up), or empty"))
        self.handles = (self.gui_truth,)
        self.with_options: tuple[Any, ...] = ()

    def question(self, prompt: str) -> Question:
        text = str(self.gui_truth.value).replace("(", "").replace(")", "").strip()
        truth = None
        if text:
            try:
                truth = [float(part) for part in text.replace(";", ",").split(",")]
            except ValueError:
                raise QuestionRefused(N_("{where}: three numbers x, y, z wanted, got {got}"),
                                      where=N_("True direction"), got=repr(text)) from None
        return question_from_dict({"kind": "direction", "prompt": prompt, "truth": truth})

    def fill(self, question: Any) -> None:
        self.gui_truth.value = "" if question.truth is None else ", ".join(f"{c:.3g}" for c in question.truth)


class StateForm:
    def __init__(self, gui: Any, scene_title: Callable[[], str]) -> None:
        self.scene_title = scene_title
        self.gui = gui
        self.gui_judge = gui.add_dropdown(N_("Judge"), (NONE, *JUDGES), initial_value=NONE, visible=False,
                                          hint=N_("how the app judges a state"))
        self.gui_target = gui.add_text(N_("Target"), "", visible=False,
                                       hint=N_("attitude: φ, θ, ψ [deg] · top_motion: loops, waves, ... · "
                                               "axis_stays: stays or flips"))
        self.handles = (self.gui_judge, self.gui_target)
        self.with_options = (self.gui_judge,)
        self.filled: State | None = None  # a lesson's state question: its target, unless the form changes

    def question(self, prompt: str) -> Question:
        chosen = for_gui(self.gui).english(str(self.gui_judge.value), (NONE, *JUDGES))
        judge_name = None if chosen == NONE else chosen
        target = None if judge_name is None else target_of(judge_name, str(self.gui_target.value))
        filled = self.filled
        if (filled is not None and judge_name == filled.judge and not str(self.gui_target.value).strip()
                and filled.scene == self.scene_title()):  # a lesson's question: its whole target
            target = None if filled.target is None else dict(filled.target)
        return question_from_dict({"kind": "state", "prompt": prompt, "scene": self.scene_title(),
                                   "judge": judge_name, "target": target})

    def fill(self, question: Any) -> None:
        self.gui_judge.value = question.judge if question.judge in JUDGES else for_gui(self.gui).gettext(NONE)
        self.gui_target.value = ""  # empty: the lesson's own target is asked (`question`)
        self.filled = question


class NumberForm:
    def __init__(self, gui: Any, scene_title: Callable[[], str]) -> None:
        self.gui_value = gui.add_text(N_("Right value"), "", visible=False, hint=N_("the right number, or empty"))
        self.gui_unit = gui.add_text(N_("Unit"), "", visible=False, hint=N_("e.g. s, rad/s, kg m²"))
        self.gui_tolerance = gui.add_text(N_("Tolerance"), "0", visible=False,
                                          hint=N_("an answer within ± this of the right value is right"))
        self.handles = (self.gui_value, self.gui_unit, self.gui_tolerance)
        self.with_options: tuple[Any, ...] = ()

    def question(self, prompt: str) -> Question:
        value = _float_or_none(str(self.gui_value.value), N_("Right value"))
        tolerance = _float_or_none(str(self.gui_tolerance.value), N_("Tolerance"))
        return question_from_dict({"kind": "number", "prompt": prompt, "value": value,
                                   "unit": str(self.gui_unit.value), "tolerance": tolerance or 0.0})

    def fill(self, question: Any) -> None:
        self.gui_value.value = "" if question.value is None else f"{question.value:.10g}"
        self.gui_unit.value = question.unit
        self.gui_tolerance.value = f"{question.tolerance:.10g}"


# ---------------------------------------------------------------------- the student's widgets
class ChoiceWidget:
    """One button per option."""

    def __init__(self, gui: Any, guard: Wrap, student: Student, send: Callable[[Any], None],
                 redraw: Callable[[], None]) -> None:
        self.gui_options = [gui.add_button(f"Option {k + 1}", visible=False) for k in range(MAX_OPTIONS)]
        for k, button in enumerate(self.gui_options):
            button.on_click(guard("answer", lambda _e, k=k: send(k)))

    def show(self, question: Question | None, controls: bool) -> None:
        options = getattr(question, "options", ()) if controls else ()
        for k, button in enumerate(self.gui_options):
            there = k < len(options)
            if there and button.label != (label := f"{k + 1}. {options[k]}"):
                button.label = label
            show_if_changed(button, there)

    def remove(self) -> None:
        pass


class DirectionWidget:
    """An arrow turned by a gizmo (a laptop) or by two sliders (a phone), then Send my direction.
    The arrow and its gizmo are made hidden now: a node made inside the app loop's frame holds back
    that frame's panel updates for this browser (app.wire), so the round only shows them."""

    def __init__(self, gui: Any, guard: Wrap, student: Student, send: Callable[[Any], None],
                 redraw: Callable[[], None]) -> None:
        self._writing = False  # the server moves the sliders: their callbacks do nothing
        self.gui = gui
        self.gui_azimuth = gui.add_slider(AZIMUTH_LABEL, min=-180.0, max=180.0, step=1.0, initial_value=0.0,
                                          visible=False, hint=AZIMUTH_HINT)
        self.gui_elevation = gui.add_slider(ELEVATION_LABEL, min=-90.0, max=90.0, step=1.0, initial_value=45.0,
                                            visible=False, hint=ELEVATION_HINT)
        self.gui_send_direction = gui.add_button(DIRECTION_LABEL, visible=False, hint=DIRECTION_HINT)
        self.gui_azimuth.on_update(guard("azimuth", lambda _e: self._sliders_moved()))
        self.gui_elevation.on_update(guard("elevation", lambda _e: self._sliders_moved()))
        self.gui_send_direction.on_click(guard("send my direction", lambda _e: send(self.direction())))
        scene = student.client.scene
        self._gizmo = scene.add_transform_controls(
            f"{ASK_ROOT}/gizmo", scale=1.2, disable_axes=True, disable_sliders=True, depth_test=False,
            wxyz=quaternion_to(self.direction()), visible=False)
        self._arrow = scene.add_arrows(
            f"{ASK_ROOT}/gizmo/arrow", np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, ARROW_LENGTH]]], np.float32),
            ARROW_COLOR, shaft_radius=0.05, head_radius=0.12, head_length=0.25)
        self._gizmo.on_update(guard("direction arrow", lambda _e: self._gizmo_moved()))

    def direction(self) -> tuple[float, float, float]:
        """The direction the sliders (and the arrow) show now, a unit 3-vector in the space frame."""
        return direction_of(float(self.gui_azimuth.value), float(self.gui_elevation.value))

    def _sliders_moved(self) -> None:
        if not self._writing:
            self._gizmo.wxyz = quaternion_to(self.direction())

    def _gizmo_moved(self) -> None:
        azimuth, elevation = angles_of(rotated_z(self._gizmo.wxyz))
        self._writing = True
        try:
            self.gui_azimuth.value = round(azimuth)
            self.gui_elevation.value = round(elevation)
        finally:
            self._writing = False

    def show(self, question: Question | None, controls: bool) -> None:
        shown = question is not None and controls
        if shown:
            tr = for_gui(self.gui)
            relabel(self.gui_azimuth, tr, AZIMUTH_LABEL, AZIMUTH_HINT)
            relabel(self.gui_elevation, tr, ELEVATION_LABEL, ELEVATION_HINT)
            relabel(self.gui_send_direction, tr, DIRECTION_LABEL, DIRECTION_HINT)
        for handle in (self.gui_azimuth, self.gui_elevation, self.gui_send_direction, self._gizmo):
            show_if_changed(handle, shown)

    def remove(self) -> None:
        self._gizmo.remove()


class StateWidget:
    """Answer from my copy (following), then Send my state (exploring the copy)."""

    def __init__(self, gui: Any, guard: Wrap, student: Student, send: Callable[[Any], None],
                 redraw: Callable[[], None]) -> None:
        self.student = student
        self.gui = gui
        self.gui_from_copy = gui.add_button(FROM_COPY_LABEL, visible=False, hint=FROM_COPY_HINT)
        self.gui_send_state = gui.add_button(STATE_LABEL, visible=False, hint=STATE_HINT)

        def from_copy() -> None:
            student.answer_from_copy()
            redraw()

        self.gui_from_copy.on_click(guard("answer from my copy", lambda _e: from_copy()))
        self.gui_send_state.on_click(guard("send my state", lambda _e: send(student.state_answer())))

    def show(self, question: Question | None, controls: bool) -> None:
        shown = question is not None and controls
        exploring = getattr(self.student, "mode", None) != "following"
        if shown:
            tr = for_gui(self.gui)
            relabel(self.gui_from_copy, tr, FROM_COPY_LABEL, FROM_COPY_HINT)
            relabel(self.gui_send_state, tr, STATE_LABEL, STATE_HINT)
        show_if_changed(self.gui_from_copy, shown and not exploring)
        show_if_changed(self.gui_send_state, shown and exploring)

    def remove(self) -> None:
        pass


class NumberWidget:
    """A number box (in the question's unit) and Send my number."""

    def __init__(self, gui: Any, guard: Wrap, student: Student, send: Callable[[Any], None],
                 redraw: Callable[[], None]) -> None:
        self.gui = gui
        self.gui_number = gui.add_number(ANSWER_LABEL, 0.0, step=0.0001, visible=False, hint=ANSWER_HINT)
        self.gui_send_number = gui.add_button(NUMBER_LABEL, visible=False, hint=NUMBER_HINT)
        self.gui_send_number.on_click(guard("send my number", lambda _e: send(self.gui_number.value)))

    def show(self, question: Question | None, controls: bool) -> None:
        shown = question is not None and controls
        unit = getattr(question, "unit", "")
        if shown:
            tr = for_gui(self.gui)
            label = tr.gettext(ANSWER_LABEL) + (f" [{unit}]" if unit else "")
            if self.gui_number.label != label:
                self.gui_number.label = label
            if self.gui_number.hint != (hint := tr.gettext(ANSWER_HINT)):
                self.gui_number.hint = hint
            relabel(self.gui_send_number, tr, NUMBER_LABEL, NUMBER_HINT)
        show_if_changed(self.gui_number, shown)
        show_if_changed(self.gui_send_number, shown)

    def remove(self) -> None:
        pass


PANELS: dict[str, KindPanels] = {
    "choice": KindPanels(N_("Choice"), ChoiceForm, ChoiceWidget),
    "direction": KindPanels(N_("Direction"), DirectionForm, DirectionWidget),
    "state": KindPanels(N_("State"), StateForm, StateWidget),
    "number": KindPanels(N_("Number"), NumberForm, NumberWidget),
}
