"""The Constrained particles scene refuses bad input with a message and keeps the state;
its readout shows (5.7), (5.12), (5.13) and says which quantity is conserved."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.scenes.constrained import DELTA_Q
from physics.quaternion import matrix_from_wxyz


def test_bad_values_are_refused_and_the_state_kept(manual) -> None:  # type: ignore[no-untyped-def]
    session = manual.session
    session.select_scene("Constrained particles")
    session.apply_preset("Turning rod")
    view = session.scene
    before = (view.sim.setup, view.sim.t, list(view.sim.q_shown))
    keys = [spec.key for spec in view.sim.setup.kind_spec.param_specs]
    for handle, value, words in ((view.gui_q[0], 2.2, "must start on the rod"),  # in the slider, off the rod (ℓ = 2)
                                 (view.gui_params[keys.index("length")], math.nan, "refused"),
                                 (view.gui_params[keys.index("length")], 0.0, "refused"),
                                 (view.gui_params[keys.index("Omega")], 99.0, "refused")):
        handle.value = value  # as the server's write: applied (or refused) at once
        assert words in view.message.text, (value, view.message.text)
        assert (view.sim.setup, view.sim.t, list(view.sim.q_shown)) == before
    view.gui_params[keys.index("Omega")].value = 1.5  # a good value restarts at t = 0 with it
    assert dict(view.sim.system.params)["Ω"] == 1.5 and view.message.text == ""
    assert session.error_count == 0, session.last_error


def test_the_readout_names_the_conserved_quantity(manual) -> None:  # type: ignore[no-untyped-def]
    session = manual.session
    session.select_scene("Constrained particles")
    view = session.scene
    for preset, words in (("Fast hoop", "Jacobi's integral"), ("Double pendulum, chaotic", "energy, conserved"),
                          ("Spherical pendulum", "L_z")):
        session.apply_preset(preset)
        session.play()
        manual.tick(0.5)
        view.show_tab("Readout")
        view.refresh()
        text = view.conserved_note.handle.content + view.readout.handle.content
        assert words in text and "(5.13)" in text and "(5.7)" in text, text
    assert session.error_count == 0, session.last_error


def test_arrows_hang_under_their_particle_and_a_paused_frame_is_exact(manual, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Turning hoop: the applied force (gravity, constant) hangs under the bead and sends nothing
    while the bead moves; the bead is drawn within TOLERANCE while playing, exactly when paused."""
    import numpy as np

    from app.kit.draw.lean import TOLERANCE

    session = manual.session
    session.select_scene("Constrained particles")
    session.apply_preset("Turning hoop")
    view = session.scene
    manual.tick(0.2)
    sent: list[str] = []
    api = session.client.scene
    original = api._queue_scene_message
    monkeypatch.setattr(api, "_queue_scene_message", lambda m: (sent.append(getattr(m, "name", "")), original(m))[1])
    session.play()
    manual.tick(1.0)
    bead = view.particles[0]._impl.name
    assert bead in sent and not any(name.startswith(f"{bead}/F") for name in sent)
    x = view.sim.evaluation().x
    np.testing.assert_allclose(view.particles[0].position, x[0], atol=0.5 * TOLERANCE * math.sqrt(3) + 1e-6)
    session.pause()
    x = view.sim.evaluation().x
    np.testing.assert_allclose(view.particles[0].position, x[0].astype(np.float32), atol=1e-6)
    assert session.error_count == 0, session.last_error


def _three(wxyz):  # type: ignore[no-untyped-def]
    """The matrix three.js draws for a quaternion as sent (not renormalized: a quantized one is
    not quite unit): (1 − |q|²) I + |q|² R(q / |q|)."""
    k2 = float(np.dot(wxyz, wxyz))
    return (1.0 - k2) * np.eye(3) + k2 * matrix_from_wxyz(wxyz)


def _drawn(arrow, frame, particle):  # type: ignore[no-untyped-def]
    """The arrow's (start, tip) in the world as sent: particle position, the turned frame `o`,
    the arrow's own turn and its tip's position (the shaft pieces' cover checked separately)."""
    R_o, R_a = _three(frame.wxyz), _three(arrow.node.wxyz)
    at, start = np.asarray(particle.position), np.asarray(arrow.node.position)
    return at + R_o @ start, at + R_o @ (start + R_a @ np.asarray(arrow.tip.position))


@pytest.mark.parametrize("preset", ["Turning hoop", "Spherical pendulum", "Double pendulum, chaotic", "Turning rod"])
def test_arrows_in_the_turned_frame_are_the_vectors(manual, preset) -> None:  # type: ignore[no-untyped-def]
    """δx_j and C hang in the particle's turned frame: what is drawn is δq ∂x_i/∂q_j and s C_i,
    to ~1 px while playing and exactly when paused; the two shaft pieces cover the shaft."""
    session = manual.session
    session.select_scene("Constrained particles")
    session.apply_preset(preset)
    view = session.scene
    session.play()
    manual.tick(0.6)
    for atol in (0.008, 1e-5):  # playing (~1 px at the default view), then paused (float32)
        if atol < 1e-3:  # the second pass: paused
            session.pause()
            manual.tick(0.05)
        ev = view.sim.evaluation()
        scale = view.sim.setup.force_scale
        for i in range(view.sim.system.n):
            expected = [(view.C_arrows[i], scale * ev.C[i])]
            expected += [(arrow, DELTA_Q * ev.J[i, :, j]) for j, arrow in enumerate(view.dx_arrows[i])]
            for arrow, vector in expected:
                if np.linalg.norm(vector) < 0.01:
                    continue
                assert arrow.visible
                start, tip = _drawn(arrow, view.turns[i], view.particles[i])
                np.testing.assert_allclose(start, ev.x[i], atol=atol)
                np.testing.assert_allclose(tip - start, vector, atol=atol)
                shaft = arrow._length - arrow._head_scale * arrow.head_length
                piece = arrow.shaft.scale[2]
                assert arrow.back.scale[2] == piece and piece <= shaft + 1e-9 <= 2 * piece + 2e-9
                assert arrow.back.position[2] == pytest.approx(-arrow._head_scale * arrow.head_length)
    assert session.error_count == 0, session.last_error


def test_turning_rod_played_for_a_minute_ends_when_the_bead_flies_off_without_a_warning(manual) -> None:  # type: ignore[no-untyped-def]
    """r = r₀ cosh Ωt reaches ℓ = 2 m at t = arccosh(2 / 0.15) / 1.2 = 2.73 s: the run ends there,
    said in plain words (no "⚠ The simulation stopped"); Reset clears the note."""
    session = manual.session
    session.select_scene("Constrained particles")
    session.apply_preset("Turning rod")
    view = session.scene
    session.play()
    manual.tick(60.0, dt=1.0 / 30.0)
    t_off = math.acosh(2.0 / 0.15) / 1.2
    assert not session.room.playing and view.sim.t == pytest.approx(t_off, abs=0.05)
    text = view.message.text
    assert "flew off" in text and "⚠" not in text and "stopped" not in text, text
    assert session.error_count == 0, session.last_error
    session.reset()
    assert view.message.text == "" and view.sim.t == 0.0


def test_the_bead_flying_off_is_said_in_the_browsers_language(manual) -> None:  # type: ignore[no-untyped-def]
    """The same end in a German browser: the room says it in English, the view writes it in
    German with a decimal comma; the replay's end line (the room's too) in Dutch."""
    from app.i18n import translator
    from app.kit.run_words import RUN_MESSAGES

    session = manual.session
    session.languages.choose("de")
    session.select_scene("Constrained particles")
    session.apply_preset("Turning rod")
    view = session.scene
    session.play()
    manual.tick(60.0, dt=1.0 / 30.0)
    assert not session.room.playing
    text = view.message.text
    assert text.startswith("**■ Die Perle erreichte das Ende des Stabs (|r| = ℓ = 2 m) kurz nach t = 2,7"), text
    assert "flew off" not in text and session.error_count == 0, session.last_error
    said = RUN_MESSAGES.in_language("**Replay reached the live moment, t = 3.25 s.**", translator("nl"))
    assert said == "**De herhaling heeft het live moment bereikt, t = 3,25 s.**"
