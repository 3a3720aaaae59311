"""The command line's words (`rigid-body-lab --help`, its errors and what it prints) in the
user's language.

The CLI's language is `--language` (the same option that sets a new browser's language): when the
command line gives one of LANGUAGES, its help, errors and start line are in it; else English.
Not the environment's locale (LANG): the app's own output then never depends on the shell it was
started from (scripts and tests that read it see English), and one option says it all
(`rigid-body-lab --language nl --help`).  `python -m physics` (a library's CLI) stays English.

`Parser` is an `argparse.ArgumentParser` whose own words (the usage line, the options' heading,
`-h`'s help, "error:") come from the app's catalogs too, and so do argparse's messages about
a bad command line ("invalid choice: ...", matched in Python's English by `ARGPARSE_ERRORS`; a
message of another Python that no entry matches stays as argparse wrote it).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

from app.i18n import DEFAULT_LANGUAGE, LANGUAGES, N_, Phrases, Translator, translator

__all__ = ["ARGPARSE_ERRORS", "Parser", "cli_language", "cli_translator"]

_ARGPARSE_ENTRIES = (
    (r"invalid choice: (?P<value>.+) \(choose from (?P<choices>.+)\)",
     N_("invalid choice: {value} (choose from {choices})")),
    (r"invalid (?P<type>\w+) value: (?P<value>.+)", N_("invalid {type} value: {value}")),
    (r"expected one argument", N_("expected one argument")),
    (r"unrecognized arguments: (?P<arguments>.+)", N_("unrecognized arguments: {arguments}")),
    (r"the following arguments are required: (?P<arguments>.+)",
     N_("the following arguments are required: {arguments}")),
    (r"ambiguous option: (?P<option>\S+) could match (?P<matches>.+)",
     N_("ambiguous option: {option} could match {matches}")),
)
ARGPARSE_ERRORS = Phrases((r"argument (?P<argument>\S+): (?P<message>.+)", N_("argument {argument}: {message}")),
                          *_ARGPARSE_ENTRIES, nested={"message": Phrases(*_ARGPARSE_ENTRIES)})
"""argparse's messages about a bad command line (Python 3.11's English) and their msgids."""


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
        message = ARGPARSE_ERRORS.in_language(message, self.tr)
        self.exit(2, self.tr.gettext("{prog}: error: {message}").format(prog=self.prog, message=message) + "\n")
