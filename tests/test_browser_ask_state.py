"""A State question as a lecturer and students use it, in Debian's Chromium, through the pages only.

The presenter (a 1024×768 projector screen) opens the heavy top's Wave preset, presents, and asks
"Find a start that makes the top loop" judged by the app (top_motion, loops wanted).  A laptop
student presses `Answer from my copy`, types dφ/dt = −31.5 deg/s into its own copy's number box
and sends its state: its panel says "loops — …" and that it is what was asked; it leaves.  A phone student
(390×844, touch) taps `Answer from my copy` and sends its copy as it is: "waves — …".  The
presenter's panel shows the judged histogram (loops 1, waves 1, 1 of 2 meet the target: the
answer of the student who left counts); in the
gallery it walks to the first answer with `Next` and presses `Play this answer`: the presenter's
room restarts from that student's state, bit for bit, and plays.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import test_browser_lecture
from conftest import DESK, tap
from test_browser import choose
from test_browser_lecture import CODE, open_folder, open_page, received, text_input

from app.ask.judges import AnswerState
from app.main import App, create_server

pytestmark = pytest.mark.browser

PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True, "device_scale_factor": 2}


@pytest.fixture
def ask_app():  # type: ignore[no-untyped-def]
    running = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE)
    try:
        yield running
    finally:
        while test_browser_lecture._CONTEXTS:  # the pages `open_page` opened
            test_browser_lecture._CONTEXTS.pop().close()
        running.stop()


def _number_box(page, handle):  # type: ignore[no-untyped-def]
    """The number box beside a slider (its root's id is the handle's uuid)."""
    return page.locator(f'[id="{handle._impl.uuid}"]').locator("xpath=..").locator("input.mantine-NumberInput-input")


def test_students_answer_a_state_from_their_copies_and_the_presenter_plays_one(  # type: ignore[no-untyped-def]
        browser, ask_app: App, wait_until) -> None:
    app = ask_app
    lectern = app.lectern
    presenter_page, presenter = open_page(browser, app, viewport={"width": 1024, "height": 768})
    presenter_page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    choose(presenter_page, presenter.gui_scene, "Heavy top")
    wait_until(lambda: presenter.room.scene.title == "Heavy top", timeout=15.0)
    presenter_page.get_by_role("button", name="Wave", exact=True).click()
    wait_until(lambda: presenter.room.sim.preset == "Wave", timeout=10.0)
    open_folder(presenter_page, "Lecture", "Presenter code")
    text_input(presenter_page, "Presenter code").click()
    presenter_page.keyboard.type(CODE, delay=20)
    received(presenter_page, presenter, "Presenter code", CODE)
    presenter_page.get_by_role("button", name="Present").click()
    wait_until(lambda: presenter.mode == "presenting", timeout=10.0)

    # The presenter asks a judged State question from its form.
    panel = presenter.ask_panel
    choose(presenter_page, panel.gui_kind, "State")
    text_input(presenter_page, "Question").fill("Find a start that makes the top loop")
    choose(presenter_page, panel.gui_judge, "top_motion")
    text_input(presenter_page, "Target").fill("loops")
    text_input(presenter_page, "Target").press("Enter")
    wait_until(lambda: panel.gui_target.value == "loops", timeout=10.0)
    presenter_page.get_by_role("button", name="Ask the class").click()
    wait_until(lambda: lectern.rounds.current is not None, timeout=10.0)
    question = lectern.rounds.current.question
    assert (question.scene, question.judge, question.target) == ("Heavy top", "top_motion", {"motion": "loops"})

    # A laptop student: its own copy, dφ/dt typed, its state sent; the verdict in its panel.
    laptop_page, laptop = open_page(browser, app, **DESK)
    laptop_page.get_by_role("button", name="Answer from my copy").click()
    wait_until(lambda: laptop.mode == "own" and hasattr(laptop.scene, "gui_rates"), timeout=15.0)
    box = _number_box(laptop_page, laptop.scene.gui_rates[1])  # dφ/dt [deg/s] of its own copy
    box.fill("-31.5")
    box.press("Enter")
    wait_until(lambda: laptop.scene.gui_rates[1].value == -31.5, timeout=10.0)
    laptop_page.get_by_role("button", name="Send my state").click()
    laptop_page.get_by_text(re.compile(r"loops — .*as asked")).first.wait_for(timeout=15_000)
    laptop_page.context.close()  # it leaves: its answer still counts (and one page less renders)

    # A phone student: taps its way to its copy and sends it as it is (the presenter's waves).
    phone_page, phone = open_page(browser, app, **PHONE)
    tap(phone_page.get_by_role("button", name="Answer from my copy"))
    wait_until(lambda: phone.mode == "own", timeout=15.0)
    tap(phone_page.get_by_role("button", name="Send my state"))
    phone_page.get_by_text(re.compile(r"waves — .*not what was asked")).first.wait_for(timeout=15_000)

    # The presenter sees the judged tally and walks the gallery.
    wait_until(lambda: lectern.rounds.tally().answered == 2, timeout=10.0)
    assert sorted(j.value for j in lectern.rounds.tally().judged) == ["loops", "waves"]
    presenter_page.get_by_text(re.compile("of 2 meet the target")).first.wait_for(timeout=10_000)
    presenter_page.get_by_role("button", name="Next", exact=True).click()
    presenter_page.get_by_text(re.compile(r"Answer 1 of 2: loops")).first.wait_for(timeout=10_000)
    presenter_page.get_by_role("button", name="Play this answer").click()
    first = AnswerState.from_dict(lectern.rounds.current.answers()[0].value)
    room = presenter.room

    def plays_the_first() -> bool:  # read under the room's lock: the press restarts, then plays, under it
        with room.lock:
            start = room.sim.initial_state
            return (room.playing and np.array_equal(start.R_space_body, first.R_space_body)
                    and np.array_equal(start.omega_body, first.omega_body))

    wait_until(plays_the_first, timeout=30.0)
    assert room.sim.model.inertia == first.inertia and room.sim.model.mgl == first.mgl
    assert presenter.error_count == 0 and phone.error_count == 0
