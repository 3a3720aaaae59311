"""End-to-end: the lecture app in headless Chromium (SwiftShader WebGL), driven by Playwright.

Two tests, each combining several checks (a browser test costs ~10-15 s on 2 cores):
1. Euler angles: the page loads; θ moved with the keyboard on its Mantine thumb reaches the
   server and changes the rendered scene (clipped screenshots differ); Play makes the body
   move and the θ slider follow (its aria-valuenow changes, with no feedback loop).
2. Free body in one browser context, a second context alongside: the scene is chosen in the
   dropdown, the Dzhanibekov preset played; invalid moments typed into the I3 box show a
   message while the body keeps moving; the other context's session is untouched.
Needs Debian's Chromium: `apt-get install chromium`.
"""

from __future__ import annotations

import io
import re
import time

import numpy as np
import pytest
from PIL import Image

from app.main import App

pytestmark = pytest.mark.browser

SCENE_CLIP = {"x": 0, "y": 0, "width": 860, "height": 800}  # left of the GUI panel
MIN_CHANGED_FRACTION = 0.005  # a visible change of the body: far more than 0.5 % of pixels


def changed_fraction(png_a: bytes, png_b: bytes) -> float:
    """Fraction of pixels whose RGB differs by more than 8/255 in any channel."""
    a = np.asarray(Image.open(io.BytesIO(png_a)).convert("RGB"), dtype=np.int16)
    b = np.asarray(Image.open(io.BytesIO(png_b)).convert("RGB"), dtype=np.int16)
    return float(np.mean(np.any(np.abs(a - b) > 8, axis=-1)))


def picture_changes(page, before: bytes, clip: dict = SCENE_CLIP, timeout: float = 15.0) -> float:
    """Screenshots of `clip` until one differs from `before` in more than MIN_CHANGED_FRACTION of
    its pixels; that fraction (AssertionError after `timeout` [s])."""
    from conftest import poll_until

    def fraction() -> float:
        changed = changed_fraction(before, page.screenshot(clip=clip, timeout=60_000))  # a busy renderer
        return changed if changed > MIN_CHANGED_FRACTION else 0.0

    return poll_until(fraction, timeout=timeout, interval=0.2)


FONTS_MS = 180_000  # [ms] a page's fonts loaded: a page load on a busy machine


def still_picture(page, clip: dict = SCENE_CLIP, timeout: float = 30.0) -> bytes:
    """A screenshot of `clip` once the picture holds still (the nodes have faded in): one that
    differs from the one before it (0.2 s earlier) in under MIN_CHANGED_FRACTION / 5 of its
    pixels (AssertionError after `timeout` [s], naming the last difference)."""
    from conftest import poll_until

    # A screenshot first waits for the page's fonts: a page just loaded on a busy machine has
    # taken more than a minute for them (the wait is the load's, so its deadline is generous).
    page.wait_for_function("document.fonts.status === 'loaded'", timeout=FONTS_MS)
    shots = [page.screenshot(clip=clip, timeout=60_000)]
    changes: list[float] = []

    def still() -> bytes | None:
        time.sleep(0.2)  # the interval between the two pictures compared
        shots.append(page.screenshot(clip=clip, timeout=60_000))
        changes.append(changed_fraction(shots[-2], shots[-1]))
        return shots[-1] if changes[-1] < MIN_CHANGED_FRACTION / 5 else None

    return poll_until(still, timeout, 0.0, what="a still picture (two screenshots alike)",
                      seen=lambda: f"changed fractions {changes[-5:]}")


def app_url(page, port: int) -> str:
    """The address of the server on `port` with the page's own device pixel ratio pinned (viser's `fixedDpr`).

    viser's client lowers the canvas resolution to 0.75-0.875 of it when frames come slowly (its
    adaptive DPR); on a loaded CI machine that happened between two screenshots of one paused
    view and every edge moved by a sub-pixel (1.9 % of pixels changed).  Pinned, a still view
    renders to the same pixels whenever it is taken."""
    return f"http://127.0.0.1:{port}/?fixedDpr={page.evaluate('window.devicePixelRatio')}"


def choose(page, handle, option: str, tries: int = 3) -> None:  # type: ignore[no-untyped-def]
    """Pick `option` in the viser dropdown `handle`, as a person does: open it, click the option,
    see the field show it; if the list closed before the click (Mantine hides a dropdown whose
    field moved out of the panel's view, as when the panel grows above it on a busy machine) or
    the field kept its value, open it again."""
    field = page.locator(f'[id="{handle._impl.uuid}"]')
    item = page.get_by_role("option", name=option, exact=True)
    for attempt in range(tries):
        field.scroll_into_view_if_needed(timeout=30_000)
        field.click()
        try:
            item.click(timeout=10_000)
            page.wait_for_function("([field, option]) => field.value === option",
                                   arg=[field.element_handle(timeout=10_000), option], timeout=10_000)
            return
        except Exception:  # noqa: BLE001 - the list closed under the pointer, or the field kept its value
            if attempt == tries - 1:
                raise AssertionError(f"{option!r} not chosen in the dropdown: it shows "
                                     f"{field.input_value(timeout=5_000)!r}") from None
            page.keyboard.press("Escape")


def open_app(page, app: App, sessions: int = 1, wait: bool = True):
    """Load the app; its session (the newest one); the software-WebGL toast closed."""
    before = set(app.sessions)
    page.goto(app_url(page, app.port))
    current = app.wait_for_sessions(sessions, timeout=90.0)
    (session,) = (s for cid, s in current.items() if cid not in before)
    if wait:
        wait_for_gui(page)
    return session


def wait_for_gui(page) -> None:
    page.get_by_text("Euler angles, z-x-z convention").wait_for(timeout=30_000)
    page.evaluate("""() => document.querySelectorAll('.mantine-Notification-closeButton')
                           .forEach((button) => button.click())""")  # every toast, none waited for


def slider_thumb(page, handle):
    """The Mantine thumb of a viser slider (its root's id is the GUI uuid)."""
    return page.locator(f'[id="{handle._impl.uuid}"] [role="slider"]')


def test_euler_scene_slider_moves_the_body_and_play_moves_the_slider(wait_until, app: App, page) -> None:
    session = open_app(page, app)
    scene = session.scene
    before = still_picture(page)  # nodes faded in
    time.sleep(0.5)  # control: half a second later a still scene renders the same
    unchanged = changed_fraction(before, page.screenshot(clip=SCENE_CLIP, timeout=60_000))
    assert unchanged < MIN_CHANGED_FRACTION / 5

    # The slider root's id is the GUI uuid; its <label for=...> carries the text.
    uuid = page.locator("label", has_text=re.compile(r"^θ")).first.get_attribute("for")
    assert uuid == scene.gui_angles[1]._impl.uuid
    thumb = slider_thumb(page, scene.gui_angles[1])
    thumb.focus()
    page.keyboard.press("End")
    wait_until(lambda: scene.sim.angles_deg[1] == 180.0, timeout=10.0)
    assert thumb.get_attribute("aria-valuenow") == "180"
    page.get_by_text("Gimbal lock").first.wait_for(timeout=5_000)  # θ = 180°: the GUI says so
    page.keyboard.press("ArrowLeft")  # one step: 179°
    wait_until(lambda: scene.sim.angles_deg[1] == 179.0, timeout=10.0)
    changed = picture_changes(page, before)  # the body turned

    # Play: θ advances at dθ/dt = 10°/s (wrapping below 180°); the slider follows.
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: scene.room.playing, timeout=10.0)
    wait_until(lambda: thumb.get_attribute("aria-valuenow") not in ("179", "180"), timeout=10.0)
    value = float(thumb.get_attribute("aria-valuenow"))
    assert 150.0 < value < 179.0
    assert scene.room.playing  # the slider's own update did not pause (no feedback)
    picture_changes(page, page.screenshot(clip=SCENE_CLIP, timeout=60_000))  # the body moves
    print(f"changed pixels: still {unchanged:.4%}, θ 50° -> 179° {changed:.2%}; slider followed to {value}")
    assert session.last_error is None


def test_free_body_invalid_moments_keep_it_moving_and_contexts_are_independent(
    wait_until, app: App, browser
) -> None:
    contexts = [browser.new_context(viewport={"width": 1280, "height": 800}) for _ in range(2)]
    try:
        page, other_page = (context.new_page() for context in contexts)
        session = open_app(page, app, sessions=1, wait=False)
        other = open_app(other_page, app, sessions=2, wait=False)  # loads meanwhile
        assert other is not session
        wait_for_gui(page)

        choose(page, session.gui_scene, "Free body")
        wait_until(lambda: session.scene.title == "Free body", timeout=10.0)
        page.get_by_role("button", name="Dzhanibekov").click()
        page.get_by_role("button", name="Play", exact=True).click()
        scene = session.scene
        wait_until(lambda: scene.room.playing and scene.sim.state.t > 0.3, timeout=10.0)
        theta = slider_thumb(page, scene.gui_angles[1])
        first = theta.get_attribute("aria-valuenow")
        wait_until(lambda: theta.get_attribute("aria-valuenow") != first, timeout=10.0)  # follows

        # I3 = 4.9 > I1 + I2: typed into the number box beside the slider.
        box = page.locator(f'[id="{scene.gui_params[2]._impl.uuid}"]').locator("xpath=..").locator(
            "input.mantine-NumberInput-input")
        box.fill("4.9")
        box.press("Enter")
        page.get_by_text("Not a rigid body").first.wait_for(timeout=10_000)
        assert scene.sim.model.inertia == (0.3, 0.75, 1.0) and scene.room.playing
        t = scene.sim.state.t
        time.sleep(0.3)
        picture_changes(page, page.screenshot(clip=SCENE_CLIP, timeout=60_000))
        wait_until(lambda: scene.sim.state.t > t + 0.5, timeout=10.0)  # the body keeps moving

        # The other browser: its own session, still the Euler scene, not playing, unchanged.
        wait_for_gui(other_page)
        assert other.scene.title == "Euler angles" and not other.scene.room.playing
        assert other.scene.sim.angles_deg == [30.0, 50.0, 20.0]
        assert other_page.locator(f'[id="{other.gui_scene._impl.uuid}"]').input_value() == "Euler angles"
        assert session.last_error is None and other.last_error is None
    finally:
        for context in contexts:
            context.close()


def playback_time(page) -> float:  # type: ignore[no-untyped-def]
    """The time [s] on an exported page's playback bar (its slider)."""
    return float(page.locator('[role="slider"]').first.get_attribute("aria-valuenow") or "nan")


def toggle_playback(page, until: float, timeout: float = 60.0) -> float:  # type: ignore[no-untyped-def]
    """On an exported page that plays: once its time reaches `until` [s], press Space (pause) and
    wait until the time stands still; that time.  If it is paused, Space first (play)."""
    def stands_still() -> float | None:
        before = playback_time(page)
        page.wait_for_timeout(300)
        return before if playback_time(page) == before else None

    deadline = time.monotonic() + timeout
    if stands_still() is not None:
        page.keyboard.press("Space")
    while playback_time(page) < until:
        assert time.monotonic() < deadline, f"the playback stood at {playback_time(page)} s, waiting for {until}"
        page.wait_for_timeout(100)
    page.keyboard.press("Space")
    while (still := stands_still()) is None:
        assert time.monotonic() < deadline, f"the playback went on after Space, at {playback_time(page)} s"
    return still


def test_an_exported_recording_plays_offline_from_a_file_and_projector_text_is_large(page, tmp_path) -> None:
    """3. `python -m app export` writes a page that plays the motion from file:// (the picture
    changes while it plays); and the projector layout's panel text measures >= 18 px at 1024 px."""
    import subprocess
    import sys

    out = tmp_path / "loop.html"
    subprocess.run([sys.executable, "-m", "app", "export", "--scene", "Heavy top", "--preset", "Loop",
                    "--seconds", "10", "--out", str(out)], check=True, timeout=120, capture_output=True)
    page.goto(out.as_uri())
    page.locator("canvas").first.wait_for(timeout=30_000)
    # The pictures are taken paused (the Space key, as a viewer would): playing, the page moves
    # its time bar 120 times a second, and a starved page took over 60 s for one screenshot.
    clip = {"x": 0, "y": 200, "width": 800, "height": 400}
    played = playback_time(page)
    assert 0.0 <= played < 5.0, f"the playback bar's time: {played}"  # NaN fails too
    t_first = toggle_playback(page, played + 2.0)
    first = page.screenshot(clip=clip, timeout=60_000)
    t_second = toggle_playback(page, t_first + 1.5)
    assert changed_fraction(first, page.screenshot(clip=clip, timeout=60_000)) > MIN_CHANGED_FRACTION, \
        (t_first, t_second)

    from app.main import create_server

    app = create_server("127.0.0.1", 0, verbose=False, projector=True)
    try:
        page.set_viewport_size({"width": 1024, "height": 768})
        page.goto(app_url(page, app.port))
        session = next(iter(app.wait_for_sessions(1, timeout=90.0).values()))
        page.get_by_text("Euler angles, z-x-z").wait_for(timeout=30_000)
        time.sleep(1.0)
        sizes = page.evaluate("() => Array.from(document.querySelectorAll('label')).map("
                              "e => parseFloat(getComputedStyle(e).fontSize))")
        assert sizes and min(sizes) >= 18.0, sizes
        panel = page.locator(f'[id="{session.gui_scene._impl.uuid}"]').bounding_box()
        assert panel is not None and panel["x"] >= 0.7 * 1024 - 20  # the 3D view keeps >= ~70 %
    finally:
        app.stop()


def test_poinsot_scene_opens_from_the_dropdown_and_its_picture_changes_while_it_plays(
        wait_until, app: App, page) -> None:
    """4. The Poinsot scene, chosen in the Scene dropdown: the ellipsoid rolls (the picture
    changes while it plays) and the session reports no error."""
    session = open_app(page, app)
    choose(page, session.gui_scene, "Poinsot")
    wait_until(lambda: session.scene.title == "Poinsot", timeout=10.0)
    page.get_by_text("Poinsot: the ellipsoid rolls").wait_for(timeout=30_000)
    session.play()
    time.sleep(2.0)
    picture_changes(page, page.screenshot(clip=SCENE_CLIP, timeout=60_000))
    assert session.room.playing and session.last_error is None


def test_inertia_scene_weighs_a_mass_from_the_browser(wait_until, app: App, page) -> None:
    """5. The Inertia scene: the mass slider moved with the keyboard reaches the server, the
    tensor read out changes, and the panel shows the new moments."""
    session = open_app(page, app)
    session.select_scene("Inertia")
    page.get_by_text("Inertia tensor (memo §3)").wait_for(timeout=30_000)
    view = session.scene
    before = view.readout.handle.content
    thumb = slider_thumb(page, view.gui_mass)
    thumb.focus()
    page.keyboard.press("End")
    wait_until(lambda: view.sim.masses[view.selected] == 10.0, timeout=10.0)
    wait_until(lambda: view.readout.handle.content != before, timeout=10.0)
    moments = view.sim.properties()["moments"]  # and the browser shows the new moments
    page.get_by_text("Principal moments I1 ≤ I2 ≤ I3 = " + ", ".join(f"{m:.5g}" for m in moments),
                     exact=False).wait_for(timeout=10_000)
    assert session.last_error is None


def test_arrows_and_segments_sent_inline_draw_as_the_raw_buffers_do(wait_until, page, monkeypatch) -> None:
    """The wire sends small arrow and segment points as msgpack numbers, not as viser's raw
    buffers (`app.wire.INLINE_NODES`): the browser draws the same pixels either way.  The same
    arrows and segments are set once through a wire's frame and once through viser's public
    path, each on a fresh server, and the two screenshots compared."""
    import viser

    from app import wire as wire_module
    from app.viser_internals import set_points
    from app.wire import Wire, capturing, end_frames

    inlined: list[str] = []
    original = wire_module._inline_points

    def counted(message, inline):  # type: ignore[no-untyped-def]
        raw = original(message, inline)
        if raw is not None:
            inlined.append(message.name)
        return raw

    monkeypatch.setattr(wire_module, "_inline_points", counted)
    arrows = np.array([[[0.0, 0.0, 0.0], [1.5, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 1.25, 0.75]],
                       [[0.0, 0.0, 0.0], [-0.5, -1.0, 1.5]]], dtype=np.float32)
    angles = np.linspace(0.0, 1.5 * np.pi, 9)
    curve = np.stack([np.cos(angles), np.sin(angles), 0.25 * angles], axis=1).astype(np.float32)
    segments = np.stack([curve[:-1], curve[1:]], axis=1)
    shots = []
    through_wire_inlined: list[str] = []
    for through_wire in (True, False):
        server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
        try:
            wire = Wire.attach(server) if through_wire else None
            node_a = server.scene.add_arrows("/a", np.zeros((3, 2, 3), dtype=np.float32), (200, 30, 30),
                                             shaft_radius=0.04, head_radius=0.09, head_length=0.2)
            node_s = server.scene.add_line_segments("/s", np.zeros((8, 2, 3), dtype=np.float32), (20, 20, 160),
                                                    thickness=4.0, thickness_units="screen")
            page.goto(app_url(page, server.get_port()))
            (client,) = wait_until(lambda server=server: list(server.get_clients().values()), timeout=30.0)
            page.locator("canvas").first.wait_for(timeout=30_000)
            if wire is not None:  # frames until one is written (the browser may not be caught up yet)
                for _ in range(100):
                    with capturing():
                        set_points(node_a, arrows)
                        set_points(node_s, segments)
                    end_frames([(wire, [client.client_id])])
                    time.sleep(0.05)
                    if wire.writes:
                        break
                through_wire_inlined = list(inlined)
            else:
                set_points(node_a, arrows)
                set_points(node_s, segments)
            shots.append(still_picture(page))  # drawn, the nodes faded in: not a fixed wait
        finally:
            server.stop()
    # Each frame the first server's wire encoded (one, or more when the page was slow to take the
    # first) carried both nodes inline; the second server's went through viser's raw buffers.
    frames = len(through_wire_inlined) // 2
    assert frames >= 1 and sorted(through_wire_inlined) == sorted(["/a", "/s"] * frames), through_wire_inlined
    assert inlined == through_wire_inlined, "viser's public path inlined points"
    changed = changed_fraction(*shots)
    print(f"changed pixels, inline against raw buffers: {changed:.4%}")
    assert changed < 0.001
    r, g, b = np.moveaxis(np.asarray(Image.open(io.BytesIO(shots[0])).convert("RGB"), dtype=np.int16), -1, 0)
    reds = np.mean((r > 150) & (r - g > 60) & (r - b > 60))  # the (lit) arrows are drawn at all
    blues = np.mean((b > 100) & (b - r > 60) & (b - g > 60))  # ... and so is the curve
    assert reds > 0.0003 and blues > 0.0003, (reds, blues)
