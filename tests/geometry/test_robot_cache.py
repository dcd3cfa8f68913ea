"""The robot's own forward kinematics (equal to yourdfpy's) and the on-disk robot cache (issue #12): a cached
robot poses exactly as a freshly read one, loads without trimesh or yourdfpy, and is used only when its
description hash and contents check out."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from geometry import Robot
from geometry.builtin import builtin_urdf_path
from geometry.robot import _cache_path

ROOT = Path(__file__).resolve().parents[2]
LAB_URDFS = (
    ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf",
    Path("/work/shared/ref/lab_robot/lab_robot.urdf"),
)
ANGLES = [(0.0, 0.0), (74.0, 30.0), (-10.0, -90.0), (95.0, 90.0), (33.3, -12.5)]


def _urdfs(tmp_path_factory=None):
    out = [builtin_urdf_path()]
    lab = next((p for p in LAB_URDFS if p.is_file()), None)
    return out + ([lab] if lab is not None else [])


def _yourdfpy_transforms(robot, values):
    urdf = robot.urdf
    cfg = np.array([values.get(n, 0.0) for n in urdf.actuated_joint_names])
    urdf.update_cfg(cfg)
    return {p.link: np.asarray(urdf.get_transform(p.link, urdf.base_link)) for p in robot.parts}


@pytest.mark.parametrize("path", _urdfs(), ids=lambda p: p.stem)
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
    from geometry.robot import JointMap

    robot = Robot.from_urdf(path, joint_map=JointMap(wing=("wing",), leg=("leg",)))
    for tw, tl in [(0.0, 0.0), (50.0, -30.0), (-40.0, 170.0)]:
        values = robot.joint_values_rad(tw, tl)
        ours = robot.link_transforms(values)
        for link, T in _yourdfpy_transforms(robot, values).items():
            np.testing.assert_array_equal(ours[link], T)
    assert robot.joint_limits_deg("leg") == (-np.inf, np.inf)
    assert robot.joint_limits_deg("wing") == pytest.approx((np.rad2deg(-1), np.rad2deg(2)))


@pytest.mark.parametrize("path", _urdfs(), ids=lambda p: p.stem)
def test_cached_robot_poses_as_the_fresh_one(path, tmp_path):
    fresh = Robot.from_urdf(path)
    first = Robot.from_urdf(path, cache_dir=tmp_path)
    assert _cache_path(tmp_path, fresh.description_hash).is_file()
    cached = Robot.from_urdf(path, cache_dir=tmp_path)
    assert cached._urdf is None  # the hit did not build yourdfpy's model
    assert cached.description_hash == fresh.description_hash and cached.name == fresh.name
    assert cached.joint_map == fresh.joint_map and cached.theta_limits_deg() == fresh.theta_limits_deg()
    for tw, tl in ANGLES:
        a, b, c = fresh.pose(tw, tl), first.pose(tw, tl), cached.pose(tw, tl)
        for x in (b, c):
            np.testing.assert_array_equal(x.hull_points_m, a.hull_points_m)
            np.testing.assert_array_equal(x.com_m, a.com_m)
            assert x.mass_kg == a.mass_kg
        np.testing.assert_array_equal(c.all_points_m(), a.all_points_m())
    assert cached.element_vertices.keys() == fresh.element_vertices.keys()  # read on demand
    for key, v in fresh.element_vertices.items():
        np.testing.assert_array_equal(cached.element_vertices[key], v)


def test_cache_with_altered_contents_is_not_used(tmp_path):
    path = builtin_urdf_path()
    fresh = Robot.from_urdf(path)
    Robot.from_urdf(path, cache_dir=tmp_path)
    npz = _cache_path(tmp_path, fresh.description_hash)
    with np.load(npz) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["mass_kg"] = arrays["mass_kg"] * 2  # hash strings kept: only the payload digest can tell
    with open(npz, "wb") as f:
        np.savez(f, **arrays)
    robot = Robot.from_urdf(path, cache_dir=tmp_path)
    assert robot.total_mass_kg == pytest.approx(fresh.total_mass_kg, abs=1e-15)
    assert robot._urdf is not None  # rebuilt from the files
    with np.load(npz) as z:  # and the cache rewritten
        np.testing.assert_array_equal(z["mass_kg"], [p.mass.mass_kg for p in fresh.parts])


def test_edited_description_misses_the_cache(tmp_path):
    src = builtin_urdf_path().parent
    shutil.copytree(src, tmp_path / "robot")
    urdf = tmp_path / "robot" / "robot.urdf"
    Robot.from_urdf(urdf, cache_dir=tmp_path / "cache")
    urdf.write_text(urdf.read_text().replace('<mass value="0.0134"/>', '<mass value="0.1134"/>'))
    robot = Robot.from_urdf(urdf, cache_dir=tmp_path / "cache")
    assert robot.total_mass_kg == pytest.approx(0.260 + 0.1, abs=1e-12)


def test_repeated_load_imports_neither_trimesh_nor_yourdfpy(tmp_path):
    """The point of the cache: a second process loads the built-in robot and computes without the mesh stack."""
    code = (
        "import sys\n"
        "from geometry.robots import load_robot\n"
        "from landscape.computation import compute\n"
        "c = compute(load_robot(), theta_w_deg=74.0, theta_l_deg=30.0, step_deg=2.0)\n"
        "print(sorted(m for m in ('trimesh', 'yourdfpy') if m in sys.modules), round(c.minimum.energy_j, 9))\n"
    )
    env = dict(os.environ, LANDSCAPE_CACHE=str(tmp_path), PYTHONPATH=str(ROOT))
    runs = [
        subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
        for _ in range(2)
    ]
    for r in runs:
        assert r.returncode == 0, r.stderr
    first, second = (r.stdout.split("] ") for r in runs)
    assert first[0] != "[" and second[0] == "["  # the first run built the files (trimesh), the second did not
    assert first[1] == second[1]  # the same start energy


def test_cache_of_other_code_is_not_used(tmp_path, monkeypatch):
    """A cache written by another version of the reader (or of trimesh, scipy) is a miss, never read."""
    import geometry.robot as gr

    path = builtin_urdf_path()
    Robot.from_urdf(path, cache_dir=tmp_path)
    assert Robot.from_urdf(path, cache_dir=tmp_path)._urdf is None
    monkeypatch.setattr(gr, "_code_key", lambda: "0123456789ab")
    assert Robot.from_urdf(path, cache_dir=tmp_path)._urdf is not None


def test_installed_version_reads_dist_info():
    import numpy
    import scipy

    from geometry.robot import installed_version

    assert installed_version("numpy") == numpy.__version__
    assert installed_version("scipy") == scipy.__version__
    assert installed_version("no-such-distribution") == "unknown"
