"""Start states: grid minima by steepest descent, and the metastable state by quasi-static continuation.

The energy of a body on flat ground depends only on its convex hull, and a local minimum over orientation is
a hull face the CoM projects strictly inside (landscape/barriers/exact.py). Quasi-static rolling from an
orientation is therefore computed exactly on the point set, without a grid or a hull (:func:`rest_face`): the
body pivots on its lowest point, rolls on its lowest edge, or rests on or tips over its lowest face, each move in
closed form until a new point touches the ground. It never crosses a ridge, so a start at a strict minimum stays there.

The continuation along a joint path follows the face the body rests on: at each joint step it keeps the same
points (the face moves with the links) as long as they still bound the hull from below and hold the CoM
strictly inside, and rolls again only where that fails.

The rolling and the whole continuation run in compiled kernels (``landscape/_minima_kernels.py``: ``rest``,
``still_rests``, ``follow_path``, the points posed per step from each part's link-frame hull vertices), matched
move by move against their NumPy reference in tests/landscape/test_minima_kernels.py.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from geometry import Pose, Robot
from geometry.errors import UsageError
from geometry.frames import canonical_pitch_roll_deg, pitch_roll_from_up, up_vector

from . import _minima_kernels
from .energy import G_M_S2, Landscape
from .grid import nearest_cell

CONTINUATION_STEP_DEG = 1.0  # joint-angle increment of the quasi-static continuation
LENGTH_RTOL = 1e-9  # lengths below this times the body size count as zero (the descent; the exact barriers merge at their own)
_MAX_MOVES = 10_000


@dataclass(frozen=True)
class Minimum:
    """A local minimum of the landscape.

    Attributes
    ----------
    pitch_deg, roll_deg : float
        Orientation, degrees, on the branch ``|pitch| <= 90``.
    energy_j, height_m : float
        Potential energy m g h, J, and CoM height h, m.
    """

    pitch_deg: float
    roll_deg: float
    energy_j: float
    height_m: float


# --------------------------------------------------------------------------------------------- rolling
def rest_face(points_m, com_m, up, *, tol_m: float | None = None):
    """Quasi-static rolling on flat ground from an up-direction to the face the body comes to rest on.

    Parameters
    ----------
    points_m : array_like of shape (K, 3)
        Points whose convex hull is the body (hull vertices or more), body frame, m.
    com_m : array_like of shape (3,)
        CoM, body frame, m; inside the hull.
    up : array_like of shape (3,)
        Start up-direction (world up in the body frame, geometry/frames.py).
    tol_m : float, optional
        Length tolerance, m; default ``LENGTH_RTOL`` times the points' extent.

    Returns
    -------
    up : ndarray of shape (3,)
        The up-direction at rest: minus the face's outward normal.
    face : ndarray of int64
        Indices of the face's corners in ``points_m`` (counter-clockwise seen from the CoM).

    Raises
    ------
    RuntimeError
        If rolling does not settle (a body with the CoM outside the hull).

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box(extents=(4.0, 2.0, 1.0))
    >>> u, face = rest_face(box.vertices, [0.0, 0.0, 0.0], up_vector(0.3, -0.2))
    >>> u.round(12).tolist(), len(face)
    ([0.0, 0.0, 1.0], 4)
    """
    d, u, tol_m = _rest_inputs(points_m, com_m, up, tol_m)
    u, face, settled = _minima_kernels.rest(d, u, tol_m, _MAX_MOVES)
    if not settled:
        raise RuntimeError(NOT_SETTLED)
    return u, face


NOT_SETTLED = "rolling down did not settle; is the CoM inside the hull? please report this body"


def _rest_inputs(points_m, com_m, up, tol_m):
    """Checked kernel inputs of :func:`rest_face`: d = c - p (K, 3), unit up, tolerance, m."""
    pts = np.asarray(points_m, dtype=np.float64).reshape(-1, 3)
    c = np.asarray(com_m, dtype=np.float64).reshape(-1)
    u = np.asarray(up, dtype=np.float64).reshape(-1)
    if len(pts) == 0 or c.shape != (3,) or u.shape != (3,):
        raise UsageError(
            f"rest_face needs points of shape (K >= 1, 3), a CoM and an up-direction of 3 numbers; got points "
            f"{np.shape(points_m)}, com {np.shape(com_m)}, up {np.shape(up)}"
        )
    if (
        not (np.isfinite(pts).all() and np.isfinite(c).all() and np.isfinite(u).all())
        or not np.linalg.norm(u) > 0
    ):
        raise UsageError(
            "rest_face needs finite points, CoM and a non-zero finite up-direction; fix the input"
        )
    d = np.ascontiguousarray(c[None, :] - pts)
    if tol_m is None:
        tol_m = LENGTH_RTOL * max(float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0))), 1e-300)
    return d, u / np.linalg.norm(u), float(tol_m)


def _deg(u: NDArray[np.float64]) -> tuple[float, float]:
    p, r = pitch_roll_from_up(u[None, :])
    return canonical_pitch_roll_deg(float(np.rad2deg(p[0])), float(np.rad2deg(r[0])))


def _pose_points(pose: Pose) -> NDArray[np.float64]:
    return pose.hull.vertices_m if "hull" in pose.__dict__ else pose.hull_points_m


def local_descent(pose: Pose, pitch_deg: float, roll_deg: float) -> tuple[float, float]:
    """The minimum reached by quasi-static rolling from an orientation (canonical pitch, roll in degrees).

    Exact (:func:`rest_face`): a start at a strict minimum stays there; descent never crosses a ridge.
    """
    u, _ = rest_face(_pose_points(pose), pose.com_m, up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg)))
    return _deg(u)


# --------------------------------------------------------------------------------------------- continuation
def _joint_chains(robot: Robot):
    """Per part with hull points: the chain of (origin 4x4, axis, type, driver) from the base, or None.

    driver is "w" (theta_w), "l" (theta_l) or None (held at 0). None overall when a joint is of a kind this
    fast path does not model (mimic, planar, floating); the caller then poses the robot step by step.
    """
    wing, leg = set(robot.joint_map.wing), set(robot.joint_map.leg)
    chains = []
    for part in robot.parts:
        chain = []
        for j in robot.kinematic_chains()[part.link]:
            if j.mimic or j.type not in ("fixed", "revolute", "continuous", "prismatic"):
                return None
            driver = "w" if j.name in wing else "l" if j.name in leg else None
            chain.append((j.origin, j.axis / np.linalg.norm(j.axis), j.type, driver))
        chains.append(chain)
    return chains


def _batch_transforms(chains, tw_rad: NDArray[np.float64], tl_rad: NDArray[np.float64]):
    """Link-to-body transforms of every part at N joint settings: (N, parts, 4, 4)."""
    n = len(tw_rad)
    out = np.zeros((n, len(chains), 4, 4))
    for i, chain in enumerate(chains):
        T = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
        for origin, axis, kind, driver in chain:
            T = T @ origin
            if kind == "fixed" or driver is None:
                continue
            q = tw_rad if driver == "w" else tl_rad
            J = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
            if kind == "prismatic":
                J[:, :3, 3] = q[:, None] * axis
            else:  # Rodrigues
                K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
                s, c = np.sin(q)[:, None, None], np.cos(q)[:, None, None]
                J[:, :3, :3] = np.eye(3) + s * K + (1 - c) * (K @ K)
            T = T @ J
        out[:, i] = T
    return out


_ARRAYS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _robot_arrays(robot: Robot):
    """(chains, pts (K, 3), part_ptr (P + 1), mass_kg (P), com_link_m (P, 3)) of a robot, or None when
    :func:`_joint_chains` cannot model its joints; computed once per robot (its parts are immutable)."""
    hit = _ARRAYS.get(robot)
    if hit is not None and hit[0] is robot.parts:
        return hit[1]
    chains = _joint_chains(robot) if robot.has_joints else None
    out = None
    if chains is not None:
        parts = robot.parts
        pts = np.ascontiguousarray(
            np.concatenate([p.hull_link_m.reshape(-1, 3) for p in parts]), dtype=np.float64
        )
        ptr = np.zeros(len(parts) + 1, dtype=np.int64)
        np.cumsum([len(p.hull_link_m) for p in parts], out=ptr[1:])
        mass = np.array([p.mass.mass_kg for p in parts], dtype=np.float64)
        com_link = np.stack([np.asarray(p.mass.com_m, dtype=np.float64) for p in parts])
        out = (chains, pts, ptr, mass, com_link)
    _ARRAYS[robot] = (robot.parts, out)
    return out


class _PathBodies:
    """The posed body along a joint path: per-step link transforms and CoM in one batch (no per-step URDF posing).

    ``d_at`` gives c - p for every part's hull point at a step (for a robot the batch cannot pose, and for the
    NumPy reference in the tests); the kernel path takes the link-frame points, their part index and the per-step
    rotations, translations and CoM instead.
    """

    def __init__(self, robot: Robot, path_deg: list[tuple[float, float]]):
        self.robot = robot
        self.path = path_deg
        fixed = _robot_arrays(robot)
        self.fast = fixed is not None
        if not self.fast:
            return
        chains, self.pts, self.part_ptr, mass, com_link = fixed
        w, l_ = (np.deg2rad(np.array([x[i] for x in path_deg], dtype=np.float64)) for i in (0, 1))
        T = _batch_transforms(chains, w, l_)
        self.rot = np.ascontiguousarray(T[:, :, :3, :3])
        self.trans = np.ascontiguousarray(T[:, :, :3, 3])
        com = np.einsum("npij,pj->npi", self.rot, com_link) + self.trans
        self.com = np.ascontiguousarray(np.einsum("p,npi->ni", mass, com) / mass.sum())

    def d_at(self, i: int) -> NDArray[np.float64]:
        """c - p for every part's hull point at path step i, m."""
        if self.fast:
            R, t, ptr = self.rot[i], self.trans[i], self.part_ptr
            return np.ascontiguousarray(
                self.com[i][None, :]
                - np.concatenate([self.pts[ptr[k] : ptr[k + 1]] @ R[k].T + t[k] for k in range(len(ptr) - 1)])
            )
        pose = self.robot.pose(*self.path[i])
        return np.ascontiguousarray(pose.com_m[None, :] - pose.hull_points_m)

    @staticmethod
    def tol_at(d: NDArray[np.float64]) -> float:
        return LENGTH_RTOL * float(np.linalg.norm(d.max(axis=0) - d.min(axis=0)))


def _degs(ups: NDArray[np.float64]) -> list[tuple[float, float]]:
    """Canonical (pitch, roll) of up-directions (N, 3), degrees."""
    p, r = pitch_roll_from_up(ups)
    p, r = np.rad2deg(p), np.rad2deg(r)
    return [canonical_pitch_roll_deg(float(a), float(b)) for a, b in zip(p, r, strict=True)]


def follow_minimum(
    robot: Robot, path_deg: list[tuple[float, float]], *, pitch_deg: float = 0.0, roll_deg: float = 0.0
) -> list[tuple[float, float]]:
    """Quasi-static continuation: the face the body rests on at each (theta_w, theta_l) of a path.

    At the first point the body rolls from (pitch, roll); afterwards it keeps its face while that face stays a
    strict minimum (``_minima_kernels.still_rests``), and rolls again from where it was only where the face is
    lost. Returns the canonical (pitch, roll) at every point of the path, degrees. The whole walk runs in one
    compiled kernel (``_minima_kernels.follow_path``).
    """
    if not path_deg:
        return []
    if not (np.isfinite(pitch_deg) and np.isfinite(roll_deg)):
        raise UsageError(f"start pitch and roll must be finite degrees; got ({pitch_deg!r}, {roll_deg!r})")
    bodies = _PathBodies(robot, path_deg)
    u = up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    if bodies.fast:
        ups, settled = _minima_kernels.follow_path(
            bodies.pts, bodies.part_ptr, bodies.rot, bodies.trans, bodies.com, LENGTH_RTOL, u, _MAX_MOVES
        )
        if not settled:
            raise RuntimeError(NOT_SETTLED)
        return _degs(ups)
    ups = np.zeros((len(path_deg), 3))
    face = np.zeros(0, dtype=np.int64)
    for i in range(len(path_deg)):
        d = bodies.d_at(i)
        tol_m = bodies.tol_at(d)
        ok = False
        if len(face):
            ok, u_new, f_new = _minima_kernels.still_rests(d, face, u, tol_m)
            if ok:
                u, face = u_new, f_new
        if not ok:
            u, face, settled = _minima_kernels.rest(d, u, tol_m, _MAX_MOVES)
            if not settled:
                raise RuntimeError(NOT_SETTLED)
        ups[i] = u
    return _degs(ups)


def ramp_deg(a: float, b: float) -> list[float]:
    """Angles from a (excluded) to b (included) in steps of at most CONTINUATION_STEP_DEG; [] when a == b.

    Examples
    --------
    >>> ramp_deg(0.0, 2.5), ramp_deg(3.0, 3.0)
    ([0.8333333333333334, 1.6666666666666667, 2.5], [])
    """
    n = int(np.ceil(abs(b - a) / CONTINUATION_STEP_DEG))
    return [float(x) for x in np.linspace(a, b, n + 1)[1:]] if n else []


def opening_path(theta_w_deg: float, theta_l_deg: float) -> list[tuple[float, float]]:
    """Joint path of a slow opening from rest: theta_w from 0, then theta_l from 0, in <= 1 deg steps."""
    path = [(0.0, 0.0)]
    path += [(w, 0.0) for w in ramp_deg(0.0, theta_w_deg)]
    path += [(theta_w_deg, l_) for l_ in ramp_deg(0.0, theta_l_deg)]
    return path


def metastable_orientation(robot: Robot, theta_w_deg: float, theta_l_deg: float) -> tuple[float, float]:
    """Where the robot rests after opening its wings slowly from rest on its back (pitch, roll in degrees).

    Starts at pitch = roll = 0 with theta_w = theta_l = 0, and follows the minimum as theta_w, then theta_l,
    grow in 1 deg steps (:func:`follow_minimum`). A robot without joints rolls down from pitch = roll = 0.
    """
    if not robot.has_joints:
        return local_descent(robot.pose(), 0.0, 0.0)
    robot.joint_values_rad(theta_w_deg, theta_l_deg)  # validate before the long walk
    return follow_minimum(robot, opening_path(theta_w_deg, theta_l_deg))[-1]


def grid_minimum(landscape: Landscape, pitch_deg: float, roll_deg: float) -> tuple[int, int]:
    """The grid cell reached by 8-neighbour steepest descent from the cell nearest an orientation."""
    i, j = nearest_cell(pitch_deg, roll_deg, landscape.step_deg)
    i, j = _minima_kernels.descend(landscape.energy_j, i, j)
    return int(i), int(j)


def as_minimum(landscape: Landscape, i: int, j: int, g_m_s2: float = G_M_S2) -> Minimum:
    e = landscape.at(i, j)
    p, r = canonical_pitch_roll_deg(landscape.angles_deg[i], landscape.angles_deg[j])
    return Minimum(p, r, e, e / (landscape.mass_kg * landscape.g_m_s2))
