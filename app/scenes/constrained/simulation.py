"""The "Constrained particles" scene's simulation (no viser): its systems (`KINDS`), a run's
initial conditions (`ConstrainedSetup`), the run (`ConstrainedSimulation`) and the presets
(`app.scenes.constrained` says what it shows).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from app.i18n import N_, Phrases
from app.kit.core.common import RunEnded, SliderSpec
from app.kit.core.history import Snapshot
from app.kit.core.presets import PRESETS_DIR, Preset, PresetError, preset_entries
from app.kit.core.samples import SampleBuffer
from app.kit.core.trace import Trace
from physics._types import Array
from physics.constrained import (
    Evaluation,
    GridIntegrator,
    LeftTheConstraint,
    System,
    bead_on_turning_hoop,
    bead_on_turning_rod,
    double_pendulum,
    spherical_pendulum,
)

__all__ = [
    "GUIDE_POINTS",
    "KINDS",
    "ConstrainedSetup",
    "ConstrainedSimulation",
    "Kind",
    "load_constrained_presets",
    "setup_of",
]

PLOT_CAPACITY = 600  # samples (60 s at 10 Hz)
PLOT_SPARE = 620  # samples stored beyond it for the replay (62 s at 1×; less at slow motion)
PATH_SECONDS = 8.0  # [s] of simulated time kept in each particle's path
PATH_SPACING = 1.0 / 15.0  # [s] between stored path points
PATH_CHUNK = 4  # points: a chunk completes every 0.2 s; its head is resent at most at 10 Hz
GUIDE_POINTS = 73  # points of the drawn constraint curve (hoop, rod)

_MASS = SliderSpec("m", N_("m [kg]"), 0.1, 5.0, 0.1, N_("the particle's mass"))
_G = SliderSpec("g", N_("g [m/s²]"), 0.0, 20.0, 0.01, N_("gravity, along −z"))
_FORCE_SCALE = SliderSpec("force_scale", N_("arrow scale [m/N]"), 0.005, 0.5, 0.005,
                          N_("length of a force arrow per newton"))


ROD_END = N_("The bead reached the end of the rod (|r| = ℓ = {limit} m) just after t = {t} s and flew off it: "
             "on a turning rod r grows like cosh Ωt, so the motion on the rod ends there. ⟲ Reset to watch it again.")
"""The run's natural end (`RunEnded`): the bead leaves the rod; {limit} [m] and {t} [s] as numbers."""
ROD_END_WORDS = Phrases(
    (r"The bead reached the end of the rod \(\|r\| = ℓ = (?P<limit>[-0-9.e+]+) m\) just after t = (?P<t>[-0-9.]+) s "
     r"and flew off it: on a turning rod r grows like cosh Ωt, so the motion on the rod ends there\. "
     r"⟲ Reset to watch it again\.", ROD_END),
    numbers=("limit", "t"),
)
"""ROD_END as the room says it (English), matched whole and written in a reader's language."""


@dataclass(frozen=True)
class Kind:
    """A system of the scene: its key (presets' `system`), title, parameter and state sliders.

    param_specs: its parameters (the builder's arguments in order, plus the arrow scale last).
    q_specs, rate_specs: per coordinate, in display units (deg and deg/s for an angle, m and m/s
    for a length).  build(*params) -> System.
    """

    key: str
    title: str
    param_specs: tuple[SliderSpec, ...]
    q_specs: tuple[SliderSpec, ...]
    rate_specs: tuple[SliderSpec, ...]
    build: Callable[..., System]

    def system(self, params: Sequence[float]) -> System:
        return self.build(*params[:-1])


COORDINATE_HINT = N_("the generalized coordinate {q}")
VELOCITY_HINT = N_("the generalized velocity {q_dot}")
"""The hints of a coordinate's and a velocity's slider ({q}: "θ", {q_dot}: "dθ/dt"), translated by the view."""


def _angle(key: str, label: str, lo: float = -180.0, hi: float = 180.0) -> SliderSpec:
    return SliderSpec(key, f"{label} [deg]", lo, hi, 0.5, COORDINATE_HINT.format(q=label))


def _rate(key: str, label: str) -> SliderSpec:
    return SliderSpec(key, f"d{label}/dt [deg/s]", -1440.0, 1440.0, 1.0, VELOCITY_HINT.format(q_dot=f"d{label}/dt"))


def translated_state_spec(spec: SliderSpec, tr: Any) -> SliderSpec:
    """A coordinate's or velocity's slider spec (`_angle`, `_rate`) in the language of `tr`
    (`app.i18n.Translator`): its hint from the template, its label (a symbol and a unit) as it is."""
    symbol = spec.label.split(" [", 1)[0]
    if spec.hint == COORDINATE_HINT.format(q=symbol):
        hint = tr.gettext(COORDINATE_HINT).format(q=symbol)
    elif spec.hint == VELOCITY_HINT.format(q_dot=symbol):
        hint = tr.gettext(VELOCITY_HINT).format(q_dot=symbol)
    else:
        hint = tr.gettext(spec.hint)
    return replace(spec.translated(tr), hint=hint)


KINDS: dict[str, Kind] = {k.key: k for k in (
    Kind("hoop", "Bead on a turning hoop",
         (SliderSpec("R", N_("hoop radius R [m]"), 0.2, 2.5, 0.05, N_("the hoop's radius")),
          SliderSpec("Omega", N_("Ω [rad/s]"), 0.0, 15.0, 0.05, N_("the hoop turns about its vertical diameter at Ω; "
                        "above Ω² R = g the bottom is unstable")),
          _MASS, _G, _FORCE_SCALE),
         (_angle("q1", "θ"),), (_rate("v1", "θ"),), bead_on_turning_hoop),
    Kind("spherical", "Spherical pendulum",
         (SliderSpec("L", N_("rod L [m]"), 0.2, 2.5, 0.05, N_("the rod's length")), _MASS, _G, _FORCE_SCALE),
         (_angle("q1", "θ", 1.0, 179.0), _angle("q2", "φ")), (_rate("v1", "θ"), _rate("v2", "φ")),
         spherical_pendulum),
    Kind("double", "Double pendulum",
         (SliderSpec("L1", N_("rod L₁ [m]"), 0.2, 1.5, 0.05, N_("the upper rod")),
          SliderSpec("L2", N_("rod L₂ [m]"), 0.2, 1.5, 0.05, N_("the lower rod")),
          SliderSpec("m1", N_("m₁ [kg]"), 0.1, 5.0, 0.1, N_("the upper particle")),
          SliderSpec("m2", N_("m₂ [kg]"), 0.1, 5.0, 0.1, N_("the lower particle")), _G, _FORCE_SCALE),
         (_angle("q1", "θ₁"), _angle("q2", "θ₂")), (_rate("v1", "θ₁"), _rate("v2", "θ₂")), double_pendulum),
    Kind("rod", "Bead on a turning rod",
         (SliderSpec("Omega", N_("Ω [rad/s]"), 0.0, 5.0, 0.05, N_("the rod turns about space z at Ω")),
          SliderSpec("length", N_("rod half length ℓ [m]"), 0.5, 2.5, 0.05, N_("the bead leaves the rod at |r| = ℓ")),
          _MASS, _G, _FORCE_SCALE),
         (SliderSpec("q1", N_("r [m]"), -2.5, 2.5, 0.01, N_("the bead's signed distance from the axis")),),
         (SliderSpec("v1", N_("dr/dt [m/s]"), -5.0, 5.0, 0.01, N_("the bead's speed along the rod")),),
         bead_on_turning_rod),
)}


@dataclass(frozen=True)
class ConstrainedSetup:
    """What a run starts from.  kind: a key of KINDS.  params: its parameter sliders' values.
    q_shown, rates_shown: the initial q, q̇ in display units (deg, deg/s or m, m/s).
    ValueError (with the message to show) if anything is out of range or not a system."""

    kind: str
    params: tuple[float, ...]
    q_shown: tuple[float, ...]
    rates_shown: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"system {self.kind!r} refused: one of {', '.join(KINDS)}")
        kind = KINDS[self.kind]
        for specs, values in ((kind.param_specs, self.params), (kind.q_specs, self.q_shown),
                              (kind.rate_specs, self.rates_shown)):
            if len(values) != len(specs):
                keys = ", ".join(s.key for s in specs)
                raise ValueError(f"{len(specs)} values expected for {keys}, got {len(values)}")
            for spec, value in zip(specs, values):
                if spec.check(value) is None:
                    raise ValueError(spec.refusal(value))
        system = kind.system(self.params)  # ValueError from the physics' own checks
        if system.limit is not None and abs(self.q_shown[0]) >= system.limit:
            raise ValueError(f"r = {self.q_shown[0]:g} m refused: the bead must start on the rod, |r| < ℓ = "
                             f"{system.limit:g} m")

    @property
    def kind_spec(self) -> Kind:
        return KINDS[self.kind]

    def system(self) -> System:
        return self.kind_spec.system(self.params)

    @property
    def force_scale(self) -> float:
        return float(self.params[-1])

    def to_si(self, values: Sequence[float]) -> Array:
        """Display units -> SI (deg -> rad for the angles)."""
        angular = self.system().angular
        return np.array([math.radians(v) if a else float(v) for v, a in zip(values, angular)])

    def with_values(self, params: Sequence[float] | None = None, q_shown: Sequence[float] | None = None,
                    rates_shown: Sequence[float] | None = None) -> ConstrainedSetup:
        return ConstrainedSetup(self.kind, tuple(float(p) for p in (self.params if params is None else params)),
                                tuple(float(p) for p in (self.q_shown if q_shown is None else q_shown)),
                                tuple(float(p) for p in (self.rates_shown if rates_shown is None else rates_shown)))


def _shown(system: System, values: Array) -> list[float]:
    """SI -> display units (rad -> deg)."""
    return [math.degrees(float(v)) if a else float(v) for v, a in zip(values, system.angular)]


class ConstrainedSimulation:
    """A constrained particle system and its run (no viser).

    Attributes:
        setup: the run's initial conditions.  system: the System built from it.  t [s], version.
        integrator: the GridIntegrator (its q, q̇ are the state).  samples: plot samples
        (q1, q2 in display units, h, E = T + V, drift = |h − h₀| / scale).  paths: per particle,
        the `Trace` of its position [m].  h0: h at t = 0.  preset: the preset the run started from.
        run: bumped at every reset (the replay's history starts afresh).
    """

    def __init__(self, setup: ConstrainedSetup) -> None:
        self.preset: str | None = None
        self.version = 0
        self.run = 0
        self.samples = SampleBuffer(("q1", "q2", "h", "E", "drift"), PLOT_CAPACITY, PLOT_SPARE)
        self.set_setup(setup)

    # ------------------------------------------------------------------ the Simulation protocol
    @property
    def t(self) -> float:
        return self.integrator.t

    def reset(self) -> None:
        setup = self.setup
        self.integrator = GridIntegrator(self.system, setup.to_si(setup.q_shown), setup.to_si(setup.rates_shown))
        self._evaluation: Evaluation | None = None
        first = self.evaluation()
        self.h0 = first.h
        self.energy_scale = max(abs(first.T) + abs(first.V if math.isfinite(first.V) else 0.0), 1e-12)
        for path in self.paths:
            path.clear()
        self.samples.clear()
        self._record()
        self.take_sample()
        self.run += 1
        self.version += 1

    def advance(self, dt: float) -> None:
        """dt [s] of simulated time in grid steps (physics.constrained.GridIntegrator); on an
        error (singular coordinates) the state stays and the error is raised.  A bead that
        reaches the end of its rod flies off it: the run is over (`RunEnded`, said in plain
        words; the state stays at its last moment on the rod)."""
        if dt == 0.0:
            return
        try:
            self.integrator.advance(dt)
        except LeftTheConstraint:
            limit = self.system.limit
            raise RunEnded(ROD_END.format(limit=f"{limit:g}", t=f"{self.t:.2f}")) from None
        self._evaluation = None
        self._record()
        self.version += 1

    # ------------------------------------------------------------------ replay (app.kit.core.history)
    def snapshot(self) -> Snapshot:
        """The moment now: t (the state shown), the grid's step count, the grid state q, q̇ (n
        each), the state shown q, q̇ (n each), the samples' mark, each path's (count, first)."""
        marks = [float(m) for path in self.paths for m in path.mark()]
        values = [*self.integrator.snapshot(), float(self.samples.mark()), *marks]
        return Snapshot(np.array(values, dtype=float))

    def restore(self, snapshot: Snapshot, later: float = 0.0) -> None:
        """The recorded moment back bit for bit, samples and paths rewound to it; then `later` [s]
        on for display (grid steps from the recorded grid state, so the state the run showed or
        would have shown then; the histories stay).  ValueError, nothing changed, if the
        snapshot is not one of this run's."""
        v = snapshot.values
        at = 2 + 4 * len(self.system.coordinates)  # the integrator's: t, steps, q, q̇ on the grid and shown
        if v.shape != (at + 1 + 2 * len(self.paths),):
            raise ValueError("this snapshot is not a constrained-particles moment")
        marks = [(int(v[at + 1 + 2 * k]), int(v[at + 2 + 2 * k])) for k in range(len(self.paths))]
        if not (0 <= int(v[at]) <= self.samples.written) or not all(
                path.can_rewind(mark) for path, mark in zip(self.paths, marks)):
            raise ValueError("this snapshot is not one of this run's moments")
        self.integrator.restore(v[:at])
        self.samples.rewind(int(v[at]))
        for path, mark in zip(self.paths, marks):
            path.rewind(mark)
        if later > 0.0:
            try:
                self.integrator.advance(later)
            except ArithmeticError:  # shown as recorded
                pass
        self._evaluation = None
        self.evaluation()  # evaluated now, as every view asks: a restored copy equals one that is drawn
        self.version += 1

    def truncate(self) -> None:
        """Forget the samples and paths after now (a branch)."""
        self.samples.truncate()
        for path in self.paths:
            path.truncate()

    def fork(self) -> ConstrainedSimulation:
        """An exact, independent copy: setup, state, integrator grid, samples, paths, preset,
        version (a deep copy; the system's functions are shared, they hold no mutable state)."""
        return copy.deepcopy(self)

    def take_sample(self) -> None:
        ev = self.evaluation()
        q = _shown(self.system, ev.q)
        self.samples.append(self.t, {"q1": q[0], "q2": q[1] if len(q) > 1 else math.nan, "h": ev.h,
                                     "E": ev.T + ev.V, "drift": abs(ev.h - self.h0) / self.energy_scale})

    # ------------------------------------------------------------------ edits
    def set_setup(self, setup: ConstrainedSetup) -> None:
        """New initial conditions (the run restarts at t = 0); a new kind gets new paths."""
        old = getattr(self, "setup", None)
        self.setup = setup
        self.system = setup.system()
        if old is None or old.kind != setup.kind or not hasattr(self, "paths"):
            self.paths = [Trace(PATH_SECONDS, PATH_SPACING, PATH_CHUNK) for _ in range(self.system.n)]
        self.reset()

    def set_display(self, force_scale: float) -> None:
        """The arrow scale only (no restart)."""
        params = list(self.setup.params)
        params[-1] = force_scale
        self.setup = self.setup.with_values(params=params)
        self.version += 1

    # ------------------------------------------------------------------ readouts
    def evaluation(self) -> Evaluation:
        """Everything (5.1)-(5.13) says about the state now (cached until it changes)."""
        if self._evaluation is None:
            g = self.integrator
            self._evaluation = self.system.evaluate(g.q, g.q_dot, g.t)
        return self._evaluation

    def _record(self) -> None:
        x = self.evaluation().x
        for k, path in enumerate(self.paths):
            path.add(self.t, x[k])

    @property
    def q_shown(self) -> list[float]:
        return _shown(self.system, self.integrator.q)

    @property
    def rates_shown(self) -> list[float]:
        return _shown(self.system, self.integrator.q_dot)

    def guide(self) -> Array | None:
        """The constraint curve at time t (N points, 3) [m]: {x_0(q, t)} for q over the system's
        guide range (hoop, rod), or None."""
        if self.system.guide is None:
            return None
        lo, hi = self.system.guide
        rows = [self.system.positions([q], self.t)[0] for q in np.linspace(lo, hi, GUIDE_POINTS)]
        return np.array(rows, dtype=float)


# ---------------------------------------------------------------------------- presets
def load_constrained_presets() -> tuple[Preset, ...]:
    """The scene's presets: each entry has `system` (a key of KINDS), `params`, `q`, `rates`
    (objects keyed by the system's slider keys, display units); PresetError naming the field."""
    path = PRESETS_DIR / "constrained.json"
    presets = []
    for where, name, entry in preset_entries(path):
        try:
            kind = KINDS.get(entry.get("system", ""))
            if kind is None:
                raise PresetError(f"{where}.system: {entry.get('system')!r} is not one of {', '.join(KINDS)}")
            values = []
            for field, specs in (("params", kind.param_specs), ("q", kind.q_specs), ("rates", kind.rate_specs)):
                given = entry.get(field)
                if not isinstance(given, dict) or set(given) != {s.key for s in specs}:
                    raise PresetError(f"{where}.{field}: an object with keys {', '.join(s.key for s in specs)}")
                values.append(tuple(given[s.key] for s in specs))
            try:
                setup = ConstrainedSetup(kind.key, *values)
            except (ValueError, TypeError) as error:
                raise PresetError(f"{where} ({name}): {error}") from None
        except PresetError as error:
            raise PresetError(f"{path}: {error}") from None
        presets.append(Preset(name=name, group=str(entry.get("group", "Presets")), note=str(entry.get("note", "")),
                              params=(float(list(KINDS).index(kind.key)), *setup.params, *setup.q_shown,
                                      *setup.rates_shown),
                              angles_deg=(0.0, 0.0, 0.0), rates=()))
    return tuple(presets)


def setup_of(preset: Preset) -> ConstrainedSetup:
    """The setup a preset stands for (its params pack: kind index, parameters, q, q̇)."""
    kind = KINDS[list(KINDS)[int(preset.params[0])]]
    a = 1 + len(kind.param_specs)
    b = a + len(kind.q_specs)
    return ConstrainedSetup(kind.key, preset.params[1:a], preset.params[a:b], preset.params[b:])
