"""A broken lesson file's error (`app.lessons.LessonError`) as a person reads it: in their
browser's language.

`app.lessons` writes its errors in English (the app's start, the logs, `python -m app`): the file,
then the field's path in the JSON and what is wrong with it ("my.json: steps[2].preset: Heavy top
has no preset 'Spin' (Sleeping, ...)").  `lesson_error_words` writes the sentence in the reader's
language; the file's name, the field's path and the values the file must hold (scene titles,
preset names, JSON keys, as the file spells them) stay as they are.

    lesson_error_words("my.json: steps[0]: not an object", translator("de"))
    # "my.json: steps[0]: kein Objekt"
"""

from __future__ import annotations

from app.i18n import N_, Phrases, Translator

__all__ = ["LESSON_ERRORS", "LESSON_FIELD_ERRORS", "lesson_error_words"]

_WHERE = r"(?P<where>[A-Za-z_][\w\[\].]*)"  # a field's path in the lesson's JSON: steps[2].camera.position

LESSON_FIELD_ERRORS = Phrases(
    (r"not readable JSON: (?P<error>.+)", N_("not readable JSON: {error}")),
    (rf"{_WHERE}: missing", N_("{where}: missing")),
    (rf"{_WHERE}: missing or empty", N_("{where}: missing or empty")),
    (rf"{_WHERE}: missing \(what to look at, which equation\)",
     N_("{where}: missing (what to look at, which equation)")),
    (rf"{_WHERE}: not an object", N_("{where}: not an object")),
    (rf"{_WHERE}: unknown field (?P<field>.+)", N_("{where}: unknown field {field}")),
    (rf"{_WHERE}: (?P<scene>.+) is not a scene \((?P<scenes>.+)\)", N_("{where}: {scene} is not a scene ({scenes})")),
    (rf"{_WHERE}: (?P<scene>.+) has no preset (?P<preset>'.*'|\".*\") \((?P<names>.*)\)",
     N_("{where}: {scene} has no preset {preset} ({names})")),
    (rf"{_WHERE}: an object with position and look_at wanted",
     N_("{where}: an object with position and look_at wanted")),
    (rf"{_WHERE}: three finite numbers wanted, got (?P<value>.+)",
     N_("{where}: three finite numbers wanted, got {value}")),
    (rf"{_WHERE}: an object of toggle labels and true/false wanted",
     N_("{where}: an object of toggle labels and true/false wanted")),
    (rf"{_WHERE}: true or false wanted", N_("{where}: true or false wanted")),
    (rf"{_WHERE}: a name wanted, got (?P<value>.+)", N_("{where}: a name wanted, got {value}")),
    (rf"{_WHERE}: (?P<value>.+) is not a method \(the methods of `python -m physics methods`: (?P<methods>.+)\)",
     N_("{where}: {value} is not a method (the methods of `python -m physics methods`: {methods})")),
    (rf"{_WHERE}: a text or a mapping of languages to texts wanted, got (?P<type>\w+)",
     N_("{where}: a text or a mapping of languages to texts wanted, got {type}")),
    (rf"{_WHERE}: unknown language (?P<code>.+) \(the languages: (?P<languages>.+)\)",
     N_("{where}: unknown language {code} (the languages: {languages})")),
    (rf"{_WHERE}: the English text \(\"en\"\) is missing", N_("{where}: the English text (\"en\") is missing")),
    (rf"{_WHERE}: a text wanted, got (?P<value>.+)", N_("{where}: a text wanted, got {value}")),
)
"""What `app.lessons` says is wrong with a field (after the file's name), matched in English."""

LESSON_ERRORS = Phrases(
    (r"(?P<file>[^:]+): (?P<error>.+)", "{file}: {error}"),
    nested={"error": LESSON_FIELD_ERRORS},
)
"""A lesson file's error: its file's name, then the field's (`LESSON_FIELD_ERRORS`)."""


def lesson_error_words(error: str, tr: Translator) -> str:
    """A lesson file's error (`LessonError`'s English words) in `tr`'s language; as it is where
    no pattern knows it (a question's own check after `.ask.`, Python's JSON parser's words)."""
    return LESSON_ERRORS.in_language(error, tr)
