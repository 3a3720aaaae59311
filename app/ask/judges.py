"""The judges of State questions: a name -> a pure function of the answer's physics.

`JUDGES` maps a judge's name (a State question's `judge`) to a function
`judge(question: State, answer: Mapping[str, Any]) -> Judged`: the judged quantity of a student's
state answer (a number with its unit, or a class such as "loops") and the words the student and
the tally see.

`check_state(question, value)` checks a state answer as it arrives (size and shape only): a flat
mapping of at most MAX_STATE_KEYS names to finite numbers (or short texts), at most
MAX_STATE_BYTES long; the judging is done by the round (`app.ask.round.Round.answer`).

A state answer is the body a student set in their own copy of the presenter's scene,
`AnswerState` (the scene's title, R_space_body (3, 3), ω_b (3,) [rad/s], the principal moments
[kg m²] and mgl [N m] of the model where the scene has one), sent as the flat mapping of
`AnswerState.to_dict`: `scene`, `R0` ... `R8` (R row by row), `w1 w2 w3` (ω_b), `I1 I2 I3`, `mgl`.
`state_of_room(room)` reads it off a room.  The physics is `physics.judging` (no app there):

* `attitude`: the angle [deg] between the answer's attitude and the target's (target
  `{"angles_deg": [φ, θ, ψ]}` z-x-z, or `{"R_space_body": 3x3}`; `within_deg` (default 10)
  for `good`): "12.4° from the target".
* `top_motion`: the heavy top's class of motion from its energy picture (steady precession,
  waves, loops, cusps, sleeping, too slow to sleep, through the vertical): "loops — …".
  Target (optional): `{"motion": "loops"}` (the class wanted, for `good`), `{"steady_tol_deg": 0.5}`.
* `axis_stays`: whether the torque-free body's kicked axis stays (target optional:
  `{"axis": 0|1|2, "within_deg": 20, "seconds": 10, "stays": true|false}`; axis: by default the
  one ω lies closest to): "stays" / "flips".

A judge raises ValueError with the message to show for an answer it cannot judge (another
scene's body, a target it cannot use): the round refuses such an answer.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from app.i18n import N_
from physics.judging import attitude_error_rad, axis_stays, top_motion
from physics.top_energy import CUSP, LOOP, SLEEPING, STEADY, THROUGH_VERTICAL, TOO_SLOW, WAVE

__all__ = ["AXIS_NAMES", "AXIS_WORDS", "FLIPS", "JUDGES", "MAX_STATE_BYTES", "MAX_STATE_KEYS", "MOTION_WORDS",
           "READERS", "STAYS", "AnswerState", "Judged", "check_state", "check_target", "judge", "judge_answer",
           "read_state", "state_of_room"]

MAX_STATE_KEYS = 64
MAX_STATE_BYTES = 4096  # the answer's repr
MAX_TEXT_CHARS = 80


@dataclass(frozen=True)
class Judged:
    """A judged state answer: `value` the judged quantity (a float in `unit`, or a class name such
    as "loops"), `words` what the student and the tally read ("attitude error 4.2°"), `good` True
    when it meets the question's target (None: no right answer)."""

    value: float | str
    words: str
    unit: str = ""
    good: bool | None = None




READERS: dict[str, Callable[[Any], dict[str, Any]]] = {}
"""scene title -> reader(simulation) -> the state answer of a room of that scene (names to numbers);
a scene without one answers its time only (`read_state`)."""


def read_state(room: Any) -> dict[str, Any]:
    """The state answer of a browser's own `room` (`app.kit.core.room.Room`): its scene's reader's;
    else its body (`state_of_room(room).to_dict()`: attitude, ω_b, moments, mgl) and its time t
    [s]; else {"t": t}."""
    reader = READERS.get(room.scene.title)
    if reader is not None:
        return reader(room.sim)
    try:
        return {**state_of_room(room).to_dict(), "t": float(room.sim.t)}
    except ValueError:
        return {"t": float(room.sim.t)}


def check_state(question: Any, value: Any) -> dict[str, Any]:
    """A state answer as a plain dict (names to finite floats or short texts); ValueError otherwise."""
    if not isinstance(value, Mapping) or not value:
        raise ValueError("a state answer is a non-empty object of names and numbers")
    if len(value) > MAX_STATE_KEYS or len(repr(value)) > MAX_STATE_BYTES:
        raise ValueError(f"a state answer holds at most {MAX_STATE_KEYS} numbers ({MAX_STATE_BYTES} bytes)")
    out: dict[str, Any] = {}
    for key, item in value.items():
        if not isinstance(key, str) or not 0 < len(key) <= 40:
            raise ValueError("a state answer's names are short texts")
        if isinstance(item, bool) or not isinstance(item, int | float | str):
            raise ValueError(f"{key}: a number wanted")
        if isinstance(item, str):
            if len(item) > MAX_TEXT_CHARS:
                raise ValueError(f"{key}: at most {MAX_TEXT_CHARS} characters")
            out[key] = item
        elif not math.isfinite(float(item)):
            raise ValueError(f"{key}: a finite number wanted")
        else:
            out[key] = float(item)
    return out


def judge(question: Any, value: Mapping[str, Any]) -> Judged | None:
    """`value` judged by the question's judge, or None (no judge, or an unknown one)."""
    if question.judge is None:
        return None
    fn = JUDGES.get(question.judge)
    return None if fn is None else fn(question, value)


AXIS_NAMES = ("x′", "y′", "z′")
MOTION_WORDS = {STEADY: N_("steady precession"), WAVE: N_("waves"), LOOP: N_("loops"), CUSP: N_("cusps"),
                SLEEPING: N_("sleeping"), TOO_SLOW: N_("too slow to sleep"),
                THROUGH_VERTICAL: N_("through the vertical")}
"""The class of motion (physics.top_energy) -> the word the student and the tally read."""
STAYS, FLIPS = N_("stays"), N_("flips")
AXIS_WORDS = (STAYS, FLIPS)
"""The axis judge's classes (its `Judged.value`: English, as kept; the tally writes them in the reader's language)."""
_ORTHO_TOL = 1e-6  # ‖Rᵀ R − 1‖ allowed in an answer's attitude
_MAX_SECONDS = 60.0  # the longest span axis_stays integrates [s]
_MAX_RATE = 1e3  # |ω| [rad/s] an answer may have


@dataclass(frozen=True, eq=False)
class AnswerState:
    """A submitted body: scene title, R_space_body (3, 3) (x = R x′), omega_body (3,) ω_b
    [rad/s], inertia (I1, I2, I3) [kg m²] (about the pivot for a heavy top) or None where the
    scene has no model, mgl [N m] (0 without gravity)."""

    scene: str
    R_space_body: np.ndarray
    omega_body: np.ndarray
    inertia: tuple[float, float, float] | None = None
    mgl: float = 0.0

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

    def __eq__(self, other: object) -> bool:
        """The same scene, model and state, bit for bit."""
        if not isinstance(other, AnswerState):
            return NotImplemented
        return (self.scene, self.inertia, self.mgl) == (other.scene, other.inertia, other.mgl) and (
            np.array_equal(self.R_space_body, other.R_space_body) and np.array_equal(self.omega_body, other.omega_body))

    __hash__ = None  # type: ignore[assignment]  # equal answers compare their arrays: not hashable

    def to_dict(self) -> dict[str, Any]:
        """The flat mapping a student's browser sends (module docstring): `scene`, `R0`...`R8`,
        `w1 w2 w3`, and `I1 I2 I3`, `mgl` where the body has a model; `from_dict` reads it back."""
        out: dict[str, Any] = {"scene": self.scene}
        out.update({f"R{k}": float(v) for k, v in enumerate(self.R_space_body.ravel())})
        out.update({f"w{k + 1}": float(v) for k, v in enumerate(self.omega_body)})
        if self.inertia is not None:
            out.update({f"I{k + 1}": float(v) for k, v in enumerate(self.inertia)})
            out["mgl"] = self.mgl
        return out

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> AnswerState:
        """The answer of `to_dict`'s mapping; ValueError naming what is wrong."""
        if not isinstance(data, Mapping):
            raise ValueError("a state answer is an object")
        scene = data.get("scene")
        if not isinstance(scene, str) or not 0 < len(scene) <= MAX_TEXT_CHARS:
            raise ValueError("a state answer names its scene")

        def numbers(keys: list[str]) -> list[float]:
            values = [data.get(key) for key in keys]
            if any(isinstance(v, bool) or not isinstance(v, int | float) for v in values):
                raise ValueError(f"a state answer needs the numbers {' '.join(keys)}")
            return [float(v) for v in values]  # type: ignore[arg-type]

        R = np.array(numbers([f"R{k}" for k in range(9)])).reshape(3, 3)
        omega = np.array(numbers(["w1", "w2", "w3"]))
        has_model = any(key in data for key in ("I1", "I2", "I3", "mgl"))
        inertia = tuple(numbers(["I1", "I2", "I3"])) if has_model else None
        mgl = numbers(["mgl"])[0] if has_model else 0.0
        return cls(scene, R, omega, inertia, mgl)  # type: ignore[arg-type]


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


def _target_of(name: str, target: Any) -> dict[str, Any]:
    """`target` checked for the judge `name` and its defaults filled in (ValueError naming the field)."""
    if target is not None and not isinstance(target, Mapping):
        raise ValueError("target: an object wanted")
    target = dict(target or {})
    unknown = sorted(str(key) for key in set(target) - set(_TARGET_KEYS[name]))
    if unknown:
        raise ValueError(f"target: {unknown[0]!r} is not a field of the {name} judge "
                         f"({', '.join(_TARGET_KEYS[name])})")
    out: dict[str, Any] = {}
    if name == "attitude":
        out["R_space_body"] = _target_attitude(target or None)
        out["within_deg"] = _number(target, "within_deg", 10.0, 0.0, 180.0)
    elif name == "top_motion":
        out["steady_tol_deg"] = _number(target, "steady_tol_deg", 0.5, 0.0, 10.0)
        wanted = target.get("motion")
        if wanted is not None and wanted not in MOTION_WORDS.values():
            raise ValueError(f"target: motion must be one of {', '.join(MOTION_WORDS.values())}, got {wanted!r}")
        out["motion"] = wanted
    else:
        axis_value = target.get("axis")
        if axis_value is not None and (isinstance(axis_value, bool) or axis_value not in (0, 1, 2)):
            raise ValueError(f"target: axis must be 0, 1 or 2 (x′, y′, z′), got {axis_value!r}")
        wanted = target.get("stays")
        if wanted is not None and not isinstance(wanted, bool):
            raise ValueError("target: stays must be true or false")
        out.update(axis=axis_value, stays=wanted, within_deg=_number(target, "within_deg", 20.0, 0.1, 179.0),
                   seconds=_number(target, "seconds", 10.0, 0.1, _MAX_SECONDS))
    return out


def check_target(name: str, target: Any) -> None:
    """ValueError naming the field when `target` is not one the judge `name` can use (a
    question's target, checked when the question is made: a lesson file at start)."""
    if name not in _TARGET_KEYS:
        raise ValueError(f"there is no judge {name!r}; choose one of {', '.join(_TARGET_KEYS)}")
    _target_of(name, target)


def judge_attitude(answer: AnswerState, target: Mapping[str, Any] | None) -> Judged:
    """The angle [deg] between the answer's attitude and the target's; good within `within_deg`."""
    checked = _target_of("attitude", target)
    degrees = math.degrees(attitude_error_rad(answer.R_space_body, checked["R_space_body"]))
    return Judged(degrees, f"{degrees:.1f}° from the target", "deg", degrees <= checked["within_deg"])


def judge_top_motion(answer: AnswerState, target: Mapping[str, Any] | None) -> Judged:
    """The heavy top's class of motion (a word of MOTION_WORDS); good when it is the target's
    `motion` (None without one)."""
    checked = _target_of("top_motion", target)
    if answer.inertia is None or answer.mgl == 0.0 or answer.inertia[0] != answer.inertia[1]:
        raise ValueError("the class of motion is judged for a heavy top (I1 = I2, m g ℓ > 0)")
    judged = top_motion(answer.inertia[0], answer.inertia[2], answer.mgl, answer.R_space_body,
                        answer.omega_body, steady_tol_rad=math.radians(checked["steady_tol_deg"]))
    word = MOTION_WORDS[judged.motion]
    wanted = checked["motion"]
    return Judged(word, f"{word} — {judged.picture.description}", "", None if wanted is None else word == wanted)


def judge_axis_stays(answer: AnswerState, target: Mapping[str, Any] | None) -> Judged:
    """"stays" or "flips": the torque-free body's axis over the target's span; good when it is
    the target's `stays` (None without one)."""
    checked = _target_of("axis_stays", target)
    if answer.inertia is None or answer.mgl != 0.0:
        raise ValueError("whether an axis stays is judged for a torque-free body")
    within_deg, seconds, wanted = checked["within_deg"], checked["seconds"], checked["stays"]
    run = axis_stays(answer.inertia, answer.R_space_body, answer.omega_body, checked["axis"],
                     math.radians(within_deg), seconds)
    name = AXIS_NAMES[run.axis]
    most = math.degrees(run.max_angle_rad)
    good = None if wanted is None else run.stays == wanted
    if run.stays:
        words = f"stays — the {name} axis stays within {within_deg:g}° for {seconds:g} s (at most {most:.1f}°)"
        return Judged(STAYS, words, "", good)
    return Judged(FLIPS, f"flips — the {name} axis leaves {within_deg:g}° at t = {run.left_at_s:.1f} s "
                           f"(it turns up to {most:.0f}°)", "", good)


_TARGET_KEYS = {
    "attitude": ("angles_deg", "R_space_body", "within_deg"),
    "top_motion": ("motion", "steady_tol_deg"),
    "axis_stays": ("axis", "within_deg", "seconds", "stays"),
}


StateJudge = Callable[[AnswerState, Any], Judged]
_STATE_JUDGES: dict[str, StateJudge] = {
    "attitude": judge_attitude,
    "top_motion": judge_top_motion,
    "axis_stays": judge_axis_stays,
}


def judge_answer(name: str, answer: AnswerState, target: Any) -> Judged:
    """Run the judge `name` on `answer` against `target`; ValueError with the message to show
    (no such judge, a target or an answer it cannot use)."""
    state_judge = _STATE_JUDGES.get(name)
    if state_judge is None:
        raise ValueError(f"there is no judge {name!r}; choose one of {', '.join(_STATE_JUDGES)}")
    try:
        return state_judge(answer, target)
    except (ArithmeticError, np.linalg.LinAlgError) as error:
        raise ValueError(f"this answer cannot be judged: {error}") from None


def _registered(name: str) -> Callable[[Any, Mapping[str, Any]], Judged]:
    def judge_state(question: Any, value: Mapping[str, Any]) -> Judged:
        answer = AnswerState.from_dict(value)
        scene = getattr(question, "scene", None)
        if scene is not None and answer.scene != scene:
            raise ValueError(f"this question is about the {scene} scene; the answer is a {answer.scene} body")
        return judge_answer(name, answer, getattr(question, "target", None))

    judge_state.__name__ = f"judge_{name}"
    judge_state.__doc__ = _STATE_JUDGES[name].__doc__
    return judge_state


JUDGES: dict[str, Callable[[Any, Mapping[str, Any]], Judged]] = {name: _registered(name) for name in _STATE_JUDGES}
"""name -> judge(question: app.ask.questions.State, answer mapping) -> Judged (module docstring)."""
