"""Share (issue 27, item 2): the stores, and sharing and opening between sessions (raw websocket
clients; the browser's path is tests/test_browser_share.py).

- `SqliteShareStore`: a code opens what was saved, also after a restart (a new store on the same
  file); typing is forgiving; a malformed, unknown or expired code raises `ShareCodeError` with
  a message that says which.
- `RedisShareStore` against a real redis-server (`app.cluster.services.start_redis`): the same,
  and Redis drops an expired moment.
- A moment shared by one browser opens in another bit for bit (the simulation, paused), seen
  from the sharer's camera; a follower who opens a code explores it and the presenter's room
  does not change; an app restarted on the same data folder opens the code.
- Hostile values in the code field, sent over a raw websocket, change nothing but the field's note.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import LectureHall, poll_until
from test_trust import fingerprint

from app.hall.share import decode_moment, encode_moment
from app.kit.core.room import Room
from app.main import create_server
from app.scenes import SCENES
from app.sharestore import (
    DEFAULT_TTL_S,
    RedisShareStore,
    ShareCodeError,
    SqliteShareStore,
    format_code,
    open_share_store,
)
from tests.test_codec import drop_caches
from tests.test_fork import assert_same

CODE = "864209"
MALFORMED = ["", "hello", "K7M2-QX9", "K7M2-QX9PQ", "K7M2-QX9U", "€€€€€€€€", "x" * 10_000, 12345678, None, ["K7M2QX9P"]]


class Clock:
    def __init__(self) -> None:
        self.now = 1.8e9

    def __call__(self) -> float:
        return self.now


def _room_bytes() -> bytes:
    scene = SCENES["Free body"]
    room = Room(scene, scene.new_simulation())
    room.play()
    for _ in range(30):
        room.advance(1 / 60)
    return encode_moment(room, None)


def _check_store(store: Any) -> str:
    payload = _room_bytes()
    code = store.save(payload)
    assert len(code) == 8 and store.load(code) == payload
    assert store.load(format_code(code).lower()) == payload  # as a person types it
    assert store.load(" " + format_code(code).replace("0", "O") + " ") == payload
    for text in MALFORMED:
        with pytest.raises(ShareCodeError, match="not a share code"):
            store.load(text)  # type: ignore[arg-type]
    unknown = "Z" * 8 if code != "Z" * 8 else "Y" * 8
    with pytest.raises(ShareCodeError, match="No shared moment has the code ZZZZ-ZZZZ|YYYY-YYYY"):
        store.load(unknown)
    return code


def test_the_sqlite_store_keeps_codes_across_a_restart_and_expires_them(tmp_path: Path) -> None:
    clock = Clock()
    path = tmp_path / "shares.sqlite3"
    store = SqliteShareStore(path, clock=clock)
    code = _check_store(store)
    store.close()
    again = SqliteShareStore(path, clock=clock)  # the app restarted
    decode_moment(again.load(code))
    clock.now += DEFAULT_TTL_S - 1.0
    again.load(code)
    clock.now += 2.0
    with pytest.raises(ShareCodeError, match=r"expired on \d{4}-\d\d-\d\d .*30 days"):
        again.load(code)
    again.save(b"x")  # saving drops what expired
    with pytest.raises(ShareCodeError, match="No shared moment"):
        again.load(code)
    with pytest.raises(ValueError, match="non-empty"):
        again.save(b"")


def test_the_redis_store_keeps_and_expires_codes() -> None:
    from app.cluster.services import start_redis, stop_process

    try:
        url, process = start_redis()
    except Exception as error:  # noqa: BLE001 - redis-server missing: .ci/run installs it
        pytest.skip(f"redis-server: {error}")
    try:
        store = open_share_store(Path("unused"), url)  # the app on several processes
        assert isinstance(store, RedisShareStore)
        code = _check_store(store)
        assert 0 < store._redis.pttl(store.PREFIX + code) <= DEFAULT_TTL_S * 1000
        short = RedisShareStore(url, ttl_s=0.3)
        brief = short.save(b"moment")
        assert short.load(brief) == b"moment"
        poll_until(lambda: short._redis.get(short.PREFIX + brief) is None, timeout=10.0)
        with pytest.raises(ShareCodeError, match="No shared moment"):
            short.load(brief)
        store.close()
        short.close()
    finally:
        stop_process(process)


@pytest.fixture
def hall(tmp_path: Path) -> Iterator[LectureHall]:
    running = LectureHall(CODE)
    running.app.share_store = SqliteShareStore(tmp_path / "shares.sqlite3")
    try:
        yield running
    finally:
        running.close()


def _played(hall: LectureHall, session: Any, title: str, frames: int = 90) -> None:
    session.select_scene(title)
    session.play()
    hall.frames(frames)
    session.pause()


def _same_moment(shared: Room, opened: Room) -> None:
    """The opened room's simulation is the shared one's, bit for bit, and it is paused."""
    expected = shared.fork()
    drop_caches(expected.sim)
    drop_caches(opened.sim)
    assert_same(expected.sim, opened.sim, "opened")
    assert opened.playing is False


def test_a_moment_shared_in_one_browser_opens_bit_for_bit_in_another(hall: LectureHall, tmp_path: Path) -> None:
    sharer, other = hall.join(), hall.join()
    _played(hall, sharer, "Heavy top")
    sharer.client.camera.position = (2.0, -3.0, 1.5)
    poll_until(lambda: tuple(sharer.client.camera.position) == (2.0, -3.0, 1.5))
    code = sharer.share.share()
    assert sharer.share.gui_code_shown.visible and code in sharer.share.gui_code_shown.content
    opened = other.share.open(code)
    assert opened is other.room and other.room.scene.title == "Heavy top" and other.error_count == 0
    _same_moment(sharer.room, other.room)
    assert tuple(other.client.camera.position) == (2.0, -3.0, 1.5)

    # The app restarted on the same data folder opens it too.
    data = tmp_path / "data"
    first = create_server("127.0.0.1", 0, verbose=False, start_loop=False, data_dir=data)
    kept = first.share_store.save(hall.app.share_store.load(code))  # type: ignore[union-attr]
    first.stop()
    second = create_server("127.0.0.1", 0, verbose=False, start_loop=False, data_dir=data)
    try:
        room, _camera = decode_moment(second.share_store.load(kept))  # type: ignore[union-attr]
        room.playing = False
        _same_moment(sharer.room, room)
    finally:
        second.stop()
    assert (data / "shares.sqlite3").is_file()


def test_a_follower_who_opens_a_code_explores_it_and_the_presenter_keeps_its_room(hall: LectureHall) -> None:
    sharer = hall.join()
    _played(hall, sharer, "Moving frame")
    code = sharer.share.share()
    shared = sharer.room  # the sharer follows the presenter from now on
    presenter = hall.join()
    presenter.select_scene("Free body")
    presenter.present(CODE)
    assert presenter.mode == "presenting"
    follower = hall.join()
    assert follower.mode == "following"
    hall.frames(10)
    before = fingerprint(presenter.room.sim)
    follower_code = follower.share.share()  # a follower shares what it sees: the presenter's room
    assert decode_moment(hall.app.share_store.load(follower_code))[0].scene.title == "Free body"  # type: ignore[union-attr]
    follower.share.open(code)
    assert follower.mode == "own" and follower.room.scene.title == "Moving frame"
    _same_moment(shared, follower.room)
    assert fingerprint(presenter.room.sim) == before and presenter.room.scene.title == "Free body"
    # The presenter opens one: the class sees it.
    presenter.share.open(follower_code)
    assert presenter.mode == "presenting" and presenter.room is hall.app.lectern.live_room
    assert presenter.room.scene.title == "Free body"


def test_malformed_unknown_and_hostile_codes_change_nothing(hall: LectureHall) -> None:
    from viser import _messages

    session, client = hall.join_with_client()
    _played(hall, session, "Poinsot", 30)
    room, before = session.room, fingerprint(session.room.sim)
    for text in ["hello", "ZZZZ-ZZZZ", "x" * 100_000, "\x00", "K7M2 QX9P"]:
        client.set_value(session.share.gui_code, text)
        poll_until(lambda text=text: session.share.gui_code.value == text, timeout=10.0)
        client.send(_messages.GuiUpdateMessage(session.share.gui_open._impl.uuid, {"value": True}))
        poll_until(lambda: session.share.gui_note.visible, timeout=10.0)
        note = session.share.gui_note.content
        assert "not a share code" in note or "No shared moment" in note, note
        session.share.gui_note.visible = False
    for value in (12345678, None, [1, 2], {"a": 1}, 1e308):
        client.set_value(session.share.gui_code, value)
    hall.frames(3)
    assert session.room is room and fingerprint(session.room.sim) == before and session.error_count == 0
