"""The speed-against-error benchmark runs and reports numbers (no timing thresholds here)."""

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.skipif(importlib.util.find_spec("matplotlib") is None, reason="pip install matplotlib")
def test_quick_run_writes_table_and_plot(tmp_path):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import work_precision

    out, png = tmp_path / "results.md", tmp_path / "plot.png"
    assert work_precision.main(["--quick", "--cases", "heavy_top", "--out", str(out), "--plot", str(png)]) == 0
    table = out.read_text()
    for method in ("dop853 (scipy)", "adaptive", "splitting4", "exact"):
        assert f"| heavy_top | exact solution | {method} |" in table
    assert "fails" not in table
    assert png.stat().st_size > 10_000
