"""Flake hunter: run chosen tests N times under a stated load and tally each test's outcomes.

    python scripts/flake_hunt.py [TEST ...] [-k EXPR] [--runs N] [--busy K] [--chromium]
                                 [--xdist N] [--out report.md]

TEST: pytest node ids or paths (default: every browser, websocket, load, bus and cluster test,
read from the test files' names and their `browser` marks, so new tests are included).  Each
run is one `python -m pytest -n 0 -p no:randomly ... --junitxml=<tmp>` (`-n N` with --xdist N).
Load, started before the first run and stopped after the last one (also on Ctrl-C or failure):
--busy K processes each spinning one core (`yes > /dev/null`), and --chromium a second headless
Debian Chromium drawing the app's scene (`python -m app --port P` on a free port, Play pressed).
The report (Markdown, printed; written to --out): the load (busy processes, Chromium, load
average at start and end, cores), then per test its passed/runs, slowest time [s] and the first
line of each distinct failure message, failures first.  Exit code 1 if any test did not pass
every run (a skip is neither; a test missing from a run counts as not passed).
"""

from __future__ import annotations

import argparse
import ast
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TESTS = ROOT / "tests"
# The default tests: modules named for browsers, websockets, load, the bus and the cluster ...
DEFAULT_NAME_PARTS = ("browser", "wire", "viser_seam", "bus", "cluster", "gate", "soak", "backpressure",
                      "frame_rate", "frame_budget", "load")
# ... and modules that talk to the app through a websocket client (their source names one).
WEBSOCKET_WORDS = ("RawClient", "ViserClient", "import websockets")
MAX_MESSAGES = 3  # distinct failure first-lines kept per test


# --- which tests --------------------------------------------------------------------------------

def browser_marked(module: Path) -> bool | list[str]:
    """True if the whole module is marked `browser` (`pytestmark`), else its test functions
    carrying `@pytest.mark.browser` (conftest's rule, read from the source)."""
    tree = ast.parse(module.read_text(encoding="utf-8"))
    marked: list[str] = []
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "pytestmark" for t in node.targets):
            if "mark.browser" in ast.unparse(node.value):
                return True
        if isinstance(node, ast.FunctionDef) and any("mark.browser" in ast.unparse(d) for d in node.decorator_list):
            marked.append(node.name)
    return marked


def default_tests(tests_dir: Path = TESTS) -> list[str]:
    """Node ids (relative to the repo root) of the default hunt: every test module whose name
    holds one of DEFAULT_NAME_PARTS or whose source one of WEBSOCKET_WORDS, and every other test
    marked `browser`."""
    chosen: list[str] = []
    for module in sorted(tests_dir.glob("test_*.py")):
        relative = module.relative_to(tests_dir.parent).as_posix()
        source = module.read_text(encoding="utf-8")
        if any(part in module.stem for part in DEFAULT_NAME_PARTS) or any(w in source for w in WEBSOCKET_WORDS):
            chosen.append(relative)
            continue
        marked = browser_marked(module)
        if marked is True:
            chosen.append(relative)
        elif marked:
            chosen.extend(f"{relative}::{name}" for name in marked)
    return chosen


# --- junit XML and the tally --------------------------------------------------------------------

@dataclass
class Outcome:
    """One test in one run: outcome "passed" | "failed" | "skipped", time [s], failure message."""

    test_id: str
    outcome: str
    time_s: float
    message: str = ""


def test_id(classname: str, name: str, root: Path = ROOT) -> str:
    """The pytest node id of a junit testcase: classname "tests.test_x.TestY" -> the longest
    dotted prefix that is a file under `root` ("tests/test_x.py::TestY::name"); else
    "classname::name"."""
    parts = classname.split(".")
    for cut in range(len(parts), 0, -1):
        path = Path(*parts[:cut]).with_suffix(".py")
        if (root / path).is_file():
            return "::".join([path.as_posix(), *parts[cut:], name])
    return f"{classname}::{name}"


def parse_junit(path: Path, root: Path = ROOT) -> list[Outcome]:
    """The outcomes in one pytest junit XML file (failure and error both count as "failed")."""
    outcomes: list[Outcome] = []
    for case in ET.parse(path).getroot().iter("testcase"):
        tid = test_id(case.get("classname", ""), case.get("name", ""), root)
        bad = case.find("failure")
        if bad is None:
            bad = case.find("error")
        if bad is not None:
            text = bad.get("message") or (bad.text or "").strip() or bad.tag
            outcomes.append(Outcome(tid, "failed", float(case.get("time", 0.0)), text.strip().splitlines()[0]))
        elif case.find("skipped") is not None:
            outcomes.append(Outcome(tid, "skipped", float(case.get("time", 0.0))))
        else:
            outcomes.append(Outcome(tid, "passed", float(case.get("time", 0.0))))
    return outcomes


@dataclass
class Tally:
    """One test over the runs: passes, runs it was not skipped in, slowest time [s], messages."""

    test_id: str
    passed: int = 0
    ran: int = 0
    skipped: int = 0
    slowest_s: float = 0.0
    messages: list[str] = field(default_factory=list)

    @property
    def flaky(self) -> bool:
        return self.passed < self.ran

    def add(self, outcome: Outcome) -> None:
        self.slowest_s = max(self.slowest_s, outcome.time_s)
        if outcome.outcome == "skipped":
            self.skipped += 1
            return
        self.ran += 1
        if outcome.outcome == "passed":
            self.passed += 1
        elif outcome.message not in self.messages and len(self.messages) < MAX_MESSAGES:
            self.messages.append(outcome.message)


def tally(runs: Sequence[Sequence[Outcome]]) -> list[Tally]:
    """Per test over `runs` (one list of outcomes per run; an empty list = a run without junit
    XML): a test missing from a run counts as a run it did not pass.  Failures first (lowest
    pass fraction), then the slowest first."""
    tallies: dict[str, Tally] = {}
    for outcomes in runs:
        for outcome in outcomes:
            tallies.setdefault(outcome.test_id, Tally(outcome.test_id)).add(outcome)
    for t in tallies.values():  # missing from a run (a crash, a hang killed): not passed
        missing = len(runs) - t.ran - t.skipped
        if missing > 0:
            t.ran += missing
            if "missing from a run" not in t.messages:
                t.messages.append("missing from a run")
    return sorted(tallies.values(), key=lambda t: (not t.flaky, t.passed / max(t.ran, 1), -t.slowest_s, t.test_id))


def exit_code(tallies: Iterable[Tally], runs_without_xml: int = 0) -> int:
    """1 if any test did not pass every run it was not skipped in (or a run left no junit XML)."""
    return 1 if runs_without_xml or any(t.flaky for t in tallies) else 0


@dataclass
class Load:
    """The stated load: busy processes, a second Chromium, load averages (1 min), cores."""

    busy: int
    chromium: bool
    load_start: float
    load_end: float
    cores: int


def render(tallies: Sequence[Tally], load: Load, runs: int, command: str, runs_without_xml: int = 0) -> str:
    """The report as Markdown: the load, then the table (test, passed/runs, slowest s, message)."""
    flaky = sum(t.flaky for t in tallies)
    lines = [
        "# Flake hunt",
        "",
        f"- command: `{command}` x {runs} runs",
        f"- load: {load.busy} busy processes, second Chromium: {'yes' if load.chromium else 'no'}, "
        f"load average (1 min) {load.load_start:.2f} at start, {load.load_end:.2f} at end, {load.cores} cores",
        f"- {len(tallies)} tests, {flaky} did not pass every run"
        + (f"; {runs_without_xml} runs left no junit XML" if runs_without_xml else ""),
        "",
        "| test | passed/runs | slowest s | first failure lines |",
        "|---|---|---|---|",
    ]
    for t in tallies:
        skipped = f" ({t.skipped} skipped)" if t.skipped else ""
        message = " / ".join(m.replace("|", "\\|") for m in t.messages)
        lines.append(f"| {t.test_id} | {t.passed}/{t.ran}{skipped} | {t.slowest_s:.2f} | {message} |")
    return "\n".join(lines) + "\n"


# --- the load -----------------------------------------------------------------------------------

def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def wait_for_port(port: int, process: subprocess.Popen[bytes], timeout_s: float = 60.0) -> None:
    """Until 127.0.0.1:port accepts a connection; RuntimeError if `process` exits or the time ends."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"the app exited with code {process.returncode} before listening on {port}")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1.0).close()
            return
        except OSError:
            time.sleep(0.2)
    raise RuntimeError(f"the app did not listen on port {port} within {timeout_s} s")


class LoadProcesses:
    """The processes making the load, each in its own session (Ctrl-C reaches only this script);
    `stop()` ends them all (SIGTERM to each group, SIGKILL after 10 s)."""

    def __init__(self) -> None:
        self.processes: list[subprocess.Popen[bytes]] = []

    def spawn(self, argv: list[str], log: Path | None = None) -> subprocess.Popen[bytes]:
        out = open(log, "wb") if log else subprocess.DEVNULL  # noqa: SIM115 - the child keeps it
        process = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                   cwd=ROOT, start_new_session=True)
        self.processes.append(process)
        return process

    def start(self, busy: int, chromium: bool, logs: Path) -> None:
        for _ in range(busy):
            self.spawn(["yes"])
        if chromium:
            port = free_port()
            app_argv = [sys.executable, "-m", "app", "--host", "127.0.0.1", "--port", str(port)]
            app = self.spawn(app_argv, logs / "app.log")
            wait_for_port(port, app)
            self.spawn([sys.executable, str(Path(__file__).resolve()), "--draw", f"http://127.0.0.1:{port}"],
                       logs / "chromium.log")

    def stop(self) -> None:
        for process in reversed(self.processes):  # the browser before the app it watches
            if process.poll() is None:
                _signal_group(process, signal.SIGTERM)
        deadline = time.monotonic() + 10.0
        for process in self.processes:
            try:
                process.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                _signal_group(process, signal.SIGKILL)
                process.wait()
        self.processes.clear()


def _signal_group(process: subprocess.Popen[bytes], sig: int) -> None:
    try:
        os.killpg(process.pid, sig)
    except ProcessLookupError:
        pass


def draw(url: str) -> None:
    """The second Chromium (the --draw child): headless Debian Chromium with the WebGL flags of
    scripts/chromium.py on `url`, Play pressed if the page has it; draws until SIGTERM."""
    sys.path.insert(0, str(ROOT))
    from playwright.sync_api import sync_playwright

    from scripts.chromium import CHROMIUM, CHROMIUM_ARGS

    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))  # leave `with`: Playwright closes Chromium
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(url)
            try:
                page.get_by_role("button", name="Play", exact=True).first.click(timeout=120_000)
                print("drawing, Play pressed", flush=True)
            except Exception as error:  # noqa: BLE001 - still drawing the scene
                print(f"drawing without Play: {error}", flush=True)
            while True:
                page.wait_for_timeout(1_000)
        finally:
            browser.close()


# --- the hunt -----------------------------------------------------------------------------------

def pytest_argv(tests: Sequence[str], keyword: str | None, xdist: int, junit: Path) -> list[str]:
    argv = [sys.executable, "-m", "pytest", "-n", str(xdist), "-p", "no:randomly", "-q",
            f"--junitxml={junit}"]
    if keyword:
        argv += ["-k", keyword]
    return argv + list(tests)


def hunt(args: argparse.Namespace) -> int:
    tests = args.tests or default_tests()
    logs = Path(tempfile.mkdtemp(prefix="flake_hunt_"))
    load = LoadProcesses()
    runs: list[list[Outcome]] = []
    runs_without_xml = 0
    load_start = os.getloadavg()[0]
    load_end = load_start
    command = " ".join(pytest_argv(["TESTS"], args.k, args.xdist, Path("<tmp>"))[1:])
    print(f"flake hunt: {len(tests)} test paths, {args.runs} runs, {args.busy} busy, "
          f"chromium {'yes' if args.chromium else 'no'}; logs in {logs}", flush=True)
    try:
        load.start(args.busy, args.chromium, logs)
        for run in range(1, args.runs + 1):
            junit = logs / f"run{run}.xml"
            with open(logs / f"run{run}.log", "wb") as out:
                started = time.monotonic()
                code = subprocess.run(pytest_argv(tests, args.k, args.xdist, junit), cwd=ROOT, stdout=out,
                                      stderr=subprocess.STDOUT).returncode
            outcomes = parse_junit(junit) if junit.exists() else []
            runs_without_xml += not junit.exists()
            runs.append(outcomes)
            failed = sum(o.outcome == "failed" for o in outcomes)
            print(f"run {run}/{args.runs}: pytest exit {code}, {len(outcomes)} tests, {failed} failed, "
                  f"{time.monotonic() - started:.0f} s", flush=True)
        load_end = os.getloadavg()[0]
    finally:
        load.stop()
    tallies = tally(runs)
    report = render(tallies, Load(args.busy, args.chromium, load_start, load_end, os.cpu_count() or 0),
                    args.runs, command, runs_without_xml)
    print(report)
    if args.out:
        Path(args.out).write_text(report, encoding="utf-8")
    return exit_code(tallies, runs_without_xml)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("tests", nargs="*",
                        help="pytest node ids or paths (default: browser/websocket/load/bus/cluster tests)")
    parser.add_argument("-k", help="a pytest -k expression selecting among the tests")
    parser.add_argument("--runs", type=int, default=5, help="how many times to run them (default 5)")
    parser.add_argument("--busy", type=int, default=0, help="busy processes (`yes > /dev/null`) during the runs")
    parser.add_argument("--chromium", action="store_true", help="a second headless Chromium drawing the app")
    parser.add_argument("--xdist", type=int, default=0, help="pytest -n N (default 0: one process)")
    parser.add_argument("--out", help="write the report as Markdown to this file")
    parser.add_argument("--list", action="store_true", help="print the tests (paths/node ids) and stop")
    parser.add_argument("--draw", help=argparse.SUPPRESS)  # internal: the --chromium child
    args = parser.parse_args(argv)
    if args.draw:
        draw(args.draw)
        return 0
    if args.list:
        print("\n".join(args.tests or default_tests()))
        return 0
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # `finally` stops the load
    try:
        return hunt(args)
    except KeyboardInterrupt:
        print("interrupted: load stopped", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
