"""Setting the motion by hand (app.kit.rigid.hand) and the heavy top's Energy tab (app.kit.rigid.energy_plot),
driven as a browser would (a raw websocket client sending gizmo drags and GUI updates).

References: ω from a gizmo position by the definition ω_s = p / scale, ω_b = Rᵀ ω_s (L: I⁻¹ Rᵀ L_s),
written here; a kick's Δω_b = J / I_k by hand; the Energy tab's marks against
`physics.top_energy.energy_picture` (itself tested in test_top_energy) and the presets' names.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from viser import _messages

from app.kit.rigid.energy_plot import energy_plot_data
from app.kit.rigid.hand import KICK_SPEC
from physics.top_energy import CUSP, LOOP, SLEEPING, STEADY, THROUGH_VERTICAL, TOO_SLOW, WAVE

OMEGA_RTOL = 1e-12  # ω from a gizmo position: a few roundings


def _drag(manual, view, kind: str, position) -> None:  # type: ignore[no-untyped-def]
    """A browser's drag of the gizmo `kind` to `position` (start, update, end)."""
    name = f"{view.root}/hand/{kind}"
    owner = str(manual.session.client_id)
    manual.client.send(_messages.TransformControlsDragStartMessage(name, owner=owner))
    manual.client.send(_messages.TransformControlsUpdateMessage(name, (1.0, 0.0, 0.0, 0.0), tuple(position),
                                                                owner=owner))
    manual.wait(lambda: view.hand.dragging == kind and view.sim.preset is None)


def _end_drag(manual, view, kind: str) -> None:  # type: ignore[no-untyped-def]
    owner = str(manual.session.client_id)
    manual.client.send(_messages.TransformControlsDragEndMessage(f"{view.root}/hand/{kind}", owner=owner))
    manual.wait(lambda: view.hand.dragging is None)


@pytest.mark.parametrize(("scene", "kind"), [("Heavy top", "omega"), ("Free body", "omega"), ("Free body", "L")])
def test_dragging_a_gizmo_sets_omega_from_the_current_attitude(manual, scene: str, kind: str) -> None:
    session = manual.session
    session.select_scene(scene)
    view = session.scene
    sim = view.sim
    session.play()
    manual.tick(0.3)
    session.pause()
    gizmo = view.hand.gizmos[kind]
    assert gizmo.visible and gizmo not in manual.app.server.scene._handle_from_transform_controls_name.values()
    np.testing.assert_allclose(gizmo.position, view.hand.tip(kind), atol=1e-6)
    R = sim.state.R_space_body.copy()
    scale = view.omega_scale if kind == "omega" else view.L_scale
    target = np.asarray(gizmo.position) + np.array([0.05, -0.04, 0.03])
    _drag(manual, view, kind, target)
    expected = R.T @ target / scale
    if kind == "L":
        expected = expected / np.asarray(sim.model.inertia)
    np.testing.assert_allclose(sim.state.omega_body, expected, rtol=OMEGA_RTOL)
    np.testing.assert_allclose(sim.state.R_space_body, R, atol=0.0)  # the attitude is kept
    assert sim.t == 0.0 and not session.room.playing
    rates = view.rates_from_state(sim.angles, sim.state)  # the sliders follow
    for handle, spec, rate in zip(view.gui_rates, view.rate_specs, rates):
        assert float(handle.value) == pytest.approx(spec.rounded(rate), abs=spec.step)
    _end_drag(manual, view, kind)
    np.testing.assert_allclose(gizmo.position, view.hand.tip(kind), atol=1e-6)  # back on the tip


def test_a_gizmo_drag_out_of_range_or_to_nan_is_refused(manual) -> None:
    session = manual.session
    session.select_scene("Free body")
    view = session.scene
    before = view.sim.state.omega_body.copy()
    restarts = view.sim.restarts
    view.hand._drag_start("omega")
    view.hand.gizmos["omega"].position = (1e3, 0.0, 0.0)  # |ω| ≫ 10 rad/s, the sliders' range
    view.hand._dragged("omega")
    assert "refused" in view.message.text and "outside its range" in view.message.text
    view.hand.gizmos["omega"].position = (math.nan, 0.0, 0.0)
    view.hand._dragged("omega")
    assert "not finite" in view.message.text
    np.testing.assert_array_equal(view.sim.state.omega_body, before)
    assert view.sim.restarts == restarts
    view.hand._drag_end()


def test_gizmos_hide_while_playing_and_only_live_in_the_controlling_browser(manual) -> None:
    session = manual.session
    session.select_scene("Heavy top")
    view = session.scene
    gizmo = view.hand.gizmos["omega"]
    assert gizmo.visible
    session.play()
    assert not gizmo.visible
    session.pause()
    manual.client.set_value(view.hand.gui_show, False)
    manual.wait(lambda: not gizmo.visible)
    assert set(view.hand.gizmos) == {"omega"}
    assert not manual.app.server.scene._handle_from_transform_controls_name  # none in the shared scene


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_a_kick_adds_J_over_I_about_a_body_axis_while_playing(manual, axis: int) -> None:
    session = manual.session
    session.select_scene("Free body")
    view = session.scene
    sim = view.sim
    session.play()
    manual.tick(0.2)
    omega, R = sim.state.omega_body.copy(), sim.state.R_space_body.copy()
    manual.client.send(_messages.GuiUpdateMessage(view.hand.gui_kick._impl.uuid, {"value": "x′ y′ z′".split()[axis]}))
    manual.wait(lambda: sim.t == 0.0)
    expected = omega.copy()
    expected[axis] += view.hand.impulse / sim.model.inertia[axis]
    np.testing.assert_allclose(sim.state.omega_body, expected, rtol=1e-15)
    np.testing.assert_array_equal(sim.state.R_space_body, R)
    assert session.room.playing  # a kick does not stop the motion
    manual.tick(0.1)
    assert sim.t > 0.0


def test_bad_kicks_are_refused_and_change_nothing(manual) -> None:
    session = manual.session
    session.select_scene("Heavy top")
    view = session.scene
    sim = view.sim
    before = sim.state.omega_body.copy()
    assert not view.hand.kick("x′", math.nan)
    assert "refused" in view.message.text
    assert not view.hand.kick("x′", KICK_SPEC.hi * 2)
    assert not view.hand.kick("w′", 0.1)
    assert "the axes are" in view.message.text
    np.testing.assert_array_equal(sim.state.omega_body, before)
    assert view.hand.kick("z′", KICK_SPEC.hi) and view.hand.kick("z′", KICK_SPEC.hi)  # ω_z′ 12 → 22 → 32 rad/s
    kicked = sim.state.omega_body.copy()
    assert not view.hand.kick("z′", KICK_SPEC.hi)  # 42 rad/s: beyond the spin slider's 40
    assert "outside its range" in view.message.text
    np.testing.assert_array_equal(sim.state.omega_body, kicked)
    manual.client.set_value(view.hand.gui_impulse, math.nan)  # the slider, from a browser
    manual.wait(lambda: "refused" in view.message.text)
    assert view.hand.impulse == 0.5


# ---------------------------------------------------------------------------- the Energy tab
PRESET_CLASSES = {"Steady": STEADY, "Wave": WAVE, "Loop": LOOP, "Cusp": CUSP, "Sleeping": SLEEPING,
                  "Too slow": TOO_SLOW, "Through the vertical": THROUGH_VERTICAL}


def test_the_energy_tab_names_each_presets_motion_and_marks_its_turning_points(manual) -> None:
    session = manual.session
    session.select_scene("Heavy top")
    view = session.scene
    view.show_tab("Energy")
    for name, motion in PRESET_CLASSES.items():
        session.apply_preset(name)
        picture = view.energy_plot.picture
        assert picture is not None and picture.motion == motion
        assert f"Motion: {motion}." in view.energy_plot.gui_motion.content
        x, U, E, turning, now = (np.asarray(column) for column in view.energy_plot.handle.data)
        assert np.all(np.diff(x) >= 0.0)
        y_hi = view.energy_plot.window[3]
        spikes = x[turning > y_hi]
        assert spikes.size == 2
        np.testing.assert_allclose(spikes, np.degrees([picture.theta_1, picture.theta_2]), atol=1e-12)
        np.testing.assert_allclose(np.unique(x[now > y_hi]), math.degrees(view.sim.angles[1]), atol=1e-9)
        assert np.all(E == picture.energy) and np.all(np.isfinite(U))


def test_the_energy_picture_follows_the_sliders_and_costs_nothing_on_another_tab(manual) -> None:
    session = manual.session
    session.select_scene("Heavy top")
    view = session.scene
    session.apply_preset("Wave")
    view.show_tab("Energy")
    assert view.energy_plot.picture.motion == WAVE
    phi_dot = view.gui_rates[1]
    manual.client.set_value(phi_dot, -31.5)  # dφ/dt against the precession: loops
    manual.wait(lambda: view.energy_plot.picture.motion == LOOP, timeout=10.0)
    view.show_tab("Setup")
    sends = view.energy_plot.sends
    session.play()
    manual.tick(1.0)
    assert view.energy_plot.sends == sends


def test_energy_plot_data_puts_the_marks_where_the_picture_says() -> None:
    from scipy.spatial.transform import Rotation

    from physics.top_energy import energy_picture

    R = Rotation.from_euler("ZXZ", [0.0, math.radians(60.0), 0.0]).as_matrix()
    picture = energy_picture(1.0, 0.5, 6.0, R, np.array([0.0, 0.0, 12.0]))  # released at rest: a cusp
    data = energy_plot_data(picture, math.radians(70.0), (0.0, 180.0, 38.0, 40.0))
    x, U, _, turning, now = data
    assert picture.motion == CUSP
    assert sorted(set(x[turning > 40.0])) == pytest.approx(np.degrees([picture.theta_1, picture.theta_2]))
    assert sorted(set(x[now > 40.0])) == pytest.approx([70.0])
    assert U.max() <= 42.0 and np.all(np.isfinite(U))  # the barriers at the poles are cut off
