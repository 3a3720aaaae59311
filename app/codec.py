"""A room's state as bytes and back: `encode_room(room) -> bytes`, `decode_room(data) -> Room`.

What it is for: an explorer's copy of a room made in another process (`Explore on my own`
across processes, through Redis) and a shared moment kept in a store (`Share`).  A decoded
room is what `Room.fork()` makes: the same scene, simulation (state bit for bit, time,
initial conditions, integrator and its internal state, plot samples, traces, preset,
version), transport (playing, time scale, sampling phase) and, unless left out, the replay
history and the moment shown (a room showing the past comes back showing it).  Advancing the
original and the decoded room by the same dt sequence gives the same states bit for bit
(`tests/test_codec.py`, every scene and preset).

The format: msgpack (msgspec) of one tagged tree, `[MAGIC, FORMAT_VERSION, scene title,
{room fields}]`.  Plain values (None, bool, int, float64, str) are msgpack's own; everything else
is a list whose first item is a tag:

- `["l", items]` list, `["u", items]` tuple, `["d", [k0, v0, k1, v1, ...]]` dict,
  `["s", items]` set, `["z", items]` frozenset, `["y", raw]` bytes;
- `["a", dtype, shape, raw, writeable]` a NumPy array: dtype from `DTYPES` (little-endian), its
  shape and raw C-ordered bytes; `["g", dtype, raw]` a NumPy scalar;
- `["o", class, {field: value}]` an object of a class of the allowlist (named `module:qualname`):
  the classes of `ALLOWED_MODULES` (the kit's core, `physics`) and those each scene's simulation
  is made of (`app.scenes.simulation_parts`: the classes of its simulation class's module and what
  the scene declares), built with `object.__new__` and its fields set (no `__init__`, no
  `__setstate__`, nothing else of the data is run);
- `["F", name]` a function of the allowlist (defined at the top level of an allowlisted module, or
  declared by a scene; the app's own object); `["f", name, defaults, kwdefaults, cells]` a
  closure: the code object comes from the allowlisted code (found through its functions'
  constants when the codec is imported), only the values its cells hold come from the data;
- `["r", n]` the n-th object built so far (shared objects stay shared: a stepper that both the
  simulation and the history's snapshots hold is one object after decoding, as after a fork).

Never pickle, never eval/exec, never import by a name read from the data: a class or function
not in the allowlist, an unknown tag, a dtype outside `DTYPES`, an array whose bytes do not fit its
shape, nesting deeper than MAX_DEPTH, more than MAX_NODES values or data longer than MAX_BYTES
raise `CodecError` with what was wrong, and nothing is built.  The scene comes from the app's
registry (`app.scenes.SCENES`) by title, and the decoded simulation must be of the class that
scene makes.

Caches are not carried: `CACHE_FIELDS` names the fields an object rebuilds on its own
(`physics.realtime.RealtimeStepper`'s generated kernels, made again on first use from the
same numbers; its state builder, made again at decoding from its splitting).  Generated code
is never encoded.

Sizes and costs, measured for each scene's first preset after 60 s of simulated time (the
replay history full), this 2-core machine under load (median of 5; `encode_room`, then
`decode_room` with and without the history):

| scene | with history | without | encode [ms] | decode [ms] | decode without [ms] |
|---|---|---|---|---|---|
| Euler angles | 137 kB | 0.5 kB | 3-15 | 13 | 0.1 |
| Inertia | 0.5 kB | 0.5 kB | 0.1 | 0.1 | 0.1 |
| Free body | 1.2 MB | 176 kB | 6-16 | 15-24 | 1.1 |
| Heavy top | 1.3 MB | 245 kB | 17-21 | 16-19 | 6-16 |
| Poinsot | 1.3 MB | 273 kB | 18-43 | 18-25 | 1.4-11 |
| Moving frame | 0.8 MB | 207 kB | 12-25 | 13-30 | 1.2 |
| Constrained particles | 64 kB | 64 kB | 0.8 | 1-2 | 1-2 |

The history is bounded by `app.kit.core.history.HISTORY_BYTES` (5 MB of snapshots) and 60 s;
the rest is the simulation's own bounded rings (plot window, traces, their rewind spare).  A
body's own mesh adds its arrays (24 bytes a vertex, 24 a face).
"""

from __future__ import annotations

import abc
import importlib
import math
import pkgutil
import sys
import types
from collections.abc import Callable, Iterable
from typing import Any

import msgspec
import numpy as np

import app.kit.core.history as _history
import app.kit.core.samples as _samples
import app.kit.core.trace as _trace
import app.kit.rigid.simulation as _rigid_simulation
import physics
import physics.dynamics as _dynamics
import physics.realtime
import physics.splitting
from app.kit.core.history import History, Snapshot
from app.kit.core.room import Room
from app.scenes import SCENES, simulation_class, simulation_parts

__all__ = ["CACHE_FIELDS", "DTYPES", "FORMAT_VERSION", "MAX_BYTES", "MAX_DEPTH", "MAX_NODES", "CodecError",
           "decode_room", "encode_room"]

MAGIC = "rigid-body-lab room"
FORMAT_VERSION = 1
MAX_BYTES = 64 * 1024 * 1024  # [bytes] the longest data decoded (a room with a big mesh is ~10 MB)
MAX_DEPTH = 40  # nested containers at most (a room needs ~12)
MAX_NODES = 2_000_000  # values at most (a room with history: ~20,000)
MAX_DIMS = 6  # array dimensions at most
DTYPES = ("float64", "float32", "int64", "int32", "int16", "int8", "uint64", "uint32", "uint16", "uint8", "bool",
          "complex128")
"""The array and scalar dtypes a room may hold (little-endian)."""

_NOT_ALLOWED = ("__main__", "casefile", "meshfile")  # physics' command line and file readers: no room holds them

ALLOWED_MODULES: tuple[types.ModuleType, ...] = (
    _history, _samples, _trace, _rigid_simulation,
    *(importlib.import_module(f"physics.{info.name}") for info in pkgutil.iter_modules(physics.__path__)
      if info.name not in _NOT_ALLOWED),
)
"""The modules whose classes and functions every room may hold: the kit's core and every module of
`physics` (listed from the package when the codec is imported, never from the data)."""

SCENE_PARTS: dict[type | Callable[..., Any], str] = {
    part: scene.title for scene in SCENES.values() for part in simulation_parts(scene)}
"""The classes and functions a scene's simulation is made of -> a scene's title: learnt from the
registry (`app.scenes.simulation_parts`: the classes of the module of the class its simulation is,
and what the scene declares in `simulation_parts`), never from a module's path."""

REFUSED = ("a scene's simulation holds the kit's core, physics, the classes of its own class's module "
           "and what its scene declares in `simulation_parts` (app.scenes.simulation_parts)")
"""The rule an encoding or decoding error names when a class or function is outside the allowlist."""


def _rebuild_state_maker(stepper: Any) -> Any:
    splitting = getattr(stepper, "_sp", None)
    if type(splitting) is not physics.splitting.Splitting:  # built by its constructor (CONSTRUCTED)
        raise CodecError("a real-time stepper without its splitting")
    return physics.splitting.state_builder(splitting)


CONSTRUCTED: dict[type, tuple[tuple[str, ...], Callable[..., Any]]] = {
    _dynamics.Model: (("inertia", "mgl", "torque_space", "extra_torque"), _dynamics.Model),
    physics.splitting.Splitting: (("model",), physics.splitting.Splitting),
}
"""class -> (the fields carried, the constructor they are given to as keywords): objects rebuilt
through their own checks (a `Model` validates its numbers; a `Splitting` derives from its model
everything its generated kernels are made from, so nothing from the data reaches generated code)."""

CACHE_FIELDS: dict[type, dict[str, Callable[[Any], Any]]] = {
    physics.splitting.Splitting: {"tables": lambda _obj: {}, "_plans": lambda _obj: {}},  # made by __init__
    physics.realtime.RealtimeStepper: {
        "_frames": lambda _obj: {},  # kernels per display step, made again on first use
        "_peek": lambda _obj: None,  # the peek's kernel, likewise
        "_make_state": _rebuild_state_maker,  # generated from the splitting's axes
    },
}
"""class -> {field: how the decoded object gets it back}: generated code, never encoded."""

_ROOM_FIELDS = ("playing", "time_scale", "_since_sample", "_live_phase", "_live_playing")


class CodecError(ValueError):
    """The data is not a room this app can build (the message says what was wrong), or a room
    holds something that cannot be encoded."""


# ---------------------------------------------------------------------------- the allowlist
def _allowed() -> Iterable[tuple[types.ModuleType, Any]]:
    """(module, value) of every class and function of the allowlist."""
    for module in ALLOWED_MODULES:
        for value in list(vars(module).values()):
            if getattr(value, "__module__", None) == module.__name__:
                yield module, value
    for part in SCENE_PARTS:
        yield sys.modules[part.__module__], part


def _collect() -> tuple[dict[str, type], dict[type, str], dict[str, types.CodeType], dict[str, types.ModuleType],
                        dict[str, Any]]:
    classes: dict[str, type] = {}
    code: dict[str, types.CodeType] = {}
    module_of: dict[str, types.ModuleType] = {}
    top: dict[str, Any] = {}

    def nested(fn_code: types.CodeType, module: types.ModuleType) -> Iterable[types.CodeType]:
        yield fn_code
        for const in fn_code.co_consts:
            if isinstance(const, types.CodeType):
                yield from nested(const, module)

    for module, value in _allowed():
        if type(value) in (type, abc.ABCMeta) and not issubclass(value, BaseException):
            classes[f"{module.__name__}:{value.__qualname__}"] = value
            members = [m for m in vars(value).values() if isinstance(m, types.FunctionType)]
            members += [m.__func__ for m in vars(value).values() if isinstance(m, classmethod | staticmethod)
                        and isinstance(m.__func__, types.FunctionType)]
            functions = members
        elif isinstance(value, types.FunctionType):
            top[f"{module.__name__}:{value.__qualname__}"] = value
            functions = [value]
        else:
            continue
        for fn in functions:
            for c in nested(fn.__code__, module):
                if module.__spec__ is None or c.co_filename != module.__spec__.origin:
                    continue  # generated (a dataclass's methods): never a room's
                key = f"{module.__name__}:{c.co_qualname}"
                code.setdefault(key, c)
                module_of.setdefault(key, module)
    names = {cls: name for name, cls in classes.items()}
    return classes, names, code, module_of, top


_CLASSES, _CLASS_NAMES, _CODE, _CODE_MODULE, _TOP = _collect()
_TOP_NAMES = {id(fn): name for name, fn in _TOP.items()}
_BUILTINS: dict[str, Any] = {"math:sqrt": math.sqrt, "math:sin": math.sin, "math:cos": math.cos,
                             "math:atan2": math.atan2, "math:isfinite": math.isfinite}
_BUILTIN_NAMES = {id(fn): name for name, fn in _BUILTINS.items()}


# ---------------------------------------------------------------------------- encoding
def _fields(obj: Any) -> dict[str, Any]:
    fields = dict(getattr(obj, "__dict__", {}))
    for cls in type(obj).__mro__:
        for name in getattr(cls, "__slots__", ()):
            if name not in ("__dict__", "__weakref__") and hasattr(obj, name):
                fields[name] = getattr(obj, name)
    return fields


class _Encoder:
    def __init__(self) -> None:
        self.memo: dict[int, int] = {}
        self.keep: list[Any] = []  # keeps encoded objects alive (ids stay unique)
        self.nodes = 0

    def _ref(self, obj: Any) -> list[Any] | None:
        index = self.memo.get(id(obj))
        if index is not None:
            return ["r", index]
        self.memo[id(obj)] = len(self.keep)
        self.keep.append(obj)
        return None

    def node(self, obj: Any, where: str, depth: int = 0) -> Any:
        self.nodes += 1
        if depth > MAX_DEPTH:
            raise CodecError(f"{where}: nested deeper than {MAX_DEPTH}")
        kind = type(obj)
        if obj is None or kind is bool or kind is str or kind is float:
            return obj
        if kind is int:
            if not -(2**63) <= obj < 2**64:
                raise CodecError(f"{where}: integer {obj} beyond 64 bits")
            return obj
        if isinstance(obj, np.generic):
            dtype = _dtype_name(obj.dtype, where)
            return ["g", dtype, np.asarray(obj).astype(obj.dtype.newbyteorder("<")).tobytes()]
        ref = self._ref(obj)
        if ref is not None:
            return ref
        deeper = depth + 1
        if kind is list:
            return ["l", [self.node(x, f"{where}[{k}]", deeper) for k, x in enumerate(obj)]]
        if kind is tuple:
            return ["u", [self.node(x, f"{where}[{k}]", deeper) for k, x in enumerate(obj)]]
        if kind is dict:
            flat: list[Any] = []
            for key, value in obj.items():
                flat.append(self.node(key, f"{where}.<key>", deeper))
                flat.append(self.node(value, f"{where}[{key!r}]", deeper))
            return ["d", flat]
        if kind is set or kind is frozenset:
            tag = "s" if kind is set else "z"
            return [tag, [self.node(x, f"{where}<item>", deeper) for x in obj]]
        if kind is bytes:
            return ["y", obj]
        if kind is np.ndarray:
            dtype = _dtype_name(obj.dtype, where)
            raw = np.ascontiguousarray(obj, dtype=obj.dtype.newbyteorder("<")).tobytes()
            return ["a", dtype, list(obj.shape), raw, bool(obj.flags.writeable)]
        if kind is types.FunctionType:
            return self.function(obj, where, deeper)
        if kind is types.BuiltinFunctionType and id(obj) in _BUILTIN_NAMES:
            return ["B", _BUILTIN_NAMES[id(obj)]]
        name = _CLASS_NAMES.get(kind)
        if name is None:
            raise CodecError(f"{where}: a {kind.__module__}.{kind.__qualname__} is not in the codec's allowlist: "
                             f"{REFUSED}")
        if issubclass(kind, tuple):  # a NamedTuple
            return ["n", name, [self.node(x, f"{where}[{k}]", deeper) for k, x in enumerate(obj)]]
        constructed = CONSTRUCTED.get(kind)
        if constructed is not None:
            return ["o", name, {key: self.node(getattr(obj, key), f"{where}.{key}", deeper) for key in constructed[0]}]
        caches = CACHE_FIELDS.get(kind, {})
        fields = {key: self.node(value, f"{where}.{key}", deeper)
                  for key, value in _fields(obj).items() if key not in caches}
        return ["o", name, fields]

    def function(self, fn: types.FunctionType, where: str, depth: int) -> Any:
        top = _TOP_NAMES.get(id(fn))
        if top is not None and fn.__closure__ is None:
            return ["F", top]
        key = f"{fn.__module__}:{fn.__qualname__}"
        if _CODE.get(key) is not fn.__code__:
            raise CodecError(f"{where}: function {key} is not one of the allowlisted modules' own "
                             f"(generated or foreign code is never encoded; {REFUSED})")
        try:
            cells = [c.cell_contents for c in fn.__closure__ or ()]
        except ValueError as exc:
            raise CodecError(f"{where}: function {key} has an empty cell") from exc
        return ["f", key, self.node(fn.__defaults__, f"{where}.__defaults__", depth),
                self.node(fn.__kwdefaults__, f"{where}.__kwdefaults__", depth),
                self.node(cells, f"{where}.<cells>", depth)]


def _dtype_name(dtype: np.dtype, where: str) -> str:
    name = dtype.name
    if name not in DTYPES:
        raise CodecError(f"{where}: dtype {dtype} is not one of {', '.join(DTYPES)}")
    return name


def encode_room(room: Room, *, history: bool = True) -> bytes:
    """The room as bytes (see the module docstring), taken under its lock.

    history: carry the replay history and the moment shown (False: the room as it shows now, live:
    a room showing the past gives that moment, as `Room.branch` would make it).  CodecError if the
    simulation holds something outside the allowlist."""
    title = getattr(room.scene, "title", None)
    if SCENES.get(title) is not room.scene:  # type: ignore[arg-type]
        raise CodecError(f"the room's scene {title!r} is not in the app's registry")
    with room.lock:
        encoder = _Encoder()
        if history or room._live is None:
            sim = room.sim
            fields: dict[str, Any] = {"sim": encoder.node(sim, "sim")}
            if history:
                fields["history"] = encoder.node(room.history, "history")
                fields["_live"] = encoder.node(room._live, "_live")
        else:  # the shown moment as a live one, without touching the room
            fork = room.fork()
            fork.branch()
            sim = fork.sim
            fields = {"sim": encoder.node(sim, "sim")}
            room = fork
        for name in _ROOM_FIELDS:
            fields[name] = encoder.node(getattr(room, name), name)
    if encoder.nodes > MAX_NODES:
        raise CodecError(f"the room has {encoder.nodes} values, more than {MAX_NODES}")
    data = msgspec.msgpack.encode([MAGIC, FORMAT_VERSION, title, fields])
    if len(data) > MAX_BYTES:
        raise CodecError(f"the room takes {len(data)} bytes, more than {MAX_BYTES}")
    return data


# ---------------------------------------------------------------------------- decoding
class _Decoder:
    def __init__(self) -> None:
        self.built: list[Any] = []
        self.nodes = 0
        self.caches: list[tuple[Any, dict[str, Callable[[Any], Any]]]] = []

    def _slot(self) -> int:
        self.built.append(_PENDING)
        return len(self.built) - 1

    def node(self, data: Any, where: str, depth: int = 0) -> Any:
        self.nodes += 1
        if self.nodes > MAX_NODES:
            raise CodecError(f"more than {MAX_NODES} values")
        if depth > MAX_DEPTH:
            raise CodecError(f"{where}: nested deeper than {MAX_DEPTH}")
        if data is None or type(data) in (bool, int, float, str):
            return data
        if type(data) is not list or not data or type(data[0]) is not str:
            raise CodecError(f"{where}: a {type(data).__name__} where a tagged value was expected")
        tag = data[0]
        deeper = depth + 1
        if tag == "r":
            _expect(data, 2, where)
            index = data[1]
            if type(index) is not int or not 0 <= index < len(self.built) or self.built[index] is _PENDING:
                raise CodecError(f"{where}: reference {index!r} to nothing built")
            return self.built[index]
        if tag == "g":
            _expect(data, 3, where)
            dtype = _dtype(data[1], where)
            raw = _bytes(data[2], where)
            if len(raw) != dtype.itemsize:
                raise CodecError(f"{where}: {len(raw)} bytes for one {dtype}")
            return np.frombuffer(raw, dtype=dtype)[0].astype(dtype.newbyteorder("="))
        if tag in ("l", "u", "s", "z"):
            _expect(data, 2, where)
            items = _list(data[1], where)
            index = self._slot()
            if tag == "l":
                out: Any = []
                self.built[index] = out
                out.extend(self.node(x, f"{where}[{k}]", deeper) for k, x in enumerate(items))
                return out
            values = [self.node(x, f"{where}[{k}]", deeper) for k, x in enumerate(items)]
            try:
                out = tuple(values) if tag == "u" else set(values) if tag == "s" else frozenset(values)
            except TypeError as exc:
                raise CodecError(f"{where}: unhashable item in a set") from exc
            self.built[index] = out
            return out
        if tag == "d":
            _expect(data, 2, where)
            flat = _list(data[1], where)
            if len(flat) % 2:
                raise CodecError(f"{where}: a dict with an odd number of keys and values")
            out = {}
            self.built.append(out)
            for k in range(0, len(flat), 2):
                key = self.node(flat[k], f"{where}.<key>", deeper)
                try:
                    hash(key)
                except TypeError as exc:
                    raise CodecError(f"{where}: unhashable dict key") from exc
                out[key] = self.node(flat[k + 1], f"{where}[{key!r}]", deeper)
            return out
        if tag == "y":
            _expect(data, 2, where)
            out = _bytes(data[1], where)
            self.built.append(out)
            return out
        if tag == "a":
            _expect(data, 5, where)
            out = _array(data, where)
            self.built.append(out)
            return out
        if tag in ("F", "B"):  # a module-level function of the kit, or a built-in
            _expect(data, 2, where)
            allowed, what = (_TOP, "function") if tag == "F" else (_BUILTINS, "built-in")
            fn = allowed.get(data[1]) if type(data[1]) is str else None
            if fn is None:
                raise CodecError(f"{where}: {what} {data[1]!r} is not in the allowlist")
            self.built.append(fn)
            return fn
        if tag == "f":
            return self.function(data, where, deeper)
        if tag == "o":
            return self.instance(data, where, deeper)
        if tag == "n":
            _expect(data, 3, where)
            cls = _CLASSES.get(data[1]) if type(data[1]) is str else None
            if cls is None or not issubclass(cls, tuple) or not hasattr(cls, "_fields"):
                raise CodecError(f"{where}: named tuple {data[1]!r} is not in the allowlist")
            items = _list(data[2], where)
            if len(items) != len(cls._fields):
                raise CodecError(f"{where}: {data[1]} takes {len(cls._fields)} values, got {len(items)}")
            index = self._slot()
            out = tuple.__new__(cls, [self.node(x, f"{where}[{k}]", deeper) for k, x in enumerate(items)])
            self.built[index] = out
            return out
        raise CodecError(f"{where}: unknown tag {tag!r}")

    def function(self, data: list[Any], where: str, depth: int) -> Any:
        _expect(data, 5, where)
        key = data[1]
        code = _CODE.get(key) if type(key) is str else None
        if code is None:
            raise CodecError(f"{where}: function {key!r} is not in the allowlist: {REFUSED}")
        index = self._slot()
        defaults = self.node(data[2], f"{where}.__defaults__", depth)
        kwdefaults = self.node(data[3], f"{where}.__kwdefaults__", depth)
        cells = self.node(data[4], f"{where}.<cells>", depth)
        if (defaults is not None and type(defaults) is not tuple) or (
                kwdefaults is not None and type(kwdefaults) is not dict):
            raise CodecError(f"{where}: bad defaults of {key}")
        if type(cells) is not list or len(cells) != len(code.co_freevars):
            raise CodecError(f"{where}: {key} needs {len(code.co_freevars)} cells")
        fn = types.FunctionType(code, vars(_CODE_MODULE[key]), code.co_name, defaults,
                                tuple(types.CellType(v) for v in cells) or None)
        fn.__kwdefaults__ = kwdefaults
        fn.__qualname__ = code.co_qualname
        self.built[index] = fn
        return fn

    def instance(self, data: list[Any], where: str, depth: int) -> Any:
        _expect(data, 3, where)
        name = data[1]
        cls = _CLASSES.get(name) if type(name) is str else None
        if cls is None:
            raise CodecError(f"{where}: class {name!r} is not in the allowlist: {REFUSED}")
        fields = data[2]
        if type(fields) is not dict:
            raise CodecError(f"{where}: the fields of {name} are not a map")
        slots = {s for c in cls.__mro__ for s in getattr(c, "__slots__", ())}
        has_dict = all(hasattr(c, "__dict__") for c in (cls,)) and "__dict__" in dir(cls)
        if issubclass(cls, tuple):
            raise CodecError(f"{where}: {name} is a named tuple, not an object")
        constructed = CONSTRUCTED.get(cls)
        if constructed is not None:
            if set(fields) != set(constructed[0]):
                raise CodecError(f"{where}: {name} takes the fields {', '.join(constructed[0])}")
            index = self._slot()
            arguments = {key: self.node(fields[key], f"{where}.{key}", depth) for key in constructed[0]}
            try:
                built = constructed[1](**arguments)
            except Exception as exc:  # noqa: BLE001 - its own checks refused the values
                raise CodecError(f"{where}: {name} refused: {type(exc).__name__}: {exc}") from None
            self.built[index] = built
            return built
        obj = object.__new__(cls)
        self.built.append(obj)
        caches = CACHE_FIELDS.get(cls, {})
        for field, value in fields.items():
            if type(field) is not str or not field.isidentifier() or field.startswith("__") or field in caches:
                raise CodecError(f"{where}: field {field!r} refused in {name}")
            if field not in slots:
                static = _static(cls, field)
                if not has_dict or static is not None and (callable(static) or hasattr(static, "__get__")):
                    raise CodecError(f"{where}: {name} has no field {field!r}")
            decoded = self.node(value, f"{where}.{field}", depth)
            if field in slots:
                object.__setattr__(obj, field, decoded)
            else:
                vars(obj)[field] = decoded
        if caches:
            self.caches.append((obj, caches))
        return obj


_PENDING = object()


def _static(cls: type, name: str) -> Any:
    for c in cls.__mro__:
        if name in vars(c):
            return vars(c)[name]
    return None


def _expect(data: list[Any], length: int, where: str) -> None:
    if len(data) != length:
        raise CodecError(f"{where}: tag {data[0]!r} takes {length - 1} values, got {len(data) - 1}")


def _list(value: Any, where: str) -> list[Any]:
    if type(value) is not list:
        raise CodecError(f"{where}: a {type(value).__name__} where a list was expected")
    return value


def _bytes(value: Any, where: str) -> bytes:
    if type(value) is not bytes:
        raise CodecError(f"{where}: a {type(value).__name__} where bytes were expected")
    return value


def _dtype(name: Any, where: str) -> np.dtype:
    if type(name) is not str or name not in DTYPES:
        raise CodecError(f"{where}: dtype {name!r} is not one of {', '.join(DTYPES)}")
    return np.dtype(name).newbyteorder("<")


def _array(data: list[Any], where: str) -> np.ndarray:
    dtype = _dtype(data[1], where)
    shape = data[2]
    raw = _bytes(data[3], where)
    if type(shape) is not list or len(shape) > MAX_DIMS or not all(type(n) is int and 0 <= n <= MAX_BYTES
                                                                   for n in shape):
        raise CodecError(f"{where}: bad array shape {shape!r}")
    count = math.prod(shape)
    if count * dtype.itemsize != len(raw):
        raise CodecError(f"{where}: {len(raw)} bytes for an array {tuple(shape)} of {dtype.name}")
    array = np.frombuffer(raw, dtype=dtype).astype(dtype.newbyteorder("="), copy=True).reshape(shape)
    if type(data[4]) is not bool:
        raise CodecError(f"{where}: the array's writeable flag is not a bool")
    array.flags.writeable = data[4]
    return array


def decode_room(data: bytes) -> Room:
    """The room `encode_room` gave these bytes for (no views); CodecError, with what was wrong,
    for anything else."""
    if not isinstance(data, bytes | bytearray | memoryview):
        raise CodecError(f"a room is bytes, not a {type(data).__name__}")
    if len(data) > MAX_BYTES:
        raise CodecError(f"{len(data)} bytes, more than {MAX_BYTES}")
    try:
        top = msgspec.msgpack.decode(data)
    except (msgspec.DecodeError, RecursionError, ValueError, TypeError) as exc:
        raise CodecError(f"not msgpack: {exc}") from None
    if type(top) is not list or len(top) != 4 or top[0] != MAGIC:
        raise CodecError("not a room of this app")
    if top[1] != FORMAT_VERSION:
        raise CodecError(f"room format {top[1]!r}, this app reads {FORMAT_VERSION}")
    title, fields = top[2], top[3]
    scene = SCENES.get(title) if type(title) is str else None
    if scene is None:
        raise CodecError(f"unknown scene {title!r}")
    if type(fields) is not dict or not {"sim", *_ROOM_FIELDS} <= set(fields) or not set(fields) <= {
            "sim", "history", "_live", *_ROOM_FIELDS}:
        raise CodecError("the room's fields are not those of a room")
    decoder = _Decoder()
    try:
        values = {name: decoder.node(value, name) for name, value in fields.items()}
        for obj, caches in decoder.caches:
            for field, rebuild in caches.items():
                if field in {s for c in type(obj).__mro__ for s in getattr(c, "__slots__", ())}:
                    object.__setattr__(obj, field, rebuild(obj))
                else:
                    vars(obj)[field] = rebuild(obj)
    except CodecError:
        raise
    except (RecursionError, AttributeError, TypeError, ValueError, KeyError, IndexError) as exc:
        raise CodecError(f"the room does not build: {type(exc).__name__}: {exc}") from None
    sim = values["sim"]
    expected = simulation_class(scene)
    if type(sim) is not expected:
        raise CodecError(f"the simulation of {title!r} is a {type(sim).__name__}, not a {expected.__name__}")
    room = Room(scene, sim)
    playing, scale = values["playing"], values["time_scale"]
    if type(playing) is not bool or type(values["_live_playing"]) is not bool:
        raise CodecError("playing is not a bool")
    for name in ("time_scale", "_since_sample", "_live_phase"):
        if type(values[name]) is not float or not math.isfinite(values[name]):
            raise CodecError(f"{name} is not a finite float")
    if not scale > 0.0:
        raise CodecError(f"time scale {scale!r} is not positive")
    history = values.get("history")
    live = values.get("_live")
    if "history" in values and not (history is None and room.history is None
                                    or type(history) is History and room.history is not None):
        raise CodecError("the history does not fit the simulation")
    if live is not None and (type(live) is not Snapshot or history is None):
        raise CodecError("the moment set aside is not a snapshot")
    room.playing = playing
    room.time_scale = scale
    room._since_sample = values["_since_sample"]
    if history is not None:
        room.history = history
    room._live = live
    room._live_phase = values["_live_phase"]
    room._live_playing = values["_live_playing"]
    _trial(room)
    return room


_TRIAL_DT = 1.0 / 60.0  # [s] of simulated time the trial copy advances


def _trial(room: Room) -> None:
    """A copy of the decoded room (`Room.fork`) advances one step, samples, snapshots and resets:
    a field of the wrong type (what the allowlist cannot see) fails here, as CodecError, not in
    every frame of the app's loop.  Failures the physics reports (an IntegrationError, the end of
    a run, a ValueError) are the simulation's own and pass: the room then stops as it would have."""
    try:
        trial = room.fork()
        sim = trial.sim
        for call in (lambda: sim.advance(_TRIAL_DT), getattr(sim, "take_sample", None),
                     getattr(sim, "snapshot", None), sim.reset):
            if call is None:
                continue
            try:
                call()
            except (ArithmeticError, ValueError, RuntimeError):
                pass
    except (TypeError, AttributeError, IndexError, KeyError, RecursionError) as exc:
        raise CodecError(f"the decoded {room.scene.title} does not run: {type(exc).__name__}: {exc}") from None
