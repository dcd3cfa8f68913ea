"""Potential energy of a rigid body on flat ground over body pitch and roll.

E(p, r) = m g h(p, r), h = u.c - min_k u.v_k: the CoM height above the lowest point. Only the convex hull
decides the lowest point, so ``h(u) = max_k (c - v_k).u`` over hull vertices, the support function of the hull
seen from the CoM. The kernel walks the hull's vertex graph from the previous grid cell's best vertex, so each
orientation costs a few dot products and no orientations x vertices array is ever formed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from geometry import Pose
from geometry.errors import UsageError
from geometry.frames import cos_sin, up_vector

from . import _energy_kernels
from .grid import DEFAULT_STEP_DEG, cells_per_turn, torus_angles_deg

G_M_S2 = 9.81


@dataclass(frozen=True)
class Landscape:
    """Energy on the pitch-roll torus.

    Attributes
    ----------
    step_deg : float
        Grid step, degrees.
    angles_deg : ndarray of shape (N,)
        Distinct angles -180 .. 180 - step, degrees, for both axes (the torus; the +180 row and column repeat
        the -180 ones and are only added on output, by :meth:`inclusive`).
    energy_j : ndarray of shape (N, N)
        E[i, j] at pitch angles_deg[i], roll angles_deg[j], J.
    mass_kg, g_m_s2 : float
        Mass and gravity used.
    """

    step_deg: float
    angles_deg: NDArray[np.float64]
    energy_j: NDArray[np.float64]
    mass_kg: float
    g_m_s2: float

    @property
    def height_m(self) -> NDArray[np.float64]:
        return self.energy_j / (self.mass_kg * self.g_m_s2)

    def inclusive(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Angles -180..180 inclusive (N + 1) and the energy with the wrap row and column repeated, J."""
        a = np.append(self.angles_deg, 180.0)
        e = np.concatenate([self.energy_j, self.energy_j[:1]], axis=0)
        e = np.concatenate([e, e[:, :1]], axis=1)
        return a, e

    def at(self, i: int, j: int) -> float:
        return float(self.energy_j[i % len(self.angles_deg), j % len(self.angles_deg)])


def _support_inputs(pose: Pose):
    d = np.ascontiguousarray(pose.com_m[None, :] - pose.hull.vertices_m, dtype=np.float64)
    return d, pose.hull.neighbor_ptr, pose.hull.neighbor_idx


def energy_landscape(pose: Pose, *, step_deg: float = DEFAULT_STEP_DEG, g_m_s2: float = G_M_S2) -> Landscape:
    """Potential energy of the posed body resting on flat ground, over the pitch-roll torus.

    Parameters
    ----------
    pose : geometry.Pose
        The rigid body (hull vertices and CoM in the body frame, m; mass, kg).
    step_deg : float
        Grid step, degrees; must divide 360.
    g_m_s2 : float
        Gravitational acceleration, m/s^2.

    Returns
    -------
    Landscape
        ``energy_j[i, j] = m g h`` at pitch ``angles_deg[i]``, roll ``angles_deg[j]``.

    Raises
    ------
    GridError
        If the step does not divide 360.

    Examples
    --------
    >>> import trimesh
    >>> from geometry import Robot
    >>> cube = Robot.from_trimesh(trimesh.creation.box(extents=(2.0, 2.0, 2.0)), mass_kg=1.0)
    >>> ls = energy_landscape(cube.pose(), step_deg=45.0, g_m_s2=1.0)
    >>> ls.energy_j[4, 4].round(4), ls.energy_j[5, 4].round(4)   # pitch 0 and 45 at roll 0
    (np.float64(1.0), np.float64(1.4142))
    """
    cells_per_turn(step_deg)
    angles = torus_angles_deg(step_deg)
    c, s = cos_sin(np.deg2rad(angles))
    d, ptr, idx = _support_inputs(pose)
    h = _energy_kernels.support_grid(d, ptr, idx, c, s, c, s)
    return Landscape(float(step_deg), angles, pose.mass_kg * g_m_s2 * h, pose.mass_kg, g_m_s2)


def height_at(pose: Pose, pitch_deg: ArrayLike, roll_deg: ArrayLike) -> NDArray[np.float64]:
    """CoM height above the lowest hull point at arbitrary orientations, m (broadcast shapes)."""
    p = np.asarray(pitch_deg, dtype=np.float64)
    r = np.asarray(roll_deg, dtype=np.float64)
    if not (np.isfinite(p).all() and np.isfinite(r).all()):
        raise UsageError("pitch and roll must be finite degrees")
    u = up_vector(np.deg2rad(p), np.deg2rad(r))
    if "hull" in pose.__dict__:  # hull already built: walk it
        d, ptr, idx = _support_inputs(pose)
        return _energy_kernels.support_points(d, ptr, idx, np.ascontiguousarray(u.reshape(-1, 3))).reshape(
            u.shape[:-1]
        )
    d = pose.com_m[None, :] - pose.hull_points_m  # few orientations: every part-hull vertex is cheaper
    return (u.reshape(-1, 3) @ d.T).max(axis=1).reshape(u.shape[:-1])


def brute_force_landscape(
    points_m: ArrayLike,
    com_m: ArrayLike,
    mass_kg: float,
    *,
    step_deg: float = DEFAULT_STEP_DEG,
    g_m_s2: float = G_M_S2,
    rows_per_chunk: int = 8,
) -> NDArray[np.float64]:
    """The lab's method: every mesh vertex against every grid orientation, vectorised NumPy.

    The reference for the fast kernel and the baseline of ``landscape bench``. Chunked by pitch rows only so
    that it fits in memory; it still forms (rows x N x vertices) arrays.

    Returns
    -------
    energy_j : ndarray of shape (N, N)
    """
    pts = np.asarray(points_m, dtype=np.float64)
    c = np.asarray(com_m, dtype=np.float64)
    angles = torus_angles_deg(step_deg)
    pr = np.deg2rad(angles)
    cp, sp = np.cos(pr), np.sin(pr)
    out = np.zeros((len(angles), len(angles)))
    for i0 in range(0, len(angles), rows_per_chunk):
        sl = slice(i0, i0 + rows_per_chunk)
        u = np.stack(
            np.broadcast_arrays(-sp[sl, None], cp[sl, None] * sp[None, :], cp[sl, None] * cp[None, :]),
            axis=-1,
        )
        low = (u @ pts.T).min(axis=-1)
        out[sl] = u @ c - low
    return mass_kg * g_m_s2 * out
