"""benchmarks/physical/hold_energy.py: along the robot's roll-overs out of the hold the rigid landscape climbs no more than
the body's kinetic energy at its departure can pay at 75 deg (it falls), while the leg's swings in the hold
throw the robot's body several times as far as the model's."""

import doctest
import math

import numpy as np
import pytest

from tests.conftest import LAB_URDF, load_script
from tests.landscape.analysis.physical.lab import DATA, needs_data


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/hold_energy.py")


def test_doctests(bench):
    assert doctest.testmod(bench).failed == 0


def test_kinetic_energy_of_a_spinning_body(bench):
    from geometry.robots import load_robot

    pose = load_robot("builtin").pose(0.0, 0.0)
    up = np.array([0.0, 0.0, 1.0])
    assert bench.kinetic_energy_j(pose, np.zeros(3), up) == 0.0
    i_com = pose.inertia_kg_m2
    # turning about the vertical: rotation about the CoM plus the CoM's speed about the lowest point
    w = np.array([0.0, 0.0, 2.0])
    lowest = pose.hull_points_m[np.argmin(pose.hull_points_m @ up)]
    d = (pose.com_m - lowest)[:2]
    expected = 0.5 * i_com[2, 2] * 4.0 + 0.5 * pose.mass_kg * 4.0 * (d @ d)
    assert math.isclose(bench.kinetic_energy_j(pose, w, up), expected, rel_tol=1e-12)


@pytest.mark.e2e  # dozens of simulated attempts at the lab robot's small step
@needs_data
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_the_robot_is_thrown_further_and_its_climb_is_paid_for(bench, capsys):
    argv = ["--data", str(DATA), "--robot", str(LAB_URDF), "--models", "physical-head"]
    assert bench.main([*argv, "--cells", "60:0,60:45,75:30"]) == 0
    out = capsys.readouterr().out
    assert "body frame (IMU minus the 2.6 deg mounting)" in out
    rows = [ln.split("|") for ln in out.splitlines() if ln.count("|") == 12 and " s | " in ln]
    assert len(rows) == 10  # every first opening rolled over out of the hold, 5 + 5
    assert all(r[6].strip() == "+1" for r in rows)  # the leg's sphere on -y, the side the robot rolls to
    climbs = {(r[1].strip(), int(r[3])): float(r[8].split("(")[0]) for r in rows}
    kes = {(r[1].strip(), int(r[3])): [float(v) for v in r[9].strip(" )").split(" (")] for r in rows}
    # at 75 deg the rigid landscape lets the recorded path fall; at 60 deg it climbs 3-14 mJ, with 9-25 mJ of
    # kinetic energy at the departure (2-6 mJ of it the rotation about the CoM)
    assert max(v for (w, _), v in climbs.items() if w == "75°") < 0.0
    assert all(3.0 < v < 15.0 for (w, _), v in climbs.items() if w == "60°")
    assert all(9.0 < v[0] < 30.0 and 2.0 < v[1] < v[0] for (w, _), v in kes.items() if w == "60°")
    throw = {ln.split("|")[1].strip(): ln.split("|") for ln in out.splitlines() if "°/s" in ln}
    assert (
        throw["60°"][3].strip() == "224 °/s, 19.6° (9)"
    )  # two swings of each of five first openings, less one
    model_range = float(throw["60°"][4].split(",")[1].split("°")[0])
    assert model_range < 0.5 * 19.6  # the model's body moves less than half as far after each swing
    # with the leg still there are no swings, for the robot or for the model (whose leg wobbles about zero)
    assert "| 60° | 0° | – (0) | – (0) |" in out
    assert bench.main([*argv, "--cells", "60:5"]) == 2
    assert "--cells 60:5 is not a recorded cell" in capsys.readouterr().err
    assert bench.main([*argv[:-1], "nosuchset"]) == 2
