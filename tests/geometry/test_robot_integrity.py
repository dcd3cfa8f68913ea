"""The robot description is trustworthy: its hash covers every file, bad descriptions are refused with one line
(issues #9 and #16). Every robot here is an exported copy of the built-in robot (no ../shared needed)."""

from pathlib import Path

import numpy as np
import pytest
import trimesh
import yourdfpy
from lxml import etree

from geometry import GeometryError, JointMap, Robot, RobotDescriptionError, UnknownJointError
from geometry.builtin import URDF_NAME, builtin_description, builtin_urdf_path
from geometry.frames import rpy_from_matrix, rpy_matrix
from geometry.urdf import read_urdf

DEFAULT_JOINTS = ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right", "leg")


def export(directory: Path, edit=None) -> Path:
    """Write the built-in robot's files into ``directory`` (as ``landscape robot export`` does); ``edit`` maps
    the URDF text to a new one."""
    directory.mkdir(parents=True, exist_ok=True)
    for name, data in builtin_description().items():
        (directory / name).write_bytes(data)
    urdf = directory / URDF_NAME
    if edit is not None:
        urdf.write_text(edit(urdf.read_text()))
    return urdf


def rename_joints(text: str, names=DEFAULT_JOINTS, prefix="j_") -> str:
    for n in names:
        text = text.replace(f'joint name="{n}"', f'joint name="{prefix}{n}"')
    return text


# ---------------------------------------------------------------------------------------------- #9: the hash
def test_hash_covers_mesh_bytes_and_not_the_directory(tmp_path):
    a = Robot.from_urdf(export(tmp_path / "a"))
    b = Robot.from_urdf(export(tmp_path / "b"))
    assert a.description_hash == b.description_hash
    mesh = tmp_path / "b" / "pendulum_sphere.obj"
    text = mesh.read_text()
    i = text.index("\nv ") + 3
    mesh.write_text(text[:i] + ("1" if text[i] != "1" else "2") + text[i + 1 :])  # one byte of one vertex
    c = Robot.from_urdf(tmp_path / "b" / URDF_NAME)
    assert c.description_hash != a.description_hash
    assert read_urdf(tmp_path / "b" / URDF_NAME).description_hash == c.description_hash
    assert read_urdf(tmp_path / "a" / URDF_NAME).description_hash == a.description_hash


def test_hash_covers_mesh_scale(tmp_path):
    a = Robot.from_urdf(export(tmp_path / "a"))
    b = Robot.from_urdf(
        export(
            tmp_path / "b",
            lambda t: t.replace(
                '<mesh filename="pendulum_sphere.obj"/>',
                '<mesh filename="pendulum_sphere.obj" scale="1.01 1.01 1.01"/>',
            ),
        )
    )
    assert a.description_hash != b.description_hash


def test_single_mesh_hash_covers_bytes_units_mass_and_com(tmp_path):
    f = tmp_path / "box.stl"
    trimesh.creation.box(extents=(40.0, 20.0, 10.0)).export(f)
    (tmp_path / "copy").mkdir()
    g = tmp_path / "copy" / "box.stl"
    g.write_bytes(f.read_bytes())
    base = Robot.from_mesh(f, units="mm", mass_kg=2.0).description_hash
    assert Robot.from_mesh(g, units="mm", mass_kg=2.0).description_hash == base
    others = {
        Robot.from_mesh(f, units="cm", mass_kg=2.0).description_hash,
        Robot.from_mesh(f, units="mm", mass_kg=3.0).description_hash,
        Robot.from_mesh(f, units="mm", mass_kg=2.0, com=[1, 0, 0]).description_hash,
        Robot.from_mesh(f, units="mm", mass_kg=2.0, com_model="shell").description_hash,
    }
    assert base not in others and len(others) == 4


# ---------------------------------------------------------------------------------------------- #16: strict XML
def test_truncated_urdf_is_refused_with_its_line_and_column(tmp_path):
    urdf = export(tmp_path)
    text = urdf.read_text()
    urdf.write_text(text[: len(text) // 2])
    with pytest.raises(RobotDescriptionError, match=r"not well-formed XML at line \d+, column \d+"):
        Robot.from_urdf(urdf)
    with pytest.raises(RobotDescriptionError, match=r"line \d+, column \d+"):
        read_urdf(urdf)


def test_dtd_and_entities_are_refused(tmp_path):
    urdf = export(
        tmp_path,
        lambda t: t.replace(
            '<?xml version="1.0"?>', '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY m "0.0134">]>'
        ).replace('<mass value="0.0134"/>', '<mass value="&m;"/>'),
    )
    with pytest.raises(RobotDescriptionError, match="DOCTYPE"):
        Robot.from_urdf(urdf)


def test_yourdfpy_structure_errors_are_description_errors(tmp_path):
    urdf = export(tmp_path, lambda t: t.replace('<joint name="leg"', "<joint"))
    with pytest.raises(RobotDescriptionError, match="lacks its required attribute 'name'"):
        Robot.from_urdf(urdf)


def test_joint_to_a_missing_link_and_disconnected_links_are_refused(tmp_path):
    urdf = export(tmp_path / "a", lambda t: t.replace('<parent link="motor4"/>', '<parent link="nolink"/>'))
    with pytest.raises(RobotDescriptionError, match="'nolink'"):
        Robot.from_urdf(urdf)


# ---------------------------------------------------------------------------------------------- #16: joint maps
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


def test_renamed_joints_with_a_map_pose_like_the_builtin(tmp_path):
    builtin = Robot.from_urdf(export(tmp_path / "a"))
    urdf = export(tmp_path / "b", rename_joints)
    assert not Robot.from_urdf(urdf).has_joints  # none of the default names and no map: rigid
    jm = JointMap(tuple(f"j_{n}" for n in DEFAULT_JOINTS[:4]), ("j_leg",))
    renamed = Robot.from_urdf(urdf, joint_map=jm)
    assert renamed.pose(74, 30).com_m == pytest.approx(builtin.pose(74, 30).com_m, abs=1e-15)
    assert renamed.robot_hash != renamed.description_hash
    assert builtin.robot_hash == builtin.description_hash
    swapped = Robot.from_urdf(urdf, joint_map=JointMap(jm.wing[:2], jm.leg))
    assert swapped.robot_hash != renamed.robot_hash


# ---------------------------------------------------------------------------------------------- #16: masses
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


def test_nan_vertex_in_a_urdf_mesh_is_refused(tmp_path):
    urdf = export(tmp_path)
    mesh = tmp_path / "motor1.obj"
    lines = mesh.read_text().splitlines()
    k = next(i for i, s in enumerate(lines) if s.startswith("v "))
    lines[k] = "v nan 0 0"
    mesh.write_text("\n".join(lines) + "\n")
    with pytest.raises(RobotDescriptionError, match="motor1.obj.*vertex 0 is not finite"):
        Robot.from_urdf(urdf)


def test_nan_vertex_in_a_mesh_file_is_refused(tmp_path):
    obj = tmp_path / "tet.obj"
    obj.write_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv nan 0 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 5 2 3\n"
    )
    with pytest.raises(GeometryError, match="vertex 4 is not finite"):
        Robot.from_mesh(obj)


# ---------------------------------------------------------------------------------------------- #16: the cache
def test_builtin_cache_is_verified_on_use(tmp_path):
    path = builtin_urdf_path(tmp_path)
    path.write_text(path.read_text().replace('<mass value="0.0134"/>', '<mass value="5"/>'))
    (path.parent / "head_left.obj").write_text("v 0 0 0\n")
    again = builtin_urdf_path(tmp_path)
    assert again == path
    files = builtin_description()
    assert all((path.parent / name).read_bytes() == data for name, data in files.items())
    assert Robot.from_urdf(again).total_mass_kg == pytest.approx(0.260, abs=1e-12)


# ---------------------------------------------------------------------------------------------- one rpy rotation
def test_rpy_matrix_is_the_urdf_convention_and_round_trips():
    rng = np.random.default_rng(5)
    for rpy in [*rng.uniform(-np.pi, np.pi, (20, 3)).tolist(), (0.3, np.pi / 2, 0.0), (0.3, -np.pi / 2, 0.0)]:
        xml = (
            f'<robot name="r"><link name="a"><visual><origin rpy="{rpy[0]!r} {rpy[1]!r} {rpy[2]!r}"/>'
            '<geometry><box size="1 1 1"/></geometry></visual></link></robot>'
        )
        ours = rpy_matrix(rpy)
        theirs = (
            yourdfpy.URDF(yourdfpy.URDF._parse_robot(etree.fromstring(xml)), load_meshes=False)
            .robot.links[0]
            .visuals[0]
            .origin[:3, :3]
        )
        assert ours == pytest.approx(theirs, abs=1e-12)
        assert rpy_matrix(rpy_from_matrix(ours)) == pytest.approx(ours, abs=1e-12)
