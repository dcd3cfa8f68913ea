"""A model set's ``[geometry]`` joint shift: one joint's origin (and everything it carries) moved, the same in the
landscape (geometry.Robot.with_joint_shift) and in the simulation (sim.urdf_edits.shift_joint); the table refused in
one line when wrong; the hash; and the lab robot's head moved back holds the body where the robot holds it."""

import numpy as np
import pybullet as pb
import pytest

from geometry import UsageError
from geometry.errors import UnknownJointError
from geometry.robots import load_robot
from landscape.minima import metastable_orientation
from sim.joint_shift import JointShift
from sim.model import sim_model
from sim.model_set import ModelSetError, load_model_set
from sim.world import World
from tests.conftest import set_with_table

SHIFT_MM = (-12.0, 0.0, 2.0)
SHIFT_M = np.array(SHIFT_MM) * 1e-3


def test_the_landscape_robot_moves_the_head_and_nothing_else():
    robot = load_robot(None)
    moved = robot.with_joint_shift("head_mount", SHIFT_M)
    assert robot.with_joint_shift("head_mount", [0.0, 0.0, 0.0]) is robot
    assert moved.robot_hash != robot.robot_hash
    head = next(p for p in robot.parts if p.link == "head").mass.mass_kg
    for w, leg in ((0.0, 0.0), (74.0, 30.0)):
        a, b = robot.pose(w, leg), moved.pose(w, leg)
        for link, t in a.link_transforms.items():
            want = SHIFT_M if link == "head" else np.zeros(3)
            assert np.allclose(b.link_transforms[link][:3, 3] - t[:3, 3], want, rtol=0.0, atol=1e-15), link
        assert np.allclose(b.com_m - a.com_m, SHIFT_M * head / a.mass_kg, rtol=0.0, atol=1e-12)
    with pytest.raises(UnknownJointError, match="no joint 'hed_mount' to shift; its joints are .*head_mount"):
        robot.with_joint_shift("hed_mount", SHIFT_M)
    with pytest.raises(UsageError, match="three finite numbers"):
        robot.with_joint_shift("head_mount", [0.0, np.inf, 0.0])


def test_the_simulated_head_moves_as_the_landscape_one():
    """Placed alike, the simulated head link sits SHIFT_M further from the base (base frame) and nothing else
    moves; the model's rest is the shifted robot's."""
    plain, moved = sim_model(), sim_model(modifiers=(JointShift("head_mount", SHIFT_MM),))
    assert moved.model_hash != plain.model_hash
    joints = np.deg2rad([60.0, 60.0, 60.0, 60.0, 20.0])

    def frames(world):
        world.place(0.0, 0.0, joints_rad=joints)
        pos, orn = pb.getBasePositionAndOrientation(world.body, physicsClientId=world.cid)
        inv = pb.invertTransform(pos, orn)
        out = {}
        for k in range(world.n_joints):
            name = pb.getJointInfo(world.body, k, physicsClientId=world.cid)[12].decode()
            p = pb.getLinkState(world.body, k, physicsClientId=world.cid)[4]
            out[name] = np.array(pb.multiplyTransforms(*inv, p, (0, 0, 0, 1))[0])
        return out

    with World(plain, dt_s=5e-4) as w0, World(moved, dt_s=5e-4) as w1:
        a, b = frames(w0), frames(w1)
    for link in a:
        want = SHIFT_M if link == "head" else np.zeros(3)
        assert np.allclose(b[link] - a[link], want, rtol=0.0, atol=1e-6), link  # pybullet: single precision
    with pytest.raises(UnknownJointError, match="no joint 'nope' to shift"):
        sim_model(modifiers=(JointShift("nope", SHIFT_MM),))


def test_the_geometry_table(tmp_path):
    ms = load_model_set(
        set_with_table(
            tmp_path, "geometry", 'shift_joint = "head_mount"\nshift_mm = [-12, 0, 2]\n', base="physical"
        )
    )
    phys = load_model_set("physical")
    assert ms.joint_shift_mm == ("head_mount", (-12.0, 0.0, 2.0))
    assert ms.joint_shift_m == ("head_mount", pytest.approx((-0.012, 0.0, 0.002)))
    assert phys.joint_shift_m is None and ms.model_set_hash != phys.model_set_hash
    assert ms.summary()["joint_shift"] == {"joint": "head_mount", "shift_mm": [-12.0, 0.0, 2.0]}
    assert "geometry" in ms.summary()["elements"] and phys.summary()["joint_shift"] is None
    robot = load_robot(None)
    assert ms.robot_for(robot).robot_hash == robot.with_joint_shift("head_mount", SHIFT_M).robot_hash
    for table, match in (
        (
            'shift_joint = "head_mount"\nshift_mm = [-31, 0, 0]\n',
            r"\[geometry\]: shift_mm must be three numbers",
        ),
        ('shift_joint = "head_mount"\nshift_mm = [1, 2]\n', r"\[geometry\]: shift_mm must be three numbers"),
        ('shift_joint = ""\nshift_mm = [1, 2, 3]\n', r"\[geometry\]: shift_joint must be a joint's name"),
        ("shift_mm = [1, 2, 3]\n", r"\[geometry\]: missing key 'shift_joint'"),
        (
            'shift_joint = "head_mount"\nshift_mm = [1, 2, 3]\nshift = 1\n',
            r"\[geometry\]: unknown key 'shift'",
        ),
    ):
        with pytest.raises(ModelSetError, match=match):
            load_model_set(set_with_table(tmp_path, "geometry", table, base="physical"))


def test_a_head_further_back_holds_the_body_further_over():
    """The hold's pitch rises with the head moved back (the built-in robot held open at 74 deg), while the rest
    with the wings closed, which the head does not touch, stays."""
    robot = load_robot(None)
    moved = robot.with_joint_shift("head_mount", [-0.015, 0.0, 0.0])
    assert metastable_orientation(moved, 74.0, 0.0)[0] > metastable_orientation(robot, 74.0, 0.0)[0] + 4.0
    assert metastable_orientation(moved, 0.0, 0.0)[0] == pytest.approx(
        metastable_orientation(robot, 0.0, 0.0)[0], abs=0.5
    )
