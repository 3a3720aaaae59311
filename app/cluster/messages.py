"""What the app's processes put on Redis, one schema: every message and value as a `msgspec.Struct`.

Each is msgpack on the wire (bytes carry buffers and encoded rooms as they are) and is read back
with its type (`LIVE_DECODER`, `ASK_DECODER`, `decode`): types, names and bounds are checked on decode, and
anything else raises `msgspec.DecodeError` (a `msgspec.ValidationError` for a wrong type); the
reader drops it with a log line and changes nothing.  The short wire names (`"w"`, `"k"`, ...)
are kept from the dicts these replaced.

- The lecture bus (`app.lecture.bus`): on CHANNEL, the source's `SceneBatch`, `HallState`,
  `Camera`, `Plot`, `CallBack`, `RoomAnswer`, `Keep` (the union `Live`); on ASK, any process's
  `Resync` and `Explore` (the union `Ask`); tagged by "k", each with its sender's worker id "w".
  Under keys: each worker's `Audience` (with its followers' `ScreenShape`s) and the `LastRoom`.
- The questions' bus (`app.cluster.askbus`): the source's `ShownRound`, each `SentAnswer`, each
  `EarlierRound`.

What a value means beyond its type (a viser message's dict, a chart's properties, a question's
dict, an answer) is checked where it is used (`app.lecture.bus.wire.decode_batch`,
`app.lecture.bus.values`, `app.ask.questions.question_from_dict`, the round's checks).
No project imports here (the lowest layer).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, TypeVar

import msgspec
from msgspec import Meta, Struct, field

__all__ = ["ASK_DECODER", "LIVE_DECODER", "Ask", "Audience", "CallBack", "Camera", "Chart", "EarlierRound", "Explore",
           "HallState", "Keep", "LastRoom", "Live", "Markdown", "Plot", "Resync", "RoomAnswer", "SceneBatch",
           "ScreenShape", "SentAnswer", "ShownRound", "decode", "encode"]

Finite = Annotated[float, Meta(ge=-1e12, le=1e12)]
"""A finite float (NaN and ±inf fail both bounds)."""
Vec3 = tuple[Finite, Finite, Finite]
LectureId = Annotated[str, Meta(max_length=64)]
RequestId = Annotated[str, Meta(min_length=1, max_length=64)]
Pixels = Annotated[int, Meta(gt=0, le=16384)]
Count = Annotated[int, Meta(ge=0)]
HallName = Literal["empty", "live", "stopped", "left"]
"""`app.lecture.follower.Hall`'s values (tests/test_bus.py checks they are the same)."""
MAX_PLOT_ELEMENTS = 16  # a plot tab's elements, carried
MAX_PLOT_COLUMNS = 16  # a chart's columns (x and its series)
MAX_MARKDOWN = 20_000  # characters of a plot tab's Markdown


class Message(Struct, tag_field="k", kw_only=True):
    """A message of the lecture bus: its kind ("k", the tag) and its sender's worker id."""

    worker: str = field(name="w")


# ---------------------------------------------------------------------- CHANNEL: the source to every process
class SceneBatch(Message, tag="scene"):
    """One frame's messages of the source's shared scene (or its whole state: `full`).

    `messages`: viser's message dicts (`Message.as_serializable_dict`, buffers as placeholders;
    checked by `decode_batch`); `buffers` their arrays' bytes, `shapes` each array's shape.
    `full`: None for a frame's batch; "*" or the workers that asked for a resync for a whole
    state.  `sent_at`: the source's `time.time()` [s]; `shown_t`: its room's time [s]."""

    seq: int = field(name="s")
    messages: list[dict[str, Any]] = field(name="m")
    buffers: list[bytes] = field(name="b")
    shapes: list[list[Count]] = field(name="sh")
    full: Literal["*"] | list[str] | None = None
    sent_at: float | None = field(name="t", default=None)
    title: str = ""
    lecture: LectureId = field(name="lid", default="")
    shown_t: Finite | None = field(name="st", default=None)


class HallState(Message, tag="hall"):
    """The hall's state: what the shared screen shows, the scene's title, the followers' status
    (`status`: `app.lecture.follower.FollowerStatus.to_dict`'s plain values, checked where it is
    read, `FollowerStatus.from_dict`; {} for none said) and the lesson caption (head, words)."""

    hall: HallName
    title: str = ""
    status: dict[str, Any] = field(default_factory=dict)
    caption: tuple[str, str] = ("", "")


class Camera(Message, tag="camera"):
    """The presenter's camera: position, look_at, up [scene units], fov [rad], aspect [width / height]."""

    position: Vec3
    look_at: Vec3
    up: Vec3
    fov: Annotated[float, Meta(gt=0.0, lt=3.2)]
    aspect: Annotated[float, Meta(gt=0.0, lt=100.0)]


class Markdown(Struct, tag="markdown", array_like=True):
    """A plot tab's Markdown element: ["markdown", text]."""

    text: Annotated[str, Meta(max_length=MAX_MARKDOWN)]


class Chart(Struct, tag="uplot", array_like=True):
    """A plot tab's uPlot chart: ["uplot", {property: plain value}, [float32 column bytes]]
    (the properties' names and values checked by `app.lecture.bus.values.plot_from_message`)."""

    props: dict[str, Any]
    columns: Annotated[list[bytes], Meta(min_length=1, max_length=MAX_PLOT_COLUMNS)]


class Plot(Message, tag="plot"):
    """The presenter's open plot tab and its elements ("" and none: no plot tab open)."""

    tab: str
    elements: Annotated[list[Markdown | Chart], Meta(max_length=MAX_PLOT_ELEMENTS)] = field(name="el")


class CallBack(Message, tag="call_back"):
    """The presenter calls everyone back."""


class RoomAnswer(Message, tag="room"):
    """The source's answer to Explore requests: the room under ROOM_KEY + `number`, or an error."""

    requests: list[str] = field(name="for")
    number: int | None = field(name="n", default=None)
    error: str | None = None


class Keep(Message, tag="keep"):
    """The source's room without history (`encode_room(history=False)`) at its time `shown_t`
    [s]; `running`: live and playing."""

    lecture: LectureId = field(name="lid")
    room: bytes
    shown_t: Finite = field(name="st")
    running: bool = field(name="run", default=False)


# ---------------------------------------------------------------------- ASK: any process to the source
class Resync(Message, tag="resync"):
    """Send your whole state (to the source `to`; None: the one the asker follows)."""

    to: str | None = None


class Explore(Message, tag="explore"):
    """Send your live room (the answer: a `RoomAnswer` naming `request`)."""

    request: RequestId = field(name="r")


Live = SceneBatch | HallState | Camera | Plot | CallBack | RoomAnswer | Keep
Ask = Resync | Explore
LIVE_DECODER: msgspec.msgpack.Decoder[Live] = msgspec.msgpack.Decoder(Live)
ASK_DECODER: msgspec.msgpack.Decoder[Ask] = msgspec.msgpack.Decoder(Ask)


# ---------------------------------------------------------------------- values under keys
class ScreenShape(Struct, array_like=True):
    """A follower's kind of screen: its camera (position, look_at, up [scene units], fov [deg]),
    its canvas [px] and its panel's rectangle [px] (x0, y0, x1, y1) or None."""

    position: Vec3
    look_at: Vec3
    up: Vec3
    fov_deg: Annotated[float, Meta(gt=0.0, lt=180.0)]
    width: Pixels
    height: Pixels
    panel: tuple[Finite, Finite, Finite, Finite] | None


class Audience(Struct, array_like=True):
    """One worker's audience (AUDIENCE_KEY): its followers and explorers, when [s, `time.time()`],
    its followers' kinds of screen."""

    following: Count
    exploring: Count
    time_s: Finite
    screens: list[ScreenShape]


class LastRoom(Struct, array_like=True):
    """The room a lecture left on the shared screen (LAST_KEY): its lecture id, `encode_room`'s bytes."""

    lecture: LectureId
    data: bytes


class ShownRound(Struct, kw_only=True):
    """The source's question round as every browser sees it (ROUND_KEY; `app.ask.hub.Shown`):
    its worker, id, the question's dict, number, open, revealed, answers counted, owner."""

    worker: str = field(name="w")
    id: Annotated[str, Meta(min_length=1, max_length=64)]
    question: dict[str, Any] = field(name="q")
    number: int = field(name="n")
    open: bool
    revealed: bool
    answered: Count = 0
    owner: Annotated[str, Meta(max_length=200)] = field(name="o", default="")


class SentAnswer(Struct, array_like=True):
    """A browser's answer on another worker (ANSWERS_KEY + round id): its token and its value
    (checked by the round's question)."""

    token: str
    value: Any


class EarlierRound(Struct, array_like=True):
    """A round that ended on some worker (EARLIER_KEY): its id and its CSV section."""

    id: str
    section: str


T = TypeVar("T")


def encode(value: Struct) -> bytes:
    """`value` as msgpack (what goes onto Redis)."""
    return msgspec.msgpack.encode(value)


def decode(data: bytes, kind: type[T]) -> T:
    """`data` read back as a `kind`; `msgspec.DecodeError` (or its `ValidationError`) for anything else."""
    return msgspec.msgpack.decode(data, type=kind)
