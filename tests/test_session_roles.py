"""The session is a façade over the browser's roles (`app.roles`): no class of theirs over 400
lines, what a session shows is typed, and the automation API keeps its names and signatures."""

from __future__ import annotations

import ast
import inspect
import typing
from pathlib import Path

from app.kit.view import SceneView
from app.lecture.follower import Follower
from app.session import Session

ROOT = Path(__file__).resolve().parents[1]
MAX_CLASS_LINES = 400


def _class_lines(path: Path) -> dict[str, int]:
    """Lines of each top-level class of the file (its `class` line to its last)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {node.name: node.end_lineno - node.lineno + 1 for node in tree.body  # type: ignore[operator]
            if isinstance(node, ast.ClassDef)}


def test_the_session_and_its_roles_have_no_class_over_400_lines() -> None:
    files = [ROOT / "app" / "session.py", *sorted((ROOT / "app" / "roles").glob("*.py"))]
    sizes = {f"{path.relative_to(ROOT)}:{name}": lines for path in files for name, lines in _class_lines(path).items()}
    assert "app/session.py:Session" in sizes and "app/roles/own_room.py:OwnRoom" in sizes, sorted(sizes)
    too_long = {name: lines for name, lines in sizes.items() if lines > MAX_CLASS_LINES}
    assert not too_long, f"classes over {MAX_CLASS_LINES} lines: {too_long}"


def test_what_a_session_shows_is_a_scene_view_or_a_followers_panel() -> None:
    shown = typing.get_type_hints(Session.scene.fget)["return"]  # type: ignore[attr-defined]
    assert set(typing.get_args(shown)) == {SceneView, Follower, type(None)}, shown


AUTOMATION_API = {
    "select_scene": "(self, title: 'str') -> 'None'",
    "apply_preset": "(self, name: 'str') -> 'None'",
    "play": "(self) -> 'None'", "pause": "(self) -> 'None'", "step": "(self) -> 'None'",
    "reset": "(self) -> 'None'", "tick": "(self, dt: 'float') -> 'None'",
    "present": "(self, code: 'str') -> 'None'", "stop_presenting": "(self) -> 'None'",
    "follow": "(self) -> 'None'", "explore": "(self) -> 'None'",
    "ask": "(self, question: 'Question | dict[str, Any]') -> 'Round'",
    "close_round": "(self) -> 'Round'", "vote_again": "(self) -> 'Round'",
    "answer": "(self, value: 'Any') -> 'Any'",
    "screenshot": "(self, *, wait: 'bool' = False) -> 'threading.Thread'",
    "record": "(self, seconds: 'Any', *, wait: 'bool' = False) -> 'threading.Thread'",
    "start_lesson": "(self, title: 'str') -> 'None'", "next_step": "(self, delta: 'int') -> 'None'",
}
AUTOMATION_PROPERTIES = ("client", "room", "scene", "simulation", "mode", "error_count", "last_error", "lock",
                         "lesson", "lesson_step", "lessons", "projector")


def test_the_automation_api_keeps_its_names_and_signatures() -> None:
    changed = {name: str(inspect.signature(getattr(Session, name))) for name in AUTOMATION_API
               if str(inspect.signature(getattr(Session, name))) != AUTOMATION_API[name]}
    assert not changed, changed
    missing = [name for name in AUTOMATION_PROPERTIES
               if not isinstance(getattr(Session, name, None), property) and name != "client"]
    assert not missing, missing
