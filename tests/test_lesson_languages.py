"""Lessons in several languages (issue 38): a lesson's texts (title, step text, a question's
prompt and options) are a string (English) or a mapping {"en": ..., "nl": ..., "de": ...},
checked at start; a browser reads the lesson in its language (English where the lesson lacks
it); a follower reads the presenter's step and caption in its own; every shipped lesson has all
three languages."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from conftest import poll_until
from test_i18n import hall  # noqa: F401 - the fixture: the app without its loop, and its sessions

from app.data import files_in
from app.i18n import LANGUAGES
from app.lessons import LESSONS_DIR, LessonError, lessons, load_lesson
from app.scenes import SCENES

EULER = "§1 Euler angles and ω"
FREE_BODY = "§6 The free body and the heavy top"


def _lesson(tmp_path: Path, data: dict[str, Any]) -> Path:
    path = tmp_path / "lesson.json"
    path.write_text(json.dumps(data, ensure_ascii=False), encoding="utf-8")
    return path


def _two_steps() -> dict[str, Any]:
    return {"title": {"en": "Nodes", "nl": "Knopen", "de": "Knoten"},
            "steps": [{"scene": "Euler angles", "text": {"en": "the line of nodes", "nl": "de knooplijn"}},
                      {"scene": "Free body", "text": "plain English",
                       "ask": {"kind": "choice", "prompt": {"en": "Which?", "de": "Welche?"},
                               "options": [{"en": "a", "nl": "een", "de": "ein"}, "b"], "correct": 0}}]}


def test_a_lesson_with_texts_in_several_languages_loads_and_falls_back_to_english(tmp_path: Path) -> None:
    lesson = load_lesson(_lesson(tmp_path, _two_steps()), SCENES)
    assert lesson.title == "Nodes" and lesson.title_in("de") == "Knoten"
    first, second = lesson.steps
    assert first.text == "the line of nodes" and first.text_in("nl") == "de knooplijn"
    assert first.text_in("de") == "the line of nodes"  # the lesson lacks German: English
    assert second.text_in("nl") == "plain English"
    assert second.ask is not None and second.ask.prompt == "Which?"
    german, dutch = second.ask_in("de"), second.ask_in("nl")
    assert german is not None and german.prompt == "Welche?" and german.options == ("ein", "b")  # type: ignore[union-attr]
    assert dutch is not None and dutch.prompt == "Which?" and dutch.options == ("een", "b")  # type: ignore[union-attr]


@pytest.mark.parametrize(("edit", "message"), [
    (lambda d: d["steps"][0].update(text={"nl": "de knooplijn"}), r"steps\[0\]\.text: the English text .* missing"),
    (lambda d: d["steps"][0].update(text={"en": "x", "fr": "la ligne"}), r"steps\[0\]\.text: unknown language 'fr'"),
    (lambda d: d["steps"][0].update(text={"en": "x", "de": 3}), r"steps\[0\]\.text\.de: a text wanted, got 3"),
    (lambda d: d["steps"][0].update(text={"en": "x", "nl": " "}), r"steps\[0\]\.text\.nl: a text wanted"),
    (lambda d: d["steps"][0].update(text=["x"]), r"steps\[0\]\.text: a text or a mapping of languages"),
    (lambda d: d.update(title={"de": "Knoten"}), r"title: the English text .* missing"),
    (lambda d: d.update(title={"en": "Nodes", "NL": "Knopen"}), r"title: unknown language 'NL'"),
    (lambda d: d["steps"][1]["ask"].update(prompt={"en": "Which?", "de": None}),
     r"steps\[1\]\.ask\.prompt\.de: a text wanted, got None"),
    (lambda d: d["steps"][1]["ask"]["options"].append({"nl": "c"}),
     r"steps\[1\]\.ask\.options\[2\]: the English text .* missing"),
])
def test_a_broken_translation_is_refused_naming_the_lesson_the_step_and_the_field(tmp_path: Path, edit,
                                                                                 message: str) -> None:
    data = _two_steps()
    edit(data)
    path = _lesson(tmp_path, data)
    with pytest.raises(LessonError, match=str(path).replace(".", r"\.") + ": " + message):
        load_lesson(path, SCENES)


def _texts(data: dict[str, Any]) -> list[tuple[str, Any]]:
    """(where, value) of every text a person reads in a lesson file's data."""
    found = [("title", data["title"])]
    for k, step in enumerate(data["steps"]):
        found.append((f"steps[{k}].text", step["text"]))
        ask = step.get("ask") or {}
        if "prompt" in ask:
            found.append((f"steps[{k}].ask.prompt", ask["prompt"]))
        found += [(f"steps[{k}].ask.options[{j}]", o) for j, o in enumerate(ask.get("options", ()))]
    return found


def test_every_shipped_lesson_has_every_text_in_english_dutch_and_german() -> None:
    paths = list(files_in(LESSONS_DIR, ".json"))
    assert len(paths) >= 9
    missing = [f"{path.name}: {where}: {sorted(set(LANGUAGES) - set(value) if isinstance(value, dict) else LANGUAGES)}"
               for path in paths for where, value in _texts(json.loads(path.read_text(encoding="utf-8")))
               if not isinstance(value, dict) or set(value) != set(LANGUAGES)]
    assert not missing, "texts lacking a language:\n" + "\n".join(missing)
    same = [f"{path.name}: {where}" for path in paths for where, value in _texts(json.loads(path.read_text("utf-8")))
            if len(value["en"]) > 12 and (value["nl"] == value["en"] or value["de"] == value["en"])]
    assert not same, "texts left in English:\n" + "\n".join(same)


def test_a_dutch_browser_reads_a_shipped_lesson_in_dutch_and_a_german_one_in_german(hall: Any) -> None:  # noqa: F811
    _app, join = hall
    dutch, english = join(), join()
    dutch.set_language("nl")
    assert "§1 Eulerhoeken en ω" in dutch.gui_lesson.options and EULER in english.gui_lesson.options
    dutch.gui_lesson.value = "§1 Eulerhoeken en ω"  # the dropdown, in Dutch: runs its first step
    dutch.next_step(1)
    lesson = lessons()[0]
    assert lesson.title == EULER and dutch.lesson is lesson and dutch.lesson_step == 1
    text = dutch.gui_lesson_text.content
    assert "knooplijn" in text and "stap 2/5" in text and "line of nodes" not in text, text
    runner = dutch.lesson_runner
    assert runner.caption.head == "§1 Eulerhoeken en ω · stap 2 van 5" and "knooplijn" in runner.caption.text
    dutch.set_language("de")  # the same step, now in German
    assert dutch.error_count == 0, dutch.last_error
    assert dutch.lesson is lesson and dutch.lesson_step == 1 and dutch.gui_lesson.value == "§1 Euler-Winkel und ω"
    assert "Knotenlinie" in dutch.gui_lesson_text.content and "Schritt 2/5" in dutch.gui_lesson_text.content
    english.start_lesson(EULER)
    assert english.gui_lesson_text.content.startswith(f"**{EULER}**, step 1/5: A rotation is one turn")


def test_a_dutch_follower_reads_an_english_presenters_lesson_step_in_dutch(hall: Any) -> None:  # noqa: F811
    app, join = hall
    lecturer, dutch, german = join(), join(), join()
    dutch.set_language("nl")
    german.set_language("de")
    lecturer.present(app.lectern.code)
    poll_until(lambda: (app.frame(1 / 60), dutch.mode.name == german.mode.name == "FOLLOWING")[1], timeout=10.0)
    lecturer.start_lesson(FREE_BODY)
    lecturer.next_step(1)  # a symmetric body: Feynman's wobbling plate
    app.frame(1 / 60)
    assert "Feynman's wobbling plate" in lecturer.gui_lesson_text.content
    status = dutch.scene.gui_status.content
    assert "het wiebelende bord van Feynman" in status and "stap 2/" in status, status
    assert "wobbling plate" not in status
    assert "Feynmans taumelnder Teller" in german.scene.gui_status.content
    caption = dutch.scene.caption
    assert caption.head.startswith("§6 Het vrije lichaam en de zware tol · stap 2 van") and \
        "wiebelende bord" in caption.text, (caption.head, caption.text)
    dutch.set_language("de")  # while following: the step in the new language
    assert "Feynmans taumelnder Teller" in dutch.scene.gui_status.content
    assert "taumelnder Teller" in dutch.scene.caption.text
    assert lecturer.error_count == dutch.error_count == german.error_count == 0


def test_a_dutch_presenters_question_from_the_lesson_is_in_dutch_and_the_follower_unknown_words_stay() -> None:
    from app.lessons import in_language  # noqa: PLC0415 - new with the languages: the other tests run without it

    lesson = next(lesson for lesson in lessons() if lesson.title == FREE_BODY)
    step = lesson.steps[2]
    dutch = step.ask_in("nl")
    assert dutch is not None and dutch.prompt.startswith("Het boek wordt om zijn middelste as")
    assert in_language(step.text, "de").startswith("Um die mittlere Achse angedreht")
    assert in_language("words of no lesson", "nl") == "words of no lesson"
