"""The judges of state answers: a name -> a pure function of the answer's physics.

An answer to a State question is the body a student set in their own copy of the presenter's
scene (`AnswerState`: the scene's title, R_space_body (3, 3), ω_b (3,) [rad/s], the principal
moments [kg m²] and mgl [N m] of the model where the scene has one).  A judge is

    judge(answer: AnswerState, target: dict | None) -> (value: float | str, verdict: str)

where `value` is what the tally collects (degrees, or a class name) and `verdict` the sentence
the student reads.  `JUDGES` is the registry a question names its judge from; `judge_answer`
runs one and raises ValueError with the message to show for a judge, target or answer it
cannot use.  The physics is `physics.judging` (no app there).

* `attitude`: the angle [deg] between the answer's attitude and the target's (target
  `{"angles_deg": [φ, θ, ψ]}` z-x-z, or `{"R_space_body": 3x3}`): "12.4° from the target".
* `top_motion`: the heavy top's class of motion from its energy picture (steady precession,
  waves, loops, cusps, sleeping, too slow to sleep, through the vertical): "loops — …".
  Target (optional): `{"steady_tol_deg": 0.5}`.
* `axis_stays`: whether the torque-free body's kicked axis stays (target optional:
  `{"axis": 0|1|2, "within_deg": 20, "seconds": 10}`; axis: by default the one ω lies
  closest to): "stays" / "flips".
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from physics.judging import attitude_error_rad, axis_stays, top_motion
from physics.top_energy import CUSP, LOOP, SLEEPING, STEADY, THROUGH_VERTICAL, TOO_SLOW, WAVE

__all__ = ["AXIS_NAMES", "JUDGES", "MOTION_WORDS", "AnswerState", "Judge", "judge_answer", "state_of_room"]

AXIS_NAMES = ("x′", "y′", "z′")
MOTION_WORDS = {STEADY: "steady precession", WAVE: "waves", LOOP: "loops", CUSP: "cusps",
                SLEEPING: "sleeping", TOO_SLOW: "too slow to sleep", THROUGH_VERTICAL: "through the vertical"}
"""The class of motion (physics.top_energy) -> the word the student and the tally read."""
_ORTHO_TOL = 1e-6  # ‖Rᵀ R − 1‖ allowed in an answer's attitude
_MAX_SECONDS = 60.0  # the longest span axis_stays integrates [s]
_MAX_RATE = 1e3  # |ω| [rad/s] an answer may have


@dataclass(frozen=True)
class AnswerState:
    """A submitted body: scene title, R_space_body (3, 3) (x = R x′), omega_body (3,) ω_b
    [rad/s], inertia (I1, I2, I3) [kg m²] (about the pivot for a heavy top) or None where the
    scene has no model, mgl [N m] (0 without gravity)."""

    scene: str
    R_space_body: np.ndarray
    omega_body: np.ndarray
    inertia: tuple[float, float, float] | None = None
    mgl: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        R = np.array(self.R_space_body, dtype=float)
        omega = np.array(self.omega_body, dtype=float)
        if R.shape != (3, 3) or omega.shape != (3,) or not (np.all(np.isfinite(R)) and np.all(np.isfinite(omega))):
            raise ValueError("an answer needs a finite 3x3 attitude and a finite ω (3 numbers)")
        if np.linalg.norm(R.T @ R - np.eye(3)) > _ORTHO_TOL or np.linalg.det(R) < 0.0:
            raise ValueError("the answer's attitude is not a rotation")
        if float(np.linalg.norm(omega)) > _MAX_RATE:
            raise ValueError(f"the answer's |ω| is above {_MAX_RATE:g} rad/s")
        object.__setattr__(self, "R_space_body", R)
        object.__setattr__(self, "omega_body", omega)
        if self.inertia is not None:
            moments = tuple(float(m) for m in self.inertia)
            if len(moments) != 3 or not all(math.isfinite(m) and m > 0.0 for m in moments):
                raise ValueError("the answer's moments of inertia must be 3 positive numbers")
            object.__setattr__(self, "inertia", moments)
        if not math.isfinite(float(self.mgl)):
            raise ValueError("the answer's m g ℓ must be finite")
        object.__setattr__(self, "mgl", float(self.mgl))

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able values (for the CSV and across processes); `from_dict` reads them back."""
        return {"scene": self.scene, "R_space_body": self.R_space_body.ravel().tolist(),
                "omega_body": self.omega_body.tolist(),
                "inertia": list(self.inertia) if self.inertia is not None else None, "mgl": self.mgl}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> AnswerState:
        """The answer of `to_dict`'s values; ValueError naming what is wrong."""
        if not isinstance(data, Mapping):
            raise ValueError("an answer state is an object")
        scene = data.get("scene")
        if not isinstance(scene, str) or len(scene) > 80:
            raise ValueError("an answer state names its scene")
        try:
            R = np.array(data.get("R_space_body"), dtype=float).reshape(3, 3)
            omega = np.array(data.get("omega_body"), dtype=float).reshape(3)
            inertia_raw = data.get("inertia")
            inertia = None if inertia_raw is None else tuple(float(m) for m in inertia_raw)
            mgl = float(data.get("mgl", 0.0))
        except (TypeError, ValueError):
            raise ValueError("an answer state needs 9 numbers of attitude and 3 of ω") from None
        if inertia is not None and len(inertia) != 3:
            raise ValueError("the answer's moments of inertia must be 3 positive numbers")
        return cls(scene, R, omega, inertia, mgl)


def state_of_room(room: Any) -> AnswerState:
    """The body `room` shows now as an answer: a rigid body's simulation (`state`, `model`) or
    one that has an attitude only (`R_space_body`, as the Euler angles scene); ValueError for a
    scene whose state is not a body."""
    sim = room.sim
    title = str(getattr(room.scene, "title", "?"))
    state, model = getattr(sim, "state", None), getattr(sim, "model", None)
    if state is not None and model is not None and hasattr(state, "R_space_body"):
        return AnswerState(title, state.R_space_body, state.omega_body, tuple(model.inertia), model.mgl)
    R = getattr(sim, "R_space_body", None)
    if R is not None:
        R = R() if callable(R) else R
        return AnswerState(title, np.asarray(R, dtype=float), np.zeros(3))
    raise ValueError(f"{title} has no body to answer with")


def _number(target: Mapping[str, Any], key: str, default: float, lo: float, hi: float) -> float:
    value = target.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not lo <= float(value) <= hi:
        raise ValueError(f"the target's {key} must be a number in [{lo:g}, {hi:g}], got {value!r}")
    return float(value)


def _target_attitude(target: Mapping[str, Any] | None) -> np.ndarray:
    if not isinstance(target, Mapping):
        raise ValueError("the attitude judge needs a target: {\"angles_deg\": [φ, θ, ψ]}")
    if "angles_deg" in target:
        try:
            angles = np.array(target["angles_deg"], dtype=float).reshape(3)
        except (TypeError, ValueError):
            raise ValueError("the target's angles_deg must be 3 numbers [deg]") from None
        if not np.all(np.isfinite(angles)):
            raise ValueError("the target's angles_deg must be finite")
        return Rotation.from_euler("ZXZ", np.radians(angles)).as_matrix()
    if "R_space_body" in target:
        return AnswerState("target", np.array(target["R_space_body"], dtype=float).reshape(3, 3),
                           np.zeros(3)).R_space_body
    raise ValueError("the attitude judge's target gives angles_deg [φ, θ, ψ] or R_space_body")


def judge_attitude(answer: AnswerState, target: Mapping[str, Any] | None) -> tuple[float, str]:
    """The angle [deg] between the answer's attitude and the target's."""
    degrees = math.degrees(attitude_error_rad(answer.R_space_body, _target_attitude(target)))
    return degrees, f"{degrees:.1f}° from the target"


def judge_top_motion(answer: AnswerState, target: Mapping[str, Any] | None) -> tuple[str, str]:
    """The heavy top's class of motion (a word of MOTION_WORDS)."""
    if answer.inertia is None or answer.mgl == 0.0 or answer.inertia[0] != answer.inertia[1]:
        raise ValueError("the class of motion is judged for a heavy top (I1 = I2, m g ℓ > 0)")
    steady_tol_deg = _number(target or {}, "steady_tol_deg", 0.5, 0.0, 10.0)
    judged = top_motion(answer.inertia[0], answer.inertia[2], answer.mgl, answer.R_space_body,
                        answer.omega_body, steady_tol_rad=math.radians(steady_tol_deg))
    word = MOTION_WORDS[judged.motion]
    return word, f"{word} — {judged.picture.description}"


def judge_axis_stays(answer: AnswerState, target: Mapping[str, Any] | None) -> tuple[str, str]:
    """"stays" or "flips": the torque-free body's axis over the target's span."""
    if answer.inertia is None or answer.mgl != 0.0:
        raise ValueError("whether an axis stays is judged for a torque-free body")
    target = target or {}
    axis_value = target.get("axis")
    if axis_value is not None and (isinstance(axis_value, bool) or axis_value not in (0, 1, 2)):
        raise ValueError(f"the target's axis must be 0, 1 or 2 (x′, y′, z′), got {axis_value!r}")
    within_deg = _number(target, "within_deg", 20.0, 0.1, 179.0)
    seconds = _number(target, "seconds", 10.0, 0.1, _MAX_SECONDS)
    run = axis_stays(answer.inertia, answer.R_space_body, answer.omega_body, axis_value,
                     math.radians(within_deg), seconds)
    name = AXIS_NAMES[run.axis]
    most = math.degrees(run.max_angle_rad)
    if run.stays:
        return "stays", f"stays — the {name} axis stays within {within_deg:g}° for {seconds:g} s (at most {most:.1f}°)"
    return "flips", (f"flips — the {name} axis leaves {within_deg:g}° at t = {run.left_at_s:.1f} s "
                     f"(it turns up to {most:.0f}°)")


Judge = Callable[[AnswerState, Any], tuple[float | str, str]]
JUDGES: dict[str, Judge] = {
    "attitude": judge_attitude,
    "top_motion": judge_top_motion,
    "axis_stays": judge_axis_stays,
}
"""Judge name (a question's `judge`) -> judge (module docstring)."""


def judge_answer(name: str, answer: AnswerState, target: Any) -> tuple[float | str, str]:
    """Run the judge `name` on `answer`; ValueError with the message to show (no such judge, a
    target or an answer it cannot use)."""
    judge = JUDGES.get(name)
    if judge is None:
        raise ValueError(f"there is no judge {name!r}; choose one of {', '.join(JUDGES)}")
    try:
        return judge(answer, target)
    except (ArithmeticError, np.linalg.LinAlgError) as error:
        raise ValueError(f"this answer cannot be judged: {error}") from None
