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

Languages: every text a person reads (the title, a step's text, its question's prompt and
options) is either a string (English) or a mapping of language codes (`app.i18n.LANGUAGES`) to
strings that has "en": `"text": {"en": "the line of nodes", "nl": "de knooplijn", "de": "die
Knotenlinie"}`.  A browser reads the lesson in its language, English where the lesson lacks it
(`Texts.get`, `Lesson.title_in`, `Step.text_in`, `Step.ask_in`).  A mapping without "en", an
unknown code or a value that is not a text is a `LessonError` like the rest.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any

from app.ask import Question, State, question_from_dict
from app.data import files_in, lessons_dir
from app.i18n import DEFAULT_LANGUAGE, LANGUAGES, Translator, translator
from app.kit.core.common import CameraView
from physics.methods import methods

__all__ = ["LESSONS_DIR", "Lesson", "LessonError", "Step", "Texts", "lessons", "load_lesson", "load_lessons",
           "caption_head", "in_language", "step_line", "step_words", "texts_of"]

LESSONS_DIR = lessons_dir()  # the shipped lessons (app.data: the checkout's or the installed ones)


class LessonError(ValueError):
    """A lesson file that cannot be used; the message names the file and the step."""


@dataclass(frozen=True)
class Texts:
    """One text a person reads, in the languages a lesson gives it: {code: text}, "en" always there."""

    by_language: dict[str, str]

    @property
    def en(self) -> str:
        """The English text."""
        return self.by_language[DEFAULT_LANGUAGE]

    def get(self, language: str) -> str:
        """The text in `language`, English where the lesson lacks it."""
        return self.by_language.get(language) or self.en

    def __str__(self) -> str:
        return self.en


def texts_of(value: Any, where: str) -> Texts:
    """A lesson's text: a string (English) or a mapping {"en": ..., "nl": ..., "de": ...} of
    non-empty strings with "en" among its known language codes; LessonError naming `where` otherwise."""
    if isinstance(value, str):
        value = {DEFAULT_LANGUAGE: value}
    if not isinstance(value, dict):
        raise LessonError(f"{where}: a text or a mapping of languages to texts wanted, got {type(value).__name__}")
    unknown = sorted(str(code) for code in value if code not in LANGUAGES)
    if unknown:
        raise LessonError(f"{where}: unknown language {unknown[0]!r} (the languages: {', '.join(LANGUAGES)})")
    if DEFAULT_LANGUAGE not in value:
        raise LessonError(f"{where}: the English text (\"en\") is missing")
    for code, text in value.items():
        if not isinstance(text, str) or not text.strip():
            raise LessonError(f"{where}.{code}: a text wanted, got {text!r}")
    return Texts(dict(value))


@dataclass(frozen=True)
class Step:
    scene: str
    text: str  # English; `texts` has every language the lesson gives
    preset: str | None = None
    camera: CameraView | None = None
    display: dict[str, bool] = field(default_factory=dict)
    play: bool | None = None
    tab: str | None = None
    integrator: str | None = None
    ask: Question | None = None  # a question to the class (`app.ask`), in English
    texts: Texts | None = None  # the text in every language the lesson gives (None: English only)
    asks: dict[str, Question] = field(default_factory=dict)  # the question in another language, by code

    def text_in(self, language: str) -> str:
        """The step's text in `language` (English where the lesson lacks it)."""
        return self.texts.get(language) if self.texts is not None else self.text

    def ask_in(self, language: str) -> Question | None:
        """The step's question in `language` (English where the lesson lacks it), or None."""
        return self.asks.get(language, self.ask)


@dataclass(frozen=True)
class Lesson:
    title: str  # English; `titles` has every language the lesson gives
    steps: tuple[Step, ...]
    path: Path | Traversable  # the file it was read from (str() names it in messages)
    titles: Texts | None = None

    def title_in(self, language: str) -> str:
        """The lesson's title in `language` (English where the lesson lacks it)."""
        return self.titles.get(language) if self.titles is not None else self.title


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
    if text is None or (isinstance(text, str) and not text.strip()):
        raise LessonError(f"{where}.text: missing (what to look at, which equation)")
    texts = texts_of(text, f"{where}.text")
    asks = _questions(entry, where, scene, scenes)
    return Step(scene=scene, text=texts.en, preset=preset, camera=camera, display=dict(display), play=play,
                tab=entry.get("tab"), integrator=entry.get("integrator"), ask=asks.pop(DEFAULT_LANGUAGE, None),
                texts=texts, asks=asks)


def _questions(entry: dict[str, Any], where: str, scene: str, scenes: dict[str, Any]) -> dict[str, Question]:
    """A step's "ask" by language code ({} for none): its prompt and options may each be a text
    or a mapping of languages (`texts_of`); "en" always, another code where one of them has it."""
    if "ask" not in entry:
        return {}
    spec = entry["ask"]
    if not isinstance(spec, dict):
        return {DEFAULT_LANGUAGE: _question(spec, where, scene, scenes)}
    prompt = texts_of(spec["prompt"], f"{where}.ask.prompt") if "prompt" in spec else None
    options = spec.get("options")
    choices = [texts_of(o, f"{where}.ask.options[{k}]") for k, o in enumerate(options)] \
        if isinstance(options, list) else None
    languages = {DEFAULT_LANGUAGE} | set(prompt.by_language if prompt else ()) | \
        {code for texts in choices or () for code in texts.by_language}
    asks = {}
    for code in sorted(languages, key=list(LANGUAGES).index):
        spec_in = dict(spec)
        if prompt is not None:
            spec_in["prompt"] = prompt.get(code)
        if choices is not None:
            spec_in["options"] = [texts.get(code) for texts in choices]
        asks[code] = _question(spec_in, where, scene, scenes)
    return asks


_FIELD_NAMED = re.compile(r"[A-Za-z_][\w\[\]]*: ")  # a question's fault that begins with its field: "options[1]: "


def _question(spec: Any, where: str, scene: str, scenes: dict[str, Any]) -> Question:
    """A step's "ask" in one language, checked (a state question's scene defaults to the step's, and must be one)."""
    if isinstance(spec, dict) and spec.get("kind") == "state" and "scene" not in spec:
        spec = {**spec, "scene": scene}
    try:
        question = question_from_dict(spec)
    except ValueError as error:  # "prompt: ..." names the field; a sentence that names none is the ask's
        named = _FIELD_NAMED.match(str(error)) is not None
        raise LessonError(f"{where}.ask.{error}" if named else f"{where}.ask: {error}") from None
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
        if not isinstance(data, dict) or data.get("title") is None:
            raise LessonError("title: missing")
        titles = texts_of(data["title"], "title")
        steps = data.get("steps")
        if not isinstance(steps, list) or not steps:
            raise LessonError("steps: missing or empty")
        own = own_presets or {}
        return Lesson(titles.en, tuple(_step(s, f"steps[{k}]", scenes, own) for k, s in enumerate(steps)), path,
                      titles=titles)
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


def step_line(lesson: Lesson, k: int, tr: Translator) -> str:
    """The Lesson folder's line of step `k` (0-based) in `tr`'s language (Markdown): the lesson's
    title, which step, its text."""
    line = tr.gettext("**{title}**, step {k}/{n}: ").format(title=lesson.title_in(tr.language), k=k + 1,
                                                             n=len(lesson.steps))
    return line + lesson.steps[k].text_in(tr.language)


def caption_head(lesson: Lesson, k: int, tr: Translator) -> str:
    """The caption's head of step `k` (0-based) in `tr`'s language: the lesson's title and which step."""
    return tr.gettext("{title} · step {k} of {n}").format(title=lesson.title_in(tr.language), k=k + 1,
                                                         n=len(lesson.steps))


_INDEX: dict[str, dict[str, str]] = {}  # by language: English step line, caption head or text -> that language's


def step_words(lesson: Lesson, k: int) -> dict[str, dict[str, str]]:
    """What a presenter on step `k` (0-based) sends its followers in English (the step's line,
    its caption's head, its text) in every other language: {code: {English: words}}.  The words
    travel with what the followers are sent (`app.lecture.follower.FollowerStatus.lesson_words`),
    so a follower on any process reads a lesson no process but the presenter's knows (a
    lecturer's own) in its language."""
    en = translator(DEFAULT_LANGUAGE)
    step = lesson.steps[k]
    english = (step_line(lesson, k, en), caption_head(lesson, k, en), step.text)
    words: dict[str, dict[str, str]] = {}
    for code in LANGUAGES:
        if code != DEFAULT_LANGUAGE:
            tr = translator(code)
            said = (step_line(lesson, k, tr), caption_head(lesson, k, tr), step.text_in(code))
            words[code] = dict(zip(english, said))
    return words


def in_language(english: str, language: str) -> str:
    """A lesson's words a presenter sent its followers in English (`step_line`, `caption_head`,
    a step's text or a lesson's title) in `language`, where a shipped lesson has them; `english`
    itself otherwise (another lesson, a text cut short: its words travel with it, `step_words`)."""
    if not english or language == DEFAULT_LANGUAGE:
        return english
    index = _INDEX.get(language)
    if index is None:
        index = _INDEX[language] = _index(language)
    return index.get(english, english)


def _index(language: str) -> dict[str, str]:
    index: dict[str, str] = {}
    for lesson in lessons():
        index[lesson.title] = lesson.title_in(language)
        for k in range(len(lesson.steps)):
            index.update(step_words(lesson, k)[language])
    return index
