"""The judges of State questions: the hook the physics fills in.

`JUDGES` maps a judge's name (a State question's `judge`) to a function
`judge(question: State, answer: Mapping[str, Any]) -> Judged`: the judged quantity of a student's
state answer (a number with its unit, or a class such as "loops") and the words the student and
the tally see.  It is empty here; the state questions' module registers its judges in it.

`check_state(question, value)` checks a state answer as it arrives (size and shape only): a flat
mapping of at most MAX_STATE_KEYS names to finite numbers (or short texts), at most
MAX_STATE_BYTES long; the judging is done by the round (`app.ask.round.Round.answer`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["JUDGES", "MAX_STATE_BYTES", "MAX_STATE_KEYS", "READERS", "Judged", "check_state", "judge", "read_state"]

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


JUDGES: dict[str, Callable[[Any, Mapping[str, Any]], Judged]] = {}
"""name -> judge(question: app.ask.questions.State, answer) -> Judged (questions import this module)."""


READERS: dict[str, Callable[[Any], dict[str, Any]]] = {}
"""scene title -> reader(simulation) -> the state answer of a room of that scene (names to numbers);
a scene without one answers its time only (`read_state`)."""


def read_state(room: Any) -> dict[str, Any]:
    """The state answer of a browser's own `room` (`app.kit.core.room.Room`): its scene's reader's, or {"t": t}."""
    reader = READERS.get(room.scene.title)
    if reader is not None:
        return reader(room.sim)
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
