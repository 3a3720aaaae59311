"""The shared scene's messages as bytes and back (`encode_batch`, `decode_batch`, checked), culled
as viser culls (`cull`), and kept as a scene's state (`Replica`); the kit's room codec (`codec`)."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any, Protocol

import numpy as np

from app.kit.core.room import Room
from app.lecture.lectern import LIVE_ROOT
from app.viser_internals import message_from_dict

__all__ = ["ALLOWED", "BusError", "Replica", "SceneMessage", "codec", "cull", "decode_batch", "encode_batch",
           "removal", "tappable"]

MAX_DEPTH = 8  # nesting of a message dict
ALLOWED = frozenset({
    "FrameMessage", "BatchedAxesMessage", "GridMessage", "LabelMessage", "PointCloudMessage", "MeshMessage",
    "BoxMessage", "IcosphereMessage", "CylinderMessage", "GlbMessage", "BatchedMeshesMessage", "BatchedGlbMessage",
    "LineSegmentsMessage", "ArrowMessage", "CatmullRomSplineMessage", "CubicBezierSplineMessage", "ImageMessage",
    "RemoveSceneNodeMessage", "SetOrientationMessage", "SetPositionMessage", "SetSceneNodeVisibilityMessage",
    "SceneNodeUpdateMessage"})
"""The viser message types the bus carries: drawings of the shared scene (no gizmo, no panel)."""
DTYPES = frozenset({"<f4", "<f8", "|u1", "<u2", "<u4", "<i4", "|i1", "<i2", "<i8", "<u8", "|b1"})


class BusError(ValueError):
    """A bus message that is not what the bus sends (dropped, logged)."""


class SceneMessage(Protocol):
    """A viser message of the shared scene (one of ALLOWED types): its node's name, the key of
    the property it sets (`redundancy_key`), its serializable dict."""

    name: str

    def redundancy_key(self) -> str: ...

    def as_serializable_dict(self, binary_buffers: list[memoryview] | None = None) -> dict[str, Any]: ...


def live_name(name: object) -> bool:
    """`name` is LIVE_ROOT or a node under it."""
    return isinstance(name, str) and (name == LIVE_ROOT or name.startswith(LIVE_ROOT + "/"))


def tappable(message: object) -> bool:
    """`message` (anything viser queues) is an ALLOWED drawing under LIVE_ROOT."""
    return type(message).__name__ in ALLOWED and live_name(getattr(message, "name", None))


def removal(name: str) -> SceneMessage:
    """viser's message removing the node `name` (and its subtree)."""
    message: SceneMessage = message_from_dict({"type": "RemoveSceneNodeMessage", "name": name}, ALLOWED)
    return message


def encode_batch(messages: Iterable[SceneMessage]) -> tuple[list[dict[str, Any]], list[bytes], list[list[int]]]:
    """viser messages as (dicts, buffers, shapes): each `as_serializable_dict` with its numpy
    arrays as placeholders {"__binary_index": i, "dtype": ...} into `buffers` (raw bytes), each
    array's shape in `shapes`."""
    views: list[memoryview] = []
    dicts = [message.as_serializable_dict(views) for message in messages]
    return dicts, [bytes(view) for view in views], [list(view.shape or ()) for view in views]


def _restore(value: object, buffers: list[bytes], shapes: list[list[int]], depth: int = 0) -> object:
    """`value` with every buffer placeholder replaced by a flat numpy array (checked dtype)."""
    if depth > MAX_DEPTH:
        raise BusError("too deeply nested")
    if isinstance(value, dict):
        if "__binary_index" in value:
            index, dtype = value.get("__binary_index"), value.get("dtype")
            if not isinstance(index, int) or not 0 <= index < len(buffers) or dtype not in DTYPES:
                raise BusError(f"bad buffer placeholder {value!r}"[:200])
            data, shape = buffers[index], shapes[index]
            if not (isinstance(shape, list) and len(shape) <= 4 and all(isinstance(n, int) and n >= 0 for n in shape)
                    and int(np.prod(shape)) * np.dtype(dtype).itemsize == len(data)):
                raise BusError("a buffer's size does not fit its dtype and shape")
            return np.frombuffer(data, dtype=dtype).reshape(shape)
        return {key: _restore(item, buffers, shapes, depth + 1) for key, item in value.items()
                if isinstance(key, str)}
    if isinstance(value, list):
        return [_restore(item, buffers, shapes, depth + 1) for item in value]
    if isinstance(value, (str, int, float, bool, bytes)) or value is None:
        return value
    raise BusError(f"unexpected value of type {type(value).__name__}")


def decode_batch(dicts: object, buffers: object, shapes: object) -> list[SceneMessage]:
    """viser message objects from `encode_batch`'s output, read from Redis: only ALLOWED types,
    only nodes under LIVE_ROOT; BusError (nothing built) for anything else."""
    if not isinstance(dicts, list) or not isinstance(buffers, list) or not all(isinstance(b, bytes) for b in buffers) \
            or not isinstance(shapes, list) or len(shapes) != len(buffers):
        raise BusError("a scene batch is a list of messages, one of buffers and one of their shapes")
    out = []
    for mapping in dicts:
        if not isinstance(mapping, dict) or not live_name(mapping.get("name")):
            raise BusError(f"not a message under {LIVE_ROOT}: {str(mapping)[:120]}")
        try:
            out.append(message_from_dict(_restore(mapping, buffers, shapes), ALLOWED))  # type: ignore[arg-type]
        except ValueError as error:
            raise BusError(str(error)) from None
    return out


def cull(messages: list[SceneMessage]) -> list[SceneMessage]:
    """`messages` without the updates a later update of the same node and property supersedes
    (as viser's buffer culls; safe across a node's removal or re-creation in between: the
    earlier value belonged to the node that went)."""
    seen: set[str] = set()
    kept = []
    for message in reversed(messages):
        if getattr(message, "lifecycle_phase", None) in ("update_simple", "update_dict"):
            key = message.redundancy_key()
            if key in seen:
                continue
            seen.add(key)
        kept.append(message)
    kept.reverse()
    return kept


class Replica:
    """The shared scene's state under LIVE_ROOT, kept from its messages: each node's last create
    and the last value of each of its properties, in order (a late process's resync)."""

    def __init__(self) -> None:
        self.entries: dict[tuple[str, str], SceneMessage] = {}

    def _drop(self, name: str, subtree: bool) -> None:
        under = name + "/"
        for key in [k for k, m in self.entries.items()
                    if m.name == name or (subtree and m.name.startswith(under))]:
            del self.entries[key]

    def add(self, message: SceneMessage) -> None:
        phase, name = getattr(message, "lifecycle_phase", None), message.name
        if phase == "remove":
            self._drop(name, subtree=True)
        elif phase == "create":
            self._drop(name, subtree=False)
            self.entries[("c", name)] = message
        else:
            key = ("u", message.redundancy_key())
            if ("c", name) in self.entries or name == LIVE_ROOT:
                self.entries[key] = message

    def nodes(self) -> set[str]:
        return {name for kind, name in self.entries if kind == "c"}

    def messages(self) -> list[SceneMessage]:
        return list(self.entries.values())


EncodeRoom = Callable[..., bytes]
DecodeRoom = Callable[[bytes], Room]


def codec() -> tuple[EncodeRoom, DecodeRoom]:
    """(encode_room, decode_room) of the kit's codec; RuntimeError naming what is missing."""
    try:
        from app.codec import decode_room, encode_room  # noqa: PLC0415 - only Explore across processes
    except ImportError as error:
        raise RuntimeError(f"Explore on another process needs the room codec (app.codec): {error}") from None
    return encode_room, decode_room
