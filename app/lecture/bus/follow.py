"""`Following`: this process's followers follow a presenter on another process (the source):
its scene batches in order (a resync when out of step), its hall, camera, plot tab and kept
room copied into `app.lecture.lectern.RemoteShow`, and its end (said, or its lease lapsed)."""

from __future__ import annotations

import collections
import dataclasses
import time
from collections.abc import Callable

from app.cluster.messages import CallBack, Camera, HallState, Keep, Live, Plot, Resync, SceneBatch
from app.lecture.bus.link import ASK, LEASE_S, RESYNC_PERIOD_S, Link, logger
from app.lecture.bus.shared import SharedScene
from app.lecture.bus.values import camera_shot, plot_from_message
from app.lecture.bus.wire import decode_batch
from app.lecture.follower import FollowerStatus, Hall
from app.lecture.lectern import Lectern, RemoteShow

__all__ = ["Following", "Kept"]


@dataclasses.dataclass(frozen=True)
class Kept:
    """The last copy of the remote presenter's room this process received ("keep").

    Attributes:
        lecture: the lecture id it belongs to.  data: `encode_room(room, history=False)`.
        t: the room's shown time [s] when encoded.  running: it was live and playing (a copy
            may then be advanced to the time last drawn here).
    """

    lecture: str
    data: bytes
    t: float
    running: bool


def copy_hall(remote: RemoteShow, message: HallState) -> None:
    """The hall's state heard from the source into `remote` (text bounded as shown).  The
    followers' status is data (`FollowerStatus.from_dict`, checked first: one that is not a
    status raises ValueError and changes nothing; none said keeps the last); the follower's
    panel writes it as words."""
    status = FollowerStatus.from_dict(message.status) if message.status else remote.status
    remote.title = message.title[:200]
    remote.status = status
    remote.caption = (message.caption[0][:400], message.caption[1][:4000])


class Following:
    """What this process knows of the remote presenter it follows.

    Attributes:
        remote_worker: the source's worker id (None: none followed).  expected: the next scene
            batch's number (None: out of step, the next asks for a resync).  asked_at, heard_at:
            `time.monotonic()` [s] of the last resync asked and of the last word heard.
        remote_lecture: its lecture id.  kept: its room's last copy received (`Kept`).
        seen_t: its room's time [s] in the last scene batch drawn here.
        delays: recent bus delays [s] (the source's publish to this process's frame).
    """

    def __init__(self, link: Link, lectern: Lectern, shared: SharedScene, yield_source: Callable[[], None]) -> None:
        self.link = link
        self.lectern = lectern
        self.shared = shared
        self.yield_source = yield_source  # a presenter elsewhere: this process's scene is no longer the lecture's
        self.remote_worker: str | None = None
        self.expected: int | None = None
        self.asked_at = -float("inf")
        self.heard_at = time.monotonic()
        self.remote_lecture = ""
        self.kept: Kept | None = None
        self.seen_t: float | None = None
        self.delays: collections.deque[float] = collections.deque(maxlen=2000)

    def heard(self, message: Live) -> None:
        """A message of the source's channel (the app loop, before its frame)."""
        if isinstance(message, SceneBatch):
            self._scene(message)
            return
        if message.worker != self.remote_worker:
            if isinstance(message, HallState) and message.hall == Hall.LIVE.value and self.remote_worker is None:
                self.ask_resync(message.worker)  # a lecture already on: this process came late
            return
        self.heard_at = time.monotonic()
        lectern, remote = self.lectern, self.lectern.remote
        if remote is None:
            return
        if isinstance(message, HallState):
            copy_hall(remote, message)
            if message.hall in (Hall.STOPPED.value, Hall.LEFT.value):
                lectern.remote_ended(left=message.hall == Hall.LEFT.value)
        elif isinstance(message, Camera):
            remote.camera = camera_shot(message)
            for follower in list(lectern.followers.values()):
                lectern.send_camera(follower)
        elif isinstance(message, Plot):
            plot = plot_from_message(message, remote.plot)
            if plot is None:
                logger.warning("bus: a plot message from %s refused", message.worker)
            else:
                remote.plot = plot
        elif isinstance(message, CallBack) and remote.hall is Hall.LIVE:
            lectern.remote_call_back()
        elif isinstance(message, Keep) and message.lecture == self.remote_lecture:
            self.kept = Kept(message.lecture, message.room, message.shown_t, message.running)

    def _scene(self, batch: SceneBatch) -> None:
        worker, full, lectern = batch.worker, batch.full, self.lectern
        mine = full == "*" or (isinstance(full, list) and self.link.worker_id in full)
        if full == "*" or (mine and (self.remote_worker != worker or lectern.remote is None)):
            self.yield_source()
            self.remote_worker = worker
            lectern.show_remote(RemoteShow(worker=worker, title=batch.title[:200]))
        if worker != self.remote_worker:
            return
        self.heard_at = time.monotonic()
        self.lecture_heard(batch.lecture)
        if mine or (full is not None and batch.seq != self.expected):  # also another's resync, if out of step
            self.shared.apply_full(decode_batch(batch.messages, batch.buffers, batch.shapes))
            self._in_step(batch)
        elif full is not None or batch.seq == self.expected:
            if full is None:
                self.shared.apply(decode_batch(batch.messages, batch.buffers, batch.shapes))
            self._in_step(batch)
        else:
            self.expected = None
            self.ask_resync()
        if batch.sent_at is not None:
            self.delays.append(time.time() - batch.sent_at)

    def _in_step(self, batch: SceneBatch) -> None:
        self.expected = batch.seq + 1
        if batch.shown_t is not None:
            self.seen_t = batch.shown_t

    def lecture_heard(self, lecture: str) -> None:
        """The remote presenter's lecture id (a new lecture: what was kept of the last one goes)."""
        if lecture != self.remote_lecture:
            self.remote_lecture = lecture
            self.kept = None
            self.seen_t = None

    def ask_resync(self, worker: str | None = None) -> None:
        """Ask the source (`worker`, else the one followed) for its whole state, at most every RESYNC_PERIOD_S."""
        now = time.monotonic()
        if now - self.asked_at < RESYNC_PERIOD_S:
            return
        self.asked_at = now
        self.link.publish(ASK, Resync(worker=self.link.worker_id, to=worker or self.remote_worker))

    def check_lease(self) -> None:
        """A live source heard nothing from for LEASE_S has left (killed: it said nothing): the
        last state stays, its pointer's markers go."""
        remote = self.lectern.remote
        if (remote is not None and remote.hall is Hall.LIVE and self.remote_worker is not None
                and time.monotonic() - self.heard_at > LEASE_S):
            self.lectern.remote_ended(left=True)
            self.shared.drop_pointer()

    def forget(self) -> None:
        """Follow no one (this process presents now): what was kept of the other's lecture goes."""
        self.remote_worker = None
        self.expected = None
        self.lecture_heard("")
