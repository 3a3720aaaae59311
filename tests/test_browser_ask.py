"""Ask the class (issue 26) as a lecturer and a class use it, in Debian's Chromium, through the
pages only (clicks, taps, keys, typing): a presenter on the projector (1024×768), two laptop
students and a phone student (390×844, touch).

The presenter types a choice question into `Ask the class` and asks it; each student answers in
its own page (the phone by tapping); the presenter's page shows the live count and the
histogram; `Vote again` keeps the first round beside the second.  Then a direction: the students
turn their arrow with the azimuth and elevation sliders (keys on a laptop, a tap on the phone's
track) and send it; the presenter sees every tip on the sphere in its 3D view and reveals the
true direction.  The server's state is read only to check.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import point_on, tap
from test_browser import choose
from test_browser_lecture import CODE, button, close_toasts, hall_app, open_page, type_into  # noqa: F401 - a fixture

from app.main import App

pytestmark = pytest.mark.browser

PHONE = {"viewport": {"width": 390, "height": 844}, "is_mobile": True, "has_touch": True, "device_scale_factor": 2}


def test_a_class_answers_a_choice_and_a_direction_through_its_pages(browser, hall_app: App,  # noqa: F811
                                                                    wait_until) -> None:
    app = hall_app
    projector, presenter = open_page(browser, app, timeout=90.0, viewport={"width": 1024, "height": 768})
    presenter.select_scene("Free body")
    presenter.apply_preset("Sphere")
    presenter.present(CODE)
    students = [open_page(browser, app, timeout=90.0, viewport={"width": 800, "height": 600}) for _ in range(2)]
    students.append(open_page(browser, app, timeout=90.0, **PHONE))
    wait_until(lambda: all(session.mode == "following" for _, session in students), timeout=20.0)
    close_toasts(projector)

    # A choice, typed and asked in the presenter's page.
    type_into(projector, "Question", "The book spins about y′. What does it do?", presenter)
    type_into(projector, "Options", "spins steadily | wobbles | flips again and again", presenter)
    button(projector, "Ask the class").click()
    wait_until(lambda: app.rounds.current is not None, timeout=10.0)
    for (page, _), option in zip(students, ("1. spins steadily", "3. flips again and again",
                                            "3. flips again and again"), strict=True):
        button(page, option).wait_for(timeout=20_000)
        close_toasts(page)
    button(students[0][0], "1. spins steadily").click()
    button(students[1][0], "3. flips again and again").click()
    tap(button(students[2][0], "3. flips again and again"))
    projector.get_by_text("3 of 3 answered", exact=False).wait_for(timeout=15_000)
    assert app.rounds.tally().counts == (1, 0, 2)
    assert "█" in projector.locator("body").inner_text()  # the histogram's bars
    students[2][0].get_by_text("Your answer:", exact=False).wait_for(timeout=10_000)  # the phone sees its answer

    # Vote again: the first round stays beside the second; a student changes its mind.
    button(projector, "Vote again").click()
    button(students[0][0], "3. flips again and again").wait_for(timeout=15_000)
    button(students[0][0], "3. flips again and again").click()
    tap(button(students[2][0], "3. flips again and again"))
    projector.get_by_text("2 of 3 answered", exact=False).wait_for(timeout=15_000)
    projector.get_by_text("round 1: 2", exact=False).first.wait_for(timeout=10_000)
    tally = app.rounds.tally()
    assert tally.counts == (0, 0, 2) and tally.previous is not None and tally.previous.counts == (1, 0, 2)

    # A direction: the students turn their arrows with the sliders and send them.
    button(projector, "New question").click()
    choose(projector, presenter.ask_panel.gui_kind, "Direction")
    type_into(projector, "Question", "Where will ω point at t = 5 s?", presenter)
    type_into(projector, "True direction", "0.287, -0.008, 0.958", presenter)
    button(projector, "Ask the class").click()
    for page, _ in students:
        button(page, "Send my direction").wait_for(timeout=20_000)
    laptop, laptop_student = students[0]
    thumb = laptop.locator(f'[id="{laptop_student.question.gui_elevation._impl.uuid}"] [role="slider"]')
    thumb.focus()
    for _ in range(40):  # 45° + 40 × 1° = 85°: nearly straight up
        laptop.keyboard.press("ArrowRight")
    wait_until(lambda: laptop_student.question.gui_elevation.value == 85.0, timeout=10.0)
    button(laptop, "Send my direction").click()
    button(students[1][0], "Send my direction").click()  # as it was: azimuth 0°, elevation 45°
    phone, phone_student = students[2]
    track = phone.locator(f'[id="{phone_student.question.gui_azimuth._impl.uuid}"]')
    close_toasts(phone)
    at = point_on(phone, track, 0.25, 0.5)
    phone.touchscreen.tap(*at)
    wait_until(lambda: phone_student.question.gui_azimuth.value < -45.0, timeout=30.0,
               what="the phone's azimuth below -45° after a tap at a quarter of its track",
               seen=lambda: (phone_student.question.gui_azimuth.value, at, track.bounding_box()))
    tap(button(phone, "Send my direction"))
    projector.get_by_text("3 tips on the sphere", exact=False).wait_for(timeout=15_000)
    button(projector, "Reveal the answer").click()
    projector.get_by_text("within 15° of the true direction", exact=False).wait_for(timeout=10_000)
    tips = presenter.ask_panel._sphere[1]
    assert tips.visible and np.asarray(tips.points).shape == (3, 3)
    elevations = sorted(np.degrees(np.arcsin(np.clip(np.asarray(app.rounds.tally().directions)[:, 2], -1, 1))))
    assert elevations == pytest.approx([45.0, 45.0, 85.0], abs=0.6)
    assert presenter.ask_panel._sphere[2].visible  # the true direction's arrow
    for _, session in [(projector, presenter), *students]:
        assert session.error_count == 0, session.last_error
