"""Compiled priority floods (minimax, or bottleneck, searches) of :mod:`landscape.barriers.grid`, on the
pitch-roll torus, and of :mod:`landscape.barriers.sphere`, on any graph in CSR form, with their binary heap.

Private: inputs are trusted (C-contiguous float64, radians) and nothing is validated here; the public wrappers
convert and check. The heap also serves the flood of :mod:`landscape._computation_kernels` and the bottleneck
search of :mod:`landscape.barriers._exact_kernels`. numba's cache does not see an edit to a function in
another file: after changing the heap, clear the cache (its place: :mod:`landscape`).
"""

from __future__ import annotations

import numba
import numpy as np


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


# ---------------------------------------------------------------------------- on the pitch-roll torus
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
