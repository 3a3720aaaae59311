"""The judges of state answers (physics.judging, app.ask.judges) against independent references:
SciPy's Rotation for attitude errors, the φ̇ of a simulated trajectory (finite differences of the
symmetry axis' azimuth, its sign changes counted) for the top's class of motion, SciPy's solve_ivp
of Euler's equations for a kicked axis."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from app.ask import Refused, Round
from app.ask import State as StateQuestion
from app.ask.judges import JUDGES, AnswerState, judge_answer
from physics.dynamics import Model, State
from physics.euler import omega_body_from_euler_rates
from physics.judging import attitude_error_rad, axis_stays, top_motion
from physics.methods import simulate
from physics.top_energy import CUSP, LOOP, STEADY, WAVE

I1, I3, MGL, SPIN = 1.0, 0.5, 6.0, 12.0  # the heavy top's presets (assets/presets/heavy_top.json)
STEADY_RATE_DEG = 63.083828634370526  # φ̇ of steady precession at θ = 60° (the preset)


def _top_start(phi_dot_deg: float, theta_deg: float = 60.0) -> tuple[np.ndarray, np.ndarray]:
    angles = np.radians([0.0, theta_deg, 0.0])
    rates = np.array([math.radians(phi_dot_deg), 0.0, 0.0])
    omega = omega_body_from_euler_rates(angles, rates)
    omega[2] = SPIN
    return Rotation.from_euler("ZXZ", angles).as_matrix(), omega


def _phi_dot_signs(R: np.ndarray, omega: np.ndarray, seconds: float = 6.0) -> tuple[int, float, float, float]:
    """(sign changes of φ̇, min φ̇, max φ̇ [rad/s], the range of θ [deg]) along an integrated run:
    φ is the azimuth of the symmetry axis e_z′ = (sin θ sin φ, −sin θ cos φ, cos θ), differenced
    at 2 ms."""
    t = np.arange(0.0, seconds, 0.002)
    run = simulate(Model(inertia=(I1, I1, I3), mgl=MGL), State(R, omega), t, method="dop853")
    axis = run.R_space_body[:, :, 2]
    phi = np.unwrap(np.arctan2(axis[:, 0], -axis[:, 1]))
    phi_dot = np.diff(phi) / np.diff(t)
    signs = np.sign(phi_dot[np.abs(phi_dot) > 1e-3 * np.abs(phi_dot).max()])
    theta_deg = np.degrees(np.arccos(np.clip(axis[:, 2], -1.0, 1.0)))
    return int(np.count_nonzero(np.diff(signs))), float(phi_dot.min()), float(phi_dot.max()), float(np.ptp(theta_deg))


def test_attitude_error_matches_scipy_for_small_and_large_turns() -> None:
    targets = Rotation.random(30, random_state=3)
    angles = np.concatenate([10.0 ** np.linspace(-12, -1, 10), np.linspace(0.2, math.pi - 1e-6, 20)])
    axes = Rotation.random(30, random_state=4).as_rotvec()
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    answers = targets * Rotation.from_rotvec(angles[:, None] * axes)
    for target, answer, angle in zip(targets.as_matrix(), answers.as_matrix(), angles):
        reference = Rotation.from_matrix(target.T @ answer).magnitude()
        error = attitude_error_rad(answer, target)
        assert error == pytest.approx(reference, rel=1e-9, abs=1e-15)
        assert error == pytest.approx(angle, rel=1e-7, abs=1e-15)


def test_attitude_judge_says_degrees_from_euler_angles_and_matrices() -> None:
    target = {"angles_deg": [30.0, 45.0, 10.0]}
    R_target = Rotation.from_euler("ZXZ", np.radians([30.0, 45.0, 10.0]))
    R_answer = R_target * Rotation.from_rotvec([0, 0, math.radians(12.4)])
    answer = AnswerState(scene="Euler angles", R_space_body=R_answer.as_matrix(), omega_body=np.zeros(3))
    question = StateQuestion("Stand it like this", "Euler angles", "attitude", target)
    judged = JUDGES["attitude"](question, answer.to_dict())
    assert judged.value == pytest.approx(12.4, abs=1e-9) and judged.unit == "deg" and judged.good is False
    assert judged.words == "12.4° from the target"
    exact = AnswerState(scene="Euler angles", R_space_body=R_target.as_matrix(), omega_body=np.zeros(3))
    judged = judge_answer("attitude", exact, {"R_space_body": exact.R_space_body.tolist()})
    assert judged.value == pytest.approx(0.0, abs=1e-6) and judged.good is True


@pytest.mark.parametrize(("phi_dot_deg", "expected"), [
    (STEADY_RATE_DEG, STEADY), (0.5 * STEADY_RATE_DEG, WAVE), (-0.5 * STEADY_RATE_DEG, LOOP), (0.0, CUSP)])
def test_top_class_agrees_with_the_sign_changes_of_a_simulated_phi_dot(phi_dot_deg: float, expected: str) -> None:
    R, omega = _top_start(phi_dot_deg)
    judged = top_motion(I1, I3, MGL, R, omega)
    assert judged.motion == expected
    changes, low, high, theta_range_deg = _phi_dot_signs(R, omega)
    if expected == STEADY:
        assert theta_range_deg < 0.05 and changes == 0
    elif expected == WAVE:
        assert changes == 0 and low > 0.05 * high  # φ̇ keeps its sign, never near zero
    elif expected == LOOP:
        assert changes >= 4 and low < -0.1 * high  # φ̇ changes sign every nod
    else:  # cusps: φ̇ touches zero at the top turning point, never goes (much) below
        assert low > -1e-3 * high and low < 0.02 * high


def test_top_judge_names_the_class_in_words_and_the_steady_tolerance_holds() -> None:
    near_steady = _top_start(STEADY_RATE_DEG + 0.05)
    assert top_motion(I1, I3, MGL, *near_steady).motion == STEADY
    loop = AnswerState(scene="Heavy top", R_space_body=_top_start(-20.0)[0], omega_body=_top_start(-20.0)[1],
                       inertia=(I1, I1, I3), mgl=MGL)
    judged = judge_answer("top_motion", loop, {"motion": "loops"})
    assert judged.value == "loops" and judged.words.startswith("loops — ") and judged.good is True
    sleeping = AnswerState(scene="Heavy top", R_space_body=Rotation.from_euler("ZXZ", [0, 0.02, 0]).as_matrix(),
                           omega_body=np.array([0.0, 0.0, SPIN]), inertia=(I1, I1, I3), mgl=MGL)
    assert judge_answer("top_motion", sleeping, None).value == "sleeping"


def _euler_reference(inertia: tuple[float, float, float], R0: np.ndarray, omega0: np.ndarray,
                     t: np.ndarray) -> np.ndarray:
    """R(t) (N, 3, 3) of the torque-free body by solve_ivp of Ṙ = R hat(ω), I ω̇ = (I ω) × ω."""
    moments = np.array(inertia)

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        R, w = y[:9].reshape(3, 3), y[9:]
        W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([(R @ W).ravel(), np.cross(moments * w, w) / moments])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([R0.ravel(), omega0]), t_eval=t, rtol=1e-8, atol=1e-9)
    return sol.y[:9].T.reshape(-1, 3, 3)


@pytest.mark.parametrize(("axis", "stays"), [(0, True), (1, False), (2, True)])
def test_axis_judge_agrees_with_solve_ivp_on_the_intermediate_axis_theorem(axis: int, stays: bool) -> None:
    inertia = (0.3, 0.75, 1.0)
    omega = np.full(3, 0.05)
    omega[axis] = 5.0
    R0 = Rotation.from_euler("ZXZ", np.radians([-30, 60, 0])).as_matrix()
    run = axis_stays(inertia, R0, omega, within_rad=math.radians(20.0), seconds=10.0)
    t = np.linspace(0.0, 10.0, 1001)
    R = _euler_reference(inertia, R0, omega, t)
    reference = np.degrees(np.arccos(np.clip(R[:, :, axis] @ R0[:, axis], -1.0, 1.0)))
    assert run.axis == axis and run.stays is stays
    assert math.degrees(run.max_angle_rad) == pytest.approx(reference.max(), abs=0.5)
    if not stays:
        assert run.left_at_s == pytest.approx(t[np.argmax(reference > 20.0)], abs=0.05)
    answer = AnswerState(scene="Free body", R_space_body=R0, omega_body=omega, inertia=inertia)
    judged = judge_answer("axis_stays", answer, {"within_deg": 20, "seconds": 10, "stays": True})
    assert judged.value == ("stays" if stays else "flips") and judged.good is stays
    assert ("stays within 20°" in judged.words) is stays, judged.words


def test_judges_refuse_bad_targets_and_answers_with_a_message() -> None:
    answer = AnswerState(scene="Euler angles", R_space_body=np.eye(3), omega_body=np.zeros(3))
    with pytest.raises(ValueError, match="target"):
        judge_answer("attitude", answer, None)
    with pytest.raises(ValueError, match="no judge"):
        judge_answer("nonsense", answer, None)
    with pytest.raises(ValueError, match="heavy top"):
        judge_answer("top_motion", answer, None)


def free_of(answer: AnswerState) -> AnswerState:
    return AnswerState("Free body", answer.R_space_body, answer.omega_body, answer.inertia, 0.0)


def test_a_round_judges_state_answers_and_refuses_another_scenes_body() -> None:
    question = StateQuestion("Find a start that makes the top loop", "Heavy top", "top_motion", {"motion": "loops"})
    round_ = Round(question)
    R, omega = _top_start(-20.0)
    loop = AnswerState("Heavy top", R, omega, (I1, I1, I3), MGL)
    kept = round_.answer("browser-a", loop.to_dict())
    assert kept.judged is not None and kept.judged.value == "loops" and kept.judged.good is True
    assert AnswerState.from_dict(kept.value) == loop and AnswerState.from_dict(kept.value) != free_of(loop)
    free = AnswerState("Free body", np.eye(3), np.array([0.0, 5.0, 0.0]), (0.3, 0.75, 1.0))
    with pytest.raises(Refused, match="Heavy top scene"):
        round_.answer("browser-b", free.to_dict())
    with pytest.raises(Refused, match="numbers"):
        round_.answer("browser-b", {"scene": "Heavy top", "R0": 1.0})
    assert [j.value for j in round_.tally().judged] == ["loops"]


def test_a_question_with_a_target_its_judge_cannot_use_is_refused_when_made() -> None:
    with pytest.raises(ValueError, match="motion must be one of"):
        StateQuestion("Make it loop", "Heavy top", "top_motion", {"motion": "spirals"})
    with pytest.raises(ValueError, match="'seconds' is not a field of the attitude judge"):
        StateQuestion("Stand it", "Euler angles", "attitude", {"angles_deg": [0, 0, 0], "seconds": 3})
    with pytest.raises(ValueError, match="needs a target"):
        StateQuestion("Stand it", "Euler angles", "attitude", None)
    with pytest.raises(ValueError, match="seconds must be a number in"):
        StateQuestion("Keep it", "Free body", "axis_stays", {"seconds": 1e9})
