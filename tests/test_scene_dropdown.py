"""The Scene dropdown keeps a browser's last choice: a scene chosen while the view of the one
chosen before is still being built is the scene shown in the end (`OwnRoom.show`), through the
websocket as a page sends it.

Seen in a busy browser run: Poinsot chosen, then Moving frame a second later, while Poinsot's view
was still built; the switch to Poinsot then wrote "Poinsot" back into the dropdown, and the
callback of the Moving frame choice, waiting for it, read "Poinsot" and switched nothing."""

from __future__ import annotations

import threading

from conftest import poll_until
from viser import _messages


def test_a_scene_chosen_while_the_last_one_is_built_is_the_one_shown(manual) -> None:
    session = manual.session
    own_room = session.own_room
    building, release = threading.Event(), threading.Event()
    build = own_room.new_view

    def slow_first_build(room):  # type: ignore[no-untyped-def]
        if not building.is_set():
            building.set()
            assert release.wait(10.0), "the test never released the first build"
        return build(room)

    own_room.new_view = slow_first_build
    uuid = session.gui_scene._impl.uuid
    manual.client.send(_messages.GuiUpdateMessage(uuid, {"value": own_room.scene_label("Poinsot")}))
    assert building.wait(10.0), "the Poinsot choice never started a view"
    later = own_room.scene_label("Moving frame")
    manual.client.send(_messages.GuiUpdateMessage(uuid, {"value": later}))
    poll_until(lambda: session.gui_scene.value == later, 10.0,  # (not manual.wait: the first holds the lock)
               what="viser to take the second choice")
    release.set()
    manual.wait(lambda: session.room.scene.title == "Moving frame", timeout=10.0)
    assert session.gui_scene.value == later
    assert session.error_count == 0, session.last_error
