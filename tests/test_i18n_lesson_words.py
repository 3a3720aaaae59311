"""A lecturer's own (★) lesson reaches each follower in its language, on any worker.

The presenter sends a lesson step in English (`FollowerStatus.lesson`, the caption) and, with it,
the step's words in every other language (`FollowerStatus.lesson_words`, `app.lessons.step_words`):
a worker that never loaded the lesson (another process, another data folder) shows its followers
the step in theirs.  Two sides: what the bus carries from a presenter running an own lesson (the
hall message, encoded and decoded as the bus does), and a German follower on a worker that hears
a presenter's hall message for a lesson no process there knows (Redis, a source played by hand).
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import redis
from conftest import browsers_joining, poll_until, redis_url  # noqa: F401 - redis_url: the workers' fixture needs it
from test_bus import Workers, workers_fixture

from app.cluster.messages import LIVE_DECODER, HallState, SceneBatch, encode
from app.i18n import translator
from app.lecture.bus import CHANNEL
from app.lecture.bus.follow import copy_hall
from app.lecture.bus.source import hall_message
from app.lecture.follower import FollowerStatus, Hall
from app.lecture.lectern import Lectern, RemoteShow
from app.main import create_server

CODE = "86420864"
workers = workers_fixture(CODE)

OWN_LESSON = {
    "title": {"en": "Spinning the book", "nl": "Het boek draaien", "de": "Das Buch drehen"},
    "steps": [{"scene": "Free body", "text": {
        "en": "Spun about its middle axis, the book tumbles.",
        "nl": "Om zijn middelste as gedraaid, gaat het boek tuimelen.",
        "de": "Um die mittlere Achse gedreht, überschlägt sich das Buch."}}],
}


@pytest.fixture
def own_hall(tmp_path: Path) -> Iterator[Any]:
    """The app without its loop, its data folder holding the own lesson OWN_LESSON; a factory of sessions."""
    (tmp_path / "lessons").mkdir()
    (tmp_path / "lessons" / "Spinning the book.json").write_text(json.dumps(OWN_LESSON), encoding="utf-8")
    running = create_server("127.0.0.1", 0, verbose=False, start_loop=False, presenter_code=CODE, data_dir=tmp_path)
    with browsers_joining(running) as join:
        yield running, join


def status_line(session: Any) -> str:
    """A follower's status line now ("" while its view is being switched: `scene` None, or not a follower's)."""
    return str(getattr(getattr(session.scene, "gui_status", None), "content", ""))


def test_the_hall_message_of_an_own_lesson_carries_the_step_in_every_language(own_hall: Any) -> None:
    app, join = own_hall
    presenter = join()
    presenter.present(CODE)
    presenter.start_lesson("★ Spinning the book")
    assert presenter.error_count == 0, presenter.last_error
    message = LIVE_DECODER.decode(encode(hall_message("a", app.lectern, Hall.LIVE)))
    assert isinstance(message, HallState)
    status = FollowerStatus.from_dict(message.status)
    assert status.lesson.startswith("**Spinning the book**, step 1/1: Spun about"), status.lesson
    german, dutch = status.lesson_words["de"], status.lesson_words["nl"]
    assert german[status.lesson].startswith("**Das Buch drehen**, Schritt 1/1: Um die mittlere Achse"), german
    assert dutch[status.lesson].startswith("**Het boek draaien**, stap 1/1: Om zijn middelste as"), dutch
    head, words = message.caption
    assert (german[head], german[words]) == ("Das Buch drehen · Schritt 1 von 1", OWN_LESSON["steps"][0]["text"]["de"])
    other = Lectern(server=None)  # type: ignore[arg-type] - another worker's lectern: it reads the message
    other.show_remote(RemoteShow(worker="a", title="Free body"))
    copy_hall(other.remote, message)  # type: ignore[arg-type]
    shown = other.follower_status().markdown(translator("nl"))
    assert "Om zijn middelste as gedraaid" in shown and "Spun about" not in shown, shown


def test_a_german_follower_on_another_worker_reads_a_lesson_no_process_there_knows(workers: Workers) -> None:
    """The test plays a source worker "s" whose presenter runs a lesson of its own; B never
    loaded it.  B's German follower reads the step's line and caption in German, from the
    words the hall message carries; its English follower reads the English."""
    workers.start("b")
    german, _ = workers.connect("b")
    english, _ = workers.connect("b")
    german.languages.choose("de")
    line_en = "**A lesson of mine**, step 1/1: The book tumbles."
    head_en, text_en = "A lesson of mine · step 1 of 1", "The book tumbles."
    words = {"de": {line_en: "**Eine Lektion von mir**, Schritt 1/1: Das Buch überschlägt sich.",
                    head_en: "Eine Lektion von mir · Schritt 1 von 1", text_en: "Das Buch überschlägt sich."}}
    status = FollowerStatus(hall=Hall.LIVE, title="Free body", lesson=line_en, lesson_words=words)
    hall = HallState(worker="s", hall="live", title="Free body", status=status.to_dict(), caption=(head_en, text_en))
    client = redis.Redis.from_url(workers.url)
    client.publish(CHANNEL, encode(SceneBatch(worker="s", seq=1, full="*", messages=[], buffers=[], shapes=[],
                                              title="Free body")))

    def heard() -> bool:  # said again until B has it (also the source's heartbeat)
        client.publish(CHANNEL, encode(hall))
        return german.mode == "following" and "Buch" in status_line(german)

    poll_until(heard, timeout=30.0, interval=0.1,
               what="B's German follower showing the step in German",
               seen=lambda: (german.mode, status_line(german)))
    status_de = german.scene.gui_status.content
    assert "**Eine Lektion von mir**, Schritt 1/1: Das Buch überschlägt sich." in status_de, status_de
    assert "tumbles" not in status_de
    caption = german.scene.caption
    assert (caption.head, caption.text) == ("Eine Lektion von mir · Schritt 1 von 1", "Das Buch überschlägt sich.")
    poll_until(lambda: english.mode == "following" and line_en in status_line(english),
               timeout=30.0, what="B's English follower showing the step in English",
               seen=lambda: (english.mode, status_line(english)))
    assert (english.scene.caption.head, english.scene.caption.text) == (head_en, text_en)
