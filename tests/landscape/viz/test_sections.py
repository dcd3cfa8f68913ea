"""Report sections (landscape/viz/sections.py) on synthetic trial rows: every sentence and choice from the data."""

import csv

import numpy as np
import pytest

from landscape.viz import sections


def _row(**kw):
    base = dict(
        status="ok",
        attempts=0,
        theta_w_deg=74.0,
        theta_l_deg=30.0,
        cv=0.1,
        phase=0.7,
        wing_period_s=2.0,
        leg_period_s=0.8,
        duration_s=10.0,
        dt_s=5e-4,
        seed=1,
        success=False,
        time_to_right_s=None,
        attempt=None,
        mode=None,
        attempt_starts_s=[],
        robot_hash="h",
        robot="r.urdf",
    )
    base.update(kw)
    return base


def _won(**kw):
    return _row(success=True, time_to_right_s=2.0, attempt=1, mode="roll", **kw)


def _map_rows(good_phases, theta_w=74.0, theta_l=30.0):
    """A single-attempt phase map without noise at Tl 0.8 s: phases 0, 0.05, ..., 0.95."""
    return [
        _row(
            attempts=1,
            cv=0.0,
            theta_w_deg=theta_w,
            theta_l_deg=theta_l,
            phase=ph,
            success=ph in good_phases,
            time_to_right_s=ph * 0.8 + 0.8 if ph in good_phases else None,
            attempt_starts_s=[ph * 0.8],
        )
        for ph in np.round(np.arange(0, 1, 0.05), 2)
    ]


def _csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


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
    sec = sections.section_probability(rows, tmp_path, tmp_path / "t.sqlite")
    text = " ".join(sec.paragraphs)
    assert "2 of 3 settings righted in some of their trials and not in others" in text
    assert "1e-3" not in text  # no claim the data do not support


def test_evolution_without_a_phase_map_says_what_to_run(tmp_path):
    rows = [_won(seed=1), _row(seed=2)]
    sec = sections.section_evolution(rows, tmp_path, tmp_path / "t.sqlite")
    assert (
        sec.missing
        and "no single-attempt phase map at Tl 0.8 s" in sec.missing
        and "landscape sweep" in sec.missing
    )


def test_evolution_takes_the_trials_phase_when_every_start_meets_a_good_phase(tmp_path):
    """Tw/Tl = 2.5 alternates phi and phi + 0.5: with good phases 0.0-0.45 every start meets one, so the section
    takes phi_1 from the multi-attempt trials at that setting (0.35, their most common) and the study setting
    from the map (74, 30), not from fixed defaults."""
    good = set(np.round(np.arange(0, 0.5, 0.05), 2))
    rows = _map_rows(good) + [_row(cv=0.0, phase=0.35, seed=s) for s in (1, 2, 3)] + [_row(cv=0.0, phase=0.6)]
    sec = sections.section_evolution(rows, tmp_path, tmp_path / "t.sqlite", attempts=4)
    assert not sec.missing
    recs = _csv(tmp_path / "evolution.csv")
    first = [r for r in recs if r["attempt"] == "1"]
    assert [float(r["phase"]) for r in first] == pytest.approx([0.35, 0.35])
    assert float(first[0]["start_s"]) == pytest.approx(0.35 * 0.8)


def test_evolution_draws_every_requested_attempt_under_heavy_noise(tmp_path):
    rows = _map_rows({0.2})
    sec = sections.section_evolution(rows, tmp_path, tmp_path / "t.sqlite", cv=3.0, seed=7, attempts=12)
    assert not sec.missing
    recs = _csv(tmp_path / "evolution.csv")
    assert sorted({float(r["noise_cv"]) for r in recs}) == [0.0, 3.0]
    for cv in (0.0, 3.0):
        assert [int(r["attempt"]) for r in recs if float(r["noise_cv"]) == cv] == list(range(1, 13))


def test_probability_never_pools_trials_of_other_durations(tmp_path):
    """3 s and 10 s trials of one setting are different protocols (#16): the cells hold one of them, the text
    says how many were left out, and the figure's title names the data's own duration."""
    rows = [_won(seed=1), _row(seed=2), _won(seed=3, duration_s=3.0), _won(seed=4, duration_s=3.0)]
    sec = sections.section_probability(rows, tmp_path, tmp_path / "t.sqlite")
    text = " ".join(sec.paragraphs)
    assert "2 trials (1 settings, φ1 = 0.7, 10 s trials, dt 0.0005 s): 1 righted" in text
    assert "2 trials of other durations, time steps or model sets are not pooled" in text
    assert [r["n"] for r in _csv(tmp_path / "probability.csv")] == ["2"]
    other_model = [_won(seed=1), _row(seed=2), _won(seed=3, model_set="physical")]
    sec = sections.section_probability(other_model, tmp_path, tmp_path / "t.sqlite")
    assert "1 trials of other durations, time steps or model sets are not pooled" in " ".join(sec.paragraphs)


def test_probability_says_why_there_is_no_estimate(tmp_path):
    """One trial per setting, or a phase the database lacks: the message says which and what to run (#17)."""
    ones = [_won(theta_l_deg=float(x)) for x in (20, 30, 40)]
    sec = sections.section_probability(ones, tmp_path, tmp_path / "t.sqlite")
    assert (
        "the 3 settings at φ1 = 0.7 have one trial each (3 trials)" in sec.missing
        and "--trials 2" in sec.missing
    )
    sec = sections.section_probability(
        [_won(seed=1), _row(seed=2)], tmp_path, tmp_path / "t.sqlite", phase=0.3
    )
    assert sec.missing == "no multi-attempt trials at φ1 = 0.3; the database has φ1 = 0.7"


def test_barriers_pose_the_wings_as_the_trials_model_set_did():
    """A shipped measured set that still hashes as stored poses each servo at its plateau; an idealised set, a
    set not shipped, a changed set or mixed sets pose every joint at theta_w, and the sentence says which."""
    from geometry.robots import load_robot
    from sim.model_set import load_model_set

    robot = load_robot(None)
    phys = load_model_set("physical")
    rows = [{"model_set": "physical", "model_set_hash": phys.model_set_hash}]
    posed, joints, text = sections._set_wing_joints(rows, robot, {60.0, 75.0})
    assert posed is robot  # physical moves no mass
    assert joints[75.0] == phys.wing_joints_deg(robot.joint_map.wing, 75.0) and set(joints) == {60.0, 75.0}
    assert "measured plateau (model set physical)" in text
    for rows, why in (
        ([{"model_set": "paper", "model_set_hash": "x"}], "idealised"),
        ([{"model_set": "mine", "model_set_hash": "x"}], "not a shipped set"),
        ([{"model_set": "physical", "model_set_hash": "old"}], "changed since the trials ran"),
        ([{"model_set": "physical", "model_set_hash": phys.model_set_hash}, {"model_set": "paper"}], "mix"),
    ):
        posed, joints, text = sections._set_wing_joints(rows, robot, {75.0})
        assert posed is robot
        assert joints is None and why in text, (rows, text)
