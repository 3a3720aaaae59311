"""`Refusal`: an error whose words a caller may say in another language.

physics speaks English (`str(error)`, its CLI's words); an app that speaks the user's language
translates `error.template` (an English message with `{name}` placeholders, marked `N_` so that
a gettext extractor finds it here) and fills in `error.fields` (strings, numbers already written
as physics writes them).  physics never imports a translation layer.

    raise InertiaError(N_("moment I{k} = {value} is not positive"), k="3", value="-1")
"""

from __future__ import annotations

__all__ = ["N_", "Refusal"]


def N_(message: str) -> str:  # noqa: N802 - gettext's name for "mark only"
    """Mark `message` for a gettext extractor; returns it unchanged."""
    return message


class Refusal(ValueError):
    """A ValueError whose message is `template.format(**fields)`.

    Attributes:
        template: the English message with `{name}` placeholders (the msgid a translation uses).
        fields: name -> text filled into the template (none: `template` is the message as it is).
    """

    def __init__(self, template: str, **fields: object) -> None:
        self.template = template
        self.fields = {name: str(value) for name, value in fields.items()}
        super().__init__(template.format(**self.fields) if fields else template)
