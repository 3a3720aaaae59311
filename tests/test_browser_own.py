"""The lecturer's own presets and lessons (app.own, the Mine folder), through the page in Debian's
Chromium, and who may save (raw websocket clients standing in for a presenter's class).

1. Save a moment of the heavy top as a preset, stop the app, start another on the same data
   folder: the preset is listed (★) and plays from the saved state.
2. Build a two-step lesson, export it, import it into an app on a fresh data folder, step
   through it; a broken lesson file is refused with the file and the field named, nothing written.
3. A follower, and a student exploring while the lecture is on, cannot save into the presenter's
   data folder; the presenter can.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import poll_until
from test_browser import choose, open_app
from test_browser_messages import choose_scene, download

from app.main import App, create_server
from physics.euler import matrix_from_euler_zxz

CODE = "135791"


@pytest.fixture
def apps():  # type: ignore[no-untyped-def]
    """start(data_dir) -> a running app on it; all stopped after the test."""
    running: list[App] = []

    def start(data_dir: Path, **options) -> App:  # type: ignore[no-untyped-def]
        app = create_server("127.0.0.1", 0, verbose=False, data_dir=data_dir, **options)
        running.append(app)
        return app

    yield start
    for app in running:
        app.stop()


def field(page, label: str):  # type: ignore[no-untyped-def]
    """The text field labelled exactly `label`."""
    row = page.locator("label", has_text=re.compile(f"^{re.escape(label)}$")).first.locator(
        "xpath=ancestor::div[contains(@class, 'Flex-root')][1]")
    return row.locator("input").first


def type_into(page, label: str, text: str, handle) -> None:  # type: ignore[no-untyped-def]
    """Type `text` into the field `label` and wait until the server has it (`handle.value`)."""
    box = field(page, label)
    box.click()
    box.press("Control+A")
    page.keyboard.type(text, delay=10)
    box.press("Enter")
    poll_until(lambda: handle.value == text, timeout=10.0)


def open_mine(page) -> None:  # type: ignore[no-untyped-def]
    page.get_by_text("Mine", exact=True).first.click()
    page.get_by_role("button", name="Save as preset").wait_for(state="visible", timeout=10_000)


pytestmark = pytest.mark.browser


def test_a_saved_preset_survives_a_restart_and_plays(browser, apps, tmp_path: Path, wait_until) -> None:
    data = tmp_path / "data"
    app = apps(data)
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    try:
        session = open_app(page, app)
        choose_scene(page, session, "Heavy top", wait_until)
        page.get_by_role("button", name="Loop").click()
        wait_until(lambda: session.room.sim.preset == "Loop", timeout=10.0)
        page.get_by_role("button", name="Play", exact=True).click()
        wait_until(lambda: session.room.playing and session.room.sim.t > 0.3, timeout=20.0)
        page.get_by_role("button", name="Pause", exact=True).click()
        wait_until(lambda: not session.room.playing, timeout=10.0)
        sim = session.room.sim
        R_saved, omega_saved = sim.state.R_space_body.copy(), sim.state.omega_body.copy()
        open_mine(page)
        type_into(page, "Name", "Loop at its top", session.own_panel.gui_name)
        page.get_by_role("button", name="Save as preset").click()
        wait_until(lambda: (data / "presets" / "heavy_top.json").is_file(), timeout=10.0)
        page.get_by_text("Saved Loop at its top").first.wait_for(timeout=10_000)
    finally:
        page.close()
    app.stop()

    again = apps(data)  # a restart: a new app on the same data folder
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    try:
        session = open_app(page, again)
        choose_scene(page, session, "Heavy top", wait_until)
        page.get_by_text("★ Mine", exact=True).first.wait_for(timeout=10_000)  # a row beside the scene's presets
        page.get_by_role("button", name="Loop at its top").click()
        wait_until(lambda: session.room.sim.preset == "Loop at its top", timeout=10.0)
        page.get_by_role("button", name="Play", exact=True).click()
        room = session.room
        wait_until(lambda: room.sim.preset == "Loop at its top" and room.playing, timeout=10.0)
        start = room.sim.initial_state
        np.testing.assert_allclose(start.R_space_body, R_saved, atol=1e-9)
        np.testing.assert_allclose(start.omega_body, omega_saved, rtol=1e-9, atol=1e-9)
        preset = again.own.preset("Heavy top", "Loop at its top")
        np.testing.assert_allclose(matrix_from_euler_zxz(*np.radians(preset.angles_deg)), R_saved, atol=1e-9)
        assert not (Path(__file__).parents[1] / "assets" / "presets" / "heavy_top.json").read_text(
            encoding="utf-8").count("Loop at its top"), "nothing is written into the package"
    finally:
        page.close()


def test_a_two_step_lesson_exports_imports_into_a_fresh_folder_and_steps(browser, apps, tmp_path: Path,
                                                                          wait_until) -> None:
    maker = apps(tmp_path / "mine")
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    try:
        session = open_app(page, maker)
        choose_scene(page, session, "Free body", wait_until)
        page.get_by_role("button", name="Dzhanibekov").click()
        wait_until(lambda: session.room.sim.preset == "Dzhanibekov", timeout=10.0)
        open_mine(page)
        type_into(page, "My lesson", "Two motions", session.own_panel.gui_lesson_title)
        type_into(page, "Step text", "The book flips every 3.9 s.", session.own_panel.gui_step_text)
        page.get_by_role("button", name="Add to lesson").click()
        page.get_by_text("Two motions: 1 step").first.wait_for(timeout=10_000)
        choose_scene(page, session, "Heavy top", wait_until)
        page.get_by_role("button", name="Loop").click()
        wait_until(lambda: session.room.sim.preset == "Loop", timeout=10.0)
        type_into(page, "Step text", "The tip draws loops.", session.own_panel.gui_step_text)
        page.get_by_role("button", name="Add to lesson").click()
        page.get_by_text("Two motions: 2 steps").first.wait_for(timeout=10_000)
        name, exported = download(page, lambda: page.get_by_role("button", name="Export lesson").click())
    finally:
        page.close()
    assert name == "Two_motions.json"
    lesson = json.loads(exported)
    assert [(s["scene"], s.get("preset"), s["text"]) for s in lesson["steps"]] == [
        ("Free body", "Dzhanibekov", "The book flips every 3.9 s."), ("Heavy top", "Loop", "The tip draws loops.")]
    assert all(len(s["camera"]["position"]) == 3 for s in lesson["steps"])

    fresh = tmp_path / "fresh"
    taker = apps(fresh)
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"title": "Broken", "steps": [lesson["steps"][0], {
        **lesson["steps"][1], "preset": "Loop-de-loop"}]}), encoding="utf-8")
    exported_path = tmp_path / name
    exported_path.write_bytes(exported)
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    try:
        session = open_app(page, taker)
        open_mine(page)
        upload = page.locator("input[type=file]").first
        upload.set_input_files(str(broken))
        page.get_by_text(re.compile(r"broken\.json: steps\[1\]\.preset: Heavy top has no preset 'Loop-de-loop'"))\
            .first.wait_for(timeout=10_000)
        assert not (fresh / "lessons").exists() or not list((fresh / "lessons").iterdir()), "nothing written"
        upload.set_input_files(str(exported_path))
        page.get_by_text("Imported Two motions (2 steps").first.wait_for(timeout=10_000)
        page.get_by_text("Lesson", exact=True).first.click()
        choose(page, session.lesson_runner.gui_lesson, "★ Two motions")
        wait_until(lambda: session.lesson_runner.step == 0 and session.room.sim.preset == "Dzhanibekov"
                   and session.scene.title == "Free body", timeout=10.0)
        page.get_by_role("button", name="Next ▶").click()
        wait_until(lambda: session.lesson_runner.step == 1 and session.room.sim.preset == "Loop"
                   and session.scene.title == "Heavy top", timeout=10.0)
        page.get_by_text("The tip draws loops.").locator("visible=true").first.wait_for(timeout=10_000)
    finally:
        page.close()


def test_only_the_presenter_saves_into_the_data_folder(apps, tmp_path: Path, wait_until) -> None:
    from conftest import RawClient

    data = tmp_path / "data"
    app = apps(data, presenter_code=CODE)
    clients = [RawClient(app.port) for _ in range(3)]
    try:
        sessions = app.wait_for_sessions(3, timeout=30.0)
        presenter, follower, student = (sessions[cid] for cid in sorted(sessions))
        by_session = dict(zip(sorted(sessions), clients))
        presenter.select_scene("Free body")
        presenter.present(CODE)
        wait_until(lambda: follower.mode == "following" and student.mode == "following", timeout=10.0)
        student.explore()
        wait_until(lambda: student.mode == "own", timeout=10.0)
        for session in (follower, student):
            client = by_session[session.client_id]
            client.set_value(session.own_panel.gui_name, "Mine now")
            client.send(_click(session.own_panel.gui_save))
            wait_until(lambda s=session: "only the presenter" in str(s.own_panel.gui_status.content), timeout=10.0)
        assert not data.exists(), "a follower's or a student's Save wrote nothing"
        assert presenter.error_count == follower.error_count == student.error_count == 0
        client = by_session[presenter.client_id]
        client.set_value(presenter.own_panel.gui_name, "The lecturer's")
        client.send(_click(presenter.own_panel.gui_save))
        wait_until(lambda: app.own.preset("Free body", "The lecturer's") is not None, timeout=10.0)
        assert (data / "presets" / "free_body.json").is_file()
    finally:
        for client in clients:
            client.close()


def _click(handle):  # type: ignore[no-untyped-def]
    from viser import _messages

    return _messages.GuiUpdateMessage(handle._impl.uuid, {"value": True})
