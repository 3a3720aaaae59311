"""Who follows and who explores: the browsers the app loop moves to follow (a new presenter's
pull, a call back that ran out), the explorers called back (`call_back`, `stay`), and the
lecture's part of every panel that does not follow (`Seat.lecture_changed`)."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Iterable

from app.lecture.lectern.seat import Mode, Seat, Stage

__all__ = ["Seating"]

logger = logging.getLogger(__name__)


class Seating:
    """The seats the app loop moves or refreshes, and the explorers called back.

    Args:
        stage: the lectern (who presents, the open seats).
        clock: the lectern's clock [s] (read at each call: a test moves it).
        lock: the lectern's lock (the lists change under it).
    """

    def __init__(self, stage: Stage, clock: Callable[[], float], lock: threading.RLock) -> None:
        self._stage = stage
        self._clock = clock
        self._lock = lock
        self._to_follow: list[Seat] = []  # seats the next tick makes follow (if they follow by default)
        self._to_refresh: list[Seat] = []  # seats whose panel the next tick refreshes
        self._called: dict[int, tuple[Seat, float]] = {}  # explorers called back: (seat, deadline [clock s])

    def follow_later(self, seats: Iterable[Seat], *, more: bool = False) -> None:
        """The next tick makes `seats` follow (those that still follow by default); instead of
        the ones it was to move, or `more` of them."""
        with self._lock:
            if more:
                self._to_follow.extend(seats)
            else:
                self._to_follow = list(seats)

    def refresh_later(self, seats: Iterable[Seat]) -> None:
        """The next tick writes the lecture's state into `seats`' panels (`refresh`), not the
        caller (a presenter's callback holds its browser's locks)."""
        with self._lock:
            self._to_refresh.extend(seats)

    def call_back(self, seats: Iterable[Seat], seconds: float) -> int:
        """Call the explorers among `seats` back: each follows again in `seconds` unless it
        presses Stay (`stay`); their panels show it; the number called."""
        with self._lock:
            deadline = self._clock() + seconds
            explorers = [seat for seat in seats if not seat.closed and seat.mode is Mode.OWN]
            for seat in explorers:
                self._called[seat.client_id] = (seat, deadline)
            self._to_refresh.extend(explorers)
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

    def uncall(self, client_id: int | None = None) -> None:
        """The browser `client_id` is no longer called back (it follows, or left); None: nobody is."""
        with self._lock:
            if client_id is None:
                self._called.clear()
            else:
                self._called.pop(client_id, None)

    def exploring(self) -> int:
        """The browsers (not the presenter) that show a room of their own."""
        presenter = self._stage.presenter
        return sum(1 for seat in self._stage.seats()
                   if seat is not presenter and not seat.closed and seat.mode is Mode.OWN)

    def move(self) -> None:
        """From the app loop: the seats due follow (a new presenter's, the called back whose
        countdown ran out, while someone presents), each in its own guard; the panels due are
        refreshed."""
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
            if not seat.closed and seat.mode is Mode.OWN and self._stage.someone_presents:
                seat.guard("called back", seat.follow)()
        if to_refresh:
            self.refresh(list({id(seat): seat for seat in to_refresh}.values()))

    def refresh(self, seats: list[Seat] | None = None) -> None:
        """Write the lecture's state into the panel of every seat that does not follow (or of
        `seats`): the presenter's badge, the explorers' "Lecture on" and countdowns."""
        for seat in self._stage.seats() if seats is None else seats:
            if seat.closed or seat.mode is Mode.FOLLOWING:
                continue
            try:
                seat.lecture_changed()
            except Exception:  # noqa: BLE001 - a browser that just left
                logger.debug("lecture refresh failed", exc_info=True)
