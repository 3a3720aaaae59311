"""benchmarks/realtime_cost.py runs both trees and prints figures (never timing thresholds: those
are the script's output); the two trees' CLI trajectories agree to round-off."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import realtime_cost  # noqa: E402


def test_realtime_cost_compares_this_tree_with_the_issue_baseline(capsys: pytest.CaptureFixture[str]) -> None:
    assert realtime_cost.main(["--cases", "heavy_top", "--frame-dt", "1/240", "--seconds", "0.05", "--runs", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "app @ 21f6295 = RealtimeStepper.step" in lines[0] and "app = GridStepper.step" in lines[0]
    row = [cell.strip() for cell in lines[-1].strip("|").split("|")]
    assert row[:2] == ["heavy_top", "1/240"]
    figures = [float(cell) for cell in row[2:-1]]  # ms per simulated second, both trees, three paths
    assert len(figures) == 6 and all(math.isfinite(f) and f > 0.0 for f in figures)
    assert float(row[-1]) < 1e-12  # the same method: trajectories differ by round-off only [rad]


def test_frame_steps_are_read_as_the_cli_reads_them() -> None:
    assert realtime_cost.seconds("1/240") == 1.0 / 240.0
    assert realtime_cost.seconds("0.01") == 0.01
