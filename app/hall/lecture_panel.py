"""The `Lecture` folder of one browser's panel: present, stop, follow, and the pointer.

This module owns `LecturePanel`: the folder (`Presenter code`, `Present`, `Stop presenting`,
`Pointer`, `Pointer label`, `Follow presenter`, a note for a refused code that stays true: the
wait counts down and the note goes when the refusal no longer holds), which of them the
browser's mode shows (`show_for`), and the pointer's click handlers on the browser's own scene
(registered only while it presents).  What the buttons do (becoming the presenter, stopping,
following) is the session's: the panel calls it through `Lecturer`.
"""

from __future__ import annotations

from typing import Any, Protocol

import viser

from app.kit.core.common import Wrap
from app.lectern import Lectern, Mode, Seat

__all__ = ["Lecturer", "LecturePanel"]


class Lecturer(Seat, Protocol):
    """What the Lecture folder drives: a browser's session (`app.session.Session` is one)."""

    def present(self, code: str) -> None:
        """Become the presenter with `code`."""
        ...

    def stop_presenting(self) -> None:
        """Release the presenter lock."""
        ...


class LecturePanel:
    """The Lecture folder of `seat`'s panel (built where the panel has it).

    Args:
        seat: the browser's session.
        guard: its guard: the folder's callbacks run in it.
        lectern: the app's lecture hall.

    Attributes:
        folder: the folder; gui_*: its widgets.
    """

    def __init__(self, seat: Lecturer, guard: Wrap, lectern: Lectern) -> None:
        self.seat = seat
        self.lectern = lectern
        gui: Any = seat.client.gui  # viser's handles type `value` read-only; it is not
        self.folder = gui.add_folder("Lecture", expand_by_default=False)
        with self.folder:
            self.gui_code = gui.add_text("Presenter code", "", hint="the code the app printed at start")
            self.gui_present = gui.add_button("Present", icon=viser.Icon.PRESENTATION,
                                              hint="show this browser's scene to everyone who follows")
            self.gui_stop = gui.add_button("Stop presenting", color="red", visible=False)
            self.gui_pointer = gui.add_checkbox("Pointer", False, visible=False,
                                                hint="click in the 3D view to point for everyone (or hold Shift)")
            self.gui_pointer_label = gui.add_text("Pointer label", "", visible=False,
                                                  hint="a few words shown beside the marker")
            self.gui_follow = gui.add_button("Follow presenter", icon=viser.Icon.USERS, visible=False)
            self.gui_note = gui.add_markdown("", visible=False)
        self._guarded_point = guard("pointer", self._pointed)
        self.gui_present.on_click(guard("present", lambda _event: seat.present(str(self.gui_code.value))))
        self.gui_stop.on_click(guard("stop presenting", lambda _event: seat.stop_presenting()))
        self.gui_follow.on_click(guard("follow", lambda _event: seat.follow()))
        self.gui_pointer.on_update(guard("pointer", lambda _event: self.set_pointer(self.gui_pointer.value)))

    def note(self, text: str) -> None:
        """Say `text` (Markdown) under the buttons ("": nothing)."""
        if self.gui_note.content != text:
            self.gui_note.content = text
        if self.gui_note.visible != bool(text):
            self.gui_note.visible = bool(text)
        if not text:
            self.lectern.watch_refusal(self.seat, None)

    def refused(self) -> None:
        """Say the lectern's refusal of this browser's code, kept true while it is shown: the wait
        counts down, and the note goes when the refusal no longer holds (`Lectern.refusal_now`)."""
        self.show_refusal()
        if self.gui_note.visible:
            self.lectern.watch_refusal(self.seat, self.show_refusal)

    def show_refusal(self) -> None:
        """The refusal's words as they are now (or no note)."""
        words = self.lectern.refusal_now(self.seat)
        self.note(f"**⚠ {words}**" if words else "")

    def show_for(self, mode: Mode) -> None:
        """The buttons for the browser's `mode`: `Present` and the code unless it presents,
        `Stop presenting` and the pointer while it does, `Follow presenter` while it explores
        and somebody else presents."""
        presenter = self.lectern.presenter
        self.gui_present.visible = self.gui_code.visible = mode is not Mode.PRESENTING
        self.gui_stop.visible = self.gui_pointer.visible = self.gui_pointer_label.visible = \
            mode is Mode.PRESENTING
        self.gui_follow.visible = mode is Mode.OWN and presenter is not None and presenter is not self.seat

    def set_pointer(self, on: Any) -> None:
        """Pointer on: a plain click points; off: only Shift + click does (while presenting)."""
        if not isinstance(on, bool):  # a client can send anything
            self.gui_pointer.value = False
            return
        scene = self.seat.client.scene
        scene.remove_click_callback(self._guarded_point)
        if self.seat.mode is not Mode.PRESENTING:
            return
        scene.on_click(modifier="shift")(self._guarded_point)
        if on:
            scene.on_click()(self._guarded_point)

    def _pointed(self, event: Any) -> None:
        """A click on the browser's own scene (only it hears them): a marker for everyone."""
        if self.seat.mode is Mode.PRESENTING:
            self.lectern.point(self.seat, event.ray_origin, event.ray_direction, str(self.gui_pointer_label.value))
