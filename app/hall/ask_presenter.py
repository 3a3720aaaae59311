"""Ask the class, the presenter's side (`AskPanel`, shown only while the browser presents).

A form (kind, question, and the kind's own fields, `app.hall.ask_kinds`; a lesson step with a
question fills it in) and `Ask the class`; then the round: the live count ("31 of 44 answered",
`count_text`: the answers against every browser following or exploring, on every process), the
kind's tally in words (`QuestionKind.tally_text`: a choice's bars, a number's histogram, a
state's judged classes; the round before it beside after `Vote again`), for a direction every
answer's tip as a point on one sphere of radius SPHERE_RADIUS around the origin (the body's
centre) in the presenter's own 3D view, the true direction an arrow once revealed; a state
round's gallery.  `Close the round`, `Vote again`, `Reveal the answer`, `Download answers (CSV)`
and `New question`; once a round has ended (`New question`, or a presenter stopped or left: the
round is the presenter's, `app.ask.hub`), `Download earlier rounds (CSV)`.  Every CSV is saved by
the browser at once (`app.kit.panel.download.save_download`).  The sphere is drawn in the
presenter's own scene (`client.scene`), so the followers' screens never show the others' answers.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import numpy as np
import viser

from app.ask import Question, Rounds, Tally
from app.ask.gallery import Gallery, GalleryEntry, GalleryPanel
from app.ask.judges import AXIS_WORDS, MOTION_WORDS, AnswerState
from app.ask.round import Round
from app.ask.state_tally import gallery_entries
from app.hall.ask_kinds import ASK_ROOT, PANELS, KindForm
from app.i18n import N_, Labels, Phrases, Translator, for_gui, translator
from app.kit.core.common import Wrap, show_if_changed, write_if_changed
from app.kit.panel.download import save_download
from app.refusals import NotAllowed

__all__ = ["ASK_LABEL", "CLOSE_LABEL", "CSV_LABEL", "EARLIER_LABEL", "LABELS", "NEW_LABEL", "REVEAL_LABEL",
           "SPHERE_RADIUS", "VOTE_AGAIN_LABEL", "AnswerSphere", "AskPanel", "count_text", "histogram_text",
           "sphere_points"]

ASK_LABEL = N_("Ask the class")
CLOSE_LABEL = N_("Close the round")
VOTE_AGAIN_LABEL = N_("Vote again")
REVEAL_LABEL = N_("Reveal the answer")
HIDE_LABEL = N_("Hide the answer")
CSV_LABEL = N_("Download answers (CSV)")
EARLIER_LABEL = N_("Download earlier rounds (CSV)")
NEW_LABEL = N_("New question")
LABELS = {panels.label: kind for kind, panels in PANELS.items()}  # the form's Kind dropdown -> kind name
SPHERE_RADIUS = 1.6  # [scene units] the sphere of the answers' tips, around the origin
TIP_COLOR = (40, 110, 230)
TRUTH_COLOR = (235, 160, 0)
TRUTH_REACH = 1.3  # the true direction's arrow ends this far out of the sphere (its tip seen past a vector)


CSV_COLUMN_WORDS: dict[str, str] = {
    "round": N_("round"), "answer": N_("answer"), "seconds": N_("seconds"), "option": N_("option"),
    "option_text": N_("option_text"), "state": N_("state"), "judged": N_("judged"),
    "judged_words": N_("judged_words"), "value": N_("value")}
"""The answers' CSV columns (`Round.CSV_COLUMNS`) a lecturer reads in their language (x, y, z stay)."""


def count_text(number: int, answered: int, expected: int, is_open: bool, tr: Translator | None = None) -> str:
    """The presenter's live count (Markdown): "**Round 1** · 31 of 44 answered · open", in `tr`'s
    language (English by default)."""
    _ = (tr or translator("en")).gettext
    state = _("open") if is_open else _("closed")
    return _("**Round {number}** · {answered} of {expected} answered · {state}").format(
        number=number, answered=answered, expected=max(expected, answered), state=state)


TALLY_LINES = Phrases(
    (r"no answers yet", N_("no answers yet")),
    (r"round (?P<number>\d+): (?P<count>\d+) answers", N_("round {number}: {count} answers")),
    (r"(?P<count>\d+) tips on the sphere in the 3D view", N_("{count} tips on the sphere in the 3D view")),
    (r"(?P<count>\d+) tips on the sphere in the 3D view · (?P<near>\d+) within 15° of the true direction",
     N_("{count} tips on the sphere in the 3D view · {near} within 15° of the true direction")),
    (r"(?P<count>\d+) states sent", N_("{count} states sent")),
    (r"(?P<count>\d+) states sent \(none judged\)", N_("{count} states sent (none judged)")),
    (r"(?P<count>\d+) not judged", N_("{count} not judged")),
    (r"✓ \*\*(?P<good>\d+)\*\* of (?P<count>\d+) meet the target",
     N_("✓ **{good}** of {count} meet the target")),
    (r"\*\*(?P<right>\d+) of (?P<count>\d+)\*\* within ±(?P<tolerance>.+) of (?P<value>.+)",
     N_("**{right} of {count}** within ±{tolerance} of {value}")),
)
"""Whole lines of a tally in words (`QuestionKind.tally_text`, English) and their msgids."""
TALLY_BESIDE = re.compile(r" · round (?P<number>\d+): (?P<count>\d+)$")
"""The round before beside a bar (after Vote again), at the end of a line."""
TALLY_CLASS_BAR = re.compile(r"^(?P<label>[a-z ]+)(?P<bar> `[█·]+` \*\*\d+\*\*)")
"""A judged class's bar of a State question's tally (`judged_histogram_text`: "loops `███` **3**")."""
JUDGED_CLASSES = frozenset((*MOTION_WORDS.values(), *AXIS_WORDS))
"""The classes a judge says (msgids, kept English in the round and the CSV)."""


def tally_in_language(text: str, tr: Translator) -> str:
    """A tally in words (Markdown lines, `QuestionKind.tally_text`) in `tr`'s language: the
    app's words translated, the options, numbers and units as they are."""
    if tr.language == "en" or not text:
        return text
    lines = []
    for line in text.split("  \n"):
        whole = TALLY_LINES.words(line, tr)
        if whole is None:
            whole = TALLY_CLASS_BAR.sub(lambda m: _class_bar(m, tr), TALLY_BESIDE.sub(
                lambda m: tr.gettext(" · round {number}: {count}").format(**m.groupdict()), line), count=1)
        lines.append(whole)
    return "  \n".join(lines)


def _class_bar(found: re.Match[str], tr: Translator) -> str:
    """A judged class's bar with the class in `tr`'s language (a line starting with another word as it is)."""
    label = found["label"]
    return (tr.gettext(label) if label in JUDGED_CLASSES else label) + found["bar"]


def csv_in_language(text: str, tr: Translator) -> str:
    """The answers' CSV `text` (`Rounds.csv`, `Rounds.earlier_csv`) with every header line of
    `Round.CSV_COLUMNS` in `tr`'s language (the lecturer's); the rows, numbers and the
    comment lines (the question as typed) as they are: machine-readable."""
    header = ",".join(Round.CSV_COLUMNS)
    shown = ",".join(tr.gettext(CSV_COLUMN_WORDS[c]) if c in CSV_COLUMN_WORDS else c for c in Round.CSV_COLUMNS)
    return "".join(shown + line[len(header):] if line.rstrip("\r\n") == header else line
                   for line in text.splitlines(keepends=True))


def histogram_text(tally: Tally, revealed: bool) -> str:
    """A choice's answers as bars of text (`Choice.tally_text`); "" for another kind."""
    return tally.question.tally_text(tally, revealed) if tally.question.kind == "choice" else ""


def sphere_points(tally: Tally) -> np.ndarray:
    """The direction answers' tips on the sphere [scene units], shape (answered, 3), float32."""
    if not tally.directions:
        return np.zeros((0, 3), dtype=np.float32)
    return (SPHERE_RADIUS * np.asarray(tally.directions, dtype=np.float64)).astype(np.float32)


class AnswerSphere:
    """A direction question's answers in one browser's 3D view (`scene`, its `client.scene`):
    a faint sphere of radius SPHERE_RADIUS around the origin, every answer's tip a point on it,
    the true direction an arrow once revealed.  Its nodes are made hidden, under `root`, when it
    is (no node is made inside a frame of the app loop); `draw` sets and shows them."""

    def __init__(self, scene: Any, root: str) -> None:
        self.handles: list[Any] = [
            scene.add_icosphere(f"{root}/sphere", radius=SPHERE_RADIUS, color=(150, 170, 200), subdivisions=3,
                                opacity=0.12, cast_shadow=False, receive_shadow=False, visible=False),
            scene.add_point_cloud(f"{root}/tips", np.zeros((1, 3), np.float32), colors=TIP_COLOR,
                                  point_size=0.12, point_shape="circle", visible=False),
            scene.add_arrows(f"{root}/truth", np.zeros((1, 2, 3), np.float32), TRUTH_COLOR, shaft_radius=0.05,
                             head_radius=0.12, head_length=0.25, visible=False),
        ]

    def draw(self, tally: Tally | None, revealed: bool = False) -> None:
        """The sphere, the tips of `tally`'s directions and (revealed) the true direction; `tally`
        None: all hidden."""
        sphere, tips, truth_arrow = self.handles
        show_if_changed(sphere, tally is not None)
        points = np.zeros((0, 3), np.float32) if tally is None else sphere_points(tally)
        if len(points):
            tips.points = points
        show_if_changed(tips, bool(len(points)))
        truth = None if tally is None else getattr(tally.question, "truth", None)
        if revealed and truth is not None:
            truth_arrow.points = np.array([[[0.0, 0.0, 0.0], [TRUTH_REACH * SPHERE_RADIUS * c for c in truth]]],
                                          np.float32)
        show_if_changed(truth_arrow, bool(revealed and truth is not None))

    def remove(self) -> None:
        for handle in self.handles:
            handle.remove()


class AskPanel:
    """The presenter's `Ask the class` folder and the sphere of directions (module docstring).

    Args:
        client: the browser.  guard: its session's guard.  rounds: the app's `Rounds`.
        audience: () -> browsers that can answer now (following + exploring, every process).
        scene_title: () -> the title of the scene shown (a State question's scene).
        presenting: () -> the browser presents now: every action of the folder is refused
            (PermissionError) otherwise; the folder's handles exist in every panel (hidden), and
            a hostile page can send them anything.
        order: the folder's place in the panel.
    """

    def __init__(self, client: viser.ClientHandle, guard: Wrap, rounds: Rounds, *,
                 audience: Callable[[], int], scene_title: Callable[[], str], presenting: Callable[[], bool],
                 order: float, play: Callable[[AnswerState], None] | None = None) -> None:
        self.client = client
        self.presenting = presenting
        self.play = play
        self.rounds = rounds
        self.audience = audience
        self.scene_title = scene_title
        self.drawn: tuple[Any, ...] = ()  # what the panel last showed (refresh writes only on change)
        self.form_extras: tuple[Any, ...] = ()  # more of the form, shown with it (`Make a task`: app.tasks.panel)
        gui: Any = client.gui
        self.folder = gui.add_folder(ASK_LABEL, order=order, visible=False)
        with self.folder:
            self.gui_kind = gui.add_dropdown(N_("Kind"), tuple(LABELS), initial_value="Choice",
                                             hint=N_("a choice, a direction in 3D, a state of the student's copy "
                                                     "or a number with a unit"))
            self.gui_prompt = gui.add_text(N_("Question"), "", hint=N_("what the class is asked"))
            self.forms: dict[str, KindForm] = {kind: panels.form(gui, scene_title) for kind, panels in PANELS.items()}
            self.gui_ask = gui.add_button(ASK_LABEL, icon=viser.Icon.HELP,
                                          hint=N_("every student answers from their own copy"))
            self.gui_count = gui.add_markdown("", visible=False)
            self.gui_histogram = gui.add_markdown("", visible=False)
            self.gui_close = gui.add_button(CLOSE_LABEL, visible=False, hint=N_("no more answers"))
            self.gui_again = gui.add_button(VOTE_AGAIN_LABEL, visible=False,
                                            hint=N_("the same question again; this round stays beside it"))
            self.gui_reveal = gui.add_button(REVEAL_LABEL, visible=False, hint=N_("the right answer on this screen"))
            self.gui_csv = gui.add_button(CSV_LABEL, icon=viser.Icon.DOWNLOAD, visible=False,
                                          hint=N_("every round's anonymous answers"))
            self.gui_new = gui.add_button(NEW_LABEL, visible=False, hint=N_("back to the form"))
            self.gui_earlier = gui.add_button(EARLIER_LABEL, icon=viser.Icon.DOWNLOAD, visible=False,
                                              hint=N_("the anonymous answers of the rounds that ended: "
                                                      "yours and those of the presenters before you"))
            self.gallery = Gallery(client.scene, root=f"{ASK_ROOT}/gallery")  # its node made now, hidden
            self.gallery_panel = GalleryPanel(gui, self.gallery, lambda entry: self.play_entry(entry), guard)
            self.gallery_panel.folder.visible = False
        self.words = Labels(gui)
        with_options = [h for form in self.forms.values() for h in form.with_options]
        self.words.take(self.folder, self.gui_prompt, self.gui_ask, self.gui_close, self.gui_again, self.gui_reveal,
                        self.gui_csv, self.gui_new, self.gui_earlier,
                        *(h for form in self.forms.values() for h in form.handles
                          if not any(h is o for o in with_options)))
        self.words.take(self.gui_kind, *with_options, options=True)
        self._alias_fields()
        # The sphere, the tips and the true direction, made hidden now (see AnswerPanel: no node is made in a frame)
        self.sphere = AnswerSphere(client.scene, ASK_ROOT)
        self._sphere = self.sphere.handles  # (sphere, tips, truth arrow), as tests read them
        self.gui_kind.on_update(guard("question kind", lambda _e: self._kind_shown()))
        self.gui_ask.on_click(guard("ask the class", lambda _e: self.ask_from_form()))
        self.gui_close.on_click(guard("close the round", lambda _e: self._changed(rounds.close_round)))
        self.gui_again.on_click(guard("vote again", lambda _e: self._changed(rounds.vote_again)))
        self.gui_reveal.on_click(guard("reveal the answer", lambda _e: self._changed(
            lambda: rounds.reveal(not (rounds.current is not None and rounds.current.revealed)))))
        self.gui_csv.on_click(guard("download answers", lambda _e: self.download()))
        self.gui_earlier.on_click(guard("download earlier rounds", lambda _e: self.download_earlier()))
        self.gui_new.on_click(guard("new question", lambda _e: self._changed(rounds.end)))

    def _check(self) -> None:
        if not self.presenting():
            raise NotAllowed(N_("only the presenter can ask the class and see its answers"))

    # ------------------------------------------------------------------ the form
    def _alias_fields(self) -> None:
        """The kinds' form fields under their old names (tests and lessons read them)."""
        forms: Any = self.forms
        self.gui_options, self.gui_correct = forms["choice"].gui_options, forms["choice"].gui_correct
        self.gui_truth = forms["direction"].gui_truth
        self.gui_judge, self.gui_target = forms["state"].gui_judge, forms["state"].gui_target

    def _kind_shown(self) -> None:
        if not self.presenting():
            return
        kind = LABELS.get(self.words.english(self.gui_kind.value))
        if kind is None:  # a client can send anything
            self.gui_kind.value = self.words.option("Choice")
            return
        for name, form in self.forms.items():
            for handle in form.handles:
                show_if_changed(handle, name == kind)

    def form_question(self) -> Question:
        """The question the form describes; ValueError naming what is wrong."""
        kind = LABELS.get(self.words.english(self.gui_kind.value), "choice")
        return self.forms[kind].question(str(self.gui_prompt.value))

    def fill(self, question: Question) -> None:
        """Put `question` into the form (a lesson step's question), ready for `Ask the class`."""
        self.gui_kind.value = self.words.option(PANELS[question.kind].label)
        self.gui_prompt.value = question.prompt
        self.forms[question.kind].fill(question)
        state_form: Any = self.forms["state"]
        if question.kind != "state":
            state_form.filled = None
        self._kind_shown()

    def ask_from_form(self) -> None:
        """`Ask the class`: the form's question goes to every student (ValueError, said, if it is not one)."""
        self._check()
        self.rounds.ask(self.form_question())
        self.refresh()

    def _changed(self, action: Callable[[], Any]) -> None:
        self._check()
        action()
        self.refresh()

    def download(self) -> None:
        """The round's anonymous answers as a CSV file, saved by the browser at once."""
        self._check()
        text = self.rounds.csv()
        if not text:
            raise LookupError("no round to download")
        round_ = self.rounds.current
        tr = for_gui(self.client.gui)  # the lecturer's language now
        name = tr.gettext("answers-round-{number}.csv").format(number=round_.number if round_ else 0)
        save_download(self.client, name, csv_in_language(text, tr))

    def download_earlier(self) -> None:
        """The rounds that ended (this presenter's and earlier presenters', `Rounds.earlier_csv`)
        as one CSV file, saved by the browser at once."""
        self._check()
        text = self.rounds.earlier_csv()
        if not text:
            raise LookupError("no earlier round to download")
        tr = for_gui(self.client.gui)
        save_download(self.client, tr.gettext("answers-earlier-rounds.csv"), csv_in_language(text, tr))

    # ------------------------------------------------------------------ the round
    def set_shown(self, shown: bool) -> None:
        """The folder is shown (while the browser presents) or not (the sphere goes too)."""
        show_if_changed(self.folder, shown)
        if not shown:
            self._draw_sphere(None)
            self._show_gallery(None)
        else:
            self.drawn = ()
            self.refresh()

    def refresh(self) -> None:
        """Show the form, or the round: its count, histogram, sphere and buttons (only what changed)."""
        if not self.folder.visible:
            return
        rounds = self.rounds
        round_ = rounds.current
        expected = self.audience()
        tr = for_gui(self.client.gui)
        key = (rounds.version, rounds.answers_version, expected, tr.language)
        self.gallery.tick()  # answers that came within the gallery's redraw period
        if key == self.drawn:
            return
        self.drawn = key
        asking = round_ is None
        for handle in (self.gui_kind, self.gui_prompt, self.gui_ask, *self.form_extras):
            show_if_changed(handle, asking)
        if asking:
            self._kind_shown()
        else:
            for form in self.forms.values():
                for handle in form.handles:
                    show_if_changed(handle, False)
        for handle in (self.gui_count, self.gui_close, self.gui_again, self.gui_csv, self.gui_new):
            show_if_changed(handle, not asking)
        show_if_changed(self.gui_earlier, rounds.has_earlier)
        if round_ is None:
            show_if_changed(self.gui_histogram, False)
            show_if_changed(self.gui_reveal, False)
            self._draw_sphere(None)
            self._show_gallery(None)
            return
        tally = round_.tally()
        question = round_.question
        write_if_changed(self.gui_count, count_text(round_.number, tally.answered, expected, tally.open, tr)
               + f"  \n{question.prompt}")
        if self.gui_close.disabled != (not tally.open):
            self.gui_close.disabled = not tally.open
        has_truth = question.has_truth
        show_if_changed(self.gui_reveal, has_truth)
        label = tr.gettext(HIDE_LABEL if round_.revealed else REVEAL_LABEL)
        if self.gui_reveal.label != label:
            self.gui_reveal.label = label
        write_if_changed(self.gui_histogram, tally_in_language(question.tally_text(tally, round_.revealed), tr))
        show_if_changed(self.gui_histogram, True)
        self._draw_sphere(tally if question.kind == "direction" else None, round_.revealed)
        self._show_gallery(round_ if question.kind == "state" else None)

    # ------------------------------------------------------------------ the gallery (State questions)
    def _show_gallery(self, round_: Any) -> None:
        """The gallery of the round's states (None: no state round; the gallery goes)."""
        shown = round_ is not None
        show_if_changed(self.gallery_panel.folder, shown)
        if not shown:
            if self.gallery.entries:
                self.gallery.clear()
            return
        self.gallery.set_entries(gallery_entries(round_))
        self.gallery.tick()
        self.gallery_panel.refresh()

    def play_entry(self, entry: GalleryEntry) -> None:
        """`Play this answer`: the chosen anonymous state in the presenter's room, playing."""
        self._check()
        if self.play is None:
            raise RuntimeError("this panel cannot play an answer")
        self.play(entry.answer)
        self.gallery_panel.line.content = for_gui(self.client.gui).gettext(
            "Playing answer {number} in the room.").format(number=entry.number)

    def _draw_sphere(self, tally: Tally | None, revealed: bool = False) -> None:
        """The sphere of the round's tips (`AnswerSphere.draw`); `tally` None: hidden."""
        self.sphere.draw(tally, revealed)

    def relabel(self, tr: Translator) -> None:
        """The folder's words in `tr`'s language (the browser chose another); the round written again."""
        self.words.relabel(tr)
        self.gallery_panel.relabel(tr)
        self.drawn = ()
        self.refresh()

    def remove(self) -> None:
        self.sphere.remove()
        self.gallery.remove()
        self.folder.remove()
