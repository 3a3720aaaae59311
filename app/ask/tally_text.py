"""A tally as the question kinds read it (`TallyView`, the shape of `app.ask.round.Tally`), and a
State question's tally in words (`judged_histogram_text`): classes (loops, waves, ...; stays,
flips) one bar each, in the order of the first answer of each; degrees (an attitude error) in
DEGREE_BINS_DEG; the answers meeting the question's target counted ("✓ 7 of 12 meet the
target"); after Vote again the round before beside each bar.  Answers no judge judged are
counted apart.  Here, not in `app.ask.round`, so that the kinds (`app.ask.questions`) read a
tally without importing the round that imports them.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol

from app.ask.judges import Judged

__all__ = ["BAR_CHARS", "DEGREE_BINS_DEG", "TallyView", "judged_histogram_text"]


class TallyView(Protocol):
    """What a kind reads of a tally (`app.ask.round.Tally` is one)."""

    @property
    def number(self) -> int: ...
    @property
    def question(self) -> Any: ...
    @property
    def answered(self) -> int: ...
    @property
    def counts(self) -> tuple[int, ...]: ...
    @property
    def judged(self) -> tuple[Judged | None, ...]: ...
    @property
    def values(self) -> tuple[float, ...]: ...
    @property
    def previous(self) -> TallyView | None: ...

    def share(self, option: int) -> float: ...

    def within(self, degrees: float) -> int: ...


BAR_CHARS = 16  # the longest bar
DEGREE_BINS_DEG = (0.0, 5.0, 10.0, 20.0, 45.0, 90.0, 180.0)  # bin edges [deg]; the last bin is closed


def _bins(judged: Sequence[Judged | None]) -> tuple[list[str], dict[str, int]]:
    """(labels in order, counts by label) of judged answers."""
    values = [j.value for j in judged if j is not None]
    if values and all(isinstance(v, float) for v in values):
        unit = next((j.unit for j in judged if j is not None), "")
        sign = "°" if unit == "deg" else f" {unit}" if unit else ""
        labels = [f"{lo:g}–{hi:g}{sign}" for lo, hi in zip(DEGREE_BINS_DEG, DEGREE_BINS_DEG[1:], strict=False)]
        counts = dict.fromkeys(labels, 0)
        for value in values:
            assert isinstance(value, float)
            k = next((i for i, hi in enumerate(DEGREE_BINS_DEG[1:]) if value < hi), len(labels) - 1)
            counts[labels[k]] += 1
        return labels, counts
    labels = []
    counts = {}
    for value in values:
        label = str(value)
        if label not in counts:
            labels.append(label)
            counts[label] = 0
        counts[label] += 1
    return labels, counts


def judged_histogram_text(tally: TallyView) -> str:
    """The judged quantity's distribution (Markdown; module docstring); "" with no judged answer."""
    judged = tally.judged
    labels, counts = _bins(judged)
    previous_counts: dict[str, int] = {}
    if tally.previous is not None:
        previous_labels, previous_counts = _bins(tally.previous.judged)
        labels += [label for label in previous_labels if label not in labels]
    if not labels:
        return "" if not tally.answered else f"{tally.answered} states sent (none judged)"
    top = max((*counts.values(), *previous_counts.values()), default=0)
    lines = []
    for label in labels:
        count = counts.get(label, 0)
        bar = "█" * (round(BAR_CHARS * count / top) if top else 0)
        line = f"{label} `{bar or '·'}` **{count}**"  # one line a bin: the gallery stays in view
        if tally.previous is not None:
            line += f" · round {tally.previous.number}: {previous_counts.get(label, 0)}"
        lines.append(line)
    said = [j for j in judged if j is not None and j.good is not None]
    if said:
        good = sum(1 for j in said if j.good)
        lines.append(f"✓ **{good}** of {len(said)} meet the target")
    unjudged = sum(1 for j in judged if j is None)
    if unjudged:
        lines.append(f"{unjudged} not judged")
    return "  \n".join(lines)
