"""The command line's words (`rigid-body-lab --help`, its errors and what it prints) in the
user's language.

The CLI's language is `--language` (the same option that sets a new browser's language): when the
command line gives one of LANGUAGES, its help, errors and start line are in it; else English.
Not the environment's locale (LANG): the app's own output then never depends on the shell it was
started from (scripts and tests that read it see English), and one option says it all
(`rigid-body-lab --language nl --help`).  `python -m physics` (a library's CLI) stays English.

`Parser` is an `argparse.ArgumentParser` whose own words (the usage line, the options' heading,
`-h`'s help, "error:") come from the app's catalogs too; argparse's messages about a bad value
("invalid choice: ...") stay Python's.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

from app.i18n import DEFAULT_LANGUAGE, LANGUAGES, N_, Translator, translator

__all__ = ["Parser", "cli_language", "cli_translator"]

def cli_language(argv: Sequence[str]) -> str:
    """The code of the CLI's language: X of `--language X` (or `--language=X`) in `argv` if it is
    one of LANGUAGES, else English."""
    for index, word in enumerate(argv):
        given = argv[index + 1] if word == "--language" and index + 1 < len(argv) else \
            word.split("=", 1)[1] if word.startswith("--language=") else None
        if given in LANGUAGES:
            return given
    return DEFAULT_LANGUAGE


def cli_translator(argv: Sequence[str]) -> Translator:
    """The translator of the CLI's language (`cli_language`)."""
    return translator(cli_language(argv))


USAGE, OPTIONS, HELP = N_("usage: "), N_("options"), N_("show this help message and exit")


class Parser(argparse.ArgumentParser):
    """An ArgumentParser speaking `tr` (its own words; the arguments' help is the caller's to translate)."""

    def __init__(self, prog: str, description: str, *, tr: Translator) -> None:
        self.tr = tr

        class Formatter(argparse.HelpFormatter):
            def add_usage(self, usage: Any, actions: Any, groups: Any, prefix: str | None = None) -> None:
                super().add_usage(usage, actions, groups, tr.gettext(USAGE) if prefix is None else prefix)

        super().__init__(prog=prog, description=description, add_help=False, formatter_class=Formatter)
        self._optionals.title = tr.gettext(OPTIONS)
        self.add_argument("-h", "--help", action="help", default=argparse.SUPPRESS, help=tr.gettext(HELP))

    def error(self, message: str) -> NoReturn:
        """Print the usage and the error (its prefix translated) to stderr; exit 2."""
        self.print_usage(sys.stderr)
        self.exit(2, self.tr.gettext("{prog}: error: {message}").format(prog=self.prog, message=message) + "\n")
