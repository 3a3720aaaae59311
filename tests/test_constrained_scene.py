"""The Constrained particles scene refuses bad input with a message and keeps the state;
its readout shows (5.7), (5.12), (5.13) and says which quantity is conserved."""

from __future__ import annotations

import math


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

    from app.kit.lean import TOLERANCE

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
