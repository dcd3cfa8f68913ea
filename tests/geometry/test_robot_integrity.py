"""The robot description is trustworthy: its hash covers every file, bad XML is refused with one line, a renamed
robot with a joint map poses like the original. Every robot here is an exported copy of the built-in robot (no
../shared needed)."""

import numpy as np
import pytest
import trimesh
import yourdfpy
from lxml import etree

from geometry import JointMap, Robot, RobotDescriptionError
from geometry.builtin import URDF_NAME, builtin_description, builtin_urdf_path
from geometry.frames import rpy_from_matrix, rpy_matrix
from geometry.urdf import read_urdf
from tests.robot_files import DEFAULT_JOINTS, export, rename_joints


# ---------------------------------------------------------------------------------------------- the hash
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


# ---------------------------------------------------------------------------------------------- strict XML
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


# ---------------------------------------------------------------------------------------------- joint maps
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


# ---------------------------------------------------------------------------------------------- the built-in robot's files
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
