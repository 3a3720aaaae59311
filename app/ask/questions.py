"""Questions to the class, as data: three frozen kinds and the one checker of their dicts.

- `Choice(prompt, options, correct)`: 2..MAX_OPTIONS options; `correct` an index or None (no
  right answer, e.g. an opinion or a prediction that is revealed by playing).  An answer is an
  option's index (int).
- `Direction(prompt, truth, frame)`: a direction in 3D, answered as a unit 3-vector in `frame`
  ("space": the scene's space axes, z up); `truth` the right answer as a unit 3-vector or None.
- `State(prompt, scene, judge, target)`: the student answers with a state of their own copy of
  the room (`Explore`); `scene` the scene's title the question is about, `judge` a name of
  `app.ask.judges.JUDGES` (or None: only collected), `target` the judge's parameters (JSON-like
  dict, or None).  What a state answer is, and how it is judged, is the judges' module's.

`question_from_dict(d)` is the one way a lesson step or an automation call becomes a question: it
checks everything and raises ValueError with a message that names the field.  `question_to_dict`
is its inverse (the wire between processes, the CSV's header).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["KINDS", "MAX_OPTIONS", "MAX_OPTION_CHARS", "MAX_PROMPT_CHARS", "MIN_OPTIONS", "Choice", "Direction",
           "Question", "State", "question_from_dict", "question_to_dict", "unit_vector"]

MIN_OPTIONS = 2
MAX_OPTIONS = 6
MAX_PROMPT_CHARS = 300
MAX_OPTION_CHARS = 80
MAX_TARGET_BYTES = 4096  # a State's target, as its JSON-like repr, at most this long
FRAMES = ("space",)


def unit_vector(value: Any, where: str = "direction") -> tuple[float, float, float]:
    """`value` (three finite numbers, not all zero) normalized to a unit 3-vector; ValueError otherwise."""
    if isinstance(value, str | bytes) or not hasattr(value, "__len__") or len(value) != 3:
        raise ValueError(f"{where}: three numbers wanted, got {_short(value)}")
    try:
        x, y, z = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: three numbers wanted, got {_short(value)}") from None
    if any(isinstance(v, bool) for v in value) or not all(map(math.isfinite, (x, y, z))):
        raise ValueError(f"{where}: three finite numbers wanted, got {_short(value)}")
    norm = math.sqrt(x * x + y * y + z * z)
    if norm < 1e-9:
        raise ValueError(f"{where}: a direction needs a nonzero vector")
    return x / norm, y / norm, z / norm


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _prompt(value: Any) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ValueError("prompt: the question's words are missing")
    if len(value) > MAX_PROMPT_CHARS:
        raise ValueError(f"prompt: at most {MAX_PROMPT_CHARS} characters (got {len(value)})")
    return value.strip()


@dataclass(frozen=True)
class Choice:
    """A question with 2..6 options; an answer is an option's index."""

    prompt: str
    options: tuple[str, ...]
    correct: int | None = None
    kind = "choice"

    def __post_init__(self) -> None:
        object.__setattr__(self, "prompt", _prompt(self.prompt))
        options = self.options
        if isinstance(options, str) or not isinstance(options, tuple | list):
            raise ValueError("options: a list of 2 to 6 texts wanted")
        if not MIN_OPTIONS <= len(options) <= MAX_OPTIONS:
            raise ValueError(f"options: {MIN_OPTIONS} to {MAX_OPTIONS} options wanted (got {len(options)})")
        cleaned = []
        for k, option in enumerate(options):
            if not isinstance(option, str) or not option.strip():
                raise ValueError(f"options[{k}]: a text wanted")
            if len(option) > MAX_OPTION_CHARS:
                raise ValueError(f"options[{k}]: at most {MAX_OPTION_CHARS} characters")
            cleaned.append(option.strip())
        if len(set(cleaned)) != len(cleaned):
            raise ValueError("options: two options are the same")
        object.__setattr__(self, "options", tuple(cleaned))
        correct = self.correct
        if correct is not None and (isinstance(correct, bool) or not isinstance(correct, int)
                                    or not 0 <= correct < len(cleaned)):
            raise ValueError(f"correct: an option's index 0..{len(cleaned) - 1} or none, got {_short(correct)}")

    def check(self, value: Any) -> int:
        """An answer as an option's index; ValueError for anything else."""
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < len(self.options):
            raise ValueError(f"an option's number 0..{len(self.options) - 1} wanted, got {_short(value)}")
        return int(value)


@dataclass(frozen=True)
class Direction:
    """A direction in 3D; an answer is a unit 3-vector in `frame` ("space")."""

    prompt: str
    truth: tuple[float, float, float] | None = None
    frame: str = "space"
    kind = "direction"

    def __post_init__(self) -> None:
        object.__setattr__(self, "prompt", _prompt(self.prompt))
        if self.truth is not None:
            object.__setattr__(self, "truth", unit_vector(self.truth, "truth"))
        if self.frame not in FRAMES:
            raise ValueError(f"frame: one of {', '.join(FRAMES)} wanted, got {_short(self.frame)}")

    def check(self, value: Any) -> tuple[float, float, float]:
        """An answer as a unit 3-vector (normalized); ValueError for anything else."""
        return unit_vector(value, "answer")


@dataclass(frozen=True)
class State:
    """A state of the student's own copy of the room; judged by `judge` (a name of
    `app.ask.judges.JUDGES`) against `target` when it is not None."""

    prompt: str
    scene: str
    judge: str | None = None
    target: Mapping[str, Any] | None = None
    kind = "state"

    def __post_init__(self) -> None:
        object.__setattr__(self, "prompt", _prompt(self.prompt))
        if not isinstance(self.scene, str) or not self.scene.strip():
            raise ValueError("scene: a scene's title wanted")
        if self.judge is not None:
            from app.ask.judges import JUDGES

            if not isinstance(self.judge, str) or (JUDGES and self.judge not in JUDGES):
                raise ValueError(f"judge: {_short(self.judge)} is not a judge ({', '.join(JUDGES) or 'none known'})")
        if self.target is not None:
            if not isinstance(self.target, Mapping) or len(repr(self.target)) > MAX_TARGET_BYTES:
                raise ValueError("target: a small object wanted")
            object.__setattr__(self, "target", dict(self.target))
        if self.judge is not None:
            from app.ask.judges import check_target

            check_target(self.judge, self.target)  # the target is one the judge can use

    def __hash__(self) -> int:
        return hash((self.prompt, self.scene, self.judge, repr(self.target)))

    def check(self, value: Any) -> Any:
        """An answer as the judges' module takes it (`app.ask.judges.check_state`); ValueError otherwise."""
        from app.ask.judges import check_state

        return check_state(self, value)


Question = Choice | Direction | State
KINDS = ("choice", "direction", "state")


def question_from_dict(d: Any) -> Question:
    """A question from its dict (a lesson step's "ask", an automation call, the bus):

        {"kind": "choice", "prompt": "...", "options": ["a", "b"], "correct": 1}
        {"kind": "direction", "prompt": "...", "truth": [0, 0, 1]}        # truth optional
        {"kind": "state", "prompt": "...", "scene": "Heavy top", "judge": "...", "target": {...}}

    A question object is returned as it is.  ValueError naming the field for anything wrong."""
    if isinstance(d, Choice | Direction | State):
        return d
    if not isinstance(d, Mapping):
        raise ValueError(f"a question is an object with a kind, got {_short(d)}")
    kind = d.get("kind")
    fields = {"choice": {"kind", "prompt", "options", "correct"},
              "direction": {"kind", "prompt", "truth", "frame"},
              "state": {"kind", "prompt", "scene", "judge", "target"}}
    if kind not in fields:
        raise ValueError(f"kind: one of {', '.join(KINDS)} wanted, got {_short(kind)}")
    unknown = sorted(str(key) for key in set(d) - fields[kind])
    if unknown:
        raise ValueError(f"{unknown[0]}: not a field of a {kind} question ({', '.join(sorted(fields[kind]))})")
    if kind == "choice":
        options = d.get("options")
        if not isinstance(options, list | tuple):
            raise ValueError("options: a list of 2 to 6 texts wanted")
        return Choice(d.get("prompt"), tuple(options), d.get("correct"))  # type: ignore[arg-type]
    if kind == "direction":
        truth = d.get("truth")
        return Direction(d.get("prompt"), None if truth is None else unit_vector(truth, "truth"),  # type: ignore[arg-type]
                         d.get("frame", "space"))
    return State(d.get("prompt"), d.get("scene"), d.get("judge"), d.get("target"))  # type: ignore[arg-type]


def question_to_dict(question: Question) -> dict[str, Any]:
    """The dict `question_from_dict` reads back into an equal question (plain JSON values)."""
    if isinstance(question, Choice):
        return {"kind": "choice", "prompt": question.prompt, "options": list(question.options),
                "correct": question.correct}
    if isinstance(question, Direction):
        return {"kind": "direction", "prompt": question.prompt,
                "truth": None if question.truth is None else list(question.truth), "frame": question.frame}
    return {"kind": "state", "prompt": question.prompt, "scene": question.scene, "judge": question.judge,
            "target": None if question.target is None else dict(question.target)}
