"""The gallery of a State question (app.ask.gallery) without a browser: one batched node for
every body, the chosen one walked with Next/Previous, an answer played in a room bit for bit;
the box glyph's edges against the closed form of a box's moments, m (b² + c²) / 12."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import viser
from scipy.spatial.transform import Rotation

from app.ask.gallery import (
    ALL_OPACITY,
    CHOSEN_COLOR,
    CHOSEN_OPACITY,
    ONE,
    Gallery,
    GalleryEntry,
    box_extents,
    play_answer,
)
from app.ask.judges import AnswerState, judge_answer
from app.kit.core.room import Room
from app.scenes.free_body import FreeBodyView
from app.scenes.heavy_top import HeavyTopView


@pytest.fixture(scope="module")
def server():
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    yield srv
    srv.stop()


def _tops(n: int) -> list[GalleryEntry]:
    R = Rotation.random(n, random_state=5).as_matrix()
    entries = []
    for k in range(n):
        answer = AnswerState("Heavy top", R[k], np.array([0.1 * k, 0.0, 12.0]), (1.0, 1.0, 0.5), 6.0)
        judged = judge_answer("top_motion", answer, None)
        entries.append(GalleryEntry(k + 1, answer, judged.value, judged.words))
    return entries


def test_forty_bodies_are_one_node_and_one_is_walked(server) -> None:
    clock = [0.0]
    gallery = Gallery(server.scene, root="/test_gallery", clock=lambda: clock[0])
    entries = _tops(40)
    gallery.set_entries(entries[:39])
    node = gallery._node  # made with the gallery, hidden
    assert not node.visible and gallery.sends == 0
    gallery.tick()
    gallery.set_entries([dataclasses.replace(e) for e in entries[:39]])  # equal copies: nothing to redraw
    assert not gallery._dirty
    gallery.set_entries(entries)  # within the redraw period: not sent yet
    gallery.tick()
    assert gallery.sends == 1 and len(node.batched_wxyzs) == 39 and node.visible
    clock[0] = 1.0
    gallery.tick()
    assert gallery.sends == 2 and len(node.batched_wxyzs) == len(node.batched_positions) == 40
    assert np.allclose(node.batched_opacities, ALL_OPACITY) and gallery.words() == "40 answers drawn faint at once."
    wxyz = Rotation.from_matrix(entries[7].answer.R_space_body).as_quat(scalar_first=True)
    assert np.allclose(np.abs(node.batched_wxyzs[7] @ wxyz), 1.0, atol=1e-6)
    gallery.previous()  # from all: the last one
    assert gallery.chosen is entries[39] and gallery.mode == ONE
    gallery.next()  # wraps to the first
    assert gallery.chosen is entries[0]
    assert gallery._node is node  # the same node, new arrays
    assert node.batched_opacities[0] == pytest.approx(CHOSEN_OPACITY) and tuple(node.batched_colors[0]) == CHOSEN_COLOR
    assert gallery.words().startswith("Answer 1 of 40: ")
    gallery.set_entries(entries[1:])  # the chosen one replaced: back to the first
    gallery.show_all()
    assert gallery.chosen is None
    gallery.clear()
    assert not node.visible
    gallery.remove()
    assert gallery._node is None


def test_play_answer_restarts_the_room_from_the_answer_bit_for_bit() -> None:
    room = Room(HeavyTopView, HeavyTopView.new_simulation())
    R = Rotation.from_euler("ZXZ", [0.3, 1.0, -0.2]).as_matrix()
    answer = AnswerState("Heavy top", R, np.array([0.4, -0.3, 15.0]), (1.2, 1.2, 0.6), 5.0)
    play_answer(room, answer)
    assert room.playing and room.sim.t == 0.0
    assert np.array_equal(room.sim.state.R_space_body, answer.R_space_body)
    assert np.array_equal(room.sim.state.omega_body, answer.omega_body)
    assert room.sim.model.inertia == (1.2, 1.2, 0.6) and room.sim.model.mgl == 5.0
    before = (room.sim.state, room.sim.model)
    with pytest.raises(ValueError, match="not one the Heavy top scene can show"):  # I1 ≠ I2
        play_answer(room, AnswerState("Heavy top", R, answer.omega_body, (1.2, 1.3, 0.6), 5.0))
    with pytest.raises(ValueError, match=r"m g ℓ \[N m\] = 1e\+06 is outside"):
        play_answer(room, AnswerState("Heavy top", R, answer.omega_body, (1.2, 1.2, 0.6), 1e6))
    assert (room.sim.state, room.sim.model) == before  # refused: nothing changed
    free_room = Room(FreeBodyView, FreeBodyView.new_simulation())
    with pytest.raises(ValueError, match="Heavy top body; the room shows Free body"):
        play_answer(free_room, answer)


@pytest.mark.parametrize("inertia", [(1.0, 2.0, 2.5), (0.3, 0.75, 1.0), (1.0, 1.0, 1.0)])
def test_box_glyph_has_the_moments_ratios(inertia: tuple[float, float, float]) -> None:
    a, b, c = box_extents(inertia)
    moments = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 12.0
    assert moments / moments[0] == pytest.approx(np.array(inertia) / inertia[0], rel=1e-9)
    assert max(a, b, c) == pytest.approx(1.2)


def test_the_tally_of_a_judged_round_is_a_histogram_and_its_gallery_is_numbered_like_the_csv() -> None:
    from app.ask import Round
    from app.ask import State as StateQuestion
    from app.ask.state_tally import gallery_entries, judged_histogram_text

    round_ = Round(StateQuestion("Stand it like this", "Euler angles", "attitude", {"angles_deg": [0, 40, 0]}),
                   clock=iter(np.arange(0.0, 100.0, 1.0)).__next__)
    for k, error_deg in enumerate((3.0, 7.0, 12.0, 14.0, 100.0)):
        R = Rotation.from_euler("ZXZ", [0.0, 40.0 + error_deg, 0.0], degrees=True).as_matrix()
        round_.answer(f"browser-{k}", AnswerState("Euler angles", R, np.zeros(3)).to_dict())
    text = judged_histogram_text(round_.tally())
    assert "0–5° `" in text and "10–20° `████████████████` **2**" in text and "90–180°" in text
    assert "✓ **2** of 5 meet the target" in text  # within 10° (the attitude judge's default)
    entries = gallery_entries(round_)
    assert [e.number for e in entries] == [row["answer"] for row in round_.rows()] == [1, 2, 3, 4, 5]
    assert entries[2].value == pytest.approx(12.0) and entries[2].verdict == "12.0° from the target"
    again = round_.vote_again()
    again.answer("browser-0", AnswerState("Euler angles", np.eye(3), np.zeros(3)).to_dict())
    text = judged_histogram_text(again.tally())  # 40° off; round 1 beside each bar
    assert "20–45° `████████` **1** · round 1: 0" in text and "10–20° `·` **0** · round 1: 2" in text


def test_a_state_round_in_the_app_judged_galleried_played_and_no_follower_can_play() -> None:
    """The app with its loop not running: the presenter asks §6's judged state question from the
    lesson (its target kept), a student answers from its copy (the step's Loop preset: as asked),
    the presenter's panel shows the judged histogram and the gallery; a follower's raw websocket
    presses its own (hidden) gallery buttons and calls play: the presenter's run does not change
    (its start, restarts, model); the presenter plays answer 1."""
    from conftest import LectureHall
    from viser import _messages

    hall = LectureHall("864213")
    try:
        presenter = hall.join()
        presenter.present("864213")
        presenter.start_lesson("§6 The free body and the heavy top")
        step = next(k for k, s in enumerate(presenter.lesson.steps) if getattr(s.ask, "judge", None))
        presenter.next_step(step - presenter.lesson_step)
        panel = presenter.ask_panel
        panel.ask_from_form()
        question = hall.app.rounds.current.question
        assert (question.judge, question.target) == ("top_motion", {"motion": "loops"})
        (alice, _), (bob, bob_client) = hall.join_with_client(), hall.join_with_client()
        hall.app.frame(1.0 / 60.0)
        alice.answer_from_copy()
        kept = alice.answer(alice.state_answer())
        judged = hall.app.rounds.current.answer_of(alice.answer_token).judged
        assert AnswerState.from_dict(kept).scene == "Heavy top" and judged is not None and judged.good is True
        for _ in range(20):
            hall.app.frame(1.0 / 60.0)
        histogram = panel.gui_histogram.content
        assert f"{judged.value} `" in histogram and "1** of 1 meet the target" in histogram
        assert panel.gallery_panel.folder.visible and panel.gallery.entries[0].number == 1
        room = presenter.room
        before = (room.sim.initial_state.R_space_body.tobytes(), room.sim.restarts, room.sim.model)
        bob_panel = bob.ask_panel.gallery_panel
        for handle, value in ((bob_panel.walk, "Next"), (bob_panel.play_button, True), (bob_panel.walk, "Nope")):
            bob_client.send(_messages.GuiUpdateMessage(handle._impl.uuid, {"value": value}))
        for _ in range(5):
            hall.app.frame(1.0 / 60.0)
        with pytest.raises(PermissionError):
            bob.play_answer(1)
        with pytest.raises(PermissionError):
            bob._play_state(AnswerState.from_dict(kept))
        assert (room.sim.initial_state.R_space_body.tobytes(), room.sim.restarts, room.sim.model) == before
        presenter.play_answer(1)
        played = AnswerState.from_dict(kept)
        assert room.playing and np.array_equal(room.sim.initial_state.R_space_body, played.R_space_body)
        assert presenter.error_count == 0 and alice.error_count == 0
    finally:
        hall.close()
