"""Start the lecture app: a viser server, one `Session` per browser, and a 60 Hz loop.

    python -m app [--host 127.0.0.1] [--port 8080] [--language en|nl|de]
    rigid-body-lab [--host ...] [--port ...]
    rigid-body-lab --workers N [--redis URL] ...   # N processes behind nginx (`app.launch`)

The server binds to loopback by default (viser's own default is 0.0.0.0, with no
authentication); pass `--host 0.0.0.0` deliberately to show it on a lecture-room network.
`create_server` builds the same app for tests: the loop runs in a thread, `App.stop()`
ends both the loop and the server.  Given a Redis URL (`--redis`, or REDIS_ENV as the launcher
passes it) the process is one worker of a lecture on several processes (`app.cluster`); SIGTERM
then stops it as Ctrl-C does.
"""

from __future__ import annotations

import argparse
import gc
import logging
import math
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import viser

from app.backpressure import FramePacer, PacerStats
from app.cli_words import Parser, cli_translator
from app.export import export_main
from app.i18n import DEFAULT_LANGUAGE, LANGUAGES, Translator, translator
from app.kit.core.presets import PresetError
from app.kit.core.room import Room
from app.lecture.gate import Gate, guess_chance, normalize_code
from app.lecture.lectern import Broadcast, Lectern, new_code
from app.lessons import LessonError, lessons
from app.own import OwnLibrary
from app.scenes import SCENES, check_presets
from app.scenes.euler_angles import VIEW as EULER_VIEW
from app.session import Session
from app.sharestore import ShareStore, open_share_store
from app.sweep import Sweep
from app.tasks.panel import attach_tasks
from app.tasks.store import TaskRules
from app.tasks.stores import open_task_store
from app.theme import configure_scene
from app.userdata import default_data_dir
from app.viser_internals import report as report_viser_internals
from app.wire import Wire, capturing, end_frames

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "LOAD_HOLD_S", "TICK_HZ", "App", "configure_scene", "create_server",
           "load_note", "main"]

logger = logging.getLogger(__name__)

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8080
TICK_HZ = 60.0
MAX_TICK_DT = 0.1  # [s] a tick never advances more than this (after a stall, or a laptop sleep)
LOAD_PERIOD = 2.0  # [s] of wall time over which the frame rate browsers get is measured
REDIS_ENV = "RBL_REDIS_URL"  # a worker's Redis URL (with its password) when not given as --redis
CODE_ENV = "RBL_PRESENTER_CODE"  # the presenter code when not given as --presenter-code (out of `ps`)
ASK_PERIOD = 0.25  # [s] the presenter's count of answers refreshes this often
BUSY_SHARE = 0.85  # below this share of tick_hz the panels say the server is busy
LOAD_HOLD_S = 10.0
"""[s] the busy note stays this long after the last busy measure: a rate near BUSY_SHARE does not
make it come and go every LOAD_PERIOD, which would move a phone's panel, scrolled to its foot,
under the finger."""


def load_note(frames: int, drawn: int, skipped: int, seconds: float, tick_hz: float) -> str:
    """What the panels say about the server's load: "" while browsers get at least BUSY_SHARE of
    tick_hz, else "Server busy: N frames a second" (N: loop iterations a second times the share
    of client frames drawn, the rate a browser sees)."""
    if seconds <= 0.0 or frames == 0:
        return ""
    share = drawn / (drawn + skipped) if drawn + skipped else 1.0
    fps = frames / seconds * share
    if fps >= BUSY_SHARE * tick_hz:
        return ""
    return (f"**Server busy: {fps:.0f} frames a second** (of {tick_hz:.0f}): the motion is computed as "
            "always, shown less often.")


def _browser(view: Any) -> Any:
    """The viser client a view's frame goes to (the presenter's for the shared scene), else its target."""
    target = view.client
    return getattr(target, "client", None) or getattr(target, "presenter", None) or target


class App:
    """A running lecture app: the server, the sessions by client id, and the tick loop.

    Attributes:
        server: the `viser.ViserServer`.
        sessions: {client_id: Session}, one per connected browser.
        tick_count: number of loop iterations so far.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        *,
        tick_hz: float = TICK_HZ,
        session_factory: Callable[[viser.ClientHandle], Session] | None = None,
        presenter_code: str | None = None,
        projector: bool = False,
        share_store: ShareStore | None = None,
        bus_factory: Callable[[viser.ViserServer, Lectern], Any] | None = None,
        gate: Gate | None = None,
        own: OwnLibrary | None = None,
        language: str = DEFAULT_LANGUAGE,
    ) -> None:
        report_viser_internals()  # once: what of viser's internals is off, and what the app does instead
        self.server = server
        self.sessions: dict[int, Session] = {}
        self.tick_hz = tick_hz
        self.tick_count = 0
        self.pacer_stats = PacerStats()  # frames drawn and skipped, time worked and slept
        self.load = ""  # what the panels say about the load ("" when the server keeps up)
        self.lectern = Lectern(server, presenter_code, gate=gate)
        self.lectern.seats = lambda: list(self.sessions.values())
        self.projector = projector
        self.language = translator(language).language  # ValueError for a language without a catalog
        """The language a new browser's panel starts in (`app.i18n`; each browser may choose another)."""
        self.own = own  # the lecturer's own presets and lessons (app.own), or None
        self.share_store = share_store
        """Where `Share` keeps its codes (`app.sharestore`); None: no Share folder."""
        self.task_store: TaskRules | None = None  # tasks between lectures (`app.tasks`); None: no Task folder
        self._session_factory = session_factory or self._new_session
        self._sessions_lock = threading.Lock()
        self._sessions_changed = threading.Condition(self._sessions_lock)
        self._owed: dict[int, float] = {}  # id(view) -> wall time [s] it has not drawn yet
        # app.wire: the shared scene's (key None) and each browser's
        self._wires: dict[int | None, Wire | None] = {None: Wire.attach(server)}
        # One lecture across processes (`app.lecture.bus`), after the shared scene's wire: None on one process
        self.bus: Any = bus_factory(server, self.lectern) if bus_factory is not None else None
        self._ask_version, self._since_ask = -1, 0.0
        self._ask_pending: set[int] = set()  # client ids whose question was not refreshed (busy then)
        self.ask_bus: Any = None  # questions across processes (`app.cluster.askbus`): None on one process
        self._stop = threading.Event()
        self._wake = threading.Event()  # the next frame now (stop; the bus: a presenter's frame from another process)
        if self.bus is not None:
            self.bus.wake = self._wake
        self.sweep = Sweep()
        """Full collections for browsers that left (`app.sweep`): what a browser held ends with it."""
        self._thread = threading.Thread(target=self._run_loop, name="app-tick-loop", daemon=True)
        server.on_client_connect(self._on_client_connect)
        server.on_client_disconnect(self._on_client_disconnect)

    # ------------------------------------------------------------------ sessions
    def _new_session(self, client: viser.ClientHandle) -> Session:
        session = Session(client, lectern=self.lectern, own=self.own, share_store=self.share_store,
                          language=self.language)
        if self.task_store is not None:
            attach_tasks(session, self.task_store)  # the Task folder and Make a task (app.tasks, issue 37)
        if self.projector:
            session.guard("projector", session.set_projector)(True)
        return session

    def _on_client_connect(self, client: viser.ClientHandle) -> None:
        """Build this client's session (runs on viser's thread pool); never raises."""
        try:
            session = self._session_factory(client)
        except Exception as error:  # noqa: BLE001 - a broken session must not break the server
            logger.exception("client %d: could not build the session", client.client_id)
            try:
                client.add_notification(
                    "Error", f"Could not build the scene: {type(error).__name__}: {error}",
                    color="red", with_close_button=True,
                )
            except Exception:  # noqa: BLE001
                pass
            return
        with self._sessions_changed:
            if client.client_id not in self.server.get_clients():
                session.close()  # disconnected while we were building
                return
            self.sessions[client.client_id] = session
            self._wires[client.client_id] = Wire.attach(self.server, client)
            self._sessions_changed.notify_all()
        logger.info("client %d: session started (%d open)", client.client_id, len(self.sessions))

    def _on_client_disconnect(self, client: viser.ClientHandle) -> None:
        with self._sessions_changed:
            session = self.sessions.pop(client.client_id, None)
            self._wires.pop(client.client_id, None)
            self._sessions_changed.notify_all()
        if session is not None:
            session.close()
        self.lectern.forget(client.client_id)
        self.sweep.left(session)
        logger.info("client %d: session ended (%d open)", client.client_id, len(self.sessions))

    def wait_for_sessions(self, count: int, timeout: float = 60.0) -> dict[int, Session]:
        """Block until exactly `count` sessions exist (a browser's session is built as it
        connects: its panels, a second or more on a busy machine); a copy of them.  TimeoutError
        if not within `timeout` [s]."""
        with self._sessions_changed:
            if not self._sessions_changed.wait_for(lambda: len(self.sessions) == count, timeout):
                raise TimeoutError(f"{len(self.sessions)} sessions after {timeout} s, wanted {count}")
            return dict(self.sessions)

    # ------------------------------------------------------------------ loop
    def start(self) -> App:
        """Start the tick loop thread; returns self."""
        self._thread.start()
        return self

    def rooms(self) -> list[Room]:
        """The rooms shown by the open sessions, each once."""
        with self._sessions_lock:
            sessions = list(self.sessions.values())
        rooms: dict[int, Room] = {}
        for session in sessions:
            if not session.closed:
                room = session.room  # a property (a follower's: the live room)
                rooms[id(room)] = room
        return list(rooms.values())

    def _run_loop(self) -> None:
        """Advance every room once a frame and draw its views, paced by a `FramePacer`.

        A view whose previous frame is still queued in viser (a slow or stalled client, or an
        overloaded server) skips this frame and later draws the current state, its throttles
        fed the time it skipped.  Under overload the whole loop slows down, so every client
        drops frames evenly, and the loop sleeps (GIL released) while viser's sender runs.
        """
        pacer = FramePacer(self.tick_hz, sleep=self._stop.wait, wake=self._wake)
        window = (time.monotonic(), 0, 0, 0)  # start, frames, drawn, skipped at the start
        busy_at = -math.inf  # [s] the end of the last window measured busy
        while not self._stop.is_set():
            self.sweep.run_if_due()  # between frames: what browsers that left held
            drawn = self.frame(min(pacer.begin(), MAX_TICK_DT), pacer)
            self.pacer_stats = stats = pacer.stats
            now = time.monotonic()
            if now - window[0] >= LOAD_PERIOD:
                start, frames, drawn_before, skipped = window
                note = load_note(stats.frames - frames, stats.drawn - drawn_before, stats.skipped - skipped,
                                 now - start, self.tick_hz)
                if note:
                    busy_at = now
                if note or now - busy_at >= LOAD_HOLD_S:
                    self._show_load(note)
                window = (now, stats.frames, stats.drawn, stats.skipped)
            pacer.end(drawn, busy=self._wires_busy)

    def frame(self, dt: float, pacer: FramePacer | None = None) -> list[Any]:
        """One frame of the loop: every room advances dt [s], every view whose browser is ready
        draws, the lectern ticks, all inside `app.wire.capturing()`; then each wire sends its
        frame.  The browsers drawn.  Tests call it with the loop not running (`start_loop=False`)."""
        rooms = self.rooms()
        views = [(room, view, _browser(view)) for room in rooms for view in list(room.views)]
        drawn = []
        owed, wires = self._owed, self._wires
        shared = wires.get(None)
        bus = self.bus
        if bus is not None:
            bus.take_in()
        with capturing():
            if bus is not None:
                bus.apply_frame()
            for room in rooms:
                try:
                    room.advance(dt)
                except Exception:  # noqa: BLE001 - a second net; rooms report their own errors
                    logger.exception("%s: advance failed", room.scene.title)
            for room, view, browser in views:
                owed[id(view)] = owed.get(id(view), 0.0) + dt
                own = wires.get(getattr(browser, "client_id", -1))
                busy = (own is not None and own.busy()) or (
                    shared is not None and isinstance(view.client, Broadcast) and shared.busy())
                if (pacer is None or pacer.ready(browser)) and not busy:
                    room.draw(view, owed.pop(id(view)))
                    drawn.append(browser)
            self.lectern.tick(dt)
            if self.ask_bus is not None:
                self.ask_bus.tick(dt)
            self._ask_tick(dt)
        self._end_frames()
        if bus is not None:
            bus.send_out(dt)
        if len(owed) > 2 * len(views) + 16:  # views that left
            live = {id(view) for _, view, _ in views}
            self._owed = {key: value for key, value in owed.items() if key in live}
        self.tick_count += 1
        return drawn

    @property
    def rounds(self) -> Any:
        """The class's questions (`app.ask.Rounds`): `rounds.current` (the round asked on this
        process, or None), `rounds.tally()` and `rounds.csv()` (its anonymous answers)."""
        return self.lectern.rounds

    def _ask_tick(self, dt: float) -> None:
        """Every browser's question as the round is now, when the round changed; every ASK_PERIOD
        the presenter's count and the browsers that were busy when it changed (each panel writes
        only what changed)."""
        rounds = self.lectern.rounds
        self._since_ask += dt
        changed = rounds.version != self._ask_version
        if not changed and self._since_ask < ASK_PERIOD:
            return
        self._since_ask = 0.0
        self._ask_version = rounds.version
        presenter = self.lectern.presenter
        with self._sessions_lock:
            if changed:
                sessions: list[Any] = list(self.sessions.values())
            else:
                sessions = [s for cid, s in self.sessions.items() if cid in self._ask_pending or s is presenter]
        for session in sessions:
            if session.questions_changed():
                self._ask_pending.discard(session.client_id)
            else:
                self._ask_pending.add(session.client_id)

    def frames_sent(self) -> bool:
        """Every frame ended so far has gone out (no wire has a delivery waiting)."""
        return not self._wires_busy()

    # ------------------------------------------------------------------ frames on the wire
    def _end_frames(self) -> None:
        """Send each wire's frame: the shared scene's to the presenter and the followers, a
        browser's own to that browser."""
        lectern = self.lectern
        presenter = lectern.presenter
        shared = [*lectern.followers, *(() if presenter is None else (presenter.client_id,))]
        end_frames((wire, shared if key is None else (key,))  # key None: the shared scene
                   for key, wire in list(self._wires.items()) if wire is not None)

    def _wires_busy(self) -> bool:
        return any(wire is not None and wire.busy() for wire in list(self._wires.values()))

    def _show_load(self, note: str) -> None:
        """Tell every panel whether the server keeps its frame rate (only when that changes)."""
        if note == self.load:
            return
        self.load = note
        if note:
            logger.warning("%s", note.replace("**", ""))
        with self._sessions_lock:
            sessions = list(self.sessions.values())
        for session in sessions:
            session.show_load(note)

    def stop(self) -> None:
        """Stop the loop and the server (idempotent)."""
        self._stop.set()
        self._wake.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        if self.bus is not None:
            self.bus.close()
            self.bus = None
        if self.ask_bus is not None:
            self.ask_bus.close()
            self.ask_bus = None
        self.lectern.close()  # the presenter lock, if this process holds it
        if self.task_store is not None:
            self.task_store.close()
        self.server.stop()

    @property
    def port(self) -> int:
        """The port the server really listens on (viser moves up if the port is busy)."""
        return self.server.get_port()


def create_server(
    host: str = DEFAULT_HOST, port: int = DEFAULT_PORT, *, verbose: bool = True, start_loop: bool = True,
    presenter_code: str | None = None, projector: bool = False,
    redis_url: str | None = None, worker_id: str | None = None, data_dir: str | Path | None = None,
    language: str = DEFAULT_LANGUAGE,
) -> App:
    """Build the app on (host, port) and start its loop.  port=0: an ephemeral port.
    presenter_code: the code that makes a browser the presenter (`App.lectern.code`; random if None).
    projector: every browser starts in the projector layout (large text, narrow panel).
    redis_url, worker_id: this app is the worker `worker_id` of a lecture on several processes
    (`app.cluster`): the presenter lock in Redis at `redis_url` (`app.lecture.gate.RedisGate`), and
    what followers on other processes see through it (`app.lecture.bus.Bus`).
    None (both): one process, as always, importing no redis.
    data_dir: the folder of what users keep (own presets and lessons, `app.own`; None: the
    platform's default, `app.userdata.default_data_dir()`), made when something is first saved.
    Share keeps its codes there too (`shares.sqlite3`, opened at the first share), or in Redis
    at `redis_url` on several processes (`app.sharestore.open_share_store`).
    language: the language a new browser's panel starts in ("en", "nl", "de": `app.i18n.LANGUAGES`;
    ValueError for another), each browser may choose its own in the Language dropdown.

    Reads every scene's presets and every lesson first: a broken file raises PresetError or
    LessonError (naming the file and the field or step) before the server starts.
    """
    translator(language)  # an unknown language, or a catalog that does not read: before the server starts
    check_presets()
    lessons()  # a broken lesson file: LessonError naming the file and the step
    gate: Gate | None = None
    if redis_url is not None:
        from app.lecture.gate import RedisGate  # noqa: PLC0415 - imports redis: only for several processes

        gate = RedisGate(redis_url, worker_id or "w1", presenter_code or new_code())
    server = viser.ViserServer(host=host, port=port, verbose=verbose)
    configure_scene(server, EULER_VIEW)
    own = OwnLibrary(data_dir, SCENES)
    for problem in own.problems:
        logger.warning("data folder: %s (left out)", problem)
    folder = Path(data_dir).expanduser() if data_dir else default_data_dir()
    bus_factory = None
    if redis_url is not None:
        from app.lecture.bus import Bus  # noqa: PLC0415 - a one-process app imports no redis

        url, worker = redis_url, worker_id or "w1"

        def bus_factory(server: viser.ViserServer, lectern: Lectern) -> Any:
            return Bus(server, lectern, url, worker)

    app = App(server, presenter_code=presenter_code, projector=projector, gate=gate, own=own,
              share_store=open_share_store(folder, redis_url), bus_factory=bus_factory, language=language)
    app.task_store = open_task_store(folder, redis_url)
    if redis_url is not None:
        from app.cluster.askbus import AskBus  # noqa: PLC0415 - a one-process app imports no redis

        app.ask_bus = AskBus(app.lectern.rounds, redis_url, worker_id or "w1", presenter=app.lectern.gate.presenter)
    if start_loop:
        app.start()
    return app


def _parse_args(argv: Sequence[str] | None, tr: Translator | None = None) -> argparse.Namespace:
    """The command line `argv` (None: sys.argv's), its help and errors in the language of `tr`
    (None: the CLI's, `app.cli_words.cli_language`)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    tr = cli_translator(argv) if tr is None else tr
    _ = tr.gettext
    parser = Parser(prog="rigid-body-lab", description=_("Rigid-body mechanics in the browser (viser)."), tr=tr)
    parser.add_argument("--host", default=DEFAULT_HOST,
                        help=_("interface to bind (default %(default)s; 0.0.0.0 exposes it to the network)"))
    parser.add_argument("--port", type=int, default=DEFAULT_PORT,
                        help=_("port (default %(default)s; viser tries the next one if busy)"))
    parser.add_argument("--presenter-code", metavar="CODE",
                        help=_("the code a browser types to present (default: a random one, printed at start)"))
    parser.add_argument("--projector", action="store_true",
                        help=_("start every browser in the projector layout (large text, narrow panel)"))
    parser.add_argument("--data-dir", metavar="PATH",
                        help=_("where own presets and lessons are kept (default: the platform's data folder, "
                               "e.g. ~/.local/share/rigid-body-lab)"))
    parser.add_argument("--workers", type=int, metavar="N",
                        help=_("serve with N app processes behind nginx on --port, one lecture through Redis "
                               "(needs nginx and redis-server)"))
    parser.add_argument("--redis", metavar="URL", default=os.environ.get(REDIS_ENV) or None,
                        help=_("with --workers: the Redis to use (redis://[:password@]host:port/0; default: "
                               "one started on a free local port).  Alone: this process is one worker of a "
                               "lecture (also read from ${variable})").format(variable=REDIS_ENV))
    parser.add_argument("--language", choices=tuple(LANGUAGES), default=DEFAULT_LANGUAGE,
                        help=_("the language a new browser's panel starts in, and this command's: {languages} "
                               "(default %(default)s; each browser may choose its own in the Language dropdown)"
                               ).format(
                            languages=", ".join(f"{code} ({name})" for code, name in LANGUAGES.items())))
    parser.add_argument("--worker-id", metavar="ID", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.presenter_code is None:
        args.presenter_code = os.environ.get(CODE_ENV) or None
    if args.workers is not None and args.workers < 1:
        parser.error(_("--workers needs at least 1"))
    return args


def _code_warning(code: str, tr: Translator | None = None) -> str:
    """A line for a presenter code that a guesser limited to the hall's rate could find in a
    90-minute lecture with more than 1e-4 chance; "" for a code long enough (in the language of `tr`)."""
    chance = guess_chance(90.0, code)
    if chance <= 1e-4:
        return ""
    return (tr or translator(DEFAULT_LANGUAGE)).gettext(
        "warning: a guesser could find the presenter code {code} with a chance of {chance} in 90 "
        "minutes; leave out --presenter-code for a random one of eight digits").format(code=repr(code),
                                                                                      chance=f"{chance:.1%}")


GC_THRESHOLDS = (10_000, 20, 20)
"""The cyclic garbage collector's thresholds in a serving process (`tune_collector`); Python's
are (700, 10, 10)."""


def tune_collector() -> None:
    """Set this process's garbage collector for serving (the command line calls it before the
    app starts; `create_server` does not, so tests keep Python's settings).

    What is loaded by now (the modules, ~80,000 objects) is frozen: full passes no longer scan it.
    A young pass comes every 10,000 net allocations instead of 700, so the objects a frame has in
    flight (messages queued for the sockets) are mostly gone before one, rather than promoted to
    the oldest generation, whose growth by a quarter starts a full pass.  A full pass scans every
    browser's objects (~4,000 a room): measured with 80 rooms playing (benchmarks/load_clients.py,
    its "full GC" columns), Python's settings gave a full pass of ~0.3 s every ~15 s, seen as a
    frame gap of ~0.4 s on every screen; tuned, none in 60 s."""
    gc.collect()
    gc.freeze()
    gc.set_threshold(*GC_THRESHOLDS)


def main(argv: Sequence[str] | None = None) -> None:
    """Command-line entry point (`rigid-body-lab`, `python -m app`): serve until Ctrl-C;
    `python -m app export ...` records a scene (`app.export`)."""
    arguments = list(sys.argv[1:] if argv is None else argv)
    if arguments[:1] == ["export"]:
        raise SystemExit(export_main(arguments[1:]))
    tr = cli_translator(arguments)
    args = _parse_args(arguments, tr)
    _ = tr.gettext
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s %(levelname)s %(message)s")
    if args.presenter_code is not None and not normalize_code(args.presenter_code):
        print("rigid-body-lab: " + _("the presenter code is empty"), file=sys.stderr)
        raise SystemExit(2)
    if args.workers is not None:
        from app.launch import launch_main  # noqa: PLC0415 - the launcher: only for --workers

        raise SystemExit(launch_main(args))
    worker = args.redis is not None
    tune_collector()
    if worker:
        signal.signal(signal.SIGTERM, _interrupt)  # a worker stops as on Ctrl-C: its lock released
    try:
        app = create_server(args.host, args.port, presenter_code=args.presenter_code, projector=args.projector,
                            redis_url=args.redis, worker_id=args.worker_id if worker else None,
                            verbose=not worker, data_dir=args.data_dir, language=args.language)
    except (PresetError, LessonError) as error:
        print(f"rigid-body-lab: {error}", file=sys.stderr)
        raise SystemExit(2) from None
    if worker:
        print(f"worker {app.lectern.gate.worker_id} on http://{args.host}:{app.port}", flush=True)
    else:
        print(_("open {url} in a browser; presenter code: {code}").format(url=f"http://{args.host}:{app.port}",
                                                                         code=app.lectern.code), flush=True)
    if args.presenter_code is not None and not worker and (warning := _code_warning(args.presenter_code, tr)):
        print(warning, flush=True)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        pass
    finally:
        app.stop()


def _interrupt(_signum: int, _frame: Any) -> None:
    raise KeyboardInterrupt


if __name__ == "__main__":
    main()
