"""A control bound to a simulation value in one call: every value the page sends is complete.

What the browser does (measured with viser 1.1.1 in Chromium, docs in VISER.md §8): a slider's
number box, an `add_number` and an `add_vector3` field are controlled React inputs, re-rendered
from the number they last sent.  Without help they send one update per keystroke (throttled to
one per 50 ms) and wreck what is typed on the way: `-0.8` arrives as 0, then 0.8 (the box
re-renders "-0" as "0"); `1e-3` as 1, -1, -13 (the "e" is dropped) and then -10 (clamped on
blur); `1e9` as 1, then 19, then the slider's maximum.  A slider's thumb sends a value every
50 ms or so while it moves; each of those is a complete value.

The two sides split the work where each thing is known:

* **In the browser**, `TYPING_GUARD_JS` (installed once per page by `install_typing_guard`)
  keeps keystrokes in a number box away from React until the text is complete: Enter, leaving
  the field, or TYPED_PAUSE_MS without a key while the text is a number.  Then the number
  (`Number(text)`, so `1e-3` and `-0.8` are understood) is handed to the box as plain decimals
  in one input event, and the box sends it once.  Text that is not a number goes back to the
  value in force; keys that cannot be part of a number are not typed at all; Escape undoes the
  edit.  While its user types, or has selected its text to type over it, nothing the server
  sends is written into that box (it is shown after the commit, or when the box loses focus):
  a slider following the motion would otherwise replace the selection, and the keys typed next
  would be appended to the new value ("5.03" + "999" taken as 5.03999 s).  Nor does the box's
  own script move the caret meanwhile: it puts the caret back on a zero-delay timer after each
  value it renders, and on a busy page that timer can fire after a Ctrl+A.  The slider's
  clamp-on-blur is skipped: an out-of-range value reaches the server, which says why it is
  refused.  Thumb drags, arrow keys on a thumb and the number boxes' step buttons are not
  touched: they send complete values.
* **On the server**, `bind(...)` gives a handle one callback (instead of a hand-written one per
  control): every update is applied when it arrives, so the next frame draws it.  A value is
  parsed and checked (`check`: a `SliderSpec`'s range, or a function that raises `Refused`),
  then `apply(value)` (a value equal to the one in force is not applied again, but it clears the
  message line: the edit ended on a valid value); a refusal (not a number, NaN, out of range, or
  `apply` returning/raising one) is said where the hand is, in the control's `ControlNote` right
  under it (a view's controls have one: `bind(..., gui=)`; the message line at the top of the
  panel holds it as the view's message but stays hidden, so the page says it once), or in the
  message line for a control without a note, and the field goes back to `current()`, the value in force, at once.  The
  note goes when the control takes a value (one applied, or the one in force sent again); a
  refusal whose words change as time passes (the Timeline's recorded stretch grows while it
  plays) says them anew at `Binding.restate()` (`Refused.restate`), so it holds the same while
  the motion plays or stands.  For HANDS_OFF_S after a browser's last update, the server's
  quiet writes (a slider following the motion) skip the field, so a thumb under the hand is not
  pulled back.  What is decided is the value as the browser sent it (taken as it arrives,
  `app.viser_internals.on_browser_value`), not the handle's value when the callback runs: a frame
  drawn in between writes the handle.

A page without the guard (a raw websocket client) gets each value it sends checked and applied
in its own room like any other: nothing it sends skips the check.  The time is a `Clock`
(`time.monotonic` by default); tests pass a `ManualClock`.
"""

from __future__ import annotations

import html
import math
import time
from collections import deque
from collections.abc import Callable
from typing import Any, Protocol

from app.kit.core.common import SliderSpec
from app.viser_internals import add_beside, on_browser_value

__all__ = [
    "BOX_DIGITS",
    "HANDS_OFF_S",
    "TYPED_PAUSE_MS",
    "TYPING_GUARD_JS",
    "Binding",
    "Clock",
    "ControlNote",
    "ManualClock",
    "MonotonicClock",
    "Refused",
    "bind",
    "install_typing_guard",
    "spec_check",
]

HANDS_OFF_S = 0.4
"""[s] after a browser's last update to a field, the server's quiet writes leave the field alone
(a slider's thumb sends every 50 ms while it moves; a slow hand pauses longer between values)."""
TYPED_PAUSE_MS = 1500
"""[ms] in the browser: a number typed into a box is committed after this long without a key."""
BOX_DIGITS = 3
"""Decimals a bound slider's number box accepts at least (viser derives 0 from a step of 1,
which would cut a typed -0.8 to -0)."""


class Refused(ValueError):
    """A value that is not applied; the message says why (at the control and in the message line).

    stale: optional; true once the message no longer holds (`MessageLine.show`).
    restate: optional; the refusal's words as they hold now (None: it no longer holds), which the
    control's note says at each `Binding.restate()` (the Timeline's stretch, growing as it plays)."""

    def __init__(self, message: str, stale: Callable[[], bool] | None = None,
                 restate: Callable[[], str | None] | None = None) -> None:
        super().__init__(message)
        self.stale = stale
        self.restate = restate


class ControlNote:
    """A refusal said where the hand is: a Markdown line right under its control (in the control's
    folder, `app.viser_internals.add_beside`), hidden while there is nothing to say."""

    def __init__(self, gui: Any, control: Any) -> None:
        self.handle = add_beside(gui, control, lambda order: gui.add_markdown("", visible=False, order=order))
        self._removed = False

    @property
    def text(self) -> str:
        """What the note says now ("" while hidden)."""
        return str(self.handle.content) if self.handle.visible else ""

    def show(self, text: str) -> None:
        content = f"**⚠ {text}**"
        if self.handle.content != content:
            self.handle.content = content
        if not self.handle.visible:
            self.handle.visible = True

    def clear(self) -> None:
        if self.handle.visible:
            self.handle.visible = False
        if self.handle.content:
            self.handle.content = ""

    def remove(self) -> None:
        """Take the note off the panel (once)."""
        if not self._removed:
            self._removed = True
            self.handle.remove()


class Clock(Protocol):
    """The time the bindings read."""

    def now(self) -> float:
        """[s] monotonic."""
        ...


class MonotonicClock:
    """time.monotonic (the running app)."""

    def now(self) -> float:
        return time.monotonic()


class ManualClock:
    """A clock the test moves by hand with `advance(dt)` [s]."""

    def __init__(self) -> None:
        self.t = 0.0

    def now(self) -> float:
        return self.t

    def advance(self, dt: float) -> None:
        self.t += dt


DEFAULT_CLOCK: Clock = MonotonicClock()


def spec_check(spec: SliderSpec) -> Callable[[Any], float]:
    """The check of a slider: a finite float within [spec.lo, spec.hi], else Refused (spec.refusal)."""

    def check(value: Any) -> float:
        number = spec.check(value)
        if number is None:
            raise Refused(spec.refusal(value))
        return number

    return check


def _same(a: Any, b: Any) -> bool:
    try:
        return bool(a == b)
    except ValueError:  # arrays
        return False


class Binding:
    """One control bound to a simulation value (see the module docstring; made by `bind`)."""

    def __init__(self, handle: Any, *, where: str, wrap: Callable[[str, Callable[..., Any]], Callable[..., Any]],
                 message: Any, quiet: Any, apply: Callable[[Any], str | None], current: Callable[[], Any],
                 check: Callable[[Any], Any], clock: Clock, note: ControlNote | None = None) -> None:
        self.handle = handle
        self.where = where
        self.note = note
        """The refusal said under the control (None: only in the message line)."""
        self._restate: Callable[[], str | None] | None = None
        self._said = ""  # the refusal last said (in the message line, and under the control)
        self._said_stale: Callable[[], bool] | None = None
        self._message = message
        self._quiet = quiet
        self._apply = apply
        self._current = current
        self._check = check
        self.clock = clock
        self.applied = 0  # values applied (tests count them)
        self.refused = 0
        self._last_update = -math.inf  # [s] clock time of the last browser update
        self._active = True
        self._arrived: deque[Any] = deque()  # values browsers sent, oldest first, not yet decided
        on_browser_value(handle, self._arrived.append)
        quiet.guard(handle, self.editing)
        handle.on_update(wrap(where, self._received))

    def editing(self) -> bool:
        """True for HANDS_OFF_S after a browser's last update: the server's quiet writes skip the
        field then."""
        return self.clock.now() - self._last_update < HANDS_OFF_S

    def release(self) -> None:
        """The user's edit is over (they pressed a button elsewhere): the server's quiet writes
        reach the field again at once, not HANDS_OFF_S after its last update."""
        self._last_update = -math.inf

    @property
    def active(self) -> bool:
        """Not closed: updates are applied."""
        return self._active

    def close(self) -> None:
        """The view goes away: updates are no longer applied; the note leaves the panel."""
        self._active = False
        self._restate = None
        if self.note is not None:
            self.note.remove()

    @property
    def refusal(self) -> str:
        """The refusal said under the control now ("" if none, or no note)."""
        return self.note.text if self.note is not None else ""

    def taken(self) -> None:
        """The control took a value: its refusal goes."""
        self._restate = None
        if self.note is not None:
            self.note.clear()

    def restate(self) -> None:
        """Say the control's refusal anew in the words that hold now (`Refused.restate`), or let it
        go if it no longer holds."""
        if self._restate is None or self.note is None:
            return
        text = self._restate()
        if text is None:
            self.taken()
            return
        self.note.show(text)
        said, self._said = self._said, text
        if said and text != said and said in self._message.text:  # the message line says it still: the same words
            self._say(text, self._said_stale)

    def _received(self, event: Any) -> None:
        if self._quiet.active or not self._active:
            return  # the server itself is showing a value on the control
        if getattr(event, "client", None) is None:
            self.decide(self.handle.value)
            return
        self._last_update = self.clock.now()
        self._quiet.forget(self.handle)  # a value the server skipped meanwhile is older than this one
        # The value as it arrived: a server write between its arrival and this callback (the loop
        # following the motion, under the session's lock this callback waits for) replaced the
        # handle's, and deciding on that would drop what the browser sent without a word.
        sent = self._arrived.popleft() if self._arrived else self.handle.value
        self.decide(sent)
        if not _same(self.handle.value, sent):  # written meanwhile: the field shows the value in force
            self.revert()

    def decide(self, value: Any) -> None:
        """Check and apply `value`; a refusal is said and the field goes back to the value in force."""
        stale = restate = None
        try:
            parsed = self._check(value)
            self._message.clear()
            if _same(parsed, self._current()):
                self.taken()
                return  # the value in force, sent again (a typed edit that ended without a number)
            refusal = self._apply(parsed)
        except Refused as error:
            refusal, stale, restate = str(error), error.stale, error.restate
        if refusal is not None:
            self.refuse(refusal, stale, restate)
            return
        self.applied += 1
        self.taken()

    def refuse(self, text: str, stale: Callable[[], bool] | None = None,
               restate: Callable[[], str | None] | None = None) -> None:
        """Say `text` under the control (in the words of `restate()` at each `restate`, if given)
        and in the message line (until `stale()`, if given), and put the field back to the value
        in force."""
        self.refused += 1
        self._say(text, stale)
        self._said, self._said_stale = text, stale
        if self.note is not None:
            self._restate = restate
            self.note.show(text)
        self.revert()

    def _say(self, text: str, stale: Callable[[], bool] | None) -> None:
        """`text` as the view's message (until `stale()`, if given): said under the control when it
        has a note, else in the message line."""
        self._message.show(text, stale, here=self.note is None)

    def revert(self) -> None:
        """The field shows the value in force again (written even while a user edits it)."""
        current = self._current()
        if not _same(self.handle.value, current):
            self._quiet.write(self.handle, current, force=True)


def bind(handle: Any, *, where: str, wrap: Callable[[str, Callable[..., Any]], Callable[..., Any]], message: Any,
         quiet: Any, apply: Callable[[Any], str | None], current: Callable[[], Any],
         spec: SliderSpec | None = None, check: Callable[[Any], Any] | None = None,
         clock: Clock | None = None, gui: Any = None) -> Binding:
    """Bind `handle` to a simulation value (see the module docstring).

    Args:
        where: the name errors are reported under ("θ slider").
        wrap: the session's guard; message: the view's `MessageLine`; quiet: the view's `Quiet`.
        apply: called with the checked value; returns a refusal text (or raises Refused) or None.
        current: the value in force, shown again after a refusal.
        spec: the slider's range (its refusal text), or `check`: value -> parsed, or Refused.
        clock: the time (tests pass a ManualClock).
        gui: the panel `handle` is in (a `client.gui`): its refusals are said right under it too
            (a `ControlNote`); None: in the message line only.
    """
    if check is None:
        if spec is None:
            raise TypeError("bind needs a spec or a check")
        check = spec_check(spec)
    precision = getattr(handle, "precision", None)
    if isinstance(precision, int) and precision < BOX_DIGITS:
        handle.precision = BOX_DIGITS  # the box accepts typed decimals (-0.8 on a step-1 slider)
    note = ControlNote(gui, handle) if gui is not None else None
    return Binding(handle, where=where, wrap=wrap, message=message, quiet=quiet, apply=apply, current=current,
                   check=check, clock=clock or DEFAULT_CLOCK, note=note)


# ---------------------------------------------------------------------------- the browser side
TYPING_GUARD_JS = """
(() => {
  if (window.__typedNumbers) return;
  window.__typedNumbers = true;
  const SELECTOR = "input.mantine-NumberInput-input";
  const PAUSE_MS = @PAUSE_MS@;
  const ALLOWED = /^[0-9.eE+\\-]$/;
  const proto = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value");
  const states = new WeakMap();
  let committing = false;
  const box = (e) => {
    const el = e.target;
    return el instanceof HTMLInputElement && el.matches(SELECTOR) ? el : null;
  };
  function stateOf(el) {
    let s = states.get(el);
    if (s) return s;
    const own = Object.getOwnPropertyDescriptor(el, "value") || proto;
    s = { dirty: false, wanted: null, shown: "", timer: 0, own };
    states.set(el, s);
    Object.defineProperty(el, "value", {
      configurable: true,
      enumerable: own.enumerable,
      get() { return own.get.call(el); },
      set(v) { if (s.dirty || (!committing && selecting(el))) { s.wanted = v; } else { own.set.call(el, v); } },
    });
    const setRange = el.setSelectionRange;  // the box's script moving the caret (a timer after a re-render)
    el.setSelectionRange = function (...args) {
      if (committing || !(s.dirty || selecting(el))) return setRange.apply(el, args);
    };
    return s;
  }
  function selecting(el) {  // its user has selected text in it to type over
    return document.activeElement === el && el.selectionStart !== el.selectionEnd;
  }
  function begin(el) {
    const s = stateOf(el);
    if (!s.dirty) { s.shown = proto.get.call(el); s.dirty = true; }  // a value held while selected stays wanted
    return s;
  }
  function flush(el, s) {  // a value held while its text was selected, shown once the edit is over
    if (!s.dirty && s.wanted !== null) { const v = s.wanted; s.wanted = null; s.own.set.call(el, v); }
  }
  function revert(el, s) {
    s.dirty = false;
    clearTimeout(s.timer);
    proto.set.call(el, s.wanted !== null ? String(s.wanted) : s.shown);
    s.wanted = null;
  }
  function send(el, rendered, text) {
    committing = true;
    try {
      states.get(el).own.set.call(el, rendered);  // the box as React last rendered it, all selected ...
      try { el.setSelectionRange(0, rendered.length); } catch (_) {}
      el.dispatchEvent(new KeyboardEvent("keydown", { key: "Unidentified", bubbles: true }));
      proto.set.call(el, text);  // ... and replaced by the number: one change, sent once
      try { el.setSelectionRange(text.length, text.length); } catch (_) {}
      el.dispatchEvent(new Event("input", { bubbles: true }));
    } finally { committing = false; }
  }
  function commit(el) {
    const s = states.get(el);
    if (!s || !s.dirty) return;
    clearTimeout(s.timer);
    const text = proto.get.call(el).trim();
    const x = text === "" ? NaN : Number(text);
    if (!Number.isFinite(x)) { revert(el, s); return; }
    const rendered = s.wanted !== null ? String(s.wanted) : s.shown;
    s.dirty = false;
    s.wanted = null;
    send(el, rendered, x.toLocaleString("en-US", { useGrouping: false, maximumFractionDigits: 20 }));
  }
  window.addEventListener("keydown", (e) => {
    const el = box(e);
    if (!el || committing) return;
    const s = states.get(el);
    const dirty = s !== undefined && s.dirty;
    if (e.key === "Enter") { if (dirty) { e.preventDefault(); e.stopImmediatePropagation(); commit(el); } return; }
    if (e.key === "Escape") { if (dirty) { e.stopImmediatePropagation(); revert(el, s); } return; }
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key.length === 1) {
      e.stopImmediatePropagation();
      if (!ALLOWED.test(e.key)) { e.preventDefault(); return; }
      begin(el);
    } else if (e.key === "Backspace" || e.key === "Delete") {
      e.stopImmediatePropagation();
      begin(el);
    } else if (dirty && (e.key === "ArrowUp" || e.key === "ArrowDown")) {
      e.stopImmediatePropagation();
    }
  }, true);
  window.addEventListener("beforeinput", (e) => {
    const el = box(e);
    if (el && !committing && e.inputType !== "insertLineBreak") begin(el);
  }, true);
  window.addEventListener("input", (e) => {
    const el = box(e);
    if (!el || committing) return;
    const s = begin(el);
    e.stopImmediatePropagation();
    clearTimeout(s.timer);
    s.timer = setTimeout(() => {
      const t = proto.get.call(el).trim();
      if (t !== "" && Number.isFinite(Number(t))) commit(el);
    }, PAUSE_MS);
  }, true);
  window.addEventListener("change", (e) => { if (box(e)) e.stopImmediatePropagation(); }, true);
  window.addEventListener("focusin", (e) => { const el = box(e); if (el) stateOf(el); }, true);
  window.addEventListener("focusout", (e) => {
    const el = box(e);
    if (!el) return;
    commit(el);
    flush(el, states.get(el));
    e.stopImmediatePropagation();
  }, true);
})();
""".replace("@PAUSE_MS@", str(TYPED_PAUSE_MS))
"""The browser half (see the module docstring).  Listeners in the capture phase on `window` run
before React's (on the root), so a keystroke stopped there never reaches the controlled input;
the box's own `value` property is wrapped so that what React writes while its user types is
kept aside and shown when the edit ends."""


def install_typing_guard(gui: Any) -> Any:
    """Add TYPING_GUARD_JS to a client's page (idempotent in the page); returns the GUI handle.

    viser's HTML element sets innerHTML, where a <script> never runs but an image's onerror does:
    the script rides on an image that cannot load (`data:,`)."""
    code = html.escape(TYPING_GUARD_JS, quote=True)
    return gui.add_html(f'<img src="data:," alt="" style="display:none" onerror="{code}">')
