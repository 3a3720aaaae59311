"""A browser's own room and how it changes it (`OwnRoom`, the explorer's role).

The scene dropdown switches scenes: the old view leaves, a new room and view are built and the
camera moves to the scene's view.  A preset (the scene's, or one of the lecturer's own,
`app.own`) starts in the room; the keys (viser's command palette, Ctrl/Cmd+K, with hotkeys) play,
step and reset it, and the palette lists the scene's presets.  A browser that came after a
lecture ended opens the room the last presenter left (`open_last_lecture`).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from typing import Any, cast

from app.i18n import N_, for_gui
from app.kit.core.room import Room
from app.kit.view import SceneView
from app.lecture.lectern import Mode
from app.refusals import NotAllowed
from app.roles.showing import FOLLOWING_REFUSAL, Browser
from app.scenes import SCENES

__all__ = ["OwnRoom"]


class OwnRoom:
    """The rooms a browser shows of its own, their views, presets and keys (module docstring).

    Owned by the browser's session for its life; the rooms it builds are the session's own room
    (`Showing.own_room`) until the next replaces it.

    Args:
        browser: the session.
    """

    def __init__(self, browser: Browser) -> None:
        self.browser = browser
        self.showing = browser.showing
        self._preset_commands: list[Any] = []
        """The palette's `Preset: …` commands of the scene shown (none while following)."""
        self._key_toast: Any = None
        """The "Following the presenter" toast a key brought up, until the next key or it closes."""
        self._labels: dict[str, str] = {}  # scene title -> the dropdown's option (`build_dropdown`)
        self._titles: dict[str, str] = {}  # the dropdown's option -> scene title
        self._relabelling = False  # the dropdown is being relabelled: its callback does nothing

    def build_dropdown(self, gui: Any, title: str) -> Any:
        """The scene dropdown (`scene_chosen`), showing `title`; its options are the scenes' titles
        in the browser's language (`scene_label`)."""
        tr = for_gui(gui)
        self._labels = {name: tr.gettext(name) for name in SCENES}
        self._titles = {label: name for name, label in self._labels.items()}
        dropdown = gui.add_dropdown(tr.gettext("Scene"), tuple(self._labels.values()),
                                    initial_value=self.scene_label(title),
                                    hint=tr.gettext("each scene models only what it needs"))
        dropdown.on_update(self.browser.guard("scene dropdown", lambda _event: self.scene_chosen()))
        return dropdown

    def relabel_dropdown(self, dropdown: Any, title: str) -> None:
        """The scene dropdown in the browser's language now, showing `title` (no switch: its
        callback ignores what this writes)."""
        tr = for_gui(self.browser.client.gui)
        self._labels = {name: tr.gettext(name) for name in SCENES}
        self._titles = {label: name for name, label in self._labels.items()}
        self._relabelling = True
        try:
            dropdown.label = tr.gettext("Scene")
            dropdown.hint = tr.gettext("each scene models only what it needs")
            dropdown.options = tuple(self._labels.values())  # (viser: a value not among them becomes the first)
            dropdown.value = self.scene_label(title)
        finally:
            self._relabelling = False

    def rebuild_view(self) -> None:
        """The view of the room shown built again (the browser's language changed): the same
        room, its state and its other views untouched; the message the old view's line said, said
        in the new language (`MessageLine.take_over`)."""
        old = self.showing.view
        self.show(self.showing.room)
        new = self.showing.view
        if isinstance(old, SceneView) and isinstance(new, SceneView) and new is not old:
            new.message.take_over(old.message)

    def scene_label(self, title: str) -> str:
        """The scene dropdown's option for the scene `title` (a key of SCENES), in the browser's language."""
        return self._labels.get(title, title)

    def scene_title(self, label: str) -> str:
        """The scene title (a key of SCENES) of a dropdown option; the option itself if it is none."""
        return self._titles.get(label, label)

    def show_title(self, title: str) -> None:
        """The scene dropdown shows the scene `title` (no switch: it shows the room's scene already)."""
        label = self.scene_label(title)
        if self.browser.gui_scene.value != label:
            self.browser.gui_scene.value = label

    # ------------------------------------------------------------------ views
    def new_view(self, room: Room) -> SceneView:
        """A view of `room` for this browser (its own, not live), offering the lecturer's presets."""
        browser = self.browser
        view = cast(SceneView, room.scene(browser.client, room, browser.guard, browser.report_error))
        self.fit_view(view)
        browser.projector_layout.fit_new_view(view)
        return view

    def fit_view(self, view: SceneView) -> None:
        """A view of this browser's: `Spin it` opens scenes here, and its presets row offers the
        lecturer's own presets of its scene (★ Mine), started here."""
        view.open_scene = self.open_scene
        own = self.browser.own
        if own is None:
            return
        view.start_own_preset = lambda name: self.start_preset(self.showing.controlled_room(), name)
        view.show_own_presets([p.name for p in own.presets(view.room.scene.title)])

    def first_view(self) -> None:
        """The first view when nobody presents: its own room (also after a lecture, not its
        frozen last state: `came_after_lecture`, said by the live bar from the first frame)."""
        browser, showing = self.browser, self.showing
        lectern = browser.lectern
        showing.came_after_lecture = lectern is not None and lectern.live
        showing.view = self.new_view(showing.own_room)
        showing.hide_live(True)
        if browser.lecture is not None:
            browser.lecture.refresh()

    def open_scene(self, title: str, prepare: Callable[[Room], None]) -> Room:
        """Show a new room of the scene `title` (SCENES), set up by `prepare(room)` first (a view
        handing a body on: "Spin it"), and move the camera to its view; the room."""
        scene = SCENES[title]
        room = Room(scene, scene.new_simulation())
        prepare(room)
        self.show(room)
        self.browser.reset_camera()
        return room

    # ------------------------------------------------------------------ scenes and rooms
    def scene_chosen(self) -> None:
        """The scene dropdown changed: a new room of its scene (a title not in SCENES, or a
        follower's choice, puts the dropdown back)."""
        browser = self.browser
        if self._relabelling:
            return
        label = str(browser.gui_scene.value)  # (a later choice changes it; its callback runs next)
        title = self.scene_title(label)
        if title not in SCENES or self.showing.mode is Mode.FOLLOWING:  # a client can send anything
            browser.gui_scene.value = self.scene_label(self.showing.room.scene.title)  # viser's setter
            if self.showing.mode is Mode.FOLLOWING:
                raise NotAllowed(FOLLOWING_REFUSAL)
            return
        if title != self.showing.room.scene.title:
            browser.lesson_runner.scene_changed()  # by hand: the lesson (and its text) ends
            scene = SCENES[title]
            self.show(Room(scene, scene.new_simulation()), chosen=label)
            browser.reset_camera()

    def show(self, room: Room, chosen: str | None = None) -> None:
        """Leave the current room and show `room` (a new view of it for this client; live while
        presenting); the scene dropdown then shows its scene, unless the browser chose another
        scene while the view was built (its callback, waiting for this one, switches to it).

        chosen: the dropdown's value this switch answers (None: its value as the switch starts)."""
        showing, browser = self.showing, self.browser
        if showing.mode is Mode.FOLLOWING:
            raise NotAllowed(FOLLOWING_REFUSAL)
        chosen = str(browser.gui_scene.value) if chosen is None else chosen
        with showing.switch_lock:
            old_view, old_room = showing.view, showing.room
            with old_room.lock:
                if old_view is not None:
                    old_view.remove()
            with room.lock:
                showing.own_room = room
                showing.view = self._view_for_mode(room)
            if str(browser.gui_scene.value) == chosen:  # no newer choice: the titles match now
                self.show_title(room.scene.title)
        browser.narrow.refresh()  # a narrow explorer's new scene panel folds too
        self.refresh_preset_commands()
        if browser.own_panel is not None:
            browser.own_panel.refresh()

    def _view_for_mode(self, room: Room) -> SceneView:
        """A new view of `room`: live for the followers while presenting, else its own."""
        lectern = self.browser.lectern
        if self.showing.mode is Mode.PRESENTING and lectern is not None:
            lectern.live_view = None  # removed by the caller; the new one goes live
            return self.live_view(room)
        return self.new_view(room)

    def live_view(self, room: Room) -> SceneView:
        """The presenter's view of `room`, drawn into the shared scene (`Lectern.make_live_view`)."""
        lectern = self.browser.lectern
        assert lectern is not None
        view = cast(SceneView, lectern.make_live_view(self.browser, room))
        self.fit_view(view)
        return view

    def open_last_lecture(self) -> None:
        """A browser that came after a lecture ended, in its own room: an exact copy of the room
        the last presenter left (`Lectern.live_copy`: paused at its time; through the bus when
        that presenter was on another process), shown in place of its own room; the camera
        goes to the scene's view when the scene changes.  PermissionError while it follows or
        presents or while somebody presents; RuntimeError when no lecture's room is kept."""
        lectern = self.browser.lectern
        if lectern is None:
            raise RuntimeError("this app has no lecture hall")
        if self.showing.mode is not Mode.OWN:
            raise NotAllowed(N_("only a browser in its own room opens the last lecture's room"))
        if lectern.someone_presents:
            raise NotAllowed(N_("a lecture is on: press 'Follow presenter' to see it"))
        if not lectern.live:
            raise RuntimeError("no lecture has left a room to open")
        copy, note = lectern.live_copy_noted()
        changed = copy.scene.title != self.showing.room.scene.title
        if changed:
            self.browser.lesson_runner.scene_changed()  # by hand: the lesson (and its text) ends
        self.show(copy)
        if changed:
            self.browser.reset_camera()
        if note:
            self.showing.scene_view().show_message(note)

    # ------------------------------------------------------------------ presets
    def start_preset(self, room: Room, name: str) -> None:
        """The preset `name` of room's scene, shipped or own, started in `room` (paused at its t = 0)."""
        scene = room.scene
        own = None if self.browser.own is None else self.browser.own.preset(scene.title, name)
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
        browser, mode = self.browser, self.showing.mode
        if browser.own is None:
            return "this app keeps no presets or lessons of its own"
        if mode is Mode.PRESENTING:
            return ""
        if mode is Mode.FOLLOWING:
            return "a follower cannot save: only the presenter can, during a lecture"
        if browser.lectern is not None and browser.lectern.presenter is not None:
            return "while a lecture is on, only the presenter can save presets and lessons"
        return ""

    def own_changed(self) -> None:
        """The own presets or lessons changed: the Mine folder, the Lesson dropdown, the commands."""
        browser = self.browser
        if browser.own_panel is not None:
            browser.own_panel.refresh()
        if browser.own is not None:
            browser.lesson_runner.add_lessons(browser.own.lessons())
        view = self.showing.view
        if isinstance(view, SceneView) and self.showing.mode is not Mode.FOLLOWING:
            self.fit_view(view)
        self.refresh_preset_commands()

    # ------------------------------------------------------------------ keys
    def build_commands(self, gui: Any) -> None:
        """Keys (viser's command palette, Ctrl/Cmd+K, with hotkeys): space play/pause, S step,
        R reset; the scene's presets as commands (`refresh_preset_commands`)."""
        for label, key, action in (("Play / pause", "space", lambda room: room.toggle()),
                                   ("Step", "S", lambda room: room.step()),
                                   ("Reset", "R", lambda room: room.reset())):
            command = gui.add_command(label, hotkey=key, description=f"key: {key}")
            command.on_trigger(self.browser.guard(label, lambda _event, action=action: self._key(action)))

    def _key(self, action: Callable[[Room], None]) -> None:
        if self.showing.mode is Mode.FOLLOWING:
            # One toast however many keys are pressed: the one on screen goes before the next.
            if self._key_toast is not None:
                with contextlib.suppress(Exception):  # closed already
                    self._key_toast.remove()
            _ = for_gui(self.browser.client.gui).gettext
            self._key_toast = self.browser.client.add_notification(
                _("Following the presenter"), _("Press 'Explore on my own' to drive your own copy."),
                auto_close_seconds=3.0)
            return
        action(self.showing.room)

    def refresh_preset_commands(self) -> None:
        """The palette's presets of the scene shown, shipped and own (none while following)."""
        for command in self._preset_commands:
            command.remove()
        self._preset_commands = []
        if self.showing.mode is Mode.FOLLOWING:
            return
        browser = self.browser
        scene = self.showing.room.scene
        own = () if browser.own is None else browser.own.presets(scene.title)
        for preset in (*scene.presets(), *own):
            command = browser.client.gui.add_command(f"Preset: {preset.name}", description=scene.title)
            command.on_trigger(browser.guard("preset command",
                                             lambda _event, name=preset.name: self.apply_preset(name)))
            self._preset_commands.append(command)

    def apply_preset(self, name: str) -> None:
        """Load a preset of the active scene, its own or one of the lecturer's, through the guard."""
        self.browser.guard("preset", lambda: self.start_preset(self.showing.controlled_room(), name))()
