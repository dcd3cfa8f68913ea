"""The probability section (landscape/viz/sections/probability.py) on synthetic trial rows: every sentence and
choice from the data."""

from landscape.viz.sections.probability import section_probability
from tests.conftest import csv_rows as _csv
from tests.landscape.viz.sections.synthetic import _row, _won


def test_probability_section_counts_the_settings_whose_trials_disagree(tmp_path):
    rows = [
        _won(seed=1),
        _row(seed=2),  # (74, 30): one righted, one not
        _won(theta_l_deg=40.0, seed=1),
        _won(theta_l_deg=40.0, seed=2),  # (74, 40): both righted
        _row(theta_l_deg=50.0, seed=1),
        _row(theta_l_deg=50.0, seed=2),
        _won(theta_l_deg=50.0, seed=3),
    ]
    sec = section_probability(rows, tmp_path, tmp_path / "t.sqlite")
    text = " ".join(sec.paragraphs)
    assert "2 of 3 settings righted in some of their trials and not in others" in text
    assert "1e-3" not in text  # no claim the data do not support


def test_probability_never_pools_trials_of_other_durations(tmp_path):
    """3 s and 10 s trials of one setting are different protocols (#16): the cells hold one of them, the text
    says how many were left out, and the figure's title names the data's own duration."""
    rows = [_won(seed=1), _row(seed=2), _won(seed=3, duration_s=3.0), _won(seed=4, duration_s=3.0)]
    sec = section_probability(rows, tmp_path, tmp_path / "t.sqlite")
    text = " ".join(sec.paragraphs)
    assert "2 trials (1 settings, φ1 = 0.7, 10 s trials, dt 0.0005 s): 1 righted" in text
    assert "2 trials of other durations, time steps or model sets are not pooled" in text
    assert [r["n"] for r in _csv(tmp_path / "probability.csv")] == ["2"]
    other_model = [_won(seed=1), _row(seed=2), _won(seed=3, model_set="physical")]
    sec = section_probability(other_model, tmp_path, tmp_path / "t.sqlite")
    assert "1 trials of other durations, time steps or model sets are not pooled" in " ".join(sec.paragraphs)


def test_probability_says_why_there_is_no_estimate(tmp_path):
    """One trial per setting, or a phase the database lacks: the message says which and what to run (#17)."""
    ones = [_won(theta_l_deg=float(x)) for x in (20, 30, 40)]
    sec = section_probability(ones, tmp_path, tmp_path / "t.sqlite")
    assert (
        "the 3 settings at φ1 = 0.7 have one trial each (3 trials)" in sec.missing
        and "--trials 2" in sec.missing
    )
    sec = section_probability([_won(seed=1), _row(seed=2)], tmp_path, tmp_path / "t.sqlite", phase=0.3)
    assert sec.missing == "no multi-attempt trials at φ1 = 0.3; the database has φ1 = 0.7"
