"""The `Mine` folder of one browser's panel: its lecturer's own presets and lessons (`app.own`).

    Name  [........]   Save as preset          the moment shown, kept in the data folder
    My presets [★ ...] Play · Rename · Delete   this scene's own presets (Rename takes Name)
    Lesson [.......]   Step text [....]   Add to lesson   Export lesson   Import lesson

`Save as preset` keeps the scene's moment (`SceneView.moment_preset`) under the name typed;
`Play` starts an own preset as the preset buttons do (paused at its t = 0) and plays it.  `Add to
lesson` appends a step made from what the browser shows (the scene, the preset its run started
from, the camera, the scene's checkboxes, the text typed) to the own lesson named; the own
lessons appear in the Lesson folder's dropdown marked ★.  `Export lesson` downloads its JSON file;
`Import lesson` takes such a file and keeps it, or says which file and which field do not load.

Who may write is `Stage.may_save()` (the presenter, or while nobody presents, a browser on its
own: `app.own`); a refusal, like every bad input here, is said on the folder's status line and
changes nothing.
"""

from __future__ import annotations

import json
from typing import Any, Protocol

import viser

from app.kit.core.common import Wrap
from app.kit.core.room import Room
from app.kit.panel.download import save_download
from app.lessons import LessonError
from app.own import OwnLibrary

__all__ = ["MINE_MARK", "NONE_CHOSEN", "OwnPanel"]

NONE_CHOSEN = "—"
MINE_MARK = "★ "  # an own preset or lesson in a list


class Stage(Protocol):
    """What the folder acts on: a browser's session (`app.session.Session` is one)."""

    client: viser.ClientHandle
    scene: Any

    @property
    def room(self) -> Room: ...

    def controlled_room(self) -> Room: ...

    def may_save(self) -> str:
        """"" if this browser may write into the data folder, else why not."""
        ...

    def start_preset(self, room: Room, name: str) -> None: ...

    def own_changed(self) -> None:
        """The own presets or lessons changed (lists and commands to refresh)."""
        ...


class OwnPanel:
    """The `Mine` folder.

    Attributes:
        folder; gui_name, gui_save; gui_mine (this scene's own presets, ★-marked), gui_actions
        (Play / Rename / Delete); gui_lesson_title, gui_step_text, gui_add, gui_export, gui_import;
        gui_status (what was done, or why not); last_export: the bytes last downloaded.
    """

    def __init__(self, gui: Any, guard: Wrap, stage: Stage, library: OwnLibrary) -> None:
        self.stage = stage
        self.library = library
        self.last_export: bytes | None = None
        self.folder = gui.add_folder("Mine", expand_by_default=False)
        with self.folder:
            self.gui_status = gui.add_markdown(f"Saved on the server running this app, in `{library.data_dir}`")
            self.gui_name = gui.add_text("Name", "", hint="the name of a preset to save, or a new name for one")
            self.gui_save = gui.add_button("Save as preset", icon=viser.Icon.DEVICE_FLOPPY,
                                           hint="keep the moment shown as a preset of this scene")
            self.gui_mine = gui.add_dropdown("My presets", (NONE_CHOSEN,), initial_value=NONE_CHOSEN)
            self.gui_actions = gui.add_button_group("Preset", ("Play", "Rename", "Delete"))
            self.gui_lesson_title = gui.add_text("My lesson", "", hint="the title of a lesson of yours")
            self.gui_step_text = gui.add_text("Step text", "", hint="what to look at, which equation")
            self.gui_add = gui.add_button("Add to lesson", icon=viser.Icon.PLUS,
                                          hint="a step from this view: scene, preset, camera, checkboxes, text")
            self.gui_export = gui.add_button("Export lesson", icon=viser.Icon.DOWNLOAD)
            self.gui_import = gui.add_upload_button("Import lesson", icon=viser.Icon.UPLOAD, mime_type=".json")
        self.gui_save.on_click(guard("save preset", lambda _e: self._said(self.save_preset)))
        self.gui_actions.on_click(guard("my preset", lambda e: self._said(self.act, str(e.target.value))))
        self.gui_add.on_click(guard("add to lesson", lambda _e: self._said(self.add_step)))
        self.gui_export.on_click(guard("export lesson", lambda _e: self._said(self.export_lesson)))
        self.gui_import.on_upload(guard("import lesson", lambda _e: self._said(self.import_uploaded)))
        self.refresh()

    # ------------------------------------------------------------------ status
    def say(self, text: str, refused: bool = False) -> None:
        self.gui_status.content = f"**⚠ {text}**" if refused else text

    def _said(self, action: Any, *args: Any) -> None:
        """Run an action; a refusal (bad input, not allowed) is said here and changes nothing."""
        try:
            action(*args)
        except (ValueError, PermissionError, LessonError) as error:
            self.say(str(error), refused=True)

    def _allowed(self) -> None:
        why_not = self.stage.may_save()
        if why_not:
            raise PermissionError(why_not)

    def refresh(self) -> None:
        """The own presets of the scene shown, in the dropdown."""
        title = self.stage.room.scene.title
        options = (NONE_CHOSEN, *(MINE_MARK + p.name for p in self.library.presets(title)))
        chosen = self.gui_mine.value
        if tuple(self.gui_mine.options) != options:
            self.gui_mine.options = options
        if chosen in options and self.gui_mine.value != chosen:
            self.gui_mine.value = chosen

    def _chosen(self) -> str:
        value = str(self.gui_mine.value)
        if not value.startswith(MINE_MARK):
            raise ValueError("choose one of your presets under My presets")
        return value[len(MINE_MARK):]

    # ------------------------------------------------------------------ presets
    def save_preset(self) -> None:
        self._allowed()
        room = self.stage.controlled_room()
        scene = room.scene
        preset = self.library.save_preset(scene.title, scene.moment_preset(room, str(self.gui_name.value)))
        room.sim.preset = preset.name  # the run shown is now that preset's (a lesson step names it)
        self.stage.own_changed()
        self.gui_mine.value = MINE_MARK + preset.name
        self.say(f"Saved **{preset.name}** ({scene.title}): {preset.note}")

    def act(self, action: str) -> None:
        name = self._chosen()
        title = self.stage.room.scene.title
        if action == "Play":
            room = self.stage.controlled_room()
            self.stage.start_preset(room, name)
            room.play()
            self.say(f"Playing **{name}**.")
            return
        self._allowed()
        if action == "Rename":
            new = " ".join(str(self.gui_name.value).split())
            self.library.rename_preset(title, name, new)
            self.stage.own_changed()
            self.gui_mine.value = MINE_MARK + new
            self.say(f"Renamed **{name}** to **{new}**.")
        elif action == "Delete":
            self.library.delete_preset(title, name)
            self.stage.own_changed()
            self.say(f"Deleted **{name}**.")
        else:
            raise ValueError(f"no action {action!r}")

    # ------------------------------------------------------------------ lessons
    def step_here(self) -> dict[str, Any]:
        """A lesson step (the JSON entry of `app.lessons`) from what this browser shows."""
        room, view, camera = self.stage.room, self.stage.scene, self.stage.client.camera
        step: dict[str, Any] = {"scene": room.scene.title}
        preset = getattr(room.sim, "preset", None)
        if preset is not None:
            step["preset"] = preset
        step["camera"] = {"position": [round(float(v), 4) for v in camera.position],
                          "look_at": [round(float(v), 4) for v in camera.look_at]}
        toggles = view.checkboxes() if hasattr(view, "checkboxes") else {}
        if toggles:
            step["display"] = {label: bool(box.value) for label, box in toggles.items()}
        step["play"] = bool(room.playing)
        step["text"] = str(self.gui_step_text.value).strip()
        return step

    def add_step(self) -> None:
        self._allowed()
        self.stage.controlled_room()
        lesson = self.library.add_step(str(self.gui_lesson_title.value), self.step_here())
        self.stage.own_changed()
        self.say(f"**{lesson.title}**: {len(lesson.steps)} step{'s' if len(lesson.steps) > 1 else ''} "
                 "(in the Lesson folder, marked ★).")

    def export_lesson(self) -> None:
        title = " ".join(str(self.gui_lesson_title.value).split())
        data = self.library.export_lesson(title)
        name = "".join(c if c.isalnum() or c in "-_" else "_" for c in title) + ".json"
        save_download(self.stage.client, name, data)
        self.last_export = data
        self.say(f"Exported **{title}** as {name}.")

    def import_uploaded(self) -> None:
        upload = self.gui_import.value
        self._allowed()
        lesson = self.library.import_lesson(upload.name, bytes(upload.content))
        self.stage.own_changed()
        self.gui_lesson_title.value = lesson.title
        self.say(f"Imported **{lesson.title}** ({len(lesson.steps)} steps; in the Lesson folder, marked ★).")

    @staticmethod
    def lesson_json(data: bytes) -> dict[str, Any]:
        """An exported lesson's JSON (for tools and tests)."""
        parsed: dict[str, Any] = json.loads(data.decode("utf-8"))
        return parsed
