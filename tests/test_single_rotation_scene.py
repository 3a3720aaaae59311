"""The Euler angles scene's single rotation D = exp(Φ hat(d)) (memo 1.1-1.3): the toggle draws and
hides the axis d and the arc Φ, the readout parses back to SciPy's numbers, Φ = 0 says the axis is
undefined, half turns keep the sign of d while sliders move, the animation turns two outlines
from 1 to D, and the §1 lesson's first step switches it on.

Sessions come from a raw websocket client with the app's loop not running (conftest `manual`):
the tests tick by hand.  References: SciPy's `Rotation` (as_rotvec, as_quat, magnitude).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app.scenes.euler_angles import (
    ANIMATION_HOLD,
    ANIMATION_SECONDS,
    ARC_SEGMENTS,
    SINGLE_ARC_RADIUS,
    arc_reference_axis,
    box_outline_segments,
)
from physics.so3 import exp_so3, rot_x, rot_z

READOUT_TOL = 5.1e-5  # the readout prints 4 decimals
DEG_TOL = 0.0051  # Φ is printed in degrees to 2 decimals
POSE_TOL = 1e-6  # node poses and points are float32 on the wire, float64 here
_NUMBER = r"-?\d+\.\d+"


def _vector(text: str, name: str) -> np.ndarray:
    match = re.search(re.escape(name) + r" = \((" + _NUMBER + r"(?:, " + _NUMBER + r")+)\)", text)
    assert match, (name, text)
    return np.array([float(x) for x in match.group(1).split(", ")])


def parse_single_readout(text: str) -> dict[str, object]:
    """Φ [deg], d (or None), A (3, 3), Φ d and q back from the readout's text."""
    angle = float(re.search(r"Φ = (" + _NUMBER + r")°", text).group(1))  # type: ignore[union-attr]
    axis = None if "d undefined" in text else _vector(text, "**d")
    rows = re.findall(r"\[\s*(" + _NUMBER + r")\s+(" + _NUMBER + r")\s+(" + _NUMBER + r")\s*\]", text)
    assert len(rows) == 3, text
    A = np.array([[float(x) for x in row] for row in rows])
    return {"angle_deg": angle, "axis": axis, "A": A, "rotvec": _vector(text, "Φ d"),
            "wxyz": _vector(text, " ")}  # the line under "q = (cos Φ/2, sin Φ/2 d)"


def drawn_axis(view) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The unit vector the d arrow points along (from its tail at -L d to its head at +L d)."""
    tail, head = np.asarray(view.single_rotation.axis.points, dtype=float)[0]
    return (head - tail) / np.linalg.norm(head - tail)


@pytest.fixture
def view(manual):  # type: ignore[no-untyped-def]
    session = manual.session
    assert session.scene.title == "Euler angles"
    return session.scene


def switch(manual, on: bool) -> None:  # type: ignore[no-untyped-def]
    with manual.session.lock:
        manual.session.scene.single_rotation.gui_toggle.value = on  # runs its callback, as a click does


def test_the_toggle_draws_and_hides_the_axis_and_the_arc(manual, view) -> None:  # type: ignore[no-untyped-def]
    single = view.single_rotation
    assert not single.gui_toggle.value and not single.node.visible
    assert not single.readout.handle.visible
    switch(manual, True)
    assert single.node.visible and single.axis.visible and single.arc.visible
    assert single.readout.handle.visible
    D = view.sim.R_space_body  # the first preset: (30°, 50°, 20°)
    reference = Rotation.from_matrix(D)
    d = reference.as_rotvec() / reference.magnitude()
    np.testing.assert_allclose(drawn_axis(view), d, atol=POSE_TOL)
    # The arc: in the plane ⟂ d at SINGLE_ARC_RADIUS, from u to D u, turning by Φ about d.
    segments = np.asarray(single.arc.points, dtype=float)
    arc = np.concatenate([segments[:ARC_SEGMENTS, 0], segments[ARC_SEGMENTS - 1:ARC_SEGMENTS, 1]])
    np.testing.assert_allclose(arc @ d, 0.0, atol=POSE_TOL)
    np.testing.assert_allclose(np.linalg.norm(arc, axis=1), SINGLE_ARC_RADIUS, atol=POSE_TOL)
    np.testing.assert_allclose(arc[-1], D @ arc[0], atol=POSE_TOL)
    turned = math.atan2(float(np.cross(arc[0], arc[-1]) @ d), float(arc[0] @ arc[-1]))
    assert turned == pytest.approx(reference.magnitude(), abs=1e-6)
    np.testing.assert_allclose(segments[ARC_SEGMENTS:, 0], 0.0)  # two spokes from the origin to the ends
    switch(manual, False)
    assert not single.node.visible and not single.readout.handle.visible
    assert single.animation_time is None and not single.ghost_turn.visible
    assert manual.session.error_count == 0, manual.session.last_error


@pytest.mark.parametrize("angles_deg", [(30.0, 50.0, 20.0), (-120.0, 100.0, 170.0), (0.0, 60.0, 180.0),
                                        (90.0, 180.0, 0.0), (10.0, 1.0, -10.0), (0.0, 0.0, 0.0)])
def test_the_readout_parses_back_to_scipys_numbers(manual, view, angles_deg) -> None:  # type: ignore[no-untyped-def]
    single = view.single_rotation
    switch(manual, True)
    with manual.session.lock:
        view.set_angles_deg(*angles_deg)
    D = Rotation.from_euler("ZXZ", np.radians(angles_deg)).as_matrix()
    reference = Rotation.from_matrix(D)
    shown = parse_single_readout(single.readout.handle.content)
    assert shown["angle_deg"] == pytest.approx(math.degrees(reference.magnitude()), abs=DEG_TOL)
    rotvec = reference.as_rotvec()
    quat = reference.as_quat(canonical=True, scalar_first=True)
    if reference.magnitude() > math.pi - 1e-9:  # a half turn: ±π d are both D (the sign is the app's choice)
        sign = 1.0 if float(shown["rotvec"] @ rotvec) > 0.0 else -1.0  # type: ignore[operator]
        rotvec, quat = sign * rotvec, np.concatenate([[abs(quat[0])], sign * np.sign(quat[0] or 1.0) * quat[1:]])
    np.testing.assert_allclose(shown["rotvec"], rotvec, atol=READOUT_TOL)  # type: ignore[arg-type]
    np.testing.assert_allclose(shown["wxyz"], quat, atol=READOUT_TOL)  # type: ignore[arg-type]
    hat = np.array([[0.0, -rotvec[2], rotvec[1]], [rotvec[2], 0.0, -rotvec[0]], [-rotvec[1], rotvec[0], 0.0]])
    np.testing.assert_allclose(shown["A"], hat, atol=READOUT_TOL)  # type: ignore[arg-type]
    if reference.magnitude() < 1e-9:
        assert shown["axis"] is None and not single.axis.visible and not single.arc.visible
    else:
        np.testing.assert_allclose(shown["axis"], rotvec / reference.magnitude(), atol=READOUT_TOL)  # type: ignore[arg-type]
        np.testing.assert_allclose(drawn_axis(view), rotvec / reference.magnitude(), atol=POSE_TOL)
    assert manual.session.error_count == 0, manual.session.last_error


def test_phi_zero_says_the_axis_is_undefined_and_draws_none(manual, view) -> None:  # type: ignore[no-untyped-def]
    single = view.single_rotation
    switch(manual, True)
    manual.session.apply_preset("D = 1")
    content = single.readout.handle.content
    assert "d undefined" in content and "Φ = 0.00°" in content
    assert single.node.visible and not single.axis.visible and not single.arc_label.visible
    with manual.session.lock:
        view.set_angles_deg(40.0, 0.0, -40.0)  # Rz(40°) Rz(-40°): 1 up to rounding, still no axis
    assert not single.axis.visible and "d undefined" in single.readout.handle.content
    with manual.session.lock:
        view.set_angles_deg(1.0, 0.0, 0.0)  # one degree about z: the axis is back, along +z
    assert single.axis.visible
    np.testing.assert_allclose(drawn_axis(view), [0.0, 0.0, 1.0], atol=POSE_TOL)


def test_sliders_through_half_turns_never_flip_the_drawn_axis(manual, view) -> None:  # type: ignore[no-untyped-def]
    """(φ, θ, 180° − φ) is a half turn for every φ, θ: dragging θ then φ in 1° steps moves d
    continuously (each drawn axis within 1.5° of the last), and the readout names the half turn."""
    single = view.single_rotation
    switch(manual, True)
    manual.session.apply_preset("half turn")
    assert "Φ = 180.00°" in single.readout.handle.content
    assert "Half turn" in single.readout.handle.content
    previous = drawn_axis(view)
    path = [(0.0, float(theta), 180.0) for theta in [*range(60, 181), *range(179, 119, -1)]] + \
        [(float(phi), 120.0, 180.0 - phi) for phi in range(0, 181)]
    for angles in path:
        with manual.session.lock:
            view.set_angles_deg(*angles)
        d = drawn_axis(view)
        assert float(d @ previous) > math.cos(math.radians(1.5)), angles
        previous = d
    assert manual.session.error_count == 0, manual.session.last_error


def test_switching_on_animates_the_single_turn_beside_the_zxz_turn(manual, view) -> None:  # type: ignore[no-untyped-def]
    single = view.single_rotation
    switch(manual, True)
    assert single.animation_time == 0.0 and single.ghost_turn.visible and single.ghost_zxz.visible
    phi, theta, psi = view.sim.angles
    rotvec = Rotation.from_matrix(view.sim.R_space_body).as_rotvec()

    def pose(node) -> np.ndarray:  # type: ignore[no-untyped-def]
        return Rotation.from_quat(np.asarray(node.wxyz), scalar_first=True).as_matrix()

    np.testing.assert_allclose(pose(single.ghost_turn), np.eye(3), atol=POSE_TOL)
    manual.tick(ANIMATION_SECONDS / 2)  # s = 1/2: half of Φ about d; z-x-z in the middle of its θ step
    np.testing.assert_allclose(pose(single.ghost_turn), exp_so3(0.5 * rotvec), atol=1e-6)
    np.testing.assert_allclose(pose(single.ghost_zxz), rot_z(phi) @ rot_x(0.5 * theta), atol=1e-6)
    manual.tick(ANIMATION_SECONDS / 2 + 0.1)  # both end on D and stay there
    for node in (single.ghost_turn, single.ghost_zxz):
        assert node.visible
        np.testing.assert_allclose(pose(node), rot_z(phi) @ rot_x(theta) @ rot_z(psi), atol=1e-6)
    manual.tick(ANIMATION_HOLD)
    assert single.animation_time is None and not single.ghost_turn.visible and not single.ghost_zxz.visible
    with manual.session.lock:
        single.animate()  # the Animate button replays it
    assert single.animation_time == 0.0 and single.ghost_turn.visible
    assert manual.session.error_count == 0, manual.session.last_error


def test_the_animate_button_switches_the_toggle_on(manual, view) -> None:  # type: ignore[no-untyped-def]
    from viser import _messages

    single = view.single_rotation
    manual.client.send(_messages.GuiUpdateMessage(single.gui_animate._impl.uuid, {"value": True}))  # a click
    manual.wait(lambda: single.gui_toggle.value)
    assert single.animation_time is not None and single.axis.visible
    assert manual.session.error_count == 0, manual.session.last_error


def test_the_euler_lessons_first_step_shows_the_single_rotation(manual) -> None:  # type: ignore[no-untyped-def]
    session = manual.session
    with session.lock:
        session.start_lesson("§1 Euler angles and ω")
    single = session.scene.single_rotation
    assert session.lesson_step == 0
    assert single.gui_toggle.value and single.axis.visible and single.animation_time == 0.0
    assert "d = (" in single.readout.handle.content
    # Stepping through the whole lesson, each step's animation done before the next: under a minute.
    seconds = 0.0
    for k in range(1, len(session.lesson.steps)):
        manual.tick(ANIMATION_SECONDS + ANIMATION_HOLD)
        seconds += ANIMATION_SECONDS + ANIMATION_HOLD
        with session.lock:
            session.next_step(1)
        assert session.lesson_step == k
    assert seconds < 60.0 and session.error_count == 0, session.last_error


def test_the_arc_keeps_its_space_axis_near_a_tie() -> None:
    d = np.array([1.0, 1.0, 1.0]) / math.sqrt(3.0)
    assert arc_reference_axis(d) in (0, 1, 2)
    for k in range(3):
        assert arc_reference_axis(d, previous=k) == k  # a tie: whichever was drawn stays
    assert arc_reference_axis(np.array([0.0, 0.0, 1.0]), previous=2) in (0, 1)  # e_z ∥ d: switch
    assert arc_reference_axis(np.array([0.8, 0.6, 0.0])) == 2


def test_box_outline_has_twelve_edges_and_three_axes() -> None:
    segments = box_outline_segments((2.0, 1.0, 0.5), 1.5)
    assert segments.shape == (15, 2, 3)
    lengths = np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1)
    assert sorted(np.round(lengths[:12], 12)) == [0.5] * 4 + [1.0] * 4 + [2.0] * 4
    np.testing.assert_allclose(segments[12:, 1], 1.5 * np.eye(3))
