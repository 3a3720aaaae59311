"""One lecture on two workers (app.lecture.bus), in Debian's Chromium, through the pages only:
a presenter's page on worker A, a laptop follower's page on worker B (one real redis-server,
both workers in this process, their loops running).

The presenter types the code and presents Free body; the follower's page on B shows the
follower panel with the presenter's scene, and the presenter's badge counts it.  The presenter
opens its Plots tab and plays: the follower's page shows the tab copied, read only.  The follower
presses `Explore on my own`: its room on B is the presenter's, bit for bit (`app.codec`); it
presses `Follow presenter` and follows again.
Needs Debian's Chromium and redis-server.  Pictures for people under $RBL_TEST_SHOTS/bus/
(follower_other_worker.png, the picture in docs/cluster.md; follower_plot_other_worker.png, with the plot).
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from conftest import DESK, TEST_SHOTS, keep_picture
from test_browser import choose
from test_browser_lecture import _CONTEXTS, close_toasts, open_folder, open_page, received, text_input
from test_codec import assert_rooms_equal

from app.cluster import services
from app.main import App, create_server

pytestmark = pytest.mark.browser

CODE = "86420135"


@pytest.fixture
def two_workers() -> Iterator[tuple[App, App]]:
    try:
        url, redis = services.start_redis()
    except services.MissingProgram as error:
        pytest.skip(str(error))
    apps: list[App] = []
    try:
        apps = [create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE, redis_url=url, worker_id=worker)
                for worker in ("a", "b")]
        yield apps[0], apps[1]
    finally:
        while _CONTEXTS:
            _CONTEXTS.pop().close()
        for app in apps:
            app.stop()
        services.stop_process(redis)


def test_a_follower_on_another_worker_follows_explores_and_comes_back(  # type: ignore[no-untyped-def]
        browser, two_workers, wait_until) -> None:
    a, b = two_workers
    presenter_page, presenter = open_page(browser, a, **DESK)
    close_toasts(presenter_page)
    choose(presenter_page, presenter.gui_scene, "Free body")
    wait_until(lambda: presenter.room.scene.title == "Free body", timeout=30.0)
    open_folder(presenter_page, "Lecture", "Presenter code")
    text_input(presenter_page, "Presenter code").click()
    presenter_page.keyboard.type(CODE, delay=30)
    received(presenter_page, presenter, "Presenter code", CODE)
    presenter_page.get_by_role("button", name="Present").click()
    wait_until(lambda: presenter.mode == "presenting", timeout=15.0)

    follower_page, follower = open_page(browser, b, **DESK)
    wait_until(lambda: follower.mode == "following", timeout=30.0)
    follower_page.get_by_text("Following the presenter").first.wait_for(timeout=30_000)
    follower_page.get_by_text("Free body").first.wait_for(timeout=30_000)  # the presenter's scene, in its panel
    close_toasts(follower_page)
    presenter_page.get_by_text("1 following").first.wait_for(timeout=30_000)  # the badge counts worker B's follower
    assert b.lectern.remote is not None and b.lectern.remote.worker == "a"
    if TEST_SHOTS:
        follower_page.wait_for_timeout(3000)  # the shared nodes fade in, the labels are laid out
        keep_picture(follower_page, "bus/follower_other_worker.png")

    # The presenter opens its Plots tab and plays: the follower on B sees the tab copied, read only.
    presenter_page.get_by_role("button", name="Plots", exact=True).click()
    presenter_page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: presenter.scene.tabs.shown == "Plots" and presenter.room.playing, timeout=15.0)
    follower_page.get_by_text("The presenter's Plots tab (read only)").first.wait_for(timeout=30_000)
    follower_page.get_by_text("ω, body components [rad/s]").first.wait_for(timeout=30_000)  # a chart's title
    keep_picture(follower_page, "bus/follower_plot_other_worker.png")
    presenter_page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not presenter.room.playing, timeout=15.0)

    follower_page.get_by_role("button", name="Explore on my own").click()
    wait_until(lambda: follower.mode == "own", timeout=30.0)
    assert follower.room.scene.title == "Free body" and follower.error_count == 0, follower.last_error
    with presenter.room.lock:
        original = presenter.room.fork()
    with follower.room.lock:
        copy = follower.room.fork()
    assert_rooms_equal(copy, original, "explored on worker B")  # paused where the presenter paused, bit for bit
    follower_page.get_by_role("button", name="Follow presenter").click()
    wait_until(lambda: follower.mode == "following", timeout=30.0)
