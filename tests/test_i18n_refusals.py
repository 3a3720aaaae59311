"""The stores' and judges' refusals, the receipt line, the judged tally and the gallery line and a
broken lesson file's error, said in the reader's language (issue 38): the stores keep English
(their exceptions' words, the CSV's verdicts), the panel writes them in the browser's language.
Server side, through the sessions of raw websocket clients."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from app.ask.judges import AnswerState
from app.ask.round import Refused
from app.i18n import translator
from app.main import create_server
from tests.conftest import browsers_joining, poll_until

CODE = "24681357"


@pytest.fixture
def hall(tmp_path: Path) -> Iterator[Any]:
    """The app without its loop, its data folder a temporary one, the presenter code known; (app, join)."""
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE, data_dir=tmp_path)
    with browsers_joining(running) as join:
        yield running, lambda language="en": join(language)


def _number_task(lecturer: Any, attempts: str = "1") -> Any:
    """`lecturer` presents and makes a number task (2.5 s ± 0.2, `attempts` attempts) from the Ask form."""
    lecturer.present(CODE)
    ask = lecturer.ask_panel
    ask.gui_kind.value = translator(lecturer.languages.code).gettext("Number")
    ask.gui_prompt.value = "T?"
    number = ask.forms["number"]
    number.gui_value.value, number.gui_unit.value, number.gui_tolerance.value = "2.5", "s", "0.2"
    lecturer.task_panel.gui_attempts.value = attempts
    with lecturer.lock:
        return lecturer.task_panel.make_from_form()


def _submitted(session: Any, name: str, value: float) -> tuple[Any, str]:
    """`session`'s Task folder: the name and the number typed, Submit; (the submission or None, what is said)."""
    panel = session.task_panel
    panel.gui_name.value, panel.gui_value.value = name, value
    submission = session.guard("submit", panel.submit)()
    return submission, panel.gui_note.content or panel.gui_verdict.content


def test_a_task_stores_refusals_reach_the_student_in_german_and_dutch_and_stay_english_in_the_store(hall: Any) -> None:
    app, join = hall
    lecturer, dirk, nora = join(), join("de"), join("nl")
    panel = dirk.task_panel
    assert panel.open("no code") is None
    assert panel.gui_note.content == "'no code' ist kein Aufgabencode: ein Code hat 8 Buchstaben und Ziffern, " \
                                     "etwa K7M2-QX9P."
    assert panel.open("ZZZZ-ZZZZ") is None
    assert panel.gui_note.content == "Keine Aufgabe hat den Code ZZZZ-ZZZZ: prüfe ihn mit deiner Lehrperson."
    task = _number_task(lecturer, attempts="2")
    assert panel.open(task.shown_code) is not None
    assert _submitted(dirk, "", 2.4) == (None, "Damit deine Antwort zählt, gib deinen Namen oder deine "
                                               "Matrikelnummer an.")
    kept, said = _submitted(dirk, "Dirk", 2.4)
    assert kept is not None, said
    nora.task_panel.open(task.shown_code)
    assert _submitted(nora, "Dirk", 2.5)[1] == ("Dirk beantwoordt deze opdracht al vanuit een andere browser: ga daar "
                                                "verder, of typ een bewijs van jezelf in Jouw bewijs.")
    assert _submitted(dirk, "Dirk", 2.45)[0] is not None
    again, said = _submitted(dirk, "Dirk", 2.5)
    assert again is None
    assert said == "Du hast deine 2 Versuche verbraucht: diese Aufgabe erlaubt keine weiteren.", said
    store = app.task_store
    store.clock = lambda: task.due + 60.0  # past the due time
    said = _submitted(nora, "Nora", 2.5)[1]
    assert said.startswith(f"De opdracht {task.shown_code} moest ingeleverd zijn vóór ") and "due" not in said, said
    store.clock = lambda: task.expires + 60.0  # past the time its code opens it
    assert nora.task_panel.open(task.shown_code) is None
    assert nora.task_panel.gui_note.content.startswith(f"De opdracht {task.shown_code} is verlopen op ")
    with pytest.raises(ValueError, match=r"^You have used your 2 attempts: this task allows no more\.$"):
        store.clock = lambda: task.created
        store.submit(task.code, dirk.answer_token, "Dirk", "", 0, 2.4)  # the store's words: English
    for session in (lecturer, dirk, nora):
        assert session.error_count == 0, session.last_error


def test_the_lecturers_receipt_lookup_reads_dutch(hall: Any) -> None:
    """The lecturer's `Check a receipt` line: who, question, attempt, the verdict and when, in Dutch;
    a code that is no receipt and a receipt nobody has said in Dutch too; the store keeps the English verdict."""
    app, join = hall
    lecturer, dirk = join("nl"), join("de")
    task = _number_task(lecturer)
    dirk.task_panel.open(task.shown_code)
    kept, said = _submitted(dirk, "Dirk", 2.4)
    assert kept is not None and kept.words == "2.4 s: right", said
    lecturer.stop_presenting()
    table = lecturer.task_panel
    assert table.open_as_lecturer(task.shown_code, CODE) is not None, table.gui_note.content
    line = table.check_receipt(kept.receipt)
    assert line.startswith(f"Bewijs **{kept.receipt[:4]}-{kept.receipt[4:]}**: Dirk, vraag 1, poging 1: "
                           f"{translator('nl').gettext('{mine}: right').format(mine='2.4 s')} · ingeleverd "), line
    assert "Receipt" not in line and "question" not in line and "right" not in line
    assert table.check_receipt("no code") == "Dat is geen bewijscode: een code is 8 letters en cijfers."
    assert table.check_receipt("ZZZZ-ZZZZ") == "Geen inzending heeft het bewijs ZZZZ-ZZZZ."
    assert table.gui_receipt_note.content == "Geen inzending heeft het bewijs ZZZZ-ZZZZ."
    assert lecturer.error_count == 0 and dirk.error_count == 0, (lecturer.last_error, dirk.last_error)


def test_a_share_code_that_opens_nothing_is_said_in_german(hall: Any) -> None:
    _app, join = hall
    german = join("de")
    share = german.share
    assert share.open("abc") is None
    assert share.gui_note.content == "'abc' ist kein Teilcode: ein Code hat 8 Buchstaben und Ziffern, etwa K7M2-QX9P."
    assert share.open("ZZZZ-ZZZZ") is None
    assert share.gui_note.content.startswith("Kein geteilter Moment hat den Code ZZZZ-ZZZZ: prüfe ihn")
    assert "shared moment" not in share.gui_note.content and german.error_count == 0, german.last_error


def _state_round(app: Any, lecturer: Any, students: list[Any]) -> None:
    """`lecturer` presents the heavy top and asks for a state the top_motion judge judges."""
    lecturer.select_scene("Heavy top")
    lecturer.present(CODE)
    poll_until(lambda: (app.frame(1 / 60), all(s.mode.name == "FOLLOWING" for s in students))[1], timeout=10.0,
               what="every student following", seen=lambda: [s.mode for s in students])
    lecturer.ask({"kind": "state", "prompt": "?", "scene": "Heavy top", "judge": "top_motion"})
    poll_until(lambda: (app.frame(1 / 60), all(s.question.folder.visible for s in students))[1], timeout=10.0,
               what="the question shown to every student")


def test_the_presenters_judged_tally_and_gallery_line_read_german(hall: Any) -> None:
    """A German presenter's histogram of judged classes and the gallery's line name the class in
    German; the round (and its CSV) keeps the English class."""
    app, join = hall
    lecturer, student = join("de"), join()
    _state_round(app, lecturer, [student])
    student.answer_from_copy()
    student.answer(student.state_answer())
    judged = app.rounds.current.answer_of(student.answer_token).judged
    assert judged is not None and isinstance(judged.value, str), judged
    german = translator("de").gettext(judged.value)
    assert german != judged.value
    panel = lecturer.ask_panel
    panel.refresh()
    histogram = panel.gui_histogram.content
    assert histogram.startswith(f"{german} `") and f"{judged.value} `" not in histogram, histogram
    panel.gallery.next()
    panel.gallery_panel.refresh()
    assert panel.gallery_panel.line.content == f"Antwort 1 von 1: {german}", panel.gallery_panel.line.content
    assert f",{judged.value}," in app.rounds.csv()  # the CSV's judged column: the English class, as kept
    assert lecturer.error_count == 0 and student.error_count == 0, (lecturer.last_error, student.last_error)


def test_a_judges_refusal_of_a_students_body_reads_dutch(hall: Any) -> None:
    """A Dutch student sends a free body to a heavy top's judged question: the judge's refusal
    in Dutch, the scenes' titles translated; nothing is kept."""
    app, join = hall
    lecturer, student = join(), join("nl")
    _state_round(app, lecturer, [student])
    body = AnswerState("Free body", np.eye(3), np.array([0.0, 0.0, 3.0]), (1.0, 2.0, 3.0), 0.0).to_dict()
    with pytest.raises(Refused) as refused:
        student.question.send(body)
    assert str(refused.value) == ("geen antwoord: deze vraag gaat over de scène Zware tol; het antwoord is een "
                                  "lichaam uit Vrij lichaam"), str(refused.value)
    assert app.rounds.current.answer_of(student.answer_token) is None
    assert lecturer.error_count == 0, lecturer.last_error


def test_a_broken_lesson_file_imported_is_said_in_german_naming_its_file_and_field(hall: Any) -> None:
    from viser._gui_handles import UploadedFile

    _app, join = hall
    german = join("de")
    mine = german.own_panel
    broken = {"title": "Kaputt", "steps": [{"scene": "Heavy top", "preset": "Nope", "text": "t"}]}
    for name, content, said in (
            ("kaputt.json", json.dumps(broken).encode(), "**⚠ kaputt.json: steps[0].preset: Heavy top hat keine "
                                                         "Voreinstellung 'Nope' ("),
            ("leer.json", json.dumps({"title": "Leer"}).encode(), "**⚠ leer.json: steps: fehlt oder ist leer**"),
            ("liste.json", json.dumps({"title": "L", "steps": [3]}).encode(),
             "**⚠ liste.json: steps[0]: kein Objekt**"),
    ):
        mine.gui_import._impl.value = UploadedFile(name, content)
        german.guard("import lesson", lambda: mine._said(mine.import_uploaded))()
        assert mine.gui_status.content.startswith(said), mine.gui_status.content
        assert "has no preset" not in mine.gui_status.content and "missing" not in mine.gui_status.content
    assert german.error_count == 0, german.last_error


@pytest.mark.parametrize("language", ["nl", "de"])
def test_every_judge_and_lesson_file_pattern_matches_its_english_and_has_a_translation(language: str) -> None:
    """Each entry of the judges' refusals and of a lesson file's faults matches the English its
    msgid writes, and the language writes it otherwise."""
    from app.ask.verdict_words import JUDGE_REFUSALS
    from app.lesson_errors import LESSON_FIELD_ERRORS

    class Sample(dict[str, str]):
        def __missing__(self, name: str) -> str:
            samples = {"where": "steps[0].camera", "preset": "'Spin'", "rate": "1000", "type": "int",
                       "most": "80", "count": "81", "least": "2", "last": "1", "number": "1e+13", "lo": "0.1",
                       "hi": "179", "kind": "choice", "judge": "attitude", "key": "within_deg",
                       "example": '{"angles_deg": [φ, θ, ψ]}'}
            return samples.get(name, "Heavy top")

    tr = translator(language)
    for table in (JUDGE_REFUSALS, LESSON_FIELD_ERRORS):
        for pattern, msgid in table.entries:
            english = msgid.format_map(Sample())
            assert pattern.fullmatch(english), msgid
            assert table.in_language(english, tr) != english, msgid
