"""Messages that stay true and notes that download, in Debian's Chromium, through the page only.

1. For the notes: `Screenshot` and `Record` are saved by the browser at once under their whole
   names (Playwright's download event, no toast to click), and the screenshot shows the scene
   without the ω drag gizmo: it equals, pixel for pixel (within a small share), the screenshot
   taken after `Drag ω` is switched off.
2. A refusal goes when it no longer holds: `999` typed into `Timeline [s]` while the motion
   plays is refused with the recorded stretch, and the refusal goes once the stretch has grown.
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
from PIL import Image
from test_browser import open_app
from test_browser_lecture import CODE, close_toasts, hall_app, open_folder, open_page, text_input  # noqa: F401
from test_browser_typing import number_box, type_into

from app.main import App

pytestmark = pytest.mark.browser

GIZMO_FREE_SHARE = 0.002  # at most this share of pixels differs between two gizmo-free screenshots


def choose_scene(page, session, title: str, wait_until) -> None:  # type: ignore[no-untyped-def]
    page.locator(f'[id="{session.gui_scene._impl.uuid}"]').click()  # the Scene dropdown
    page.get_by_role("option", name=title).click()
    wait_until(lambda: session.scene.title == title, timeout=10.0)


def download(page, click) -> tuple[str, bytes]:  # type: ignore[no-untyped-def]
    """(suggested name, bytes) of the download that `click()` starts."""
    with page.expect_download(timeout=30_000) as info:
        click()
    done = info.value
    with open(done.path(), "rb") as f:
        return done.suggested_filename, f.read()


def test_screenshot_and_record_download_with_whole_names_and_no_gizmo(wait_until, app: App, page) -> None:
    session = open_app(page, app)
    choose_scene(page, session, "Heavy top", wait_until)
    view = session.scene
    gizmo = view.hand.gizmos["omega"]
    wait_until(lambda: gizmo.visible, timeout=10.0)
    time.sleep(1.5)  # nodes fade in
    page.get_by_text("For the notes", exact=True).first.click()
    shot = page.get_by_role("button", name="Screenshot")
    name, with_gizmo_on = download(page, shot.click)
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
    _, without_gizmo = download(page, shot.click)
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


def test_refusals_go_when_they_no_longer_hold_and_replay_shows_one_time(wait_until, app: App, page) -> None:
    session = open_app(page, app)
    view = session.scene  # Euler angles
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: view.sim.t > 1.0, timeout=20.0)
    timeline = view.timeline
    assert timeline is not None
    page.get_by_role("button", name="Pause", exact=True).click()  # the refusal holds while paused:
    wait_until(lambda: not session.room.playing, timeout=10.0)  # the page has time to show it
    type_into(page, number_box(page, timeline.gui_slider), "999", delay=20, end="Enter")
    page.get_by_text("is recorded").first.wait_for(state="visible", timeout=10_000)
    page.get_by_role("button", name="Play", exact=True).click()
    page.get_by_text("is recorded").first.wait_for(state="hidden", timeout=10_000)  # the stretch grew
    assert session.room.playing

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
    presenter_page, presenter = open_page(browser, hall_app, viewport={"width": 1280, "height": 800})
    close_toasts(presenter_page)
    open_folder(presenter_page, "Lecture", "Presenter code")
    text_input(presenter_page, "Presenter code").fill(CODE)
    presenter_page.get_by_role("button", name="Present").click()
    wait_until(lambda: presenter.mode == "presenting", timeout=15.0)
    page, follower = open_page(browser, hall_app, viewport={"width": 1280, "height": 800})
    wait_until(lambda: follower.mode == "following", timeout=15.0)
    page.get_by_text("Following the presenter").first.wait_for(timeout=30_000)
    close_toasts(page)

    toasts = page.locator(".mantine-Notification-root", has_text="Press 'Explore on my own'")
    page.mouse.click(300, 400)  # the 3D view has the focus
    for key in ("Space", "r", "s"):
        page.keyboard.press(key)
        page.wait_for_timeout(300)
    toasts.first.wait_for(state="visible", timeout=10_000)
    page.wait_for_timeout(800)  # the last key's toast has come (3 s before they close)
    assert toasts.count() == 1

    open_folder(page, "Lecture", "Presenter code")
    text_input(page, "Presenter code").fill(CODE)
    present = page.get_by_role("button", name="Present", exact=True)
    present.click()
    busy = page.get_by_text("Someone else is presenting")
    busy.first.wait_for(state="visible", timeout=10_000)
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
