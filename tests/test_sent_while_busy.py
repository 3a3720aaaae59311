"""What a browser sends while its session is busy is what the session acts on, through the
websocket as a page sends it (a raw client; the loop not running: the test is the loop).

A browser's update is taken by viser as it arrives; its callback then waits for the session's
lock, held by the frame being drawn or the callback before.  Whatever the server writes to the
control meanwhile must not replace what the browser sent:

- the Scene dropdown keeps the last choice: a scene chosen while the view of the one chosen before
  is still built is the scene shown (`OwnRoom.show`).  Seen in busy browser runs: Poinsot, then
  Moving frame a second later; the switch to Poinsot wrote "Poinsot" back into the dropdown, and
  the Moving frame callback, waiting for it, read "Poinsot" and switched nothing.
- a bound control decides on the value sent (`Binding`, `on_browser_value`): a time typed into the
  Timeline while a frame wrote the slider's following value is refused or taken, not lost.  Seen
  in busy browser runs: 999 typed while playing brought neither a refusal nor a value."""

from __future__ import annotations

import threading

from conftest import poll_until
from viser import _messages

from app.viser_internals import PANEL_INPUTS


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


def test_a_time_typed_while_a_frame_writes_the_timeline_is_refused_or_taken(manual) -> None:
    assert PANEL_INPUTS.on, "viser's internals changed: values are read when the callback runs"
    session = manual.session
    session.play()
    manual.tick(2.0)
    session.pause()
    view = session.scene
    timeline = view.timeline
    slider = timeline.gui_slider
    shown, t_paused = slider.value, session.room.shown_t
    assert shown > 1.0
    for sent, refused, applied in ((999.0, 1, 0), (1.0, 1, 1)):
        timeline.binding.release()  # the last edit long over: a frame writes the slider again
        with session.lock:  # a frame being drawn: the browser's callback waits for it
            manual.client.send(_messages.GuiUpdateMessage(slider._impl.uuid, {"value": sent}))
            poll_until(lambda sent=sent: slider.value == sent, 10.0, what=f"viser to take {sent}")
            timeline.refresh()  # the frame shows the room's time on the slider, as a playing room's does
            assert slider.value == shown
        manual.wait(lambda applied=applied, refused=refused: (timeline.binding.refused, timeline.binding.applied)
                    == (refused, applied), timeout=10.0)
        assert abs(session.room.shown_t - (t_paused if applied == 0 else sent)) < 1e-9  # (a recorded step's float)
        assert slider.value == (shown if applied == 0 else sent)  # the field shows the value in force
        assert ("999" in timeline.binding.refusal) == (applied == 0)  # said under the slider, gone once taken
    assert session.error_count == 0, session.last_error
