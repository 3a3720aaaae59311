"""A lesson file's faults in a step's `ask` (its question, a State question's `target`) and a
rigid body's run stopped or refused by its integrator, said in the reader's language (issue 38):
the lesson loader and the simulation keep English (the logs, the app's start), the panel writes
them in the browser's language.  Server side, through the sessions of raw websocket clients."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest
from test_i18n_refusals import hall  # noqa: F401 - the fixture: the app and join(language)

from app.i18n import translator
from app.lessons import LessonError, load_lesson
from tests.conftest import poll_until

STEP = {"scene": "Heavy top", "text": "t"}
ATTITUDE = {"kind": "state", "prompt": "Where?", "judge": "attitude"}


def _imported(session: Any, name: str, ask: Any) -> str:
    """`session`'s own-lesson import of a one-step lesson whose step asks `ask`: what it says."""
    from viser._gui_handles import UploadedFile

    mine = session.own_panel
    lesson = {"title": "Vraag", "steps": [{**STEP, "ask": ask}]}
    mine.gui_import._impl.value = UploadedFile(name, json.dumps(lesson).encode())
    session.guard("import lesson", lambda: mine._said(mine.import_uploaded))()
    return str(mine.gui_status.content)


def test_a_lesson_steps_bad_question_and_target_are_said_in_dutch_and_german(hall: Any) -> None:  # noqa: F811
    """A Dutch and a German lecturer import lessons whose step's `ask` is broken (the question's
    words, its options, a State question's judge and target): each reads the file, the field and
    the fault in their language, the values the file must hold as the file spells them."""
    _app, join = hall
    dutch, german = join("nl"), join("de")
    for session, name, ask, said in (
            (dutch, "leeg.json", {"kind": "choice", "options": ["a", "b"]},
             "**⚠ leeg.json: steps[0].ask.prompt: de tekst van de vraag ontbreekt**"),
            (dutch, "dubbel.json", {"kind": "choice", "prompt": "?", "options": ["a", "a"]},
             "**⚠ dubbel.json: steps[0].ask.options: twee antwoordmogelijkheden zijn gelijk**"),
            (german, "richter.json", {**ATTITUDE, "judge": "nope"},
             "**⚠ richter.json: steps[0].ask.judge: 'nope' ist keine Bewertung (attitude, top_motion, axis_stays)**"),
            (german, "ziel.json", {**ATTITUDE, "target": {"angles_deg": [0, 90, 0], "within": 5}},
             "**⚠ ziel.json: steps[0].ask.target: 'within' ist kein Feld der Bewertung attitude "
             "(angles_deg, R_space_body, within_deg)**"),
            (german, "weit.json", {**ATTITUDE, "target": {"angles_deg": [0, 90, 0], "within_deg": 200.5}},
             "**⚠ weit.json: steps[0].ask: within_deg des Ziels muss eine Zahl in [0; 180] sein, erhalten: 200.5**"),
            (dutch, "as.json", {**ATTITUDE, "judge": "axis_stays", "target": {"axis": 4}},
             "**⚠ as.json: steps[0].ask.target: axis moet 0, 1 of 2 zijn (x′, y′, z′), gekregen: 4**"),
            (dutch, "geen.json", {**ATTITUDE},
             "**⚠ geen.json: steps[0].ask: de beoordeling attitude heeft een doel nodig: "
             "{\"angles_deg\": [φ, θ, ψ]}**"),
    ):
        shown = _imported(session, name, ask)
        assert shown == said, shown
        for english in ("wanted", "missing", "is not", "needs a target", "must be", "the same"):
            assert english not in shown, (english, shown)
    assert dutch.error_count == 0 and german.error_count == 0, (dutch.last_error, german.last_error)


def test_every_question_fault_a_lesson_can_hold_is_written_whole_in_english_and_otherwise_in_dutch(
        tmp_path: Path) -> None:
    """Each `ask` fault the lesson loader writes (the question's own check and its judge's) is one
    `LESSON_FIELD_ERRORS` knows: a field's path, then words the Dutch catalog writes otherwise."""
    from app.lesson_errors import LESSON_FIELD_ERRORS
    from app.scenes import SCENES

    asks: list[Any] = [
        {"kind": "choice", "prompt": "x" * 301, "options": ["a", "b"]},
        {"kind": "choice", "prompt": "p", "options": "ab"},
        {"kind": "choice", "prompt": "p", "options": ["a"]},
        {"kind": "choice", "prompt": "p", "options": ["a", "b" * 81]},
        {"kind": "choice", "prompt": "p", "options": ["a", "b"], "correct": 5},
        {"kind": "choice", "prompt": "p", "options": ["a", "b"], "truth": 1},
        {"kind": "number", "prompt": "p", "value": "x", "unit": "s", "tolerance": 0.1},
        {"kind": "number", "prompt": "p", "value": 1e13, "unit": "s", "tolerance": 0.1},
        {"kind": "number", "prompt": "p", "value": 1, "unit": "s" * 21, "tolerance": 0.1},
        {"kind": "number", "prompt": "p", "value": 1, "unit": "s", "tolerance": -0.5},
        {"kind": "direction", "prompt": "p", "truth": [0, 0]},
        {"kind": "direction", "prompt": "p", "truth": [0, 0, 0]},
        {"kind": "direction", "prompt": "p", "frame": "body"},
        {"kind": "vote", "prompt": "p"},
        3,
        {**ATTITUDE, "target": [1]},
        {**ATTITUDE, "target": {"angles_deg": [1, 2]}},
        {**ATTITUDE, "target": {"within_deg": 10}},
        {**ATTITUDE, "judge": "top_motion", "target": {"motion": "dance"}},
        {**ATTITUDE, "judge": "axis_stays", "target": {"stays": 1}},
        {**ATTITUDE, "judge": "axis_stays", "target": {"x": "y" * 5000}},
        {**ATTITUDE, "scene": 3},
    ]
    dutch = translator("nl")
    for k, ask in enumerate(asks):
        path = tmp_path / f"les{k}.json"
        path.write_text(json.dumps({"title": "T", "steps": [{**STEP, "ask": ask}]}), encoding="utf-8")
        with pytest.raises(LessonError) as broken:
            load_lesson(path, SCENES)
        fault = str(broken.value).removeprefix(f"{path}: ")
        assert fault.startswith("steps[0].ask") and not fault.startswith("steps[0].ask. "), fault
        written = LESSON_FIELD_ERRORS.words(fault, dutch)
        assert written is not None and written != fault, fault


def _said(scene: Any) -> str:
    """The scene's message line, without its warning's marks (`**⚠ ...**`)."""
    return str(scene.message.text).removeprefix("**⚠ ").removesuffix("**")


def _heavy_top(join: Any, language: str, preset: str) -> tuple[Any, Any]:
    session = join(language)
    session.select_scene("Heavy top")
    session.apply_preset(preset)
    return session, session.scene


def test_the_euler_angle_lagrangian_stopping_at_the_vertical_is_said_in_german(hall: Any) -> None:  # noqa: F811
    """A German browser runs the heavy top through the vertical with the Euler-angle Lagrangian:
    the stop (the singular Lagrangian, going on with the splitting) is said in German, the
    numbers with a decimal comma, the methods' names as the dropdown shows them."""
    _app, join = hall
    session, scene = _heavy_top(join, "de", "Through the vertical")
    scene.transport.gui_integrator.value = "euler_lagrange"
    assert scene.sim.integrator == "euler_lagrange"
    session.play()
    poll_until(lambda: (session.tick(0.05), not scene.room.playing)[1], timeout=30.0,
               what="the run stopped at the vertical", seen=lambda: (scene.sim.t, scene.message.text))
    text = _said(scene)
    assert text.startswith("Die Simulation wurde angehalten: euler_lagrange wurde angehalten: die Lagrange-Funktion "
                           "in Euler-Winkeln ist singulär bei θ = "), text
    assert text.endswith("Drücke Abspielen, um mit splitting4 weiterzurechnen."), text
    assert "singular" not in text and "stopped" not in text and "Press Play" not in text, text
    theta = text.split("θ = ", 1)[1].split(" rad", 1)[0]
    assert "," in theta and "." not in theta, theta  # a number a person reads: the German decimal comma
    assert session.error_count == 0, session.last_error


def test_choosing_the_euler_angle_lagrangian_at_the_vertical_is_refused_in_dutch(hall: Any) -> None:  # noqa: F811
    """A Dutch browser sets θ = 0 and picks the Euler-angle Lagrangian: refused in Dutch, the
    method in use kept; an English browser reads the simulation's own words."""
    _app, join = hall
    for language, starts, ends in (
            ("nl", "euler_lagrange kan vanaf hier niet verder: de Lagrangiaan in Euler-hoeken is singulier bij θ = 0 "
                   "rad (sin θ in een noemer, sin θ = 0), al in de begintoestand, t = 0 s; kies een andere methode",
             ". splitting4 blijft in gebruik."),
            ("en", "euler_lagrange cannot go on from here: the Euler-angle Lagrangian is singular at θ = 0 rad",
             ". Staying with splitting4."),
    ):
        session, scene = _heavy_top(join, language, "Steady")
        scene.gui_angles[1].value = 0.0  # θ: the top upright
        assert math.sin(scene.sim.angles[1]) == pytest.approx(0.0, abs=1e-12)
        scene.transport.gui_integrator.value = "euler_lagrange"
        text = _said(scene)
        assert scene.sim.integrator == "splitting4", scene.sim.integrator
        assert text.startswith(starts) and text.endswith(ends), text
        assert session.error_count == 0, session.last_error
