"""`python -m physics` behaves as docs/CASEFILE.md says, bad-input rules included."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from physics.methods import methods

EXAMPLE = {"model": "free", "inertia": [1.0, 2.0, 3.0], "euler0": [0.3, 1.1, -0.4],
           "euler_rates0": [0.5, 0.2, 1.5], "t_end": 5.0, "n_samples": 21}
TRAJ_KEYS = {"t", "R", "omega_body", "euler_zxz", "energy", "L_space", "evaluations", "wall_s", "method"}


def run_cli(tmp_path: Path, case: dict | str, *args: str) -> tuple[subprocess.CompletedProcess, Path]:
    case_path, out = tmp_path / "case.json", tmp_path / "traj.npz"
    case_path.write_text(case if isinstance(case, str) else json.dumps(case))
    result = subprocess.run([sys.executable, "-m", "physics", "simulate", str(case_path), "--out", str(out), *args],
                            capture_output=True, text=True, timeout=120)
    return result, out


def test_methods_lists_each_method_with_one_line():
    result = subprocess.run([sys.executable, "-m", "physics", "methods"], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0
    names = [line.split()[0] for line in result.stdout.splitlines()]
    assert {"exact", "splitting4", "free_kick", "adaptive", "dop853", "euler_lagrange", "realtime"} <= set(names)


def test_example_case_writes_every_key(tmp_path):
    result, out = run_cli(tmp_path, EXAMPLE)
    assert result.returncode == 0, result.stderr
    traj = np.load(out)
    assert TRAJ_KEYS <= set(traj.files)
    n = EXAMPLE["n_samples"]
    assert traj["R"].shape == (n, 3, 3) and traj["omega_body"].shape == (n, 3)
    assert traj["euler_zxz"].shape == (n, 3) and traj["L_space"].shape == (n, 3)
    assert str(traj["method"]) == "exact"
    np.testing.assert_allclose(traj["t"], np.linspace(0.0, 5.0, n), rtol=0, atol=0)
    # Initial attitude from the z-x-z angles, against SciPy's intrinsic "ZXZ".
    np.testing.assert_allclose(traj["R"][0], Rotation.from_euler("ZXZ", EXAMPLE["euler0"]).as_matrix(), atol=1e-14)
    # Torque-free: energy and L_space constant (relative 1e-12).
    assert np.ptp(traj["energy"]) <= 1e-12 * abs(traj["energy"][0])
    assert np.ptp(traj["L_space"], axis=0).max() <= 1e-12 * np.linalg.norm(traj["L_space"][0])
    # euler_zxz reproduces R (continuous branch, unwrapped angles).
    R_from_angles = Rotation.from_euler("ZXZ", traj["euler_zxz"]).as_matrix()
    np.testing.assert_allclose(R_from_angles, traj["R"], atol=1e-12)


OTHER_METHODS = [name for name, method in methods().items() if not method.reference]
"""Every registered method but the closed form (a new one is tested without an edit here)."""


@pytest.mark.parametrize("method", OTHER_METHODS)
def test_each_method_agrees_with_the_exact_solution(tmp_path, method):
    exact, out_exact = run_cli(tmp_path, EXAMPLE)
    reference = np.load(out_exact)["R"].copy()
    result, out = run_cli(tmp_path, EXAMPLE, "--method", method)
    assert result.returncode == 0, result.stderr
    traj = np.load(out)
    assert str(traj["method"]) == method
    angle_error = Rotation.from_matrix(np.swapaxes(reference, 1, 2) @ traj["R"]).magnitude().max()
    assert angle_error < 1e-6, f"{method}: {angle_error:.2e} rad"


def test_realtime_writes_one_sample_per_frame(tmp_path):
    result, out = run_cli(tmp_path, EXAMPLE, "--realtime", "--frame-dt", "0.05")
    assert result.returncode == 0, result.stderr
    traj = np.load(out)
    np.testing.assert_allclose(np.diff(traj["t"]), 0.05, rtol=1e-12)
    assert traj["t"][-1] == pytest.approx(5.0)
    assert np.ptp(traj["energy"]) <= 1e-6 * traj["energy"][0]



def test_frame_dt_accepts_a_fraction_as_written(tmp_path):
    short = {**EXAMPLE, "t_end": 0.25, "n_samples": 2}
    result, out = run_cli(tmp_path, short, "--realtime", "--frame-dt", "1/240")
    assert result.returncode == 0, result.stderr
    t = np.load(out)["t"]
    assert len(t) == 61 and t[1] == 1.0 / 240.0  # p/q is float(p) / float(q), exactly
    result, out = run_cli(tmp_path, short, "--realtime", "--frame-dt", "4.1666e-3")
    assert result.returncode == 0 and np.load(out)["t"][1] == 4.1666e-3


@pytest.mark.parametrize(("value", "phrase"), [("abc", "fraction p/q"), ("1/2/3", "fraction p/q"),
                                               ("1/0", "denominator"), ("1/x", "fraction p/q"),
                                               ("-1/60", "positive"), ("0", "positive"), ("inf", "positive")])
def test_bad_frame_dt_exits_2_with_one_line_and_no_file(tmp_path, value, phrase):
    result, out = run_cli(tmp_path, EXAMPLE, "--realtime", f"--frame-dt={value}")
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "--frame-dt" in lines[0] and phrase in lines[0], result.stderr
    assert not out.exists()

BAD_CASES = {
    "unknown key": ({**EXAMPLE, "inertai": [1, 2, 3]}, "unknown key"),
    "triangle": ({**EXAMPLE, "inertia": [1.0, 1.0, 3.0]}, "I"),
    "negative moment": ({**EXAMPLE, "inertia": [-1.0, 2.0, 2.0]}, "positive"),
    "nan": ('{"model": "free", "inertia": [1, 2, NaN], "euler0": [0, 1, 0], "euler_rates0": [0, 0, 1],'
            ' "t_end": 1, "n_samples": 3}', "non-finite"),
    "non-increasing": ({k: v for k, v in EXAMPLE.items() if k not in ("t_end", "n_samples")} | {"t": [0, 1, 1]},
                       "increasing"),
    "non-orthogonal R0": ({"model": "free", "inertia": [1, 2, 3], "R0": [[1, 0, 0], [0, 1, 0], [0, 0, 1.001]],
                           "omega0_body": [0, 0, 1], "t_end": 1, "n_samples": 3}, "orthogonal"),
    "reflection": ({"model": "free", "inertia": [1, 2, 3], "R0": [[1, 0, 0], [0, 1, 0], [0, 0, -1]],
                    "omega0_body": [0, 0, 1], "t_end": 1, "n_samples": 3}, "det"),
    "unknown model": ({**EXAMPLE, "model": "magnetic"}, "model"),
    "missing mgl": ({**EXAMPLE, "model": "heavy_top"}, "mgl"),
    "not json": ("{model: free", "JSON"),
}


@pytest.mark.parametrize("name", BAD_CASES)
def test_bad_input_exits_2_with_one_line_and_no_file(tmp_path, name):
    case, phrase = BAD_CASES[name]
    result, out = run_cli(tmp_path, case)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and phrase in lines[0], result.stderr
    assert not out.exists()


def test_lamina_is_a_valid_body(tmp_path):
    result, _ = run_cli(tmp_path, {**EXAMPLE, "inertia": [1.0, 2.0, 3.0 * (1 + 0)]})
    assert result.returncode == 0, result.stderr


def test_euler_lagrange_through_the_pole_fails_clearly(tmp_path):
    """Exit 1 with one line naming the singularity (how quickly: tests/test_lagrange.py counts
    the work done before it stops)."""
    case = {"model": "free", "inertia": [1.0, 1.0, 1.5], "R0": np.eye(3).tolist(),
            "omega0_body": [0.0, 0.0, 1.0], "t_end": 1.0, "n_samples": 3}
    result, out = run_cli(tmp_path, case, "--method", "euler_lagrange")
    assert result.returncode == 1 and "θ" in result.stderr and not out.exists()
    assert len(result.stderr.strip().splitlines()) == 1


def test_wall_s_counts_the_computation_not_imports_or_set_up(tmp_path):
    """wall_s of an exact free-body run against the same solve timed in this process once the
    modules are imported and warm.  Timing the imports and first-use set-up as well gave ~9 ms
    for a ~0.5 ms solve; allowed here: 2x the in-process time + 1 ms, each the best of its runs.

    A busy machine only adds time to a run (the process waits for a core), so the best of several
    runs is the solve's own time: the CLI runs until one run is within the bound, 10 runs at
    most (beside two `yes` and a Chromium, the best of 3 was once 15 ms against 1.8 ms)."""
    from physics.casefile import load_case
    from physics.methods import simulate

    case_path = tmp_path / "case.json"
    case_json = {**EXAMPLE, "n_samples": 101}
    case_path.write_text(json.dumps(case_json))
    case = load_case(case_path)
    simulate(case.model, case.state0, case.t)  # imports and first use, untimed
    in_process = min(simulate(case.model, case.state0, case.t).wall_s for _ in range(10))
    bound = 2.0 * in_process + 1e-3
    cli_runs: list[float] = []
    while len(cli_runs) < 10 and min(cli_runs, default=float("inf")) > bound:
        cli_runs.append(float(np.load(run_cli(tmp_path, case_json)[1])["wall_s"]))
    assert min(cli_runs) <= bound, (cli_runs, in_process)
