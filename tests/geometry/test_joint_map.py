"""Joint maps: their text form, what they refuse, and their check against a robot's joints."""

import pytest

from geometry import GeometryError, JointMap, Robot, UnknownJointError
from tests.robot_files import export, rename_joints


def test_joint_map_parse():
    jm = JointMap.parse("wing=a, b;leg=c")
    assert jm.wing == ("a", "b") and jm.leg == ("c",)
    with pytest.raises(GeometryError, match="not 'wing=NAME"):
        JointMap.parse("arm=x")


def test_unknown_joint(lab_robot):
    with pytest.raises(UnknownJointError, match="'nope' is not in"):
        Robot.from_urdf(lab_robot.source, joint_map=JointMap(wing=("nope",)))


@pytest.mark.parametrize(
    "text, match",
    [
        ("wing=;leg=", "names no joint"),
        ("", "names no joint"),
        ("wing=a,,b", "empty name"),
        ("wing=leg;leg=leg", "twice"),
        ("wing=a,a;leg=b", "twice"),
        ("wing=a;wing=b;leg=c", "twice"),
        ("arm=x", "not 'wing=NAME"),
    ],
)
def test_bad_joint_maps_are_refused(text, match):
    with pytest.raises(GeometryError, match=match):
        JointMap.parse(text)


@pytest.mark.parametrize(
    "text, wing, leg",
    [
        ("wing=a", ("a",), ()),
        ("wing=a;leg=", ("a",), ()),
        ("leg=c", (), ("c",)),
        ("wing=a,b;leg=c", ("a", "b"), ("c",)),
    ],
)
def test_either_joint_group_may_be_left_out(text, wing, leg):
    jm = JointMap.parse(text)
    assert (jm.wing, jm.leg) == (wing, leg)
    assert JointMap.parse(jm.text()) == jm


def test_joint_map_round_trips_through_its_text():
    jm = JointMap.parse(" wing = a, b ; leg = c ")
    assert JointMap.parse(jm.text()) == jm and jm.text() == "wing=a,b;leg=c"


def test_joint_map_must_name_movable_joints(tmp_path):
    urdf = export(tmp_path)
    with pytest.raises(UnknownJointError, match="'head_mount' is fixed"):
        Robot.from_urdf(urdf, joint_map=JointMap.parse("wing=head_mount;leg=leg"))
    with pytest.raises(UnknownJointError, match="'nope' is not in"):
        Robot.from_urdf(urdf, joint_map=JointMap.parse("wing=nope;leg=leg"))


def test_partial_default_joints_are_an_error_naming_the_missing(tmp_path):
    urdf = export(tmp_path, lambda t: rename_joints(t, ("leg",), prefix="x"))
    with pytest.raises(UnknownJointError, match="4 of the 5 default joints; missing: leg"):
        Robot.from_urdf(urdf)
