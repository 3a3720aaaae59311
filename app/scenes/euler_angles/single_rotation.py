"""The Euler-angles scene's single rotation D = exp(A), A = Φ hat(d) (memo 1.1-1.3): its nodes,
its panel folder, its readout and its animation (`SingleRotationPart`, owned by the view).

Drawn with the toggle `Single rotation` (off by default): the axis d (a near-black line through
the origin, both ways, its head at +d) and the angle Φ (an arc about d, in the plane through the
origin perpendicular to d, from the projection of the space axis e_k most perpendicular to d to
D of it, which is the projection of the body axis e_k′; the two spokes in the colours of e_k and
e_k′).  Read out (`readouts.single_rotation_text`): Φ, d, A = Φ hat(d), the rotation vector Φ d
and the quaternion.  At Φ = 0 (below `physics.so3.AXIS_UNDEFINED_ANGLE`) no axis is drawn and
the readout says the axis is undefined; within `HALF_TURN_BAND` of Φ = π the axis comes from
(D + 1)/2 = d dᵀ with the sign nearer the last axis drawn (`physics.so3.single_rotation`), so
sliders through half turns do not flip it.

The animation: switching the toggle on, or the `Animate` button, turns two outlines of the box
from the space axes to D over ANIMATION_SECONDS: a dark one by exp(s Φ hat(d)), s = 0 → 1 (the
single turn), and beside it a coloured one through the three Euler steps z-x-z (in the colours
of the φ, θ, ψ arcs: purple while φ turns about z, pink for θ about the line of nodes, teal for
ψ about z′); both end on the body, stay ANIMATION_HOLD seconds and go.  Their legend rides on
them (a label on each outline, the coloured one naming its step) and is written in the folder
while they are drawn.  The animation is this
view's (a presenter's is seen by the followers); it follows D if the angles move meanwhile.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import viser

from app.i18n import N_, Translator, translator
from app.kit.core.common import BODY_AXIS_COLORS, SPACE_AXIS_COLORS, Wrap, axis_segments, polyline_segments
from app.kit.core.target import DrawTarget
from app.kit.draw.labels import AXES, LabelLayer
from app.kit.panel.gui import Readout
from app.scenes.euler_angles.readouts import single_angle_text, single_rotation_text
from app.scenes.euler_angles.simulation import EulerAnglesSimulation, box_edges
from app.viser_internals import set_points, set_position, set_wxyz
from physics.quaternion import wxyz_from_matrix
from physics.so3 import SingleRotation, exp_so3, rot_x, rot_z, single_rotation, turn_path

ENGLISH = translator("en")

__all__ = ["ANIMATION_HOLD", "ANIMATION_SECONDS", "ARC_SEGMENTS", "SINGLE_ARC_RADIUS", "SingleRotationPart",
           "arc_reference_axis", "box_outline_segments"]

SINGLE_COLOR = (40, 40, 40)  # the axis d, the arc Φ and the single-turn outline: near black
SINGLE_AXIS_HALF_LENGTH = 2.3  # [scene units] d is drawn from -this to +this, past the space axes
SINGLE_ARC_RADIUS = 1.6  # [scene units] outside the φ θ ψ arcs (at most 1.2)
ARC_SEGMENTS = 48  # segments of the Φ arc
ARC_HYSTERESIS = 0.25  # the Φ arc keeps its space axis e_k until another is this much more perpendicular to d
ANIMATION_SECONDS = 4.0  # [s] of wall time: the outlines turn from 1 to D
ANIMATION_HOLD = 1.5  # [s] they then stay on the body, and go
TURN_LEGEND = "dark: one turn sΦ about d"  # the label on the single-turn outline
ZXZ_LEGENDS = ("coloured: z-x-z, now φ about z", "coloured: z-x-z, now θ about the line of nodes",
               "coloured: z-x-z, now ψ about z′")  # the label on the z-x-z outline, step by step
PANEL_LEGEND = N_("**The two outlines:** dark, one turn by sΦ about d (s = 0 → 1); coloured, the z-x-z "
                "steps: φ about z (purple), θ about the line of nodes (pink), ψ about z′ (teal).")


def arc_reference_axis(axis: np.ndarray, previous: int | None = None) -> int:
    """Index k of the space axis e_k the Φ arc starts from: the one most perpendicular to the
    unit axis d (3,) (smallest |d_k|), except that `previous` is kept while it is within
    ARC_HYSTERESIS of the best (near a tie, as for d = (1, 1, 1)/√3, the arc does not jump)."""
    magnitudes = np.abs(np.asarray(axis, dtype=float))
    best = int(np.argmin(magnitudes))
    if previous is not None and magnitudes[previous] <= magnitudes[best] + ARC_HYSTERESIS:
        return previous
    return best


def box_outline_segments(edges: Sequence[float] | np.ndarray, axis_length: float) -> np.ndarray:
    """The 12 edges of a box centred at the origin with edge lengths `edges` (3,) along x y z,
    then its three axes from the origin, `axis_length` long: segments (15, 2, 3)."""
    half = 0.5 * np.asarray(edges, dtype=float)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float) * half
    lines = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    box = np.array([[corners[a], corners[b]] for a, b in lines])
    return np.concatenate([box, axis_segments(np.eye(3), axis_length)])


def _outline_colors(color: tuple[int, int, int]) -> np.ndarray:
    """Colours (15, 2, 3) of `box_outline_segments`: the box in `color`, the axes x′ y′ z′."""
    colors = np.empty((15, 2, 3), dtype=np.uint8)
    colors[:12] = color
    colors[12:] = np.array(BODY_AXIS_COLORS, dtype=np.uint8)[:, None, :]
    return colors


class SingleRotationPart:
    """The single rotation of one view: nodes under `{root}/d`, the panel folder, the readout and
    the animation (see the module docstring).

    `step_colors` are the three colours of the z-x-z outline's steps (φ, θ, ψ), `outline_axis_length`
    [scene units] the length of the outlines' axes.  Built in two steps at the view's places:
    the nodes here, the folder by `build_gui`; `connect` hooks up the controls.
    """

    def __init__(self, client: DrawTarget, root: str, labels: LabelLayer, sim: EulerAnglesSimulation,
                 step_colors: Sequence[tuple[int, int, int]], outline_axis_length: float) -> None:
        self.client = client
        self.sim = sim
        self._labels = labels
        self._step_colors = tuple(step_colors)
        self._outline_axis_length = outline_axis_length
        self._single: tuple[int, SingleRotation] | None = None  # (sim version, D as one turn)
        self._last_axis: np.ndarray | None = None  # the axis d last drawn (its sign is kept near Φ = π)
        self._arc_axis: int | None = None  # k of the space axis e_k the Φ arc starts from
        self.animation_time: float | None = None  # [s] into the animation; None: not animating
        self._zxz_step = -1
        scene = client.scene
        single = f"{root}/d"
        self.node = scene.add_frame(single, show_axes=False, visible=False)
        self.axis = scene.add_arrows(f"{single}/d", np.zeros((1, 2, 3)), SINGLE_COLOR, shaft_radius=0.014,
                                     head_radius=0.06, head_length=0.14)
        self.axis_label = labels.add(scene.add_label(f"{single}/dl", "d", font_screen_scale=1.8,
                                                     anchor="center-center"), AXES)
        self.arc = scene.add_line_segments(f"{single}/a", np.zeros((ARC_SEGMENTS + 2, 2, 3)),
                                           np.zeros((ARC_SEGMENTS + 2, 2, 3), dtype=np.uint8),
                                           thickness=4.0, thickness_units="screen")
        self.arc_label = labels.add(scene.add_label(f"{single}/al", "Φ", font_screen_scale=1.6,
                                                    anchor="center-center"), AXES)
        self.ghost_turn = scene.add_frame(f"{single}/g1", show_axes=False, visible=False)
        self.ghost_zxz = scene.add_frame(f"{single}/g3", show_axes=False, visible=False)
        outline = box_outline_segments(box_edges(sim.moments), outline_axis_length)
        self.ghost_turn_lines = scene.add_line_segments(f"{single}/g1/l", outline,
                                                        _outline_colors(SINGLE_COLOR), thickness=3.0,
                                                        thickness_units="screen")
        self.ghost_zxz_lines = scene.add_line_segments(f"{single}/g3/l", outline,
                                                       _outline_colors(self._step_colors[0]), thickness=3.0,
                                                       thickness_units="screen")
        self._outline_moments = sim.moments
        # The legend on the outlines themselves: a label at the tip of each one's x′ (single turn)
        # or y′ (z-x-z) axis, moved with it (`draw_animation`).
        self._legend_tip = 1.15 * outline_axis_length
        self.ghost_turn_label = labels.add(scene.add_label(
            f"{single}/t1", TURN_LEGEND, font_screen_scale=1.3, anchor="bottom-left", visible=False),
            AXES, wanted=False)
        self.ghost_zxz_label = labels.add(scene.add_label(
            f"{single}/t3", ZXZ_LEGENDS[0], font_screen_scale=1.3, anchor="bottom-left", visible=False),
            AXES, wanted=False)

    def build_gui(self, tr: Translator = ENGLISH) -> Any:
        """The folder "Single rotation D = exp(Φ hat d)": the toggle, Animate and the readout
        (hidden while the toggle is off), in the language of `tr`; returns the folder."""
        gui = self.client.gui
        _ = tr.gettext
        self.folder = gui.add_folder(_("Single rotation D = exp(Φ hat d)"))
        with self.folder:
            self.gui_toggle = gui.add_checkbox(
                _("Single rotation"), False,
                hint=_("D as one turn by Φ about the unit axis d (memo 1.1-1.3); switching it on animates once"))
            self.gui_animate = gui.add_button(
                _("Animate"), icon=viser.Icon.PLAYER_PLAY,
                hint=_("two outlines turn from the space axes to D: dark, by sΦ about d (s = 0 → 1); "
                       "coloured, z-x-z in three steps (φ purple, θ pink, ψ teal)"))
            self.gui_legend = gui.add_markdown(_(PANEL_LEGEND), visible=False)
            self.readout = Readout(gui)
            self.readout.handle.visible = False
        return self.folder

    def connect(self, wrap: Wrap, refresh: Callable[[], None]) -> None:
        """The toggle starts (or stops) the animation, then `refresh`es the view; Animate animates."""
        def toggled() -> None:
            if self.gui_toggle.value:
                self.animate()
            else:
                self.stop_animation()
            refresh()

        self.gui_toggle.on_update(wrap("single rotation", lambda _event: toggled()))
        self.gui_animate.on_click(wrap("animate", lambda _event: self.animate()))

    @property
    def on(self) -> bool:
        """Whether the toggle is on."""
        return bool(self.gui_toggle.value)

    def rotation(self) -> SingleRotation:
        """D as one turn (`physics.so3.single_rotation`), computed once per simulation version,
        the sign of d near Φ = π the one nearer the axis last drawn."""
        if self._single is None or self._single[0] != self.sim.version:
            rotation = single_rotation(self.sim.R_space_body, self._last_axis)
            if rotation.axis is not None:
                self._last_axis = rotation.axis
            self._single = (self.sim.version, rotation)
        return self._single[1]

    def reshape(self) -> None:
        """The outlines' box for the simulation's moments (sent only when they changed)."""
        if self.sim.moments != self._outline_moments:
            outline = box_outline_segments(box_edges(self.sim.moments), self._outline_axis_length)
            self.ghost_turn_lines.points = outline
            self.ghost_zxz_lines.points = outline
            self._outline_moments = self.sim.moments

    def render(self) -> None:
        """The axis d (both ways from the origin) and the arc Φ about it, if the toggle is on and
        D has an axis (Φ > 0)."""
        on = self.on
        rotation = self.rotation() if on else None
        shown = rotation is not None and rotation.axis is not None
        if self.node.visible != on:
            self.node.visible = on
        for node in (self.axis, self.arc):
            if node.visible != shown:
                node.visible = shown
        for label in (self.axis_label, self.arc_label):
            self._labels.want(label, shown)  # the view's LabelLayer shows it where there is room
        if rotation is None or rotation.axis is None:
            return
        d = rotation.axis
        set_points(self.axis, np.array([[-SINGLE_AXIS_HALF_LENGTH * d, SINGLE_AXIS_HALF_LENGTH * d]],
                                       dtype=np.float32))
        tip = (SINGLE_AXIS_HALF_LENGTH + 0.25) * d
        set_position(self.axis_label, (float(tip[0]), float(tip[1]), float(tip[2])))
        k = arc_reference_axis(d, self._arc_axis)
        if k != self._arc_axis:
            self._arc_axis = k
            colors = np.empty((ARC_SEGMENTS + 2, 2, 3), dtype=np.uint8)
            colors[:ARC_SEGMENTS] = SINGLE_COLOR
            colors[ARC_SEGMENTS] = SPACE_AXIS_COLORS[k]
            colors[ARC_SEGMENTS + 1] = BODY_AXIS_COLORS[k]
            self.arc.colors = colors
        e_k = np.eye(3)[k]
        u = e_k - float(d @ e_k) * d  # e_k projected on the plane ⟂ d
        u *= SINGLE_ARC_RADIUS / float(np.linalg.norm(u))
        points = turn_path(d, rotation.angle, u, ARC_SEGMENTS)  # u, ..., D u
        spokes = np.array([[np.zeros(3), points[0]], [np.zeros(3), points[-1]]])
        set_points(self.arc, np.concatenate([polyline_segments(points), spokes]).astype(np.float32))
        middle = 0.8 * points[ARC_SEGMENTS // 2]  # inside the arc: clear of the d label at the axis tip
        set_position(self.arc_label, (float(middle[0]), float(middle[1]), float(middle[2])))
        text = single_angle_text(rotation.angle)
        if self.arc_label.text != text:
            self.arc_label.text = text

    def render_readout(self) -> None:
        """Φ, d, A = Φ hat(d), the rotation vector and the quaternion (shown with the toggle)."""
        on = self.on
        if self.readout.handle.visible != on:
            self.readout.handle.visible = on
        if not on:
            return
        self.readout.set(single_rotation_text(self.rotation(), self.sim.R_space_body))

    # ------------------------------------------------------------------ the animation
    def animate(self) -> None:
        """Run the animation from s = 0 (switching the toggle on if it is off, which starts it)."""
        if not self.gui_toggle.value:
            self.gui_toggle.value = True  # its callback comes back here
            return
        self.animation_time = 0.0
        self._zxz_step = -1
        self.draw_animation()

    def advance(self, dt: float) -> None:
        """The animation `dt` [s] on (nothing if it is not running)."""
        if self.animation_time is not None:
            self.animation_time += dt
            with self.client.atomic():
                self.draw_animation()

    def stop_animation(self) -> None:
        self.animation_time = None
        for node in (self.ghost_turn, self.ghost_zxz):
            if node.visible:
                node.visible = False
        self._show_legend(False)

    def _show_legend(self, shown: bool) -> None:
        """The outlines' legend: their labels (through the view's LabelLayer) and the panel's line."""
        for label in (self.ghost_turn_label, self.ghost_zxz_label):
            self._labels.want(label, shown)
        legend = getattr(self, "gui_legend", None)
        if legend is not None and legend.visible != shown:
            legend.visible = shown

    def draw_animation(self) -> None:
        """The two outlines at the animation's time: exp(s Φ hat(d)) and the z-x-z turn, where
        s = time / ANIMATION_SECONDS (at most 1); gone after ANIMATION_HOLD more seconds."""
        time = self.animation_time
        if time is None:
            return
        if time >= ANIMATION_SECONDS + ANIMATION_HOLD or not self.gui_toggle.value:
            self.stop_animation()
            return
        s = min(time / ANIMATION_SECONDS, 1.0)
        rotation = self.rotation()
        phi, theta, psi = self.sim.angles
        steps = [min(max(3.0 * s - k, 0.0), 1.0) for k in range(3)]  # φ, then θ, then ψ
        R_zxz = rot_z(steps[0] * phi) @ rot_x(steps[1] * theta) @ rot_z(steps[2] * psi)
        step = min(int(3.0 * s), 2)
        if step != self._zxz_step:
            self._zxz_step = step
            self.ghost_zxz_lines.colors = _outline_colors(self._step_colors[step])
            self.ghost_zxz_label.text = ZXZ_LEGENDS[step]
            self._show_legend(True)
        R_turn = exp_so3(s * rotation.rotvec)
        set_wxyz(self.ghost_turn, wxyz_from_matrix(R_turn))
        set_wxyz(self.ghost_zxz, wxyz_from_matrix(R_zxz))
        for label, tip in ((self.ghost_turn_label, R_turn[:, 0]), (self.ghost_zxz_label, R_zxz[:, 1])):
            point = self._legend_tip * tip
            set_position(label, (float(point[0]), float(point[1]), float(point[2])))
        for node in (self.ghost_turn, self.ghost_zxz):
            if not node.visible:
                node.visible = True
