"""Barriers on a uniform sampling of the sphere of up-directions (an icosphere graph) instead of the torus.

The pitch-roll torus covers the sphere twice and crowds its samples near the poles p = +-90 deg; an icosphere of
subdivision level k has 10 4^k + 2 nearly evenly spaced up-directions (about 69 / 2^k deg apart). The same priority
flood runs on its vertex graph, with the same target sets as :mod:`landscape.barriers.grid`: upright (u_z < 0) for
righting and another local minimum (not within 2.5 spacings of the start) for escape. Pitch-wise and roll-wise
barriers are sectors of the *torus* around the start, and a path over the pole changes sheet; a graph on the
sphere does not know the sheet, so those two are left to :func:`landscape.computation.compute` (None here). ``benchmarks/accuracy.py`` compares it
with the grid and the exact method.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import trimesh
from numpy.typing import NDArray

from geometry import Pose
from geometry.errors import UsageError
from geometry.frames import canonical_pitch_roll_deg, pitch_roll_from_up, up_vector
from landscape import _energy_kernels
from landscape.barriers import _flood_kernels
from landscape.barriers._base import Barrier, Exit
from landscape.energy import G_M_S2
from landscape.grid import wrap_deg
from landscape.minima import Minimum


@dataclass(frozen=True)
class SphereGraph:
    """Icosphere vertices (unit up-directions, in a coherent order) and their adjacency (CSR)."""

    u: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    ptr: NDArray[np.int64]
    idx: NDArray[np.int64]
    spacing_deg: float


@lru_cache(maxsize=4)
def sphere_graph(subdivisions: int) -> SphereGraph:
    """The icosphere graph of a subdivision level (cached).

    Examples
    --------
    >>> g = sphere_graph(3)
    >>> len(g.u), 10 * 4**3 + 2  # an icosphere's vertex count
    (642, 642)
    >>> round(sphere_graph(0).spacing_deg, 4), round(float(np.degrees(np.arctan(2.0))), 4)  # icosahedron edge
    (63.4349, 63.4349)
    """
    ico = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    u = np.asarray(ico.vertices, dtype=np.float64)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    p, r = pitch_roll_from_up(u)
    p_deg, r_deg = np.rad2deg(p), np.rad2deg(r)
    band = np.round(p_deg / 2.0)
    order = np.lexsort((np.where(band % 2 == 0, r_deg, -r_deg), band))  # boustrophedon: neighbours stay close
    inv = np.empty_like(order)
    inv[order] = np.arange(len(order))
    edges = inv[np.asarray(ico.edges_unique, dtype=np.int64)]
    both = np.concatenate([edges, edges[:, ::-1]])
    both = both[np.lexsort((both[:, 1], both[:, 0]))]
    ptr = np.zeros(len(u) + 1, dtype=np.int64)
    np.cumsum(np.bincount(both[:, 0], minlength=len(u)), out=ptr[1:])
    u = np.ascontiguousarray(u[order])
    spacing = float(np.rad2deg(np.mean(np.arccos(np.clip((u[edges[:, 0]] * u[edges[:, 1]]).sum(1), -1, 1)))))
    return SphereGraph(u, p_deg[order], r_deg[order], ptr, both[:, 1].copy(), spacing)


def subdivisions_for_step(step_deg: float) -> int:
    """The icosphere level whose vertex spacing (about 69.1 / 2^k deg) is closest to a grid step.

    Examples
    --------
    >>> subdivisions_for_step(1.0), subdivisions_for_step(0.5)
    (6, 7)
    """
    return int(np.clip(np.round(np.log2(69.1 / step_deg)), 1, 8))


@dataclass(frozen=True)
class SphereBarrier:
    """Start minimum (a graph vertex) and exits, as the grid method reports them."""

    start: Minimum
    barrier: Barrier
    n_vertices: int


def _exit(g, energy, level, cell, parent, e_start, p0, r0, kind):
    if cell < 0:
        return None
    path = [cell]
    while parent[path[-1]] >= 0:
        path.append(int(parent[path[-1]]))
    path = np.array(path[::-1])
    k = int(path[np.argmax(energy[path])])
    sp, sr = canonical_pitch_roll_deg(g.pitch_deg[k], g.roll_deg[k])
    deg = np.stack([g.pitch_deg[path], np.rad2deg(np.unwrap(np.deg2rad(g.roll_deg[path])))], axis=1)
    if kind is None:
        dp, dr = abs(float(wrap_deg(sp - p0))), abs(float(wrap_deg(sr - r0)))
        kind = "pitch" if dp >= dr else "roll"
    return Exit(float(level - e_start), sp, sr, kind, deg)


def sphere_barrier(
    pose: Pose,
    start_pitch_deg: float,
    start_roll_deg: float,
    *,
    subdivisions: int = 6,
    g_m_s2: float = G_M_S2,
) -> SphereBarrier:
    """Righting and escape barriers on an icosphere of up-directions (pitch-/roll-wise are None).

    Parameters
    ----------
    pose : geometry.Pose
    start_pitch_deg, start_roll_deg : float
        The start minimum is the vertex reached by steepest descent from the vertex nearest this orientation.
    subdivisions : int
        Icosphere level (6: 40962 directions about 1.1 deg apart; 7: 163842, about 0.55 deg).
    """
    if not 1 <= subdivisions <= 8:
        raise UsageError(f"subdivisions must be 1..8; got {subdivisions!r}")
    g = sphere_graph(subdivisions)
    d = np.ascontiguousarray(pose.com_m[None, :] - pose.hull.vertices_m)
    energy = (
        pose.mass_kg
        * g_m_s2
        * _energy_kernels.support_points(d, pose.hull.neighbor_ptr, pose.hull.neighbor_idx, g.u)
    )
    u0 = up_vector(np.deg2rad(start_pitch_deg), np.deg2rad(start_roll_deg))
    s = int(_flood_kernels.descend_graph(energy, g.ptr, g.idx, int(np.argmax(g.u @ u0))))
    e_start = float(energy[s])
    p0, r0 = canonical_pitch_roll_deg(g.pitch_deg[s], g.roll_deg[s])
    tol = 1e-9 * float(energy.max() - energy.min()) + 1e-15
    is_min = _flood_kernels.local_minima_graph(energy, g.ptr, g.idx, tol)
    same = g.u @ g.u[s] > np.cos(np.deg2rad(2.5 * g.spacing_deg))
    upright = (g.u[:, 2] < 0).astype(np.int8)
    none = np.zeros(len(g.u), dtype=np.bool_)
    start = Minimum(p0, r0, e_start, e_start / (pose.mass_kg * g_m_s2))
    if upright[s]:
        zero = Exit(0.0, p0, r0, "roll", np.array([[p0, r0]]))
        return SphereBarrier(start, Barrier(zero, None, None, None), len(g.u))
    lv, cl, par = _flood_kernels.flood_graph(energy, g.ptr, g.idx, s, upright, none, is_min, same, tol, False)
    righting = _exit(g, energy, lv[0], int(cl[0]), par, e_start, p0, r0, None)
    zeros = np.zeros(len(g.u), dtype=np.int8)
    lv, cl, par = _flood_kernels.flood_graph(energy, g.ptr, g.idx, s, zeros, none, is_min, same, tol, True)
    escape = _exit(g, energy, lv[2], int(cl[2]), par, e_start, p0, r0, None)
    return SphereBarrier(start, Barrier(righting, None, None, escape), len(g.u))


SECTORS = False


def solve(
    pose: Pose,
    landscape,
    start_deg: tuple[float, float],
    *,
    step_deg: float,
    connectivity: int,
    g_m_s2: float,
):
    """The registry's entry (:mod:`landscape.barriers`): the search on an icosphere spaced about ``step_deg``."""
    sb = sphere_barrier(pose, *start_deg, subdivisions=subdivisions_for_step(step_deg), g_m_s2=g_m_s2)
    return sb.start, sb.barrier
