"""The lecturer's own presets and lessons in the data folder (app.own), without a browser: what is
kept, what is refused (with the file and the field named), and that the package is never written."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest

from app.data import files_in, lessons_dir, presets_dir
from app.kit.core.room import Room
from app.lessons import LessonError
from app.main import _parse_args
from app.own import OwnLibrary
from app.scenes import SCENES


def _package_digest() -> str:
    digest = hashlib.sha256()
    for folder in (presets_dir(), lessons_dir()):
        for path in files_in(folder, ".json"):
            digest.update(path.read_bytes())
    return digest.hexdigest()


def _moment(title: str, preset: str | None = None, seconds: float = 0.5) -> Room:
    scene = SCENES[title]
    room = Room(scene, scene.new_simulation())
    if preset is not None:
        scene.apply_preset(room, preset)
    room.play()
    for _ in range(round(seconds * 60)):
        room.advance(1.0 / 60.0)
    return room


def test_a_saved_moment_is_kept_and_starts_where_it_was(tmp_path: Path) -> None:
    before = _package_digest()
    room = _moment("Free body", "Dzhanibekov", seconds=1.0)
    scene = room.scene
    OwnLibrary(tmp_path, SCENES).save_preset("Free body", scene.moment_preset(room, "  mid   flip "))
    library = OwnLibrary(tmp_path, SCENES)  # read again, as after a restart
    (kept,) = library.presets("Free body")
    assert kept.name == "mid flip" and kept.group == "Mine" and "Dzhanibekov" in kept.note
    again = Room(scene, scene.new_simulation())
    scene.start_preset(again.sim, kept)
    np.testing.assert_allclose(again.sim.state.R_space_body, room.sim.state.R_space_body, atol=1e-12)
    np.testing.assert_allclose(again.sim.state.omega_body, room.sim.state.omega_body, atol=1e-12)
    assert json.loads((tmp_path / "presets" / "free_body.json").read_text())["scene"] == "Free body"
    assert _package_digest() == before, "the package's presets and lessons are never written"


def test_names_are_checked_and_presets_renamed_and_deleted(tmp_path: Path) -> None:
    library = OwnLibrary(tmp_path, SCENES)
    room = _moment("Heavy top", "Loop")
    moment = room.scene.moment_preset
    with pytest.raises(ValueError, match="has a preset 'Loop' of its own"):
        library.save_preset("Heavy top", moment(room, "Loop"))
    with pytest.raises(ValueError, match="give the preset a name"):
        library.save_preset("Heavy top", moment(room, "   "))
    library.save_preset("Heavy top", moment(room, "A"))
    library.save_preset("Heavy top", moment(room, "B"))
    with pytest.raises(ValueError, match="named 'B' already"):
        library.rename_preset("Heavy top", "A", "B")
    library.rename_preset("Heavy top", "A", "C")
    library.delete_preset("Heavy top", "B")
    assert [p.name for p in OwnLibrary(tmp_path, SCENES).presets("Heavy top")] == ["C"]
    with pytest.raises(ValueError, match="cannot keep what it shows"):
        SCENES["Inertia"].moment_preset(_moment("Inertia"), "x")


def test_a_broken_own_file_is_left_out_and_named(tmp_path: Path) -> None:
    (tmp_path / "presets").mkdir()
    (tmp_path / "presets" / "heavy_top.json").write_text(json.dumps({"presets": [
        {"name": "x", "params": {"I1": 1, "I3": 0.5, "mgl": 99}, "angles_deg": [0, 60, 0],
         "rates": {"spin": 1, "phi_dot": 0, "theta_dot": 0}}]}))
    library = OwnLibrary(tmp_path, SCENES)
    assert library.presets("Heavy top") == ()
    (problem,) = library.problems
    assert "heavy_top.json: presets[0].params.mgl: 99" in problem


def test_a_lesson_that_does_not_load_is_refused_with_file_and_field_and_nothing_written(tmp_path: Path) -> None:
    library = OwnLibrary(tmp_path, SCENES)
    bad = {"title": "Bad", "steps": [{"scene": "Heavy top", "preset": "Loop", "text": "ok"},
                                     {"scene": "Heavy top", "camera": {"position": [1, 2], "look_at": [0, 0, 0]},
                                      "text": "bad camera"}]}
    with pytest.raises(LessonError, match=r"^bad\.json: steps\[1\]\.camera\.position: three finite numbers"):
        library.import_lesson("bad.json", json.dumps(bad).encode())
    with pytest.raises(LessonError, match=r"^notes\.json: not readable JSON"):
        library.import_lesson("notes.json", b"{nope")
    assert not tmp_path.exists() or not any(tmp_path.rglob("*.json"))
    lesson = library.add_step("Mine", {"scene": "Heavy top", "preset": "Loop", "text": "loops"})
    assert len(lesson.steps) == 1
    with pytest.raises(LessonError, match=r"steps\[1\]\.text: missing"):
        library.add_step("Mine", {"scene": "Heavy top", "text": " "})
    assert len(OwnLibrary(tmp_path, SCENES).lessons()["Mine"].steps) == 1


def test_the_command_line_takes_a_data_folder() -> None:
    assert _parse_args(["--data-dir", "/tmp/lecture"]).data_dir == "/tmp/lecture"
    assert _parse_args([]).data_dir is None
