"""The outcome rule (landscape/analysis/physical/outcome.py) on synthetic recordings."""

import math

import numpy as np
import pytest

from landscape.analysis.physical.attempts import (
    attempt_outcomes,
)
from landscape.analysis.physical.outcome import trial_outcome
from tests.landscape.analysis.physical.lab import _recording


def test_outcome_rights_on_the_attempt_that_contains_the_final_upright_stretch():
    t = -1.0 + 0.02 * np.arange(300)  # -1 .. 4.98 s
    up = np.where(t >= 2.5, -1.0, 1.0)
    roll = np.where(t >= 2.5, -92.0, 0.0)
    out = trial_outcome(_recording(up, roll), theta_w_measured_deg=59.1)
    assert out.success and out.attempts == 2 and out.direction == -1 and out.first_upright_attempt == 2
    assert out.time_to_right_s == pytest.approx(2.5, abs=1e-9)


def test_a_robot_that_rights_and_falls_back_fails_but_counts_a_roll_over_and_a_lab_success():
    t = -1.0 + 0.02 * np.arange(300)
    up = np.where((t >= 0.8) & (t < 1.6), -1.0, 1.0)  # upright 0.8 s during attempt 1, then back
    out = trial_outcome(_recording(up, np.full(300, 91.0)))
    assert not out.success and math.isnan(out.time_to_right_s) and out.attempts == 3
    assert out.upright_directions == (1,) and out.first_upright_attempt == 1
    counts = attempt_outcomes([out])
    assert (counts[0].attempts, counts[0].successes) == (1, 1)


def test_brief_or_shallow_upright_excursions_are_not_rightings():
    t = -1.0 + 0.02 * np.arange(300)
    brief = np.where((t >= 1.0) & (t < 1.2), -1.0, 1.0)  # 0.18 s
    shallow = np.where((t >= 1.0) & (t < 2.0), -0.3, 1.0)  # 1 s at u_z = -0.3 (near the pole)
    for up in (brief, shallow):
        out = trial_outcome(_recording(up, np.full(300, 90.0)))
        assert not out.success and out.upright_directions == ()
