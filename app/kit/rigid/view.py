"""The view of a rigid-body simulation (free body, heavy top) for one browser.

`RigidBodyView` draws a `RigidBodySimulation` with the kit's widgets (stage, body, line of
nodes, ω and L) and the kit's panel (transport, presets, Setup / Readout / Plots tabs), and
turns the browser's edits into calls on its room.  A scene subclasses it and fills in the
class attributes and hooks (the model of its parameters, the initial ω from its rate sliders,
its body's shape, its extras); see `app.kit.rigid.torque_free` and `app.scenes.heavy_top`.
In three layers: `app.kit.rigid.scene.RigidBodyScene` (what a scene declares, its simulation
from presets), `app.kit.rigid.panel.RigidBodyPanel` (the panel and its edits) and here the
drawing.

Per frame (`frame`) the view sends only what changed: the body's pose, the line of nodes, the
ω arrow (L only when it moved), the scene's extras, at display resolution
(`app.kit.draw.widgets.POSE_QUANTUM`: what did not change at it is not sent); nothing at all while
paused.  Only for what is on screen: the sliders follow the motion (Setup tab) and the status
line at 2 Hz, the readout (Readout tab) at 10 Hz, the plots and the accuracy panel at 4 Hz
(Plots tab, live plots on).

The exact ghost (Display: "Exact ghost") is `app.kit.rigid.ghost.ExactGhost`; the texts (status,
readout, Lagrange tab, accuracy, legend) are pure functions of the simulation in
`app.kit.rigid.text`.  On the ω plot the exact solution's flips (ω along the intermediate axis
changing sign, a free body with three different moments) are vertical grey segments, at the
times `physics.poinsot.flip_times` gives.

Sliders follow the motion without feedback (`SceneView.quiet`).  A user's edit of an angle or rate
slider pauses the room and restarts the run (t = 0) from the sliders' values.  Bad input
never stops the motion: out-of-range values are refused and the slider goes back; moments
that are not a body (InertiaError) are refused with a message while the last valid body moves.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import viser

from app.kit.core.common import L_COLOR, OMEGA_COLOR, Throttle, Wrap
from app.kit.core.room import Room
from app.kit.draw.widgets import NODES_LABELS, POSE_QUANTUM, Body, LineOfNodes, Stage, Vector, quantized
from app.kit.rigid.ghost import ExactGhost
from app.kit.rigid.lagrange_arrows import GeneralizedForceArrows
from app.kit.rigid.panel import ANGLE_SPECS, PLOT_PERIOD, READOUT_PERIOD, SLIDER_PERIOD, STATUS_PERIOD, RigidBodyPanel
from app.kit.rigid.simulation import RigidBodySimulation
from app.kit.rigid.text import legend_text
from app.viser_internals import set_wxyz
from physics._types import Vec3
from physics.dynamics import Model

__all__ = ["ANGLE_SPECS", "SLIDER_PERIOD", "RigidBodyView", "tilt_matrix", "tilt_wxyz"]

ARROW_RANGE = (0.5, 2.6)  # [scene units] an arrow outside this at a restart is rescaled


def tilt_wxyz(phi: float, theta: float) -> tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) of the φ-θ frame Rz(φ) Rx(θ) (angles [rad]): its x axis
    is the line of nodes, its z axis the body's z′."""
    cp, sp = math.cos(0.5 * phi), math.sin(0.5 * phi)
    ct, st = math.cos(0.5 * theta), math.sin(0.5 * theta)
    return (cp * ct, cp * st, sp * st, sp * ct)


def tilt_matrix(phi: float, theta: float) -> np.ndarray:
    """Rz(φ) Rx(θ) (3, 3) (angles [rad]), the rotation of `tilt_wxyz`."""
    cp, sp, ct, st = math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta)
    return np.array([[cp, -sp * ct, sp * st], [sp, cp * ct, -cp * st], [0.0, st, ct]])



class RigidBodyView(RigidBodyPanel):
    """One browser's view of a room with a `RigidBodySimulation`: what its scene declares
    (`app.kit.rigid.scene.RigidBodyScene`: a scene subclasses this class and fills those in),
    its panel (`app.kit.rigid.panel.RigidBodyPanel`) and, here, its construction, its 3D
    drawing and the per-frame update."""

    # ------------------------------------------------------------------ construction
    def __init__(self, client: viser.ClientHandle, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        super().__init__(client, room, wrap, report_error)
        self.sim: RigidBodySimulation = room.sim
        self.track_points(self.sim)
        self._drawn_version = -1
        self._drawn_restarts = -1
        self._drawn_model: Model | None = None
        self._drawn_preset: str | None = None
        self.omega_scale = 0.3  # [scene units per rad/s]
        self.L_scale = 0.3  # [scene units per kg m²/s]
        self._slider_throttle = Throttle(SLIDER_PERIOD)
        self._readout_throttle = Throttle(READOUT_PERIOD)
        self._status_throttle = Throttle(STATUS_PERIOD)
        self._plot_throttle = Throttle(PLOT_PERIOD)
        self.ghost: ExactGhost
        self._rates_shown: tuple[float, ...] | None = None
        self.build()

    def _build_scene(self) -> None:
        scene = self.client.scene
        root = self.root
        labels = self.labels
        Stage(scene, root, grid_z=self.grid_z, labels=labels)
        model = self.sim.model
        tilt = self.tilt_frame
        self._tilt_node = scene.add_frame(f"{root}/tilt", show_axes=False) if tilt else None
        self._tilt_wxyz: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)  # as sent
        parent = f"{root}/tilt" if tilt else root
        self.body = Body(scene, f"{parent}/b", lambda s, parent: self.build_shape(s, parent, model),
                         axis_length=self.body_axis_length, labels=labels)
        self._drawn_model = model
        defined, undefined = (self.tr.gettext(text) for text in NODES_LABELS)
        self.nodes = LineOfNodes(scene, f"{parent}/nodes", labels=labels, riding=tilt, text=(defined, undefined))
        self.omega = Vector(scene, f"{parent}/w", OMEGA_COLOR, "ω", labels=labels,
                            label_at_middle=self.omega_label_at_middle)
        self.L = Vector(scene, f"{parent}/L", L_COLOR, "L", labels=labels)
        # The Lagrange tab: the torque M and its projections Q_φ e_z, Q_θ e_n, Q_ψ e_z′ (6.10).
        self.q_arrows = GeneralizedForceArrows(scene, root, labels)
        self.build_extras()

    def frame(self, dt: float) -> None:
        """The per-frame update: poses and arrows if the state changed; throttled text."""
        sim = self.sim
        with self.client.atomic():
            if sim.version != self._drawn_version:
                if sim.restarts != self._drawn_restarts or sim.model != self._drawn_model:
                    self._restarted()
                self._drawn_version = sim.version
                self.quantum = POSE_QUANTUM if self.room.playing else None
                try:
                    self._draw()
                finally:
                    self.quantum = None
            self.labels.update(dt)
            if not self.room.playing:
                return
            if self._slider_throttle.ready(dt) and self.tabs.shown == "Setup":
                self._sync_state_sliders()
                self._refresh_gimbal_note()
            if self._status_throttle.ready(dt):
                self._refresh_status()
                self.ghost.refresh_note()
            if self._readout_throttle.ready(dt) and self.tabs.shown in ("Readout", "Lagrange"):
                self._refresh_readout()
            if self._plot_throttle.ready(dt) and self.tabs.shown == "Plots":
                self._push_plots()

    def refresh(self) -> None:
        """Everything at once (after an edit, a step, a restart; never per frame)."""
        sim = self.sim
        with self.client.atomic():
            if sim.restarts != self._drawn_restarts or sim.model != self._drawn_model:
                self._restarted()
            self._drawn_version = sim.version
            self.nodes.visible = bool(self.gui_show_nodes.value)
            self.body.show_axes(bool(self.gui_show_body_axes.value))
            self.omega.enabled = bool(self.gui_show_omega.value)
            self.L.enabled = bool(self.gui_show_L.value)
            self._draw()
            self._sync_state_sliders()
            self.show_values(self.gui_params, self.param_specs, self.params_from_model(sim.model))
            self.transport.show(self.room.playing, self.room.time_scale, sim.integrator)
            self._refresh_status()
            self.ghost.refresh_note()
            self._refresh_gimbal_note()
            if self.tabs.shown in ("Readout", "Lagrange"):
                self._refresh_readout()
            self.q_arrows.show(self.tabs.shown == "Lagrange")
            self.plots.set_visible(bool(self.gui_live_plots.value))
            if self.tabs.shown == "Plots":
                self._push_plots()
            if self.hand is not None:
                self.hand.refresh()
            self.labels.settle()

    # ------------------------------------------------------------------ drawing
    def _restarted(self) -> None:
        """A new run (or a new body) in the simulation: reshape, rescale, clear the history."""
        sim = self.sim
        if sim.model != self._drawn_model:
            model = sim.model
            self.body.reshape(lambda scene, parent: self.build_shape(scene, parent, model))
            self.gui_param_status.content = self.shape_status(model)
            self._drawn_model = model
            self.ghost.reshape(model)
        preset = getattr(sim, "preset", None)
        R, omega = sim.state.R_space_body, sim.state.omega_body
        if (preset is not None and preset != self._drawn_preset or not self._arrows_fit(R, omega)) \
                and not (self.hand is not None and self.hand.dragging):  # the scale holds during a drag
            self._rescale_arrows(R, omega)
        self._drawn_preset = preset
        self.presets_row.show_note(self.preset_shown())
        self._drawn_restarts = sim.restarts
        self.restart_extras()

    def _draw(self) -> None:
        """Poses and arrows of the current state: only what changed is sent."""
        sim = self.sim
        R = sim.state.R_space_body
        omega_body = sim.state.omega_body
        quantum = self.quantum
        phi, theta = float(sim.angles[0]), float(sim.angles[1])
        if self._tilt_node is not None:  # R = R_tilt R_spin: ω and L in the φ-θ frame's components
            R_tilt = tilt_matrix(phi, theta)
            wxyz = tilt_wxyz(phi, theta)
            if quantum is not None:
                wxyz = quantized(wxyz, quantum)  # type: ignore[assignment]
            if wxyz != self._tilt_wxyz:
                self._tilt_wxyz = wxyz
                set_wxyz(self._tilt_node, wxyz)
            R = R_tilt.T @ R  # R_spin: a turn about z′ (exactly, up to rounding)
        self.body.pose(R, quantum)
        self.nodes.update(phi, theta, quantum)
        self.omega.update(R @ omega_body * self.omega_scale, quantum=quantum)
        L_parent = R @ (np.asarray(sim.model.inertia) * omega_body)
        self.L.update(L_parent * self.L_scale, rtol=1e-6, quantum=quantum)
        self.ghost.draw(quantum)
        self.draw_extras(sim)

    def fit_arrows(self) -> None:
        """Rescale the arrows if the current ω or L is outside ARROW_RANGE (after a drag)."""
        R, omega = self.sim.state.R_space_body, self.sim.state.omega_body
        if not self._arrows_fit(R, omega):
            self._rescale_arrows(R, omega)

    def _arrows_fit(self, R: np.ndarray, omega_body: Vec3) -> bool:
        lo, hi = ARROW_RANGE
        fixed = self.fixed_omega_scale()
        if fixed is not None and fixed != self.omega_scale:
            return False
        w = 0.0 if fixed is not None else float(np.linalg.norm(omega_body)) * self.omega_scale
        L = float(np.linalg.norm(np.asarray(self.sim.model.inertia) * omega_body)) * self.L_scale
        return (w == 0.0 or lo <= w <= hi) and (L == 0.0 or lo <= L <= hi)

    def _rescale_arrows(self, R: np.ndarray, omega_body: Vec3) -> None:
        w = float(np.linalg.norm(omega_body))
        L = float(np.linalg.norm(np.asarray(self.sim.model.inertia) * omega_body))
        self.omega_scale = self.arrow_lengths[0] / w if w > 0.0 else self.omega_scale
        fixed = self.fixed_omega_scale()
        if fixed is not None:
            self.omega_scale = fixed
        self.L_scale = self.arrow_lengths[1] / L if L > 0.0 else self.L_scale
        self.gui_legend.content = legend_text(bool(self.sim.model.mgl), self.omega_scale, self.L_scale, self.tr)
