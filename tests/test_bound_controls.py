"""Every scene's bound controls, through a raw websocket client against the real app: a refused
value leaves the simulation unchanged, the message line says why, and the control shows the
value in force again (app.kit.panel.binding: a browser's update applies when it arrives)."""

from __future__ import annotations

import copy
import re
from typing import Any

import numpy as np
import pytest


def snapshot(sim: Any) -> Any:
    """What a refused edit must leave unchanged, for every kind of simulation."""
    keys = ("model", "angles_deg", "rates_deg", "moments", "setup", "masses", "positions", "about", "mesh_mass",
            "preset", "restarts")
    state = getattr(sim, "state", None)
    parts = {key: copy.deepcopy(getattr(sim, key)) for key in keys if hasattr(sim, key)}
    if state is not None and hasattr(state, "R_space_body"):
        parts["R"] = state.R_space_body.copy()
        parts["omega"] = state.omega_body.copy()
    return parts


def assert_same(a: dict[str, Any], b: dict[str, Any]) -> None:
    assert a.keys() == b.keys()
    for key in a:
        if isinstance(a[key], np.ndarray) or isinstance(b[key], np.ndarray):
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
        else:
            assert a[key] == b[key], key


# (scene, control (view -> handle), refused value, what the message says)
CASES = [
    ("Euler angles", lambda v: v.gui_angles[1], 500.0, "θ [deg] = 500.0 refused: the range is 0 to 180"),
    ("Euler angles", lambda v: v.gui_rates[0], float("nan"), "nan refused"),
    ("Euler angles", lambda v: v.gui_moments[2], 4.9, "I3 = 4.9 refused: not a rigid body"),
    ("Euler angles", lambda v: v.transport.gui_time_scale, 100.0, "Time scale 100.0 refused"),
    ("Free body", lambda v: v.gui_params[2], 4.9, "Not a rigid body"),
    ("Free body", lambda v: v.gui_angles[0], 1e6, "1000000.0 refused: the range is -180 to 180"),
    ("Free body", lambda v: v.gui_rates[1], -1e3, "-1000.0 refused"),
    ("Heavy top", lambda v: v.gui_params[1], 4.9, "Not a rigid body"),
    ("Heavy top", lambda v: v.gui_params[2], -1.0, "-1.0 refused: the range is 0 to 30"),
    ("Poinsot", lambda v: v.gui_energy, 7.0, "refused"),
    ("Moving frame", lambda v: v.gui_params[v._param_keys.index("k")], 1e6, "1000000.0 refused"),
    ("Moving frame", lambda v: v.gui_angles[1], -5.0, "-5.0 refused"),
    ("Inertia", lambda v: v.gui_mass, -5.0, "m [kg] = -5.0 refused: the range is 0.1 to 10"),
    ("Inertia", lambda v: v.gui_mass, 0.0, "m [kg] = 0.0 refused"),
    ("Inertia", lambda v: v.gui_mass, 1e9, "m [kg] = 1000000000.0 refused"),
    ("Inertia", lambda v: v.gui_position, (99.0, 0.0, 0.0), "x = (99.0, 0.0, 0.0) refused: three numbers within"),
    ("Inertia", lambda v: v.gui_about, (0.0, float("nan"), 0.0), "O = (0.0, nan, 0.0) refused"),
    ("Inertia", lambda v: v.mesh_panel.gui_amount, -1.0, "Refused: mass -1.0 kg: a number from 0.001 to 10000 wanted"),
]


@pytest.mark.parametrize(("scene", "control", "bad", "said"), CASES,
                         ids=[f"{c[0]}-{k}" for k, c in enumerate(CASES)])
def test_a_refused_value_changes_nothing_says_why_and_the_control_goes_back(manual, scene: str, control: Any,
                                                                              bad: Any, said: str) -> None:
    session = manual.session
    session.select_scene(scene)
    view = session.scene
    handle = control(view)
    shown = handle.value
    before = snapshot(view.sim)
    manual.client.set_value(handle, bad)
    manual.wait(lambda: said in view.message.text)
    assert_same(snapshot(view.sim), before)
    assert handle.value == pytest.approx(shown, abs=1e-9)  # the value in force, not the refused one
    note = binding_of(view, handle).note
    assert note is not None and said in note.text  # said right under the control too
    assert note.handle in view.gui_roots  # (folded with the panel on a phone)
    assert session.last_error is None


def test_letters_sent_for_a_mass_change_nothing(manual) -> None:
    """viser 1.1.1 casts a slider's incoming value with float() before any callback: "abc" never
    reaches the app (the binding refuses strings that do: tests/test_binding.py), "2" does."""
    session = manual.session
    session.select_scene("Inertia")
    view = session.scene
    masses = view.sim.masses.copy()
    manual.client.set_value(view.gui_mass, "abc")
    manual.client.set_value(view.gui_position, ("a", "b", "c"))
    masses[view.selected] = 2.0
    manual.client.set_value(view.gui_mass, "2")
    manual.wait(lambda: view.sim.masses[view.selected] == 2.0)
    np.testing.assert_array_equal(view.sim.masses, masses)
    assert session.last_error is None


def binding_of(view: Any, handle: Any) -> Any:
    """The view's binding of `handle` (the transport's time scale's included)."""
    (binding,) = (b for b in view._all_bindings() if b.handle is handle)
    return binding


def test_a_good_value_after_a_refusal_applies_and_clears_the_message(manual) -> None:
    session = manual.session
    session.select_scene("Inertia")
    view = session.scene
    manual.client.set_value(view.gui_mass, 1e9)
    manual.wait(lambda: "refused" in view.message.text)
    assert "refused" in binding_of(view, view.gui_mass).refusal
    manual.client.set_value(view.gui_mass, 2.5)
    manual.wait(lambda: view.sim.masses[view.selected] == 2.5)
    assert view.message.text == "" and view.gui_mass.value == 2.5
    assert binding_of(view, view.gui_mass).refusal == ""  # the refusal under the box is gone too


def test_a_views_refusal_notes_leave_the_panel_with_it(manual) -> None:
    session = manual.session
    view = session.scene  # Euler angles
    notes = [b.note for b in view._all_bindings()]
    assert notes and all(note is not None and not note.handle._impl.removed for note in notes)
    session.select_scene("Free body")
    assert all(note.handle._impl.removed for note in notes)
    assert session.last_error is None


def test_every_bound_slider_in_every_scene_applies_a_browser_value_when_it_arrives(manual, monkeypatch) -> None:
    """Time stands still (a ManualClock nobody moves): a binding that waited for a pause, or for
    a next value, would never apply.  Each slider of each scene gets one value a step away from
    the one it shows, from the raw client, and must take it at once (or refuse it, said)."""
    import viser

    from app.kit.panel.binding import ManualClock
    from app.kit.view import SceneView
    from app.scenes import SCENES

    monkeypatch.setattr(SceneView, "clock", ManualClock())
    session = manual.session
    tried = 0
    for title in [*list(SCENES)[1:], list(SCENES)[0]]:  # the first scene last: its view made after the patch
        session.select_scene(title)
        view = session.scene
        bindings = list(view._bindings)
        if view.transport is not None:
            bindings.append(view.transport.time_scale_binding)
        for binding in bindings:
            handle = binding.handle
            if not isinstance(handle, viser.GuiSliderHandle) or not handle.visible \
                    or view.timeline is not None and binding is view.timeline.binding:
                continue
            shown = float(handle.value)
            step = float(handle.step)
            value = shown + step if shown + step <= handle.max else shown - step
            refused = binding.refused
            decided = binding.applied + refused
            manual.client.set_value(handle, value)
            manual.wait(lambda b=binding, d=decided: b.applied + b.refused > d)
            assert binding.applied + binding.refused == decided + 1, (title, binding.where)
            if binding.refused == refused:
                assert handle.value == pytest.approx(value), (title, binding.where)
            tried += 1
    assert tried >= 20 and session.last_error is None


@pytest.mark.parametrize("playing", [True, False], ids=["playing", "paused"])
def test_a_time_typed_outside_the_timeline_is_refused_the_same_while_playing_or_paused(manual,
                                                                                     playing: bool) -> None:
    """One rule for the Timeline's box: 999 s is refused with the recorded stretch, said under the
    slider, the slider back at the time shown at once and the motion as it was; while it plays the
    refusal stays, in the stretch's words as they are now; a time taken lets it go."""
    from app.kit.core.room import LIVE, SCRUBBING
    from app.kit.panel.timeline import LIVE_FOLLOW_PERIOD

    session = manual.session  # Euler angles
    view, room = session.scene, session.room
    timeline = view.timeline
    assert timeline is not None
    session.play()
    manual.tick(2.0)
    if not playing:
        session.pause()
    slider, binding = timeline.gui_slider, timeline.binding
    manual.client.set_value(slider, 999.0)
    manual.wait(lambda: binding.refusal != "", timeout=10.0)
    said = re.search(r"Time 999\.0 s refused: only 0\.00 s to (\d+\.\d\d) s is recorded", binding.refusal)
    assert said is not None, binding.refusal
    assert slider.value == pytest.approx(timeline._shown_value(), abs=1e-9) and slider.value < 999.0
    assert room.playing == playing and room.mode == LIVE
    manual.tick(2.0)
    stretch = room.stretch()
    assert stretch is not None
    now = re.search(r"Time 999\.0 s refused: only 0\.00 s to (\d+\.\d\d) s is recorded", binding.refusal)
    assert now is not None, binding.refusal  # still said ...
    assert stretch[1] - LIVE_FOLLOW_PERIOD - 0.01 <= float(now[1]) <= stretch[1] + 0.01  # ... and true now
    assert (float(now[1]) > float(said[1]) + 0.5) == playing and room.playing == playing
    manual.client.set_value(slider, 1.0)
    manual.wait(lambda: binding.refusal == "", timeout=10.0)
    assert room.mode == SCRUBBING and room.shown_t == pytest.approx(1.0)
    assert session.last_error is None
