"""Speed against error: every method on the public cases in benchmarks/cases/, measured in one run.

For each case and method (over a sweep of tolerances or step sizes) it records the maximum
attitude error against the reference (the exact solution where one exists, otherwise DOP853 at
rtol 1e-14 checked against the adaptive method at the same tolerance), the energy and |L| drift,
the number of evaluations and the wall time.  The peer is what a user would otherwise pick:
scipy `solve_ivp` DOP853 on the quaternion ODE; MuJoCo's RK4 joins when `mujoco` is installed.
Ratios "at equal error" interpolate each method's wall time at the peer's error levels on the
log-log work-precision curve.

    python benchmarks/work_precision.py            # writes benchmarks/results.md, docs/img/work_precision.png
    python benchmarks/work_precision.py --quick    # fewer points, for a smoke run
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import math
import platform
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from physics import free_kick, integrators  # noqa: E402
from physics.casefile import Case, load_case  # noqa: E402
from physics.dynamics import Model, Trajectory, angular_momentum_space, energy  # noqa: E402
from physics.methods import exact_solution, simulate_realtime  # noqa: E402

CASES = ROOT / "benchmarks" / "cases"


@dataclass
class Point:
    """One run: method, setting (tolerance or step), errors, cost."""

    case: str
    method: str
    setting: str
    attitude_error: float  # max rotation angle of R_refᵀ R [rad]
    energy_drift: float  # max |E - E0| / |E0|
    L_drift: float  # max ||L_s| - |L_s0|| / |L_s0|
    evaluations: int
    wall_s: float


def attitude_error(R_ref: np.ndarray, R: np.ndarray) -> float:
    return float(Rotation.from_matrix(np.swapaxes(R_ref, 1, 2) @ R).magnitude().max())


def drifts(model: Model, traj: Trajectory) -> tuple[float, float]:
    """(max |E - E0| / |E0|, max drift of the conserved part of L / |L0|): |L_s| for a free body,
    L_s·e_z for a heavy top (gravity turns L about e_z); nan where nothing is conserved."""
    E = np.array([energy(model, r, w) for r, w in zip(traj.R_space_body, traj.omega_body)])
    L = np.array([angular_momentum_space(model, r, w) for r, w in zip(traj.R_space_body, traj.omega_body)])
    L0 = max(float(np.linalg.norm(L[0])), 1e-300)
    energy_drift = float(np.max(np.abs(E - E[0])) / max(abs(E[0]), 1e-300)) if model.conservative else math.nan
    if model.kind == "free":
        conserved = np.linalg.norm(L, axis=1)
    elif model.kind == "heavy_top":
        conserved = L[:, 2]
    else:
        return energy_drift, math.nan
    return energy_drift, float(np.max(np.abs(conserved - conserved[0])) / L0)


def reference(case: Case) -> tuple[np.ndarray, str]:
    """R (N,3,3) of the reference and how it was obtained."""
    try:
        R, _ = exact_solution(case.model, case.state0)(case.t)
        return R, "exact solution"
    except ValueError:
        R = integrators.integrate_dop853(case.model, case.state0, case.t, rtol=3e-14, atol=1e-16).R_space_body
        R2 = integrators.integrate_adaptive(case.model, case.state0, case.t, rtol=3e-14, atol=1e-16).R_space_body
        return R, f"DOP853 rtol 3e-14 (adaptive at 3e-14 agrees to {attitude_error(R, R2):.1e} rad)"


def best_of(runs: int, fn):
    """The run with the least wall time of `runs` repeats (the others only warm up)."""
    best = None
    for _ in range(runs):
        traj = fn()
        if best is None or traj.wall_s < best.wall_s:
            best = traj
    return best


def run_point(case_name: str, case: Case, R_ref: np.ndarray, method: str, setting: str, fn) -> Point:
    traj = fn()
    energy_drift, L_drift = drifts(case.model, traj)
    return Point(case_name, method, setting, attitude_error(R_ref, traj.R_space_body), energy_drift, L_drift,
                 traj.evaluations, traj.wall_s)


def sweeps(case: Case, quick: bool) -> dict[str, list[tuple[str, object]]]:
    """method -> [(setting label, thunk returning a Trajectory)]."""
    model, s0, t = case.model, case.state0, case.t
    if quick:
        tolerances, angles = [1e-6, 1e-9, 1e-12], [0.2, 0.05]
    elif t[-1] > 1000.0:  # the long run: fewer, costlier points
        tolerances, angles = [1e-8, 1e-10, 1e-12], [0.1, 0.05]
    else:
        tolerances, angles = [1e-6, 1e-8, 1e-10, 1e-11, 1e-12, 1e-13], [0.4, 0.2, 0.1, 0.05, 0.025, 0.0125]
    scale = max(integrators.rate_scale(model, s0.R_space_body, s0.omega_body), 1.0)
    plan: dict[str, list[tuple[str, object]]] = {
        "dop853 (scipy)": [(f"rtol {tol:.0e}", lambda tol=tol: integrators.integrate_dop853(
            model, s0, t, rtol=tol, atol=tol * 1e-2)) for tol in tolerances],
        "adaptive": [(f"rtol {tol:.0e}", lambda tol=tol: integrators.integrate_adaptive(
            model, s0, t, rtol=tol, atol=tol * 1e-2)) for tol in tolerances],
        "splitting4": [(f"hΩ {a:g}", lambda a=a: integrators.integrate_splitting(model, s0, t, h=a / scale))
                       for a in angles],
    }
    try:
        exact_solution(model, s0)
        plan["exact"] = [("closed form", lambda: _timed_exact(model, s0, t))]
    except ValueError:
        if free_kick.applies(model):  # a torque without a closed form: the kick-drift composition
            plan["free_kick"] = [(f"tol {tol:.0e} (h {free_kick.step_for(model, s0, tol):.3g} s)",
                                  lambda tol=tol: free_kick.integrate_free_kick(model, s0, t, tol=tol))
                                 for tol in tolerances]
    if importlib.util.find_spec("mujoco") is not None:
        steps = (1e-2, 1e-3) if t[-1] <= 1000.0 else (1e-2,)
        plan["mujoco rk4"] = [(f"h {h:g}", lambda h=h: mujoco_rk4(model, s0, t, h)) for h in steps]
    return plan


def _timed_exact(model: Model, s0, t: np.ndarray) -> Trajectory:
    start = time.perf_counter()
    R, omega = exact_solution(model, s0)(t)
    return Trajectory(t, R, omega, 0, time.perf_counter() - start, "exact")


def mujoco_rk4(model: Model, s0, t: np.ndarray, h: float) -> Trajectory:
    """MuJoCo's RK4 on a free-floating body (free model only; a ball joint for the top), run in a
    temporary working directory: MuJoCo writes its warnings to MUJOCO_LOG.TXT there."""
    with tempfile.TemporaryDirectory() as tmp, contextlib.chdir(tmp):
        return _mujoco_rk4(model, s0, t, h)


def _mujoco_rk4(model: Model, s0, t: np.ndarray, h: float) -> Trajectory:
    import mujoco

    # A top: a ball joint at the pivot, mass 1 at ℓ = 0.1 on z', g = mgl / (m ℓ); MuJoCo takes the
    # inertia about the centre of mass, so the transverse moments lose m ℓ².
    ell = 0.1 if model.mgl else 0.0
    I1, I2, I3 = model.inertia[0] - ell**2, model.inertia[1] - ell**2, model.inertia[2]
    joint = '<joint type="ball"/>' if model.mgl else "<freejoint/>"
    xml = f"""<mujoco><option timestep="{h}" integrator="RK4" gravity="0 0 {-model.mgl / ell if ell else 0.0}"/>
      <worldbody><body>{joint}<inertial pos="0 0 {ell}" mass="1" diaginertia="{I1} {I2} {I3}"/></body>
      </worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    q0 = Rotation.from_matrix(s0.R_space_body).as_quat(scalar_first=True)
    if model.mgl:
        d.qpos[:] = q0
        d.qvel[:] = s0.omega_body
    else:
        d.qpos[3:7] = q0
        d.qvel[3:6] = s0.omega_body
    R = np.empty((len(t), 3, 3))
    omega = np.empty((len(t), 3))
    start = time.perf_counter()
    steps = 0
    for k, tk in enumerate(t):
        while steps < round(tk / h):  # count steps: d.time accumulates rounding
            mujoco.mj_step(m, d)
            steps += 1
        quat = d.qpos[:4] if model.mgl else d.qpos[3:7]
        R[k] = Rotation.from_quat(quat, scalar_first=True).as_matrix()
        omega[k] = d.qvel[:3] if model.mgl else d.qvel[3:6]
    return Trajectory(t, R, omega, 4 * steps, time.perf_counter() - start, "mujoco rk4")


def wall_at_error(points: list[Point], error: float) -> float | None:
    """Wall time a method needs for `error`, interpolated log-log along its sweep; None outside it."""
    pts = sorted((p.attitude_error, p.wall_s) for p in points if p.attitude_error > 0)
    for (e1, w1), (e2, w2) in zip(pts, pts[1:]):
        if e1 <= error <= e2:
            s = 0.0 if e2 == e1 else math.log(error / e1) / math.log(e2 / e1)
            return math.exp(math.log(w1) + s * math.log(w2 / w1))
    if pts and pts[0][0] <= error:  # more accurate than asked everywhere: its cheapest such run
        return min(w for e, w in pts if e <= error)
    return None


def ratios_at_equal_error(by_method: dict[str, list[Point]], peer: str) -> dict[str, str]:
    """method -> 'wall / peer wall' at the peer's three most accurate error levels that it reaches.

    The exact solution is the reference of its own case (its error there is 0 by construction;
    its accuracy is measured in tests/test_exact_*.py), so it is compared with the peer's most
    accurate run: a ratio below 1 there means faster AND more accurate."""
    out = {}
    peer_points = sorted(by_method[peer], key=lambda p: p.attitude_error)
    for name, points in by_method.items():
        if name == peer:
            continue
        if all(p.attitude_error == 0.0 for p in points):
            best = peer_points[0]
            out[name] = f"{points[0].wall_s / best.wall_s:.2g} against DOP853's best ({best.attitude_error:.0e} rad)"
            continue
        cells = []
        for p in peer_points[:3]:
            w = wall_at_error(points, p.attitude_error)
            if w is not None:
                cells.append(f"{w / p.wall_s:.3f} @ {p.attitude_error:.0e}")
        out[name] = "; ".join(cells) if cells else "n/a (never as accurate)"
    return out


def realtime_rows(case_name: str, case: Case, frame_dt: float, t_end: float | None = None) -> dict:
    """The app's frame-by-frame stepping on a case: error against the reference and cost."""
    t_end = min(float(case.t[-1]), t_end or math.inf)
    traj = simulate_realtime(case.model, case.state0, t_end, frame_dt)
    sub = Case(case.model, case.state0, traj.t)
    R_ref, _ = reference(sub)
    energy_drift, L_drift = drifts(case.model, traj)
    return {"case": case_name, "error": attitude_error(R_ref, traj.R_space_body), "energy": energy_drift,
            "L": L_drift, "ms_per_s": 1e3 * traj.wall_s / t_end, "evals": traj.evaluations}


def long_run_drift(case: Case) -> dict:
    """splitting4 at its default step over the whole long case: drift and trend of E and |L|."""
    traj = integrators.integrate_splitting(case.model, case.state0, case.t)
    E = np.array([energy(case.model, r, w) for r, w in zip(traj.R_space_body, traj.omega_body)])
    rel = (E - E[0]) / abs(E[0])
    slope = np.polyfit(case.t, rel, 1)[0]
    energy_drift, L_drift = drifts(case.model, traj)
    R_ref, _ = reference(case)
    return {"max_dE": energy_drift, "trend": slope * case.t[-1], "L": L_drift,
            "error": attitude_error(R_ref, traj.R_space_body), "wall": traj.wall_s, "evals": traj.evaluations}


def plot(points: list[Point], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    names = sorted({p.case for p in points}, key=[p.case for p in points].index)
    cols = 3
    rows = math.ceil(len(names) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    styles = {"dop853 (scipy)": ("k", "o"), "adaptive": ("tab:blue", "s"), "splitting4": ("tab:orange", "^"),
              "exact": ("tab:green", "*"), "mujoco rk4": ("tab:purple", "d"), "free_kick": ("tab:red", "v")}
    for ax, name in zip(axes.flat, names):
        for method, (color, marker) in styles.items():
            pts = sorted((p.wall_s, max(p.attitude_error, 1e-17)) for p in points if p.case == name and p.method == method)  # noqa: E501
            if pts:
                ax.loglog(*zip(*pts), marker=marker, color=color, label=method, ms=8 if marker == "*" else 5)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # minor labels overlap on a short decade
        ax.set_title(name.replace("_", " "))
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel("max attitude error [rad]")
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=8)
    fig.suptitle("Work-precision: attitude error against wall time (lower left is better)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer points and shorter runs (smoke test)")
    parser.add_argument("--cases", nargs="*", help="case names (default: all in benchmarks/cases)")
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results.md")
    parser.add_argument("--plot", type=Path, default=ROOT / "docs" / "img" / "work_precision.png")
    args = parser.parse_args(argv)

    names = args.cases or sorted(p.stem for p in CASES.glob("*.json"))
    sweep_cases = [n for n in names if not (args.quick and load_case(CASES / f"{n}.json").t[-1] > 1000.0)]
    points: list[Point] = []
    lines = ["# Speed against error", "",
             f"Measured by `python benchmarks/work_precision.py{' --quick' if args.quick else ''}` on "
             f"{time.strftime('%Y-%m-%d')}, one process, {platform.processor() or platform.machine()}, "
             f"Python {platform.python_version()}. Errors are the maximum over the case's output times.",
             ""]
    lines += ["## Work-precision", "",
              "| case | reference | method | setting | attitude error [rad] | max ΔE/E | max ΔL/L (free: norm, top: L_z) | evaluations | wall [s] |",  # noqa: E501
              "|---|---|---|---|---|---|---|---|---|"]
    ratio_lines = ["", "## Wall-time ratio against DOP853 at equal error", "",
                   "Each cell: this method's wall time / DOP853's, at DOP853's error (its three most accurate runs). "
                   "Below 1 is faster.", "", "| case | method | ratio @ error |", "|---|---|---|"]
    for name in sweep_cases:
        case = load_case(CASES / f"{name}.json")
        if args.quick:
            case = Case(case.model, case.state0, case.t[: max(3, len(case.t) // 10)])
        R_ref, how = reference(case)
        by_method: dict[str, list[Point]] = {}
        for method, runs in sweeps(case, args.quick).items():
            for setting, thunk in runs:
                try:
                    p = run_point(name, case, R_ref, method, setting, lambda case=case, thunk=thunk: best_of(1 if args.quick or case.t[-1] > 1000.0 else 2, thunk))  # noqa: E501
                except Exception as error:  # a method that fails on a case is reported, not hidden
                    lines.append(f"| {name} | {how} | {method} | {setting} | fails: {error} | | | | |")
                    continue
                points.append(p)
                by_method.setdefault(method, []).append(p)
                lines.append(f"| {name} | {how} | {method} | {setting} | {p.attitude_error:.2e} | {p.energy_drift:.1e} | "  # noqa: E501
                             f"{p.L_drift:.1e} | {p.evaluations} | {p.wall_s:.4f} |")
                print(lines[-1], flush=True)
        for method, cell in ratios_at_equal_error(by_method, "dop853 (scipy)").items():
            ratio_lines.append(f"| {name} | {method} | {cell} |")
    lines += ratio_lines

    lines += ["", "## Real time (the app's stepping, display step 1/240 s, sub-steps included)", "",
              "| case | attitude error [rad] | max ΔE/E | max ΔL/L | wall per simulated second [ms] | evaluations |",
              "|---|---|---|---|---|---|"]
    for name in names:
        case = load_case(CASES / f"{name}.json")
        row = realtime_rows(name, case, 1.0 / 240.0, t_end=2.0 if args.quick else 100.0)
        lines.append(f"| {name} | {row['error']:.1e} | {row['energy']:.1e} | {row['L']:.1e} | {row['ms_per_s']:.2f} | {row['evals']} |")  # noqa: E501
        print(lines[-1], flush=True)

    if "long_run" in names and not args.quick:
        case = load_case(CASES / "long_run.json")
        row = long_run_drift(case)
        lines += ["", f"## Long run ({case.t[-1]:.0f} s, splitting4 at its default step)", "",
                  "| max ΔE/E | linear trend of ΔE/E over the run | max ΔL/L | attitude error [rad] | wall [s] | evaluations |",  # noqa: E501
                  "|---|---|---|---|---|---|",
                  f"| {row['max_dE']:.1e} | {row['trend']:.1e} | {row['L']:.1e} | {row['error']:.1e} | {row['wall']:.2f} | {row['evals']} |"]  # noqa: E501
        print(lines[-1], flush=True)

    args.out.write_text("\n".join(lines) + "\n")
    args.plot.parent.mkdir(parents=True, exist_ok=True)
    plot(points, args.plot)
    print(f"wrote {args.out} and {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
