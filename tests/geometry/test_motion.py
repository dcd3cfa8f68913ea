"""The posed body's joint Jacobian (geometry/motion.py) against central differences of posing."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from geometry import Robot
from geometry.motion import pose_rates
from geometry.robots import load_robot

STEP_DEG = 1e-4


def _central(robot, pose_at, angle: str):
    """Central differences of the hull points and the CoM per radian of ``angle``."""
    h = np.deg2rad(STEP_DEG)
    plus, minus = pose_at(angle, STEP_DEG), pose_at(angle, -STEP_DEG)
    return (plus.hull_points_m - minus.hull_points_m) / (2 * h), (plus.com_m - minus.com_m) / (2 * h)


def _check(robot, pose, pose_at):
    rates = pose_rates(robot, pose)
    assert sorted(rates) == ["theta_l", "theta_w"]
    for angle, r in rates.items():
        pts, com = _central(robot, pose_at, angle)
        scale = np.abs(r.hull_points_m_per_rad).max()
        # central differences: truncation (h^2 ~ 3e-12) and rounding (1e-16 m / 1.7e-6 rad) far below 1e-9 m/rad
        assert np.abs(pts - r.hull_points_m_per_rad).max() <= 1e-9 * scale, angle
        assert np.abs(com - r.com_m_per_rad).max() <= 1e-9 * scale, angle


@pytest.mark.parametrize("theta_w, theta_l", [(0.0, 0.0), (60.0, 30.0), (74.0, -20.0), (90.0, 45.0)])
def test_rates_are_the_derivative_of_posing(theta_w, theta_l):
    robot = load_robot()

    def pose_at(angle, d):
        return robot.pose(theta_w + d * (angle == "theta_w"), theta_l + d * (angle == "theta_l"))

    _check(robot, robot.pose(theta_w, theta_l), pose_at)


def test_rates_with_each_wing_joint_at_its_own_angle_turn_them_together():
    """A model set's servo plateaus: the derivative turns every wing joint by the same angle."""
    robot = load_robot()
    wing = dict(zip(robot.joint_map.wing, (56.5, 73.1, 58.1, 59.1), strict=True))

    def pose_at(angle, d):
        values = {k: v + d * (angle == "theta_w") for k, v in wing.items()}
        return robot.pose_joints(values | {j: 20.0 + d * (angle == "theta_l") for j in robot.joint_map.leg})

    _check(robot, pose_at("theta_w", 0.0), pose_at)


def test_the_leg_swings_the_com_sideways_by_its_mass_moment():
    """Closed form: the leg turns about the body's z axis, so the CoM moves by (leg mass / total) times the leg's
    own CoM velocity, w x (c_leg - o), which at theta_l = 0 points along -y (the leg hangs along x)."""
    robot = load_robot()
    pose = robot.pose(74.0, 0.0)
    r = pose_rates(robot, pose)["theta_l"]
    (leg_joint,) = [j for j in robot.joints if j.name in robot.joint_map.leg]
    frame = pose.link_transforms[leg_joint.parent] @ leg_joint.origin
    axis = frame[:3, :3] @ (leg_joint.axis / np.linalg.norm(leg_joint.axis))
    (leg,) = [p for p in robot.parts if p.link == leg_joint.child]
    c_leg = pose.link_transforms[leg.link][:3, :3] @ leg.mass.com_m + pose.link_transforms[leg.link][:3, 3]
    want = leg.mass.mass_kg / robot.total_mass_kg * np.cross(axis, c_leg - frame[:3, 3])
    assert np.allclose(r.com_m_per_rad, want, rtol=0, atol=1e-15)
    assert abs(r.com_m_per_rad[1]) > 0 and r.com_m_per_rad[0] == pytest.approx(0.0, abs=1e-15)


def test_a_rigid_body_has_no_rates():
    box = Robot.from_trimesh(trimesh.creation.box(extents=(0.2, 0.1, 0.05)), name="box")
    assert pose_rates(box, box.pose()) == {}


@pytest.mark.shared
def test_rates_on_the_lab_robot(lab_robot):
    def pose_at(angle, d):
        return lab_robot.pose(74.0 + d * (angle == "theta_w"), 30.0 + d * (angle == "theta_l"))

    _check(lab_robot, lab_robot.pose(74.0, 30.0), pose_at)
