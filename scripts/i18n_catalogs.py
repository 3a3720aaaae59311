"""The translation catalogs (app/locale, `app.i18n`): extract, update, compile, check.

    python scripts/i18n_catalogs.py extract   # app/**.py, physics/**.py (babel.cfg), assets/presets -> messages.pot
    python scripts/i18n_catalogs.py update    # the .pot merged into every app/locale/<lang>/LC_MESSAGES/messages.po
    python scripts/i18n_catalogs.py compile   # every .po -> its .mo beside it (the wheel's build does this too)
    python scripts/i18n_catalogs.py check     # exit 1 naming every entry untranslated or fuzzy
    python scripts/i18n_catalogs.py init xx   # a new language's messages.po from the .pot

The marks extracted: `_("...")`, `N_("...")`, `gettext("...")` (also as `tr.gettext`), and
`ngettext("one", "many", n)`; never one inside an f-string (the extractor does not look there).
Translate in the .po files (msgstr); `check` and tests/test_i18n.py fail while any entry is empty
or fuzzy.  A new language also needs its line in `app.i18n.LANGUAGES`.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LOCALE = ROOT / "app" / "locale"
POT = LOCALE / "messages.pot"
KEYWORDS = ("_", "N_", "gettext", "ngettext:1,2")


def pybabel(*args: str) -> None:
    """Run Babel's command line (`pybabel ...`) in this process."""
    from babel.messages.frontend import CommandLineInterface  # noqa: PLC0415

    CommandLineInterface().run(["pybabel", "-q", *args])


def po_files() -> list[Path]:
    return sorted(LOCALE.glob("*/LC_MESSAGES/messages.po"))


PRESETS = ROOT / "assets" / "presets"
PRESET_WORDS = ("group", "name", "note")
"""What a person reads of a preset (assets/presets/*.json): its row's label, its button, its note."""


def extract(out: Path = POT) -> Path:
    """The marked strings of app/**.py and physics/**.py (babel.cfg) and the presets' words
    (`preset_messages`) into the template `out`; `out`."""
    keywords = [arg for keyword in KEYWORDS for arg in ("-k", keyword)]
    pybabel("extract", "-F", str(ROOT / "babel.cfg"), "--no-default-keywords", *keywords, "--sort-by-file",
            "--no-wrap", "--project", "rigid-body-lab", "-o", str(out), str(ROOT))
    # Paths relative to the checkout (the .pot is the same on every machine).
    out.write_text(out.read_text(encoding="utf-8").replace(str(ROOT) + "/", ""), encoding="utf-8")
    add_preset_messages(out)
    return out


def preset_messages() -> list[tuple[str, str]]:
    """(text, where) of every preset's group, name and note in assets/presets/*.json."""
    import json  # noqa: PLC0415

    found = []
    for path in sorted(PRESETS.glob("*.json")):
        for index, preset in enumerate(json.loads(path.read_text(encoding="utf-8")).get("presets", [])):
            for key in PRESET_WORDS:
                if isinstance(preset.get(key), str) and preset[key]:
                    found.append((preset[key], f"{path.relative_to(ROOT)}:{index + 1}"))
    return found


def add_preset_messages(pot: Path) -> None:
    """The presets' words appended to the template `pot` (each once, where it is first found; a
    text the code marks already is left where it is)."""
    from babel.messages.pofile import escape, read_po  # noqa: PLC0415

    with pot.open("rb") as handle:
        known = {message.id for message in read_po(handle)}
    blocks = []
    for text, where in preset_messages():
        if text not in known:
            known.add(text)
            blocks.append(f"#: {where}\nmsgid {escape(text)}\nmsgstr \"\"\n")
    with pot.open("a", encoding="utf-8") as handle:
        handle.write("".join("\n" + block for block in blocks))


def update() -> None:
    pybabel("update", "-i", str(POT), "-d", str(LOCALE), "--no-wrap", "--ignore-obsolete")


def compile_all() -> list[Path]:
    """Every .po compiled to the .mo beside it; the .mo files."""
    sys.path.insert(0, str(ROOT))
    from app.i18n import compile_po  # noqa: PLC0415

    written = []
    for po in po_files():
        mo = po.with_suffix(".mo")
        mo.write_bytes(compile_po(po.read_bytes(), locale=po.parent.parent.name))
        written.append(mo)
    return written


def problems() -> list[str]:
    """Every entry of every .po that is untranslated (an empty msgstr) or fuzzy, named."""
    from babel.messages.pofile import read_po  # noqa: PLC0415

    found = []
    for po in po_files():
        with po.open("rb") as handle:
            catalog = read_po(handle)
        for message in catalog:
            if not message.id:
                continue
            strings = message.string if isinstance(message.string, tuple) else (message.string,)
            if message.fuzzy or not all(strings):
                found.append(f"{po.relative_to(ROOT)}: {'fuzzy' if message.fuzzy else 'untranslated'}: "
                             f"{message.id!r}")
    return found


def main(argv: list[str]) -> int:
    command = argv[0] if argv else ""
    if command == "extract":
        extract()
    elif command == "update":
        update()
    elif command == "compile":
        for mo in compile_all():
            print(mo.relative_to(ROOT))
    elif command == "check":
        found = problems()
        print("\n".join(found) or "every entry translated")
        return 1 if found else 0
    elif command == "init" and len(argv) == 2:
        pybabel("init", "-i", str(POT), "-d", str(LOCALE), "-l", argv[1], "--no-wrap")
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
