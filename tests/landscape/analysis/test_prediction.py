"""The state predictor of the first righting attempt (landscape.analysis.prediction) on attempts whose outcome
is known by construction."""

import numpy as np
import pytest

from landscape.analysis import prediction as pr
from landscape.analysis.trials import PhaseMap


def _map(tl: float) -> PhaseMap:
    """A map at Tl ``tl`` whose phases below 0.5 right from rest."""
    phases = np.arange(0.0, 1.0, 0.25)
    good = (phases < 0.5).astype(float)[None, :]
    return PhaseMap(
        72.0, tl, np.array([30.0]), phases, good, np.where(good > 0, 0.5, np.nan), np.ones((1, 4), int)
    )


def _state(key, attempt, *, phase=0.0, roll=0.0, success=False, tw=2.0, tl=0.8):
    return pr.OpeningState(key, tw, tl, attempt, phase, roll, 0.0, 0.0, 0.0, 0.0, 0.0, success)


def test_the_vote_follows_the_state_when_the_phase_is_the_same():
    """Fitted on attempts at one phase that right when the body opens rolled past 10 deg and fail otherwise:
    new attempts at that phase are predicted by their roll, though the map from rest calls the phase good."""
    fit = [_state(f"t{i}", 1, phase=0.25, roll=r, success=r > 10) for i, r in enumerate(range(-20, 21, 2))]
    p = pr.fit_state_predictor(fit, {0.8: _map(0.8)}, 30.0, k=3)
    got = p.rights([_state("n", 1, phase=0.25, roll=18.0), _state("n", 2, phase=0.25, roll=-18.0)])
    assert got.tolist() == [True, False]


def test_first_predicted_is_the_first_attempt_voted_to_right():
    fit = [_state(f"t{i}", 1, roll=r, success=r > 10) for i, r in enumerate(range(-20, 21, 2))]
    p = pr.fit_state_predictor(fit, {0.8: _map(0.8)}, 30.0, k=3)
    trial = [_state("n", 1, roll=0.0), _state("n", 2, roll=4.0), _state("n", 3, roll=19.0)]
    assert pr.first_predicted(p, trial) == 3
    assert pr.first_predicted(p, trial[:2]) is None


def test_held_out_predictions_never_see_the_setting_they_predict():
    """Two settings whose attempts are identical but for their outcome: each is predicted from the other only,
    so every prediction is the other setting's outcome (fitted in-sample it would be its own)."""
    a = [
        ({"wing_period_s": 2.0, "leg_period_s": 0.8, "k": i}, [_state(f"a{i}", 1, success=True)])
        for i in range(6)
    ]
    b = [
        ({"wing_period_s": 3.0, "leg_period_s": 0.8, "k": i}, [_state(f"b{i}", 1, success=False, tw=3.0)])
        for i in range(6)
    ]
    out = pr.held_out_state_predictions(a + b, {0.8: _map(0.8)}, [], 30.0, k=3)
    assert [p for r, p in out if r["wing_period_s"] == 2.0] == [None] * 6
    assert [p for r, p in out if r["wing_period_s"] == 3.0] == [1] * 6


def test_score_has_a_wilson_interval():
    s = pr.score("state", [True] * 91 + [False] * 9, held_out=True)
    assert (s.trials, s.correct, s.accuracy) == (100, 91, 0.91)
    assert s.ci95[0] == pytest.approx(0.8377, abs=1e-4) and s.ci95[1] == pytest.approx(0.9519, abs=1e-4)
    assert s.as_json() == {
        "name": "state",
        "trials": 100,
        "correct": 91,
        "accuracy": 0.91,
        "ci95": [s.ci95[0], s.ci95[1]],
        "held_out": True,
    }


def _opening(k, phase, heading, start):
    return pr.OpeningState("t", 2.0, 0.8, k, phase, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, False, heading, start)


def test_from_rest_follows_each_attempts_phase_and_heading_and_the_time_left():
    """The same phase fails from rest at the heading the trial starts with and rights once the robot has turned
    to 30 deg; an attempt that would right after the trial's end is passed over; attempts after the predicted
    one are never asked for."""
    asked = []

    def from_rest(s):
        asked.append(s.attempt)
        good = (s.phase == 0.0 and abs(s.heading_deg - 30.0) < 5.0) or s.phase == 0.5
        return good, 1.0

    trial = [_opening(1, 0.0, 0.0, 0.0), _opening(2, 0.7, 10.0, 2.0), _opening(3, 0.0, 31.0, 4.0)]
    trial.append(_opening(4, 0.5, 31.0, 6.0))
    assert pr.first_predicted_from_rest(trial, from_rest, 10.0) == 3 and asked == [1, 2, 3]
    assert pr.first_predicted_from_rest(trial, from_rest, 5.0) is None  # 4 + 1 + 0.3 s hold > 5 s
    assert asked == [1, 2, 3, 1, 2, 3, 4]


def test_from_rest_key_rounds_phase_and_heading():
    assert pr.from_rest_key(_opening(2, 0.3000000000004, 12.34567891, 2.0)) == (0.3, 12.345679)
    assert pr.from_rest_key(_opening(2, 1.0, -3.0, 2.0)) == (0.0, -3.0)
    assert pr.from_rest_key(_opening(2, 0.99999999997, 0.0, 2.0)) == (0.0, 0.0)  # a phase, never 1
    assert str(pr.from_rest_key(_opening(2, 0.5, -1e-9, 2.0))[1]) == "0.0"  # one key for +0 and -0
