"""The verdicts of the judges (`app.ask.judges`) and of the question kinds (`verdict`,
`answer_words` in `app.ask.questions`), written in English where they are made and stored (a
task's submission keeps them), in a browser's language where a person reads them:

    verdict_in_language("loops — the top loops ... ✓ as asked", translator("de"))
    # "Schleifen — ... ✓ wie gefragt"

What is not the app's (a choice's option, a typed number) stays as written; a judge's refusal
of a body (`app.ask.judges`: "this question is about the Heavy top scene; ...") is written in the
reader's language where it is said (`JUDGE_REFUSALS`, nested in the refusals that carry it).
"""

from __future__ import annotations

from app.i18n import N_, Phrases, Translator

__all__ = ["ANSWER_WORDS", "JUDGED", "JUDGE_REFUSALS", "VERDICTS", "answer_in_language", "judge_refusal_words",
           "verdict_in_language"]

_NUMBER = r"-?[0-9][0-9.e+-]*"

JUDGE_REFUSALS = Phrases(
    (r"this question is about the (?P<scene>.+) scene; the answer is a (?P<answer>.+) body",
     N_("this question is about the {scene} scene; the answer is a {answer} body")),
    (r"the class of motion is judged for a heavy top \(I1 = I2, m g ℓ > 0\)",
     N_("the class of motion is judged for a heavy top (I1 = I2, m g ℓ > 0)")),
    (r"whether an axis stays is judged for a torque-free body",
     N_("whether an axis stays is judged for a torque-free body")),
    (r"this answer cannot be judged: (?P<error>.+)", N_("this answer cannot be judged: {error}")),
    (r"(?P<scene>.+) has no body to answer with", N_("{scene} has no body to answer with")),
    (r"an answer needs a finite 3x3 attitude and a finite ω \(3 numbers\)",
     N_("an answer needs a finite 3x3 attitude and a finite ω (3 numbers)")),
    (r"the answer's attitude is not a rotation", N_("the answer's attitude is not a rotation")),
    (rf"the answer's \|ω\| is above (?P<rate>{_NUMBER}) rad/s", N_("the answer's |ω| is above {rate} rad/s")),
    (r"the answer's moments of inertia must be 3 positive numbers",
     N_("the answer's moments of inertia must be 3 positive numbers")),
    (r"the answer's m g ℓ must be finite", N_("the answer's m g ℓ must be finite")),
    (r"a state answer is an object", N_("a state answer is an object")),
    (r"a state answer names its scene", N_("a state answer names its scene")),
    (r"a state answer needs the numbers (?P<keys>.+)", N_("a state answer needs the numbers {keys}")),
    translated=("scene", "answer"), numbers=("rate",),
)
"""A judge's refusal of a state answer (`app.ask.judges`: a body of another scene, a model the
judge cannot use, a malformed state), matched in English; a scene's title translated."""

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
    nested={"judged": JUDGED, "mine": _MINE, "error": JUDGE_REFUSALS},
)
"""A student's own answer in words during a round (`QuestionKind.answer_words`, Markdown)."""


def verdict_in_language(words: str, tr: Translator) -> str:
    """A verdict (`QuestionKind.verdict`'s or a judge's words) in `tr`'s language; the words as
    they are where no pattern knows them."""
    found = VERDICTS.words(words, tr)
    return found if found is not None else JUDGED.in_language(words, tr)


def judge_refusal_words(refusal: str, tr: Translator) -> str:
    """A judge's refusal (`JUDGE_REFUSALS`, English) in `tr`'s language; as it is when no pattern knows it."""
    return JUDGE_REFUSALS.in_language(refusal, tr)


def answer_in_language(words: str, tr: Translator) -> str:
    """A student's answer in words (`QuestionKind.answer_words`, Markdown) in `tr`'s language."""
    return ANSWER_WORDS.in_language(words, tr)
