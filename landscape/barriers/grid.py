"""Minimal barriers by graph search on the pitch-roll grid (the bottleneck-path problem, by priority flood).

From the start cell the flood always expands the lowest cell on its frontier; the flood level when it first
reaches a set of cells is the lowest possible maximum energy along any grid path to that set.

- *righting*: reach the upright set u_z < 0 by any path. Its direction is "pitch" (a somersault over head or
  tail) when the saddle lies further from the start in pitch than in roll, else "roll" (to one side).
- *pitch-wise* and *roll-wise*: the same, with the path kept in the sector ``|d roll| <= |d pitch|`` (resp.
  ``|d pitch| <= |d roll|``) around the start, as the lab's rays in the pitch-roll plane are. Without the sector a
  "pitch-wise" path could roll over the side saddle first and walk to the head along the side.
- *escape*: reach any other grid local minimum (another basin), the start's own orientation excepted (its twin
  on the double cover and its plateau).

The grid is a torus: both axes wrap and the duplicate +180 row and column are not stored, so they cannot create
false paths. The rows p = +-90 deg are one orientation each; their energies are equal to the last bit (exact
cosines), so moving along them is free. 8-connectivity by default (4 on request); ties pop in cell order, so
results do not depend on heap order.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from geometry.errors import UsageError
from geometry.frames import canonical_pitch_roll_deg, up_vector
from landscape.barriers import _flood_kernels
from landscape.barriers._base import Barrier, Exit
from landscape.energy import Landscape
from landscape.grid import wrap_deg


def _path(parent: NDArray[np.int64], cell: int, n: int, angles: NDArray[np.float64]) -> NDArray[np.float64]:
    cells = _flood_kernels.tree_path(parent, cell)
    ij = np.stack([cells // n, cells % n], axis=1)
    # unwrap so the path is continuous in degrees
    step = angles[1] - angles[0]
    deg = angles[ij].astype(np.float64)
    jumps = np.diff(ij, axis=0)
    jumps = np.where(jumps > 1, jumps - n, np.where(jumps < -1, jumps + n, jumps))
    deg[1:] = deg[0] + np.cumsum(jumps * step, axis=0)
    return deg


def _direction(start_deg: NDArray[np.float64], saddle_deg: NDArray[np.float64]) -> str:
    dp, dr = np.abs(wrap_deg(saddle_deg - start_deg))
    return "pitch" if dp >= dr else "roll"


def _exit(
    landscape: Landscape, level: float, cell: int, parent, e_start: float, kind: str | None
) -> Exit | None:
    if cell < 0:
        return None
    n = len(landscape.angles_deg)
    path = _path(parent, cell, n, landscape.angles_deg)
    ij = np.round((path + 180) / landscape.step_deg).astype(np.int64) % n  # round half to even, as round()
    e_path = landscape.energy_j[ij[:, 0], ij[:, 1]]
    k = int(np.argmax(e_path))
    sp, sr = canonical_pitch_roll_deg(*path[k])
    direction = kind or _direction(path[0], path[k])
    return Exit(float(level - e_start), sp, sr, direction, path)


def grid_barrier(landscape: Landscape, start: tuple[int, int], *, connectivity: int = 8) -> Barrier:
    """Righting, pitch-wise, roll-wise and escape barriers from a start cell.

    Parameters
    ----------
    landscape : Landscape
        Energy on the torus.
    start : (int, int)
        Start cell (i, j), usually a grid minimum.
    connectivity : {8, 4}
        Grid neighbours.

    Returns
    -------
    Barrier

    Examples
    --------
    >>> import trimesh
    >>> from geometry import Robot
    >>> from landscape.energy import energy_landscape
    >>> cube = Robot.from_trimesh(trimesh.creation.box(extents=(2.0, 2.0, 2.0)), mass_kg=1.0)
    >>> ls = energy_landscape(cube.pose(), step_deg=1.0, g_m_s2=1.0)
    >>> b = grid_barrier(ls, (180, 180))
    >>> round(b.righting.barrier_j, 6), round(float(np.sqrt(2)) - 1, 6)
    (0.414214, 0.414214)
    """
    if connectivity not in (4, 8):
        raise UsageError(f"connectivity must be 4 or 8; got {connectivity!r}")
    n = len(landscape.angles_deg)
    e = np.ascontiguousarray(landscape.energy_j)
    i0, j0 = start[0] % n, start[1] % n
    s = i0 * n + j0
    e_start = float(e[i0, j0])
    span = float(e.max() - e.min())
    tol = 1e-9 * span + 1e-15
    u = up_vector(np.deg2rad(landscape.angles_deg)[:, None], np.deg2rad(landscape.angles_deg)[None, :])
    upright = u[..., 2] < 0
    target = np.ascontiguousarray(upright.ravel().astype(np.int8))
    u0 = u[i0, j0]
    same = (u @ u0 > np.cos(np.deg2rad(2.5 * landscape.step_deg))).ravel()
    is_min = _flood_kernels.local_minima(e, tol)
    none = np.zeros(n * n, dtype=np.bool_)
    if upright[i0, j0]:
        a0 = landscape.angles_deg
        zero = Exit(0.0, *canonical_pitch_roll_deg(a0[i0], a0[j0]), "roll", np.array([[a0[i0], a0[j0]]]))
        righting = pitch = roll = zero
    else:
        levels, cells, parent = _flood_kernels.flood(
            e, s, target, none, is_min, same, tol, connectivity, False
        )
        righting = _exit(landscape, levels[0], int(cells[0]), parent, e_start, None)
        d = np.abs(wrap_deg(landscape.angles_deg - landscape.angles_deg[i0]))[:, None]
        dr = np.abs(wrap_deg(landscape.angles_deg - landscape.angles_deg[j0]))[None, :]
        out = []
        for kind, outside in (("pitch", dr > d), ("roll", d > dr)):
            outside = np.ascontiguousarray(outside.ravel())
            outside[s] = False
            levels, cells, parent = _flood_kernels.flood(
                e, s, target, outside, is_min, same, tol, connectivity, False
            )
            out.append(_exit(landscape, levels[0], int(cells[0]), parent, e_start, kind))
        pitch, roll = out
    levels, cells, parent = _flood_kernels.flood(
        e, s, np.zeros(n * n, dtype=np.int8), none, is_min, same, tol, connectivity, True
    )
    escape = _exit(landscape, levels[2], int(cells[2]), parent, e_start, None)
    return Barrier(righting, pitch, roll, escape)


SECTORS = True


def solve(
    pose,
    landscape: Landscape,
    start_deg: tuple[float, float],
    *,
    step_deg: float,
    connectivity: int,
    g_m_s2: float,
):
    """The registry's entry (:mod:`landscape.barriers`): the grid minimum nearest ``start_deg`` and its
    barriers on ``landscape``."""
    from landscape.minima import as_minimum, grid_minimum

    cell = grid_minimum(landscape, *start_deg)
    return as_minimum(landscape, *cell), grid_barrier(landscape, cell, connectivity=connectivity)
