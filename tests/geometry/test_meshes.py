"""Reading meshes: a vertex that is not finite is refused, in a URDF's mesh and in a mesh file."""

import pytest

from geometry import GeometryError, Robot, RobotDescriptionError
from tests.robot_files import export


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
