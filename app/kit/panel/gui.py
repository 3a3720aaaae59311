"""Panel pieces every scene shares, written once: the message line, the transport (play /
pause / step / reset / time scale / integrator / status), the presets row, the panel tabs
(Setup / Readout / Plots), a readout that sends only when it changed, and sliders that refuse
what is out of range.

Each piece builds its handles in the current GUI container and reports user actions through
callbacks that the view wraps with the session's guard.  Values a browser sends are checked
here (viser does not: a [0, 10] slider accepts 1e6 or NaN from a hand-written client): a
refused value goes back to the last valid one and the message line says why.

The tabs are a row of buttons over three folders rather than viser's tab group, because the
server is told which one is shown: a closed tab's readouts and plots are neither computed nor
sent (`Tabs.shown`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

import viser

from app.i18n import N_, Said, Translator, Words, for_gui, translator, written
from app.kit.core.common import SliderSpec, Wrap, checked_value
from app.kit.core.presets import Preset
from app.kit.panel.binding import Clock, Refused, bind

__all__ = [
    "LOOKING_BACK_STATUS",
    "PAUSE_LABEL",
    "PLAY_LABEL",
    "RESET_LABEL",
    "STEP_LABEL",
    "TIME_SCALE_RANGE",
    "MessageLine",
    "PresetsRow",
    "Quiet",
    "Readout",
    "Tabs",
    "Transport",
    "add_slider",
    "writing_quietly",
]

TIME_SCALE_RANGE = (0.1, 4.0)
PLAY_LABEL, PAUSE_LABEL = N_("Play"), N_("Pause")
STEP_LABEL, RESET_LABEL = N_("▶| Step"), N_("⟲ Reset")  # glyphs the GUI font has (⏭ ⏸ are missing)
LOOKING_BACK_STATUS = N_("⟲ Looking back: the time shown is under the Timeline.")  # one line, as the scenes' status
ENGLISH = translator("en")

Callback = Callable[[Any], None]
"""The session's guard: (where, fn) -> fn that runs under the locks and reports exceptions."""


_writes = threading.local()  # .depth: how many `Quiet.write`s this thread is inside


def writing_quietly() -> bool:
    """True on a thread inside a `Quiet.write`: a callback running now is the server's own write
    echoed back (its writer holds the locks it needs; `app.session.Session.guard` takes none)."""
    return getattr(_writes, "depth", 0) > 0


class Quiet:
    """Writes handles' values from the server without their callbacks acting on them.

    viser runs a handle's `on_update` synchronously when the server assigns its value (with
    `event.client` None); a callback that starts with `if quiet.active: return` then ignores
    what the server itself shows (a slider following the motion), so there is no feedback loop.
    `active` is true only on the thread that writes: a browser's update handled meanwhile on
    viser's thread pool still acts.
    A bound control (`app.kit.panel.binding`) registers a guard: while it says its user is editing,
    quiet writes skip that field (unless forced: a refusal putting the value in force back); the
    last value skipped is owed to the field and written by `flush` (each frame) once its user
    has stopped, so a preset applied just after a typed value still reaches the box.
    """

    def __init__(self) -> None:
        self._writers: set[int] = set()  # the threads inside `write`
        self._guards: dict[int, Callable[[], bool]] = {}
        self._owed: dict[int, tuple[Any, Any]] = {}  # id(handle) -> (handle, the last value skipped)

    @property
    def active(self) -> bool:
        """This thread is writing through this Quiet now."""
        return threading.get_ident() in self._writers

    def guard(self, handle: Any, editing: Callable[[], bool]) -> None:
        """Skip writes to `handle` while `editing()` is true."""
        self._guards[id(handle)] = editing

    def editing(self, handle: Any) -> bool:
        guard = self._guards.get(id(handle))
        return guard is not None and guard()

    def write(self, handle: Any, value: Any, force: bool = False) -> None:
        """`handle.value = value` (only if it differs, and not while its user edits it unless
        `force`), callbacks silenced."""
        if not force and self.editing(handle):
            self._owed[id(handle)] = (handle, value)
            return
        self._owed.pop(id(handle), None)
        if handle.value == value:
            return
        thread = threading.get_ident()
        outer = thread in self._writers
        self._writers.add(thread)
        _writes.depth = getattr(_writes, "depth", 0) + 1
        try:
            handle.value = value
        finally:
            _writes.depth -= 1
            if not outer:
                self._writers.discard(thread)


    def forget(self, handle: Any) -> None:
        """Drop the value owed to `handle` (its user sent a value: what was skipped is older)."""
        self._owed.pop(id(handle), None)

    def flush(self) -> None:
        """Write the values owed to fields whose users have stopped editing them (each frame:
        nothing to do, and nothing allocated, while nothing is owed)."""
        if not self._owed:
            return
        for handle, value in list(self._owed.values()):
            if not self.editing(handle):
                self.write(handle, value)


class MessageLine:
    """A Markdown line, hidden unless there is something to say (a refusal, a stopped run).

    A message says what is true now: shown with `stale` (a function, true once the message no
    longer holds: the recorded stretch it quotes has grown), it goes at the next `recheck()`
    after that (the Timeline rechecks whenever it shows the room's state).  The same message
    shown again is one message (nothing is sent).  A message said elsewhere on the page (a
    refusal under its own control, `app.kit.panel.binding.ControlNote`) is the view's message
    (`text`) but the line stays hidden, so the page says it once.

    Languages: a message given as `Words` (a function of a translator: `app.i18n.Said`, a
    `Phrases` sentence) is written in the browser's language (`app.i18n.for_gui`) and kept, so
    that a view built again in the browser's new language says it in that language (`take_over`);
    a plain text stays as given."""

    def __init__(self, gui: Any) -> None:
        self.gui = gui
        self.handle = gui.add_markdown("", visible=False)
        self._stale: Callable[[], bool] | None = None
        self._elsewhere = ""  # the message said elsewhere on the page (the line hidden)
        self._words: Words | None = None  # the message shown here, as given

    @property
    def text(self) -> str:
        """The view's message now ("" for none), wherever the page says it."""
        return str(self.handle.content) if self.handle.visible else self._elsewhere

    def show(self, words: Words, stale: Callable[[], bool] | None = None, *, here: bool = True) -> None:
        """Say `words` (a text, or a function of the browser's translator giving it) until
        `stale()`, if given; `here=False`: it is said elsewhere on the page."""
        text = written(words, for_gui(self.gui))
        content = text if text.startswith("**") else f"**⚠ {text}**"
        self._stale = stale
        if not here:
            self._elsewhere, self._words = content, None
            self._hide()
            return
        self._elsewhere = ""
        self._words = words
        if self.handle.content != content or not self.handle.visible:
            self.handle.content = content
            self.handle.visible = True

    def take_over(self, old: MessageLine) -> None:
        """Say what `old` (the line of a view this one replaces) says here, in this line's
        browser's language; nothing if it says nothing here."""
        if old._words is not None and old.handle.visible:
            self.show(old._words, old._stale)

    def recheck(self) -> None:
        """Clear the message if it was shown with a `stale` test that now says it no longer holds."""
        if self._stale is not None and self.text and self._stale():
            self.clear()

    def clear(self) -> None:
        self._stale = None
        self._elsewhere = ""
        self._words = None
        self._hide()

    def _hide(self) -> None:
        if self.handle.visible:
            self.handle.visible = False
            self.handle.content = ""


def add_slider(gui: Any, spec: SliderSpec, value: float = 0.0) -> Any:
    """A slider for `spec` showing `value` (rounded to the step)."""
    return gui.add_slider(spec.label, spec.lo, spec.hi, spec.step, spec.rounded(value),
                          marks=spec.marks or None, hint=spec.hint or None)


class Transport:
    """Play/Pause (one toggle), Step · Reset, time scale, integrator (optional), status line,
    in the language of `tr` (`app.i18n`; English by default).

    The handles only report: `on_toggle()`, `on_step()`, `on_reset()`, `on_time_scale(x)`,
    `on_integrator(name)`.  `show(playing, time_scale, integrator)` makes them show a room's
    state (a click never changes them directly, so every view of a room shows the same).
    integrators: the menu's names (a scene's methods; no menu if empty); integrator: the one
    shown first (default: the first); integrator_hint: the menu's hint.
    """

    def __init__(self, gui: Any, wrap: Wrap, message: MessageLine, *,
                 on_toggle: Callable[[], None], on_step: Callable[[], None], on_reset: Callable[[], None],
                 on_time_scale: Callable[[float], None],
                 integrators: Sequence[str] = (), on_integrator: Callable[[str], None] | None = None,
                 integrator: str | None = None, integrator_hint: str | None = None,
                 clock: Clock | None = None, tr: Translator = ENGLISH) -> None:
        _ = tr.gettext
        self.tr = tr
        self._message = message
        self.play_label, self.pause_label = _(PLAY_LABEL), _(PAUSE_LABEL)
        step_label, reset_label = _(STEP_LABEL), _(RESET_LABEL)
        self.gui_play = gui.add_button(self.play_label, color="green", icon=viser.Icon.PLAYER_PLAY_FILLED,
                                       hint=_("start / pause the motion"))
        self.gui_step_reset = gui.add_button_group(_("Step · Reset"), (step_label, reset_label))
        lo, hi = TIME_SCALE_RANGE
        self.gui_time_scale = gui.add_slider(
            _("Time scale [×]"), lo, hi, 0.05, 1.0,
            marks=tuple((x, f"{tr.general(x)}×") for x in (0.1, 1.0, 2.0, 3.0, 4.0)),
            hint=_("simulated seconds per second of wall time (slow motion below 1)"),
        )
        self.gui_integrator = None
        first = integrator if integrator is not None else (integrators[0] if integrators else "")
        if integrators:
            self.gui_integrator = gui.add_dropdown(_("Integrator"), tuple(integrators), initial_value=first,
                                                   hint=integrator_hint)
        self.gui_status = gui.add_markdown("")
        self.looking_back: Callable[[], bool] = lambda: False
        """True while the room shows a recorded moment: the Timeline's status line says the time
        then, and this one LOOKING_BACK_STATUS instead of the scene's (one time in the panel)."""
        self._time_scale = 1.0
        self._integrator = first
        self.quiet = Quiet()

        self.gui_play.on_click(wrap("play button", lambda _event: on_toggle()))

        def step_or_reset(event: Any) -> None:
            choice = event.target.value
            if choice == step_label:
                on_step()
            elif choice == reset_label:
                on_reset()

        self.gui_step_reset.on_click(wrap("step/reset buttons", step_or_reset))

        def time_scale(value: float) -> None:
            on_time_scale(value)
            return None

        def check_time_scale(value: Any) -> float:
            number = checked_value(value, lo, hi)
            if number is None:
                raise Refused(_("Time scale {value} refused: it must be between {lo}× and {hi}×.").format(
                    value=repr(value), lo=tr.general(lo), hi=tr.general(hi)))
            return number

        self.time_scale_binding = bind(self.gui_time_scale, where="time scale", wrap=wrap, message=message,
                                       quiet=self.quiet, apply=time_scale, current=lambda: self._time_scale,
                                       check=check_time_scale, clock=clock, gui=gui)
        if self.gui_integrator is not None and on_integrator is not None:
            menu = self.gui_integrator

            def choose(_event: Any) -> None:
                if self.quiet.active:
                    return
                if menu.value not in menu.options:  # a client can send any string
                    message.show(Said(N_("Integrator {name} refused."), name=repr(menu.value)))
                    self.quiet.write(menu, self._integrator)
                    return
                on_integrator(str(menu.value))

            menu.on_update(wrap("integrator", choose))

    @property
    def handles(self) -> list[Any]:
        """All GUI handles, for removal."""
        out = [self.gui_play, self.gui_step_reset, self.gui_time_scale, self.gui_status]
        return out + ([self.gui_integrator] if self.gui_integrator is not None else [])

    def show(self, playing: bool, time_scale: float, integrator: str = "") -> None:
        """Show a room's transport state: the toggle offers Pause while playing, Play while paused."""
        label = self.pause_label if playing else self.play_label
        if self.gui_play.label != label:
            self.gui_play.label = label
            self.gui_play.icon = viser.Icon.PLAYER_PAUSE_FILLED if playing else viser.Icon.PLAYER_PLAY_FILLED
            self.gui_play.color = "orange" if playing else "green"
        self._time_scale = time_scale
        self.quiet.write(self.gui_time_scale, time_scale)
        if self.gui_integrator is not None and integrator:
            self._integrator = integrator
            self.quiet.write(self.gui_integrator, integrator)

    def set_status(self, text: str) -> None:
        if self.looking_back():
            text = self.tr.gettext(LOOKING_BACK_STATUS)
        if self.gui_status.content != text:
            self.gui_status.content = text


class PresetsRow:
    """One button row per preset group, the lecturer's own presets in a row of their own
    (`OWN_ROW`, hidden while there are none: `show_own`), and the chosen preset's note below them."""

    OWN_ROW = N_("★ Mine")

    def __init__(self, gui: Any, wrap: Wrap, presets: Sequence[Preset], on_preset: Callable[[str], None],
                 on_own: Callable[[str], None] | None = None, tr: Translator = ENGLISH) -> None:
        self._tr = tr
        groups: dict[str, list[str]] = {}
        for preset in presets:
            groups.setdefault(preset.group, []).append(preset.name)
        # A preset's button shows its name translated (the preset files' words are in the catalogs:
        # scripts/i18n_catalogs.py extracts them); a click hands on the English name, the API's.
        self.names = {tr.gettext(preset.name): preset.name for preset in presets}
        self.groups = []
        for label, names in groups.items():
            group = gui.add_button_group(tr.gettext(label), tuple(tr.gettext(name) for name in names))
            group.on_click(wrap(f"{label} presets", lambda event: on_preset(self._english(str(event.target.value)))))
            self.groups.append(group)
        self.gui_own = gui.add_button_group(
            tr.gettext(self.OWN_ROW), ("—",), visible=False,
            hint=tr.gettext("your own presets of this scene (the Mine folder keeps them)"))
        self._own: tuple[str, ...] = ()
        own_chosen = on_own or on_preset
        self.gui_own.on_click(wrap("own presets", lambda event: own_chosen(str(event.target.value))))
        self.gui_note = gui.add_markdown("")

    def show_own(self, names: Sequence[str]) -> None:
        """The lecturer's own presets of the scene (none: the row hides)."""
        names = tuple(names)
        if names == self._own:
            return
        self._own = names
        if names:
            self.gui_own.options = names
        self.gui_own.visible = bool(names)

    def _english(self, label: str) -> str:
        """The English name of the preset whose button shows `label` (itself if none does)."""
        return self.names.get(label, label)

    def show_note(self, preset: Preset | None) -> None:
        _ = self._tr.gettext
        content = f"**{_(preset.name)}.** {_(preset.note)}" if preset is not None else ""
        if self.gui_note.content != content:
            self.gui_note.content = content


class Tabs:
    """Setup / Readout / Plots: a button row over three folders, one shown at a time.

    Use `with tabs.tab("Readout"):` to fill a tab; `shown` is the tab on screen.
    """

    def __init__(self, gui: Any, wrap: Wrap, names: Sequence[str] = ("Setup", "Readout", "Plots"),
                 on_change: Callable[[str], None] | None = None, tr: Translator = ENGLISH) -> None:
        self.names = tuple(names)
        self.shown = self.names[0]
        self._tr = tr
        self.labels = {name: tr.gettext(name) for name in self.names}
        """name -> the button's text in the browser's language (the names are what code and lessons use)."""
        self._names = {label: name for name, label in self.labels.items()}
        self.gui_buttons = gui.add_button_group(tr.gettext("Show"), tuple(self.labels.values()))
        self.folders = {name: gui.add_folder(None, visible=name == self.shown) for name in self.names}
        self._on_change = on_change

        def chosen(event: Any) -> None:
            label = str(event.target.value)
            self.show(self._names.get(label, label))

        self.gui_buttons.on_click(wrap("tab buttons", chosen))

    @property
    def handles(self) -> list[Any]:
        return [self.gui_buttons, *self.folders.values()]

    def tab(self, name: str) -> Any:
        return self.folders[name]

    def show(self, name: str) -> None:
        if name not in self.folders:  # a client can send any string
            return
        if name != self.shown:
            self.folders[self.shown].visible = False
            self.folders[name].visible = True
            self.shown = name
            self.gui_buttons.label = f"{self._tr.gettext('Show')} · {self.labels[name]}"
            if self._on_change is not None:
                self._on_change(name)


class Readout:
    """A Markdown element that is sent only when its text changed."""

    def __init__(self, gui: Any, content: str = "") -> None:
        self.handle = gui.add_markdown(content)

    def set(self, content: str) -> None:
        if self.handle.content != content:
            self.handle.content = content
