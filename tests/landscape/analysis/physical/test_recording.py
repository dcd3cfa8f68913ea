"""Reading recordings (landscape/analysis/physical/recording.py): the quaternion convention, the IMU's mounting,
one-line errors for a bad directory or file, and the seam a lab with another file format plugs its reader into."""

import math

import numpy as np
import pytest

from geometry.frames import up_vector
from landscape.analysis.physical import recording as rec
from landscape.analysis.physical.cells import physical_cells
from landscape.analysis.physical.outcome import physical_trials
from landscape.analysis.physical.recording import (
    PhysicalDataError,
    Recording,
    imu_to_body,
    pitch_roll_from_quat_deg,
    read_recording,
    register_reader,
    trial_cell,
    trial_files,
    up_in_body,
    up_z_mounted,
)
from landscape.cli import main
from tests.landscape.analysis.physical.lab import _quat_from_pitch_roll


def _read_csv(path):
    """A made-up format: one line per sample, time (s from the first opening) and world-up's body-z component;
    every opening 2 s apart."""
    t, up_z = np.loadtxt(path, delimiter=",", unpack=True)
    w, leg, trial = trial_cell(path) + (int(path.name.split("_")[-1].split(".")[0]),)
    return Recording(
        path.name, w, leg, trial, t, np.zeros_like(t), np.ones_like(t), up_z, np.arange(0.0, t[-1], 2.0)
    )


@pytest.fixture
def csv_reader(monkeypatch):
    monkeypatch.setattr(rec, "_READERS", dict(rec._READERS))
    register_reader(".csv", _read_csv)


def _write(path, t, up_z):
    np.savetxt(path, np.column_stack([t, up_z]), delimiter=",")


def test_a_registered_reader_feeds_every_analysis(tmp_path, csv_reader):
    t = np.arange(-0.5, 5.0, 0.02)
    _write(
        tmp_path / "run5_75_75_75_75_15_1.csv", t, np.where(t > 2.5, -1.0, 1.0)
    )  # rights in the 2nd opening
    _write(tmp_path / "run5_75_75_75_75_15_2.csv", t, np.ones_like(t))  # never rights
    (tmp_path / "notes.csv").write_text("not a trial\n")
    assert [p.name for p in trial_files(tmp_path)] == [
        "run5_75_75_75_75_15_1.csv",
        "run5_75_75_75_75_15_2.csv",
    ]
    trials = physical_trials(tmp_path)
    assert [(t.success, t.attempts) for t in trials] == [(True, 2), (False, 3)]
    assert math.isclose(trials[0].time_to_right_s, 2.5, abs_tol=1e-9)  # the first sample past 2.5 s
    (cell,) = physical_cells(trials)
    assert (cell.theta_w_cmd_deg, cell.theta_l_deg, cell.n, cell.successes) == (75.0, 15.0, 2, 1)


def test_a_name_without_a_registered_reader_names_the_formats(tmp_path, csv_reader):
    with pytest.raises(PhysicalDataError, match=r"run5_W_W_W_W_L_K\.bag\.mat or run5_W_W_W_W_L_K\.csv"):
        read_recording(tmp_path / "run5_60_60_60_60_0_1.txt")
    with pytest.raises(PhysicalDataError, match=r"holds no trial file run5_W_W_W_W_L_K\.bag\.mat or"):
        trial_files(tmp_path)


def test_the_labs_format_alone_reads_as_before(tmp_path):
    with pytest.raises(
        PhysicalDataError, match=r"^'x\.csv' is not a trial file name run5_W_W_W_W_L_K\.bag\.mat$"
    ):
        read_recording(tmp_path / "x.csv")
    with pytest.raises(ValueError, match="must start with a dot"):
        register_reader("csv", _read_csv)


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
