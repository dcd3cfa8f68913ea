"""``--model`` on compute and barrier-map (issue #15): a measured set poses each wing servo at its own plateau; an
idealised set, or each joint given the same angle, is the plain computation."""

import json

import numpy as np
import pytest

from landscape.cli import main
from landscape.computation import barrier_map, compute
from sim.model_set import load_model_set
from tests.conftest import LAB_URDF, needs_lab


def test_equal_wing_joints_are_the_plain_computation():
    from geometry.robots import load_robot

    robot = load_robot(None)
    plain = compute(robot, theta_w_deg=74.0, theta_l_deg=20.0)
    same = compute(
        robot, theta_w_deg=74.0, theta_l_deg=20.0, wing_joints_deg=dict.fromkeys(robot.joint_map.wing, 74.0)
    )
    assert same.start_deg == pytest.approx(plain.start_deg, abs=1e-9)
    assert same.barrier.righting.barrier_j == pytest.approx(plain.barrier.righting.barrier_j, abs=1e-12)
    assert same.barrier.escape.barrier_j == pytest.approx(plain.barrier.escape.barrier_j, abs=1e-12)


def test_measured_plateaus_are_the_largest_knots_and_interpolate_between_commands():
    m = load_model_set("physical").measured
    for i, c in enumerate(m.wing_command_deg):
        assert m.wing_plateaus_deg(c) == pytest.approx(np.asarray(m.wing_knots_deg)[:, i].max(axis=1))
    knots = np.asarray(m.wing_knots_deg)  # (servo, command, knot)
    mid = m.wing_plateaus_deg(
        67.5
    )  # halfway between 60 and 75: every knot halfway, the plateau their largest
    assert mid == pytest.approx(((knots[:, 0] + knots[:, 1]) / 2).max(axis=1), abs=1e-9)
    for bad in (59.0, 91.0, float("nan")):
        with pytest.raises(ValueError, match="outside the measured wing commands"):
            m.wing_plateaus_deg(bad)


@needs_lab
def test_compute_and_barrier_map_with_the_physical_set(tmp_path, capsys):
    from geometry.robots import load_robot

    robot = load_robot(LAB_URDF)
    joints = dict(
        zip(robot.joint_map.wing, load_model_set("physical").measured.wing_plateaus_deg(75.0), strict=True)
    )
    want = compute(robot, theta_w_deg=75.0, theta_l_deg=0.0, wing_joints_deg=joints)
    args = ["compute", "--robot", str(LAB_URDF), "--theta-w", "75", "--model", "physical", "--json"]
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["model_set"] == "physical" and doc["wing_joints_deg"] == pytest.approx(joints)
    assert doc["barrier"]["righting_j"] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)
    # the asymmetric plateaus (left pitch 73.66, right 73.36 ...) tilt the start off the mirror plane
    assert doc["minimum"]["roll_deg"] != 0.0
    bm = barrier_map(robot, [75.0], [0.0], wing_joints_deg={75.0: joints}, workers=1)
    assert bm.righting_j[0, 0] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)
    out = tmp_path / "map"
    assert main(["barrier-map", "--robot", str(LAB_URDF), "--theta-w", "60,75", "--theta-l", "0",
                 "--model", "physical", "--out", str(out)]) == 0  # fmt: skip
    rows = (out / "barrier_map.csv").read_text().splitlines()
    assert len(rows) == 3 and rows[2].startswith("75.0,0.0,")
    # the CSV keeps 1e-9 J (landscape.viz.files.CSV_DECIMALS)
    assert float(rows[2].split(",")[5]) == pytest.approx(want.barrier.righting.barrier_j, abs=5e-10)
    capsys.readouterr()
    assert main(["compute", "--robot", str(LAB_URDF), "--theta-w", "50", "--model", "physical"]) == 2
    err = capsys.readouterr().err
    assert "theta_w = 50 deg is outside the measured wing commands [60, 90] deg" in err
    assert "Traceback" not in err


@needs_lab
def test_the_posed_set_holds_the_body_where_the_robots_imu_reads_its_hold(capsys):
    """physical-posed: each wing servo's plateau 15 deg further open at 60: the hold at 68.3 deg (the robot's IMU
    reads 68.1), against 57.6 deg for physical, and the righting barrier down from 31.0 to 9.2 mJ."""
    held = {}
    for name in ("physical", "physical-posed"):
        args = ["compute", "--robot", str(LAB_URDF), "--theta-w", "60", "--model", name, "--json"]
        assert main(args) == 0
        doc = json.loads(capsys.readouterr().out)
        held[name] = (doc["minimum"]["pitch_deg"], doc["barrier"]["righting_j"])
        plateaus = load_model_set(name).measured.wing_plateaus_deg(60.0)
        assert doc["wing_joints_deg"] == pytest.approx(
            dict(zip(doc["wing_joints_deg"], plateaus, strict=True))
        )
    assert held["physical"][0] == pytest.approx(57.58, abs=0.01) and held["physical-posed"][
        0
    ] == pytest.approx(68.27, abs=0.01)
    assert held["physical"][1] == pytest.approx(30.964e-3, abs=1e-5)
    assert held["physical-posed"][1] == pytest.approx(9.178e-3, abs=1e-5)


def test_an_idealised_set_poses_every_joint_at_theta_w(capsys):
    assert main(["compute", "--theta-w", "74", "--model", "paper", "--json"]) == 0
    with_set = json.loads(capsys.readouterr().out)
    assert main(["compute", "--theta-w", "74", "--json"]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert with_set["barrier"] == plain["barrier"] and with_set["wing_joints_deg"] is None


def test_a_rigid_body_takes_no_model_set(tmp_path, capsys):
    import trimesh

    mesh = tmp_path / "box.stl"
    trimesh.creation.box(extents=(0.1, 0.06, 0.04)).export(mesh)
    assert main(["compute", "--mesh", str(mesh), "--model", "physical"]) == 2
    err = capsys.readouterr().err
    assert "--model physical poses wing joints, but box is a rigid body without joints" in err
    assert len(err.strip().splitlines()) == 1


def test_a_set_that_moves_the_com_moves_it_in_compute_and_barrier_map(tmp_path, capsys):
    """`compute --model FILE` and `barrier-map --model FILE` with a `[mass] com_offset_y_mm` give the landscape
    of the robot with its CoM moved (geometry.Robot.with_com_offset), as its trials simulate it."""
    from pathlib import Path

    from geometry.robots import load_robot

    f = tmp_path / "moved.toml"
    f.write_text(Path(load_model_set("paper").source).read_text() + "\n[mass]\ncom_offset_y_mm = -2.0\n")
    want = compute(load_robot(None).with_com_offset([0.0, -2e-3, 0.0]), theta_w_deg=74.0, theta_l_deg=20.0)
    assert main(["compute", "--theta-w", "74", "--theta-l", "20", "--model", str(f), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["barrier"]["righting_j"] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)
    assert main(["compute", "--theta-w", "74", "--theta-l", "20", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["barrier"]["righting_j"] > doc["barrier"]["righting_j"] + 1e-4
    out = tmp_path / "map"
    assert (
        main(["barrier-map", "--theta-w", "74", "--theta-l", "20", "--model", str(f), "--out", str(out)]) == 0
    )
    row = (out / "barrier_map.csv").read_text().splitlines()[1].split(",")
    assert float(row[5]) == pytest.approx(want.barrier.righting.barrier_j, abs=5e-10)  # 1e-9 J in the CSV
