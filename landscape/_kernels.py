"""Compiled kernels. Private: inputs are trusted (C-contiguous float64, radians), nothing is validated here.

The public wrappers in ``energy.py``, ``minima.py`` and ``barrier.py`` convert and check their input.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def _climb(d, ptr, idx, ux, uy, uz, v):
    """Steepest ascent of u.d over the hull's vertex graph from vertex v; the max of a linear function."""
    best = d[v, 0] * ux + d[v, 1] * uy + d[v, 2] * uz
    while True:
        nxt = -1
        for k in range(ptr[v], ptr[v + 1]):
            w = idx[k]
            val = d[w, 0] * ux + d[w, 1] * uy + d[w, 2] * uz
            if val > best:
                best = val
                nxt = w
        if nxt < 0:
            return best, v
        v = nxt


@numba.njit(cache=True)
def support_grid(d, ptr, idx, cos_p, sin_p, cos_r, sin_r):
    """h[i, j] = max_k d_k . u(p_i, r_j) by warm-started hill climbing on the hull graph.

    d : (K, 3) vectors c - v_k from each hull vertex to the CoM. Returns (P, R) float64.
    """
    n_p = cos_p.shape[0]
    n_r = cos_r.shape[0]
    out = np.zeros((n_p, n_r))
    row_start = 0
    for i in range(n_p):
        ux = -sin_p[i]
        v = row_start
        for j in range(n_r):
            val, v = _climb(d, ptr, idx, ux, cos_p[i] * sin_r[j], cos_p[i] * cos_r[j], v)
            out[i, j] = val
            if j == 0:
                row_start = v
    return out


@numba.njit(cache=True)
def support_points(d, ptr, idx, u):
    """h_k = max over hull vertices of d . u_k for arbitrary unit vectors u (M, 3), warm-started in order."""
    m = u.shape[0]
    out = np.zeros(m)
    v = 0
    for k in range(m):
        val, v = _climb(d, ptr, idx, u[k, 0], u[k, 1], u[k, 2], v)
        out[k] = val
    return out


# ---------------------------------------------------------------------------- binary heap on (energy, cell)
@numba.njit(cache=True)
def _less(e1, i1, e2, i2):
    return e1 < e2 or (e1 == e2 and i1 < i2)


@numba.njit(cache=True)
def _push(he, hi, size, e, i):
    k = size
    he[k] = e
    hi[k] = i
    while k > 0:
        parent = (k - 1) >> 1
        if _less(he[k], hi[k], he[parent], hi[parent]):
            he[k], he[parent] = he[parent], he[k]
            hi[k], hi[parent] = hi[parent], hi[k]
            k = parent
        else:
            break
    return size + 1


@numba.njit(cache=True)
def _pop(he, hi, size):
    e0 = he[0]
    i0 = hi[0]
    size -= 1
    he[0] = he[size]
    hi[0] = hi[size]
    k = 0
    while True:
        left = 2 * k + 1
        if left >= size:
            break
        c = left
        if left + 1 < size and _less(he[left + 1], hi[left + 1], he[left], hi[left]):
            c = left + 1
        if _less(he[c], hi[c], he[k], hi[k]):
            he[k], he[c] = he[c], he[k]
            hi[k], hi[c] = hi[c], hi[k]
            k = c
        else:
            break
    return e0, i0, size


@numba.njit(cache=True)
def flood(energy, start, target, blocked, is_min, same_as_start, tol, connectivity, stop_at_escape):
    """Priority flood (minimax / bottleneck search) over the pitch-roll torus from cell ``start``.

    energy : (N, N) energies on the torus (both axes wrap); cells are numbered i * N + j.
    target : (N * N) int8; 1 or 2 = absorbing target of that kind (reached, never expanded), 0 = plain.
    blocked : (N * N) bool, cells the flood never enters.
    is_min : (N * N) bool, grid local minima; same_as_start : (N * N) bool, cells that are the start's own
        orientation (itself, its twin and its plateau), never counted as another basin.
    Returns (levels, cells, parent): levels[k] and cells[k] give, for k = 0 (target 1), 1 (target 2),
    2 (another basin), the flood level at the first pop of such a cell and that cell (-1 if never reached);
    parent is the search tree (-1 at the start and in unvisited cells).
    """
    n = energy.shape[0]
    total = n * n
    flat = energy.ravel()
    parent = np.full(total, -1, dtype=np.int64)
    seen = np.zeros(total, dtype=np.bool_)
    he = np.zeros(total)
    hi = np.zeros(total, dtype=np.int64)
    levels = np.full(3, np.inf)
    cells = np.full(3, -1, dtype=np.int64)
    e_start = flat[start]
    size = _push(he, hi, 0, flat[start], start)
    seen[start] = True
    level = e_start
    found = 0
    while size > 0:
        e, c, size = _pop(he, hi, size)
        if e > level:
            level = e
        t = target[c]
        if t > 0:
            if cells[t - 1] < 0:
                cells[t - 1] = c
                levels[t - 1] = level
                found += 1
            continue
        if found > 0 and not stop_at_escape:
            break
        if cells[2] < 0 and is_min[c] and level > e_start + tol and not same_as_start[c]:
            cells[2] = c
            levels[2] = level
            if stop_at_escape:
                break
        ci = c // n
        cj = c - ci * n
        for di in range(-1, 2):
            for dj in range(-1, 2):
                if di == 0 and dj == 0:
                    continue
                if connectivity == 4 and di != 0 and dj != 0:
                    continue
                ni = (ci + di) % n
                nj = (cj + dj) % n
                nc = ni * n + nj
                if not seen[nc] and not blocked[nc]:
                    seen[nc] = True
                    parent[nc] = c
                    size = _push(he, hi, size, flat[nc], nc)
    return levels, cells, parent


@numba.njit(cache=True)
def local_minima(energy, tol):
    """(N * N) bool: cells no 8-neighbour of which is lower by more than tol (torus)."""
    n = energy.shape[0]
    out = np.zeros(n * n, dtype=np.bool_)
    for i in range(n):
        for j in range(n):
            e = energy[i, j]
            ok = True
            for di in range(-1, 2):
                for dj in range(-1, 2):
                    if energy[(i + di) % n, (j + dj) % n] < e - tol:
                        ok = False
            out[i * n + j] = ok
    return out


@numba.njit(cache=True)
def descend(energy, i, j):
    """Steepest descent over the 8-neighbours of the torus grid until no neighbour is lower."""
    n = energy.shape[0]
    while True:
        bi, bj = i, j
        best = energy[i, j]
        for di in range(-1, 2):
            for dj in range(-1, 2):
                ni = (i + di) % n
                nj = (j + dj) % n
                if energy[ni, nj] < best:
                    best = energy[ni, nj]
                    bi, bj = ni, nj
        if bi == i and bj == j:
            return i, j
        i, j = bi, bj


@numba.njit(cache=True)
def tree_path(parent, cell):
    """The cells from the root of a search tree (``parent`` -1) to ``cell``, root first."""
    m = 1
    c = cell
    while parent[c] >= 0:
        c = parent[c]
        m += 1
    out = np.empty(m, dtype=np.int64)
    c = cell
    for k in range(m - 1, -1, -1):
        out[k] = c
        c = parent[c]
    return out


# ---------------------------------------------------------------------------- the grid computed only where searched
@numba.njit(cache=True)
def _lazy_at(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, i, j, v):
    """Energy of torus cell (i, j), computed on first use as :func:`support_grid` computes it (hill climbing
    on the hull graph warm-started at vertex ``v``, times ``scale`` = m g) and kept in ``energy``/``known``;
    ``vert`` keeps the vertex that attains it (the warm start of its neighbours)."""
    n = energy.shape[0]
    c = i * n + j
    if not known[i, j]:
        val, w = _climb(d, ptr, idx, -sin_a[i], cos_a[i] * sin_a[j], cos_a[i] * cos_a[j], v)
        energy[i, j] = scale * val
        known[i, j] = True
        vert[c] = w
    return energy[i, j]


@numba.njit(cache=True)
def lazy_descend(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, i, j):
    """:func:`descend` on a grid whose energies are computed on first use (:func:`_lazy_at`)."""
    n = energy.shape[0]
    _lazy_at(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, i, j, 0)
    while True:
        bi, bj = i, j
        v = vert[i * n + j]
        best = energy[i, j]
        for di in range(-1, 2):
            for dj in range(-1, 2):
                ni = (i + di) % n
                nj = (j + dj) % n
                e = _lazy_at(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, ni, nj, v)
                if e < best:
                    best = e
                    bi, bj = ni, nj
        if bi == i and bj == j:
            return i, j
        i, j = bi, bj


@numba.njit(cache=True)
def lazy_sector_flood(
    energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, i0, j0, dist_p, dist_r, pitch_sector, connectivity
):
    """:func:`flood` from cell (i0, j0) to the upright set (``cos p cos r < 0``) with the path kept in a sector,
    on a grid whose energies are computed on first use (:func:`_lazy_at`): only the cells the flood reaches.

    ``dist_p[i]``, ``dist_r[j]``: |wrapped pitch and roll difference| of row i and column j from the start,
    degrees. The sector keeps cells with ``dist_r <= dist_p`` (``pitch_sector``) or ``dist_p <= dist_r``, and
    always the start. Returns (level, cell, parent): the flood level at the first upright cell popped and that
    cell (inf, -1 if none); ``parent`` is the search tree, valid on the cells reached (-1 at the start).
    """
    n = energy.shape[0]
    total = n * n
    parent = np.empty(total, dtype=np.int64)
    seen = np.zeros(total, dtype=np.bool_)
    he = np.empty(total)
    hi = np.empty(total, dtype=np.int64)
    start = i0 * n + j0
    e_start = _lazy_at(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, i0, j0, 0)
    parent[start] = -1
    size = _push(he, hi, 0, e_start, start)
    seen[start] = True
    level = e_start
    while size > 0:
        e, c, size = _pop(he, hi, size)
        if e > level:
            level = e
        ci = c // n
        cj = c - ci * n
        if cos_a[ci] * cos_a[cj] < 0:
            return level, c, parent
        v = vert[c]
        for di in range(-1, 2):
            ni = ci + di
            if ni < 0:
                ni += n
            elif ni >= n:
                ni -= n
            for dj in range(-1, 2):
                if di == 0 and dj == 0:
                    continue
                if connectivity == 4 and di != 0 and dj != 0:
                    continue
                nj = cj + dj
                if nj < 0:
                    nj += n
                elif nj >= n:
                    nj -= n
                nc = ni * n + nj
                if seen[nc] or nc == start:
                    continue
                if pitch_sector:
                    if dist_r[nj] > dist_p[ni]:
                        continue
                elif dist_p[ni] > dist_r[nj]:
                    continue
                seen[nc] = True
                parent[nc] = c
                size = _push(
                    he,
                    hi,
                    size,
                    _lazy_at(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, ni, nj, v),
                    nc,
                )
    return np.inf, -1, parent


# ---------------------------------------------------------------------------- the same searches on any graph (CSR)
@numba.njit(cache=True)
def flood_graph(energy, ptr, idx, start, target, blocked, is_min, same_as_start, tol, stop_at_escape):
    """:func:`flood` on a graph given by CSR adjacency (ptr, idx), e.g. an icosphere of up-directions."""
    total = energy.shape[0]
    parent = np.full(total, -1, dtype=np.int64)
    seen = np.zeros(total, dtype=np.bool_)
    he = np.zeros(total)
    hi = np.zeros(total, dtype=np.int64)
    levels = np.full(3, np.inf)
    cells = np.full(3, -1, dtype=np.int64)
    e_start = energy[start]
    size = _push(he, hi, 0, energy[start], start)
    seen[start] = True
    level = e_start
    found = 0
    while size > 0:
        e, c, size = _pop(he, hi, size)
        if e > level:
            level = e
        t = target[c]
        if t > 0:
            if cells[t - 1] < 0:
                cells[t - 1] = c
                levels[t - 1] = level
                found += 1
            continue
        if found > 0 and not stop_at_escape:
            break
        if cells[2] < 0 and is_min[c] and level > e_start + tol and not same_as_start[c]:
            cells[2] = c
            levels[2] = level
            if stop_at_escape:
                break
        for k in range(ptr[c], ptr[c + 1]):
            nc = idx[k]
            if not seen[nc] and not blocked[nc]:
                seen[nc] = True
                parent[nc] = c
                size = _push(he, hi, size, energy[nc], nc)
    return levels, cells, parent


@numba.njit(cache=True)
def local_minima_graph(energy, ptr, idx, tol):
    """Nodes no neighbour of which is lower by more than tol."""
    n = energy.shape[0]
    out = np.zeros(n, dtype=np.bool_)
    for c in range(n):
        ok = True
        for k in range(ptr[c], ptr[c + 1]):
            if energy[idx[k]] < energy[c] - tol:
                ok = False
                break
        out[c] = ok
    return out


@numba.njit(cache=True)
def descend_graph(energy, ptr, idx, c):
    """Steepest descent over graph neighbours until none is lower."""
    while True:
        best, nxt = energy[c], c
        for k in range(ptr[c], ptr[c + 1]):
            if energy[idx[k]] < best:
                best, nxt = energy[idx[k]], idx[k]
        if nxt == c:
            return c
        c = nxt


# ---------------------------------------------------------------------------- quasi-static rolling on a point set
# The same moves as the NumPy reference in landscape/minima.py (``_rest``, ``_still_rests``), one point set
# d = c - p (K, 3) at a time; ``follow_path`` runs the whole continuation along a joint path.
@numba.njit(cache=True)
def _dot3(a0, a1, a2, b0, b1, b2):
    return a0 * b0 + a1 * b1 + a2 * b2


@numba.njit(cache=True)
def _unit(v):
    n = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    out = np.zeros(3)
    out[0] = v[0] / n
    out[1] = v[1] / n
    out[2] = v[2] / n
    return out


@numba.njit(cache=True)
def _cross3(a, b):
    out = np.zeros(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@numba.njit(cache=True)
def _basis(u):
    """Two unit vectors spanning the plane normal to u (the reference's deterministic choice)."""
    k = 0
    for i in range(1, 3):
        if abs(u[i]) < abs(u[k]):
            k = i
    a = np.zeros(3)
    a[k] = 1.0
    e1 = _unit(_cross3(u, a))
    return e1, _cross3(u, e1)


@numba.njit(cache=True)
def _heights(d, u):
    k = d.shape[0]
    hv = np.zeros(k)
    for i in range(k):
        hv[i] = d[i, 0] * u[0] + d[i, 1] * u[1] + d[i, 2] * u[2]
    return hv


@numba.njit(cache=True)
def _convex_polygon(xy):
    """Counter-clockwise hull of 2-D points (monotone chain, stable sort by x then y), collinear dropped."""
    n = xy.shape[0]
    order = np.zeros(n, dtype=np.int64)
    for i in range(n):
        order[i] = i
    for i in range(1, n):  # stable insertion sort on (x, y)
        v = order[i]
        j = i - 1
        while j >= 0 and (xy[order[j], 0], xy[order[j], 1]) > (xy[v, 0], xy[v, 1]):
            order[j + 1] = order[j]
            j -= 1
        order[j + 1] = v
    out = np.zeros(2 * n + 2, dtype=np.int64)
    m = 0
    for half in range(2):
        start = m
        for q in range(n):
            i = order[q] if half == 0 else order[n - 1 - q]
            while m - start >= 2:
                o = out[m - 2]
                a = out[m - 1]
                turn = (xy[a, 0] - xy[o, 0]) * (xy[i, 1] - xy[o, 1]) - (xy[a, 1] - xy[o, 1]) * (
                    xy[i, 0] - xy[o, 0]
                )
                if turn > 0:
                    break
                m -= 1
            out[m] = i
            m += 1
        m -= 1  # drop each half's last point (the other half's first)
    return out[:m].copy()


@numba.njit(cache=True)
def _contact(d, u, tol):
    """(active, xy, poly) as the reference ``_contact``: lowest points, ground-plane positions, their hull."""
    return _contact_hv(d, _heights(d, u), u, tol)


@numba.njit(cache=True)
def _contact_hv(d, hv, u, tol):
    """:func:`_contact` with the heights hv = d @ u already computed."""
    top = hv.max()
    n = 0
    for i in range(hv.shape[0]):
        if hv[i] >= top - tol:
            n += 1
    active = np.zeros(n, dtype=np.int64)
    n = 0
    for i in range(hv.shape[0]):
        if hv[i] >= top - tol:
            active[n] = i
            n += 1
    e1, e2 = _basis(u)
    xy = np.zeros((n, 2))
    for q in range(n):
        i = active[q]
        xy[q, 0] = -(d[i, 0] * e1[0] + d[i, 1] * e1[1] + d[i, 2] * e1[2])
        xy[q, 1] = -(d[i, 0] * e2[0] + d[i, 1] * e2[1] + d[i, 2] * e2[2])
    if n == 1:
        return active, xy, np.zeros(1, dtype=np.int64)
    i0 = 0
    best = xy[0, 0] + xy[0, 1] * 1e-3
    for q in range(1, n):
        v = xy[q, 0] + xy[q, 1] * 1e-3
        if v < best:
            best = v
            i0 = q
    j0 = 0
    far = -1.0
    for q in range(n):
        rx = xy[q, 0] - xy[i0, 0]
        ry = xy[q, 1] - xy[i0, 1]
        v = rx * rx + ry * ry
        if v > far:
            far = v
            j0 = q
    jx = xy[j0, 0] - xy[i0, 0]
    jy = xy[j0, 1] - xy[i0, 1]
    length = np.hypot(jx, jy)
    if length <= tol:
        poly = np.zeros(1, dtype=np.int64)
        poly[0] = i0
        return active, xy, poly
    off_max = 0.0
    amin = 0
    amax = 0
    along_min = np.inf
    along_max = -np.inf
    for q in range(n):
        rx = xy[q, 0] - xy[i0, 0]
        ry = xy[q, 1] - xy[i0, 1]
        along = (rx * jx + ry * jy) / length
        off = abs((rx * jy - ry * jx) / length)
        if off > off_max:
            off_max = off
        if along < along_min:
            along_min = along
            amin = q
        if along > along_max:
            along_max = along
            amax = q
    if off_max <= tol:
        poly = np.zeros(2, dtype=np.int64)
        poly[0] = amin
        poly[1] = amax
        return active, xy, poly
    return active, xy, _convex_polygon(xy)


@numba.njit(cache=True)
def _polygon_margin(xy, poly):
    """Signed distance of the origin inside a CCW polygon, the nearest edge, and where along it (0..1)."""
    m = poly.shape[0]
    inside_min = np.inf
    best = np.inf
    k = 0
    s_k = 0.0
    for q in range(m):
        ax = xy[poly[q], 0]
        ay = xy[poly[q], 1]
        bx = xy[poly[(q + 1) % m], 0]
        by = xy[poly[(q + 1) % m], 1]
        ex = bx - ax
        ey = by - ay
        length = np.sqrt(ex * ex + ey * ey)
        inside = (ex * (-ay) - ey * (-ax)) / length
        if inside < inside_min:
            inside_min = inside
        s = -(ax * ex + ay * ey) / length**2
        s = min(max(s, 0.0), 1.0)
        px = ax + s * ex
        py = ay + s * ey
        dist = np.sqrt(px * px + py * py)
        if dist < best:
            best = dist
            k = q
            s_k = s
    return inside_min, k, s_k


@numba.njit(cache=True)
def _first_touch(d, k, u, t):
    """Smallest rotation s > 0 of u toward t about a line through point k at which another point is lowest.

    Point j reaches point k's height where ``(d_j - d_k).(cos s u + sin s t) = 0``, at
    ``s = (atan2(y, x) - pi/2) mod 2 pi`` with x, y its offsets along u and t. The arctangent is taken only for
    points that can beat the best so far: y <= 0 gives s >= pi/2, x > 0 < y gives s > 3 pi/2, and otherwise
    s = atan2(-x, y) grows with -x / y (pruned with a relative margin, so the minimum is the reference's).
    """
    two_pi = 2.0 * np.pi
    half_pi = 0.5 * np.pi
    best = np.inf
    tan_best = np.inf
    for j in range(d.shape[0]):
        x0 = d[j, 0] - d[k, 0]
        x1 = d[j, 1] - d[k, 1]
        x2 = d[j, 2] - d[k, 2]
        x = x0 * u[0] + x1 * u[1] + x2 * u[2]
        y = x0 * t[0] + x1 * t[1] + x2 * t[2]
        if y <= 0.0 and best <= half_pi:
            continue
        if y > 0.0 and x > 0.0 and best <= 1.5 * np.pi:
            continue
        if y > 0.0 and x <= 0.0 and best < half_pi and -x > y * tan_best * (1.0 + 1e-6):
            continue
        s = (np.arctan2(y, x) - half_pi) % two_pi  # Python's (and NumPy's) float modulo
        if s >= 1e-12 and s < best:
            best = s
            tan_best = np.tan(best) if best < half_pi else np.inf
    return best


@numba.njit(cache=True)
def _rotate(u, t, s):
    out = np.zeros(3)
    c = np.cos(s)
    sn = np.sin(s)
    for i in range(3):
        out[i] = c * u[i] + sn * t[i]
    return _unit(out)


@numba.njit(cache=True)
def _norm3(v):
    return np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


@numba.njit(cache=True)
def _pivot(d, k, u):
    """Tip about point k: steepest descent of d_k.u, to where another point touches."""
    dk = d[k].copy()
    du = dk[0] * u[0] + dk[1] * u[1] + dk[2] * u[2]
    grad = np.zeros(3)
    for i in range(3):
        grad[i] = dk[i] - du * u[i]
    n = _norm3(grad)
    ndk = _norm3(dk)
    if n < 1e-15 * ndk:
        t = _basis(u)[0]
    else:
        t = np.zeros(3)
        for i in range(3):
            t[i] = -grad[i] / n
    s_end = np.pi - np.arccos(min(max(du / ndk, -1.0), 1.0))
    return _rotate(u, t, min(_first_touch(d, k, u, t), s_end))


@numba.njit(cache=True)
def _roll_edge(d, a, b, u, tol):
    """Roll about the line through points a and b, or pivot on an end the CoM lies beyond."""
    e = np.zeros(3)
    for i in range(3):
        e[i] = d[a, i] - d[b, i]
    length = _norm3(e)
    for i in range(3):
        e[i] = e[i] / length
    foot = d[a, 0] * e[0] + d[a, 1] * e[1] + d[a, 2] * e[2]
    if foot < -tol:
        return _pivot(d, a, u)
    if foot > length + tol:
        return _pivot(d, b, u)
    w = np.zeros(3)
    for i in range(3):
        w[i] = d[a, i] - foot * e[i]
    t = _cross3(e, u)
    nt = _norm3(t)
    for i in range(3):
        t[i] = t[i] / nt
    wt = w[0] * t[0] + w[1] * t[1] + w[2] * t[2]
    if wt > 0 or (wt == 0.0 and a >= b):
        for i in range(3):
            t[i] = -t[i]
    return _rotate(u, t, _first_touch(d, a, u, t))


@numba.njit(cache=True)
def _roll_step(d, u, tol):
    """One quasi-static move from u: (new u, empty face) or (u, face point indices) when at rest."""
    active, xy, poly = _contact(d, u, tol)
    none = np.zeros(0, dtype=np.int64)
    m = poly.shape[0]
    if m >= 3:
        margin, k, s = _polygon_margin(xy, poly)
        if margin > tol:
            return u, active[poly]
        a = poly[k]
        b = poly[(k + 1) % m]
        length = np.hypot(xy[b, 0] - xy[a, 0], xy[b, 1] - xy[a, 1])
        if s * length <= tol:
            return _pivot(d, active[a], u), none
        if (1.0 - s) * length <= tol:
            return _pivot(d, active[b], u), none
        return _roll_edge(d, active[a], active[b], u, tol), none
    if m == 2:
        return _roll_edge(d, active[poly[0]], active[poly[1]], u, tol), none
    return _pivot(d, active[poly[0]], u), none


@numba.njit(cache=True)
def _face_up(d, face, u_hint):
    """The up-direction resting on the plane through a face's corners (the one nearest u_hint)."""
    m = face.shape[0]
    f0 = face[0]
    s12 = 0.0
    s21 = 0.0
    s20 = 0.0
    s02 = 0.0
    s01 = 0.0
    s10 = 0.0
    for q in range(m):
        a = face[q]
        b = face[(q + 1) % m]
        q0 = d[a, 0] - d[f0, 0]
        q1 = d[a, 1] - d[f0, 1]
        q2 = d[a, 2] - d[f0, 2]
        r0 = d[b, 0] - d[f0, 0]
        r1 = d[b, 1] - d[f0, 1]
        r2 = d[b, 2] - d[f0, 2]
        s12 += q1 * r2
        s21 += q2 * r1
        s20 += q2 * r0
        s02 += q0 * r2
        s01 += q0 * r1
        s10 += q1 * r0
    n = np.zeros(3)
    n[0] = s12 - s21
    n[1] = s20 - s02
    n[2] = s01 - s10
    n = _unit(n)
    if n[0] * u_hint[0] + n[1] * u_hint[1] + n[2] * u_hint[2] < 0:
        for i in range(3):
            n[i] = -n[i]
    return n


@numba.njit(cache=True)
def rest(d, u, tol, max_moves):
    """Quasi-static rolling from u on the points d = c - p (K, 3) to rest.

    Returns (up at rest, face indices, settled); settled is False after ``max_moves`` moves.
    """
    for _ in range(max_moves):
        u, face = _roll_step(d, u, tol)
        if face.shape[0] > 0:
            return _face_up(d, face, u), face, True
    return u, np.zeros(0, dtype=np.int64), False


@numba.njit(cache=True)
def still_rests(d, face, u_prev, tol):
    """(ok, up, face): whether ``face`` still bounds the points from below, holds the CoM strictly inside and
    was stood on at u_prev, as the reference ``_still_rests``."""
    none = np.zeros(0, dtype=np.int64)
    u = _face_up(d, face, u_prev)
    k = d.shape[0]
    hv = np.zeros(k)
    hp = np.zeros(k)
    top = -np.inf
    top_prev = -np.inf
    for i in range(k):  # heights at u and at u_prev in one pass over the points
        a = d[i, 0] * u[0] + d[i, 1] * u[1] + d[i, 2] * u[2]
        b = d[i, 0] * u_prev[0] + d[i, 1] * u_prev[1] + d[i, 2] * u_prev[2]
        hv[i] = a
        hp[i] = b
        top = max(top, a)
        top_prev = max(top_prev, b)
    hmin = np.inf
    hmax = -np.inf
    for q in range(face.shape[0]):
        h = hv[face[q]]
        hmin = min(hmin, h)
        hmax = max(hmax, h)
    if hmax - hmin > tol:  # no longer flat
        return False, u, none
    if top > hmax + tol:  # another point pokes below the face's plane
        return False, u, none
    active, xy, poly = _contact_hv(d, hv, u, tol)
    if poly.shape[0] < 3 or _polygon_margin(xy, poly)[0] <= tol:
        return False, u, none
    new_face = active[poly]
    for q in range(new_face.shape[0]):
        if hp[new_face[q]] >= top_prev - tol:
            return True, u, new_face
    return False, u, none


@numba.njit(cache=True)
def posed_points(pts, part_ptr, rot, trans, com, out):
    """out[k] = com - (rot[p] @ pts[k] + trans[p]) for the points k of each part p (rows part_ptr[p] to
    part_ptr[p + 1]): c - p in the body frame for one joint setting. Returns the norm of the points'
    bounding-box diagonal, m.
    """
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for p in range(part_ptr.shape[0] - 1):
        for i in range(3):
            r0 = rot[p, i, 0]
            r1 = rot[p, i, 1]
            r2 = rot[p, i, 2]
            c = com[i] - trans[p, i]
            lo_i = lo[i]
            hi_i = hi[i]
            for k in range(part_ptr[p], part_ptr[p + 1]):
                v = c - (r0 * pts[k, 0] + r1 * pts[k, 1] + r2 * pts[k, 2])
                out[k, i] = v
                lo_i = min(lo_i, v)
                hi_i = max(hi_i, v)
            lo[i] = lo_i
            hi[i] = hi_i
    return np.sqrt((hi[0] - lo[0]) ** 2 + (hi[1] - lo[1]) ** 2 + (hi[2] - lo[2]) ** 2)


@numba.njit(cache=True)
def follow_path(pts, part_ptr, rot, trans, com, rtol, u0, max_moves):
    """The face-following continuation along N joint settings.

    pts (K, 3) every part's hull points in its link frame, part p's in rows part_ptr[p] to part_ptr[p + 1], rot (N, P, 3, 3) and
    trans (N, P, 3) the link-to-body transforms, com (N, 3) the CoM, rtol the relative length tolerance, u0 the
    start up-direction. Returns (ups (N, 3), settled): the up-direction at rest at each step; settled is False if
    rolling did not settle at some step (ups are valid up to it).
    """
    n = rot.shape[0]
    k = pts.shape[0]
    ups = np.zeros((n, 3))
    d = np.zeros((k, 3))
    u = u0.copy()
    face = np.zeros(0, dtype=np.int64)
    for s in range(n):
        tol = rtol * posed_points(pts, part_ptr, rot[s], trans[s], com[s], d)
        ok = False
        if face.shape[0] > 0:
            ok, u_new, f_new = still_rests(d, face, u, tol)
            if ok:
                u = u_new
                face = f_new
        if not ok:
            u, face, settled = rest(d, u, tol, max_moves)
            if not settled:
                return ups, False
        ups[s] = u
    return ups, True


# ------------------------------------------------------------------------- exact method (barriers/exact.py)
@numba.njit(cache=True)
def minimax_graph(ptr, other, edge, weight, sources, goal, stop):
    """Bottleneck Dijkstra on an undirected graph in CSR form (``ptr``, neighbour ``other``, ``edge`` index and
    ``weight`` of each adjacency): the lowest possible maximum edge weight from the sources.

    Goal nodes are settled but never expanded; with ``stop`` the search ends at the first goal settled. The heap
    orders (level, node) as Python tuples do, so the result equals landscape.barriers.exact's reference search.
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
    it is reached. The arithmetic of landscape.barriers.exact's NumPy reference, operation for operation
    (its trigonometric functions may differ in the last bit)."""
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
    landscape.barriers.exact's NumPy reference, operation for operation."""
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
    The arithmetic of landscape.barriers.exact's NumPy reference, operation for operation."""
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


@numba.njit(cache=True)
def cell_step(d, k, u):
    """Steepest descent of h(u) = max_j d_j.u inside vertex k's cell: along the great circle from ``u`` away from
    ``d[k]`` to the cell's boundary (where another vertex becomes as low) or to the antipode of ``d[k]``.

    Returns (the new unit up-direction (3,), True), or (``u``, False) when ``u`` is balanced on the vertex
    (parallel to ``d[k]``). landscape.barriers.exact's ``_cell_step_reference`` is the NumPy version.
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


@numba.njit(cache=True)
def arcs(pts, tri, nb, tri_face, n_f):
    """The face-edge graph's arcs: landscape.barriers.exact's ``_arcs_reference`` compiled (the same numbers).

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
