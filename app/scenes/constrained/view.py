"""The "Constrained particles" scene's view: `ConstrainedView` draws a `ConstrainedSimulation`
for one browser (`app.scenes.constrained`).

What a playing frame sends (the turning hoop, the default; tests/test_frame_budget.py counts the
bytes, docs/performance.md has the figures): the hoop's turn (one orientation), the bead's position, the
turn of the bead's frame `o` and C's tip (a position) — the four numbers α, θ, C's direction
about the hoop and |C|.  How:

- a particle's virtual displacements and C hang in a frame `o` at the particle turned so that
  its z runs along ∂x_i/∂q_1 and its x along C_i's part across it: on a smooth single constraint
  (hoop, rod, the spherical pendulum's θ) δx_1 and C's direction are then fixed in it (5.7) and
  the frame's turn moves them all; F (gravity) hangs under the particle unturned and is sent
  never;
- an arrow's shaft is two pieces of one length P = 2^k (one from the start, one ending at the
  head, overlapping in the middle) covering any shaft length in [P, 2P]: a change of length
  moves the tip only (one position message; the label rides on the tip), the pieces' scale is
  sent when the length leaves [P, 2P];
- while playing, poses and lengths are on power-of-two grids (`app.kit.draw.lean.Pose` with a
  turn_quantum; positions and lengths 2^-8 m, quaternion components 2^-9, the guide's 2^-10:
  ~1 px or finer; such numbers go on the wire as float32) and a node is sent only when what is
  drawn changed; paused,
  everything is exact (float32).  What is drawn is a function of the state alone, so followers
  and late views draw the same;
- the status line and the q, q̇ sliders follow at 2 Hz while playing, the paths' chunks as
  `app.kit.draw.widgets.TraceLines` sends them.

Much lower it does not go: those four messages carry four changing numbers a frame, and F
needs a frame at the particle that turns about z only, so the bead's position cannot ride on a
turn.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import viser

from app.i18n import N_
from app.kit.core.common import CameraView, SliderSpec, Throttle, Wrap
from app.kit.core.key_number import KeyNumber
from app.kit.core.presets import Preset
from app.kit.core.room import Room
from app.kit.draw.labels import DETAIL
from app.kit.draw.lean import TOLERANCE, Pose, snap
from app.kit.draw.widgets import Stage, TraceLines, Vector
from app.kit.panel.gui import PresetsRow, Readout, Tabs, Transport, add_slider
from app.kit.panel.plots import LivePlots, PlotSpec
from app.kit.view import SceneView, nth
from app.scenes.constrained.readouts import conserved_text, key_numbers_of, readout_text, status_text
from app.scenes.constrained.simulation import (
    GUIDE_POINTS,
    ROD_END_WORDS,
    ConstrainedSetup,
    ConstrainedSimulation,
    load_constrained_presets,
    setup_of,
    translated_state_spec,
)
from app.viser_internals import set_points, set_position, set_scale
from physics._types import Array
from physics.constrained import System
from physics.quaternion import wxyz_from_matrix

__all__ = ["DELTA_Q", "VIEW", "ConstrainedView"]

DELTA_Q = 0.35  # [rad or m] the virtual displacements are drawn for this δq_j
ARROW_QUANTUM = 2.0**-9  # while playing, an arrow turns in steps of ~2 ARROW_QUANTUM rad (~1 px at 1.5 m)
POSITION_QUANTUM = 2.0**-8  # [m] while playing, a particle moves in steps of this (~0.5 px)
DX_HEAD = 18 * POSITION_QUANTUM  # [m] head lengths on the grid (0.07, 0.09 m): a shaft's length is too
FORCE_HEAD = 23 * POSITION_QUANTUM
GUIDE_QUANTUM = 2.0**-10  # the guide turns in steps of ~2 GUIDE_QUANTUM rad (~1 px at GUIDE_REACH)
READOUT_PERIOD = 0.5  # [s] of wall time: the status line and the Readout tab shown, while playing (2 Hz)
PLOT_PERIOD = 0.25
SLIDER_PERIOD = 0.5  # the q, q̇ sliders follow at 2 Hz while playing (a refresh writes them exactly)
GUIDE_REACH = 2.5  # [m] the largest hoop radius / rod half length: its far end moves ~1 px per snapping step
GUIDE_TURN_ATOL = 1e-9  # [m] the curve now is drawn as the first one turned about z if it is that to this
PARTICLE_RADIUS = 0.07
PARTICLE_COLORS = ((20, 110, 220), (220, 120, 20))
ROD_COLOR = (90, 90, 100)
GUIDE_COLOR = (150, 120, 60)
F_COLOR = (25, 25, 25)
C_COLOR = (210, 30, 30)
DX_COLORS = ((0, 150, 150), (140, 60, 210))

VIEW = CameraView(position=(3.9, -5.2, 1.6), look_at=(0.7, 0.0, -0.6), fov_deg=45.0)


class ConstrainedView(SceneView):
    """One browser's view of a room with a `ConstrainedSimulation`."""

    transport: Transport  # built by build_head

    title = N_("Constrained particles")  # the scene dropdown shows it translated (app.i18n)
    root = "/cp"  # node names are short: every message of a frame carries its node's name
    view = VIEW

    @classmethod
    def read_presets(cls) -> tuple[Preset, ...]:
        return load_constrained_presets()

    @classmethod
    def simulation_from_preset(cls, preset: Preset) -> ConstrainedSimulation:
        return ConstrainedSimulation(setup_of(preset))

    @classmethod
    def start_preset(cls, sim: ConstrainedSimulation, preset: Preset) -> None:
        sim.set_setup(setup_of(preset))

    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: ConstrainedSimulation = room.sim
        self._drawn_version = -1
        self._built_for: tuple[str, int] | None = None  # (kind, id of the paths) the system part was built for
        self._system_handles: list[Any] = []
        self._system_bindings: list[Any] = []
        self._readout_throttle = Throttle(READOUT_PERIOD)
        self._plot_throttle = Throttle(PLOT_PERIOD)
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self.build()

    # ------------------------------------------------------------------ building
    def _build_scene(self) -> None:
        scene = self.client.scene
        Stage(scene, f"{self.root}/stage", grid_z=-2.4, size=6.0, axis_length=1.2, labels=self.labels)
        self.pivot = scene.add_icosphere(f"{self.root}/pivot", radius=0.04, color=ROD_COLOR, subdivisions=1,
                                         cast_shadow=False, receive_shadow=False)

    def _build_system_scene(self) -> None:
        """The nodes of the current system (rebuilt when the system changes)."""
        scene = self.client.scene
        base = f"{self.root}/s"
        self.system_node = scene.add_frame(base, show_axes=False)
        sim = self.sim
        n, m = sim.system.n, sim.system.m
        # The guide (hoop, rod) hangs in a frame: a guide that turns about z (x_0(q, t) = Rz(α) x_0(q, 0))
        # is drawn once and turned by one small message a frame, not resent as 72 segments.
        self.guide_frame = scene.add_frame(f"{base}/g", show_axes=False)
        self.guide = scene.add_line_segments(f"{base}/g/l", np.zeros((1, 2, 3)), GUIDE_COLOR,
                                             thickness=4.0, thickness_units="screen",
                                             visible=sim.system.guide is not None)
        self.guide_pose = Pose(self.guide_frame, tolerance=POSITION_QUANTUM, turn_quantum=GUIDE_QUANTUM)
        self._guide_start: tuple[System, Array] | None = None  # the system and its guide (N, 3) at t = 0
        self._guide_turns = True  # whether the guide now is that one turned about z
        self.links = scene.add_line_segments(f"{base}/links", np.zeros((max(1, len(sim.system.links)), 2, 3)),
                                             ROD_COLOR, thickness=4.0, thickness_units="screen",
                                             visible=bool(sim.system.links))
        self.pivot.visible = bool(sim.system.links)
        self._links_drawn: np.ndarray | None = None  # the links' points as sent
        # A particle's arrows hang under it (they start at its centre): they only turn and stretch.
        self.particles = [scene.add_icosphere(f"{base}/p{i}", radius=PARTICLE_RADIUS,
                                              color=PARTICLE_COLORS[i % 2], subdivisions=2, cast_shadow=False,
                                              receive_shadow=False) for i in range(n)]
        self.particle_poses = [Pose(node, tolerance=POSITION_QUANTUM, turn_quantum=ARROW_QUANTUM)
                               for node in self.particles]
        self.paths_space = [TraceLines(scene, f"{base}/t{i}", _lighter(PARTICLE_COLORS[i % 2]), sim.paths[i],
                                       thickness=2.0) for i in range(n)]
        coordinate = sim.system.coordinates
        # Labels only on the last particle's arrows (the others share the colours: the legend says).
        # With two coordinates the second arrow's label sits at its middle (two tips are often close).
        # Each particle's virtual displacements and C hang in a frame `o` turned so that its z runs along
        # ∂x_i/∂q_1 and its x along C_i's part across it: on one smooth constraint (hoop, rod) the frame's
        # turn is all that moves them (one message a frame), C only stretches (5.7: C ⊥ δx).
        self.turns = [scene.add_frame(f"{base}/p{i}/o", show_axes=False) for i in range(n)]
        self.turn_poses = [Pose(node, tolerance=POSITION_QUANTUM, turn_quantum=ARROW_QUANTUM) for node in self.turns]
        self.dx_arrows = [[_Arrow(scene, f"{base}/p{i}/o/dx{j}", DX_COLORS[j], f"δx({coordinate[j]})", i == n - 1,
                                  shaft_radius=0.012, head_radius=0.035, head_length=DX_HEAD, font_scale=1.3,
                                  label_at_middle=j == 1, labels=self.labels, priority=DETAIL)
                           for j in range(m)] for i in range(n)]
        self.F_arrows = [_Arrow(scene, f"{base}/p{i}/F", F_COLOR, "F", i == n - 1, shaft_radius=0.016,
                                head_radius=0.045, head_length=FORCE_HEAD, font_scale=1.5, labels=self.labels)
                         for i in range(n)]
        self.C_arrows = [_Arrow(scene, f"{base}/p{i}/o/C", C_COLOR, "C", i == n - 1, shaft_radius=0.016,
                                head_radius=0.045, head_length=FORCE_HEAD, font_scale=1.5, labels=self.labels)
                         for i in range(n)]

    def _build_gui(self) -> None:
        gui = self.client.gui
        wrap = self._wrap
        tr = self.tr
        _ = tr.gettext
        self.build_head(_(
            "### Constrained particles (memo §2, §5)\n"
            "x_i = x_i(q, t) (5.1).  Teal/violet: virtual displacements ∂x_i/∂q_j δq (5.6); black: applied "
            "force F; red: constraint force **C = m ẍ − F**, with **C · ∂x/∂q_j = 0** (5.7)."))
        self.tabs = Tabs(gui, wrap, (N_("Setup"), N_("Readout"), N_("Plots")), on_change=lambda _name: self.refresh(),
                         tr=tr)
        with self.tabs.tab("Setup"):
            self.presets_row = PresetsRow(gui, wrap, self.presets(), self.choose_preset, self.choose_own_preset,
                                          tr=tr)
            self.folder_state = gui.add_folder(_("State q, q̇ (restarts at t = 0)"))
            self.folder_params = gui.add_folder(_("Parameters (restart at t = 0)"))
            with gui.add_folder(_("Display"), expand_by_default=False):
                self.gui_show_dx = gui.add_checkbox(_("Virtual displacements"), True,
                                                    hint=_("∂x_i/∂q_j δq_j, drawn for δq = {dq} (rad or m)").format(
                                                        dq=tr.general(DELTA_Q)))
                self.gui_show_forces = gui.add_checkbox(_("Forces F and C"), True)
                self.gui_show_paths = gui.add_checkbox(_("Paths"), True)
        with self.tabs.tab("Readout"):
            self.conserved_note = Readout(gui)
            self.readout = Readout(gui)
        with self.tabs.tab("Plots"):
            self.folder_plots = gui.add_folder(_("Plots"))
        for handle in (self.gui_show_dx, self.gui_show_forces, self.gui_show_paths):
            handle.on_update(wrap("display toggle", lambda _event: self.refresh()))
        self._gui_roots = [self.gui_intro, self.message.handle, *self.transport.handles, *self.tabs.handles]

    def _build_system_gui(self) -> None:
        """The chosen system's sliders and plots (rebuilt when the system changes)."""
        gui = self.client.gui
        sim = self.sim
        kind = sim.setup.kind_spec
        tr = self.tr
        q_specs = [translated_state_spec(spec, tr) for spec in kind.q_specs]
        rate_specs = [translated_state_spec(spec, tr) for spec in kind.rate_specs]
        param_specs = [spec.translated(tr) for spec in kind.param_specs]
        with self.folder_state:
            self.gui_q = [add_slider(gui, spec, value) for spec, value in zip(q_specs, sim.setup.q_shown)]
            self.gui_rates = [add_slider(gui, spec, value)
                              for spec, value in zip(rate_specs, sim.setup.rates_shown)]
        with self.folder_params:
            self.gui_params = [add_slider(gui, spec, value) for spec, value in zip(param_specs, sim.setup.params)]
        for index, handle in enumerate(self.gui_q):
            self._bind(handle, f"{kind.q_specs[index].key} slider", self._state_edit("q", index),
                       nth(lambda: self.sim.setup.q_shown, index), q_specs[index])
        for index, handle in enumerate(self.gui_rates):
            self._bind(handle, f"{kind.rate_specs[index].key} slider", self._state_edit("rates", index),
                       nth(lambda: self.sim.setup.rates_shown, index), rate_specs[index])
        for index, handle in enumerate(self.gui_params):
            self._bind(handle, f"{kind.param_specs[index].key} slider", self._param_edit(index),
                       nth(lambda: self.sim.setup.params, index), param_specs[index])
        system = sim.system
        units = ["deg" if a else "m" for a in system.angular]
        with self.folder_plots:
            specs = [
                PlotSpec("q(t)", ("q1", "q2")[: system.m],
                         tuple(f"{c} [{u}]" for c, u in zip(system.coordinates, units)),
                         ("#1e6ed8", "#dc7814")[: system.m]),
                PlotSpec(tr.gettext("h = T₂ − T₀ + V and T + V [J]"), ("h", "E"), ("h [J]", "T + V [J]"),
                         ("#1b9e3a", "#888888")),
                PlotSpec("|h − h₀| / (|T| + |V|)₀ (log10)", ("drift",), ("drift",), ("#c0392b",), log=True),
            ]
            self.plots = LivePlots(gui, sim.samples, specs, height=170)
        self._system_handles = [*self.gui_q, *self.gui_rates, *self.gui_params, *self.plots.handles]

    def plot_elements(self, tab: str) -> list[Any]:
        """Plots: the system's charts."""
        return list(self.plots.handles) if tab == "Plots" else []

    def _bind(self, handle: Any, where: str, apply: Callable[[float], str | None], current: Callable[[], Any],
              spec: SliderSpec) -> None:
        binding = self.bind(handle, where, apply, current, spec=spec)
        self._bindings.remove(binding)  # closed with the system's panel, not the view's
        self._system_bindings.append(binding)

    def _ensure_system_built(self) -> None:
        """(Re)build the system's nodes and sliders if the system kind or its paths changed."""
        key = (self.sim.setup.kind, id(self.sim.paths[0]))
        if key == self._built_for:
            return
        if self._built_for is not None:
            for binding in self._system_bindings:
                binding.close()
            for handle in self._system_handles:
                handle.remove()
            self.system_node.remove()
        self._system_bindings, self._system_handles = [], []
        self._built_for = key
        self._build_system_scene()
        self._build_system_gui()

    def remove_panel(self) -> None:
        for binding in self._system_bindings:
            binding.close()
        self._system_bindings = []
        super().remove_panel()

    # ------------------------------------------------------------------ callbacks
    def _edit(self, setup_change: Callable[[ConstrainedSetup], ConstrainedSetup]) -> str | None:
        try:
            setup = setup_change(self.sim.setup)
        except ValueError as error:
            return str(error)
        self.message.clear()
        self.sim.preset = None
        self.sim.set_setup(setup)
        self.room.refresh()
        return None

    def _state_edit(self, field: str, index: int) -> Callable[[float], str | None]:
        def apply(value: float) -> str | None:
            def change(setup: ConstrainedSetup) -> ConstrainedSetup:
                values = list(getattr(setup, f"{field}_shown"))
                values[index] = value
                return setup.with_values(**{f"{field}_shown": values})

            return self._edit(change)

        return apply

    def _param_edit(self, index: int) -> Callable[[float], str | None]:
        def apply(value: float) -> str | None:
            if index == len(self.sim.setup.params) - 1:  # the arrow scale: display only
                self.sim.set_display(value)
                self.room.refresh()
                return None

            def change(setup: ConstrainedSetup) -> ConstrainedSetup:
                params = list(setup.params)
                params[index] = value
                # Keep the state shown now (angles wrapped): the new run starts from it.
                return setup.with_values(params=params, q_shown=_wrapped(self.sim.q_shown, setup.kind_spec.q_specs),
                                         rates_shown=self.sim.rates_shown)

            return self._edit(change)

        return apply

    # ------------------------------------------------------------------ the view protocol
    def show_message(self, text: str, stale: Callable[[], bool] | None = None) -> None:
        """Say `text` (`SceneView.show_message`); the room's "■ <the bead left the rod>" in this
        view's language (`ROD_END_WORDS`)."""
        inner = text[len("**■ "):-len("**")] if text.startswith("**■ ") and text.endswith("**") else ""
        said = ROD_END_WORDS.words(inner, self.tr) if inner else None
        super().show_message(text if said is None else f"**■ {said}**", stale)

    def frame(self, dt: float) -> None:
        if self.sim.version == self._drawn_version:
            self.labels.update(dt)  # the camera may have moved
            return
        with self.client.atomic():
            self._ensure_system_built()
            self._draw()
            self.labels.update(dt)
            if self._readout_throttle.ready(dt):
                self._refresh_status()
                if self.tabs is not None and self.tabs.shown == "Readout":
                    self._render_readout()
            if self._plot_throttle.ready(dt) and self.tabs is not None and self.tabs.shown == "Plots":
                self.plots.push()
            if self._slider_throttle.ready(dt) and self.tabs is not None and self.tabs.shown == "Setup":
                self._show_state_sliders()

    def refresh(self) -> None:
        with self.client.atomic():
            self._ensure_system_built()
            self.transport.show(self.room.playing, self.room.time_scale)
            self.presets_row.show_note(self.preset_shown())
            kind = self.sim.setup.kind_spec
            self.show_values(self.gui_params, kind.param_specs, self.sim.setup.params)
            self._show_state_sliders()
            self._draw()
            self._refresh_status()
            self._render_readout()
            self.plots.push()
            self.labels.settle()

    def key_numbers(self) -> list[KeyNumber]:
        """q, q̇ now and the parameters, from the simulation (`readouts.key_numbers_of`), whatever
        tab shows (the q, q̇ sliders follow the motion on the Setup tab only)."""
        return key_numbers_of(self.sim)

    def _show_state_sliders(self) -> None:
        """While playing the q, q̇ sliders follow the motion; paused at t = 0 they show the setup."""
        kind = self.sim.setup.kind_spec
        self.show_values(self.gui_q, kind.q_specs, _clamped(self.sim.q_shown, kind.q_specs))
        self.show_values(self.gui_rates, kind.rate_specs, _clamped(self.sim.rates_shown, kind.rate_specs))

    def _draw(self) -> None:
        sim = self.sim
        self._drawn_version = sim.version
        ev = sim.evaluation()
        guide = sim.guide()
        if guide is not None:
            self._draw_guide(guide)
        exact = not self.room.playing  # while playing: at display resolution (~1 px), sent when changed
        if sim.system.links:
            ends = [np.zeros(3) if a < 0 else ev.x[a] for a, _ in sim.system.links]
            links = np.array([[e, ev.x[b]] for e, (_, b) in zip(ends, sim.system.links)], dtype=float)
            if not exact:
                links = np.round(links / TOLERANCE) * TOLERANCE
            links32 = links.astype(np.float32)
            if self._links_drawn is None or not np.array_equal(links32, self._links_drawn):
                set_points(self.links, links32)
                self._links_drawn = links32
        for i, pose in enumerate(self.particle_poses):
            pose.set(position=ev.x[i], exact=exact)
        show_paths = bool(self.gui_show_paths.value)
        for lines, trace in zip(self.paths_space, sim.paths):
            if show_paths:
                lines.sync(trace, lazy=not exact)
            else:
                lines.hide(trace)
        quantum = None if exact else ARROW_QUANTUM
        scale = sim.setup.force_scale
        show_dx, show_forces = bool(self.gui_show_dx.value), bool(self.gui_show_forces.value)
        def drawn(vector: Array) -> Array:
            """While playing, the vector with its length on the POSITION_QUANTUM grid (~0.5 px): a
            length message only when the drawn length changed."""
            length = float(np.linalg.norm(vector))
            return vector if exact or length < TOLERANCE else vector * (snap(length, POSITION_QUANTUM) / length)

        grid = None if exact else POSITION_QUANTUM
        for arrow in (*(a for row in self.dx_arrows for a in row), *self.F_arrows, *self.C_arrows):
            arrow.grid = grid
        for i in range(sim.system.n):
            R = _turn(ev.J[i, :, 0], ev.C[i])
            self.turn_poses[i].set(wxyz_from_matrix(R), exact=exact)
            for j, arrow in enumerate(self.dx_arrows[i]):
                arrow.enabled = show_dx
                arrow.update(drawn(R.T @ (DELTA_Q * ev.J[i, :, j])), quantum=quantum)
            self.F_arrows[i].enabled = show_forces
            self.F_arrows[i].update(drawn(scale * ev.F[i]), quantum=quantum)
            self.C_arrows[i].enabled = show_forces
            self.C_arrows[i].update(drawn(R.T @ (scale * ev.C[i])), quantum=quantum)

    def _draw_guide(self, guide: Array) -> None:
        """The constraint curve now (N, 3): as the curve at t = 0 turned about z when it is that
        (to GUIDE_TURN_ATOL), else as points."""
        system = self.sim.system
        if self._guide_start is None or self._guide_start[0] is not system:
            assert system.guide is not None
            lo, hi = system.guide
            start = np.array([system.positions([q], 0.0)[0] for q in np.linspace(lo, hi, GUIDE_POINTS)], dtype=float)
            set_points(self.guide, np.stack([start[:-1], start[1:]], axis=1).astype(np.float32))
            self._guide_start, self._guide_turns = (system, start), True
        if self._guide_turns:
            start = self._guide_start[1]
            k = int(np.argmax(np.hypot(start[:, 0], start[:, 1])))
            alpha = math.atan2(guide[k, 1], guide[k, 0]) - math.atan2(start[k, 1], start[k, 0])
            c, s_ = math.cos(alpha), math.sin(alpha)
            turned = start @ np.array([[c, s_, 0.0], [-s_, c, 0.0], [0.0, 0.0, 1.0]])  # rows Rz(α) x
            if np.max(np.abs(turned - guide)) <= GUIDE_TURN_ATOL:
                turn = (math.cos(0.5 * alpha), 0.0, 0.0, math.sin(0.5 * alpha))
                self.guide_pose.set(turn, exact=not self.room.playing)
                return
            self._guide_turns = False  # not a turn of the first curve: drawn as points from now on
        self.guide_pose.set((1.0, 0.0, 0.0, 0.0))
        set_points(self.guide, np.stack([guide[:-1], guide[1:]], axis=1).astype(np.float32))

    def _refresh_status(self) -> None:
        self.transport.set_status(status_text(self.sim.t, self.room.playing, self.room.time_scale, self.tr))

    def _render_readout(self) -> None:
        ev = self.sim.evaluation()
        self.conserved_note.set(conserved_text(self.sim, ev, self.tr))
        self.readout.set(readout_text(self.sim, ev, self.tr))


def _wrapped(values: Sequence[float], specs: Sequence[SliderSpec]) -> list[float]:
    """Angles on a (−180, 180) slider wrapped into it (the same configuration)."""
    return [(v + 180.0) % 360.0 - 180.0 if (s.lo, s.hi) == (-180.0, 180.0) else float(v) for v, s in zip(values, specs)]


def _clamped(values: Sequence[float], specs: Sequence[SliderSpec]) -> list[float]:
    """Angles wrapped to (−180, 180] where the slider is, everything clamped to the sliders."""
    return [min(max(value, spec.lo), spec.hi) for value, spec in zip(_wrapped(values, specs), specs)]


def _turn(along: Array, across: Array) -> Array:
    """The frame (columns x, y, z, a rotation (3, 3)) whose z runs along `along` and whose x along
    `across`'s part perpendicular to it (fallbacks when either is ~0 or they are parallel: world
    axes), a function of the two vectors alone."""
    length = float(np.linalg.norm(along))
    z = np.asarray(along, dtype=float) / length if length > 1e-9 else np.array([0.0, 0.0, 1.0])
    for candidate in (np.asarray(across, dtype=float), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        x = candidate - float(candidate @ z) * z
        norm = float(np.linalg.norm(x))
        if norm > 1e-6 * max(1.0, float(np.linalg.norm(candidate))):
            x = x / norm
            break
    return np.column_stack([x, np.cross(z, x), z])


def _lighter(color: tuple[int, int, int], weight: float = 0.5) -> tuple[int, int, int]:
    r, g, b = (int(round(c + weight * (255 - c))) for c in color)
    return r, g, b


class _Arrow(Vector):
    """A `Vector` whose label is drawn only if `labelled` (3D labels sparingly)."""

    def __init__(self, scene: Any, name: str, color: tuple[int, int, int], text: str, labelled: bool,
                 **kwargs: Any) -> None:
        if not labelled:
            kwargs.pop("labels", None)  # no label: nothing for the view's LabelLayer
        super().__init__(scene, name, color, text, labelled=labelled, **kwargs)
        self.labelled = labelled
        self.grid: float | None = None  # while playing, lengths are sent as multiples of this [m]
        # The shaft in two pieces of one length P: one from the start (`shaft`), one ending at the
        # head (`back`, under the tip): they cover a shaft of length S in [P, 2P] exactly (overlapping
        # in the middle), so a change of length moves the tip only; P = 2^k changes rarely.
        radius = float(kwargs.get("shaft_radius", 0.03))
        self._piece = 1.0 - self.head_length  # as built: both pieces cover the shaft of length 1
        self.back = scene.add_arrows(f"{self.tip.name}/b", np.array([[[0.0, 0.0, -1.0], [0.0, 0.0, 0.0]]]), color,
                                     shaft_radius=radius, head_radius=radius, head_length=1e-6,
                                     position=(0.0, 0.0, -self.head_length), scale=(1.0, 1.0, self._piece))
        self.shaft.scale = (1.0, 1.0, self._piece)

    def _set_length(self, length: float) -> None:
        """Draw the arrow `length` long (`Vector`'s, the shaft in two pieces: the tip moves; the
        pieces change only when the shaft's length leaves [P, 2P]).  While playing the length is
        on the grid (a float64 on a power-of-two grid ends in zero bytes: the tip's position compresses)."""
        if self.grid is not None:
            length = max(round(length / self.grid), 1) * self.grid
        super()._set_length(length)

    def _draw_shaft(self, shaft: float, head: float) -> None:
        piece = 2.0 ** math.floor(math.log2(shaft))
        if piece != self._piece:
            self._piece = piece
            set_scale(self.shaft, (1.0, 1.0, piece))
            set_scale(self.back, (1.0, 1.0, piece))
        if head != self._head_scale:  # the back piece ends where the head begins
            set_position(self.back, (0.0, 0.0, -head * self.head_length))

