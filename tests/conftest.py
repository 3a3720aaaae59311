"""Fixtures for the app tests: the app on a loopback ephemeral port, raw websocket clients
(no browser) and, for tests marked `browser`, Debian's Chromium driven by Playwright.

Browser: /usr/lib/chromium/chromium (override with $CHROMIUM), launched with the flags of
docs/VISER.md.  If playwright or Chromium is missing the browser tests are skipped with
a hint (`apt-get install chromium`), except under CI=true, where that is a failure.
"""

from __future__ import annotations

import contextlib
import math
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

if TYPE_CHECKING:  # imported lazily below, so the physics tests never load viser
    from viser import _messages

    from app.main import App

from scripts.chromium import CHROMIUM, CHROMIUM_ARGS, INSTALL_HINT  # noqa: E402
from scripts.flake_hunt import browser_marked  # noqa: E402 - the browser tests of a module, read from its source

WAIT_S = 30.0
"""[s] The default deadline of a wait for something the server does asynchronously: a poll
returns as soon as it holds, and a busy machine (two `yes`, load average 13) takes many times a
quiet one's second."""


def poll_until(predicate: Callable[[], Any], timeout: float = WAIT_S, interval: float = 0.01, *,
               what: str = "condition", seen: Callable[[], Any] | None = None) -> Any:
    """Poll `predicate` until it returns a truthy value; that value, or AssertionError naming
    `what` was waited for and, if `seen` is given, what `seen()` returned at the deadline."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            saw = "" if seen is None else f"; saw {seen()!r}"
            raise AssertionError(f"{what} not met within {timeout} s{saw}"[:2000])
        time.sleep(interval)


TEST_SHOTS = os.environ.get("RBL_TEST_SHOTS")
"""A folder: browser tests keep there the pictures they take for people (no assertion reads them);
unset, they take none (under SwiftShader a picture costs seconds)."""


def keep_picture(shown: Any, name: str, **options: Any) -> None:
    """`shown.screenshot(...)` (a Playwright page or locator) into $RBL_TEST_SHOTS/`name`, if set."""
    if TEST_SHOTS:
        path = Path(TEST_SHOTS) / name
        path.parent.mkdir(parents=True, exist_ok=True)
        shown.screenshot(path=str(path), **options)


def keep_words(name: str, text: str) -> None:
    """`text` into $RBL_TEST_SHOTS/`name` beside the pictures, if set (what a page said, for people)."""
    if TEST_SHOTS:
        path = Path(TEST_SHOTS) / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def scenes_without_an_entry(table: Any, name: str) -> str:
    """What is wrong with a per-scene test table (a dict by scene title, or a collection of titles)
    against the registry (`app.scenes.SCENES`): each registered scene it lacks and each title it
    holds that is no scene, named with the table; "" if it fits."""
    from app.scenes import SCENES  # noqa: PLC0415 - the registry imports the kit; conftest stays light

    lacking = [title for title in SCENES if title not in table]
    stale = [title for title in table if title not in SCENES]
    problems = [f"the scene {title!r} of app.scenes.SCENES has no entry in {name}" for title in lacking]
    problems += [f"{name} has an entry {title!r}, which is no scene of app.scenes.SCENES" for title in stale]
    return "; ".join(problems)


BROWSER_GROUP = "browser"
STILL_PAGE_MODULES = ("tests/test_browser_language_scenes.py", "tests/test_browser_language.py")
"""Browser modules whose pages play nothing (panels laid out and measured): a second browser
group, on the other process, beside the first (`pytest_xdist_make_scheduler`)."""


BROWSER_TIMEOUT_S = 900.0
"""[s] pytest-timeout's limit for a browser test that sets none (pyproject's `timeout`, 300 s, is
for the rest): a hang guard, not a speed check.  With two `yes` and a second Chromium beside the
suite, the slowest browser tests took 4.5-6 times their quiet time (the four-page ask test 66 s
quiet, past 300 s busy; a scene's pictures 49 s and 290 s)."""


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Each browser test without its own `timeout` mark gets BROWSER_TIMEOUT_S."""
    for item in items:
        if item.get_closest_marker("browser") and not item.get_closest_marker("timeout"):
            item.add_marker(pytest.mark.timeout(BROWSER_TIMEOUT_S))


def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """The suite on 2 processes (pyproject's addopts: `-n 2 --dist loadgroup`): xdist's scope
    scheduling with these groups, each run by one process in collection order:

    - the browser tests in RBL_BROWSER_GROUPS groups (default 1), module by module in turn: each
      group one Chromium, one page drawing at a time in it; the STILL_PAGE_MODULES in a group of
      their own, which the other process starts at once;
    - every other test with its module: a module-scoped fixture (a server, a cluster of
      workers, a Redis) starts once.

    The groups are read from the nodeids (the `xdist_group` mark is not used: xdist 3.8 renames
    nodeids for it, which pytest 9 ignores).

    Two browser groups end the suite sooner (a quiet run of ac31cd2: 744 s and 740 s per process,
    12:33, where one group held 1,053 s of browser tests), but two Chromiums drawing at once
    starved each other's pages: in two of three quiet runs a page took 120 s for a screenshot or
    missed a tap, where one group's runs passed.  One group stays the default."""
    if config.getvalue("dist") != "loadgroup":
        return None
    browser_groups = max(1, int(os.environ.get("RBL_BROWSER_GROUPS", "1")))
    browser_modules: list[str] = []
    from xdist.scheduler import LoadScopeScheduling

    config.option.loadscopereorder = False  # collection order: the browser group starts early
    root = config.rootpath
    cache: dict[str, bool | list[str]] = {}

    class ModulesAndTheBrowser(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            module, _, rest = nodeid.partition("::")
            if module not in cache:
                path = root / module
                cache[module] = browser_marked(path) if path.suffix == ".py" and path.exists() else []
            browser = cache[module]
            name = rest.split("[", 1)[0].split("::")[-1]
            if not (browser is True or name in browser):  # type: ignore[operator]
                return module
            if module in STILL_PAGE_MODULES:
                return f"{BROWSER_GROUP}-still"
            if module not in browser_modules:
                browser_modules.append(module)
            part = browser_modules.index(module) % browser_groups
            return BROWSER_GROUP if part == 0 else f"{BROWSER_GROUP}-{part}"

        def _assign_work_unit(self, node: Any) -> None:
            if not self._ordered:  # the first assignment: the queue is complete, nothing taken yet
                self._ordered = True
                self.workqueue = type(self.workqueue)(sorted(self.workqueue.items(), key=lambda unit: _rank(unit[0])))
            super()._assign_work_unit(node)

        _ordered = False

        def remove_node(self, node: Any) -> str | None:
            """A worker gone: its unfinished work back on the queue, and only that.  xdist 3.8 puts
            back its whole workload: its finished modules became empty units that left the last
            workers waiting for ever (pytest-xdist#1378), and the test it died in was run again
            (#1371), where xdist has already reported it failed."""
            workload = self.assigned_work.pop(node)
            # a worker runs its units, and their tests, in order: the first not done is where it died
            crashed = next(((scope, nodeid) for scope, unit in workload.items()
                            for nodeid, done in unit.items() if not done), None)
            if crashed is None:
                return None
            workload[crashed[0]][crashed[1]] = True
            for scope, unit in workload.items():
                if not all(unit.values()):
                    self.workqueue[scope] = unit
            for other in self.assigned_work:
                self._reschedule(other)
            return crashed[1]

        def _reschedule(self, node: Any) -> None:
            """Units for `node` until it holds more than 2 tests (xdist gives one unit a call), and
            the end once the queue is empty: a worker runs a test only once it holds the next one
            or the end, so a replacement worker given one unit of one test waited for ever
            (pytest-xdist#1327)."""
            if node.shutting_down:
                return
            while self.workqueue and self._pending_of(self.assigned_work[node]) <= 2:
                self._assign_work_unit(node)
            if not self.workqueue:
                node.shutdown()

    return ModulesAndTheBrowser(config, log)


_WORKER_SECONDS: dict[str, list[float]] = {}  # xdist worker id: [seconds in tests, browser-group seconds]


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    """On the controller: each xdist worker's time in its tests' setup, call and teardown."""
    node = getattr(report, "node", None)
    worker = getattr(getattr(node, "gateway", None), "id", None)
    if worker is not None:
        seconds = _WORKER_SECONDS.setdefault(worker, [0.0, 0.0])
        seconds[0] += report.duration
        if "browser" in report.keywords:
            seconds[1] += report.duration


_CHROMIUM_CPU_S: list[float] = []  # CPU seconds of each Chromium this process ran (with its child processes)


def _process_table() -> dict[int, tuple[int, float, str]]:
    """Every process: pid -> (ppid, its own CPU seconds so far: utime + stime, its name) (Linux /proc)."""
    ticks = os.sysconf("SC_CLK_TCK")
    table = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            name, _, rest = stat.read_text().partition(" (")[2].rpartition(")")
        except OSError:  # ended meanwhile
            continue
        fields = rest.split()
        table[int(stat.parent.name)] = (int(fields[1]), (int(fields[11]) + int(fields[12])) / ticks, name)
    return table


class ChromiumCpu:
    """The CPU seconds [s] of the Chromium processes this process started (through Playwright's
    driver: the browser, its renderers and GPU process), sampled every `period_s` by a thread: a process
    that ends is counted as last sampled (Chromium's renderers are reaped by no ancestor of ours,
    so the kernel's children's times miss them)."""

    def __init__(self, period_s: float = 1.0) -> None:
        import threading

        self.seen: dict[int, float] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(period_s,), name="chromium-cpu", daemon=True)
        self._thread.start()

    def _run(self, period_s: float) -> None:
        while not self._stop.wait(period_s):
            self.sample()

    def sample(self) -> None:
        table = _process_table()
        ours = {os.getpid()}
        grown = True
        while grown:
            more = {pid for pid, (ppid, _, _) in table.items() if ppid in ours} - ours
            grown = bool(more)
            ours |= more
        for pid in ours:
            if table[pid][2].startswith("chrom"):
                self.seen[pid] = table[pid][1]

    def total(self) -> float:
        """The CPU seconds [s] seen so far (sampled now)."""
        self.sample()
        return sum(self.seen.values())

    def stop(self) -> float:
        """Stop sampling; the CPU seconds seen."""
        self._stop.set()
        return self.total()


_CHROMIUM_NOW: list[ChromiumCpu] = []  # the sampler of this process's Chromium while it runs
_CHROMIUM_BY_MODULE: dict[str, float] = {}  # test module -> the CPU seconds Chromium used in its tests


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None) -> Iterator[None]:
    """The CPU Chromium used during each test (its setup, call and teardown), summed by module."""
    cpu = _CHROMIUM_NOW[0] if _CHROMIUM_NOW else None
    before = cpu.total() if cpu is not None else 0.0
    yield
    cpu = cpu or (_CHROMIUM_NOW[0] if _CHROMIUM_NOW else None)
    if cpu is not None:
        module = item.nodeid.split("::")[0]
        _CHROMIUM_BY_MODULE[module] = _CHROMIUM_BY_MODULE.get(module, 0.0) + cpu.total() - before


def pytest_sessionfinish(session: pytest.Session) -> None:
    """On an xdist worker: hand the CPU its Chromiums used to the controller (`workeroutput`)."""
    output = getattr(session.config, "workeroutput", None)
    if output is not None:
        output["chromium_cpu_s"] = sum(_CHROMIUM_CPU_S)
        output["chromium_by_module"] = dict(_CHROMIUM_BY_MODULE)


def pytest_testnodedown(node: Any, error: Any) -> None:
    """On the controller: a worker's Chromium CPU, for the summary."""
    seconds = getattr(node, "workeroutput", {}).get("chromium_cpu_s", 0.0)
    worker = getattr(getattr(node, "gateway", None), "id", "?")
    _WORKER_SECONDS.setdefault(worker, [0.0, 0.0])
    _CHROMIUM_BY_WORKER[worker] = seconds
    for module, cpu_s in getattr(node, "workeroutput", {}).get("chromium_by_module", {}).items():
        _CHROMIUM_BY_MODULE[module] = _CHROMIUM_BY_MODULE.get(module, 0.0) + cpu_s


_CHROMIUM_BY_WORKER: dict[str, float] = {}


def pytest_terminal_summary(terminalreporter: Any) -> None:
    """Where the suite's time went: each process's seconds in tests, its share in browser tests
    (the process that ends last sets the suite's time) and the CPU its Chromium used."""
    for worker, (total, browser) in sorted(_WORKER_SECONDS.items()):
        terminalreporter.write_line(f"{worker}: {total:.0f} s in tests, {browser:.0f} s of them in browser tests, "
                                    f"Chromium {_CHROMIUM_BY_WORKER.get(worker, 0.0):.0f} CPU-s")
    if not _WORKER_SECONDS and _CHROMIUM_CPU_S:
        terminalreporter.write_line(f"Chromium: {sum(_CHROMIUM_CPU_S):.0f} CPU-s")
    top = sorted(_CHROMIUM_BY_MODULE.items(), key=lambda item: -item[1])[:10]
    if top:
        terminalreporter.write_line("Chromium CPU-s by module (the 10 most): "
                                    + ", ".join(f"{Path(module).stem} {cpu_s:.0f}" for module, cpu_s in top))


HEAVY_MODULES = ("tests/test_fork.py", "tests/test_soak.py", "tests/test_replay.py", "tests/test_cli.py",
                 "tests/test_in_the_picture.py", "tests/test_export.py", "tests/test_memory.py",
                 "tests/test_euler.py", "tests/test_package.py", "tests/test_frame_budget.py")
"""The non-browser modules that took longest (over 40 s each in a loaded run of 2026-11-28, docs/testing.md),
longest first: the other process starts them while the browser group
runs, and ends on short modules."""


def _rank(scope: str) -> tuple[int, int]:
    """Where a scope goes in the queue: the browser groups first (the longest, they start at once),
    then HEAVY_MODULES in their order, then the rest in collection order (sorted() is stable)."""
    if scope == BROWSER_GROUP or scope.startswith(BROWSER_GROUP + "-"):
        return (0, 0)
    if scope in HEAVY_MODULES:
        return (1, HEAVY_MODULES.index(scope))
    return (2, 0)


@pytest.fixture(autouse=True, scope="session")
def _data_folder(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """The app's default data folder (`app.userdata`, XDG_DATA_HOME on Linux) is a temporary one:
    no test writes into the user's (a Share pressed by test_trust's hostile follower, say)."""
    old = os.environ.get("XDG_DATA_HOME")
    os.environ["XDG_DATA_HOME"] = str(tmp_path_factory.mktemp("xdg_data"))
    yield
    if old is None:
        os.environ.pop("XDG_DATA_HOME", None)
    else:
        os.environ["XDG_DATA_HOME"] = old


@pytest.fixture
def wait_until() -> Callable[..., Any]:
    """`poll_until(predicate, timeout=WAIT_S)`: wait for something the server does asynchronously."""
    return poll_until


@pytest.fixture(scope="module")
def server() -> Iterator[Any]:
    """A private viser server nobody connects to (views drawn without a browser), quiet."""
    import contextlib
    import io

    import viser

    with contextlib.redirect_stdout(io.StringIO()):
        running = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    yield running
    with contextlib.redirect_stdout(io.StringIO()):
        running.stop()


@pytest.fixture
def app() -> Iterator[App]:
    """The lecture app on 127.0.0.1 and an ephemeral port, its 60 Hz loop running."""
    from app.main import create_server

    running = create_server("127.0.0.1", 0, verbose=False)
    try:
        yield running
    finally:
        running.stop()


class RawClient:
    """A browser stand-in speaking viser's websocket protocol (docs/VISER.md §3).

    It sends the first ViewerCameraMessage (without which viser does not register a client)
    and then GUI updates; a thread drains (and ignores) what the server sends.
    """

    def __init__(self, port: int) -> None:
        import viser
        from viser import _messages
        from websockets.sync.client import connect

        self._ws = connect(
            f"ws://127.0.0.1:{port}", subprotocols=[f"viser-v{viser.__version__}"],
            max_size=None, open_timeout=10,
        )
        self.frames_received = 0
        self._reader = threading.Thread(target=self._drain, daemon=True)
        self._reader.start()
        self.send(_messages.ViewerCameraMessage(
            wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, 3.0, 3.0), fov=math.radians(50.0),
            near=0.01, far=100.0, image_height=600, image_width=800,
            look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0),
        ))

    def _drain(self) -> None:
        try:
            for _frame in self._ws:
                self.frames_received += 1
        except Exception:  # noqa: BLE001 - closed
            pass

    def send(self, message: _messages.Message) -> None:
        import msgspec.msgpack

        self._ws.send(msgspec.msgpack.encode(message.as_serializable_dict()))

    def set_value(self, handle: Any, value: Any) -> None:
        """What a browser sends when the user moves the GUI element `handle` to `value`."""
        from viser import _messages

        self.send(_messages.GuiUpdateMessage(handle._impl.uuid, {"value": value}))

    def close(self) -> None:
        self._ws.close()
        self._reader.join(timeout=5.0)


@contextlib.contextmanager
def browsers_joining(app: Any, timeout: float = 20.0) -> Iterator[Callable[..., Any]]:
    """For an app started without its loop: `join(language=None)` opens a raw websocket browser
    (`RawClient`, kept in `join.clients`) and returns its new session, in `language` if given; on
    exit every browser joined closes and the app stops."""
    clients: list[RawClient] = []

    def join(language: str | None = None) -> Any:
        before = set(app.sessions)
        clients.append(RawClient(app.port))
        session = poll_until(lambda: next((s for c, s in dict(app.sessions).items() if c not in before), None),
                             timeout=timeout, what="the new browser's session")
        if language is not None:
            session.set_language(language)
        return session

    join.clients = clients  # type: ignore[attr-defined]
    try:
        yield join
    finally:
        for client in clients:
            client.close()
        app.stop()


@pytest.fixture
def connect(app: App) -> Iterator[Callable[[], RawClient]]:
    """Factory of raw websocket clients to `app`; all are closed after the test."""
    clients: list[RawClient] = []

    def make() -> RawClient:
        client = RawClient(app.port)
        clients.append(client)
        return client

    yield make
    for client in clients:
        client.close()


class Manual:
    """The app without its loop (the test ticks by hand), one raw client and its session."""

    def __init__(self, app: App) -> None:
        self.app = app
        self.client = RawClient(app.port)
        self.session = next(iter(app.wait_for_sessions(1).values()))

    def wait(self, predicate: Callable[[], Any], timeout: float = WAIT_S) -> Any:
        """Poll until `predicate` holds, then until the session's callback that made it hold
        (on viser's thread pool, under the session lock) has finished."""
        value = poll_until(predicate, timeout)
        with self.session.lock:
            pass
        return value

    def tick(self, seconds: float, dt: float = 1.0 / 60.0) -> None:
        """Tick the session as the loop would, `seconds` of wall time in steps of dt."""
        for _ in range(int(round(seconds / dt))):
            self.session.tick(dt)


@pytest.fixture
def manual() -> Iterator[Manual]:
    """The app on an ephemeral port with its loop NOT running, one RawClient connected."""
    from app.main import create_server

    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    harness = None
    try:
        harness = Manual(running)
        yield harness
    finally:
        if harness is not None:
            with harness.session.lock:  # let a callback still running on viser's pool finish
                pass
            harness.client.close()
        running.stop()


def _browser_missing() -> str | None:
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "python playwright is not installed"
    if not Path(CHROMIUM).exists():
        return f"Chromium is not installed at {CHROMIUM}"
    return None


BROWSER_FPS = float(os.environ.get("RBL_BROWSER_FPS", "6"))
"""The most frames a second a test page draws (RBL_BROWSER_FPS; 0: as many as it can).  SwiftShader
draws WebGL on the CPU, and a playing page's cost grows with the frames it draws: an 800×600 page
playing the Euler scene took 0.81 cores at 10 frames a second and 0.34 at 3 (2026-11-29, Chromium's
CPU over 10 s; idle, 0.1 at any rate).  The whole suite, quiet, on one machine the same day: 19:22
at 10 (Chromium 1,368 CPU-s), then 16:30 and 23:32 at 6 (1,176 and 1,661): that machine's speed
varied more than the frame rate saves, every test passed in all three.  Older: uncapped, one
playing 1280×800 page took 1.8 of the 2 cores; at 5, with two browser groups, three tests that
wait for the camera or a frame failed."""
_FPS_CAP_JS = """(() => {
  // At most %s frames a second: a requestAnimationFrame callback runs in the next due frame, and
  // every callback of that frame runs in it (they share its timestamp); cancelAnimationFrame kept true.
  const period = 1000 / %s, raf = window.requestAnimationFrame.bind(window);
  const caf = window.cancelAnimationFrame.bind(window), native = new Map();
  let next = 1, due = 0, open = -1;
  window.requestAnimationFrame = (callback) => {
    const id = next++;
    const tick = (now) => {
      if (now !== open) {
        if (now + 1 < due) { native.set(id, raf(tick)); return; }
        open = now;
        due = Math.max(due + period, now);
      }
      native.delete(id);
      callback(now);
    };
    native.set(id, raf(tick));
    return id;
  };
  window.cancelAnimationFrame = (id) => {
    const handle = native.get(id);
    if (handle !== undefined) { caf(handle); native.delete(id); }
  };
})();"""


class CappedBrowser:
    """A Playwright browser whose every new context and page draws at most BROWSER_FPS frames a
    second (an init script, before the page's own); everything else is the browser's."""

    def __init__(self, browser: Any) -> None:
        self._browser = browser

    def __getattr__(self, name: str) -> Any:
        return getattr(self._browser, name)

    def new_context(self, **options: Any) -> Any:
        context = self._browser.new_context(**options)
        if BROWSER_FPS > 0:
            context.add_init_script(_FPS_CAP_JS % (BROWSER_FPS, BROWSER_FPS))
        return context

    def new_page(self, **options: Any) -> Any:
        page = self._browser.new_page(**options)
        if BROWSER_FPS > 0:
            page.add_init_script(_FPS_CAP_JS % (BROWSER_FPS, BROWSER_FPS))
        return page


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """Headless Debian Chromium (SwiftShader WebGL) via Playwright, one per test session, its
    pages capped at BROWSER_FPS frames a second (`CappedBrowser`)."""
    missing = _browser_missing()
    if missing is not None:
        message = f"{missing}: {INSTALL_HINT}"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"CI=true and the browser tests cannot run: {message}", pytrace=False)
        pytest.skip(message)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        cpu = ChromiumCpu()
        chromium = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        _CHROMIUM_NOW.append(cpu)
        try:
            yield CappedBrowser(chromium)
        finally:
            _CHROMIUM_NOW.remove(cpu)
            _CHROMIUM_CPU_S.append(cpu.stop())  # before close: its processes end with it
            chromium.close()


RUNNING_JS = """async () => {
  await new Promise((drawn) => requestAnimationFrame(() => requestAnimationFrame(drawn)));
  return document.getAnimations().filter(a => a.playState === 'running')
    .map(a => a.transitionProperty || a.animationName || a.constructor.name);
}"""
"""The page's CSS transitions and animations running once it has drawn two more frames (a folder
opening: its height, opacity).  A folder starts its transition in the frame after the click: on
a busy page that frame can come seconds later, and until then the open folder's rows lie, still
clipped, under the rows that follow it."""


def settled_box(page: Any, locator: Any, timeout: float = 30.0) -> dict[str, float]:
    """`locator`'s bounding box [CSS px] once no transition runs on the page and two reads 0.1 s
    apart agree: a panel that has just appeared may still slide in, and a tap at its first box
    lands beside its control.  AssertionError naming the last two reads if not."""
    deadline = time.monotonic() + timeout
    previous = None
    while True:
        box = locator.bounding_box()
        running = page.evaluate(RUNNING_JS)
        if box is not None and box == previous and not running:
            return dict(box)
        if time.monotonic() > deadline:
            raise AssertionError(f"the box kept moving for {timeout} s (running: {running}): {previous} then {box}")
        previous = box
        page.wait_for_timeout(100)


_AT_POINT_JS = """(element, [x, y]) => {
  const hit = document.elementFromPoint(x, y);
  if (hit !== null && element.contains(hit)) return '';
  if (hit === null) return 'nothing';
  const kind = hit.className ? '.' + String(hit.className).split(' ')[0] : '';
  return hit.tagName.toLowerCase() + kind + ' "' + (hit.innerText || '').slice(0, 40) + '"';
}"""


def point_on(page: Any, locator: Any, fx: float, fy: float, timeout: float = 30.0) -> tuple[float, float]:
    """The page point [CSS px] at fractions (fx, fy) of `locator`'s settled box, once that point is
    on the element itself: scrolled into view, and no toast or sheet lies over it (a tap by
    coordinates goes to whatever is on top).  AssertionError naming what lay there if not."""
    deadline = time.monotonic() + timeout
    while True:
        locator.scroll_into_view_if_needed()
        box = settled_box(page, locator, timeout=max(1.0, deadline - time.monotonic()))
        x, y = box["x"] + fx * box["width"], box["y"] + fy * box["height"]
        over = locator.evaluate(_AT_POINT_JS, [x, y])
        if not over:
            return x, y
        if time.monotonic() > deadline:
            raise AssertionError(f"({x:.0f}, {y:.0f}) in {box} stayed under {over} for {timeout} s")
        page.wait_for_timeout(200)


BUTTONS_JS = """() => [...document.querySelectorAll('button')]
    .map((b) => [(b.innerText || b.getAttribute('aria-label') || '').trim(), b.checkVisibility()])
    .filter(([name]) => name).map(([name, shown]) => (shown ? name : `${name} (hidden)`)).join(' | ')"""
"""The names of a page's buttons, hidden ones marked: what a failed tap saw instead."""


def tap(locator: Any, timeout: float = 90.0) -> None:
    """Tap `locator` as a finger does, once: Playwright's tap, which waits up to `timeout` [s]
    while the element moves or something lies over it (a phone's panel scrolled to its foot moves
    when the busy note there comes or goes, and a busy page draws the move seconds later).  Never
    tried again: on a starved page a tap can land and its call still time out, and a second tap
    would press what the first one brought.  AssertionError with Playwright's last words and the
    page's buttons if not."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    try:
        locator.tap(timeout=timeout * 1000)
    except PlaywrightTimeout as error:
        buttons = locator.page.evaluate(BUTTONS_JS)
        raise AssertionError(f"could not tap {locator} in {timeout} s: {error}\n"
                             f"the page's buttons: {buttons}") from None


DESK = {"viewport": {"width": 800, "height": 600}}
"""A desktop page whose size no assertion reads (the laptops, projectors and phones whose layout a
test checks keep their sizes): playing, it costs SwiftShader 0.52 cores where a 1280×800 page
costs 0.80 (10 frames a second, Chromium's CPU over 10 s, measured)."""


@pytest.fixture
def page(browser: Any, request: pytest.FixtureRequest) -> Iterator[Any]:
    """A fresh page, 1280x800 or the test module's `PAGE` (a context's options, e.g. DESK);
    closed after the test."""
    context = browser.new_context(**getattr(request.module, "PAGE", {"viewport": {"width": 1280, "height": 800}}))
    try:
        yield context.new_page()
    finally:
        context.close()


class LectureHall:
    """The app with its loop NOT running (the test ticks), a known presenter code and the raw
    clients that joined (tests of the lecture hall)."""

    def __init__(self, code: str) -> None:
        from app.main import create_server

        self.app = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=code)
        self.clients: list[Any] = []

    def join_with_client(self, client_factory: Callable[[int], Any] = RawClient) -> tuple[Any, Any]:
        """Connect one more browser (a RawClient, or what `client_factory(port)` makes): (its
        session, the client)."""
        return join(self.app, self.clients, client_factory, timeout=10.0)

    def join(self) -> Any:
        """Connect one more raw browser; its session."""
        return self.join_with_client()[0]

    def frames(self, count: int, dt: float = 1.0 / 60.0) -> None:
        """`count` frames of the loop: every room ticks, then the lectern."""
        for _ in range(count):
            for room in self.app.rooms():
                room.tick(dt)
            self.app.lectern.tick(dt)

    def leave(self, since: int = 0) -> None:
        """The clients that joined after the first `since` close; once no session and no presenter
        remain, the question round ends and the earlier rounds are forgotten (the next test's hall)."""
        app = self.app
        for client in self.clients[since:]:
            client.close()
        del self.clients[since:]
        poll_until(lambda: not app.sessions and app.lectern.presenter is None, timeout=20.0,
                   what="every browser gone and no presenter", seen=lambda: (list(app.sessions), app.lectern.presenter))
        app.rounds.end()
        app.rounds.earlier.clear()

    def close(self) -> None:
        for client in self.clients:
            client.close()
        self.app.stop()


def hall_fixture(code: str, hall_class: type[LectureHall] = LectureHall) -> Any:
    """A pytest fixture, to assign to the name the tests ask for (`hall = hall_fixture(CODE)`):
    a fresh `hall_class(code)` for each test, closed after it."""

    @pytest.fixture
    def fresh_hall() -> Iterator[LectureHall]:
        with contextlib.closing(hall_class(code)) as running:
            yield running

    return fresh_hall


def shared_hall_fixtures(code: str) -> tuple[Any, Any]:
    """Two pytest fixtures, to assign to their names (`_one_hall, hall = shared_hall_fixtures(CODE)`):
    `_one_hall`, one LectureHall with `code` for the module (its start is the slow part), and
    `hall`, that hall for one test, whose browsers leave after it (`LectureHall.leave`)."""

    @pytest.fixture(scope="module")
    def _one_hall() -> Iterator[LectureHall]:
        with contextlib.closing(LectureHall(code)) as running:
            yield running

    @pytest.fixture
    def hall(_one_hall: LectureHall) -> Iterator[LectureHall]:
        before = len(_one_hall.clients)
        yield _one_hall
        _one_hall.leave(since=before)

    return _one_hall, hall


def join(app: App, clients: list[Any], factory: Callable[[int], Any] = RawClient,
         timeout: float = 20.0) -> tuple[Any, Any]:
    """One more browser stand-in made by `factory(port)` on `app`, appended to `clients`: (its
    session, the client)."""
    before = set(app.sessions)
    client = factory(app.port)
    clients.append(client)
    sessions = app.wait_for_sessions(len(before) + 1, timeout=timeout)
    (session,) = (s for cid, s in sessions.items() if cid not in before)
    return session, client


ROOT = Path(__file__).resolve().parent.parent


class WorkerProcess:
    """A real worker, `python -m app --redis URL --worker-id ID --presenter-code CODE`, on a free
    port of 127.0.0.1, its output in a file under /tmp; started and awaited ("worker ID on" said)
    on entering, killed (if alive) and its file removed on leaving."""

    def __init__(self, url: str, code: str, worker_id: str = "w1", start_timeout: float = 120.0) -> None:
        from app.cluster import services

        self.worker_id = worker_id
        self.port = services.free_port()
        self._start_timeout = start_timeout
        self._out = Path("/tmp") / f"rbl-worker-{worker_id}-{self.port}-{os.getpid()}.out"
        self._command = [sys.executable, "-m", "app", "--host", "127.0.0.1", "--port", str(self.port),
                         "--redis", url, "--worker-id", worker_id, "--presenter-code", code]
        self.process: subprocess.Popen[bytes] | None = None

    def output(self) -> str:
        """What the worker printed so far."""
        return self._out.read_text(errors="replace") if self._out.exists() else ""

    def __enter__(self) -> WorkerProcess:
        with self._out.open("wb") as out:
            self.process = subprocess.Popen(self._command, cwd=ROOT, stdout=out, stderr=subprocess.STDOUT)
        try:
            said = f"worker {self.worker_id} on"
            poll_until(lambda: said in self.output() or self.process.poll() is not None,  # type: ignore[union-attr]
                       self._start_timeout, 0.2, what=f"worker {self.worker_id} to start",
                       seen=lambda: self.output()[-500:])
            assert self.process.poll() is None, self.output()
        except BaseException:
            self.__exit__(None, None, None)
            raise
        return self

    def kill(self) -> None:
        """SIGKILL the worker (no word said to anyone) and reap it."""
        assert self.process is not None
        self.process.kill()
        self.process.wait(10)

    def __exit__(self, *exc: object) -> None:
        if self.process is not None and self.process.poll() is None:
            self.kill()
        self._out.unlink(missing_ok=True)


def lecturer_presenting(port: int, code: str, scene: str | None = None) -> Any:
    """A websocket lecturer (`benchmarks.ws_client.ViserClient`) on `port` that chose `scene` (if
    given), typed `code` and pressed Present, awaited until its `Stop presenting` shows."""
    from benchmarks.ws_client import ViserClient

    lecturer = ViserClient(port)
    try:
        lecturer.wait_for_label("Presenter code", timeout=60.0)
        if scene is not None:
            lecturer.set_value("Scene", scene, "Dropdown")
        lecturer.set_value("Presenter code", code)
        lecturer.click("Present")
        lecturer.state.wait_for(lambda: (b := lecturer.state.find_gui("Stop presenting", "Button")) is not None
                                and b.props.get("visible", True), timeout=30.0)
    except BaseException:
        lecturer.close()
        raise
    return lecturer


def world_rotation(handle: Any) -> Any:
    """R_world_node (3, 3): the node's wxyz composed with its parents' (viser names are paths)."""
    import numpy as _np
    from scipy.spatial.transform import Rotation as _Rotation

    impl = handle._impl
    nodes = impl.api._handle_from_node_name
    R = _Rotation.from_quat(_np.asarray(impl.wxyz, dtype=float), scalar_first=True).as_matrix()
    name = impl.name
    while "/" in name.strip("/"):
        name = name.rsplit("/", 1)[0]
        if name in nodes:
            R = _Rotation.from_quat(_np.asarray(nodes[name]._impl.wxyz, dtype=float), scalar_first=True).as_matrix() @ R
    return R


@pytest.fixture(scope="module")
def redis_url() -> Iterator[str]:
    """A redis-server of the test module's own (in memory, a free port), stopped after it; the
    module is skipped, with the install command, where redis-server is missing."""
    from app.cluster import services  # noqa: PLC0415 - only the modules that ask for Redis import it

    try:
        url, process = services.start_redis()
    except services.MissingProgram as error:
        pytest.skip(str(error))
    try:
        yield url
    finally:
        services.stop_process(process)
