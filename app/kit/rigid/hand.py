"""Setting a rigid body's motion by hand: gizmos at the tips of ω (and L) and the Kick buttons.

`HandControls` belongs to one `app.kit.rigid.view.RigidBodyView` (Free body, Heavy top, and
Poinsot through Free body) and adds, in the Setup tab, the folder "Set ω by hand":

* **Gizmos** (translation only) at the tip of the ω arrow, and of the L arrow where the scene
  asks for it (`RigidBodyView.hand_gizmos`).  They go into `view.controls` only: the scene of
  the browser that controls the room, never a shared scene (app.kit.core.target); with no controls
  (a recording) there are none.  They show while the room is paused (dragging one also
  pauses it) and the "Drag ω" checkbox is on.  Dragging the ω gizmo to p [scene units] sets
  ω_s = p / omega_scale, ω_b = Rᵀ ω_s; the L gizmo sets L_s = p / L_scale, ω_b = I⁻¹ Rᵀ L_s.
  The run restarts from the current attitude with that ω (as the rate sliders do: t = 0,
  paused), the sliders follow, and the arrows keep their scale until the drag ends.
* **Kick**: an impulse J [N m s] (a bound slider) and the buttons x′ y′ z′: a short torque
  impulse J e_k about a body axis adds Δω_b = I⁻¹ (J e_k) (`omega_after_kick`) to the current
  state, and the run goes on from there (a new run at t = 0, playing if it was).  Kick about
  the largest and smallest axes, then the middle one, to show which rotations are stable.

Refused with a message, nothing changed: a non-finite position or impulse, an impulse outside
its slider's range, an axis that is not x′ y′ z′, and an ω whose rate sliders would be out of
their range (at gimbal lock, where the Euler rates are undefined, |ω| above GIMBAL_OMEGA_MAX).
"""

from __future__ import annotations

import functools
import math
from typing import Any, Protocol

import numpy as np

from app.i18n import N_, Said, Translator, Words, written
from app.kit.core.common import SliderSpec
from app.kit.panel.gui import add_slider
from physics._types import Vec3
from physics.dynamics import State
from physics.euler import GimbalLockError

__all__ = ["AXES", "GIMBAL_OMEGA_MAX", "KICK_SPEC", "HandControls", "omega_after_kick"]

AXES = ("x′", "y′", "z′")
KICK_SPEC = SliderSpec("kick", N_("Kick J [N m s]"), -5.0, 5.0, 0.01,
                       N_("the torque impulse of a kick, about the body axis chosen below"),
                       ((-5.0, "-5"), (0.0, "0"), (5.0, "5")))
GIMBAL_OMEGA_MAX = 50.0  # [rad/s] the largest |ω| set by hand where the Euler rates are undefined
GIZMO_SCALE = 0.45  # [scene units] the gizmos' size


def omega_after_kick(inertia: tuple[float, float, float], omega_body: Vec3, axis: int, impulse: float) -> Vec3:
    """ω_b [rad/s] (3,) after a short torque impulse `impulse` [N m s] about the body axis `axis`
    (0, 1, 2 = x′ y′ z′): ΔL_b = J e_k, Δω_b = I⁻¹ ΔL_b (principal moments `inertia` [kg m²]);
    the attitude does not change during the short impulse."""
    omega = np.array(omega_body, dtype=float)
    omega[axis] += impulse / float(inertia[axis])
    return omega


class HandView(Protocol):
    """What `HandControls` needs of its view (`app.kit.rigid.view.RigidBodyView` is one; a
    protocol, so the kit's modules import each other in one direction only)."""

    sim: Any  # app.kit.rigid.simulation.RigidBodySimulation
    room: Any  # app.kit.core.room.Room
    root: str
    controls: Any  # the controlling browser's scene, or None
    message: Any  # app.kit.panel.gui.MessageLine
    tr: Translator  # the browser's words
    omega_scale: float
    L_scale: float
    gizmos_hidden: bool
    @property
    def hand_gizmos(self) -> tuple[str, ...]: ...

    @property
    def rate_specs(self) -> tuple[Any, ...]: ...
    _wrap: Any

    def rates_from_state(self, angles: Any, state: Any) -> tuple[float, ...]: ...

    def fit_arrows(self) -> None: ...

    def bind(self, handle: Any, where: str, apply: Any, current: Any, spec: Any = None, check: Any = None) -> Any: ...


class HandControls:
    """The gizmos and the Kick of one rigid-body view (see the module docstring).

    Attributes:
        gizmos: "omega" (and "L") -> the transform-controls handle (empty without controls).
        dragging: the gizmo being dragged, or None.
        impulse: the kick's J [N m s].
        last_change: (ω_b before, ω_b after) [rad/s] of the last drag or kick applied, or None.
    """

    def __init__(self, view: HandView, gui: Any) -> None:
        self.view = view
        self.dragging: str | None = None
        self.impulse = 0.5
        self.last_change: tuple[np.ndarray, np.ndarray] | None = None
        self.gizmos: dict[str, Any] = {}
        _ = view.tr.gettext
        self.kick_spec = KICK_SPEC.translated(view.tr)
        with gui.add_folder(_("Set ω by hand"), expand_by_default=False):
            if "L" in view.hand_gizmos:
                label, hint = _("Drag ω and L"), _("when paused: a gizmo at the tip of ω and L sets ω")
            else:
                label, hint = _("Drag ω"), _("when paused: a gizmo at the tip of ω sets ω")
            self.gui_show = gui.add_checkbox(label, True, hint=hint)
            self.gui_impulse = add_slider(gui, self.kick_spec, self.impulse)
            self.gui_kick = gui.add_button_group(_("Kick about"), AXES)
        view.bind(self.gui_impulse, "kick impulse", self._set_impulse, lambda: self.impulse, spec=self.kick_spec)
        self.gui_kick.on_click(view._wrap("kick", lambda event: self.kick(event.target.value, self.impulse)))
        self.gui_show.on_update(view._wrap("drag ω", lambda _event: self.refresh()))
        controls = view.controls  # interactive handles only in the controlling browser's own scene
        if controls is not None:
            for kind in view.hand_gizmos:
                gizmo = controls.add_transform_controls(
                    f"{view.root}/hand/{kind}", scale=GIZMO_SCALE, disable_rotations=True, depth_test=False,
                    opacity=0.85, visible=False)
                gizmo.on_update(view._wrap(f"{kind} gizmo", lambda event, k=kind: self._gizmo_event(k, event)))
                self.gizmos[kind] = gizmo

    # ------------------------------------------------------------------ drawing
    def tip(self, kind: str) -> np.ndarray:
        """Where the arrow `kind` ("omega" or "L") ends [scene units] (3,)."""
        view = self.view
        R, omega = view.sim.state.R_space_body, view.sim.state.omega_body
        if kind == "omega":
            return np.asarray(R @ omega * view.omega_scale, dtype=float)
        return np.asarray(R @ (np.asarray(view.sim.model.inertia) * omega) * view.L_scale, dtype=float)

    def refresh(self) -> None:
        """Show the gizmos at the tips while paused (the one being dragged stays under the mouse)."""
        shown = bool(self.gui_show.value) and not self.view.room.playing and not self.view.gizmos_hidden
        for kind, gizmo in self.gizmos.items():
            if gizmo.visible != shown:
                gizmo.visible = shown
            if shown and kind != self.dragging:
                position = tuple(float(x) for x in self.tip(kind))
                if tuple(gizmo.position) != position:
                    gizmo.position = position

    # ------------------------------------------------------------------ edits
    def refusal(self, omega_body: Vec3) -> str | None:
        """Why ω_b cannot be set (not finite, a rate slider out of range) in the view's language, or None."""
        words = self.refused_words(omega_body)
        return None if words is None else written(words, self.view.tr)

    def refused_words(self, omega_body: Vec3) -> Words | None:
        """Why ω_b cannot be set now, as words for any language (a function of a translator), or None."""
        view = self.view
        if not np.all(np.isfinite(omega_body)):
            return Said(N_("ω = {omega} refused: not finite."), omega=repr(omega_body))
        state = State(view.sim.state.R_space_body, omega_body, 0.0)
        try:
            rates = view.rates_from_state(view.sim.angles, state)
        except GimbalLockError:
            norm = float(np.linalg.norm(omega_body))
            return functools.partial(_gimbal_refusal, norm) if norm > GIMBAL_OMEGA_MAX else None
        for spec, rate in zip(view.rate_specs, rates):
            if spec.check(rate) is None:
                return functools.partial(_rate_refusal, spec, float(rate))
        return None

    def set_omega_body(self, omega_body: Vec3, what: Words) -> bool:
        """Restart the run from the current attitude with ω_b [rad/s] (3,), keeping the room's
        transport; False (and a message "what: why", in the browser's language, nothing changed) if refused."""
        view = self.view
        omega_body = np.asarray(omega_body, dtype=float)
        refusal = self.refused_words(omega_body)
        if refusal is not None:
            view.message.show(functools.partial(_what_refused, what, refusal))
            return False
        sim = view.sim
        sim.preset = None
        self.last_change = (sim.state.omega_body.copy(), omega_body.copy())
        sim.restart(State(sim.state.R_space_body, omega_body, 0.0), angles=sim.angles)
        view.message.clear()
        view.room.refresh()
        return True

    def _set_impulse(self, value: float) -> None:
        self.impulse = float(value)

    def kick(self, axis: Any, impulse: Any) -> bool:
        """Kick about the body axis `axis` ("x′", "y′", "z′" or 0, 1, 2) with J = impulse [N m s];
        False (and a message) if refused."""
        view = self.view
        k = AXES.index(axis) if axis in AXES else axis if axis in (0, 1, 2) else None
        if k is None:
            view.message.show(Said(N_("Kick about {axis} refused: the axes are {axes}."), axis=repr(axis),
                                   axes=", ".join(AXES)))
            return False
        J = KICK_SPEC.check(impulse)
        if J is None:
            view.message.show(functools.partial(_spec_refusal, KICK_SPEC, impulse))
            return False
        omega = omega_after_kick(view.sim.model.inertia, view.sim.state.omega_body, int(k), J)
        return self.set_omega_body(omega, functools.partial(_kick_words, J, AXES[int(k)]))

    def _gizmo_event(self, kind: str, event: Any) -> None:
        """viser's gizmo callback: event.phase is "start", "update" or "end" of a drag."""
        phase = getattr(event, "phase", "update")
        if phase == "start":
            self._drag_start(kind)
        elif phase == "end":
            self._drag_end()
        else:
            self._dragged(kind)

    def _drag_start(self, kind: str) -> None:
        self.dragging = kind
        self.view.room.playing = False

    def _dragged(self, kind: str) -> None:
        view = self.view
        gizmo = self.gizmos[kind]
        try:
            p = np.array([float(x) for x in gizmo.position])
        except (TypeError, ValueError):
            p = np.full(3, math.nan)
        R = view.sim.state.R_space_body
        if kind == "omega":
            omega_body = R.T @ p / view.omega_scale
        else:
            omega_body = (R.T @ p / view.L_scale) / np.asarray(view.sim.model.inertia)
        held, self.dragging = self.dragging, kind  # an update without its drag start (a raw client)
        try:
            view.room.playing = False
            self.set_omega_body(omega_body, Said(N_("{arrow} dragged"), arrow="ω" if kind == "omega" else "L"))
        finally:
            self.dragging = held if held is not None else None

    def _drag_end(self) -> None:
        self.dragging = None
        self.view.fit_arrows()
        self.view.room.refresh()


# ------------------------------------------------------------------ words said in the message line
def _what_refused(what: Words, refusal: Words, tr: Translator) -> str:
    """"what: why" in `tr`'s language (the hand's refused edit)."""
    return f"{written(what, tr)}: {written(refusal, tr)}"


def _gimbal_refusal(norm: float, tr: Translator) -> str:
    return tr.gettext(N_("|ω| = {norm} rad/s refused: at most {most} rad/s near gimbal lock.")).format(
        norm=f"{norm:.3g}", most=tr.general(GIMBAL_OMEGA_MAX))


def _rate_refusal(spec: Any, rate: float, tr: Translator) -> str:
    """A rate slider's range refused (`spec` its English `SliderSpec`, `rate` the value it would take)."""
    return tr.gettext(N_("{label} would be {rate}, outside its range {lo} to {hi}: refused.")).format(
        label=tr.gettext(spec.label), rate=f"{rate:.4g}", lo=tr.general(spec.lo), hi=tr.general(spec.hi))


def _spec_refusal(spec: SliderSpec, value: Any, tr: Translator) -> str:
    """A slider's value refused, in `tr`'s language (`SliderSpec.refusal`)."""
    return spec.translated(tr).refusal(value)


def _kick_words(J: float, axis: str, tr: Translator) -> str:  # noqa: N803 - J is the impulse's symbol
    return tr.gettext(N_("Kick J = {J} N m s about {axis}")).format(J=tr.general(J), axis=axis)
