"""One `Session` per connected browser: its scene dropdown, its error display, its view, its mode.

A session shows one room (`app.kit.core.room.Room`: a simulation, its transport state and the views
watching it) through one view built for its client: its own room, or, while it follows a
presenter, the room on the shared screen (`app.lectern`).  The dropdown at the top switches
scenes: the old view leaves, a new room and view are built and the camera moves to the scene's
view.

This module owns the guard and the error display, the rooms and views (scene switching, keys,
the presets' commands) and the browser's mode (present, stop presenting, follow, explore,
close).  The rest of the panel is in `app.hall`, one module per concern: the projector layout
(`app.hall.projector`), the lesson (`app.hall.lesson_runner`), recordings and screenshots
(`app.hall.notes`), the Lecture folder and the live bar (`app.hall.lecture_panel`) and a narrow
explorer's folded panel (`app.hall.narrow`); the session's methods of the same names delegate
to them.

Every callback a session registers is wrapped by `Session.guard`: it runs under the room's
lock, and an exception is logged and shown in this client's GUI, never reaching viser's threads
or the app loop.  The public actions (`select_scene`, `apply_preset`, `play`, `pause`, `step`,
`reset`, `tick`) go through the guard too, so tools may call them from any thread and learn
of a refusal from `error_count` and `last_error`:

    session.select_scene("Free body"); session.apply_preset("Dzhanibekov"); session.play()
"""

from __future__ import annotations

import contextlib
import functools
import logging
import math
import threading
from collections.abc import Callable
from typing import Any, TypeVar

import viser

from app.ask import Question, new_token
from app.ask.gallery import play_answer
from app.ask.judges import read_state
from app.ask.state_tally import gallery_entries
from app.hall.ask import AnswerPanel, AskPanel
from app.hall.follower import is_narrow
from app.hall.lecture_panel import LecturePanel
from app.hall.lesson_runner import LessonRunner
from app.hall.narrow import NarrowPanel
from app.hall.notes import Notes
from app.hall.own_panel import OwnPanel
from app.hall.projector import PROJECTOR_CSS, PROJECTOR_LABEL_SCALE, ProjectorLayout, projector_view
from app.hall.share import Camera, SharePanel
from app.kit.core.common import CameraView, apply_camera
from app.kit.core.room import Room, Scene
from app.kit.draw.screen import body_centre, centred_view
from app.kit.panel.gui import writing_quietly
from app.lectern import LIVE_ROOT, Lectern, Mode
from app.lessons import Lesson
from app.own import OwnLibrary
from app.scenes import DEFAULT_SCENE, SCENES
from app.sharestore import ShareStore

__all__ = ["PROJECTOR_CSS", "PROJECTOR_LABEL_SCALE", "SCENES", "Mode", "Session", "projector_view"]

logger = logging.getLogger(__name__)

R = TypeVar("R")
LAST = 1e9  # a GUI order after anything a panel adds (viser orders by creation count)


class Session:
    """The state of one browser tab: built on connect, dropped on disconnect.

    Attributes:
        client: the viser client this session draws to.
        room: the room it shows; scene: its view of that room (the active scene).
        mode: own room, presenting or following (`app.lectern.Mode`).
        last_error: the last error message shown, or None; error_count: errors so far.
        projector_layout, lesson_runner, notes, lecture (None without a lectern): the panel's
            parts (`app.hall`).
    """

    def __init__(self, client: viser.ClientHandle, scene: str = DEFAULT_SCENE, *,
                 lectern: Lectern | None = None, own: OwnLibrary | None = None,
                 share_store: ShareStore | None = None) -> None:
        self.client = client
        self.lectern = lectern
        self.own = own  # the lecturer's own presets and lessons (app.own), or None: no Mine folder
        self.share_store = share_store
        self.mode = Mode.OWN
        self.explored = False  # pressed "Explore on my own": a new presenter does not pull it back
        self.came_after_lecture = False
        """Connected after a lecture ended (its last state on the shared screen, nobody presenting):
        it landed in its own room, told so, the last lecture's room one click away
        (`open_last_lecture`); ends when it follows or presents."""
        self.client_id: int = client.client_id
        self.answer_token = new_token()  # this browser's anonymous answers (`app.ask`): never sent, never shown
        self.closed = False
        self.last_error: str | None = None
        self.error_count = 0
        self._switch_lock = threading.RLock()
        self._busy = threading.RLock()  # held by the guard for the whole of a callback or an action
        with self._busy, client.atomic():  # the first panel leaves at once; clicks wait for it
            self._build(client.gui, scene)

    def _build(self, gui: Any, scene: str) -> None:
        lectern = self.lectern
        # Created first, so they sit at the top of the panel where they are seen.
        self.gui_error = gui.add_markdown("", visible=False)
        self.gui_error_dismiss = gui.add_button("Dismiss message", color="red", visible=False)
        self.gui_error_dismiss.on_click(self.guard("dismiss", lambda _event: self.clear_error()))
        # "Server busy: N frames a second" (app.main) comes and goes with the load: last in the
        # panel, so that it never moves a slider under the hand.
        self.gui_load = gui.add_markdown("", visible=False, order=LAST)
        self.gui_scene = gui.add_dropdown("Scene", tuple(SCENES), initial_value=scene,
                                          hint="each scene models only what it needs")
        self.gui_scene.on_update(self.guard("scene dropdown", lambda _event: self._scene_chosen()))
        self._guarded_tick = self.guard("tick", self._tick)
        # The panel's parts, in the panel's order.
        self.projector_layout = ProjectorLayout(
            self.client, self.guard, lambda: None if self.mode is Mode.FOLLOWING else self.scene)
        # The live bar (app.hall.lecture_panel) and a narrow explorer's line sit right under the error line.
        top = float(self.gui_error_dismiss.order)
        self.lecture = LecturePanel(self, self.guard, lectern, order=top) if lectern is not None else None
        # Ask the class (app.hall.ask): the presenter's folder under the live bar, a student's question above all
        self.ask_panel = self.question = None
        if lectern is not None:
            self.ask_panel = AskPanel(self.client, self.guard, lectern.rounds, order=top + 0.3,
                                      audience=lambda: sum(lectern.total_audience()),
                                      scene_title=lambda: self.room.scene.title,
                                      presenting=lambda: self.mode is Mode.PRESENTING,
                                      play=self._play_state)
            self.question = AnswerPanel(self, self.guard, lectern.rounds, order=-20.0)
        self.narrow = NarrowPanel(self.client, self.guard, self._foldable, lambda: self.room, order=top + 0.5,
                                  copy=lambda: self.explored, own=lambda: self.mode is Mode.OWN)
        self.lesson_runner = LessonRunner(gui, self.guard, self, on_step=self._lesson_stepped)
        self.notes = Notes(self.client, self.guard, self.report_error, lambda: self.room, lambda: self.scene)
        self.share = None if self.share_store is None else SharePanel(
            self.client, self.guard, self.share_store, lambda: self.room, self.open_moment)
        self._room = Room(SCENES[scene], SCENES[scene].new_simulation())  # the Mine folder lists its presets
        self.own_panel = OwnPanel(gui, self.guard, self, self.own) if self.own is not None else None
        if self.own is not None:
            self.lesson_runner.add_lessons(self.own.lessons())
        # Their widgets, by the names tools and tests use.
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
        """The folders a collapsed follower's panel hides (`app.lectern.Seat`)."""
        self._preset_commands: list[Any] = []
        self._key_toast: Any = None  # the "Following the presenter" toast a key brought up
        self._build_commands(gui)
        self._shadow: Any = None
        self.scene: Any = None
        if lectern is not None and lectern.someone_presents:
            self.follow()
        else:
            # Nobody presents: its own room, also after a lecture (not the frozen last state).
            self.came_after_lecture = lectern is not None and lectern.live
            self.scene = self._new_view(self._room)
            self._hide_live(True)
            if self.lecture is not None:
                self.lecture.refresh()  # "the lecture has ended" from the first frame
        self._refresh_preset_commands()
        self._show_questions()  # the round asked now, or none, from the first frame
        self._fit_phone()

    def _fit_phone(self) -> None:
        """A narrow screen (a phone) with its own room, from the first panel on: the folded phone
        layout (`app.hall.narrow`) and the camera centring the body above its bottom sheet."""
        if self.mode is Mode.OWN and is_narrow(self.client.camera):
            self.narrow.start()
            self.reset_camera()

    @property
    def room(self) -> Room:
        """The room this browser shows: its own, or (following) the one on the shared screen."""
        if self.mode is Mode.FOLLOWING and self.lectern is not None:
            live = self.lectern.live_room
            if live is not None:
                return live
        return self._room

    @property
    def lock(self) -> threading.RLock:
        """Held for the whole of each of this session's callbacks and actions (the guard takes it,
        then the lock of the room shown)."""
        return self._busy

    @property
    def simulation(self) -> Any:
        return self.room.sim

    def _new_view(self, room: Room) -> Any:
        scene: Scene = room.scene
        view: Any = scene(self.client, room, self.guard, self.report_error)
        view.open_scene = self.open_scene
        self._offer_own(view)
        self.projector_layout.fit_new_view(view)
        return view

    def _offer_own(self, view: Any) -> None:
        """The lecturer's own presets of the view's scene in its presets row (★ Mine), started here."""
        if self.own is None:
            return
        view.start_own_preset = lambda name: self.start_preset(self.controlled_room(), name)
        view.show_own_presets([p.name for p in self.own.presets(view.room.scene.title)])

    def _foldable(self) -> list[Any]:
        """What a narrow explorer's panel folds away (`app.hall.narrow.NarrowPanel`): the scene
        dropdown, the lesson, the session's own folders and the view's panel."""
        view = self.scene
        roots = list(view.gui_roots) if self.mode is not Mode.FOLLOWING and hasattr(view, "gui_roots") else []
        return [self.gui_scene, self.lesson_runner.folder, *self.own_folders, *roots]

    def open_scene(self, title: str, prepare: Callable[[Room], None]) -> Room:
        """Show a new room of the scene `title` (SCENES), set up by `prepare(room)` first (a view
        handing a body on: "Spin it"), and move the camera to its view; the room."""
        scene = SCENES[title]
        room = Room(scene, scene.new_simulation())
        prepare(room)
        self.show(room)
        self.reset_camera()
        return room

    # ------------------------------------------------------------------ errors
    def guard(self, where: str, fn: Callable[..., R]) -> Callable[..., R | None]:
        """`fn` wrapped so that it runs under this session's lock and the room's, and an exception
        is logged and shown, never raised.

        where: a short name for the message ("θ slider", "tick", ...).
        """

        @functools.wraps(fn)
        def guarded(*args: Any, **kwargs: Any) -> R | None:
            with contextlib.ExitStack() as locks:
                if not writing_quietly():
                    # (A callback echoing the server's own quiet write runs under its writer's
                    # locks: the app loop draws under the room's, and taking this session's lock
                    # after it would deadlock with a callback that holds it and waits for the room.)
                    locks.enter_context(self._busy)
                    with self._switch_lock:
                        room = self.room
                    locks.enter_context(room.lock)
                try:
                    return fn(*args, **kwargs)
                except Exception as error:  # noqa: BLE001 - this is the safety net
                    self.report_error(where, error)
                    return None

        return guarded

    def report_error(self, where: str, error: BaseException) -> None:
        """Log `error` (with traceback, once per distinct message) and show it in the GUI."""
        message = f"{where}: {type(error).__name__}: {error}"
        self.error_count += 1
        if message == self.last_error:
            return  # a frame failing at 60 Hz: log and notify once, not 60 times a second
        self.last_error = message
        logger.error("client %d: error in %s", self.client_id, where, exc_info=error)
        try:
            self.gui_error.content = f"**⚠ Something went wrong** (the app keeps running)\n\n`{message}`"
            self.gui_error.visible = True
            self.gui_error_dismiss.visible = True
            self.client.add_notification("Error", message, color="red", auto_close_seconds=10.0,
                                         with_close_button=True)
        except Exception:  # noqa: BLE001 - e.g. the client has just disconnected
            logger.exception("client %d: could not show the error message", self.client_id)

    def show_load(self, note: str) -> None:
        """Say (or stop saying) that the server cannot keep its frame rate (called by the app loop)."""
        if self.closed:
            return
        try:
            self.gui_load.content = note
            self.gui_load.visible = bool(note)
        except Exception:  # noqa: BLE001 - the client has just gone
            logger.debug("load note not shown", exc_info=True)

    def clear_error(self) -> None:
        """Hide the error message."""
        self.last_error = None
        self.gui_error.visible = False
        self.gui_error_dismiss.visible = False

    # ------------------------------------------------------------------ scenes and rooms
    def _scene_chosen(self) -> None:
        title = self.gui_scene.value
        if title not in SCENES or self.mode is Mode.FOLLOWING:  # a client can send anything
            self.gui_scene.value = self.room.scene.title  # viser's setter
            if self.mode is Mode.FOLLOWING:
                raise PermissionError("this browser follows the presenter: press 'Explore on my own' first")
            return
        if title != self.room.scene.title:
            self.lesson_runner.scene_changed()  # by hand: the lesson (and its text) ends
            scene = SCENES[title]
            self.show(Room(scene, scene.new_simulation()))
            self.reset_camera()

    def show(self, room: Room) -> None:
        """Leave the current room and show `room` (a new view of it for this client)."""
        if self.mode is Mode.FOLLOWING:
            raise PermissionError("this browser follows the presenter: press 'Explore on my own' first")
        with self._switch_lock:
            old_view, old_room = self.scene, self.room
            with old_room.lock:
                old_view.remove()
            with room.lock:
                self._room = room
                if self.mode is Mode.PRESENTING and self.lectern is not None:
                    self.lectern.live_view = None  # removed above; the new one goes live
                    self.scene = self.lectern.make_live_view(self, room)
                    self.scene.open_scene = self.open_scene
                    self._offer_own(self.scene)
                else:
                    self.scene = self._new_view(room)
            if self.gui_scene.value != room.scene.title:
                self.gui_scene.value = room.scene.title  # the titles match now
        self.narrow.refresh()  # a narrow explorer's new scene panel folds too
        self._refresh_preset_commands()
        if self.own_panel is not None:
            self.own_panel.refresh()

    def watch(self, room: Room) -> None:
        """Show another session's room: this client becomes one more view of its simulation."""
        self.guard("watch", self.show)(room)

    def select_scene(self, title: str) -> None:
        """Switch to the scene `title` (a key of SCENES), as the dropdown does."""
        if title not in SCENES:
            raise ValueError(f"unknown scene {title!r}; choose one of {', '.join(SCENES)}")
        self.guard("scene", self.switch_scene)(title)

    def switch_scene(self, title: str) -> None:
        """Show a new room of the scene `title`, as the dropdown does (within the guard)."""
        self.gui_scene.value = title  # runs _scene_chosen synchronously

    def controlled_room(self) -> Room:
        """The room this browser may change (PermissionError while it follows the presenter)."""
        if self.mode is Mode.FOLLOWING:
            raise PermissionError("this browser follows the presenter: press 'Explore on my own' first")
        return self.room

    def apply_preset(self, name: str) -> None:
        """Load a preset of the active scene, its own or one of the lecturer's (`app.own`); a name
        it has neither of is an error (through the guard)."""
        self.guard("preset", lambda: self.start_preset(self.controlled_room(), name))()

    def start_preset(self, room: Room, name: str) -> None:
        """The preset `name` of room's scene, shipped or own, started in `room` (paused at its t = 0)."""
        scene = room.scene
        own = None if self.own is None else self.own.preset(scene.title, name)
        if own is None:
            scene.apply_preset(room, name)
            return
        scene.start_preset(room.sim, own)
        room.sim.preset = own.name
        room.pause()  # every view redraws

    def may_save(self) -> str:
        """"" if this browser may write the lecturer's data folder (app.own), else why not: the
        presenter may, and while nobody presents, a browser on its own; followers and students
        exploring during a lecture may not."""
        if self.own is None:
            return "this app keeps no presets or lessons of its own"
        if self.mode is Mode.PRESENTING:
            return ""
        if self.mode is Mode.FOLLOWING:
            return "a follower cannot save: only the presenter can, during a lecture"
        if self.lectern is not None and self.lectern.presenter is not None:
            return "while a lecture is on, only the presenter can save presets and lessons"
        return ""

    def own_changed(self) -> None:
        """The own presets or lessons changed: the Mine folder, the Lesson dropdown, the commands."""
        if self.own_panel is not None:
            self.own_panel.refresh()
        if self.own is not None:
            self.lesson_runner.add_lessons(self.own.lessons())
        if self.scene is not None and self.mode is not Mode.FOLLOWING:
            self._offer_own(self.scene)
        self._refresh_preset_commands()

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

    def _tick(self, dt: float) -> None:
        self.room.tick(dt)

    # ------------------------------------------------------------------ keys
    def _build_commands(self, gui: Any) -> None:
        """Keys (viser's command palette, Ctrl/Cmd+K, with hotkeys): space play/pause, S step,
        R reset; the scene's presets as commands (refreshed when the scene changes)."""
        for label, key, action in (("Play / pause", "space", lambda room: room.toggle()),
                                   ("Step", "S", lambda room: room.step()),
                                   ("Reset", "R", lambda room: room.reset())):
            command = gui.add_command(label, hotkey=key, description=f"key: {key}")
            command.on_trigger(self.guard(label, lambda _event, action=action: self._key(action)))

    def _key(self, action: Callable[[Room], None]) -> None:
        if self.mode is Mode.FOLLOWING:
            # One toast however many keys are pressed: the one on screen goes before the next.
            if self._key_toast is not None:
                with contextlib.suppress(Exception):  # closed already
                    self._key_toast.remove()
            self._key_toast = self.client.add_notification(
                "Following the presenter", "Press 'Explore on my own' to drive your own copy.",
                auto_close_seconds=3.0)
            return
        action(self.room)

    def _refresh_preset_commands(self) -> None:
        for command in self._preset_commands:
            command.remove()
        self._preset_commands = []
        if self.mode is Mode.FOLLOWING:
            return
        scene = self.room.scene
        own = () if self.own is None else self.own.presets(scene.title)
        for preset in (*scene.presets(), *own):
            command = self.client.gui.add_command(f"Preset: {preset.name}", description=scene.title)
            command.on_trigger(self.guard("preset command",
                                          lambda _event, name=preset.name: self.apply_preset(name)))
            self._preset_commands.append(command)

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
        """The current step's text (shown to the followers of a presenter running a lesson)."""
        return self.lesson_runner.text()

    def lecture_changed(self) -> None:
        """The lecture's state in this panel (`app.lectern.Seat.lecture_changed`): the live bar, and a
        narrow explorer's line (its layout ends if the screen became wide).  Skipped while one of
        this browser's callbacks runs (it may be switching views; the next refresh comes soon),
        so the app loop never waits for a browser."""
        if self.closed or not self._busy.acquire(blocking=False):
            return
        try:
            if self.lecture is not None:
                self.lecture.refresh()
            narrow = self.narrow
            if narrow.on and not is_narrow(self.client.camera):
                narrow.end()
            narrow.refresh()
        finally:
            self._busy.release()

    def call_back(self) -> None:
        """Ask every explorer back to the presenter (the `Call everyone back` button; presenter only)."""
        if self.lecture is None:
            raise RuntimeError("this app has no lecture hall")
        self.guard("call everyone back", self.lecture.call_back)()

    def caption_words(self) -> tuple[str, str]:
        """(head, words) of the lesson caption (`app.hall.lesson_runner.LessonRunner.caption_words`)."""
        return self.lesson_runner.caption_words()

    def _lesson_stepped(self) -> None:
        if self.lectern is not None and self.lectern.presenter is self:
            self.lectern.refresh_followers()
        lesson, k = self.lesson_runner.lesson, self.lesson_runner.step
        question = lesson.steps[k].ask if lesson is not None and 0 <= k < len(lesson.steps) else None
        if question is not None and self.ask_panel is not None:
            self.ask_panel.fill(question)  # the lecturer asks it with `Ask the class`

    def record(self, seconds: Any, *, wait: bool = False) -> threading.Thread:
        """Record the next `seconds` of the scene shown, offered as .html and .viser downloads
        (`app.hall.notes.Notes.record`)."""
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

    # ------------------------------------------------------------------ the lecture hall: this browser's mode
    def _show_mode(self) -> None:
        """The panel for this browser's mode: a follower has no scene or lesson to drive (its own
        folders are its follower panel's to show)."""
        if self.lecture is None:
            return
        following = self.mode is Mode.FOLLOWING
        self.lecture.show_for(self.mode)
        self._show_questions()
        self.gui_scene.visible = not following
        self.lesson_runner.folder.visible = not following
        self.narrow.refresh()

    # ------------------------------------------------------------------ ask the class (app.hall.ask, app.ask)
    def _show_questions(self) -> None:
        """The presenter's `Ask the class` folder while presenting; a student's question otherwise."""
        if self.ask_panel is not None and self.question is not None:
            presenting = self.mode is Mode.PRESENTING
            self.ask_panel.set_shown(presenting)
            self.question.active = not presenting
            self.question.refresh()

    def questions_changed(self) -> bool:
        """Show the round as it is now (the count, a student's question): called by the app loop,
        outside the guard; skipped (False) while one of this browser's callbacks runs, so the app
        loop never waits for a browser (it calls again soon)."""
        if self.closed or self.question is None:
            return True
        if not self._busy.acquire(blocking=False):
            return False
        try:
            if self.mode is Mode.PRESENTING and self.ask_panel is not None:
                self.ask_panel.refresh()
            self.question.refresh()
        except Exception as error:  # noqa: BLE001 - the app loop must not die from a browser
            self.report_error("question", error)
        finally:
            self._busy.release()
        return True

    def _rounds(self) -> Any:
        if self.lectern is None:
            raise RuntimeError("this app has no lecture hall")
        return self.lectern.rounds

    def _presenter_only(self, what: str) -> Any:
        if self.mode is not Mode.PRESENTING:
            raise PermissionError(f"only the presenter can {what}")
        return self._rounds()

    def ask(self, question: Question | dict[str, Any]) -> Any:
        """Ask the class `question` (a question or its dict, `app.ask.question_from_dict`): the new
        round (`app.ask.Round`).  Presenter only: PermissionError otherwise; ValueError for a bad question."""
        round_ = self._presenter_only("ask the class").ask(question)
        self._questions_shown()
        return round_

    def close_round(self) -> Any:
        """Close the current round (presenter only); the round."""
        round_ = self._presenter_only("close the round").close_round()
        self._questions_shown()
        return round_

    def vote_again(self) -> Any:
        """The same question again, the closed round beside the new one (presenter only); the new round."""
        round_ = self._presenter_only("vote again").vote_again()
        self._questions_shown()
        return round_

    def _play_state(self, answer: Any) -> None:
        """The gallery's `Play this answer`: only the presenter's room plays a student's state."""
        self._presenter_only("play an answer")
        play_answer(self.room, answer)

    def play_answer(self, number: int) -> None:
        """Play the current State round's anonymous answer `number` (1.. as in its CSV) in the
        presenter's room (presenter only); LookupError for no such answer, ValueError for another
        scene's body."""
        rounds = self._presenter_only("play an answer")
        round_ = rounds.current
        entries = {} if round_ is None else {e.number: e for e in gallery_entries(round_)}
        if number not in entries:
            raise LookupError(f"no state answer number {number}")
        self._play_state(entries[number].answer)

    def _questions_shown(self) -> None:
        if self.ask_panel is not None:
            self.guard("ask the class", self.ask_panel.refresh)()

    def answer(self, value: Any) -> Any:
        """Answer the round the class is asked now with `value` (an option's index, a 3-vector, a
        state dict), as this browser (its anonymous token); the answer as kept.  `app.ask.Refused`
        (a ValueError with the reason) for a refused answer; the presenter does not answer."""
        if self.mode is Mode.PRESENTING:
            raise PermissionError("the presenter asks; the class answers")
        return self._rounds().answer(self.answer_token, value)

    def my_answer(self) -> Any:
        """This browser's answer to the round shown, or None."""
        return None if self.lectern is None else self.lectern.rounds.mine(self.answer_token)

    def answer_from_copy(self) -> None:
        """A State question: leave the presenter with an exact copy of the room to answer from."""
        if self.mode is Mode.FOLLOWING:
            self.explore()

    def state_answer(self) -> Any:
        """This browser's own room's state, as a State question takes it (`app.ask.judges.read_state`)."""
        if self.mode is not Mode.OWN:
            raise PermissionError("answer from your own copy: press 'Answer from my copy' first")
        return read_state(self._room)

    def folded_for_question(self, folded: bool) -> None:
        """While a question waits for this browser's answer, the follower's panel is folded away."""
        follower = self.scene if self.mode is Mode.FOLLOWING else None
        folder = getattr(follower, "folder", None)
        if folder is not None and folder.visible == folded:
            folder.visible = not folded

    def _hide_live(self, hide: bool) -> None:
        """Hide the shared (presenter's) scene in this browser: an invisible node of the same
        name in this browser's own scope is drawn instead of the shared one and its children."""
        if hide and self._shadow is None:
            self._shadow = self.client.scene.add_frame(LIVE_ROOT, show_axes=False, visible=False)
        elif not hide and self._shadow is not None:
            self._shadow.remove()
            self._shadow = None

    def present(self, code: str) -> None:
        """Become the presenter with `code`: this browser's room goes live for every follower."""
        lectern = self.lectern
        panel = self.lecture
        if lectern is None or panel is None:
            raise RuntimeError("this app has no lecture hall")
        if lectern.try_code(self, code) is not None:
            panel.refused()  # the lectern's words, kept true while shown
            return
        panel.note("")
        self.came_after_lecture = False
        copy_note = ""
        if self.mode is Mode.FOLLOWING:
            copy_note = self._explore()  # an exact copy of what is on screen, then it goes live
        self.narrow.end()  # a presenter has the whole panel
        with self._switch_lock:
            panel.gui_code.value = ""
            room = self.room
            self._hide_live(False)  # first: removing the shadow removes what this browser has under it
            with room.lock:
                self.scene.remove()
                self.scene = lectern.make_live_view(self, room)
                self.scene.open_scene = self.open_scene
                self._offer_own(self.scene)
            self.mode = Mode.PRESENTING
            self.narrow.end()  # again: a phone's fold begun at connect meanwhile ends here
        lectern.start(self)
        self._show_mode()
        panel.set_pointer(bool(panel.gui_pointer.value))
        if copy_note:
            self.scene.show_message(copy_note)  # what the new presenter took over

    def stop_presenting(self) -> None:
        """Release the lock; the followers keep the last state; this browser keeps the room."""
        lectern = self.lectern
        if lectern is None or self.mode is not Mode.PRESENTING:
            return
        lectern.release(self, disconnected=False)
        with self._switch_lock:
            room = self.room
            with room.lock:
                self.scene.remove_panel()  # its shared nodes stay: the followers' last state
                self.mode = Mode.OWN
                self.scene = self._new_view(room)
            self._hide_live(True)
        self._show_mode()
        if self.lecture is not None:
            self.lecture.set_pointer(False)

    def following_by_default(self) -> bool:
        """A browser with its own room that has not chosen to explore follows a new presenter."""
        return self.mode is Mode.OWN and not self.explored

    def follow(self) -> None:
        """Follow the presenter (or the last state a presenter left): the shared scene and a
        read-only panel; this browser's own room goes."""
        lectern = self.lectern
        if lectern is None or not lectern.live or self.mode is not Mode.OWN:
            return
        with self._switch_lock:
            self.narrow.end()  # a follower's panel has its own narrow layout
            if self.scene is not None:
                with self._room.lock:
                    self.scene.remove()
                    self._room.remove_view(self.scene)
            self.scene = None
            self.lesson_runner.end()
            self.mode = Mode.FOLLOWING
            self.narrow.end()  # again: a phone's fold begun at connect meanwhile (`_fit_phone`) ends here
            self.explored = False
            self.came_after_lecture = False
            self._hide_live(False)
            self.scene = lectern.add_follower(self)
        self._show_mode()
        self._refresh_preset_commands()

    def explore(self) -> None:
        """Leave the presenter with an exact copy of what the shared screen shows now (the same
        scene, state, time, traces, plots and replay history, playing if it plays: `Room.fork`),
        seen from where this browser looked (its camera stays); a narrow screen keeps the phone
        layout (`app.hall.narrow.NarrowPanel`: one line and `Details`).  When the presenter's
        process has died, the best copy this process has, with a line saying what it is."""
        self._explore()

    def _explore(self) -> str:
        """`explore`; the copy's note ("" for an exact copy), also said in the view's message
        line: a presenter's process that died leaves the last state its room was seen in here,
        or only its scene (`app.cluster.bus.Bus.fetch_room_noted`)."""
        lectern = self.lectern
        if lectern is None or self.mode is not Mode.FOLLOWING:
            return ""
        copy, note = lectern.live_copy_noted()
        self._leave_presenter_for(copy)
        if note:
            self.scene.show_message(note)
        return note

    def open_last_lecture(self) -> None:
        """A browser that came after a lecture ended (`came_after_lecture`), in its own room:
        an exact copy of the room the last presenter left (what `Explore on my own` copies then,
        `Lectern.live_copy`: paused at its time; through the bus when that presenter was on
        another process), shown in place of its own room; the camera goes to the scene's view
        when the scene changes.  PermissionError while it follows or presents or while somebody
        presents (follow the presenter then); RuntimeError when no lecture's room is kept."""
        lectern = self.lectern
        if lectern is None:
            raise RuntimeError("this app has no lecture hall")
        if self.mode is not Mode.OWN:
            raise PermissionError("only a browser in its own room opens the last lecture's room")
        if lectern.someone_presents:
            raise PermissionError("a lecture is on: press 'Follow presenter' to see it")
        if not lectern.live:
            raise RuntimeError("no lecture has left a room to open")
        copy, note = lectern.live_copy_noted()
        changed = copy.scene.title != self.room.scene.title
        if changed:
            self.lesson_runner.scene_changed()  # by hand: the lesson (and its text) ends
        self.show(copy)
        if changed:
            self.reset_camera()
        if note:
            self.scene.show_message(note)

    def _leave_presenter_for(self, copy: Room) -> None:
        """A follower leaves the presenter and explores `copy` (its camera stays)."""
        lectern = self.lectern
        assert lectern is not None
        narrow = is_narrow(self.client.camera)
        with self._switch_lock:
            lectern.remove_follower(self)
            self.mode = Mode.OWN
            self.explored = True
            self._room = copy
            self._hide_live(True)
            with copy.lock:
                self.scene = self._new_view(copy)
            if self.gui_scene.value != copy.scene.title:
                self.gui_scene.value = copy.scene.title  # titles match: no switch
        self._show_mode()
        if narrow:
            self.narrow.start()
            self._centre_body()
        self._refresh_preset_commands()

    def _centre_body(self) -> None:
        """A narrow explorer's camera: where it looked from (direction, distance, fov), moved
        sideways so the body is in the middle of what its bottom sheet leaves (`centred_view`)."""
        camera = self.client.camera
        try:
            view = CameraView(tuple(float(c) for c in camera.position),  # type: ignore[arg-type]
                              tuple(float(c) for c in camera.look_at),  # type: ignore[arg-type]
                              tuple(float(c) for c in camera.up_direction),  # type: ignore[arg-type]
                              math.degrees(float(camera.fov)))
        except (AttributeError, TypeError, ValueError):  # not reported yet: nothing to keep
            return
        distance = math.dist(view.position, view.look_at)
        if distance > 0.0:
            apply_camera(self.client, centred_view(view, body_centre(self._room.scene.view), distance))

    def open_moment(self, room: Room, camera: Camera | None = None) -> None:
        """Show a shared moment (`app.hall.share`): in this browser's own room, on the presenter's
        screen while presenting, and, while following, by leaving the presenter to explore it
        (the shared screen never changes); then look from the camera it was shared with."""
        if self.mode is Mode.FOLLOWING:
            self._leave_presenter_for(room)
        else:
            self.show(room)
        if self.share is not None:
            self.share.set_camera(camera)

    def close(self) -> None:
        """Leave the room (its client is gone; viser drops the client's nodes); a presenter who
        leaves releases the lock, the followers keep the last state."""
        self.closed = True
        if self.lectern is not None:
            if self.mode is Mode.PRESENTING:
                self.lectern.release(self, disconnected=True)
                return
            if self.mode is Mode.FOLLOWING:
                self.lectern.remove_follower(self, disconnected=True)
                return
        room = self._room
        with room.lock:
            room.remove_view(self.scene)
            if not room.views:
                room.playing = False
