"""A following browser's panel (`Follower`) and the words it shows.

This module owns:

- `Hall`: what the shared screen shows (the lectern keeps it; the words follow it).
- `FollowerStatus`: what the followers' panel says, as a value (the hall, the scene and preset,
  the presenter's `Transport`, the lesson step, the scene's key numbers).  The lectern makes it
  where the shared screen is (`FollowerStatus.of_room`); `app.lecture.bus` carries it to the
  other workers as plain values (`to_dict` / `from_dict`, checked); a presenter who stopped or
  left is its `hall` (`ended`), never an edit of words.  Only the panel that shows it writes it
  as Markdown (`markdown`: who presents what, or plainly that the presenter stopped or left;
  `line`: the same in one line, for a narrow screen).
- `is_narrow`: a phone-like view, whose panel collapses to one line and a `Details` button so
  the body stays in view.
- `Follower`: the panel itself: the status, `Follow camera`, `Explore on my own`, the presenter's
  lesson caption over the 3D view (`app.lecture.caption`; its `Caption` checkbox hides it on this
  screen) and the presenter's open plot, read only (`app.lecture.room_plot`).

The panel knows nothing of the lectern or the session: whoever builds it (`Lectern.add_follower`)
hands it the browser's client, its guard, the actions of its buttons and the browser's own
folders, which a collapsed panel hides; the lectern hands it the status (`show_status`).
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping, Sequence
from typing import Annotated, Any, Literal, cast

import msgspec
import viser

from app.i18n import N_, Translator, for_gui, translator
from app.kit.core.common import Wrap
from app.kit.core.key_number import KeyNumber
from app.kit.core.room import LIVE, REPLAYING, SCRUBBING, Room
from app.kit.draw.screen import NARROW_ASPECT, NARROW_PX, narrow_size
from app.lecture.caption import Caption
from app.lecture.room_plot import PlotMirror
from app.lessons import in_language

__all__ = ["DEFAULT_ASPECT", "NARROW_ASPECT", "NARROW_PX", "Follower", "FollowerStatus", "Hall", "Transport",
           "ended_head", "ended_line", "is_narrow", "transport_words", "view_aspect"]

DEFAULT_ASPECT = 1.6  # a browser whose view size is not known yet
MAX_LINE_CHARS = 400  # a title or preset in a status read from another worker
MAX_TEXT_CHARS = 4000  # the lesson step's text in it
MAX_KEY_NUMBERS = 64  # its key numbers
MAX_LESSON_WORDS = 8  # languages of the lesson step's words, and words in each (its line, caption head, text)
FOLLOWING_TITLE = N_("Following the presenter")
DETAILS_LABEL = N_("Details")
HIDE_DETAILS_LABEL = N_("Hide details")
DETAILS_HINT = N_("the presenter's numbers and your options")
FOLLOW_CAMERA_LABEL = N_("Follow camera")
FOLLOW_CAMERA_HINT = N_("see what the presenter's camera sees")
EXPLORE_LABEL = N_("Explore on my own")
EXPLORE_HINT = N_("an exact copy of what the presenter shows now, yours to change")
CAPTION_LABEL = N_("Caption")
CAPTION_HINT = N_("the lesson's words over the 3D view")
TransportMode = Literal["live", "replaying", "scrubbing"]  # `Room.mode` (LIVE, REPLAYING, SCRUBBING)


class Hall(enum.StrEnum):
    """What the shared screen shows."""

    EMPTY = "empty"  # nobody has presented yet
    LIVE = "live"  # a presenter is presenting
    STOPPED = "stopped"  # the presenter pressed Stop presenting: the last state stays
    LEFT = "left"  # the presenter's browser went away: the last state stays


def view_aspect(camera: Any) -> float:
    """Width / height of a browser's 3D view (DEFAULT_ASPECT before it is known)."""
    try:
        width, height = float(camera.image_width), float(camera.image_height)
    except (AttributeError, TypeError, ValueError):
        return DEFAULT_ASPECT
    return width / height if width > 0.0 and height > 0.0 else DEFAULT_ASPECT


def is_narrow(camera: Any) -> bool:
    """A phone-like view (`app.kit.draw.screen.narrow_size`: at most NARROW_PX wide, or portrait,
    aspect below NARROW_ASPECT; the label layout keeps labels off such a view's bottom sheet)."""
    try:
        width = float(camera.image_width)
    except (AttributeError, TypeError, ValueError):
        return False
    return narrow_size(width, width / view_aspect(camera))


class Transport(msgspec.Struct, frozen=True, kw_only=True):
    """What the presenter's transport does (`app.kit.core.room.Room`): the room's `mode` (LIVE,
    REPLAYING or SCRUBBING), `playing`, the simulation's time `t`, the time shown `shown_t` and
    the live end `live_t` [s], and `time_scale` (simulated s per wall s)."""

    mode: TransportMode = "live"
    playing: bool = False
    t: float = 0.0
    shown_t: float = 0.0
    live_t: float = 0.0
    time_scale: float = 1.0

    @classmethod
    def of_room(cls, room: Room) -> Transport:
        """`room`'s transport now."""
        return cls(mode=cast(TransportMode, room.mode), playing=bool(room.playing), t=float(room.sim.t),
                   shown_t=float(room.shown_t), live_t=float(room.live_t), time_scale=float(room.time_scale))


def _english() -> Translator:
    return translator("en")


def transport_words(transport: Transport, tr: Translator | None = None) -> str:
    """What the presenter's transport is doing, in words (playing, paused, looking back,
    replaying), in `tr`'s language (English by default)."""
    tr = tr or _english()
    _ = tr.gettext
    if transport.mode == REPLAYING:
        return _("⟲ replaying t = {shown} s of {live} s ({scale}×)").format(
            shown=tr.decimal(transport.shown_t, 1), live=tr.decimal(transport.live_t, 1),
            scale=tr.general(transport.time_scale))
    if transport.mode == SCRUBBING:
        return _("⟲ looking back at t = {shown} s (live: {live} s)").format(
            shown=tr.decimal(transport.shown_t, 1), live=tr.decimal(transport.live_t, 1))
    return _("▶ playing") if transport.playing else _("paused")


_Line = Annotated[str, msgspec.Meta(max_length=MAX_LINE_CHARS)]
_Text = Annotated[str, msgspec.Meta(max_length=MAX_TEXT_CHARS)]
_Code = Annotated[str, msgspec.Meta(max_length=16)]
_Words = Annotated[dict[_Text, _Text], msgspec.Meta(max_length=MAX_LESSON_WORDS)]


def _cut(text: object) -> str:
    """`text` cut to the length of a status's text (`MAX_TEXT_CHARS`)."""
    return str(text)[:MAX_TEXT_CHARS]


class FollowerStatus(msgspec.Struct, frozen=True, kw_only=True):
    """What the followers' panel says, as data: made where the shared screen is (`of_room`; the
    lectern), carried across workers as plain values (`to_dict` / `from_dict`, checked), and
    written as Markdown only by the panel that shows it (`markdown`, `line`).

    Attributes:
        hall: what the shared screen shows (`Hall`); STOPPED and LEFT say so in the head.
        title: the scene's title ("": nothing on the shared screen).  preset: its preset or "".
        transport: the presenter's transport (`Transport`), None before it is known.
        lesson: the presenter's lesson step ("" for none; shown only while LIVE).
        lesson_words: the words of the step the presenter sends in English (`lesson`, the
            caption's head and words) in the other languages: {code: {English: words}}
            (`app.lessons.step_words`).  They travel with the status, so a follower on any
            process reads the step in its language, a lesson only the presenter's process knows too.
        key_numbers: the scene's key numbers (`KeyNumber`: English labels, numbers), written
            in the words of the browser that shows them.
    """

    hall: Hall = Hall.EMPTY
    title: _Line = ""
    preset: _Line = ""
    transport: Transport | None = None
    lesson: _Text = ""
    lesson_words: Annotated[dict[_Code, _Words], msgspec.Meta(max_length=MAX_LESSON_WORDS)] = msgspec.field(
        default_factory=dict)
    key_numbers: Annotated[tuple[KeyNumber, ...], msgspec.Meta(max_length=MAX_KEY_NUMBERS)] = ()

    @classmethod
    def of_room(cls, room: Room | None, hall: Hall, lesson: str = "",
                key_numbers: Sequence[KeyNumber] = (),
                lesson_words: Mapping[str, Mapping[str, str]] | None = None) -> FollowerStatus:
        """The status of `room` (the room on the shared screen, None if there is none) in `hall`;
        its texts cut to the lengths `from_dict` accepts (a long lesson step is not refused; its
        words in another language then match the English cut the same way)."""
        if room is None:
            return cls(hall=hall)
        preset = getattr(room.sim, "preset", None)
        words = {str(code)[:16]: {_cut(english): _cut(said)
                                  for english, said in list(by_english.items())[:MAX_LESSON_WORDS]}
                 for code, by_english in list((lesson_words or {}).items())[:MAX_LESSON_WORDS]}
        return cls(hall=hall, title=str(room.scene.title)[:MAX_LINE_CHARS],
                   preset=str(preset)[:MAX_LINE_CHARS] if preset else "", transport=Transport.of_room(room),
                   lesson=_cut(lesson), lesson_words=words,
                   key_numbers=tuple(key_numbers[:MAX_KEY_NUMBERS]))

    def lesson_in(self, english: str, language: str) -> str:
        """Words of the lesson the presenter sent in English (the step's line, its caption's head
        or words) in `language`: as the status carries them, else as a shipped lesson has them
        (`app.lessons.in_language`), else `english` itself."""
        return self.lesson_words.get(language, {}).get(english) or in_language(english, language)

    def ended(self, hall: Hall) -> FollowerStatus:
        """The same status once the presenter stopped (`hall` STOPPED) or left (LEFT)."""
        return self if hall is self.hall else msgspec.structs.replace(self, hall=hall)

    def to_dict(self) -> dict[str, Any]:
        """Plain values (str, float, bool, lists, dicts) for a bus message."""
        plain: dict[str, Any] = msgspec.to_builtins(self)
        return plain

    @classmethod
    def from_dict(cls, data: Any) -> FollowerStatus:
        """The status `to_dict` gave, checked (types, a known hall and mode, lengths);
        ValueError (msgspec.ValidationError) for anything else."""
        status: FollowerStatus = msgspec.convert(data, cls)
        return status

    def markdown(self, tr: Translator | None = None) -> str:
        """The followers' panel text: who presents what (or plainly that the presenter stopped or
        left), the scene and preset, the time (once: while the presenter looks back, the head's),
        the lesson step while live, the scene's key numbers (lines); the app's words in `tr`'s
        language (English by default): the scene, a shipped preset's name and the key numbers'
        labels from the catalog, the lesson step where the lesson has it (`app.lessons.in_language`),
        a lecturer's own preset as named."""
        tr = tr or _english()
        _ = tr.gettext
        if not self.title:
            return _("Nobody is presenting.")
        live, transport = self.hall is Hall.LIVE, self.transport
        if not live:
            head = ended_head(self.hall, tr)
        else:
            head = _("**Presenter:** {doing}").format(
                doing=transport_words(transport, tr) if transport is not None else _("presenting"))
        title = _(self.title)  # a scene's title is in the catalog
        scene = (_("Scene **{title}** · preset **{preset}**").format(title=title, preset=_(self.preset))
                 if self.preset else _("Scene **{title}**").format(title=title))
        lines = [head, scene]
        if transport is not None and (transport.mode == LIVE or not live):
            lines.append(f"t = {tr.decimal(transport.t, 1)} s · {tr.general(transport.time_scale)}×")
        if self.lesson and live:
            lines.append(self.lesson_in(self.lesson, tr.language))  # the lesson's words where it has them
        lines.extend(number.words(tr) for number in self.key_numbers)
        return "  \n".join(lines)

    def line(self, tr: Translator | None = None) -> str:
        """The same in one line (Markdown), for a narrow screen, in `tr`'s language (English by default)."""
        tr = tr or _english()
        _ = tr.gettext
        transport = self.transport
        if not self.title:
            return _("Nobody is presenting.")
        title = _(self.title)
        if self.hall is not Hall.LIVE:
            return ended_line(self.hall, title, tr)
        if transport is None:
            return f"**{title}**"
        if transport.mode != LIVE:
            return _("**⟲ {title}** · t = {shown} of {live} s").format(
                title=title, shown=tr.decimal(transport.shown_t, 1), live=tr.decimal(transport.live_t, 1))
        state = "▶" if transport.playing else "⏸"
        return f"**{state} {title}** · t = {tr.decimal(transport.t, 1)} s"


def ended_head(hall: Hall, tr: Translator | None = None) -> str:
    """The first line of the followers' status once the presenter stopped or left ("" otherwise),
    in `tr`'s language (English by default)."""
    _ = (tr or _english()).gettext
    if hall is Hall.STOPPED:
        return _("**The presenter stopped presenting**: this is the last state they showed. "
                 "Explore it on your own, or wait for the next presenter.")
    if hall is Hall.LEFT:
        return _("**The presenter has left**: this is the last state they showed. "
                 "A new presenter can take over with the code.")
    return ""


def ended_line(hall: Hall, title: str, tr: Translator | None = None) -> str:
    """The followers' one line once the presenter stopped or left, in `tr`'s language (English by default)."""
    _ = (tr or _english()).gettext
    if hall is Hall.STOPPED:
        return _("**Presenter stopped** · last state: {title}").format(title=title)
    return _("**Presenter left** · last state: {title}").format(title=title)


class Follower:
    """A following browser's panel: what the presenter shows, read only, and the way out.

    Wide screens see the whole status; a narrow one (`is_narrow`) sees one status line and a
    `Details` button that opens the rest.  The collapsed panel also hides `own_folders` (the
    browser's own folders: projector, notes, lecture); `remove` shows them again.

    Args:
        client: the following browser.
        guard: its session's guard (`Session.guard`): every callback of the panel runs in it.
        explore: the `Explore on my own` button's action.
        follow_camera_changed: called with this panel when `Follow camera` is toggled.
        own_folders: handles of the browser's own panel that a collapsed panel hides.

    Attributes:
        camera: the browser's camera (its view's size sets the layout; the lectern moves it while
            `follow_camera`).
        narrow: the view is narrow; expanded: the whole panel is shown.
    """

    def __init__(self, client: viser.ClientHandle, guard: Wrap, *,
                 explore: Callable[[], None], follow_camera_changed: Callable[[Follower], None],
                 own_folders: Sequence[Any] = ()) -> None:
        gui = client.gui
        self.tr = for_gui(gui)
        """The browser's words (`app.i18n`): the panel and its status speak them (`relabel`)."""
        self.camera = client.camera
        self.own_folders = tuple(own_folders)
        self.narrow = is_narrow(self.camera)
        self.expanded = not self.narrow
        self.folder = gui.add_folder(FOLLOWING_TITLE, order=-10.0)
        with self.folder:
            self.gui_line = gui.add_markdown("")
            self.gui_details = gui.add_button(DETAILS_LABEL, icon=viser.Icon.CHEVRON_DOWN, hint=DETAILS_HINT)
            self.gui_status = gui.add_markdown("")
            self.gui_follow_camera = gui.add_checkbox(FOLLOW_CAMERA_LABEL, True, hint=FOLLOW_CAMERA_HINT)
            self.gui_explore = gui.add_button(EXPLORE_LABEL, icon=viser.Icon.USER, hint=EXPLORE_HINT)
            self.gui_caption = gui.add_checkbox(CAPTION_LABEL, True, hint=CAPTION_HINT)
            self.caption = Caption(gui)
            self.plot = PlotMirror(gui)
        self.gui_explore.on_click(guard("explore", lambda _event: explore()))
        self.gui_details.on_click(guard("details", lambda _event: self.set_expanded(not self.expanded)))
        self.gui_follow_camera.on_update(guard("follow camera", lambda _event: follow_camera_changed(self)))
        self.gui_caption.on_update(guard("caption", lambda _event: self.show_caption(*self._caption_words)))
        self._caption_words = ("", "")
        self._status: FollowerStatus | None = None  # the status last shown (`relabel` writes it again)
        self.relabel(self.tr)  # (lays the panel out)

    def relabel(self, tr: Translator) -> None:
        """The panel in `tr`'s language (its widgets and the status last shown)."""
        self.tr = tr
        _ = tr.gettext
        if self.folder.label != _(FOLLOWING_TITLE):
            self.folder.label = _(FOLLOWING_TITLE)
        handle: Any
        for handle, label, hint in ((self.gui_follow_camera, FOLLOW_CAMERA_LABEL, FOLLOW_CAMERA_HINT),
                                    (self.gui_explore, EXPLORE_LABEL, EXPLORE_HINT),
                                    (self.gui_caption, CAPTION_LABEL, CAPTION_HINT),
                                    (self.gui_details, None, DETAILS_HINT)):
            if label is not None and handle.label != _(label):
                handle.label = _(label)
            if handle.hint != _(hint):
                handle.hint = _(hint)
        self._layout()
        if self._status is not None:
            self.show_status(self._status)
        if any(self._caption_words):
            self.show_caption(*self._caption_words)  # the lesson's words in the new language

    @property
    def follow_camera(self) -> bool:
        return bool(self.gui_follow_camera.value)

    def set_expanded(self, expanded: bool) -> None:
        self.expanded = bool(expanded)
        self._layout()

    def set_narrow(self, narrow: bool) -> None:
        """The browser's view became narrow (or wide): collapse (or expand) the panel."""
        if narrow != self.narrow:
            self.narrow = narrow
            self.expanded = not narrow
            self._layout()

    def fit_screen(self) -> bool:
        """Lay the panel out for the browser's view size now (`set_narrow`); True if it changed."""
        narrow = is_narrow(self.camera)
        if narrow == self.narrow:
            return False
        self.set_narrow(narrow)
        return True

    def _layout(self) -> None:
        full = self.expanded
        self.gui_line.visible = not full
        self.gui_details.visible = self.narrow
        label = self.tr.gettext(HIDE_DETAILS_LABEL if full else DETAILS_LABEL)
        if self.gui_details.label != label:
            self.gui_details.label = label
        for handle in (self.gui_status, self.gui_follow_camera, self.gui_explore, self.gui_caption):
            handle.visible = full
        self.plot.set_shown(full)
        self._show_own_folders(full)

    def _show_own_folders(self, shown: bool) -> None:
        for handle in self.own_folders:
            if handle.visible != shown:
                handle.visible = shown

    def show_status(self, status: FollowerStatus) -> None:
        """Write `status` as Markdown (`FollowerStatus.markdown`, and `line` for the collapsed
        panel); unchanged text is not sent."""
        self._status = status
        text, line = status.markdown(self.tr), status.line(self.tr)
        if self.gui_status.content != text:
            self.gui_status.content = text
        if self.gui_line.content != line:
            self.gui_line.content = line

    def show_caption(self, head: str, words: str) -> None:
        """The presenter's caption (`app.hall.lesson_runner.LessonRunner.caption_words`; "" words:
        none), over this screen's 3D view unless its `Caption` checkbox is off."""
        self._caption_words = (head, words)
        language = self.tr.language  # the presenter sends English: the lesson's words in this browser's,
        status = self._status or FollowerStatus()  # as the status last shown carries them
        head, words = status.lesson_in(head, language), status.lesson_in(words, language)
        shown = self.gui_caption.value is True  # a client can send anything
        self.caption.show(head if shown else "", words if shown else "")

    def show_plot(self, tab: str, elements: Sequence[Any]) -> None:
        """The presenter's open plot tab and its elements (`app.kit.view.SceneView.room_plot`)."""
        self.plot.show(tab, elements)

    def remove(self) -> None:
        """The panel goes; the browser's own folders are shown again."""
        self.folder.remove()
        self._show_own_folders(True)
