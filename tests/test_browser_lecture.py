"""The lecture hall as a lecturer and students use it, in Debian's Chromium, through the pages
only (clicks, mouse drags, keys): a presenter context, a laptop follower, a phone follower.

1. The presenter opens Inertia, adds a mass, types the code and presents; clicking a ball in
   its page selects it (the presenter's own clickable copy).  The laptop follower drags the
   mouse across every ball and where the presenter's gizmo is, clicks the balls, presses the
   keys: the presenter's numbers do not move.  `Explore on my own` then shows the presenter's
   three masses in the follower's own panel, and its own drags are its own.
2. A phone follower (390×844, touch) sees a one-line panel and the body: the pixels at the
   body's projected position are the body's, not the panel's.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import base64
import io
import math
import time

import numpy as np
import pytest
from conftest import DESK, poll_until
from PIL import Image
from test_browser import app_url, choose  # noqa: F401 - choose: for the browser tests that import from here

from app.main import App, create_server
from app.viser_internals import input_handle

pytestmark = pytest.mark.browser

CODE = "246810"


_CONTEXTS: list = []  # the browser contexts a test opened (closed after it: a page left open keeps rendering)


def serving(**options):  # type: ignore[no-untyped-def]
    """A quiet app on a free port (`create_server` with `options`), yielded; afterwards the
    browser contexts a test opened are closed, then the app stops."""
    running = create_server("127.0.0.1", 0, verbose=False, **options)
    try:
        yield running
    finally:
        while _CONTEXTS:
            _CONTEXTS.pop().close()
        running.stop()


@pytest.fixture
def hall_app():  # type: ignore[no-untyped-def]
    yield from serving(presenter_code=CODE)


def project(camera, point, width: float, height: float) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """Pixel (x right, y down) of a world point in a browser whose camera is `camera`
    (position, look_at, up, vertical fov [rad]) and whose view is width x height CSS px."""
    eye, target = np.asarray(camera.position, float), np.asarray(camera.look_at, float)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, np.asarray(camera.up_direction, float))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = np.asarray(point, float) - eye
    z = float(d @ forward)
    f = 0.5 * height / math.tan(0.5 * float(camera.fov))
    return 0.5 * width + f * float(d @ right) / z, 0.5 * height - f * float(d @ up) / z


def open_page(browser, app: App, timeout: float = 90.0, **context):  # type: ignore[no-untyped-def]
    """A new context and page on the app, its session and canvas awaited up to `timeout` [s]; (page, session)."""
    before = set(app.sessions)
    opened = browser.new_context(**context)
    _CONTEXTS.append(opened)
    page = opened.new_page()
    page.goto(app_url(page, app.port), timeout=timeout * 1000)
    session = poll_until(lambda: next((s for cid, s in dict(app.sessions).items() if cid not in before), None),
                         timeout=timeout, interval=0.2, what="the new page's session",
                         seen=lambda: f"{len(app.sessions)} sessions, {len(before)} before")
    page.locator("canvas").first.wait_for(timeout=timeout * 1000)
    return page, session


def close_toasts(page) -> None:  # type: ignore[no-untyped-def]
    """Press the close button of every toast shown now, in one step in the page: a toast that
    closes by itself meanwhile is not waited for (a click per counted toast waited 30 s for a
    toast gone, or re-indexed, since the count)."""
    page.evaluate("""() => document.querySelectorAll('.mantine-Notification-closeButton')
                           .forEach((button) => button.click())""")


def open_folder(page, folder: str, inside: str) -> None:  # type: ignore[no-untyped-def]
    """Open the folder `folder` until the text `inside` shows: a click on its title only while
    `inside` is hidden, then a wait (a second click while it unfolds on a busy machine would fold
    it again)."""
    shown = page.get_by_text(inside, exact=True).first
    for _ in range(3):
        if not shown.is_visible():
            page.get_by_text(folder, exact=True).first.click()
        try:
            shown.wait_for(state="visible", timeout=20_000)
            return
        except Exception:  # noqa: BLE001 - the click landed before the panel was laid out
            continue
    raise AssertionError(f"the folder {folder!r} did not open")


def open_folder_to(page, folder: str, field: str) -> None:  # type: ignore[no-untyped-def]
    """Open the folder `folder` until its text field `field` shows: a click on its title only
    while the field is hidden, then a wait (a second click while it unfolds on a busy machine
    would fold it again)."""
    box = text_input(page, field)
    for _ in range(3):
        if not box.is_visible():
            page.get_by_text(folder, exact=True).first.click()
        try:
            box.wait_for(state="visible", timeout=20_000)
            return
        except Exception:  # noqa: BLE001 - the click landed before the panel was laid out
            continue
    raise AssertionError(f"the {folder} folder did not open")


def text_input(page, label: str):  # type: ignore[no-untyped-def]
    """viser's text field labelled `label` (its <label for> names no element: the input is the
    one in the label's row)."""
    row = page.locator("label", has_text=label).first.locator("xpath=ancestor::div[contains(@class, 'Flex-root')][1]")
    return row.locator("input").first


def button(page, name: str):  # type: ignore[no-untyped-def]
    """The page's button named exactly `name`."""
    return page.get_by_role("button", name=name, exact=True)


def type_into(page, label: str, text: str, session=None) -> None:  # type: ignore[no-untyped-def]
    """Type `text` into the page's emptied text field labelled `label`, then Enter; with
    `session`, wait until its server holds `text` (`received`)."""
    field = text_input(page, label)
    field.wait_for(state="visible", timeout=30_000)
    field.click()
    field.fill("")
    page.keyboard.type(text, delay=5)
    field.press("Enter")
    if session is not None:
        received(page, session, label, text)


def received(page, session, label: str, text: str, timeout: float = 30.0) -> None:  # type: ignore[no-untyped-def]
    """Wait until `session`'s server holds `text` in the field labelled `label`.

    viser's page sends a field's value at most every 50 ms and keeps only the latest message of
    any kind meanwhile: a click or another field's keystroke within 50 ms of the last keystroke
    replaces that keystroke's value, which the server then never gets. A test that types and then
    acts waits for the value to arrive."""
    uuid = page.locator("label", has_text=label).first.get_attribute("for")
    handle = input_handle(session.client, uuid)
    assert handle is not None, f"no input {label!r} ({uuid}) in the session's panel"
    expected: object = text if isinstance(handle.value, str) else float(text)  # a number box holds a float
    poll_until(lambda: handle.value == expected, timeout, 0.02, what=f"the server's {label!r} to be {text!r}",
               seen=lambda: handle.value)


def present_in_page(page, session, timeout: float = 30.0) -> None:  # type: ignore[no-untyped-def]
    """Type CODE into the page's `Presenter code` and press Present; waits until `session` presents."""
    open_folder(page, "Lecture", "Presenter code")
    text_input(page, "Presenter code").click()
    page.keyboard.type(CODE, delay=30)
    received(page, session, "Presenter code", CODE)
    button(page, "Present").click()
    poll_until(lambda: session.mode == "presenting", timeout, 0.05, what="the page's session presenting",
               seen=lambda: (session.mode, session.last_error))


def play_and_present(page, session, title: str) -> None:  # type: ignore[no-untyped-def]
    """In the page (its first scene drawn, its toasts closed): choose the scene `title`, press
    Play, then present (`present_in_page`)."""
    page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    close_toasts(page)
    choose(page, session.gui_scene, title)
    poll_until(lambda: session.scene.title == title, 15.0, 0.05, what=f"the scene {title!r} chosen",
               seen=lambda: session.scene.title)
    press_play(page, session)
    present_in_page(page, session)


def press_play(page, session) -> None:  # type: ignore[no-untyped-def]
    """Press the Play of the view `session` shows now (by its id: right after a scene is chosen,
    the old scene's Play is still on the page until the new panel arrives, and a press on it
    reaches nobody); waits until the room plays."""
    page.locator(f'[id="{session.scene.transport.gui_play._impl.uuid}"]').click(timeout=30_000)
    poll_until(lambda: session.room.playing, 30.0, 0.05, what=f"{session.scene.title!r} playing after Play",
               seen=lambda: (session.room.sim.t, session.last_error))


def present_and_follow(browser, app: App, presenter_page, presenter, wait_until):  # type: ignore[no-untyped-def]
    """The presenter types the code and presents, through its page; a laptop follower joins and
    sees the shared scene.  (follower page, follower session)."""
    present_in_page(presenter_page, presenter)
    follower_page, follower = open_page(browser, app, **DESK)
    wait_until(lambda: follower.mode == "following", timeout=15.0)
    follower_page.get_by_text("Following the presenter").first.wait_for(timeout=30_000)
    close_toasts(follower_page)
    camera_settled(follower)  # the camera follows the presenter's
    return follower_page, follower


def camera_settled(session, quiet_s: float = 0.5, timeout: float = 30.0) -> None:  # type: ignore[no-untyped-def]
    """Wait until the camera `session`'s browser reports (position and look-at, scene units) has
    not changed for `quiet_s` [s]: the view a test projects points through is the one drawn."""
    last: list = [None, time.monotonic()]  # [(position, look_at), when it was first seen]

    def settled() -> bool:
        camera = session.client.camera
        now = (tuple(np.round(camera.position, 4)), tuple(np.round(camera.look_at, 4)))
        if now != last[0]:
            last[:] = [now, time.monotonic()]
        return time.monotonic() - last[1] >= quiet_s

    poll_until(settled, timeout, 0.05, what=f"the browser's camera unchanged for {quiet_s} s", seen=lambda: last[0])


def snapshot(sim) -> tuple[bytes, bytes, bytes]:  # type: ignore[no-untyped-def]
    props = sim.properties()
    return sim.masses.tobytes(), sim.positions.tobytes(), np.asarray(props["O"]).tobytes()


def test_followers_cannot_move_the_presenters_masses_and_explore_copies_them(browser, hall_app: App, wait_until
                                                                             ) -> None:
    app = hall_app
    presenter_page, presenter = open_page(browser, app, viewport={"width": 1280, "height": 800})
    presenter_page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    close_toasts(presenter_page)
    choose(presenter_page, presenter.gui_scene, "Inertia")
    presenter_page.get_by_text("Inertia tensor (memo §3)").wait_for(timeout=30_000)
    presenter_page.get_by_role("button", name="Add mass").click()
    wait_until(lambda: len(presenter.scene.sim.masses) == 3, timeout=10.0)
    follower_page, follower = present_and_follow(browser, app, presenter_page, presenter, wait_until)
    sim = presenter.scene.sim
    before = snapshot(sim)

    # The presenter clicks its second ball in its own page: selected (its own clickable copy).
    camera = presenter.client.camera
    x, y = project(camera, sim.positions[1], 1280, 800)
    presenter_page.mouse.click(x, y)
    wait_until(lambda: presenter.scene.selected == 1, timeout=10.0)

    # The follower drags across every ball and the gizmo's place, clicks, presses keys.
    fcam = follower.client.camera
    for point in [*sim.positions, sim.positions[1] + np.array([0.3, 0.0, 0.0])]:
        fx, fy = project(fcam, point, DESK["viewport"]["width"], DESK["viewport"]["height"])
        follower_page.mouse.click(fx, fy)
        follower_page.mouse.move(fx, fy)
        follower_page.mouse.down()
        follower_page.mouse.move(fx + 120, fy - 80, steps=8)
        follower_page.mouse.up()
    for key in ("Space", "s", "r", "ArrowRight"):
        follower_page.keyboard.press(key)
    time.sleep(1.5)
    with presenter.lock:
        pass
    assert snapshot(sim) == before and presenter.scene.sim is sim
    assert presenter.mode == "presenting" and presenter.error_count == 0, presenter.last_error

    # Explore on my own: the presenter's three masses, in the follower's own room and panel.
    follower_page.get_by_role("button", name="Explore on my own").click()
    wait_until(lambda: follower.mode == "own", timeout=10.0)
    follower_page.get_by_text("3 point masses").first.wait_for(timeout=15_000)
    assert snapshot(follower.scene.sim) == before and follower.scene.sim is not sim
    follower_page.get_by_role("button", name="Add mass").click()  # its own now
    wait_until(lambda: len(follower.scene.sim.masses) == 4, timeout=10.0)
    assert len(sim.masses) == 3 and snapshot(sim) == before
    open_folder(follower_page, "Lecture", "Follow presenter")
    follower_page.get_by_role("button", name="Follow presenter").click()
    wait_until(lambda: follower.mode == "following", timeout=10.0)


def test_a_phone_follower_sees_the_body_not_the_panel(browser, hall_app: App, wait_until, tmp_path) -> None:
    app = hall_app
    presenter_page, presenter = open_page(browser, app, viewport={"width": 1280, "height": 800})
    presenter.select_scene("Heavy top")
    presenter.present(CODE)
    presenter.play()
    phone, follower = open_page(browser, app, viewport={"width": 390, "height": 844}, is_mobile=True,
                                has_touch=True, device_scale_factor=2)
    wait_until(lambda: follower.mode == "following" and follower.scene.narrow, timeout=15.0)
    phone.get_by_role("button", name="Details").wait_for(timeout=15_000)
    close_toasts(phone)
    presenter.pause()  # the body holds still: what is projected is what is drawn
    wait_until(lambda: not presenter.room.playing, timeout=10.0)
    camera_settled(follower)
    # The pivot and the disc's centre (the body) where the phone's camera projects them.
    camera = follower.client.camera
    sim = presenter.room.sim
    disc = 0.8 * np.asarray(sim.state.R_space_body)[:, 2]  # part way up the symmetry axis
    panel = phone.locator("text=Following the presenter").first.bounding_box()
    assert panel is not None
    at = [project(camera, point, 390, 844) for point in ((0.0, 0.0, 0.0), tuple(disc))]
    for (px, py), point in zip(at, ("the pivot", "the disc"), strict=True):
        assert 0 < px < 390 and 0 < py < 844, f"the body at {point} is off the phone's screen: ({px:.0f}, {py:.0f})"
        assert py < panel["y"] - 20, "the panel covers the body"
    path = tmp_path / "phone.png"
    shares: list[float] = []

    def body_drawn() -> bool:  # the paused body drawn (its nodes faded in) where it is projected
        phone.screenshot(path=str(path), timeout=120_000)  # SwiftShader at 2x under a loaded suite
        pixels = np.asarray(Image.open(path).convert("RGB"), dtype=int)
        scale = pixels.shape[1] / 390.0  # device pixels per CSS pixel
        patches = [pixels[int(py * scale) - 12:int(py * scale) + 12, int(px * scale) - 12:int(px * scale) + 12]
                   for px, py in at]
        shares[:] = [float(np.mean(np.any(np.abs(patch - 255) > 30, axis=-1))) for patch in patches]
        return all(share > 0.3 for share in shares)

    poll_until(body_drawn, 60.0, 0.2, what="body pixels (a share > 0.3) at the pivot and the disc on the phone",
               seen=lambda: f"shares {shares}")
    # The panel is one line and a button: it leaves most of the screen to the 3D view.
    box = phone.get_by_role("button", name="Details").bounding_box()
    assert box is not None and box["y"] > 0.6 * 844
    phone.get_by_role("button", name="Details").tap()
    phone.get_by_role("button", name="Explore on my own").wait_for(timeout=10_000)


def _magenta_share(png, x: float, y: float, half: int = 45) -> float:  # type: ignore[no-untyped-def]
    """Share of pixels of the pointer's colour (235, 0, 140, shaded) around (x, y) [px] in `png`
    (a path or a file)."""
    pixels = np.asarray(Image.open(png).convert("RGB"), dtype=int)[int(y) - half:int(y) + half,
                                                                          int(x) - half:int(x) + half]
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return float(np.mean((r > 150) & (g < 80) & (b > 70) & (b < 200) & (r - b > 50)))


POINT_AGAIN_S = 2.0  # [s] half a marker's life (POINTER_SECONDS = 4 s): one lives while the next comes


def _drawn_shares(page, x: float, y: float, until, point, timeout: float = 120.0) -> list[float]:  # type: ignore[no-untyped-def]
    """`_magenta_share` around (x, y) of every frame `page` draws, caught by Chromium's screencast
    (a screenshot of a starved page can take longer than a marker lives; the screencast misses no
    frame the page draws), until `until(shares)` or `timeout` [s]; `point()` every POINT_AGAIN_S
    meanwhile, as a lecturer points again when the class has not seen it."""
    viewport = page.viewport_size
    cdp = page.context.new_cdp_session(page)
    shares: list[float] = []

    def on_frame(frame) -> None:  # type: ignore[no-untyped-def]
        cdp.send("Page.screencastFrameAck", {"sessionId": frame["sessionId"]})
        shares.append(_magenta_share(io.BytesIO(base64.b64decode(frame["data"])), x, y))

    cdp.on("Page.screencastFrame", on_frame)
    cdp.send("Page.startScreencast", {"format": "png", "maxWidth": viewport["width"],
                                       "maxHeight": viewport["height"], "everyNthFrame": 1})
    deadline, pointed = time.monotonic() + timeout, time.monotonic()
    try:
        while not until(shares) and time.monotonic() < deadline:
            if time.monotonic() - pointed > POINT_AGAIN_S:
                point()
                pointed = time.monotonic()
            page.wait_for_timeout(100)  # the frames' events come in here
    finally:
        cdp.send("Page.stopScreencast")
        cdp.detach()
    return shares


def test_the_presenter_points_and_the_follower_sees_it_but_cannot_point(browser, hall_app: App, wait_until,
                                                                        tmp_path) -> None:
    from app.lecture.lectern import LIVE_ROOT

    app = hall_app

    def markers() -> list[str]:
        return [n for n in app.server.scene._handle_from_node_name if n.startswith(f"{LIVE_ROOT}/pointer/")
                and n.count("/") == 3]

    presenter_page, presenter = open_page(browser, app, viewport={"width": 1280, "height": 800})
    presenter_page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    close_toasts(presenter_page)
    follower_page, follower = present_and_follow(browser, app, presenter_page, presenter, wait_until)
    before = tmp_path / "before.png"
    follower_page.screenshot(path=str(before))

    # The follower clicks and shift-clicks the body: nothing appears; it has no Pointer box.
    fx, fy = project(follower.client.camera, (0.0, 0.0, 0.0), DESK["viewport"]["width"], DESK["viewport"]["height"])
    follower_page.mouse.click(fx, fy)
    follower_page.keyboard.down("Shift")
    follower_page.mouse.click(fx, fy)
    follower_page.keyboard.up("Shift")
    time.sleep(1.0)
    assert markers() == [] and follower_page.get_by_text("Pointer", exact=True).count() == 0

    # The presenter ticks Pointer and clicks the body: a marker for everyone.
    presenter_page.get_by_text("Pointer", exact=True).first.click()
    wait_until(lambda: presenter.gui_pointer.value is True, timeout=10.0)
    time.sleep(1.0)  # the browser has been told to send scene clicks
    px, py = project(presenter.client.camera, (0.0, 0.0, 0.0), 1280, 800)
    presenter_page.mouse.click(px, py)
    wait_until(lambda: len(markers()) == 1, timeout=10.0)
    # Every frame the follower's page draws, the presenter pointing again while none shows a marker
    # (a starved page may draw none in a marker's 4 s): one shows it.
    baseline = _magenta_share(before, fx, fy)
    def marked(drawn: list[float]) -> bool:
        return any(share > baseline + 0.01 for share in drawn)

    shares = _drawn_shares(follower_page, fx, fy, marked, lambda: presenter_page.mouse.click(px, py))
    assert marked(shares), f"the follower never showed a marker: {baseline}, {shares}"
    wait_until(lambda: markers() == [], timeout=15.0)  # it fades and goes
