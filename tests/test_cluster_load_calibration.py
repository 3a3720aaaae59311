"""The calibration of benchmarks/cluster_load.py's tables, without servers: the ratios to the
reference, the order of the interleaved runs, the refusal on a busy machine (load average and
CPU probe replaced), the reading of /proc/stat and the Markdown the table is written in."""

from __future__ import annotations

import contextlib
import datetime
import math
from pathlib import Path

import pytest

from benchmarks import cluster_load
from benchmarks.cluster_load import REF, THIS, Measured, ReportInfo

CLK_TCK = cluster_load.CLK_TCK


def test_ratio_is_this_over_the_reference_and_nan_without_a_usable_reference() -> None:
    assert cluster_load.ratio(42.4, 40.0) == pytest.approx(1.06)
    assert cluster_load.ratio(0.0, 40.0) == 0.0
    for value, reference in [(42.4, 0.0), (42.4, -1.0), (math.nan, 40.0), (42.4, math.nan), (-1.0, 40.0),
                             (math.inf, 40.0)]:
        assert math.isnan(cluster_load.ratio(value, reference)), (value, reference)


def test_runs_interleave_in_mirrored_pairs() -> None:
    assert cluster_load.interleaved(1, True) == [THIS, REF]
    assert cluster_load.interleaved(2, True) == [THIS, REF, REF, THIS]
    assert cluster_load.interleaved(3, True) == [THIS, REF, REF, THIS, THIS, REF]
    assert cluster_load.interleaved(2, False) == [THIS, THIS]


def test_busy_reason_names_the_load_average_and_the_probe() -> None:
    assert cluster_load.busy_reason(0.9, 2, (0.1, 0.0), 0.5) is None
    by_load = cluster_load.busy_reason(1.2, 2, (0.1, 0.0), 0.5)
    assert by_load is not None and "1.20 on 2 cores" in by_load and "0.60 a core" in by_load
    assert "probe" not in by_load
    by_probe = cluster_load.busy_reason(0.2, 2, (0.45, 0.15), 0.5)  # stolen time counts as busy
    assert by_probe is not None and "45 % of the cores busy and 15 % stolen" in by_probe
    assert "load average" not in by_probe


def test_machine_sample_reads_busy_and_stolen_time_from_proc_stat() -> None:
    # user nice system idle iowait irq softirq steal guest guest_nice
    text = "cpu  1000 20 300 5000 70 0 8 40 0 0\ncpu0 1 2 3 4 5 6 7 8 0 0\n"
    sample = cluster_load.sample_machine(text)
    assert sample.busy_s == pytest.approx((1000 + 20 + 300 + 0 + 8) / CLK_TCK)
    assert sample.steal_s == pytest.approx(40 / CLK_TCK)
    later = cluster_load.MachineSample(sample.busy_s + 1.5, sample.steal_s + 0.25, sample.wall_s + 2.0)
    assert cluster_load.machine_percent(sample, later) == pytest.approx((75.0, 12.5))


@pytest.fixture
def no_measurement(monkeypatch: pytest.MonkeyPatch) -> list[tuple]:
    """cluster_load.run and reference_tree replaced: the calls are recorded, nothing is started;
    the fake run returns one row's runs (this tree faster than the reference)."""
    calls: list[tuple] = []

    def fake_run(cases, order, roots, warmup, seconds, report=print):
        calls.append(("run", cases, order, roots))
        return [Measured("1 process", "80 own rooms", tree, [40.0, 44.0] if tree == THIS else [38.0, 40.0],
                         {"app": 90.0}, 30.0, 5.0, 0.0) for tree in order]

    @contextlib.contextmanager
    def fake_tree(rev):
        calls.append(("tree", rev))
        yield Path("/nonexistent/reference")

    monkeypatch.setattr(cluster_load, "run", fake_run)
    monkeypatch.setattr(cluster_load, "reference_tree", fake_tree)
    return calls


def test_a_busy_machine_is_refused_before_anything_starts(monkeypatch, no_measurement, tmp_path, capsys) -> None:
    monkeypatch.setattr(cluster_load.os, "getloadavg", lambda: (3.8, 3.0, 2.5))
    monkeypatch.setattr(cluster_load, "cpu_probe", lambda seconds=2.0: (0.05, 0.0))
    output = tmp_path / "table.md"
    with pytest.raises(SystemExit) as refused:
        cluster_load.main(["--rooms", "80", "--followers", "", "--output", str(output)])
    assert refused.value.code == 2
    message = capsys.readouterr().err
    assert "busy" in message and "load average 3.80" in message and "--force" in message
    assert no_measurement == [] and not output.exists()


def test_a_busy_probe_is_refused_even_with_a_low_load_average(monkeypatch, no_measurement, capsys) -> None:
    monkeypatch.setattr(cluster_load.os, "getloadavg", lambda: (0.1, 0.1, 0.1))
    monkeypatch.setattr(cluster_load, "cpu_probe", lambda seconds=2.0: (0.9, 0.0))
    with pytest.raises(SystemExit) as refused:
        cluster_load.main(["--rooms", "80", "--followers", "", "--reference", "none"])
    assert refused.value.code == 2 and "90 % of the cores busy" in capsys.readouterr().err
    assert no_measurement == []


def test_force_measures_and_marks_the_table_busy(monkeypatch, no_measurement, tmp_path) -> None:
    monkeypatch.setattr(cluster_load.os, "getloadavg", lambda: (3.8, 3.0, 2.5))
    monkeypatch.setattr(cluster_load, "cpu_probe", lambda seconds=2.0: (0.05, 0.0))
    output = tmp_path / "table.md"
    cluster_load.main(["--rooms", "80", "--followers", "", "--force", "--reference", "none", "--output", str(output)])
    table = output.read_text()
    assert "measured on a busy machine" in table.splitlines()[0]
    assert "**Measured on a busy machine** (`--force`): 1-minute load average 3.80" in table
    assert [c[0] for c in no_measurement] == ["run"]


def test_a_quiet_machine_measures_the_reference_interleaved(monkeypatch, no_measurement, tmp_path) -> None:
    monkeypatch.setattr(cluster_load.os, "getloadavg", lambda: (0.3, 0.3, 0.3))
    monkeypatch.setattr(cluster_load, "cpu_probe", lambda seconds=2.0: (0.05, 0.01))
    output = tmp_path / "table.md"
    cluster_load.main(["--rooms", "80", "--followers", "", "--reference", "HEAD", "--output", str(output)])
    (tree_call, rev), run_call = no_measurement
    assert tree_call == "tree" and len(rev) >= 7 and all(c in "0123456789abcdef" for c in rev)
    _run, cases, order, roots = run_call
    assert cases == [("rooms", 80)] and order == [THIS, REF, REF, THIS]
    assert roots == {THIS: None, REF: Path("/nonexistent/reference")}
    table = output.read_text()
    assert "busy machine" not in table and f"reference: {rev} (`--reference HEAD`)" in table
    assert "| 1 process | 80 own rooms | this tree | 40.0 / 42.0 | ×1.05 / ×1.08 |" in table


def _info(**changes) -> ReportInfo:
    info = ReportInfo(datetime.datetime(2026, 11, 28, 6, 5, tzinfo=datetime.UTC),
                      datetime.datetime(2026, 11, 28, 6, 19, tzinfo=datetime.UTC), "abc1234", ("v1", "def5678"),
                      2, "AMD EPYC", "3.11.7", 0.31, 1.95, (0.04, 0.01), None, 3.0, 8.0, [THIS, REF, REF, THIS])
    return ReportInfo(**{**info.__dict__, **changes})


def test_the_table_is_markdown_with_its_calibration() -> None:
    results = [
        Measured("1 process", "80 own rooms", THIS, [40.0, 44.0], {"app": 88.0}, 30.0, 4.0, 0.0),
        Measured("1 process", "80 own rooms", REF, [38.0, 40.0], {"app": 90.0}, 29.0, 6.0, 0.0),
        Measured("1 process", "80 own rooms", REF, [34.0, 36.0], {"app": 92.0}, 31.0, 8.0, 1.0),
        Measured("1 process", "80 own rooms", THIS, [42.0, 46.0], {"app": 90.0}, 32.0, 6.0, 1.0),
        Measured("2 workers", "80 own rooms", THIS, [30.0, 31.0], {"worker 1": 80.0, "worker 2": 76.0,
                                                                  "nginx": 9.0, "redis": 0.0}, 30.0, 4.0, 0.0,
                 "no lecture"),
        Measured("2 workers", "80 own rooms", REF, error="worker: no 'BENCH_PORT '"),
    ]
    table = cluster_load.format_report(results, _info())
    lines = table.splitlines()
    assert lines[0] == "### Capacity (benchmarks/cluster_load.py), 2026-11-28 06:05–06:19 UTC"
    assert "- this tree: abc1234; reference: def5678 (`--reference v1`)" in table
    assert "2 CPUs, AMD EPYC, Python 3.11.7; 1-minute load average 0.31 before, 1.95 after" in table
    assert "in the order this tree, reference, reference, this tree; window 8 s after 3 s warm-up" in table
    assert "- during the runs other work took 6 % of one core (median; at most 8 %), the hypervisor stole at most 1 %" \
        in table
    rows = [line for line in lines if line.startswith("|")]
    assert rows[:2] == cluster_load.TABLE_HEAD
    assert {row.count("|") for row in rows} == {rows[0].count("|")}
    # medians over the runs: this tree min 41, median 43; the reference min 36, median 37
    assert rows[2] == ("| 1 process | 80 own rooms | this tree | 41.0 / 43.0 | ×1.14 / ×1.16 | 42.0, 44.0 "
                       "| app 89 | 31 | 5 | 0 | - |")
    assert rows[3] == ("| 1 process | 80 own rooms | reference | 36.0 / 37.0 | — | 39.0, 35.0 "
                       "| app 91 | 30 | 7 | 0 | - |")
    assert rows[4].startswith("| 2 workers | 80 own rooms | this tree | 30.0 / 30.5 | — | 30.5 | 80 + 76, nginx 9, "
                              "redis 0 | 30 | 4 | 0 | no lecture |")
    assert rows[5].startswith("| 2 workers | 80 own rooms | reference | no run gave figures |")
    assert "- 2 workers, 80 own rooms, reference: worker: no 'BENCH_PORT '" in table
    assert "busy machine" not in table


def test_a_table_without_reference_says_it_carries_no_calibration() -> None:
    results = [Measured("1 process", "80 own rooms", THIS, [40.0], {"app": 88.0}, 30.0, 4.0, 0.0)]
    table = cluster_load.format_report(results, _info(reference=None, order=[THIS], busy="load 3"))
    assert "no reference (`--reference none`): these figures carry no calibration" in table
    assert "| 1 process | 80 own rooms | this tree | 40.0 / 40.0 | — | 40.0 |" in table
    assert table.splitlines()[0].endswith("measured on a busy machine")
