"""Lessons: the shipped files load, each step applies (scene, preset, toggles, play), a presenter's
followers see the step, and a broken file is refused naming the file and the step."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from app.lessons import LESSONS_DIR, LessonError, lessons, load_lesson
from app.scenes import SCENES


def test_the_shipped_lessons_load_and_every_step_applies(manual) -> None:
    shipped = lessons()
    assert {"§1 Euler angles and ω", "§4 Inertial forces in a moving frame", "§5 Lagrange's equations, live",
            "§6 The free body and the heavy top"} <= {lesson.title for lesson in shipped}
    session = manual.session
    for lesson in shipped:
        session.gui_lesson.value = lesson.title  # the dropdown: runs its first step
        for k, step in enumerate(lesson.steps):
            if k:
                session.next_step(1)
            assert session.lesson_step == k and session.room.scene.title == step.scene
            if step.preset is not None:
                assert session.simulation.preset == step.preset
            if step.play is not None:
                assert session.room.playing is step.play
            toggles = {label: h.value for label, h in session.scene.checkboxes().items()}
            assert all(toggles[label] == value for label, value in step.display.items()), (lesson.title, k)
            if step.tab is not None:
                assert session.scene.tabs.shown == step.tab
            if step.integrator is not None:
                assert session.simulation.integrator == step.integrator
            assert step.text in session.gui_lesson_text.content
            manual.tick(0.2)
        session.next_step(1)  # past the end: stays on the last step
        assert session.lesson_step == len(lesson.steps) - 1
    assert session.error_count == 0, session.last_error


@pytest.mark.parametrize(("edit", "message"), [
    (lambda d: d["steps"][1].update(scene="Nope"), r"steps\[1\]\.scene: 'Nope' is not a scene"),
    (lambda d: d["steps"][0].update(preset="Nope"), r"steps\[0\]\.preset: Euler angles has no preset 'Nope'"),
    (lambda d: d["steps"][2].pop("text"), r"steps\[2\]\.text: missing"),
    (lambda d: d["steps"][3].update(camera={"position": [1, 2], "look_at": [0, 0, 0]}),
     r"steps\[3\]\.camera\.position: three finite numbers"),
    (lambda d: d["steps"][0].update(colour="red"), r"steps\[0\]: unknown field 'colour'"),
    (lambda d: d.update(steps=[]), r"steps: missing or empty"),
    (lambda d: d["steps"][0].update(ask={"kind": "choice", "prompt": "x", "options": ["a"]}),
     r"steps\[0\]\.ask\.options: 2 to 6 options wanted"),
    (lambda d: d["steps"][1].update(ask={"kind": "state", "prompt": "x", "scene": "Nope"}),
     r"steps\[1\]\.ask\.scene: 'Nope' is not a scene"),
])
def test_a_broken_lesson_is_refused_naming_the_file_and_the_step(tmp_path: Path, edit, message: str) -> None:
    data = json.loads((LESSONS_DIR / "1_euler_angles.json").read_text(encoding="utf-8"))
    edit(data)
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(LessonError, match=str(path).replace(".", r"\.") + ": " + message):
        load_lesson(path, SCENES)


def test_a_presenters_lesson_reaches_the_followers() -> None:
    from conftest import RawClient

    from app.main import create_server

    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code="1")
    clients = [RawClient(app.port), RawClient(app.port)]
    try:
        a, b = app.wait_for_sessions(2).values()
        a.present("1")
        app.lectern.tick(1 / 60)  # the loop moves the other browser to follow
        a.start_lesson("§6 The free body and the heavy top")
        a.next_step(1)
        assert b.mode == "following" and "Feynman's wobbling plate" in b.scene.gui_status.content
        b.guard("lesson", b.start_lesson)("§1 Euler angles and ω")  # a follower cannot run one
        assert b.error_count == 1 and a.room.scene.title == "Free body"
    finally:
        for client in clients:
            client.close()
        app.stop()
