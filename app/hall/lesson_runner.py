"""The `Lesson` folder of one browser's panel and the lesson it runs (`app.lessons`: the data).

This module owns `LessonRunner`: the folder (the lesson dropdown, Back / Next, the step's
text, the `Caption` checkbox), the step's caption over the browser's 3D view
(`app.lecture.caption`; while the browser presents, the checkbox decides for every follower too),
the → / ← keys, the running lesson and its step, and applying a step to the browser's
stage (`Stage`: the scene, the preset, the toggles, the tab, the integrator, the camera, play
or pause).  A scene chosen by hand ends the lesson (`scene_changed`).

Languages: the dropdown's titles, the step's text and caption are in the browser's language
(`app.i18n.for_gui`; English where the lesson lacks it, `app.lessons.Texts`); what a presenter
sends its followers is English (`text(english=True)`) with the step's words in the other languages
(`followers_words`), and each follower's panel shows it in its own language, on any process.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import viser

from app.i18n import N_, Labels, Translator, for_gui, translator
from app.kit.core.common import Wrap, apply_camera
from app.kit.core.room import Room
from app.lecture.caption import Caption
from app.lessons import Lesson, caption_head, lessons, step_line, step_words

__all__ = ["NO_LESSON", "LessonRunner", "Stage"]

NO_LESSON = "—"  # the dropdown's entry for no lesson
OWN_MARK = "★ "  # before an own lesson's title in the dropdown


class Stage(Protocol):
    """What a lesson step drives: a browser's session (`app.session.Session` is one)."""

    client: viser.ClientHandle
    scene: Any
    """The view of the room shown."""

    @property
    def room(self) -> Room:
        """The room shown."""
        ...

    def controlled_room(self) -> Room:
        """The room the browser may change; PermissionError while it follows the presenter."""
        ...

    def switch_scene(self, title: str) -> None:
        """Show a new room of the scene `title`, as the scene dropdown does."""
        ...

    def start_preset(self, room: Room, name: str) -> None:
        """Start the preset `name` (the scene's, or the lecturer's own) in `room`."""
        ...


class LessonRunner:
    """The Lesson folder and the running lesson.

    Args:
        gui: the browser's panel.
        guard: its session's guard: the folder's and the keys' callbacks run in it.
        stage: what the steps drive.
        on_step: called after a step has been applied (the presenter's followers read its text).

    Attributes:
        lessons: the lessons by title.  lesson: the one running, or None; step: its step shown
        (0-based; -1 before the first).  folder: the Lesson folder.
    """

    def __init__(self, gui: Any, guard: Wrap, stage: Stage, on_step: Callable[[], None]) -> None:
        self.stage = stage
        self._gui = gui
        self._on_step = on_step
        self.lessons = {lesson.title: lesson for lesson in lessons()}
        self.lesson: Lesson | None = None
        self.step = -1
        self._stepping = False  # a step is switching the scene: the lesson goes on
        self._relabelling = False  # the dropdown's titles change language: the lesson goes on
        self.folder = gui.add_folder(N_("Lesson"), expand_by_default=False)
        with self.folder:
            self.gui_lesson = gui.add_dropdown(N_("Lesson"), self._options(), initial_value=NO_LESSON,
                                               hint=N_("a walk through one section of the memo"))
            self.gui_steps = gui.add_button_group(N_("Step"), (N_("◀ Back"), N_("Next ▶")))
            self.gui_text = gui.add_markdown("")
            self.gui_caption = gui.add_checkbox(N_("Caption"), True,
                                                hint=N_("the step's words over the 3D view, large; "
                                                        "while presenting, on every follower's screen too"))
        self.words = Labels(gui)
        self.words.take(self.folder, self.gui_lesson, self.gui_caption)
        self.words.take(self.gui_steps, options=True)
        self.caption = Caption(gui)
        self.gui_caption.on_update(guard("caption", lambda _event: self._caption_changed()))
        self.gui_lesson.on_update(guard("lesson", lambda _event: self.start(self._title(str(self.gui_lesson.value)))))
        self.gui_steps.on_click(guard("lesson step", lambda event: self.next_step(
            -1 if str(event.target.value).startswith("◀") else 1)))
        for label, key, delta in (("Lesson: next step", "arrowright", 1), ("Lesson: back", "arrowleft", -1)):
            command = gui.add_command(label, hotkey=key, description=f"key: {key}")
            command.on_trigger(guard(label, lambda _event, delta=delta: self.next_step(delta)))

    def add_lessons(self, own: dict[str, Lesson]) -> None:
        """The lecturer's own lessons (`app.own`) in the dropdown after the shipped ones, marked ★."""
        shipped = {lesson.title: lesson for lesson in lessons()}
        self.lessons = {**shipped, **{OWN_MARK + title: lesson for title, lesson in own.items()}}
        self._show_options()

    @property
    def tr(self) -> Translator:
        """The browser's language (`app.i18n.for_gui`)."""
        return for_gui(self._gui)

    def _shown_title(self, title: str) -> str:
        """A dropdown entry's title (a key of `lessons`) as the browser's language writes it."""
        lesson = self.lessons.get(title)
        if lesson is None:
            return title
        own = OWN_MARK if title.startswith(OWN_MARK) and not lesson.title.startswith(OWN_MARK) else ""
        return own + lesson.title_in(self.tr.language)

    def _options(self) -> tuple[str, ...]:
        return (NO_LESSON, *(self._shown_title(title) for title in self.lessons))

    def _title(self, shown: str) -> str:
        """The key of `lessons` of a dropdown entry in any language (itself when none is: NO_LESSON, or anything
        a client sends)."""
        if shown in self.lessons:
            return shown
        return next((title for title in self.lessons if self._shown_title(title) == shown), shown)

    def _show_options(self) -> None:
        options = self._options()
        if tuple(self.gui_lesson.options) == options:
            return
        running = next((title for title, lesson in self.lessons.items() if lesson is self.lesson), None)
        shown = NO_LESSON if running is None else self._shown_title(running)
        self._relabelling = True  # viser's setters run start(): nothing (the lesson goes on)
        try:
            self.gui_lesson.options = options
            if self.gui_lesson.value != shown:
                self.gui_lesson.value = shown
        finally:
            self._relabelling = False

    def relabel(self, tr: Translator) -> None:
        """The browser's language changed to `tr`'s: the folder's own words, the lessons' titles,
        the step's text and the caption in it."""
        self.words.relabel(tr)
        self._show_options()
        if self.lesson is not None and self.step >= 0:
            self.gui_text.content = self.text()
            self.caption.show(*self.caption_words())

    def text(self, *, english: bool = False) -> str:
        """The current step's text (Markdown) in the browser's language, or in English (what a
        presenter's followers are sent: each shows it in its own, `app.lessons.in_language`)."""
        if self.lesson is None or self.step < 0:
            return ""
        return step_line(self.lesson, self.step, translator("en") if english else self.tr)

    def followers_words(self) -> dict[str, dict[str, str]]:
        """The current step's words a presenter's followers are sent in English (its line, its
        caption) in every other language, {code: {English: words}} ({} with no lesson running:
        `app.lessons.step_words`)."""
        if self.lesson is None or self.step < 0:
            return {}
        return step_words(self.lesson, self.step)

    def caption_words(self, *, english: bool = False) -> tuple[str, str]:
        """(head, words) of the caption over the 3D view: the lesson and step, and the step's
        text, in the browser's language or in English; ("", "") with no lesson running or the
        `Caption` checkbox off."""
        if self.lesson is None or self.step < 0 or self.gui_caption.value is not True:
            return "", ""
        tr = translator("en") if english else self.tr
        return caption_head(self.lesson, self.step, tr), self.lesson.steps[self.step].text_in(tr.language)

    def _caption_changed(self) -> None:
        self.caption.show(*self.caption_words())
        self._on_step()  # a presenter's followers follow its choice

    def end(self) -> None:
        """No lesson runs: its text goes (here and, for a presenter, on the followers' panels)."""
        self.lesson, self.step = None, -1
        self.gui_text.content = ""
        self.caption.show("", "")
        if self.gui_lesson.value != NO_LESSON:
            self.gui_lesson.value = NO_LESSON  # runs start(NO_LESSON): nothing more

    def scene_changed(self) -> None:
        """The browser's scene changes: by hand, the lesson (and its text) ends; by a step, it goes on."""
        if not self._stepping:
            self.end()

    def start(self, title: str) -> None:
        """Run the lesson `title` from its first step (NO_LESSON: none)."""
        if self._relabelling:
            return  # the dropdown relabelled in another language: the lesson goes on
        title = self._title(title)
        if title not in self.lessons:  # NO_LESSON, or anything a client sends
            self.lesson, self.step = None, -1
            self.gui_text.content = ""
            self.caption.show("", "")
            return
        self.stage.controlled_room()  # PermissionError while following
        self.lesson = self.lessons[title]
        self.step = -1
        self.next_step(1)

    def next_step(self, delta: int) -> None:
        """Go `delta` steps on (1 Next, -1 Back) in the running lesson, and apply that step."""
        if self.lesson is None:
            return
        stage = self.stage
        stage.controlled_room()  # PermissionError while following
        k = min(max(self.step + delta, 0), len(self.lesson.steps) - 1)
        self.step = k
        step = self.lesson.steps[k]
        if step.scene != stage.room.scene.title:
            self._stepping = True
            try:
                stage.switch_scene(step.scene)
            finally:
                self._stepping = False
        room = stage.room
        if step.preset is not None:
            stage.start_preset(room, step.preset)
        view = stage.scene
        toggles = view.checkboxes()
        for label, value in step.display.items():
            toggle = toggles.get(label)  # a lesson names it in English
            if toggle is None:
                raise ValueError(f"lesson step {self.step + 1}: {step.scene} has no checkbox {label!r}")
            if toggle.value != value:
                toggle.value = value  # runs its callback: the view redraws
        if step.tab is not None:
            view.show_tab(step.tab)
        if step.integrator is not None:
            view.set_integrator(step.integrator)
        if step.camera is not None:
            apply_camera(stage.client, step.camera)
        if step.play is True:
            room.play()
        elif step.play is False:
            room.pause()
        self.gui_text.content = self.text()
        self.caption.show(*self.caption_words())
        self._on_step()
