"""A narrow screen (a phone) with its own room: the folded panel and the camera (`PhoneFit`).

The folded panel itself is `app.hall.narrow.NarrowPanel` (one status line and `Details`); a
following phone has the follower's own narrow layout (`app.lecture.follower.Follower`).  This role
says when the fold starts (at connect, and when a follower leaves to explore), what it folds,
and where a narrow explorer's camera looks from (the body centred above the bottom sheet).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from app.hall.narrow import NarrowPanel
from app.kit.core.common import CameraView, apply_camera
from app.kit.draw.screen import body_centre, centred_view
from app.kit.view import SceneView
from app.lecture.follower import is_narrow
from app.lecture.lectern import Mode
from app.roles.showing import Browser

__all__ = ["PhoneFit"]


class PhoneFit:
    """When a browser's panel folds for a narrow screen, and what it folds (module docstring).

    Holds no state of its own: the fold's state is the session's `NarrowPanel` (`narrow`), and
    the screen's size is the client's camera's.

    Args:
        browser: the session.
    """

    def __init__(self, browser: Browser) -> None:
        self.browser = browser

    def build_fold(self, *, order: float, copy: Callable[[], bool]) -> NarrowPanel:
        """The folded panel's line and `Details` at `order` (`NarrowPanel`; `copy`: the room is a
        copy of the presenter's), folding `foldable`."""
        browser = self.browser
        return NarrowPanel(browser.client, browser.guard, self.foldable, lambda: browser.showing.room, order=order,
                           copy=copy, own=lambda: browser.showing.mode is Mode.OWN)

    def narrow_now(self) -> bool:
        """The browser's view is phone-like now (`app.lecture.follower.is_narrow`)."""
        return is_narrow(self.browser.client.camera)

    def fit_at_connect(self) -> None:
        """A narrow screen with its own room, from the first panel on: the folded layout and the
        camera centring the body above its bottom sheet.  (`NarrowPanel.start` does nothing once
        the browser follows or presents: a switch on another thread ends the fold for good.)"""
        if self.browser.showing.mode is Mode.OWN and self.narrow_now():
            self.browser.narrow.start()
            self.browser.reset_camera()

    def fit_explorer(self, narrow: bool) -> None:
        """A follower that left to explore on a `narrow` screen keeps the phone layout, and its
        camera moves sideways to centre the body (`centre_body`)."""
        if narrow:
            self.browser.narrow.start()
            self.centre_body()

    def foldable(self) -> list[Any]:
        """What a narrow explorer's panel folds away (`app.hall.narrow.NarrowPanel`): the scene and
        Language dropdowns, the lesson, the session's own folders and the view's panel."""
        browser = self.browser
        view = browser.showing.view
        roots: list[Any] = []
        if isinstance(view, SceneView) and browser.showing.mode is not Mode.FOLLOWING:
            roots = list(view.gui_roots)
        return [browser.gui_scene, browser.gui_language, browser.lesson_runner.folder, *browser.own_folders, *roots]

    def screen_changed(self) -> None:
        """The lecture's periodic refresh: a fold whose screen became wide ends; the line is rewritten."""
        narrow = self.browser.narrow
        if narrow.on and not self.narrow_now():
            narrow.end()
        narrow.refresh()

    def centre_body(self) -> None:
        """A narrow explorer's camera: where it looked from (direction, distance, fov), moved
        sideways so the body is in the middle of what its bottom sheet leaves (`centred_view`)."""
        client = self.browser.client
        camera = client.camera
        try:
            view = CameraView(tuple(float(c) for c in camera.position),  # type: ignore[arg-type]
                              tuple(float(c) for c in camera.look_at),  # type: ignore[arg-type]
                              tuple(float(c) for c in camera.up_direction),  # type: ignore[arg-type]
                              math.degrees(float(camera.fov)))
        except (AttributeError, TypeError, ValueError):  # not reported yet: nothing to keep
            return
        distance = math.dist(view.position, view.look_at)
        if distance > 0.0:
            room = self.browser.showing.own_room
            apply_camera(client, centred_view(view, body_centre(room.scene.view), distance))
