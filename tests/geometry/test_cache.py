"""The per-user disk cache of parsed robots: a cached robot poses exactly as a freshly read one, loads without
trimesh or yourdfpy, and is used only when its description hash, contents and code key check out."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import geometry.cache
from geometry import Robot
from geometry.builtin import builtin_urdf_path
from geometry.cache import _cache_path, installed_version
from tests.conftest import HAVE_LAB, LAB_URDF

ROOT = Path(__file__).resolve().parents[2]
ANGLES = [(0.0, 0.0), (74.0, 30.0), (-10.0, -90.0), (95.0, 90.0), (33.3, -12.5)]
URDFS = [builtin_urdf_path(), *([LAB_URDF] if HAVE_LAB else [])]


@pytest.mark.parametrize("path", URDFS, ids=lambda p: p.stem)
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
    path = builtin_urdf_path()
    Robot.from_urdf(path, cache_dir=tmp_path)
    assert Robot.from_urdf(path, cache_dir=tmp_path)._urdf is None
    monkeypatch.setattr(geometry.cache, "_code_key", lambda: "0123456789ab")
    assert Robot.from_urdf(path, cache_dir=tmp_path)._urdf is not None


def test_installed_version_reads_dist_info():
    import numpy
    import scipy

    assert installed_version("numpy") == numpy.__version__
    assert installed_version("scipy") == scipy.__version__
    assert installed_version("no-such-distribution") == "unknown"
