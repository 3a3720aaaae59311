"""A session's guard (`Guard`) and its error display (`ErrorLine`).

Every callback a session registers, and every public action, runs in the session's guard: under
the session's lock and the lock of the room it shows; an exception it catches is logged and shown
in the error line at the top of the browser's panel, never raised into viser's threads or the
app loop.
"""

from __future__ import annotations

import contextlib
import functools
import logging
import threading
from collections.abc import Callable
from typing import Any, TypeVar

import viser

from app.i18n import N_, Phrases, Translator, for_gui, refusal_text
from app.kit.core.room import Room
from app.kit.panel.gui import writing_quietly
from physics.refusal import Refusal

__all__ = ["LOAD_PHRASES", "ErrorLine", "Guard"]

R = TypeVar("R")

logger = logging.getLogger("app.session")

LOAD_PHRASES = Phrases(
    (r"\*\*Server busy: (?P<fps>\d+) frames a second\*\* \(of (?P<hz>\d+)\): the motion is computed as always, "
     r"shown less often\.",
     N_("**Server busy: {fps} frames a second** (of {hz}): the motion is computed as always, shown less often.")))
"""The app loop's load note (`app.main.load_note`, English) and its msgid."""


class ErrorLine:
    """A browser's error display: the message and `Dismiss message` (created first, so they sit
    at the top of the panel where they are seen), and the "Server busy" note (last in the panel,
    so that it never moves a slider under the hand).  Owned by the session for its life.

    Args:
        client: the browser.  guard: the session's guard (`Dismiss message` runs in it).
        last_order: the load note's place (viser's `order`, after anything a panel adds).

    Attributes:
        last_error: the message shown, or None (none yet, or dismissed).
        error_count: errors reported so far (a message repeated at once counts, shown once).
        gui_error, gui_error_dismiss, gui_load: the widgets.
    """

    def __init__(self, client: viser.ClientHandle, guard: Callable[[str, Callable[..., Any]], Callable[..., Any]],
                 *, last_order: float) -> None:
        gui = client.gui
        self.client = client
        self.tr: Translator = for_gui(gui)
        self.last_error: str | None = None
        self._refusal: Refusal | None = None  # the error shown, when it is a refusal
        self.error_count = 0
        self.load_note = ""  # the load note in English, as the app loop wrote it
        self.gui_error = gui.add_markdown("", visible=False)
        self.gui_error_dismiss = gui.add_button(self.tr.gettext("Dismiss message"), color="red", visible=False)
        self.gui_error_dismiss.on_click(guard("dismiss", lambda _event: self.clear()))
        self.gui_load = gui.add_markdown("", visible=False, order=last_order)

    @property
    def order(self) -> float:
        """The place right under the error line (the live bar and a narrow explorer's line go there)."""
        return float(self.gui_error_dismiss.order)

    def report(self, where: str, error: BaseException) -> None:
        """Log `error` (with traceback, once per distinct message) and show it in the GUI: a
        refusal of what was typed or sent (`physics.refusal.Refusal`) in the browser's words,
        any other error as `where: Type: message`."""
        self.error_count += 1
        message = f"{where}: {type(error).__name__}: {error}"
        if message == self.last_error:
            return  # a frame failing at 60 Hz: log and notify once, not 60 times a second
        self.last_error = message
        self._refusal = error if isinstance(error, Refusal) else None
        logger.error("client %d: error in %s", self.client.client_id, where, exc_info=error)
        try:
            self._write_error()
            self.gui_error.visible = True
            self.gui_error_dismiss.visible = True
            shown = message if self._refusal is None else self._refused_words(self._refusal)
            self.client.add_notification(self.tr.gettext("Error"), shown, color="red", auto_close_seconds=10.0,
                                         with_close_button=True)
        except Exception:  # noqa: BLE001 - e.g. the client has just disconnected
            logger.exception("client %d: could not show the error message", self.client.client_id)

    def _refused_words(self, refusal: Refusal) -> str:
        """`refusal` in this browser's language, its fields too where they are words of the panel
        (a form's label: "Right option")."""
        return refusal_text(refusal, self.tr, {name: self.tr.gettext(value) if value else value
                                              for name, value in refusal.fields.items()})

    def _write_error(self) -> None:
        """The error line's words in this browser's language: a refusal's own words under "Not
        accepted", another error's text as raised under "Something went wrong"."""
        if self.last_error is None:
            self.gui_error.content = ""
        elif self._refusal is not None:
            headline = self.tr.gettext("**⚠ Not accepted**")
            self.gui_error.content = f"{headline}\n\n{self._refused_words(self._refusal)}"
        else:
            headline = self.tr.gettext("**⚠ Something went wrong** (the app keeps running)")
            self.gui_error.content = f"{headline}\n\n`{self.last_error}`"

    def show_load(self, note: str) -> None:
        """Say (or stop saying) that the server cannot keep its frame rate: `note` as the app loop
        writes it (English, `LOAD_PHRASES`; "" stops), shown in this browser's language."""
        self.load_note = note
        try:
            self.gui_load.content = LOAD_PHRASES.in_language(note, self.tr)
            self.gui_load.visible = bool(note)
        except Exception:  # noqa: BLE001 - the client has just gone
            logger.debug("load note not shown", exc_info=True)

    def relabel(self, tr: Translator) -> None:
        """Write the error line, its button and the load note in `tr`'s language."""
        self.tr = tr
        self.gui_error_dismiss.label = tr.gettext("Dismiss message")
        self._write_error()
        self.show_load(self.load_note)

    def clear(self) -> None:
        """Hide the error message."""
        self.last_error = None
        self.gui_error.visible = False
        self.gui_error_dismiss.visible = False


class Guard:
    """Wraps a session's callbacks and actions (`wrap`); owned by the session for its life.

    Args:
        busy: the session's lock, held for the whole of a wrapped call.
        switch_lock: held by a switch of what the browser shows (`Showing.switch_lock`): the
            room shown is read under it.
        room: the room shown now.  report: shows an exception (`ErrorLine.report`).
    """

    def __init__(self, busy: threading.RLock, switch_lock: threading.RLock, room: Callable[[], Room],
                 report: Callable[[str, BaseException], None]) -> None:
        self._busy = busy
        self._switch_lock = switch_lock
        self._room = room
        self._report = report

    def wrap(self, where: str, fn: Callable[..., R]) -> Callable[..., R | None]:
        """`fn` wrapped so that it runs under the session's lock and the room's, and an exception
        is logged and shown, never raised.

        where: a short name for the message ("θ slider", "tick", ...).
        """

        @functools.wraps(fn)
        def guarded(*args: Any, **kwargs: Any) -> R | None:
            with contextlib.ExitStack() as locks:
                if not writing_quietly():
                    # (A callback echoing the server's own quiet write runs under its writer's
                    # locks: the app loop draws under the room's, and taking this session's lock
                    # after it would deadlock with a callback that holds it and waits for the room.)
                    locks.enter_context(self._busy)
                    with self._switch_lock:
                        room = self._room()
                    locks.enter_context(room.lock)
                try:
                    return fn(*args, **kwargs)
                except Exception as error:  # noqa: BLE001 - this is the safety net
                    self._report(where, error)
                    return None

        return guarded
