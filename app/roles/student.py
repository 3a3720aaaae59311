"""Answering the class's question (`Student`, every browser but the presenter's).

A browser answers the round asked now (`app.ask`) under its anonymous token, never sent and
never shown; a State question is answered from its own room (a follower leaves with an exact
copy first: `answer_from_copy`).  The question panel (`app.hall.ask_student`) shows
the round; the presenter's `Ask the class` folder (`app.hall.ask_presenter`) shows instead
while this browser presents.
"""

from __future__ import annotations

from typing import Any

from app.ask import new_token
from app.ask.judges import read_state
from app.hall.ask import AnswerPanel
from app.i18n import N_
from app.lecture.follower import Follower
from app.lecture.lectern import Mode
from app.refusals import NotAllowed
from app.roles.following import Following
from app.roles.showing import Browser

__all__ = ["Student"]


class Student:
    """A browser's answers and the question shown (module docstring); what its question panel
    drives (`app.hall.ask_kinds.Student`).

    Owned by the browser's session for its life.

    Args:
        browser: the session.  following: the follower's role (a State answer's copy).

    Attributes:
        client: the browser.
        answer_token: this browser's anonymous answers' token, for the browser's life.
    """

    def __init__(self, browser: Browser, following: Following) -> None:
        self.browser = browser
        self.client = browser.client
        self.showing = browser.showing
        self.following = following
        self.answer_token = new_token()

    @property
    def mode(self) -> Mode:
        """The browser's mode (`Showing.mode`; a State question's widget reads it)."""
        return self.showing.mode

    def build_question(self, *, order: float) -> AnswerPanel | None:
        """The question panel at `order` (None without a lecture hall)."""
        lectern = self.browser.lectern
        return None if lectern is None else AnswerPanel(self, self.browser.guard, lectern.rounds, order=order)

    def answer(self, value: Any) -> Any:
        """Answer the round the class is asked now with `value` (an option's index, a 3-vector,
        a state dict, a number); the answer as kept.  `app.ask.Refused` (a ValueError with the
        reason) for a refused answer; PermissionError for the presenter."""
        lectern = self.browser.lectern
        if self.showing.mode is Mode.PRESENTING:
            raise NotAllowed(N_("the presenter asks; the class answers"))
        if lectern is None:
            raise RuntimeError("this app has no lecture hall")
        return lectern.rounds.answer(self.answer_token, value)

    def my_answer(self) -> Any:
        """This browser's answer to the round shown, or None."""
        lectern = self.browser.lectern
        return None if lectern is None else lectern.rounds.mine(self.answer_token)

    def state_answer(self) -> Any:
        """This browser's own room's state, as a State question takes it (`app.ask.judges.read_state`)."""
        if self.showing.mode is not Mode.OWN:
            raise NotAllowed(N_("answer from your own copy: press 'Answer from my copy' first"))
        return read_state(self.showing.own_room)

    def answer_from_copy(self) -> None:
        """A State question: leave the presenter with an exact copy of the room to answer from."""
        if self.showing.mode is Mode.FOLLOWING:
            self.following.explore()

    def folded_for_question(self, folded: bool) -> None:
        """While a question waits for this browser's answer, the follower's panel is folded away."""
        view = self.showing.view
        if self.showing.mode is Mode.FOLLOWING and isinstance(view, Follower) and view.folder.visible == folded:
            view.folder.visible = not folded

    def show_questions(self) -> None:
        """The presenter's `Ask the class` folder while presenting; a student's question otherwise."""
        browser = self.browser
        if browser.ask_panel is not None and browser.question is not None:
            presenting = self.showing.mode is Mode.PRESENTING
            browser.ask_panel.set_shown(presenting)
            browser.question.active = not presenting
            browser.question.refresh()

    def questions_changed(self) -> bool:
        """Show the round as it is now (the count, a student's question): called by the app loop,
        outside the guard; skipped (False) while one of this browser's callbacks runs, so the
        app loop never waits for a browser (it calls again soon)."""
        browser = self.browser
        if browser.closed or browser.question is None:
            return True
        if not browser.lock.acquire(blocking=False):
            return False
        try:
            if self.showing.mode is Mode.PRESENTING and browser.ask_panel is not None:
                browser.ask_panel.refresh()
            browser.question.refresh()
        except Exception as error:  # noqa: BLE001 - the app loop must not die from a browser
            browser.report_error("question", error)
        finally:
            browser.lock.release()
        return True
