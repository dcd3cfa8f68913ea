"""Slow NumPy and Python twins of the compiled kernels, and the former start search, for the tests only.

Each twin computes what its kernel computes with array operations (or Python's heapq), so a test can compare
the two on random and real bodies, with numba's JIT on and off:

- the exact method's kernels (landscape/barriers/_exact_kernels.py): ``minimax_reference``,
  ``torus_path_reference``, ``merge_coplanar_reference``, ``arcs_reference``, ``arc_geometry_reference``,
  ``face_margins_reference``, ``face_exits_reference``, ``cell_step_reference``, and the one-arc-at-a-time
  forms of its batched path pieces, ``arc_points_reference`` and ``piece_reference`` (and ``minimax_kernel``,
  the compiled search called as the exact method calls it);
- the rolling kernels (landscape/_minima_kernels.py): ``rest_reference``, ``still_rests_reference``,
  ``first_touch_reference``, ``convex_polygon_reference``, ``polygon_margin_reference`` and the whole
  continuation, ``follow_minimum_reference``;
- the former start search, a pattern search of the CoM height on the pitch-roll grid at every joint step
  (``former_metastable_orientation``), which the exact continuation must match in energy.
"""

from __future__ import annotations

import heapq
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from geometry import Pose, Robot
from geometry.frames import canonical_pitch_roll_deg, up_vector
from landscape import minima
from landscape.barriers import _exact_kernels, exact
from landscape.energy import height_at

REPO = Path(__file__).resolve().parents[2]
PATTERN_STEPS_DEG = (2.0, 1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125)  # the former search's steps
_DIRS = np.array([(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)], dtype=np.float64)


# --------------------------------------------------------------------------------------------- exact method
def minimax_reference(n: int, eu, ev, ew, sources: list[int], goal: NDArray[np.bool_], stop: bool):
    """``landscape.barriers.exact._adjacency`` and the bottleneck search of ``_exact_kernels.minimax_graph``, with
    Python's heapq: (level per node, parent edge per node, first goal settled or -1)."""
    ptr = np.zeros(n + 1, dtype=np.int64)
    ends = np.concatenate([eu, ev])
    order = np.argsort(ends, kind="stable")
    np.cumsum(np.bincount(ends, minlength=n), out=ptr[1:])
    m = len(eu)
    other = np.concatenate([ev, eu])[order].tolist()
    edge = (order % m).tolist()
    wl = np.asarray(ew)[order % m].tolist()
    ptr_l = ptr.tolist()
    goal_l = goal.tolist()
    level = [np.inf] * n
    parent = [-1] * n
    done = [False] * n
    heap = []
    for s in sources:
        level[s] = -np.inf
        heap.append((-np.inf, s))
    heapq.heapify(heap)
    first = -1
    while heap:
        lv, x = heapq.heappop(heap)
        if done[x]:
            continue
        done[x] = True
        if goal_l[x]:
            if first < 0:
                first = x
                if stop:
                    break
            continue
        for q in range(ptr_l[x], ptr_l[x + 1]):
            y = other[q]
            if done[y]:
                continue
            nl = max(lv, wl[q])
            if nl < level[y] or (nl == level[y] and parent[y] < 0 and level[y] != -np.inf):
                level[y] = nl
                parent[y] = edge[q]
                heapq.heappush(heap, (nl, y))
    return np.array(level), np.array(parent, dtype=np.int64), first


def minimax_kernel(n: int, eu, ev, ew, sources: list[int], goal, stop: bool):
    """The compiled search ``_exact_kernels.minimax_graph`` on the graph of edges (eu, ev) weighted ew, called as
    the exact method calls it: what :func:`minimax_reference` is compared with."""
    ptr, other, edge, weight = exact._adjacency(n, eu, ev, ew)
    level, parent, first = _exact_kernels.minimax_graph(
        ptr,
        other,
        edge,
        weight,
        np.asarray(sources, dtype=np.int64),
        np.ascontiguousarray(goal, dtype=np.bool_),
        bool(stop),
    )
    return level, parent, int(first)


def torus_path_reference(us: NDArray[np.float64], start_deg: tuple[float, float]) -> NDArray[np.float64]:
    """``landscape.barriers.exact._torus_path`` (``_exact_kernels.torus_path``) in Python."""
    out = [start_deg]
    for p, r in exact._deg(us).tolist():
        out.append(exact._nearest_rep(p, r, *out[-1]))
    return np.array(out[1:], dtype=np.float64).reshape(-1, 2)


def merge_coplanar_reference(pts, tri, eq, nb, tol_m: float):
    """The face of each triangle, as ``_exact_kernels.merge_coplanar`` finds it, with NumPy and scipy."""
    n_t = len(tri)
    # a triangle joins its neighbour's face when the normals agree and its far vertex lies on that plane
    i = np.repeat(np.arange(n_t), 3)
    j = nb.ravel()
    far = tri[j, :]  # vertices of the neighbour; the one not shared is the far vertex
    shared = (far[:, :, None] == tri[i][:, None, :]).any(axis=2)
    far_v = far[np.arange(len(j)), np.argmin(shared, axis=1)]
    dist = np.abs(np.einsum("ij,ij->i", eq[i, :3], pts[far_v]) + eq[i, 3])
    close = (dist <= tol_m) & (np.linalg.norm(eq[i, :3] - eq[j, :3], axis=1) <= exact.ANGLE_TOL_RAD)
    adj = coo_matrix((np.ones(int(close.sum())), (i[close], j[close])), shape=(n_t, n_t))
    _, tri_face = connected_components(adj, directed=False)
    return tri_face.astype(np.int64)


def arcs_reference(pts: NDArray[np.float64], tri, nb, tri_face, n_f: int):
    """``landscape.barriers.exact._arcs`` (``_exact_kernels.arcs``) in NumPy."""
    k_v = len(pts)
    t_i = np.repeat(np.arange(len(tri)), 3)
    t_j = nb.ravel()
    opp = np.tile(np.arange(3), len(tri))
    e_v = np.stack([tri[t_i, (opp + 1) % 3], tri[t_i, (opp + 2) % 3]], axis=1)
    fa, fb = tri_face[t_i], tri_face[t_j]
    keep = fa < fb
    e_v, fa, fb = e_v[keep], fa[keep], fb[keep]
    pair = fa * n_f + fb
    uniq, inv = np.unique(pair, return_inverse=True)
    n_a = len(uniq)
    arc_faces = np.stack([uniq // n_f, uniq % n_f], axis=1).astype(np.int64)
    # the full segment of collinear sub-edges: the extreme vertices along the first sub-edge's direction
    first = np.zeros(n_a, dtype=np.int64)
    first[inv[::-1]] = np.arange(len(inv))[::-1]
    dirs = pts[e_v[first, 1]] - pts[e_v[first, 0]]
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    proj = np.einsum("ik,ijk->ij", dirs[inv], pts[e_v])  # (E, 2) positions along the edge line, m
    lo_val = np.full(n_a, np.inf)
    hi_val = np.full(n_a, -np.inf)
    np.minimum.at(lo_val, inv, proj.min(axis=1))
    np.maximum.at(hi_val, inv, proj.max(axis=1))
    arc_a = np.zeros(n_a, dtype=np.int64)
    arc_b = np.zeros(n_a, dtype=np.int64)
    flat_v = e_v.ravel()
    flat_p = proj.ravel()
    flat_i = np.repeat(inv, 2)
    is_lo = flat_p == lo_val[flat_i]
    is_hi = flat_p == hi_val[flat_i]
    arc_a[flat_i[is_lo]] = flat_v[is_lo]
    arc_b[flat_i[is_hi]] = flat_v[is_hi]
    pa = np.concatenate([e_v[:, 0], arc_a])
    pb = np.concatenate([e_v[:, 1], arc_b])
    keys = np.minimum(pa, pb) * k_v + np.maximum(pa, pb)
    keys, first_k = np.unique(keys, return_index=True)
    pair_arc = (keys, np.concatenate([inv, np.arange(n_a)])[first_k].astype(np.int64))
    return arc_faces, arc_a, arc_b, pair_arc


def arc_geometry_reference(pts, com, face_up, face_h, arc_faces, arc_a, arc_b):
    """``landscape.barriers.exact._arc_geometry`` (``_exact_kernels.arc_geometry``) in NumPy."""
    u0 = face_up[arc_faces[:, 0]]
    u1 = face_up[arc_faces[:, 1]]
    cos_t = np.clip(np.einsum("ij,ij->i", u0, u1), -1.0, 1.0)
    theta = np.arccos(cos_t)
    t = u1 - cos_t[:, None] * u0
    tn = np.linalg.norm(t, axis=1)
    t = np.where(tn[:, None] > 0, t / np.where(tn > 0, tn, 1.0)[:, None], 0.0)
    seg = pts[arc_b] - pts[arc_a]
    seg_len = np.linalg.norm(seg, axis=1)
    e = seg / seg_len[:, None]
    da = com[None, :] - pts[arc_a]
    foot = np.einsum("ij,ij->i", da, e)
    w = da - foot[:, None] * e
    amp_a = np.einsum("ij,ij->i", w, u0)
    amp_b = np.einsum("ij,ij->i", w, t)
    peak_s = np.arctan2(amp_b, amp_a)
    on_arc = (peak_s > 0) & (peak_s < theta)
    h_ends = np.maximum(face_h[arc_faces[:, 0]], face_h[arc_faces[:, 1]])
    arc_max = np.where(on_arc, np.maximum(np.hypot(amp_a, amp_b), h_ends), h_ends)
    end_up = np.where((face_h[arc_faces[:, 0]] >= face_h[arc_faces[:, 1]])[:, None], u0, u1)
    peak_up = np.where(on_arc[:, None], np.cos(peak_s)[:, None] * u0 + np.sin(peak_s)[:, None] * t, end_up)
    return theta, t, seg_len, foot, w, peak_s, arc_max, peak_up


def face_margins_reference(pts, normal, proj, face_ptr, face_idx, half_face, half_a, half_b, n_f):
    """``landscape.barriers.exact._face_margins`` (``_exact_kernels.face_margins``) in NumPy."""
    centroid = np.zeros((n_f, 3))
    np.add.at(centroid, np.repeat(np.arange(n_f), np.diff(face_ptr)), pts[face_idx])
    centroid /= np.diff(face_ptr)[:, None]
    a, b = pts[half_a], pts[half_b]
    e = (b - a) / np.linalg.norm(b - a, axis=1, keepdims=True)
    m = np.cross(normal[half_face], e)
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    m *= np.sign(np.einsum("ij,ij->i", centroid[half_face] - a, m))[:, None]
    dist = np.einsum("ij,ij->i", proj[half_face] - a, m)
    out = np.full(n_f, np.inf)
    np.minimum.at(out, half_face, dist)
    return out


def face_exits_reference(pts, proj, half_ptr, half_arc, half_a, half_b, arc_faces, margin, tol_m):
    """``landscape.barriers.exact._face_exits`` (``_exact_kernels.face_exits``) in NumPy."""
    n_f = len(half_ptr) - 1
    face = np.repeat(np.arange(n_f), np.diff(half_ptr))
    a, b = pts[half_a], pts[half_b]
    seg = b - a
    seg_len = np.linalg.norm(seg, axis=1)
    s = np.clip(np.einsum("ij,ij->i", proj[face] - a, seg) / seg_len**2, 0.0, 1.0)
    dist = np.linalg.norm(a + s[:, None] * seg - proj[face], axis=1)
    order = np.lexsort((np.arange(len(face)), dist, face))  # nearest per face, ties to the first half-edge
    best = order[half_ptr[:-1]]
    along = s[best] * seg_len[best]
    arc = half_arc[best]
    other = np.where(arc_faces[arc, 0] == np.arange(n_f), arc_faces[arc, 1], arc_faces[arc, 0])
    out = np.where(
        along <= tol_m, -2 - half_a[best], np.where(along >= seg_len[best] - tol_m, -2 - half_b[best], other)
    )
    return np.where(margin > tol_m, -1, out).astype(np.int64)


def cell_step_reference(ex: exact.ExactLandscape, k: int, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """``landscape.barriers.exact._cell_step`` (``_exact_kernels.cell_step``) in NumPy."""
    g = ex._g
    dk = g.d[k]
    grad = dk - (dk @ u) * u
    n = np.linalg.norm(grad)
    if n < 1e-15 * np.linalg.norm(dk):  # balanced on the vertex: fall onto its lowest face
        faces = g.vface_idx[g.vface_ptr[k] : g.vface_ptr[k + 1]]
        f = int(faces[np.argmin(ex.face_height_m[faces])])
        return ex.face_up[f].copy()
    t = -grad / n
    diff = g.d - dk
    a = diff @ u
    b = diff @ t
    s = np.mod(np.arctan2(b, a) - np.pi / 2, 2 * np.pi)
    s[k] = np.inf
    s[s < 1e-12] = np.inf
    s_end = np.pi - np.arccos(np.clip(dk @ u / np.linalg.norm(dk), -1.0, 1.0))
    step = min(float(s.min()), s_end)
    out = np.cos(step) * u + np.sin(step) * t
    return out / np.linalg.norm(out)


def arc_points_reference(ex: exact.ExactLandscape, arc: int, s0: float, s1: float) -> NDArray[np.float64]:
    """Up-directions along an arc from s0 to s1 (``np.linspace``, at most ``PATH_STEP_DEG`` apart):
    ``exact._pieces_points`` one piece at a time, with the piece's first point."""
    g = ex._g
    n = max(2, int(np.ceil(abs(s1 - s0) / np.deg2rad(exact.PATH_STEP_DEG))) + 1)
    s = np.linspace(s0, s1, n)
    u0 = ex.face_up[ex.arc_faces[arc, 0]]
    return np.cos(s)[:, None] * u0 + np.sin(s)[:, None] * g.arc_t[arc]


def piece_reference(ex: exact.ExactLandscape, arc: int, forward: bool) -> tuple:
    """A whole arc, forward (face 0 -> face 1) or back: ``exact._whole_pieces`` one arc at a time."""
    theta = float(ex._g.arc_theta[arc])
    return exact._pieces(ex, arc, 0.0 if forward else theta, theta if forward else 0.0)[0]


# --------------------------------------------------------------------------------------------- rolling
def _cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """a x b for 3-vectors (np.cross costs ten times more on single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _basis(u: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Two unit vectors spanning the plane normal to u (deterministic)."""
    a = np.zeros(3)
    a[int(np.argmin(np.abs(u)))] = 1.0
    e1 = _cross(u, a)
    e1 /= np.linalg.norm(e1)
    return e1, _cross(u, e1)


def first_touch_reference(
    d: NDArray[np.float64], k: int, u: NDArray[np.float64], t: NDArray[np.float64]
) -> float:
    """Smallest rotation s > 0 of u toward t (about a line through point k) at which another point is lowest.

    Point j reaches point k's height where ``(d_j - d_k).(cos s u + sin s t) = 0``.
    """
    diff = d - d[k]
    s = np.mod(np.arctan2(diff @ t, diff @ u) - np.pi / 2, 2 * np.pi)
    s[s < 1e-12] = np.inf
    return float(s.min())


def _rotate(u: NDArray[np.float64], t: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    out = np.cos(s) * u + np.sin(s) * t
    return out / np.linalg.norm(out)


def convex_polygon_reference(xy: NDArray[np.float64]) -> NDArray[np.int64]:
    """Counter-clockwise convex hull of 2-D points (monotone chain), indices; collinear points dropped."""
    order = np.lexsort((xy[:, 1], xy[:, 0]))

    def half(idx):
        out: list[int] = []
        for i in idx:
            while len(out) >= 2:
                o, a = xy[out[-2]], xy[out[-1]]
                if (a[0] - o[0]) * (xy[i][1] - o[1]) - (a[1] - o[1]) * (xy[i][0] - o[0]) > 0:
                    break
                out.pop()
            out.append(int(i))
        return out

    lower, upper = half(order), half(order[::-1])
    return np.array(lower[:-1] + upper[:-1], dtype=np.int64)


def _contact(d: NDArray[np.float64], u: NDArray[np.float64], tol_m: float):
    """The lowest points at u and their shape on the ground.

    Returns ``(active, xy, poly)``: indices of the points within ``tol_m`` of the lowest, their positions in the
    ground plane relative to the CoM's projection (m), and the counter-clockwise hull of those positions as
    indices into ``active`` (1 point, 2 for a segment, >= 3 for a polygon).
    """
    hv = d @ u
    active = np.flatnonzero(hv >= hv.max() - tol_m)
    e1, e2 = _basis(u)
    xy = -np.stack([d[active] @ e1, d[active] @ e2], axis=1)
    if len(active) == 1:
        return active, xy, np.zeros(1, dtype=np.int64)
    i = int(np.argmin(xy[:, 0] + xy[:, 1] * 1e-3))
    r = xy - xy[i]
    j = int(np.argmax(r[:, 0] ** 2 + r[:, 1] ** 2))
    length = float(np.hypot(*r[j]))
    if length <= tol_m:  # one point
        return active, xy, np.array([i], dtype=np.int64)
    along = r @ r[j] / length
    off = (r[:, 0] * r[j, 1] - r[:, 1] * r[j, 0]) / length
    if np.abs(off).max() <= tol_m:  # collinear: a segment between the extremes
        return active, xy, np.array([int(np.argmin(along)), int(np.argmax(along))], dtype=np.int64)
    return active, xy, convex_polygon_reference(xy)


def polygon_margin_reference(xy: NDArray[np.float64], poly: NDArray[np.int64]) -> tuple[float, int, float]:
    """Signed distance of the origin inside a CCW polygon (m), the nearest edge, and where along it (0..1)."""
    a = xy[poly]
    b = np.concatenate([a[1:], a[:1]])
    e = b - a
    length = np.linalg.norm(e, axis=1)
    inside = (e[:, 0] * (-a[:, 1]) - e[:, 1] * (-a[:, 0])) / length  # cross(e, 0 - a) / |e|
    s = np.clip(-np.einsum("ij,ij->i", a, e) / length**2, 0.0, 1.0)
    dist = np.linalg.norm(a + s[:, None] * e, axis=1)
    k = int(np.lexsort((np.arange(len(poly)), dist))[0])
    return float(inside.min()), k, float(s[k])


def _roll_step(d, u, tol_m):
    """One quasi-static move from u. Returns (new u, None) or (u, face point indices) when at rest."""
    active, xy, poly = _contact(d, u, tol_m)
    if len(poly) >= 3:
        margin, k, s = polygon_margin_reference(xy, poly)
        if margin > tol_m:
            return u, active[poly]
        length = np.linalg.norm(xy[poly[(k + 1) % len(poly)]] - xy[poly[k]])
        if s * length <= tol_m:
            return _pivot(d, int(active[poly[k]]), u), None
        if (1.0 - s) * length <= tol_m:
            return _pivot(d, int(active[poly[(k + 1) % len(poly)]]), u), None
        return _roll_edge(d, int(active[poly[k]]), int(active[poly[(k + 1) % len(poly)]]), u, tol_m), None
    if len(poly) == 2:
        return _roll_edge(d, int(active[poly[0]]), int(active[poly[1]]), u, tol_m), None
    return _pivot(d, int(active[poly[0]]), u), None


def _pivot(d, k, u):
    """Tip about point k: steepest descent of d_k.u, to where another point touches (landscape/barriers/exact.py)."""
    dk = d[k]
    grad = dk - (dk @ u) * u
    n = np.linalg.norm(grad)
    if n < 1e-15 * np.linalg.norm(dk):  # balanced on the point: fall to a fixed side
        t = _basis(u)[0]
    else:
        t = -grad / n
    s_end = np.pi - np.arccos(np.clip(dk @ u / np.linalg.norm(dk), -1.0, 1.0))
    return _rotate(u, t, min(first_touch_reference(d, k, u, t), s_end))


def _roll_edge(d, a, b, u, tol_m):
    """Roll about the line through points a and b (both lowest), or pivot on an end the CoM lies beyond."""
    e = d[a] - d[b]  # p_b - p_a
    length = np.linalg.norm(e)
    e = e / length
    foot = d[a] @ e  # CoM foot on the line, m from a toward b
    if foot < -tol_m:
        return _pivot(d, a, u)
    if foot > length + tol_m:
        return _pivot(d, b, u)
    w = d[a] - foot * e  # from the line to the CoM
    t = _cross(e, u)
    t /= np.linalg.norm(t)
    if w @ t > 0:
        t = -t
    elif w @ t == 0.0:  # balanced on the edge: fall to the side of the lower index
        t = t if a < b else -t
    return _rotate(u, t, first_touch_reference(d, a, u, t))


def rest_reference(d, u, tol_m):
    """NumPy reference of ``landscape.minima.rest_face`` (and of ``_minima_kernels.rest``) on the vectors d = c - p."""
    for _ in range(minima._MAX_MOVES):
        u, face = _roll_step(d, u, tol_m)
        if face is not None:
            return _face_up(d, face, u), face
    raise RuntimeError(minima.NOT_SETTLED)


def _face_up(d, face, u_hint):
    """The up-direction resting on the plane through a face's corners (the one nearest u_hint)."""
    q = d[face] - d[face[0]]
    q2 = np.concatenate([q[1:], q[:1]])
    n = np.array(
        [
            q[:, 1] @ q2[:, 2] - q[:, 2] @ q2[:, 1],
            q[:, 2] @ q2[:, 0] - q[:, 0] @ q2[:, 2],
            q[:, 0] @ q2[:, 1] - q[:, 1] @ q2[:, 0],
        ]
    )
    n /= np.linalg.norm(n)
    return n if n @ u_hint >= 0 else -n


def still_rests_reference(d, face, u_prev, tol_m):
    """The up-direction resting on ``face`` if it is still a strict minimum reached from u_prev, else None.

    The face (the same points, moved with their links) must bound the hull from below, hold the CoM's
    projection strictly inside, and the body at the previous orientation must stand on one of its points.
    NumPy reference of ``_minima_kernels.still_rests``.
    """
    u = _face_up(d, face, u_prev)
    hv = d @ u
    h = hv[face]
    if h.max() - h.min() > tol_m:  # no longer flat
        return None, None
    top = hv.max()
    if top > h.max() + tol_m:  # another point pokes below the face's plane
        return None, None
    active, xy, poly = _contact(d, u, tol_m)
    if len(poly) < 3 or polygon_margin_reference(xy, poly)[0] <= tol_m:
        return None, None
    face = active[poly]
    lowest = np.flatnonzero(d @ u_prev >= (d @ u_prev).max() - tol_m)
    if not np.isin(lowest, face).any():
        return None, None
    return u, face


def follow_minimum_reference(
    robot: Robot, path_deg: list[tuple[float, float]], *, pitch_deg: float = 0.0, roll_deg: float = 0.0
) -> list[tuple[float, float]]:
    """NumPy reference of ``landscape.minima.follow_minimum`` (the code before the kernels): same moves, same
    tolerances, one NumPy call per test."""
    if not path_deg:
        return []
    bodies = minima._PathBodies(robot, path_deg)
    u = up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    face = None
    out = []
    for i in range(len(path_deg)):
        d = bodies.d_at(i)
        tol_m = bodies.tol_at(d)
        new = (None, None) if face is None else still_rests_reference(d, face, u, tol_m)
        if new[0] is None:
            new = rest_reference(d, u, tol_m)
        u, face = new
        out.append(minima._deg(u))
    return out


# --------------------------------------------------------------------------------------------- former start search
def pattern_descent(pose: Pose, pitch_deg: float, roll_deg: float) -> tuple[float, float]:
    """The former start search: pattern search of h to 0.03 deg.

    Moves to the lowest of 8 neighbours at a shrinking step from 2 deg, so it can jump a ridge narrower
    than the step.
    """
    p, r = float(pitch_deg), float(roll_deg)
    h = float(height_at(pose, p, r))
    for step in PATTERN_STEPS_DEG:
        while True:
            cand = np.array([p, r]) + step * _DIRS
            hc = height_at(pose, cand[:, 0], cand[:, 1])
            k = int(np.argmin(hc))
            if hc[k] < h - 1e-15:
                p, r, h = float(cand[k, 0]), float(cand[k, 1]), float(hc[k])
            else:
                break
    return canonical_pitch_roll_deg(p, r)


def follow_minimum_grid(
    robot: Robot, path_deg: list[tuple[float, float]], *, pitch_deg: float = 0.0, roll_deg: float = 0.0
) -> list[tuple[float, float]]:
    """The former continuation: pose the robot and pattern-search at every step."""
    out = []
    p, r = pitch_deg, roll_deg
    for tw, tl in path_deg:
        p, r = pattern_descent(robot.pose(tw, tl), p, r)
        out.append((p, r))
    return out


def former_metastable_orientation(
    robot: Robot, theta_w_deg: float, theta_l_deg: float
) -> tuple[float, float]:
    """:func:`landscape.minima.metastable_orientation` by the former search: pattern search at every step."""
    if not robot.has_joints:
        return pattern_descent(robot.pose(), 0.0, 0.0)
    return follow_minimum_grid(robot, minima.opening_path(theta_w_deg, theta_l_deg))[-1]


def run_without_jit(code: str, *, timeout_s: float = 300.0) -> str:
    """Run Python ``code`` in a fresh interpreter with numba's JIT off (``NUMBA_DISABLE_JIT=1``, so the kernels
    run as the Python they are written in) and the repository on its path; its standard output, stripped.

    Raises
    ------
    AssertionError
        With the interpreter's standard error, if the code fails.
    """
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=str(REPO))
    res = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=timeout_s
    )
    assert res.returncode == 0, res.stderr
    return res.stdout.strip()
