"""The lecturer's 3D views of a task's answers, the ones `Ask the class` shows for a live round
(`app.hall.ask_presenter`): a direction question's answers as tips on the sphere around the
origin (`AnswerSphere`, the true direction an arrow), a state question's as the gallery of the
submitted bodies (`app.ask.gallery`: all faint at once, or one at a time, and `Play this answer`
in the lecturer's own room).  One answer a student: the attempt that counts (`model.counted`).

`3D view` chooses the question; when a task is opened as lecturer it shows the first direction
or state question at once.  Its options are written in the browser's language ("Q1 · Kugel der
Spitzen") and read back through the same words (`view_labels(task, tr)`), so the question an
option means is known in every language; another language chosen keeps the question shown.
`TaskViews` is made the first time a browser opens a task as its lecturer (a student's browser
never has it), inside the Task folder; its nodes are in that browser's own scene
(`client.scene`): a class following a presenter never sees them.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from app.ask.gallery import Gallery, GalleryEntry, GalleryPanel
from app.ask.judges import AnswerState
from app.ask.round import Tally
from app.hall.ask_presenter import AnswerSphere
from app.i18n import N_, Labels, Translator, for_gui, translator
from app.kit.core.common import show_if_changed
from app.tasks.model import Submission, Task, counted

__all__ = ["NO_VIEW", "VIEW_ROOT", "TaskViews", "counted_answers", "view_labels"]

VIEW_ROOT = "/task_views"  # the lecturer's sphere and gallery, in their own browser's scene
NO_VIEW = N_("none")  # the `3D view` option that shows nothing (a msgid: written in the browser's language)
VIEW_KINDS = {"direction": N_("sphere of tips"), "state": N_("gallery")}
"""A question's kind -> the view of its answers (msgids)."""


def view_labels(task: Task, tr: Translator | None = None) -> dict[str, int]:
    """The `3D view` options of `task` in `tr`'s language (English by default): "Q1 · sphere of
    tips", "Q3 · gallery" (German "Q1 · Kugel der Spitzen") -> the question's index (0-based),
    for its direction and state questions, in order."""
    tr = tr or translator("en")
    return {f"Q{k + 1} · {tr.gettext(VIEW_KINDS[q.kind])}": k
            for k, q in enumerate(task.questions) if q.kind in VIEW_KINDS}


def counted_answers(task: Task, submissions: list[Submission], index: int) -> list[Submission]:
    """One submission a student to question `index`, the one that counts, in the order the
    students first submitted to it."""
    by_student: dict[str, list[Submission]] = {}
    for s in sorted(submissions, key=lambda s: (s.at, s.attempt)):
        if s.question == index:
            by_student.setdefault(s.student.key, []).append(s)
    chosen = (counted(subs, task.policy.counts) for subs in by_student.values())
    return [c for c in chosen if c is not None]


def _gallery_entries(answers: list[Submission]) -> list[GalleryEntry]:
    """The state answers as the gallery's entries, numbered 1, 2, ... (a value that is not a body is left out)."""
    entries = []
    for number, submission in enumerate(answers, start=1):
        try:
            state = AnswerState.from_dict(submission.value)
        except (ValueError, TypeError, KeyError):
            continue
        entries.append(GalleryEntry(number, state, None, submission.words))
    return entries


class TaskViews:
    """The `3D view` dropdown, the sphere and the gallery of one lecturer's browser (module docstring).

    Args:
        client: the browser.  gui: its GUI (inside the Task folder when made).  guard: its
            session's guard.  play: called with the gallery's chosen answer (`Play this answer`).
    """

    def __init__(self, client: Any, gui: Any, guard: Any, play: Callable[[GalleryEntry], None]) -> None:
        self._lock = threading.RLock()  # the poll thread and the browser's callbacks both draw
        self.task: Task | None = None
        self.submissions: list[Submission] = []
        self.gui_view = gui.add_dropdown(N_("3D view"), (NO_VIEW,), initial_value=NO_VIEW,
                                         hint=N_("a question's answers in your 3D view: tips on a sphere, or the "
                                                 "gallery of the students' bodies"))
        self.words = Labels(gui)
        self.words.take(self.gui_view)
        self.tr = for_gui(gui)  # the language the options are written in now
        self._write_options(None, None)
        self.sphere = AnswerSphere(client.scene, VIEW_ROOT)
        self.gallery = Gallery(client.scene, root=f"{VIEW_ROOT}/gallery")
        self.gallery_panel = GalleryPanel(gui, self.gallery, play, guard)
        self.gallery_panel.folder.visible = False
        self.gui_view.on_update(guard("3D view", lambda _e: self.draw()))

    def relabel(self, tr: Translator) -> None:
        """The dropdown (its options too, the question shown kept) and the gallery's folder in
        `tr`'s language (the browser chose another)."""
        with self._lock:
            self.words.relabel(tr)
            index = self.chosen()
            self.tr = tr
            self._write_options(self.task, index)
        self.gallery_panel.relabel(tr)

    def _write_options(self, task: Task | None, index: int | None) -> None:
        """The dropdown's options for `task` (none but `NO_VIEW` without one) in this browser's
        language, question `index` shown (`NO_VIEW` for None); only what changed is sent."""
        labels = {} if task is None else view_labels(task, self.tr)
        options = (self.tr.gettext(NO_VIEW), *labels)
        if tuple(self.gui_view.options) != options:
            self.gui_view.options = options
        value = next((label for label, k in labels.items() if k == index), options[0])
        if self.gui_view.value != value:
            self.gui_view.value = value

    def show(self, task: Task, submissions: list[Submission]) -> None:
        """The views of `task` with `submissions` (a task newly shown: its first viewable question)."""
        with self._lock:
            labels = view_labels(task, self.tr)
            new = self.task is None or self.task.code != task.code
            if not new and self.task == task and self.submissions == list(submissions):
                return  # the table polled again, nothing new: nothing sent
            index = next(iter(labels.values()), None) if new else self.chosen()
            self.task, self.submissions = task, list(submissions)
            self._write_options(task, index)
            show_if_changed(self.gui_view, bool(labels))
            self.draw()

    def chosen(self) -> int | None:
        """The question (0-based) the `3D view` shows, or None (nothing, or a value no option is)."""
        task = self.task
        if task is None:
            return None
        return view_labels(task, self.tr).get(str(self.gui_view.value))

    def draw(self) -> None:
        """The sphere or the gallery of the chosen question, the other hidden."""
        with self._lock:
            task, index = self.task, self.chosen()
            kind = None if task is None or index is None else task.questions[index].kind
            answers = [] if task is None or index is None else counted_answers(task, self.submissions, index)
            if kind == "direction" and task is not None and index is not None:
                question = task.questions[index]
                values = [s.value for s in answers]
                self.sphere.draw(Tally(1, question, False, len(values),
                                       **question.tally_fields(values, [None] * len(values))), revealed=True)
            else:
                self.sphere.draw(None)
            show_if_changed(self.gallery_panel.folder, kind == "state")
            if kind == "state":
                self.gallery.set_entries(_gallery_entries(answers))
                self.gallery.draw()
                self.gallery_panel.refresh()
            elif self.gallery.entries:
                self.gallery.clear()

    def hide(self) -> None:
        """No task shown: the dropdown, the sphere and the gallery hidden."""
        with self._lock:
            self.task, self.submissions = None, []
            show_if_changed(self.gui_view, False)
            self.draw()
