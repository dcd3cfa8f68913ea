"""Attempts by the lab's rule and as pitch-roll paths (landscape/analysis/physical/attempts.py): synthetic
recordings, then the lab's published counts on the real files (skipped without ../shared)."""

import numpy as np
import pytest

from landscape.analysis.physical.attempts import (
    LAB_ATTEMPTS_PER_TRIAL,
    attempt_outcomes,
    physical_attempts,
    recorded_attempt_counts,
    recording_attempts,
)
from landscape.analysis.physical.outcome import UPRIGHT_HOLD_S, PhysicalTrial, physical_trials
from landscape.analysis.physical.recording import (
    WING_COMMANDS_DEG,
    PhysicalDataError,
)
from tests.landscape.analysis.physical.lab import DATA, _recording, needs_data


def test_attempt_rule_caps_at_five_openings():
    late = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 12.0, 7, 1, (1,), 7, 14.0)  # rights on the 7th
    c = attempt_outcomes([late])[0]
    assert (c.attempts, c.successes) == (5, 0)


@needs_data
def test_derived_per_attempt_counts_reproduce_robot_attempts_mat():
    recorded = recorded_attempt_counts(DATA)
    assert [(c.successes, c.attempts) for c in recorded] == [(12, 58), (15, 42), (17, 34)]
    assert [round(c.theta_w_measured_deg, 1) for c in recorded] == [59.1, 73.6, 82.1]
    derived = attempt_outcomes(physical_trials(DATA))
    assert [(c.successes, c.attempts) for c in derived] == [(12, 58), (15, 42), (17, 34)]


def test_attempts_split_at_openings_and_end_after_the_robot_rights():
    t = -1.0 + 0.02 * np.arange(300)  # -1 .. 4.98 s; openings at 0, 2, 4 s
    up = np.where(t >= 2.5, -1.0, 1.0)  # upright from 2.5 s: during the second opening
    roll = np.clip(t, 0.0, None) * 10.0
    atts = recording_attempts(_recording(up, roll), theta_w_measured_deg=59.1)
    assert [(a.attempt, a.righted) for a in atts] == [(1, False), (2, True)]
    a1, a2 = atts
    assert a1.t_s[0] == pytest.approx(0.0) and a1.t_s[-1] == pytest.approx(1.98)
    # the righting attempt runs from its opening to UPRIGHT_HOLD_S after the robot is upright
    assert a2.t_s[0] == pytest.approx(2.0) and a2.t_s[-1] == pytest.approx(2.5 + UPRIGHT_HOLD_S - 0.02)
    assert a2.roll_deg == pytest.approx(a2.t_s * 10.0)
    assert a1.theta_w_measured_deg == 59.1 and a1.theta_l_deg == 15.0
    never = recording_attempts(_recording(np.ones(300), np.zeros(300)))
    assert [(a.attempt, a.righted) for a in never] == [(1, False), (2, False), (3, False)]
    assert [
        a.attempt for a in recording_attempts(_recording(np.ones(300), np.zeros(300)), max_attempts=2)
    ] == [
        1,
        2,
    ]


def test_no_trial_at_the_asked_wing_angle_says_which_there_are(tmp_path):
    import h5py

    f = tmp_path / "run5_60_60_60_60_0_1.bag.mat"
    with h5py.File(f, "w") as h:
        h["quat"] = np.zeros((6, 3))
        h["servo"] = np.zeros((5, 3))
    with pytest.raises(PhysicalDataError, match=r"no physical trial at wing 75.0 deg.*commands are 60/0 deg"):
        physical_attempts(tmp_path, theta_w_cmd_deg=75.0)


@needs_data
def test_attempt_paths_reproduce_the_lab_per_attempt_counts():
    """The attempts cut from the trial files, capped at the lab's five per trial, are robot_attempts.mat's."""
    atts = physical_attempts(DATA, max_attempts=LAB_ATTEMPTS_PER_TRIAL)
    counts = [
        (sum(a.righted for a in atts if a.theta_w_cmd_deg == w), sum(a.theta_w_cmd_deg == w for a in atts))
        for w in WING_COMMANDS_DEG
    ]
    assert counts == [(12, 58), (15, 42), (17, 34)]
    l0 = physical_attempts(DATA, theta_w_cmd_deg=75.0, theta_l_deg=0.0)
    assert {a.name for a in l0} == {f"run5_75_75_75_75_0_{k}.bag.mat" for k in range(1, 6)}
    assert all(a.theta_w_measured_deg == pytest.approx(73.6, abs=0.1) for a in l0)
    assert all(np.isfinite(a.pitch_deg).all() and len(a.pitch_deg) > 10 for a in l0)
