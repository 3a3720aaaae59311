"""The exact ghost of RigidBodyView (Free body, Heavy top, Poinsot) and the flip marks on the ω plot.

References: SciPy's Rotation (exp/log of the magnified attitude), scipy solve_ivp at rtol 1e-12
(`free_body_reference` of test_app, independent of `physics`) for the exact attitude and for
the flips (sign changes of ω_y′).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from test_app import free_body_reference

from app.kit.draw.widgets import POSE_QUANTUM
from app.kit.rigid.simulation import magnified_attitude

POSE_ATOL = 1e-6  # node poses travel as float quaternions (exact ones after a refresh)


def _pose(handle) -> np.ndarray:  # type: ignore[no-untyped-def]
    return Rotation.from_quat(np.asarray(handle.wxyz), scalar_first=True).as_matrix()


def test_magnified_attitude_is_the_exact_one_at_k0_the_body_at_k1_and_scales_the_error() -> None:
    rng = np.random.default_rng(7)
    for _ in range(20):
        R_exact = Rotation.random(random_state=rng).as_matrix()
        error = rng.normal(size=3) * 1e-3
        R = R_exact @ Rotation.from_rotvec(error).as_matrix()  # body-frame error
        np.testing.assert_allclose(magnified_attitude(R_exact, R, 0.0), R_exact, atol=1e-15)
        np.testing.assert_allclose(magnified_attitude(R_exact, R, 1.0), R, atol=1e-14)
        ghost = magnified_attitude(R_exact, R, 1e3)
        np.testing.assert_allclose(Rotation.from_matrix(R_exact.T @ ghost).as_rotvec(), 1e3 * error, rtol=1e-9)
    with pytest.raises(ValueError, match="finite and >= 0"):
        magnified_attitude(np.eye(3), np.eye(3), -1.0)


def test_the_ghost_costs_nothing_when_off(manual, monkeypatch) -> None:
    session = manual.session
    session.select_scene("Free body")
    view = session.scene
    assert view.ghost.body is None and not view.ghost.gui_toggle.value  # off by default, not even built
    sent: list[str] = []
    api = session.client.scene
    original = api._queue_scene_message
    monkeypatch.setattr(api, "_queue_scene_message", lambda m: (sent.append(getattr(m, "name", "")), original(m))[1])
    session.play()
    manual.tick(0.5)
    assert view.ghost.body is None and not any("ghost" in name for name in sent)
    view.ghost.set(True)
    view.ghost.set(False)  # built once; hidden, it is neither evaluated nor sent
    sent.clear()
    calls: list[int] = []
    monkeypatch.setattr(view.ghost.body, "pose", lambda _R: calls.append(1))
    manual.tick(0.5)
    assert not any("ghost" in name for name in sent) and calls == []
    assert not view.ghost.gui_note.visible


@pytest.mark.parametrize("scene", ["Free body", "Poinsot"])
def test_the_ghost_follows_the_exact_solution_at_k0_and_the_solid_body_at_k1(manual, scene: str) -> None:
    session = manual.session
    session.select_scene(scene)
    session.apply_preset("Dzhanibekov")
    view = session.scene
    sim = view.sim
    R0, w0, I = sim.initial_state.R_space_body, sim.initial_state.omega_body, sim.model.inertia
    manual.client.set_value(view.ghost.gui_toggle, True)  # from a browser
    manual.wait(lambda: view.ghost.body is not None and view.ghost.body.node.visible)
    session.play()
    manual.tick(2.0)
    R_reference, _ = free_body_reference(I, R0, w0, sim.t)
    # While playing, a frame sends poses at display resolution (quaternions in multiples of POSE_QUANTUM) ...
    np.testing.assert_allclose(_pose(view.ghost.body.node), R_reference, atol=4 * POSE_QUANTUM)
    error = sim.attitude_error()
    session.pause()  # a refresh: the note (5 Hz while playing) shows the current error
    # ... a refresh (here the pause) exactly.
    np.testing.assert_allclose(_pose(view.ghost.body.node), R_reference, atol=POSE_ATOL)
    assert 0.0 < error < 1e-5  # splitting4 at 1/60 s: a small, non-zero error
    assert f"{error:.2e} rad" in view.ghost.gui_note.content and "k = 0" in view.ghost.gui_note.content
    view.ghost.set_k(1.0)
    np.testing.assert_allclose(_pose(view.ghost.body.node), _pose(view.body.node), atol=POSE_ATOL)
    np.testing.assert_allclose(_pose(view.ghost.body.node), sim.state.R_space_body, atol=POSE_ATOL)
    view.ghost.set_k(1e6)  # the drift made visible: the ghost is 1e6 times the error away
    shown = Rotation.from_matrix(R_reference.T @ _pose(view.ghost.body.node)).magnitude()
    assert shown == pytest.approx(math.remainder(1e6 * error, 2 * math.pi) % (2 * math.pi) if 1e6 * error > math.pi
                                  else 1e6 * error, rel=1e-3)
    assert "10⁶" in view.ghost.gui_k.value
    session.select_scene("Heavy top")  # the top has a closed form too: its ghost works the same way
    top = session.scene
    top.ghost.set(True)
    session.play()
    manual.tick(1.0)
    session.pause()
    R_exact = top.sim.exact()(np.array([top.sim.t]))[0][0]
    np.testing.assert_allclose(_pose(top.ghost.body.node), R_exact, atol=POSE_ATOL)
    top.set_integrator("exact")
    assert top.sim.attitude_error() == 0.0
    assert session.error_count == 0, session.last_error


def test_a_bad_magnification_from_a_browser_is_refused(manual) -> None:
    session = manual.session
    session.select_scene("Free body")
    view = session.scene
    view.ghost.set(True)
    manual.client.set_value(view.ghost.gui_k, "10⁹")
    manual.wait(lambda: "refused" in view.message.text)
    assert view.ghost.k == 0.0 and view.ghost.gui_k.value == "0 (exact)"


def test_flips_are_marked_on_the_omega_plot_where_the_solution_changes_sign(manual) -> None:
    session = manual.session
    session.select_scene("Free body")
    session.apply_preset("Dzhanibekov")
    view = session.scene
    sim = view.sim
    R0, w0, I = sim.initial_state.R_space_body, sim.initial_state.omega_body, sim.model.inertia
    session.play()
    manual.tick(9.0)  # two flips (~2.3 s and ~6.2 s)
    view.tabs.show("Plots")
    chart = view.plots.handles[view.plots._flip_chart]
    assert chart.series[-1]["label"] == "flip (exact)"
    x, *columns, marks = (np.asarray(c) for c in chart.data)
    assert len(columns) == 3 and np.all(np.diff(x) >= 0.0)
    at = x[np.abs(marks) > 0.0]
    flip_times = np.unique(at)
    assert len(flip_times) == 2 and np.all(np.isin(np.round(at, 12), np.round(flip_times, 12)))
    for t in flip_times:  # ω_y′ of an independent solution changes sign there
        before = free_body_reference(I, R0, w0, t - 1e-6)[1][1]
        after = free_body_reference(I, R0, w0, t + 1e-6)[1][1]
        assert before * after < 0.0, t
    # No flips for a symmetric body: the series is the zero line.
    session.apply_preset("Disc")
    manual.tick(3.0)
    view._push_plots()
    assert not np.any(np.asarray(chart.data[-1]))
