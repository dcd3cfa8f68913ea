"""A model set's ``[mass] com_offset_y_mm``: the whole body's CoM moved sideways, the same in the landscape
(geometry.Robot.with_com_offset) and in the simulation (sim.urdf_edits.shift_com); the table refused in one line when
wrong; the hash; and a one-sided barrier."""

import numpy as np
import pytest

from geometry import UsageError
from geometry.robots import load_robot
from landscape.computation import compute
from sim.mass import ComOffset
from sim.model import sim_model
from sim.model_set import ModelSetError, load_model_set
from sim.world import World
from tests.conftest import set_with_table

OFFSET_MM = -2.0
OFFSET_M = np.array([0.0, OFFSET_MM * 1e-3, 0.0])


def test_the_landscape_robot_moves_its_com_and_nothing_else():
    robot = load_robot(None)
    moved = robot.with_com_offset(OFFSET_M)
    assert robot.with_com_offset([0.0, 0.0, 0.0]) is robot
    assert moved.total_mass_kg == pytest.approx(robot.total_mass_kg, rel=1e-12)
    assert moved.robot_hash != robot.robot_hash and moved.description_hash != robot.description_hash
    for w, leg in ((0.0, 0.0), (74.0, 30.0), (74.0, -30.0)):
        a, b = robot.pose(w, leg), moved.pose(w, leg)
        assert np.allclose(b.com_m - a.com_m, OFFSET_M, rtol=0.0, atol=1e-12)
        assert np.array_equal(a.hull_points_m, b.hull_points_m)
    with pytest.raises(UsageError, match="three finite numbers"):
        robot.with_com_offset([0.0, np.nan, 0.0])


def test_the_simulated_com_moves_as_the_landscape_one():
    """Placed rolled 90 deg (world up = body +y, the same hull on the ground), the CoM height changes by the
    offset's y, and the mass stays."""
    joints = np.deg2rad([60.0, 60.0, 60.0, 60.0, 20.0])
    plain, moved = sim_model(merge_fixed=True), sim_model(merge_fixed=True, modifiers=(ComOffset(OFFSET_MM),))
    assert moved.model_hash != plain.model_hash
    with World(plain, dt_s=5e-4) as w0, World(moved, dt_s=5e-4) as w1:
        for w in (w0, w1):
            w.place(0.0, np.deg2rad(90.0), joints_rad=joints)
        assert w1.mass_kg == pytest.approx(w0.mass_kg, rel=1e-12)
        assert w1.com_height_m() - w0.com_height_m() == pytest.approx(OFFSET_M[1], abs=1e-9)


def test_the_mass_table(tmp_path):
    ms = load_model_set(set_with_table(tmp_path, "mass", "com_offset_y_mm = -1.5\n", base="physical"))
    phys = load_model_set("physical")
    assert ms.com_offset_y_mm == -1.5 and ms.com_offset_m == (0.0, -1.5e-3, 0.0)
    assert phys.com_offset_y_mm == 0.0 and ms.model_set_hash != phys.model_set_hash
    robot = load_robot(None)
    assert phys.robot_for(robot) is robot
    assert np.allclose(ms.robot_for(robot).pose(0.0, 0.0).com_m - robot.pose(0.0, 0.0).com_m, [0, -1.5e-3, 0])
    for table, match in (
        ("com_offset_y_mm = 11.0\n", r"\[mass\]: com_offset_y_mm must be in \[-10, 10\] mm"),
        ("com_offset_y_mm = nan\n", "finite number"),
        ("com_ofset_y_mm = 1.0\n", r"\[mass\]: unknown key 'com_ofset_y_mm'"),
        ("", r"\[mass\]: missing key 'com_offset_y_mm'"),
    ):
        with pytest.raises(ModelSetError, match=match):
            load_model_set(set_with_table(tmp_path, "mass", table, base="physical"))


def test_an_offset_lowers_the_barrier_on_one_side():
    """Moved to -y, the CoM sits nearer the saddle at +roll: the minimal barrier drops (built-in robot at 74 deg:
    8.69 -> 7.42 mJ) and leaves at +roll, the side the lab robot rolls to 43 times in 46; moved to +y, the mirror
    image."""
    robot = load_robot(None)
    exits = [
        compute(r, theta_w_deg=74.0, theta_l_deg=0.0, step_deg=2.0).barrier.righting
        for r in (robot, robot.with_com_offset(OFFSET_M), robot.with_com_offset(-OFFSET_M))
    ]
    assert exits[1].barrier_j < 0.9 * exits[0].barrier_j
    assert exits[2].barrier_j == pytest.approx(exits[1].barrier_j, rel=1e-9)
    assert exits[1].saddle_roll_deg > 20.0 and exits[2].saddle_roll_deg < -20.0
