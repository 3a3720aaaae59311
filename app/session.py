"""One `Session` per connected browser: its own GUI, scene nodes and simulation.

Everything a session draws goes through `client.gui` / `client.scene`, so two browsers never
share sliders or bodies.  A dropdown at the top of the panel switches between the lecture
scenes (`SCENES`); the old scene removes its GUI and nodes, the new one builds its own and
moves the camera to its view.  Every callback a session registers is wrapped by
`Session.guard`: an exception is logged and shown in that client's GUI, and never reaches
viser's threads or the app loop.  All callbacks and ticks of one session run under
`Session.lock` (viser runs sync callbacks on a 32-thread pool, and the 60 Hz loop runs in its
own thread).  The public actions (`select_scene`, `play`, `pause`, `step`, `reset`,
`apply_preset`) take the lock too, so benchmarks and tests may call them from any thread:

    session.select_scene("Free body"); session.apply_preset("Dzhanibekov"); session.play()
"""

from __future__ import annotations

import functools
import logging
import threading
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

import viser

from app.common import apply_camera
from app.explorer import ExplorerScene
from app.free_body import FreeBodyScene
from app.heavy_top import HeavyTopScene

__all__ = ["Guard", "LectureScene", "SCENES", "Session"]

logger = logging.getLogger(__name__)

R = TypeVar("R")
Guard = Callable[[str, Callable[..., Any]], Callable[..., Any]]


class LectureScene(Protocol):
    """What a session needs from a scene."""

    title: str
    playing: bool

    def tick(self, dt: float) -> None:
        """Advance by dt [s] of wall time (called at ~60 Hz from the app loop)."""

    def play(self) -> None: ...

    def pause(self) -> None: ...

    def step(self) -> None: ...

    def reset(self) -> None: ...

    def remove(self) -> None:
        """Remove the scene's GUI elements and scene nodes from the client."""


SCENES: dict[str, Callable[[viser.ClientHandle, Guard], Any]] = {
    ExplorerScene.title: ExplorerScene,
    FreeBodyScene.title: FreeBodyScene,
    HeavyTopScene.title: HeavyTopScene,
}
"""Scene title (the dropdown option) -> scene class(client, guard)."""
DEFAULT_SCENE = ExplorerScene.title


class Session:
    """The state of one browser tab: built on connect, dropped on disconnect.

    Attributes:
        client: the viser client this session draws to.
        scene: the active lecture scene (`SCENES`).
        lock: serialises this session's callbacks and ticks (re-entrant, since assigning a
            handle's value on the server runs its callbacks synchronously).
        last_error: the last error message shown in the GUI, or None.
    """

    def __init__(self, client: viser.ClientHandle, scene: str = DEFAULT_SCENE) -> None:
        self.client = client
        self.client_id: int = client.client_id
        self.lock = threading.RLock()
        self.closed = False
        self.last_error: str | None = None
        self.error_count = 0
        gui = client.gui
        # Created first, so they sit at the top of the panel where they are seen.
        self.gui_error = gui.add_markdown("", visible=False)
        self.gui_error_dismiss = gui.add_button("Dismiss message", color="red", visible=False)
        self.gui_error_dismiss.on_click(self.guard("dismiss", lambda _event: self.clear_error()))
        self.gui_scene = gui.add_dropdown("Scene", tuple(SCENES), initial_value=scene,
                                          hint="each scene models only what it needs")
        self.gui_scene.on_update(self.guard("scene dropdown", lambda _event: self._scene_chosen()))
        with self.lock:
            self.scene: Any = SCENES[scene](client, self.guard)

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

    # ------------------------------------------------------------------ scenes
    def _scene_chosen(self) -> None:
        title = self.gui_scene.value
        if title not in SCENES:  # a client can send any string
            self.gui_scene.value = self.scene.title
            return
        if title == self.scene.title:
            return
        old = self.scene
        old.remove()
        self.scene = SCENES[title](self.client, self.guard)  # builds its GUI, sets its camera
        apply_camera(self.client, self.scene.view)

    def select_scene(self, title: str) -> None:
        """Switch to the scene `title` (a key of SCENES), as the dropdown does."""
        if title not in SCENES:
            raise ValueError(f"unknown scene {title!r}; choose one of {', '.join(SCENES)}")
        with self.lock:
            self.gui_scene.value = title  # runs _scene_chosen synchronously

    def play(self) -> None:
        """Start the active scene's motion."""
        self.guard("play", self.scene.play)()

    def pause(self) -> None:
        self.guard("pause", self.scene.pause)()

    def step(self) -> None:
        self.guard("step", self.scene.step)()

    def reset(self) -> None:
        self.guard("reset", self.scene.reset)()

    def apply_preset(self, name: str) -> None:
        """Load a preset of the active scene (free body, heavy top)."""
        self.guard("preset", self.scene.apply_preset)(name)

    def tick(self, dt: float) -> None:
        """Advance the active scene by dt [s]; errors are reported, never raised."""
        if self.closed:
            return
        self.guard("tick", self.scene.tick)(dt)

    def close(self) -> None:
        """Mark the session closed (its client is gone; viser drops the client's nodes)."""
        with self.lock:
            self.closed = True
            self.scene.playing = False
