"""Simplified convex collision hulls: what contact with flat ground needs of a link's meshes (pure).

Contact with flat ground only ever touches the convex hull of a link, so each collision mesh is replaced by its
convex hull, and a hull with more than a few dozen vertices is simplified by *support-gap refinement*: starting
from the six axis-extreme vertices, the vertex that sticks out furthest beyond the current subset, measured along
``N_DIRECTIONS`` evenly spread directions, is added until no direction sees a gap above ``tol`` or
``max_vertices`` is reached. The support function ``h(d) = max_v v.d`` is the height of the lowest point of the
link above the ground when ``d`` points down, so the gap bounds how much higher the simplified link rests than the
original in any of those directions. ``benchmarks/sim_convergence.py`` checks that outcomes do not change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull

N_DIRECTIONS = 2000
"""Directions on which the support gap of a simplified hull is measured (Fibonacci sphere)."""

HULL_TOL_M = 1e-4
"""Default largest support gap of a simplified hull, m."""

HULL_MAX_VERTICES = 96
"""Default vertex budget of a simplified hull (Bullet's advice: keep convex hulls under ~100 vertices)."""


def fibonacci_directions(n: int) -> NDArray[np.float64]:
    """``n`` unit vectors spread evenly over the sphere.

    Examples
    --------
    >>> d = fibonacci_directions(100)
    >>> d.shape, bool(np.allclose(np.linalg.norm(d, axis=1), 1.0))
    ((100, 3), True)
    """
    k = np.arange(n, dtype=np.float64) + 0.5
    z = 1.0 - 2.0 * k / n
    rho = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k
    return np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=1)


@dataclass(frozen=True)
class SimplifiedHull:
    """A convex hull reduced to the vertices that matter for contact.

    Attributes
    ----------
    vertices : ndarray of shape (K, 3)
        Kept vertices, in the units of the input points.
    faces : ndarray of shape (F, 3) of int64
        Outward triangles of the hull of ``vertices``.
    n_full : int
        Vertex count of the full convex hull.
    gap : float
        Largest support gap over the test directions, input units (0 when nothing was dropped).
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    n_full: int
    gap: float


def simplified_hull(
    points: ArrayLike, *, tol: float, max_vertices: int = HULL_MAX_VERTICES
) -> SimplifiedHull:
    """Convex hull of ``points``, simplified by support-gap refinement (see the module docstring).

    Parameters
    ----------
    points : array_like of shape (N, 3)
        Vertices, any length unit.
    tol : float
        Largest support gap allowed, same unit as ``points``; ``0`` keeps the full hull.
    max_vertices : int
        Vertex budget (>= 4); refinement stops there even if the gap is larger.

    Returns
    -------
    SimplifiedHull

    Examples
    --------
    >>> s = simplified_hull(trimesh.creation.icosphere(subdivisions=4).vertices, tol=0.02, max_vertices=200)
    >>> s.n_full, len(s.vertices) < 200, s.gap <= 0.02
    (2562, True, True)
    """
    pts = np.unique(np.asarray(points, dtype=np.float64).reshape(-1, 3), axis=0)
    full = pts[ConvexHull(pts).vertices]
    dirs = fibonacci_directions(N_DIRECTIONS)
    proj = full @ dirs.T  # (K, D)
    h_full = proj.max(axis=0)
    if tol <= 0 or len(full) <= max(4, min(max_vertices, 24)):
        keep = np.arange(len(full))
    else:
        seed = {int(np.argmax(full[:, a] * s)) for a in range(3) for s in (1.0, -1.0)}
        keep = sorted(seed)
        h = proj[keep].max(axis=0)
        while len(keep) < max_vertices:
            gap = h_full - h
            j = int(np.argmax(gap))
            if gap[j] <= tol:
                break
            v = int(np.argmax(proj[:, j]))
            keep.append(v)
            h = np.maximum(h, proj[v])
        keep = np.asarray(keep)
    verts = full[keep]
    gap = float((h_full - (verts @ dirs.T).max(axis=0)).max())
    tri = trimesh.Trimesh(verts, ConvexHull(verts).simplices, process=True)
    trimesh.repair.fix_normals(tri)
    return SimplifiedHull(
        np.asarray(tri.vertices), np.asarray(tri.faces, dtype=np.int64), len(full), max(gap, 0.0)
    )


def hull_obj_text(hull: SimplifiedHull) -> str:
    """Wavefront OBJ text of a hull (vertices and 1-based faces)."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in hull.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in hull.faces]
    return "\n".join(lines) + "\n"
