"""Convex hulls of point sets, with the vertex adjacency the landscape kernels walk on."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull, QhullError

from .errors import GeometryError


@dataclass(frozen=True)
class Hull:
    """Convex hull of a point set.

    Attributes
    ----------
    vertices_m : ndarray of shape (K, 3)
        Hull vertices, m.
    neighbor_ptr, neighbor_idx : ndarray of int64
        Vertex adjacency in CSR form: the neighbours of vertex ``k`` are
        ``neighbor_idx[neighbor_ptr[k]:neighbor_ptr[k + 1]]``. For a degenerate (flat or collinear) point
        set every vertex is joined to every other, which keeps hill climbing exact.
    simplices : ndarray of shape (F, 3) of int64
        Triangles of the hull surface (indices into ``vertices_m``); empty for a degenerate set.
    equations : ndarray of shape (F, 4) or None
        Qhull's plane of each triangle (outward unit normal, offset: ``n.x + offset <= 0`` inside), m; None
        for a degenerate set.
    neighbors : ndarray of shape (F, 3) of int64 or None
        Qhull's neighbouring triangle opposite each vertex of each triangle; None for a degenerate set.
        (The exact barrier method builds its faces from these; its choice between equal saddles does not
        depend on Qhull's numbering.)
    """

    vertices_m: NDArray[np.float64]
    neighbor_ptr: NDArray[np.int64]
    neighbor_idx: NDArray[np.int64]
    simplices: NDArray[np.int64]
    equations: NDArray[np.float64] | None = None
    neighbors: NDArray[np.int64] | None = None


def _csr(n: int, edges: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Symmetric CSR adjacency of n vertices from undirected edges (duplicates merged, neighbours sorted)."""
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    # each directed pair (a, b) as the one integer a * n + b: a 1-D unique sorts them as (a, b) rows would
    key = _sorted_unique(np.concatenate([edges[:, 0] * n + edges[:, 1], edges[:, 1] * n + edges[:, 0]]))
    counts = np.bincount(key // n, minlength=n)
    ptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(counts, out=ptr[1:])
    return ptr, (key % n).astype(np.int64)


def _sorted_unique(x: NDArray[np.int64]) -> NDArray[np.int64]:
    """``np.unique`` of integers by one sort (NumPy 2's hashing ``np.unique`` is slower on these sizes)."""
    x = np.sort(x)
    if len(x) < 2:
        return x
    keep = np.empty(len(x), dtype=bool)
    keep[0] = True
    np.not_equal(x[1:], x[:-1], out=keep[1:])
    return x[keep]


def _unique_rows(pts: NDArray[np.float64]) -> NDArray[np.float64]:
    """``np.unique(pts, axis=0)`` (rows sorted by x, then y, then z; equal rows once), by one lexsort."""
    if len(pts) < 2:
        return pts.copy()
    s = pts[np.lexsort((pts[:, 2], pts[:, 1], pts[:, 0]))]
    keep = np.ones(len(s), dtype=bool)
    keep[1:] = (s[1:] != s[:-1]).any(axis=1)
    return s[keep]


def convex_hull(points_m: ArrayLike, *, merge_tol_m: float | None = None) -> Hull:
    """Convex hull of points, robust to duplicates and flat sets.

    Parameters
    ----------
    points_m : array_like of shape (N, 3)
        Points, m. Must be finite.
    merge_tol_m : float, optional
        Merge facets closer than this to coplanar, m (Qhull's centrum pre-merge, option ``C-``): a point within
        about this distance of the hull of the others is no vertex, and the triangles of one merged facet share
        one plane (``equations``). The result is convex by at least this margin at every edge, so rounding noise
        below it (a CAD export's finely triangulated flat faces, say) leaves no sliver facets or kinked edges.
        None (default) keeps Qhull's roundoff-only merging: every point that is a vertex in floating point stays
        one.

    Returns
    -------
    Hull

    Raises
    ------
    GeometryError
        If a point is not finite or there are no points.

    Examples
    --------
    >>> import trimesh
    >>> h = convex_hull(trimesh.creation.box(extents=(1, 1, 1)).vertices)
    >>> len(h.vertices_m), int(np.diff(h.neighbor_ptr).min())
    (8, 3)

    A box whose faces carry 1e-12 m of noise keeps every noisy point as a vertex unless merged:

    >>> box = trimesh.creation.box(extents=(0.4, 0.3, 0.02)).subdivide().subdivide()
    >>> noisy = box.vertices + np.random.default_rng(0).uniform(-1e-12, 1e-12, box.vertices.shape)
    >>> len(convex_hull(noisy).vertices_m) > 8, len(convex_hull(noisy, merge_tol_m=1e-10).vertices_m)
    (True, 8)
    """
    pts = np.asarray(points_m, dtype=np.float64).reshape(-1, 3)
    if len(pts) == 0:
        raise GeometryError("cannot take the convex hull of no points; the robot has no geometry")
    bad = ~np.isfinite(pts).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise GeometryError(f"geometry has a non-finite vertex {pts[i].tolist()} at index {i}; fix the mesh")
    if merge_tol_m is not None and not (np.isfinite(merge_tol_m) and merge_tol_m > 0):
        raise GeometryError(f"merge_tol_m must be a positive length in m; got {merge_tol_m!r}")
    # Never pass Qhull's 'Qbb' here: it rescales the last coordinate of the caller's array in place
    options = None if merge_tol_m is None else f"C-{float(merge_tol_m)!r}"
    try:  # duplicates are fine: all but one of equal points are left inside
        qh = ConvexHull(pts, qhull_options=options)
    except (QhullError, ValueError):
        # flat, collinear or too few points: keep them all (once each) and join every pair
        pts = _unique_rows(pts)
        n = len(pts)
        ii, jj = np.triu_indices(n, 1)
        ptr, idx = _csr(n, np.stack([ii, jj], axis=1).astype(np.int64))
        return Hull(pts, ptr, idx, np.zeros((0, 3), dtype=np.int64))
    used = _sorted_unique(np.asarray(qh.simplices, dtype=np.int64).ravel())  # = qh.vertices
    # vertices sorted by x, then y, then z, whatever the input order (sorting only the vertices is cheaper)
    keep = used[np.lexsort((pts[used, 2], pts[used, 1], pts[used, 0]))]
    remap = np.full(len(pts), -1, dtype=np.int64)
    remap[keep] = np.arange(len(keep))
    simp = remap[np.asarray(qh.simplices, dtype=np.int64)]
    edges = np.concatenate([simp[:, [0, 1]], simp[:, [1, 2]], simp[:, [2, 0]]])
    ptr, idx = _csr(len(keep), edges)
    eq = np.ascontiguousarray(qh.equations, dtype=np.float64)
    nb = np.ascontiguousarray(qh.neighbors, dtype=np.int64)
    return Hull(pts[keep], ptr, idx, simp, eq, nb)


def depth_inside_m(hull: Hull, point_m: ArrayLike) -> float:
    """Distance of ``point_m`` inside the hull's surface, m: positive inside, negative outside (the largest
    distance past any face plane); ``-inf`` for a flat hull, which has no inside.

    Examples
    --------
    >>> import trimesh
    >>> h = convex_hull(trimesh.creation.box(extents=(2, 2, 2)).vertices)
    >>> depth_inside_m(h, [0.0, 0.0, 0.5]), depth_inside_m(h, [0.0, 0.0, 3.0])
    (0.5, -2.0)
    """
    if not len(hull.simplices):
        return -np.inf
    p = np.asarray(point_m, dtype=np.float64)
    if hull.equations is not None:  # Qhull's outward unit normals and offsets
        return float(np.min(-(hull.equations[:, :3] @ p + hull.equations[:, 3])))
    v = hull.vertices_m
    p0, p1, p2 = (v[hull.simplices[:, k]] for k in range(3))
    n = np.cross(p1 - p0, p2 - p0)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    # orient every face normal outward: away from the vertex centroid, which is inside
    flip = np.einsum("ij,ij->i", n, p0 - v.mean(axis=0)) < 0
    n[flip] *= -1.0
    return float(np.min(np.einsum("ij,ij->i", n, p0 - p)))
