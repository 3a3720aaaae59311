"""A State question's tally in words: the distribution of the judged quantity (Markdown bars),
and the gallery's entries of a round.

* `judged_histogram_text(tally)`: classes (loops, waves, ...; stays, flips) one bar each, in the
  order of the first answer of each; degrees (an attitude error) in DEGREE_BINS_DEG; the answers
  meeting the question's target counted ("✓ 7 of 12 meet the target"); after Vote again the
  round before beside each bar.  Answers no judge judged are counted apart.
* `gallery_entries(round_)`: the round's state answers as `app.ask.gallery.GalleryEntry`s,
  numbered 1, 2, ... oldest first as in the CSV (`Round.rows`); an answer that is not a body
  (`AnswerState.from_dict` refuses it) is left out, the others keep their numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from app.ask.gallery import GalleryEntry
from app.ask.judges import AnswerState, Judged
from app.ask.round import Tally

__all__ = ["BAR_CHARS", "DEGREE_BINS_DEG", "gallery_entries", "judged_histogram_text"]

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


def judged_histogram_text(tally: Tally) -> str:
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


def gallery_entries(round_: Any) -> tuple[GalleryEntry, ...]:
    """The round's state answers for the gallery (module docstring)."""
    entries: list[GalleryEntry] = []
    for number, answer in enumerate(round_.answers(), start=1):
        try:
            state = AnswerState.from_dict(answer.value)
        except (ValueError, TypeError):
            continue
        judged = answer.judged
        value = None if judged is None else judged.value
        if isinstance(value, float) and not math.isfinite(value):
            value = None
        entries.append(GalleryEntry(number, state, value, "" if judged is None else judged.words))
    return tuple(entries)
