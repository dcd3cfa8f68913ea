import numpy as np
import pytest
import trimesh

from geometry import GeometryError, JointLimitError, JointMap, Robot, RobotDescriptionError, UnknownJointError

# Reference values from ../shared/ref/lab_robot/README.md (CoM in mm)
LAB_COM_MM = {
    (0, 0): (7.5156, -0.0621, 3.4843),
    (74, 0): (15.2153, -0.0621, -1.6171),
    (90, 0): (16.0227, -0.0621, 0.0043),
    (74, 50): (19.9858, -10.2925, -1.6171),
}


@pytest.mark.parametrize("angles", sorted(LAB_COM_MM))
def test_lab_robot_com(lab_robot, angles):
    pose = lab_robot.pose(*angles)
    assert pose.mass_kg == pytest.approx(0.260, abs=1e-12)
    assert pose.com_m * 1e3 == pytest.approx(LAB_COM_MM[angles], abs=1e-4)


def test_lab_robot_limits(lab_robot):
    assert lab_robot.theta_limits_deg() == {
        "theta_w": pytest.approx((-10, 95)),
        "theta_l": pytest.approx((-90, 90)),
    }
    with pytest.raises(JointLimitError, match=r"limits \[-10, 95\]"):
        lab_robot.pose(96, 0)
    with pytest.raises(JointLimitError, match="finite"):
        lab_robot.pose(np.nan, 0)


def test_missing_files(tmp_path):
    with pytest.raises(RobotDescriptionError, match="not found"):
        Robot.from_urdf(tmp_path / "none.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text(
        "<robot name='x'><link name='a'><visual><geometry><mesh filename='missing.obj'/></geometry>"
        "</visual><inertial><mass value='1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/>"
        "</inertial></link></robot>"
    )
    with pytest.raises(RobotDescriptionError, match="missing.obj"):
        Robot.from_urdf(bad)
    garbage = tmp_path / "garbage.urdf"
    garbage.write_text("not xml at all <<<")
    with pytest.raises(RobotDescriptionError, match="not well-formed XML at line 1, column 1"):
        Robot.from_urdf(garbage)


def test_primitive_urdf(tmp_path):
    """A URDF of primitives: a box body and a sphere on a revolute leg."""
    urdf = tmp_path / "prim.urdf"
    urdf.write_text("""<robot name="prim">
  <link name="body"><collision><geometry><box size="0.2 0.1 0.05"/></geometry></collision>
    <inertial><mass value="1.0"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
  <link name="foot"><collision><origin xyz="0.1 0 0"/><geometry><sphere radius="0.02"/></geometry></collision>
    <inertial><origin xyz="0.1 0 0"/><mass value="1.0"/>
      <inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial></link>
  <link name="flap"/>
  <joint name="hip" type="revolute"><parent link="body"/><child link="foot"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="flap" type="continuous"><parent link="body"/><child link="flap"/><axis xyz="1 0 0"/></joint>
</robot>""")
    r = Robot.from_urdf(urdf, joint_map=JointMap(wing=("flap",), leg=("hip",)))
    p = r.pose(0, 90 * 0.5)
    # foot CoM rotated 45 deg about z: (0.1 cos45, 0.1 sin45, 0); body at origin; equal masses
    assert p.com_m == pytest.approx([0.05 * np.cos(np.pi / 4), 0.05 * np.sin(np.pi / 4), 0], abs=1e-12)


def test_mesh_robot_units(tmp_path):
    box = trimesh.creation.box(extents=(40.0, 20.0, 10.0))
    f = tmp_path / "box.stl"
    box.export(f)
    r_mm = Robot.from_mesh(f, units="mm", mass_kg=2.0)
    p = r_mm.pose()
    assert p.theta_w_deg is None
    assert np.ptp(p.hull.vertices_m, axis=0) == pytest.approx([0.04, 0.02, 0.01])
    assert p.com_m == pytest.approx([0, 0, 0], abs=1e-12)
    r_c = Robot.from_mesh(f, units="mm", com=[5, 0, 0])
    assert r_c.pose().com_m == pytest.approx([0.005, 0, 0])


def test_mesh_robot_bad_input(tmp_path):
    with pytest.raises(RobotDescriptionError, match="not found"):
        Robot.from_mesh(tmp_path / "nope.stl")
    junk = tmp_path / "junk.stl"
    junk.write_bytes(b"\x00\x01garbage")
    with pytest.raises(RobotDescriptionError):
        Robot.from_mesh(junk)
    nan_box = trimesh.creation.box(extents=(1, 1, 1))
    v = nan_box.vertices.copy()
    v[3, 1] = np.nan
    with pytest.raises(GeometryError, match="not finite"):
        Robot.from_trimesh(trimesh.Trimesh(v, nan_box.faces, process=False))


def test_pose_joints_sets_each_joint_on_its_own():
    """Equal angles on every wing joint give pose(theta_w, theta_l) exactly; one wing joint moved alone moves only
    that wing's points (the body and the other wing stay); bad names and angles are refused."""
    from geometry.robots import load_robot

    rb = load_robot()
    wing, leg = rb.joint_map.wing, rb.joint_map.leg
    a = rb.pose(74.0, 30.0)
    b = rb.pose_joints({**{n: 74.0 for n in wing}, **{n: 30.0 for n in leg}})
    assert np.array_equal(a.hull_points_m, b.hull_points_m) and np.array_equal(a.com_m, b.com_m)
    assert b.theta_w_deg is None
    base = rb.pose_joints({n: 60.0 for n in wing})
    one = rb.pose_joints({**{n: 60.0 for n in wing}, wing[0]: 70.0})
    moved = np.linalg.norm(one.hull_points_m - base.hull_points_m, axis=1) > 1e-12
    assert 0 < moved.sum() < len(moved) and not np.array_equal(one.com_m, base.com_m)
    with pytest.raises(UnknownJointError, match="not a movable joint"):
        rb.pose_joints({"nosuchjoint": 1.0})
    with pytest.raises(JointLimitError, match="outside joint"):
        rb.pose_joints({wing[0]: float("nan")})
