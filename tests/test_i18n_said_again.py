"""A message on a browser's screen is said again in the language the browser changes to.

What a panel says (the error line's refusal, the message line under the scene's panel, the
Mine folder's status line, the Lecture folder's note on a refused code) is kept as data (a
`Refusal`, an `app.i18n.Said`, an English sentence and its `Phrases`), not as the words first
written: choosing another language in the Language dropdown writes it again in that language,
and the next message comes in it too.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import browsers_joining

from app.main import create_server

CODE = "24681357"


@pytest.fixture
def session(tmp_path: Path) -> Iterator[Any]:
    """One English browser's session on the app without its loop (its data folder a temporary one)."""
    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE, data_dir=tmp_path)
    with browsers_joining(app) as join:
        yield join()


def test_a_refusal_on_the_error_line_is_said_again_in_the_new_language(session: Any) -> None:
    session.present(CODE)
    panel = session.ask_panel
    panel.gui_prompt.value = "Which?"
    panel.gui_options.value = "a | b"
    panel.gui_correct.value = "3"
    session.guard("ask the class", panel.ask_from_form)()
    shown = session.errors.gui_error.content
    assert shown.startswith("**⚠ Not accepted**") and "option 3 is not one of the 2 options" in shown, shown
    session.languages.choose("de")
    shown = session.errors.gui_error.content
    assert shown.startswith("**⚠ Nicht angenommen**"), shown
    assert "Option 3 ist keine der 2 Optionen" in shown and "not one of" not in shown, shown


def test_the_message_under_the_scene_panel_is_said_again_in_the_new_language(session: Any) -> None:
    session.guard("test", session.scene.choose_preset)("nope")
    assert session.scene.message.text == "**⚠ No preset named 'nope'.**"
    session.languages.choose("de")  # the scene's panel is built again in German: the message goes on in it
    assert session.scene.message.text == "**⚠ Keine Voreinstellung namens 'nope'.**", session.scene.message.text
    session.room.notify("The simulation stopped: non-finite state")  # the room's words (English), said in German
    assert session.scene.message.text.startswith("**⚠ Die Simulation wurde angehalten: non-finite state")
    session.languages.choose("nl")
    assert session.scene.message.text == "**⚠ De simulatie is gestopt: non-finite state**", session.scene.message.text
    assert session.error_count == 0, session.last_error


def test_the_mine_folders_status_is_said_again_in_the_new_language(session: Any) -> None:
    panel = session.own_panel
    panel.gui_lesson_title.value = "nope"
    session.guard("export lesson", lambda: panel._said(panel.export_lesson))()
    assert panel.gui_status.content == "**⚠ no lesson of yours named 'nope'**", panel.gui_status.content
    session.languages.choose("de")
    assert panel.gui_status.content == "**⚠ keine eigene Lektion namens 'nope'**", panel.gui_status.content


def test_a_refused_code_is_said_again_in_the_new_language(session: Any) -> None:
    session.present("11111111")
    note = session.lecture.gui_note
    assert note.visible and note.content.startswith("**⚠ Wrong presenter code ("), note.content
    session.languages.choose("de")
    assert note.visible and note.content.startswith("**⚠ Falscher Vortragscode (noch "), note.content
