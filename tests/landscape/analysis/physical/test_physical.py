"""The physical trials as data (landscape/analysis/physical.py): rules on synthetic records, then the lab's
published counts and the issue #15 tables on the real files (skipped without ../shared)."""

import math
import os
from pathlib import Path

import numpy as np
import pytest

from geometry.frames import up_vector
from landscape.analysis.physical.attempts import (
    LAB_ATTEMPTS_PER_TRIAL,
    attempt_outcomes,
    physical_attempts,
    recorded_attempt_counts,
    recording_attempts,
)
from landscape.analysis.physical.cells import lateralisation, physical_cells
from landscape.analysis.physical.measured import WING_COMMANDS_DEG
from landscape.analysis.physical.outcome import UPRIGHT_HOLD_S, PhysicalTrial, physical_trials, trial_outcome
from landscape.analysis.physical.recording import (
    PhysicalDataError,
    Recording,
    imu_to_body,
    pitch_roll_from_quat_deg,
    read_recording,
    trial_files,
    up_in_body,
    up_z_mounted,
)
from landscape.analysis.physical.resting import resting_pitch_table
from landscape.cli import main

DATA = (
    Path(os.environ.get("LANDSCAPE_SHARED", Path(__file__).resolve().parents[4].parent / "shared"))
    / "ref"
    / ("physical_robot")
)
needs_data = pytest.mark.skipif(
    not (DATA / "robot_attempts.mat").is_file(), reason="../shared/ref/physical_robot is absent"
)


def _quat_from_pitch_roll(pitch_deg, roll_deg):
    """Body-to-world quaternion (x, y, z, w) of R = Ry(p) Rx(r), built independently of the module."""
    p, r = np.deg2rad(pitch_deg) / 2, np.deg2rad(roll_deg) / 2
    qy = np.array([0.0, np.sin(p), 0.0, np.cos(p)])
    qx = np.array([np.sin(r), 0.0, 0.0, np.cos(r)])
    x1, y1, z1, w1 = qy
    x2, y2, z2, w2 = qx
    return np.array(
        [
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        ]
    )


@pytest.mark.parametrize("pitch,roll", [(0.0, 0.0), (30.0, -20.0), (67.9, 5.0), (-45.0, 170.0), (10.0, 95.0)])
def test_pitch_roll_from_quaternion_inverts_the_frames_convention(pitch, roll):
    q = _quat_from_pitch_roll(pitch, roll)
    p, r = pitch_roll_from_quat_deg(q[None])
    assert p[0] == pytest.approx(pitch, abs=1e-9)
    assert r[0] == pytest.approx(roll, abs=1e-9)
    x, y = q[0], q[1]
    assert 1 - 2 * (x * x + y * y) == pytest.approx(
        up_vector(np.deg2rad(pitch), np.deg2rad(roll))[2], abs=1e-12
    )


def _recording(up_z, roll_deg, openings=(0.0, 2.0, 4.0), dt=0.02, t0=-1.0):
    n = len(up_z)
    t = t0 + dt * np.arange(n)
    return Recording(
        "x",
        60.0,
        15.0,
        1,
        t,
        np.zeros(n),
        np.asarray(roll_deg, float),
        np.asarray(up_z, float),
        np.asarray(openings, float),
    )


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


def test_attempt_rule_caps_at_five_openings():
    late = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 12.0, 7, 1, (1,), 7, 14.0)  # rights on the 7th
    c = attempt_outcomes([late])[0]
    assert (c.attempts, c.successes) == (5, 0)


def test_cells_use_the_wilson_interval():
    ts = [
        PhysicalTrial(str(k), 75.0, 73.6, 30.0, k, k < 3, 1.0 + k if k < 3 else math.nan, 1, 1, (1,), 1, 5.0)
        for k in range(5)
    ]
    (c,) = physical_cells(ts)
    z = 1.959963984540054
    p, n = 3 / 5, 5
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    assert (c.n, c.successes, c.median_time_to_right_s) == (5, 3, 2.0)
    assert (c.ci_low, c.ci_high) == pytest.approx((centre - half, centre + half), abs=1e-12)


def test_a_missing_data_directory_is_one_clear_error(tmp_path, capsys):
    with pytest.raises(PhysicalDataError, match="does not exist"):
        physical_trials(tmp_path / "nope")
    with pytest.raises(PhysicalDataError, match="no trial file"):
        trial_files(tmp_path)
    assert main(["physical", "table", "--data", str(tmp_path), "--out", str(tmp_path / "o")]) == 2
    assert "no trial file" in capsys.readouterr().err


def test_a_file_that_is_not_hdf5_is_refused(tmp_path):
    bad = tmp_path / "run5_60_60_60_60_0_1.bag.mat"
    bad.write_text("not hdf5")
    with pytest.raises(PhysicalDataError, match="not a lab trial file"):
        read_recording(bad)


# ---------------------------------------------------------------------------------------- the lab's data
@needs_data
def test_derived_per_attempt_counts_reproduce_robot_attempts_mat():
    recorded = recorded_attempt_counts(DATA)
    assert [(c.successes, c.attempts) for c in recorded] == [(12, 58), (15, 42), (17, 34)]
    assert [round(c.theta_w_measured_deg, 1) for c in recorded] == [59.1, 73.6, 82.1]
    derived = attempt_outcomes(physical_trials(DATA))
    assert [(c.successes, c.attempts) for c in derived] == [(12, 58), (15, 42), (17, 34)]


@needs_data
def test_trials_cells_and_lateralisation():
    trials = physical_trials(DATA)
    assert len(trials) == 60
    cells = {(c.theta_w_cmd_deg, c.theta_l_deg): c.successes for c in physical_cells(trials)}
    # the issue: at 60 deg the robot rights with theta_l 15-45 in 13 of 15 trials; at 74 deg, 15 deg: 5/5
    assert cells[(60.0, 15.0)] + cells[(60.0, 30.0)] + cells[(60.0, 45.0)] == 13
    assert cells[(75.0, 15.0)] == 5 and cells[(60.0, 0.0)] == cells[(75.0, 0.0)] == 0
    lat = lateralisation(trials)
    assert (lat.positive, lat.negative) == (43, 3)


@needs_data
def test_resting_pitch_reproduces_the_issue_table():
    rows = resting_pitch_table(DATA)
    got = [
        (r.theta_w_cmd_deg, round(r.median_deg, 1), round(r.q25_deg, 1), round(r.q75_deg, 1), r.n)
        for r in rows
    ]
    # the issue's table read 85.3 [82.9, 85.7] at 90 deg from the ZYX pitch, which folds back where the robot's
    # nose passes vertical; the nose's pitch (sagittal_pitch_deg) reads 86.7
    assert got == [(60.0, 67.9, 66.9, 69.2, 33), (75.0, 82.8, 80.3, 85.4, 23), (90.0, 86.7, 85.9, 87.9, 16)]
    # the body does not come back to its pre-opening rest when the wings close: the reference is path-dependent
    hist = [(round(r.first_opening_median_deg, 1), round(r.closed_median_deg, 1)) for r in rows]
    assert hist == [(68.2, -10.7), (80.2, -11.0), (86.2, -4.4)]


@needs_data
def test_model_pitch_on_the_lab_urdf(lab_robot):
    """Issue #15's model column: the metastable pitch with every wing joint at the measured plateau, minus the
    rest at theta_w = 0 (as `landscape physical kinematics` and the report compute it)."""
    from landscape.analysis.physical.hold import plateau_hold_deg
    from landscape.minima import metastable_orientation

    rest = metastable_orientation(lab_robot, 0.0, 0.0)[0]
    hold = plateau_hold_deg(lab_robot, DATA, (60.0, 75.0, 90.0))
    assert [round(hold[c] - rest, 1) for c in (60.0, 75.0, 90.0)] == [65.2, 75.7, 81.4]


@needs_data
def test_physical_table_command_writes_both_files(tmp_path, capsys):
    assert main(["physical", "table", "--data", str(DATA), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "12/58" in out and "43 of 46" in out
    rows = (tmp_path / "trials.csv").read_text().splitlines()
    assert len(rows) == 61 and rows[0].startswith("name,theta_w_cmd_deg,theta_w_measured_deg")
    assert len((tmp_path / "cells.csv").read_text().splitlines()) == 13


# ---------------------------------------------------------------------------------------- attempt paths
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


def test_world_up_in_the_body_frame_with_the_imus_mounting():
    """The IMU reads the body's pitch plus its mounting (landscape.analysis.physical.mounting.mounting_from_rests), so the
    body's pitch is the IMU's minus the mounting; the gyro turns the same way."""
    from geometry.frames import pitch_roll_from_up, up_vector

    p, r = np.deg2rad([60.0, -20.0, 85.0]), np.deg2rad([10.0, 170.0, -35.0])
    pb, rb = pitch_roll_from_up(up_vector(p, r))
    assert np.allclose(pb, p) and np.allclose(rb, r)
    # an IMU that reads level, mounted 30 deg, sits on a body pitched -30 deg
    level = np.array([[0.0, 0.0, 0.0, 1.0]])
    assert np.allclose(np.rad2deg(pitch_roll_from_up(up_in_body(level, 30.0))[0]), -30.0)
    q = np.array([[0.0, np.sin(np.radians(20)), 0.0, np.cos(np.radians(20))]])  # the IMU pitched 40 deg
    assert np.allclose(pitch_roll_from_quat_deg(q)[0], 40.0)
    assert np.allclose(np.rad2deg(pitch_roll_from_up(up_in_body(q, 2.6))[0]), 37.4)
    assert np.allclose(up_in_body(q, 2.6)[..., 2], up_z_mounted(q, 2.6))
    assert np.allclose(imu_to_body([0.0, 0.0, 1.0], 2.6), up_in_body(level, 2.6)[0])
