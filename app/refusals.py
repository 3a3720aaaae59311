"""`NotAllowed`: a refusal of an action this browser may not take (only the presenter may),
said in the reader's language.

It is a `PermissionError` (code that catches one keeps doing so) and a `physics.refusal.Refusal`
(an English msgid and its fields): `str(error)` stays English for logs and tests, and the error
line writes it in the browser's language (`app.roles.guard.ErrorLine`, `app.i18n.refusal_text`).

    raise NotAllowed(N_("only the presenter can point"))
"""

from __future__ import annotations

from physics.refusal import Refusal

__all__ = ["NotAllowed"]


class NotAllowed(Refusal, PermissionError):
    """A PermissionError whose message is a msgid (`template`) and its `fields` (`Refusal`)."""
