"""The convex hull's sort-and-merge steps (issue #12: one lexsort and an integer-keyed unique instead of
``np.unique(axis=0)``; then Qhull on the points as given, only its vertices sorted) give exactly the former
vertices and order, and the former adjacency and triangles where no face has four or more coplanar vertices
(Qhull splits such a face into triangles by the order it sees the points in)."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from geometry import Robot
from geometry.builtin import builtin_urdf_path
from geometry.hull import convex_hull


def _former_hull(points):
    """The former implementation, verbatim in effect: np.unique rows, qhull, np.unique edge rows."""
    pts = np.unique(np.asarray(points, dtype=np.float64), axis=0)
    qh = ConvexHull(pts)
    keep = np.asarray(qh.vertices, dtype=np.int64)
    remap = np.full(len(pts), -1, dtype=np.int64)
    remap[keep] = np.arange(len(keep))
    simp = remap[np.asarray(qh.simplices, dtype=np.int64)]
    edges = np.concatenate([simp[:, [0, 1]], simp[:, [1, 2]], simp[:, [2, 0]]])
    both = np.unique(np.concatenate([edges, edges[:, ::-1]]), axis=0)
    ptr = np.zeros(len(keep) + 1, dtype=np.int64)
    np.cumsum(np.bincount(both[:, 0], minlength=len(keep)), out=ptr[1:])
    return pts[keep], ptr, both[:, 1], simp


def _assert_same(points):
    h = convex_hull(points)
    v, ptr, idx, simp = _former_hull(points)
    np.testing.assert_array_equal(h.vertices_m, v)
    np.testing.assert_array_equal(h.neighbor_ptr, ptr)
    np.testing.assert_array_equal(h.neighbor_idx, idx)
    np.testing.assert_array_equal(h.simplices, simp)


@pytest.mark.parametrize("seed", range(4))
def test_hull_equals_former_on_random_points_with_duplicates_and_ties(seed):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(300, 3))
    pts[:60, 0] = np.round(pts[:60, 0], 1)  # ties in x, sorted by y then z
    pts = np.concatenate([pts, pts[::7]])  # exact duplicates
    _assert_same(rng.permutation(pts))


def _assert_same_surface(points):
    """The former vertices in the former order, and triangles tiling the same surface: as many triangles and
    edges (a triangulated sphere has 2 V - 4 and 3 V - 6), each one's centroid on the other's boundary."""
    h = convex_hull(points)
    v, ptr, idx, simp = _former_hull(points)
    np.testing.assert_array_equal(h.vertices_m, v)
    assert len(h.neighbor_idx) == len(idx) and h.simplices.shape == simp.shape
    tol = 1e-12 * float(np.ptp(v, axis=0).max())
    for mine, theirs in ((h.simplices, simp), (simp, h.simplices)):
        n = np.cross(v[theirs[:, 1]] - v[theirs[:, 0]], v[theirs[:, 2]] - v[theirs[:, 0]])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        n *= np.sign(np.einsum("ij,ij->i", n, v[theirs[:, 0]] - v.mean(axis=0)))[:, None]  # outward
        offset = np.einsum("ij,ij->i", n, v[theirs[:, 0]])
        centroid = v[mine].mean(axis=1)
        height = (centroid @ n.T - offset).max(axis=1)  # above the other surface (> 0 outside)
        assert np.abs(height).max() <= tol


def test_hull_equals_former_on_the_robot():
    robot = Robot.from_urdf(builtin_urdf_path())
    for tw, tl in [(0.0, 0.0), (74.0, 30.0), (90.0, -40.0)]:
        _assert_same_surface(robot.pose(tw, tl).hull_points_m)
