"""Recordings for lecture notes: `python -m app export` and the panel's Record button."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from app.scenes import SCENES

ROOT = Path(__file__).resolve().parents[1]


def _export(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "app", "export", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=120)


def test_export_writes_a_standalone_html_and_a_viser_file(tmp_path: Path) -> None:
    out = _export("--scene", "Heavy top", "--preset", "Loop", "--seconds", "10", "--out", str(tmp_path / "loop.html"),
                  cwd=ROOT)
    assert out.returncode == 0, out.stderr
    html = (tmp_path / "loop.html").read_text(encoding="utf-8")
    assert "__VISER_EMBED_DATA__" in html and "http://" not in html.split("__VISER_EMBED_DATA__")[1][:100]
    assert len(html) < 3e6  # "at most a few MB for 10 s"
    out = _export("--scene", "Free body", "--seconds", "4", "--out", str(tmp_path / "flip.viser"), cwd=ROOT)
    assert out.returncode == 0, out.stderr
    data = (tmp_path / "flip.viser").read_bytes()
    assert 1000 < len(data) < 1e6


@pytest.mark.parametrize(("args", "message"), [
    (("--scene", "Nope"), "no scene 'Nope'; the scenes are: " + ", ".join(SCENES)),
    (("--scene", "Heavy top", "--preset", "Nope"), "Heavy top has no preset 'Nope'; its presets are: Steady"),
    (("--scene", "Heavy top", "--seconds", "-1"), "seconds = -1.0"),
    (("--scene", "Heavy top", "--seconds", "nan"), "seconds = nan"),
])
def test_export_refuses_a_bad_name_or_value_in_one_line(tmp_path: Path, args: tuple[str, ...], message: str
                                                         ) -> None:
    out = _export(*args, "--out", str(tmp_path / "x.html"), cwd=ROOT)
    assert out.returncode == 2 and message in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x.html").exists()


def test_the_record_button_offers_both_files_and_leaves_the_scene_alone(manual) -> None:
    session = manual.session
    session.select_scene("Heavy top")
    session.apply_preset("Wave")
    session.play()
    manual.tick(0.5)
    t, R = session.simulation.t, session.simulation.state.R_space_body.copy()
    session.record(3, wait=True)
    assert session.last_recording is not None and session.error_count == 0, session.last_error
    html, data = session.last_recording
    assert b"__VISER_EMBED_DATA__" in html and len(data) > 1000
    assert session.simulation.t == t and (session.simulation.state.R_space_body == R).all()
    session.guard("record", session.record)(1e6)  # out of range: refused with a message
    assert session.error_count == 1 and "refused" in (session.last_error or "")
