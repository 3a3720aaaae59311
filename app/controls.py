"""The playback controls every animated scene shows at the top of its panel.

Play/Pause (one toggle button), Step and Reset, the time scale (slow motion 0.1x to fast 4x),
the integrator (where the scene has a choice) and a one-line status (simulated time, method).
This module only builds the GUI and reports clicks; the scene owns the state and decides what
a click does.  Values a client sends out of range are refused (the handle goes back to the
last valid value) and said so in `gui_message`, the scene's message line.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser

from app.common import Guard, checked_value

__all__ = [
    "INTEGRATOR_EXACT",
    "INTEGRATOR_REALTIME",
    "STEP_DT",
    "TIME_SCALE_RANGE",
    "PlaybackControls",
]

INTEGRATOR_REALTIME = "splitting4 (real time)"
"""physics.integrators.step_realtime: 4th-order symplectic splitting with automatic sub-steps."""
INTEGRATOR_EXACT = "exact"
"""physics.methods.exact_solution evaluated at the simulated time (closed form)."""
TIME_SCALE_RANGE = (0.1, 4.0)
STEP_DT = 1.0 / 60.0  # [s] of wall time one "Step" click stands for (times the time scale)
PLAY_LABEL, PAUSE_LABEL = "Play", "Pause"
STEP_LABEL, RESET_LABEL = "▶| Step", "⟲ Reset"  # glyphs the GUI font has (⏭ ⏸ are missing)


class PlaybackControls:
    """GUI handles: gui_message (hidden unless there is something to say), gui_play,
    gui_step_reset, gui_time_scale, gui_integrator (or None), gui_status.

    Callbacks receive no arguments; they run under the session lock (through `guard`).
    """

    def __init__(
        self,
        gui: viser.GuiApi | Any,
        guard: Guard,
        *,
        on_toggle: Callable[[], None],
        on_step: Callable[[], None],
        on_reset: Callable[[], None],
        on_time_scale: Callable[[float], None],
        integrators: tuple[str, ...] = (),
        on_integrator: Callable[[str], None] | None = None,
    ) -> None:
        self.gui_message = gui.add_markdown("", visible=False)
        self.gui_play = gui.add_button(PLAY_LABEL, color="green", icon=viser.Icon.PLAYER_PLAY_FILLED,
                                       hint="start / pause the motion")
        self.gui_step_reset = gui.add_button_group("Step · Reset", (STEP_LABEL, RESET_LABEL))
        lo, hi = TIME_SCALE_RANGE
        self.gui_time_scale = gui.add_slider(
            "Time scale [×]", lo, hi, 0.05, 1.0,
            marks=((0.1, "0.1×"), (1.0, "1×"), (2.0, "2×"), (3.0, "3×"), (4.0, "4×")),
            hint="simulated seconds per second of wall time (slow motion below 1)",
        )
        self.gui_integrator = None
        if integrators:
            self.gui_integrator = gui.add_dropdown(
                "Integrator", integrators, initial_value=integrators[0],
                hint="splitting4: the real-time symplectic method; exact: the closed form",
            )
        self.gui_status = gui.add_markdown("")
        self._last_scale = 1.0
        self._last_integrator = integrators[0] if integrators else ""

        self.gui_play.on_click(guard("play button", lambda _event: on_toggle()))

        def step_or_reset(event: Any) -> None:
            choice = event.target.value
            if choice == STEP_LABEL:
                on_step()
            elif choice == RESET_LABEL:
                on_reset()

        self.gui_step_reset.on_click(guard("step/reset buttons", step_or_reset))

        def time_scale(_event: Any) -> None:
            value = checked_value(self.gui_time_scale.value, lo, hi)
            if value is None:
                self.show_message(f"Time scale {self.gui_time_scale.value!r} refused: it must be "
                                  f"between {lo:g}× and {hi:g}×.")
                self.gui_time_scale.value = self._last_scale
                return
            self._last_scale = value
            on_time_scale(value)

        self.gui_time_scale.on_update(guard("time scale", time_scale))

        if self.gui_integrator is not None and on_integrator is not None:
            integrator = self.gui_integrator

            def choose(_event: Any) -> None:
                if integrator.value not in integrator.options:  # a client can send any string
                    self.show_message(f"Integrator {integrator.value!r} refused.")
                    integrator.value = self._last_integrator
                    return
                self._last_integrator = integrator.value
                on_integrator(integrator.value)

            integrator.on_update(guard("integrator", choose))

    @property
    def handles(self) -> list[Any]:
        """All GUI handles, for removal."""
        out = [self.gui_message, self.gui_play, self.gui_step_reset, self.gui_time_scale, self.gui_status]
        if self.gui_integrator is not None:
            out.append(self.gui_integrator)
        return out

    def show_playing(self, playing: bool) -> None:
        """The toggle shows what a click does: Pause while playing, Play while paused."""
        self.gui_play.label = PAUSE_LABEL if playing else PLAY_LABEL
        self.gui_play.icon = viser.Icon.PLAYER_PAUSE_FILLED if playing else viser.Icon.PLAYER_PLAY_FILLED
        self.gui_play.color = "orange" if playing else "green"

    def show_message(self, text: str) -> None:
        """A refused input or a physics problem, in the scene's message line (until cleared)."""
        self.gui_message.content = f"**⚠ {text}**" if not text.startswith("**") else text
        self.gui_message.visible = True

    def clear_message(self) -> None:
        self.gui_message.visible = False
        self.gui_message.content = ""

    def set_status(self, text: str) -> None:
        if self.gui_status.content != text:
            self.gui_status.content = text
