"""Outcome tables (landscape/analysis/physical/cells.py): the Wilson interval, and the lab's trials and the
``physical table`` command on the real files (skipped without ../shared)."""

import math

import pytest

from landscape.analysis.physical.cells import lateralisation, physical_cells
from landscape.analysis.physical.outcome import PhysicalTrial, physical_trials
from landscape.cli import main
from tests.landscape.analysis.physical.lab import DATA, needs_data


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
def test_physical_table_command_writes_both_files(tmp_path, capsys):
    assert main(["physical", "table", "--data", str(DATA), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "12/58" in out and "43 of 46" in out
    rows = (tmp_path / "trials.csv").read_text().splitlines()
    assert len(rows) == 61 and rows[0].startswith("name,theta_w_cmd_deg,theta_w_measured_deg")
    assert len((tmp_path / "cells.csv").read_text().splitlines()) == 13
