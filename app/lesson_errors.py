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

__all__ = ["LESSON_ERRORS", "LESSON_FIELD_ERRORS", "QUESTION_FIELD_ERRORS", "lesson_error_words"]

_WHERE = r"(?P<where>[A-Za-z_][\w\[\].]*)"  # a field's path in the lesson's JSON: steps[2].camera.position

_FILE_ENTRIES = (
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

_N = r"[-+0-9.e]+|inf|nan"  # a number as Python's :g writes it

_QUESTION_ENTRIES = (  # after `steps[k].ask`: `app.ask.question_from_dict`'s and the judges' words
    (rf"{_WHERE}: the question's words are missing", N_("{where}: the question's words are missing")),
    (rf"{_WHERE}: at most (?P<most>[0-9]+) characters \(got (?P<count>[0-9]+)\)",
     N_("{where}: at most {most} characters (got {count})")),
    (rf"{_WHERE}: at most (?P<most>[0-9]+) characters", N_("{where}: at most {most} characters")),
    (rf"{_WHERE}: a list of 2 to 6 texts wanted", N_("{where}: a list of 2 to 6 texts wanted")),
    (rf"{_WHERE}: (?P<least>[0-9]+) to (?P<most>[0-9]+) options wanted \(got (?P<count>[0-9]+)\)",
     N_("{where}: {least} to {most} options wanted (got {count})")),
    (rf"{_WHERE}: a text wanted", N_("{where}: a text wanted")),
    (rf"{_WHERE}: two options are the same", N_("{where}: two options are the same")),
    (rf"{_WHERE}: an option's index 0\.\.(?P<last>-?[0-9]+) or none, got (?P<value>.+)",
     N_("{where}: an option's index 0..{last} or none, got {value}")),
    (rf"{_WHERE}: a number wanted, got (?P<value>.+)", N_("{where}: a number wanted, got {value}")),
    (rf"{_WHERE}: a number of size at most (?P<most>{_N}) wanted, got a huge one",
     N_("{where}: a number of size at most {most} wanted, got a huge one")),
    (rf"{_WHERE}: a number of size at most (?P<most>{_N}) wanted, got (?P<number>{_N})",
     N_("{where}: a number of size at most {most} wanted, got {number}")),
    (rf"{_WHERE}: a finite number wanted, got (?P<value>.+)", N_("{where}: a finite number wanted, got {value}")),
    (rf"{_WHERE}: three numbers wanted, got (?P<value>.+)", N_("{where}: three numbers wanted, got {value}")),
    (rf"{_WHERE}: a direction needs a nonzero vector", N_("{where}: a direction needs a nonzero vector")),
    (rf"{_WHERE}: one of (?P<choices>.+) wanted, got (?P<value>.+)",
     N_("{where}: one of {choices} wanted, got {value}")),
    (rf"{_WHERE}: a scene's title wanted", N_("{where}: a scene's title wanted")),
    (rf"{_WHERE}: (?P<judge>.+) is not a judge \((?P<judges>.+)\)",
     N_("{where}: {judge} is not a judge ({judges})")),
    (rf"{_WHERE}: a small object wanted", N_("{where}: a small object wanted")),
    (rf"{_WHERE}: a text of at most (?P<most>[0-9]+) characters wanted, got (?P<value>.+)",
     N_("{where}: a text of at most {most} characters wanted, got {value}")),
    (rf"{_WHERE}: zero or more wanted, got (?P<number>{_N})", N_("{where}: zero or more wanted, got {number}")),
    (rf"{_WHERE}: a question is an object with a kind, got (?P<value>.+)",
     N_("{where}: a question is an object with a kind, got {value}")),
    (rf"{_WHERE}: not a field of a (?P<kind>\w+) question \((?P<fields>.+)\)",
     N_("{where}: not a field of a {kind} question ({fields})")),
    (rf"{_WHERE}: an object wanted", N_("{where}: an object wanted")),
    (rf"{_WHERE}: (?P<key>.+) is not a field of the (?P<judge>\w+) judge \((?P<keys>.+)\)",
     N_("{where}: {key} is not a field of the {judge} judge ({keys})")),
    (rf"{_WHERE}: the target's (?P<key>\w+) must be a number in \[(?P<lo>{_N}), (?P<hi>{_N})\], got (?P<value>.+)",
     N_("{where}: the target's {key} must be a number in [{lo}, {hi}], got {value}")),
    (rf"{_WHERE}: the attitude judge needs a target: (?P<example>\{{.*\}})",
     N_("{where}: the attitude judge needs a target: {example}")),
    (rf"{_WHERE}: the target's angles_deg must be 3 numbers \[deg\]",
     N_("{where}: the target's angles_deg must be 3 numbers [deg]")),
    (rf"{_WHERE}: the target's angles_deg must be finite", N_("{where}: the target's angles_deg must be finite")),
    (rf"{_WHERE}: the attitude judge's target gives angles_deg \[φ, θ, ψ\] or R_space_body",
     N_("{where}: the attitude judge's target gives angles_deg [φ, θ, ψ] or R_space_body")),
    (rf"{_WHERE}: motion must be one of (?P<motions>.+), got (?P<value>.+)",
     N_("{where}: motion must be one of {motions}, got {value}")),
    (rf"{_WHERE}: axis must be 0, 1 or 2 \(x′, y′, z′\), got (?P<value>.+)",
     N_("{where}: axis must be 0, 1 or 2 (x′, y′, z′), got {value}")),
    (rf"{_WHERE}: stays must be true or false", N_("{where}: stays must be true or false")),
)

LESSON_FIELD_ERRORS = Phrases(*_FILE_ENTRIES, *_QUESTION_ENTRIES, numbers=("most", "number", "lo", "hi"))
"""What `app.lessons` says is wrong with a field (after the file's name), matched in English: the
file's own faults, then a step's `ask` (`app.ask.question_from_dict`'s words and a State question's
judge's about its `target`, `app.ask.judges.check_target`, after `steps[k].ask`).  The values the
file must hold (kinds, judges, fields, motions) stay as they are; a number the app wrote (a limit)
takes the language's decimal sign."""

QUESTION_FIELD_ERRORS = Phrases(*_QUESTION_ENTRIES, numbers=("most", "number", "lo", "hi"))
"""A lesson step's `ask` faults alone (`LESSON_FIELD_ERRORS` holds them too)."""

LESSON_ERRORS = Phrases(
    (r"(?P<file>[^:]+): (?P<error>.+)", "{file}: {error}"),
    nested={"error": LESSON_FIELD_ERRORS},
)
"""A lesson file's error: its file's name, then the field's (`LESSON_FIELD_ERRORS`)."""


def lesson_error_words(error: str, tr: Translator) -> str:
    """A lesson file's error (`LessonError`'s English words) in `tr`'s language; as it is where
    no pattern knows it (a question's own check after `.ask.`, Python's JSON parser's words)."""
    return LESSON_ERRORS.in_language(error, tr)
