"""The judges' and the question kinds' verdicts in a student's language (`app.ask.verdict_words`,
issue 38): made in English by the real judges and kinds (and stored so: a task keeps them),
written in Dutch and German where a student reads them, numbers with a decimal comma; what is not
the app's (a lecturer's option, a typed number) stays as written; a sentence no pattern knows
stays English rather than half translated."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app.ask import Choice, Direction, Number
from app.ask import State as StateQuestion
from app.ask.judges import MOTION_WORDS, AnswerState, judge_answer
from app.ask.verdict_words import ANSWER_WORDS, JUDGED, VERDICTS, answer_in_language, verdict_in_language
from app.i18n import translator

I1, I3, MGL, SPIN = 1.0, 0.5, 6.0, 12.0
ENGLISH_WORDS = re.compile(r"\b(from the target|stays within|leaves|axis|as asked|not what was asked|right|wrong|"
                           r"collected|your state|azimuth|elevation|loops)\b")
"""The English words of the verdicts: none may be left in a Dutch or German one."""


def _judged_words() -> list[str]:
    """What the three state judges say, from real answers (as tests/test_judges.py makes them)."""
    target = Rotation.from_euler("ZXZ", np.radians([30.0, 45.0, 10.0]))
    tilted = AnswerState(scene="Euler angles", omega_body=np.zeros(3),
                         R_space_body=(target * Rotation.from_rotvec([0, 0, math.radians(12.4)])).as_matrix())
    attitude = judge_answer("attitude", tilted, {"angles_deg": [30.0, 45.0, 10.0]})
    theta = math.radians(60.0)
    R = Rotation.from_euler("ZXZ", [0.0, theta, 0.0]).as_matrix()
    omega = np.array([0.0, math.sin(theta) * math.radians(-20.0), SPIN])
    loop = judge_answer("top_motion", AnswerState(scene="Heavy top", R_space_body=R, omega_body=omega,
                                                  inertia=(I1, I1, I3), mgl=MGL), {"motion": "loops"})
    words = [attitude.words, loop.words]
    for axis in (0, 1):  # the first stays, the intermediate one flips
        spin = np.full(3, 0.05)
        spin[axis] = 5.0
        body = AnswerState(scene="Free body", R_space_body=np.eye(3), omega_body=spin, inertia=(0.3, 0.75, 1.0))
        words.append(judge_answer("axis_stays", body, {"within_deg": 20, "seconds": 10, "stays": True}).words)
    return words


@pytest.mark.parametrize("language", ["nl", "de"])
def test_every_judges_words_read_in_the_students_language(language: str) -> None:
    tr = translator(language)
    attitude, loop, stays, flips = _judged_words()
    assert attitude == "12.4° from the target" and loop.startswith("loops — ")
    assert stays.startswith("stays — ") and flips.startswith("flips — ")
    for english in (attitude, loop, stays, flips):
        words = verdict_in_language(english, tr)
        assert words != english and not ENGLISH_WORDS.search(words), (english, words)
        assert not re.search(r"\d\.\d", words), f"a decimal point in {words!r}"
    assert verdict_in_language(attitude, tr) == tr.gettext("{degrees}° from the target").format(degrees="12,4")
    assert verdict_in_language(loop, tr).startswith(tr.gettext("loops") + " — ")


@pytest.mark.parametrize("language", ["nl", "de"])
def test_every_kinds_verdict_and_answer_words_read_in_the_students_language(language: str) -> None:
    tr = translator(language)
    choice = Choice("What does it do?", ("spins", "wobbles"), correct=1)
    direction = Direction("Where is L?", truth=(0.0, 0.0, 1.0))
    number = Number("The flip period", unit="s", value=2.4, tolerance=0.1)
    state = StateQuestion("Make it loop", "Heavy top", "top_motion", {"motion": "loops"})
    unjudged = StateQuestion("Anything", "Heavy top")
    verdicts = [choice.verdict(1)[1], choice.verdict(0)[1], direction.verdict((0.0, 0.0, 1.0))[1],
                direction.verdict((1.0, 0.0, 0.0))[1], number.verdict(2.45)[1], number.verdict(3.0)[1],
                unjudged.verdict({"t": 1.0})[1]]
    assert verdicts[:2] == ["2. wobbles: right", "1. spins: wrong"]
    for english in verdicts:
        words = verdict_in_language(english, tr)
        assert words != english and not ENGLISH_WORDS.search(words), (english, words)
    assert "wobbles" in verdict_in_language(verdicts[0], tr)  # the lecturer's option, as typed
    assert verdict_in_language("2.45 s: right", tr).startswith("2.45 s")  # the student's number, as typed
    for verdict in ("loops — x ✓ as asked", "12.4° from the target ✗ not what was asked"):
        assert not ENGLISH_WORDS.search(verdict_in_language(verdict, tr)), verdict
    shown = [answer_in_language(w, tr) for w in (direction.answer_words((0.0, 1.0, 0.0)), "**your state**",
                                                    "**12.4° from the target** ✓ as asked", state.answer_words({}))]
    for english, words in zip((direction.answer_words((0.0, 1.0, 0.0)), "**your state**",
                               "**12.4° from the target** ✓ as asked", state.answer_words({})), shown, strict=True):
        assert words != english and words.startswith("**") and not ENGLISH_WORDS.search(words.split("(")[0]), words


def test_every_pattern_matches_its_own_english_and_every_msgid_is_translated() -> None:
    """Each entry's msgid, filled with sample fields, is English its pattern matches whole (the
    pattern and the msgid say the same sentence); each is translated in both catalogs; the top's
    classes of motion too."""
    sample = {"degrees": "4.2", "axis": "y′", "within": "20", "seconds": "10", "most": "3.5", "t": "1.2",
              "motion": "loops", "description": "a description", "azimuth": "30", "elevation": "-10",
              "angle": "12", "judged": "4.2° from the target", "mine": "azimuth 30°, elevation -10°",
              "error": "no body"}
    for phrases in (JUDGED, VERDICTS, ANSWER_WORDS):
        for pattern, msgid in phrases.entries:
            english = msgid.format(**sample)
            assert pattern.fullmatch(english), (msgid, english)
    for language in ("nl", "de"):
        tr = translator(language)
        for msgid in (*JUDGED.msgids, *VERDICTS.msgids, *MOTION_WORDS.values()):
            assert msgid.startswith("{motion}") or tr.gettext(msgid) != msgid, (language, msgid)
    assert verdict_in_language("a verdict nobody wrote yet", translator("de")) == "a verdict nobody wrote yet"
