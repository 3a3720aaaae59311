"""The last English words of the panel in other languages (issue 38): the panel's header (viser's
"Connected"), the presenter-only refusals, the heavy top's "No energy picture" reason and the
inertia checks' refusals each go through a msgid.

The msgid path is checked with a translator that marks every word it writes (`«msgid»`), so
these pass with any catalog; the tests named `..._in_german` check the German catalog's words
(they pass once the catalogs carry the new msgids)."""

from __future__ import annotations

import ast
import gettext
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import app.roles.language as language_role
from app.i18n import Translator, translator
from app.kit.rigid.energy_plot import EnergyPlot
from app.main import create_server
from app.refusals import NotAllowed
from app.roles.language import APP_NAME
from app.scenes.inertia.simulation import spin_moments
from physics.exact_top import HeavySymmetricTopExact
from physics.inertia import (
    InertiaError,
    MeshError,
    cylinder_dimensions_from_moments,
    mesh_mass_properties,
    validate_inertia_tensor,
)
from physics.refusal import Refusal
from tests.conftest import browsers_joining

CODE = "24681357"
ROOT = Path(__file__).resolve().parents[1]


class Marked(gettext.NullTranslations):
    """Every message written as «message» (its plural forms too): what went through gettext shows."""

    def gettext(self, message: str) -> str:
        return f"«{message}»"

    def ngettext(self, msgid1: str, msgid2: str, n: int) -> str:
        return f"«{msgid1 if n == 1 else msgid2}»"


MARKED = Translator("de", Marked())


@pytest.fixture
def hall() -> Iterator[Any]:
    """The app without its loop, the presenter code known; (app, join): join(language) opens a browser."""
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE)
    with browsers_joining(running) as join:
        yield running, lambda language="en": join(language)


@pytest.fixture
def labels(monkeypatch: pytest.MonkeyPatch) -> list[tuple[int, str | None]]:
    """Every panel label the app sets: (the GUI's id, the label), in order."""
    import viser._gui_api  # noqa: PLC0415 - the public method's class, recorded

    said: list[tuple[int, str | None]] = []
    original = viser._gui_api.GuiApi.set_panel_label

    def record(self: Any, label: str | None) -> None:
        said.append((id(self), label))
        original(self, label)

    monkeypatch.setattr(viser._gui_api.GuiApi, "set_panel_label", record)
    return said


# ------------------------------------------------------------------ the panel's header
def test_the_panel_header_names_the_app_through_gettext_on_connect_and_on_a_language_change(
        hall: Any, labels: list[tuple[int, str | None]], monkeypatch: pytest.MonkeyPatch) -> None:
    _app, join = hall
    session = join("en")
    gui = id(session.client.gui)
    assert (gui, APP_NAME) in labels, f"no panel label 'Rigid-body lab' for the new browser: {labels}"
    monkeypatch.setattr(language_role, "translator", lambda _code: MARKED)
    session.set_language("de")
    mine = [label for at, label in labels if at == gui]
    assert mine[-1] == f"«{APP_NAME}»", f"the header after a language change: {mine}"


def test_the_panel_header_names_the_app_in_german(hall: Any, labels: list[tuple[int, str | None]]) -> None:
    """Needs the catalogs' entry for "Rigid-body lab"."""
    _app, join = hall
    session = join("en")
    session.set_language("de")
    german = translator("de").gettext(APP_NAME)
    assert german != APP_NAME, "the German catalog has no name for the app"
    assert [label for at, label in labels if at == id(session.client.gui)][-1] == german


# ------------------------------------------------------------------ presenter-only refusals
def test_presenter_only_actions_are_refused_with_msgids_and_stay_permission_errors(hall: Any) -> None:
    app, join = hall
    student = join("en")
    with pytest.raises(PermissionError) as pointed:
        app.lectern.point(student, np.zeros(3), np.array([0.0, 0.0, -1.0]))
    with pytest.raises(PermissionError) as called:
        app.lectern.call_back(student)
    for refused, words in ((pointed.value, "only the presenter can point"),
                           (called.value, "only the presenter can call everyone back")):
        assert isinstance(refused, NotAllowed) and isinstance(refused, Refusal)
        assert refused.template == words and str(refused) == words
    student.guard("ask the class", student.ask_panel.ask_from_form)()
    assert "only the presenter can ask the class and see its answers" in str(student.last_error)
    student.guard("make a task", student.task_panel.make_from_form)()
    assert "only the presenter can make a task" in str(student.last_error)
    assert app.lectern.rounds.current is None


def test_a_refused_call_back_goes_through_gettext_in_the_error_line(
        hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    _app, join = hall
    student = join("en")
    monkeypatch.setattr(language_role, "translator", lambda _code: MARKED)
    student.set_language("de")
    student.call_back()
    shown = student.errors.gui_error.content
    assert "«only the presenter can call everyone back»" in shown, shown
    assert "PermissionError" not in shown and "NotAllowed" not in shown
    assert "only the presenter can call everyone back" in str(student.last_error)  # English for logs


def test_a_refused_call_back_is_said_in_german(hall: Any) -> None:
    """Needs the catalogs' entry for "only the presenter can call everyone back"."""
    _app, join = hall
    student = join("de")
    student.call_back()
    shown = student.errors.gui_error.content
    german = translator("de").gettext("only the presenter can call everyone back")
    assert german != "only the presenter can call everyone back", "the German catalog lacks the refusal"
    assert shown.startswith("**⚠ Nicht angenommen**") and german in shown, shown


# ------------------------------------------------------------------ the heavy top's energy picture
class Markdown:
    content = ""


class Plot:
    """The GUI calls EnergyPlot makes (a Markdown's content kept)."""

    def add_markdown(self, content: str) -> Markdown:
        return Markdown()

    def add_uplot(self, **_kwargs: Any) -> Any:
        return Markdown()


def _top_refusal() -> Refusal:
    with pytest.raises(Refusal) as refused:
        HeavySymmetricTopExact(-1.0, 1.0, 0.5, np.eye(3), np.zeros(3))
    return refused.value


def test_the_exact_top_refuses_with_a_msgid_and_the_plot_says_it_through_gettext() -> None:
    refusal = _top_refusal()
    assert isinstance(refusal, ValueError)
    assert refusal.template == "moments must be finite and positive, got I1={I1}, I3={I3}"
    assert str(refusal) == "moments must be finite and positive, got I1=-1.0, I3=1.0"
    plot = EnergyPlot(Plot(), MARKED)
    plot.show(None, 0.0, refusal)
    assert plot.gui_motion.content == ("«**No energy picture:** {reason}»".format(
        reason="«moments must be finite and positive, got I1={I1}, I3={I3}»".format(I1="-1.0", I3="1.0")))
    plot.show(None, 0.0, ArithmeticError("overflow"))  # no refusal: its own words
    assert plot.gui_motion.content.endswith("overflow»")


def test_the_energy_picture_reason_in_german() -> None:
    """Needs the catalogs' entry for the exact top's refusal."""
    plot = EnergyPlot(Plot(), translator("de"))
    plot.show(None, 0.0, _top_refusal())
    assert "moments must be" not in plot.gui_motion.content, plot.gui_motion.content


# ------------------------------------------------------------------ inertia's refusals
@pytest.mark.parametrize(("refuse", "english"), [
    (lambda: validate_inertia_tensor(np.eye(2)), "inertia tensor must have shape (3, 3), got (2, 2)"),
    (lambda: validate_inertia_tensor([[1, 0, 0], [0, np.nan, 0], [0, 0, 1]]),
     "inertia tensor must be finite, got [[1.0, 0.0, 0.0], [0.0, nan, 0.0], [0.0, 0.0, 1.0]]"),
    (lambda: validate_inertia_tensor([[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]),
     "inertia tensor is not symmetric: max |I - I^T| = 0.5 > 1e-10 * max |I| = 1e-10"),
    (lambda: cylinder_dimensions_from_moments(-1.0, 1.0), "moments must be finite and > 0, got I1 = -1, I3 = 1"),
    (lambda: cylinder_dimensions_from_moments(0.2, 1.0),
     "no uniform cylinder has I1 = 0.2 < I3/2 = 0.5 (the flat disc has I1 = I3/2)"),
    (lambda: mesh_mass_properties(np.zeros((0, 3)), [[0, 1, 2]]),
     "vertices must have shape (V, 3) with V > 0, got (0, 3)"),
    (lambda: mesh_mass_properties(np.eye(3), [[0, 1, 3]]), "face 0 = [0, 1, 3] has an index outside [0, 2]"),
])
def test_inertia_refusals_carry_a_msgid_that_formats_to_their_english(refuse: Any, english: str) -> None:
    with pytest.raises((InertiaError, MeshError)) as refused:
        refuse()
    error = refused.value
    assert str(error) == english
    assert error.fields, "a refusal with values in its words gives them as fields"
    assert error.template.format(**error.fields) == english and "{" in error.template


def test_a_zero_principal_moment_is_refused_with_a_msgid() -> None:
    with pytest.raises(InertiaError) as refused:
        spin_moments(np.array([1e-20, 1.0, 1.0]))
    assert refused.value.template == "a principal moment is zero ({moment} kg m²)"
    assert str(refused.value) == "a principal moment is zero (1e-20 kg m²)"


def _raised_from_f_strings(path: Path, names: set[str]) -> list[str]:
    """`raise Name(f"...")` in `path` for a class in `names`: 'line: source' each."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call):
            call = node.exc
            if isinstance(call.func, ast.Name) and call.func.id in names and call.args \
                    and isinstance(call.args[0], ast.JoinedStr):
                found.append(f"{path.name}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_refusal_is_raised_from_an_f_string() -> None:
    """Every InertiaError and MeshError raised in physics/inertia.py and the Inertia scene, and every
    refusal of the exact top, carries a msgid and its fields (an f-string's words never reach a catalog)."""
    found = _raised_from_f_strings(ROOT / "physics" / "inertia.py", {"InertiaError", "MeshError"})
    found += _raised_from_f_strings(ROOT / "app" / "scenes" / "inertia" / "simulation.py", {"InertiaError"})
    found += _raised_from_f_strings(ROOT / "physics" / "exact_top.py", {"Refusal"})
    assert found == [], "\n".join(found)
