"""The translation layer (`app.i18n`): the catalogs complete and in step with the code, a panel
built in Dutch or German holding no English among its translated widgets, the language chosen per
browser (the Language dropdown, `--language`), refusals and numbers a person reads in the
browser's language.  The browser test is tests/test_browser_language.py."""

from __future__ import annotations

import argparse
import json
import re
import string
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import viser
from babel.messages.pofile import read_po
from babel.support import Translations

from app.cli_words import cli_language
from app.hall.lesson_runner import OWN_MARK
from app.i18n import catalog_bytes, compile_po, for_gui, language_named, refusal_text, translator
from app.lessons import lessons, load_lesson
from app.main import _parse_args, create_server
from app.scenes import SCENES
from physics.inertia import InertiaError, validate_principal_moments
from physics.methods import methods
from scripts import i18n_catalogs
from tests.conftest import RawClient, browsers_joining, poll_until

ROOT = Path(__file__).resolve().parents[1]
LOCALE = ROOT / "app" / "locale"
TRANSLATED = ("nl", "de")


def _catalog(path: Path) -> Any:
    with path.open("rb") as handle:
        return read_po(handle)


def _msgids(catalog: Any) -> set[str]:
    return {m.id for m in catalog if m.id}


# ---------------------------------------------------------------------------------- the catalogs
@pytest.mark.parametrize("language", TRANSLATED)
def test_every_entry_of_the_catalog_is_translated_and_none_is_fuzzy(language: str) -> None:
    catalog = _catalog(LOCALE / language / "LC_MESSAGES" / "messages.po")
    entries = [m for m in catalog if m.id]
    assert len(entries) >= 60
    untranslated = [m.id for m in entries if not all(m.string if isinstance(m.string, tuple) else (m.string,))]
    fuzzy = [m.id for m in entries if m.fuzzy]
    assert untranslated == [] and fuzzy == []
    assert not catalog.fuzzy  # the header too (a fuzzy header makes gettext ignore the plural rule)
    assert i18n_catalogs.problems() == []


def test_the_template_holds_every_marked_string_of_the_code_and_every_catalog_holds_the_template(
        tmp_path: Path) -> None:
    """A string marked in the code but not extracted (or a catalog not updated) fails here."""
    fresh = _msgids(_catalog(i18n_catalogs.extract(tmp_path / "messages.pot")))
    assert {"Play", "Scene", "Language", "Euler angles", "φ [deg]"} <= fresh
    assert fresh == _msgids(_catalog(LOCALE / "messages.pot"))
    for language in TRANSLATED:
        assert _msgids(_catalog(LOCALE / language / "LC_MESSAGES" / "messages.po")) == fresh, language


def _fields(text: str) -> list[str]:
    return sorted(name for _, name, _, _ in string.Formatter().parse(text) if name is not None)


@pytest.mark.parametrize("language", TRANSLATED)
def test_the_catalog_compiles_and_keeps_every_placeholder_and_line_break(language: str) -> None:
    po = LOCALE / language / "LC_MESSAGES" / "messages.po"
    translations = Translations(__import__("io").BytesIO(compile_po(po.read_bytes(), locale=language)))
    catalog = _catalog(po)
    for message in catalog:
        if not message.id:
            continue
        if isinstance(message.id, tuple):  # plural forms: one, many (Dutch and German have two)
            one, many = message.id
            forms = (translations.ngettext(one, many, 1), translations.ngettext(one, many, 2))
            assert forms == tuple(message.string), message.id
            assert [_fields(f) for f in forms] == [_fields(one), _fields(many)], message.id
            continue
        shown = translations.gettext(message.id)
        assert shown == message.string, message.id  # compiled as written
        assert _fields(shown) == _fields(message.id), message.id
        assert shown.count("\n") == message.id.count("\n"), message.id
        assert shown.startswith("### ") == message.id.startswith("### "), message.id
    assert catalog_bytes(language)  # what the app reads (the .mo, or the .po compiled in memory)


def test_the_translator_speaks_the_language_and_writes_numbers_the_local_way() -> None:
    nl, de, en = translator("nl"), translator("de"), translator("en")
    assert (nl.gettext("Scene"), de.gettext("Scene"), en.gettext("Scene")) == ("Scène", "Szene", "Scene")
    assert nl.gettext("never a msgid") == "never a msgid"
    assert nl.gettext("") == ""  # not the catalog's header
    assert (en.decimal(-1234.5, 2), nl.decimal(-1234.5, 2), de.decimal(1.25, 1)) == ("-1234.50", "-1234,50", "1,2")
    assert (en.general(0.1), nl.general(0.1), de.general(30.0)) == ("0.1", "0,1", "30")
    assert nl.ngettext("{n} answer", "{n} answers", 2) == "{n} answers"  # no such entry: English forms
    assert nl.english("Hoekbogen") == "Angle arcs" and de.english("Winkelbögen") == "Angle arcs"
    assert language_named("Deutsch") == "de" and language_named("nl") == "nl" and language_named("Klingon") is None
    with pytest.raises(ValueError, match="unknown language"):
        translator("fr")


# ---------------------------------------------------------------------------------- the command line
def test_language_option_chooses_the_default_and_refuses_another() -> None:
    assert _parse_args([]).language == "en"
    assert _parse_args(["--language", "de", "--port", "9000"]).language == "de"
    with pytest.raises(SystemExit):
        _parse_args(["--language", "fr"])
    with pytest.raises(ValueError, match="unknown language"):
        create_server("127.0.0.1", 0, verbose=False, start_loop=False, language="fr")


def _help(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    """`rigid-body-lab <argv> --help` as printed."""
    with pytest.raises(SystemExit):
        _parse_args([*argv, "--help"])
    return capsys.readouterr().out


def test_the_command_lines_help_in_dutch_with_language(monkeypatch: pytest.MonkeyPatch,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """`--language nl --help`: the help (argparse's own words too) in Dutch; the shell's locale
    changes nothing (LANG=de: still Dutch; no --language: English)."""
    monkeypatch.setenv("LANG", "de_DE.UTF-8")
    dutch = _help(capsys, ["--language", "nl"])
    assert dutch.startswith("gebruik: rigid-body-lab") and "\nopties:\n" in dutch
    assert "toon deze hulptekst en stop" in dutch and "Mechanica van starre lichamen" in dutch
    english_words = ("usage:", "options:", "show this help", "interface to bind", "in a browser",
                     "the language a new", "where own presets", "serve with N", "projector layout")
    assert [words for words in english_words if words in " ".join(dutch.split())] == []
    german = _help(capsys, ["--language=de"])
    assert german.startswith("Aufruf: ") and "diese Hilfe anzeigen und beenden" in german
    english = _help(capsys, [])
    assert english.startswith("usage: ") and "show this help message and exit" in english
    assert cli_language(["--language", "xx"]) == "en" and cli_language(["--port", "1", "--language", "de"]) == "de"


def test_the_command_lines_errors_in_its_language(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        _parse_args(["--language", "de", "--workers", "0"])
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("Aufruf: ") and "rigid-body-lab: Fehler: --workers braucht mindestens 1" in err


@pytest.mark.parametrize(("argv", "said"), [
    (["--language", "de", "--port", "x"], "rigid-body-lab: Fehler: Argument --port: ungültiger int-Wert: 'x'"),
    (["--language", "nl", "--port"], "rigid-body-lab: fout: argument --port: verwacht één argument"),
    (["--language=nl", "--scene", "x"], "rigid-body-lab: fout: onbekende argumenten: --scene x"),
    (["--language", "de", "--language", "fr"],
     "rigid-body-lab: Fehler: Argument --language: ungültige Auswahl: 'fr' (wähle aus 'en', 'nl', 'de')"),
    (["--port", "x"], "rigid-body-lab: error: argument --port: invalid int value: 'x'"),
])
def test_argparses_own_messages_in_the_command_lines_language(capsys: pytest.CaptureFixture[str], argv: list[str],
                                                               said: str) -> None:
    with pytest.raises(SystemExit) as caught:
        _parse_args(argv)
    assert caught.value.code == 2
    assert said in capsys.readouterr().err


def test_workers_get_the_language_too(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    import app.launch as launch

    started: list[list[str]] = []
    monkeypatch.setattr(launch, "_popen", lambda args, **_kw: started.append(list(args)))
    launch.start_worker("w1", 1234, tmp_path, "redis://x", "12345678", language="nl")
    launch.start_worker("w2", 1235, tmp_path, "redis://x", "12345678")
    assert started[0][-2:] == ["--language", "nl"] and "--language" not in started[1]
    assert isinstance(_parse_args(["--workers", "2", "--language", "nl"]), argparse.Namespace)


# ---------------------------------------------------------------------------------- panels
def _texts(handle: Any) -> Iterator[tuple[str, str]]:
    """(what, text) of a GUI handle and every handle under it: labels, hints, options, Markdown."""
    yield from _texts_here(handle)
    for child in list(getattr(handle, "_children", {}).values()):
        yield from _texts(child)


def _translated_part(session: Any) -> list[tuple[str, str]]:
    """The texts of the scene and Language dropdowns, the Projector checkbox and the scene's
    panel (its Timeline, its presets' rows and note too), less the typed-number script."""
    view = session.scene
    texts: list[tuple[str, str]] = []
    for handle in (session.gui_scene, session.gui_language, session.gui_projector, *view.gui_roots):
        if type(handle).__name__ == "GuiHtmlHandle":
            continue
        texts.extend(_texts(handle))
    return texts


def _texts_here(handle: Any) -> list[tuple[str, str]]:
    """(what, text) of one handle: its label, hint, options and (Markdown) content, those not empty."""
    props = getattr(getattr(handle, "_impl", None), "props", None)
    if props is None:
        return []
    kind = type(handle).__name__
    out = [(f"{kind}.{f}", getattr(props, f)) for f in ("label", "hint") if getattr(props, f, None)]
    if isinstance(handle, viser.GuiMarkdownHandle) and handle.content:
        out.append((f"{kind}.content", str(handle.content)))
    return out + [(f"{kind}.options", str(o)) for o in getattr(props, "options", None) or ()]


WORD = re.compile(r"[A-Za-z]{3,}")
SYMBOLS_ONLY = {"English", "Nederlands", "Deutsch"}  # the Language dropdown names each language in its own
METHOD_NAMES = set(methods())  # the integrator menu's options: physics' names, as the CLI takes them


@pytest.fixture
def hall() -> Iterator[Any]:
    """The app without its loop, English by default, and a factory of raw clients' sessions."""
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    clients: dict[int, RawClient] = {}  # session's client id -> the raw client it serves

    def join() -> Any:
        before = set(running.sessions)
        client = RawClient(running.port)
        session = poll_until(lambda: next((s for c, s in dict(running.sessions).items() if c not in before), None),
                             timeout=20.0)
        clients[session.client_id] = client
        return session

    running.raw_clients = clients  # type: ignore[attr-defined]
    try:
        yield running, join
    finally:
        for client in clients.values():
            client.close()
        running.stop()


@pytest.mark.parametrize("language", TRANSLATED)
def test_a_panel_built_in_another_language_shows_no_english_among_its_translated_widgets(hall: Any,
                                                                                         language: str) -> None:
    app, join = hall
    english, other = join(), join()
    other.set_language(language)
    assert other.error_count == 0, other.last_error
    tr = translator(language)
    msgids = _msgids(_catalog(LOCALE / language / "LC_MESSAGES" / "messages.po"))
    changed = {m for m in msgids if tr.gettext(m) != m}  # "Pause" is German too, "Poinsot" a name
    shown = _translated_part(other)
    assert len(shown) >= 60
    english_left = [(what, text) for what, text in shown if text in changed]
    assert english_left == []
    # Nothing of the English panel's words is left either (a string never marked would be):
    # only texts without a word (symbols, units, numbers: "I1 [kg m²]", "D", "ω"), the
    # language names and msgids the language writes the same way.
    english_texts = {text for _, text in _translated_part(english)}
    same = sorted({text for _, text in shown if text in english_texts and WORD.search(text)
                   and text not in SYMBOLS_ONLY and text not in msgids - changed})
    assert same == []
    assert for_gui(other.client.gui) is tr and for_gui(english.client.gui) is translator("en")


@pytest.mark.parametrize("language", TRANSLATED)
@pytest.mark.parametrize("title", list(SCENES))
def test_every_scenes_panel_built_in_another_language_shows_no_english(hall: Any, title: str,
                                                                       language: str) -> None:
    """Each scene of the dropdown, opened in a Dutch or German browser with a preset applied: none
    of its wrapped widgets (presets' buttons and note too) shows a msgid the language translates,
    nor a text with a word the English panel of the same scene shows (a string never marked would)."""
    app, join = hall
    english, other = join(), join()
    other.set_language(language)
    for session in (english, other):
        session.select_scene(title)
        session.apply_preset(session.room.scene.presets()[-1].name)  # the API names it in English
        assert session.error_count == 0, session.last_error
    assert other.scene.presets_row.gui_note.content  # the preset's note is shown (and checked below)
    tr = translator(language)
    msgids = _msgids(_catalog(LOCALE / language / "LC_MESSAGES" / "messages.po"))
    changed = {m for m in msgids if tr.gettext(m) != m}
    shown = _translated_part(other)
    assert len(shown) >= 20, shown
    assert [(what, text) for what, text in shown if text in changed] == []
    english_texts = {text for _, text in _translated_part(english)}
    same = sorted({text for _, text in shown if text in english_texts and WORD.search(text)
                   and text not in SYMBOLS_ONLY | METHOD_NAMES and text not in msgids - changed})
    assert same == []


def test_a_refusal_from_physics_keeps_its_english_words_and_carries_what_a_translation_needs() -> None:
    """physics stays English (its CLI, `str(error)`); the app translates the template it carries."""
    with pytest.raises(InertiaError) as caught:
        validate_principal_moments((1.0, 1.0, 3.0))
    error = caught.value
    assert str(error) == "I1 + I2 >= I3 fails: 1 + 1 < 3"
    assert refusal_text(error, translator("en")) == str(error)
    assert refusal_text(error, translator("nl")) == "I1 + I2 >= I3 geldt niet: 1 + 1 < 3"
    assert refusal_text(error, translator("de")) == "I1 + I2 >= I3 gilt nicht: 1 + 1 < 3"
    assert refusal_text(ValueError("plain words"), translator("de")) == "plain words"


@pytest.mark.parametrize(("language", "refused", "reason"), [
    ("nl", "Geen star lichaam", "I1 + I2 >= I3 geldt niet: 1 + 1 < 3"),
    ("de", "Kein starrer Körper", "I1 + I2 >= I3 gilt nicht: 1 + 1 < 3"),
])
def test_a_refusal_from_physics_shows_in_the_browsers_language(hall: Any, language: str, refused: str,
                                                              reason: str) -> None:
    """A non-physical body typed into the Free body panel (I3 = 3 with I1 = I2 = 1, as a browser
    sends it): physics' InertiaError said in that browser's language, prefix and reason; nothing changes."""
    app, join = hall
    session = join()
    session.set_language(language)
    session.select_scene("Free body")
    view = session.scene
    view._param_edit(0)(1.0)
    view._param_edit(1)(1.0)
    for index, value in enumerate((1.0, 1.0, 2.0)):
        app.raw_clients[session.client_id].set_value(view.gui_params[index], value)
    poll_until(lambda: tuple(view.sim.model.inertia) == (1.0, 1.0, 2.0), timeout=10.0)
    app.raw_clients[session.client_id].set_value(view.gui_params[2], 3.0)
    note = poll_until(lambda: view.message.text if reason in view.message.text else None, timeout=10.0)
    assert refused in note and "fails" not in note and "refused" not in note.lower()
    assert reason in view.gui_param_status.content and "Each moment" not in view.gui_param_status.content
    assert tuple(view.sim.model.inertia) == (1.0, 1.0, 2.0)  # refused: the last valid body keeps moving
    assert session.error_count == 0, session.last_error


def test_a_preset_button_shows_its_name_translated_and_starts_the_english_preset(hall: Any) -> None:
    """The Heavy top's "Sleeping" in a German browser: the button reads "Schlafend", a click (as
    the browser sends it) starts the preset "Sleeping", the note is German; the API keeps English."""
    app, join = hall
    german = join()
    german.set_language("de")
    german.select_scene("Heavy top")
    row = german.scene.presets_row
    group = next(g for g in row.groups if "Schlafend" in g._impl.props.options)
    assert group.label == "Aufrecht" and "Sleeping" not in group._impl.props.options
    app.raw_clients[german.client_id].set_value(group, "Schlafend")
    poll_until(lambda: german.room.sim.preset == "Sleeping", timeout=10.0)
    poll_until(lambda: row.gui_note.content.startswith("**Schlafend.** Fast aufrecht und schnell"), timeout=10.0,
               what="the German note of Sleeping (the callback writes it after the preset starts)",
               seen=lambda: row.gui_note.content[:60])
    german.apply_preset("Too slow")
    assert german.room.sim.preset == "Too slow" and row.gui_note.content.startswith("**Zu langsam.**")
    assert german.error_count == 0, german.last_error


def test_switching_language_relabels_that_browser_only_and_changes_nothing_of_its_room(hall: Any) -> None:
    app, join = hall
    dutch, english = join(), join()
    dutch.apply_preset(dutch.room.scene.presets()[1].name)
    dutch.room.tick(0.0)
    room, state = dutch.room, (dutch.room.sim.t, tuple(dutch.room.sim.angles_deg), dutch.room.playing)
    english_panel = _translated_part(english)
    dutch.gui_language.value = "Nederlands"  # as the dropdown sends it (runs its callback)
    assert dutch.error_count == 0, dutch.last_error
    assert dutch.languages.code == "nl" and dutch.room is room
    assert (room.sim.t, tuple(room.sim.angles_deg), room.playing) == state
    assert dutch.scene.transport.gui_play.label == "Afspelen" and dutch.gui_scene.label == "Scène"
    assert dutch.scene.nodes.label.text == "knooplijn (onbepaald)"  # "D = 1": θ = 0, the line undefined
    assert dutch.scene.timeline.gui_slider.label == "Tijdlijn [s]" and dutch.gui_projector.label == "Projector"
    assert dutch.gui_scene.value == "Euler-hoeken" and dutch.gui_language.label == "Taal"
    assert len(room.views) == 1  # the old view left, the new one joined
    assert english.languages.code == "en" and _translated_part(english) == english_panel
    dutch.select_scene("Free body")  # the API keeps English titles whatever the language
    assert dutch.room.scene.title == "Free body" and dutch.gui_scene.value == "Vrij lichaam"
    assert dutch.error_count == 0, dutch.last_error
    dutch.gui_language.value = "Klingon"  # a client can send anything: refused, nothing changes
    assert dutch.languages.code == "nl" and dutch.gui_language.value == "Nederlands"
    assert dutch.error_count == 1 and "Klingon" in str(dutch.last_error)
    dutch.set_language("en")
    assert dutch.gui_scene.value == "Free body" and dutch.scene.transport.gui_play.label == "Play"


def test_the_default_language_is_every_new_browsers_and_a_lesson_finds_its_checkboxes(hall: Any) -> None:
    app, join = hall
    app.language = "de"
    german = join()
    assert german.languages.code == "de" and german.gui_language.value == "Deutsch"
    assert german.scene.folder_display.label == "Darstellung"
    assert "Angle arcs" in german.scene.checkboxes()  # lessons name checkboxes in English
    assert german.scene.checkboxes()["Angle arcs"].label == "Winkelbögen"


def test_refusals_and_numbers_of_the_euler_panel_in_the_browsers_language(hall: Any) -> None:
    app, join = hall
    dutch = join()
    dutch.set_language("nl")
    view = dutch.scene
    app.raw_clients[dutch.client_id].set_value(view.gui_angles[0], 999.0)  # as a browser sends it
    note = poll_until(lambda: view.message.text, timeout=10.0)
    assert "φ [°] = 999.0 geweigerd: het bereik is -180 tot 180." in note
    assert dutch.room.sim.angles_deg[0] == 30.0  # refused: nothing changed
    view._moment_edit(2)(5.0)  # I3 = 5 with I1 = I2 = 1: no rigid body
    status = view.gui_moments_status.content
    assert "Geen star lichaam" in status and "geldt niet" in status and "kg m²" in status
    assert re.search(r"I = \(\d,\d\d; \d,\d\d; \d,\d\d\)", status), status
    view.room.sim.t = 1.25
    view._refresh_status()
    assert view.transport.gui_status.content.startswith("**t = 1,25 s** · gepauzeerd · 1×")



def test_a_follower_keeps_its_language_and_explores_in_it_while_the_presenter_speaks_english(hall: Any) -> None:
    app, join = hall
    lecturer, student = join(), join()
    student.set_language("de")
    lecturer.present(app.lectern.code)
    assert lecturer.error_count == 0, lecturer.last_error
    poll_until(lambda: (app.frame(1 / 60), student.mode.name == "FOLLOWING")[1], timeout=10.0)  # the loop's work
    assert student.languages.code == "de" and student.gui_scene.label == "Szene"
    assert student.gui_language.label == "Sprache"
    lecturer.select_scene("Free body")
    assert lecturer.scene.transport.gui_play.label == "Play"  # the presenter's panel stays English
    student.set_language("nl")  # while following: its own widgets relabel, the shared screen is untouched
    assert student.error_count == 0, student.last_error
    assert student.mode.name == "FOLLOWING" and student.gui_scene.label == "Scène"
    student.explore()
    assert student.error_count == 0, student.last_error
    assert student.room.scene.title == "Free body" and student.gui_scene.value == "Vrij lichaam"
    assert student.scene.transport.gui_play.label == "Afspelen"
    assert lecturer.scene.transport.gui_play.label == "Play" and lecturer.languages.code == "en"


def test_a_presenter_switching_language_keeps_presenting_the_same_room(hall: Any) -> None:
    app, join = hall
    lecturer, student = join(), join()
    lecturer.present(app.lectern.code)
    poll_until(lambda: (app.frame(1 / 60), student.mode.name == "FOLLOWING")[1], timeout=10.0)
    room = lecturer.room
    lecturer.play()
    lecturer.set_language("nl")
    assert lecturer.error_count == 0, lecturer.last_error
    assert lecturer.mode.name == "PRESENTING" and lecturer.room is room and room.playing
    assert lecturer.scene.transport.gui_play.label == "Pauze" and len(room.views) == 1
    app.frame(1 / 60)
    assert student.mode.name == "FOLLOWING" and student.room is room and student.languages.code == "en"
    assert student.gui_scene.label == "Scene" and student.error_count == 0, student.last_error


def test_every_shipped_lesson_runs_in_a_german_browser_without_an_error(hall: Any) -> None:
    """Lessons name scenes, checkboxes and tabs in English: a German panel finds them all (the
    shipped lessons only: an own lesson another test saved in the data folder is not this test's)."""
    app, join = hall
    german = join()
    german.set_language("de")
    shipped = {lesson.title: lesson for lesson in lessons()}
    assert shipped and set(shipped) <= set(german.lessons)
    for title, lesson in shipped.items():
        german.start_lesson(title)
        for _step in range(len(lesson.steps) - 1):
            german.next_step(1)
        assert german.error_count == 0, f"{title}: {german.last_error}"
        assert german.scene.transport is None or german.scene.transport.tr.language == "de"


def test_two_words_one_german_translation_a_lesson_still_names_the_checkbox(hall: Any, tmp_path: Path) -> None:
    """German "Knotenlinie" is both the checkbox "Line of nodes" and the 3D label "line of nodes":
    a lesson step switching "Line of nodes" finds the German checkbox (it failed on 34df603 when the
    reverse lookup picked the label's msgid), and what a widget can show picks the msgid meant."""
    de = translator("de")
    shared = {text: msgids for text in {de.gettext(m) for m in ("Line of nodes", "Loop", "Mass")}
              if len(msgids := de.englishes(text)) > 1}
    assert set(shared) == {"Knotenlinie", "Schleife", "Masse"}, shared  # the catalog as it is; a change shows here
    assert de.english("Knotenlinie", ("Line of nodes", "Angle arcs")) == "Line of nodes"
    assert de.english("Knotenlinie", ("line of nodes",)) == "line of nodes"
    assert de.english("Schleife", ("Cusp", "Loop")) == "Loop" and de.english("Schleife", ("loop",)) == "loop"
    assert de.english("nirgends", ("Loop",)) == "nirgends"  # no entry: the text itself
    path = tmp_path / "nodes.json"
    path.write_text(json.dumps({"title": "Nodes", "steps": [
        {"scene": "Heavy top", "display": {"Line of nodes": False}, "text": "no line"},
        {"scene": "Heavy top", "display": {"Line of nodes": True}, "text": "the line"}]}), encoding="utf-8")
    lesson = load_lesson(path, SCENES)
    app, join = hall
    german = join()
    german.set_language("de")
    german.lesson_runner.add_lessons({"Nodes": lesson})
    german.start_lesson(OWN_MARK + "Nodes")
    assert german.error_count == 0, german.last_error
    toggle = german.scene.checkboxes()["Line of nodes"]
    assert toggle.label == "Knotenlinie" and toggle.value is False
    german.next_step(1)
    assert german.error_count == 0 and toggle.value is True, german.last_error


def test_a_follower_and_a_student_read_their_panels_in_their_language_the_lecturers_words_as_typed(
        hall: Any) -> None:
    """The follower's panel, the explorer's live bar and the question panel in each browser's
    language (the first two also relabelled while following); a refusal of an answer too."""
    app, join = hall
    lecturer, german, english = join(), join(), join()
    german.set_language("de")
    lecturer.present(app.lectern.code)
    poll_until(lambda: (app.frame(1 / 60), german.mode.name == "FOLLOWING")[1], timeout=10.0)
    panel = german.showing.view
    assert panel.folder.label == "Dem Vortragenden folgen" and panel.gui_explore.label == "Selbst erkunden"
    poll_until(lambda: (app.frame(1 / 60), "Vortragender:" in panel.gui_status.content)[1], timeout=10.0)
    assert "Szene **Euler-Winkel**" in panel.gui_status.content
    assert english.showing.view.gui_explore.label == "Explore on my own"
    german.set_language("nl")  # while following: the same panel, relabelled
    assert german.error_count == 0, german.last_error
    assert german.showing.view is panel and panel.gui_explore.label == "Zelf verkennen"
    assert "Presentator:" in panel.gui_status.content and "Scène **Euler-hoeken**" in panel.gui_status.content
    lecturer.ask({"kind": "number", "prompt": "How long is one turn?", "unit": "s", "value": 2.0})
    poll_until(lambda: (app.frame(1 / 60), german.question.folder.visible)[1], timeout=10.0)
    question = german.question
    assert question.folder.label == "Vraag" and question.gui_send_number.label == "Stuur mijn getal"
    assert question.gui_number.label == "Jouw antwoord [s]"
    assert question.gui_prompt.content == "**Vraag 1** · How long is one turn?"  # the lecturer's words as typed
    assert english.question.gui_send_number.label == "Send my number"
    german.guard("answer", question.send)(2.1)
    assert german.error_count == 0, german.last_error
    assert question.gui_mine.content.startswith("Jouw antwoord: **2.1 s**")
    assert question.gui_change.label == "Wijzig mijn antwoord"
    lecturer.close_round()
    question.redraw()
    assert "*De ronde is gesloten.*" in question.gui_prompt.content
    german.guard("answer", question.send)(3.0)  # refused: said in Dutch, nothing changes
    assert german.error_count == 1 and "de ronde is gesloten" in str(german.last_error)
    assert german.my_answer() == 2.1
    german.explore()
    app.frame(1 / 60)
    assert german.lecture.gui_follow.label == "Volg presentator"
    assert german.lecture.gui_lecture_on.content.startswith("**● College bezig** · de presentator toont")
    german.set_language("de")  # the live bar follows the language
    assert german.lecture.gui_follow.label == "Vortragendem folgen"
    assert "Vorlesung läuft" in german.lecture.gui_lecture_on.content


# ------------------------------------------------------------------ the presenter's parts and the folders
def _texts_of(*roots: Any) -> list[tuple[str, str]]:
    """(what, text) of every widget under `roots` (shown or hidden), less the HTML (styles)."""
    return [(what, text) for root in roots if type(root).__name__ != "GuiHtmlHandle" for what, text in _texts(root)]


def _presenters_part(session: Any) -> list[tuple[str, str]]:
    """The presenter's words: the live bar (badge, Stop presenting, Pointer, Call everyone back),
    the Lecture folder and Ask the class (the form of every kind, the round, its tally, the
    gallery, Make a task)."""
    lecture = session.lecture
    return _texts_of(lecture.bar, lecture.folder, session.ask_panel.folder)


def _folders_part(session: Any) -> list[tuple[str, str]]:
    """The Lesson, notes, Share, Task and Mine folders' own words (the lessons' titles in the
    Lesson dropdown are the lessons', translated with them elsewhere)."""
    runner = session.lesson_runner
    texts = _texts_of(session.notes.folder, session.share.folder, session.task_panel.folder,
                      session.own_panel.folder)
    lesson = [(what, text) for what, text in _texts_of(runner.folder)
              if not (what == "GuiDropdownHandle.options" and text in runner.lessons)]
    return texts + lesson


def _english_left(shown: list[tuple[str, str]], english_panel: list[tuple[str, str]],
                  language: str) -> tuple[list[tuple[str, str]], list[str]]:
    """(msgids shown untranslated, texts with a word shown as the English panel shows them) of a
    panel part in `language`; the judges' names (identifiers) and msgids the language writes the
    same way are no English left."""
    from app.ask import JUDGES

    tr = translator(language)
    msgids = _msgids(_catalog(LOCALE / language / "LC_MESSAGES" / "messages.po"))
    changed = {m for m in msgids if tr.gettext(m) != m}
    left = [(what, text) for what, text in shown if text in changed]
    english_texts = {text for _, text in english_panel}
    same = sorted({text for _, text in shown if text in english_texts and WORD.search(text)
                   and text not in SYMBOLS_ONLY and text not in msgids - changed and text not in JUDGES})
    return left, same


def _round_with_an_answer(app: Any, lecturer: Any, student: Any) -> None:
    """`lecturer` presents and asks a choice (no words of its own), `student` answers it."""
    lecturer.present(app.lectern.code)
    assert lecturer.error_count == 0, lecturer.last_error
    poll_until(lambda: (app.frame(1 / 60), student.mode.name == "FOLLOWING")[1], timeout=10.0)
    lecturer.ask({"kind": "choice", "prompt": "?", "options": ["A", "B"], "correct": 0})
    poll_until(lambda: (app.frame(1 / 60), student.question.folder.visible)[1], timeout=10.0)
    student.answer(0)
    lecturer.ask_panel.refresh()
    assert lecturer.error_count == 0 and student.error_count == 0, (lecturer.last_error, student.last_error)


@pytest.mark.parametrize("language", TRANSLATED)
def test_the_presenters_panel_with_a_round_open_shows_no_english_in_another_language(hall: Any,
                                                                                     language: str) -> None:
    """Built in English, presenting with a round open, then switched: the live bar, Lecture and
    Ask the class (every kind's form, the count, the tally, the buttons) in the language; the
    same panel back in English is the English words the tests click."""
    app, join = hall
    lecturer, student = join(), join()
    _round_with_an_answer(app, lecturer, student)
    english_panel = _presenters_part(lecturer)
    assert ("GuiButtonHandle.label", "Stop presenting") in english_panel
    assert ("GuiButtonHandle.label", "Close the round") in english_panel
    assert any("1 of 1 answered" in text for _, text in english_panel)
    lecturer.set_language(language)
    assert lecturer.error_count == 0, lecturer.last_error
    app.frame(1 / 60)
    shown = _presenters_part(lecturer)
    assert len(shown) >= 60
    left, same = _english_left(shown, english_panel, language)
    assert left == [] and same == []
    tr = translator(language)
    assert lecturer.gui_stop.label == tr.gettext("Stop presenting") != "Stop presenting"
    assert lecturer.ask_panel.gui_close.label == tr.gettext("Close the round")
    assert tr.gettext("**Round {number}** · {answered} of {expected} answered · {state}").format(
        number=1, answered=1, expected=1, state=tr.gettext("open")) in lecturer.ask_panel.gui_count.content
    assert lecturer.gui_badge.content == tr.gettext("**● Live** · {following} following · {exploring} exploring"
                                                    ).format(following=1, exploring=0)
    lecturer.close_round()  # the presenter's buttons still act in another language
    lecturer.ask_panel.refresh()
    assert tr.gettext("closed") in lecturer.ask_panel.gui_count.content
    lecturer.set_language("en")
    assert lecturer.gui_stop.label == "Stop presenting" and lecturer.ask_panel.gui_close.label == "Close the round"
    assert lecturer.ask_panel.gui_csv.label == "Download answers (CSV)" and lecturer.error_count == 0


@pytest.mark.parametrize("language", TRANSLATED)
def test_the_ask_form_reads_its_translated_dropdowns(hall: Any, language: str) -> None:
    """The Kind, Right option and Judge dropdowns show words in the language; the question the
    form makes is the same as in English."""
    app, join = hall
    lecturer, _student = join(), join()
    lecturer.set_language(language)
    lecturer.present(app.lectern.code)
    panel = lecturer.ask_panel
    tr = translator(language)
    assert tuple(panel.gui_kind.options) == tuple(tr.gettext(k) for k in ("Choice", "Direction", "State", "Number"))
    assert panel.gui_correct.value == tr.gettext("none") and panel.gui_judge.value == tr.gettext("none")
    panel.gui_kind.value = tr.gettext("Number")  # as the dropdown sends it
    assert panel.forms["number"].gui_value.visible and not panel.gui_options.visible
    panel.gui_kind.value = tr.gettext("Choice")
    panel.gui_prompt.value = "?"
    panel.gui_options.value = "A | B"
    assert panel.form_question().correct is None
    panel.gui_correct.value = "2"
    assert panel.form_question().correct == 1
    panel.gui_kind.value = "Klingon"  # a client can send anything: back to Choice, in the language
    assert panel.gui_kind.value == tr.gettext("Choice") and lecturer.error_count == 0, lecturer.last_error


@pytest.mark.parametrize("language", TRANSLATED)
def test_the_lesson_notes_share_task_and_mine_folders_show_no_english_in_another_language(
        hall: Any, language: str) -> None:
    """Built in the language (the app's default) and switched to it later: the same words."""
    app, join = hall
    english = join()
    app.language = language
    built = join()
    app.language = "en"
    switched = join()
    switched.set_language(language)
    assert built.error_count == 0 and switched.error_count == 0, (built.last_error, switched.last_error)
    english_panel = _folders_part(english)
    for session in (built, switched):
        shown = _folders_part(session)
        assert len(shown) >= 60
        left, same = _english_left(shown, english_panel, language)
        assert left == [] and same == []
    assert sorted(_folders_part(built)) == sorted(_folders_part(switched))
    tr = translator(language)
    assert built.task_panel.gui_open.label == tr.gettext("Open the task") != "Open the task"
    assert built.own_panel.gui_actions.options == tuple(tr.gettext(a) for a in ("Play", "Rename", "Delete"))


def test_the_lecturers_csv_has_its_headers_in_the_lecturers_language_and_numbers_as_written(
        hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """A German lecturer's answers: German column names, the question as typed, numbers with a
    point (machine-readable); the same round downloaded by an English presenter: English headers."""
    import app.hall.ask_presenter as ask_presenter

    saved: list[tuple[str, str]] = []
    monkeypatch.setattr(ask_presenter, "save_download",
                        lambda _client, name, data: saved.append((name, data if isinstance(data, str)
                                                                   else data.decode())))
    app, join = hall
    lecturer, student = join(), join()
    lecturer.set_language("de")
    _round_with_an_answer(app, lecturer, student)
    lecturer.ask_panel.download()
    name, text = saved[-1]
    lines = text.splitlines()
    assert name == "antworten-runde-1.csv"
    assert lines[0] == "# choice: ?"  # the comment line: the question as typed
    header = lines[[k for k, line in enumerate(lines) if not line.startswith("#")][0]]
    assert header == "runde,antwort,sekunden,auswahl,auswahl_text,x,y,z,zustand,bewertet,bewertung,wert"
    row = lines[-1].split(",")
    assert row[:2] == ["1", "1"] and re.fullmatch(r"\d+\.\d\d", row[2]), row  # seconds written with a point
    assert row[3:5] == ["1", "A"]
    lecturer.set_language("en")
    lecturer.ask_panel.download()
    name, text = saved[-1]
    assert name == "answers-round-1.csv"
    assert "round,answer,seconds,option,option_text,x,y,z,state,judged,judged_words,value" in text.splitlines()
    lecturer.set_language("nl")
    lecturer.guard("new question", lambda: lecturer.ask_panel._changed(lecturer.ask_panel.rounds.end))()
    lecturer.ask_panel.download_earlier()
    name, text = saved[-1]
    assert name == "antwoorden-eerdere-rondes.csv"
    assert "ronde,antwoord,seconden,optie,optie_tekst,x,y,z,toestand,beoordeeld,beoordeling,waarde" in text.splitlines()
    assert lecturer.error_count == 0, lecturer.last_error


@pytest.fixture
def task_hall(tmp_path: Path) -> Iterator[Any]:
    """The app without its loop, its data folder a temporary one, the presenter code known."""
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code="24681357",
                            data_dir=tmp_path)
    with browsers_joining(running) as join:
        yield running, join


def test_a_task_made_read_and_downloaded_in_german_and_its_csv_stays_machine_readable(
        task_hall: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """A German presenter makes a number task through the translated form; a Dutch student
    submits; the German lecturer's table and gradebook CSV speak German (header row), the
    score written with a point in the CSV, with a comma in the table."""
    import app.tasks.panel as task_panel

    saved: list[tuple[str, str]] = []
    monkeypatch.setattr(task_panel, "save_download", lambda _client, name, data: saved.append((name, str(data))))
    app, join = task_hall
    lecturer, student = join(), join()
    lecturer.set_language("de")
    student.set_language("nl")
    de, nl = translator("de"), translator("nl")
    with lecturer.lock:
        lecturer.present("24681357")
    ask, maker = lecturer.ask_panel, lecturer.task_panel
    ask.gui_kind.value = de.gettext("Number")
    ask.gui_prompt.value = "T?"
    number = ask.forms["number"]
    number.gui_value.value, number.gui_unit.value, number.gui_tolerance.value = "2.5", "s", "0.2"
    maker.gui_attempts.value = "3"
    maker.gui_counts.value = de.gettext("last")
    with lecturer.lock:
        task = maker.make_from_form()
    assert (task.policy.attempts, task.policy.counts) == (3, "last")
    assert maker.gui_made.content.startswith(f"Aufgabencode **{task.shown_code}**")
    assert "3 Versuche, der letzte zählt" in maker.gui_made.content
    panel = student.task_panel
    panel.open(task.shown_code)
    panel.gui_name.value, panel.gui_value.value = "Ann", 2.6
    assert panel.submit() is not None, panel.gui_note.content
    assert panel.gui_verdict.content.startswith("Jouw poging 1 (Ann)") and "nog 2 pogingen" in panel.gui_verdict.content
    assert panel.gui_submit.label == nl.gettext("Submit")
    with lecturer.lock:
        lecturer.stop_presenting()
    table_panel = lecturer.task_panel
    assert table_panel.open_as_lecturer(task.shown_code, "24681357") is not None, table_panel.gui_note.content
    table = table_panel.gui_table.content
    assert f"**Aufgabe {task.shown_code}** · 1 Frage · fällig" in table
    assert "| Name | Matrikelnummer | Versuche | Punkte | Urteil | Zuletzt abgegeben (UTC) |" in table
    assert "| 1 | 1,00 |" in table and "1 Person, 1 Abgabe" in table and "1 geantwortet · 1 richtig" in table
    table_panel.download()
    name, text = saved[-1]
    assert name == f"aufgabe-{task.shown_code}-ergebnisse.csv"
    header, row = text.splitlines()[:2]
    assert header == "name,matrikelnummer,punkte,versuche,zuletzt_abgegeben,urteil"
    assert row.startswith("Ann,,1.000,1,")  # numbers and the ISO time as a program reads them
    lecturer.set_language("en")  # the table follows the lecturer's language
    assert "| Name | Number | Attempts | Score | Verdict | Last submitted (UTC) |" in table_panel.gui_table.content
    assert lecturer.error_count == 0 and student.error_count == 0, (lecturer.last_error, student.last_error)


def test_a_refused_presenter_code_is_said_in_the_browsers_language_and_stays_true(hall: Any) -> None:
    """A wrong code in a Dutch browser: the Lecture folder's note in Dutch, the tries left counted;
    another presenter busy: said in German; every refusal the lectern words has a translation."""
    from app.hall.lecture_panel import CODE_REFUSALS, refusal_in_language

    app, join = hall
    dutch, german, presenter = join(), join(), join()
    dutch.set_language("nl")
    german.set_language("de")
    dutch.present("not the code")
    assert dutch.mode.name == "OWN"
    assert dutch.gui_lecture_note.content.startswith("**⚠ Verkeerde presentatorcode (nog ")
    assert "pogingen deze minuut).**" in dutch.gui_lecture_note.content
    presenter.present(app.lectern.code)
    german.present(app.lectern.code)
    assert german.gui_lecture_note.content == "**⚠ Jemand anderes trägt vor und muss zuerst aufhören.**"
    dutch.set_language("de")  # the note follows the language when it is said again
    dutch.lecture.show_refusal()
    assert dutch.gui_lecture_note.content.startswith("**⚠ Falscher Vortragscode (noch ")
    nl = translator("nl")
    for pattern, msgid in CODE_REFUSALS.entries:
        english = msgid.format(wait=7)
        assert pattern.fullmatch(english), msgid
        assert refusal_in_language(english, nl) == nl.gettext(msgid).format(wait=7) != english
    assert refusal_in_language("a refusal nobody wrote yet", nl) == "a refusal nobody wrote yet"
    assert dutch.error_count == 0 and german.error_count == 0, (dutch.last_error, german.last_error)


def test_the_mine_folder_says_its_refusals_and_the_notes_name_their_files_in_the_browsers_language(
        task_hall: Any) -> None:
    from app.hall.own_panel import OWN_REFUSALS, own_refusal_words

    app, join = task_hall
    german, follower = join(), join()
    german.set_language("de")
    follower.set_language("nl")
    mine = german.own_panel
    mine.gui_name.value = "   "
    german.guard("save preset", lambda: mine._said(mine.save_preset))()
    assert mine.gui_status.content == "**⚠ gib der Voreinstellung einen Namen**"
    mine.gui_name.value = "Meine"
    german.guard("save preset", lambda: mine._said(mine.save_preset))()
    assert mine.gui_status.content.startswith("**Meine** gespeichert (Euler-Winkel)")
    german.present("24681357")
    poll_until(lambda: (app.frame(1 / 60), follower.mode.name == "FOLLOWING")[1], timeout=10.0)
    follower.own_panel.gui_name.value = "x"
    follower.guard("save preset", lambda: follower.own_panel._said(follower.own_panel.save_preset))()
    assert follower.own_panel.gui_status.content == (
        "**⚠ wie volgt kan niet bewaren: tijdens een college kan alleen de presentator dat**")
    assert german.notes._file_title(german.room) == "euler-winkel"
    de = translator("de")
    for pattern, msgid in OWN_REFUSALS.entries:
        english = msgid.format(most=80, scene="Free body", name="'Spin'", why="no rigid body")
        assert pattern.fullmatch(english), msgid
        assert own_refusal_words(english, de) != english, msgid
    assert own_refusal_words("Free body has a preset named 'Spin' already", de) == (
        "Freier Körper hat schon eine Voreinstellung namens 'Spin'")
    assert german.error_count == 0 and follower.error_count == 0, (german.last_error, follower.last_error)


@pytest.mark.parametrize("title", ["Free body", "Heavy top", "Poinsot"])
def test_the_rigid_bodies_line_of_nodes_reads_german_in_a_german_browser(hall: Any, title: str) -> None:
    """The 3D label of the line of nodes in the rigid-body scenes (their own `LineOfNodes`, not
    the Euler-angles scene's), after a switch to German."""
    _, join = hall
    german = join()
    german.select_scene(title)
    assert german.scene.nodes.label.text.startswith("line of nodes")
    german.set_language("de")
    assert german.scene.nodes.label.text.startswith("Knotenlinie"), german.scene.nodes.label.text
    assert german.error_count == 0, german.last_error
