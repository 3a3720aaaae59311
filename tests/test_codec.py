"""app.codec: a room as bytes and back, exact for every scene and preset, and hostile bytes refused.

Each case is `tests/test_fork.py`'s played and edited room.  Its bytes decode to a room equal to
a fork of it (field by field, bit for bit; the generated kernels a stepper caches are the only
fields left out, `app.codec.CACHE_FIELDS`), and the decoded room and the fork, advanced by the
same frames, stay equal, traces, plots and history included.
"""

from __future__ import annotations

import math
from typing import Any

import msgspec
import numpy as np
import pytest
import viser

from app.codec import CACHE_FIELDS, MAX_BYTES, MAX_DEPTH, CodecError, decode_room, encode_room
from app.kit.core.room import Room
from app.scenes import SCENES, simulation_class, simulation_parts
from app.scenes.euler_angles.view import RateArrow
from app.scenes.moving_frame.simulation import MovingFrameSetup
from tests.test_fork import (
    CASES,
    DT,
    EDITS,
    TIME_SCALE,
    _played_room,
    assert_equal_values,
    assert_same,
    build_view,
    picture,
    play,
)

FRAMES = 40  # before the edit, after it, and after the decoding: traces, plots and history all hold rows

SIZES: dict[str, int] = {}


def drop_caches(root: Any) -> None:
    """Empty the caches `app.codec` does not carry, everywhere in `root`'s graph (they are made
    again on first use; the numbers do not depend on them)."""
    seen: set[int] = set()
    stack = [root]
    while stack:
        obj = stack.pop()
        if id(obj) in seen or isinstance(obj, str | bytes | int | float | np.ndarray | np.generic | type(None)):
            continue
        seen.add(id(obj))
        rules = CACHE_FIELDS.get(type(obj))
        if rules:
            for name, rebuild in rules.items():
                object.__setattr__(obj, name, rebuild(obj))
        if isinstance(obj, list | tuple | set | frozenset):
            stack.extend(obj)
        elif isinstance(obj, dict):
            stack.extend(obj.values())
        elif not callable(obj):
            stack.extend(getattr(obj, "__dict__", {}).values())
            for cls in type(obj).__mro__:
                stack.extend(getattr(obj, s) for s in getattr(cls, "__slots__", ()) if hasattr(obj, s))


def assert_rooms_equal(a: Room, b: Room, where: str) -> None:
    drop_caches((a.sim, a.history, a._live))
    drop_caches((b.sim, b.history, b._live))
    assert a.scene is b.scene
    assert (a.playing, a.time_scale, a._since_sample, a._live_playing) == (
        b.playing, b.time_scale, b._since_sample, b._live_playing), where
    assert_same(a.sim, b.sim, f"{where}.sim")
    assert_same((a.history, a._live, a._live_phase), (b.history, b._live, b._live_phase), f"{where}.history")


def advance(room: Room, frames: int) -> None:
    for _ in range(frames):
        room.advance(DT)


@pytest.mark.parametrize(("title", "index", "preset"), CASES)
def test_a_decoded_room_is_the_fork_and_goes_on_identically(server: viser.ViserServer, title: str, index: int,
                                                           preset: str) -> None:
    """test_fork's case, shorter and with the view drawing only where an edit needs it."""
    scene = SCENES[title]
    room = Room(scene, scene.new_simulation())
    view = build_view(server, room)
    scene.apply_preset(room, preset)
    room.set_time_scale(TIME_SCALE)
    room.play()
    advance(room, FRAMES)
    EDITS[title](room, view, index)
    room.play()
    advance(room, FRAMES + 3)  # mid sampling period
    view.remove()
    data = encode_room(room)
    SIZES[f"{title}/{preset}"] = len(data)
    fork = room.fork()
    decoded = decode_room(data)
    assert decoded.views == [] and decoded.scene is room.scene
    assert_rooms_equal(fork, decoded, f"{title}/{preset}")
    assert encode_room(decoded) == data  # the same bytes again

    advance(fork, FRAMES)
    advance(decoded, FRAMES)
    assert_rooms_equal(fork, decoded, f"{title}/{preset} played on")
    if decoded.history is not None and decoded.stretch() is not None:
        first, live = decoded.stretch()  # type: ignore[misc]
        for r in (fork, decoded):
            r.scrub(0.5 * (first + live))
        assert_rooms_equal(fork, decoded, f"{title}/{preset} scrubbed")
        for r in (fork, decoded):
            r.resume()
        assert_rooms_equal(fork, decoded, f"{title}/{preset} resumed")


@pytest.mark.parametrize("title", ["Heavy top", "Moving frame"])
def test_a_decoded_room_draws_what_the_original_draws(server: viser.ViserServer, title: str) -> None:
    room, view = _played_room(server, title, 0, SCENES[title].presets()[0].name)
    decoded = decode_room(encode_room(room))
    decoded_view = build_view(server, decoded)
    view.refresh()
    assert_equal_values(picture(view), picture(decoded_view), f"{title} drawn")
    play(room, 30)
    play(decoded, 30)
    assert_equal_values(picture(view), picture(decoded_view), f"{title} drawn, played on")
    for v in (view, decoded_view):
        v.remove()


@pytest.mark.parametrize("method", ["adaptive", "dop853", "splitting4", "free_kick", "exact", "euler_lagrange"])
def test_every_integrator_of_a_top_is_carried(method: str) -> None:
    scene = SCENES["Heavy top"]
    room = Room(scene, scene.new_simulation())
    room.play()
    advance(room, 10)
    room.sim.set_integrator(method)
    advance(room, 20)
    assert room.sim.integrator == method
    fork, decoded = room.fork(), decode_room(encode_room(room))
    assert_rooms_equal(fork, decoded, method)
    advance(fork, 20)
    advance(decoded, 20)
    assert_rooms_equal(fork, decoded, f"{method} played on")


def test_without_history_the_shown_moment_comes_back_live(server: viser.ViserServer) -> None:
    room, view = _played_room(server, "Heavy top", 0, SCENES["Heavy top"].presets()[0].name)
    first, live = room.stretch()  # type: ignore[misc]
    room.scrub(0.5 * (first + live))
    light = encode_room(room, history=False)
    assert len(light) < len(encode_room(room))
    decoded = decode_room(light)
    assert decoded.mode == "live" and decoded.sim.t == room.shown_t and room.mode == "scrubbing"
    branched = room.fork()
    branched.branch()
    drop_caches(branched.sim)
    assert_same(branched.sim, decoded.sim)
    view.remove()


def test_a_room_with_a_users_mesh_is_exact(server: viser.ViserServer) -> None:
    from app.scenes.inertia import MESHES_DIR, read_mesh

    path = next(iter(sorted(MESHES_DIR.glob("*.stl"))))
    vertices, faces = read_mesh(path.name, path.read_bytes())[:2]
    free = Room(SCENES["Free body"], SCENES["Free body"].new_simulation())
    free.sim.mesh = (np.array(vertices), np.array(faces))
    for a in free.sim.mesh:
        a.flags.writeable = False
    free.play()
    play(free, 30)
    decoded = decode_room(encode_room(free))
    assert all(not a.flags.writeable for a in decoded.sim.mesh)
    assert_rooms_equal(free.fork(), decoded, "mesh")


# ---------------------------------------------------------------------------- hostile bytes
def _room_bytes() -> bytes:
    scene = SCENES["Free body"]
    room = Room(scene, scene.new_simulation())
    room.play()
    for _ in range(20):
        room.advance(1 / 60)
    return encode_room(room)


def _tree() -> list[Any]:
    return msgspec.msgpack.decode(_room_bytes())


def _find(node: Any, tag: str) -> list[Any] | None:
    if isinstance(node, list):
        if node and node[0] == tag:
            return node
        for item in node:
            found = _find(item, tag)
            if found is not None:
                return found
    elif isinstance(node, dict):
        for item in node.values():
            found = _find(item, tag)
            if found is not None:
                return found
    return None


def _mutated(change: Any) -> bytes:
    tree = _tree()
    change(tree)
    return msgspec.msgpack.encode(tree)


def _set(tag: str, index: int, value: Any) -> Any:
    def change(tree: list[Any]) -> None:
        node = _find(tree, tag)
        assert node is not None
        node[index] = value
    return change


def _nested(depth: int) -> bytes:
    node: Any = 1.0
    for _ in range(depth):
        node = ["l", [node]]
    tree = _tree()
    tree[3]["sim"][2]["preset"] = node
    return msgspec.msgpack.encode(tree)


HOSTILE = {
    "empty": b"",
    "garbage": b"\x93\xff\x00garbage",
    "not a room": msgspec.msgpack.encode(["hello", 1, "Free body", {}]),
    "a pickle": b"\x80\x04\x95\x0c\x00\x00\x00\x00\x00\x00\x00\x8c\x02os\x94\x8c\x06system\x94\x93\x94.",
    "unknown scene": _mutated(lambda t: t.__setitem__(2, "Rocket")),
    "unknown tag": _mutated(lambda t: t[3].__setitem__("sim", ["x", 1])),
    "class outside the allowlist": _mutated(_set("o", 1, "os:_wrap_close")),
    "builtin class": _mutated(_set("o", 1, "builtins:object")),
    "function outside the allowlist": _mutated(lambda t: t[3]["sim"][2].__setitem__("preset", ["F", "os:system"])),
    "closure outside the allowlist": _mutated(lambda t: t[3]["sim"][2].__setitem__(
        "preset", ["f", "builtins:eval", None, None, ["l", []]])),
    "object dtype": _mutated(_set("a", 1, "object")),
    "wrong array size": _mutated(_set("a", 2, [3, 3, 3])),
    "huge array shape": _mutated(_set("a", 2, [2**40, 2**40])),
    "method shadowed": _mutated(lambda t: t[3]["sim"][2].__setitem__("advance", 1.0)),
    "dunder field": _mutated(lambda t: t[3]["sim"][2].__setitem__("__class__", 1.0)),
    "dangling reference": _mutated(lambda t: t[3]["sim"][2].__setitem__("preset", ["r", 10**6])),
    "deep nesting": _nested(MAX_DEPTH + 5),
    "very deep nesting": b"\x91" * 100_000 + b"\xc0",
    "wrong simulation class": _mutated(lambda t: t[3].__setitem__("sim", ["l", []])),
    "NaN time scale": _mutated(lambda t: t[3].__setitem__("time_scale", math.nan)),
    "a field of the wrong type": _mutated(lambda t: t[3]["sim"][2].__setitem__("state", "not a state")),
    "a missing field": _mutated(lambda t: t[3]["sim"][2].pop("samples")),
    "too long": b"\x00" * (MAX_BYTES + 1),
}


@pytest.mark.parametrize("name", list(HOSTILE))
def test_hostile_bytes_are_refused_with_a_clear_message(name: str) -> None:
    with pytest.raises(CodecError) as caught:
        decode_room(HOSTILE[name])
    assert str(caught.value), name


def test_what_a_room_cannot_hold_is_refused_when_encoded() -> None:
    scene = SCENES["Free body"]
    room = Room(scene, scene.new_simulation())
    room.sim.preset = lambda: None  # a lambda of this test: not the app's code
    with pytest.raises(CodecError, match="not one of the allowlisted"):
        encode_room(room)
    room.sim.preset = object()
    with pytest.raises(CodecError, match="not in the codec's allowlist"):
        encode_room(room)


NOT_A_PART = "app.scenes.euler_angles.view:RateArrow"  # an app class of a scene, which no simulation is made of


def test_a_class_no_scene_declares_is_refused_naming_the_rule() -> None:
    """The codec's classes come from the registry (`app.scenes.simulation_parts`), not from a module's
    path: a class of a scene's package that no scene's simulation is made of is refused, and the
    message says where a scene declares what its simulation holds."""
    assert RateArrow not in {part for scene in SCENES.values() for part in simulation_parts(scene)}
    with pytest.raises(CodecError, match=r"RateArrow.*simulation_parts"):
        decode_room(_mutated(_set("o", 1, NOT_A_PART)))
    scene = SCENES["Free body"]
    room = Room(scene, scene.new_simulation())
    room.sim.preset = object.__new__(RateArrow)
    with pytest.raises(CodecError, match=r"not in the codec's allowlist.*simulation_parts"):
        encode_room(room)


def test_each_scenes_parts_are_derived_from_the_simulation_it_makes() -> None:
    """No scene lists its simulation's classes: the class of the simulation it makes and its module's
    classes are its parts; what a scene declares (Heavy top's and Poinsot's traced points) is added."""
    for scene in SCENES.values():
        parts = simulation_parts(scene)
        assert type(scene.new_simulation()) is simulation_class(scene) and simulation_class(scene) in parts
        assert set(scene.simulation_parts) <= set(parts), scene.title
    assert MovingFrameSetup in simulation_parts(SCENES["Moving frame"])  # same module as its simulation class


def test_sizes_per_scene(capsys: pytest.CaptureFixture[str]) -> None:
    """Prints the encoded size of each case above (run after them: `-k codec`)."""
    with capsys.disabled():
        for name, size in sorted(SIZES.items()):
            print(f"\n  {name}: {size / 1024:.0f} kB", end="")
