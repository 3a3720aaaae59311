"""Every "not allowed" refusal of the app is a msgid (issue 38): raised as `app.refusals.NotAllowed`
(still a PermissionError, `str()` English for logs and tests) and said in the error line in the
browser's language.

No bare `raise PermissionError(...)` is left in app/ (an AST scan; the one exception says why).
The msgid path is checked with a translator that marks every word it writes (`«msgid»`), so
these pass with any catalog."""

from __future__ import annotations

import ast
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import app.roles.language as language_role
from app.i18n import N_, Said
from app.main import create_server
from app.refusals import NotAllowed
from app.scenes import SCENES
from tests.conftest import browsers_joining, poll_until
from tests.test_i18n_last_english import MARKED

CODE = "24681357"
APP_DIR = Path(__file__).resolve().parents[1] / "app"

BARE_ALLOWED = {
    ("hall/own_panel.py", "_allowed"):
        "raises `may_save`'s English reason, caught by `OwnPanel._said` and said through OWN_REFUSALS",
}
"""(file under app/, function) -> why a bare PermissionError raised there is said in the reader's language."""


def _bare_permission_errors() -> list[tuple[str, str, int]]:
    """(file under app/, enclosing function, line) of each `raise PermissionError(...)` in app/."""
    found: list[tuple[str, str, int]] = []
    for path in sorted(APP_DIR.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for function in ast.walk(tree):
            if not isinstance(function, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            for node in ast.walk(function):
                if (isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call)
                        and isinstance(node.exc.func, ast.Name) and node.exc.func.id == "PermissionError"):
                    found.append((path.relative_to(APP_DIR).as_posix(), function.name, node.lineno))
    return found


def test_no_bare_permission_error_is_raised_in_the_app() -> None:
    bare = _bare_permission_errors()
    left = [(file, name, line) for file, name, line in bare if (file, name) not in BARE_ALLOWED]
    assert not left, f"PermissionErrors with English words only (raise NotAllowed(N_(...)) instead): {left}"
    assert {(file, name) for file, name, _line in bare} == set(BARE_ALLOWED), "an exception no longer needed"


@pytest.fixture
def hall() -> Iterator[Any]:
    """The app without its loop, the presenter code known; (app, join): join(language) opens a browser."""
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE)
    with browsers_joining(running) as join:
        yield running, lambda language="en": join(language)


def _marked_error_line(session: Any) -> str:
    shown = str(session.errors.gui_error.content)
    assert "PermissionError" not in shown and "NotAllowed" not in shown, shown
    return shown


def test_closing_a_round_without_presenting_is_refused_through_gettext(
        hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    app, join = hall
    student = join("en")
    with pytest.raises(PermissionError) as refused:
        student.close_round()
    assert isinstance(refused.value, NotAllowed)
    assert str(refused.value) == "only the presenter can close the round"  # English for logs
    monkeypatch.setattr(language_role, "translator", lambda _code: MARKED)
    student.set_language("de")
    student.guard("close the round", student.close_round)()
    assert "«only the presenter can close the round»" in _marked_error_line(student)
    assert app.lectern.rounds.current is None


def test_a_follower_choosing_a_scene_is_refused_through_gettext(hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    _app, join = hall
    presenter, student = join("en"), join("en")
    presenter.present(CODE)
    student.follow()
    poll_until(lambda: student.mode == "following", timeout=20.0, what="the student following",
               seen=lambda: student.mode)
    words = "this browser follows the presenter: press 'Explore on my own' first"
    with pytest.raises(PermissionError, match="Explore on my own") as refused:
        student.controlled_room()
    assert isinstance(refused.value, NotAllowed) and str(refused.value) == words
    with pytest.raises(PermissionError) as copy:
        student.state_answer()
    assert str(copy.value) == "answer from your own copy: press 'Answer from my copy' first"
    monkeypatch.setattr(language_role, "translator", lambda _code: MARKED)
    student.set_language("de")
    other = next(title for title in SCENES if title != student.room.scene.title)
    student.select_scene(other)
    assert f"«{words}»" in _marked_error_line(student)


# ------------------------------------------------------------------ the message line's refusals, said again
def _click(timeline: Any, label: str) -> None:
    """A press of the Timeline's button `label`, as the browser sends it."""
    for callback in timeline.gui_buttons._impl.update_cb:
        callback(type("Event", (), {"target": type("T", (), {"value": label})(), "client": None})())


def test_a_refused_branch_is_said_again_through_gettext_when_the_browser_changes_language(
        hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    _app, join = hall
    session = join("en")
    session.select_scene("Free body")
    words = "Branch here continues from a moment in the past: move the Timeline back first."
    _click(session.scene.timeline, "Branch here")  # the live moment is shown: nothing to branch from
    assert session.scene.message.text == f"**⚠ {words}**", session.scene.message.text
    monkeypatch.setattr(language_role, "translator", lambda _code: MARKED)
    session.set_language("de")
    assert session.scene.message.text == f"**⚠ «{words}»**", session.scene.message.text
    assert session.error_count == 0, session.last_error


def test_refused_hand_edits_are_said_again_through_gettext_when_the_browser_changes_language(
        hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    _app, join = hall
    kicked, dragged = join("en"), join("en")
    for session in (kicked, dragged):
        session.select_scene("Free body")
    assert not kicked.scene.hand.kick(0, 99.0)  # beyond the kick slider's range
    assert kicked.scene.message.text == "**⚠ Kick J [N m s] = 99.0 refused: the range is -5 to 5.**", \
        kicked.scene.message.text
    assert not dragged.scene.hand.set_omega_body(np.full(3, math.nan), Said(N_("{arrow} dragged"), arrow="ω"))
    assert dragged.scene.message.text == "**⚠ ω dragged: ω = array([nan, nan, nan]) refused: not finite.**", \
        dragged.scene.message.text
    monkeypatch.setattr(language_role, "translator", lambda _code: MARKED)
    for session in (kicked, dragged):
        session.set_language("de")
    assert kicked.scene.message.text == "**⚠ ««Kick J [N m s]» = 99.0 refused: the range is -5 to 5.»**", \
        kicked.scene.message.text
    assert dragged.scene.message.text == "**⚠ «ω dragged»: «ω = array([nan, nan, nan]) refused: not finite.»**", \
        dragged.scene.message.text
    assert kicked.error_count == 0 and dragged.error_count == 0, (kicked.last_error, dragged.last_error)
