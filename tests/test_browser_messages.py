"""Messages that stay true and notes that download, in Debian's Chromium, through the page only.

1. For the notes: `Screenshot` and `Record` are saved by the browser at once under their whole
   names (Playwright's download event, no toast to click), and the screenshot shows the scene
   without the ω drag gizmo: it equals, pixel for pixel (within a small share), the screenshot
   taken after `Drag ω` is switched off.
2. A refusal is said where the hand is: `1e9` typed into Heavy top's spin box far down the panel
   is refused right under the box (in the viewport, within NEAR_PX of it), and the refusal goes
   once the box takes a good value.  `999` typed into `Timeline [s]` is refused alike while the
   motion plays and while it stands: under the slider, with the recorded stretch (growing with
   it while it plays, the refusal staying), and the box shows the slider's value again at once.
   While replaying, the panel shows one time (the Timeline's).
3. The lecture hall: a follower who presses space, R and S sees one toast; its "Someone else is
   presenting" goes when the presenter stops; four wrong codes say "1 try left", a fifth "wait
   N s", and N counts down.
4. Smaller: Single rotation's two animated outlines carry their legend (on each outline and in
   the folder) while they move; a binary file named .obj is refused in plain words.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import io
import re
import time

import numpy as np
import pytest
from conftest import DESK, keep_picture
from PIL import Image
from playwright.sync_api import Error as PlaywrightError
from test_browser import choose, open_app, slider_thumb, still_picture
from test_browser_lecture import CODE, close_toasts, hall_app, open_folder, open_page, text_input  # noqa: F401
from test_browser_typing import binding_of, number_box, type_into

from app.main import App

pytestmark = pytest.mark.browser

GIZMO_FREE_SHARE = 0.002  # at most this share of pixels differs between two gizmo-free screenshots
NEAR_PX = 150  # [px] a refusal said "at the control": its text this close to the box, above or below


def said_near(page, box, pattern: re.Pattern[str]) -> list[tuple[str, float]]:  # type: ignore[no-untyped-def]
    """(text, vertical gap [px] to `box`) of each shown element matching `pattern` that lies
    wholly inside the viewport (read in one go: an element may leave the page meanwhile)."""
    height = page.viewport_size["height"]
    top, bottom = box.evaluate("el => { const r = el.getBoundingClientRect(); return [r.top, r.bottom]; }")
    rects = page.get_by_text(pattern).evaluate_all(
        "els => els.map(el => { const r = el.getBoundingClientRect();"
        " return [el.innerText, r.top, r.bottom, r.width > 0 && r.height > 0]; })")
    return [(text, max(0.0, y0 - bottom, top - y1)) for text, y0, y1, shown in rects
            if shown and y0 >= 0 and y1 <= height]


def wait_for_page(page, what: str, seen, done, timeout: float = 30.0):  # type: ignore[no-untyped-def]
    """Poll `seen()` (what the page shows) until `done(it)`; the page's events are delivered meanwhile."""
    deadline = time.monotonic() + timeout
    it = seen()
    while not done(it):
        if time.monotonic() > deadline:
            raise AssertionError(f"waited {timeout:g} s for {what}; the page showed {it!r}")
        page.wait_for_timeout(100)
        it = seen()
    return it


def refusal_beside(page, box, pattern: re.Pattern[str], timeout: float = 30.0) -> str:  # type: ignore[no-untyped-def]
    """The refusal matching `pattern` said beside `box` (within NEAR_PX, in the viewport)."""
    near = wait_for_page(page, f"{pattern.pattern!r} within {NEAR_PX} px of the box, in view",
                         lambda: said_near(page, box, pattern), lambda it: any(gap <= NEAR_PX for _, gap in it),
                         timeout)
    return next(text for text, gap in near if gap <= NEAR_PX)


def box_shows_slider(page, box, handle) -> tuple[str, str | None]:  # type: ignore[no-untyped-def]
    """(the box's text, the slider thumb's value) of a slider."""
    return box.input_value(), slider_thumb(page, handle).get_attribute("aria-valuenow")


def same_number(shown: tuple[str, str | None]) -> bool:
    try:
        return shown[1] is not None and abs(float(shown[0]) - float(shown[1])) < 1e-6
    except ValueError:
        return False


def recorded_end(refused: re.Pattern[str], text: str) -> float:
    """[s] the end of the recorded stretch a Timeline refusal quotes (its pattern's group 1)."""
    found = refused.search(text)
    assert found is not None, text
    return float(found[1])


def shot(page, name: str) -> None:  # type: ignore[no-untyped-def]
    keep_picture(page, f"messages/{name}")


def choose_scene(page, session, title: str, wait_until) -> None:  # type: ignore[no-untyped-def]
    choose(page, session.gui_scene, title)
    wait_until(lambda: session.scene.title == title, timeout=10.0)


def download(page, click, seen=lambda: "") -> tuple[str, bytes]:  # type: ignore[no-untyped-def]
    """(suggested name, bytes) of the download that `click()` starts, waited for up to 60 s (a
    render of the 3D view on a busy machine); on a timeout the error says `seen()` (the server's side)."""
    try:
        with page.expect_download(timeout=60_000) as info:
            click()
        done = info.value
    except PlaywrightError as error:
        raise AssertionError(f"no download within 60 s of the click; the server: {seen()}") from error
    with open(done.path(), "rb") as f:
        return done.suggested_filename, f.read()


def test_screenshot_and_record_download_with_whole_names_and_no_gizmo(wait_until, app: App, page) -> None:
    session = open_app(page, app)
    choose_scene(page, session, "Heavy top", wait_until)
    view = session.scene
    gizmo = view.hand.gizmos["omega"]
    wait_until(lambda: gizmo.visible, timeout=10.0)
    still_picture(page)  # nodes faded in
    page.get_by_text("For the notes", exact=True).first.click()
    shot = page.get_by_role("button", name="Screenshot")
    def server_side() -> str:
        return (f"last_screenshot {'set' if session.last_screenshot else 'none'}, errors {session.error_count}, "
                f"last error {session.last_error!r}")

    name, with_gizmo_on = download(page, shot.click, server_side)
    assert name.startswith("heavy_top_t0.0s") and name.endswith(".png")
    wait_until(lambda: gizmo.visible, timeout=10.0)  # back after the render

    page.get_by_text("Set ω by hand", exact=True).first.click()
    drag = page.get_by_role("checkbox", name="Drag ω").first
    for _ in range(3):  # a click that lands while the opened folder still lays out is clicked again
        if drag.is_checked():
            page.get_by_text("Drag ω", exact=True).first.click()  # the checkbox: the gizmo goes
        try:
            wait_until(lambda: not gizmo.visible, timeout=10.0)
            break
        except AssertionError:
            continue
    assert not gizmo.visible, "the gizmo stays after three clicks on Drag ω"
    time.sleep(0.5)
    _, without_gizmo = download(page, shot.click, server_side)
    a = np.asarray(Image.open(io.BytesIO(with_gizmo_on)).convert("RGBA"), dtype=int)
    b = np.asarray(Image.open(io.BytesIO(without_gizmo)).convert("RGBA"), dtype=int)
    assert a.shape == b.shape and a[..., 3].max() > 0  # something was drawn
    differs = float(np.mean(np.any(np.abs(a - b) > 24, axis=-1)))
    assert differs < GIZMO_FREE_SHARE, f"{differs:.4f} of the pixels differ: the gizmo is in the screenshot"

    seconds = page.locator("label", has_text="Record [s]").first.locator(
        "xpath=ancestor::div[contains(@class, 'Flex-root')][1]").locator("input").first
    seconds.fill("")
    seconds.type("1")
    seconds.press("Enter")
    wait_until(lambda: session.notes.gui_record_seconds.value == 1.0, timeout=10.0)
    record = page.get_by_role("button", name="Record", exact=True)
    downloads: list = []
    page.on("download", lambda d: downloads.append(d))
    record.click()
    deadline = time.monotonic() + 60.0
    while len(downloads) < 2 and time.monotonic() < deadline:
        page.wait_for_timeout(200)  # the page's events are delivered while it waits
    assert {d.suggested_filename for d in downloads} == {"heavy_top_1s.html", "heavy_top_1s.viser"}
    assert session.error_count == 0


def test_a_refusal_far_down_the_panel_is_said_beside_the_box_and_goes_with_a_good_value(
        wait_until, app: App, page) -> None:
    session = open_app(page, app)
    choose_scene(page, session, "Heavy top", wait_until)
    view = session.scene
    spin = view.gui_rates[0]  # spin ω_z′ [rad/s], range -40 to 40, under the angles: far down the panel
    box = number_box(page, spin)
    type_into(page, box, "1e9", delay=20, end="Enter", whole=True)
    said = refusal_beside(page, box, re.compile(r"1000000000\.0 refused"))
    assert "the range is -40 to 40" in said, said
    wait_for_page(page, "the box back at the value in force (12)", box.input_value, lambda text: text == "12")
    shot(page, "after_row5_spin_1e9_refused.png")
    taken = binding_of(view, spin).applied
    type_into(page, box, "15", delay=20, end="Enter", whole=True)
    wait_until(lambda: binding_of(view, spin).applied > taken and spin.value == 15.0, timeout=30.0)
    wait_for_page(page, "the refusal gone", lambda: said_near(page, box, re.compile(r"refused")),
                  lambda near: near == [])
    shot(page, "after_row5_spin_15_taken.png")
    assert session.error_count == 0


BOX_STATE_JS = """el => ({focused: el === document.activeElement, selection: [el.selectionStart, el.selectionEnd],
               text: el.value})"""
"""What a number box holds and whether its text is selected (the typing guard holds server writes then)."""


def test_a_time_typed_into_the_timeline_is_refused_alike_playing_or_paused_and_replay_shows_one_time(
        wait_until, app: App, page) -> None:
    session = open_app(page, app)
    view = session.scene  # Euler angles
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: view.sim.t > 1.0, timeout=20.0)
    timeline = view.timeline
    assert timeline is not None
    box = number_box(page, timeline.gui_slider)
    # The recording holds a run's last 60 s: on a slow page the run can play past them before the
    # paused round, and the stretch then starts later than 0.00 s.
    refused = re.compile(r"Time 999\.0 s refused: only \d+\.\d\d s to (\d+\.\d\d) s is recorded")
    for playing in (True, False):
        if not playing:
            page.get_by_role("button", name="Pause", exact=True).click()
            wait_until(lambda: not session.room.playing, timeout=10.0)
        typed, refused_before = time.monotonic(), timeline.binding.refused
        type_into(page, box, "999", delay=20, end="Enter", whole=True)
        try:
            said = refusal_beside(page, box, refused)  # under the slider, with the stretch
        except AssertionError as error:
            raise AssertionError(f"{'playing' if playing else 'paused'}: {error}; the box "
                                 f"{box.input_value()!r}, focused "
                                 f"{box.evaluate('el => el === document.activeElement')}; "
                                 f"the server: message {view.message.text!r}, refused {timeline.binding.refused}, "
                                 f"applied {timeline.binding.applied}, t shown {session.room.shown_t:.2f}, "
                                 f"errors {session.error_count} {session.last_error!r}") from error
        try:
            shown = wait_for_page(page, "the box showing the slider's value", lambda: box_shows_slider(
                page, box, timeline.gui_slider), same_number)
        except AssertionError as error:
            raise AssertionError(f"{'playing' if playing else 'paused'}: {error}; the page's box "
                                 f"{box.evaluate(BOX_STATE_JS)}; the server: slider {timeline.gui_slider.value}, "
                                 f"refused {refused_before} before the keys and {timeline.binding.refused} now, "
                                 f"applied {timeline.binding.applied}, t shown {session.room.shown_t:.2f}, "
                                 f"playing {session.room.playing}") from error
        print(f"{'playing' if playing else 'paused'}: the box showed {shown[0]} "
              f"{time.monotonic() - typed:.2f} s after the keys were typed")
        shot(page, f"after_row6_timeline_999_{'playing' if playing else 'paused'}.png")
        assert session.room.playing == playing
        if playing:  # the stretch grows: the refusal stays, in words that hold now
            first = recorded_end(refused, said)
            wait_for_page(page, "the refusal quoting a longer stretch, still under the slider",
                          lambda: refusal_beside(page, box, refused),
                          lambda text, first=first: recorded_end(refused, text) > first + 0.5)
            shot(page, "after_row6_timeline_999_playing_later.png")
    type_into(page, box, "1", delay=20, end="Enter", whole=True)  # a time taken: the refusal goes
    wait_until(lambda: session.room.shown_t == 1.0, timeout=30.0)
    wait_for_page(page, "the refusal gone", lambda: said_near(page, box, refused), lambda near: near == [])

    page.get_by_role("button", name="Replay", exact=True).click()
    page.get_by_text("Replaying t = ").first.wait_for(state="visible", timeout=10_000)
    page.get_by_text("Looking back: the time shown is under the Timeline").first.wait_for(state="visible",
                                                                                       timeout=10_000)
    assert page.get_by_text(re.compile(r"t = \d")).filter(visible=True).count() == 1  # one time in the panel


def test_single_rotation_outlines_have_a_legend_and_a_binary_obj_is_refused_in_plain_words(
        wait_until, app: App, page, tmp_path) -> None:
    session = open_app(page, app)
    part = session.scene.single_rotation  # Euler angles
    page.get_by_text("Single rotation", exact=True).first.click()  # the checkbox: the animation starts
    wait_until(lambda: part.animation_time is not None, timeout=10.0)
    page.get_by_text("The two outlines:").first.wait_for(state="visible", timeout=10_000)
    assert session.scene.labels.wanted(part.ghost_turn_label) and session.scene.labels.wanted(part.ghost_zxz_label)
    assert part.ghost_zxz_label.text.startswith("coloured: z-x-z, now")
    page.get_by_text("The two outlines:").first.wait_for(state="hidden", timeout=20_000)  # gone with them

    choose_scene(page, session, "Inertia", wait_until)
    page.get_by_text("Solid mesh").first.click()  # open the folder
    binary = tmp_path / "cube.obj"
    binary.write_bytes(bytes(range(256)) * 8)
    with page.expect_file_chooser() as chooser:  # the mesh's upload button (the Mine folder has one too)
        page.get_by_role("button", name="Upload STL / OBJ / PLY / OFF / GLB").click()
    chooser.value.set_files(str(binary))
    page.get_by_text("holds binary bytes").first.wait_for(state="visible", timeout=20_000)
    assert "UnicodeDecodeError" not in session.scene.message.text


def test_lecture_notes_stay_true_and_a_followers_keys_bring_one_toast(browser, hall_app: App,  # noqa: F811
                                                                     wait_until) -> None:
    presenter_page, presenter = open_page(browser, hall_app, **DESK)
    close_toasts(presenter_page)
    open_folder(presenter_page, "Lecture", "Presenter code")
    text_input(presenter_page, "Presenter code").fill(CODE)
    presenter_page.get_by_role("button", name="Present").click()
    wait_until(lambda: presenter.mode == "presenting", timeout=15.0)
    page, follower = open_page(browser, hall_app, **DESK)
    wait_until(lambda: follower.mode == "following", timeout=15.0)
    page.get_by_text("Following the presenter").first.wait_for(timeout=30_000)
    close_toasts(page)

    toasts = page.locator(".mantine-Notification-root", has_text="Press 'Explore on my own'")
    page.mouse.click(300, 400)  # the 3D view has the focus
    for key in ("Space", "r", "s"):
        page.keyboard.press(key)
        page.wait_for_timeout(300)
    toasts.first.wait_for(state="visible", timeout=30_000)
    counts = []
    for _ in range(20):  # read 20 times 0.1 s apart while the first toast shows (3 s): never two at once
        counts.append(toasts.count())
        page.wait_for_timeout(100)
    assert max(counts) <= 1, f"toasts on the page, read every 0.1 s after the first: {counts}"

    open_folder(page, "Lecture", "Presenter code")
    text_input(page, "Presenter code").fill(CODE)
    present = page.get_by_role("button", name="Present", exact=True)
    present.click()
    busy = page.get_by_text("Someone else is presenting")
    try:
        busy.first.wait_for(state="visible", timeout=30_000)
    except Exception:  # noqa: BLE001 - say what the server had of the press
        lecture = follower.lecture
        raise AssertionError(
            f"no 'Someone else is presenting' 30 s after Present: the follower's note on the server "
            f"{lecture.gui_note.content!r} (visible: {lecture.gui_note.visible}), its refusal on record "
            f"{hall_app.lectern.presenter_lock._refused.get(follower.client_id)!r}, mode {follower.mode}, "
            f"last error {follower.last_error!r}") from None
    presenter_page.get_by_role("button", name="Stop presenting").click()
    busy.first.wait_for(state="hidden", timeout=10_000)  # true no more

    text_input(page, "Presenter code").fill("111111")
    for _ in range(4):
        present.click()
        page.wait_for_timeout(200)
    page.get_by_text("1 try left").first.wait_for(state="visible", timeout=10_000)
    present.click()
    wait = page.get_by_text(re.compile(r"wait \d+ s"))
    wait.first.wait_for(state="visible", timeout=10_000)
    first = int(re.search(r"wait (\d+) s", wait.first.inner_text()).group(1))
    wait_until(lambda: int(re.search(r"wait (\d+) s", wait.first.inner_text()).group(1)) <= first - 2,
               timeout=15.0)  # the wait counts down
