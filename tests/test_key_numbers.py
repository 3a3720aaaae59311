"""The followers' key numbers come from the room's simulation, not from the presenter's widgets
(issue 34, row 2): a view does not keep its sliders current while another tab shows (the rigid
body's sliders follow the motion only on the Setup tab), so numbers read from the widgets froze
while t ran on.

- Every scene of the registry: its key numbers do not change when the slider widgets are set to
  stale values (the widgets are not their source).
- The rigid-body scenes, playing with another tab open (Heavy top on the Energy tab, preset
  Loop): φ, θ, ψ and the rates equal the values computed from the simulation's state (Euler
  angles z-x-z of R_space_body, Euler rates of ω_b, in degrees, rounded to the slider's step),
  and they change over time while the sliders stand still.
- Constrained particles (its own key numbers, `readouts.key_numbers_text`), playing on the
  Readout tab: θ, φ and their rates are the integrator's q, q̇ in degrees, and move.
- Across workers (app.lecture.bus ships `Lectern.follower_status()`, whose words are `status()`): the status a
  worker would ship carries moving numbers while the presenter's sliders are stale, and with two
  workers on one Redis, the status the other worker's followers read moves with t.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import pytest
import viser
from conftest import poll_until
from test_bus import _present as present_on
from test_bus import workers

from app.kit.core.common import SliderSpec, wrap_deg
from app.kit.rigid.view import ANGLE_SPECS, RigidBodyView
from app.scenes import SCENES
from physics.euler import euler_rates_from_omega_body, euler_zxz_from_matrix

__all__ = ["workers"]  # a fixture, for pytest

CODE = "24681357"

# (scene, preset, tab open while playing): a moving run of each rigid-body scene with a tab
# other than Setup open (the tab on which the sliders follow the motion).
RIGID_RUNS = [
    ("Heavy top", "Loop", "Energy"),
    ("Free body", "Dzhanibekov", "Plots"),
    ("Poinsot", "Dzhanibekov", "Readout"),
]


def key_values(lines: list[str]) -> dict[str, float]:
    """"label = number" lines -> {label: number} (other lines left out)."""
    found = {}
    for line in lines:
        match = re.fullmatch(r"(.+) = (-?[0-9.e+-]+|nan|inf)", line)
        if match:
            found[match.group(1)] = float(match.group(2))
    return found


def english_lines(view: Any) -> list[str]:
    """The view's key numbers as an English follower's panel writes them."""
    return [number.words() for number in view.key_numbers()]


def bound_sliders(view: Any) -> list[Any]:
    """The slider widgets the view's key numbers are labelled after (its bound sliders but the
    timeline's, which says t, shown in the status already)."""
    timeline = view.timeline.binding if view.timeline is not None else None
    bindings = [*view._bindings, *getattr(view, "_system_bindings", ())]  # a constrained system's own
    return [b.handle for b in bindings if isinstance(b.handle, viser.GuiSliderHandle) and b is not timeline]


def make_stale(view: Any) -> dict[str, Any]:
    """Write a value into every bound slider widget (its callbacks silenced, as the server's
    writes are) that differs from the one shown: what a slider no longer kept current shows.
    {label: the stale value}."""
    stale = {}
    for handle in bound_sliders(view):
        value = float(handle.value)
        other = float(handle.min) if value != float(handle.min) else float(handle.max)
        view.quiet.write(handle, other)
        stale[str(handle.label)] = other
    return stale


def expected_rigid(view: RigidBodyView) -> dict[str, float]:
    """φ, θ, ψ [deg] and the rate sliders' values computed here from the simulation's state
    (R_space_body, ω_b), rounded to the sliders' steps."""
    state = view.sim.state
    angles = np.asarray(euler_zxz_from_matrix(state.R_space_body), dtype=float)
    phi, theta, psi = np.degrees(angles)
    values = {ANGLE_SPECS[0].label: wrap_deg(float(phi)), ANGLE_SPECS[1].label: float(theta),
              ANGLE_SPECS[2].label: wrap_deg(float(psi))}
    phi_dot, theta_dot, psi_dot = (math.degrees(r) for r in euler_rates_from_omega_body(angles, state.omega_body))
    omega = state.omega_body
    by_key = {"phi_dot": phi_dot, "theta_dot": theta_dot, "psi_dot": psi_dot, "spin": float(omega[2]),
              "w1": float(omega[0]), "w2": float(omega[1]), "w3": float(omega[2])}
    for spec in view.rate_specs:
        values[spec.label] = by_key[spec.key]
    specs: dict[str, SliderSpec] = {s.label: s for s in (*ANGLE_SPECS, *view.rate_specs)}
    return {label: specs[label].rounded(value) for label, value in values.items()}


def assert_close_to_the_state(shown: dict[str, float], expected: dict[str, float], view: RigidBodyView) -> None:
    """Each key number within one slider step of the value computed from the state (the two
    roundings may fall on either side of a half step; angles compared modulo 360°)."""
    steps = {s.label: s.step for s in (*ANGLE_SPECS, *view.rate_specs)}
    for label, value in expected.items():
        assert label in shown, f"no key number {label!r} in {sorted(shown)}"
        difference = shown[label] - value
        if label in (ANGLE_SPECS[0].label, ANGLE_SPECS[2].label):
            difference = (difference + 180.0) % 360.0 - 180.0
        assert abs(difference) <= steps[label] + 1e-9, \
            f"{label}: the followers read {shown[label]}, the state says {value} (t = {view.sim.t:.3f} s)"


@pytest.mark.parametrize("title", list(SCENES))
def test_key_numbers_do_not_come_from_the_slider_widgets(manual, title: str) -> None:
    session = manual.session
    session.select_scene(title)
    view = session.scene
    before = view.key_numbers()
    widgets = {str(h.label): float(h.value) for h in bound_sliders(view)}
    shown = key_values([number.words() for number in before])
    # Fresh, the sliders and the key numbers named after them say the same (the same lines as before the fix).
    assert {label: value for label, value in shown.items() if label in widgets} == \
        pytest.approx({label: value for label, value in widgets.items() if label in shown}), title
    stale = make_stale(view)
    assert view.key_numbers() == before, f"{title}: the key numbers followed the widgets set to {stale}"


@pytest.mark.parametrize(("title", "preset", "tab"), RIGID_RUNS)
def test_key_numbers_follow_the_motion_with_another_tab_open(manual, title: str, preset: str, tab: str) -> None:
    session = manual.session
    session.select_scene(title)
    session.apply_preset(preset)
    view = session.scene
    assert isinstance(view, RigidBodyView)
    view.show_tab(tab)
    session.play()
    widgets = {str(h.label): h.value for h in bound_sliders(view)}
    readings = []
    for _ in range(3):
        manual.tick(0.5)
        shown = key_values(english_lines(view))
        assert_close_to_the_state(shown, expected_rigid(view), view)
        readings.append((view.sim.t, shown))
    # The sliders were not kept current meanwhile (another tab showed) ...
    assert {str(h.label): h.value for h in bound_sliders(view)} == widgets
    # ... and the numbers moved with t all the same.
    phi = ANGLE_SPECS[0].label
    assert readings[0][0] < readings[1][0] < readings[2][0]
    assert len({shown[phi] for _, shown in readings}) == 3 or title == "Poinsot", readings
    assert readings[0][1] != readings[1][1] != readings[2][1], readings
    assert session.last_error is None


def test_constrained_key_numbers_follow_q_with_another_tab_open(manual) -> None:
    """The spherical pendulum playing with its Readout tab open (its q, q̇ sliders follow the
    motion on the Setup tab only): θ, φ and their rates are the integrator's q, q̇ in degrees."""
    session = manual.session
    session.select_scene("Constrained particles")
    session.apply_preset("Spherical pendulum")
    view = session.scene
    view.show_tab("Readout")
    session.play()
    kind = view.sim.setup.kind_spec
    widgets = [h.value for h in bound_sliders(view)]
    readings = []
    for _ in range(3):
        manual.tick(0.5)
        shown = key_values(english_lines(view))
        q_deg = np.degrees(view.sim.integrator.q)
        q_dot_deg = np.degrees(view.sim.integrator.q_dot)
        for spec, value in zip((*kind.q_specs, *kind.rate_specs), (*q_deg, *q_dot_deg)):
            assert spec.label in shown, f"no key number {spec.label!r} in {view.key_numbers()}"
            difference = shown[spec.label] - float(value)
            if (spec.lo, spec.hi) == (-180.0, 180.0):
                difference = (difference + 180.0) % 360.0 - 180.0
            assert abs(difference) <= spec.step, (spec.label, shown[spec.label], float(value), view.sim.t)
        readings.append(shown)
    assert [h.value for h in bound_sliders(view)] == widgets  # the sliders stood still ...
    assert readings[0] != readings[1] != readings[2], readings  # ... the numbers moved
    assert session.last_error is None


def test_the_status_a_worker_ships_carries_moving_numbers_while_the_sliders_are_stale(lecture_hall) -> None:
    """`Lectern.status()` is the words of what app.lecture.bus ships to the other workers'
    followers (`Lectern.follower_status`, in its "hall" message): with the presenter on the
    Energy tab of a playing heavy top, and its slider widgets stale, the shipped φ moves with t
    and matches the state."""
    hall = lecture_hall
    presenter = hall.join()
    presenter.select_scene("Heavy top")
    presenter.present(CODE)
    assert presenter.mode == "presenting", presenter.last_error
    presenter.apply_preset("Loop")
    view = presenter.scene
    view.show_tab("Energy")
    presenter.play()
    make_stale(view)
    phi = ANGLE_SPECS[0].label
    shipped = []
    for _ in range(3):
        hall.frames(30)  # 0.5 s: one FOLLOW_PERIOD
        status = hall.app.lectern.status()
        lines = [line.strip(" `*-") for line in status.splitlines()]
        numbers = key_values(lines)
        assert phi in numbers, f"no {phi} line in the shipped status:\n{status}"
        assert_close_to_the_state(numbers, expected_rigid(view), view)
        shipped.append(numbers[phi])
    assert len(set(shipped)) == 3, f"the shipped φ stood still: {shipped}"


def test_a_follower_on_another_worker_reads_moving_numbers_while_the_sliders_are_stale(workers) -> None:
    """Two workers on one Redis (tests/test_bus.py): the presenter on A plays Heavy top (Loop)
    on its Energy tab, its slider widgets stale; B's followers' status (what the bus brought,
    `RemoteShow.status`) shows φ taking new values as t runs on."""
    workers.start("a")
    b = workers.start("b")
    presenter = present_on(workers, "a", "Heavy top")
    follower, _ = workers.connect("b")
    poll_until(lambda: follower.mode == "following", timeout=30.0)
    presenter.guard("test", presenter.apply_preset)("Loop")
    view = presenter.scene
    presenter.guard("test", lambda: view.show_tab("Energy"))()
    presenter.guard("test", presenter.play)()
    with presenter.lock:
        make_stale(view)
    phi = ANGLE_SPECS[0].label
    seen: dict[str, float] = {}

    def moved() -> bool:
        status = b.lectern.status()
        time_line = re.search(r"t = ([0-9.]+) s", status)
        numbers = key_values([line.strip(" `*-") for line in status.splitlines()])
        if "playing" in status and time_line and phi in numbers:
            seen.setdefault(time_line.group(1), numbers[phi])
        return len(set(seen.values())) >= 3

    try:
        poll_until(moved, timeout=30.0, interval=0.1)
    except AssertionError:
        raise AssertionError(f"B's followers read φ by t: {seen}; status now:\n{b.lectern.status()}") from None
    assert b.lectern.remote is not None and b.lectern.remote.worker == "a"
    assert presenter.last_error is None and follower.last_error is None


@pytest.fixture
def lecture_hall():
    from conftest import LectureHall

    hall = LectureHall(CODE)
    try:
        yield hall
    finally:
        hall.close()
