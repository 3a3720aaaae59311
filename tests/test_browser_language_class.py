"""A lecture in three languages, in Debian's Chromium, through the pages only (issue 38's "Done when"):

A lecturer presents in English (1024×768) while a Dutch and a German student (800×600), each
having picked their language in the page's Language dropdown (the Dutch one before the lecture,
the German one while already following), follow: their follower panel reads Dutch / German
("De presentator volgen", "Zelf verkennen" / "Dem Vortragenden folgen", "Selbst erkunden"), the
key numbers under the scene written their way too ("I3 [kg m²] = 2,6").  The
lecturer asks a choice question (typed in English: it stays as typed); each student answers it
in their own page, whose question panel speaks their language ("Vraag 1", "Jouw antwoord",
"Wijzig mijn antwoord" / "Frage 1", "Deine Antwort", "Meine Antwort ändern"); then the Dutch
student explores and reads the live bar in Dutch ("College bezig", "Volg presentator").  At each
step the student's page holds none of the English words wrapped for these panels (the catalog's
msgids of app/lecture/follower.py, app/hall/lecture_panel.py, app/hall/ask_student.py,
app/hall/ask_kinds.py and app/roles/language.py that the language writes otherwise) nor viser's
own header words ("Connected"), and the lecturer's page stays English.

Pictures for people: $RBL_TEST_SHOTS/i18n2/ (none when unset).
"""

from __future__ import annotations

import re
import time
from pathlib import Path
from typing import Any

import pytest
from babel.messages.pofile import read_po
from conftest import DESK, keep_picture
from test_browser_lecture import button, close_toasts, hall_app, open_page, present_in_page, type_into  # noqa: F401

from app.i18n import translator
from app.main import App

pytestmark = pytest.mark.browser

LAPTOP = DESK
ROOT = Path(__file__).resolve().parents[1]
WRAPPED_IN = ("app/lecture/follower.py", "app/hall/lecture_panel.py", "app/hall/ask_student.py",
              "app/hall/ask_kinds.py", "app/roles/language.py")
VISER_STATUS = ("Connected", "Connecting...", "Inactive")
"""viser's own words in the panel's header when the app sets no label there: none on any page."""
PROMPT = "A book spins about its middle axis. What does it do?"  # the lecturer's words: stay as typed
OPTIONS = ("spins steadily", "wobbles", "flips again and again")


def wrapped_english(language: str) -> dict[str, str]:
    """The English pieces (the literal text between placeholders and Markdown marks, those with a
    word of 4 letters or more) of every msgid marked in WRAPPED_IN that `language` writes otherwise;
    piece -> its msgid."""
    with (ROOT / "app" / "locale" / "messages.pot").open("rb") as handle:
        catalog = read_po(handle)
    tr = translator(language)
    pieces: dict[str, str] = {}
    for message in catalog:
        if not message.id or not any(path in WRAPPED_IN for path, _ in message.locations):
            continue
        if tr.gettext(message.id) == message.id:
            continue  # "Details", "Azimut"/"Elevation" in German: the same word
        for piece in re.split(r"\{[^}]*\}|\*+|·", message.id):
            piece = piece.strip(" .:;,()[]")
            if re.search(r"[A-Za-z]{4,}", piece):
                pieces[piece] = message.id
    return pieces


def english_left(page: Any, language: str) -> list[str]:
    """The wrapped English pieces the page shows now (its whole visible text; the lecturer's prompt
    and options, which stay as typed, taken out first)."""
    text = page.locator("body").inner_text()
    for typed in (PROMPT, *OPTIONS):
        text = text.replace(typed, "")
    left = [f"{piece!r} (of {msgid!r})" for piece, msgid in wrapped_english(language).items()
            if re.search(rf"(?<![A-Za-z]){re.escape(piece)}(?![A-Za-z])", text)]
    return left + [f"{status!r} (viser's header)" for status in VISER_STATUS if status in text.splitlines()]


def shows(page: Any, words: str, timeout: float = 30.0) -> None:
    """Wait until the page shows `words` (a text's part); AssertionError naming what it shows instead."""
    try:
        page.get_by_text(words, exact=False).first.wait_for(timeout=timeout * 1000)
    except Exception:  # noqa: BLE001 - say what the page showed instead
        raise AssertionError(f"the page never showed {words!r}; it shows: "
                             f"{page.locator('body').inner_text()[:1500]!r}") from None


def pick_language(page: Any, session: Any, name: str, code: str) -> None:
    """Pick `name` in the page's Language dropdown, as a person does; waits for the session to speak `code`."""
    page.locator(f'[id="{session.gui_language._impl.uuid}"]').click()
    page.get_by_role("option", name=name, exact=True).click()
    deadline = time.monotonic() + 30.0
    while session.languages.code != code:
        assert time.monotonic() < deadline, f"the session speaks {session.languages.code}, not {code}, " \
                                            f"30 s after choosing {name}; last error: {session.last_error}"
        page.wait_for_timeout(50)


def shot(page: Any, name: str) -> None:
    keep_picture(page, f"i18n2/{name}")


def no_english(page: Any, language: str, when: str) -> None:
    left = english_left(page, language)
    assert left == [], f"{language} page, {when}: English left: {left}"


def test_an_english_lecture_followed_and_answered_in_dutch_and_german(browser, hall_app: App,  # noqa: F811
                                                                      wait_until) -> None:
    app = hall_app
    assert len(wrapped_english("nl")) >= 40 and len(wrapped_english("de")) >= 40  # the check has teeth
    lecturer_page, lecturer = open_page(browser, app, timeout=90.0, viewport={"width": 1024, "height": 768})
    dutch_page, dutch = open_page(browser, app, timeout=90.0, **LAPTOP)
    german_page, german = open_page(browser, app, timeout=90.0, **LAPTOP)
    for page in (lecturer_page, dutch_page, german_page):
        button(page, "Play").wait_for(timeout=90_000)
        close_toasts(page)
    pick_language(dutch_page, dutch, "Nederlands", "nl")  # before the lecture
    button(dutch_page, "Afspelen").wait_for(timeout=30_000)

    # The lecturer presents in English; both students follow.
    present_in_page(lecturer_page, lecturer)
    wait_until(lambda: dutch.mode == "following" and german.mode == "following", timeout=30.0)
    shows(dutch_page, "De presentator volgen")
    button(dutch_page, "Zelf verkennen").wait_for(timeout=30_000)
    shows(dutch_page, "Presentator:")
    shows(german_page, "Following the presenter")  # still English: it has not picked yet
    pick_language(german_page, german, "Deutsch", "de")  # while following: the panel is relabelled
    shows(german_page, "Dem Vortragenden folgen")
    button(german_page, "Selbst erkunden").wait_for(timeout=30_000)
    shows(german_page, "Vortragender:")
    assert german.mode == "following"
    for page in (dutch_page, german_page):  # the key numbers too: Euler angles' I3, a decimal comma
        shows(page, "I3 [kg m²] = 2,6")
        assert page.get_by_text("I3 [kg m²] = 2.6", exact=False).count() == 0
    close_toasts(dutch_page)
    close_toasts(german_page)
    no_english(dutch_page, "nl", "following")
    no_english(german_page, "de", "following")
    shot(dutch_page, "follower_nl.png")
    shot(german_page, "follower_de.png")

    # The lecturer asks a choice question, in English.
    type_into(lecturer_page, "Question", PROMPT, lecturer)
    type_into(lecturer_page, "Options", " | ".join(OPTIONS), lecturer)
    button(lecturer_page, "Ask the class").click()
    wait_until(lambda: app.rounds.current is not None, timeout=15.0)
    for page, head in ((dutch_page, "Vraag 1"), (german_page, "Frage 1")):
        shows(page, head)
        shows(page, PROMPT)  # the lecturer's words, as typed
        button(page, f"1. {OPTIONS[0]}").wait_for(timeout=30_000)
    no_english(dutch_page, "nl", "asked")
    no_english(german_page, "de", "asked")
    shot(dutch_page, "question_nl.png")
    button(dutch_page, f"1. {OPTIONS[0]}").click()
    button(german_page, f"3. {OPTIONS[2]}").click()
    lecturer_page.get_by_text("2 of 2 answered", exact=False).wait_for(timeout=30_000)
    assert app.rounds.tally().counts == (1, 0, 1)
    shows(dutch_page, "Jouw antwoord:")
    button(dutch_page, "Wijzig mijn antwoord").wait_for(timeout=30_000)
    shows(german_page, "Deine Antwort:")
    button(german_page, "Meine Antwort ändern").wait_for(timeout=30_000)
    close_toasts(dutch_page)
    close_toasts(german_page)
    no_english(dutch_page, "nl", "answered")
    no_english(german_page, "de", "answered")
    shot(dutch_page, "answered_nl.png")
    shot(german_page, "answered_de.png")

    # The Dutch student explores: its live bar speaks Dutch; the German one still follows in German.
    button(dutch_page, "Zelf verkennen").click()
    wait_until(lambda: dutch.mode == "own", timeout=30.0)
    shows(dutch_page, "College bezig")
    button(dutch_page, "Volg presentator").wait_for(timeout=30_000)
    close_toasts(dutch_page)
    no_english(dutch_page, "nl", "exploring")
    no_english(german_page, "de", "still following")
    shot(dutch_page, "exploring_nl.png")

    # The lecturer's page stays English.
    assert button(lecturer_page, "Stop presenting").count() == 1
    assert lecturer_page.get_by_text("Jouw antwoord", exact=False).count() == 0
    assert lecturer.languages.code == "en"
    shot(lecturer_page, "lecturer_en.png")
    for session in (lecturer, dutch, german):
        assert session.error_count == 0, session.last_error
