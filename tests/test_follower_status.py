"""The follower's status as a value (`app.lecture.follower.FollowerStatus`).

- It crosses workers as data: the bus's hall message (`app.lecture.bus.source.hall_message`)
  carries `to_dict`, encoded as the bus encodes it (`app.cluster.messages`), and the other worker
  reads it (`app.lecture.bus.follow.copy_hall`, `from_dict`: checked, a wrong hall, transport
  mode, type or length is a ValueError, which drops the message) into the same value, shown in
  the same words.
- A presenter on another worker who stops or leaves is the status's `hall`, not an edit of its
  words: a follower there reads what a follower on the presenter's own worker reads (the head
  says so, the lesson step goes, the time shown stays), also when the presenter was looking back.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import pytest

from app.cluster.messages import LIVE_DECODER, HallState, encode
from app.i18n import translator
from app.kit.core.key_number import KeyNumber
from app.kit.core.room import Room
from app.lecture.bus.follow import copy_hall
from app.lecture.bus.source import hall_message
from app.lecture.follower import FollowerStatus, Hall
from app.lecture.lectern import Lectern, RemoteShow
from app.scenes import SCENES

LESSON = "**Step 3/7** · the tennis-racket flip"
KEY_NUMBERS = [KeyNumber("ω₁", (0.1,), unit="rad/s"), KeyNumber("principal moments about O", (2.5, 5.0), unit="kg m²")]


def _room(looking_back: bool) -> Room:
    """A Free body room played 2 s, paused; `looking_back`: scrubbed back to t = 1 s."""
    scene = SCENES["Free body"]
    room = Room(scene, scene.new_simulation())
    room.play()
    for _ in range(120):
        room.advance(1.0 / 60.0)
    room.pause()
    if looking_back:
        room.scrub(1.0)
    return room


def _through_the_bus(status: FollowerStatus) -> FollowerStatus:
    """`status` as another worker reads it from a hall message (encoded and decoded as the bus does)."""
    message = LIVE_DECODER.decode(encode(HallState(worker="a", hall=status.hall.value, status=status.to_dict())))
    assert isinstance(message, HallState)
    return FollowerStatus.from_dict(message.status)


def _hear(source: Lectern, other: Lectern) -> None:
    """`source`'s hall message (`hall_message`, as its bus sends it) heard by `other` (`copy_hall`)."""
    message = LIVE_DECODER.decode(encode(hall_message("a", source, source.hall)))
    assert isinstance(message, HallState) and other.remote is not None
    copy_hall(other.remote, message)


def _lectern_showing(room: Room, *, presenting: bool) -> Lectern:
    """A lectern (no server) whose shared screen shows `room`: its presenter on a lesson step, or
    (not `presenting`) the last state a presenter who left showed."""
    lectern = Lectern(server=None)  # type: ignore[arg-type]
    lectern.live_view = SimpleNamespace(key_numbers=lambda: KEY_NUMBERS)
    lectern._live_room = room
    if presenting:
        lectern.presenter = SimpleNamespace(lesson_text=lambda: LESSON, lesson_words=dict,  # type: ignore[assignment]
                                            caption_words=lambda: ("", ""))
        lectern.hall = Hall.LIVE
    else:
        lectern.hall = Hall.LEFT
    return lectern


@pytest.mark.parametrize("looking_back", [False, True])
def test_the_status_crosses_workers_as_the_same_value_and_words(looking_back: bool) -> None:
    source = _lectern_showing(_room(looking_back), presenting=True)
    status = source.follower_status()
    assert status.hall is Hall.LIVE and status.title == "Free body" and status.lesson == LESSON
    assert status.transport is not None and status.transport.mode == ("scrubbing" if looking_back else "live")
    other = Lectern(server=None)  # type: ignore[arg-type]
    other.show_remote(RemoteShow(worker="a", title="Free body"))
    _hear(source, other)
    heard = other.follower_status()
    assert heard == status, (heard, status)
    assert (heard.markdown(), heard.line()) == (source.status(), source.status_line())
    assert LESSON in heard.markdown() and "Dzhanibekov" in heard.markdown()


@pytest.mark.parametrize("change", [
    {"hall": "nobody"}, {"title": 3}, {"title": "x" * 5000}, {"lesson": ["a"]}, {"key_numbers": [1, 2]},
    {"key_numbers": ["k = 1"]}, {"key_numbers": [{"label": "k", "values": [1.0]}] * 1000},
    {"key_numbers": [{"label": "k", "values": ["one"]}]}, {"key_numbers": [{"label": "k" * 5000, "values": []}]},
    {"key_numbers": [{"label": "k", "values": [1.0] * 1000}]}, {"transport": {"mode": "flying"}},
    {"transport": {"t": "soon"}}, {"lesson_words": {"de": "Schritt"}}, {"lesson_words": {"de": {"a": "b" * 5000}}},
    {"lesson_words": {f"l{k}": {} for k in range(100)}},
])
def test_a_status_that_is_not_one_is_refused(change: dict[str, Any]) -> None:
    plain = _through_the_bus(FollowerStatus.of_room(_room(False), Hall.LIVE, LESSON, KEY_NUMBERS)).to_dict()
    with pytest.raises(ValueError):
        FollowerStatus.from_dict({**plain, **change})
    with pytest.raises(ValueError):
        FollowerStatus.from_dict("**Presenter:** ▶ playing")  # the words, as the bus once sent them


def test_a_status_made_of_long_words_is_one_the_other_workers_accept() -> None:
    """A long lesson step or many key numbers are cut where the status is made, so the source never
    sends a status the others refuse (each refusal would drop a hall message)."""
    numbers = [KeyNumber.made("k" * 5000, [1.0] * 5000, unit="u" * 5000, name="n" * 5000)] * 500
    status = FollowerStatus.of_room(_room(False), Hall.LIVE, "x" * 10_000, numbers)
    heard = _through_the_bus(status)
    assert heard == status and heard.lesson == "x" * len(heard.lesson) and 0 < len(heard.lesson) < 10_000
    assert 0 < len(heard.key_numbers) < 500 and all(0 < len(n.label) < 1000 and 0 < len(n.values) < 100
                                                    for n in heard.key_numbers)


def test_key_numbers_are_written_in_each_followers_words() -> None:
    """The key numbers cross as English labels and numbers: each follower reads the labels from
    its catalog and the numbers written its way (a decimal comma, the values apart by "; ");
    symbols and units stay."""
    status = _through_the_bus(FollowerStatus.of_room(_room(False), Hall.LIVE, LESSON, KEY_NUMBERS))
    english, dutch, german = (status.markdown(translator(code)) for code in ("en", "nl", "de"))
    assert "ω₁ = 0.1 rad/s" in english and "principal moments about O = 2.5, 5 kg m²" in english
    assert "ω₁ = 0,1 rad/s" in dutch and "ω₁ = 0,1 rad/s" in german
    for words, language in ((dutch, "nl"), (german, "de")):
        label = translator(language).gettext("principal moments about O")
        assert label != "principal moments about O", f"{language}: the label is not in the catalog"
        assert f"{label} = 2,5; 5 kg m²" in words and "principal moments" not in words


@pytest.mark.parametrize("looking_back", [False, True])
def test_a_presenter_who_left_another_worker_reads_as_on_its_own(looking_back: bool) -> None:
    """B's followers, after A's presenter left, read what A's own followers read: the head says
    the presenter left, the lesson step is gone, the time shown stays (a looking-back status's
    head carried it)."""
    room = _room(looking_back)
    source = _lectern_showing(room, presenting=True)
    other = Lectern(server=None)  # type: ignore[arg-type]
    other.show_remote(RemoteShow(worker="a", title="Free body"))
    _hear(source, other)
    assert other.status() == source.status()  # while live: the same words
    other.remote_ended(left=True)
    left_here = _lectern_showing(room, presenting=False)  # A, once its presenter left
    assert other.hall is Hall.LEFT and other.follower_status().hall is Hall.LEFT
    assert other.status() == left_here.status(), (other.status(), left_here.status())
    assert other.status_line() == left_here.status_line() == "**Presenter left** · last state: Free body"
    text = other.status()
    assert text.startswith("**The presenter has left**") and LESSON not in text
    assert f"t = {room.sim.t:.1f} s" in text, text


def test_a_remote_show_before_its_first_status_names_its_scene() -> None:
    lectern = Lectern(server=None)  # type: ignore[arg-type]
    lectern.show_remote(RemoteShow(worker="a", title="Heavy top"))
    assert "Heavy top" in lectern.status() and "Nobody" not in lectern.status()
    assert lectern.status_line() == "**Heavy top**"
    lectern.remote_ended(left=False)
    assert lectern.status().startswith("**The presenter stopped presenting**") and "Heavy top" in lectern.status()
