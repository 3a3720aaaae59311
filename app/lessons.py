"""Lessons are data: `assets/lessons/*.json`, a sequence of steps a lecturer walks through.

    {"title": "§1 Euler angles and ω", "steps": [
        {"scene": "Euler angles", "preset": "gimbal lock",        # a scene and (optional) preset
         "camera": {"position": [5.9, -2.0, 3.3], "look_at": [0, 0, 0]},   # optional
         "display": {"Angle arcs": true},                        # optional: the scene's checkboxes
         "tab": "Lagrange", "integrator": "exact",               # optional: panel tab, integrator
                                                                 # (a name of physics.methods)
         "play": false,                                          # optional: play or pause
         "text": "θ = 0: only φ + ψ is defined (memo 1.13).",
         "ask": {"kind": "choice", "prompt": "...", "options": ["a", "b"], "correct": 0}}]}
                                                                 # optional: a question to the class
                                                                 # (`app.ask.question_from_dict`; a state
                                                                 # question's scene is the step's)

A step's question fills the presenter's `Ask the class` form (`app.hall.ask`): the lecturer asks
it when the class is ready.  `Next` / `Back` in the panel (and the → / ← keys) apply a step: the scene, the preset, the
camera, the toggles, play or pause, and the text in the panel.  When a presenter runs a lesson,
the followers see its motion and its text.  Files are read and checked at start; a broken one
stops the app with a `LessonError` naming the file and the step (`steps[2].preset: ...`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any

from app.ask import Question, State, question_from_dict
from app.data import files_in, lessons_dir
from app.kit.core.common import CameraView
from physics.methods import methods

__all__ = ["LESSONS_DIR", "Lesson", "LessonError", "Step", "lessons", "load_lesson", "load_lessons"]

LESSONS_DIR = lessons_dir()  # the shipped lessons (app.data: the checkout's or the installed ones)


class LessonError(ValueError):
    """A lesson file that cannot be used; the message names the file and the step."""


@dataclass(frozen=True)
class Step:
    scene: str
    text: str
    preset: str | None = None
    camera: CameraView | None = None
    display: dict[str, bool] = field(default_factory=dict)
    play: bool | None = None
    tab: str | None = None
    integrator: str | None = None
    ask: Question | None = None  # a question to the class (`app.ask`)


@dataclass(frozen=True)
class Lesson:
    title: str
    steps: tuple[Step, ...]
    path: Path | Traversable  # the file it was read from (str() names it in messages)


def _vector(value: Any, where: str) -> tuple[float, float, float]:
    if not isinstance(value, list) or len(value) != 3 or not all(
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in value):
        raise LessonError(f"{where}: three finite numbers wanted, got {value!r}")
    return float(value[0]), float(value[1]), float(value[2])


def _step(entry: Any, where: str, scenes: dict[str, Any], own: Mapping[str, Sequence[str]]) -> Step:
    if not isinstance(entry, dict):
        raise LessonError(f"{where}: not an object")
    unknown = sorted(set(entry) - {"scene", "preset", "camera", "display", "play", "text", "tab", "integrator",
                                  "ask"})
    if unknown:
        raise LessonError(f"{where}: unknown field {unknown[0]!r}")
    scene = entry.get("scene")
    if scene not in scenes:
        raise LessonError(f"{where}.scene: {scene!r} is not a scene ({', '.join(scenes)})")
    preset = entry.get("preset")
    if preset is not None:
        names = [p.name for p in scenes[scene].presets()] + list(own.get(scene, ()))
        if preset not in names:
            raise LessonError(f"{where}.preset: {scene} has no preset {preset!r} ({', '.join(names)})")
    camera = None
    if "camera" in entry:
        spec = entry["camera"]
        if not isinstance(spec, dict):
            raise LessonError(f"{where}.camera: an object with position and look_at wanted")
        camera = CameraView(_vector(spec.get("position"), f"{where}.camera.position"),
                            _vector(spec.get("look_at"), f"{where}.camera.look_at"))
    display = entry.get("display", {})
    if not isinstance(display, dict) or not all(isinstance(k, str) and isinstance(v, bool)
                                                for k, v in display.items()):
        raise LessonError(f"{where}.display: an object of toggle labels and true/false wanted")
    play = entry.get("play")
    if play is not None and not isinstance(play, bool):
        raise LessonError(f"{where}.play: true or false wanted")
    for name in ("tab", "integrator"):
        if name in entry and not isinstance(entry[name], str):
            raise LessonError(f"{where}.{name}: a name wanted, got {entry[name]!r}")
    registry = methods()
    if "integrator" in entry and entry["integrator"] not in registry:
        raise LessonError(f"{where}.integrator: {entry['integrator']!r} is not a method "
                          f"(the methods of `python -m physics methods`: {', '.join(registry)})")
    text = entry.get("text")
    if not isinstance(text, str) or not text.strip():
        raise LessonError(f"{where}.text: missing (what to look at, which equation)")
    return Step(scene=scene, text=text, preset=preset, camera=camera, display=dict(display), play=play,
                tab=entry.get("tab"), integrator=entry.get("integrator"), ask=_question(entry, where, scene, scenes))


def _question(entry: dict[str, Any], where: str, scene: str, scenes: dict[str, Any]) -> Question | None:
    """A step's "ask", checked (a state question's scene defaults to the step's, and must be one)."""
    if "ask" not in entry:
        return None
    spec = entry["ask"]
    if isinstance(spec, dict) and spec.get("kind") == "state" and "scene" not in spec:
        spec = {**spec, "scene": scene}
    try:
        question = question_from_dict(spec)
    except ValueError as error:
        raise LessonError(f"{where}.ask.{error}") from None
    if isinstance(question, State) and question.scene not in scenes:
        raise LessonError(f"{where}.ask.scene: {question.scene!r} is not a scene ({', '.join(scenes)})")
    return question


def load_lesson(path: Path | Traversable, scenes: dict[str, Any],
                own_presets: Mapping[str, Sequence[str]] | None = None) -> Lesson:
    """One lesson file, checked against the scenes and their presets (LessonError if broken).
    own_presets: {scene title: names} of the lecturer's own presets a step may name too (`app.own`)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise LessonError(f"{path}: not readable JSON: {error}") from None
    try:
        if not isinstance(data, dict) or not isinstance(data.get("title"), str):
            raise LessonError("title: missing")
        steps = data.get("steps")
        if not isinstance(steps, list) or not steps:
            raise LessonError("steps: missing or empty")
        own = own_presets or {}
        return Lesson(data["title"], tuple(_step(s, f"steps[{k}]", scenes, own) for k, s in enumerate(steps)), path)
    except LessonError as error:
        raise LessonError(f"{path}: {error}") from None


def load_lessons(scenes: dict[str, Any], directory: Path | Traversable = LESSONS_DIR) -> tuple[Lesson, ...]:
    """Every lesson (*.json) in `directory`, by file name."""
    return tuple(load_lesson(path, scenes) for path in files_in(directory, ".json"))


_LESSONS: tuple[Lesson, ...] | None = None


def lessons() -> tuple[Lesson, ...]:
    """The shipped lessons (assets/lessons, through `app.data`), read once, checked against the registered scenes."""
    global _LESSONS
    if _LESSONS is None:
        from app.scenes import SCENES

        _LESSONS = load_lessons(SCENES)
    return _LESSONS
