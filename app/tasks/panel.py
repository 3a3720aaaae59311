"""Tasks in the panel: the `Task` folder every browser has (a student's and a lecturer's way in)
and `Make a task` in the presenter's `Ask the class` form (`attach_tasks` builds both for a
session; `app.main` calls it for every new browser).

- A student types the code in `Task code` and presses `Open the task`: their own room opens with
  the task's scene and preset (a follower leaves the presenter with a copy first), the folder
  shows the lecturer's words, the due time, the attempts and the question (`Next question` and
  `Previous question` walk a worksheet); they give a name or student number (once per task),
  answer (a number, an option, a direction, or the state of their room) and press `Submit`: the
  verdict, the attempt and the receipt code are said under it.
- The presenter fills the Ask form as for the class, sets `Due in [h]`, `Attempts` and `Counts`
  and presses `Make a task` (or first `Add to the worksheet` for each question of a worksheet):
  the task code is shown.
- The lecturer types the task code and the presenter code (`Lecturer's code`) and presses
  `Open as lecturer`: the live table (one row a student), the 3D views of a direction or state
  question's answers (`app.tasks.views`: the sphere of tips, the gallery), `Download results
  (CSV)`, `Close the task` and `Extend` (the due time `Due in [h]` from now).

Every action checks who may do it on the server (a hostile page can press hidden buttons and
send any value): a student reads only their own submissions, the lecturer's buttons need the
presenter code checked in this browser, `Make a task` needs this browser to present.  A refusal
is said in the folder and changes nothing; a `Make a task` form filled wrongly (the due time, the
attempts, the words, the Ask form's question) is said under its button in the browser's language,
the field named as the form names it (`MAKER_FIELDS`).
"""

from __future__ import annotations

import math
import threading
import time
import weakref
from collections.abc import Callable
from datetime import UTC, datetime
from typing import Any

import viser

from app.ask.gallery import GalleryEntry, play_answer
from app.ask.questions import Question
from app.ask.round import Tally
from app.ask.verdict_words import verdict_in_language
from app.hall.ask_kinds import direction_of
from app.hall.ask_presenter import tally_in_language
from app.i18n import N_, Labels, Translator, for_gui, translator
from app.kit.panel.download import save_download
from app.lecture.gate import code_matches
from app.refusals import NotAllowed
from app.scenes import SCENES
from app.sharestore import EXAMPLE, format_code
from app.tasks.model import (
    GRADEBOOK_COLUMNS,
    MAX_QUESTIONS,
    GradebookRow,
    Submission,
    Task,
    TaskCodeError,
    TaskRefused,
    counted,
    gradebook_csv,
    gradebook_rows,
    is_judged,
    iso_time,
)
from app.tasks.store import TaskRules
from app.tasks.views import TaskViews
from app.tasks.words import cell as _cell
from app.tasks.words import receipt_words, refusal_words

__all__ = ["ADD_LABEL", "CLOSE_LABEL", "CSV_LABEL", "EXTEND_LABEL", "LECTURER_LABEL", "MAKE_LABEL", "OPEN_LABEL",
           "RECEIPT_LABEL", "SUBMIT_LABEL", "TASK_FOLDER", "TaskPanel", "attach_tasks", "table_text", "tallies_text"]

TASK_FOLDER = N_("Task")
OPEN_LABEL = N_("Open the task")
LECTURER_LABEL = N_("Open as lecturer")
SUBMIT_LABEL = N_("Submit")
NEXT_LABEL = N_("Next question")
PREVIOUS_LABEL = N_("Previous question")
MAKE_LABEL = N_("Make a task")
ADD_LABEL = N_("Add to the worksheet")
CSV_LABEL = N_("Download results (CSV)")
CLOSE_LABEL = N_("Close the task")
EXTEND_LABEL = N_("Extend")
RECEIPT_LABEL = N_("Check a receipt")
POLL_S = 2.0  # [s] the lecturer's open table is written again this often (other processes' submissions)
ATTEMPT_CHOICES = ("1", "2", "3", "5", "10", N_("unlimited"))


def table_text(task: Task, submissions: list[Submission], now: float, tr: Translator | None = None) -> str:
    """The lecturer's live table (Markdown): a line about the task, then one row a student
    (name, number, attempts, score, verdict, when), in `tr`'s language (English by default; the
    students' names and the judges' verdicts as they are)."""
    tr = tr or translator("en")
    _ = tr.gettext
    rows = gradebook_rows(task, submissions)
    state = _("closed") if task.closed else _("open") if now < task.due else _("past its due time")
    judged = [r.score for r in rows if r.score is not None]
    mean = _(" · mean score {mean}").format(mean=tr.decimal(sum(judged) / len(judged), 2)) if judged else ""
    head = (_("**Task {code}**").format(code=task.shown_code) + " · "
            + tr.ngettext("{count} question", "{count} questions", len(task.questions)).format(
                count=len(task.questions))
            + " · " + _("due {due}").format(due=iso_time(task.due)) + f" · {state} · {policy_words(task, tr)}  \n"
            + tr.ngettext("{count} student", "{count} students", len(rows)).format(count=len(rows)) + ", "
            + tr.ngettext("{count} submission", "{count} submissions", len(submissions)).format(
                count=len(submissions)) + mean)
    if not rows:
        return head + "  \n" + _("no submissions yet")
    number = "Number" if tr.language == "en" else _("Student number")  # ("Number" is a question's kind)
    columns = (_("Name"), number, _("Attempts"), _("Score"), _("Verdict"), _("Last submitted (UTC)"))
    lines = [head, "", "| " + " | ".join(columns) + " |", "|---|---|---|---|---|---|"]
    for r in rows:
        score = "–" if r.score is None else tr.decimal(r.score, 2)
        lines.append(f"| {_cell(r.name) or '–'} | {_cell(r.number) or '–'} | {r.attempts} | {score} | "
                     f"{_cell(_verdict_cell(r))} | {short_time(r.last_submitted, tr)} |")
    return "\n".join(lines)


def policy_words(task: Task, tr: Translator) -> str:
    """The task's attempts and which counts (`Policy.words`) in `tr`'s language."""
    policy = task.policy
    if tr.language == "en":
        return policy.words()
    _ = tr.gettext
    if policy.attempts == 1:
        return tr.ngettext("{count} attempt", "{count} attempts", 1).format(count=1)
    many = (_("unlimited attempts") if policy.attempts is None
            else tr.ngettext("{count} attempt", "{count} attempts", policy.attempts).format(count=policy.attempts))
    return _("{attempts}, the {counts} counts").format(attempts=many, counts=_(policy.counts))


GRADEBOOK_WORDS: dict[str, str] = {
    "name": N_("name"), "number": N_("number"), "score": N_("score"), "attempts": N_("attempts"),
    "last_submitted": N_("last_submitted"), "verdict": N_("verdict")}
"""The gradebook's CSV columns (`model.GRADEBOOK_COLUMNS`) a lecturer reads in their language."""


def gradebook_in_language(text: str, tr: Translator) -> str:
    """The gradebook's CSV `text` with its header row in `tr`'s language (the lecturer's); the
    rows (names, scores with a point, ISO times) as they are: machine-readable."""
    header = ",".join(GRADEBOOK_COLUMNS)
    first, newline, rest = text.partition("\n")
    if first != header:
        return text
    return ",".join(tr.gettext(GRADEBOOK_WORDS[c]) for c in GRADEBOOK_COLUMNS) + newline + rest


def tallies_text(task: Task, submissions: list[Submission], now: float, tr: Translator | None = None) -> str:
    """Per question, the counted answers (one a student: `model.counted`) in words: how many
    answered and were right, and a choice's bars or a number's histogram (`QuestionKind.tally_text`,
    the right answer marked) as `Ask the class` shows them."""
    by_student: dict[str, list[Submission]] = {}
    for s in submissions:
        by_student.setdefault(s.student.key, []).append(s)
    lines = []
    for index, question in enumerate(task.questions):
        chosen = [c for subs in by_student.values()
                  if (c := counted([s for s in subs if s.question == index], task.policy.counts)) is not None]
        right = sum(1 for c in chosen if c.score == 1.0)
        words = tr or translator("en")
        line = (f"**Q{index + 1}** · " + words.gettext("{count} answered").format(count=len(chosen))
                + (words.gettext(" · {count} right").format(count=right) if is_judged(question) else ""))
        if chosen and question.kind in ("choice", "number"):
            values = [c.value for c in chosen]
            tally = Tally(1, question, task.open_now(now), len(chosen),
                          **question.tally_fields(values, [None] * len(values)))
            line += "  \n" + tally_in_language(question.tally_text(tally, revealed=True), words)
        lines.append(line)
    return "  \n".join(lines)


def short_time(seconds: float, tr: Translator | None = None) -> str:
    """`seconds` since the epoch as "28 Nov 14:05" (UTC), for the table's narrow column; the
    month's name in `tr`'s language."""
    when = datetime.fromtimestamp(seconds, UTC)
    if tr is None or tr.language == "en":
        return when.strftime("%d %b %H:%M")
    from babel.dates import format_datetime  # noqa: PLC0415 - Babel's month names

    return str(format_datetime(when, "dd MMM HH:mm", tzinfo=UTC, locale=tr.language))


def _verdict_cell(row: GradebookRow) -> str:
    """The table's verdict: the words for one question; for a worksheet a mark a question
    ("1 ✓ · 2 ✗ · 3 –": right, wrong, not answered; "·" answered, not judged), the words in the CSV."""
    if len(row.scores) <= 1:
        return row.verdict
    marks = []
    for k, (score, answered) in enumerate(zip(row.scores, row.answered, strict=True)):
        mark = "–" if not answered else "✓" if score == 1.0 else "✗" if score == 0.0 else "·"
        marks.append(f"{k + 1} {mark}")
    return " · ".join(marks)


MAX_DUE_HOURS = 24 * 400  # [h] `Due in [h]` and `New due in [h]` at most this (model.MAX_DUE_AHEAD_S)


def _hours(value: Any, where: str = N_("Due in [h]")) -> float:
    """[h] a due time typed in the field `where` (a msgid); TaskRefused naming it unless a number
    more than 0 and at most MAX_DUE_HOURS."""
    try:
        hours = float(value)
    except (TypeError, ValueError):
        hours = math.nan
    if not math.isfinite(hours) or not 0.0 < hours <= MAX_DUE_HOURS:
        raise TaskRefused(N_("{where}: a number of hours, more than 0 and at most {most}"), where=where,
                          most=MAX_DUE_HOURS)
    return hours


MAKER_FIELDS = {"due": N_("Due in [h]"), "attempts": N_("Attempts"), "counts": N_("Counts"),
                "words": N_("Words for the task"), "prompt": N_("Question"), "options": N_("Options"),
                "correct": N_("Right option"), "value": N_("Right value"), "unit": N_("Unit"),
                "tolerance": N_("Tolerance"), "truth": N_("True direction")}
"""A task's or a question's field a refusal names (`model.make_task`'s, `app.ask.questions`'
`where`) -> the field of `Make a task` or the Ask form the lecturer fills (a msgid)."""


def attach_tasks(session: Any, store: TaskRules) -> TaskPanel:
    """Build the `Task` folder (after `Share`) and `Make a task` (in the Ask form) for `session`
    (an `app.session.Session`); kept as `session.task_panel`."""
    panel = TaskPanel(session, store)
    session.task_panel = panel
    return panel


class TaskMaking:
    """The presenter's `Make a task` in the Ask form (a part of `TaskPanel`): the worksheet of
    questions added, the task made of them and its code said under the button."""

    session: Any
    store: TaskRules
    clock: Callable[[], float]
    ask: Any
    worksheet: list[tuple[Question, str | None, str | None]]
    made: Task | None

    def _build_maker(self, gui: Any, guard: Any) -> None:
        ask = getattr(self.session, "ask_panel", None)
        self.ask = ask
        if ask is None:
            return
        base = float(ask.gui_ask.order)
        with ask.folder:
            self.gui_due = gui.add_number(N_("Due in [h]"), 168.0, min=0.01, step=0.01, order=base + 0.11,
                                          hint=N_("a task: the students answer at home until then"))
            self.gui_attempts = gui.add_dropdown(N_("Attempts"), ATTEMPT_CHOICES, initial_value="1",
                                                 order=base + 0.12)
            self.gui_counts = gui.add_dropdown(N_("Counts"), (N_("best"), N_("last")), initial_value="best",
                                               order=base + 0.13, hint=N_("which attempt counts for the grade"))
            self.gui_words = gui.add_text(N_("Words for the task"), "", order=base + 0.14,
                                          hint=N_("what the students read with the question"))
            self.gui_add = gui.add_button(ADD_LABEL, order=base + 0.15,
                                          hint=N_("this question, then the next: one task of several questions"))
            self.gui_make = gui.add_button(MAKE_LABEL, icon=viser.Icon.CLIPBOARD_LIST, order=base + 0.16,
                                           hint=N_("a task code the students use at home, in their own room"))
            self.gui_made = gui.add_markdown("", visible=False, order=base + 0.17)
        self.maker_words = Labels(gui)
        self.maker_words.take(self.gui_due, self.gui_words, self.gui_add, self.gui_make)
        self.maker_words.take(self.gui_attempts, self.gui_counts, options=True)
        ask.form_extras = (self.gui_due, self.gui_attempts, self.gui_counts, self.gui_words, self.gui_add,
                           self.gui_make)  # shown with the form, hidden while a round runs
        self.gui_add.on_click(guard("add to the worksheet", lambda _e: self.add_to_worksheet()))
        self.gui_make.on_click(guard("make a task", lambda _e: self.make_from_form()))

    def _presenting(self) -> None:
        ask = self.ask
        if ask is None or not ask.presenting():
            raise NotAllowed(N_("only the presenter can make a task"))

    def add_to_worksheet(self) -> None:
        """The Ask form's question joins the worksheet of the next task made here; a form filled
        wrongly is said under the button in this browser's language (`_refused`), nothing added."""
        self._presenting()
        assert self.ask is not None
        tr = for_gui(self.session.client.gui)
        try:
            if len(self.worksheet) >= MAX_QUESTIONS:
                raise TaskRefused(N_("A worksheet has at most {most} questions."), most=MAX_QUESTIONS)
            question = self.ask.form_question()
        except ValueError as error:
            self._said_made(self._refused(error, tr))
            return
        scene, preset = self._place_now()
        self.worksheet.append((question, scene, preset))
        self._said_made(tr.ngettext("{count} question in the worksheet; *{make}* makes the task of them.",
                                    "{count} questions in the worksheet; *{make}* makes the task of them.",
                                    len(self.worksheet)).format(count=len(self.worksheet), make=tr.gettext(MAKE_LABEL)))

    def make_from_form(self) -> Task | None:
        """`Make a task`: the worksheet's questions (or the Ask form's question alone), the scene
        and preset shown, due `Due in [h]` from now: a task; its code said under the button.  A
        form filled wrongly is said there instead, in this browser's language (None, nothing made)."""
        self._presenting()
        assert self.ask is not None
        tr = for_gui(self.session.client.gui)
        try:
            task = self._task_of_form()
        except ValueError as error:  # a TaskRefused, or the Ask form's question check
            self._said_made(self._refused(error, tr))
            return None
        self.worksheet = []
        self.made = task
        self._said_made(tr.gettext("Task code **{code}** · due {due} · {policy}: students type it in the {folder} "
                                   "folder and open it.").format(code=task.shown_code, due=iso_time(task.due),
                                                                  policy=policy_words(task, tr),
                                                                  folder=tr.gettext(TASK_FOLDER)))
        return task

    def _task_of_form(self) -> Task:
        """The task the form and the worksheet describe, kept in the store; ValueError (a
        TaskRefused, or a question's check) naming what is wrong, nothing kept."""
        assert self.ask is not None
        entries = list(self.worksheet) or [(self.ask.form_question(), *self._place_now())]
        words = self.maker_words
        chosen = words.english(self.gui_attempts.value)
        if chosen not in ATTEMPT_CHOICES:  # a client can send anything
            raise TaskRefused(N_("{where}: choose one of the options"), where="attempts")
        hours = _hours(self.gui_due.value)
        return self.store.create([q for q, _, _ in entries], due=self.clock() + 3600.0 * hours,
                                 attempts=None if chosen == "unlimited" else int(chosen),
                                 counts=words.english(self.gui_counts.value), scene=entries[0][1],
                                 preset=entries[0][2], words=str(self.gui_words.value),
                                 places=[(scene, preset) for _, scene, preset in entries] if len(entries) > 1 else ())

    @staticmethod
    def _refused(error: ValueError, tr: Translator) -> str:
        """What the form's refusal `error` says, in `tr`'s language, the field named as the form names it."""
        return refusal_words(error, tr, MAKER_FIELDS)

    def _place_now(self) -> tuple[str | None, str | None]:
        """(scene, preset) of the room shown now."""
        room = self.session.room
        preset = getattr(room.sim, "preset", None)
        return room.scene.title, preset if isinstance(preset, str) else None

    def _said_made(self, text: str) -> None:
        self.gui_made.content = text
        self.gui_made.visible = True


class TaskPanel(TaskMaking):
    """One browser's tasks: the `Task` folder and, for a presenter, `Make a task` (module docstring).

    Attributes:
        task: the task opened as a student (or None); question: its question shown (0-based).
        lecturer_task: the task opened as lecturer (or None).  made: the last task made here.
        worksheet: the questions added for the next task made here.
    """

    def __init__(self, session: Any, store: TaskRules, clock: Callable[[], float] | None = None) -> None:
        self.session = session
        self.store = store
        self.clock: Callable[[], float] = clock or (lambda: store.clock())
        """[s since the epoch] the time the folder says things by: the store's clock (the one that
        refuses a late submission) unless given."""
        self.task: Task | None = None
        self.question = 0
        self.lecturer_task: Task | None = None
        self.views: TaskViews | None = None  # the lecturer's 3D views, made at the first `Open as lecturer`
        self.made: Task | None = None
        self.worksheet: list[tuple[Question, str | None, str | None]] = []
        """The questions added for the next task made here, each with the scene and preset shown then."""
        self.opened_place: tuple[str | None, str | None] | None = None  # the place the student's room opened
        self._polling = False
        client: viser.ClientHandle = session.client
        self.client = client
        guard = session.guard
        gui: Any = client.gui
        share = getattr(session, "share", None)
        order = None if share is None else float(share.folder.order) + 0.5
        with client.atomic():
            self.folder = gui.add_folder(TASK_FOLDER, order=order, expand_by_default=False)
            with self.folder:
                self.gui_code = gui.add_text(N_("Task code"), "",
                                             hint=N_("the code your lecturer gave, like {example}"))
                self.gui_open = gui.add_button(OPEN_LABEL, icon=viser.Icon.SCHOOL,
                                               hint=N_("the task's scene opens in your own room with its question"))
                self.gui_note = gui.add_markdown("", visible=False)
                self.gui_about = gui.add_markdown("", visible=False)
                self.gui_name = gui.add_text(N_("Your name"), "", visible=False, hint=N_("given once per task"))
                self.gui_student_number = gui.add_text(N_("Student number"), "", visible=False,
                                                       hint=N_("or your name, or both"))
                self.gui_my_receipt = gui.add_text(N_("Your receipt"), "", visible=False,
                                                   hint=N_("to go on from another browser: a receipt of yours"))
                self.gui_choice = gui.add_dropdown(N_("Your option"), ("-",), visible=False)
                self.gui_value = gui.add_number(N_("Your number"), 0.0, step=0.0001, visible=False)
                self.gui_azimuth = gui.add_slider(N_("Azimuth [deg]"), min=-180.0, max=180.0, step=1.0,
                                                  initial_value=0.0, visible=False)
                self.gui_elevation = gui.add_slider(N_("Elevation [deg]"), min=-90.0, max=90.0, step=1.0,
                                                    initial_value=45.0, visible=False)
                self.gui_submit = gui.add_button(SUBMIT_LABEL, icon=viser.Icon.SEND, visible=False,
                                                 hint=N_("your answer is judged and kept; a receipt code is shown"))
                self.gui_verdict = gui.add_markdown("", visible=False)
                self.gui_previous = gui.add_button(PREVIOUS_LABEL, visible=False)
                self.gui_next = gui.add_button(NEXT_LABEL, visible=False)
                self.gui_lecturer_code = gui.add_text(N_("Lecturer's code"), "",
                                                      hint=N_("the presenter code: the lecturer "
                                                              "sees every submission of the task"))
                self.gui_lecturer = gui.add_button(LECTURER_LABEL, icon=viser.Icon.TABLE)
                self.gui_table = gui.add_markdown("", visible=False)
                self.gui_csv = gui.add_button(CSV_LABEL, icon=viser.Icon.DOWNLOAD, visible=False,
                                              hint=N_("one row a student: name, number, score 0-1, attempts, "
                                                   "last submitted, verdict"))
                self.gui_extend_hours = gui.add_number(N_("New due in [h]"), 24.0, min=0.01, step=0.01, visible=False,
                                                       hint=N_("Extend: due this many hours from now, open again"))
                self.gui_extend = gui.add_button(EXTEND_LABEL, visible=False)
                self.gui_close = gui.add_button(CLOSE_LABEL, visible=False, hint=N_("no more submissions"))
                self.gui_receipt = gui.add_text(N_("Receipt"), "", visible=False,
                                                hint=N_("a receipt code a student shows: the submission it stands for"))
                self.gui_check = gui.add_button(RECEIPT_LABEL, visible=False)
                self.gui_receipt_note = gui.add_markdown("", visible=False)
            self.gui_open.on_click(guard("open the task", lambda _e: self.open(self.gui_code.value)))
            self.gui_submit.on_click(guard("submit", lambda _e: self.submit()))
            self.gui_next.on_click(guard("next question", lambda _e: self.show_question(self.question + 1)))
            self.gui_previous.on_click(guard("previous question", lambda _e: self.show_question(self.question - 1)))
            self.gui_lecturer.on_click(guard("open as lecturer", lambda _e: self.open_as_lecturer(
                self.gui_code.value, self.gui_lecturer_code.value)))
            self.gui_csv.on_click(guard("download results", lambda _e: self.download()))
            self.gui_close.on_click(guard("close the task", lambda _e: self.close_task()))
            self.gui_check.on_click(guard("check a receipt", lambda _e: self.check_receipt(self.gui_receipt.value)))
            self.gui_extend.on_click(guard("extend the task", lambda _e: self.extend(self.gui_extend_hours.value)))
            self.words = Labels(gui)
            self.words.take(self.folder, self.gui_open, self.gui_name, self.gui_student_number, self.gui_my_receipt,
                            self.gui_choice, self.gui_value, self.gui_submit, self.gui_azimuth, self.gui_elevation,
                            self.gui_previous, self.gui_next,
                            self.gui_lecturer_code, self.gui_lecturer, self.gui_csv, self.gui_extend_hours,
                            self.gui_extend, self.gui_close, self.gui_receipt, self.gui_check)
            self.words.take(self.gui_code, example=EXAMPLE)
            self._build_maker(gui, guard)
        changed = weakref.WeakMethod(self._store_changed)  # the store does not keep a closed browser's panel

        def listener(code: str) -> None:
            method = changed()
            if method is None:
                store.listeners.remove(listener)
            else:
                method(code)

        store.listeners.append(listener)

    def relabel(self, tr: Translator) -> None:
        """The folder's words (and `Make a task`'s) in `tr`'s language (the browser chose another);
        the question shown and the lecturer's table written again."""
        self.words.relabel(tr)
        if self.ask is not None:
            self.maker_words.relabel(tr)
        if self.views is not None:
            self.views.relabel(tr)
        if self.task is not None and self.gui_about.visible:
            self.show_question(self.question)
        if self.lecturer_task is not None:
            self.refresh_table()

    def _(self, message: str) -> str:
        """`message` in this browser's language now."""
        return for_gui(self.client.gui).gettext(message)

    # ------------------------------------------------------------------ the student's side
    def _say(self, text: str) -> None:
        self.gui_note.content = text
        self.gui_note.visible = bool(text)

    def open(self, text: Any) -> Task | None:
        """Open the task of the code typed as a student: its scene in this browser's own room, its
        first question.  A code that opens nothing is said (None)."""
        try:
            task = self.store.task(text)
        except TaskCodeError as error:
            self._say(refusal_words(error, for_gui(self.client.gui)))
            return None
        session = self.session
        if getattr(session, "mode", None) == "presenting":
            self._say(self._("A presenter's screen is the class's: stop presenting to do a task."))
            return None
        if getattr(session, "mode", None) == "following":
            session.explore()  # the student's own room, a copy of the shared one first
        else:
            session.following.keep_own()  # a lecture starting meanwhile leaves the task where it is
        self.opened_place = None
        self.task = task
        self.lecturer_task = None
        self._show_lecturer(False)
        self._say("")
        self.show_question(0)
        return task

    def _open_place(self, task: Task, index: int) -> None:
        """The student's own room opened with question `index`'s scene and preset (once per place)."""
        place = task.place(index)
        if place == self.opened_place:
            return
        self.opened_place = place
        scene, preset = place
        if scene not in SCENES:
            return
        session = self.session

        def prepare(room: Any) -> None:
            if preset:
                try:
                    session.start_preset(room, preset)
                except (ValueError, KeyError, LookupError) as error:
                    self._say(self._("(the preset {preset} is not on this app: {error})").format(
                        preset=repr(preset), error=error))

        opener = getattr(session, "open_scene", None)  # the session's, or its own room role's (app.roles)
        if opener is None:
            opener = session.own_room.open_scene
        opener(scene, prepare)

    def show_question(self, index: int) -> None:
        """Show question `index` (0-based) of the task opened, its widget and my last verdict."""
        task = self.task
        if task is None:
            raise LookupError("open a task first")
        index = max(0, min(len(task.questions) - 1, int(index)))
        self.question = index
        self._open_place(task, index)
        question = task.questions[index]
        many = len(task.questions) > 1
        _ = self._
        state = "" if task.open_now(self.clock()) else " · **" + _("no longer open") + "**"
        words = f"{task.words}  \n" if task.words else ""
        which = _("Question {index} of {count}: ").format(index=index + 1, count=len(task.questions)) if many else ""
        self.gui_about.content = (f"{words}**{which}{question.prompt}**  \n"
                                  + _("Due {due}").format(due=iso_time(task.due))
                                  + f" · {policy_words(task, for_gui(self.client.gui))}{state}")
        self.gui_about.visible = True
        token = self.session.answer_token
        student = self.store.student(task.code, token)
        for handle in (self.gui_name, self.gui_student_number, self.gui_my_receipt):
            handle.visible = student is None
        kind = question.kind
        if kind == "choice":
            options = tuple(f"{k + 1}. {o}" for k, o in enumerate(getattr(question, "options", ())))
            self.gui_choice.options = options
            self.gui_choice.value = options[0]
        if kind == "number":
            unit = getattr(question, "unit", "")
            self.gui_value.label = _("Your number") + (f" [{unit}]" if unit else "")
        self.gui_choice.visible = kind == "choice"
        self.gui_value.visible = kind == "number"
        self.gui_azimuth.visible = self.gui_elevation.visible = kind == "direction"
        self.gui_submit.label = _("Submit the state of my room") if kind == "state" else _(SUBMIT_LABEL)
        self.gui_submit.visible = True
        self.gui_previous.visible = many and index > 0
        self.gui_next.visible = many and index < len(task.questions) - 1
        mine = [s for s in self.store.mine(task.code, token) if s.question == index]
        self._show_verdict(task, mine[-1] if mine else None, len(mine), student.name or student.number
                           if student is not None else "")

    def _show_verdict(self, task: Task, last: Submission | None, used: int, who: str) -> None:
        allowed = task.policy.attempts
        tr = for_gui(self.client.gui)
        _ = tr.gettext
        if last is None:
            text = _("Answering as **{who}**.").format(who=who) if who else ""
        else:
            left = (_("you may try again") if allowed is None else
                    tr.ngettext("{count} attempt left", "{count} attempts left", allowed - used).format(
                        count=allowed - used) if used < allowed else _("no attempts left"))
            text = _("Your attempt {attempt} ({who}): **{verdict}** · {left}  \n"
                     "Receipt **{receipt}** · submitted {at}").format(
                attempt=last.attempt, who=who, verdict=verdict_in_language(last.words, tr), left=left,
                receipt=format_code(last.receipt),
                at=iso_time(last.at))
        self.gui_verdict.content = text
        self.gui_verdict.visible = bool(text)

    def _answer(self, question: Question) -> Any:
        """This browser's answer to `question` as its widget holds it."""
        kind = question.kind
        if kind == "choice":
            value = str(self.gui_choice.value)
            options = [f"{k + 1}. {o}" for k, o in enumerate(getattr(question, "options", ()))]
            return options.index(value) if value in options else value
        if kind == "number":
            return self.gui_value.value
        if kind == "direction":
            return direction_of(float(self.gui_azimuth.value), float(self.gui_elevation.value))
        return self.session.state_answer()

    def submit(self) -> Submission | None:
        """`Submit`: the answer shown, judged and kept (its verdict and receipt said), or the
        refusal said (None) and nothing kept."""
        task = self.task
        if task is None:
            self._say(self._("Open a task first: type its code and press *Open the task*."))
            return None
        question = task.questions[self.question]
        try:
            submission = self.store.submit(task.code, self.session.answer_token, self.gui_name.value,
                                           self.gui_student_number.value, self.question, self._answer(question),
                                           receipt=self.gui_my_receipt.value)
        except (TaskRefused, TaskCodeError, PermissionError) as error:
            self._say(refusal_words(error, for_gui(self.client.gui)))
            return None
        self._say("")
        self.show_question(self.question)
        return submission

    # ------------------------------------------------------------------ the lecturer's side
    def open_as_lecturer(self, code_text: Any, presenter_code: Any) -> Task | None:
        """The task of `code_text` opened as its lecturer (the presenter code checked): its live
        table and its buttons.  A wrong code is said (None); wrong codes are limited per minute."""
        lectern = getattr(self.session, "lectern", None)
        if lectern is None:
            self._say(self._("This app has no presenter code: nobody may open a task as lecturer."))
            return None
        try:
            task = self.store.task(code_text)
        except TaskCodeError as error:
            self._say(refusal_words(error, for_gui(self.client.gui)))
            return None
        if not self.store.lecturer_codes.allow("hall"):  # counted before it is compared: no guess slips through
            self._say(self._("Too many lecturer's codes were tried on this app: wait a minute."))
            return None
        if not isinstance(presenter_code, str) or len(presenter_code) > 64 or not code_matches(
                presenter_code, lectern.code):
            self._say(self._("Wrong lecturer's code: the presenter code is wanted."))
            return None
        self.lecturer_task = task
        self.gui_lecturer_code.value = ""
        self._say("")
        if self.views is None:
            with self.folder:
                self.views = TaskViews(self.client, self.client.gui, self.session.guard, self._play_entry)
        self._show_lecturer(True)
        self.refresh_table()
        self._start_polling()
        return task

    def _start_polling(self) -> None:
        """While the table is open, it is written again every POLL_S (submissions made on other
        processes; this process's own call `_store_changed` at once)."""
        if self._polling:
            return
        self._polling = True
        panel = weakref.ref(self)

        def poll() -> None:
            while True:
                time.sleep(POLL_S)
                me = panel()
                if me is None or me.session.closed or me.lecturer_task is None:
                    if me is not None:
                        me._polling = False
                    return
                try:
                    me.refresh_table()
                except Exception:  # noqa: BLE001 - the store is gone (the app stops): the next poll ends it
                    pass
                del me

        threading.Thread(target=poll, name="task-table", daemon=True).start()

    def _show_lecturer(self, shown: bool) -> None:
        for handle in (self.gui_table, self.gui_csv, self.gui_extend_hours, self.gui_extend, self.gui_close,
                       self.gui_receipt, self.gui_check):
            handle.visible = shown
        if not shown and self.views is not None:
            self.views.hide()

    def _play_entry(self, entry: GalleryEntry) -> None:
        """The gallery's `Play this answer`: the chosen student's state in this browser's room, playing
        (the lecturer's own room, or the class's while presenting; never a presenter's room followed)."""
        self._lecturers()
        session, answer = self.session, entry.answer
        if getattr(session, "mode", None) == "following":
            raise NotAllowed(N_("press Explore on my own first: an answer plays in your own room"))
        if session.room.scene.title != answer.scene and answer.scene in SCENES:  # its scene opened first
            session.own_room.open_scene(answer.scene, lambda room: play_answer(room, answer))
        else:
            play_answer(session.room, answer)
        if self.views is not None:
            self.views.gallery_panel.line.content = self._("Playing answer {number} in your room.").format(
                number=entry.number)

    def _lecturers(self) -> Task:
        if self.lecturer_task is None:
            raise NotAllowed(N_("only the lecturer, with the presenter code, can see or change a task"))
        return self.lecturer_task

    def refresh_table(self) -> str:
        """The live table written again (the lecturer's); its text."""
        task = self.store.task(self._lecturers().code)
        self.lecturer_task = task
        submissions = self.store.submissions(task.code)
        now = self.clock()
        tr = for_gui(self.client.gui)
        text = table_text(task, submissions, now, tr) + "\n\n" + tallies_text(task, submissions, now, tr)
        if self.gui_table.content != text:
            self.gui_table.content = text
        if self.views is not None:
            self.views.show(task, submissions)
        return text

    def download(self) -> None:
        task = self.store.task(self._lecturers().code)
        tr = for_gui(self.client.gui)  # the lecturer's language now
        save_download(self.client, tr.gettext("task-{code}-results.csv").format(code=task.shown_code),
                      gradebook_in_language(gradebook_csv(task, self.store.submissions(task.code)), tr))

    def check_receipt(self, text: Any) -> str:
        """The submission a receipt code stands for, said under it (the lecturer's, of the task
        opened: another task's receipt is not shown); its words."""
        task = self._lecturers()
        tr = for_gui(self.client.gui)
        try:
            words = receipt_words(self.store.receipt(text), task, tr)
        except TaskCodeError as error:
            words = refusal_words(error, tr)
        self.gui_receipt_note.content = words
        self.gui_receipt_note.visible = True
        return words

    def close_task(self) -> None:
        self.store.close_task(self._lecturers().code)
        self.refresh_table()

    def extend(self, hours: Any) -> None:
        self.store.extend(self._lecturers().code, self.clock() + 3600.0 * _hours(hours, N_("New due in [h]")))
        self.refresh_table()

    def _store_changed(self, code: str) -> None:
        """A task changed in this process: the lecturer's table of it is written again."""
        if self.lecturer_task is not None and self.lecturer_task.code == code and not self.session.closed:
            self.refresh_table()
