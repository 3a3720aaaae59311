"""The lecture hall: one presenter, protected by a code, and the browsers that follow.

**Who may write what** (the rule every part of the app keeps):

1. A room is changed only by the browser that controls it: its own room by a browser exploring
   alone, the live room by the presenter.  Nothing a follower's browser sends — GUI updates,
   gizmo drags, clicks on scene nodes, uploads, keys, camera moves — changes the presenter's
   room or the shared scene.
2. This holds by construction, not by checks: viser delivers a GUI event only to handles of the
   sender's own panel (`client.gui`), and a gizmo drag or node click to the handles of the scope
   it was addressed to; a handle in the shared scene (`server.scene`) answers *every* browser.
   So the shared scene holds drawings only: a presenter's view draws its 3D there through a
   `Broadcast` target, whose panel and whose interactive handles (`controls`: gizmos, clickable
   nodes) are the presenter's own (`app.kit.core.target`).  A follower's panel holds only its own
   things (follow the camera, explore, the projector layout, the presenter code); its session
   refuses every action on a room while it follows (PermissionError, said in its panel).
3. Tests: a hostile follower on a raw websocket that drags every gizmo it was sent, clicks every
   node, sends an update for every GUI id it has seen and uploads a mesh leaves the presenter's
   simulation bit-identical (tests/test_trust.py), and a browser follower's drags do not move
   the presenter's numbers (tests/test_browser_lecture.py).

The rest:

- **The lock.**  `Lectern` asks its gate (`app.cluster.gate`: `LocalGate` in one process,
  `RedisGate` across `--workers`; one set of rules) who presents and whether a code is right.
  The code (`python -m app --presenter-code CODE`, or a random one of eight digits in two
  groups, printed at start) is typed into `Presenter code` with or without its spaces or dashes;
  `Present` makes the browser the presenter.  While someone presents, every code gets the same
  answer, "Someone else is presenting", and is not evaluated; wrong codes are limited per
  browser (MAX_TRIES a minute) and over all browsers and processes together
  (`app.cluster.gate.MAX_WRONG` a sliding minute; the others wait, not evaluated): a script has
  <= 1e-4 chance in a 90-minute lecture, and when it stops the lecturer gets in within a
  minute.  Every refusal stays true while shown (`refusal_now`: a wait counts down and goes,
  "someone else is presenting" goes when they stop); `Stop presenting` or a disconnect releases
  the lock; the presenting process renews it from its loop (`tick`), so a process that dies
  frees it within `app.cluster.gate.LEASE_S`.
- **One simulation, drawn once for everyone.**  The presenter's view draws into the shared scene
  (under LIVE_ROOT): the room advances and draws once per frame however many browsers follow.
- **Followers.**  Every other browser follows by default: it shows the shared scene and a small
  panel (`app.hall.follower.Follower`, built and written here): who presents what (scene,
  preset, lesson step, time, the scene's key numbers), or plainly that the presenter stopped or
  left; the lesson step's caption over the 3D view and the presenter's open plot tab, read
  only (`caption`, `room_plot`); `Follow camera` (the presenter's viewing direction, framed for
  the follower's own screen) and `Explore on my own`, which gives it an exact copy of the room as shown now
  (`Room.fork`: state, time, traces, plots, replay history, playing), seen from where the
  browser looked.  While a presenter presents, "Lecture on" and `Follow presenter` top an
  explorer's panel (`app.hall.lecture_panel`).  On a narrow screen (a phone) the panel shrinks
  to one status line and a `Details` button, so the body stays in view; an explorer there
  keeps that layout (`app.hall.narrow`).
- **The pointer.**  The presenter ticks `Pointer` (or holds Shift) and clicks in the 3D view: a
  marker (a ring and a dot, and the short label typed under `Pointer label`) appears there on
  every follower's screen and fades within POINTER_SECONDS.  The click handler is registered on
  the presenter's own scene (`client.scene.on_click`), so only the presenter can point.
- **The room is live, on the presenter's panel.**  A badge counts the browsers following and
  exploring (`audience`); `Call everyone back` (`call_back`) offers every explorer the way back:
  each sees a countdown of CALL_BACK_SECONDS and follows again when it ends, unless it presses
  `Stay` (`stay`).  A class expects "eyes to the front" to bring everyone back, also the
  students who are not watching their panel; the one in the middle of an experiment keeps it
  with one press.  The lectern moves the called browsers from the app loop (`tick`), each in
  its own guard, and refreshes the lecture's part of every panel that is not following
  (`Seat.lecture_changed`) every FOLLOW_PERIOD.
- **A presenter who stops or leaves** leaves the last state on the followers' screens (a paused
  copy, which `Explore` copies), with a note; a new presenter takes over with the code.  A
  browser that connects after that follows nobody (`someone_presents` is false): it lands in its
  own room, told that the lecture ended, with the last room one click away (`live_copy`;
  `app.hall.lecture_panel`), and follows the next presenter.

**Who owns each piece of lecture state, and what ends it** (the one list; each end is done where
named; tested in tests/test_round_ends.py and tests/test_browser_round_ends.py).  "Stop"
is `Stop presenting`, "tab closed" a disconnect (`Session.close`), "lock lost" `_renew_lock`
finding someone else holds it; all three go through `release`.  "Worker killed": another
process's presenter whose process dies without a word.

Each piece, as *owner* → *what ends it*:

- **presenter lock** (`app.cluster.gate`): the presenter → stop, tab closed: `release` frees it;
  worker killed: its lease lapses within `app.cluster.gate.LEASE_S`.
- **question round** (`Rounds.current`, `app.ask.hub`; ROUND_KEY, `app.cluster.askbus`): the
  presenter who asked it (`Rounds.begin` in `start`; `Shown.owner`) → stop, tab closed, lock
  lost: `release` calls `Rounds.end_lecture`: the round closes, leaves every panel, answers are
  refused, and it is kept in `Rounds.earlier` (the next presenter's `Download earlier rounds
  (CSV)`, on any worker: `askbus.EARLIER_KEY`); the source deletes ROUND_KEY.  Worker killed:
  the other workers show it only while its owner holds the lock (<= LEASE_S), and its key
  lapses within `askbus.ROUND_LIVE_S`.
  `New question` ends it too (`Rounds.end`, kept the same way).
- **a student's question, arrow and gizmo** (`app.hall.ask.AnswerPanel`, the student's own
  scene, /ask/gizmo): the round → hidden once `Rounds.shown()` is None (the app loop's
  `_ask_tick`, on `Rounds.version`).
- **sphere, tips, true arrow; a State round's gallery** (`app.hall.ask.AskPanel`, the presenter's
  own scene, /ask and /ask/gallery): the presenter's browser and its round → hidden when the
  round ends (`AskPanel.refresh`) or the browser stops presenting (`set_shown(False)`); tab
  closed: viser drops the browser's nodes.
- **caption** (`caption`, from `Seat.caption_words`; `app.hall.caption`): the presenter →
  ("", "") once `presenter` is None or the hall is not LIVE, cleared on every follower by
  `release`'s `refresh_followers`; worker killed: the bus's `remote_ended` (hall LEFT).
- **pointer markers** (`Pointer`, shared scene, POINTER_ROOT): the presenter → fade within
  POINTER_SECONDS; `release` clears them; worker killed: `app.cluster.bus.Bus._drop_pointer`
  removes them when the bus takes it that the presenter left.
- **shared plot** (`room_plot`, `app.hall.room_plot`): the presenter's open plot tab → ("", [])
  once `presenter` is None or the remote hall is not LIVE: cleared on every follower.
- **lesson step** (`Seat.lesson_text` in `status`): the presenter's session → not in the
  followers' status once `presenter` is None or the hall is not LIVE.
- **call back** (`_called`): the presenter → `start`, `release` and `remote_ended` clear it.
- **live view** (the shared 3D under LIVE_ROOT: `live_view`, `_live_room`): the presenter →
  stop, tab closed: detached, its nodes the followers' last state (paused, `Explore` copies it)
  with a note, until the next presenter (`make_live_view` → `_forget_live_view`) or another
  process's (`show_remote`); worker killed: the bus's replica stays the same way, and `Explore`
  (`live_copy_noted`) copies the last state the bus kept of it, or its scene, saying so.
- **the room a lecture left** (LAST_KEY, `app.cluster.bus`): the lecture (its presenter's start,
  `Bus.lecture_id`) → offered only to that lecture's followers and newcomers; the next lecture's
  room replaces it; the key lapses after `LAST_TTL_S`.
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import enum
import logging
import math
import threading
import time
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import Any, Protocol

import numpy as np
import viser

from app.ask import Rounds
from app.cluster.gate import RENEW_PERIOD, Gate, GateUnavailable, LocalGate, Verdict
from app.cluster.gate import new_code as new_gate_code
from app.hall.follower import Follower, Hall, ended_head, ended_line, status_line, status_text, view_aspect
from app.kit.core.room import Room
from app.kit.draw.labels import POINTER, Screen
from app.kit.draw.screen import BODY_WIDTH_SHARE, NARROW_MARGIN, screen_of
from app.viser_internals import atomic_unless_captured

__all__ = ["BODY_WIDTH_SHARE", "CALL_BACK_SECONDS", "CAMERA_PERIOD", "FOLLOW_PERIOD", "LIVE_ROOT", "MAX_TRIES",
           "POINTER_ROOT", "POINTER_SECONDS", "Broadcast", "Lectern", "Mode", "Pointer", "RemoteShow", "Seat",
           "fitted_camera", "new_code", "pointed_at"]

logger = logging.getLogger(__name__)

LIVE_ROOT = "/l"  # the presenter's 3D in the shared scene hangs under this node (every follower message
# carries its node's name: short)
POINTER_ROOT = LIVE_ROOT + "/pointer"  # the pointer's markers (`Pointer`), under the live root
MAX_TRIES = 5  # wrong codes a browser may try ...
TRIES_WINDOW = 60.0  # ... per this many seconds
DOWN_NOTE_SECONDS = 10.0  # [s] "the presenter lock does not answer" stays this long (then try again)
FOLLOW_PERIOD = 0.5  # [s] the followers' panels refresh this often (they are many)
CAMERA_PERIOD = 0.1  # [s] the presenter's camera reaches the followers at most this often
POINTER_SECONDS = 4.0  # [s] a pointer marker stays this long, fading
POINTER_MARKERS = 4  # at most this many at once (the oldest goes)
POINTER_COLOR = (235, 0, 140)
POINTER_RADIUS = 0.22  # [scene units] of the ring
POINTER_LABEL_CHARS = 40
CALL_BACK_SECONDS = 10.0  # [s] an explorer called back has to press Stay before it follows again
FOLLOWER_SCREENS_PERIOD = 0.25  # [s] the followers' kinds of screen are looked at again after this long
MAX_LABEL_SCREENS = 6  # a presenter's labels are laid out for its screen and at most 5 kinds of follower's


class Mode(enum.StrEnum):
    """What a browser's session shows."""

    OWN = "own"  # its own room (exploring alone)
    PRESENTING = "presenting"  # its room, live for everyone who follows
    FOLLOWING = "following"  # the live room, read only


class Seat(Protocol):
    """What the lectern needs of a browser's session (`app.session.Session` is one)."""

    client: viser.ClientHandle
    client_id: int
    closed: bool
    mode: Mode
    own_folders: tuple[Any, ...]
    """The session's own folders (projector, notes, lecture), which a collapsed follower's panel hides."""

    def guard(self, where: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        """`fn` run under the session's locks, its errors shown in its panel, never raised."""
        ...

    def following_by_default(self) -> bool:
        """True if a new presenter should pull this browser along."""
        ...

    def follow(self) -> None:
        """Follow the presenter (the lectern calls it when a presenter starts)."""
        ...

    def explore(self) -> None:
        """Leave the presenter with an exact copy of the live room (the follower's button)."""
        ...

    def report_error(self, where: str, error: BaseException) -> None:
        """Log `error` and show it in the session's panel."""
        ...

    def lesson_text(self) -> str:
        """The presenter's current lesson step, or ""."""
        ...

    def stop_presenting(self) -> None:
        """Stop presenting (the lectern calls it when this browser's lock was lost)."""
        ...

    def lecture_changed(self) -> None:
        """Show the lecture's state in the panel (who follows, a call back): called by the lectern,
        outside the session's guard (it only writes widgets, and only what changed)."""
        ...

    def caption_words(self) -> tuple[str, str]:
        """(head, words) of the presenter's lesson caption; ("", "") for none (`app.hall.caption`)."""
        ...


@dataclasses.dataclass
class RemoteShow:
    """What a presenter on another process shows, as this process's followers see it
    (`app.cluster.bus` writes it; the shared scene's nodes come through the bus too).

    Attributes:
        worker: the presenting process's worker id.  hall: LIVE, STOPPED or LEFT.
        title: the scene's title.  status, line: the followers' panel text and its one line.
        caption: (head, words) of the lesson caption.
        plot: (tab, elements) of the presenter's open plot tab (`Lectern.room_plot`; elements
            `app.hall.room_plot.ChartCopy` / `MarkdownCopy`), ("", ()) for none.
        camera: the presenter's camera (position, look_at, up [scene units], fov [rad], aspect
            [width / height]) or None before it is known.
    """

    worker: str
    hall: Hall = Hall.LIVE
    title: str = ""
    status: str = ""
    line: str = ""
    caption: tuple[str, str] = ("", "")
    plot: tuple[str, tuple[Any, ...]] = ("", ())
    camera: dict[str, Any] | None = None


def new_code() -> str:
    """A random presenter code: eight digits in two groups ("4821 0937"), easy to read out in a
    lecture hall and long enough not to be guessed (`app.cluster.gate.new_code`)."""
    return new_gate_code()


class Broadcast:
    """The presenter's draw target (`app.kit.core.target.DrawTarget`): the 3D into the shared scene
    under LIVE_ROOT, the panel, the interactive handles and the camera in the presenter's browser."""

    root_prefix = LIVE_ROOT

    def __init__(self, server: viser.ViserServer, client: viser.ClientHandle,
                 screens: Callable[[], list[Screen]] | None = None) -> None:
        self.server = server
        self.presenter = client
        self.scene = server.scene
        self.gui = client.gui
        self.controls = client.scene  # gizmos and clickable nodes: the presenter's only
        self.camera = client.camera
        self.client_id = client.client_id
        self.screens = screens  # the screens the shared labels are laid out for (`Lectern.label_screens`)

    def atomic(self) -> contextlib.AbstractContextManager[None]:
        """The shared scene's and the presenter's `atomic()`, except inside the app loop's frame
        for those a wire holds together (`app.viser_internals.atomic_unless_captured`)."""
        return atomic_unless_captured(self.server, self.presenter)

    def add_notification(self, title: str, body: str, **kwargs: Any) -> Any:
        return self.presenter.add_notification(title, body, **kwargs)


def fitted_camera(position: Any, look_at: Any, aspect_from: float, aspect_to: float, fov: float | None = None,
                  up: Any = (0.0, 0.0, 1.0)) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The presenter's camera (position, look_at [scene units], aspect, vertical `fov` [rad])
    made for a narrower view of aspect `aspect_to`, with the same fov and viewing direction.

    The scenes frame their body in the left BODY_WIDTH_SHARE of a wide view (the panel floats on
    the right), so only that share of the presenter's width is kept, with a margin: the distance
    grows by NARROW_MARGIN BODY_WIDTH_SHARE aspect_from / aspect_to (tan(h/2) = aspect tan(fov/2),
    h the horizontal angle), and with `fov` given both points move sideways (along the view's right, from `up`)
    by (BODY_WIDTH_SHARE - 1) d aspect_from tan(fov/2), d = |position - look_at|, so that share's
    middle is the narrow view's middle.  A view at least that wide keeps the presenter's camera."""
    eye, target = np.asarray(position, dtype=float), np.asarray(look_at, dtype=float)
    factor = BODY_WIDTH_SHARE * aspect_from / aspect_to if aspect_to > 0.0 else 1.0
    if factor > 1.0:
        factor *= NARROW_MARGIN
        offset = eye - target
        if fov is not None:
            forward = -offset / np.linalg.norm(offset)
            right = np.cross(forward, np.asarray(up, dtype=float))
            if np.linalg.norm(right) > 1e-9:  # looking along `up` has no sideways
                shift = (BODY_WIDTH_SHARE - 1.0) * np.linalg.norm(offset) * aspect_from * math.tan(fov / 2.0)
                target = target + shift * right / np.linalg.norm(right)
        eye = target + factor * offset
    return (float(eye[0]), float(eye[1]), float(eye[2])), (float(target[0]), float(target[1]), float(target[2]))


def pointed_at(ray_origin: Any, ray_direction: Any, look_at: Any) -> np.ndarray:
    """Where a click points in 3D: the point of the click's ray nearest the camera's look-at
    point (a click on the body lands near the body; the scene has no depth to read back).
    ValueError for a ray that is not finite or has no direction."""
    origin, direction = np.asarray(ray_origin, dtype=float), np.asarray(ray_direction, dtype=float)
    target = np.asarray(look_at, dtype=float)
    length = float(np.linalg.norm(direction))
    if origin.shape != (3,) or direction.shape != (3,) or not (np.all(np.isfinite(origin))
                                                              and np.all(np.isfinite(direction)) and length > 0.0):
        raise ValueError(f"a click's ray {ray_origin!r} + s {ray_direction!r} is not a ray")
    direction = direction / length
    s = max(float((target - origin) @ direction), 0.0)
    return origin + s * direction


class Pointer:
    """The presenter's markers in the shared scene (under LIVE_ROOT, so a browser exploring on
    its own, which hides LIVE_ROOT, does not see them): a ring facing the camera, a dot and an
    optional label each, fading over POINTER_SECONDS."""

    def __init__(self, scene: Any) -> None:
        self.scene = scene
        self.markers: list[tuple[float, list[Any]]] = []  # (age [s], handles)
        self.count = 0

    def add(self, point: np.ndarray, facing: np.ndarray, label: str, labels: Any = None) -> None:
        """A marker at `point` [scene units], its ring perpendicular to `facing`; its label is
        registered with `labels` (the live view's `LabelLayer`), if given, above every other
        (POINTER): the others make room for it."""
        if len(self.markers) >= POINTER_MARKERS:
            self._remove(self.markers.pop(0)[1])
        facing = facing / float(np.linalg.norm(facing))
        helper = np.array([0.0, 0.0, 1.0]) if abs(facing[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        u = np.cross(facing, helper)
        u /= float(np.linalg.norm(u))
        v = np.cross(facing, u)
        angles = np.linspace(0.0, 2.0 * np.pi, 49)
        ring = POINTER_RADIUS * (np.cos(angles)[:, None] * u + np.sin(angles)[:, None] * v)
        segments = np.stack([ring[:-1], ring[1:]], axis=1).astype(np.float32)
        name = f"{POINTER_ROOT}/{self.count}"
        self.count += 1
        frame = self.scene.add_frame(name, show_axes=False, position=tuple(float(x) for x in point))
        handles = [frame,
                   self.scene.add_line_segments(f"{name}/ring", segments, POINTER_COLOR, thickness=7.0,
                                                thickness_units="screen"),
                   self.scene.add_icosphere(f"{name}/dot", radius=0.05, color=POINTER_COLOR, subdivisions=2)]
        if label:
            handle = self.scene.add_label(f"{name}/label", label, position=tuple(1.3 * POINTER_RADIUS * u),
                                          font_screen_scale=1.6, anchor="bottom-left")
            handles.append(handle)
            if labels is not None:
                labels.add(handle, POINTER)
                labels.settle()
        self.markers.append((0.0, handles))

    def tick(self, dt: float) -> None:
        """Age the markers: each shrinks to nothing over POINTER_SECONDS, then goes."""
        kept = []
        for age, handles in self.markers:
            age += dt
            if age >= POINTER_SECONDS:
                self._remove(handles)
                continue
            shrink = round(1.0 - (age / POINTER_SECONDS) ** 3, 2)  # stays large, then goes quickly
            if handles[0].scale != shrink:
                handles[0].scale = shrink
            kept.append((age, handles))
        self.markers = kept

    def clear(self) -> None:
        for _, handles in self.markers:
            self._remove(handles)
        self.markers = []

    @staticmethod
    def _remove(handles: list[Any]) -> None:
        with contextlib.suppress(Exception):  # gone already
            handles[0].remove()


class Lectern:
    """The presenter lock, the live room and the followers (see the module docstring).

    Attributes:
        code: the presenter code.  presenter: the presenting seat, or None.
        hall: what the shared screen shows (`app.hall.follower.Hall`).
        live_view: the view drawing the shared scene (kept after the presenter stops or leaves,
            its nodes the followers' last state, until a new presenter starts).
    """

    def __init__(self, server: viser.ViserServer, code: str | None = None,
                 clock: Callable[[], float] = time.monotonic, gate: Gate | None = None) -> None:
        self.server = server
        self.gate: Gate = gate if gate is not None else LocalGate(code if code else new_code(), clock)
        """The presenter lock and the code (`app.cluster.gate`)."""
        self.code = self.gate.code
        self.presenter: Seat | None = None
        self.hall = Hall.EMPTY
        self.live_view: Any = None
        self._live_room: Room | None = None
        self._followers: dict[int, tuple[Seat, Follower]] = {}  # by client id
        self._tries: dict[int, collections.deque[float]] = collections.defaultdict(collections.deque)
        self._refused: dict[int, str] = {}  # client id -> "wrong", "wait", "hall", "busy" or "down": its last refusal
        self._hall_wait: dict[int, float] = {}  # client id -> when [clock s] the hall's limit lets it try
        self._since_renew = 0.0
        self._refusal_watchers: dict[int, tuple[Seat, Callable[[], None]]] = {}  # `watch_refusal`
        self._since_refusals = 0.0
        self._clock = clock
        self._lock = threading.RLock()
        self._since_status = 0.0
        self._camera_due = False
        self._since_camera = 0.0
        self._to_follow: list[Seat] = []
        self._to_refresh: list[Seat] = []  # seats whose panel the next tick refreshes
        self._called: dict[int, tuple[Seat, float]] = {}  # explorers called back: (seat, deadline [clock s])
        self._watched: set[int] = set()  # client ids whose camera the lectern hears
        self.pointer = Pointer(server.scene) if server is not None else None
        self.rounds = Rounds()
        """The class's questions (`app.ask.hub`): the current round, asked by the presenter."""
        self.seats: Callable[[], list[Seat]] = lambda: []
        """Set by the app: its open sessions."""
        # One lecture across processes (`app.cluster.bus`; unused on one process):
        self.remote: RemoteShow | None = None
        """A presenter on another process, shown here (None: the shared screen is this process's)."""
        self.events: list[Callable[[str], None]] = []
        """Told "start", "stopped" or "left" when this process's presenter starts, stops or leaves,
        "call_back" when it calls everyone back."""
        self.remote_audience: Callable[[], tuple[int, int]] = lambda: (0, 0)
        """(following, exploring) on the other processes, added to the presenter's badge."""
        self.fetch_remote: Callable[[], Room] | None = None
        """An exact copy of the remote presenter's room (Explore on this process)."""
        self.fetch_remote_noted: Callable[[], tuple[Room, str]] | None = None
        """The same with a note: "" for an exact copy, else what the copy is (the presenter's
        process gone: the last state seen here, or only the scene)."""
        self.clear_shared: Callable[[], None] = lambda: None
        """Remove another process's nodes from the shared scene (before this one draws there)."""
        self._follower_screens: tuple[float, list[Screen]] | None = None  # (when, `follower_screens`)
        self.remote_screens: Callable[[], list[Screen]] = lambda: []
        """The kinds of follower's screen on the other processes (`label_screens` adds them)."""

    # ------------------------------------------------------------------ the lock
    def _recent_tries(self, seat: Any) -> collections.deque[float]:
        """`seat`'s wrong codes within the last TRIES_WINDOW (older ones dropped)."""
        now = self._clock()
        tries = self._tries[seat.client_id]
        while tries and tries[0] < now - TRIES_WINDOW:
            tries.popleft()
        return tries

    def _wait_words(self, tries: collections.deque[float], head: str = "Too many wrong codes") -> str:
        wait = max(1, math.ceil(TRIES_WINDOW - (self._clock() - tries[0])))
        return f"{head}: wait {wait} s before trying again."

    def _holder(self, seat: Any) -> str:
        return self.gate.holder(seat.client_id)

    def _someone_else(self, seat: Any) -> bool:
        """Someone other than `seat` presents (here or, through the gate, on another process)."""
        if self.presenter is not None and self.presenter is not seat:
            return True
        try:
            holder = self.gate.presenter()
        except GateUnavailable:
            return False
        return holder is not None and holder != self._holder(seat)

    def try_code(self, seat: Any, code: str) -> str | None:
        """None if `seat` may present with `code` (the gate's lock is then `seat`'s, for `start`),
        else the refusal: someone else presents (every code, not evaluated), the browser's or
        the hall's limit of wrong codes (not evaluated), a wrong code, or the lock unreachable.
        The refusal's words as they are now come from `refusal_now`."""
        with self._lock:
            cid = seat.client_id
            if self.presenter is not None and self.presenter is not seat:
                self._refused[cid] = "busy"
                return self.refusal_now(seat)
            tries = self._recent_tries(seat)
            if len(tries) >= MAX_TRIES:
                self._refused[cid] = "wait"
                return self._wait_words(tries)
            try:
                answer = self.gate.claim(self._holder(seat), str(code))
            except GateUnavailable as error:
                logger.warning("presenter code not checked: %s", error)
                self._hall_wait[cid] = self._clock() + DOWN_NOTE_SECONDS
                self._refused[cid] = "down"
                return self.refusal_now(seat)
            if answer.verdict is Verdict.OK:
                self._refused.pop(cid, None)
                return None
            if answer.verdict is Verdict.WRONG:
                tries.append(self._clock())
                self._refused[cid] = "wrong"
            elif answer.verdict is Verdict.WAIT:
                self._hall_wait[cid] = self._clock() + answer.wait_s
                self._refused[cid] = "hall"
            else:
                self._refused[cid] = "busy"
            return self.refusal_now(seat)

    def refusal_now(self, seat: Any) -> str | None:
        """`seat`'s last refusal (`try_code`) in the words true now, or None once it no longer
        holds: the wait counts down and ends, the tries left grow back as the minute passes,
        "someone else is presenting" ends when they stop or leave."""
        with self._lock:
            cid = seat.client_id
            kind = self._refused.get(cid)
            tries = self._recent_tries(seat)
            words: str | None = None
            if kind in ("wait", "wrong") and len(tries) >= MAX_TRIES:
                words = self._wait_words(tries, "Too many wrong codes" if kind == "wait" else
                                         "Wrong presenter code, no tries left")
            elif kind == "wrong" and tries:
                left = MAX_TRIES - len(tries)
                words = f"Wrong presenter code ({left} {'try' if left == 1 else 'tries'} left this minute)."
            elif kind == "hall" and self._hall_wait.get(cid, 0.0) > self._clock():
                wait = max(1, math.ceil(self._hall_wait[cid] - self._clock()))
                words = (f"Too many wrong codes in this lecture hall (someone may be guessing): wait {wait} s "
                         "before trying again.")
            elif kind == "busy" and self._someone_else(seat):
                words = "Someone else is presenting; they must stop first."
            elif kind == "down" and self._hall_wait.get(cid, 0.0) > self._clock():
                words = "The presenter lock does not answer (the lecture's Redis); try again in a moment."
            if words is None:
                self._refused.pop(cid, None)
                self._hall_wait.pop(cid, None)
            return words

    def watch_refusal(self, seat: Any, show: Callable[[], None] | None) -> None:
        """Call `show()` (in `seat`'s guard) every FOLLOW_PERIOD while `seat` has a refusal on
        screen, so its words stay true (`refusal_now`); None: stop."""
        with self._lock:
            if show is None:
                self._refusal_watchers.pop(seat.client_id, None)
            else:
                self._refusal_watchers[seat.client_id] = (seat, show)

    def start(self, seat: Seat) -> None:
        """`seat` presents: its room goes live; everyone else follows (or keeps exploring)."""
        with self._lock:
            try:
                self.gate.start(self._holder(seat))  # a lock lost meanwhile: `tick` stops the presenter
            except GateUnavailable as error:
                logger.warning("presenter lock not confirmed: %s", error)
            self._since_renew = 0.0
            self.presenter = seat
            self.hall = Hall.LIVE
            self.rounds.begin(self._holder(seat))  # its rounds are its own; one left from before ends
            self._called.clear()
            self._to_refresh.extend(self.seats())  # explorers: "Lecture on"
            # The app loop moves them (each in its own guard): not from the presenter's callback,
            # which holds the presenter's locks.
            self._to_follow = [other for other in self.seats()
                               if other is not seat and other.following_by_default()]
        self.refresh_followers()
        self._tell("start")

    def release(self, seat: Seat, *, disconnected: bool) -> None:
        """The presenter stops (Stop presenting) or leaves (disconnect): the lock is free, its
        question round ends (kept as an earlier round), its pointer markers go.  The followers
        keep the last state on screen (a paused copy of the room, which is what Explore then
        copies), with a note, until a new presenter starts (the module docstring's table)."""
        with self._lock:
            try:
                self.gate.release(self._holder(seat))
            except GateUnavailable as error:  # the lease lapses by itself
                logger.warning("presenter lock not released: %s", error)
            if self.presenter is not seat:
                return
            self.presenter = None
            self.hall = Hall.LEFT if disconnected else Hall.STOPPED
            self.rounds.end_lecture("the presenter left" if disconnected else "the presenter stopped")
            self._called.clear()
            self._to_refresh.extend(self.seats())
            if self.pointer is not None:
                self.pointer.clear()
            view, room = self.live_view, self._live_room
            if view is not None and room is not None:
                with room.lock:
                    room.remove_view(view)  # detached: its nodes stay, nothing draws them
                    last = room.fork()
                last.playing = False
                self._live_room = last
        self.refresh_followers()
        self._tell("left" if disconnected else "stopped")

    def _tell(self, event: str) -> None:
        for listener in list(self.events):
            try:
                listener(event)
            except Exception:  # noqa: BLE001 - the bus must not break the lock
                logger.exception("lecture event %s", event)

    def _forget_live_view(self) -> None:
        """Remove the previous presenter's shared nodes (a new presenter draws afresh), also
        those of a presenter on another process."""
        if self.remote is not None:
            self.remote = None
            self.clear_shared()
        view, self.live_view = self.live_view, None
        if view is not None:
            with contextlib.suppress(Exception):  # its nodes may be gone already
                view._root_node.remove()

    def make_live_view(self, seat: Seat, room: Room) -> Any:
        """The presenter's view of `room`: 3D into the shared scene, panel and controls in its browser."""
        with self._lock:
            self._forget_live_view()
            view = room.scene(Broadcast(self.server, seat.client, self.label_screens), room, seat.guard,
                              seat.report_error)
            self.live_view = view
            self._live_room = room
        self._watch_camera(seat)
        return view

    def _watch_camera(self, seat: Seat) -> None:
        """Hear `seat`'s camera (once per browser): a presenter's moves reach the followers, a
        follower's view size sets its layout."""
        if seat.client_id in self._watched:
            return
        self._watched.add(seat.client_id)
        seat.client.camera.on_update(lambda _camera: self._camera_moved(seat))

    # ------------------------------------------------------------------ followers
    @property
    def live_room(self) -> Room | None:
        """The room on the shared screen now (the presenter's, or the last state one left)."""
        return self._live_room if self.live_view is not None else None

    @property
    def live(self) -> bool:
        """Something is on the shared screen (a presenter, or the last state one left; here or
        on another process)."""
        return self.live_view is not None or self.remote is not None

    @property
    def someone_presents(self) -> bool:
        """A presenter presents, on this process or another."""
        remote = self.remote
        return self.presenter is not None or (remote is not None and remote.hall is Hall.LIVE)

    def live_title(self) -> str:
        """The title of the scene on the shared screen ("" for none)."""
        room, remote = self.live_room, self.remote
        if room is not None:
            return str(room.scene.title)
        return remote.title if remote is not None else ""

    def live_copy(self) -> Room:
        """An exact copy of the room on the shared screen (`Room.fork`; through the bus when it is
        another process's).  RuntimeError when nothing is shown."""
        live = self.live_room
        if live is not None:
            return live.fork()
        if self.remote is not None and self.fetch_remote is not None:
            return self.fetch_remote()
        raise RuntimeError("there is nothing on the shared screen to explore")

    def live_copy_noted(self) -> tuple[Room, str]:
        """(`live_copy`, a note): "" for an exact copy; a remote presenter's process that died
        leaves the best copy to be had with a note saying what it is (`fetch_remote_noted`)."""
        if self.live_room is None and self.remote is not None and self.fetch_remote_noted is not None:
            return self.fetch_remote_noted()
        return self.live_copy(), ""

    # ------------------------------------------------------------------ a presenter on another process
    def show_remote(self, show: RemoteShow) -> None:
        """A presenter on another process starts: this process's last live view goes, `show`
        is on the shared screen and the browsers that follow by default follow it."""
        with self._lock:
            if self.live_view is not None:
                self._forget_live_view()
                self._live_room = None
            self.remote = show
            self.hall = show.hall
            self._called.clear()
            self._to_refresh.extend(self.seats())
            self._to_follow = [seat for seat in self.seats()
                               if seat is not self.presenter and seat.following_by_default()]
        self.refresh_followers()

    def remote_ended(self, left: bool) -> None:
        """The remote presenter stopped (or left: its process ended or said so): the last state
        stays on screen with a note."""
        with self._lock:
            remote = self.remote
            if remote is None or remote.hall is not Hall.LIVE:
                return
            remote.hall = self.hall = Hall.LEFT if left else Hall.STOPPED
            lines = remote.status.split("  \n")
            remote.status = "  \n".join([ended_head(remote.hall), *lines[1:]])
            remote.line = ended_line(remote.hall, remote.title)
            self._called.clear()
            self._to_refresh.extend(self.seats())
        self.refresh_followers()

    def remote_call_back(self) -> int:
        """The remote presenter calls everyone back: this process's explorers (`call_back`)."""
        with self._lock:
            deadline = self._clock() + CALL_BACK_SECONDS
            explorers = [other for other in self.seats() if not other.closed and other.mode is Mode.OWN]
            for other in explorers:
                self._called[other.client_id] = (other, deadline)
            self._to_refresh.extend(explorers)
        return len(explorers)

    @property
    def followers(self) -> Mapping[int, Follower]:
        """The following browsers' panels by client id (read only: `add_follower`,
        `remove_follower` change them)."""
        entries = list(self._followers.items())  # one step: other threads add and remove followers
        return MappingProxyType({client_id: follower for client_id, (_, follower) in entries})

    def add_follower(self, seat: Seat) -> Follower:
        """`seat` follows: its panel (`Follower`, hiding the seat's own folders when collapsed),
        the status written, the presenter's camera sent."""
        follower = Follower(seat.client, seat.guard, explore=seat.explore, follow_camera_changed=self.send_camera,
                            own_folders=seat.own_folders)
        follower.show_status(self.status(), self.status_line())
        follower.show_caption(*self.caption())
        follower.show_plot(*self.room_plot())
        self._followers[seat.client_id] = (seat, follower)
        self._follower_screens = None
        with self._lock:
            self._called.pop(seat.client_id, None)
        self._watch_camera(seat)
        self.send_camera(follower)
        return follower

    def remove_follower(self, seat: Seat, *, disconnected: bool = False) -> None:
        """`seat` follows no more: its panel goes (nothing to remove if its browser has
        `disconnected`)."""
        entry = self._followers.pop(seat.client_id, None)
        self._follower_screens = None
        if entry is not None and not disconnected:
            entry[1].remove()

    def audience(self) -> tuple[int, int]:
        """(following, exploring): the browsers following the shared screen, and the others
        (not the presenter) that show a room of their own (the presenter's badge)."""
        following = sum(1 for seat, _ in list(self._followers.values()) if not seat.closed)
        presenter = self.presenter
        exploring = sum(1 for seat in self.seats()
                        if seat is not presenter and not seat.closed and seat.mode is Mode.OWN)
        return following, exploring

    def total_audience(self) -> tuple[int, int]:
        """`audience` summed over every process (the presenter's badge)."""
        following, exploring = self.audience()
        if self.presenter is None:
            return following, exploring
        more_following, more_exploring = self.remote_audience()
        return following + more_following, exploring + more_exploring

    def call_back(self, seat: Seat) -> int:
        """The presenter asks every explorer back: each follows again in CALL_BACK_SECONDS unless
        it presses Stay (`stay`); the number asked.  PermissionError for anyone but the presenter."""
        with self._lock:
            if seat is not self.presenter:
                raise PermissionError("only the presenter can call everyone back")
            deadline = self._clock() + CALL_BACK_SECONDS
            explorers = [other for other in self.seats()
                         if other is not seat and not other.closed and other.mode is Mode.OWN]
            for other in explorers:
                self._called[other.client_id] = (other, deadline)
            self._to_refresh.extend([seat, *explorers])  # shown by the loop, not from the presenter's callback
        self._tell("call_back")
        return len(explorers)

    def call_back_left(self, seat: Seat) -> float | None:
        """Seconds [s] before `seat`, called back, follows again; None if it is not called."""
        entry = self._called.get(seat.client_id)
        if entry is None or entry[0] is not seat:
            return None
        return max(0.0, entry[1] - self._clock())

    def stay(self, seat: Seat) -> None:
        """`seat`, called back, keeps exploring."""
        with self._lock:
            entry = self._called.get(seat.client_id)
            if entry is not None and entry[0] is seat:
                del self._called[seat.client_id]

    def _follower_resized(self, seat: Seat, follower: Follower) -> None:
        """A follower's view changed size (or its camera moved): collapse its panel on a narrow
        screen, and frame the presenter's view for its aspect."""
        if seat.guard("follower layout", follower.fit_screen)():
            self.send_camera(follower)

    def _key_numbers(self) -> list[str]:
        view = self.live_view
        if view is None:
            return []
        try:
            return list(view.key_numbers())
        except Exception:  # noqa: BLE001 - a status line must not break the followers' refresh
            logger.debug("key numbers failed", exc_info=True)
            return []

    def status(self) -> str:
        """The followers' panel text (`app.hall.follower.status_text`)."""
        presenter, remote = self.presenter, self.remote
        if remote is not None and presenter is None:
            return remote.status
        lesson = presenter.lesson_text() if presenter is not None and self.hall is Hall.LIVE else ""
        return status_text(self.live_room, self.hall, lesson, self._key_numbers())

    def status_line(self) -> str:
        """The followers' status in one line, for a narrow screen (`app.hall.follower.status_line`)."""
        if self.remote is not None and self.presenter is None:
            return self.remote.line
        return status_line(self.live_room, self.hall)

    def caption(self) -> tuple[str, str]:
        """(head, words) of the lesson caption over every follower's 3D view: the presenter's
        (`Seat.caption_words`) while one presents; ("", "") otherwise."""
        presenter, remote = self.presenter, self.remote
        if presenter is None and remote is not None:
            return remote.caption if remote.hall is Hall.LIVE else ("", "")
        if presenter is None or self.hall is not Hall.LIVE:
            return "", ""
        return presenter.caption_words()

    def room_plot(self) -> tuple[str, list[Any]]:
        """(tab, elements): the plot tab the presenter has open and its panel elements, which
        every follower sees copied (`app.kit.view.SceneView.room_plot`; a presenter on another
        process: what the bus brought, `RemoteShow.plot`); ("", []) for none."""
        view, presenter, remote = self.live_view, self.presenter, self.remote
        if presenter is None and remote is not None:
            return (remote.plot[0], list(remote.plot[1])) if remote.hall is Hall.LIVE else ("", [])
        if presenter is None or view is None:
            return "", []
        try:
            return view.room_plot()
        except Exception:  # noqa: BLE001 - the followers' refresh must not break
            logger.debug("room plot failed", exc_info=True)
            return "", []

    def refresh_followers(self) -> None:
        """Write the status, the caption and the presenter's plot into every follower's panel."""
        status, line = self.status(), self.status_line()
        caption, plot = self.caption(), self.room_plot()
        for seat, follower in list(self._followers.values()):
            if seat.closed:
                continue
            try:
                follower.show_status(status, line)
                follower.show_caption(*caption)
                follower.show_plot(*plot)
            except Exception:  # noqa: BLE001 - a follower that just left
                logger.debug("follower refresh failed", exc_info=True)

    def refresh_seats(self, seats: list[Seat] | None = None) -> None:
        """Write the lecture's state into the panel of every seat that does not follow (or of
        `seats`): the presenter's badge, the explorers' "Lecture on" and countdowns."""
        for seat in self.seats() if seats is None else seats:
            if seat.closed or seat.mode is Mode.FOLLOWING:
                continue
            try:
                seat.lecture_changed()
            except Exception:  # noqa: BLE001 - a browser that just left
                logger.debug("lecture refresh failed", exc_info=True)

    def tick(self, dt: float) -> None:
        """Called by the app loop every frame: move the browsers that follow a new presenter and
        the explorers whose call back ran out, refresh the followers and the lecture's part of
        the other panels at FOLLOW_PERIOD, send the presenter's camera at CAMERA_PERIOD when
        it moved."""
        with self._lock:
            to_follow, self._to_follow = self._to_follow, []
            to_refresh, self._to_refresh = self._to_refresh, []
            now = self._clock()
            called_back = [seat for seat, deadline in self._called.values() if deadline <= now]
            for seat in called_back:
                del self._called[seat.client_id]
        for seat in to_follow:
            if not seat.closed and seat.following_by_default():
                seat.guard("follow the presenter", seat.follow)()
        for seat in called_back:
            if not seat.closed and seat.mode is Mode.OWN and self.someone_presents:
                seat.guard("called back", seat.follow)()
        if to_refresh:
            self.refresh_seats(list({id(seat): seat for seat in to_refresh}.values()))
        if self.pointer is not None and self.pointer.markers:
            with self._lock:
                self.pointer.tick(dt)
        self._since_status += dt
        if self._since_status >= FOLLOW_PERIOD:
            self._since_status = 0.0
            remote = self.remote
            if remote is not None and remote.hall is Hall.LIVE:  # a browser that joined while the bus said so
                with self._lock:
                    self._to_follow.extend(seat for seat in self.seats()
                                           if not seat.closed and seat.following_by_default())
            if self._followers:
                self.refresh_followers()
            self.refresh_seats()
        self._since_renew += dt
        if self._since_renew >= RENEW_PERIOD and self.presenter is not None:
            self._since_renew = 0.0
            self._renew_lock()
        self._since_refusals += dt
        if self._since_refusals >= FOLLOW_PERIOD and self._refusal_watchers:
            self._since_refusals = 0.0
            with self._lock:
                watchers = list(self._refusal_watchers.items())
            for client_id, (seat, show) in watchers:
                if seat.closed:
                    self._refusal_watchers.pop(client_id, None)
                else:
                    seat.guard("presenter code note", show)()
        self._since_camera += dt
        if self._camera_due and self._since_camera >= CAMERA_PERIOD:
            self._camera_due = False
            self._since_camera = 0.0
            for _, follower in list(self._followers.values()):
                self.send_camera(follower)

    def _renew_lock(self) -> None:
        """Renew the presenter's lease in the gate (from the loop: a process that stalls or dies
        lets it lapse); a presenter whose lock someone else took meanwhile stops presenting."""
        seat = self.presenter
        if seat is None:
            return
        try:
            held = self.gate.renew(self._holder(seat))
        except GateUnavailable as error:
            logger.warning("presenter lock not renewed: %s", error)
            return
        if not held and not seat.closed:
            logger.warning("client %d: the presenter lock went to someone else", seat.client_id)
            seat.guard("presenter lock", seat.stop_presenting)()
            seat.report_error("presenter lock", RuntimeError("the presenter lock lapsed and someone else "
                                                             "took it; you no longer present"))

    def close(self) -> None:
        """Free what this process holds in the gate (the app stops)."""
        with contextlib.suppress(Exception):
            self.gate.close()

    def forget(self, client_id: int) -> None:
        """The browser `client_id` left (its session closed): drop what the lectern kept under its
        id (wrong codes, refusals, refusal note, call back, camera heard, following).  Client
        ids are never reused, so nothing of it is needed again."""
        with self._lock:
            self._tries.pop(client_id, None)
            self._refused.pop(client_id, None)
            self._hall_wait.pop(client_id, None)
            self._refusal_watchers.pop(client_id, None)
            self._called.pop(client_id, None)
            self._watched.discard(client_id)
            if self._followers.pop(client_id, None) is not None:
                self._follower_screens = None

    def point(self, seat: Seat, ray_origin: Any, ray_direction: Any, label: str = "") -> np.ndarray:
        """The presenter points: a marker where its click's ray passes nearest its camera's
        look-at point (`pointed_at`), for every follower.  PermissionError for anyone else,
        ValueError for a ray that is not one; the point [scene units]."""
        if seat is not self.presenter or self.pointer is None:
            raise PermissionError("only the presenter can point")
        point = pointed_at(ray_origin, ray_direction, seat.client.camera.look_at)
        text = str(label).strip()[:POINTER_LABEL_CHARS]
        with self._lock:
            view = self.live_view
            self.pointer.add(point, np.asarray(ray_direction, dtype=float), text,
                             view.labels if view is not None else None)
        return point

    def label_screens(self) -> list[Screen]:
        """The screens the shared scene's labels are laid out for (`LabelLayer.screens`): the
        presenter's, then one of each kind of follower's (`follower_screens`), then those of the
        followers on other processes (`remote_screens`); at most MAX_LABEL_SCREENS in all.  Read
        without the lectern's lock (the layout holds a room's)."""
        screens: list[Screen] = []
        presenter = self.presenter
        if presenter is not None:
            own = screen_of(presenter.client.camera, docked=bool(getattr(presenter, "projector", False)))
            if own is not None:
                screens.append(own)
        for screen in (*self.follower_screens(), *self.remote_screens()):
            if len(screens) >= MAX_LABEL_SCREENS:
                break
            if screen not in screens:
                screens.append(screen)
        return screens

    def follower_screens(self) -> list[Screen]:
        """One screen of each kind of this process's followers (its canvas's aspect, its panel
        docked or not, the camera's place), those that follow the presenter's camera first, the
        narrowest first (a phone sees the picture from farthest: its labels lie closest); at most
        MAX_LABEL_SCREENS.  Kept until a follower comes, goes or its camera moves (its browser
        moves it or the lectern does), and at most FOLLOWER_SCREENS_PERIOD (500 followers: a
        tenth of the loop's time when every layout looked at every follower's camera)."""
        now = time.monotonic()
        cached = self._follower_screens
        if cached is not None and now - cached[0] < FOLLOWER_SCREENS_PERIOD:
            return cached[1]
        kinds: dict[Any, tuple[tuple[bool, float], Screen]] = {}
        for seat, follower in tuple(self._followers.values()):
            screen = screen_of(follower.camera, docked=bool(getattr(seat, "projector", False)))
            if screen is None:
                continue
            aspect = screen.width / screen.height
            kind = (round(aspect, 2), screen.panel is None,
                    tuple(round(c, 1) for c in (*screen.view.position, *screen.view.look_at)))
            if kind not in kinds:
                kinds[kind] = ((not follower.follow_camera, aspect), screen)
        screens = [screen for _rank, screen in sorted(kinds.values(), key=lambda item: item[0])][:MAX_LABEL_SCREENS]
        self._follower_screens = (now, screens)
        return screens

    def _camera_moved(self, seat: Seat) -> None:
        if seat is self.presenter:
            self._camera_due = True
            return
        entry = self._followers.get(seat.client_id)
        if entry is not None and entry[0] is seat:
            self._follower_screens = None
            self._follower_resized(*entry)

    def send_camera(self, follower: Follower) -> None:
        """Put a follower's camera where the presenter's is (if it follows the camera): the
        presenter's viewing direction and look_at, the distance fitted to the follower's aspect
        (`fitted_camera`) so a phone shows what the presenter's wide view shows."""
        presenter, remote = self.presenter, self.remote
        if not follower.follow_camera:
            return
        if presenter is not None:
            source = presenter.client.camera
            shot: dict[str, Any] = {"position": source.position, "look_at": source.look_at,
                                    "up": source.up_direction, "fov": float(source.fov), "aspect": view_aspect(source)}
        elif remote is not None and remote.camera is not None:
            shot = remote.camera
        else:
            return
        try:
            camera = follower.camera
            position, look_at = fitted_camera(shot["position"], shot["look_at"], shot["aspect"],
                                              view_aspect(camera), shot["fov"], shot["up"])
            camera.up_direction = tuple(shot["up"])
            camera.position = position
            camera.look_at = look_at
            camera.fov = shot["fov"]
        except Exception:  # noqa: BLE001 - the presenter's camera is not known yet, or a client left
            logger.debug("camera not sent", exc_info=True)
        self._follower_screens = None  # its screen's view moved

