"""Case files (docs/CASEFILE.md): one rigid-body problem as JSON -> (Model, State, output times).

Every problem with the input raises `CaseError` with a one-line message naming it; nothing
is computed for a case that is not a physical problem.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from physics.dynamics import Model, State
from physics.euler import matrix_from_euler_zxz, omega_body_from_euler_rates
from physics.inertia import InertiaError

__all__ = ["Case", "CaseError", "case_from_dict", "load_case"]

_KEYS = {"model", "inertia", "mgl", "torque_space", "R0", "omega0_body", "euler0", "euler_rates0",
         "t", "t_end", "n_samples"}
_MODELS = ("free", "heavy_top", "const_torque")
ORTHOGONALITY_TOL = 1e-9  # ‖R0ᵀR0 − 1‖ above this is not a rotation (docs/CASEFILE.md)


class CaseError(ValueError):
    """The case is not a physical problem; the message says what is wrong, in one line."""


@dataclass(frozen=True)
class Case:
    """model: the body and torque; state0: the state at t = 0; t: (N,) output times [s]."""

    model: Model
    state0: State
    t: np.ndarray


def _vector(data: dict[str, Any], key: str, shape: tuple[int, ...]) -> np.ndarray:
    try:
        value = np.array(data[key], dtype=float)
    except (TypeError, ValueError) as error:
        raise CaseError(f"{key}: not an array of numbers ({error})") from None
    if value.shape != shape:
        raise CaseError(f"{key}: expected shape {shape}, got {value.shape}")
    if not np.all(np.isfinite(value)):
        raise CaseError(f"{key}: contains a non-finite number: {value.tolist()}")
    return value


def _number(data: dict[str, Any], key: str) -> float:
    value = data[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CaseError(f"{key}: expected a number, got {value!r}")
    if not math.isfinite(value):
        raise CaseError(f"{key}: must be finite, got {value}")
    return float(value)


def _times(data: dict[str, Any]) -> np.ndarray:
    if "t" in data:
        if "t_end" in data or "n_samples" in data:
            raise CaseError("give either t or t_end with n_samples, not both")
        t = np.array(data["t"], dtype=float) if isinstance(data["t"], list) else None
        if t is None or t.ndim != 1 or t.size == 0:
            raise CaseError("t: expected a non-empty list of times")
        if not np.all(np.isfinite(t)):
            raise CaseError("t: contains a non-finite number")
    elif "t_end" in data and "n_samples" in data:
        t_end = _number(data, "t_end")
        n = data["n_samples"]
        if isinstance(n, bool) or not isinstance(n, int) or n < 2:
            raise CaseError(f"n_samples: expected an integer >= 2, got {n!r}")
        if t_end <= 0.0:
            raise CaseError(f"t_end: must be positive, got {t_end}")
        t = np.linspace(0.0, t_end, n)
    else:
        raise CaseError("missing output times: give t, or t_end and n_samples")
    if t[0] != 0.0:
        raise CaseError(f"t: must start at 0, starts at {t[0]}")
    if np.any(np.diff(t) <= 0.0):
        raise CaseError("t: times must be strictly increasing")
    return t


def case_from_dict(data: dict[str, Any]) -> Case:
    """Validate a parsed CASE.json (a dict) and build the `Case`."""
    if not isinstance(data, dict):
        raise CaseError("a case is a JSON object")
    unknown = sorted(set(data) - _KEYS)
    if unknown:
        raise CaseError(f"unknown key(s): {', '.join(unknown)} (allowed: {', '.join(sorted(_KEYS))})")
    kind = data.get("model")
    if kind not in _MODELS:
        raise CaseError(f"model: expected one of {', '.join(_MODELS)}, got {kind!r}")
    if "inertia" not in data:
        raise CaseError("missing key: inertia")
    for key, only in (("mgl", "heavy_top"), ("torque_space", "const_torque")):
        if key in data and kind != only:
            raise CaseError(f"{key}: only for model {only!r}")
        if key not in data and kind == only:
            raise CaseError(f"missing key: {key} (required for model {only!r})")
    inertia = _vector(data, "inertia", (3,))
    mgl = _number(data, "mgl") if kind == "heavy_top" else 0.0
    torque = _vector(data, "torque_space", (3,)) if kind == "const_torque" else np.zeros(3)
    try:
        model = Model(inertia=tuple(inertia), mgl=mgl, torque_space=tuple(torque))
    except InertiaError as error:
        raise CaseError(f"inertia: {error}") from None

    matrix_keys, euler_keys = {"R0", "omega0_body"} & set(data), {"euler0", "euler_rates0"} & set(data)
    if matrix_keys and euler_keys:
        raise CaseError("give either R0/omega0_body or euler0/euler_rates0, not both")
    if euler_keys:
        if len(euler_keys) != 2:
            raise CaseError("euler0 and euler_rates0 go together")
        angles, rates = _vector(data, "euler0", (3,)), _vector(data, "euler_rates0", (3,))
        R0 = matrix_from_euler_zxz(*angles)
        omega0 = omega_body_from_euler_rates(angles, rates)
    elif len(matrix_keys) == 2:
        R0, omega0 = _vector(data, "R0", (3, 3)), _vector(data, "omega0_body", (3,))
        deviation = float(np.linalg.norm(R0.T @ R0 - np.eye(3)))
        if deviation > ORTHOGONALITY_TOL:
            raise CaseError(f"R0: not orthogonal (‖R0ᵀR0 − 1‖ = {deviation:.3g} > {ORTHOGONALITY_TOL:g})")
        if np.linalg.det(R0) < 0.0:
            raise CaseError("R0: det R0 = -1, a reflection, not a rotation")
    else:
        raise CaseError("missing initial state: give R0 and omega0_body, or euler0 and euler_rates0")
    return Case(model=model, state0=State(R0, omega0, 0.0), t=_times(data))


def load_case(path: str | Path) -> Case:
    """Read and validate CASE.json; `CaseError` for unreadable files and bad JSON too."""
    try:
        text = Path(path).read_text()
    except OSError as error:
        raise CaseError(f"cannot read {path}: {error.strerror}") from None
    try:
        data = json.loads(text)  # NaN and Infinity parse as floats and are refused below
    except json.JSONDecodeError as error:
        raise CaseError(f"{path}: not valid JSON ({error})") from None
    return case_from_dict(data)
