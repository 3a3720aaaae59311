"""The translation layer: every word a person reads in a translated part of the panel goes
through a `Translator` (gettext catalogs read with Babel), chosen per browser.

Catalogs: `app/locale/<lang>/LC_MESSAGES/messages.po` in the repository (`messages.pot` beside
them is what extraction finds), compiled to `messages.mo` by the wheel's build (setup.py) so the
wheel carries them; they are read with `importlib.resources`.  A checkout (`python -m app`, the
tests, an editable install) compiles a `.po` in memory when its `.mo` is missing or older.
The workflow (extract -> update -> translate -> compile -> check): `scripts/i18n_catalogs.py`.

    tr = translator("nl")
    tr.gettext("Scene")                            # "Scène"
    tr.ngettext("{n} answer", "{n} answers", 3)    # plural forms from the catalog's header
    tr.decimal(1.5, 2)                              # "1,50": a number a person reads, never one typed

Marking: `_("...")` (a local `_ = tr.gettext`) where a string is used, `N_("...")` for a module
constant translated later (`tr.gettext(CONSTANT)`); the keywords are in babel.cfg.

Per browser: a session sets its panel's translator (`set_translator(client.gui, tr)`); a view
reads it from the GUI its panel goes to (`for_gui(gui)`), English for a GUI nobody set (a
recorder, a tool).  A part built once per browser keeps its widgets' English words in a `Labels`
and writes them again in the language the browser chooses (`Labels.relabel`).  English is the
msgids themselves (no catalog): the English panel is the app's words as they always were,
numbers written as Python writes them.
"""

from __future__ import annotations

import functools
import gettext as _gettext
import io
import re
import threading
from collections.abc import Callable, Iterable, Mapping
from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any
from weakref import WeakKeyDictionary

__all__ = [
    "DEFAULT_LANGUAGE",
    "DOMAIN",
    "LANGUAGES",
    "Labels",
    "N_",
    "Phrases",
    "Said",
    "Words",
    "Translator",
    "catalog_bytes",
    "compile_po",
    "for_gui",
    "language_named",
    "locale_dir",
    "refusal_text",
    "set_translator",
    "translator",
    "written",
]

LANGUAGES: dict[str, str] = {"en": "English", "nl": "Nederlands", "de": "Deutsch"}
"""Code -> the language's own name (the Language dropdown's options: each in its own language)."""
DEFAULT_LANGUAGE = "en"
DOMAIN = "messages"


def N_(message: str) -> str:  # noqa: N802 - gettext's name for "mark only"
    """Mark `message` for extraction; translated where it is used (`Translator.gettext`)."""
    return message


def locale_dir() -> Traversable:
    """app/locale: `<lang>/LC_MESSAGES/messages.{po,mo}` (the .po only in a checkout)."""
    return resources.files("app") / "locale"


def compile_po(po_text: bytes, *, locale: str) -> bytes:
    """The .mo bytes of a .po file's bytes (fuzzy entries left out, as gettext does)."""
    from babel.messages.mofile import write_mo  # noqa: PLC0415 - only when a catalog is compiled
    from babel.messages.pofile import read_po  # noqa: PLC0415

    catalog = read_po(io.BytesIO(po_text), locale=locale)
    out = io.BytesIO()
    write_mo(out, catalog, use_fuzzy=False)
    return out.getvalue()


def catalog_bytes(language: str) -> bytes:
    """The compiled catalog (.mo bytes) of `language`: the .mo file, or the .po compiled in
    memory when the .mo is missing or older than it (a checkout).  FileNotFoundError if neither."""
    folder = locale_dir() / language / "LC_MESSAGES"
    mo, po = folder / f"{DOMAIN}.mo", folder / f"{DOMAIN}.po"
    if mo.is_file() and not (po.is_file() and _older(mo, po)):
        return mo.read_bytes()
    if po.is_file():
        return compile_po(po.read_bytes(), locale=language)
    raise FileNotFoundError(f"no catalog for {language!r} in {folder}")


def _older(mo: Traversable, po: Traversable) -> bool:
    """The .mo was written before the .po (both files on disk); False where times are unknown."""
    if isinstance(mo, Path) and isinstance(po, Path):
        return mo.stat().st_mtime < po.stat().st_mtime
    return False


class Translator:
    """One language's words and numbers.

    Attributes:
        language: its code (a key of LANGUAGES).
    """

    def __init__(self, language: str, translations: _gettext.NullTranslations) -> None:
        self.language = language
        self._translations = translations
        self._english: dict[str, tuple[str, ...]] | None = None  # translation -> msgids, at first use

    def gettext(self, message: str) -> str:
        """`message` (an English msgid) in this language; itself when the catalog lacks it or it is ""."""
        return self._translations.gettext(message) if message else message

    __call__ = gettext

    def ngettext(self, singular: str, plural: str, n: int) -> str:
        """The singular or plural form for `n`, as this language's plural rule says."""
        return self._translations.ngettext(singular, plural, n)

    def english(self, text: str, among: Iterable[str] | None = None) -> str:
        """The English msgid `text` translates (a widget's label back to the name code and
        lessons use: "Hoekbogen" -> "Angle arcs"); `text` itself when no entry translates to it.
        Two msgids may share a translation (German "Knotenlinie" is "Line of nodes" and "line of
        nodes"): `among` (the English words the widget can show) picks the one meant."""
        found = self.englishes(text)
        if among is not None:
            wanted = set(among)
            found = tuple(m for m in found if m in wanted)
        return found[0] if found else text

    def englishes(self, text: str) -> tuple[str, ...]:
        """Every English msgid that translates to `text` (in catalog order; () when none does)."""
        if self._english is None:
            catalog = getattr(self._translations, "_catalog", {})
            english: dict[str, tuple[str, ...]] = {}
            for key, value in catalog.items():
                if isinstance(key, str) and key and isinstance(value, str):
                    english[value] = (*english.get(value, ()), key)
            self._english = english
        return self._english.get(text, ())

    def all(self, messages: Iterable[str]) -> tuple[str, ...]:
        """Each of `messages` translated."""
        return tuple(self.gettext(m) for m in messages)

    def decimal(self, value: float, decimals: int) -> str:
        """`value` with `decimals` digits after the separator, as this language writes a number to
        read (no grouping): English "1.50", Dutch and German "1,50".  Never for a value typed or parsed."""
        if self.language == DEFAULT_LANGUAGE:
            return f"{value:.{decimals}f}"
        from babel.numbers import format_decimal  # noqa: PLC0415 - Babel's number formats

        pattern = "0." + "0" * decimals if decimals > 0 else "0"
        return str(format_decimal(value, format=pattern, locale=self.language, group_separator=False))

    def general(self, value: float) -> str:
        """`value` as Python's `:g` writes it (up to 6 significant digits), with this language's
        decimal separator: English "0.1", Dutch and German "0,1"."""
        return self.local_point(f"{value:g}")

    @property
    def decimal_sign(self) -> str:
        """The sign this language writes between a number's whole part and its fraction ("." or ",")."""
        if self.language == DEFAULT_LANGUAGE:
            return "."
        from babel.numbers import get_decimal_symbol  # noqa: PLC0415

        return str(get_decimal_symbol(self.language))

    def local_point(self, number: str) -> str:
        """A number as Python wrote it ("4.2") with this language's decimal sign ("4,2")."""
        return number if self.language == DEFAULT_LANGUAGE else number.replace(".", self.decimal_sign)

    def __repr__(self) -> str:
        return f"Translator({self.language!r})"


def refusal_text(error: BaseException, tr: Translator, fields: Mapping[str, Any] | None = None) -> str:
    """What `error` says, in the language of `tr`: a refusal from `physics` (`physics.refusal.Refusal`:
    an English template marked where it is raised, and its fields) translated and filled in, with
    `fields` in place of its own where given (some already written in `tr`'s language); any other
    error's own words (English)."""
    template, own = getattr(error, "template", None), getattr(error, "fields", None)
    if not (isinstance(template, str) and isinstance(own, dict)):
        return str(error)
    if not own:  # the template is the message as it is (no placeholders filled)
        return tr.gettext(template)
    try:
        return tr.gettext(template).format(**(own if fields is None else fields))
    except (KeyError, IndexError, ValueError):  # a catalog entry that lost a placeholder: physics' words
        return str(error)


class Said:
    """Words on a person's screen kept as data, so that they are said again in another language
    when the browser changes its language (`app.kit.panel.gui.MessageLine`): `msgid` (English with
    `{name}` placeholders, marked `N_` where it is written) and its fields, filled in as given.
    Called with a translator, it is the words in that language.

        said = Said(N_("No preset named {name}."), name="'spin'")
        said(translator("de"))  # 'Keine Voreinstellung namens 'spin'.'
    """

    __slots__ = ("fields", "msgid")

    def __init__(self, msgid: str, **fields: object) -> None:
        self.msgid = msgid
        self.fields = {name: str(value) for name, value in fields.items()}

    def __call__(self, tr: Translator) -> str:
        text = tr.gettext(self.msgid)
        try:
            return text.format(**self.fields) if self.fields else text
        except (KeyError, IndexError, ValueError):  # a catalog entry that lost a placeholder: the English
            return self.msgid.format(**self.fields)

    def __repr__(self) -> str:
        return f"Said({self.msgid!r}, **{self.fields!r})"


Words = str | Callable[[Translator], str]
"""Words for a person kept so that they can be written in any language: a function of a
translator writing them in its language (`Said`, `functools.partial(PHRASES.in_language,
english)`), or a text that stays as it is."""


def written(words: Words, tr: Translator) -> str:
    """`words` written in `tr`'s language (a plain text as it is)."""
    return words if isinstance(words, str) else words(tr)


class Phrases:
    """English sentences a lower layer writes whole (a refusal, a verdict), matched as a whole
    and written in a browser's language: each entry is (a regular expression matching the English
    sentence, with named groups; the msgid its translation is, with the same names as placeholders).

        REFUSALS = Phrases((r"too fast: at most (?P<rate>[0-9]+) answers a second",
                            N_("too fast: at most {rate} answers a second")))
        REFUSALS.in_language("too fast: at most 5 answers a second", translator("nl"))

    Args:
        entries: (pattern, msgid), tried in order (the first whole match is taken).
        translated: group names whose text is a msgid too (a scene's title): translated.
        numbers: group names whose text is a number as Python wrote it: its decimal point
            written the language's way.
        nested: group name -> the Phrases its text is (a verdict inside a sentence): written by those.
    """

    def __init__(self, *entries: tuple[str, str], translated: Iterable[str] = (), numbers: Iterable[str] = (),
                 nested: dict[str, Phrases] | None = None) -> None:
        self.entries = tuple((re.compile(pattern, re.S), msgid) for pattern, msgid in entries)
        self.translated, self.numbers = frozenset(translated), frozenset(numbers)
        self.nested = dict(nested or {})

    @property
    def msgids(self) -> tuple[str, ...]:
        """The msgids of the entries, in order."""
        return tuple(msgid for _pattern, msgid in self.entries)

    def words(self, text: str, tr: Translator) -> str | None:
        """`text` in `tr`'s language when an entry matches it whole; None when none does."""
        for pattern, msgid in self.entries:
            found = pattern.fullmatch(text)
            if found is None:
                continue
            fields = {name: self._field(name, value or "", tr) for name, value in found.groupdict().items()}
            return tr.gettext(msgid).format(**fields)
        return None

    def in_language(self, text: str, tr: Translator) -> str:
        """`text` in `tr`'s language (`words`); `text` as it is when no entry matches it."""
        found = self.words(text, tr)
        return text if found is None else found

    def _field(self, name: str, value: str, tr: Translator) -> str:
        if name in self.nested:
            return self.nested[name].in_language(value, tr)
        if name in self.translated:
            return tr.gettext(value)
        if name in self.numbers:
            return tr.local_point(value)
        return value


@functools.cache
def translator(language: str) -> Translator:
    """The translator of `language` (a key of LANGUAGES), read once; ValueError for another code."""
    if language not in LANGUAGES:
        raise ValueError(f"unknown language {language!r}; choose one of {', '.join(LANGUAGES)}")
    if language == DEFAULT_LANGUAGE:
        return Translator(language, _gettext.NullTranslations())
    from babel.support import Translations  # noqa: PLC0415

    return Translator(language, Translations(io.BytesIO(catalog_bytes(language)), domain=DOMAIN))


def language_named(name: str) -> str | None:
    """The code of a language given by its code or its own name ("nl", "Nederlands"); None if unknown."""
    if name in LANGUAGES:
        return name
    return next((code for code, own in LANGUAGES.items() if own == name), None)


_BY_GUI: WeakKeyDictionary[Any, Translator] = WeakKeyDictionary()
_BY_GUI_LOCK = threading.Lock()


def set_translator(gui: Any, tr: Translator) -> None:
    """The panel built in `gui` (a browser's `client.gui`) speaks `tr` from now on."""
    with _BY_GUI_LOCK:
        _BY_GUI[gui] = tr


def for_gui(gui: Any) -> Translator:
    """The translator of the browser whose panel `gui` is; English for a GUI nobody set."""
    with _BY_GUI_LOCK:
        found = _BY_GUI.get(gui)
    return found if found is not None else translator(DEFAULT_LANGUAGE)


class Labels:
    """The words of one panel part's widgets, kept as English msgids and written in a browser's
    language: `take` a handle made with English words (marked `N_`), `relabel` writes every
    handle's label, hint (and, for a dropdown taken with `options=True`, its options, the value
    kept) in a translator's language, sending only what changed.

    Args:
        gui: the browser's panel (its translator, `for_gui`, is the language `take` writes in).
    """

    def __init__(self, gui: Any) -> None:
        self.gui = gui
        self.tr = for_gui(gui)
        self._taken: list[tuple[Any, str, str, tuple[str, ...] | None, dict[str, Any]]] = []

    def take(self, *handles: Any, options: bool = False, **fields: Any) -> None:
        """Keep `handles`' English label and hint (and options) and write them in this part's
        language; `fields` fill the placeholders of a label or hint msgid (`{seconds}`; a str field
        is a msgid too, translated)."""
        for handle in handles:
            label, hint = str(getattr(handle, "label", "") or ""), str(getattr(handle, "hint", "") or "")
            kept = tuple(str(o) for o in handle.options) if options else None
            self._taken.append((handle, label, hint, kept, fields))
            self._write(handle, label, hint, kept, fields, translator(DEFAULT_LANGUAGE))

    def relabel(self, tr: Translator | None = None) -> None:
        """Every handle taken in `tr`'s language (the browser's now by default)."""
        old, self.tr = self.tr, tr or for_gui(self.gui)
        for handle, label, hint, kept, fields in self._taken:
            self._write(handle, label, hint, kept, fields, old)

    def option(self, english: str) -> str:
        """A dropdown's option `english` as this part shows it now."""
        return self.tr.gettext(english)

    def english(self, shown: Any) -> str:
        """The English option of a dropdown's value shown (`option`'s inverse)."""
        kept = {o for _handle, _label, _hint, options, _fields in self._taken for o in options or ()}
        return self.tr.english(str(shown), kept or None)

    def _write(self, handle: Any, label: str, hint: str, kept: tuple[str, ...] | None, fields: dict[str, Any],
               old: Translator) -> None:
        tr = self.tr
        fields = {name: tr.gettext(value) if isinstance(value, str) else value for name, value in fields.items()}
        if label and handle.label != (text := tr.gettext(label).format(**fields) if fields else tr.gettext(label)):
            handle.label = text
        if hint and handle.hint != (text := tr.gettext(hint).format(**fields) if fields else tr.gettext(hint)):
            handle.hint = text
        if kept is not None:
            value = old.english(str(handle.value), kept)
            shown = tuple(tr.gettext(o) for o in kept)
            if tuple(handle.options) != shown:
                handle.options = shown
                if type(handle).__name__ != "GuiButtonGroupHandle":  # a button group keeps no value
                    handle.value = tr.gettext(value) if value in kept else shown[0]
