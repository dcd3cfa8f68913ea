"""Compiled kernels of :mod:`landscape.minima`: quasi-static rolling on a point set, the face-following
continuation along a joint path, and steepest descent on the pitch-roll grid.

Private: inputs are trusted (C-contiguous float64, radians) and nothing is validated here; the public wrappers
convert and check. The rolling makes the same moves as its NumPy reference (``rest_reference``,
``still_rests_reference`` in tests/landscape/_references.py), one point set d = c - p (K, 3) at a time;
``follow_path`` runs the whole continuation along a joint path.
"""

from __future__ import annotations

import numba
import numpy as np


# ---------------------------------------------------------------------------- quasi-static rolling on a point set
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
    was stood on at u_prev, as the reference ``still_rests_reference``."""
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


# ---------------------------------------------------------------------------- steepest descent on the torus grid
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
