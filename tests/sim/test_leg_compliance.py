"""A leg that bends (sim.compliance.LegCompliance, a model set's ``[leg_compliance]``): values refused in one line,
the table and its hash, a stiff spring that follows the profile like the servo, a soft one that lags and swings
past it, and too stiff a spring refused before the trial."""

import numpy as np
import pytest

from sim.compliance import ComplianceError, LegCompliance, check_spring_stability
from sim.model_set import load_model_set
from sim.trial import run_trial
from tests.conftest import set_with_table


@pytest.mark.parametrize(
    "k, c, match",
    [(0.0, 0.0, "must be > 0"), (1.0, -1.0, ">= 0"), (float("nan"), 0.0, "finite"), (True, 0.0, "finite")],
)
def test_bad_values_are_refused(k, c, match):
    with pytest.raises(ComplianceError, match=f"leg_compliance .*{match}"):
        LegCompliance(k, c)


def test_stability_bound():
    check_spring_stability(LegCompliance(0.08, 0.001), 2e-4, 1e-3)
    with pytest.raises(
        ComplianceError, match=r"leg_compliance stiffness_n_m_rad 100 is too stiff.*the leg's"
    ):
        check_spring_stability(LegCompliance(100.0), 2e-4, 1e-3)


def _leg(tmp_path, table: str | None):
    """One 1.5 s trial at 74/30 deg: (time, leg command, leg angle) after the first opening starts, degrees."""
    ms = (
        load_model_set(set_with_table(tmp_path, "leg_compliance", table))
        if table
        else load_model_set("paper")
    )
    r = run_trial(74.0, 30.0, phase=0.3, cv=0.0, rng=1, duration_s=1.5, trace=True, model_set=ms)
    tr = r.trace
    m = tr.t_s > r.attempt_starts_s[0]
    return tr.t_s[m], tr.leg_cmd_deg[m], tr.leg_deg[m]


def test_a_stiff_leg_follows_its_profile_and_a_soft_one_swings_past_it(tmp_path):
    """A stiff spring (2 N m/rad, near-critical damping) tracks the command as the servo does; a soft one
    (0.08 N m/rad, ringing at about 3 Hz) lags the command and overshoots it."""
    _, cmd, rigid = _leg(tmp_path, None)
    _, cmd_s, stiff = _leg(tmp_path, "stiffness_n_m_rad = 2.0\ndamping_n_m_s_rad = 0.03\n")
    _, cmd_f, soft = _leg(tmp_path, "stiffness_n_m_rad = 0.08\ndamping_n_m_s_rad = 0.001\n")
    amp = np.abs(cmd).max()
    assert np.abs(rigid - cmd).max() < 0.1 * amp
    assert np.abs(stiff - cmd_s).max() < 0.25 * amp
    assert np.abs(soft).max() > 1.15 * amp  # swings past the command
    assert np.abs(soft - cmd_f).max() > 0.4 * amp  # and lags it


def test_too_stiff_a_leg_is_refused_before_the_trial(tmp_path):
    ms = load_model_set(set_with_table(tmp_path, "leg_compliance", "stiffness_n_m_rad = 1000.0\n"))
    with pytest.raises(ComplianceError, match="leg_compliance stiffness_n_m_rad 1000 is too stiff"):
        run_trial(74.0, 30.0, phase=0.3, cv=0.0, rng=1, duration_s=0.5, model_set=ms)
