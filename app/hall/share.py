"""The `Share` folder of one browser's panel: a short code for exactly what is on screen, and
`Open a shared moment` for a code someone gave.

A moment is the room shown (`app.codec.encode_room` without the replay history: scene, preset,
parameters, state and time bit for bit, traces and plots so far; the moment on screen if the
room shows the past) and this browser's camera, kept in the app's `ShareStore`
(`app.sharestore`: SQLite in the data folder, Redis on several processes) under a code like
`K7M2-QX9P` for 30 days.  Opening a code shows that moment paused, seen from the camera it was
shared with: in this browser's own room; a presenter's screen shows it to the class; a follower
leaves the presenter and explores it (nothing a follower does changes the shared screen).

The code alone travels: viser's page keeps its address's query to itself (its websocket asks
for `/`), so a link cannot carry it to the server; the folder says where to type it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import msgspec
import viser

from app.codec import CodecError, decode_room, encode_room
from app.i18n import N_, Labels, Translator, for_gui, refusal_text
from app.kit.core.common import Wrap
from app.kit.core.room import Room
from app.sharestore import EXAMPLE, ShareCodeError, ShareStore, format_code

__all__ = ["Camera", "SharePanel", "decode_moment", "encode_moment"]

MOMENT_MAGIC = "rigid-body-lab moment"
MOMENT_VERSION = 1

Camera = dict[str, Any]
"""position, look_at, up_direction: (3,) in the world frame [m]; fov: vertical field of view [rad]."""

_VECTORS = ("position", "look_at", "up_direction")


def encode_moment(room: Room, camera: Camera | None) -> bytes:
    """The room shown (no history) and the camera, as bytes (msgpack: magic, version, room, camera)."""
    return msgspec.msgpack.encode([MOMENT_MAGIC, MOMENT_VERSION, encode_room(room, history=False), camera])


def decode_moment(data: bytes) -> tuple[Room, Camera | None]:
    """(room, camera) from `encode_moment`'s bytes; CodecError naming what is wrong otherwise."""
    try:
        top = msgspec.msgpack.decode(data)
    except (msgspec.DecodeError, RecursionError, ValueError, TypeError) as exc:
        raise CodecError(f"not a shared moment: {exc}") from None
    if type(top) is not list or len(top) != 4 or top[0] != MOMENT_MAGIC or top[1] != MOMENT_VERSION:
        raise CodecError("not a shared moment of this app")
    room_bytes, camera = top[2], top[3]
    if type(room_bytes) is not bytes:
        raise CodecError("a shared moment without its room")
    return decode_room(room_bytes), _camera(camera)


def _camera(value: Any) -> Camera | None:
    if value is None:
        return None
    if type(value) is not dict or set(value) != {*_VECTORS, "fov"}:
        raise CodecError("the shared camera is not a camera")
    out: Camera = {}
    for name in _VECTORS:
        vector = value[name]
        if type(vector) is not list or len(vector) != 3 or not all(
                type(x) in (int, float) and math.isfinite(x) for x in vector):
            raise CodecError(f"the shared camera's {name} is not 3 finite numbers")
        out[name] = tuple(float(x) for x in vector)
    fov = value["fov"]
    if type(fov) not in (int, float) or not 0.0 < fov < math.pi:
        raise CodecError("the shared camera's field of view is not an angle in (0, π)")
    out["fov"] = float(fov)
    return out


def camera_of(client: viser.ClientHandle) -> Camera:
    """The browser's camera now (as `Camera`)."""
    camera = client.camera
    return {"position": [float(x) for x in camera.position], "look_at": [float(x) for x in camera.look_at],
            "up_direction": [float(x) for x in camera.up_direction], "fov": float(camera.fov)}


class SharePanel:
    """The `Share` folder.

    Args:
        client: the browser.  guard: its session's guard (callbacks run in it).
        store: where codes are kept.  room: the room the browser shows now (a follower's: the
        presenter's).  open_room(room, camera): shows an opened moment (`Session.open_moment`).

    Attributes:
        folder, gui_share, gui_code_shown, gui_code, gui_open, gui_note: its widgets.
        last_code: the code this browser shared last (as shown, `K7M2-QX9P`), or None.
    """

    def __init__(self, client: viser.ClientHandle, guard: Wrap, store: ShareStore, room: Callable[[], Room],
                 open_room: Callable[[Room, Camera | None], None]) -> None:
        self.client = client
        self.store = store
        self._room = room
        self._open_room = open_room
        self.last_code: str | None = None
        gui = client.gui
        self.folder = gui.add_folder(N_("Share"), expand_by_default=False)
        with self.folder:
            self.gui_share = gui.add_button(N_("Share"), icon=viser.Icon.SHARE,
                                            hint=N_("a short code for exactly what is on screen, "
                                                    "which anyone on this app can open (kept 30 days)"))
            self.gui_code_shown = gui.add_markdown("", visible=False)
            self.gui_code = gui.add_text(N_("Shared code"), "", hint=N_("a code someone shared, like {example}"))
            self.gui_open = gui.add_button(N_("Open a shared moment"), icon=viser.Icon.FOLDER_OPEN,
                                           hint=N_("show the moment of the code above, paused, as it was shared"))
            self.gui_note = gui.add_markdown("", visible=False)
        self.words = Labels(gui)
        self.words.take(self.folder, self.gui_share, self.gui_code, self.gui_open, example=EXAMPLE)
        self.gui_share.on_click(guard("Share", lambda _event: self.share()))
        self.gui_open.on_click(guard("Open a shared moment", lambda _event: self.open(self.gui_code.value)))

    def relabel(self, tr: Translator) -> None:
        """The folder's words in `tr`'s language (the browser chose another); the code shown said again."""
        self.words.relabel(tr)
        if self.last_code is not None and self.gui_code_shown.visible:
            self.gui_code_shown.content = self._code_words(self.last_code)

    def _code_words(self, code: str) -> str:
        return for_gui(self.client.gui).gettext(
            "Code **{code}**: anyone on this app types it in *Shared code* below and presses "
            "*Open a shared moment* (kept 30 days).").format(code=code)

    def _say(self, text: str) -> None:
        self.gui_note.content = text
        self.gui_note.visible = bool(text)

    def share(self) -> str:
        """Keep what is on screen; its code (as shown), also written in the folder."""
        room = self._room()
        with room.lock:
            data = encode_moment(room, camera_of(self.client))
        code = format_code(self.store.save(data))
        self.last_code = code
        self.gui_code_shown.content = self._code_words(code)
        self.gui_code_shown.visible = True
        self._say("")
        return code

    def open(self, text: Any) -> Room | None:
        """Show the moment of the code in `text`; a code that opens nothing is said in the folder
        and nothing changes (None)."""
        try:
            data = self.store.load(text)
        except ShareCodeError as error:
            self._say(refusal_text(error, for_gui(self.client.gui)))
            return None
        try:
            room, camera = decode_moment(data)
        except CodecError as error:
            self._say(for_gui(self.client.gui).gettext("This moment cannot be opened by this app ({error}).")
                      .format(error=error))
            return None
        room.playing = False  # shown paused at the moment, as shared
        self._open_room(room, camera)
        self._say("")
        return room

    def set_camera(self, camera: Camera | None) -> None:
        """Look from the camera a moment was shared with."""
        if camera is None:
            return
        with self.client.atomic():
            self.client.camera.up_direction = camera["up_direction"]
            self.client.camera.position = camera["position"]
            self.client.camera.look_at = camera["look_at"]
            self.client.camera.fov = camera["fov"]
