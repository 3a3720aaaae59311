"""The suite's own scheduler (tests/conftest.py, `pytest_xdist_make_scheduler`) when a worker dies
mid-test: the run ends, the test it died in is reported failed once and not run again, and every
other test runs once.  A small suite in a temporary folder, run by `python -m pytest -n 2` with
this scheduler as a plugin: six modules of quick tests, one of which (the first, one in the middle or
the last) ends its worker's process."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
PLUGIN = f'''
import importlib.util
spec = importlib.util.spec_from_file_location("rbl_suite_conftest", {str(TESTS / "conftest.py")!r})
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
pytest_xdist_make_scheduler = module.pytest_xdist_make_scheduler
'''
"""Only the scheduler hook of the suite's conftest, as a plugin (`-p rbl_scheduler`)."""
MODULE = '''
import os, pathlib
def _ran(name):
    with open(pathlib.Path(__file__).parent / "ran.txt", "a") as out:
        out.write(name + "\\n")
def test_one():
    _ran("{name}::test_one")
def test_two():
    _ran("{name}::test_two")
    if {dies}:
        os._exit(3)  # the worker's process ends here, as a crash does
def test_three():
    _ran("{name}::test_three")
'''


@pytest.mark.timeout(180)
@pytest.mark.parametrize("dying", ["test_m0", "test_m3", "test_m5"])
def test_a_worker_that_dies_costs_one_failed_test_and_the_run_ends(tmp_path: Path, dying: str) -> None:
    (tmp_path / "rbl_scheduler.py").write_text(PLUGIN)
    names = [f"test_m{i}" for i in range(6)]
    for name in names:
        (tmp_path / f"{name}.py").write_text(MODULE.format(name=name, dies=name == dying))
    run = subprocess.run([sys.executable, "-m", "pytest", "-p", "rbl_scheduler", "-n", "2", "--dist", "loadgroup",
                          "-p", "no:cacheprovider", "-o", "addopts=", "-q", "."],
                         cwd=tmp_path, capture_output=True, text=True, timeout=150,
                         env={"PYTHONPATH": f"{tmp_path}:{TESTS.parent}:{TESTS}", "PATH": "/usr/bin:/bin"})
    tail = run.stdout[-1500:] + run.stderr[-1500:]
    assert "1 failed, 17 passed" in run.stdout, tail
    assert f"{dying}.py::test_two" in run.stdout and "crashed" in run.stdout, tail
    ran = (tmp_path / "ran.txt").read_text().split()
    expected = [f"{name}::{test}" for name in names for test in ("test_one", "test_two", "test_three")]
    assert sorted(ran) == sorted(expected), f"every test once, the one that died too: {sorted(ran)}"
