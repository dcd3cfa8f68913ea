"""URDF to kinematics: the robot's own forward kinematics equal yourdfpy's to the bit (mimic joints and
unnormalised axes too), and a malformed joint tree or inertial is refused with one line naming the link or joint."""

import numpy as np
import pytest

from geometry import JointMap, Robot, RobotDescriptionError
from geometry.builtin import URDF_NAME, builtin_description, builtin_urdf_path
from tests.conftest import HAVE_LAB, LAB_URDF
from tests.robot_files import export

ANGLES = [(0.0, 0.0), (74.0, 30.0), (-10.0, -90.0), (95.0, 90.0), (33.3, -12.5)]
URDFS = [builtin_urdf_path(), *([LAB_URDF] if HAVE_LAB else [])]


def _yourdfpy_transforms(robot, values):
    urdf = robot.urdf
    cfg = np.array([values.get(n, 0.0) for n in urdf.actuated_joint_names])
    urdf.update_cfg(cfg)
    return {p.link: np.asarray(urdf.get_transform(p.link, urdf.base_link)) for p in robot.parts}


@pytest.mark.parametrize("path", URDFS, ids=lambda p: p.stem)
def test_link_transforms_equal_yourdfpy(path):
    robot = Robot.from_urdf(path)
    for tw, tl in ANGLES:
        values = robot.joint_values_rad(tw, tl)
        ours = robot.link_transforms(values)
        theirs = _yourdfpy_transforms(robot, values)
        for link, T in theirs.items():
            np.testing.assert_array_equal(ours[link], T)  # the same arithmetic: equal to the bit


MIMIC_URDF = """<robot name="m">
  <link name="base"><inertial><mass value="1"/><origin xyz="0 0 0"/></inertial>
    <collision><geometry><box size="0.2 0.1 0.05"/></geometry></collision></link>
  <link name="a"><inertial><mass value="0.5"/><origin xyz="0.05 0 0"/></inertial>
    <collision><origin xyz="0.05 0 0"/><geometry><box size="0.1 0.02 0.02"/></geometry></collision></link>
  <link name="b"><inertial><mass value="0.5"/><origin xyz="0.05 0 0"/></inertial>
    <collision><origin xyz="0.05 0 0"/><geometry><box size="0.1 0.02 0.02"/></geometry></collision></link>
  <link name="c"><collision><geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="wing" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0.1 0 0" rpy="0.1 0.2 0.3"/><axis xyz="0 2 1"/><limit lower="-1" upper="2" effort="1" velocity="1"/></joint>
  <joint name="leg" type="continuous"><parent link="base"/><child link="b"/>
    <origin xyz="-0.1 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="follow" type="revolute"><parent link="a"/><child link="c"/>
    <origin xyz="0.1 0 0"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
    <mimic joint="wing" multiplier="-0.5" offset="0.25"/></joint>
</robot>
"""


def test_mimic_and_unnormalised_axes_equal_yourdfpy(tmp_path):
    path = tmp_path / "m.urdf"
    path.write_text(MIMIC_URDF)
    robot = Robot.from_urdf(path, joint_map=JointMap(wing=("wing",), leg=("leg",)))
    for tw, tl in [(0.0, 0.0), (50.0, -30.0), (-40.0, 170.0)]:
        values = robot.joint_values_rad(tw, tl)
        ours = robot.link_transforms(values)
        for link, T in _yourdfpy_transforms(robot, values).items():
            np.testing.assert_array_equal(ours[link], T)
    assert robot.joint_limits_deg("leg") == (-np.inf, np.inf)
    assert robot.joint_limits_deg("wing") == pytest.approx((np.rad2deg(-1), np.rad2deg(2)))


def test_yourdfpy_structure_errors_are_description_errors(tmp_path):
    urdf = export(tmp_path, lambda t: t.replace('<joint name="leg"', "<joint"))
    with pytest.raises(RobotDescriptionError, match="lacks its required attribute 'name'"):
        Robot.from_urdf(urdf)


def test_joint_to_a_missing_link_and_disconnected_links_are_refused(tmp_path):
    urdf = export(tmp_path / "a", lambda t: t.replace('<parent link="motor4"/>', '<parent link="nolink"/>'))
    with pytest.raises(RobotDescriptionError, match="'nolink'"):
        Robot.from_urdf(urdf)


@pytest.mark.parametrize(
    "old, new, match",
    [
        ('<mass value="0.0134"/>', '<mass value="-0.0134"/>', "link 'head': mass"),
        ('<mass value="0.0134"/>', '<mass value="nan"/>', "link 'head': mass"),
        (
            '<origin xyz="0.02694 0 -0.000934" rpy="0 0 0"/>',
            '<origin xyz="0.02694 inf -0.000934" rpy="0 0 0"/>',
            "link 'head': inertial origin",
        ),
    ],
)
def test_bad_masses_name_the_link_and_field(tmp_path, old, new, match):
    text = builtin_description()[URDF_NAME].decode()
    assert text.count(old) == 1
    urdf = export(tmp_path, lambda t: t.replace(old, new))
    with pytest.raises(RobotDescriptionError, match=match):
        Robot.from_urdf(urdf)


def test_nan_inertia_names_the_link_and_field(tmp_path):
    def edit(t):
        i = t.index('<link name="pendulum">')
        j = t.index('ixx="', i) + 5
        return t[:j] + "nan" + t[t.index('"', j) :]

    with pytest.raises(RobotDescriptionError, match="link 'pendulum': inertia"):
        Robot.from_urdf(export(tmp_path, edit))
