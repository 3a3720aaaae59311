"""The panel's language chosen per browser, in Debian's Chromium, through the pages (issue 38):

1. Two laptops (1280×800) open the app; one picks `Nederlands` in the Language dropdown and reads
   Dutch (Scène, Taal, Afspelen, the Euler-angles folders), presses `Afspelen` and its room
   plays; the other still reads English (Scene, Play) and its room stands still.
2. A German phone (390×844, touch, the app started with `--language de`): the folded panel's
   line and `Details` are German; unfolded, the panel's German text is neither cut (a text wider
   than its box, past the panel's edge, or a word broken across lines where it has no hyphen) nor
   overlapping another, and the panel does not scroll sideways; the same check on a German
   1280×800 laptop with its `Darstellung` folder open.
3. The control panel's header names the app in German (in Dutch after choosing Nederlands), never
   viser's "Connected" once the name showed (needs the catalogs' entry for "Rigid-body lab").

Pictures for people: $RBL_TEST_SHOTS/i18n/ (none when unset).
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from typing import Any

import pytest
from conftest import RUNNING_JS, keep_picture
from test_browser import app_url
from test_browser_lecture import CODE, close_toasts, open_folder, open_page, received, serving, text_input

from app.i18n import translator
from app.main import App
from app.roles.language import APP_NAME

pytestmark = pytest.mark.browser

PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True, "device_scale_factor": 2}
LAPTOP = {"viewport": {"width": 1280, "height": 800}}

TEXT_BOXES_JS = r"""() => {
  // The panel (the outermost positioned box holding the Language dropdown's label) and every piece
  // of text in it that is drawn: its box, and how wide its text is against its box.
  const named = (selector, pattern) => [...document.querySelectorAll(selector)]
    .find(e => pattern.test(e.textContent.trim()));
  const label = named('label', /^(Language|Taal|Sprache)$/) || named('button', /^Details$/);
  if (!label) return null;
  let panel = null;
  for (let e = label; e && e !== document.body; e = e.parentElement) {
    const style = getComputedStyle(e);
    const floats = style.position === 'fixed' || style.position === 'absolute';
    if (floats && e.getBoundingClientRect().width > 150) panel = e;
  }
  if (!panel) return null;
  const box = panel.getBoundingClientRect();
  const texts = [];
  const walker = document.createTreeWalker(panel, NodeFilter.SHOW_TEXT);
  for (let node = walker.nextNode(); node; node = walker.nextNode()) {
    const text = node.textContent.trim();
    const el = node.parentElement;
    if (!text || !el || el.closest('pre, code, .katex, [aria-hidden="true"]')) continue;
    const style = getComputedStyle(el);
    if (style.visibility === 'hidden' || style.display === 'none' || el.getClientRects().length === 0) continue;
    const range = document.createRange();
    range.selectNodeContents(node);
    const rects = [...range.getClientRects()].filter(r => r.width > 0 && r.height > 0);
    if (!rects.length) continue;
    const r = range.getBoundingClientRect();
    // Scrolled out of its area (under the panel's header): not drawn.
    const viewport = el.closest('.mantine-ScrollArea-viewport');
    if (viewport) {
      const v = viewport.getBoundingClientRect();
      if (r.y < v.y - 1 || r.bottom > v.bottom + 1) continue;
    }
    const clips = style.overflow !== 'visible' || style.textOverflow === 'ellipsis';
    texts.push({text, x: r.x, y: r.y, right: r.right, bottom: r.bottom,
                lines: rects.map(q => [q.x, q.y, q.right, q.bottom]),
                pieces: text.split(/[\s\u00AD\u2010-]+/).filter(Boolean).length,  // where a line may break
                cut: clips && el.scrollWidth > el.clientWidth + 1, tag: el.tagName});
  }
  const sideways = [...panel.querySelectorAll('.mantine-ScrollArea-viewport')].map(v => v.scrollWidth - v.clientWidth);
  return {panel: {x: box.x, y: box.y, right: box.right, bottom: box.bottom}, texts, sideways};
}"""
"""The panel's box, its drawn texts (box [CSS px], each line's box, cut: wider than the element that clips
it) and how far each of its scroll areas scrolls sideways [px]."""


def shot(page: Any, name: str) -> None:
    keep_picture(page, f"i18n/{name}")


def settled_boxes(page: Any, timeout: float = 30.0) -> dict[str, Any]:
    """The panel's text boxes (TEXT_BOXES_JS) once no transition runs on the page and two reads
    0.1 s apart agree (a folder opening or the panel scrolling has finished); AssertionError
    naming the last two reads and what still ran if not.  Two equal reads alone prove nothing on
    a busy machine: a transition's time moves only when Chromium draws a frame, and frames can be
    seconds apart there."""
    deadline = time.monotonic() + timeout
    previous = None
    while True:
        found = page.evaluate(TEXT_BOXES_JS)
        assert found is not None, "no panel on the page"
        running = page.evaluate(RUNNING_JS)
        if found == previous and not running:
            return found
        if time.monotonic() > deadline:
            raise AssertionError(f"the panel's text kept moving for {timeout} s (running: {running}): "
                                 f"{previous} then {found}")
        previous = found
        page.wait_for_timeout(100)


def text_problems(page: Any) -> tuple[list[str], dict[str, Any]]:
    """What is wrong with the panel's text as drawn (once settled): texts cut, past the panel's
    right edge, a word broken where it has no break, or overlapping another text (a line's box over
    another's by more than 2 px each way); the raw boxes."""
    found = settled_boxes(page)
    panel, texts = found["panel"], found["texts"]
    problems = [f"cut: {t['text']!r}" for t in texts if t["cut"]]
    rows = [len({round(box[1]) for box in t["lines"]}) for t in texts]  # a hyphen drawn at a break has a box of its own
    problems += [f"a word broken across lines: {t['text']!r} ({n} lines: {t['lines']})"
                 for t, n in zip(texts, rows) if n > t["pieces"]]
    problems += [f"past the panel's edge ({t['right']:.0f} > {panel['right']:.0f}): {t['text']!r}"
                 for t in texts if t["right"] > panel["right"] + 1 and t["x"] < panel["right"]]
    for i, a in enumerate(texts):  # line by line: a wrapped text's box holds the texts beside its lines
        for b in texts[i + 1:]:
            if any(min(p[2], q[2]) - max(p[0], q[0]) > 2 and min(p[3], q[3]) - max(p[1], q[1]) > 2
                   for p in a["lines"] for q in b["lines"]):
                problems.append(f"overlap: {a['text']!r} and {b['text']!r}")
    problems += [f"the panel scrolls sideways by {s} px" for s in found["sideways"] if s > 1]
    return problems, found


def choose(page: Any, dropdown: Any, option: str) -> None:
    """Pick `option` in the viser dropdown `dropdown` (a handle), as a person does."""
    page.locator(f'[id="{dropdown._impl.uuid}"]').click()
    page.get_by_role("option", name=option, exact=True).click()


def button(page: Any, name: str) -> Any:
    return page.get_by_role("button", name=name, exact=True)


@pytest.fixture
def german_app() -> Iterator[App]:
    yield from serving(language="de")


@pytest.fixture
def english_app() -> Iterator[App]:
    yield from serving()


def test_one_browser_picks_dutch_and_reads_dutch_while_another_stays_english(browser, english_app: App,
                                                                            wait_until) -> None:
    dutch_page, dutch = open_page(browser, english_app, 90.0, **LAPTOP)
    english_page, english = open_page(browser, english_app, 90.0, **LAPTOP)
    for page in (dutch_page, english_page):
        button(page, "Play").wait_for(timeout=90_000)
        close_toasts(page)
    choose(dutch_page, dutch.gui_language, "Nederlands")
    try:
        button(dutch_page, "Afspelen").wait_for(timeout=30_000)
    except Exception:  # noqa: BLE001 - say what the page showed instead
        raise AssertionError(f"no Afspelen button after choosing Nederlands; the session speaks "
                             f"{dutch.languages.code}, its last error: {dutch.last_error}") from None
    for words in ("Scène", "Taal", "Euler-hoeken z-x-z [°]", "Euler-hoeksnelheden [°/s]", "Uitlezing"):
        dutch_page.get_by_text(words, exact=True).first.wait_for(timeout=30_000)
    assert button(dutch_page, "Play").count() == 0
    assert dutch.languages.code == "nl" and english.languages.code == "en"
    button(dutch_page, "Afspelen").click()
    wait_until(lambda: dutch.room.playing, timeout=15.0)
    button(dutch_page, "Pauze").wait_for(timeout=30_000)  # the toggle, in Dutch too
    shot(dutch_page, "laptop_nl.png")
    # The other browser: English as it was, its room standing still.
    for words in ("Scene", "Language", "Euler angles z-x-z [deg]", "Euler rates [deg/s]"):
        english_page.get_by_text(words, exact=True).first.wait_for(timeout=30_000)
    assert button(english_page, "Play").count() == 1 and button(english_page, "Afspelen").count() == 0
    assert english_page.get_by_text("Scène", exact=True).count() == 0
    assert not english.room.playing and english.room is not dutch.room
    shot(english_page, "laptop_en_beside_nl.png")
    assert dutch.error_count == 0 and english.error_count == 0, (dutch.last_error, english.last_error)


def test_a_german_phone_and_laptop_show_german_text_neither_cut_nor_overlapping(browser, german_app: App,
                                                                              wait_until) -> None:
    page, session = open_page(browser, german_app, 90.0, **PHONE)
    details = button(page, "Details")
    details.wait_for(timeout=90_000)
    page.get_by_text("Deine Szene", exact=False).first.wait_for(timeout=30_000)  # the folded line, German
    close_toasts(page)
    shot(page, "phone_de_folded.png")
    problems, _ = text_problems(page)
    assert problems == [], f"the folded German phone panel: {problems}"
    details.tap()
    button(page, "Abspielen").wait_for(timeout=30_000)
    button(page, "Details ausblenden").wait_for(timeout=30_000)
    close_toasts(page)
    shot(page, "phone_de.png")
    problems, found = text_problems(page)
    assert len(found["texts"]) >= 15, f"too few texts found in the panel: {found['texts']}"
    assert problems == [], f"the German phone panel (390x844): {problems}"
    assert not any(t["text"] in ("Play", "Scene", "Language") for t in found["texts"])
    assert session.languages.code == "de" and session.error_count == 0, session.last_error

    laptop, laptop_session = open_page(browser, german_app, 90.0, **LAPTOP)
    button(laptop, "Abspielen").wait_for(timeout=90_000)
    close_toasts(laptop)
    laptop.get_by_text("Darstellung", exact=True).first.click()  # the collapsed folder with the long labels
    laptop.get_by_text("Zwischensysteme", exact=True).first.wait_for(timeout=30_000)
    shot(laptop, "laptop_de.png")
    problems, _ = text_problems(laptop)
    assert problems == [], f"the German laptop panel (1280x800): {problems}"
    assert laptop_session.error_count == 0, laptop_session.last_error


GERMAN_FOLDERS = (("Lektion", "Weiter ▶"), ("Für die Notizen", "Bildschirmfoto"),
                  ("Teilen", "Geteilten Moment öffnen"),
                  ("Aufgabe", "Aufgabe öffnen"), ("Meins", "Lektion importieren"))
"""The folders of the Lesson, notes, Share, Task and Mine parts in German: (title, their last button's words)."""


def folders_fit(page: Any, where: str) -> None:
    """Open each folder of GERMAN_FOLDERS in turn (its last button scrolled into view), check the
    panel's German text as drawn (`text_problems`), a screenshot each, and fold it again."""
    for title, last in GERMAN_FOLDERS:
        folder = page.get_by_text(title, exact=True).first  # the folder's title (before its widgets)
        folder.scroll_into_view_if_needed(timeout=30_000)
        folder.click()
        end = page.get_by_text(last, exact=True).last
        end.wait_for(state="visible", timeout=30_000)
        end.scroll_into_view_if_needed(timeout=30_000)
        close_toasts(page)
        shot(page, f"{where}_de_{title.split()[-1].lower()}.png")
        problems, _ = text_problems(page)
        assert problems == [], f"the German {title} folder ({where}): {problems}"
        folder.click()
        end.wait_for(state="hidden", timeout=30_000)


@pytest.fixture
def german_hall() -> Iterator[App]:
    yield from serving(language="de", presenter_code=CODE)


def test_a_german_presenter_asking_the_class_and_the_folders_fit_the_laptop_and_the_phone(
        browser, german_hall: App, german_app: App, wait_until) -> None:
    """A German laptop presents (Vorlesung, Vortragscode, Vortragen) and asks the class a choice
    through its page: the live bar and `Frage an die Klasse` with the round open are German,
    neither cut nor overlapping at 1280×800; then the Lesson, notes, Share, Task and Mine folders,
    each open in turn, on the laptop and on a German phone (390×844) of another app (no lecture
    ended there: its live bar, pinned over the panel's scroll, stays empty)."""
    app = german_hall
    page, session = open_page(browser, app, 90.0, **LAPTOP)
    button(page, "Abspielen").wait_for(timeout=90_000)
    close_toasts(page)
    open_folder(page, "Vorlesung", "Vortragscode")
    text_input(page, "Vortragscode").click()
    page.keyboard.type(CODE, delay=30)
    received(page, session, "Vortragscode", CODE)
    button(page, "Vortragen").click()
    wait_until(lambda: session.mode == "presenting", timeout=20.0)
    button(page, "Vortrag beenden").first.wait_for(timeout=30_000)
    for label, text in (("Frage", "Dreht er sich gleichmäßig?"), ("Optionen", "ja | nein")):
        field = text_input(page, label)
        field.click()
        field.fill("")
        page.keyboard.type(text, delay=5)
        received(page, session, label, text)
    button(page, "Frage an die Klasse").click()
    button(page, "Runde schließen").wait_for(timeout=30_000)
    page.get_by_text("0 von 0 geantwortet", exact=False).first.wait_for(timeout=30_000)
    for english in ("Stop presenting", "Close the round", "Vote again", "Download answers (CSV)"):
        assert button(page, english).count() == 0, english
    close_toasts(page)
    shot(page, "laptop_de_presenting.png")
    problems, _ = text_problems(page)
    assert problems == [], f"the German presenter's panel with a round open (1280x800): {problems}"
    button(page, "Vortrag beenden").first.click()  # (the live bar is pinned: the panel scrolls under it)
    wait_until(lambda: session.mode == "own", timeout=20.0)
    folders_fit(page, "laptop")
    assert session.error_count == 0, session.last_error

    phone, phone_session = open_page(browser, german_app, 90.0, **PHONE)
    details = button(phone, "Details")
    details.wait_for(timeout=90_000)
    details.tap()
    button(phone, "Details ausblenden").wait_for(timeout=30_000)
    close_toasts(phone)
    folders_fit(phone, "phone")
    assert phone_session.error_count == 0, phone_session.last_error


STATUS_WATCH = """
window.__statusAfterName = [];
(() => {
  // viser's own status words ("Connected", ...) in the page once the app's name (any language) showed.
  const shown = (word) => document.evaluate(`boolean(//*[normalize-space(text())='${word}'])`, document, null,
                                            XPathResult.BOOLEAN_TYPE, null).booleanValue;
  const names = %s;
  let named = false;
  new MutationObserver(() => {
    named = named || names.some(shown);
    if (!named) return;
    for (const word of ['Connected', 'Connecting...', 'Inactive'])
      if (shown(word) && !window.__statusAfterName.includes(word)) window.__statusAfterName.push(word);
  }).observe(document, {childList: true, subtree: true, characterData: true});
})();
"""
"""An init script (its %s: the app's names, a JSON list): `window.__statusAfterName` lists viser's
status words seen in the page after one of the names showed."""


def test_a_german_panel_header_names_the_app_in_german_and_never_says_connected(browser, german_app: App,
                                                                               wait_until) -> None:
    """The header of the control panel (viser's "Connected" when no label is set): the app's name
    in German from the first panel on, in Dutch after choosing Nederlands, never viser's status
    words once it showed.  Needs the catalogs' entry for "Rigid-body lab"."""
    german, dutch = translator("de").gettext(APP_NAME), translator("nl").gettext(APP_NAME)
    assert german != APP_NAME and dutch != APP_NAME, f"the catalogs name the app {german!r}, {dutch!r}"
    context = browser.new_context(**LAPTOP)
    try:
        context.add_init_script(STATUS_WATCH % json.dumps([APP_NAME, german, dutch]))
        before = set(german_app.sessions)
        page = context.new_page()
        page.goto(app_url(page, german_app.port), timeout=90_000)
        session = wait_until(lambda: next((s for cid, s in dict(german_app.sessions).items() if cid not in before),
                                          None), timeout=90.0)
        header = page.get_by_text(german, exact=True)
        try:
            header.first.wait_for(timeout=90_000)
        except Exception:  # noqa: BLE001 - say what the page showed instead
            raise AssertionError(f"the page never showed {german!r}; it shows: "
                                 f"{page.locator('body').inner_text()[:800]!r}") from None
        button(page, "Abspielen").wait_for(timeout=90_000)
        close_toasts(page)
        shot(page, "header_de.png")
        assert page.get_by_text("Connected", exact=True).count() == 0
        choose(page, session.gui_language, "Nederlands")
        page.get_by_text(dutch, exact=True).first.wait_for(timeout=30_000)
        assert header.count() == 0, f"{german!r} still shown after choosing Nederlands"
        assert page.evaluate("window.__statusAfterName") == [], "viser's status words came back"
        assert session.error_count == 0, session.last_error
    finally:
        context.close()
