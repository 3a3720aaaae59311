"""Simulation, view, room: the three nouns of the scene kit.

- A **simulation** (no viser in it) holds a scene's state and advances it: `advance(dt)`,
  `reset()` (back to its own initial conditions, never read from widgets), `t`, and `version`
  (bumped on every change of what is drawn, so views redraw only when needed).  One that
  keeps plot samples has `take_sample()`, which the room calls at SAMPLE_PERIOD of wall time.
  `fork()` is an exact, independent copy (an explorer's private room, a recording): the same
  state bit for bit, time, history (samples, traces), initial conditions and integrator state.
- A **view** draws one simulation for one browser (`client.scene` / `client.gui`) and turns
  that browser's GUI events into calls on its room.  `frame(dt)` is the per-frame update,
  `refresh()` redraws everything after an edit, `remove()` takes the view's nodes and panel
  away.
- A **room** is one simulation, its transport state (playing, time scale) and the views
  watching it.  The app loop calls `room.tick(dt)` once per frame: the simulation advances
  once, whatever the number of views, then every view draws.  Today each browser has its own
  room; a presenter's room has many views.

All of a room's work runs under `room.lock` (re-entrant: assigning a handle's value on the
server runs its callback synchronously), taken by the loop's tick and by the session's guard
around every callback.  The app loop calls `advance` once per frame and `draw` for each view
whose previous frame has left (`app.backpressure.FramePacer`); `tick` does both for one room.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any, Protocol, runtime_checkable

from app.kit.common import CameraView
from app.kit.gui import Wrap
from app.kit.presets import Preset

__all__ = ["Room", "Scene", "Simulation", "View"]

logger = logging.getLogger(__name__)

STEP_DT = 1.0 / 60.0  # [s] of wall time one "Step" click stands for (times the time scale)
SAMPLE_PERIOD = 0.1  # [s] of wall time between plot samples while playing (10 Hz)


@runtime_checkable
class Simulation(Protocol):
    """What a room needs from a simulation (no viser)."""

    version: int

    @property
    def t(self) -> float:
        """Simulated time [s] since the run started."""
        ...

    def advance(self, dt: float) -> None:
        """Advance by dt [s] of simulated time; raises (e.g. IntegrationError) on failure."""

    def reset(self) -> None:
        """Back to the initial conditions of this run (t = 0)."""

    def fork(self) -> Simulation:
        """An exact, independent copy of what is shown now: the same t, state bit for bit,
        initial conditions (Reset in the copy goes where the original's would), integrator and
        its internal state, histories (plot samples, traces), preset and version.  Nothing
        mutable is shared, and advancing both by the same dt sequence gives the same states bit
        for bit.  Costs well under a millisecond (tests/test_fork.py)."""
        ...


class View(Protocol):
    """What a room needs from a view (one browser's drawing of the room's simulation)."""

    def frame(self, dt: float) -> None:
        """The per-frame update after the simulation advanced; dt [s] of wall time."""

    def refresh(self) -> None:
        """Redraw everything (after a step, a reset, an edit; never per frame)."""

    def show_message(self, text: str) -> None:
        """Say something in the view's message line (a refusal, a stopped run)."""

    def remove(self) -> None:
        """Remove the view's nodes and panel from its client."""

    def report_error(self, where: str, error: BaseException) -> None:
        """Log and show an exception raised while drawing (the session's error display)."""


class Scene(Protocol):
    """A scene of the dropdown: a view class with its title, camera view, presets, and the
    simulation it starts (see `app.kit` for the recipe)."""

    title: str
    view: CameraView

    @classmethod
    def presets(cls) -> tuple[Preset, ...]:
        """The scene's presets (assets/presets/*.json; PresetError if the file is broken)."""
        ...

    @classmethod
    def new_simulation(cls) -> Simulation:
        """A simulation at the scene's first preset."""
        ...

    @classmethod
    def apply_preset(cls, room: Room, name: str) -> None:
        """Load the preset `name` into the room's simulation (ValueError naming the valid ones)."""
        ...

    def __call__(self, client: Any, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> View: ...


class Room:
    """One simulation, its transport state and the views that watch it.

    Attributes:
        sim: the simulation.  playing, time_scale: the transport.  views: the views drawing it.
        scene: the scene (view class) that made it; lock: see the module docstring.
        ticks: frames in which the simulation advanced (tests check: once per frame).
    """

    def __init__(self, scene: Any, sim: Any) -> None:
        self.scene = scene
        self.sim = sim
        self.playing = False
        self.time_scale = 1.0
        self.views: list[Any] = []
        self.lock = threading.RLock()
        self.ticks = 0
        self._since_sample = 0.0

    def fork(self) -> Room:
        """A new room (no views) with a fork of the simulation (`Simulation.fork`), the same
        scene, transport (playing, time scale) and sampling phase, so it goes on as this one does."""
        with self.lock:
            room = Room(self.scene, self.sim.fork())
            room.playing = self.playing
            room.time_scale = self.time_scale
            room._since_sample = self._since_sample
        return room

    # ------------------------------------------------------------------ views
    def add_view(self, view: Any) -> None:
        with self.lock:
            self.views.append(view)

    def remove_view(self, view: Any) -> None:
        with self.lock:
            if view in self.views:
                self.views.remove(view)

    def refresh(self) -> None:
        """Every view redraws everything (after a change that is not a frame)."""
        for view in list(self.views):
            view.refresh()

    def notify(self, text: str) -> None:
        for view in list(self.views):
            view.show_message(text)

    # ------------------------------------------------------------------ transport
    def play(self) -> None:
        with self.lock:
            self.playing = True
            self.refresh()

    def pause(self) -> None:
        with self.lock:
            self.playing = False
            self.refresh()

    def toggle(self) -> None:
        self.pause() if self.playing else self.play()

    def set_time_scale(self, scale: float) -> None:
        with self.lock:
            self.time_scale = float(scale)
            self.refresh()

    def step(self) -> None:
        """Pause, and advance one display frame (STEP_DT times the time scale)."""
        with self.lock:
            self.playing = False
            if self._advance(STEP_DT * self.time_scale):
                self._sample()
            self.refresh()

    def reset(self) -> None:
        """Pause and go back to the initial conditions of this run."""
        with self.lock:
            self.playing = False
            self.sim.reset()
            self.refresh()

    def _advance(self, dt_sim: float) -> bool:
        """Advance the simulation; on failure pause and say so in every view (False)."""
        try:
            self.sim.advance(dt_sim)
        except (ArithmeticError, ValueError, RuntimeError) as error:  # IntegrationError is a RuntimeError
            self.playing = False
            logger.warning("simulation stopped: %s", error)
            self.notify(f"The simulation stopped: {error}")
            self.refresh()
            return False
        return True

    def _sample(self) -> None:
        take_sample = getattr(self.sim, "take_sample", None)
        if take_sample is not None:
            take_sample()

    def advance(self, dt: float) -> None:
        """The simulation's part of a frame: dt [s] of wall time times the time scale, if playing
        (once per frame, whatever the number of views); plot samples at SAMPLE_PERIOD."""
        with self.lock:
            if self.playing and self._advance(dt * self.time_scale):
                self.ticks += 1
                self._since_sample += dt
                if self._since_sample >= SAMPLE_PERIOD * (1.0 - 1e-9):
                    self._since_sample = 0.0
                    self._sample()

    def draw(self, view: Any, dt: float) -> None:
        """One view's part of a frame (dt [s] of wall time since it last drew); its errors go
        to its own session, never to the loop or the other views."""
        with self.lock:
            try:
                view.frame(dt)
            except Exception as error:  # noqa: BLE001 - one broken view must not stop the others
                view.report_error("frame", error)

    def tick(self, dt: float) -> None:
        """One frame: the simulation advances once, then every view draws."""
        with self.lock:
            self.advance(dt)
            for view in list(self.views):
                self.draw(view, dt)
