"""One `Session` per connected browser: its own GUI, scene nodes and (later) simulation.

Everything a session draws goes through `client.gui` / `client.scene`, so two browsers never
share sliders or bodies.  Every callback a session registers is wrapped by `Session.guard`:
an exception is logged and shown in that client's GUI, and never reaches viser's threads or
the app loop.  All callbacks and ticks of one session run under `Session.lock` (viser runs
sync callbacks on a 32-thread pool, and the 60 Hz loop runs in its own thread).
"""

from __future__ import annotations

import functools
import logging
import threading
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

import viser

from app.explorer import ExplorerScene

__all__ = ["Guard", "LectureScene", "Session"]

logger = logging.getLogger(__name__)

R = TypeVar("R")
Guard = Callable[[str, Callable[..., Any]], Callable[..., Any]]


class LectureScene(Protocol):
    """What a session needs from a scene (Euler angles now; free body, heavy top next)."""

    title: str

    def tick(self, dt: float) -> None:
        """Advance by dt [s] of wall time (called at ~60 Hz from the app loop)."""

    def remove(self) -> None:
        """Remove the scene's GUI elements and scene nodes from the client."""


class Session:
    """The state of one browser tab: built on connect, dropped on disconnect.

    Attributes:
        client: the viser client this session draws to.
        scene: the active lecture scene (today always the `ExplorerScene`).
        lock: serialises this session's callbacks and ticks (re-entrant, since assigning a
            handle's value on the server runs its callbacks synchronously).
        last_error: the last error message shown in the GUI, or None.
    """

    def __init__(self, client: viser.ClientHandle) -> None:
        self.client = client
        self.client_id: int = client.client_id
        self.lock = threading.RLock()
        self.closed = False
        self.last_error: str | None = None
        self.error_count = 0
        gui = client.gui
        # Created first, so it sits at the top of the panel where it is seen.
        self.gui_error = gui.add_markdown("", visible=False)
        self.gui_error_dismiss = gui.add_button("Dismiss message", color="red", visible=False)
        self.gui_error_dismiss.on_click(self.guard("dismiss", lambda _event: self.clear_error()))
        with self.lock:
            self.scene: LectureScene = ExplorerScene(client, self.guard)

    def guard(self, where: str, fn: Callable[..., R]) -> Callable[..., R | None]:
        """`fn` wrapped so that it runs under `lock` and an exception is logged and shown.

        where: a short name for the message ("θ slider", "tick", ...).
        """

        @functools.wraps(fn)
        def guarded(*args: Any, **kwargs: Any) -> R | None:
            with self.lock:
                try:
                    return fn(*args, **kwargs)
                except Exception as error:  # noqa: BLE001 - this is the safety net
                    self.report_error(where, error)
                    return None

        return guarded

    def report_error(self, where: str, error: BaseException) -> None:
        """Log `error` (with traceback, once per distinct message) and show it in the GUI."""
        message = f"{where}: {type(error).__name__}: {error}"
        self.error_count += 1
        if message == self.last_error:
            return  # a tick failing at 60 Hz: log and notify once, not 60 times a second
        self.last_error = message
        logger.error("client %d: error in %s", self.client_id, where, exc_info=error)
        try:
            self.gui_error.content = (
                f"**⚠ Something went wrong** (the app keeps running)\n\n`{message}`"
            )
            self.gui_error.visible = True
            self.gui_error_dismiss.visible = True
            self.client.add_notification(
                "Error", message, color="red", auto_close_seconds=10.0, with_close_button=True
            )
        except Exception:  # noqa: BLE001 - e.g. the client has just disconnected
            logger.exception("client %d: could not show the error message", self.client_id)

    def clear_error(self) -> None:
        """Hide the error message."""
        self.last_error = None
        self.gui_error.visible = False
        self.gui_error_dismiss.visible = False

    def tick(self, dt: float) -> None:
        """Advance the active scene by dt [s]; errors are reported, never raised."""
        if self.closed:
            return
        self.guard("tick", self.scene.tick)(dt)

    def close(self) -> None:
        """Mark the session closed (its client is gone; viser drops the client's nodes)."""
        with self.lock:
            self.closed = True
