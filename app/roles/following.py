"""Following the presenter and leaving to explore a copy (`Following`, the follower's role).

A following browser shows the shared scene (drawn by the presenter's view) and a read-only
panel, `app.lecture.follower.Follower`, which the lectern builds (`Lectern.add_follower`); its own
room goes.  `Explore on my own` leaves with an exact copy of what the shared screen shows now
(`Room.fork`), seen from where it looked; a narrow screen keeps the phone layout
(`app.roles.phone`).  A browser with its own room that has not chosen to explore follows a new
presenter (`by_default`).
"""

from __future__ import annotations

from app.kit.core.room import Room
from app.lecture.follower import Follower
from app.lecture.lectern import Lectern, Mode
from app.roles.own_room import OwnRoom
from app.roles.phone import PhoneFit
from app.roles.showing import Browser

__all__ = ["Following"]


class Following:
    """Follow the presenter, and leave to explore (module docstring).

    Owned by the browser's session for its life.

    Args:
        browser: the session.  own_room: its own room's role (the explorer's views).
        phone: the narrow screen's fit.

    Attributes:
        explored: it pressed `Explore on my own` (or explored a shared moment): a new presenter
            does not pull it back; ends when it follows again.
    """

    def __init__(self, browser: Browser, own_room: OwnRoom, phone: PhoneFit) -> None:
        self.browser = browser
        self.showing = browser.showing
        self.own_room = own_room
        self.phone = phone
        self.explored = False

    def by_default(self) -> bool:
        """A browser with its own room that has not chosen to explore follows a new presenter."""
        return self.showing.mode is Mode.OWN and not self.explored

    def keep_own(self) -> None:
        """This browser chose its own room (a task opened in it): a new presenter does not pull it
        along; `Follow presenter` still does."""
        self.explored = True

    def follow(self) -> None:
        """Follow the presenter (or the last state a presenter left): the shared scene and a
        read-only panel; this browser's own room goes."""
        browser, showing = self.browser, self.showing
        lectern = browser.lectern
        if lectern is None or not lectern.live or showing.mode is not Mode.OWN:
            return
        with showing.switch_lock:
            browser.narrow.end()  # a follower's panel has its own narrow layout
            self._drop_own_view()
            browser.lesson_runner.end()
            showing.mode = Mode.FOLLOWING
            browser.narrow.end()  # again: a phone's fold begun at connect meanwhile ends here
            self.explored = False
            showing.came_after_lecture = False
            showing.hide_live(False)
            showing.view = self._follower_panel(lectern)
        browser.show_mode()
        self.own_room.refresh_preset_commands()

    def _drop_own_view(self) -> None:
        """The view of the browser's own room goes (within the switch)."""
        showing = self.showing
        view, room = showing.view, showing.own_room
        if view is not None:
            with room.lock:
                view.remove()
                room.remove_view(view)
        showing.view = None

    def _follower_panel(self, lectern: Lectern) -> Follower:
        """The follower's panel, built by the lectern for this browser."""
        return lectern.add_follower(self.browser)

    def explore(self) -> str:
        """Leave the presenter with an exact copy of what the shared screen shows now (the same
        scene, state, time, traces, plots and replay history, playing if it plays: `Room.fork`);
        the copy's note ("" for an exact copy), also said in the view's message line: a
        presenter's process that died leaves the last state its room was seen in here, or only
        its scene (`app.lecture.bus.Bus.fetch_room_noted`).  Nothing while not following."""
        lectern = self.browser.lectern
        if lectern is None or self.showing.mode is not Mode.FOLLOWING:
            return ""
        copy, note = lectern.live_copy_noted()
        self.leave_for(copy)
        if note:
            self.showing.scene_view().show_message(note)
        return note

    def leave_for(self, copy: Room) -> None:
        """A follower leaves the presenter and explores `copy` (its camera stays)."""
        browser, showing = self.browser, self.showing
        lectern = browser.lectern
        assert lectern is not None
        narrow = self.phone.narrow_now()
        with showing.switch_lock:
            lectern.remove_follower(browser)
            showing.mode = Mode.OWN
            self.explored = True
            showing.own_room = copy
            showing.hide_live(True)
            with copy.lock:
                showing.view = self.own_room.new_view(copy)
            self.own_room.show_title(copy.scene.title)  # titles match: no switch
        browser.show_mode()
        self.phone.fit_explorer(narrow)
        self.own_room.refresh_preset_commands()
