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

**The parts** (`Lectern` keeps who presents and what the shared screen shows, and the methods
other code calls; each part reads that state through `app.lecture.lectern.seat.Stage`):

- `app.lecture.lectern.lock.PresenterLock`: the code, the refusals and their words, the lease.
- `app.lecture.lectern.followers.Followers`: the following browsers' panels and what is written into
  them (the status as an `app.lecture.follower.FollowerStatus`, the caption, the plot), the
  presenter's camera fitted to each screen, the kinds of follower's screen for the labels.
- `app.lecture.lectern.seating.Seating`: the seats the app loop moves (a new presenter's pull, a call
  back that ran out) and the lecture's part of the panels that do not follow.
- `app.lecture.lectern.broadcast`: the presenter's draw target into the shared scene, the pointer.
- `app.lecture.lectern.seat`: `Seat`, `Mode`, `RemoteShow` (another worker's show), `Stage`.

The rest:

- **The lock.**  `Lectern` asks its gate (`app.lecture.gate`: `LocalGate` in one process,
  `RedisGate` across `--workers`; one set of rules) who presents and whether a code is right.
  The code (`python -m app --presenter-code CODE`, or a random one of eight digits in two
  groups, printed at start) is typed into `Presenter code` with or without its spaces or dashes;
  `Present` makes the browser the presenter.  While someone presents, every code gets the same
  answer, "Someone else is presenting", and is not evaluated; wrong codes are limited per
  browser (MAX_TRIES a minute) and over all browsers and processes together
  (`app.lecture.gate.MAX_WRONG` a sliding minute; the others wait, not evaluated): a script has
  <= 1e-4 chance in a 90-minute lecture, and when it stops the lecturer gets in within a
  minute.  Every refusal stays true while shown (`refusal_now`: a wait counts down and goes,
  "someone else is presenting" goes when they stop); `Stop presenting` or a disconnect releases
  the lock; the presenting process renews it from its loop (`tick`), so a process that dies
  frees it within `app.lecture.gate.LEASE_S`.
- **One simulation, drawn once for everyone.**  The presenter's view draws into the shared scene
  (under LIVE_ROOT): the room advances and draws once per frame however many browsers follow.
- **Followers.**  Every other browser follows by default: it shows the shared scene and a small
  panel (`app.lecture.follower.Follower`, built and written by `Followers`): who presents what
  (scene, preset, lesson step, time, the scene's key numbers: a `FollowerStatus`, written as
  Markdown by the panel), or plainly that the presenter stopped or left; the lesson step's
  caption over the 3D view and the presenter's open plot tab, read only (`caption`,
  `room_plot`); `Follow camera` (the presenter's viewing direction, framed for the follower's
  own screen) and `Explore on my own`, which gives it an exact copy of the room as shown now
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
is `Stop presenting`, "tab closed" a disconnect (`Session.close`), "lock lost"
`PresenterLock.tick` finding someone else holds it; all three go through `release`.  "Worker killed": another
process's presenter whose process dies without a word.

Each piece, as *owner* → *what ends it*:

- **presenter lock** (`app.lecture.gate`): the presenter → stop, tab closed: `release` frees it;
  worker killed: its lease lapses within `app.lecture.gate.LEASE_S`.
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
- **caption** (`caption`, from `Seat.caption_words`; `app.lecture.caption`): the presenter →
  ("", "") once `presenter` is None or the hall is not LIVE, cleared on every follower by
  `release`'s `refresh_followers`; worker killed: the bus's `remote_ended` (hall LEFT).
- **pointer markers** (`Pointer`, shared scene, POINTER_ROOT): the presenter → fade within
  POINTER_SECONDS; `release` clears them; worker killed: `app.lecture.bus.Bus._drop_pointer`
  removes them when the bus takes it that the presenter left.
- **shared plot** (`room_plot`, `app.lecture.room_plot`): the presenter's open plot tab → ("", [])
  once `presenter` is None or the remote hall is not LIVE: cleared on every follower.
- **lesson step** (`Seat.lesson_text` in `FollowerStatus.lesson`, its words in the other languages,
  `Seat.lesson_words`, in `FollowerStatus.lesson_words`): the presenter's session → not
  in the followers' status once `presenter` is None or the hall is not LIVE (`markdown` shows
  it only while LIVE: also on another worker, whatever the last status heard said).
- **the followers' status** (`FollowerStatus`, made by `Followers.status`; another worker's:
  `RemoteShow.status`, from the bus as data): the shared screen → made anew at every refresh;
  stop, tab closed, lock lost: `release` sets the hall (STOPPED, LEFT), which the status says;
  worker killed: the bus's `remote_ended` sets `RemoteShow.hall` (`FollowerStatus.ended`): the
  last scene, time and key numbers stay, the head says the presenter left.
- **call back** (`Seating`'s called): the presenter → `start`, `release`, `show_remote` and
  `remote_ended` clear it; a browser that follows or leaves is no longer called.
- **live view** (the shared 3D under LIVE_ROOT: `live_view`, `live_room`): the presenter →
  stop, tab closed: detached, its nodes the followers' last state (paused, `Explore` copies it)
  with a note, until the next presenter (`make_live_view` → `_forget_live_view`) or another
  process's (`show_remote`); worker killed: the bus's replica stays the same way, and `Explore`
  (`live_copy_noted`) copies the last state the bus kept of it, or its scene, saying so.
- **the room a lecture left** (LAST_KEY, `app.lecture.bus`): the lecture (its presenter's start,
  `Bus.lecture_id`) → offered only to that lecture's followers and newcomers; the next lecture's
  room replaces it; the key lapses after `LAST_TTL_S`.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import viser

from app.ask import Rounds
from app.i18n import N_
from app.kit.core.room import Room
from app.kit.draw.labels import Screen
from app.kit.draw.screen import BODY_WIDTH_SHARE, NARROW_MARGIN
from app.lecture.follower import Follower, FollowerStatus, Hall
from app.lecture.gate import Gate, LocalGate
from app.lecture.gate import new_code as new_gate_code
from app.lecture.lectern.broadcast import (
    LIVE_ROOT,
    POINTER_LABEL_CHARS,
    POINTER_ROOT,
    POINTER_SECONDS,
    Broadcast,
    Pointer,
    fitted_camera,
    pointed_at,
)
from app.lecture.lectern.followers import CAMERA_PERIOD, MAX_LABEL_SCREENS, Followers
from app.lecture.lectern.lock import MAX_TRIES, PresenterLock
from app.lecture.lectern.seat import FOLLOW_PERIOD, Mode, RemoteShow, Seat
from app.lecture.lectern.seating import Seating
from app.refusals import NotAllowed

__all__ = ["BODY_WIDTH_SHARE", "CALL_BACK_SECONDS", "CAMERA_PERIOD", "FOLLOW_PERIOD", "LIVE_ROOT", "MAX_LABEL_SCREENS",
           "MAX_TRIES", "NARROW_MARGIN", "POINTER_ROOT", "POINTER_SECONDS", "Broadcast", "Lectern", "Mode", "Pointer",
           "RemoteShow", "Seat", "fitted_camera", "new_code", "pointed_at"]

logger = logging.getLogger(__name__)

CALL_BACK_SECONDS = 10.0  # [s] an explorer called back has to press Stay before it follows again


def new_code() -> str:
    """A random presenter code: eight digits in two groups ("4821 0937"), easy to read out in a
    lecture hall and long enough not to be guessed (`app.lecture.gate.new_code`)."""
    return new_gate_code()


class Lectern:
    """Who presents and what the shared screen shows (see the module docstring), and the parts
    that do the rest: the lock (`presenter_lock`), the followers' panels (`follower_panels`), the
    seats the loop moves (`seating`).  The methods other code calls are here.

    Who presents (`presenter`), the hall (`hall`), the live view and room, and another
    process's show (`remote`) change only in `start`, `release`, `make_live_view`,
    `show_remote` and `remote_ended`; the parts read them (`app.lecture.lectern.seat.Stage`).

    Attributes:
        code: the presenter code.  presenter: the presenting seat, or None.
        hall: what the shared screen shows (`app.lecture.follower.Hall`).
        live_view: the view drawing the shared scene (kept after the presenter stops or leaves,
            its nodes the followers' last state, until a new presenter starts).
    """

    def __init__(self, server: viser.ViserServer, code: str | None = None,
                 clock: Callable[[], float] = time.monotonic, gate: Gate | None = None) -> None:
        self.server = server
        gate = gate if gate is not None else LocalGate(code if code else new_code(), clock)
        self.code = gate.code
        self.presenter: Seat | None = None
        self.hall = Hall.EMPTY
        self.live_view: Any = None
        self._live_room: Room | None = None
        self._clock = clock
        self._lock = threading.RLock()
        self._since_status = 0.0
        self.pointer = Pointer(server.scene) if server is not None else None
        self.rounds = Rounds()
        """The class's questions (`app.ask.hub`): the current round, asked by the presenter."""
        self.seats: Callable[[], list[Seat]] = lambda: []
        """Set by the app: its open sessions."""
        # One lecture across processes (`app.lecture.bus` sets these; unused on one process):
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
        self.remote_screens: Callable[[], list[Screen]] = lambda: []
        """The kinds of follower's screen on the other processes (`label_screens` adds them)."""
        clock_now = lambda: self._clock()  # noqa: E731 - read at each call: a test moves the lectern's clock
        self.presenter_lock = PresenterLock(gate, self, clock_now, self._lock)
        """The code, the refusals, the presenter's lease (`app.lecture.lectern.lock`)."""
        self.follower_panels = Followers(self)
        """The following browsers' panels and what they show (`app.lecture.lectern.followers`)."""
        self.seating = Seating(self, clock_now, self._lock)
        """The seats the loop moves and refreshes, the explorers called back (`app.lecture.lectern.seating`)."""

    # ------------------------------------------------------------------ presenting

    @property
    def gate(self) -> Gate:
        """The presenter lock and the code (`app.lecture.gate`), the one the lock part asks."""
        return self.presenter_lock.gate

    @gate.setter
    def gate(self, gate: Gate) -> None:
        self.presenter_lock.gate = gate
    def try_code(self, seat: Any, code: str) -> str | None:
        """None if `seat` may present with `code`, else the refusal (`PresenterLock.try_code`)."""
        return self.presenter_lock.try_code(seat, code)

    def refusal_now(self, seat: Any) -> str | None:
        """`seat`'s last refusal in the words true now, or None (`PresenterLock.refusal_now`)."""
        return self.presenter_lock.refusal_now(seat)

    def watch_refusal(self, seat: Any, show: Callable[[], None] | None) -> None:
        """Keep `seat`'s refusal true on screen with `show` (None: stop; `PresenterLock.watch_refusal`)."""
        self.presenter_lock.watch_refusal(seat, show)

    def start(self, seat: Seat) -> None:
        """`seat` presents: its room goes live; everyone else follows (or keeps exploring)."""
        with self._lock:
            self.presenter_lock.start(seat)
            self.presenter = seat
            self.hall = Hall.LIVE
            self.rounds.begin(self.presenter_lock.holder(seat))  # its rounds are its own; one left from before ends
            self.seating.uncall()
            self.seating.refresh_later(self.seats())  # explorers: "Lecture on"
            # The app loop moves them (each in its own guard): not from the presenter's callback,
            # which holds the presenter's locks.
            self.seating.follow_later(other for other in self.seats()
                                      if other is not seat and other.following_by_default())
        self.refresh_followers()
        self._tell("start")

    def release(self, seat: Seat, *, disconnected: bool) -> None:
        """The presenter stops (Stop presenting) or leaves (disconnect): the lock is free, its
        question round ends (kept as an earlier round), its pointer markers go.  The followers
        keep the last state on screen (a paused copy of the room, which is what Explore then
        copies), with a note, until a new presenter starts (the module docstring's table)."""
        with self._lock:
            self.presenter_lock.release(seat)
            if self.presenter is not seat:
                return
            self.presenter = None
            self.hall = Hall.LEFT if disconnected else Hall.STOPPED
            self.rounds.end_lecture("the presenter left" if disconnected else "the presenter stopped")
            self.seating.uncall()
            self.seating.refresh_later(self.seats())
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
            try:
                view._root_node.remove()
            except Exception:  # noqa: BLE001 - its nodes may be gone already
                logger.debug("live view's nodes already gone", exc_info=True)

    def make_live_view(self, seat: Seat, room: Room) -> Any:
        """The presenter's view of `room`: 3D into the shared scene, panel and controls in its browser."""
        with self._lock:
            self._forget_live_view()
            view = room.scene(Broadcast(self.server, seat.client, self.label_screens), room, seat.guard,
                              seat.report_error)
            self.live_view = view
            self._live_room = room
        self.follower_panels.watch_camera(seat)
        return view

    def point(self, seat: Seat, ray_origin: Any, ray_direction: Any, label: str = "") -> np.ndarray:
        """The presenter points: a marker where its click's ray passes nearest its camera's
        look-at point (`pointed_at`), for every follower.  PermissionError for anyone else,
        ValueError for a ray that is not one; the point [scene units]."""
        if seat is not self.presenter or self.pointer is None:
            raise NotAllowed(N_("only the presenter can point"))
        point = pointed_at(ray_origin, ray_direction, seat.client.camera.look_at)
        text = str(label).strip()[:POINTER_LABEL_CHARS]
        with self._lock:
            view = self.live_view
            self.pointer.add(point, np.asarray(ray_direction, dtype=float), text,
                             view.labels if view is not None else None)
        return point

    # ------------------------------------------------------------------ the shared screen
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
            self.seating.uncall()
            self.seating.refresh_later(self.seats())
            self.seating.follow_later(seat for seat in self.seats()
                                      if seat is not self.presenter and seat.following_by_default())
        self.refresh_followers()

    def remote_ended(self, left: bool) -> None:
        """The remote presenter stopped (or left: its process ended or said so): the last state
        stays on screen, its status saying so (`FollowerStatus.ended`)."""
        with self._lock:
            remote = self.remote
            if remote is None or remote.hall is not Hall.LIVE:
                return
            remote.hall = self.hall = Hall.LEFT if left else Hall.STOPPED
            remote.status = remote.status.ended(remote.hall)
            self.seating.uncall()
            self.seating.refresh_later(self.seats())
        self.refresh_followers()

    def remote_call_back(self) -> int:
        """The remote presenter calls everyone back: this process's explorers (`call_back`)."""
        return self.seating.call_back(self.seats(), CALL_BACK_SECONDS)

    # ------------------------------------------------------------------ followers and explorers
    @property
    def followers(self) -> Mapping[int, Follower]:
        """The following browsers' panels by client id (read only: `add_follower`,
        `remove_follower` change them)."""
        return self.follower_panels.panels

    def add_follower(self, seat: Seat) -> Follower:
        """`seat` follows: its panel (`Followers.add`); a call back of it ends."""
        follower = self.follower_panels.add(seat)
        self.seating.uncall(seat.client_id)
        return follower

    def remove_follower(self, seat: Seat, *, disconnected: bool = False) -> None:
        """`seat` follows no more: its panel goes (`Followers.remove`)."""
        self.follower_panels.remove(seat, disconnected=disconnected)

    def follower_status(self) -> FollowerStatus:
        """What the followers' panels say, as a value (`Followers.status`): the bus sends it."""
        return self.follower_panels.status()

    def status(self) -> str:
        """The followers' panel text as they show it (`FollowerStatus.markdown`)."""
        return self.follower_status().markdown()

    def status_line(self) -> str:
        """The followers' one line as a narrow screen shows it (`FollowerStatus.line`)."""
        return self.follower_status().line()

    def caption(self) -> tuple[str, str]:
        """(head, words) of the lesson caption over every follower's 3D view (`Followers.caption`)."""
        return self.follower_panels.caption()

    def room_plot(self) -> tuple[str, list[Any]]:
        """(tab, elements) of the presenter's open plot tab, copied for the followers (`Followers.room_plot`)."""
        return self.follower_panels.room_plot()

    def refresh_followers(self) -> None:
        """Write the status, the caption and the presenter's plot into every follower's panel."""
        self.follower_panels.refresh()

    def refresh_seats(self, seats: list[Seat] | None = None) -> None:
        """Write the lecture's state into the panels that do not follow (`Seating.refresh`)."""
        self.seating.refresh(seats)

    def send_camera(self, follower: Follower) -> None:
        """Put a follower's camera where the presenter's is (`Followers.send_camera`)."""
        self.follower_panels.send_camera(follower)

    def label_screens(self) -> list[Screen]:
        """The screens the shared scene's labels are laid out for (`Followers.label_screens`)."""
        return self.follower_panels.label_screens()

    def follower_screens(self) -> list[Screen]:
        """One screen of each kind of this process's followers (`Followers.follower_screens`)."""
        return self.follower_panels.follower_screens()

    def audience(self) -> tuple[int, int]:
        """(following, exploring): the browsers following the shared screen, and the others
        (not the presenter) that show a room of their own (the presenter's badge)."""
        return len(self.follower_panels.seats()), self.seating.exploring()

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
                raise NotAllowed(N_("only the presenter can call everyone back"))
            called = self.seating.call_back([other for other in self.seats() if other is not seat], CALL_BACK_SECONDS)
            self.seating.refresh_later([seat])  # shown by the loop, not from the presenter's callback
        self._tell("call_back")
        return called

    def call_back_left(self, seat: Seat) -> float | None:
        """Seconds [s] before `seat`, called back, follows again; None if it is not called."""
        return self.seating.call_back_left(seat)

    def stay(self, seat: Seat) -> None:
        """`seat`, called back, keeps exploring."""
        self.seating.stay(seat)

    # ------------------------------------------------------------------ the loop, and the end
    def tick(self, dt: float) -> None:
        """Called by the app loop every frame: move the browsers that follow a new presenter and
        the explorers whose call back ran out, refresh the followers and the lecture's part of
        the other panels at FOLLOW_PERIOD, renew the presenter's lease, keep the refusals on
        screen true, send the presenter's camera at CAMERA_PERIOD when it moved."""
        self.seating.move()
        if self.pointer is not None and self.pointer.markers:
            with self._lock:
                self.pointer.tick(dt)
        self._since_status += dt
        if self._since_status >= FOLLOW_PERIOD:
            self._since_status = 0.0
            remote = self.remote
            if remote is not None and remote.hall is Hall.LIVE:  # a browser that joined while the bus said so
                self.seating.follow_later((seat for seat in self.seats()
                                           if not seat.closed and seat.following_by_default()), more=True)
            if self.follower_panels.seats():
                self.refresh_followers()
            self.refresh_seats()
        self.presenter_lock.tick(dt)
        self.follower_panels.tick(dt)

    def close(self) -> None:
        """Free what this process holds in the gate (the app stops)."""
        self.presenter_lock.close()

    def forget(self, client_id: int) -> None:
        """The browser `client_id` left (its session closed): drop what the lectern kept under its
        id (wrong codes, refusals, refusal note, call back, camera heard, following).  Client
        ids are never reused, so nothing of it is needed again."""
        with self._lock:
            self.presenter_lock.forget(client_id)
            self.seating.uncall(client_id)
            self.follower_panels.forget(client_id)
