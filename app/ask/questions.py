"""Questions to the class, as data: each kind one frozen class behind one protocol
(`QuestionKind`), registered once by its name in `KINDS`.

- `Choice(prompt, options, correct)`: 2..MAX_OPTIONS options; `correct` an index or None (no
  right answer, e.g. an opinion or a prediction that is revealed by playing).  An answer is an
  option's index (int).
- `Direction(prompt, truth, frame)`: a direction in 3D, answered as a unit 3-vector in `frame`
  ("space": the scene's space axes, z up); `truth` the right answer as a unit 3-vector or None.
- `State(prompt, scene, judge, target)`: the student answers with a state of their own copy of
  the room (`Explore`); `scene` the scene's title the question is about, `judge` a name of
  `app.ask.judges.JUDGES` (or None: only collected), `target` the judge's parameters (JSON-like
  dict, or None).  What a state answer is, and how it is judged, is the judges' module's.
- `Number(prompt, value, unit, tolerance)`: a number with a unit ("the flip period in s"); an
  answer is a finite float, right when |answer - value| <= tolerance (value None: only collected).

A kind says everything that differs between kinds: `check` (an answer as kept), `to_dict` /
`from_dict`, `tally_fields` (its part of a `Tally`), `tally_text` (the presenter's Markdown),
`csv_row` / `csv_head`, `answer_words` (a student's own answer).  The panels' side of a kind
(the presenter's form fields, the student's widget) is `app.hall.ask_kinds`, keyed by the same name.

`question_from_dict(d)` is the one way a lesson step or an automation call becomes a question: it
checks everything and raises ValueError with a message that names the field.  `question_to_dict`
is its inverse (the wire between processes, the CSV's header).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Protocol

from app.ask.tally_text import TallyView as Tally
from app.i18n import N_
from physics.refusal import Refusal

if TYPE_CHECKING:
    from app.ask.judges import Judged

__all__ = ["DIRECTION_RIGHT_DEG", "KINDS", "MAX_NUMBER", "MAX_OPTIONS", "MAX_OPTION_CHARS", "MAX_PROMPT_CHARS",
           "MIN_OPTIONS", "Choice", "Direction", "Number", "Question", "QuestionKind", "QuestionRefused", "State",
           "finite_number",
           "question_from_dict", "question_to_dict", "unit_vector"]

MIN_OPTIONS = 2
MAX_OPTIONS = 6
MAX_PROMPT_CHARS = 300
MAX_OPTION_CHARS = 80
MAX_TARGET_BYTES = 4096  # a State's target, as its JSON-like repr, at most this long
FRAMES = ("space",)
MAX_NUMBER = 1e12  # a Number question's value, tolerance and answers are at most this in size
MAX_UNIT_CHARS = 20
BAR_CHARS = 16  # the longest bar of a histogram (text)


class QuestionRefused(Refusal):
    """A question (or an answer) that is not one: a ValueError naming the field (`where`), its
    English words a msgid template with its fields (said in a reader's language by
    `app.i18n.refusal_text`)."""


def finite_number(value: Any, where: str = "answer") -> float:
    """`value` (an int or float, not a bool or a text) as a finite float of size at most
    MAX_NUMBER; ValueError naming `where` otherwise (NaN, inf, 1e400, "3")."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise QuestionRefused(N_("{where}: a number wanted, got {got}"), where=where, got=_short(value))
    try:
        number = float(value)
    except OverflowError:
        raise QuestionRefused(N_("{where}: a number of size at most {most} wanted, got a huge one"), where=where,
                              most=f"{MAX_NUMBER:g}") from None
    if not math.isfinite(number):
        raise QuestionRefused(N_("{where}: a finite number wanted, got {got}"), where=where, got=_short(value))
    if abs(number) > MAX_NUMBER:
        raise QuestionRefused(N_("{where}: a number of size at most {most} wanted, got {got}"), where=where,
                              most=f"{MAX_NUMBER:g}", got=f"{number:g}")
    return number


DIRECTION_RIGHT_DEG = 15.0  # [deg] a direction answer within this of the true one is right (a task's score)


def _plain(words: str) -> str:
    """Markdown answer words without their bold marks."""
    return words.replace("**", "")


class QuestionKind(Protocol):
    """What every kind of question is (one class each, registered in `KINDS` by `kind`)."""

    kind: ClassVar[str]
    FIELDS: ClassVar[frozenset[str]]  # the keys of its dict
    prompt: str

    def check(self, value: Any) -> Any:
        """An answer as kept (a checked, plain value); ValueError with the student's message otherwise."""
        ...

    def judged(self, value: Any) -> Judged | None:
        """A checked answer's judgement kept beside it (a State's), or None."""
        ...

    @property
    def has_truth(self) -> bool:
        """The question has a right answer the presenter can reveal."""
        ...

    def to_dict(self) -> dict[str, Any]:
        """The dict `from_dict` (and `question_from_dict`) reads back into an equal question."""
        ...

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Any:
        """The question from its dict (keys already checked against FIELDS); ValueError naming a field."""
        ...

    def tally_fields(self, values: Sequence[Any], judged: Sequence[Judged | None]) -> dict[str, Any]:
        """Its part of a `Tally` (keyword arguments) from the checked answers."""
        ...

    def tally_text(self, tally: Tally, revealed: bool) -> str:
        """The presenter's tally in words (Markdown); the right answer marked once `revealed`."""
        ...

    def csv_head(self) -> str:
        """Comment lines of the CSV after the question's own ("" or lines ending in a newline)."""
        ...

    def csv_row(self, value: Any, judged: Judged | None) -> dict[str, Any]:
        """An answer's own columns of the CSV (`Round.CSV_COLUMNS`)."""
        ...

    def answer_words(self, value: Any) -> str:
        """A student's own answer in words (Markdown)."""
        ...

    def verdict(self, value: Any) -> tuple[float | None, str]:
        """(score, words) of a checked answer, as a task's judge says it: 1.0 right, 0.0 wrong,
        None not judged (no right answer: collected); plain words ("2.4 s: right")."""
        ...


def unit_vector(value: Any, where: str = "direction") -> tuple[float, float, float]:
    """`value` (three finite numbers, not all zero) normalized to a unit 3-vector; ValueError otherwise."""
    if isinstance(value, str | bytes) or not hasattr(value, "__len__") or len(value) != 3:
        raise QuestionRefused(N_("{where}: three numbers wanted, got {got}"), where=where, got=_short(value))
    try:
        x, y, z = (float(v) for v in value)
    except (TypeError, ValueError):
        raise QuestionRefused(N_("{where}: three numbers wanted, got {got}"), where=where,
                              got=_short(value)) from None
    if any(isinstance(v, bool) for v in value) or not all(map(math.isfinite, (x, y, z))):
        raise QuestionRefused(N_("{where}: three finite numbers wanted, got {got}"), where=where, got=_short(value))
    norm = math.sqrt(x * x + y * y + z * z)
    if norm < 1e-9:
        raise QuestionRefused(N_("{where}: a direction needs a nonzero vector"), where=where)
    return x / norm, y / norm, z / norm


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _prompt(value: Any) -> str:
    if not isinstance(value, str) or not value.strip():
        raise QuestionRefused(N_("{where}: the question's words are missing"), where="prompt")
    if len(value) > MAX_PROMPT_CHARS:
        raise QuestionRefused(N_("{where}: at most {most} characters (got {count})"), where="prompt",
                              most=MAX_PROMPT_CHARS, count=len(value))
    return value.strip()


def _no_judgement(self: Any, value: Any) -> Judged | None:
    """No judgement is kept beside this kind's answers."""
    return None


@dataclass(frozen=True)
class Choice:
    """A question with 2..6 options; an answer is an option's index."""

    prompt: str
    options: tuple[str, ...]
    correct: int | None = None
    kind: ClassVar[str] = "choice"
    FIELDS: ClassVar[frozenset[str]] = frozenset({"kind", "prompt", "options", "correct"})

    def __post_init__(self) -> None:
        object.__setattr__(self, "prompt", _prompt(self.prompt))
        options = self.options
        if isinstance(options, str) or not isinstance(options, tuple | list):
            raise QuestionRefused(N_("{where}: a list of {least} to {most} texts wanted"), where="options",
                                  least=MIN_OPTIONS, most=MAX_OPTIONS)
        if not MIN_OPTIONS <= len(options) <= MAX_OPTIONS:
            raise QuestionRefused(N_("{where}: {least} to {most} options wanted (got {count})"), where="options",
                                  least=MIN_OPTIONS, most=MAX_OPTIONS, count=len(options))
        cleaned = []
        for k, option in enumerate(options):
            if not isinstance(option, str) or not option.strip():
                raise ValueError(f"options[{k}]: a text wanted")
            if len(option) > MAX_OPTION_CHARS:
                raise ValueError(f"options[{k}]: at most {MAX_OPTION_CHARS} characters")
            cleaned.append(option.strip())
        if len(set(cleaned)) != len(cleaned):
            raise QuestionRefused(N_("{where}: two options are the same"), where="options")
        object.__setattr__(self, "options", tuple(cleaned))
        correct = self.correct
        if correct is not None and (isinstance(correct, bool) or not isinstance(correct, int)
                                    or not 0 <= correct < len(cleaned)):
            raise QuestionRefused(N_("{where}: an option's index 0..{last} or none, got {got}"), where="correct",
                                  last=len(cleaned) - 1, got=_short(correct))

    def check(self, value: Any) -> int:
        """An answer as an option's index; ValueError for anything else."""
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < len(self.options):
            raise ValueError(f"an option's number 0..{len(self.options) - 1} wanted, got {_short(value)}")
        return int(value)

    judged = _no_judgement

    @property
    def has_truth(self) -> bool:
        return self.correct is not None

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "prompt": self.prompt, "options": list(self.options), "correct": self.correct}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Choice:
        options = d.get("options")
        if not isinstance(options, list | tuple):
            raise ValueError("options: a list of 2 to 6 texts wanted")
        return cls(d.get("prompt"), tuple(options), d.get("correct"))  # type: ignore[arg-type]

    def tally_fields(self, values: Sequence[Any], judged: Sequence[Judged | None]) -> dict[str, Any]:
        counts = [0] * len(self.options)
        for value in values:
            counts[value] += 1
        return {"counts": tuple(counts)}

    def tally_text(self, tally: Tally, revealed: bool) -> str:
        """The answers as bars of text, one line per option, with the round before it beside each
        bar after Vote again; the right option marked ✓ once revealed."""
        top = max((*tally.counts, *(tally.previous.counts if tally.previous is not None else ())), default=0)
        lines = []
        for k, option in enumerate(self.options):
            count = tally.counts[k]
            bar = "█" * (round(BAR_CHARS * count / top) if top else 0)
            mark = " ✓" if revealed and self.correct == k else ""
            share = f"{100.0 * tally.share(k):.0f} %" if tally.answered else "–"
            line = f"{k + 1}. {option}{mark}  \n`{bar or '·'}` **{count}** ({share})"
            if tally.previous is not None:
                line += f" · round {tally.previous.number}: {tally.previous.counts[k]}"
            lines.append(line)
        return "  \n".join(lines)

    def csv_head(self) -> str:
        return ("# options: " + " | ".join(f"{k + 1}. {o}" for k, o in enumerate(self.options))
                + ("" if self.correct is None else f" (correct: {self.correct + 1})") + "\n")

    def csv_row(self, value: Any, judged: Judged | None) -> dict[str, Any]:
        return {"option": value + 1, "option_text": self.options[value]}

    def answer_words(self, value: Any) -> str:
        return f"**{value + 1}. {self.options[value]}**"

    def verdict(self, value: Any) -> tuple[float | None, str]:
        mine = _plain(self.answer_words(value))
        if self.correct is None:
            return None, f"{mine} (collected)"
        return (1.0, f"{mine}: right") if value == self.correct else (0.0, f"{mine}: wrong")


@dataclass(frozen=True)
class Direction:
    """A direction in 3D; an answer is a unit 3-vector in `frame` ("space")."""

    prompt: str
    truth: tuple[float, float, float] | None = None
    frame: str = "space"
    kind: ClassVar[str] = "direction"
    FIELDS: ClassVar[frozenset[str]] = frozenset({"kind", "prompt", "truth", "frame"})

    def __post_init__(self) -> None:
        object.__setattr__(self, "prompt", _prompt(self.prompt))
        if self.truth is not None:
            object.__setattr__(self, "truth", unit_vector(self.truth, "truth"))
        if self.frame not in FRAMES:
            raise ValueError(f"frame: one of {', '.join(FRAMES)} wanted, got {_short(self.frame)}")

    def check(self, value: Any) -> tuple[float, float, float]:
        """An answer as a unit 3-vector (normalized); ValueError for anything else."""
        return unit_vector(value, "answer")

    judged = _no_judgement

    @property
    def has_truth(self) -> bool:
        return self.truth is not None

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "prompt": self.prompt, "truth": None if self.truth is None else list(self.truth),
                "frame": self.frame}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Direction:
        truth = d.get("truth")
        return cls(d.get("prompt"), None if truth is None else unit_vector(truth, "truth"),  # type: ignore[arg-type]
                   d.get("frame", "space"))

    def tally_fields(self, values: Sequence[Any], judged: Sequence[Judged | None]) -> dict[str, Any]:
        return {"directions": tuple(values)}

    def tally_text(self, tally: Tally, revealed: bool) -> str:
        near = f" · {tally.within(15.0)} within 15° of the true direction" if revealed else ""
        return f"{tally.answered} tips on the sphere in the 3D view{near}"

    def csv_head(self) -> str:
        return ""

    def csv_row(self, value: Any, judged: Judged | None) -> dict[str, Any]:
        return dict(zip("xyz", (f"{c:.4f}" for c in value), strict=True))

    def answer_words(self, value: Any) -> str:
        x, y, z = value
        azimuth = math.degrees(math.atan2(y, x))
        elevation = math.degrees(math.asin(max(-1.0, min(1.0, z))))
        return f"**azimuth {azimuth:.0f}°, elevation {elevation:.0f}°**"

    def verdict(self, value: Any) -> tuple[float | None, str]:
        if self.truth is None:
            return None, f"{_plain(self.answer_words(value))} (collected)"
        cosine = max(-1.0, min(1.0, sum(a * b for a, b in zip(value, self.truth, strict=True))))
        angle_deg = math.degrees(math.acos(cosine))
        good = angle_deg <= DIRECTION_RIGHT_DEG
        return (1.0 if good else 0.0), f"{angle_deg:.0f}° from the true direction: {'right' if good else 'wrong'}"


@dataclass(frozen=True)
class State:
    """A state of the student's own copy of the room; judged by `judge` (a name of
    `app.ask.judges.JUDGES`) against `target` when it is not None."""

    prompt: str
    scene: str
    judge: str | None = None
    target: Mapping[str, Any] | None = None
    kind: ClassVar[str] = "state"
    FIELDS: ClassVar[frozenset[str]] = frozenset({"kind", "prompt", "scene", "judge", "target"})

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

    def judged(self, value: Any) -> Judged | None:
        """The judges' module's judgement of a checked state (None: no judge)."""
        from app.ask.judges import judge

        return judge(self, value)

    @property
    def has_truth(self) -> bool:
        return False

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "prompt": self.prompt, "scene": self.scene, "judge": self.judge,
                "target": None if self.target is None else dict(self.target)}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> State:
        return cls(d.get("prompt"), d.get("scene"), d.get("judge"), d.get("target"))  # type: ignore[arg-type]

    def tally_fields(self, values: Sequence[Any], judged: Sequence[Judged | None]) -> dict[str, Any]:
        return {"judged": tuple(judged)}

    def tally_text(self, tally: Tally, revealed: bool) -> str:
        from app.ask.tally_text import judged_histogram_text

        return judged_histogram_text(tally) or f"{tally.answered} states sent"

    def csv_head(self) -> str:
        return ""

    def csv_row(self, value: Any, judged: Judged | None) -> dict[str, Any]:
        row = {"state": " ".join(f"{key}={val:g}" if isinstance(val, float) else f"{key}={val}"
                                 for key, val in value.items())}
        if judged is not None:
            shown = judged.value
            row.update({"judged": f"{shown:g}" if isinstance(shown, float) else shown, "judged_words": judged.words})
        return row

    def answer_words(self, value: Any) -> str:
        if self.judge is None:
            return "**your state**"
        try:
            judged = self.judged(value)
        except ValueError as error:
            return f"**your state** (not judged: {error})"
        if judged is None:
            return "**your state**"
        mark = "" if judged.good is None else " ✓ as asked" if judged.good else " ✗ not what was asked"
        return f"**{judged.words}**{mark}"

    def verdict(self, value: Any) -> tuple[float | None, str]:
        judged = self.judged(value)
        if judged is None:
            return None, "your state was collected (not judged)"
        if judged.good is None:
            return None, judged.words
        return (1.0, f"{judged.words} ✓ as asked") if judged.good else (0.0, f"{judged.words} ✗ not what was asked")


@dataclass(frozen=True)
class Number:
    """A number with a unit ("the flip period in s"); an answer is a finite float, right when
    |answer - value| <= tolerance (`value` None: no right answer, only collected)."""

    prompt: str
    value: float | None = None
    unit: str = ""
    tolerance: float = 0.0
    kind: ClassVar[str] = "number"
    FIELDS: ClassVar[frozenset[str]] = frozenset({"kind", "prompt", "value", "unit", "tolerance"})

    def __post_init__(self) -> None:
        object.__setattr__(self, "prompt", _prompt(self.prompt))
        if self.value is not None:
            object.__setattr__(self, "value", finite_number(self.value, "value"))
        if not isinstance(self.unit, str) or len(self.unit.strip()) > MAX_UNIT_CHARS:
            raise QuestionRefused(N_("{where}: a text of at most {most} characters wanted, got {got}"), where="unit",
                                  most=MAX_UNIT_CHARS, got=_short(self.unit))
        object.__setattr__(self, "unit", self.unit.strip())
        tolerance = finite_number(self.tolerance, "tolerance")
        if tolerance < 0.0:
            raise QuestionRefused(N_("{where}: zero or more wanted, got {got}"), where="tolerance",
                                  got=f"{tolerance:g}")
        object.__setattr__(self, "tolerance", tolerance)

    def check(self, value: Any) -> float:
        """An answer as a finite float; ValueError for anything else (a text, NaN, inf, 1e400)."""
        return finite_number(value, "answer")

    judged = _no_judgement

    def right(self, value: float) -> bool | None:
        """`value` is within the tolerance of the right value (None: no right value)."""
        if self.value is None:
            return None
        slack = 1e-9 * max(1.0, abs(self.value))  # 2.1 - 2.0 is a hair over 0.1 in floats
        return abs(value - self.value) <= self.tolerance + slack

    @property
    def has_truth(self) -> bool:
        return self.value is not None

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "prompt": self.prompt, "value": self.value, "unit": self.unit,
                "tolerance": self.tolerance}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Number:
        return cls(d.get("prompt"), d.get("value"), d.get("unit", ""), d.get("tolerance", 0.0))  # type: ignore[arg-type]

    def tally_fields(self, values: Sequence[Any], judged: Sequence[Judged | None]) -> dict[str, Any]:
        return {"values": tuple(values)}

    def with_unit(self, value: float) -> str:
        """`value` in words with the unit: "2.5 s"."""
        return f"{value:.4g} {self.unit}".strip()

    def bins(self, values: Sequence[float], most: int = 8) -> list[tuple[float, float, int]]:
        """The answers' histogram: (low, high, answers) per bin, bins of equal width from the least
        to the greatest answer, 1 + log2(answers) of them (Sturges) but at most `most` and at most
        the distinct answers; one bin when they are all equal; [] without answers."""
        if not values:
            return []
        low, high = min(values), max(values)
        if high - low <= 1e-12 * max(1.0, abs(low)):
            return [(low, high, len(values))]
        count = max(2, min(most, len(set(values)), 1 + math.ceil(math.log2(len(values)))))
        width = (high - low) / count
        counts = [0] * count
        for value in values:
            counts[min(count - 1, int((value - low) / width))] += 1
        return [(low + k * width, low + (k + 1) * width, n) for k, n in enumerate(counts)]

    def tally_text(self, tally: Tally, revealed: bool) -> str:
        """The answers as a histogram of bars (Markdown), the bins holding right answers marked ✓
        and the right count said once revealed, the round before it said after Vote again."""
        if not tally.values:
            return "no answers yet"
        bins = self.bins(tally.values)
        top = max(n for _, _, n in bins)
        lines = []
        for low, high, n in bins:
            bar = "█" * round(BAR_CHARS * n / top) if n else ""
            span = self.with_unit(low) if low == high else f"{low:.4g} … {self.with_unit(high)}"
            holds_right = self.value is not None and low - self.tolerance <= self.value <= high + self.tolerance
            mark = " ✓" if revealed and holds_right else ""
            lines.append(f"{span}{mark} `{bar or '·'}` **{n}**")  # one line a bin
        if revealed and self.value is not None:
            right = sum(1 for v in tally.values if self.right(v))
            lines.append(f"**{right} of {tally.answered}** within ±{self.with_unit(self.tolerance)} "
                         f"of {self.with_unit(self.value)}")
        if tally.previous is not None:
            lines.append(f"round {tally.previous.number}: {tally.previous.answered} answers")
        return "  \n".join(lines)

    def csv_head(self) -> str:
        if self.value is None:
            return f"# unit: {self.unit or '-'}\n"
        return f"# right: {self.with_unit(self.value)} ± {self.with_unit(self.tolerance)}\n"

    def csv_row(self, value: Any, judged: Judged | None) -> dict[str, Any]:
        row: dict[str, Any] = {"value": f"{value:.10g}"}
        if self.value is not None:
            row.update({"judged": f"{value - self.value:+.6g}",
                        "judged_words": "right" if self.right(value) else "wrong"})
        return row

    def answer_words(self, value: Any) -> str:
        return f"**{self.with_unit(value)}**"

    def verdict(self, value: Any) -> tuple[float | None, str]:
        mine, right = _plain(self.answer_words(value)), self.right(value)
        if right is None:
            return None, f"{mine} (collected)"
        return (1.0, f"{mine}: right") if right else (0.0, f"{mine}: wrong")


Question = Choice | Direction | State | Number
KINDS: dict[str, type[Choice] | type[Direction] | type[State] | type[Number]] = {
    kind.kind: kind for kind in (Choice, Direction, State, Number)}  # every kind, by its name: the one registry


def question_from_dict(d: Any) -> Question:
    """A question from its dict (a lesson step's "ask", an automation call, the bus):

        {"kind": "choice", "prompt": "...", "options": ["a", "b"], "correct": 1}
        {"kind": "direction", "prompt": "...", "truth": [0, 0, 1]}        # truth optional
        {"kind": "state", "prompt": "...", "scene": "Heavy top", "judge": "...", "target": {...}}
        {"kind": "number", "prompt": "...", "value": 2.5, "unit": "s", "tolerance": 0.2}

    A question object is returned as it is.  ValueError naming the field for anything wrong."""
    if isinstance(d, tuple(KINDS.values())):
        return d  # type: ignore[return-value]
    if not isinstance(d, Mapping):
        raise ValueError(f"a question is an object with a kind, got {_short(d)}")
    kind = d.get("kind")
    cls = KINDS.get(kind) if isinstance(kind, str) else None
    if cls is None:
        raise ValueError(f"kind: one of {', '.join(KINDS)} wanted, got {_short(kind)}")
    unknown = sorted(str(key) for key in set(d) - cls.FIELDS)
    if unknown:
        raise ValueError(f"{unknown[0]}: not a field of a {kind} question ({', '.join(sorted(cls.FIELDS))})")
    return cls.from_dict(d)


def question_to_dict(question: Question) -> dict[str, Any]:
    """The dict `question_from_dict` reads back into an equal question (plain JSON values)."""
    return question.to_dict()
