"""fork(): in every scene and preset, an exact, independent copy of what is shown now.

Each case plays a preset with a view drawing it, edits something the scene lets a user edit,
plays on, and forks the room.  The fork is compared with the original field by field
(`assert_same`, a generic walk over the objects: every float and array bit for bit, and no
mutable object shared), then both go on for the same frames and must stay identical, a view
built on the fork must draw the same traces and plots as the original's view, and editing or
advancing one must leave the other as it was.

Views draw into a private viser server (no browser), as `app.export` does.
"""

from __future__ import annotations

import copy
import math
import struct
import time
import types
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
import viser
from conftest import scenes_without_an_entry

from app.export import RecorderTarget
from app.kit.core.room import Room
from app.kit.core.trace import Trace
from app.kit.draw.widgets import TraceLines
from app.scenes import SCENES
from app.scenes.moving_frame import KEYS as MOVING_KEYS
from app.scenes.moving_frame import MovingFrameSetup
from physics.dynamics import Model

DT = 1.0 / 60.0
TIME_SCALE = 3.0  # 300 frames = 15 s of simulated time: the heavy top's 12 s trace drops chunks
FRAMES_BEFORE_EDIT = 120
FRAMES_AFTER_EDIT = 183  # not a multiple of the 6 frames between plot samples: the fork is mid-period
FRAMES_AFTER_FORK = 60
FORK_BUDGET_S = 5e-3  # [s] the median cost of a fork allowed here (measured: ~0.05-0.15 ms)


# ---------------------------------------------------------------------------- the comparison
_ATOMS = (type(None), bool, int, str, bytes, type, types.FunctionType, types.BuiltinFunctionType,
          types.MethodType, types.ModuleType)


def assert_same(a: Any, b: Any, where: str = "sim", seen: set[tuple[int, int]] | None = None) -> None:
    """a and b hold the same values (floats and arrays bit for bit, NaN equal to NaN) and share
    no mutable object: lists, dicts, objects and writeable arrays are distinct; functions,
    classes and read-only arrays may be shared."""
    seen = set() if seen is None else seen
    if (id(a), id(b)) in seen:
        return
    seen.add((id(a), id(b)))
    assert type(a) is type(b), f"{where}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, float):
        assert struct.pack("d", a) == struct.pack("d", b), f"{where}: {a!r} vs {b!r}"
    elif isinstance(a, np.generic):
        assert a.tobytes() == b.tobytes(), f"{where}: {a!r} vs {b!r}"
    elif isinstance(a, types.FunctionType):  # shared, or the same code over the same values
        if a is not b:
            assert a.__code__ is b.__code__, f"{where}: different functions {a!r}, {b!r}"
            cells = tuple(c.cell_contents for c in a.__closure__ or ())
            other_cells = tuple(c.cell_contents for c in b.__closure__ or ())
            assert_same((cells, a.__defaults__), (other_cells, b.__defaults__), f"{where}.<closure>", seen)
    elif isinstance(a, type | types.BuiltinFunctionType | types.ModuleType):
        assert a is b, f"{where}: {a!r} vs {b!r}"
    elif isinstance(a, _ATOMS):
        assert a == b, f"{where}: {a!r} vs {b!r}"
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape, f"{where}: {a.dtype}{a.shape} vs {b.dtype}{b.shape}"
        assert a.tobytes() == b.tobytes(), f"{where}: arrays differ"
        if a.flags.writeable or b.flags.writeable:
            assert not np.shares_memory(a, b), f"{where}: a writeable array is shared"
    elif isinstance(a, tuple):
        assert len(a) == len(b), f"{where}: lengths {len(a)} vs {len(b)}"
        for k, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{k}]", seen)
    elif isinstance(a, list):
        assert a is not b and len(a) == len(b), f"{where}: shared, or lengths {len(a)} vs {len(b)}"
        for k, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{k}]", seen)
    elif isinstance(a, dict):
        assert a is not b, f"{where}: a dict is shared"
        assert list(a) == list(b), f"{where}: keys {list(a)} vs {list(b)}"
        for key in a:
            assert_same(a[key], b[key], f"{where}[{key!r}]", seen)
    else:
        assert a is not b, f"{where}: a {type(a).__name__} is shared"
        fields = dict(getattr(a, "__dict__", {}))
        for cls in type(a).__mro__:
            for name in getattr(cls, "__slots__", ()):
                if hasattr(a, name):
                    fields[name] = getattr(a, name)
        other = dict(getattr(b, "__dict__", {}))
        for cls in type(b).__mro__:
            for name in getattr(cls, "__slots__", ()):
                if hasattr(b, name):
                    other[name] = getattr(b, name)
        assert list(fields) == list(other), f"{where}: fields {list(fields)} vs {list(other)}"
        assert fields or isinstance(a, types.SimpleNamespace), f"{where}: nothing to compare in {type(a)}"
        for name in fields:
            assert_same(fields[name], other[name], f"{where}.{name}", seen)


def assert_equal_values(a: Any, b: Any, where: str) -> None:
    """Equal drawn data: arrays bit for bit, tuples and lists element by element."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape and a.tobytes() == b.tobytes(), f"{where}: drawn data differ"
    elif isinstance(a, tuple | list):
        assert len(a) == len(b), f"{where}: lengths {len(a)} vs {len(b)}"
        for k, (x, y) in enumerate(zip(a, b)):
            assert_equal_values(x, y, f"{where}[{k}]")
    elif isinstance(a, dict):
        assert list(a) == list(b), f"{where}: {list(a)} vs {list(b)}"
        for key in a:
            assert_equal_values(a[key], b[key], f"{where}[{key!r}]")
    else:
        assert a == b, f"{where}: {a!r} vs {b!r}"


# ---------------------------------------------------------------------------- views without a browser
_views = iter(range(10**6))


def _report(where: str, error: BaseException) -> None:
    raise error


def build_view(server: viser.ViserServer, room: Room) -> Any:
    view = room.scene(RecorderTarget(server, f"/v{next(_views)}"), room, lambda _where, fn: fn, _report)
    tabs = getattr(view, "tabs", None)
    if tabs is not None and "Plots" in tabs.names:
        tabs.show("Plots")  # the plots are pushed while their tab is shown
    return view


def play(room: Room, frames: int) -> None:
    for _ in range(frames):
        room.tick(DT)


def picture(view: Any) -> dict[str, Any]:
    """What a view shows that has a history or a pose: traces, plots, the body's pose."""
    shown: dict[str, Any] = {}
    for name in ("trace", "herpolhode"):
        if hasattr(view, name):
            shown[name] = getattr(view, name).shown_segments()
    for name in ("paths_space", "paths_body"):
        if hasattr(view, name):
            shown[name] = [lines.shown_segments() for lines in getattr(view, name)]
    plots = getattr(view, "plots", None)
    if plots is not None:
        plots.push()
        shown["plots"] = [handle.data for handle in plots.handles]
    body = getattr(view, "body", None)
    if body is not None:
        shown["body"] = (tuple(body.node.wxyz), tuple(body.node.position))
    return shown


# ---------------------------------------------------------------------------- a user's edits
def _edit_euler(room: Room, view: Any, index: int) -> None:
    room.sim.set_moments((1.5, 2.0, 3.0))
    room.sim.set_rates([20.0 + index, -15.0, 40.0])
    room.refresh()


def _edit_inertia(room: Room, view: Any, index: int) -> None:
    system = room.sim
    system.set_particles([*system.masses, 0.7], [*system.positions, [0.3, -0.2, 0.4 + 0.1 * index]])
    system.set_about([0.1, 0.2, -0.3])
    room.refresh()


def _edit_free(room: Room, view: Any, index: int) -> None:
    room.sim.set_model(Model(inertia=(1.1, 2.0, 2.5)))
    view.set_integrator(("splitting4", "exact")[index % 2])


def _edit_top(room: Room, view: Any, index: int) -> None:
    model = room.sim.model
    room.sim.set_model(Model(inertia=model.inertia, mgl=0.8 * model.mgl))
    view.set_integrator(("splitting4", "exact", "euler_lagrange")[index % 3])


def _edit_poinsot(room: Room, view: Any, index: int) -> None:
    restarts = room.sim.restarts
    view.set_energy(0.5)
    if room.sim.restarts == restarts:  # refused on that side of the separatrix (two equal moments)
        view.set_energy(-0.5)
    assert room.sim.restarts == restarts + 1, view.message.handle.content


def _edit_moving(room: Room, view: Any, index: int) -> None:
    setup = room.sim.setup
    params = list(setup.params)
    params[MOVING_KEYS.index("k")] = 7.5
    room.sim.set_setup(MovingFrameSetup(tuple(params), setup.angles_deg))
    params[MOVING_KEYS.index("force_scale")] = 0.5
    room.sim.set_display(MovingFrameSetup(tuple(params), setup.angles_deg))
    room.refresh()


def _edit_constrained(room: Room, view: Any, index: int) -> None:
    params = list(room.sim.setup.params)
    params[-2] = 9.0 + 0.1 * index  # g (every system's next-to-last parameter)
    view._param_edit(len(params) - 2)(params[-2])  # as the slider does: the state kept, angles wrapped
    view._param_edit(len(params) - 1)(0.04)  # the arrow scale: no restart
    assert view.message.text == "", view.message.text


EDITS: dict[str, Callable[[Room, Any, int], None]] = {
    "Euler angles": _edit_euler, "Inertia": _edit_inertia, "Free body": _edit_free, "Heavy top": _edit_top,
    "Poinsot": _edit_poinsot, "Moving frame": _edit_moving, "Constrained particles": _edit_constrained,
}
CASES = [(title, index, preset.name) for title, scene in SCENES.items()
         for index, preset in enumerate(scene.presets())]


def test_every_scene_has_an_edit_here() -> None:
    problems = scenes_without_an_entry(EDITS, "EDITS of tests/test_fork.py (a user's edit of the scene)")
    assert not problems, problems


def _played_room(server: viser.ViserServer, title: str, index: int, preset: str) -> tuple[Room, Any]:
    """A room of the scene at `preset`, played, edited, played on, with one view drawing it."""
    scene = SCENES[title]
    room = Room(scene, scene.new_simulation())
    view = build_view(server, room)
    scene.apply_preset(room, preset)
    room.set_time_scale(TIME_SCALE)
    room.play()
    play(room, FRAMES_BEFORE_EDIT)
    EDITS[title](room, view, index)
    room.play()
    play(room, FRAMES_AFTER_EDIT)
    return room, view


@pytest.mark.parametrize(("title", "index", "preset"), CASES)
def test_a_fork_is_exact_independent_and_goes_on_identically(server: viser.ViserServer, title: str, index: int,
                                                            preset: str) -> None:
    room, view = _played_room(server, title, index, preset)
    assert room.sim.t > 0.0 or not room.playing

    fork = room.fork()
    assert fork is not room and fork.scene is room.scene and fork.views == []
    assert (fork.playing, fork.time_scale) == (room.playing, room.time_scale)
    assert_same(room.sim, fork.sim)

    # A view built on the fork now shows what the original's view shows.
    forked_view = build_view(server, fork)
    view.refresh()  # playing frames draw at display resolution (app.kit.draw.widgets.POSE_QUANTUM), a new view exactly
    shown, shown_fork = picture(view), picture(forked_view)
    assert_equal_values(shown, shown_fork, f"{title}/{preset} at the fork")
    if title in ("Heavy top", "Poinsot", "Moving frame") and room.playing:
        traces = [shown.get("trace"), shown.get("herpolhode"), *shown.get("paths_space", ())]
        assert max(len(t) for t in traces if t is not None) > 10, "the trace so far is drawn"

    # Both go on identically (each with its view drawing it).
    play(room, FRAMES_AFTER_FORK)
    play(fork, FRAMES_AFTER_FORK)
    assert_same(room.sim, fork.sim)
    assert_equal_values(picture(view), picture(forked_view), f"{title}/{preset} after playing on")

    # Independent: editing and advancing the original leaves the fork as it was, and back.
    kept = copy.deepcopy(fork.sim)
    EDITS[title](room, view, index + 1)
    room.reset()
    room.play()
    play(room, 5)
    assert_same(fork.sim, kept, "fork")
    kept = copy.deepcopy(room.sim)
    fork.sim.reset()
    play(fork, 5)
    assert_same(room.sim, kept, "original")
    for v in (view, forked_view):
        v.remove()


REPLAYABLE = [title for title, scene in SCENES.items() if Room(scene, scene.new_simulation()).history is not None]


@pytest.mark.parametrize("title", REPLAYABLE)
def test_a_fork_carries_the_replay_history_and_scrubs_as_the_original(server: viser.ViserServer, title: str) -> None:
    """An explorer's copy can look back: the same recorded stretch, a scrub to the same moment
    shows the same state in both (nothing shared: the fork's stepper is its own), and a copy
    made while the past is shown shows it and resumes to the same live moment."""
    room, view = _played_room(server, title, 0, SCENES[title].presets()[0].name)
    fork = room.fork()
    assert fork.stretch() == room.stretch() and fork.stretch() is not None
    first, live = fork.stretch()  # type: ignore[misc]
    assert live - first > 5.0, (first, live)
    fork.scrub(live - 5.0)
    room.scrub(live - 5.0)
    assert fork.mode == room.mode == "scrubbing"
    assert_same(room.sim, fork.sim)
    copy_in_the_past = room.fork()
    assert copy_in_the_past.mode == "scrubbing" and copy_in_the_past.live_t == room.live_t
    for r in (room, fork, copy_in_the_past):
        r.resume()
    assert_same(room.sim, fork.sim)
    assert_same(room.sim, copy_in_the_past.sim)
    assert_reset_agrees(server, room, view, title)  # the played room, live again: as the test below
    view.remove()


def assert_reset_agrees(server: viser.ViserServer, room: Room, view: Any, title: str) -> None:
    """A fork of `room` (drawn by `view`) and the room, both Reset: the same simulation and picture."""
    fork = room.fork()
    forked_view = build_view(server, fork)  # views read derived values (Inertia keeps its axes): both drawn
    room.reset()
    fork.reset()
    assert_same(room.sim, fork.sim)
    assert_equal_values(picture(view), picture(forked_view), f"{title} after Reset")
    forked_view.remove()


@pytest.mark.parametrize("title", [title for title in SCENES if title not in REPLAYABLE])
def test_reset_in_the_fork_goes_where_the_original_goes(server: viser.ViserServer, title: str) -> None:
    """(The scenes with a replay history check this at the end of the test above, on the same
    played room: playing it once for both.)"""
    room, view = _played_room(server, title, 0, SCENES[title].presets()[0].name)
    assert_reset_agrees(server, room, view, title)
    view.remove()


@pytest.mark.parametrize("title", list(SCENES))
def test_a_fork_costs_well_under_a_few_milliseconds(title: str) -> None:
    scene = SCENES[title]
    room = Room(scene, scene.new_simulation())
    room.playing = True
    for _ in range(300):
        room.advance(DT)
    room.fork()  # first use
    costs = []
    for _ in range(30):
        start = time.perf_counter()
        room.fork()
        costs.append(time.perf_counter() - start)
    assert float(np.median(costs)) < FORK_BUDGET_S, f"{title}: median {np.median(costs) * 1e3:.2f} ms"


def test_a_mesh_is_shared_read_only_and_the_rest_copied(server: viser.ViserServer) -> None:
    """A mesh (up to MAX_FACES faces) is not copied by a fork: both hold the same read-only
    arrays; the Inertia scene's and the Free body's (handed on by "Spin it") alike."""
    from app.scenes.inertia import MESHES_DIR, InertiaSystem, read_mesh

    path = next(iter(sorted(MESHES_DIR.glob("*.stl"))))
    system = InertiaSystem([1.0], [[0.0, 0.0, 0.0]])
    system.set_mesh(path.name, *read_mesh(path.name, path.read_bytes()), mass=2.0)
    system.set_about([0.1, 0.0, 0.0])
    room = Room(SCENES["Inertia"], system)
    view = build_view(server, room)
    fork = room.fork()
    forked_view = build_view(server, fork)  # draws the shared mesh
    assert_same(system, fork.sim)
    assert fork.sim.mesh is not None and system.mesh is not None
    assert all(a is b and not a.flags.writeable for a, b in zip(fork.sim.mesh, system.mesh))
    fork.sim.weigh_mesh(mass=3.0)
    assert system.mesh_mass == 2.0 and fork.sim.mesh_mass == 3.0
    fork.refresh()
    assert "m = 2 kg" in view.readout.handle.content and "m = 3 kg" in forked_view.readout.handle.content

    free = Room(SCENES["Free body"], SCENES["Free body"].new_simulation())
    free.sim.mesh = (np.array(system.mesh[0]), np.array(system.mesh[1]))  # as "Spin it" hands it on
    free_view = build_view(server, free)
    free.play()
    play(free, 30)
    free_fork = free.fork()
    assert_same(free.sim, free_fork.sim)
    assert all(a is b and not a.flags.writeable for a, b in zip(free_fork.sim.mesh, free.sim.mesh))
    for v in (view, forked_view, free_view):
        v.remove()


# ---------------------------------------------------------------------------- the trace itself
def test_a_trace_keeps_exactly_the_chunks_newer_than_its_window() -> None:
    """Against a reference computed from every point ever added: complete chunks whose newest
    point is older than `seconds` before the newest point are dropped, nothing else."""
    rng = np.random.default_rng(7)
    trace = Trace(seconds=2.0, spacing=0.05, chunk_points=6)
    stride = trace.stride
    times: list[float] = []
    points: list[np.ndarray] = []
    t = 0.0
    for _ in range(2000):
        t += float(rng.choice([0.01, 0.05, 0.07, 0.2]))
        point = rng.normal(size=3)
        before = trace.count
        trace.add(t, point)
        if trace.count > before:
            times.append(t)
            points.append(point)
        n = len(times)
        complete = [c for c in range(n // stride + 1) if c * stride + stride <= n - 1]
        dropped = sum(1 for c in complete if times[c * stride + stride] < times[-1] - trace.seconds)
        assert trace.first == dropped * stride and trace.count == n
        assert len(trace) <= trace.max_chunks * stride + 1
    assert all(b - a >= trace.spacing - 1e-12 for a, b in zip(times, times[1:]))
    np.testing.assert_array_equal(trace.points(trace.first, trace.count), np.array(points[trace.first:]))
    np.testing.assert_array_equal(trace.times(trace.first, trace.count), np.array(times[trace.first:]))
    with pytest.raises(IndexError):
        trace.points(trace.first - 1, trace.count)


def test_trace_lines_built_late_draw_what_lines_drawn_all_along_draw(server: viser.ViserServer) -> None:
    trace = Trace(seconds=1.0, spacing=0.02, chunk_points=8)
    along = TraceLines(server.scene, "/trace_test/along", (0, 0, 0), trace)
    for k in range(400):
        t = k * 0.02
        trace.add(t, np.array([math.cos(3 * t), math.sin(3 * t), 0.1 * t]))
        along.sync(trace, 2.0)
        if k in (0, 1, 2, 7, 8, 150, 399):
            late = TraceLines(server.scene, f"/trace_test/late_{k}", (0, 0, 0), trace)
            late.sync(trace, 2.0)
            np.testing.assert_array_equal(late.shown_segments(), along.shown_segments())
    shown = along.shown_segments()  # consecutive points from the oldest kept, times 2
    expected = (2.0 * trace.points(trace.first, trace.count)).astype(np.float32)
    assert trace.count - 2 <= trace.first + shown.shape[0] <= trace.count - 1  # the head trails by one at most
    assert shown.shape[0] >= trace.seconds / trace.spacing - 1
    np.testing.assert_array_equal(shown[:, 0], expected[: shown.shape[0]])
    np.testing.assert_array_equal(shown[:, 1], expected[1: shown.shape[0] + 1])
    trace.clear()
    along.sync(trace, 2.0)
    assert along.point_count == 0 and along.shown_segments().shape == (0, 2, 3)
