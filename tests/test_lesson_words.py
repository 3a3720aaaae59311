"""A lesson never asks the room for a control a follower does not have.

Every step of every lesson (assets/lessons) is run in a presenting browser's session, and its
words are checked against that step's panel as the code builds it (`SceneView.panel_controls`,
the scene's tabs) and against what a follower has (its panel's own inputs, and the presenter's
open plot tab, copied read only: `app.kit.view.PLOT_TABS`):

- a panel tab named in the words must be a plot tab that the step opens (followers see it);
- no button of the presenter's panel is named (followers have none of them);
- a sentence that tells someone to act (press, drag, raise, ...) names no control of the
  presenter's panel.
"""

from __future__ import annotations

import re

import viser

from app.kit.view import PLOT_TABS
from app.viser_internals import panel_inputs

CODE = "135790"
ACTING = ("press", "click", "tap", "drag", "raise", "lower", "move", "tick", "untick", "type", "choose", "select",
          "set", "turn", "open", "use", "try", "pick", "slide")
"""Verbs that, opening a sentence, tell the reader to work a control."""


def _name(label: str) -> str:
    """A control's name as words would give it: no unit in brackets, no leading symbols."""
    label = re.sub(r"\s*\[[^\]]*\]\s*$", "", str(label)).strip()
    return re.sub(r"^[^\w(]+", "", label).strip()


def _named(name: str, text: str) -> bool:
    return bool(name) and re.search(rf"(?<![\w′]){re.escape(name)}(?![\w′])", text) is not None


def _sentences(text: str) -> list[str]:
    return [s.strip() for s in re.split(r"(?<=[.!?:;])\s+|—", text) if s.strip()]


def test_no_lesson_asks_a_follower_for_a_control_it_lacks() -> None:
    from conftest import LectureHall

    hall = LectureHall(CODE)
    try:
        presenter = hall.join()
        follower = hall.join()
        presenter.present(CODE)
        hall.frames(2)
        assert follower.mode == "following"
        mine = follower.scene  # the follower's panel (`app.lecture.follower.Follower`)
        follower_labels = {_name(h.label) for h in (mine.gui_follow_camera, mine.gui_explore, mine.gui_caption,
                                                     mine.gui_details)}
        problems: list[str] = []
        checked = 0
        for title, lesson in presenter.lessons.items():
            presenter.start_lesson(title)
            for k, step in enumerate(lesson.steps):
                if k:
                    presenter.next_step(1)
                assert presenter.error_count == 0, presenter.last_error
                view = presenter.scene
                where = f"{title}, step {k + 1}"
                text = step.text
                inputs = panel_inputs(view.client.gui, view._gui_roots)
                assert inputs, "viser's panel registry is off: the panel's controls cannot be listed"
                tabs = set(view.tabs.names) if view.tabs is not None else set()
                buttons = {_name(h.label) for h in inputs if isinstance(h, viser.GuiButtonHandle)}
                controls = {_name(h.label) for h in inputs if h.label} | buttons | tabs
                controls -= follower_labels
                for tab in tabs:
                    if _named(tab, text) and not (tab in PLOT_TABS and step.tab == tab):
                        problems.append(f"{where}: names the {tab} tab, which followers do not see")
                for button in sorted(buttons - follower_labels):
                    if _named(button, text):
                        problems.append(f"{where}: names the presenter's button {button!r}")
                for sentence in _sentences(text):
                    first = sentence.split()[0].lower().strip("\"'(")
                    if first in ACTING:
                        hit = sorted(c for c in controls if _named(c, sentence))
                        problems.append(f"{where}: tells the room to act on {hit or 'the panel'}: {sentence!r}")
                checked += 1
        assert checked >= 30
        assert not problems, "\n".join(problems)
    finally:
        hall.close()


def test_the_check_catches_what_the_lessons_said_before() -> None:
    """The rules above, on words the lessons once had (a check that finds nothing proves nothing)."""
    assert _named("Plots", "Watch ω_y′ change sign in the Plots tab.")
    assert _named("θ", "Drag θ: d moves") and _sentences("Drag θ: d moves")[0].split()[0].lower() in ACTING
    assert _named("Play", "the method stops; press Play to go on")
    assert _named("Animate", "Animate replays both.")
    assert _name("⟲ Reset") == "Reset" and _name("Ω [rad/s]") == "Ω" and _name("φ₀ [deg]") == "φ₀"
    assert not _named("x′", "x′₀") and not _named("Plots", "Plotsy")
