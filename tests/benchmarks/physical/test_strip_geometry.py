"""benchmarks/physical/strip_geometry.py: a URDF copy whose named links keep their mass but lose their shape."""

import numpy as np
import pytest

from tests.conftest import LAB_URDF, load_script


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/strip_geometry.py")


@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_the_stripped_leg_weighs_the_same_and_cannot_touch(bench, tmp_path, capsys):
    from geometry.robots import load_robot

    assert bench.main([str(LAB_URDF), "--link", "pendulum", "--out", str(tmp_path)]) == 0
    assert "pendulum keep their mass, lose their shape" in capsys.readouterr().out
    full, stripped = load_robot(LAB_URDF), load_robot(tmp_path / LAB_URDF.name)  # meshes found from elsewhere
    a, b = full.pose(0.0, 30.0), stripped.pose(0.0, 30.0)
    assert b.mass_kg == pytest.approx(a.mass_kg) and np.allclose(b.com_m, a.com_m)
    legs = [p for p in b.parts if p.link == "pendulum"]
    assert legs and all(len(p.hull_link_m) == 0 for p in legs)
    assert len(b.hull_points_m) < len(a.hull_points_m)


def test_it_refuses_what_it_cannot_strip(bench, tmp_path, capsys):
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"/></robot>')
    assert bench.main([str(urdf), "--link", "leg", "--out", str(tmp_path / "o")]) == 2
    assert "has no link 'leg'; its links: a" in capsys.readouterr().err
    (tmp_path / "x.urdf").write_text("<sdf/>")
    assert bench.main([str(tmp_path / "x.urdf"), "--link", "a"]) == 2
    assert "not <robot>" in capsys.readouterr().err
    assert bench.main([str(tmp_path / "none.urdf"), "--link", "a"]) == 2
    assert "does not exist" in capsys.readouterr().err
