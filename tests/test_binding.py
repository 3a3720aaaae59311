"""app.kit.binding on the server, no browser: a fake handle, a ManualClock, updates counted.

The browser sends a box's value once per keystroke unless guarded (measured: `-0.8` arrives as
0 then 0.8, `1e9` as 1 then 19); these tests feed such streams to a binding and check what is
applied, refused and written back.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import pytest

from app.kit.binding import DRAG_S, SETTLE_S, ManualClock, Refused, bind
from app.kit.common import SliderSpec
from app.kit.gui import Quiet

SPEC = SliderSpec("I3", "I3 [kg m²]", 0.05, 5.0, 0.01)
ANGLE = SliderSpec("phi", "φ [deg]", -180.0, 180.0, 1.0)
BROWSER = SimpleNamespace(client=object())  # an event from a browser (the server's own has client None)
SERVER = SimpleNamespace(client=None)


class FakeHandle:
    """A viser handle as the binding sees it: `value`, `precision`, `on_update`; counts writes."""

    def __init__(self, value: Any) -> None:
        self._value = value
        self.precision = 0
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

    def show(self, text: str) -> None:
        self.text = text

    def clear(self) -> None:
        self.text = ""


class Rig:
    """A handle bound to `self.in_force`; `apply` refuses a sum of moments breaking I1 + I2 >= I3."""

    def __init__(self, value: float = 1.0, spec: SliderSpec = SPEC) -> None:
        self.clock = ManualClock()
        self.handle = FakeHandle(value)
        self.message = Message()
        self.quiet = Quiet()
        self.in_force = value
        self.applied: list[float] = []
        self.binding = bind(self.handle, where="I3 slider", wrap=lambda _where, fn: fn, message=self.message,
                            quiet=self.quiet, apply=self.apply, current=lambda: self.in_force, spec=spec,
                            clock=self.clock)

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


def test_a_keystroke_burst_applies_only_the_complete_value() -> None:
    for gap in (0.05, 0.15, 0.3):  # typed fast (one throttled send per 50 ms) or slowly
        rig = Rig(spec=ANGLE)
        rig.stream([-0.0, -0.8], gap)
        rig.clock.advance(SETTLE_S)
        assert rig.applied == [-0.8], gap
        assert rig.handle.writes == []  # nothing written into the field the user typed in
        assert math.copysign(1.0, rig.in_force) == -1.0 and rig.handle.value == -0.8


def test_a_refused_completion_applies_nothing_and_puts_the_value_in_force_back() -> None:
    for gap in (0.05, 0.3):
        rig = Rig(value=1.5)
        rig.stream([1.0, 1e9], gap)  # "1e9" typed: 1, then 1e9
        rig.clock.advance(SETTLE_S)
        assert rig.applied == [] and rig.in_force == 1.5, gap
        assert "1000000000.0 refused: the range is 0.05 to 5" in rig.message.text
        assert rig.handle.value == 1.5 and rig.handle.writes == [1.5]  # back to the value in force, not to 1


def test_a_refusal_by_apply_is_said_and_the_field_goes_back() -> None:
    rig = Rig(value=1.5)
    rig.handle.receive(4.9)
    assert rig.applied == [] and rig.binding.held == (4.9,)  # held: not yet decided
    rig.clock.advance(SETTLE_S)
    assert "I3 = 4.9 refused: not a rigid body" in rig.message.text
    assert rig.handle.value == 1.5 and rig.in_force == 1.5


def test_a_drag_stream_applies_each_value_as_it_comes() -> None:
    rig = Rig()
    values = [1.0 + 0.01 * k for k in range(1, 21)]
    rig.handle.receive(values[0])
    for k, value in enumerate(values[1:], start=1):
        rig.clock.advance(0.05)  # the browser's cadence while the thumb moves
        rig.handle.receive(value)
        assert rig.applied[-1] == value and len(rig.applied) == k  # live: applied at once
    rig.clock.advance(SETTLE_S)
    assert rig.applied == values[1:]  # the first was superseded within the drag, never applied
    assert rig.clock.pending == 0


def test_a_lone_update_applies_after_the_pause_and_not_before() -> None:
    rig = Rig()
    rig.handle.receive(1.7)
    rig.clock.advance(SETTLE_S * 0.9)
    assert rig.applied == []
    rig.clock.advance(SETTLE_S * 0.2)
    assert rig.applied == [1.7] and rig.message.text == ""


def test_nothing_is_written_into_the_field_while_an_edit_is_held() -> None:
    rig = Rig()
    rig.handle.receive(1.2)
    rig.quiet.write(rig.handle, 1.0)  # the server following the motion
    assert rig.handle.writes == [] and rig.binding.editing()
    rig.clock.advance(SETTLE_S)
    assert rig.applied == [1.2] and not rig.binding.editing()
    rig.quiet.write(rig.handle, 1.0)
    assert rig.handle.writes == [1.0]


def test_nothing_is_written_into_a_slider_while_it_is_dragged_nor_in_the_pause_after() -> None:
    rig = Rig()
    rig.stream([1.1, 1.2, 1.3], 0.05)
    rig.quiet.write(rig.handle, 1.0)
    rig.clock.advance(SETTLE_S * 0.9)
    rig.quiet.write(rig.handle, 1.0)
    assert rig.handle.writes == [] and rig.applied == [1.2, 1.3]
    rig.clock.advance(SETTLE_S * 0.2)
    rig.quiet.write(rig.handle, 1.0)
    assert rig.handle.writes == [1.0]


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), "abc", "1e", None, [1.0], -5.0, 0.0, 1e9])
def test_not_a_number_or_out_of_range_is_refused(bad: Any) -> None:
    rig = Rig(value=1.5)
    rig.handle.receive(bad)
    rig.clock.advance(SETTLE_S)
    assert rig.applied == [] and rig.in_force == 1.5
    assert f"{bad!r} refused" in rig.message.text
    assert rig.handle.value == 1.5


def test_the_servers_own_assignment_applies_at_once() -> None:
    rig = Rig()
    rig.handle.value = 1.25  # handle.value = x on the server: the callback runs with client None
    assert rig.applied == [1.25] and rig.clock.pending == 0
    rig.handle.value = 7.0
    assert "refused" in rig.message.text and rig.handle.value == 1.25


def test_a_custom_check_and_a_closed_binding() -> None:
    clock = ManualClock()
    handle = FakeHandle((0.0, 0.0, 0.0))
    message, applied = Message(), []

    def check(value: Any) -> tuple[float, ...]:
        if len(value) != 3 or any(abs(v) > 3.0 for v in value):
            raise Refused(f"x = {value!r} refused: three numbers within ±3 m.")
        return tuple(value)

    binding = bind(handle, where="x", wrap=lambda _where, fn: fn, message=message, quiet=Quiet(),
                   apply=lambda v: applied.append(v), current=lambda: (0.0, 0.0, 0.0), check=check, clock=clock)
    handle.receive((9.0, 0.0, 0.0))
    clock.advance(SETTLE_S)
    assert applied == [] and "within ±3 m" in message.text and handle.value == (0.0, 0.0, 0.0)
    handle.receive((1.0, 2.0, 3.0))
    binding.close()  # the view went away before the pause ended
    clock.advance(SETTLE_S)
    assert applied == []


def test_drag_window_is_shorter_than_the_pause() -> None:
    assert 0.05 < DRAG_S < SETTLE_S <= 0.4
