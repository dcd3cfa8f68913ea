"""Compiled kernels of :mod:`landscape.energy`: the support function by a walk on the hull's vertex graph.

Private: inputs are trusted (C-contiguous float64, radians) and nothing is validated here; the public wrappers
convert and check. The walk (``_climb``) also gives the energy of a cell in
:mod:`landscape._computation_kernels`, and ``support_points`` the energy over up-directions in
:mod:`landscape.barriers.sphere`. numba's cache does not see an edit to a function in another file: after
changing ``_climb``, clear the cache (its place: :mod:`landscape`).
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
