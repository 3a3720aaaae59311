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
  watching it.  Each frame the app loop (`app.main.App.frame`) calls `room.advance(dt)` on every
  room (the simulation advances once, whatever the number of views), then `room.draw` for each
  view whose browser is ready; `room.tick(dt)` does both for one room.  A browser that explores
  has a room of its own; a presenter's room has a view per follower.

**Replay** (`app.kit.core.history`): a room whose simulation is replayable records its last minute
of motion in `history` while it plays.  `mode` is LIVE, SCRUBBING or REPLAYING.  `scrub(t)`
sets the live moment aside (a snapshot: nothing is written into the simulation while the room
shows the past, so it comes back exactly) and restores the recorded moment t into `sim` itself
(views keep drawing `room.sim`; the presenter's followers follow).  In the past, Play / Pause
replays / stops the recording at the time scale (`replay()` starts it), Step steps it;
`resume()` puts the live moment back and plays on if it was playing; `branch()` makes the shown
moment the live one (the recorded future is dropped) and plays on from it; Reset, a preset or
an edit that starts a new run return to live.  A time outside the recorded stretch is refused
(ValueError with the message to show), and nothing changes.

All of a room's work runs under `room.lock` (re-entrant: assigning a handle's value on the
server runs its callback synchronously), taken by the loop's tick and by the session's guard
around every callback.  The app loop calls `advance` once per frame and `draw` for each view
whose previous frame has left (`app.backpressure.FramePacer`); `tick` does both for one room.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from typing import Any, Protocol, runtime_checkable

from app.kit.core.common import CameraView, RunEnded, Wrap, keep_phase
from app.kit.core.history import History, Snapshot, fork_with_refs, is_replayable
from app.kit.core.presets import Preset

__all__ = ["LIVE", "REPLAYING", "SCRUBBING", "Room", "Scene", "Simulation", "View"]

logger = logging.getLogger(__name__)

STEP_DT = 1.0 / 60.0  # [s] of wall time one "Step" click stands for (times the time scale)
SAMPLE_PERIOD = 0.1  # [s] of wall time between plot samples while playing (10 Hz)
LIVE, SCRUBBING, REPLAYING = "live", "scrubbing", "replaying"  # Room.mode
_END_SLACK = 1e-9  # [s] a replay this close to the live moment has reached it


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

    timeline: Any
    """The view's replay `Timeline` (`app.kit.panel.timeline`), redrawn after the view; None if none."""

    def frame(self, dt: float) -> None:
        """The per-frame update after the simulation advanced; dt [s] of wall time."""

    def refresh(self) -> None:
        """Redraw everything (after a step, a reset, an edit; never per frame)."""

    def show_message(self, text: str, stale: Callable[[], bool] | None = None) -> None:
        """Say something in the view's message line (a refusal, a stopped run), until `stale()`."""

    def remove(self) -> None:
        """Remove the view's nodes and panel from its client."""

    def report_error(self, where: str, error: BaseException) -> None:
        """Log and show an exception raised while drawing (the session's error display)."""


class Scene(Protocol):
    """A scene of the dropdown: a view class with its title, camera view, presets, and the
    simulation it starts (see `app.kit` for the recipe)."""

    title: str
    view: CameraView
    @property
    def simulation_parts(self) -> tuple[type | Callable[..., Any], ...]:
        """Classes and functions the scene's simulation holds from modules other than the one of
        its own class (`app.scenes.simulation_parts`: what the room codec may decode)."""
        ...

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
        """Load the preset `name` into the room's simulation, paused at its t = 0 (ValueError
        naming the valid ones)."""
        ...

    def __call__(self, client: Any, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> View: ...


class Room:
    """One simulation, its transport state and the views that watch it.

    Attributes:
        sim: the simulation.  playing, time_scale: the transport (in the past, playing means
        replaying).  views: the views drawing it.
        scene: the scene (view class) that made it; lock: see the module docstring.
        ticks: frames in which the simulation advanced (tests check: once per frame).
        history: the recorded last minute (`app.kit.core.history.History`), None for a simulation
        without motion to replay.
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
        self.history: History | None = History() if is_replayable(sim) else None
        self._live: Any = None  # the live moment set aside while the past is shown (a Snapshot)
        self._live_phase = 0.0  # its sampling phase
        self._live_playing = False  # whether it was playing

    def fork(self) -> Room:
        """A new room (no views) with a fork of the simulation (`Simulation.fork`), the same
        scene, transport (playing, time scale) and sampling phase, so it goes on as this one does,
        and the same replay history and moment shown (an explorer's copy scrubs the last minute
        too; a copy made while the past is shown shows it, its live moment set aside alike)."""
        with self.lock:
            history, live = self.history, self._live
            carried = history is not None and len(history) > 0 and history.run == self.sim.run
            refs = history.distinct_refs() if carried and history is not None else []
            if live is not None:
                refs.append(live.refs)
            forked = fork_with_refs(self.sim, refs) if carried else None
            room = Room(self.scene, forked[0] if forked is not None else self.sim.fork())
            room.playing = self.playing
            room.time_scale = self.time_scale
            room._since_sample = self._since_sample
            if forked is not None and history is not None and room.history is not None:
                copies = forked[1]
                room.history = history.fork(copies)
                if live is not None:
                    room._live = Snapshot(live.values.copy(), copies.get(id(live.refs), live.refs))
                    room._live_phase, room._live_playing = self._live_phase, self._live_playing
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
        self._sync_run()
        for view in list(self.views):
            view.refresh()
            timeline = view.timeline
            if timeline is not None:
                timeline.refresh()
            recheck = getattr(getattr(view, "message", None), "recheck", None)
            if recheck is not None:
                recheck()  # a message that no longer holds goes (`MessageLine.show`'s `stale`)

    def notify(self, text: str, stale: Callable[[], bool] | None = None) -> None:
        """Say `text` in every view's message line (until `stale()` says it no longer holds)."""
        for view in list(self.views):
            if stale is None:
                view.show_message(text)
            else:
                view.show_message(text, stale)

    # ------------------------------------------------------------------ replay
    @property
    def mode(self) -> str:
        """LIVE, SCRUBBING (a recorded moment shown, paused) or REPLAYING."""
        if self._live is None:
            return LIVE
        return REPLAYING if self.playing else SCRUBBING

    @property
    def shown_t(self) -> float:
        """Simulated time [s] of what is shown (the live time when live)."""
        return float(self.sim.t)

    @property
    def live_t(self) -> float:
        """Simulated time [s] of the live moment (set aside while the past is shown)."""
        return float(self._live.t) if self._live is not None else float(self.sim.t)

    def stretch(self) -> tuple[float, float] | None:
        """(t_first, t_live) [s]: the recorded stretch a scrub may show; None if nothing is
        recorded of this run (or the scene has no motion)."""
        history = self.history
        if history is None or not len(history) or history.run != self.sim.run:
            return None
        return history.t_first, self.live_t

    def _sync_run(self) -> None:
        """A new run started (an edit, a preset) while the past was shown: the past is gone."""
        if self._live is not None and self.history is not None and self.history.run != self.sim.run:
            self._live = None
            self.playing = False

    def _record(self, force: bool = False) -> None:
        if self.history is not None and self._live is None:
            self.history.record(self.sim, force=force, aux=self._since_sample)

    def _set_aside(self) -> None:
        """Entering the past: the live moment becomes the newest snapshot and is kept aside."""
        if self._live is None:
            assert self.history is not None
            self._record(force=True)
            self._live = self.sim.snapshot()
            self._live_phase = self._since_sample
            self._live_playing = self.playing
            self.playing = False

    def _show(self, t: float) -> None:
        """Restore the recorded moment t into the simulation (the newest snapshot at or before
        t, then the rest of the way for display)."""
        assert self.history is not None
        index = self.history.index_at(t)
        snapshot = self.history.snapshot(index)
        self.sim.restore(snapshot, later=max(0.0, t - snapshot.t))
        self._since_sample = self.history.aux(index)

    def _check_time(self, t: Any) -> float:
        """t as a float inside the recorded stretch, or ValueError with the message to show."""
        if self.history is None:
            raise ValueError(f"{getattr(self.scene, 'title', 'This scene')} has no motion to replay.")
        self._sync_run()
        if self._live is None:
            self._record(force=True)  # the live moment is the end of the stretch
        try:
            number = float(t)
        except (TypeError, ValueError):
            number = math.nan
        if not math.isfinite(number) or not self.history.contains(number):
            raise ValueError(self.history.outside_message(t))
        return number

    def scrub(self, t: Any) -> None:
        """Show the recorded moment t [s] (paused); ValueError, nothing changed, if t is outside
        the recorded stretch [t_first, t_live]."""
        with self.lock:
            number = self._check_time(t)
            self._set_aside()
            self.playing = False
            self._show(number)
            self.refresh()

    def replay(self, t: Any = None) -> None:
        """Replay the recording at the time scale from t [s] (default: the moment shown, or the
        start of the stretch if that is the live moment), ending at the live moment."""
        with self.lock:
            if t is None:
                if self.history is None or self.stretch() is None:
                    self._check_time(math.nan)  # the refusal message
                stretch = self.stretch()
                assert stretch is not None
                t = self.sim.t if self._live is not None and self.sim.t < stretch[1] - _END_SLACK else stretch[0]
            number = self._check_time(t)
            self._set_aside()
            self._show(number)
            self.playing = True
            self.refresh()

    def _replay_by(self, dt_sim: float) -> None:
        """The replay's part of a frame: dt_sim [s] further along the recording."""
        t = self.sim.t + dt_sim
        if t >= self.live_t - _END_SLACK:
            self.resume()
            self.notify(f"**Replay reached the live moment, t = {self.sim.t:.2f} s.**")
            return
        self._show(t)

    def resume(self) -> None:
        """Back to the live moment, exactly as it was set aside; playing on if it was playing."""
        with self.lock:
            self._sync_run()
            if self._live is None:
                return
            self.sim.restore(self._live)
            self._since_sample = self._live_phase
            self.playing = self._live_playing
            self._live = None
            self.refresh()

    def branch(self) -> None:
        """The moment shown becomes the live one: the recorded future is dropped and the motion
        plays on from here (the exact solution with it: same run).  ValueError if the live
        moment is shown."""
        with self.lock:
            self._sync_run()
            if self._live is None or self.history is None:
                raise ValueError("Branch here continues from a moment in the past: move the Timeline back first.")
            self.sim.truncate()
            self.history.cut_after(self.sim.t)
            self._live = None
            self._record(force=True)
            self.playing = True
            self.refresh()

    # ------------------------------------------------------------------ transport
    def play(self) -> None:
        """Play: a new run from its start, live; the same run while the past is shown, a replay."""
        with self.lock:
            self._sync_run()  # a new run since the past was shown: that past is gone first
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
        """Pause, and advance one display frame (STEP_DT times the time scale); in the past, step
        the replay."""
        with self.lock:
            self._sync_run()
            self.playing = False
            if self._live is not None:
                self._replay_by(STEP_DT * self.time_scale)
            else:
                self._record_start()
                if self._advance(STEP_DT * self.time_scale):
                    self._sample()
                    self._record()
            self.refresh()

    def reset(self) -> None:
        """Pause and go back to the initial conditions of this run (live again: a new run)."""
        with self.lock:
            self.playing = False
            self._live = None
            self.sim.reset()
            if self.history is not None:
                self.history.clear()
                self._record()
            self.refresh()

    def _record_start(self) -> None:
        """Before a run's first advance: its start is the first snapshot."""
        history = self.history
        if history is not None and (history.run != self.sim.run or not len(history)):
            self._record()

    def _advance(self, dt_sim: float) -> bool:
        """Advance the simulation; on failure pause and say so in every view (False)."""
        try:
            self.sim.advance(dt_sim)
        except RunEnded as end:  # the motion is over, as the physics says: no warning
            self.playing = False
            sim, t_end = self.sim, self.sim.t
            self.notify(f"**■ {end}**", stale=lambda: sim is not self.sim or sim.t != t_end)  # a new run
            self.refresh()
            return False
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
        (once per frame, whatever the number of views); plot samples at SAMPLE_PERIOD; the
        moment recorded (`history`).  In the past, the replay moves on instead."""
        with self.lock:
            self._sync_run()
            if not self.playing:
                return
            if self._live is not None:
                self._replay_by(dt * self.time_scale)
                self.ticks += 1
                return
            self._record_start()
            if self._advance(dt * self.time_scale):
                self.ticks += 1
                self._since_sample += dt
                if self._since_sample >= SAMPLE_PERIOD * (1.0 - 1e-9):
                    self._since_sample = keep_phase(self._since_sample, SAMPLE_PERIOD)
                    self._sample()
                self._record()

    def draw(self, view: Any, dt: float) -> None:
        """One view's part of a frame (dt [s] of wall time since it last drew); its errors go
        to its own session, never to the loop or the other views.  A view that left the room
        since the loop listed the views (its browser switched scenes or started presenting
        meanwhile) draws nothing: its nodes are gone."""
        with self.lock:
            if view not in self.views:
                return
            try:
                view.frame(dt)
                quiet = getattr(view, "quiet", None)
                if quiet is not None:
                    quiet.flush()  # values a user's edit held back from its fields
                timeline = view.timeline
                if timeline is not None:
                    timeline.frame(dt)
            except Exception as error:  # noqa: BLE001 - one broken view must not stop the others
                view.report_error("frame", error)

    def tick(self, dt: float) -> None:
        """One frame: the simulation advances once, then every view draws."""
        with self.lock:
            self.advance(dt)
            for view in list(self.views):
                self.draw(view, dt)
