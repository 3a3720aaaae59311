"""The phone's folded panel (`app.hall.narrow.NarrowPanel`) never outlives a switch away from the
browser's own room: a fold begun at connect (one thread) and a switch to following (another
thread) leave exactly one layout, the follower's."""

from __future__ import annotations

import threading
import time
from types import SimpleNamespace
from typing import Any

from app.hall.narrow import NarrowPanel


class Handle(SimpleNamespace):
    def on_click(self, callback: Any) -> Any:
        return callback


class Gui:
    def add_markdown(self, content: str, **kw: Any) -> Handle:
        return Handle(content=content, visible=kw.get("visible", True), label="")

    def add_button(self, label: str, **kw: Any) -> Handle:
        return Handle(label=label, visible=kw.get("visible", True), content="")


def panel(own: Any, handles: Any = list) -> NarrowPanel:
    room = SimpleNamespace(mode="live", playing=False, scene=SimpleNamespace(title="Heavy top"),
                           sim=SimpleNamespace(t=0.0), shown_t=0.0)
    return NarrowPanel(SimpleNamespace(gui=Gui()), lambda _name, f: f, handles, lambda: room,  # type: ignore[arg-type]
                       order=0.0, own=own)


def test_start_does_nothing_when_the_browser_has_no_room_of_its_own() -> None:
    narrow = panel(own=lambda: False)
    narrow.start()
    assert not narrow.on and not narrow.gui_details.visible and not narrow.gui_line.visible


def test_an_end_during_a_fold_waits_for_it_and_wins() -> None:
    """The fold is slowed inside `refresh` (its handles read while the switch ends the layout);
    the end runs after it, so Details and the line are hidden at the end, the folded handle shown."""
    mode = {"own": True}
    entered, release = threading.Event(), threading.Event()
    scene_slider = Handle(visible=True, label="φ", content="")

    def handles() -> list[Handle]:
        entered.set()
        release.wait(5.0)
        return [scene_slider]

    narrow = panel(own=lambda: mode["own"], handles=handles)
    fold = threading.Thread(target=narrow.start)
    fold.start()
    assert entered.wait(5.0)

    def switch() -> None:  # as `Session.follow`: the mode changes, then the layout ends
        mode["own"] = False
        narrow.end()

    follow = threading.Thread(target=switch)
    follow.start()
    time.sleep(0.05)  # the switch is blocked on the fold's lock (checked below: it has not ended)
    assert follow.is_alive(), "end() ran while the fold was half done"
    release.set()
    fold.join(5.0)
    follow.join(5.0)
    assert not narrow.on and not narrow.gui_details.visible and not narrow.gui_line.visible
    assert scene_slider.visible, "the fold's handle stays hidden after the switch"
    narrow.start()  # a late start (the connect's) after the switch does nothing
    assert not narrow.on and not narrow.gui_details.visible
