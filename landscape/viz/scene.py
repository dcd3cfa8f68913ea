"""Laying a computation out for the renderers: torus paths broken where they wrap, the twin of an orientation
nearest a drawn path, the robot's part meshes in the world frame. Plain arrays in, plain arrays out."""

from __future__ import annotations

import numpy as np
import trimesh
from numpy.typing import NDArray
from scipy.spatial import QhullError

from geometry import Pose
from geometry.frames import body_to_world


def wrapped_path_deg(path_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """A continuous (unwrapped) torus path moved into [-180, 180), with a NaN row wherever it wraps.

    Examples
    --------
    >>> wrapped_path_deg(np.array([[170.0, 0.0], [179.0, 0.0], [188.0, 0.0]])).tolist()
    [[170.0, 0.0], [179.0, 0.0], [nan, nan], [-172.0, 0.0]]
    """
    w = (np.asarray(path_deg, dtype=np.float64).reshape(-1, 2) + 180.0) % 360.0 - 180.0
    breaks = np.flatnonzero((np.abs(np.diff(w, axis=0)) > 180.0).any(axis=1)) + 1
    return np.insert(w, breaks, np.nan, axis=0)


def nearest_twin_deg(pitch_deg: float, roll_deg: float, near_deg: NDArray[np.float64]) -> tuple[float, float]:
    """Of the two torus points of one orientation, (p, r) and (180 - p, r + 180), the one nearer ``near_deg``.

    The landscape over the full pitch-roll square shows every orientation twice; a mark belongs on the copy
    the drawn path passes.

    Examples
    --------
    >>> nearest_twin_deg(70.0, 10.0, np.array([[100.0, -170.0]]))
    (110.0, -170.0)
    """
    near = np.asarray(near_deg, dtype=np.float64).reshape(-1, 2)
    near = near[np.isfinite(near).all(axis=1)]
    twins = np.array([[pitch_deg, roll_deg], [180.0 - pitch_deg, roll_deg + 180.0]])
    twins = (twins + 180.0) % 360.0 - 180.0
    if not len(near):
        return float(twins[0, 0]), float(twins[0, 1])
    d = (np.abs(twins[:, None, :] - near[None, :, :]) + 180.0) % 360.0 - 180.0
    k = int(np.argmin(np.linalg.norm(d, axis=-1).min(axis=1)))
    return float(twins[k, 0]), float(twins[k, 1])


def posed_meshes_world(pose: Pose, pitch_deg: float, roll_deg: float
                       ) -> tuple[list[tuple[NDArray[np.float64], NDArray[np.int64]]], NDArray[np.float64]]:
    """The posed robot's part meshes resting on the ground at body pitch and roll.

    Each part is drawn as the convex hull of its geometry (the hull is what decides the contact). Parts are
    placed by their link transforms, rotated by ``body_to_world(p, r)`` and shifted so the lowest point is
    at z = 0 and the CoM above the origin.

    Returns
    -------
    meshes : list of (vertices_m (V, 3), faces (F, 3))
        World frame, m.
    com_m : ndarray of shape (3,)
        CoM in the world frame, m; ``com_m[2]`` is the CoM height above the ground.
    """
    rot = body_to_world(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    meshes = []
    for part in pose.parts:
        if len(part.hull_link_m) < 4:
            continue
        try:
            hull = trimesh.convex.convex_hull(part.hull_link_m)
        except QhullError:  # flat or degenerate part: nothing to draw
            continue
        T = pose.link_transforms[part.link]
        v = (np.asarray(hull.vertices) @ T[:3, :3].T + T[:3, 3]) @ rot.T
        meshes.append((v, np.asarray(hull.faces, dtype=np.int64)))
    com = rot @ pose.com_m
    low = min(float(v[:, 2].min()) for v, _ in meshes)
    shift = np.array([com[0], com[1], low])
    return [(v - shift, f) for v, f in meshes], com - shift


# ------------------------------------------------------------------------------------------------ command
