"""One registry of integrators (`physics.methods`): the app's menu and its stepping come from it.

- every entry is complete (name, one line, bodies, a Stepper the app can call per frame) and its
  Stepper's snapshot puts it back bit for bit;
- stepping through each entry, in a bare Stepper and in the app's `RigidBodySimulation`, gives
  after N frames the same floats as calling the method directly (the GridStepper for splitting4,
  the closed form for exact, the integrator from frame to frame for the others);
- each rigid scene's integrator menu is the registry's names that apply to its body;
- a method added to the registry is in the menu and steps with no other change;
- a lesson naming a method not in the registry is refused at load; no method name is spelt
  in a comparison anywhere in app/.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app.kit.rigid.simulation import RigidBodySimulation
from app.lessons import LESSONS_DIR, LessonError, load_lesson
from app.scenes import SCENES
from physics.dop853 import integrate_adaptive
from physics.dynamics import Model, State
from physics.free_kick import integrate_free_kick
from physics.lagrange import integrate_euler_lagrange
from physics.methods import Method, RunStepper, Stepper, applicable, exact_solution, methods, realtime_method
from physics.realtime import GridStepper
from physics.scipy_peer import integrate_dop853

ROOT = Path(__file__).resolve().parents[1]
DT = 1.0 / 60.0
FRAMES = 30
ANGLES = np.radians([30.0, 50.0, 20.0])

BODIES = {
    "free": (Model(inertia=(0.3, 0.75, 1.0)), np.array([0.05, 5.0, 0.05])),
    "top": (Model(inertia=(1.0, 1.0, 0.5), mgl=6.0), np.array([0.3, -0.4, 9.0])),
}


def _start(body: str) -> tuple[Model, State]:
    model, omega = BODIES[body]
    return model, State(Rotation.from_euler("ZXZ", ANGLES).as_matrix(), omega.copy(), 0.0)


def _direct(name: str, model: Model, state0: State, frames: int) -> State:
    """The state after `frames` frames of DT by calling the method itself, as the app did before
    the registry stepped it."""
    if name == "splitting4":
        grid = GridStepper(model, state0)
        for _ in range(frames):
            state = grid.step(DT)
        return state
    if name == "exact":  # the closed form at the time the frames add up to
        t = state0.t
        for _ in range(frames):
            t += DT
        R, omega = exact_solution(model, state0)(np.array([t - state0.t]))
        return State(R[0], omega[0], t)
    integrate = {"adaptive": integrate_adaptive, "dop853": integrate_dop853,
                 "euler_lagrange": integrate_euler_lagrange, "free_kick": integrate_free_kick}[name]
    state = state0
    for _ in range(frames):
        trajectory = integrate(model, state, np.array([state.t + DT]))
        state = State(trajectory.R_space_body[0], trajectory.omega_body[0], float(trajectory.t[0]))
    return state


def _same(a: State, b: State) -> None:
    np.testing.assert_array_equal(a.R_space_body, b.R_space_body)
    np.testing.assert_array_equal(a.omega_body, b.omega_body)
    assert a.t == b.t


def test_every_entry_is_complete_and_the_cli_names_are_the_keys() -> None:
    registry = methods()
    assert set(registry) >= {"exact", "splitting4", "adaptive", "dop853", "euler_lagrange"}
    for name, method in registry.items():
        assert method.name == name and " " not in name
        assert method.summary and "\n" not in method.summary and method.bodies
    assert registry[realtime_method()].realtime and not registry[realtime_method()].reference
    assert [name for name, m in registry.items() if m.reference] == ["exact"]
    model, _ = _start("free")
    assert applicable(model) == list(registry)
    assert "exact" not in applicable(Model(inertia=(1.0, 1.2, 0.5), mgl=6.0))  # an asymmetric top


@pytest.mark.parametrize("body", sorted(BODIES))
@pytest.mark.parametrize("name", sorted(methods()))
def test_stepping_through_each_entry_is_calling_the_method(name: str, body: str) -> None:
    model, state0 = _start(body)
    expected = _direct(name, model, state0, FRAMES)

    stepper = methods()[name].stepper(model, state0)
    assert isinstance(stepper, Stepper)
    for _ in range(FRAMES):
        state = stepper.step(DT)
    _same(state, expected)
    assert stepper.state is state

    sim = RigidBodySimulation(model, state0, angles=ANGLES)
    assert sim.set_integrator(name) is None and sim.integrator == name
    for _ in range(FRAMES):
        sim.advance(DT)
    _same(sim.state, expected)
    assert sim.method is methods()[name]
    assert (sim.attitude_error() == 0.0) is methods()[name].reference


@pytest.mark.parametrize("name", sorted(methods()))
def test_a_steppers_snapshot_puts_it_back_bit_for_bit(name: str) -> None:
    model, state0 = _start("top")
    stepper = methods()[name].stepper(model, state0)
    for _ in range(3):
        stepper.step(0.7 * DT)  # off the grid: a GridStepper peeks
    values = list(stepper.snapshot())
    later = [stepper.step(DT) for _ in range(4)]
    stepper.restore(values)
    again = [stepper.step(DT) for _ in range(4)]
    for a, b in zip(later, again):
        _same(a, b)
    with pytest.raises(ValueError):
        stepper.restore(values[:-1])


def test_the_app_switches_mid_run_as_before() -> None:
    """exact from the middle of a run joins the closed form from the run's start; back to
    splitting4, the grid starts from the state where exact left it."""
    model, state0 = _start("free")
    sim = RigidBodySimulation(model, state0, angles=ANGLES)
    for _ in range(10):
        sim.advance(DT)
    sim.set_integrator("exact")
    for _ in range(5):
        sim.advance(DT)
    R, omega = exact_solution(model, state0)(np.array([sim.t]))
    np.testing.assert_array_equal(sim.state.R_space_body, R[0])
    at = sim.state
    sim.set_integrator("splitting4")
    sim.advance(DT)
    _same(sim.state, GridStepper(model, at).step(DT))


def test_a_method_that_cannot_start_or_go_on_keeps_or_hands_over_the_motion() -> None:
    model, _ = _start("top")
    upright = State(np.eye(3), np.array([0.0, 0.0, 9.0]), 0.0)
    sim = RigidBodySimulation(model, upright, angles=np.zeros(3))
    message = sim.set_integrator("euler_lagrange")
    assert message is not None and "sin θ in a denominator" in message and sim.integrator == "splitting4"
    with pytest.raises(ValueError, match="unknown integrator 'Euler-angle Lagrangian'"):
        sim.set_integrator("Euler-angle Lagrangian")
    asymmetric = RigidBodySimulation(Model(inertia=(1.0, 1.2, 0.5), mgl=6.0), _start("top")[1], angles=ANGLES)
    message = asymmetric.set_integrator("exact")
    assert message is not None and "does not apply" in message and asymmetric.integrator == "splitting4"


def test_each_rigid_scenes_menu_is_the_registrys_names_for_its_body(manual) -> None:
    seen = []
    for title in SCENES:
        manual.session.select_scene(title)
        scene = manual.session.scene
        sim = getattr(scene, "sim", None)
        if not isinstance(sim, RigidBodySimulation):
            continue
        seen.append(title)
        menu = scene.transport.gui_integrator
        assert list(menu.options) == applicable(sim.model), title
        assert menu.value == sim.integrator == realtime_method()
        registry = methods()
        for name in menu.options:  # the hint names the real-time ones, and only those
            assert (name in (menu.hint or "")) == registry[name].realtime, (title, name)
    assert {"Free body", "Heavy top", "Poinsot"} <= set(seen)


def test_a_method_added_to_the_registry_is_in_the_menu_and_steps(manual, monkeypatch) -> None:
    """Adding a method is one entry: here a toy one (DOP853 under another name); its run must be
    a top-level function (a lambda is refused with the reason)."""
    with pytest.raises(TypeError, match="must be a function defined at the top level"):
        Method("toy", "a lambda", lambda model: True, lambda m, s, t: integrate_dop853(m, s, t))
    toy = Method("toy", "scipy DOP853 under another name, for this test", lambda model: True, integrate_dop853)
    monkeypatch.setitem(methods(), "toy", toy)
    manual.session.select_scene("Heavy top")
    scene = manual.session.scene
    assert "toy" in scene.transport.gui_integrator.options
    assert isinstance(toy.stepper(*_start("top")), RunStepper)
    scene.transport.gui_integrator.value = "toy"
    assert scene.sim.integrator == "toy"
    start = scene.sim.state
    manual.session.play()
    manual.tick(0.25)
    assert scene.sim.t > 0.2 and manual.session.last_error is None
    _same(scene.sim.state, _direct("dop853", scene.sim.model, start, round(scene.sim.t / DT)))


def test_a_lesson_naming_an_unknown_method_is_refused_at_load(tmp_path: Path) -> None:
    data = json.loads((LESSONS_DIR / "5_lagrange.json").read_text(encoding="utf-8"))
    data["steps"][2]["integrator"] = "Euler-angle Lagrangian"  # the app's old name
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(LessonError, match=r"steps\[2\]\.integrator: 'Euler-angle Lagrangian' is not a method"):
        load_lesson(path, SCENES)


def test_no_method_name_is_compared_in_the_app() -> None:
    names = "|".join(re.escape(name) for name in methods())
    compared = re.compile(rf"""(==|!=|\bin)\s*\(?\s*["']({names})["']|["']({names})["']\s*(==|!=)""")
    old = re.compile(r"splitting4 \(real time\)|Euler-angle Lagrangian\"|INTEGRATOR_(EXACT|REALTIME|LAGRANGE)")
    for path in (ROOT / "app").rglob("*.py"):
        source = path.read_text(encoding="utf-8")
        assert not compared.search(source), path
        assert not old.search(source), path
