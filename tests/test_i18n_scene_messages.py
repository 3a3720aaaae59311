"""A scene's message is said again in the language the browser changes to.

The Inertia scene's refused mesh (a physics refusal inside the scene's sentence), the Moving
frame's refused choice and the note on an inexact copy of a lecture's room are kept as data (an
`app.i18n.Said`, a function of a translator, an English sentence matched by
`app.kit.run_words.RUN_MESSAGES`), not as the words first written: choosing German in the
Language dropdown writes them again in German.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import browsers_joining

from app.i18n import translator
from app.kit.run_words import RUN_MESSAGES
from app.main import create_server


@pytest.fixture
def session(tmp_path: Path) -> Iterator[Any]:
    """One English browser's session on the app without its loop (its data folder a temporary one)."""
    with browsers_joining(create_server("127.0.0.1", 0, verbose=False, start_loop=False, data_dir=tmp_path)) as join:
        yield join()


def test_a_refused_mesh_is_said_again_in_the_new_language(session: Any) -> None:
    session.select_scene("Inertia")
    session.guard("mesh", session.scene.mesh_panel.load_mesh)("junk.obj", b"this is no mesh")
    shown = session.scene.message.text
    assert shown.startswith("**⚠ Mesh refused: junk.obj") and shown.endswith("The last valid body stays.**"), shown
    session.languages.choose("de")
    shown = session.scene.message.text
    assert shown.startswith("**⚠ Netz abgelehnt: junk.obj"), shown
    assert shown.endswith("Der letzte gültige Körper bleibt.**") and "Mesh refused" not in shown, shown
    assert session.error_count == 0, session.last_error


def test_a_refused_choice_in_the_moving_frame_is_said_again_in_the_new_language(session: Any) -> None:
    session.select_scene("Moving frame")
    view = session.scene
    view.quiet.write(view.gui_forces_on, "nobody")  # as a client could send it; the callback runs below
    session.guard("forces on", view._forces_on_chosen)(None)
    assert session.scene.message.text.startswith("**⚠ Forces on 'nobody' refused: choose one of "), \
        session.scene.message.text
    session.languages.choose("de")
    shown = session.scene.message.text
    assert shown.startswith("**⚠ Kräfte auf 'nobody' abgelehnt: wähle eines von "), shown


def test_the_note_on_a_copied_room_is_said_again_in_the_new_language(session: Any) -> None:
    note = ("The presenter's worker is gone: this is the last state of its room that this server saw "
            "(t = 3.25 s), paused.")
    session.scene.show_message(note)  # as OwnRoom.open_last_lecture shows the copy's note
    assert session.scene.message.text == f"**⚠ {note}**", session.scene.message.text
    session.languages.choose("de")
    german = RUN_MESSAGES.in_language(note, translator("de"))
    assert "3,25" in german, german  # the sentence is matched: its number written the German way at least
    assert session.scene.message.text == f"**⚠ {german}**", session.scene.message.text
