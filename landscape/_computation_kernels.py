"""Compiled kernels of :mod:`landscape.computation`: steepest descent and the sector-restricted flood on the
pitch-roll torus, with each cell's energy computed on first use, so only where the search goes.

Private: inputs are trusted (C-contiguous float64, radians) and nothing is validated here; the public wrappers
convert and check.
"""

from __future__ import annotations

import numba
import numpy as np

from ._energy_kernels import _climb
from .barriers._flood_kernels import _pop, _push


@numba.njit(cache=True)
def _lazy_at(energy, known, vert, d, ptr, idx, cos_a, sin_a, scale, i, j, v):
    """Energy of torus cell (i, j), computed on first use as ``_energy_kernels.support_grid`` computes it
    (hill climbing on the hull graph warm-started at vertex ``v``, times ``scale`` = m g) and kept in
    ``energy``/``known``; ``vert`` keeps the vertex that attains it (the warm start of its neighbours)."""
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
    """``_minima_kernels.descend`` on a grid whose energies are computed on first use (:func:`_lazy_at`)."""
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
    """``barriers._flood_kernels.flood`` from cell (i0, j0) to the upright set (``cos p cos r < 0``) with the
    path kept in a sector, on a grid whose energies are computed on first use (:func:`_lazy_at`): only the cells
    the flood reaches.

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
