"""The lecture hall: one presenter, protected by a code, and the browsers that follow.

- **The lock.**  `Lectern` holds the presenter code (`python -m app --presenter-code CODE`, or a
  random one printed at start) and the presenting session.  A browser presents by typing the
  code into `Presenter code` and pressing `Present`: a wrong code is refused with a message, at
  most MAX_TRIES per minute per browser; one presenter at a time; `Stop presenting` or a
  disconnect releases the lock.
- **One simulation, drawn once for everyone.**  The presenter's view draws its 3D into the
  shared scene (`server.scene`, under LIVE_ROOT) through a `Broadcast` target, and its panel into
  the presenter's own browser: the room advances and draws once per frame however many browsers
  follow, and viser sends the same messages to all of them.
- **Followers.**  Every other browser follows by default: it shows the shared scene and a small
  panel (`Follower`) with what the presenter shows (scene, preset, time, the controls' values,
  read only), a `Follow camera` toggle and `Explore on my own`, which gives it a private copy
  of the presenter's current state; `Follow presenter` comes back.  A browser that does not
  follow hides the shared scene with an invisible node of the same name in its own scope
  (viser draws a browser's own variant of a name over the shared one).
- **A presenter who leaves** (disconnect) leaves the last state on the followers' screens, with
  a note; a new presenter takes over with the code.
"""

from __future__ import annotations

import collections
import contextlib
import logging
import secrets
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

import viser

from app.kit.common import apply_camera

if TYPE_CHECKING:
    from app.session import Session

__all__ = ["FOLLOW_PERIOD", "LIVE_ROOT", "MAX_TRIES", "Broadcast", "Follower", "Lectern", "fork_simulation", "new_code"]

logger = logging.getLogger(__name__)

LIVE_ROOT = "/live"  # the presenter's 3D in the shared scene hangs under this node
MAX_TRIES = 5  # wrong codes a browser may try ...
TRIES_WINDOW = 60.0  # ... per this many seconds
FOLLOW_PERIOD = 0.5  # [s] the followers' panels refresh this often (they are many)
CAMERA_PERIOD = 0.1  # [s] the presenter's camera reaches the followers at most this often


def fork_simulation(scene: Any, sim: Any) -> Any:
    """A private copy of a simulation's current state, its own run starting there at t = 0."""
    fork = getattr(sim, "fork", None)
    if fork is not None:
        return fork()
    from app.kit.rigid import RigidBodySimulation
    from app.scenes.euler_angles import EulerAnglesSimulation
    from physics.dynamics import State

    copy: Any
    if isinstance(sim, RigidBodySimulation):
        copy = RigidBodySimulation(sim.model, State(sim.state.R_space_body, sim.state.omega_body, 0.0),
                                   angles=sim.angles, momentum_kind=sim.momentum_kind)
        copy.set_integrator(sim.integrator)
    elif isinstance(sim, EulerAnglesSimulation):
        copy = EulerAnglesSimulation(sim.angles_deg, sim.rates_deg, sim.moments)
    else:
        return scene.new_simulation()
    copy.preset = getattr(sim, "preset", None)
    return copy


def new_code() -> str:
    """A random presenter code: six digits, easy to read out in a lecture hall."""
    return f"{secrets.randbelow(10**6):06d}"


class Broadcast:
    """What a presenter's view draws to: the shared scene under LIVE_ROOT, the presenter's panel.

    It stands in for a `viser.ClientHandle` in the view: `scene` is `server.scene` (every
    browser), `gui`, `camera` and notifications are the presenter's, `atomic()` holds both.
    """

    root_prefix = LIVE_ROOT

    def __init__(self, server: viser.ViserServer, client: viser.ClientHandle) -> None:
        self.server = server
        self.presenter = client
        self.scene = server.scene
        self.gui = client.gui
        self.camera = client.camera
        self.client_id = client.client_id

    @contextlib.contextmanager
    def atomic(self) -> Iterator[None]:
        with self.server.atomic(), self.presenter.atomic():
            yield

    def add_notification(self, *args: Any, **kwargs: Any) -> Any:
        return self.presenter.add_notification(*args, **kwargs)


class Follower:
    """A following browser's panel: what the presenter shows, read only, and the way out."""

    def __init__(self, session: Session, lectern: Lectern) -> None:
        gui = session.client.gui
        self.session = session
        self.folder = gui.add_folder("Following the presenter")
        with self.folder:
            self.gui_status = gui.add_markdown("")
            self.gui_follow_camera = gui.add_checkbox("Follow camera", True,
                                                      hint="see what the presenter's camera sees")
            self.gui_explore = gui.add_button("Explore on my own", icon=viser.Icon.USER,
                                              hint="a private copy of the presenter's current state")
        self.gui_explore.on_click(session.guard("explore", lambda _event: session.explore()))
        self.gui_follow_camera.on_update(session.guard("follow camera", lambda _event: lectern.send_camera(self)))
        self.refresh(lectern)

    @property
    def follow_camera(self) -> bool:
        return bool(self.gui_follow_camera.value)

    def refresh(self, lectern: Lectern) -> None:
        status = lectern.status()
        if self.gui_status.content != status:
            self.gui_status.content = status

    def remove(self) -> None:
        self.folder.remove()


class Lectern:
    """The presenter lock, the live room and the followers (see the module docstring).

    Attributes:
        code: the presenter code.  presenter: the presenting session, or None.
        live_view: the view drawing the shared scene (kept after the presenter leaves, so the
            followers keep the last state, until a new presenter starts).
        left: True when the last presenter disconnected (the followers see the last state).
    """

    def __init__(self, server: viser.ViserServer, code: str | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.server = server
        self.code = code if code else new_code()
        self.presenter: Session | None = None
        self.live_view: Any = None
        self.left = False
        self.followers: dict[int, Follower] = {}
        self._tries: dict[int, collections.deque[float]] = collections.defaultdict(collections.deque)
        self._clock = clock
        self._lock = threading.RLock()
        self._since_status = 0.0
        self._camera_due = False
        self._since_camera = 0.0
        self._to_follow: list[Session] = []

    # ------------------------------------------------------------------ the lock
    def try_code(self, session: Session, code: str) -> str | None:
        """None if `session` may present with `code`, else the refusal (rate limit included)."""
        with self._lock:
            now = self._clock()
            tries = self._tries[session.client_id]
            while tries and tries[0] < now - TRIES_WINDOW:
                tries.popleft()
            if len(tries) >= MAX_TRIES:
                wait = TRIES_WINDOW - (now - tries[0])
                return f"Too many wrong codes: wait {wait:.0f} s before trying again."
            if not secrets.compare_digest(str(code).strip(), self.code):
                tries.append(now)
                return f"Wrong presenter code ({MAX_TRIES - len(tries)} tries left this minute)."
            if self.presenter is not None and self.presenter is not session:
                return "Someone else is presenting; they must stop first."
            return None

    def start(self, session: Session) -> None:
        """`session` presents: its room goes live; everyone else follows (or keeps exploring)."""
        with self._lock:
            self.presenter = session
            self.left = False
            # The app loop moves them (each in its own guard): not from the presenter's callback,
            # which holds the presenter's locks.
            self._to_follow = [other for other in self.sessions()
                               if other is not session and other.following_by_default()]
        self.refresh_followers()

    def release(self, session: Session, *, disconnected: bool) -> None:
        """The presenter stops (Stop presenting) or leaves (disconnect): the lock is free.  The
        followers keep the last state on screen with a note, until a new presenter starts."""
        with self._lock:
            if self.presenter is not session:
                return
            self.presenter = None
            self.left = disconnected
            view = self.live_view
            if view is not None:
                view.room.remove_view(view)  # detached: its nodes stay, nothing draws them
                view.room.playing = False
        self.refresh_followers()

    def _forget_live_view(self) -> None:
        """Remove the previous presenter's shared nodes (a new presenter draws afresh)."""
        view, self.live_view = self.live_view, None
        if view is not None:
            with contextlib.suppress(Exception):  # its nodes may be gone already
                view._root_node.remove()

    def make_live_view(self, session: Session, room: Any) -> Any:
        """The presenter's view of `room`: 3D into the shared scene, panel into its browser."""
        with self._lock:
            self._forget_live_view()
            view = room.scene(Broadcast(self.server, session.client), room, session.guard, session.report_error)
            self.live_view = view
        session.client.camera.on_update(lambda _camera: self._camera_moved(session))
        return view

    # ------------------------------------------------------------------ followers
    def sessions(self) -> list[Session]:
        return list(self._sessions())

    _sessions: Callable[[], Any] = staticmethod(lambda: [])  # set by the app: its open sessions

    @property
    def live_room(self) -> Any:
        return self.live_view.room if self.live_view is not None else None

    @property
    def live(self) -> bool:
        """Something is on the shared screen (a presenter, or the last state one left)."""
        return self.live_view is not None

    def add_follower(self, session: Session) -> Follower:
        follower = Follower(session, self)
        self.followers[session.client_id] = follower
        self.send_camera(follower)
        return follower

    def remove_follower(self, session: Session) -> None:
        follower = self.followers.pop(session.client_id, None)
        if follower is not None:
            follower.remove()

    def status(self) -> str:
        """The followers' panel text: who presents what, and the controls' values (read only)."""
        view = self.live_view
        if view is None:
            return "Nobody is presenting."
        room = view.room
        head = ("**The presenter has left**; this is the last state. A new presenter can take over."
                if self.left else "**Presenter:** " + ("▶ playing" if room.playing else "paused"))
        preset = getattr(room.sim, "preset", None)
        lines = [head, f"Scene **{room.scene.title}**" + (f" · preset **{preset}**" if preset else ""),
                 f"t = {room.sim.t:.1f} s · {room.time_scale:g}×"]
        lesson = getattr(self.presenter, "lesson_text", "") if self.presenter is not None else ""
        if lesson:
            lines.append(lesson)
        values = getattr(view, "control_values", None)
        if values is not None:
            lines.append("  \n".join(f"{label} = {value}" for label, value in values()))
        return "  \n".join(lines)

    def refresh_followers(self) -> None:
        for follower in list(self.followers.values()):
            if follower.session.closed:
                continue
            try:
                follower.refresh(self)
            except Exception:  # noqa: BLE001 - a follower that just left
                logger.debug("follower refresh failed", exc_info=True)

    def tick(self, dt: float) -> None:
        """Called by the app loop every frame: move the browsers that follow a new presenter,
        refresh the followers at FOLLOW_PERIOD, send the presenter's camera at CAMERA_PERIOD when
        it moved."""
        with self._lock:
            to_follow, self._to_follow = self._to_follow, []
        for session in to_follow:
            if not session.closed and session.following_by_default():
                session.guard("follow the presenter", session.follow)()
        self._since_status += dt
        if self._since_status >= FOLLOW_PERIOD and self.followers:
            self._since_status = 0.0
            self.refresh_followers()
        self._since_camera += dt
        if self._camera_due and self._since_camera >= CAMERA_PERIOD:
            self._camera_due = False
            self._since_camera = 0.0
            for follower in list(self.followers.values()):
                self.send_camera(follower)

    def _camera_moved(self, session: Session) -> None:
        if session is self.presenter:
            self._camera_due = True

    def send_camera(self, follower: Follower) -> None:
        """Put a follower's camera where the presenter's is (if it follows the camera)."""
        presenter = self.presenter
        if presenter is None or not follower.follow_camera:
            return
        source = presenter.client.camera
        try:
            camera = follower.session.client.camera
            camera.up_direction = tuple(source.up_direction)
            camera.position = tuple(source.position)
            camera.look_at = tuple(source.look_at)
            camera.fov = float(source.fov)
        except Exception:  # noqa: BLE001 - the presenter's camera is not known yet, or a client left
            logger.debug("camera not sent", exc_info=True)

    def reset_view(self, session: Session) -> None:
        apply_camera(session.client, self.live_room.scene.view)
