"""A task's refusals and a receipt's line as a person reads them: in their browser's language.

The stores (`app.tasks.store`, `app.tasks.model`, `app.sharestore`) raise in English (logs, tools)
with the msgid and its fields (`physics.refusal.Refusal`: `template`, `fields`); the Task folder
says them in the reader's language (`refusal_words`): a judge's refusal inside one ("Not judged:
this question is about the Heavy top scene; ...") written by `app.ask.verdict_words`, a field's
name ("Name: at most 80 characters, got 95") translated; codes, dates and numbers as they are.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from app.ask.verdict_words import judge_refusal_words, verdict_in_language
from app.i18n import N_, Translator, refusal_text
from app.sharestore import format_code
from app.tasks.model import Submission, Task, iso_time

__all__ = ["cell", "receipt_words", "refusal_words"]

FIELD_NAMES = (N_("Name"), N_("Student number"))
"""The fields a student types whose name a refusal says (`model.check_student`'s `where`)."""


def refusal_words(error: BaseException, tr: Translator, names: Mapping[str, str] | None = None) -> str:
    """What `error` says, in `tr`'s language (`app.i18n.refusal_text`), its `error` field (an
    answer's check or a judge's words) and `where` (a field's name) translated too; `names`: a
    field's name -> the msgid a form calls it ("words" -> "Words for the task")."""
    fields = getattr(error, "fields", None)
    if not isinstance(fields, dict):
        return refusal_text(error, tr)
    shown = dict(fields)
    if "error" in shown:
        shown["error"] = judge_refusal_words(str(shown["error"]), tr)
    if "where" in shown:
        where = str(shown["where"])
        shown["where"] = tr.gettext((names or {}).get(where, where))
    return refusal_text(error, tr, shown)


def receipt_words(found: Submission, task: Task, tr: Translator) -> str:
    """The lecturer's line about a receipt's submission (Markdown) in `tr`'s language: who, which
    question and attempt, the verdict (translated) and when; another task's receipt said so."""
    _ = tr.gettext
    if found.task != task.code:
        return _("The receipt {receipt} is not of the task {task}.").format(receipt=format_code(found.receipt),
                                                                             task=task.shown_code)
    who = " ".join(part for part in (found.student.name, found.student.number) if part)
    return _("Receipt **{receipt}**: {who}, question {question}, attempt {attempt}: {verdict} · submitted {at}").format(
        receipt=format_code(found.receipt), who=cell(who), question=found.question + 1, attempt=found.attempt,
        verdict=cell(verdict_in_language(found.words, tr)), at=iso_time(found.at))


def cell(text: Any) -> str:
    """A student's words in a Markdown table cell or line (no pipes, no markup)."""
    return "".join(" " if c in "|\\`*_[]<>#" else c for c in str(text))
