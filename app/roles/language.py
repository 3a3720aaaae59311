"""A browser's language (`Language`): the Language dropdown and the panel relabelled in it.

Each browser speaks its own language (`app.i18n`), the app's default (`--language`) at first.
Choosing another in the dropdown relabels this browser's panel only: its own widgets (the scene
and Language dropdowns) relabelled, and the scene's panel built again for the same room (its
state and its other views untouched), unless it follows a presenter (then the follower's panel,
the lectern's, is relabelled; the next view it builds, exploring, is in its language); the live
bar and the student's question panel are written again in it.

The panel's header names the app in the browser's language (`APP_NAME`, viser's panel label) in
place of viser's own English "Connected" / "Connecting..." (its icon beside it still shows the
connection's state).
"""

from __future__ import annotations

from typing import Any

from app.i18n import LANGUAGES, N_, Translator, language_named, set_translator, translator
from app.kit.view import SceneView
from app.lecture.follower import Follower
from app.lecture.lectern import Mode
from app.roles.own_room import OwnRoom
from app.roles.showing import Browser

__all__ = ["APP_NAME", "Language"]

APP_NAME = N_("Rigid-body lab")
"""The app's name: the panel's header, in each browser's language."""


class Language:
    """The language of one browser and its dropdown (module docstring).

    Args:
        browser: the session.  own_room: its own room's role (the scene dropdown, the views).
        language: the code it starts in (a key of `app.i18n.LANGUAGES`; ValueError for another).
    """

    def __init__(self, browser: Browser, own_room: OwnRoom, language: str) -> None:
        self.browser = browser
        self.own_room = own_room
        self.tr: Translator = translator(language)
        """This browser's words (`app.i18n.Translator`): its panel's translated parts speak it."""
        set_translator(browser.client.gui, self.tr)
        browser.client.gui.set_panel_label(self.tr.gettext(APP_NAME))
        self.dropdown: Any = None

    @property
    def code(self) -> str:
        return self.tr.language

    def build_dropdown(self, gui: Any) -> Any:
        """The Language dropdown (each language by its own name), its callback guarded by the session's guard."""
        _ = self.tr.gettext
        self.dropdown = gui.add_dropdown(_("Language"), tuple(LANGUAGES.values()), initial_value=LANGUAGES[self.code],
                                         hint=_("the language of this browser's panel"))
        self.dropdown.on_update(self.browser.guard("language dropdown", lambda _event: self.chosen()))
        return self.dropdown

    def choose(self, language: str) -> None:
        """Speak `language` (a code or its own name; ValueError for another), as the dropdown does."""
        code = language_named(language)
        if code is None:
            raise ValueError(f"unknown language {language!r}; choose one of {', '.join(LANGUAGES)}")
        self.dropdown.value = LANGUAGES[code]  # runs `chosen`

    def chosen(self) -> None:
        """The dropdown changed: a name that is no language (a client can send any) puts it back
        (ValueError, shown by the guard); another language relabels this browser's panel."""
        chosen = str(self.dropdown.value)
        code = language_named(chosen)
        if code is None:
            self.dropdown.value = LANGUAGES[self.code]
            raise ValueError(f"unknown language {chosen!r}")
        if code != self.code:
            self.relabel(code)

    def parts(self) -> list[Any]:
        """The panel's parts that relabel themselves (`relabel(tr)`): the error line and load note,
        the live bar and Lecture folder, Ask the class, the Lesson, notes, Share, Task and Mine
        folders (those built)."""
        browser: Any = self.browser
        names = ("errors", "lecture", "ask_panel", "lesson_runner", "notes", "share", "task_panel", "own_panel")
        return [part for name in names if hasattr(part := getattr(browser, name, None), "relabel")]

    def relabel(self, language: str) -> None:
        """This browser's panel in `language` (module docstring)."""
        browser = self.browser
        self.tr = translator(language)
        set_translator(browser.client.gui, self.tr)
        _ = self.tr.gettext
        with browser.client.atomic():
            browser.client.gui.set_panel_label(_(APP_NAME))
            self.dropdown.label = _("Language")
            self.dropdown.hint = _("the language of this browser's panel")
            browser.projector_layout.relabel(self.tr)
            following = browser.showing.mode is Mode.FOLLOWING
            dropdown = browser.gui_scene
            title = self.own_room.scene_title(str(dropdown.value)) if following else browser.showing.room.scene.title
            self.own_room.relabel_dropdown(dropdown, title)
            view = browser.showing.view
            if following and isinstance(view, Follower):
                view.relabel(self.tr)
            if not following and isinstance(view, SceneView):
                self.own_room.rebuild_view()
            for part in self.parts():
                part.relabel(self.tr)  # the presenter's parts and the folders (`app.i18n.Labels`)
            if browser.question is not None:
                browser.question.redraw()
