"""The recording seam (landscape/analysis/physical/recording.py): a lab with another file format registers one
reader, and every analysis then reads its files."""

import math

import numpy as np
import pytest

from landscape.analysis.physical import recording as rec
from landscape.analysis.physical.cells import physical_cells
from landscape.analysis.physical.outcome import physical_trials
from landscape.analysis.physical.recording import (
    PhysicalDataError,
    Recording,
    read_recording,
    register_reader,
    trial_cell,
    trial_files,
)


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
