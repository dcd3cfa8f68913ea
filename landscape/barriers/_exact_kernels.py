"""Compiled kernels of :mod:`landscape.barriers.exact`: the face-edge graph of the hull (coplanar facets
merged, arcs, their geometry, face margins and where each face tips), rolling down inside vertex cells, the
bottleneck search on the face graph, and the continuous torus path through its points.

Private: inputs are trusted (C-contiguous float64, radians unless a docstring says degrees) and nothing is
validated here; the public wrappers convert and check. Each kernel does its NumPy or Python reference's
arithmetic (tests/landscape/_references.py), operation for operation, so the results are the same numbers.
"""

from __future__ import annotations

import numba
import numpy as np

from ._flood_kernels import _pop, _push


# ---------------------------------------------------------------------------- searches
@numba.njit(cache=True)
def minimax_graph(ptr, other, edge, weight, sources, goal, stop):
    """Bottleneck Dijkstra on an undirected graph in CSR form (``ptr``, neighbour ``other``, ``edge`` index and
    ``weight`` of each adjacency): the lowest possible maximum edge weight from the sources.

    Goal nodes are settled but never expanded; with ``stop`` the search ends at the first goal settled. The heap
    orders (level, node) as Python tuples do, so the result equals the reference search with Python's heapq.
    Returns (level per node, parent edge per node, first goal settled or -1).
    """
    n = ptr.shape[0] - 1
    level = np.full(n, np.inf)
    parent = np.full(n, -1, dtype=np.int64)
    done = np.zeros(n, dtype=np.bool_)
    cap = other.shape[0] + sources.shape[0] + 1
    he = np.zeros(cap)
    hi = np.zeros(cap, dtype=np.int64)
    size = 0
    for k in range(sources.shape[0]):
        s = sources[k]
        level[s] = -np.inf
        size = _push(he, hi, size, -np.inf, s)
    first = -1
    while size > 0:
        lv, x, size = _pop(he, hi, size)
        if done[x]:
            continue
        done[x] = True
        if goal[x]:
            if first < 0:
                first = x
                if stop:
                    break
            continue
        for q in range(ptr[x], ptr[x + 1]):
            y = other[q]
            if done[y]:
                continue
            w = weight[q]
            nl = lv if lv >= w else w
            if nl < level[y] or (nl == level[y] and parent[y] < 0 and level[y] != -np.inf):
                level[y] = nl
                parent[y] = edge[q]
                size = _push(he, hi, size, nl, y)
    return level, parent, first


@numba.njit(cache=True)
def _wrap180(x):
    return (x + 180.0) % 360.0 - 180.0


@numba.njit(cache=True)
def torus_path(pr, p_start, r_start):
    """A continuous torus path through canonical (pitch, roll) points (M, 2), degrees: each point's
    representative ((p, r) or (180 - p, r + 180), shifted by whole turns) nearest the previous one, in the larger
    of the pitch and roll differences (ties keep (p, r); at a pole the roll is the previous one's)."""
    m = pr.shape[0]
    out = np.zeros((m, 2))
    p_ref = p_start
    r_ref = r_start
    for k in range(m):
        p = pr[k, 0]
        r = pr[k, 1]
        pole = abs(abs(p) - 90.0) < 1e-9
        p1 = p_ref + _wrap180(p - p_ref)
        r1 = r_ref if pole else r_ref + _wrap180(r - r_ref)
        p2 = p_ref + _wrap180(180.0 - p - p_ref)
        r2 = r_ref if pole else r_ref + _wrap180(r + 180.0 - r_ref)
        if max(abs(p2 - p_ref), abs(r2 - r_ref)) < max(abs(p1 - p_ref), abs(r1 - r_ref)) - 1e-12:
            p_ref, r_ref = p2, r2
        else:
            p_ref, r_ref = p1, r1
        out[k, 0] = p_ref
        out[k, 1] = r_ref
    return out


# ---------------------------------------------------------------------------- the face-edge graph
@numba.njit(cache=True)
def _norm3_seq(x0, x1, x2):
    """|x| as ``np.linalg.norm(axis=1)`` computes it: sqrt((x0^2 + x1^2) + x2^2)."""
    return np.sqrt(x0 * x0 + x1 * x1 + x2 * x2)


@numba.njit(cache=True)
def _dot3_einsum(a0, a1, a2, b0, b1, b2):
    """a.b as ``np.einsum("ij,ij->i", a, b)`` computes it for three columns: (a0 b0 + a2 b2) + a1 b1."""
    return (a0 * b0 + a2 * b2) + a1 * b1


@numba.njit(cache=True)
def _edge_unit(pts, a, b):
    """Unit direction from vertex a to vertex b and their distance, as NumPy's ``seg / norm(seg)`` computes
    them: (e0, e1, e2, length)."""
    d0 = pts[b, 0] - pts[a, 0]
    d1 = pts[b, 1] - pts[a, 1]
    d2 = pts[b, 2] - pts[a, 2]
    ln = _norm3_seq(d0, d1, d2)
    return d0 / ln, d1 / ln, d2 / ln, ln


@numba.njit(cache=True)
def arc_geometry(pts, com, face_up, face_h, arc_faces, arc_a, arc_b):
    """Each edge arc between two face up-directions (``arc_faces``; edge from vertex ``arc_a`` to ``arc_b``):
    its angle theta, unit tangent t at the first face, edge length, the foot of the perpendicular from the CoM
    along the edge (m from ``arc_a``), that perpendicular w, where the CoM height w.u peaks along the arc
    (angle from the first face, may lie outside [0, theta]), the highest CoM height on the arc, m, and where
    it is reached. The arithmetic of the NumPy reference, operation for operation (its trigonometric
    functions may differ in the last bit)."""
    n_a = arc_faces.shape[0]
    theta = np.zeros(n_a)
    t = np.zeros((n_a, 3))
    seg_len = np.zeros(n_a)
    foot = np.zeros(n_a)
    w = np.zeros((n_a, 3))
    peak_s = np.zeros(n_a)
    arc_max = np.zeros(n_a)
    peak_up = np.zeros((n_a, 3))
    for k in range(n_a):
        f0 = arc_faces[k, 0]
        f1 = arc_faces[k, 1]
        u0 = face_up[f0]
        u1 = face_up[f1]
        c = _dot3_einsum(u0[0], u0[1], u0[2], u1[0], u1[1], u1[2])
        c = min(max(c, -1.0), 1.0)
        theta[k] = np.arccos(c)
        t0 = u1[0] - c * u0[0]
        t1 = u1[1] - c * u0[1]
        t2 = u1[2] - c * u0[2]
        tn = _norm3_seq(t0, t1, t2)
        if tn > 0:
            t[k, 0] = t0 / tn
            t[k, 1] = t1 / tn
            t[k, 2] = t2 / tn
        a = arc_a[k]
        e0, e1, e2, ln = _edge_unit(pts, a, arc_b[k])
        seg_len[k] = ln
        d0 = com[0] - pts[a, 0]
        d1 = com[1] - pts[a, 1]
        d2 = com[2] - pts[a, 2]
        ft = _dot3_einsum(d0, d1, d2, e0, e1, e2)
        foot[k] = ft
        w0 = d0 - ft * e0
        w1 = d1 - ft * e1
        w2 = d2 - ft * e2
        w[k, 0] = w0
        w[k, 1] = w1
        w[k, 2] = w2
        amp_a = _dot3_einsum(w0, w1, w2, u0[0], u0[1], u0[2])
        amp_b = _dot3_einsum(w0, w1, w2, t[k, 0], t[k, 1], t[k, 2])
        pk = np.arctan2(amp_b, amp_a)
        peak_s[k] = pk
        h_ends = max(face_h[f0], face_h[f1])
        if pk > 0 and pk < theta[k]:
            arc_max[k] = max(np.hypot(amp_a, amp_b), h_ends)
            cp = np.cos(pk)
            sp = np.sin(pk)
            for j in range(3):
                peak_up[k, j] = cp * u0[j] + sp * t[k, j]
        else:
            arc_max[k] = h_ends
            for j in range(3):
                peak_up[k, j] = u0[j] if face_h[f0] >= face_h[f1] else u1[j]
    return theta, t, seg_len, foot, w, peak_s, arc_max, peak_up


@numba.njit(cache=True)
def face_margins(pts, normal, proj, face_ptr, face_idx, half_ptr, half_a, half_b):
    """Signed distance of each face's CoM projection ``proj`` (F, 3) inside its boundary, m: the minimum over
    the face's boundary half-edges (``half_ptr`` CSR, end vertices ``half_a``, ``half_b``) of the distance to the
    edge line, positive toward the face's vertex centroid (``face_ptr``/``face_idx`` CSR). The arithmetic of
    the NumPy reference, operation for operation."""
    n_f = face_ptr.shape[0] - 1
    out = np.full(n_f, np.inf)
    for f in range(n_f):
        c0 = 0.0
        c1 = 0.0
        c2 = 0.0
        for q in range(face_ptr[f], face_ptr[f + 1]):
            v = face_idx[q]
            c0 += pts[v, 0]
            c1 += pts[v, 1]
            c2 += pts[v, 2]
        cnt = float(face_ptr[f + 1] - face_ptr[f])
        c0 /= cnt
        c1 /= cnt
        c2 /= cnt
        n0 = normal[f, 0]
        n1 = normal[f, 1]
        n2 = normal[f, 2]
        best = np.inf
        for h in range(half_ptr[f], half_ptr[f + 1]):
            a = half_a[h]
            e0, e1, e2, _ = _edge_unit(pts, a, half_b[h])
            m0 = n1 * e2 - n2 * e1
            m1 = n2 * e0 - n0 * e2
            m2 = n0 * e1 - n1 * e0
            lm = _norm3_seq(m0, m1, m2)
            m0 /= lm
            m1 /= lm
            m2 /= lm
            side = _dot3_einsum(c0 - pts[a, 0], c1 - pts[a, 1], c2 - pts[a, 2], m0, m1, m2)
            sg = np.sign(side)
            m0 *= sg
            m1 *= sg
            m2 *= sg
            dist = _dot3_einsum(
                proj[f, 0] - pts[a, 0], proj[f, 1] - pts[a, 1], proj[f, 2] - pts[a, 2], m0, m1, m2
            )
            if best == best and (dist != dist or dist < best):  # np.minimum: NaN wins
                best = dist
        out[f] = best
    return out


@numba.njit(cache=True)
def face_exits(pts, proj, half_ptr, half_arc, half_a, half_b, arc_faces, margin, tol_m):
    """Where each face tips when the CoM's projection ``proj`` lies outside it: the boundary half-edge nearest
    the projection (ties to the first), giving -1 (the face is a minimum: ``margin > tol_m``), the face across
    that edge, or -2 - k for pivoting on its end vertex k when the nearest point is within ``tol_m`` of it.
    The arithmetic of the NumPy reference, operation for operation."""
    n_f = half_ptr.shape[0] - 1
    out = np.full(n_f, -1, dtype=np.int64)
    for f in range(n_f):
        best = -1
        best_d = np.inf
        best_s = 0.0
        best_len = 0.0
        for h in range(half_ptr[f], half_ptr[f + 1]):
            a = half_a[h]
            b = half_b[h]
            s0 = pts[b, 0] - pts[a, 0]
            s1 = pts[b, 1] - pts[a, 1]
            s2 = pts[b, 2] - pts[a, 2]
            ln = _norm3_seq(s0, s1, s2)
            num = _dot3_einsum(
                proj[f, 0] - pts[a, 0], proj[f, 1] - pts[a, 1], proj[f, 2] - pts[a, 2], s0, s1, s2
            )
            s = num / (ln * ln)
            if s != s:
                pass
            elif s < 0.0:
                s = 0.0
            elif s > 1.0:
                s = 1.0
            x0 = pts[a, 0] + s * s0 - proj[f, 0]
            x1 = pts[a, 1] + s * s1 - proj[f, 1]
            x2 = pts[a, 2] + s * s2 - proj[f, 2]
            dist = _norm3_seq(x0, x1, x2)
            # np.lexsort order: smaller first, NaN last, ties to the first half-edge
            if best < 0 or dist < best_d or (best_d != best_d and dist == dist):
                best = h
                best_d = dist
                best_s = s
                best_len = ln
        if best < 0 or margin[f] > tol_m:
            continue
        along = best_s * best_len
        if along <= tol_m:
            out[f] = -2 - half_a[best]
        elif along >= best_len - tol_m:
            out[f] = -2 - half_b[best]
        else:
            arc = half_arc[best]
            out[f] = arc_faces[arc, 1] if arc_faces[arc, 0] == f else arc_faces[arc, 0]
    return out


# ---------------------------------------------------------------------------- rolling down
@numba.njit(cache=True)
def cell_step(d, k, u):
    """Steepest descent of h(u) = max_j d_j.u inside vertex k's cell: along the great circle from ``u`` away from
    ``d[k]`` to the cell's boundary (where another vertex becomes as low) or to the antipode of ``d[k]``.

    Returns (the new unit up-direction (3,), True), or (``u``, False) when ``u`` is balanced on the vertex
    (parallel to ``d[k]``). ``cell_step_reference`` is the NumPy version.
    """
    dk0 = d[k, 0]
    dk1 = d[k, 1]
    dk2 = d[k, 2]
    u0 = u[0]
    u1 = u[1]
    u2 = u[2]
    du = dk0 * u0 + dk1 * u1 + dk2 * u2
    g0 = dk0 - du * u0
    g1 = dk1 - du * u1
    g2 = dk2 - du * u2
    n = np.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    ndk = np.sqrt(dk0 * dk0 + dk1 * dk1 + dk2 * dk2)
    out = np.zeros(3)
    if n < 1e-15 * ndk:
        out[0] = u0
        out[1] = u1
        out[2] = u2
        return out, False
    t0 = -g0 / n
    t1 = -g1 / n
    t2 = -g2 / n
    best = np.inf
    two_pi = 2.0 * np.pi
    for j in range(d.shape[0]):
        if j == k:
            continue
        x0 = d[j, 0] - dk0
        x1 = d[j, 1] - dk1
        x2 = d[j, 2] - dk2
        a = x0 * u0 + x1 * u1 + x2 * u2
        b = x0 * t0 + x1 * t1 + x2 * t2
        s = (np.arctan2(b, a) - np.pi / 2) % two_pi
        if s >= 1e-12 and s < best:
            best = s
    c = du / ndk
    c = -1.0 if c < -1.0 else (1.0 if c > 1.0 else c)
    s_end = np.pi - np.arccos(c)
    step = s_end if s_end < best else best
    cs = np.cos(step)
    sn = np.sin(step)
    out[0] = cs * u0 + sn * t0
    out[1] = cs * u1 + sn * t1
    out[2] = cs * u2 + sn * t2
    m = np.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2])
    out[0] /= m
    out[1] /= m
    out[2] /= m
    return out, True


@numba.njit(cache=True)
def roll_in_cells(d, u, tol, max_steps):
    """Quasi-static rolling while one hull vertex alone is lowest: :func:`cell_step` after cell_step.

    At each step ``hv = d @ u``; while exactly one vertex lies within ``tol`` of the top, step inside its cell.
    Returns (u, top, first, second, n_active, steps): the up-direction reached, the top vertex, the first two
    active vertices in index order, how many are active (1 with ``steps < max_steps``: balanced on ``top``,
    cell_step did not move) and the steps taken. landscape.barriers.exact's ``_descend_from`` is the caller.
    """
    k_v = d.shape[0]
    hv = np.empty(k_v)
    for step in range(max_steps):
        top = 0
        for j in range(k_v):
            hv[j] = d[j, 0] * u[0] + d[j, 1] * u[1] + d[j, 2] * u[2]
            if hv[j] > hv[top]:
                top = j
        lim = hv[top] - tol
        n_act = 0
        first = -1
        second = -1
        for j in range(k_v):
            if hv[j] >= lim:
                if n_act == 0:
                    first = j
                elif n_act == 1:
                    second = j
                n_act += 1
        if n_act != 1:
            return u, top, first, second, n_act, step
        out, moved = cell_step(d, top, u)
        if not moved:
            return u, top, first, second, 1, step
        u = out
    return u, -1, -1, -1, 0, max_steps


# ---------------------------------------------------------------------------- construction
@numba.njit(cache=True)
def arcs(pts, tri, nb, tri_face, n_f):
    """The face-edge graph's arcs, as the NumPy reference ``arcs_reference`` builds them (the same numbers).

    Returns (arc_faces (A, 2), arc_a (A,), arc_b (A,), pair keys (P,), pair arcs (P,)).
    """
    n_t = tri.shape[0]
    k_v = pts.shape[0]
    # boundary edges between different faces, each once (fa < fb), in triangle order
    m = 0
    for i in range(n_t):
        for o in range(3):
            if tri_face[i] < tri_face[nb[i, o]]:
                m += 1
    e0 = np.empty(m, dtype=np.int64)
    e1 = np.empty(m, dtype=np.int64)
    pair = np.empty(m, dtype=np.int64)
    m = 0
    for i in range(n_t):
        for o in range(3):
            fa = tri_face[i]
            fb = tri_face[nb[i, o]]
            if fa < fb:
                e0[m] = tri[i, (o + 1) % 3]
                e1[m] = tri[i, (o + 2) % 3]
                pair[m] = fa * n_f + fb
                m += 1
    order = np.argsort(pair, kind="mergesort")
    inv = np.empty(m, dtype=np.int64)
    n_a = 0
    for q in range(m):
        if q == 0 or pair[order[q]] != pair[order[q - 1]]:
            n_a += 1
        inv[order[q]] = n_a - 1
    arc_faces = np.empty((n_a, 2), dtype=np.int64)
    first = np.full(n_a, -1, dtype=np.int64)
    for e in range(m):
        a = inv[e]
        if first[a] < 0:
            first[a] = e
            arc_faces[a, 0] = pair[e] // n_f
            arc_faces[a, 1] = pair[e] % n_f
    # the full segment of collinear sub-edges: the extreme vertices along the first sub-edge's direction
    dirs = np.empty((n_a, 3))
    for a in range(n_a):
        e = first[a]
        x0 = pts[e1[e], 0] - pts[e0[e], 0]
        x1 = pts[e1[e], 1] - pts[e0[e], 1]
        x2 = pts[e1[e], 2] - pts[e0[e], 2]
        nrm = np.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
        dirs[a, 0] = x0 / nrm
        dirs[a, 1] = x1 / nrm
        dirs[a, 2] = x2 / nrm
    lo_val = np.full(n_a, np.inf)
    hi_val = np.full(n_a, -np.inf)
    proj = np.empty((m, 2))
    for e in range(m):
        a = inv[e]
        for j in range(2):
            v = e0[e] if j == 0 else e1[e]
            proj[e, j] = dirs[a, 0] * pts[v, 0] + dirs[a, 1] * pts[v, 1] + dirs[a, 2] * pts[v, 2]
        lo = min(proj[e, 0], proj[e, 1])
        hi = max(proj[e, 0], proj[e, 1])
        if lo < lo_val[a]:
            lo_val[a] = lo
        if hi > hi_val[a]:
            hi_val[a] = hi
    arc_a = np.zeros(n_a, dtype=np.int64)
    arc_b = np.zeros(n_a, dtype=np.int64)
    for e in range(m):  # the last vertex at the extreme wins, as NumPy's fancy assignment leaves it
        a = inv[e]
        for j in range(2):
            v = e0[e] if j == 0 else e1[e]
            if proj[e, j] == lo_val[a]:
                arc_a[a] = v
            if proj[e, j] == hi_val[a]:
                arc_b[a] = v
    # (vertex pair -> arc): sub-edges first, then each arc's full segment; the first occurrence of each pair
    keys = np.empty(m + n_a, dtype=np.int64)
    val = np.empty(m + n_a, dtype=np.int64)
    for e in range(m):
        keys[e] = min(e0[e], e1[e]) * k_v + max(e0[e], e1[e])
        val[e] = inv[e]
    for a in range(n_a):
        keys[m + a] = min(arc_a[a], arc_b[a]) * k_v + max(arc_a[a], arc_b[a])
        val[m + a] = a
    korder = np.argsort(keys, kind="mergesort")
    n_k = 0
    for q in range(m + n_a):
        if q == 0 or keys[korder[q]] != keys[korder[q - 1]]:
            n_k += 1
    out_k = np.empty(n_k, dtype=np.int64)
    out_v = np.empty(n_k, dtype=np.int64)
    n_k = 0
    for q in range(m + n_a):
        if q == 0 or keys[korder[q]] != keys[korder[q - 1]]:
            out_k[n_k] = keys[korder[q]]
            out_v[n_k] = val[korder[q]]
            n_k += 1
    return arc_faces, arc_a, arc_b, out_k, out_v


@numba.njit(cache=True)
def merge_coplanar(pts, tri, eq, nb, tol_m, angle_tol):
    """Merged faces of a triangulated convex hull: a triangle joins its neighbour's face when their unit normals
    (``eq[:, :3]``) differ by at most ``angle_tol`` and the neighbour's far vertex lies within ``tol_m`` of the
    triangle's plane. Returns the face of each triangle, faces numbered in order of their first triangle (as
    ``scipy.sparse.csgraph.connected_components`` numbers them)."""
    n_t = tri.shape[0]
    root = np.arange(n_t)
    for i in range(n_t):
        for q in range(3):
            j = nb[i, q]
            far = tri[j, 0]
            for r in range(3):  # the neighbour's vertex not shared with triangle i (the first, if all are)
                v = tri[j, r]
                if v != tri[i, 0] and v != tri[i, 1] and v != tri[i, 2]:
                    far = v
                    break
            dist = abs(
                _dot3_einsum(eq[i, 0], eq[i, 1], eq[i, 2], pts[far, 0], pts[far, 1], pts[far, 2]) + eq[i, 3]
            )
            dn = _norm3_seq(eq[i, 0] - eq[j, 0], eq[i, 1] - eq[j, 1], eq[i, 2] - eq[j, 2])
            if dist <= tol_m and dn <= angle_tol:
                a = i
                while root[a] != a:
                    root[a] = root[root[a]]
                    a = root[a]
                b = j
                while root[b] != b:
                    root[b] = root[root[b]]
                    b = root[b]
                if a != b:
                    if a < b:
                        root[b] = a
                    else:
                        root[a] = b
    label = np.full(n_t, -1, dtype=np.int64)
    face = np.zeros(n_t, dtype=np.int64)
    n_f = 0
    for i in range(n_t):
        a = i
        while root[a] != a:
            a = root[a]
        if label[a] < 0:
            label[a] = n_f
            n_f += 1
        face[i] = label[a]
    return face
