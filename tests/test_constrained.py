"""physics.constrained: equations of motion from x_i(q, t) alone, checked independently.

- Each preset's q̈ against sympy.physics.mechanics.LagrangesMethod, the Lagrangian written out
  by hand here (T from the particles' velocities, V from gravity), at random states.
- Jet derivatives against central finite differences.
- Closed forms: the turning hoop's equilibrium cos θ* = g/(Ω²R) and its small-oscillation rate,
  the double pendulum's normal modes, the rod's r = r₀ cosh Ωt.
- Conservation: Jacobi's integral / the energy drifts ≤ 1e-8 relative a minute (10 s run), the spherical
  pendulum's L_z; the residual of (5.13) on the simulated motion (≤ 1e-9 relative); the
  constraint forces' virtual work (per particle for one particle, summed for two).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics.constrained import (
    GridIntegrator,
    Jet,
    LeftTheConstraint,
    SingularCoordinatesError,
    System,
    bead_on_turning_hoop,
    bead_on_turning_rod,
    cos,
    derivatives,
    double_pendulum,
    hoop_equilibrium,
    hoop_small_oscillation_rate,
    sin,
    spherical_pendulum,
    sqrt,
)

RNG_SEED = 17
Q_DDOT_RTOL = 1e-11  # q̈ against sympy's, relative to the size of the terms
CONSERVED_RTOL_PER_MINUTE = 1e-8  # h's drift per minute of motion, relative to |T| + |V| at the start
LONG_RUN_S = 10.0  # [s] of motion in the conservation runs; the drift allowed follows it (linear in time)
CONSERVED_RTOL = CONSERVED_RTOL_PER_MINUTE * LONG_RUN_S / 60.0  # over LONG_RUN_S
RESIDUAL_RTOL = 1e-9  # (5.13) on the simulated motion, relative to the largest term


# ---------------------------------------------------------------------------- sympy references
def _sympy_accelerations(kind: str, params: dict[str, float]):  # type: ignore[no-untyped-def]
    """A function (q, q̇, t) -> q̈ from LagrangesMethod on the Lagrangian written out here."""
    sp = pytest.importorskip("sympy")  # the test extra (pyproject.toml); not needed at run time
    from sympy.physics.mechanics import LagrangesMethod, Particle, Point, ReferenceFrame, dynamicsymbols

    t = sp.symbols("t")
    N = ReferenceFrame("N")
    O = Point("O")
    O.set_vel(N, 0)
    g = params["g"]
    if kind == "hoop":
        th = dynamicsymbols("theta")
        qs = [th]
        R, W = params["R"], params["Omega"]
        p = O.locatenew("P", R * sp.sin(th) * sp.cos(W * t) * N.x + R * sp.sin(th) * sp.sin(W * t) * N.y
                        - R * sp.cos(th) * N.z)
        points = [(p, params["m"])]
    elif kind == "spherical":
        th, ph = dynamicsymbols("theta phi")
        qs = [th, ph]
        L = params["L"]
        p = O.locatenew("P", L * sp.sin(th) * sp.cos(ph) * N.x + L * sp.sin(th) * sp.sin(ph) * N.y
                        - L * sp.cos(th) * N.z)
        points = [(p, params["m"])]
    elif kind == "double":
        a, b = dynamicsymbols("a b")
        qs = [a, b]
        p1 = O.locatenew("P1", params["L1"] * (sp.sin(a) * N.x - sp.cos(a) * N.z))
        p2 = p1.locatenew("P2", params["L2"] * (sp.sin(b) * N.x - sp.cos(b) * N.z))
        points = [(p1, params["m1"]), (p2, params["m2"])]
    else:
        r = dynamicsymbols("r")
        qs = [r]
        W = params["Omega"]
        p = O.locatenew("P", r * sp.cos(W * t) * N.x + r * sp.sin(W * t) * N.y)
        points = [(p, params["m"])]
    particles, V = [], 0
    for k, (point, mass) in enumerate(points):
        point.set_vel(N, point.pos_from(O).dt(N))
        particles.append(Particle(f"p{k}", point, mass))
        V += mass * g * point.pos_from(O).dot(N.z)
    Lag = sum(part.kinetic_energy(N) for part in particles) - V
    lm = LagrangesMethod(Lag, qs)
    lm.form_lagranges_equations()
    rhs = lm.rhs()  # (q̇, q̈)
    m = len(qs)
    q_dots = [q.diff(t) for q in qs]
    xs, vs = sp.symbols(f"x0:{m}"), sp.symbols(f"v0:{m}")
    subs = {**{qd: v for qd, v in zip(q_dots, vs)}}
    q_ddot = [rhs[m + j].subs(subs).subs({q: x for q, x in zip(qs, xs)}) for j in range(m)]
    fn = sp.lambdify((*xs, *vs, t), q_ddot, "math")
    return lambda q, v, time: np.array(fn(*q, *v, time), dtype=float)


CASES = [
    ("hoop", {"R": 1.3, "Omega": 3.7, "m": 0.8, "g": 9.81}, lambda p: bead_on_turning_hoop(**p)),
    ("spherical", {"L": 1.2, "m": 1.5, "g": 9.81}, lambda p: spherical_pendulum(**p)),
    ("double", {"L1": 0.9, "L2": 1.3, "m1": 1.7, "m2": 0.6, "g": 9.81}, lambda p: double_pendulum(**p)),
    ("rod", {"Omega": 1.4, "length": 2.0, "m": 0.7, "g": 9.81}, lambda p: bead_on_turning_rod(**p)),
]


@pytest.mark.parametrize(("kind", "params", "build"), CASES, ids=[c[0] for c in CASES])
def test_equations_of_motion_match_sympy_lagranges_method(kind, params, build) -> None:  # type: ignore[no-untyped-def]
    system: System = build(params)
    reference = _sympy_accelerations(kind, params)
    rng = np.random.default_rng(RNG_SEED)
    for _ in range(25):
        q = rng.uniform(0.2, 2.9, system.m) * rng.choice([-1.0, 1.0], system.m)
        if kind == "spherical":
            q[0] = abs(q[0])  # θ in (0, π): away from the coordinates' poles
        q_dot = rng.normal(0.0, 2.0, system.m)
        t = float(rng.uniform(0.0, 10.0))
        expected = reference(q, q_dot, t)
        got = system.accelerations(q, q_dot, t)
        ev = system.evaluate(q, q_dot, t)
        scale = 1.0 + float(np.max(np.abs(expected)))
        np.testing.assert_allclose(got, expected, rtol=0.0, atol=Q_DDOT_RTOL * scale)
        np.testing.assert_allclose(ev.q_ddot, got, rtol=0.0, atol=Q_DDOT_RTOL * scale)  # both routes agree


# ---------------------------------------------------------------------------- jets
def _fancy(q, t):  # type: ignore[no-untyped-def]
    """A position function using every Jet operation."""
    a, b = q[0], q[1]
    return [[sin(a) * cos(b) / (2.0 + cos(t * a)), sqrt(1.5 + a * a) - b**3, np.exp(0.3 * a * b) - np.log(2.0 + t)],
            [1.0 / (1.2 + sin(b)), a - 2.0 * b + t * t, 0.5]]


def test_jet_derivatives_match_central_finite_differences() -> None:
    rng = np.random.default_rng(RNG_SEED)
    h = 1e-5  # central differences: truncation ~h² ~ 1e-10, rounding ~1e-16 / h ~ 1e-11
    for _ in range(10):
        q, q_dot, t = rng.uniform(-1, 1, 2), rng.normal(0, 1, 2), float(rng.uniform(0, 2))

        def x_of(qq, tt):  # type: ignore[no-untyped-def]
            return np.array([[float(c) for c in row] for row in _fancy(list(qq), tt)])

        x, J, x_t, x_dot, x_dot_q, a0 = derivatives(_fancy, q, q_dot, t)
        np.testing.assert_allclose(x, x_of(q, t), atol=1e-15)
        for j in range(2):
            e = np.eye(2)[j] * h
            np.testing.assert_allclose(J[:, :, j], (x_of(q + e, t) - x_of(q - e, t)) / (2 * h), atol=1e-8)
        np.testing.assert_allclose(x_t, (x_of(q, t + h) - x_of(q, t - h)) / (2 * h), atol=1e-8)

        def along(s, q=q, q_dot=q_dot, t=t):  # type: ignore[no-untyped-def]  # the motion q + s q̇, t + s
            return x_of(q + s * q_dot, t + s)

        np.testing.assert_allclose(x_dot, (along(h) - along(-h)) / (2 * h), atol=1e-8)
        h2 = 1e-4  # second differences: truncation ~h² ~ 1e-8, rounding ~1e-16 / h² ~ 1e-8
        np.testing.assert_allclose(a0, (along(h2) - 2 * along(0.0) + along(-h2)) / h2**2, atol=5e-7)
        for j in range(2):  # ∂ẋ/∂q_j: ẋ at q ± h e_j with q̇ held
            e = np.eye(2)[j] * h
            plus = derivatives(_fancy, q + e, q_dot, t)[3]
            minus = derivatives(_fancy, q - e, q_dot, t)[3]
            np.testing.assert_allclose(x_dot_q[:, :, j], (plus - minus) / (2 * h), atol=1e-8)


def test_jets_on_numpy_ufuncs_and_floats_agree() -> None:
    jet = Jet(0.7, (1.0, 0.0), 0.3, (0.0, 0.0), 0.0)
    for fn, ref in ((np.sin, math.sin), (np.cos, math.cos), (np.sqrt, math.sqrt), (np.exp, math.exp),
                    (np.log, math.log)):
        assert fn(jet).v == ref(0.7)
    assert (2.0 * jet - jet / 2.0 + 1.0).v == pytest.approx(2.05)
    assert sin(0.7) == math.sin(0.7) and cos(0.7) == math.cos(0.7)


# ---------------------------------------------------------------------------- closed forms
def _settle(system: System, q0: float, seconds: float, dt: float = 1.0 / 60.0) -> tuple[np.ndarray, np.ndarray]:
    g = GridIntegrator(system, [q0], [0.0])
    ts, qs = [0.0], [q0]
    for _ in range(int(round(seconds / dt))):
        g.advance(dt)
        ts.append(g.t)
        qs.append(float(g.q[0]))
    return np.array(ts), np.array(qs)


def _frequency(ts: np.ndarray, qs: np.ndarray) -> float:
    """[rad/s] from the times of successive up-crossings of the mean (linear interpolation)."""
    mean = 0.5 * (qs.max() + qs.min())
    s = qs - mean
    ups = [ts[k] - s[k] * (ts[k + 1] - ts[k]) / (s[k + 1] - s[k]) for k in range(len(s) - 1) if s[k] < 0 <= s[k + 1]]
    return 2.0 * math.pi / float(np.mean(np.diff(ups)))


@pytest.mark.parametrize("Omega", [2.0, 5.0, 8.0])
def test_turning_hoop_equilibrium_and_small_oscillation_rate(Omega: float) -> None:
    R, g = 1.0, 9.81
    theta_star = hoop_equilibrium(R, Omega, g)
    if Omega * Omega * R > g:
        assert math.cos(theta_star) == pytest.approx(g / (Omega * Omega * R), rel=1e-14)
    system = bead_on_turning_hoop(R, Omega, 1.0, g)
    assert abs(system.accelerations(np.array([theta_star]), np.array([0.0]), 0.3)[0]) < 1e-12  # at rest there
    amplitude = 1e-3  # [rad]: nonlinear frequency shift ~ amplitude² ~ 1e-6
    ts, qs = _settle(system, theta_star + amplitude, 12.0)
    assert abs(0.5 * (qs.max() + qs.min()) - theta_star) < 1e-5  # oscillates about θ*
    assert _frequency(ts, qs) == pytest.approx(hoop_small_oscillation_rate(R, Omega, g), rel=1e-4)


def test_double_pendulum_normal_mode_frequencies() -> None:
    """Equal rods L and masses m: ω² = (2 ∓ √2) g/L, mode shapes θ₂/θ₁ = ±√2."""
    L, g = 1.0, 9.81
    system = double_pendulum(L, L, 1.0, 1.0, g)
    for sign, omega in ((1.0, math.sqrt((2 - math.sqrt(2)) * g / L)), (-1.0, math.sqrt((2 + math.sqrt(2)) * g / L))):
        amplitude = 1e-3
        integ = GridIntegrator(system, [amplitude, sign * math.sqrt(2) * amplitude], [0.0, 0.0])
        ts, q1, q2 = [0.0], [amplitude], [sign * math.sqrt(2) * amplitude]
        for _ in range(600):
            integ.advance(1.0 / 60.0)
            ts.append(integ.t)
            q1.append(float(integ.q[0]))
            q2.append(float(integ.q[1]))
        assert _frequency(np.array(ts), np.array(q1)) == pytest.approx(omega, rel=1e-4)
        keep = np.abs(q1) > 0.5 * amplitude
        np.testing.assert_allclose(np.array(q2)[keep] / np.array(q1)[keep], sign * math.sqrt(2), rtol=1e-3)


def test_bead_on_turning_rod_flies_out_as_cosh_and_leaves_the_rod() -> None:
    Omega, r0 = 1.2, 0.15
    system = bead_on_turning_rod(Omega, 2.0, 1.0, 9.81)
    integ = GridIntegrator(system, [r0], [0.0])
    for _ in range(120):
        integ.advance(1.0 / 60.0)
    assert integ.q[0] == pytest.approx(r0 * math.cosh(Omega * integ.t), rel=1e-12)
    with pytest.raises(LeftTheConstraint, match="left the rod"):
        for _ in range(600):
            integ.advance(1.0 / 60.0)
    assert abs(integ.q[0]) <= 2.0 and integ.t < math.acosh(2.0 / r0) / Omega  # the state before it left, kept


# ---------------------------------------------------------------------------- conservation, residual, (5.7)
LONG_RUNS = [
    ("turning hoop, fast", bead_on_turning_hoop(1.0, 5.0, 1.0, 9.81), [math.radians(5.0)], [0.0]),
    ("turning hoop, over the top", bead_on_turning_hoop(1.0, 4.0, 1.0, 9.81), [2.5], [6.0]),
    ("spherical", spherical_pendulum(1.2, 1.0, 9.81), [math.radians(60.0), 0.0], [0.0, math.radians(120.0)]),
    ("double, chaotic", double_pendulum(1.0, 1.0, 1.0, 1.0, 9.81), [math.radians(110.0), math.radians(150.0)],
     [0.0, 0.0]),
    ("double, unequal", double_pendulum(0.7, 1.2, 2.0, 0.5, 9.81), [2.0, -1.0], [1.0, 3.0]),
]


@pytest.mark.parametrize(("name", "system", "q0", "v0"), LONG_RUNS, ids=[r[0] for r in LONG_RUNS])
def test_conserved_quantity_drift_a_minute_and_the_5_13_residual_on_the_motion(name, system, q0, v0) -> None:  # type: ignore[no-untyped-def]
    """Frames of 1/60 s ± 10 % (the grid makes the motion independent of them), LONG_RUN_S of
    motion: h may drift CONSERVED_RTOL_PER_MINUTE in proportion (an RK8 step's error in h adds
    up linearly in time; measured worst case, the chaotic double pendulum: 3e-11 after 10 s,
    5e-10 after 60 s, against 1.7e-9 allowed here and 1e-8 over 60 s)."""
    integ = GridIntegrator(system, q0, v0)
    first = system.evaluate(q0, v0, 0.0)
    scale = abs(first.T) + abs(first.V)
    rng = np.random.default_rng(RNG_SEED)
    worst_h = worst_residual = 0.0
    L_z0 = None
    while integ.t < LONG_RUN_S:
        integ.advance(1.0 / 60.0 * (1.0 + 0.2 * (rng.random() - 0.5)))
        if rng.random() < 0.05 or integ.t >= LONG_RUN_S:
            ev = system.evaluate(integ.q, integ.q_dot, integ.t)
            worst_h = max(worst_h, abs(ev.h - first.h) / scale)
            terms = ev.terms
            size = max(float(np.max(np.abs(np.concatenate([terms.ddt_dT_dqdot, terms.dT_dq, terms.Q])))), 1.0)
            worst_residual = max(worst_residual, float(np.max(np.abs(terms.residual))) / size)
            if name == "spherical":
                L_z = float(ev.p[1])  # p_φ = m (x ẏ − y ẋ)
                x, v = ev.x[0], ev.x_dot[0]
                assert L_z == pytest.approx(system.masses[0] * (x[0] * v[1] - x[1] * v[0]), rel=1e-12)
                L_z0 = L_z if L_z0 is None else L_z0
                assert abs(L_z - L_z0) <= CONSERVED_RTOL * abs(L_z0)
    assert worst_h <= CONSERVED_RTOL, f"{name}: h drifted by {worst_h:.1e} relative"
    assert worst_residual <= RESIDUAL_RTOL, f"{name}: residual {worst_residual:.1e}"


def test_the_energy_is_not_conserved_on_a_moving_constraint_but_h_is() -> None:
    system = bead_on_turning_hoop(1.0, 5.0, 1.0, 9.81)
    integ = GridIntegrator(system, [0.1], [0.0])
    first = system.evaluate([0.1], [0.0], 0.0)
    energies = []
    for _ in range(120):
        integ.advance(1.0 / 60.0)
        ev = system.evaluate(integ.q, integ.q_dot, integ.t)
        energies.append(ev.T + ev.V)
        assert ev.h == pytest.approx(first.h, rel=1e-10)
        assert ev.T1 == pytest.approx(0.0, abs=1e-12)  # on the hoop ∂x/∂θ ⊥ ∂x/∂t
    assert max(energies) - min(energies) > 1.0  # [J] the motor does work


@pytest.mark.parametrize(("kind", "params", "build"), CASES, ids=[c[0] for c in CASES])
def test_constraint_forces_do_no_virtual_work(kind, params, build) -> None:  # type: ignore[no-untyped-def]
    system: System = build(params)
    rng = np.random.default_rng(RNG_SEED)
    for _ in range(10):
        q = rng.uniform(0.3, 2.8, system.m)
        q_dot = rng.normal(0.0, 2.0, system.m)
        ev = system.evaluate(q, q_dot, float(rng.uniform(0, 5)))
        size = float(np.max(np.abs(ev.C))) * float(np.max(np.abs(ev.J))) + 1.0
        np.testing.assert_allclose(ev.virtual_work.sum(axis=0), 0.0, atol=1e-13 * size)  # (5.8)-(5.11)
        np.testing.assert_allclose(ev.Q, np.einsum("nc,ncj->j", ev.F, ev.J), atol=1e-13 * size)  # (5.12)
        if system.n == 1:
            np.testing.assert_allclose(ev.virtual_work, 0.0, atol=1e-13 * size)  # (5.7) per particle
            assert np.linalg.norm(ev.C) > 1e-3  # there is a constraint force, and it is perpendicular
        else:  # the middle rod: along itself, equal and opposite, virtual work on each particle
            rod = ev.x[1] - ev.x[0]
            C2 = ev.C[1]
            assert np.linalg.norm(np.cross(C2, rod)) < 1e-10 * np.linalg.norm(C2) * np.linalg.norm(rod)
            assert ev.virtual_work[0, 0] == pytest.approx(-ev.virtual_work[1, 0], rel=1e-12)


def test_singular_coordinates_and_bad_parameters_are_refused_clearly() -> None:
    system = spherical_pendulum(1.0, 1.0, 9.81)
    with pytest.raises(SingularCoordinatesError, match="singular"):
        system.accelerations(np.array([0.0, 0.3]), np.array([0.1, 0.1]), 0.0)
    for bad in ({"L": 0.0}, {"L": -1.0}, {"L": math.nan}, {"m": 0.0}, {"g": math.inf}):
        with pytest.raises(ValueError, match="refused"):
            spherical_pendulum(**bad)
    with pytest.raises(ValueError, match="refused"):
        bead_on_turning_hoop(R=1.0, Omega=math.nan)
