"""The replay's panel piece, under the transport: `Timeline [s]`, Replay · Resume · Branch here.

`Timeline` only reports to its room (`app.kit.core.room.Room.scrub`, `replay`, `resume`, `branch`)
and shows the room's replay state, so every view of a room shows the same.  `SceneView.build`
adds one under the transport of every scene whose simulation can be replayed (the room has a
`history`); the room draws it after its view (`frame`, `refresh`).

- The slider spans the recorded stretch [t_first, t_live] [s] (rounded outwards to its step;
  a value within one step of an end is taken as that end).  Moving it pauses and shows the
  recorded moment; a time outside the stretch (a hand-written client) is refused with the
  stretch in the message, and nothing changes.  While live it follows the live time once a
  second (its text and range with it), while replaying at 5 Hz.
- Replay: plays the recording from the moment shown (from the start if the live moment is
  shown) at the transport's time scale; Play / Pause pause and go on; it ends at the live moment.
- Resume: back to the live moment, exactly as it was; plays on if it was playing.
- Branch here: the moment shown becomes the live one and the motion plays on from it.
- The status line: "Replaying t = 12.3 s of 40.1 s (0.1×)".  While the room shows a recorded
  moment it is the panel's one time: the transport's own status line says no time meanwhile
  (`Transport.looking_back`; it keeps its place, so nothing moves under the hand).
- A typed time outside the stretch is refused the same way while the motion plays or stands:
  the box shows the slider's value again at once, and the refusal is said right under the slider
  (`app.kit.panel.binding.ControlNote`), quoting the stretch as it is now ("only 0.00 s to 6.20 s
  is recorded", said anew whenever the Timeline shows the room's state, so it stays true while the
  stretch grows); it goes when the slider takes a time or a button is pressed, or once the
  stretch has grown to hold the time refused.  The message line at the top of the panel says it
  too, until the stretch has moved on by STALE_S (`MessageLine.show(..., stale)`).
"""

from __future__ import annotations

import functools
import math
from typing import Any

from app.i18n import N_, Phrases, Translator, translator
from app.kit.core.common import Throttle, Wrap
from app.kit.core.history import HISTORY_SECONDS
from app.kit.core.room import LIVE, REPLAYING, Room
from app.kit.panel.binding import Binding, Clock, Refused, bind
from app.kit.panel.gui import MessageLine, Quiet

__all__ = ["BRANCH_LABEL", "REPLAY_LABEL", "RESUME_LABEL", "STALE_S", "TIMELINE_LABEL", "TIMELINE_STEP", "Timeline",
           "TIMELINE_REFUSALS", "stretch_moved", "timeline_text"]

ENGLISH = translator("en")
TIMELINE_LABEL = N_("Timeline [s]")
REPLAY_LABEL, RESUME_LABEL, BRANCH_LABEL = N_("Replay"), N_("Resume"), N_("Branch here")
"""(The replay button is not called "Replay": a page's "Play" button must stay the only one whose
name contains "play", which the browser tests' locators rely on.)"""
TIMELINE_STEP = 0.01  # [s] the slider's step
FOLLOW_PERIOD = 0.2  # [s] of wall time between the slider's updates while replaying (5 Hz)
LIVE_FOLLOW_PERIOD = 1.0  # [s] ... while live (1 Hz): the recorded stretch only grows, nobody reads it closely
STALE_S = 0.5  # [s] a refusal quoting the stretch goes once either end has moved this far

TIMELINE_REFUSALS = Phrases(
    (r"Time (?P<t>.+) refused: nothing is recorded yet \(play first\)\.",
     N_("Time {t} refused: nothing is recorded yet (play first).")),
    (r"Time (?P<t>.+) s refused: only (?P<lo>\S+) s to (?P<hi>\S+) s is recorded \(the last (?P<seconds>\S+) s of "
     r"this run\)\.",
     N_("Time {t} s refused: only {lo} s to {hi} s is recorded (the last {seconds} s of this run).")),
    (r"Branch here continues from a moment in the past: move the Timeline back first\.",
     N_("Branch here continues from a moment in the past: move the Timeline back first.")),
    (r"(?P<scene>.+) has no motion to replay\.", N_("{scene} has no motion to replay.")),
    translated=("scene",), numbers=("lo", "hi", "seconds"),
)
"""The refusals of the Timeline's buttons and slider (`app.kit.core.room`, `app.kit.core.history`:
English), matched whole, and their msgids."""


def stretch_moved(then: tuple[float, float] | None, now: tuple[float, float] | None) -> bool:
    """The recorded stretch `now` is no longer the one `then` (an end moved by STALE_S or more)."""
    if then is None or now is None:
        return then is not now
    return max(abs(now[0] - then[0]), abs(now[1] - then[1])) >= STALE_S


def timeline_text(room: Room, tr: Translator = ENGLISH) -> str:
    """The status line of the room's replay state, in the language of `tr`."""
    _ = tr.gettext
    stretch = room.stretch()
    if stretch is None:
        return _("Replay: the last {seconds} s of motion are kept once it plays.").format(
            seconds=tr.general(HISTORY_SECONDS))
    t_first, t_live = (tr.decimal(t, 2) for t in stretch)
    if room.mode == LIVE:
        return _("Live · recorded {first} s to {live} s; move the Timeline to look back.").format(
            first=t_first, live=t_live)
    t = tr.decimal(room.shown_t, 2)
    if room.mode == REPLAYING:
        return _("**Replaying t = {t} s of {live} s ({scale}×)**").format(t=t, live=t_live,
                                                                          scale=tr.general(room.time_scale))
    return _("**Showing t = {t} s of {live} s** (paused): {replay}, {resume} or {branch}.").format(
        t=t, live=t_live, replay=_(REPLAY_LABEL), resume=_(RESUME_LABEL), branch=_(BRANCH_LABEL))


class Timeline:
    """The slider, the three buttons and the status line (see the module docstring)."""

    def __init__(self, gui: Any, wrap: Wrap, message: MessageLine, room: Room, *, order: float | None = None,
                 clock: Clock | None = None, tr: Translator = ENGLISH) -> None:
        self.room = room
        self._message = message
        self.tr = tr
        _ = tr.gettext
        replay, resume, branch = _(REPLAY_LABEL), _(RESUME_LABEL), _(BRANCH_LABEL)

        def stale_now() -> Any:
            """A test of the message just shown: the stretch it quotes has moved on."""
            then = room.stretch()
            return lambda: stretch_moved(then, room.stretch())
        orders = [None] * 3 if order is None else [order + 0.1 * k for k in (1, 2, 3)]
        self.gui_slider = gui.add_slider(_(TIMELINE_LABEL), 0.0, TIMELINE_STEP, TIMELINE_STEP, 0.0, disabled=True,
                                         order=orders[0],
                                         hint=_("scrub back through the last minute of motion (pauses it)"))
        self.gui_buttons = gui.add_button_group(_("Past"), (replay, resume, branch), order=orders[1])
        self.gui_status = gui.add_markdown("", order=orders[2])
        self.quiet = Quiet()
        self._range = (0.0, TIMELINE_STEP)
        self._follow = Throttle(FOLLOW_PERIOD)
        self._follow_live = Throttle(LIVE_FOLLOW_PERIOD)
        self._owed = False  # the slider's last quiet write was skipped (its user was editing): done later

        def scrub(value: float) -> None:
            stretch = room.stretch()
            if stretch is not None:  # a value on the slider's rounded ends is the stretch's end
                lo, hi = stretch
                if lo - TIMELINE_STEP <= value <= hi + TIMELINE_STEP:
                    value = min(max(value, lo), hi)
            try:
                room.scrub(value)
            except ValueError as error:
                raise Refused(TIMELINE_REFUSALS.in_language(str(error), tr), stale_now(),
                              lambda: self._refusal_now(value)) from None
            message.clear()

        def check(value: Any) -> float:
            try:
                number = float(value)
            except (TypeError, ValueError):
                number = math.nan
            if not math.isfinite(number):
                raise Refused(_("Time {value} refused: not a number of seconds.").format(value=repr(value)))
            return number

        self.binding: Binding = bind(self.gui_slider, where="timeline", wrap=wrap, message=message, quiet=self.quiet,
                                     apply=scrub, current=lambda: self._shown_value(), check=check, clock=clock,
                                     gui=gui)

        def clicked(event: Any) -> None:
            choice = str(event.target.value)
            if choice in (replay, resume, branch):
                self.binding.release()  # a button pressed: the hand has left the slider
            try:
                if choice == replay:
                    room.replay()
                elif choice == resume:
                    room.resume()
                elif choice == branch:
                    room.branch()
                else:  # a client can send any string
                    return
            except ValueError as error:  # the room's English words, said in the browser's language
                message.show(functools.partial(TIMELINE_REFUSALS.in_language, str(error)), stale_now())
                return
            message.clear()
            self.binding.taken()  # the Timeline moved on: the refusal under its slider goes

        self.gui_buttons.on_click(wrap("timeline buttons", clicked))

    @property
    def handles(self) -> list[Any]:
        """All GUI handles, for removal (the refusal note under the slider goes with its binding)."""
        return [self.gui_slider, self.gui_buttons, self.gui_status]

    def _refusal_now(self, t: float) -> str | None:
        """The refusal of the time t [s] in the words that hold now (the stretch as recorded now);
        None once the stretch holds t, or once a new run dropped the stretch it was refused from."""
        history, stretch = self.room.history, self.room.stretch()
        if history is None or stretch is None or stretch[0] - TIMELINE_STEP <= t <= stretch[1] + TIMELINE_STEP:
            return None
        return TIMELINE_REFUSALS.in_language(str(history.outside_message(t)), self.tr)

    def _shown_value(self) -> float:
        lo, hi = self._range
        return min(max(round(self.room.shown_t / TIMELINE_STEP) * TIMELINE_STEP, lo), hi)

    def frame(self, dt: float) -> None:
        """Per frame: follow the room while it moves, at LIVE_FOLLOW_PERIOD live, at FOLLOW_PERIOD
        replaying; a write the user's editing held back (`Binding.editing`) is done once they
        stopped, even when the room stands still."""
        if self._owed and not self.quiet.editing(self.gui_slider):
            self.refresh()
            return
        if not self.room.playing:
            return
        throttle = self._follow_live if self.room.mode == LIVE else self._follow
        if throttle.ready(dt):
            self.refresh()

    def refresh(self) -> None:
        """Show the room's replay state now."""
        room = self.room
        stretch = room.stretch()
        slider = self.gui_slider
        if stretch is None:
            lo, hi = 0.0, TIMELINE_STEP
        else:
            lo = math.floor(stretch[0] / TIMELINE_STEP + 1e-9) * TIMELINE_STEP
            hi = max(lo + TIMELINE_STEP, math.ceil(stretch[1] / TIMELINE_STEP - 1e-9) * TIMELINE_STEP)
        lo, hi = round(lo, 6), round(hi, 6)
        disabled = stretch is None or stretch[1] - stretch[0] <= 0.0
        if (lo, hi) != self._range:
            if not self.quiet.editing(slider):
                slider.max = hi
                slider.min = lo
                self._range = (lo, hi)
        if slider.disabled != disabled:
            slider.disabled = disabled
        value = round(self._shown_value(), 6)
        self.quiet.write(slider, value)
        self._owed = (lo, hi) != self._range or slider.value != value  # skipped while its user edits
        text = timeline_text(room, self.tr)
        if self.gui_status.content != text:
            self.gui_status.content = text
        self._message.recheck()
        self.binding.restate()
