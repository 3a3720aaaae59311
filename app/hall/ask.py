"""Ask the class in the panels: the presenter's `Ask the class` folder and a student's question.

**The presenter** (`AskPanel`, shown only while the browser presents): a form (kind, question,
options, the right option or the true direction; a lesson step with a question fills it in) and
`Ask the class`; then the round: the live count ("31 of 44 answered", `count_text`: the answers
against every browser following or exploring, on every process), for a choice a histogram in
the panel (`histogram_text`, bars of text; the round before it beside after `Vote again`), for a
direction every answer's tip as a point on one sphere of radius SPHERE_RADIUS around the origin
(the body's centre) in the presenter's own 3D view, the true direction an arrow once revealed.
`Close the round`, `Vote again`, `Reveal the answer`, `Download answers (CSV)` and `New
question`; once a round has ended (`New question`, or a presenter stopped or left: the round is
the presenter's, `app.ask.hub`), `Download earlier rounds (CSV)`.  Every CSV is saved by the
browser at once (`app.kit.panel.download.save_download`).  The sphere is drawn in the
presenter's own scene (`client.scene`), so the followers' screens never show the others' answers.

**A student** (`AnswerPanel`, every browser but the presenter's): while a round is open, the
question and its controls sit at the top of the panel and the follower's panel is folded away
until the student answers; a choice is one button per option, a direction is an arrow turned by
a gizmo (a laptop) or by two sliders, azimuth and elevation (a phone), then `Send my
direction`; a state is `Answer from my copy` (an exact copy of the presenter's room to work in,
`Explore`) then `Send my state`.  Answered, the panel says the answer and offers `Change my
answer` until the round closes.  The arrow and its gizmo are in the student's own scene: no
other browser sees or moves them.

Everything a student sends goes through `Student.answer` (the session: its anonymous token, the
app's `Rounds`), where the round's rules hold (`app.ask.round`): a refused answer is said in the
student's panel and changes nothing.  Both panels refresh from the app loop (`refresh`), writing
only what changed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, Protocol

import numpy as np
import viser

from app.ask import JUDGES, Choice, Direction, Question, Rounds, Shown, State, Tally, question_from_dict
from app.ask.gallery import Gallery, GalleryEntry, GalleryPanel
from app.ask.judges import MOTION_WORDS, AnswerState, judge
from app.ask.questions import MAX_OPTIONS
from app.ask.state_tally import gallery_entries, judged_histogram_text
from app.kit.core.common import Wrap, show_if_changed, write_if_changed
from app.kit.panel.download import save_download

__all__ = ["ASK_LABEL", "CHANGE_LABEL", "CLOSE_LABEL", "CSV_LABEL", "DIRECTION_LABEL", "EARLIER_LABEL",
           "FROM_COPY_LABEL", "NEW_LABEL",
           "REVEAL_LABEL", "SPHERE_RADIUS", "STATE_LABEL", "VOTE_AGAIN_LABEL", "AnswerPanel", "AskPanel", "Student",
           "answer_words", "count_text", "direction_of", "histogram_text", "quaternion_to", "sphere_points"]

ASK_LABEL = "Ask the class"
CLOSE_LABEL = "Close the round"
VOTE_AGAIN_LABEL = "Vote again"
REVEAL_LABEL = "Reveal the answer"
HIDE_LABEL = "Hide the answer"
CSV_LABEL = "Download answers (CSV)"
EARLIER_LABEL = "Download earlier rounds (CSV)"
NEW_LABEL = "New question"
DIRECTION_LABEL = "Send my direction"
FROM_COPY_LABEL = "Answer from my copy"
STATE_LABEL = "Send my state"
CHANGE_LABEL = "Change my answer"
KINDS = {"Choice": "choice", "Direction": "direction", "State": "state"}
SPHERE_RADIUS = 1.6  # [scene units] the sphere of the answers' tips, around the origin
ARROW_LENGTH = 2.2  # [scene units] a student's arrow (out of the scenes' bodies)
ARROW_COLOR = (0, 150, 150)  # teal: no axis, vector or pointer of the scenes has it
TIP_COLOR = (40, 110, 230)
TRUTH_COLOR = (235, 160, 0)
TRUTH_REACH = 1.3  # the true direction's arrow ends this far out of the sphere (its tip seen past a vector)
BAR_CHARS = 16  # the longest bar of the histogram
ASK_ROOT = "/ask"  # the presenter's sphere and a student's arrow, each in its own browser's scene


def count_text(number: int, answered: int, expected: int, is_open: bool) -> str:
    """The presenter's live count (Markdown): "**Round 1** · 31 of 44 answered · open"."""
    state = "open" if is_open else "closed"
    return f"**Round {number}** · {answered} of {max(expected, answered)} answered · {state}"


def histogram_text(tally: Tally, revealed: bool) -> str:
    """A choice's answers as bars of text, one line per option (Markdown), with the round before
    it beside each bar after Vote again; the right option marked ✓ once revealed."""
    question = tally.question
    if not isinstance(question, Choice):
        return ""
    top = max((*tally.counts, *(tally.previous.counts if tally.previous is not None else ())), default=0)
    lines = []
    for k, option in enumerate(question.options):
        count = tally.counts[k]
        bar = "█" * (round(BAR_CHARS * count / top) if top else 0)
        mark = " ✓" if revealed and question.correct == k else ""
        share = f"{100.0 * tally.share(k):.0f} %" if tally.answered else "–"
        line = f"{k + 1}. {option}{mark}  \n`{bar or '·'}` **{count}** ({share})"
        if tally.previous is not None:
            line += f" · round {tally.previous.number}: {tally.previous.counts[k]}"
        lines.append(line)
    return "  \n".join(lines)


def answer_words(question: Question, value: Any) -> str:
    """A student's own answer in words (Markdown)."""
    if isinstance(question, Choice):
        return f"**{value + 1}. {question.options[value]}**"
    if isinstance(question, Direction):
        x, y, z = value
        azimuth = math.degrees(math.atan2(y, x))
        elevation = math.degrees(math.asin(max(-1.0, min(1.0, z))))
        return f"**azimuth {azimuth:.0f}°, elevation {elevation:.0f}°**"
    if isinstance(question, State) and question.judge is not None:
        try:
            judged = judge(question, value)
        except ValueError as error:
            return f"**your state** (not judged: {error})"
        if judged is not None:
            mark = "" if judged.good is None else " ✓ as asked" if judged.good else " ✗ not what was asked"
            return f"**{judged.words}**{mark}"
    return "**your state**"


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
            raise ValueError(f"Target: φ, θ, ψ in degrees wanted, got {text!r}") from None
        if len(angles) != 3:
            raise ValueError(f"Target: three angles φ, θ, ψ [deg] wanted, got {len(angles)}")
        return {"angles_deg": angles}
    if judge_name == "top_motion":
        if text not in MOTION_WORDS.values():
            raise ValueError(f"Target: one of {', '.join(MOTION_WORDS.values())}, got {text!r}")
        return {"motion": text}
    if judge_name == "axis_stays":
        if text not in ("stays", "flips"):
            raise ValueError(f"Target: stays or flips, got {text!r}")
        return {"stays": text == "stays"}
    raise ValueError("Target: choose a judge first")


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


def sphere_points(tally: Tally) -> np.ndarray:
    """The direction answers' tips on the sphere [scene units], shape (answered, 3), float32."""
    if not tally.directions:
        return np.zeros((0, 3), dtype=np.float32)
    return (SPHERE_RADIUS * np.asarray(tally.directions, dtype=np.float64)).astype(np.float32)


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
        gui: Any = client.gui
        self.folder = gui.add_folder(ASK_LABEL, order=order, visible=False)
        with self.folder:
            self.gui_kind = gui.add_dropdown("Kind", tuple(KINDS), initial_value="Choice",
                                             hint="a choice, a direction in 3D, or a state of the student's copy")
            self.gui_prompt = gui.add_text("Question", "", hint="what the class is asked")
            self.gui_options = gui.add_text("Options", "", hint="2 to 6 options, separated by |")
            self.gui_correct = gui.add_dropdown("Right option", ("none", *map(str, range(1, MAX_OPTIONS + 1))),
                                                initial_value="none", hint="revealed on demand")
            self.gui_truth = gui.add_text("True direction", "", visible=False,
                                          hint="x, y, z in the space frame (z up), or empty")
            self.gui_judge = gui.add_dropdown("Judge", ("none", *JUDGES), initial_value="none", visible=False,
                                              hint="how the app judges a state")
            self.gui_target = gui.add_text("Target", "", visible=False,
                                           hint="attitude: φ, θ, ψ [deg] · top_motion: loops, waves, ... · "
                                                "axis_stays: stays or flips")
            self.gui_ask = gui.add_button(ASK_LABEL, icon=viser.Icon.HELP,
                                          hint="every student answers from their own copy")
            self.gui_count = gui.add_markdown("", visible=False)
            self.gui_histogram = gui.add_markdown("", visible=False)
            self.gui_close = gui.add_button(CLOSE_LABEL, visible=False, hint="no more answers")
            self.gui_again = gui.add_button(VOTE_AGAIN_LABEL, visible=False,
                                            hint="the same question again; this round stays beside it")
            self.gui_reveal = gui.add_button(REVEAL_LABEL, visible=False, hint="the right answer on this screen")
            self.gui_csv = gui.add_button(CSV_LABEL, icon=viser.Icon.DOWNLOAD, visible=False,
                                          hint="every round's anonymous answers")
            self.gui_new = gui.add_button(NEW_LABEL, visible=False, hint="back to the form")
            self.gui_earlier = gui.add_button(EARLIER_LABEL, icon=viser.Icon.DOWNLOAD, visible=False,
                                              hint="the anonymous answers of the rounds that ended: "
                                                   "yours and those of the presenters before you")
            self.gallery = Gallery(client.scene, root=f"{ASK_ROOT}/gallery")  # its node made now, hidden
            self.gallery_panel = GalleryPanel(gui, self.gallery, lambda entry: self.play_entry(entry), guard)
            self.gallery_panel.folder.visible = False
        self._filled: State | None = None  # a lesson's state question: its target, unless the form changes
        # The sphere, the tips and the true direction, made hidden now (see AnswerPanel: no node is made in a frame)
        scene = client.scene
        self._sphere: list[Any] = [
            scene.add_icosphere(f"{ASK_ROOT}/sphere", radius=SPHERE_RADIUS, color=(150, 170, 200), subdivisions=3,
                                opacity=0.12, cast_shadow=False, receive_shadow=False, visible=False),
            scene.add_point_cloud(f"{ASK_ROOT}/tips", np.zeros((1, 3), np.float32), colors=TIP_COLOR,
                                  point_size=0.12, point_shape="circle", visible=False),
            scene.add_arrows(f"{ASK_ROOT}/truth", np.zeros((1, 2, 3), np.float32), TRUTH_COLOR, shaft_radius=0.05,
                             head_radius=0.12, head_length=0.25, visible=False),
        ]
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
            raise PermissionError("only the presenter can ask the class and see its answers")

    # ------------------------------------------------------------------ the form
    def _kind_shown(self) -> None:
        if not self.presenting():
            return
        kind = KINDS.get(str(self.gui_kind.value))
        if kind is None:  # a client can send anything
            self.gui_kind.value = "Choice"
            return
        for handle, shown in ((self.gui_options, kind == "choice"), (self.gui_correct, kind == "choice"),
                              (self.gui_truth, kind == "direction"), (self.gui_judge, kind == "state"),
                              (self.gui_target, kind == "state")):
            show_if_changed(handle, shown)

    def form_question(self) -> Question:
        """The question the form describes; ValueError naming what is wrong."""
        kind = KINDS.get(str(self.gui_kind.value), "choice")
        prompt = str(self.gui_prompt.value)
        if kind == "choice":
            options = [o.strip() for o in str(self.gui_options.value).split("|") if o.strip()]
            correct = None if self.gui_correct.value == "none" else int(self.gui_correct.value) - 1
            if correct is not None and correct >= len(options):
                raise ValueError(f"the right option {correct + 1} is not one of the {len(options)} options")
            return question_from_dict({"kind": kind, "prompt": prompt, "options": options, "correct": correct})
        if kind == "direction":
            text = str(self.gui_truth.value).replace("(", "").replace(")", "").strip()
            truth = None
            if text:
                try:
                    truth = [float(part) for part in text.replace(";", ",").split(",")]
                except ValueError:
                    raise ValueError(f"True direction: three numbers x, y, z wanted, got {text!r}") from None
            return question_from_dict({"kind": kind, "prompt": prompt, "truth": truth})
        judge_name = None if self.gui_judge.value == "none" else str(self.gui_judge.value)
        target = None if judge_name is None else target_of(judge_name, str(self.gui_target.value))
        filled = self._filled
        if (filled is not None and judge_name == filled.judge and not str(self.gui_target.value).strip()
                and filled.scene == self.scene_title()):  # a lesson's question: its whole target
            target = None if filled.target is None else dict(filled.target)
        return question_from_dict({"kind": kind, "prompt": prompt, "scene": self.scene_title(), "judge": judge_name,
                                   "target": target})

    def fill(self, question: Question) -> None:
        """Put `question` into the form (a lesson step's question), ready for `Ask the class`."""
        self.gui_kind.value = {v: k for k, v in KINDS.items()}[question.kind]
        self.gui_prompt.value = question.prompt
        if isinstance(question, Choice):
            self.gui_options.value = " | ".join(question.options)
            self.gui_correct.value = "none" if question.correct is None else str(question.correct + 1)
        elif isinstance(question, Direction):
            self.gui_truth.value = "" if question.truth is None else ", ".join(f"{c:.3g}" for c in question.truth)
        elif isinstance(question, State):
            self.gui_judge.value = question.judge if question.judge in JUDGES else "none"
            self.gui_target.value = ""  # empty: the lesson's own target is asked (`form_question`)
        self._filled = question if isinstance(question, State) else None
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
        save_download(self.client, f"answers-round-{round_.number if round_ else 0}.csv", text)

    def download_earlier(self) -> None:
        """The rounds that ended (this presenter's and earlier presenters', `Rounds.earlier_csv`)
        as one CSV file, saved by the browser at once."""
        self._check()
        text = self.rounds.earlier_csv()
        if not text:
            raise LookupError("no earlier round to download")
        save_download(self.client, "answers-earlier-rounds.csv", text)

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
        key = (rounds.version, rounds.answers_version, expected)
        self.gallery.tick()  # answers that came within the gallery's redraw period
        if key == self.drawn:
            return
        self.drawn = key
        asking = round_ is None
        for handle in (self.gui_kind, self.gui_prompt, self.gui_ask):
            show_if_changed(handle, asking)
        if asking:
            self._kind_shown()
        else:
            for handle in (self.gui_options, self.gui_correct, self.gui_truth, self.gui_judge, self.gui_target):
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
        write_if_changed(self.gui_count, count_text(round_.number, tally.answered, expected, tally.open)
               + f"  \n{question.prompt}")
        if self.gui_close.disabled != (not tally.open):
            self.gui_close.disabled = not tally.open
        has_truth = getattr(question, "correct", None) is not None or getattr(question, "truth", None) is not None
        show_if_changed(self.gui_reveal, has_truth)
        label = HIDE_LABEL if round_.revealed else REVEAL_LABEL
        if self.gui_reveal.label != label:
            self.gui_reveal.label = label
        if isinstance(question, Choice):
            write_if_changed(self.gui_histogram, histogram_text(tally, round_.revealed))
        elif isinstance(question, Direction):
            near = f" · {tally.within(15.0)} within 15° of the true direction" if round_.revealed else ""
            write_if_changed(self.gui_histogram, f"{tally.answered} tips on the sphere in the 3D view{near}")
        else:
            histogram = judged_histogram_text(tally)
            write_if_changed(self.gui_histogram, histogram or f"{tally.answered} states sent")
        show_if_changed(self.gui_histogram, True)
        self._draw_sphere(tally if isinstance(question, Direction) else None, round_.revealed)
        self._show_gallery(round_ if isinstance(question, State) else None)

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
        self.gallery_panel.line.content = f"Playing answer {entry.number} in the room."

    def _draw_sphere(self, tally: Tally | None, revealed: bool = False) -> None:
        """The sphere, the tips of the answers and (revealed) the true direction, in this browser's
        scene; `tally` None: hidden."""
        sphere, tips, truth_arrow = self._sphere
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
        for handle in self._sphere:
            handle.remove()
        self.gallery.remove()
        self.folder.remove()


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
        self._writing = False  # the server moves the sliders: their callbacks do nothing
        gui: Any = student.client.gui
        self.folder = gui.add_folder("Question", order=order, visible=False)
        with self.folder:
            self.gui_prompt = gui.add_markdown("")
            self.gui_options = [gui.add_button(f"Option {k + 1}", visible=False) for k in range(MAX_OPTIONS)]
            self.gui_azimuth = gui.add_slider("Azimuth", min=-180.0, max=180.0, step=1.0, initial_value=0.0,
                                              visible=False, hint="[deg] from x towards y, about the vertical z")
            self.gui_elevation = gui.add_slider("Elevation", min=-90.0, max=90.0, step=1.0, initial_value=45.0,
                                                visible=False, hint="[deg] above the horizontal x-y plane")
            self.gui_send_direction = gui.add_button(DIRECTION_LABEL, visible=False,
                                                     hint="or turn the arrow in the 3D view first")
            self.gui_from_copy = gui.add_button(FROM_COPY_LABEL, visible=False,
                                                hint="an exact copy of the presenter's scene, yours to change")
            self.gui_send_state = gui.add_button(STATE_LABEL, visible=False, hint="your copy's state as it is now")
            self.gui_mine = gui.add_markdown("", visible=False)
            self.gui_change = gui.add_button(CHANGE_LABEL, visible=False, hint="until the round closes")
        for k, button in enumerate(self.gui_options):
            button.on_click(guard("answer", lambda _e, k=k: self.send(k)))
        self.gui_azimuth.on_update(guard("azimuth", lambda _e: self._sliders_moved()))
        self.gui_elevation.on_update(guard("elevation", lambda _e: self._sliders_moved()))
        self.gui_send_direction.on_click(guard("send my direction", lambda _e: self.send(self.direction())))
        self.gui_from_copy.on_click(guard("answer from my copy", lambda _e: self._from_copy()))
        self.gui_send_state.on_click(guard("send my state", lambda _e: self.send(student.state_answer())))
        self.gui_change.on_click(guard("change my answer", lambda _e: self._edit()))
        # The arrow and its gizmo, made hidden now: a node made inside the app loop's frame holds
        # back that frame's panel updates for this browser (app.wire), so the round only shows them.
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

    def send(self, value: Any) -> None:
        """Answer `value`; the panel then shows the answer (a refusal is raised: the guard says it)."""
        self.student.answer(value)
        self.editing = False
        self.drawn = ()
        self.refresh()

    def _edit(self) -> None:
        self.editing = True
        self.drawn = ()
        self.refresh()

    def _from_copy(self) -> None:
        self.student.answer_from_copy()
        self.drawn = ()
        self.refresh()

    def _sliders_moved(self) -> None:
        if not self._writing:
            self._gizmo.wxyz = quaternion_to(self.direction())

    def _gizmo_moved(self) -> None:
        direction = rotated_z(self._gizmo.wxyz)
        azimuth, elevation = angles_of(direction)
        self._writing = True
        try:
            self.gui_azimuth.value = round(azimuth)
            self.gui_elevation.value = round(elevation)
        finally:
            self._writing = False

    def _arrow_shown(self, shown: bool) -> None:
        """The student's arrow and its gizmo (rotation only), in its own scene."""
        show_if_changed(self._gizmo, shown)

    def refresh(self) -> None:
        """Show the round the class is asked now (or nothing), the controls or this browser's answer."""
        shown: Shown | None = self.rounds.shown() if self.active else None
        mine = self.student.my_answer() if shown is not None else None
        key = (None if shown is None else (shown.id, shown.open), self.editing, mine is None,
               repr(mine), getattr(self.student, "mode", None))
        if key == self.drawn:
            return
        self.drawn = key
        if shown is None:
            show_if_changed(self.folder, False)
            self._arrow_shown(False)
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
        head = f"**Question {shown.number}** · {question.prompt}"
        if not shown.open:
            head += "  \n*The round is closed.*"
        write_if_changed(self.gui_prompt, head)
        show_if_changed(self.folder, True)
        is_choice, is_direction, is_state = (isinstance(question, kind) for kind in (Choice, Direction, State))
        for k, button in enumerate(self.gui_options):
            there = is_choice and controls and k < len(question.options)  # type: ignore[union-attr]
            if there:
                label = f"{k + 1}. {question.options[k]}"  # type: ignore[union-attr]
                if button.label != label:
                    button.label = label
            show_if_changed(button, there)
        for handle in (self.gui_azimuth, self.gui_elevation, self.gui_send_direction):
            show_if_changed(handle, is_direction and controls)
        self._arrow_shown(is_direction and controls)
        exploring = getattr(self.student, "mode", None) != "following"
        show_if_changed(self.gui_from_copy, is_state and controls and not exploring)
        show_if_changed(self.gui_send_state, is_state and controls and exploring)
        show_if_changed(self.gui_mine, mine is not None)
        if mine is not None:
            write_if_changed(self.gui_mine, f"Your answer: {answer_words(question, mine)}"
                   + (" · you can change it until the round closes." if shown.open else ""))
        show_if_changed(self.gui_change, mine is not None and shown.open and not self.editing)
        self.student.folded_for_question(shown.open and mine is None)

    def remove(self) -> None:
        self._gizmo.remove()
        self.folder.remove()
