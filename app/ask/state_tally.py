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
from typing import Any

from app.ask.gallery import GalleryEntry
from app.ask.judges import AnswerState
from app.ask.tally_text import BAR_CHARS, DEGREE_BINS_DEG, judged_histogram_text

__all__ = ["BAR_CHARS", "DEGREE_BINS_DEG", "gallery_entries", "judged_histogram_text"]


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
