"""The lecturer's own presets and lessons, kept in the app's data folder (`--data-dir`).

    DATA/presets/<scene's preset file>.json   the scene's own presets, in the format of
                                              assets/presets (`app.kit.core.presets`), group "Mine"
    DATA/lessons/<title>.json                 own lessons, in the format of assets/lessons (`app.lessons`)

Nothing here writes into the package (assets/ stays as shipped); a file is written whole to a
temporary name and renamed, so a crash leaves the old file or the new one.  A preset is the
moment a room shows, named (`SceneView.moment_preset`: the scene's parameters, attitude and rates
now, as a new t = 0); its name may not be one of the scene's own presets (each name means one
thing in a lesson).  A lesson step names a scene, a preset (shipped or own), the camera, the
scene's checkboxes and a text.  Importing a lesson checks it as the app checks its own at start
(`app.lessons.load_lesson`, against the scenes and their presets, own ones included) and refuses
a file that does not load with the file and the field named (`LessonError`), writing nothing.

Who may write (`Session.may_save`): the presenter, or, while nobody presents, a browser exploring
on its own: a lecturer setting up before or after a lecture.  While a lecture is on, followers
and students exploring on their own cannot save, rename, delete or import (they can still export
a lesson to keep): a class on one server shares one data folder, and it is the lecturer's.
"""

from __future__ import annotations

import json
import os
import re
import tempfile
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from app.kit.core.presets import Preset, PresetError, load_presets
from app.lessons import Lesson, LessonError, load_lesson
from app.userdata import ensure_data_dir

__all__ = ["OWN_GROUP", "OwnLibrary", "preset_entry"]

OWN_GROUP = "Mine"  # the group of an own preset (the scene's presets have theirs)
MAX_NAME = 60  # characters of a preset's or lesson's name


def preset_entry(scene: Any, preset: Preset) -> dict[str, Any]:
    """The JSON entry of `preset` for the scene class `scene` (the format of assets/presets)."""
    entry: dict[str, Any] = {"name": preset.name, "group": preset.group, "note": preset.note,
                             "angles_deg": [float(a) for a in preset.angles_deg]}
    if scene.param_specs:
        entry["params"] = {spec.key: float(v) for spec, v in zip(scene.param_specs, preset.params)}
    if scene.rate_specs:
        entry["rates"] = {spec.key: float(v) for spec, v in zip(scene.rate_specs, preset.rates)}
    return entry


def _clean_name(name: str, what: str) -> str:
    name = " ".join(str(name).split())
    if not name:
        raise ValueError(f"give the {what} a name")
    if len(name) > MAX_NAME:
        raise ValueError(f"the {what}'s name is longer than {MAX_NAME} characters")
    return name


def _write_json(path: Path, data: Any) -> None:
    """`data` as JSON at `path`, written whole (a temporary file renamed over it)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=".", suffix=".json", dir=path.parent)
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            json.dump(data, out, ensure_ascii=False, indent=1)
            out.write("\n")
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


class OwnLibrary:
    """The own presets and lessons in `data_dir` (None: `app.userdata.default_data_dir()`),
    created when something is first saved.  Thread safe (one lock).

    scenes: {title: scene class} (app.scenes.SCENES).  problems: files of the folder that did not
    load (each message names the file and the field); they are left as they are, not listed.
    """

    def __init__(self, data_dir: str | Path | None, scenes: Mapping[str, Any]) -> None:
        self._given = data_dir
        self.scenes = scenes
        self._lock = threading.RLock()
        self.problems: list[str] = []
        self._presets: dict[str, tuple[Preset, ...]] = {}
        self._lessons: dict[str, Lesson] = {}
        self.reload()

    @property
    def data_dir(self) -> Path:
        """The data folder (not created)."""
        from app.userdata import default_data_dir

        return Path(self._given).expanduser() if self._given else default_data_dir()

    def _folder(self, name: str) -> Path:
        return ensure_data_dir(self.data_dir) / name

    def _preset_path(self, title: str) -> Path:
        return self.data_dir / "presets" / self.scenes[title].preset_file

    # ------------------------------------------------------------------ reading
    def reload(self) -> None:
        """Read every own preset and lesson again; the files that do not load go to `problems`."""
        with self._lock:
            self.problems = []
            self._presets = {}
            for title, scene in self.scenes.items():
                path = self._preset_path(title)
                if not path.is_file() or not scene.preset_file:
                    continue
                try:
                    found = load_presets(path, scene.param_specs, scene.rate_specs, check=scene.check_preset)
                except PresetError as error:
                    self.problems.append(str(error))
                    continue
                shipped = {p.name for p in scene.presets()}
                self._presets[title] = tuple(p for p in found if p.name not in shipped)
            self._lessons = {}
            folder = self.data_dir / "lessons"
            for path in sorted(folder.glob("*.json")) if folder.is_dir() else ():
                try:
                    lesson = load_lesson(path, dict(self.scenes), self.preset_names())
                except LessonError as error:
                    self.problems.append(str(error))
                    continue
                self._lessons[lesson.title] = lesson

    def presets(self, title: str) -> tuple[Preset, ...]:
        """The own presets of the scene `title`, in the order saved."""
        with self._lock:
            return self._presets.get(title, ())

    def preset(self, title: str, name: str) -> Preset | None:
        return next((p for p in self.presets(title) if p.name == name), None)

    def preset_names(self) -> dict[str, tuple[str, ...]]:
        """{scene title: its own presets' names} (what a lesson may name besides the shipped ones)."""
        with self._lock:
            return {title: tuple(p.name for p in presets) for title, presets in self._presets.items()}

    def lessons(self) -> dict[str, Lesson]:
        """The own lessons by title."""
        with self._lock:
            return dict(self._lessons)

    # ------------------------------------------------------------------ presets
    def _store_presets(self, title: str, presets: tuple[Preset, ...]) -> None:
        scene = self.scenes[title]
        path = self._folder("presets") / scene.preset_file
        if presets:
            _write_json(path, {"scene": title, "presets": [preset_entry(scene, p) for p in presets]})
        else:
            path.unlink(missing_ok=True)
        self._presets[title] = presets

    def save_preset(self, title: str, preset: Preset) -> Preset:
        """Keep `preset` (a moment of the scene `title`) under its name, replacing an own preset of
        that name; ValueError for a name the scene's presets have or a preset the scene refuses."""
        scene = self.scenes[title]
        name = _clean_name(preset.name, "preset")
        if name in {p.name for p in scene.presets()}:
            raise ValueError(f"{title} has a preset {name!r} of its own: choose another name")
        preset = Preset(name, OWN_GROUP, preset.note, preset.params, preset.angles_deg, preset.rates)
        entry = preset_entry(scene, preset)
        with tempfile.TemporaryDirectory() as scratch:  # checked as the file will be read
            probe = Path(scratch) / "preset.json"
            probe.write_text(json.dumps({"presets": [entry]}), encoding="utf-8")
            try:
                load_presets(probe, scene.param_specs, scene.rate_specs, check=scene.check_preset)
            except PresetError as error:
                raise ValueError(f"this moment cannot be a preset: {str(error).split(': ', 1)[1]}") from None
        with self._lock:
            kept = tuple(p for p in self.presets(title) if p.name != name)
            self._store_presets(title, (*kept, preset))
        return preset

    def rename_preset(self, title: str, old: str, new: str) -> None:
        """Rename an own preset (ValueError if there is none, or for a name already used)."""
        new = _clean_name(new, "preset")
        with self._lock:
            presets = self.presets(title)
            if old not in {p.name for p in presets}:
                raise ValueError(f"no preset of yours named {old!r} in {title}")
            if new in {p.name for p in presets} | {p.name for p in self.scenes[title].presets()}:
                raise ValueError(f"{title} has a preset named {new!r} already")
            self._store_presets(title, tuple(
                Preset(new, p.group, p.note, p.params, p.angles_deg, p.rates) if p.name == old else p
                for p in presets))

    def delete_preset(self, title: str, name: str) -> None:
        """Delete an own preset (ValueError if there is none)."""
        with self._lock:
            presets = self.presets(title)
            if name not in {p.name for p in presets}:
                raise ValueError(f"no preset of yours named {name!r} in {title}")
            self._store_presets(title, tuple(p for p in presets if p.name != name))

    # ------------------------------------------------------------------ lessons
    def _lesson_path(self, title: str) -> Path:
        stem = re.sub(r"[^\w-]+", "_", title, flags=re.UNICODE).strip("_")[:MAX_NAME] or "lesson"
        return self._folder("lessons") / f"{stem}.json"

    def _write_lesson(self, title: str, data: dict[str, Any]) -> Lesson:
        path = self._lesson_path(title)
        old = self._lessons.get(title)
        if old is not None and Path(str(old.path)) != path:
            Path(str(old.path)).unlink(missing_ok=True)
        _write_json(path, data)
        lesson = load_lesson(path, dict(self.scenes), self.preset_names())
        self._lessons[title] = lesson
        return lesson

    def add_step(self, title: str, step: dict[str, Any]) -> Lesson:
        """Append `step` (an entry of a lesson file's `steps`) to the own lesson `title`, made if
        new; the lesson (LessonError naming the field if the step is not one)."""
        title = _clean_name(title, "lesson")
        with self._lock:
            old = self._lessons.get(title)
            steps = [] if old is None else json.loads(Path(str(old.path)).read_text(encoding="utf-8"))["steps"]
            data = {"title": title, "steps": [*steps, step]}
            with tempfile.TemporaryDirectory() as scratch:  # checked before anything is written
                probe = Path(scratch) / "step.json"
                probe.write_text(json.dumps(data, ensure_ascii=False), encoding="utf-8")
                load_lesson(probe, dict(self.scenes), self.preset_names())
            return self._write_lesson(title, data)

    def export_lesson(self, title: str) -> bytes:
        """The own lesson `title` as the JSON file the app reads."""
        with self._lock:
            lesson = self._lessons.get(title)
            if lesson is None:
                raise ValueError(f"no lesson of yours named {title!r}")
            return Path(str(lesson.path)).read_bytes()

    def import_lesson(self, file_name: str, content: bytes) -> Lesson:
        """A lesson file (as exported, or as in assets/lessons) checked and kept; LessonError naming
        `file_name` and the field if it does not load (nothing is written then)."""
        with self._lock, tempfile.TemporaryDirectory() as scratch:
            probe = Path(scratch) / (Path(file_name).name or "lesson.json")
            probe.write_bytes(content)
            try:
                lesson = load_lesson(probe, dict(self.scenes), self.preset_names())
            except LessonError as error:  # named by the file the user chose, not the scratch copy
                raise LessonError(str(error).replace(str(probe), probe.name)) from None
            data = json.loads(content.decode("utf-8"))
            return self._write_lesson(lesson.title, data)
