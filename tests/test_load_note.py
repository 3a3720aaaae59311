"""Overload is shown: when browsers get fewer than BUSY_SHARE x 60 frames a second, every panel
says "Server busy: N frames a second"; it goes away once the server has kept up for LOAD_HOLD_S."""

from __future__ import annotations

import time

from conftest import RawClient, poll_until

from app.main import BUSY_SHARE, LOAD_HOLD_S, LOAD_PERIOD, create_server, load_note


def test_the_note_follows_the_rate_browsers_get() -> None:
    assert load_note(120, 240, 0, 2.0, 60.0) == ""  # 60 fps, every client frame drawn
    assert load_note(int(2 * BUSY_SHARE * 60) + 1, 100, 0, 2.0, 60.0) == ""
    note = load_note(48, 48, 0, 2.0, 60.0)  # 24 loop iterations a second
    assert "Server busy: 24 frames a second" in note and "of 60" in note
    # The loop runs at 60 but half the client frames are skipped (their last frame had not left).
    assert "Server busy: 30 frames a second" in load_note(120, 100, 100, 2.0, 60.0)
    assert load_note(0, 0, 0, 0.0, 60.0) == ""


def test_a_slow_loop_is_said_in_the_panel_and_the_note_goes_when_it_keeps_up() -> None:
    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    app.tick_hz = 20.0  # a rate a loaded machine keeps up with: the note's going does not depend on its speed
    app.start()
    client = RawClient(app.port)
    try:
        session = next(iter(app.wait_for_sessions(1).values()))
        room = session.room
        advance = room.advance

        def slow(dt: float) -> None:  # a frame that costs 150 ms: the loop manages < 7 of its 20 a second
            time.sleep(0.15)
            advance(dt)

        room.advance = slow  # type: ignore[method-assign]
        poll_until(lambda: session.gui_load.visible, timeout=30.0, what="the busy note shown")
        assert "Server busy" in session.gui_load.content and "(of 20)" in session.gui_load.content
        assert app.load == session.gui_load.content
        room.advance = advance  # type: ignore[method-assign]
        kept_up = time.monotonic()
        poll_until(lambda: not session.gui_load.visible, timeout=30.0 + LOAD_HOLD_S, what="the busy note gone",
                   seen=lambda: session.gui_load.content)
        assert app.load == ""
        # It stayed LOAD_HOLD_S after the last window measured busy, which ended at most one
        # window (and one slow frame) before the loop kept up again.
        assert time.monotonic() - kept_up >= LOAD_HOLD_S - LOAD_PERIOD - 0.15
    finally:
        client.close()
        app.stop()


def test_the_load_note_and_the_error_line_speak_the_browsers_language() -> None:
    """The note the loop writes (English) is shown in each browser's language, and written anew
    when the browser changes language; so is the error line's headline and its button."""
    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
    clients = [RawClient(app.port), RawClient(app.port)]
    try:
        english, german = app.wait_for_sessions(2).values()
        german.languages.choose("de")
        app._show_load(load_note(48, 48, 0, 2.0, 60.0))
        assert english.gui_load.content.startswith("**Server busy: 24 frames a second** (of 60)")
        assert german.gui_load.content.startswith("**Server ausgelastet: 24 Bilder pro Sekunde** (von 60)")
        german.errors.report("a test", ValueError("the error's own words"))
        assert german.errors.gui_error.content.startswith("**⚠ Etwas ist schiefgegangen**")
        assert "`a test: ValueError: the error's own words`" in german.errors.gui_error.content
        assert german.errors.gui_error_dismiss.label == "Meldung schließen"
        german.languages.choose("nl")
        assert german.gui_load.content.startswith("**Server druk: 24 beelden per seconde** (van 60)")
        assert german.errors.gui_error.content.startswith("**⚠ Er ging iets mis**")
        assert german.errors.gui_error_dismiss.label == "Melding sluiten"
        app._show_load("")
        assert not german.gui_load.visible and not english.gui_load.visible
    finally:
        for client in clients:
            client.close()
        app.stop()


def test_a_refused_form_is_said_in_the_browsers_words_and_other_errors_as_raised() -> None:
    """A German presenter's `Ask the class` with a right option that is none of the options: the
    error line says the refusal (a `Refusal`) in German, the form's label too, under "Nicht
    angenommen"; `last_error` keeps the English for logs and tests; an error that is no refusal
    is shown as raised."""
    app = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code="864277")
    client = RawClient(app.port)
    try:
        (presenter,) = app.wait_for_sessions(1).values()
        presenter.languages.choose("de")
        presenter.present("864277")
        panel = presenter.ask_panel
        panel.gui_prompt.value = "Welche?"
        panel.gui_options.value = "a | b"
        panel.gui_correct.value = "3"
        presenter.guard("ask the class", panel.ask_from_form)()
        assert app.lectern.rounds.current is None  # nothing asked
        shown = presenter.errors.gui_error.content
        assert shown.startswith("**⚠ Nicht angenommen**"), shown
        assert "Richtige Option: Option 3 ist keine der 2 Optionen" in shown
        assert "QuestionRefused" not in shown and "option 3 is not one of the 2 options" in presenter.last_error
        presenter.guard("a test", lambda: 1 / 0)()
        assert presenter.errors.gui_error.content.startswith("**⚠ Etwas ist schiefgegangen**")
        assert "`a test: ZeroDivisionError: division by zero`" in presenter.errors.gui_error.content
    finally:
        client.close()
        app.stop()
