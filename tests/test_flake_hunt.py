"""scripts/flake_hunt.py's junit parser, tally, report and exit code, fed two small junit XML
files (two runs) written here: no pytest subprocess, no browser."""

from __future__ import annotations

from pathlib import Path

from scripts.flake_hunt import Load, default_tests, exit_code, parse_junit, render, tally

RUN_1 = """<?xml version="1.0" encoding="utf-8"?>
<testsuites><testsuite name="pytest" tests="4">
  <testcase classname="tests.test_a" name="test_steady" time="1.25"/>
  <testcase classname="tests.test_a.TestGroup" name="test_flaky[2]" time="3.50"/>
  <testcase classname="tests.test_a" name="test_skips" time="0.01"><skipped message="no chromium"/></testcase>
  <testcase classname="tests.test_a" name="test_gone" time="0.50"/>
</testsuite></testsuites>
"""
RUN_2 = """<?xml version="1.0" encoding="utf-8"?>
<testsuites><testsuite name="pytest" tests="3">
  <testcase classname="tests.test_a" name="test_steady" time="2.75"/>
  <testcase classname="tests.test_a.TestGroup" name="test_flaky[2]" time="9.00">
    <failure message="AssertionError: frames within 10 s: saw 3&#10;assert 3 &gt;= 50">trace</failure>
  </testcase>
  <testcase classname="tests.test_a" name="test_skips" time="0.02"><skipped message="no chromium"/></testcase>
</testsuite></testsuites>
"""
LOAD = Load(busy=2, chromium=True, load_start=1.5, load_end=3.25, cores=2)


def _runs(tmp_path: Path) -> list:
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_a.py").write_text("", encoding="utf-8")  # classnames map to this file
    runs = []
    for number, text in enumerate((RUN_1, RUN_2), start=1):
        junit = tmp_path / f"run{number}.xml"
        junit.write_text(text, encoding="utf-8")
        runs.append(parse_junit(junit, root=tmp_path))
    return runs


def test_the_tally_counts_passes_per_run_keeps_the_slowest_time_and_puts_failures_first(tmp_path: Path) -> None:
    tallies = tally(_runs(tmp_path))
    by_id = {t.test_id: t for t in tallies}
    assert set(by_id) == {"tests/test_a.py::test_steady", "tests/test_a.py::TestGroup::test_flaky[2]",
                          "tests/test_a.py::test_skips", "tests/test_a.py::test_gone"}
    steady, flaky = by_id["tests/test_a.py::test_steady"], by_id["tests/test_a.py::TestGroup::test_flaky[2]"]
    assert (steady.passed, steady.ran, steady.slowest_s, steady.flaky) == (2, 2, 2.75, False)
    assert (flaky.passed, flaky.ran, flaky.slowest_s, flaky.flaky) == (1, 2, 9.0, True)
    assert flaky.messages == ["AssertionError: frames within 10 s: saw 3"]  # the first line only
    skips = by_id["tests/test_a.py::test_skips"]
    assert (skips.passed, skips.ran, skips.skipped, skips.flaky) == (0, 0, 2, False)
    gone = by_id["tests/test_a.py::test_gone"]  # missing from run 2 (a crash): not passed
    assert (gone.passed, gone.ran, gone.flaky, gone.messages) == (1, 2, True, ["missing from a run"])
    assert [t.flaky for t in tallies] == [True, True, False, False]  # failures first
    assert exit_code(tallies) == 1


def test_the_report_states_the_load_and_a_row_per_test(tmp_path: Path) -> None:
    tallies = tally(_runs(tmp_path))
    report = render(tallies, LOAD, runs=2, command="pytest -n 0 TESTS")
    assert "2 busy processes, second Chromium: yes, load average (1 min) 1.50 at start, 3.25 at end, 2 cores" in report
    assert "| tests/test_a.py::TestGroup::test_flaky[2] | 1/2 | 9.00 | AssertionError: frames within 10 s: saw 3 |" \
        in report
    assert "| tests/test_a.py::test_steady | 2/2 | 2.75 |  |" in report
    assert "| tests/test_a.py::test_skips | 0/0 (2 skipped) |" in report
    assert "4 tests, 2 did not pass every run" in report
    rows = [line for line in report.splitlines() if line.startswith("| tests/")]
    assert rows[0].startswith("| tests/test_a.py::TestGroup::test_flaky[2]")  # the worst first


def test_every_run_passed_exits_0_and_a_run_without_junit_exits_1(tmp_path: Path) -> None:
    runs = _runs(tmp_path)
    steady_only = [[o for o in run if o.test_id.endswith("test_steady")] for run in runs]
    assert exit_code(tally(steady_only)) == 0
    assert exit_code(tally(steady_only), runs_without_xml=1) == 1


def test_the_default_selection_reads_names_and_browser_marks(tmp_path: Path) -> None:
    tests = tmp_path / "tests"
    tests.mkdir()
    (tests / "test_bus.py").write_text("def test_x(): pass\n", encoding="utf-8")
    (tests / "test_physics.py").write_text("def test_y(): pass\n", encoding="utf-8")
    (tests / "test_scene.py").write_text(
        "import pytest\n\n@pytest.mark.browser\ndef test_in_chromium(): pass\n\ndef test_z(): pass\n", encoding="utf-8")
    (tests / "test_hall.py").write_text("from conftest import RawClient\ndef test_w(): pass\n", encoding="utf-8")
    assert default_tests(tests) == ["tests/test_bus.py", "tests/test_hall.py", "tests/test_scene.py::test_in_chromium"]
