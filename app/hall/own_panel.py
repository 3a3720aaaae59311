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

import functools
import json
from typing import Any, Protocol

import viser

from app.i18n import N_, Labels, Phrases, Said, Translator, Words, for_gui, written
from app.kit.core.common import Wrap
from app.kit.core.room import Room
from app.kit.panel.download import save_download
from app.lesson_errors import lesson_error_words
from app.lessons import LessonError
from app.own import OwnLibrary

__all__ = ["MINE_MARK", "NONE_CHOSEN", "OwnPanel"]

NONE_CHOSEN = "—"
MINE_MARK = "★ "  # an own preset or lesson in a list


OWN_REFUSALS = Phrases(
    (r"give the preset a name", N_("give the preset a name")),
    (r"give the lesson a name", N_("give the lesson a name")),
    (r"the preset's name is longer than (?P<most>\d+) characters",
     N_("the preset's name is longer than {most} characters")),
    (r"the lesson's name is longer than (?P<most>\d+) characters",
     N_("the lesson's name is longer than {most} characters")),
    (r"(?P<scene>.+) has a preset (?P<name>'.*'|\".*\") of its own: choose another name",
     N_("{scene} has a preset {name} of its own: choose another name")),
    (r"this moment cannot be a preset: (?P<why>.+)", N_("this moment cannot be a preset: {why}")),
    (r"no preset of yours named (?P<name>'.*'|\".*\") in (?P<scene>.+)",
     N_("no preset of yours named {name} in {scene}")),
    (r"(?P<scene>.+) has a preset named (?P<name>'.*'|\".*\") already",
     N_("{scene} has a preset named {name} already")),
    (r"no lesson of yours named (?P<name>'.*'|\".*\")", N_("no lesson of yours named {name}")),
    (r"this app keeps no presets or lessons of its own",
     N_("this app keeps no presets or lessons of its own")),
    (r"a follower cannot save: only the presenter can, during a lecture",
     N_("a follower cannot save: only the presenter can, during a lecture")),
    (r"while a lecture is on, only the presenter can save presets and lessons",
     N_("while a lecture is on, only the presenter can save presets and lessons")),
    translated=("scene",),
)
"""The refusals of the Mine folder's actions (`app.own`, `OwnRoom.may_save`), matched in English, and their msgids."""


def own_refusal_words(refusal: str, tr: Translator) -> str:
    """A refusal (English, from `app.own` or `may_save`) in `tr`'s language, a scene's title
    translated; the words as they are when no pattern knows them."""
    return OWN_REFUSALS.in_language(refusal, tr)


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
        self.gui = gui
        self._status_is_where = True  # the status line says where the data folder is (nothing done yet)
        self._status: tuple[Words, bool] | None = None  # what the status line said last (`say`), None: nothing yet
        self.folder = gui.add_folder(N_("Mine"), expand_by_default=False)
        with self.folder:
            self.gui_status = gui.add_markdown(self._where())
            self.gui_name = gui.add_text(N_("Name"), "", hint=N_("the name of a preset to save, or a new name for one"))
            self.gui_save = gui.add_button(N_("Save as preset"), icon=viser.Icon.DEVICE_FLOPPY,
                                           hint=N_("keep the moment shown as a preset of this scene"))
            self.gui_mine = gui.add_dropdown(N_("My presets"), (NONE_CHOSEN,), initial_value=NONE_CHOSEN)
            self.gui_actions = gui.add_button_group(N_("Preset"), (N_("Play"), N_("Rename"), N_("Delete")))
            self.gui_lesson_title = gui.add_text(N_("My lesson"), "", hint=N_("the title of a lesson of yours"))
            self.gui_step_text = gui.add_text(N_("Step text"), "", hint=N_("what to look at, which equation"))
            self.gui_add = gui.add_button(N_("Add to lesson"), icon=viser.Icon.PLUS,
                                          hint=N_("a step from this view: scene, preset, camera, checkboxes, text"))
            self.gui_export = gui.add_button(N_("Export lesson"), icon=viser.Icon.DOWNLOAD)
            self.gui_import = gui.add_upload_button(N_("Import lesson"), icon=viser.Icon.UPLOAD, mime_type=".json")
        self.words = Labels(gui)
        self.words.take(self.folder, self.gui_name, self.gui_save, self.gui_mine, self.gui_lesson_title,
                        self.gui_step_text, self.gui_add, self.gui_export, self.gui_import)
        self.words.take(self.gui_actions, options=True)
        self.gui_save.on_click(guard("save preset", lambda _e: self._said(self.save_preset)))
        self.gui_actions.on_click(guard("my preset", lambda e: self._said(
            self.act, self.words.english(e.target.value))))
        self.gui_add.on_click(guard("add to lesson", lambda _e: self._said(self.add_step)))
        self.gui_export.on_click(guard("export lesson", lambda _e: self._said(self.export_lesson)))
        self.gui_import.on_upload(guard("import lesson", lambda _e: self._said(self.import_uploaded)))
        self.refresh()

    def _where(self) -> str:
        return for_gui(self.gui).gettext("Saved on the server running this app, in `{folder}`").format(
            folder=self.library.data_dir)

    def relabel(self, tr: Translator) -> None:
        """The folder's words in `tr`'s language (the browser chose another), its status line's too."""
        self.words.relabel(tr)
        if self._status_is_where:
            self.gui_status.content = self._where()
        elif self._status is not None:
            self.say(*self._status)

    def _(self, message: str) -> str:
        return for_gui(self.gui).gettext(message)

    # ------------------------------------------------------------------ status
    def say(self, words: Words, refused: bool = False) -> None:
        """Say `words` in the status line, in the browser's language (kept: `relabel` says them again)."""
        self._status_is_where = False
        self._status = (words, refused)
        text = written(words, for_gui(self.gui))
        self.gui_status.content = f"**⚠ {text}**" if refused else text

    def _said(self, action: Any, *args: Any) -> None:
        """Run an action; a refusal (bad input, not allowed) is said here and changes nothing."""
        try:
            action(*args)
        except LessonError as error:  # a lesson file imported that does not load: its file, field and fault
            self.say(functools.partial(lesson_error_words, str(error)), refused=True)
        except (ValueError, PermissionError) as error:
            self.say(functools.partial(own_refusal_words, str(error)), refused=True)

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
            raise ValueError(self._("choose one of your presets under My presets"))
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
        self.say(lambda tr: tr.gettext("Saved **{name}** ({scene}): {note}").format(
            name=preset.name, scene=tr.gettext(scene.title), note=preset.note))

    def act(self, action: str) -> None:
        name = self._chosen()
        title = self.stage.room.scene.title
        if action == "Play":
            room = self.stage.controlled_room()
            self.stage.start_preset(room, name)
            room.play()
            self.say(Said(N_("Playing **{name}**."), name=name))
            return
        self._allowed()
        if action == "Rename":
            new = " ".join(str(self.gui_name.value).split())
            self.library.rename_preset(title, name, new)
            self.stage.own_changed()
            self.gui_mine.value = MINE_MARK + new
            self.say(Said(N_("Renamed **{name}** to **{new}**."), name=name, new=new))
        elif action == "Delete":
            self.library.delete_preset(title, name)
            self.stage.own_changed()
            self.say(Said(N_("Deleted **{name}**."), name=name))
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
        count = len(lesson.steps)
        self.say(lambda tr: tr.ngettext("**{title}**: {count} step (in the Lesson folder, marked ★).",
                                        "**{title}**: {count} steps (in the Lesson folder, marked ★).",
                                        count).format(title=lesson.title, count=count))

    def export_lesson(self) -> None:
        title = " ".join(str(self.gui_lesson_title.value).split())
        data = self.library.export_lesson(title)
        name = "".join(c if c.isalnum() or c in "-_" else "_" for c in title) + ".json"
        save_download(self.stage.client, name, data)
        self.last_export = data
        self.say(Said(N_("Exported **{title}** as {name}."), title=title, name=name))

    def import_uploaded(self) -> None:
        upload = self.gui_import.value
        self._allowed()
        lesson = self.library.import_lesson(upload.name, bytes(upload.content))
        self.stage.own_changed()
        self.gui_lesson_title.value = lesson.title
        count = len(lesson.steps)
        self.say(lambda tr: tr.ngettext(
            "Imported **{title}** ({count} step; in the Lesson folder, marked ★).",
            "Imported **{title}** ({count} steps; in the Lesson folder, marked ★).",
            count).format(title=lesson.title, count=count))

    @staticmethod
    def lesson_json(data: bytes) -> dict[str, Any]:
        """An exported lesson's JSON (for tools and tests)."""
        parsed: dict[str, Any] = json.loads(data.decode("utf-8"))
        return parsed
