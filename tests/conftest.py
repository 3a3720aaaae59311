"""Fixtures for the app tests: the app on a loopback ephemeral port, raw websocket clients
(no browser) and, for tests marked `browser`, Debian's Chromium driven by Playwright.

Browser: /usr/lib/chromium/chromium (override with $CHROMIUM), launched with the flags of
docs/VISER.md.  If playwright or Chromium is missing the browser tests are skipped with
a hint (`apt-get install chromium`), except under CI=true, where that is a failure.
"""

from __future__ import annotations

import math
import os
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


def poll_until(predicate: Callable[[], Any], timeout: float = 5.0, interval: float = 0.01) -> Any:
    """Poll `predicate` until it returns a truthy value; that value, or AssertionError."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"condition not met within {timeout} s")
        time.sleep(interval)


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


def _browser_tests(module: Path) -> bool | set[str]:
    """The browser tests of a test module, read from its source: True if the whole module is
    marked (`pytestmark = pytest.mark.browser`), else the names of its test functions that carry
    `@pytest.mark.browser`."""
    import ast

    tree = ast.parse(module.read_text(encoding="utf-8"))
    marked: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "pytestmark" for t in node.targets):
            if "mark.browser" in ast.unparse(node.value):
                return True
        if isinstance(node, ast.FunctionDef) and any("mark.browser" in ast.unparse(d) for d in node.decorator_list):
            marked.add(node.name)
    return marked


def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """The suite on 2 processes (pyproject's addopts: `-n 2 --dist loadgroup`): xdist's scope
    scheduling with these groups, each run by one process in collection order:

    - every browser test in BROWSER_GROUP: one Chromium, one page drawing at a time (two
      Chromiums drawing at once on 2 cores time each other's pages out);
    - every other test with its module: a module-scoped fixture (a server, a cluster of
      workers, a Redis) starts once.

    The groups are read from the nodeids (the `xdist_group` mark is not used: xdist 3.8 renames
    nodeids for it, which pytest 9 ignores)."""
    if config.getvalue("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadScopeScheduling

    config.option.loadscopereorder = False  # collection order: the browser group starts early
    root = config.rootpath
    cache: dict[str, bool | set[str]] = {}

    class ModulesAndTheBrowser(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            module, _, rest = nodeid.partition("::")
            if module not in cache:
                path = root / module
                cache[module] = _browser_tests(path) if path.suffix == ".py" and path.exists() else set()
            browser = cache[module]
            name = rest.split("[", 1)[0].split("::")[-1]
            return BROWSER_GROUP if browser is True or name in browser else module  # type: ignore[operator]

    return ModulesAndTheBrowser(config, log)


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
    """`poll_until(predicate, timeout=5.0)`: wait for something the server does asynchronously."""
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

    def wait(self, predicate: Callable[[], Any], timeout: float = 5.0) -> Any:
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


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """Headless Debian Chromium (SwiftShader WebGL) via Playwright, one per test session."""
    missing = _browser_missing()
    if missing is not None:
        message = f"{missing}: {INSTALL_HINT}"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"CI=true and the browser tests cannot run: {message}", pytrace=False)
        pytest.skip(message)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        try:
            yield chromium
        finally:
            chromium.close()


@pytest.fixture
def page(browser: Any) -> Iterator[Any]:
    """A fresh 1280x800 page; closed after the test."""
    context = browser.new_context(viewport={"width": 1280, "height": 800})
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
        before = set(self.app.sessions)
        client = client_factory(self.app.port)
        self.clients.append(client)
        sessions = self.app.wait_for_sessions(len(before) + 1)
        (session,) = (s for cid, s in sessions.items() if cid not in before)
        return session, client

    def join(self) -> Any:
        """Connect one more raw browser; its session."""
        return self.join_with_client()[0]

    def frames(self, count: int, dt: float = 1.0 / 60.0) -> None:
        """`count` frames of the loop: every room ticks, then the lectern."""
        for _ in range(count):
            for room in self.app.rooms():
                room.tick(dt)
            self.app.lectern.tick(dt)

    def close(self) -> None:
        for client in self.clients:
            client.close()
        self.app.stop()


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
