"""The following browsers: their panels (`app.lecture.follower.Follower`), what is written into
them (the status as a `FollowerStatus`, the caption, the presenter's open plot), the presenter's
camera fitted to each one's screen, and the kinds of follower's screen the shared labels are
laid out for.  What the shared screen shows is the lectern's (`Stage`); this part reads it."""

from __future__ import annotations

import logging
import time
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from app.kit.core.key_number import KeyNumber
from app.kit.draw.labels import Screen
from app.kit.draw.screen import screen_of
from app.lecture.follower import Follower, FollowerStatus, Hall, view_aspect
from app.lecture.lectern.broadcast import fitted_camera
from app.lecture.lectern.seat import Seat, Stage

__all__ = ["CAMERA_PERIOD", "FOLLOWER_SCREENS_PERIOD", "MAX_LABEL_SCREENS", "Followers"]

logger = logging.getLogger(__name__)

CAMERA_PERIOD = 0.1  # [s] the presenter's camera reaches the followers at most this often
FOLLOWER_SCREENS_PERIOD = 0.25  # [s] the followers' kinds of screen are looked at again after this long
MAX_LABEL_SCREENS = 6  # a presenter's labels are laid out for its screen and at most 5 kinds of follower's


class Followers:
    """The panels of this process's following browsers, by client id, and what they show.

    Args:
        stage: the lectern (who presents, what the shared screen shows, another process's show).
    """

    def __init__(self, stage: Stage) -> None:
        self._stage = stage
        self._followers: dict[int, tuple[Seat, Follower]] = {}  # by client id
        self._watched: set[int] = set()  # client ids whose camera the lectern hears
        self._screens: tuple[float, list[Screen]] | None = None  # (when, `follower_screens`)
        self._camera_due = False
        self._since_camera = 0.0

    @property
    def panels(self) -> Mapping[int, Follower]:
        """The following browsers' panels by client id (read only: `add`, `remove` change them)."""
        entries = list(self._followers.items())  # one step: other threads add and remove followers
        return MappingProxyType({client_id: follower for client_id, (_, follower) in entries})

    def seats(self) -> list[Seat]:
        """The following seats that are still open."""
        return [seat for seat, _ in list(self._followers.values()) if not seat.closed]

    def add(self, seat: Seat) -> Follower:
        """`seat` follows: its panel (`Follower`, hiding the seat's own folders when collapsed),
        the status written, the presenter's camera sent."""
        follower = Follower(seat.client, seat.guard, explore=seat.explore, follow_camera_changed=self.send_camera,
                            own_folders=seat.own_folders)
        follower.show_status(self.status())
        follower.show_caption(*self.caption())
        follower.show_plot(*self.room_plot())
        self._followers[seat.client_id] = (seat, follower)
        self._screens = None
        self.watch_camera(seat)
        self.send_camera(follower)
        return follower

    def remove(self, seat: Seat, *, disconnected: bool = False) -> None:
        """`seat` follows no more: its panel goes (nothing to remove if its browser has
        `disconnected`)."""
        entry = self._followers.pop(seat.client_id, None)
        self._screens = None
        if entry is not None and not disconnected:
            entry[1].remove()

    def forget(self, client_id: int) -> None:
        """The browser `client_id` left: its panel and its camera's listener are no longer kept."""
        self._watched.discard(client_id)
        if self._followers.pop(client_id, None) is not None:
            self._screens = None

    # ------------------------------------------------------------------ what the panels show
    def _key_numbers(self) -> list[KeyNumber]:
        view = self._stage.live_view
        if view is None:
            return []
        try:
            return list(view.key_numbers())
        except Exception:  # noqa: BLE001 - a status line must not break the followers' refresh
            logger.debug("key numbers failed", exc_info=True)
            return []

    def status(self) -> FollowerStatus:
        """The followers' status: of the room on the shared screen, or as another process's
        presenter's process made it (`RemoteShow.shown_status`)."""
        stage = self._stage
        presenter, remote = stage.presenter, stage.remote
        if remote is not None and presenter is None:
            return remote.shown_status()
        lesson, words = "", {}  # the lesson step while live: in English, and its words in the other languages
        if presenter is not None and stage.hall is Hall.LIVE:
            lesson, words = presenter.lesson_text(), presenter.lesson_words()
        return FollowerStatus.of_room(stage.live_room, stage.hall, lesson, self._key_numbers(), words)

    def caption(self) -> tuple[str, str]:
        """(head, words) of the lesson caption over every follower's 3D view: the presenter's
        (`Seat.caption_words`) while one presents; ("", "") otherwise."""
        stage = self._stage
        presenter, remote = stage.presenter, stage.remote
        if presenter is None and remote is not None:
            return remote.caption if remote.hall is Hall.LIVE else ("", "")
        if presenter is None or stage.hall is not Hall.LIVE:
            return "", ""
        return presenter.caption_words()

    def room_plot(self) -> tuple[str, list[Any]]:
        """(tab, elements): the plot tab the presenter has open and its panel elements, which
        every follower sees copied (`app.kit.view.SceneView.room_plot`; a presenter on another
        process: what the bus brought, `RemoteShow.plot`); ("", []) for none."""
        stage = self._stage
        view, presenter, remote = stage.live_view, stage.presenter, stage.remote
        if presenter is None and remote is not None:
            return (remote.plot[0], list(remote.plot[1])) if remote.hall is Hall.LIVE else ("", [])
        if presenter is None or view is None:
            return "", []
        try:
            return view.room_plot()
        except Exception:  # noqa: BLE001 - the followers' refresh must not break
            logger.debug("room plot failed", exc_info=True)
            return "", []

    def refresh(self) -> None:
        """Write the status, the caption and the presenter's plot into every follower's panel."""
        status, caption, plot = self.status(), self.caption(), self.room_plot()
        for seat, follower in list(self._followers.values()):
            if seat.closed:
                continue
            try:
                follower.show_status(status)
                follower.show_caption(*caption)
                follower.show_plot(*plot)
            except Exception:  # noqa: BLE001 - a follower that just left
                logger.debug("follower refresh failed", exc_info=True)

    # ------------------------------------------------------------------ cameras and screens
    def watch_camera(self, seat: Seat) -> None:
        """Hear `seat`'s camera (once per browser): a presenter's moves reach the followers, a
        follower's view size sets its layout."""
        if seat.client_id in self._watched:
            return
        self._watched.add(seat.client_id)
        seat.client.camera.on_update(lambda _camera: self._camera_moved(seat))

    def _camera_moved(self, seat: Seat) -> None:
        if seat is self._stage.presenter:
            self._camera_due = True
            return
        entry = self._followers.get(seat.client_id)
        if entry is not None and entry[0] is seat:
            self._screens = None
            self._resized(*entry)

    def _resized(self, seat: Seat, follower: Follower) -> None:
        """A follower's view changed size (or its camera moved): collapse its panel on a narrow
        screen, and frame the presenter's view for its aspect."""
        if seat.guard("follower layout", follower.fit_screen)():
            self.send_camera(follower)

    def send_camera(self, follower: Follower) -> None:
        """Put a follower's camera where the presenter's is (if it follows the camera): the
        presenter's viewing direction and look_at, the distance fitted to the follower's aspect
        (`fitted_camera`) so a phone shows what the presenter's wide view shows."""
        presenter, remote = self._stage.presenter, self._stage.remote
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
        self._screens = None  # its screen's view moved

    def tick(self, dt: float) -> None:
        """From the app loop: send the presenter's camera to every follower at most every
        CAMERA_PERIOD, when it moved."""
        self._since_camera += dt
        if self._camera_due and self._since_camera >= CAMERA_PERIOD:
            self._camera_due = False
            self._since_camera = 0.0
            for _, follower in list(self._followers.values()):
                self.send_camera(follower)

    def label_screens(self) -> list[Screen]:
        """The screens the shared scene's labels are laid out for (`LabelLayer.screens`): the
        presenter's, then one of each kind of follower's (`follower_screens`), then those of the
        followers on other processes (`Stage.remote_screens`); at most MAX_LABEL_SCREENS in all.
        Read without the lectern's lock (the layout holds a room's)."""
        screens: list[Screen] = []
        presenter = self._stage.presenter
        if presenter is not None:
            own = screen_of(presenter.client.camera, docked=bool(getattr(presenter, "projector", False)))
            if own is not None:
                screens.append(own)
        for screen in (*self.follower_screens(), *self._stage.remote_screens()):
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
        cached = self._screens
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
        self._screens = (now, screens)
        return screens
