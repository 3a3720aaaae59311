"""What one browser shows now (`Showing`), and what its roles need of its session (`Browser`).

A browser shows one room through one thing built for its client (`ShownView`): a scene view
(`app.kit.view.SceneView`) of its own room, or of its room live on the shared screen while it
presents; or, while it follows, the follower's panel (`app.lecture.follower.Follower`), the shared
scene drawn by the presenter's view.  `Showing` holds the mode, that view and the browser's own
room; the roles (`app.roles`) switch them together under `switch_lock`.
"""

from __future__ import annotations

import threading
from typing import Any, Protocol

import viser

from app.hall.ask import AnswerPanel, AskPanel
from app.hall.lecture_panel import LecturePanel
from app.hall.lesson_runner import LessonRunner
from app.hall.narrow import NarrowPanel
from app.hall.own_panel import OwnPanel
from app.hall.projector import ProjectorLayout
from app.i18n import N_
from app.kit.core.room import Room
from app.kit.view import SceneView
from app.lecture.follower import Follower
from app.lecture.lectern import LIVE_ROOT, Lectern, Mode, Seat
from app.own import OwnLibrary
from app.refusals import NotAllowed

__all__ = ["Browser", "ShownView", "Showing"]

ShownView = SceneView | Follower
"""What a browser shows its room through: a scene view (own room, presenting) or a follower's panel."""

FOLLOWING_REFUSAL = N_("this browser follows the presenter: press 'Explore on my own' first")
"""The refusal of a change to the room while following (a msgid: `NotAllowed(FOLLOWING_REFUSAL)`)."""


class Showing:
    """What one browser shows now (see the module docstring); owned by its session for the
    browser's life.

    Args:
        client: the browser.  lectern: the app's lecture hall, or None.  room: its first own room.

    Attributes:
        mode: own room, presenting or following (`app.lecture.lectern.Mode`).
        view: the view shown (`ShownView`); None before the first is built and, within a
            switch to following, until the follower's panel is.
        own_room: the browser's own room: shown while OWN, live while PRESENTING, kept unseen
            while FOLLOWING (a new one replaces it when it explores a copy).
        came_after_lecture: it connected after a lecture ended (the last state on the shared
            screen, nobody presenting): it landed in its own room, the last lecture's room one
            click away (`OwnRoom.open_last_lecture`); ends when it follows or presents.
        switch_lock: held while a switch changes mode, view and room together, and by the
            guard while it reads `room`.
    """

    def __init__(self, client: viser.ClientHandle, lectern: Lectern | None, room: Room) -> None:
        self._client = client
        self._lectern = lectern
        self.mode = Mode.OWN
        self.view: ShownView | None = None
        self.own_room = room
        self.came_after_lecture = False
        self.switch_lock = threading.RLock()
        self.shadow: Any = None
        """An invisible node hiding the shared scene in this browser (None while it shows it:
        following or presenting); `hide_live` adds and removes it."""

    @property
    def room(self) -> Room:
        """The room this browser shows: its own, or (following) the one on the shared screen."""
        if self.mode is Mode.FOLLOWING and self._lectern is not None:
            live = self._lectern.live_room
            if live is not None:
                return live
        return self.own_room

    def controlled_room(self) -> Room:
        """The room this browser may change (PermissionError while it follows the presenter)."""
        if self.mode is Mode.FOLLOWING:
            raise NotAllowed(FOLLOWING_REFUSAL)
        return self.room

    def scene_view(self) -> SceneView:
        """The scene view shown (own room or presenting); RuntimeError while following."""
        view = self.view
        if not isinstance(view, SceneView):
            raise RuntimeError("this browser shows no scene view of its own")
        return view

    def hide_live(self, hide: bool) -> None:
        """Hide the shared (presenter's) scene in this browser: an invisible node of the same
        name in this browser's own scope is drawn instead of the shared one and its children."""
        if hide and self.shadow is None:
            self.shadow = self._client.scene.add_frame(LIVE_ROOT, show_axes=False, visible=False)
        elif not hide and self.shadow is not None:
            self.shadow.remove()
            self.shadow = None


class Browser(Seat, Protocol):
    """What the roles need of a browser's session (`app.session.Session` is one): the lectern's
    seat, what it shows, and its panel's parts (`app.hall`)."""

    lectern: Lectern | None
    own: OwnLibrary | None
    showing: Showing
    gui_scene: Any
    gui_language: Any
    projector_layout: ProjectorLayout
    lecture: LecturePanel | None
    ask_panel: AskPanel | None
    question: AnswerPanel | None
    narrow: NarrowPanel
    lesson_runner: LessonRunner
    own_panel: OwnPanel | None

    @property
    def lock(self) -> threading.RLock:
        """Held for the whole of each of the session's callbacks and actions."""
        ...

    def reset_camera(self) -> None:
        """The scene's camera view (centred for the projector layout)."""
        ...

    def show_mode(self) -> None:
        """The panel for the browser's mode (after a switch)."""
        ...
