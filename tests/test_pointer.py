"""The presenter's pointer: Shift + click (or a plain click with `Pointer` ticked) in the
presenter's browser puts a marker in the shared scene for every follower, which fades and goes
after POINTER_SECONDS; a follower's clicks point nowhere (the click handler lives on the
presenter's own scene), and the lectern refuses anyone else."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest
from conftest import RawClient, poll_until

from app.lecture.lectern import LIVE_ROOT, POINTER_SECONDS, pointed_at
from app.main import create_server

CODE = "112358"
DT = 1.0 / 60.0


def _click(client: RawClient, modifier: str | None, origin=(4.0, -3.0, 2.0), direction=(-4.0, 3.0, -2.0)) -> None:  # type: ignore[no-untyped-def]
    from viser import _messages

    client.send(_messages.ScenePointerMessage("click", origin, direction, ((0.5, 0.5),), modifier))


def _markers(app) -> list[str]:  # type: ignore[no-untyped-def]
    return sorted(name for name in app.server.scene._handle_from_node_name
                  if name.startswith(f"{LIVE_ROOT}/pointer/") and name.count("/") == 3)


@pytest.fixture
def hall() -> Iterator[tuple]:  # type: ignore[type-arg]
    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE)
    clients = [RawClient(app.port)]
    presenter = next(iter(app.wait_for_sessions(1).values()))
    presenter.present(CODE)
    clients.append(RawClient(app.port))
    sessions = app.wait_for_sessions(2)
    (follower,) = (s for s in sessions.values() if s is not presenter)
    for _ in range(3):
        app.lectern.tick(DT)
    try:
        yield app, presenter, follower, clients
    finally:
        for client in clients:
            client.close()
        app.stop()


def test_pointed_at_is_the_rays_point_nearest_the_look_at() -> None:
    point = pointed_at((4.0, -3.0, 2.0), (-8.0, 6.0, -4.0), (0.0, 0.0, 0.0))
    np.testing.assert_allclose(point, 0.0, atol=1e-12)
    point = pointed_at((0.0, 0.0, 5.0), (1.0, 0.0, 0.0), (3.0, 1.0, 0.0))
    np.testing.assert_allclose(point, (3.0, 0.0, 5.0), atol=1e-12)
    for bad in ((0.0, 0.0, 0.0), (math.nan, 0.0, 1.0)):
        with pytest.raises(ValueError):
            pointed_at((0.0, 0.0, 5.0), bad, (0.0, 0.0, 0.0))


def test_only_the_presenter_points_and_the_marker_fades(hall) -> None:  # type: ignore[no-untyped-def]
    app, presenter, follower, (presenter_client, follower_client) = hall
    assert presenter.gui_pointer.visible and not follower.gui_pointer.visible
    _click(follower_client, "shift")
    _click(follower_client, None)
    _click(presenter_client, None)  # Pointer not ticked: a plain click is no pointing
    presenter.gui_pointer_label.value = "the flip"
    _click(presenter_client, "shift")
    poll_until(lambda: len(_markers(app)) == 1)
    (marker,) = _markers(app)
    nodes = app.server.scene._handle_from_node_name  # the click's callback makes the marker, then its label
    label = poll_until(lambda: nodes.get(f"{marker}/label"))
    assert label.text == "the flip"
    with pytest.raises(PermissionError):
        app.lectern.point(follower, (0.0, 0.0, 5.0), (0.0, 0.0, -1.0))
    presenter.gui_pointer.value = True  # ticked: a plain click points
    _click(presenter_client, None)
    poll_until(lambda: len(_markers(app)) == 2)
    for _ in range(int(POINTER_SECONDS / DT) + 2):
        app.lectern.tick(DT)
    assert _markers(app) == []
    assert presenter.error_count == 0 and follower.error_count == 0, (presenter.last_error, follower.last_error)
    presenter.stop_presenting()
    _click(presenter_client, "shift")  # no longer presenting: no pointing
    presenter.gui_pointer.value = True
    _click(presenter_client, None)
    for _ in range(10):
        app.lectern.tick(DT)
    assert _markers(app) == [] and presenter.error_count == 0, presenter.last_error
