"""The "Poinsot" readout (app.scenes.poinsot.readouts) and the flip schedule as pure functions: no
browser, no viser.  The numbers printed are checked against values computed here: T = ½ Σ I_k ω_k²,
|L| = |I ω|, and the flip period 2K(m)/λ of the textbook solution of Euler's equations (Landau &
Lifshitz §37, about the largest axis: λ = √((I3 − I2)(L² − 2T I1)/(I1 I2 I3)),
m = (I2 − I1)(2T I3 − L²)/((I3 − I2)(L² − 2T I1)), K from SciPy's `ellipk`); a symmetric body's ω_⊥
turns at λ = (I3 − I1) ω3 / I1 in the body."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.special import ellipk

from app.scenes.poinsot import poinsot_text
from app.scenes.poinsot.simulation import next_flip_time
from physics.poinsot import motion


def _number(text: str, pattern: str) -> float:
    match = re.search(pattern, text)
    assert match, f"{pattern!r} not in the text"
    return float(match.group(1))


def _invariants(I: np.ndarray, omega: np.ndarray) -> tuple[float, float]:
    return 0.5 * float(np.sum(I * omega * omega)), float(np.linalg.norm(I * omega))


def test_a_flipping_body_shows_T_L_and_the_flip_period() -> None:
    I, omega = np.array([1.0, 2.0, 3.0]), np.array([0.3, 0.2, 1.0])
    T, L = _invariants(I, omega)
    text = poinsot_text(I, T, motion(I, T, L), 0.4, 1.25)
    assert text.startswith("```\n") and text.endswith("\n```")
    assert _number(text, r"T = (\S+) J") == pytest.approx(0.5 * (0.09 + 0.08 + 3.0), rel=1e-4)
    assert _number(text, r"\|L\| = (\S+) kg m²/s") == pytest.approx(math.sqrt(0.09 + 0.16 + 9.0), rel=1e-4)
    assert _number(text, r"\|L\|²/\(2T\) = (\S+) kg m²") == pytest.approx(9.25 / 3.17, rel=1e-4)
    assert "(I_mid = 2)" in text and "ω: 1 rad/s = 0.4 scene units" in text
    L2, E2 = L * L, 2.0 * T
    rate = math.sqrt((I[2] - I[1]) * (L2 - E2 * I[0]) / (I[0] * I[1] * I[2]))
    m = (I[1] - I[0]) * (E2 * I[2] - L2) / ((I[2] - I[1]) * (L2 - E2 * I[0]))
    assert _number(text, r"flip period 2K\(m\)/λ = (\S+) s") == pytest.approx(2.0 * ellipk(m) / rate, abs=6e-5)
    assert _number(text, r"\(m = (\S+),") == pytest.approx(m, abs=6e-7)
    assert _number(text, r"λ = (\S+) rad/s\)") == pytest.approx(rate, rel=1e-3)
    assert "next flip at t = 1.250 s" in text
    assert "next flip" not in poinsot_text(I, T, motion(I, T, L), 0.4, None)


def test_a_symmetric_body_a_steady_spin_and_a_body_at_rest() -> None:
    I, omega = np.array([1.0, 1.0, 2.0]), np.array([0.5, 0.0, 3.0])
    T, L = _invariants(I, omega)
    text = poinsot_text(I, T, motion(I, T, L), 0.4, None)
    expected = (I[2] - I[0]) * omega[2] / I[0]
    assert _number(text, r"ω_⊥ turns at λ = (\S+) rad/s; no flip") == pytest.approx(expected, rel=1e-3)
    I = np.array([1.0, 2.0, 3.0])
    T, L = _invariants(I, np.array([0.0, 0.0, 2.0]))
    assert "steady rotation about a principal axis: no flip" in poinsot_text(I, T, motion(I, T, L), 0.4, None)
    assert poinsot_text(I, 0.0, None, 0.4, None) == "The body is at rest: no ellipsoid."


def test_the_next_flip_follows_the_schedule() -> None:
    schedule = (0.5, 2.0)  # first flip at 0.5 s, then every 2 s
    assert next_flip_time(schedule, 0.2) == 0.5
    assert next_flip_time(schedule, 0.5) == 2.5
    assert next_flip_time(schedule, 3.0) == 4.5
    assert next_flip_time(None, 3.0) is None
