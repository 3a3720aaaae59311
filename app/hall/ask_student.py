"""Ask the class, a student's side (`AnswerPanel`, every browser but the presenter's).

While a round is open, the question and its controls sit at the top of the panel and the
follower's panel is folded away until the student answers.  The controls are the kind's widget
(`app.hall.ask_kinds`): a choice is one button per option, a direction an arrow turned by a
gizmo (a laptop) or by two sliders, azimuth and elevation (a phone), then `Send my direction`; a
state is `Answer from my copy` (an exact copy of the presenter's room to work in, `Explore`) then
`Send my state`; a number a number box then `Send my number`.  Answered, the panel says the
answer (`QuestionKind.answer_words`) and offers `Change my answer` until the round closes.  The
arrow and its gizmo are in the student's own scene: no other browser sees or moves them.

Everything a student sends goes through `Student.answer` (the session: its anonymous token, the
app's `Rounds`), where the round's rules hold (`app.ask.round`): a refused answer is said in the
student's panel and changes nothing.  The panel refreshes from the app loop (`refresh`), writing
only what changed.
"""

from __future__ import annotations

from typing import Any

from app.ask import Question, Rounds, Shown
from app.ask.round import Refused
from app.ask.verdict_words import JUDGE_REFUSALS, answer_in_language
from app.hall.ask_kinds import PANELS, KindWidget, Student, direction_of, relabel
from app.i18n import N_, Phrases, Translator, for_gui, translator
from app.kit.core.common import Wrap, show_if_changed, write_if_changed

__all__ = ["CHANGE_LABEL", "REFUSALS", "AnswerPanel", "answer_words", "refusal_words"]

CHANGE_LABEL = N_("Change my answer")
CHANGE_HINT = N_("until the round closes")
QUESTION_TITLE = N_("Question")

REFUSALS = Phrases(
    (r"no question is asked now", N_("no question is asked now")),
    (r"the round is closed: answers are no longer taken",
     N_("the round is closed: answers are no longer taken")),
    (r"too fast: at most (?P<rate>\d+) answers a second", N_("too fast: at most {rate} answers a second")),
    (r"the round is full \((?P<count>\d+) answers\)", N_("the round is full ({count} answers)")),
    (r"this browser has no answer token", N_("this browser has no answer token")),
    (r"the question's process cannot be reached", N_("the question's process cannot be reached")),
    (r"not an answer: (?P<error>.*)", N_("not an answer: {error}")),
    nested={"error": JUDGE_REFUSALS},
)
"""The refusals of an answer (`app.ask.round`, `app.ask.hub`), matched in English, and their msgids."""


def refusal_words(refusal: str, tr: Translator) -> str:
    """An answer's refusal (`Refused`'s English words) in `tr`'s language; the words as they are
    when no pattern knows them (a detail after "not an answer:" stays as the check wrote it)."""
    return REFUSALS.in_language(refusal, tr)


def answer_words(question: Question, value: Any, tr: Translator | None = None) -> str:
    """A student's own answer in words (Markdown, `QuestionKind.answer_words`), in `tr`'s language
    (English by default): a direction's and a state's words translated (`app.ask.verdict_words`),
    a choice's option and a number as they are."""
    tr = tr or translator("en")
    return answer_in_language(question.answer_words(value), tr)


class AnswerPanel:
    """A student's question: at the top of the panel while a round is shown (module docstring).

    Args:
        student: the browser's session.  guard: its guard.  rounds: the app's `Rounds`.
        order: the folder's place (above the follower's panel).
    """

    def __init__(self, student: Student, guard: Wrap, rounds: Rounds, *, order: float) -> None:
        self.student = student
        self.rounds = rounds
        self.active = True  # False while the browser presents (its own questions are not for it)
        self.editing = True  # the controls are shown (before an answer, or after Change my answer)
        self.drawn: tuple[Any, ...] = ()
        self._round_id: str | None = None  # the round the panel last showed (None: none)
        self._mine_seen = ""  # repr of this browser's answer when the panel last looked
        gui: Any = student.client.gui
        self.gui = gui
        self.folder = gui.add_folder(QUESTION_TITLE, order=order, visible=False)
        with self.folder:
            self.gui_prompt = gui.add_markdown("")
            self.widgets: dict[str, KindWidget] = {
                kind: panels.widget(gui, guard, student, self.send, self._redraw) for kind, panels in PANELS.items()}
            self.gui_mine = gui.add_markdown("", visible=False)
            self.gui_change = gui.add_button(CHANGE_LABEL, visible=False, hint=CHANGE_HINT)
        self.gui_change.on_click(guard("change my answer", lambda _e: self._edit()))
        self._alias_widgets()

    def _alias_widgets(self) -> None:
        """The kinds' controls under their old names (tests read them)."""
        widgets: Any = self.widgets
        self.gui_options = widgets["choice"].gui_options
        direction = widgets["direction"]
        self.gui_azimuth, self.gui_elevation = direction.gui_azimuth, direction.gui_elevation
        self.gui_send_direction = direction.gui_send_direction
        self.gui_from_copy, self.gui_send_state = widgets["state"].gui_from_copy, widgets["state"].gui_send_state
        self.gui_number, self.gui_send_number = widgets["number"].gui_number, widgets["number"].gui_send_number

    def direction(self) -> tuple[float, float, float]:
        """The direction the sliders (and the arrow) show now, a unit 3-vector in the space frame."""
        widget: Any = self.widgets["direction"]
        azimuth, elevation = float(widget.gui_azimuth.value), float(widget.gui_elevation.value)
        return direction_of(azimuth, elevation)

    def send(self, value: Any) -> None:
        """Answer `value`; the panel then shows the answer (a refusal is raised in the browser's
        language: the guard says it)."""
        try:
            self.student.answer(value)
        except Refused as refusal:
            raise Refused(refusal_words(str(refusal), for_gui(self.gui))) from None
        self.editing = False
        self.drawn = ()
        self.refresh()

    def _edit(self) -> None:
        self.editing = True
        self.drawn = ()
        self.refresh()

    def _redraw(self) -> None:
        self.drawn = ()
        self.refresh()

    def redraw(self) -> None:
        """Write the panel again (the browser's language changed)."""
        self._redraw()

    def refresh(self) -> None:
        """Show the round the class is asked now (or nothing), the controls or this browser's answer."""
        shown: Shown | None = self.rounds.shown() if self.active else None
        mine = self.student.my_answer() if shown is not None else None
        tr = for_gui(self.gui)
        key = (None if shown is None else (shown.id, shown.open), self.editing, mine is None,
               repr(mine), getattr(self.student, "mode", None), tr.language)
        if key == self.drawn:
            return
        self.drawn = key
        if shown is None:
            show_if_changed(self.folder, False)
            for widget in self.widgets.values():
                widget.show(None, False)
            self.student.folded_for_question(False)
            self.editing, self._round_id = True, None
            return
        question = shown.question
        if shown.id != self._round_id:  # a round (re)appears: its controls only if not answered yet
            self.editing, self._round_id = mine is None, shown.id
        elif mine is not None and repr(mine) != self._mine_seen:  # a new answer kept (any way in): shown
            self.editing = False
        self._mine_seen = repr(mine)
        if mine is None:
            self.editing = True
        controls = shown.open and self.editing
        _ = tr.gettext
        head = _("**Question {number}** · {prompt}").format(number=shown.number, prompt=question.prompt)
        if not shown.open:
            head += "  \n" + _("*The round is closed.*")
        write_if_changed(self.gui_prompt, head)
        if self.folder.label != _(QUESTION_TITLE):
            self.folder.label = _(QUESTION_TITLE)
        relabel(self.gui_change, tr, CHANGE_LABEL, CHANGE_HINT)
        show_if_changed(self.folder, True)
        for kind, widget in self.widgets.items():
            widget.show(question if kind == question.kind else None, controls)
        show_if_changed(self.gui_mine, mine is not None)
        if mine is not None:
            words = answer_words(question, mine, tr)
            write_if_changed(self.gui_mine, _("Your answer: {answer} · you can change it until the round closes.")
                             .format(answer=words) if shown.open else _("Your answer: {answer}").format(answer=words))
        show_if_changed(self.gui_change, mine is not None and shown.open and not self.editing)
        self.student.folded_for_question(shown.open and mine is None)

    def remove(self) -> None:
        for widget in self.widgets.values():
            widget.remove()
        self.folder.remove()
