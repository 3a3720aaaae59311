"""Presenting (`Presenting`, the presenter's role): this browser's room live for every follower.

`present(code)` takes the presenter lock (`Lectern.try_code`; a refusal is said in the Lecture
folder and changes nothing); a follower first leaves with an exact copy of what is on screen,
which then goes live.  `stop` releases the lock: the followers keep the last state, this
browser keeps the room.  While presenting it calls everyone back, steps a lesson for the
followers (their status and caption), and asks the class (`app.ask`): a round asked, closed,
asked again, a student's state answer played in its room.
"""

from __future__ import annotations

from typing import Any

from app.ask import Question, Round, Rounds
from app.ask.gallery import play_answer
from app.ask.state_tally import gallery_entries
from app.hall.ask import AskPanel
from app.hall.lecture_panel import LecturePanel
from app.i18n import N_
from app.kit.core.room import Room
from app.lecture.lectern import Lectern, Mode
from app.refusals import NotAllowed
from app.roles.following import Following
from app.roles.own_room import OwnRoom
from app.roles.showing import Browser

__all__ = ["Presenting"]


class Presenting:
    """Present, stop presenting, and what only the presenter does (module docstring).

    Owned by the browser's session for its life; holds no state of its own (the lock is the
    lectern's, the mode `Showing.mode`).

    Args:
        browser: the session.  own_room: its own room's role (the views).
        following: the follower's role (a follower that presents explores a copy first).
    """

    def __init__(self, browser: Browser, own_room: OwnRoom, following: Following) -> None:
        self.browser = browser
        self.showing = browser.showing
        self.own_room = own_room
        self.following = following

    def build_ask_panel(self, *, order: float) -> AskPanel | None:
        """The presenter's `Ask the class` folder at `order` (None without a lecture hall)."""
        browser, lectern = self.browser, self.browser.lectern
        if lectern is None:
            return None
        return AskPanel(browser.client, browser.guard, lectern.rounds, order=order,
                        audience=lambda: sum(lectern.total_audience()),
                        scene_title=lambda: self.showing.room.scene.title,
                        presenting=lambda: self.showing.mode is Mode.PRESENTING, play=self.play_state)

    def _hall(self) -> tuple[Lectern, LecturePanel]:
        browser = self.browser
        if browser.lectern is None or browser.lecture is None:
            raise RuntimeError("this app has no lecture hall")
        return browser.lectern, browser.lecture

    def present(self, code: str) -> None:
        """Become the presenter with `code`: this browser's room goes live for every follower."""
        lectern, panel = self._hall()
        browser, showing = self.browser, self.showing
        if lectern.try_code(browser, code) is not None:
            panel.refused()  # the lectern's words, kept true while shown
            return
        panel.note("")
        showing.came_after_lecture = False
        copy_note = ""
        if showing.mode is Mode.FOLLOWING:
            copy_note = self.following.explore()  # an exact copy of what is on screen, then it goes live
        browser.narrow.end()  # a presenter has the whole panel
        with showing.switch_lock:
            panel.gui_code.value = ""
            self._go_live(showing.room)
            showing.mode = Mode.PRESENTING
            browser.narrow.end()  # again: a phone's fold begun at connect meanwhile ends here
        lectern.start(browser)
        browser.show_mode()
        panel.set_pointer(bool(panel.gui_pointer.value))
        if copy_note:
            showing.scene_view().show_message(copy_note)  # what the new presenter took over

    def _go_live(self, room: Room) -> None:
        """The view of `room` goes; a live one replaces it (within the switch)."""
        showing = self.showing
        showing.hide_live(False)  # first: removing the shadow removes what this browser has under it
        with room.lock:
            if showing.view is not None:
                showing.view.remove()
            showing.view = self.own_room.live_view(room)

    def stop(self) -> None:
        """Release the lock; the followers keep the last state; this browser keeps the room."""
        browser, showing = self.browser, self.showing
        lectern = browser.lectern
        if lectern is None or showing.mode is not Mode.PRESENTING:
            return
        lectern.release(browser, disconnected=False)
        with showing.switch_lock:
            room = showing.room
            with room.lock:
                showing.scene_view().remove_panel()  # its shared nodes stay: the followers' last state
                showing.mode = Mode.OWN
                showing.view = self.own_room.new_view(room)
            showing.hide_live(True)
        browser.show_mode()
        if browser.lecture is not None:
            browser.lecture.set_pointer(False)

    def call_back(self) -> None:
        """Ask every explorer back to the presenter (the `Call everyone back` button), in the guard."""
        _, panel = self._hall()
        self.browser.guard("call everyone back", panel.call_back)()

    def lesson_stepped(self) -> None:
        """The lesson moved a step: the followers see it; a step's question fills `Ask the class`."""
        browser = self.browser
        if browser.lectern is not None and browser.lectern.presenter is browser:
            browser.lectern.refresh_followers()
        lesson, k = browser.lesson_runner.lesson, browser.lesson_runner.step
        language = browser.lesson_runner.tr.language  # the question as the lecturer reads the lesson
        question = lesson.steps[k].ask_in(language) if lesson is not None and 0 <= k < len(lesson.steps) else None
        if question is not None and browser.ask_panel is not None:
            browser.ask_panel.fill(question)  # the lecturer asks it with `Ask the class`

    # ------------------------------------------------------------------ ask the class (app.ask)
    def rounds(self) -> Rounds:
        """The app's rounds (RuntimeError without a lecture hall)."""
        if self.browser.lectern is None:
            raise RuntimeError("this app has no lecture hall")
        return self.browser.lectern.rounds

    def _presenter_only(self, refusal: str) -> Rounds:
        """The app's rounds while this browser presents; `NotAllowed(refusal)` (a msgid) otherwise."""
        if self.showing.mode is not Mode.PRESENTING:
            raise NotAllowed(refusal)
        return self.rounds()

    def ask(self, question: Question | dict[str, Any]) -> Round:
        """Ask the class `question` (a question or its dict, `app.ask.question_from_dict`): the
        new round.  PermissionError unless presenting; ValueError for a bad question."""
        round_ = self._presenter_only(N_("only the presenter can ask the class")).ask(question)
        self._questions_shown()
        return round_

    def close_round(self) -> Round:
        """Close the current round (presenter only); the round."""
        round_ = self._presenter_only(N_("only the presenter can close the round")).close_round()
        self._questions_shown()
        return round_

    def vote_again(self) -> Round:
        """The same question again, the closed round beside the new one (presenter only); the new round."""
        round_ = self._presenter_only(N_("only the presenter can vote again")).vote_again()
        self._questions_shown()
        return round_

    def _questions_shown(self) -> None:
        panel = self.browser.ask_panel
        if panel is not None:
            self.browser.guard("ask the class", panel.refresh)()

    def play_state(self, answer: Any) -> None:
        """The gallery's `Play this answer`: only the presenter's room plays a student's state."""
        self._presenter_only(N_("only the presenter can play an answer"))
        play_answer(self.showing.room, answer)

    def play_answer(self, number: int) -> None:
        """Play the current State round's anonymous answer `number` (1.. as in its CSV) in the
        presenter's room (presenter only); LookupError for no such answer, ValueError for
        another scene's body."""
        round_ = self._presenter_only(N_("only the presenter can play an answer")).current
        entries = {} if round_ is None else {e.number: e for e in gallery_entries(round_)}
        if number not in entries:
            raise LookupError(f"no state answer number {number}")
        self.play_state(entries[number].answer)
