"""One `Session` per connected browser: the automation façade over its roles and its panel.

A session shows one room (`app.kit.core.room.Room`: a simulation, its transport state and the
views watching it) through one view built for its client (`app.roles.showing.ShownView`): its
own room's view, its room live on the shared screen while it presents, or the follower's panel
while it follows a presenter (`app.lecture.lectern`).

The session owns the guard, the panel's parts (`app.hall`: the projector layout, the lesson,
notes, sharing, the Lecture folder and live bar, a narrow explorer's fold, Ask the class, the
Mine folder) and the browser's roles (`app.roles`): its own room (`OwnRoom`: scenes, presets,
keys), following (`Following`), presenting (`Presenting`), answering (`Student`) and a narrow
screen's fit (`PhoneFit`).  Its public methods are thin delegations to them.

Every callback a session registers is wrapped by `Session.guard`: it runs under the session's
lock and the room's, and an exception is logged and shown in this client's GUI
(`app.roles.guard.ErrorLine`), never reaching viser's threads or the app loop.  The public
actions (`select_scene`, `apply_preset`, `play`, `pause`, `step`, `reset`, `tick`) go through
the guard too, so tools may call them from any thread and learn of a refusal from
`error_count` and `last_error`:

    session.select_scene("Free body"); session.apply_preset("Dzhanibekov"); session.play()
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, TypeVar

import viser

from app.ask import Question, Round
from app.hall.lecture_panel import LecturePanel
from app.hall.lesson_runner import LessonRunner
from app.hall.notes import Notes
from app.hall.own_panel import OwnPanel
from app.hall.projector import PROJECTOR_CSS, PROJECTOR_LABEL_SCALE, ProjectorLayout, projector_view
from app.hall.share import Camera, SharePanel
from app.i18n import DEFAULT_LANGUAGE
from app.kit.core.room import Room
from app.lecture.lectern import Lectern, Mode
from app.lessons import Lesson
from app.own import OwnLibrary
from app.roles.following import Following
from app.roles.guard import ErrorLine, Guard
from app.roles.language import Language
from app.roles.own_room import OwnRoom
from app.roles.phone import PhoneFit
from app.roles.presenting import Presenting
from app.roles.showing import Showing, ShownView
from app.roles.student import Student
from app.scenes import DEFAULT_SCENE, SCENES
from app.sharestore import ShareStore

__all__ = ["PROJECTOR_CSS", "PROJECTOR_LABEL_SCALE", "SCENES", "Mode", "Session", "projector_view"]

R = TypeVar("R")
LAST = 1e9  # a GUI order after anything a panel adds (viser orders by creation count)


class Session:
    """The state of one browser tab: built on connect, dropped on disconnect (`close`).

    Attributes:
        client (client_id), lectern (or None), own (`app.own`, or None: no Mine folder), share_store.
        showing: what it shows (`app.roles.showing.Showing`: mode, view, own room).
        own_room, languages, phone, following, presenting, student: its roles (`app.roles`).
        errors, projector_layout, lecture, ask_panel, question (None without a lectern), narrow,
            lesson_runner, notes, share, own_panel: the panel's parts (`app.hall`).
    """

    def __init__(self, client: viser.ClientHandle, scene: str = DEFAULT_SCENE, *,
                 lectern: Lectern | None = None, own: OwnLibrary | None = None,
                 share_store: ShareStore | None = None, language: str = DEFAULT_LANGUAGE) -> None:
        self.client = client
        self.client_id: int = client.client_id
        self.lectern = lectern
        self.own = own
        self.share_store = share_store
        self.closed = False
        self._busy = threading.RLock()  # held by the guard for the whole of a callback or an action
        self.showing = Showing(client, lectern, Room(SCENES[scene], SCENES[scene].new_simulation()))
        self._guard = Guard(self._busy, self.showing.switch_lock, lambda: self.room, self.report_error)
        self.own_room = OwnRoom(self)
        self.languages = Language(self, self.own_room, language)  # ValueError for a language without a catalog
        self.phone = PhoneFit(self)
        self.following = Following(self, self.own_room, self.phone)
        self.presenting = Presenting(self, self.own_room, self.following)
        self.student = Student(self, self.following)
        with self._busy, client.atomic():  # the first panel leaves at once; clicks wait for it
            self._build(client.gui, scene)
            self._show_first_view()

    def _build(self, gui: Any, scene: str) -> None:
        """The panel's parts, in the panel's order (viser orders by creation)."""
        self.errors = ErrorLine(self.client, self.guard, last_order=LAST)
        self.gui_error, self.gui_load = self.errors.gui_error, self.errors.gui_load
        self.gui_scene, self.gui_language = self.own_room.build_dropdown(gui, scene), self.languages.build_dropdown(gui)
        self._guarded_tick = self.guard("tick", lambda dt: self.room.tick(dt))
        self.projector_layout = ProjectorLayout(
            self.client, self.guard, lambda: None if self.mode is Mode.FOLLOWING else self.scene)
        top = self.errors.order  # the live bar and a narrow explorer's line sit right under the error line
        self.lecture = None if self.lectern is None else LecturePanel(self, self.guard, self.lectern, order=top)
        self.ask_panel = self.presenting.build_ask_panel(order=top + 0.3)  # under the live bar
        self.question = self.student.build_question(order=-20.0)  # a student's question above all
        self.narrow = self.phone.build_fold(order=top + 0.5, copy=lambda: self.following.explored)
        self.lesson_runner = LessonRunner(gui, self.guard, self, on_step=self.presenting.lesson_stepped)
        self.notes = Notes(self.client, self.guard, self.report_error, lambda: self.room, lambda: self.scene)
        self.share = None if self.share_store is None else SharePanel(
            self.client, self.guard, self.share_store, lambda: self.room, self.open_moment)
        self.own_panel = OwnPanel(gui, self.guard, self, self.own) if self.own is not None else None
        if self.own is not None:
            self.lesson_runner.add_lessons(self.own.lessons())
        self._alias_widgets()
        self.own_room.build_commands(gui)

    def _alias_widgets(self) -> None:
        """The parts' widgets by the names tools and tests use; the folders a follower's panel hides."""
        self.gui_projector = self.projector_layout.gui_checkbox
        self.lesson_folder = self.lesson_runner.folder
        self.gui_lesson, self.gui_lesson_text = self.lesson_runner.gui_lesson, self.lesson_runner.gui_text
        self.notes_folder = self.notes.folder
        if self.lecture is not None:
            panel = self.lecture
            self.lecture_folder, self.gui_lecture_note = panel.folder, panel.gui_note
            self.gui_present, self.gui_stop, self.gui_follow = panel.gui_present, panel.gui_stop, panel.gui_follow
            self.gui_pointer, self.gui_pointer_label = panel.gui_pointer, panel.gui_pointer_label
            self.gui_badge, self.gui_call_back, self.gui_stay = panel.gui_badge, panel.gui_call_back, panel.gui_stay
        self.own_folders: tuple[Any, ...] = (self.gui_projector, self.notes_folder,
                                             *(() if self.share is None else (self.share.folder,)),
                                             *(() if self.lecture is None else (self.lecture.folder,)),
                                             *(() if self.own_panel is None else (self.own_panel.folder,)))
        """The folders a collapsed follower's panel hides (`app.lecture.lectern.Seat`)."""

    def _show_first_view(self) -> None:
        """Follow a presenter, or its own room (`OwnRoom.first_view`); the round asked now; a phone's fold."""
        if self.lectern is not None and self.lectern.someone_presents:
            self.follow()
        else:
            self.own_room.first_view()
        self.own_room.refresh_preset_commands()
        self.student.show_questions()  # the round asked now, or none, from the first frame
        self.phone.fit_at_connect()

    # ------------------------------------------------------------------ what it shows
    @property
    def room(self) -> Room:
        """The room this browser shows: its own, or (following) the one on the shared screen."""
        return self.showing.room

    @property
    def scene(self) -> ShownView | None:
        """The view shown: a scene view, or the follower's panel (`Showing.view`)."""
        return self.showing.view

    @scene.setter
    def scene(self, view: ShownView | None) -> None:
        self.showing.view = view

    @property
    def mode(self) -> Mode:
        """Own room, presenting or following (`Showing.mode`)."""
        return self.showing.mode

    @mode.setter
    def mode(self, mode: Mode) -> None:
        self.showing.mode = mode

    @property
    def came_after_lecture(self) -> bool:
        """Connected after a lecture ended (`Showing.came_after_lecture`)."""
        return self.showing.came_after_lecture

    @property
    def lock(self) -> threading.RLock:
        """Held for the whole of each of this session's callbacks and actions (`guard`)."""
        return self._busy

    @property
    def simulation(self) -> Any:
        return self.room.sim

    # ------------------------------------------------------------------ errors
    def guard(self, where: str, fn: Callable[..., R]) -> Callable[..., R | None]:
        """`fn` run under this session's lock and the room's, an exception shown, never raised (`Guard.wrap`)."""
        return self._guard.wrap(where, fn)

    def report_error(self, where: str, error: BaseException) -> None:
        """Log `error` (with traceback, once per distinct message) and show it in the GUI."""
        self.errors.report(where, error)

    @property
    def last_error(self) -> str | None:
        """The last error message shown, or None (`ErrorLine.last_error`)."""
        return self.errors.last_error

    @property
    def error_count(self) -> int:
        """Errors so far (`ErrorLine.error_count`)."""
        return self.errors.error_count

    def show_load(self, note: str) -> None:
        """Say (or stop saying) that the server cannot keep its frame rate (called by the app loop)."""
        if not self.closed:
            self.errors.show_load(note)

    # ------------------------------------------------------------------ its own room (app.roles.own_room)
    def watch(self, room: Room) -> None:
        """Show another session's room: this client becomes one more view of its simulation."""
        self.guard("watch", self.own_room.show)(room)

    def select_scene(self, title: str) -> None:
        """Switch to the scene `title` (a key of SCENES), as the dropdown does."""
        if title not in SCENES:
            raise ValueError(f"unknown scene {title!r}; choose one of {', '.join(SCENES)}")
        self.guard("scene", self.switch_scene)(title)

    def switch_scene(self, title: str) -> None:
        """Show a new room of the scene `title`, as the dropdown does (within the guard)."""
        self.gui_scene.value = self.own_room.scene_label(title)  # runs `OwnRoom.scene_chosen` synchronously

    def set_language(self, language: str) -> None:
        """Speak `language` (a code or its own name), as the Language dropdown does (`Language.choose`)."""
        self.guard("language", self.languages.choose)(language)

    def controlled_room(self) -> Room:
        """The room this browser may change (PermissionError while it follows the presenter)."""
        return self.showing.controlled_room()

    def apply_preset(self, name: str) -> None:
        """Load a preset of the active scene, its own or one of the lecturer's, through the guard."""
        self.own_room.apply_preset(name)

    def start_preset(self, room: Room, name: str) -> None:
        """The preset `name` of room's scene, shipped or own, started in `room` (`OwnRoom.start_preset`)."""
        self.own_room.start_preset(room, name)

    def may_save(self) -> str:
        """"" if this browser may write the lecturer's data folder, else why not (`OwnRoom.may_save`)."""
        return self.own_room.may_save()

    def own_changed(self) -> None:
        """The own presets or lessons changed: the Mine folder, the Lesson dropdown, the commands."""
        self.own_room.own_changed()

    def open_last_lecture(self) -> None:
        """The room the last presenter left, in place of its own (`OwnRoom.open_last_lecture`)."""
        self.own_room.open_last_lecture()

    def open_moment(self, room: Room, camera: Camera | None = None) -> None:
        """Show a shared moment (`app.hall.share`) here, leaving the presenter to explore it while
        following (the shared screen never changes); then look from the camera it was shared with."""
        if self.mode is Mode.FOLLOWING:
            self.following.leave_for(room)
        else:
            self.own_room.show(room)
        if self.share is not None:
            self.share.set_camera(camera)

    def play(self) -> None:
        """Start the motion of the room shown."""
        self.guard("play", lambda: self.controlled_room().play())()

    def pause(self) -> None:
        self.guard("pause", lambda: self.controlled_room().pause())()

    def step(self) -> None:
        self.guard("step", lambda: self.controlled_room().step())()

    def reset(self) -> None:
        self.guard("reset", lambda: self.controlled_room().reset())()

    def tick(self, dt: float) -> None:
        """Advance the session's room by dt [s] of wall time (what the loop does for every room)."""
        if not self.closed:
            self._guarded_tick(dt)

    # ------------------------------------------------------------------ the panel's parts (app.hall)
    def set_projector(self, on: bool) -> None:
        """Projector layout for this browser (`app.hall.projector.ProjectorLayout.set`)."""
        self.projector_layout.set(on)

    @property
    def projector(self) -> bool:
        """The projector layout is in force."""
        return self.projector_layout.on

    def reset_camera(self) -> None:
        """The scene's camera view (centred for the projector layout)."""
        self.projector_layout.reset_camera(self.room.scene.view)

    @property
    def lessons(self) -> dict[str, Lesson]:
        """The lessons by title."""
        return self.lesson_runner.lessons

    @property
    def lesson(self) -> Lesson | None:
        """The lesson running, or None."""
        return self.lesson_runner.lesson

    @property
    def lesson_step(self) -> int:
        """The running lesson's step shown (0-based; -1 before the first)."""
        return self.lesson_runner.step

    def start_lesson(self, title: str) -> None:
        """Run the lesson `title` from its first step ("—": none)."""
        self.lesson_runner.start(title)

    def next_step(self, delta: int) -> None:
        """Go `delta` steps on (1 Next, -1 Back) in the running lesson, and apply that step."""
        self.lesson_runner.next_step(delta)

    def lesson_text(self) -> str:
        """The current step's text in English, as followers are sent it (`app.lessons.in_language`)."""
        return self.lesson_runner.text(english=True)

    def lesson_words(self) -> dict[str, dict[str, str]]:
        """The words followers are sent in English, in every other language (`LessonRunner.followers_words`)."""
        return self.lesson_runner.followers_words()

    def caption_words(self) -> tuple[str, str]:
        """(head, words) of the lesson caption in English, as followers are sent it (`LessonRunner`)."""
        return self.lesson_runner.caption_words(english=True)

    def record(self, seconds: Any, *, wait: bool = False) -> threading.Thread:
        """Record the next `seconds` of the scene shown (`app.hall.notes.Notes.record`)."""
        return self.notes.record(seconds, wait=wait)

    def screenshot(self, *, wait: bool = False) -> threading.Thread:
        """Offer a PNG of this browser's view (`app.hall.notes.Notes.screenshot`)."""
        return self.notes.screenshot(wait=wait)

    @property
    def last_recording(self) -> tuple[bytes, bytes] | None:
        """(.html, .viser) last offered, or None."""
        return self.notes.last_recording

    @property
    def last_screenshot(self) -> bytes | None:
        """The PNG last offered, or None."""
        return self.notes.last_screenshot

    # ------------------------------------------------------------------ the lecture hall: the mode
    def lecture_changed(self) -> None:
        """The live bar and a narrow explorer's line (`PhoneFit.screen_changed`); skipped while one
        of this browser's callbacks runs (the next refresh comes soon: the app loop never waits)."""
        if self.closed or not self._busy.acquire(blocking=False):
            return
        try:
            if self.lecture is not None:
                self.lecture.refresh()
            self.phone.screen_changed()
        finally:
            self._busy.release()

    def show_mode(self) -> None:
        """The panel for this browser's mode: a follower has no scene or lesson to drive (its own
        folders are its follower panel's to show)."""
        if self.lecture is None:
            return
        following = self.mode is Mode.FOLLOWING
        self.lecture.show_for(self.mode)
        self.student.show_questions()
        self.gui_scene.visible = not following
        self.lesson_runner.folder.visible = not following
        self.narrow.refresh()

    def present(self, code: str) -> None:
        """Become the presenter with `code` (`Presenting.present`)."""
        self.presenting.present(code)

    def stop_presenting(self) -> None:
        """Release the presenter lock; the followers keep the last state (`Presenting.stop`)."""
        self.presenting.stop()

    def call_back(self) -> None:
        """Ask every explorer back to the presenter (presenter only; `Presenting.call_back`)."""
        self.presenting.call_back()

    def following_by_default(self) -> bool:
        """A browser with its own room that has not chosen to explore follows a new presenter."""
        return self.following.by_default()

    def follow(self) -> None:
        """Follow the presenter, or the last state one left (`Following.follow`)."""
        self.following.follow()

    def explore(self) -> None:
        """Leave the presenter with an exact copy of the shared screen (`Following.explore`)."""
        self.following.explore()

    # ------------------------------------------------------------------ ask the class (app.roles.student)
    def ask(self, question: Question | dict[str, Any]) -> Round:
        """Ask the class `question` (presenter only): the new round (`Presenting.ask`)."""
        return self.presenting.ask(question)

    def close_round(self) -> Round:
        """Close the current round (presenter only); the round."""
        return self.presenting.close_round()

    def vote_again(self) -> Round:
        """The same question again (presenter only); the new round."""
        return self.presenting.vote_again()

    def _play_state(self, answer: Any) -> None:
        """The gallery's `Play this answer` (`Presenting.play_state`)."""
        self.presenting.play_state(answer)

    def play_answer(self, number: int) -> None:
        """Play the current State round's answer `number` (presenter only; `Presenting.play_answer`)."""
        self.presenting.play_answer(number)

    @property
    def answer_token(self) -> str:
        """This browser's anonymous answers' token (`Student.answer_token`): never sent, never shown."""
        return self.student.answer_token

    def answer(self, value: Any) -> Any:
        """Answer the round asked now, as this browser (`Student.answer`)."""
        return self.student.answer(value)

    def my_answer(self) -> Any:
        """This browser's answer to the round shown, or None."""
        return self.student.my_answer()

    def state_answer(self) -> Any:
        """This browser's own room's state, as a State question takes it (`Student.state_answer`)."""
        return self.student.state_answer()

    def answer_from_copy(self) -> None:
        """A State question: leave the presenter with an exact copy of the room to answer from."""
        self.student.answer_from_copy()

    def folded_for_question(self, folded: bool) -> None:
        """While a question waits for this browser's answer, the follower's panel is folded away."""
        self.student.folded_for_question(folded)

    def questions_changed(self) -> bool:
        """Show the round as it is now (called by the app loop; `Student.questions_changed`)."""
        return self.student.questions_changed()

    # ------------------------------------------------------------------ the end
    def close(self) -> None:
        """Its client is gone (viser drops its nodes): a presenter's lock is released (the
        followers keep the last state), a follower's panel forgotten, its own room left."""
        self.closed = True
        if self.lectern is not None:
            if self.mode is Mode.PRESENTING:
                self.lectern.release(self, disconnected=True)
                return
            if self.mode is Mode.FOLLOWING:
                self.lectern.remove_follower(self, disconnected=True)
                return
        room = self.showing.own_room
        with room.lock:
            room.remove_view(self.scene)
            if not room.views:
                room.playing = False
