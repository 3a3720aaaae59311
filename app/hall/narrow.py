"""An explorer's panel on a narrow screen: one status line and `Details` (`NarrowPanel`).

A phone that follows the presenter sees one status line and `Details` (`app.lecture.follower`),
so the body stays in view.  A phone that opens the app with nobody presenting gets this layout
from its first frame (the session starts it while it builds the panel), with "Your scene" in
the line.  When a follower presses `Explore on my own` it keeps that layout: its own
room's panel (the scene's transport, tabs and sliders, the scene dropdown, its own folders) is
folded away behind `Details`, and one line says what its own copy does ("▶ Heavy top · t =
12.3 s · your own copy").  `Details` unfolds the whole panel, `Hide details` folds it again.
The lecture's live bar (`app.hall.lecture_panel`: "Lecture on", `Follow presenter`, `Stay`) is
not folded: the way back stays one tap away.

The panel folds what `handles()` returns (the session hands the list: they change with the
scene) and unfolds exactly what it folded, so a handle the view hid itself stays hidden.
`refresh` folds handles that appeared since (a new scene's panel, a message) and writes the
line; the lectern calls it every FOLLOW_PERIOD through the session (`Seat.lecture_changed`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

import viser

from app.i18n import Translator, for_gui, translator
from app.kit.core.common import Wrap
from app.kit.core.room import LIVE, Room

__all__ = ["NarrowPanel", "own_line"]

ENGLISH = translator("en")


def own_line(room: Room, copy: bool = True, tr: Translator = ENGLISH) -> str:
    """An explorer's status in one line (Markdown): what its own room does ("Your copy" of the
    presenter's room, or `copy` False: "Your scene", a browser that never followed), in the
    language of `tr`."""
    _ = tr.gettext
    whose = _("Your copy") if copy else _("Your scene")
    title = _(room.scene.title)
    if room.mode != LIVE:
        looking = _("looking back at t = {t} s").format(t=tr.decimal(room.shown_t, 1))
        return f"**{whose}** · {title} · {looking}"
    state = _("▶ playing") if room.playing else _("paused")
    return f"**{whose}** · {title} · {state} · t = {tr.decimal(room.sim.t, 1)} s"


class NarrowPanel:
    """One status line and `Details` in place of a browser's own panel (see the module docstring).

    Args:
        client: the browser.
        guard: its session's guard: `Details` runs in it.
        handles: the panel's handles to fold (now).
        room: the browser's own room (now), for the line.
        copy: the room is a copy of the presenter's (the line says "Your copy", else "Your scene").
        order: where the line and `Details` sit in the panel (viser's `order`).
        own: the browser has its own room now (not following, not presenting): `start` does
            nothing otherwise.  A session switching to following or presenting changes its mode
            first and then calls `end`; start, end and refresh run one at a time, so a fold that
            began at connect (another thread) ends with the switch and never outlives it.

    Attributes:
        on: the narrow layout is in force; expanded: `Details` unfolded the panel.
    """

    def __init__(self, client: viser.ClientHandle, guard: Wrap, handles: Callable[[], Sequence[Any]],
                 room: Callable[[], Room], *, order: float, copy: Callable[[], bool] = lambda: True,
                 own: Callable[[], bool] = lambda: True) -> None:
        gui = self._gui = client.gui  # its language: `app.i18n.for_gui`, read at each refresh
        self._handles = handles
        self._own = own
        self._lock = threading.RLock()
        self._room = room
        self._copy = copy
        self.on = False
        self.expanded = False
        self._folded: dict[int, Any] = {}  # id -> handle this panel hid
        self.gui_line = gui.add_markdown("", visible=False, order=order)
        self.gui_details = gui.add_button("Details", icon=viser.Icon.CHEVRON_DOWN, visible=False, order=order + 0.01,
                                          hint="your scene's controls")
        self.gui_details.on_click(guard("details", lambda _event: self.set_expanded(not self.expanded)))

    def start(self) -> None:
        """The narrow layout: the panel folded to the line and `Details` (while the browser has
        its own room)."""
        with self._lock:
            if not self._own():
                return
            self.on, self.expanded = True, False
            self.refresh()

    def end(self) -> None:
        """Back to the whole panel (what was folded is shown again); the line and button go."""
        with self._lock:
            self.on = self.expanded = False
            self._unfold()
            for handle in (self.gui_line, self.gui_details):
                if handle.visible:
                    handle.visible = False

    def set_expanded(self, expanded: bool) -> None:
        """`Details` pressed: unfold (True) or fold (False) the panel."""
        with self._lock:
            if not self.on:
                return
            self.expanded = bool(expanded)
            self.refresh()

    def refresh(self) -> None:
        """Fold what should be folded (handles that appeared since included), write the line."""
        with self._lock:
            if self.on:
                self._fold()

    def _fold(self) -> None:
        """`refresh` with the layout on (the lock held)."""
        folded = not self.expanded
        current = list(self._handles())
        kept = {id(handle) for handle in current}
        self._folded = {key: handle for key, handle in self._folded.items() if key in kept}  # a view removed since
        if folded:
            for handle in current:
                if handle.visible:
                    self._folded[id(handle)] = handle
                    handle.visible = False
        else:
            self._unfold()
        if not self.gui_details.visible:
            self.gui_details.visible = True
        tr = for_gui(self._gui)
        label = tr.gettext("Details") if folded else tr.gettext("Hide details")
        if self.gui_details.label != label:
            self.gui_details.label = label
            self.gui_details.hint = tr.gettext("your scene's controls")
        if self.gui_line.visible != folded:
            self.gui_line.visible = folded
        if folded:
            line = own_line(self._room(), self._copy(), tr)
            if self.gui_line.content != line:
                self.gui_line.content = line

    def _unfold(self) -> None:
        folded, self._folded = list(self._folded.values()), {}
        for handle in folded:
            try:
                handle.visible = True
            except Exception:  # noqa: BLE001 - removed with its view since
                continue
