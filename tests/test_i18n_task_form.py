"""The lecturer's task parts in the browser's language (issue 38): the `3D view` dropdown of a
task opened as lecturer (its options written in German or Dutch, the question an option means
still known) and the `Make a task` form's checks (what a form filled wrongly says under the
button).  Server side, through the sessions of raw websocket clients."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from app.i18n import translator
from app.main import create_server
from tests.conftest import RawClient, browsers_joining, poll_until

CODE = "24681357"
DEADLINE_S = 30.0  # a busy machine
ENGLISH_VIEWS = ("none", "sphere of tips", "gallery")


@pytest.fixture
def hall(tmp_path: Path) -> Iterator[Any]:
    """The app without its loop, its data folder a temporary one, the presenter code known; (app, join)."""
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE, data_dir=tmp_path)
    with browsers_joining(running, timeout=DEADLINE_S) as join:
        def join_with_client(language: str = "en") -> tuple[RawClient, Any]:
            session = join(language)
            return join.clients[-1], session

        yield running, join_with_client


def _views_task(app: Any) -> Any:
    """A task of three questions: a direction (Q1), a number (Q2, no 3D view) and a state (Q3)."""
    questions = [{"kind": "direction", "prompt": "Where does L point?", "truth": [0, 0, 1]},
                 {"kind": "number", "prompt": "T?", "value": 2.5, "unit": "s", "tolerance": 0.2},
                 {"kind": "state", "prompt": "Make it flip.", "scene": "Free body"}]
    return app.task_store.create(questions, due=app.task_store.clock() + 3600.0)


def test_the_3d_view_dropdown_speaks_the_lecturers_language_and_keeps_the_question_chosen(hall: Any) -> None:
    """A German lecturer's `3D view` reads "Q1 · <sphere of tips in German>", a choice made through
    the browser shows that question's view; Dutch keeps the question chosen, written in Dutch;
    English again reads as it always did."""
    app, join = hall
    client, lecturer = join("de")
    task = _views_task(app)
    panel = lecturer.task_panel
    assert panel.open_as_lecturer(task.shown_code, CODE) is not None, panel.gui_note.content
    views = panel.views
    de, nl = translator("de"), translator("nl")
    sphere_de, gallery_de = de.gettext("sphere of tips"), de.gettext("gallery")
    assert sphere_de != "sphere of tips" and gallery_de != "gallery", "the German catalog lacks the views' words"
    assert tuple(views.gui_view.options) == (de.gettext("none"), f"Q1 · {sphere_de}", f"Q3 · {gallery_de}")
    assert views.gui_view.value == f"Q1 · {sphere_de}" and views.chosen() == 0
    assert views.sphere.handles[0].visible  # the first direction question's sphere, shown at once
    words = " ".join(views.gui_view.options)
    assert not any(re.search(rf"\b{english}\b", words) for english in ENGLISH_VIEWS), words

    client.set_value(views.gui_view, f"Q3 · {gallery_de}")  # chosen through the browser
    poll_until(lambda: views.gallery_panel.folder.visible and views.chosen() == 2, timeout=DEADLINE_S,
               what="the gallery of Q3 chosen in German", seen=lambda: (views.gui_view.value, views.chosen()))
    assert not views.sphere.handles[0].visible

    lecturer.set_language("nl")
    assert tuple(views.gui_view.options) == (nl.gettext("none"), f"Q1 · {nl.gettext('sphere of tips')}",
                                             f"Q3 · {nl.gettext('gallery')}")
    assert views.gui_view.value == f"Q3 · {nl.gettext('gallery')}" and views.chosen() == 2
    assert views.gallery_panel.folder.visible
    panel.refresh_table()  # the table polled again: the Dutch option stays chosen
    assert views.gui_view.value == f"Q3 · {nl.gettext('gallery')}" and views.chosen() == 2

    client.set_value(views.gui_view, nl.gettext("none"))
    poll_until(lambda: views.chosen() is None and not views.gallery_panel.folder.visible, timeout=DEADLINE_S,
               what="nothing shown by the Dutch none", seen=lambda: views.gui_view.value)
    lecturer.set_language("en")
    assert tuple(views.gui_view.options) == ("none", "Q1 · sphere of tips", "Q3 · gallery")
    assert views.gui_view.value == "none"
    assert lecturer.error_count == 0, lecturer.last_error


def _presenting_form(session: Any, language: str) -> Any:
    """`session` presents, the Ask form filled with a good number question; its task panel."""
    session.present(CODE)
    tr = translator(language)
    ask = session.ask_panel
    ask.gui_kind.value = tr.gettext("Number")
    ask.gui_prompt.value = "T?"
    number = ask.forms["number"]
    number.gui_value.value, number.gui_unit.value, number.gui_tolerance.value = "2.5", "s", "0.2"
    return session.task_panel


def _refused(session: Any, act: Any) -> str:
    """`act` (Make a task, Add to the worksheet) refused, nothing made; what is said under the button."""
    panel = session.task_panel
    made, worksheet = panel.made, list(panel.worksheet)
    with session.lock:
        assert act() is None
    assert panel.made is made and panel.worksheet == worksheet
    assert panel.gui_made.visible
    return str(panel.gui_made.content)


@pytest.mark.parametrize("language", ["de", "nl"])
def test_the_make_a_task_forms_checks_are_said_in_the_lecturers_language(hall: Any, language: str) -> None:
    """A due time out of range, words too long and a question without words are said under
    `Make a task` in German or Dutch, the field named as the form names it; nothing is made and
    nothing goes to the error line; the English panel says them in English."""
    app, join = hall
    _client, lecturer = join(language)
    tr = translator(language)
    panel = _presenting_form(lecturer, language)
    panel.gui_due.value = 0.0
    said = _refused(lecturer, panel.make_from_form)
    assert said == tr.gettext("{where}: a number of hours, more than 0 and at most {most}").format(
        where=tr.gettext("Due in [h]"), most=9600), said
    assert tr.gettext("Due in [h]") in said and "number of hours" not in said, said
    panel.gui_due.value = 24.0
    panel.gui_words.value = "w" * 2500
    said = _refused(lecturer, panel.make_from_form)
    assert said == tr.gettext("{where}: at most {most} characters, got {count}").format(
        where=tr.gettext("Words for the task"), most=2000, count=2500), said
    assert "characters" not in said and "Words" not in said, said
    panel.gui_words.value = ""
    lecturer.ask_panel.gui_prompt.value = ""
    said = _refused(lecturer, panel.add_to_worksheet)
    assert said == tr.gettext("{where}: the question's words are missing").format(
        where=tr.gettext("Question")), said
    assert "missing" not in said, said
    lecturer.ask_panel.gui_prompt.value = "T?"
    panel.gui_attempts.value = "many"  # a hostile page sends anything
    said = _refused(lecturer, panel.make_from_form)
    assert said == tr.gettext("{where}: choose one of the options").format(where=tr.gettext("Attempts")), said
    panel.gui_attempts.value = "2"
    with lecturer.lock:
        task = panel.make_from_form()  # filled right: made
    assert task is not None and app.task_store.task(task.code) == task
    assert lecturer.error_count == 0, lecturer.last_error

    lecturer.set_language("en")
    panel.gui_due.value = 1e6
    assert _refused(lecturer, panel.make_from_form) == "Due in [h]: a number of hours, more than 0 and at most 9600"
