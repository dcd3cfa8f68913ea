"""Escape saddles on noisy bodies (issue #12 §2): every reported escape saddle is a critical point whose two
sides roll into different basins, checked independently of the hull graph; barriers agree with a fine grid."""

import numpy as np
import pytest
import trimesh

from geometry import Robot, pitch_roll_from_up, up_vector
from landscape.barriers.exact import exact_barrier
from landscape.barriers.grid import grid_barrier
from landscape.energy import energy_landscape
from landscape.minima import grid_minimum, rest_face


def _jittered_box(extents_mm, subdivisions, amp_mm, seed):
    """A box (mm) whose bottom-face vertices are moved by up to amp_mm in x, y and z."""
    rng = np.random.default_rng(seed)
    mesh = trimesh.creation.box(extents=extents_mm)
    for _ in range(subdivisions):
        mesh = mesh.subdivide()
    v = mesh.vertices.copy()
    bottom = v[:, 2] < v[:, 2].min() + 1e-9
    v[bottom] += rng.uniform(-amp_mm, amp_mm, size=(int(bottom.sum()), 3))
    return Robot.from_trimesh(trimesh.Trimesh(v, mesh.faces, process=False), units="mm")


def _ellipsoid(subdivisions=3):
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    mesh.apply_scale((60.0, 40.0, 30.0))
    return Robot.from_trimesh(mesh, com=[3.0, -2.0, 1.5], units="mm")


BODIES = {
    "box": lambda: _jittered_box((100, 60, 30), 0, 0.3, 0),
    "small box": lambda: _jittered_box((20, 15, 8), 0, 0.9, 0),  # escape 50x below righting, 5 deg away
    "fine box": lambda: _jittered_box((100, 60, 30), 3, 0.5, 2),
    "plate": lambda: _jittered_box((100, 80, 10), 2, 0.3, 3),
    "ellipsoid": _ellipsoid,
}


def _h(pose, u):
    """Brute force: CoM height over every hull point, m."""
    return (np.atleast_2d(u) @ (pose.com_m - pose.hull_points_m).T).max(axis=1)


def _rotate(u, axis, angle_rad):
    axis = axis / np.linalg.norm(axis)
    return (
        u * np.cos(angle_rad)
        + np.cross(axis, u) * np.sin(angle_rad)
        + axis * (axis @ u) * (1 - np.cos(angle_rad))
    )


@pytest.mark.parametrize("name", sorted(BODIES))
def test_escape_saddle_joins_two_basins(name):
    """A saddle, not a slope: the body rests on an edge of two lowest points (brute force over the points);
    rocking about that edge lowers the CoM both ways, tilting along it raises it both ways, and rolling (on the
    point set, no hull graph) from the two rocked orientations reaches the start's face and another minimum."""
    pose = BODIES[name]().pose()
    b = exact_barrier(pose, 0.0, 0.0)
    e = b.barrier.escape
    u_s = up_vector(*np.deg2rad([e.saddle_pitch_deg, e.saddle_roll_deg]))
    d = pose.com_m - pose.hull_points_m
    hv = d @ u_s
    size = np.ptp(pose.hull_points_m, axis=0).max()
    low = np.flatnonzero(hv >= hv.max() - 1e-9 * size)
    edge = pose.hull_points_m[low]
    span = edge - edge[0]
    k = int(np.argmax(np.linalg.norm(span, axis=1)))
    axis = span[k] / np.linalg.norm(span[k])
    assert np.linalg.norm(np.cross(span, axis), axis=1).max() <= 1e-9 * size  # an edge, not a face or point
    tilt = np.cross(u_s, axis)
    minima = b.landscape.face_up[b.landscape.critical.minima_face]
    near = np.arccos(np.clip(minima @ u_s, -1, 1)).min()
    ends = set()
    for angle in (0.1 * near, -0.1 * near):
        rocked = _rotate(u_s, axis, angle)
        assert _h(pose, rocked)[0] < _h(pose, u_s)[0]
        assert _h(pose, _rotate(u_s, tilt, angle))[0] > _h(pose, u_s)[0]
        up, _ = rest_face(pose.hull_points_m, pose.com_m, rocked)
        ends.add(int(np.argmax(minima @ up)))
    start_row = int(np.argmax(minima @ b.landscape.face_up[b.start_face]))
    assert start_row in ends and len(ends) == 2


def _lipschitz_tol(pose, step_deg):
    """m g R step: how far a grid barrier can sit from the exact one (R = farthest hull point from the CoM);
    a grid path lies within step/sqrt(2) of a continuous one and h is R-Lipschitz in angle (1.5 > sqrt 2)."""
    radius = np.linalg.norm(pose.hull_points_m - pose.com_m, axis=1).max()
    return 1.5 * radius * np.deg2rad(step_deg) * pose.mass_kg * 9.81


@pytest.mark.parametrize("name", ["plate", "ellipsoid", "box"])
def test_righting_matches_fine_grid(name):
    """Righting barrier against a brute-force flood on a 0.5 deg grid, within the grid's Lipschitz bound."""
    pose = BODIES[name]().pose()
    b = exact_barrier(pose, 0.0, 0.0)
    ls = energy_landscape(pose, step_deg=0.5)
    gb = grid_barrier(ls, grid_minimum(ls, b.start.pitch_deg, b.start.roll_deg))
    tol = _lipschitz_tol(pose, 0.5)
    assert abs(gb.righting.barrier_j - b.barrier.righting.barrier_j) <= tol


def test_ellipsoid_escape_matches_fine_grid():
    """On the ellipsoid the minima are facets several degrees apart, which the 0.5 deg grid resolves."""
    pose = _ellipsoid().pose()
    b = exact_barrier(pose, 0.0, 0.0)
    ls = energy_landscape(pose, step_deg=0.5)
    gb = grid_barrier(ls, grid_minimum(ls, b.start.pitch_deg, b.start.roll_deg))
    assert abs(gb.escape.barrier_j - b.barrier.escape.barrier_j) <= _lipschitz_tol(pose, 0.5)
    p, r = pitch_roll_from_up(b.landscape.face_up[b.start_face][None, :])
    assert (b.start.pitch_deg, b.start.roll_deg) == pytest.approx(
        (float(np.rad2deg(p[0])), float(np.rad2deg(r[0]))), abs=1e-9
    )
