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


def _hmap():
    """Phases 0 and 0.5 at headings 0, 30 and 60 deg: phase 0 rights at heading 30 only, phase 0.5 everywhere
    but at 60 deg (1 s after its opening)."""
    runs = [(0.0, h, h == 30.0, 1.0) for h in (0.0, 30.0, 60.0)]
    runs += [(0.5, h, h != 60.0, 1.0) for h in (0.0, 30.0, 60.0)]
    return pr.HeadingMap.from_runs(0.8, runs)


def test_heading_map_looks_up_the_nearest_phase_and_heading_modulo_a_quarter_turn():
    m = _hmap()
    assert m.lookup(0.02, 28.0) == (True, 1.0)
    assert m.lookup(0.98, 29.0 + 90.0)[0] and m.lookup(0.0, 29.0 - 180.0)[0]  # a quarter turn is the same
    assert not m.lookup(0.0, 46.0)[0] and not m.lookup(0.0, 80.0)[0]  # 80 deg is nearest to 90 = 0
    assert m.lookup(0.5, 80.0)[0] and not m.lookup(0.5, 58.0)[0]
    assert np.isnan(m.lookup(0.0, 0.0)[1])


def test_heading_map_refuses_a_grid_with_a_hole_or_a_repeat():
    runs = [(0.0, h, True, 1.0) for h in (0.0, 45.0)] + [(0.5, 0.0, True, 1.0)]
    with pytest.raises(ValueError, match="no attempt at phase 0.5, heading 45"):
        pr.HeadingMap.from_runs(0.8, runs)
    with pytest.raises(ValueError, match="two attempts at phase 0, heading 90"):
        pr.HeadingMap.from_runs(0.8, [*runs, (0.5, 45.0, True, 1.0), (0.0, 90.0, False, 1.0)])
    with pytest.raises(ValueError, match="at least one heading"):
        pr.heading_grid(0)


def test_first_predicted_by_heading_follows_each_attempts_heading_and_the_time_left():
    """The same phase is predicted to fail at the heading it starts with and to right once the robot has turned
    to 30 deg; an attempt that would right after the trial's end is not the predicted one."""

    def st(k, phase, heading, start):
        return pr.OpeningState("t", 2.0, 0.8, k, phase, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, False, heading, start)

    m = _hmap()
    trial = [st(1, 0.0, 0.0, 0.0), st(2, 0.5, 60.0, 2.0), st(3, 0.0, 31.0, 4.0)]
    assert pr.first_predicted_by_heading(m, trial, 10.0) == 3
    assert pr.first_predicted_by_heading(m, trial, 5.0) is None  # 4 + 1 + 0.3 s hold > 5 s
    assert pr.first_predicted_by_heading(m, [st(1, 0.5, 2.0, 0.0)], 10.0) == 1
