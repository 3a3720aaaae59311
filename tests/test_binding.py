"""app.kit.panel.binding on the server, no browser: a fake handle, a ManualClock, updates counted.

The page sends complete values (its typing guard, tested in the browser in
test_browser_typing.py); here every update must be applied the moment it arrives, however slowly
or quickly updates come, checked and refused with the field back at the value in force, and the
server's quiet writes must leave a field alone while its user moves it.  A refusal is said where
the hand is: in a note right under the control (in its folder, ordered just after it), which goes
once the control takes a value.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import pytest

from app.kit.core.common import SliderSpec
from app.kit.panel.binding import HANDS_OFF_S, ManualClock, Refused, bind
from app.kit.panel.gui import MessageLine, Quiet
from app.viser_internals import BESIDE_GAP

SPEC = SliderSpec("I3", "I3 [kg m²]", 0.05, 5.0, 0.01)
ANGLE = SliderSpec("phi", "φ [deg]", -180.0, 180.0, 1.0)
BROWSER = SimpleNamespace(client=object())  # an event from a browser (the server's own has client None)
SERVER = SimpleNamespace(client=None)


class FakeHandle:
    """A viser handle as the binding sees it: `value`, `precision`, `on_update`; counts writes."""

    def __init__(self, value: Any) -> None:
        self._value = value
        self.precision = 0
        self.order = 7.0
        self.callbacks: list[Any] = []
        self.writes: list[Any] = []

    def on_update(self, callback: Any) -> None:
        self.callbacks.append(callback)

    @property
    def value(self) -> Any:
        return self._value

    @value.setter
    def value(self, value: Any) -> None:  # the server writing: viser runs the callbacks at once
        self._value = value
        self.writes.append(value)
        for callback in self.callbacks:
            callback(SERVER)

    def receive(self, value: Any) -> None:
        """What viser does with a browser's GuiUpdateMessage."""
        self._value = value
        for callback in self.callbacks:
            callback(BROWSER)


class Message:
    def __init__(self) -> None:
        self.text = ""

    def show(self, text: str, stale: object = None, *, here: bool = True) -> None:
        self.text = text
        self.here = here

    def clear(self) -> None:
        self.text = ""


class FakeMarkdown:
    """A Markdown element as a note sees it: `content`, `visible`, `order`, `remove`."""

    def __init__(self, content: str, visible: bool, order: float) -> None:
        self.content, self.visible, self.order = content, visible, order
        self.removed = 0

    def remove(self) -> None:
        self.removed += 1


class FakeGui:
    """A panel: the Markdown elements added to it."""

    def __init__(self) -> None:
        self.added: list[FakeMarkdown] = []

    def add_markdown(self, content: str, visible: bool = True, order: float | None = None) -> FakeMarkdown:
        self.added.append(FakeMarkdown(content, visible, float(order if order is not None else 0.0)))
        return self.added[-1]


class Rig:
    """A handle bound to `self.in_force`; `apply` refuses a sum of moments breaking I1 + I2 >= I3.
    With `gui`, the handle's refusals are said under it too (`ControlNote`)."""

    def __init__(self, value: float = 1.0, spec: SliderSpec = SPEC, gui: FakeGui | None = None) -> None:
        self.clock = ManualClock()
        self.handle = FakeHandle(value)
        self.message = Message()
        self.quiet = Quiet()
        self.in_force = value
        self.applied: list[float] = []
        self.binding = bind(self.handle, where="I3 slider", wrap=lambda _where, fn: fn, message=self.message,
                            quiet=self.quiet, apply=self.apply, current=lambda: self.in_force, spec=spec,
                            clock=self.clock, gui=gui)

    def apply(self, value: float) -> str | None:
        if value > 2.0:  # I1 = I2 = 1: I3 <= 2
            return f"I3 = {value:g} refused: not a rigid body (I1 + I2 >= I3)."
        self.applied.append(value)
        self.in_force = value
        return None

    def stream(self, values: list[Any], gap: float) -> None:
        for k, value in enumerate(values):
            if k:
                self.clock.advance(gap)
            self.handle.receive(value)


@pytest.mark.parametrize("gap", [0.0, 0.03, 0.05, 0.12, 0.25, 0.6, 2.0])
def test_each_update_applies_when_it_arrives_however_far_apart(gap: float) -> None:
    rig = Rig()
    values = [1.0 + 0.1 * k for k in range(1, 9)]  # a thumb dragged fast (50 ms) or slowly (250 ms a step)
    for k, value in enumerate(values, start=1):
        rig.clock.advance(gap)
        rig.handle.receive(value)
        assert rig.applied == values[:k]  # this value, now: no pause waited for, none skipped
    assert rig.handle.writes == [] and rig.message.text == ""


def test_a_typed_negative_fraction_applies_exactly_once() -> None:
    rig = Rig(spec=ANGLE)
    rig.handle.receive(-0.8)  # what the page's guard sends for "-0.8" typed
    assert rig.applied == [-0.8] and rig.binding.applied == 1
    assert math.copysign(1.0, rig.in_force) == -1.0 and rig.handle.writes == []


def test_a_refused_value_applies_nothing_and_puts_the_value_in_force_back() -> None:
    rig = Rig(value=1.5)
    rig.handle.receive(1e9)
    assert rig.applied == [] and rig.in_force == 1.5 and rig.binding.refused == 1
    assert "1000000000.0 refused: the range is 0.05 to 5" in rig.message.text
    assert rig.handle.value == 1.5 and rig.handle.writes == [1.5]  # back to the value in force


def test_a_refusal_by_apply_is_said_and_the_field_goes_back() -> None:
    rig = Rig(value=1.5)
    rig.handle.receive(4.9)
    assert "I3 = 4.9 refused: not a rigid body" in rig.message.text
    assert rig.applied == [] and rig.handle.value == 1.5 and rig.in_force == 1.5


def test_a_good_value_after_a_refusal_clears_the_message() -> None:
    rig = Rig(value=1.5)
    rig.handle.receive(4.9)
    rig.handle.receive(1.75)
    assert rig.applied == [1.75] and rig.message.text == ""


def test_nothing_is_written_into_a_slider_while_it_is_moved_nor_just_after() -> None:
    rig = Rig()
    for value in (1.1, 1.2, 1.3):
        rig.clock.advance(0.25)  # a slow hand
        rig.handle.receive(value)
        rig.quiet.write(rig.handle, 1.0)  # the server following the motion
    rig.clock.advance(HANDS_OFF_S * 0.9)
    rig.quiet.write(rig.handle, 1.0)
    assert rig.handle.writes == [] and rig.applied == [1.1, 1.2, 1.3] and rig.binding.editing()
    rig.clock.advance(HANDS_OFF_S * 0.2)
    rig.quiet.write(rig.handle, 1.0)
    assert rig.handle.writes == [1.0] and not rig.binding.editing()


def test_a_value_skipped_while_the_user_edits_is_written_once_they_stop_unless_they_sent_a_newer_one() -> None:
    """A preset applied just after a typed value: the server's write is held back while the hand
    is on the field and written by the next frame's `flush` once it is off (before: it was
    dropped, and the box kept the typed value under a simulation that had moved on)."""
    rig = Rig()
    rig.handle.receive(1.25)  # typed
    rig.quiet.write(rig.handle, 0.5)  # a preset, at once
    rig.quiet.flush()
    assert rig.handle.writes == [], "written while the user's hand is on the field"
    rig.clock.advance(HANDS_OFF_S * 1.1)
    rig.quiet.flush()
    assert rig.handle.writes == [0.5] and rig.handle.value == 0.5
    rig.quiet.flush()
    assert rig.handle.writes == [0.5], "an owed value is written once"
    rig.handle.receive(1.5)
    rig.quiet.write(rig.handle, 0.75)  # skipped: the hand is on it ...
    rig.handle.receive(1.6)  # ... and the user sends a newer value
    rig.clock.advance(HANDS_OFF_S * 1.1)
    rig.quiet.flush()
    assert rig.handle.writes == [0.5] and rig.applied[-1] == 1.6, "an owed value older than the user's was written"


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), "abc", "1e", None, [1.0], -5.0, 0.0, 1e9])
def test_not_a_number_or_out_of_range_is_refused(bad: Any) -> None:
    rig = Rig(value=1.5)
    rig.handle.receive(bad)
    assert rig.applied == [] and rig.in_force == 1.5
    assert f"{bad!r} refused" in rig.message.text
    assert rig.handle.value == 1.5


def test_the_servers_own_assignment_applies_at_once_and_does_not_count_as_a_hand() -> None:
    rig = Rig()
    rig.handle.value = 1.25  # handle.value = x on the server: the callback runs with client None
    assert rig.applied == [1.25] and not rig.binding.editing()
    rig.handle.value = 7.0
    assert "refused" in rig.message.text and rig.handle.value == 1.25


def test_a_custom_check_and_a_closed_binding() -> None:
    handle = FakeHandle((0.0, 0.0, 0.0))
    message, applied = Message(), []

    def check(value: Any) -> tuple[float, ...]:
        if len(value) != 3 or any(abs(v) > 3.0 for v in value):
            raise Refused(f"x = {value!r} refused: three numbers within ±3 m.")
        return tuple(value)

    binding = bind(handle, where="x", wrap=lambda _where, fn: fn, message=message, quiet=Quiet(),
                   apply=lambda v: applied.append(v), current=lambda: (0.0, 0.0, 0.0), check=check,
                   clock=ManualClock())
    handle.receive((9.0, 0.0, 0.0))
    assert applied == [] and "within ±3 m" in message.text and handle.value == (0.0, 0.0, 0.0)
    handle.receive((1.0, 2.0, 3.0))
    assert applied == [(1.0, 2.0, 3.0)]
    binding.close()  # the view went away
    handle.receive((1.5, 2.0, 3.0))
    assert applied == [(1.0, 2.0, 3.0)]


def test_a_refusal_is_said_under_its_control_and_goes_when_the_control_takes_a_value() -> None:
    gui = FakeGui()
    rig = Rig(value=1.5, gui=gui)
    (note,) = gui.added
    assert not note.visible and note.order == rig.handle.order + BESIDE_GAP  # right after its control
    rig.handle.receive(1e9)
    assert note.visible and "1000000000.0 refused: the range is 0.05 to 5" in note.content
    assert rig.binding.refusal == note.content and rig.handle.value == 1.5  # the box shows the value in force
    assert "refused" in rig.message.text  # the view's message holds it ...
    assert not rig.message.here  # ... but the page says it once, under the box (the top line stays hidden)
    rig.handle.receive(4.9)  # refused by apply: said there as well
    assert "I3 = 4.9 refused: not a rigid body" in rig.binding.refusal and note.visible
    rig.handle.receive(1.75)  # a value taken: the refusal goes
    assert rig.applied == [1.75] and not note.visible and rig.binding.refusal == ""
    rig.handle.receive(-3.0)
    assert note.visible
    rig.handle.receive(1.75)  # the value in force sent again (an edit that ended on it) is taken too
    assert not note.visible and rig.binding.refusal == ""
    rig.binding.close()
    assert note.removed == 1
    rig.binding.close()
    assert note.removed == 1  # once


def test_a_refusal_whose_words_change_is_said_anew_and_goes_once_it_no_longer_holds() -> None:
    gui = FakeGui()
    handle, message = FakeHandle(0.0), Message()
    recorded = [5.0]  # [s] the end of a recorded stretch, growing

    def words(value: float) -> str | None:
        return None if value <= recorded[0] else f"t = {value:g} s refused: only 0 s to {recorded[0]:g} s recorded"

    def apply(value: float) -> None:
        if words(value) is not None:
            raise Refused(str(words(value)), restate=lambda: words(value))

    binding = bind(handle, where="t", wrap=lambda _where, fn: fn, message=message, quiet=Quiet(), apply=apply,
                   current=lambda: 0.0, check=float, clock=ManualClock(), gui=gui)
    handle.receive(8.0)
    assert binding.refusal.endswith("only 0 s to 5 s recorded**") and message.text.endswith("to 5 s recorded")
    recorded[0] = 6.0
    binding.restate()
    assert binding.refusal.endswith("only 0 s to 6 s recorded**")  # true as it is now, not as it was
    assert message.text.endswith("to 6 s recorded")  # and the message line in the same words
    recorded[0] = 8.5
    binding.restate()
    assert binding.refusal == ""  # 8 s is recorded now: the refusal no longer holds


def test_a_note_sits_in_its_controls_folder_right_under_it(server: Any) -> None:
    gui = server.gui
    with gui.add_folder("Far down") as folder:
        first = gui.add_slider("a", 0.0, 1.0, 0.1, 0.5)
        second = gui.add_slider("b", 0.0, 1.0, 0.1, 0.5)
    binding = bind(first, where="a", wrap=lambda _where, fn: fn, message=Message(), quiet=Quiet(),
                   apply=lambda _value: None, current=lambda: 0.5, spec=SliderSpec("a", "a", 0.0, 1.0, 0.1),
                   gui=gui)  # bound after the folder's block, as the scenes do
    note = binding.note
    assert note is not None
    assert note.handle._impl.parent_container_id == folder._impl.uuid
    assert first.order < note.handle.order < second.order
    with folder:  # bound inside the folder's own block
        third = gui.add_slider("c", 0.0, 1.0, 0.1, 0.5)
        inside = bind(third, where="c", wrap=lambda _where, fn: fn, message=Message(), quiet=Quiet(),
                      apply=lambda _value: None, current=lambda: 0.5, spec=SliderSpec("c", "c", 0.0, 1.0, 0.1),
                      gui=gui)
    assert inside.note is not None and inside.note.handle._impl.parent_container_id == folder._impl.uuid
    binding.close()
    inside.close()
    folder.remove()


def test_a_message_said_elsewhere_is_the_views_message_with_its_line_hidden() -> None:
    line = MessageLine(FakeGui())
    line.show("x = 9 refused: within ±3 m.", here=False)
    assert line.text == "**⚠ x = 9 refused: within ±3 m.**" and not line.handle.visible
    line.show("Run stopped.")
    assert line.handle.visible and line.text == "**⚠ Run stopped.**"
    line.show("t = 999 refused.", lambda: True, here=False)
    assert not line.handle.visible and line.text
    line.recheck()  # stale: it goes
    assert line.text == ""
