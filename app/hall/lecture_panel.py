"""The lecture's parts of one browser's panel: the live bar at the top, and the `Lecture` folder.

This module owns `LecturePanel`:

- **The live bar**, at the top of the panel (right under the error line), outside every folder,
  so that every layout shows it (the projector's docked panel included), and pinned there: its
  widgets sit in one unlabelled form (`bar`, one `<form>` element in the page) that LIVE_BAR_CSS
  keeps at the top of the panel's scroll (`position: sticky`), so a long scene panel scrolls
  under it and `Stop presenting` stays in sight whatever scene, preset or folder is open:
  - while the browser presents: the badge ("● Live · 3 following · 1 exploring", `live_badge`),
    `Stop presenting`, `Pointer` and `Call everyone back`;
  - while it explores and somebody else presents: "Lecture on" with `Follow presenter`; when
    the presenter calls everyone back, the countdown ("following again in 7 s") and `Stay`;
  - when it came after a lecture ended (in its own room, `Lecturer.came_after_lecture`): "The
    lecture has ended" (`ended_text`) and `Open the last lecture's room` (a copy of the room
    the presenter left, `Lecturer.open_last_lecture`), until it follows or presents.
- **The Lecture folder**: `Presenter code`, `Present`, `Pointer label`, a note for a refused code
  that stays true (the wait counts down, the note goes when the refusal no longer holds).

`refresh` (called by the lectern every FOLLOW_PERIOD through `Seat.lecture_changed`, and when
the browser's mode changes) shows what the browser's mode and the lectern's state call for,
writing only what changed.  The pointer's click handlers sit on the browser's own scene,
registered only while it presents.  What the buttons do (becoming the presenter, stopping,
following, calling back) is the session's and the lectern's: the panel calls them through
`Lecturer`, and the lectern refuses a call back from anyone but the presenter.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import Any, Protocol

import viser

from app.i18n import N_, Labels, Phrases, Translator, for_gui, translator
from app.kit.core.common import Wrap, show_if_changed, write_if_changed
from app.lecture.follower import Hall
from app.lecture.lectern import CALL_BACK_SECONDS, Lectern, Mode, Seat

__all__ = ["CALL_BACK_LABEL", "FOLLOW_LABEL", "LAST_ROOM_LABEL", "LIVE_BAR_CLASS", "LIVE_BAR_CSS", "STAY_LABEL",
           "LecturePanel", "Lecturer", "call_text", "ended_text", "live_badge"]

CALL_BACK_LABEL = N_("Call everyone back")
FOLLOW_LABEL = N_("Follow presenter")
FOLLOW_HINT = N_("back to the presenter's live scene")
STAY_LABEL = N_("Stay")
STAY_HINT = N_("keep exploring your own copy")
LAST_ROOM_LABEL = N_("Open the last lecture's room")
LAST_ROOM_HINT = N_("a copy of the room the presenter left, paused, yours to change")
LIVE_BAR_CLASS = "rb-live-bar"  # the marker inside the live bar's form (the CSS finds the form by it)
LIVE_BAR_CSS = f"""<div class="{LIVE_BAR_CLASS}"><style>
.mantine-ScrollArea-viewport div[style*="overflow: hidden"]:has(.{LIVE_BAR_CLASS}) {{
  overflow: clip !important; min-width: 0; }}
form:has(.{LIVE_BAR_CLASS}) {{ position: sticky; top: 0; z-index: 20; background: var(--mantine-color-body); }}
form:has(.{LIVE_BAR_CLASS}):has(button:not([hidden])) {{
  padding-top: 0.4em; box-shadow: 0 0.3em 0.4em -0.3em rgba(0,0,0,0.25); }}
</style></div>"""
"""The live bar pinned at the top of the panel's scroll: an HTML element inside the bar's form,
whose style (it applies to the whole page) makes that form sticky over an opaque background,
with a shadow while it shows anything.  viser wraps the panel's contents in a collapse whose
`overflow: hidden` would be the sticky form's scroll box (it never scrolls): between the panel's
scroller and the bar it becomes `overflow: clip`, which clips the same and scrolls nothing, with
`min-width: 0` (a grid item that is no scroll box would otherwise grow to its content's width,
and the panel would scroll sideways)."""


CODE_REFUSALS = Phrases(
    (r"Too many wrong codes: wait (?P<wait>\d+) s before trying again\.",
     N_("Too many wrong codes: wait {wait} s before trying again.")),
    (r"Wrong presenter code, no tries left: wait (?P<wait>\d+) s before trying again\.",
     N_("Wrong presenter code, no tries left: wait {wait} s before trying again.")),
    (r"Too many wrong codes in this lecture hall \(someone may be guessing\): wait (?P<wait>\d+) s "
                r"before trying again\.",
     N_("Too many wrong codes in this lecture hall (someone may be guessing): wait {wait} s before trying again.")),
    (r"Someone else is presenting; they must stop first\.",
     N_("Someone else is presenting; they must stop first.")),
    (r"The presenter lock does not answer \(the lecture's Redis\); try again in a moment\.",
     N_("The presenter lock does not answer (the lecture's Redis); try again in a moment.")),
)
"""The lectern's refusals of a presenter code (`app.lecture.lectern`), matched in English, and their msgids."""
TRIES_LEFT = re.compile(r"Wrong presenter code \((?P<left>\d+) tr(?:y|ies) left this minute\)\.")


def refusal_in_language(words: str, tr: Translator) -> str:
    """A refusal of a presenter code (the lectern's English words) in `tr`'s language; the words
    as they are when no pattern knows them."""
    found = TRIES_LEFT.fullmatch(words)
    if found:
        left = int(found["left"])
        return tr.ngettext("Wrong presenter code ({left} try left this minute).",
                           "Wrong presenter code ({left} tries left this minute).", left).format(left=left)
    return CODE_REFUSALS.in_language(words, tr)


def live_badge(following: int, exploring: int, tr: Translator | None = None) -> str:
    """The presenter's badge (Markdown): the room is live, who follows and who explores, in
    `tr`'s language (English by default)."""
    _ = (tr or translator("en")).gettext
    return _("**● Live** · {following} following · {exploring} exploring").format(
        following=following, exploring=exploring)


def call_text(seconds_left: float, tr: Translator | None = None) -> str:
    """An explorer's offer to come back (Markdown), `seconds_left` [s] before it follows, in
    `tr`'s language (English by default)."""
    _ = (tr or translator("en")).gettext
    return _("**The presenter calls everyone back**: following again in {seconds} s. "
             "Press {stay} to keep exploring.").format(seconds=max(1, math.ceil(seconds_left)), stay=_(STAY_LABEL))


def lecture_on_text(scene: str, tr: Translator | None = None) -> str:
    """An explorer's reminder (Markdown) that a lecture runs, showing `scene` ("" for a scene not
    known yet), in `tr`'s language (English by default; a scene's title translated)."""
    _ = (tr or translator("en")).gettext
    return _("**● Lecture on** · the presenter shows {scene}").format(scene=_(scene) if scene else _("a scene"))


def ended_text(hall: Hall, scene: str, tr: Translator | None = None) -> str:
    """A newcomer's line (Markdown) once the lecture ended (`hall` STOPPED or LEFT), its last scene
    `scene` ("" when not known), in `tr`'s language (English by default)."""
    _ = (tr or translator("en")).gettext
    how = _("the presenter has left") if hall is Hall.LEFT else _("the presenter stopped presenting")
    return _("**The lecture has ended** ({how}; last scene: {scene}). This room is your own.").format(
        how=how, scene=_(scene) if scene else _("a scene"))


class Lecturer(Seat, Protocol):
    """What the lecture's panel drives: a browser's session (`app.session.Session` is one)."""

    @property
    def came_after_lecture(self) -> bool:
        """It connected after a lecture ended (and has not followed or presented since)."""
        ...

    def open_last_lecture(self) -> None:
        """Show a copy of the room the last presenter left, in place of its own."""
        ...

    def present(self, code: str) -> None:
        """Become the presenter with `code`."""
        ...

    def stop_presenting(self) -> None:
        """Release the presenter lock."""
        ...


class LecturePanel:
    """The live bar and the Lecture folder of `seat`'s panel (built where the panel has them).

    Args:
        seat: the browser's session.
        guard: its guard: the callbacks run in it.
        lectern: the app's lecture hall.
        order: the live bar's place in the panel (viser's `order`: it goes right after this).

    Attributes:
        bar: the live bar's form (pinned at the top of the panel); folder: the Lecture folder;
        gui_*: the widgets.
    """

    def __init__(self, seat: Lecturer, guard: Wrap, lectern: Lectern, *, order: float = -5.0) -> None:
        self.seat = seat
        self.lectern = lectern
        gui: Any = seat.client.gui  # viser's handles type `value` read-only; it is not
        orders = iter(order + 0.01 * k for k in range(1, 20))
        # The live bar (top of the panel, in no folder), in one unlabelled form pinned by LIVE_BAR_CSS.
        self.bar = gui.add_form(None, order=next(orders))
        with self.bar:
            self._build_bar(gui, orders)
        # The Lecture folder.
        self.folder = gui.add_folder(N_("Lecture"), expand_by_default=False)
        with self.folder:
            self.gui_code = gui.add_text(N_("Presenter code"), "", hint=N_("the code the app printed at start"))
            self.gui_present = gui.add_button(N_("Present"), icon=viser.Icon.PRESENTATION,
                                              hint=N_("show this browser's scene to everyone who follows"))
            self.gui_pointer_label = gui.add_text(N_("Pointer label"), "", visible=False,
                                                  hint=N_("a few words shown beside the marker"))
            self.gui_note = gui.add_markdown("", visible=False)
        self.words = Labels(gui)
        self.words.take(self.folder, self.gui_code, self.gui_present, self.gui_pointer_label, self.gui_stop,
                        self.gui_pointer, self.gui_stay, self.gui_follow, self.gui_last_room)
        self.words.take(self.gui_call_back, seconds=f"{CALL_BACK_SECONDS:g}", stay=STAY_LABEL)
        self._guarded_point = guard("pointer", self._pointed)
        self.gui_present.on_click(guard("present", lambda _event: seat.present(str(self.gui_code.value))))
        self.gui_stop.on_click(guard("stop presenting", lambda _event: seat.stop_presenting()))
        self.gui_follow.on_click(guard("follow", lambda _event: seat.follow()))
        self.gui_pointer.on_update(guard("pointer", lambda _event: self.set_pointer(self.gui_pointer.value)))
        self.gui_call_back.on_click(guard("call everyone back", lambda _event: self.call_back()))
        self.gui_stay.on_click(guard("stay", lambda _event: self.stay()))
        self.gui_last_room.on_click(guard("last lecture's room", lambda _event: seat.open_last_lecture()))

    def _build_bar(self, gui: Any, orders: Iterator[float]) -> None:
        """The live bar's widgets (inside `bar`), hidden until `refresh` shows them."""
        self.gui_pin = gui.add_html(LIVE_BAR_CSS, order=next(orders))
        self.gui_badge = gui.add_markdown("", visible=False, order=next(orders))
        self.gui_stop = gui.add_button(N_("Stop presenting"), color="red", visible=False, order=next(orders))
        self.gui_pointer = gui.add_checkbox(N_("Pointer"), False, visible=False, order=next(orders),
                                            hint=N_("click in the 3D view to point for everyone (or hold Shift)"))
        self.gui_call_back = gui.add_button(CALL_BACK_LABEL, visible=False, order=next(orders),
                                            hint=N_("every explorer follows again in {seconds} s "
                                                    "unless they press {stay}"))
        self.gui_lecture_on = gui.add_markdown("", visible=False, order=next(orders))
        self.gui_stay = gui.add_button(STAY_LABEL, visible=False, order=next(orders), hint=STAY_HINT)
        self.gui_follow = gui.add_button(FOLLOW_LABEL, icon=viser.Icon.USERS, visible=False, order=next(orders),
                                         hint=FOLLOW_HINT)
        self.gui_ended = gui.add_markdown("", visible=False, order=next(orders))
        self.gui_last_room = gui.add_button(LAST_ROOM_LABEL, icon=viser.Icon.HISTORY, visible=False,
                                            order=next(orders), hint=LAST_ROOM_HINT)

    def relabel(self, tr: Translator) -> None:
        """The folder's and the live bar's words in `tr`'s language (the browser chose another), a
        refusal of its code shown under the buttons too."""
        self.words.relabel(tr)
        self.refresh()
        if self.gui_note.visible:
            self.show_refusal()

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
        self.note(f"**⚠ {refusal_in_language(words, for_gui(self.seat.client.gui))}**" if words else "")

    def show_for(self, mode: Mode) -> None:
        """The panel for the browser's `mode` (`refresh`)."""
        self.refresh()

    def refresh(self) -> None:
        """Show what the browser's mode and the lecture call for: `Present` and the code unless
        it presents; the badge, `Stop presenting`, the pointer and `Call everyone back` while it
        does; "Lecture on" and `Follow presenter` while it explores and somebody else presents
        (with the countdown and `Stay` while it is called back); "The lecture has ended" and
        `Open the last lecture's room` while a browser that came after the lecture ended is in
        its own room and nobody presents.  Only what changed is sent."""
        mode, lectern = self.seat.mode, self.lectern
        presenter = lectern.presenter
        presenting = mode is Mode.PRESENTING
        exploring = mode is Mode.OWN and lectern.someone_presents and presenter is not self.seat
        show_if_changed(self.gui_code, not presenting)
        show_if_changed(self.gui_present, not presenting)
        for handle in (self.gui_badge, self.gui_stop, self.gui_pointer, self.gui_pointer_label, self.gui_call_back):
            show_if_changed(handle, presenting)
        if presenting:
            following, explorers = lectern.total_audience()
            write_if_changed(self.gui_badge, live_badge(following, explorers, for_gui(self.seat.client.gui)))
            if self.gui_call_back.disabled != (explorers == 0):
                self.gui_call_back.disabled = explorers == 0
        tr = for_gui(self.seat.client.gui)  # the explorer's words: its language now
        left = lectern.call_back_left(self.seat) if exploring else None
        if exploring:
            write_if_changed(self.gui_lecture_on, call_text(left, tr) if left is not None
                   else lecture_on_text(lectern.live_title() or "", tr))
        show_if_changed(self.gui_lecture_on, exploring)
        show_if_changed(self.gui_follow, exploring)
        show_if_changed(self.gui_stay, left is not None)
        ended = (mode is Mode.OWN and self.seat.came_after_lecture and lectern.live
                 and not lectern.someone_presents and lectern.hall in (Hall.STOPPED, Hall.LEFT))
        if ended:
            write_if_changed(self.gui_ended, ended_text(lectern.hall, lectern.live_title() or "", tr))
        show_if_changed(self.gui_ended, ended)
        show_if_changed(self.gui_last_room, ended)

    def call_back(self) -> None:
        """The presenter asks every explorer back (`Lectern.call_back`); said in the badge's place."""
        called = self.lectern.call_back(self.seat)
        tr = for_gui(self.seat.client.gui)
        self.seat.client.add_notification(
            tr.gettext("Called everyone back"),
            tr.ngettext("{count} explorer will follow again in {seconds} s unless they press {stay}.",
                        "{count} explorers will follow again in {seconds} s unless they press {stay}.",
                        called).format(count=called, seconds=f"{CALL_BACK_SECONDS:g}", stay=tr.gettext(STAY_LABEL)),
            auto_close_seconds=4.0)

    def stay(self) -> None:
        """This explorer keeps exploring (`Lectern.stay`)."""
        self.lectern.stay(self.seat)
        self.refresh()

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
