import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from geometry import Robot
from landscape.energy import brute_force_landscape, energy_landscape, height_at
from landscape.grid import GridError, cells_per_turn, grid_angles_deg


def _cube(half=1.0, mass=1.0, com=None):
    return Robot.from_trimesh(trimesh.creation.box(extents=(2 * half,) * 3), mass_kg=mass, com=com)


def test_cube_closed_form():
    """Cube of half-side a at roll 0: z_com = a (|cos p| + |sin p|)."""
    a = 0.05
    ls = energy_landscape(_cube(a).pose(), step_deg=1.0, g_m_s2=1.0)
    j0 = np.flatnonzero(ls.angles_deg == 0.0)[0]
    p = np.deg2rad(ls.angles_deg)
    assert ls.energy_j[:, j0] == pytest.approx(a * (np.abs(np.cos(p)) + np.abs(np.sin(p))), rel=1e-12)


def test_sphere_offset_com_closed_form():
    """Sphere of radius r, CoM offset d: U = m g (r - d cos t), t the tilt from the CoM-lowest pose."""
    r, d, m, g = 0.05, 0.01, 0.3, 9.81
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=r)
    body = Robot.from_trimesh(sphere, mass_kg=m, com=[0, 0, -d])
    ls = energy_landscape(body.pose(), step_deg=2.0, g_m_s2=g)
    P, R = np.meshgrid(np.deg2rad(ls.angles_deg), np.deg2rad(ls.angles_deg), indexing="ij")
    cos_t = np.cos(P) * np.cos(R)  # u_z: t = angle between world-up and body +z
    facet = r - np.abs((sphere.face_normals * sphere.triangles_center).sum(axis=1)).min()  # facet sag, m
    assert np.abs(ls.energy_j - m * g * (r - d * cos_t)).max() <= m * g * facet


def test_fast_matches_lab_method_random_body():
    rng = np.random.default_rng(7)
    pts = rng.normal(size=(400, 3)) * [0.1, 0.05, 0.02]
    body = Robot.from_trimesh(trimesh.convex.convex_hull(pts), com=[0.01, -0.02, 0.003])
    pose = body.pose()
    fast = energy_landscape(pose, step_deg=2.0)
    slow = brute_force_landscape(pts, pose.com_m, pose.mass_kg, step_deg=2.0)
    assert np.abs(fast.energy_j - slow).max() <= 1e-12 * np.abs(slow).max()


def test_lab_robot_matches_lab_method(lab_robot):
    pose = lab_robot.pose(74, 30)
    fast = energy_landscape(pose, step_deg=3.0)
    slow = brute_force_landscape(pose.all_points_m(), pose.com_m, pose.mass_kg, step_deg=3.0)
    assert np.abs(fast.energy_j - slow).max() <= 1e-12 * np.abs(slow).max()


def test_kernel_without_jit():
    """The compiled kernel and its pure-Python form agree (NUMBA_DISABLE_JIT=1 in a subprocess)."""
    code = (
        "import numpy as np, trimesh\n"
        "from geometry import Robot\n"
        "from landscape.energy import energy_landscape, brute_force_landscape\n"
        "b = Robot.from_trimesh(trimesh.creation.box(extents=(3, 2, 1)), com=[0.1, 0.2, -0.1])\n"
        "p = b.pose(); f = energy_landscape(p, step_deg=20.0)\n"
        "s = brute_force_landscape(p.hull.vertices_m, p.com_m, 1.0, step_deg=20.0)\n"
        "print(float(np.abs(f.energy_j - s).max()))\n"
    )
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert float(out.stdout) < 1e-12


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=3, max_size=3), st.floats(0.1, 10))
def test_translation_and_scale_invariance(shift, scale):
    box = trimesh.creation.box(extents=(0.3, 0.2, 0.1))
    com = np.array([0.02, -0.01, 0.005])
    base = energy_landscape(Robot.from_trimesh(box, com=com).pose(), step_deg=10.0)
    moved = box.copy()
    moved.apply_translation(shift)
    e_moved = energy_landscape(Robot.from_trimesh(moved, com=com + shift).pose(), step_deg=10.0)
    assert np.allclose(e_moved.energy_j, base.energy_j, rtol=1e-9, atol=1e-12)
    scaled = box.copy()
    scaled.apply_scale(scale)
    e_scaled = energy_landscape(Robot.from_trimesh(scaled, com=com * scale).pose(), step_deg=10.0)
    assert np.allclose(e_scaled.energy_j, scale * base.energy_j, rtol=1e-9)


def test_double_cover_symmetry():
    """E(p, r) = E(180 - p, r + 180): the torus covers the sphere twice."""
    body = Robot.from_trimesh(trimesh.creation.box(extents=(0.3, 0.2, 0.1)), com=[0.03, 0.01, -0.02])
    ls = energy_landscape(body.pose(), step_deg=5.0)
    n = len(ls.angles_deg)
    i = np.arange(n)
    twin_i = (n // 2 - i) % n  # 180 - p
    twin_j = (i + n // 2) % n  # r + 180
    assert np.allclose(ls.energy_j, ls.energy_j[twin_i][:, twin_j], rtol=1e-12)
    # the pole rows are one orientation each: constant along roll, to the last bit
    pole = ls.energy_j[np.flatnonzero(ls.angles_deg == 90.0)[0]]
    assert np.ptp(pole) == 0.0


def test_height_at_matches_grid():
    body = _cube(0.5, com=[0.1, 0, 0])
    pose = body.pose()
    ls = energy_landscape(pose, step_deg=15.0, g_m_s2=1.0)
    P, R = np.meshgrid(ls.angles_deg, ls.angles_deg, indexing="ij")
    assert np.allclose(height_at(pose, P, R), ls.energy_j, atol=1e-14)


@pytest.mark.parametrize("step", [7.0, 0.0, -1.0, np.nan, 0.01])
def test_bad_steps(step):
    with pytest.raises(GridError):
        cells_per_turn(step)


def test_inclusive_grid():
    a = grid_angles_deg(1.0)
    assert a[0] == -180 and a[-1] == 180 and len(a) == 361
    ls = energy_landscape(_cube().pose(), step_deg=30.0)
    ang, e = ls.inclusive()
    assert e.shape == (13, 13) and np.array_equal(e[-1], e[0]) and np.array_equal(e[:, -1], e[:, 0])


def test_fine_step_matches_the_closed_form():
    """The finest supported grid (0.1 deg, 3600 x 3600 cells): cube of half-side a, z_com = a (|cos p| + |sin p|)
    along roll 0 and, by symmetry, along pitch 0."""
    a = 0.05
    ls = energy_landscape(_cube(a).pose(), step_deg=0.1, g_m_s2=1.0)
    assert ls.energy_j.shape == (3600, 3600)
    t = np.deg2rad(ls.angles_deg)
    j0 = np.flatnonzero(np.isclose(ls.angles_deg, 0.0))[0]
    closed = a * (np.abs(np.cos(t)) + np.abs(np.sin(t)))
    assert ls.energy_j[:, j0] == pytest.approx(closed, rel=1e-12)
    assert ls.energy_j[j0, :] == pytest.approx(closed, rel=1e-12)
