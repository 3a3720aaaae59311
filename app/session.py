"""One `Session` per connected browser: its scene dropdown, its error display, its view.

A session shows one room (`app.kit.room.Room`: a simulation, its transport state and the views
watching it) through one view built for its client.  Today each session makes its own room;
`watch(room)` makes it a second view of another session's room (the presenter mode builds on
this).  The dropdown at the top switches scenes: the old view leaves, a new room and view are
built and the camera moves to the scene's view.

Every callback a session registers is wrapped by `Session.guard`: it runs under the room's
lock, and an exception is logged and shown in this client's GUI, never reaching viser's threads
or the app loop.  The public actions (`select_scene`, `apply_preset`, `play`, `pause`, `step`,
`reset`, `tick`) go through the guard too, so tools may call them from any thread and learn
of a refusal from `error_count` and `last_error`:

    session.select_scene("Free body"); session.apply_preset("Dzhanibekov"); session.play()
"""

from __future__ import annotations

import functools
import logging
import threading
from collections.abc import Callable
from typing import Any, TypeVar

import imageio.v3 as iio
import viser

from app.export import MAX_SECONDS, record
from app.kit.common import CameraView, apply_camera, checked_value
from app.kit.room import Room, Scene
from app.lectern import LIVE_ROOT, Lectern, Mode
from app.lessons import Lesson, lessons
from app.scenes import DEFAULT_SCENE, SCENES
from app.viser_internals import scene_nodes

__all__ = ["PROJECTOR_CSS", "PROJECTOR_LABEL_SCALE", "SCENES", "Mode", "Session", "projector_view"]

BRAND_COLOR = (200, 110, 0)
PROJECTOR_LABEL_SCALE = 1.4
PROJECTOR_CSS = """<style>
html { font-size: 20px; }
label, button, input, .mantine-Text-root, .mantine-Button-label, .mantine-InputWrapper-label,
.mantine-NumberInput-input, .mantine-Select-input, .mantine-TextInput-input, p, li, td { font-size: 19px !important; }
code, pre { font-size: 15px !important; }
.mantine-Slider-markLabel { display: none; }
.mantine-Flex-root:has(> div > p > label) { flex-wrap: wrap; }
.mantine-Flex-root > div:has(> p > label) { width: 100% !important; }
h3 { font-size: 22px !important; }
</style>"""

logger = logging.getLogger(__name__)

R = TypeVar("R")


def projector_view(view: CameraView) -> CameraView:
    """A scene's camera view for the projector layout: the panel is a narrow side bar there, so
    the view looks nearer the origin (scenes frame their body left of centre, for the floating
    panel) and from 10 % farther."""
    look_at = tuple(0.3 * c for c in view.look_at)
    position = tuple(a + 1.1 * (p - a) for p, a in zip(view.position, look_at))
    return CameraView(position, look_at, view.up, view.fov_deg)  # type: ignore[arg-type]


class Session:
    """The state of one browser tab: built on connect, dropped on disconnect.

    Attributes:
        client: the viser client this session draws to.
        room: the room it shows; scene: its view of that room (the active scene).
        last_error: the last error message shown, or None; error_count: errors so far.
    """

    def __init__(self, client: viser.ClientHandle, scene: str = DEFAULT_SCENE, *,
                 lectern: Lectern | None = None) -> None:
        self.client = client
        self.lectern = lectern
        self.mode = Mode.OWN
        self.explored = False  # pressed "Explore on my own": a new presenter does not pull it back
        self.last_recording: tuple[bytes, bytes] | None = None  # (.html, .viser) last offered
        self.last_screenshot: bytes | None = None  # PNG last offered
        self.client_id: int = client.client_id
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
        self.gui_load = gui.add_markdown("", visible=False)  # "Server busy: N frames a second" (app.main)
        self.gui_scene = gui.add_dropdown("Scene", tuple(SCENES), initial_value=scene,
                                          hint="each scene models only what it needs")
        self.gui_scene.on_update(self.guard("scene dropdown", lambda _event: self._scene_chosen()))
        self._guarded_tick = self.guard("tick", self._tick)
        self._guarded_point = self.guard("pointer", self._pointed)
        self.gui_projector = gui.add_checkbox("Projector", False, hint="large text, a narrow panel, large 3D labels")
        self.gui_projector.on_update(self.guard("projector", lambda _event: self.set_projector(
            bool(self.gui_projector.value))))
        if lectern is not None:
            self._build_lecture_panel(gui)
        self._build_lesson_panel(gui)
        self._build_notes_panel(gui)
        self.projector = False
        self._projector_style: Any = None
        self._preset_commands: list[Any] = []
        self._build_commands(gui)
        self._shadow: Any = None
        self._own_panel_shown = True
        self._room = Room(SCENES[scene], SCENES[scene].new_simulation())
        self.scene: Any = None
        if lectern is not None and lectern.live:
            self.follow()
        else:
            self.scene = self._new_view(self._room)
            self._hide_live(True)
        self._refresh_preset_commands()

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
        if self.projector:
            self._scale_labels(view.root, PROJECTOR_LABEL_SCALE)
        return view

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
            with self._busy:
                with self._switch_lock:
                    room = self.room
                with room.lock:
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
            if not self._in_lesson_step:
                self._end_lesson()  # a scene chosen by hand: the lesson (and its text) ends
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
                else:
                    self.scene = self._new_view(room)
            if self.gui_scene.value != room.scene.title:
                self.gui_scene.value = room.scene.title  # the titles match now
        self._refresh_preset_commands()

    def watch(self, room: Room) -> None:
        """Show another session's room: this client becomes one more view of its simulation."""
        self.guard("watch", self.show)(room)

    def select_scene(self, title: str) -> None:
        """Switch to the scene `title` (a key of SCENES), as the dropdown does."""
        if title not in SCENES:
            raise ValueError(f"unknown scene {title!r}; choose one of {', '.join(SCENES)}")
        self.guard("scene", self._select)(title)

    def _select(self, title: str) -> None:
        self.gui_scene.value = title  # runs _scene_chosen synchronously

    def _controlled_room(self) -> Room:
        """The room this browser may change (PermissionError while it follows the presenter)."""
        if self.mode is Mode.FOLLOWING:
            raise PermissionError("this browser follows the presenter: press 'Explore on my own' first")
        return self.room

    def apply_preset(self, name: str) -> None:
        """Load a preset of the active scene; a name it does not have is an error (through the guard)."""
        self.guard("preset", lambda: self.room.scene.apply_preset(self._controlled_room(), name))()

    def play(self) -> None:
        """Start the motion of the room shown."""
        self.guard("play", lambda: self._controlled_room().play())()

    def pause(self) -> None:
        self.guard("pause", lambda: self._controlled_room().pause())()

    def step(self) -> None:
        self.guard("step", lambda: self._controlled_room().step())()

    def reset(self) -> None:
        self.guard("reset", lambda: self._controlled_room().reset())()

    def tick(self, dt: float) -> None:
        """Advance the session's room by dt [s] of wall time (what the loop does for every room)."""
        if not self.closed:
            self._guarded_tick(dt)

    def _tick(self, dt: float) -> None:
        self.room.tick(dt)

    # ------------------------------------------------------------------ keys and the projector
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
            self.client.add_notification("Following the presenter", "Press 'Explore on my own' to drive "
                                         "your own copy.", auto_close_seconds=3.0)
            return
        action(self.room)

    def _refresh_preset_commands(self) -> None:
        for command in self._preset_commands:
            command.remove()
        self._preset_commands = []
        if self.mode is Mode.FOLLOWING:
            return
        scene = self.room.scene
        for preset in scene.presets():
            command = self.client.gui.add_command(f"Preset: {preset.name}", description=scene.title)
            command.on_trigger(self.guard("preset command",
                                          lambda _event, name=preset.name: self.apply_preset(name)))
            self._preset_commands.append(command)

    def set_projector(self, on: bool) -> None:
        """Projector layout for this browser: panel text >= 18 px, a narrower collapsible panel,
        3D labels PROJECTOR_LABEL_SCALE times larger."""
        on = bool(on)
        if on == self.projector:
            return
        self.projector = on
        if on:
            self._projector_style = self.client.gui.add_html(PROJECTOR_CSS)
        elif self._projector_style is not None:
            self._projector_style.remove()
            self._projector_style = None
        gui = self.client.gui
        gui.configure_theme(show_share_button=False, brand_color=BRAND_COLOR,
                            control_width="small" if on else "large")
        if on:  # docked on the right, narrow and collapsible: the 3D view keeps >= 70 % of 1024 px
            gui.main_panel.dock_right()
        else:
            gui.main_panel.float()
        if self.gui_projector.value != on:
            self.gui_projector.value = on
        if self.mode is not Mode.FOLLOWING and self.scene is not None:
            self._scale_labels(self.scene.root, PROJECTOR_LABEL_SCALE if on else 1.0 / PROJECTOR_LABEL_SCALE)
        if self.mode is not Mode.FOLLOWING:
            apply_camera(self.client, projector_view(self.room.scene.view) if on else self.room.scene.view)

    def reset_camera(self) -> None:
        """The scene's camera view (centred for the projector layout)."""
        view = self.room.scene.view
        apply_camera(self.client, projector_view(view) if self.projector else view)

    def _scale_labels(self, root: str, factor: float) -> None:
        """Multiply the screen size of every 3D label under `root` (this browser's nodes)."""
        for name, handle in scene_nodes(self.client.scene).items():
            if name.startswith(root + "/") and hasattr(handle, "font_screen_scale"):
                handle.font_screen_scale = float(handle.font_screen_scale) * factor

    # ------------------------------------------------------------------ lessons
    def _build_lesson_panel(self, gui: Any) -> None:
        self.lessons = {lesson.title: lesson for lesson in lessons()}
        self.lesson: Lesson | None = None
        self.lesson_step = -1
        self._in_lesson_step = False
        self.lesson_folder = gui.add_folder("Lesson", expand_by_default=False)
        with self.lesson_folder:
            self.gui_lesson = gui.add_dropdown("Lesson", ("—", *self.lessons), initial_value="—",
                                               hint="a walk through one section of the memo")
            self.gui_lesson_steps = gui.add_button_group("Step", ("◀ Back", "Next ▶"))
            self.gui_lesson_text = gui.add_markdown("")
        self.gui_lesson.on_update(self.guard("lesson", lambda _event: self.start_lesson(str(self.gui_lesson.value))))
        self.gui_lesson_steps.on_click(self.guard("lesson step", lambda event: self.next_step(
            -1 if str(event.target.value).startswith("◀") else 1)))
        for label, key, delta in (("Lesson: next step", "arrowright", 1), ("Lesson: back", "arrowleft", -1)):
            command = gui.add_command(label, hotkey=key, description=f"key: {key}")
            command.on_trigger(self.guard(label, lambda _event, delta=delta: self.next_step(delta)))

    def lesson_text(self) -> str:
        """The current step's text (shown to the followers of a presenter running a lesson)."""
        if self.lesson is None or self.lesson_step < 0:
            return ""
        return f"**{self.lesson.title}**, step {self.lesson_step + 1}/{len(self.lesson.steps)}: " + \
            self.lesson.steps[self.lesson_step].text

    def _end_lesson(self) -> None:
        """No lesson runs: its text goes (here and, for a presenter, on the followers' panels)."""
        self.lesson, self.lesson_step = None, -1
        self.gui_lesson_text.content = ""
        if self.gui_lesson.value != "—":
            self.gui_lesson.value = "—"  # runs start_lesson("—"): nothing more

    def _refuse_while_following(self) -> None:
        if self.mode is Mode.FOLLOWING:
            raise PermissionError("this browser follows the presenter: press 'Explore on my own' first")

    def start_lesson(self, title: str) -> None:
        """Run the lesson `title` from its first step ("—": none)."""
        if title not in self.lessons:  # "—", or anything a client sends
            self.lesson, self.lesson_step = None, -1
            self.gui_lesson_text.content = ""
            return
        self._refuse_while_following()
        self.lesson = self.lessons[title]
        self.lesson_step = -1
        self.next_step(1)

    def next_step(self, delta: int) -> None:
        """Go `delta` steps on (1 Next, -1 Back) in the running lesson, and apply that step."""
        if self.lesson is None:
            return
        self._refuse_while_following()
        k = min(max(self.lesson_step + delta, 0), len(self.lesson.steps) - 1)
        self.lesson_step = k
        step = self.lesson.steps[k]
        if step.scene != self.room.scene.title:
            self._in_lesson_step = True
            try:
                self._select(step.scene)
            finally:
                self._in_lesson_step = False
        room = self.room
        if step.preset is not None:
            room.scene.apply_preset(room, step.preset)
        view = self.scene
        toggles = view.checkboxes()
        for label, value in step.display.items():
            toggle = toggles.get(label)
            if toggle is None:
                raise ValueError(f"lesson step {self.lesson_step + 1}: {step.scene} has no checkbox {label!r}")
            if toggle.value != value:
                toggle.value = value  # runs its callback: the view redraws
        if step.tab is not None:
            view.show_tab(step.tab)
        if step.integrator is not None:
            view.set_integrator(step.integrator)
        if step.camera is not None:
            apply_camera(self.client, step.camera)
        if step.play is True:
            room.play()
        elif step.play is False:
            room.pause()
        self.gui_lesson_text.content = self.lesson_text()
        if self.lectern is not None and self.lectern.presenter is self:
            self.lectern.refresh_followers()

    # ------------------------------------------------------------------ recordings and screenshots
    def _build_notes_panel(self, gui: Any) -> None:
        self.notes_folder = gui.add_folder("For the notes", expand_by_default=False)
        with self.notes_folder:
            self.gui_record_seconds = gui.add_number("Record [s]", 10.0, min=1.0, max=60.0, step=1.0,
                                                     hint="simulated seconds from now, computed faster than real time")
            self.gui_record = gui.add_button("Record", icon=viser.Icon.VIDEO,
                                             hint="download the motion as .html (plays offline) and .viser")
            self.gui_record_progress = gui.add_progress_bar(0.0, visible=False)
            self.gui_screenshot = gui.add_button("Screenshot", icon=viser.Icon.CAMERA,
                                                 hint="download a PNG of this view, for slides")
        self.gui_record.on_click(self.guard("record", lambda _event: self.record(self.gui_record_seconds.value)))
        self.gui_screenshot.on_click(self.guard("screenshot", lambda _event: self.screenshot()))

    def record(self, seconds: Any, *, wait: bool = False) -> threading.Thread:
        """Record the next `seconds` of the scene shown, from its current state, and offer it as
        .html and .viser downloads.  The copy is taken now (`Room.fork`; the room shown is not
        touched); the frames are computed in a thread.  ValueError for a value out of range."""
        value = checked_value(seconds, 1.0, MAX_SECONDS)
        if value is None:
            raise ValueError(f"Record: {seconds!r} s refused: between 1 and {MAX_SECONDS:g} s")
        room = self.room
        copy = room.fork()
        title = room.scene.title.lower().replace(" ", "_")
        bar = self.gui_record_progress

        def work() -> None:
            try:
                bar.visible = True
                html = record(copy, value, fmt="html", progress=lambda f: setattr(bar, "value", 50.0 * f))
                data = record(copy, value, fmt="viser", progress=lambda f: setattr(bar, "value", 50.0 + 50.0 * f))
                self.client.send_file_download(f"{title}_{value:g}s.html", html)
                self.client.send_file_download(f"{title}_{value:g}s.viser", data)
                self.last_recording = (html, data)
            except Exception as error:  # noqa: BLE001 - shown, never raised into a thread
                self.report_error("record", error)
            finally:
                bar.visible = False

        thread = threading.Thread(target=work, name=f"record-{self.client_id}", daemon=True)
        thread.start()
        if wait:
            thread.join()
        return thread

    def screenshot(self, *, wait: bool = False) -> threading.Thread:
        """Ask this browser for a render of its view and offer it as a PNG download (in a
        thread: the browser answers in a second or so)."""

        def work() -> None:
            try:
                image = self.client.get_render(height=720, width=1280, transport_format="png")
                png = iio.imwrite("<bytes>", image, extension=".png")
                self.client.send_file_download("scene.png", png)
                self.last_screenshot = png
            except Exception as error:  # noqa: BLE001
                self.report_error("screenshot", error)

        thread = threading.Thread(target=work, name=f"screenshot-{self.client_id}", daemon=True)
        thread.start()
        if wait:
            thread.join()
        return thread

    # ------------------------------------------------------------------ the lecture hall
    def _build_lecture_panel(self, gui: Any) -> None:
        self.lecture_folder = gui.add_folder("Lecture", expand_by_default=False)
        with self.lecture_folder:
            self.gui_code = gui.add_text("Presenter code", "", hint="the code the app printed at start")
            self.gui_present = gui.add_button("Present", icon=viser.Icon.PRESENTATION,
                                              hint="show this browser's scene to everyone who follows")
            self.gui_stop = gui.add_button("Stop presenting", color="red", visible=False)
            self.gui_pointer = gui.add_checkbox("Pointer", False, visible=False,
                                                hint="click in the 3D view to point for everyone (or hold Shift)")
            self.gui_pointer_label = gui.add_text("Pointer label", "", visible=False,
                                                  hint="a few words shown beside the marker")
            self.gui_follow = gui.add_button("Follow presenter", icon=viser.Icon.USERS, visible=False)
            self.gui_lecture_note = gui.add_markdown("", visible=False)
        self.gui_present.on_click(self.guard("present", lambda _event: self.present(str(self.gui_code.value))))
        self.gui_stop.on_click(self.guard("stop presenting", lambda _event: self.stop_presenting()))
        self.gui_follow.on_click(self.guard("follow", lambda _event: self.follow()))
        self.gui_pointer.on_update(self.guard("pointer", lambda _event: self._pointer_mode(self.gui_pointer.value)))

    def _lecture_note(self, text: str) -> None:
        self.gui_lecture_note.content = text
        self.gui_lecture_note.visible = bool(text)

    def _show_lecture_buttons(self) -> None:
        """The panel for this browser's mode: a follower has no scene, lesson or notes to drive;
        `Follow presenter` is offered only while somebody else presents."""
        lectern = self.lectern
        if lectern is None:
            return
        following = self.mode is Mode.FOLLOWING
        self.gui_present.visible = self.gui_code.visible = self.mode is not Mode.PRESENTING
        self.gui_stop.visible = self.gui_pointer.visible = self.gui_pointer_label.visible = \
            self.mode is Mode.PRESENTING
        self.gui_follow.visible = (self.mode is Mode.OWN and lectern.presenter is not None
                                   and lectern.presenter is not self)
        self.gui_scene.visible = not following
        self.lesson_folder.visible = not following
        self._apply_own_panel()

    def show_own_panel(self, shown: bool) -> None:
        """Show or hide this session's own folders (a narrow follower's panel is one line)."""
        self._own_panel_shown = bool(shown)
        self._apply_own_panel()

    def _apply_own_panel(self) -> None:
        shown = self._own_panel_shown or self.mode is not Mode.FOLLOWING
        for handle in (self.gui_projector, self.notes_folder, *([self.lecture_folder] if self.lectern else [])):
            if handle.visible != shown:
                handle.visible = shown

    # The pointer: scene-level clicks on this browser's own scene (only it hears them).
    def _pointed(self, event: Any) -> None:
        if self.lectern is not None and self.mode is Mode.PRESENTING:
            self.lectern.point(self, event.ray_origin, event.ray_direction, str(self.gui_pointer_label.value))

    def _pointer_mode(self, on: Any) -> None:
        """Pointer on: a plain click points; off: only Shift + click does (while presenting)."""
        if not isinstance(on, bool):  # a client can send anything
            self.gui_pointer.value = False
            return
        scene = self.client.scene
        scene.remove_click_callback(self._guarded_point)
        if self.mode is not Mode.PRESENTING:
            return
        scene.on_click(modifier="shift")(self._guarded_point)
        if on:
            scene.on_click()(self._guarded_point)

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
        if lectern is None:
            raise RuntimeError("this app has no lecture hall")
        refusal = lectern.try_code(self, code)
        if refusal is not None:
            self._lecture_note(f"**⚠ {refusal}**")
            return
        self._lecture_note("")
        if self.mode is Mode.FOLLOWING:
            self.explore()  # an exact copy of what is on screen, then it goes live
        with self._switch_lock:
            self.gui_code.value = ""
            room = self.room
            self._hide_live(False)  # first: removing the shadow removes what this browser has under it
            with room.lock:
                self.scene.remove()
                self.scene = lectern.make_live_view(self, room)
                self.scene.open_scene = self.open_scene
            self.mode = Mode.PRESENTING
        lectern.start(self)
        self._show_lecture_buttons()
        self._pointer_mode(bool(self.gui_pointer.value))

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
        self._show_lecture_buttons()
        self._pointer_mode(False)

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
            if self.scene is not None:
                with self._room.lock:
                    self.scene.remove()
                    self._room.remove_view(self.scene)
            self.scene = None
            self._end_lesson()
            self.mode = Mode.FOLLOWING
            self.explored = False
            self._hide_live(False)
            self.scene = lectern.add_follower(self)
        self._show_lecture_buttons()
        self._refresh_preset_commands()

    def explore(self) -> None:
        """Leave the presenter with an exact copy of what the shared screen shows now (the same
        scene, state, time, traces and plots, playing if it plays: `Room.fork`)."""
        lectern = self.lectern
        if lectern is None or self.mode is not Mode.FOLLOWING:
            return
        live = lectern.live_room
        if live is None:
            raise RuntimeError("there is nothing on the shared screen to explore")
        copy = live.fork()
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
        self._show_lecture_buttons()
        self._refresh_preset_commands()
        if lectern.presenter is not None:  # the same view as the presenter's
            lectern.reset_view(self)

    def close(self) -> None:
        """Leave the room (its client is gone; viser drops the client's nodes); a presenter who
        leaves releases the lock, the followers keep the last state."""
        self.closed = True
        if self.lectern is not None:
            if self.mode is Mode.PRESENTING:
                self.lectern.release(self, disconnected=True)
                return
            if self.mode is Mode.FOLLOWING:
                self.lectern.followers.pop(self.client_id, None)
                return
        room = self._room
        with room.lock:
            room.remove_view(self.scene)
            if not room.views:
                room.playing = False
