"""app.kit.draw.lean: poses at display resolution, arcs in pieces, arrows as turned frames."""

from __future__ import annotations

import math

import numpy as np
import pytest
import viser
from scipy.spatial.transform import Rotation

from app.kit.draw.lean import TOLERANCE, ArcPieces, FrameArrow, Pose, snap, turn_z_onto, world_pose


@pytest.fixture(scope="module")
def scene():  # type: ignore[no-untyped-def]
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    yield server.scene
    server.stop()


@pytest.mark.parametrize("vector", [(0.0, 0.0, 1.0), (1.0, 2.0, -0.5), (0.0, 0.0, -2.0), (1e-3, 0.0, -1.0)])
def test_turn_z_onto_takes_z_to_the_vector(vector: tuple[float, float, float]) -> None:
    R = Rotation.from_quat(turn_z_onto(vector), scalar_first=True).as_matrix()
    np.testing.assert_allclose(R @ [0.0, 0.0, 1.0], np.array(vector) / np.linalg.norm(vector), atol=1e-12)


def test_snapped_pose_is_a_function_of_the_state_and_sent_only_when_it_changed(scene) -> None:  # type: ignore[no-untyped-def]
    a = Pose(scene.add_frame("/lean/a"), reach=2.0)
    b = Pose(scene.add_frame("/lean/b"), reach=2.0)
    angles = np.linspace(0.0, 0.2, 121)  # 0.1 rad/s for 2 s at 60 frames/s: ~0.8 px a frame at reach 2
    for k, angle in enumerate(angles):
        q = (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2))
        a.set(q, exact=False)
        if k % 7 == 0 or k == len(angles) - 1:  # b skips frames: at the same state it draws what a draws
            b.set(q, exact=False)
    assert tuple(a.handle.wxyz) == tuple(b.handle.wxyz)
    assert a.sent < len(angles)  # sub-pixel steps were not sent
    drawn = 2.0 * math.atan2(float(a.handle.wxyz[3]), float(a.handle.wxyz[0]))
    assert abs(drawn - angles[-1]) * a.reach <= TOLERANCE  # within display resolution
    a.set((math.cos(0.1), 0.0, 0.0, math.sin(0.1)), exact=True)
    assert float(a.handle.wxyz[0]) == pytest.approx(math.cos(0.1), abs=1e-7)  # paused: exact


def test_arc_pieces_cover_exactly_zero_to_the_angle(scene) -> None:  # type: ignore[no-untyped-def]
    fixed, moving = scene.add_frame("/lean/fixed"), scene.add_frame("/lean/fixed/moving")
    radius = 1.2
    arc = ArcPieces(scene, fixed.name, moving.name, "arc",
                    lambda t: np.array([radius * math.cos(t), radius * math.sin(t), 0.0]), (200, 0, 100))
    for angle_deg in (-170.0, -45.0, 5.0, 19.0, 20.0, 75.0, 180.0):
        angle = math.radians(angle_deg)
        moving.wxyz = (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2))
        arc.show(angle)
        covered = []  # angles [rad] of every drawn segment end, world
        for node in [*arc.pieces.values(), *arc.tails.values(), arc.short]:
            if node.visible:
                R, p = world_pose(node)
                ends = np.asarray(node.points, dtype=float).reshape(-1, 3) @ R.T + p
                np.testing.assert_allclose(np.linalg.norm(ends, axis=1), radius, rtol=1e-6)
                covered += [math.atan2(y, x) for x, y, _ in ends]
        lo, hi = sorted((0.0, angle))
        slack = 1e-6
        assert min(covered) == pytest.approx(lo, abs=1e-6) or angle_deg == 180.0
        assert max(covered) == pytest.approx(hi, abs=1e-6) or angle_deg in (180.0, -170.0) and max(covered) <= slack
        assert all(lo - slack <= c <= hi + slack for c in covered) or abs(angle_deg) == 180.0


def test_frame_arrow_draws_the_vector_from_its_start(scene) -> None:  # type: ignore[no-untyped-def]
    arrow = FrameArrow(scene, "/lean/arrow", (230, 90, 0), shaft_radius=0.03, head_radius=0.08, head_length=0.16)
    for vector, start in (((0.3, -1.0, 1.5), (0.1, 0.2, 0.3)), ((0.31, -1.02, 1.49), (0.1, 0.2, 0.3))):
        arrow.set(vector, start)
        np.testing.assert_allclose(arrow.world_segment(), [start, np.add(start, vector)], atol=1e-6)
        arrow.set(vector, start, exact=False)  # playing: within display resolution
        np.testing.assert_allclose(arrow.world_segment(), [start, np.add(start, vector)], atol=2 * TOLERANCE)
    assert snap(0.0031, 0.002) == pytest.approx(0.004)
