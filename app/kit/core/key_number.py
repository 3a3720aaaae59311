"""A key number of a scene, as data: what the followers' read-only panel lists below the scene
(`app.lecture.follower.FollowerStatus.key_numbers`), made by the presenter's view
(`SceneView.key_numbers`), carried across workers as plain values and written in the words of
the browser that shows it (`words`).

    KeyNumber("φ [deg]", (30.0,)).words(translator("de"))              # "φ [deg] = 30"
    KeyNumber("m", (6.0,), unit="kg", name="box.stl").words(tr)       # "box.stl: m = 6 kg"
    KeyNumber("principal moments about O", (2.5, 5.0), unit="kg m²").words(translator("nl"))
    # "hoofdtraagheidsmomenten om O = 2,5; 5 kg m²" (the label from the catalog, numbers the Dutch way)
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from app.i18n import Translator, translator

__all__ = ["MAX_KEY_CHARS", "MAX_KEY_VALUES", "KeyNumber"]

MAX_KEY_CHARS = 200
"""The longest label, unit or name a key number carries (a longer one is cut where it is made)."""
MAX_KEY_VALUES = 32
"""The most values one key number carries (a system of more masses lists the first ones)."""

_Short = Annotated[str, msgspec.Meta(max_length=MAX_KEY_CHARS)]


class KeyNumber(msgspec.Struct, frozen=True):
    """One key number.

    Attributes:
        label: what it is, an English msgid (a slider's label, "φ [deg]"; a symbol is its own msgid),
            translated where it is shown.
        values: its value or values, in the unit the label or `unit` says, rounded where made.
        unit: a unit symbol written after the values ("kg m²"; never translated), or "".
        name: a proper name it is of (a mesh's file name), written before it, or "".
    """

    label: _Short
    values: Annotated[tuple[float, ...], msgspec.Meta(max_length=MAX_KEY_VALUES)]
    unit: _Short = ""
    name: _Short = ""

    @classmethod
    def made(cls, label: str, values: tuple[float, ...] | list[float], unit: str = "", name: str = "") -> KeyNumber:
        """A key number whose texts and values are cut to what `msgspec.convert` accepts."""
        return cls(str(label)[:MAX_KEY_CHARS], tuple(float(v) for v in values)[:MAX_KEY_VALUES],
                   str(unit)[:MAX_KEY_CHARS], str(name)[:MAX_KEY_CHARS])

    def words(self, tr: Translator | None = None) -> str:
        """One line, "label = values unit" (after "name: " when it has one), the label in `tr`'s
        language and the numbers written its way (`Translator.general`; English by default),
        separated by "; " where a decimal comma would make ", " ambiguous."""
        tr = tr or translator("en")
        values = ("; " if tr.decimal_sign == "," else ", ").join(tr.general(v) for v in self.values)
        line = f"{tr.gettext(self.label)} = {values}" + (f" {self.unit}" if self.unit else "")
        return f"{self.name}: {line}" if self.name else line
