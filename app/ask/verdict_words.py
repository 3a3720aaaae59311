"""The verdicts of the judges (`app.ask.judges`) and of the question kinds (`verdict`,
`answer_words` in `app.ask.questions`), written in English where they are made and stored (a
task's submission keeps them), in a browser's language where a person reads them:

    verdict_in_language("loops — the top loops ... ✓ as asked", translator("de"))
    # "Schleifen — ... ✓ wie gefragt"

What is not the app's (a choice's option, a typed number, a judge's refusal) stays as written.
"""

from __future__ import annotations

from app.i18n import N_, Phrases, Translator

__all__ = ["ANSWER_WORDS", "JUDGED", "VERDICTS", "answer_in_language", "verdict_in_language"]

_NUMBER = r"-?[0-9][0-9.e+-]*"

JUDGED = Phrases(
    (rf"(?P<degrees>{_NUMBER})° from the target", N_("{degrees}° from the target")),
    (rf"stays — the (?P<axis>\S+) axis stays within (?P<within>{_NUMBER})° for (?P<seconds>{_NUMBER}) s "
     rf"\(at most (?P<most>{_NUMBER})°\)",
     N_("stays — the {axis} axis stays within {within}° for {seconds} s (at most {most}°)")),
    (rf"flips — the (?P<axis>\S+) axis leaves (?P<within>{_NUMBER})° at t = (?P<t>{_NUMBER}) s "
     rf"\(it turns up to (?P<most>{_NUMBER})°\)",
     N_("flips — the {axis} axis leaves {within}° at t = {t} s (it turns up to {most}°)")),
    (r"(?P<motion>[a-z ]+) — (?P<description>.+)", N_("{motion} — {description}")),
    numbers=("degrees", "within", "seconds", "most", "t"), translated=("motion", "description"),
)
"""What a state judge says (`Judged.words`): the attitude's error, whether an axis stays, the
heavy top's class of motion and its description (both msgids)."""

_MINE = Phrases(
    (r"azimuth (?P<azimuth>-?[0-9]+)°, elevation (?P<elevation>-?[0-9]+)°",
     N_("azimuth {azimuth}°, elevation {elevation}°")),
)
"""A student's answer in plain words where the app wrote them (a direction)."""

VERDICTS = Phrases(
    (r"your state was collected \(not judged\)", N_("your state was collected (not judged)")),
    (r"(?P<angle>[0-9]+)° from the true direction: right", N_("{angle}° from the true direction: right")),
    (r"(?P<angle>[0-9]+)° from the true direction: wrong", N_("{angle}° from the true direction: wrong")),
    (r"(?P<judged>.+) ✓ as asked", N_("{judged} ✓ as asked")),
    (r"(?P<judged>.+) ✗ not what was asked", N_("{judged} ✗ not what was asked")),
    (r"(?P<mine>.+) \(collected\)", N_("{mine} (collected)")),
    (r"(?P<mine>.+): right", N_("{mine}: right")),
    (r"(?P<mine>.+): wrong", N_("{mine}: wrong")),
    nested={"judged": JUDGED, "mine": _MINE},
)
"""A task's verdict on a submission (`QuestionKind.verdict`'s words)."""

ANSWER_WORDS = Phrases(
    (r"\*\*(?P<judged>.+)\*\* ✓ as asked", N_("**{judged}** ✓ as asked")),
    (r"\*\*(?P<judged>.+)\*\* ✗ not what was asked", N_("**{judged}** ✗ not what was asked")),
    (r"\*\*your state\*\* \(not judged: (?P<error>.+)\)", N_("**your state** (not judged: {error})")),
    (r"\*\*your state\*\*", N_("**your state**")),
    (r"\*\*(?P<mine>azimuth .+)\*\*", "**{mine}**"),
    (r"\*\*(?P<judged>.+)\*\*", "**{judged}**"),
    nested={"judged": JUDGED, "mine": _MINE},
)
"""A student's own answer in words during a round (`QuestionKind.answer_words`, Markdown)."""


def verdict_in_language(words: str, tr: Translator) -> str:
    """A verdict (`QuestionKind.verdict`'s or a judge's words) in `tr`'s language; the words as
    they are where no pattern knows them."""
    found = VERDICTS.words(words, tr)
    return found if found is not None else JUDGED.in_language(words, tr)


def answer_in_language(words: str, tr: Translator) -> str:
    """A student's answer in words (`QuestionKind.answer_words`, Markdown) in `tr`'s language."""
    return ANSWER_WORDS.in_language(words, tr)
