"""Start states: grid minima by steepest descent, and the metastable state by quasi-static continuation.

The energy of a body on flat ground depends only on its convex hull, and a local minimum over orientation is
a hull face the CoM projects strictly inside (landscape/exact.py). Quasi-static rolling from an orientation is
therefore computed exactly on the point set, without a grid or a hull (:func:`rest_face`): the body pivots on
its lowest point, rolls on its lowest edge, or rests on or tips over its lowest face, each move in closed form
until a new point touches the ground. It never crosses a ridge, so a start at a strict minimum stays there.

The continuation along a joint path follows the face the body rests on: at each joint step it keeps the same
points (the face moves with the links) as long as they still bound the hull from below and hold the CoM
strictly inside, and rolls again only where that fails.

The rolling and the whole continuation run in compiled kernels (``landscape/_kernels.py``: ``rest``,
``still_rests``, ``follow_path``, the points posed per step from each part's link-frame hull vertices); the NumPy
functions here (``_rest``, ``_still_rests``, :func:`_follow_minimum_numpy`) are their reference, matched move by
move in tests/landscape/test_rolling_kernels.py.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from geometry import Pose, Robot
from geometry.errors import UsageError
from geometry.frames import canonical_pitch_roll_deg, pitch_roll_from_up, up_vector

from . import _kernels
from .energy import G_M_S2, Landscape, height_at
from .grid import nearest_cell

CONTINUATION_STEP_DEG = 1.0  # joint-angle increment of the quasi-static continuation
LENGTH_RTOL = 1e-9  # lengths below this times the body size count as zero (the descent; the exact barriers merge at their own)
_PATTERN_STEPS_DEG = (2.0, 1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125)
_DIRS = np.array([(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)], dtype=np.float64)
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
def _cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """a x b for 3-vectors (np.cross costs ten times more on single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _basis(u: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Two unit vectors spanning the plane normal to u (deterministic)."""
    a = np.zeros(3)
    a[int(np.argmin(np.abs(u)))] = 1.0
    e1 = _cross(u, a)
    e1 /= np.linalg.norm(e1)
    return e1, _cross(u, e1)


def _first_touch(d: NDArray[np.float64], k: int, u: NDArray[np.float64], t: NDArray[np.float64]) -> float:
    """Smallest rotation s > 0 of u toward t (about a line through point k) at which another point is lowest.

    Point j reaches point k's height where ``(d_j - d_k).(cos s u + sin s t) = 0``.
    """
    diff = d - d[k]
    s = np.mod(np.arctan2(diff @ t, diff @ u) - np.pi / 2, 2 * np.pi)
    s[s < 1e-12] = np.inf
    return float(s.min())


def _rotate(u: NDArray[np.float64], t: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    out = np.cos(s) * u + np.sin(s) * t
    return out / np.linalg.norm(out)


def _convex_polygon(xy: NDArray[np.float64]) -> NDArray[np.int64]:
    """Counter-clockwise convex hull of 2-D points (monotone chain), indices; collinear points dropped."""
    order = np.lexsort((xy[:, 1], xy[:, 0]))

    def half(idx):
        out: list[int] = []
        for i in idx:
            while len(out) >= 2:
                o, a = xy[out[-2]], xy[out[-1]]
                if (a[0] - o[0]) * (xy[i][1] - o[1]) - (a[1] - o[1]) * (xy[i][0] - o[0]) > 0:
                    break
                out.pop()
            out.append(int(i))
        return out

    lower, upper = half(order), half(order[::-1])
    return np.array(lower[:-1] + upper[:-1], dtype=np.int64)


def _contact(d: NDArray[np.float64], u: NDArray[np.float64], tol_m: float):
    """The lowest points at u and their shape on the ground.

    Returns ``(active, xy, poly)``: indices of the points within ``tol_m`` of the lowest, their positions in the
    ground plane relative to the CoM's projection (m), and the counter-clockwise hull of those positions as
    indices into ``active`` (1 point, 2 for a segment, >= 3 for a polygon).
    """
    hv = d @ u
    active = np.flatnonzero(hv >= hv.max() - tol_m)
    e1, e2 = _basis(u)
    xy = -np.stack([d[active] @ e1, d[active] @ e2], axis=1)
    if len(active) == 1:
        return active, xy, np.zeros(1, dtype=np.int64)
    i = int(np.argmin(xy[:, 0] + xy[:, 1] * 1e-3))
    r = xy - xy[i]
    j = int(np.argmax(r[:, 0] ** 2 + r[:, 1] ** 2))
    length = float(np.hypot(*r[j]))
    if length <= tol_m:  # one point
        return active, xy, np.array([i], dtype=np.int64)
    along = r @ r[j] / length
    off = (r[:, 0] * r[j, 1] - r[:, 1] * r[j, 0]) / length
    if np.abs(off).max() <= tol_m:  # collinear: a segment between the extremes
        return active, xy, np.array([int(np.argmin(along)), int(np.argmax(along))], dtype=np.int64)
    return active, xy, _convex_polygon(xy)


def _polygon_margin(xy: NDArray[np.float64], poly: NDArray[np.int64]) -> tuple[float, int, float]:
    """Signed distance of the origin inside a CCW polygon (m), the nearest edge, and where along it (0..1)."""
    a = xy[poly]
    b = np.concatenate([a[1:], a[:1]])
    e = b - a
    length = np.linalg.norm(e, axis=1)
    inside = (e[:, 0] * (-a[:, 1]) - e[:, 1] * (-a[:, 0])) / length  # cross(e, 0 - a) / |e|
    s = np.clip(-np.einsum("ij,ij->i", a, e) / length**2, 0.0, 1.0)
    dist = np.linalg.norm(a + s[:, None] * e, axis=1)
    k = int(np.lexsort((np.arange(len(poly)), dist))[0])
    return float(inside.min()), k, float(s[k])


def _roll_step(d, u, tol_m):
    """One quasi-static move from u. Returns (new u, None) or (u, face point indices) when at rest."""
    active, xy, poly = _contact(d, u, tol_m)
    if len(poly) >= 3:
        margin, k, s = _polygon_margin(xy, poly)
        if margin > tol_m:
            return u, active[poly]
        length = np.linalg.norm(xy[poly[(k + 1) % len(poly)]] - xy[poly[k]])
        if s * length <= tol_m:
            return _pivot(d, int(active[poly[k]]), u), None
        if (1.0 - s) * length <= tol_m:
            return _pivot(d, int(active[poly[(k + 1) % len(poly)]]), u), None
        return _roll_edge(d, int(active[poly[k]]), int(active[poly[(k + 1) % len(poly)]]), u, tol_m), None
    if len(poly) == 2:
        return _roll_edge(d, int(active[poly[0]]), int(active[poly[1]]), u, tol_m), None
    return _pivot(d, int(active[poly[0]]), u), None


def _pivot(d, k, u):
    """Tip about point k: steepest descent of d_k.u, to where another point touches (landscape/exact.py)."""
    dk = d[k]
    grad = dk - (dk @ u) * u
    n = np.linalg.norm(grad)
    if n < 1e-15 * np.linalg.norm(dk):  # balanced on the point: fall to a fixed side
        t = _basis(u)[0]
    else:
        t = -grad / n
    s_end = np.pi - np.arccos(np.clip(dk @ u / np.linalg.norm(dk), -1.0, 1.0))
    return _rotate(u, t, min(_first_touch(d, k, u, t), s_end))


def _roll_edge(d, a, b, u, tol_m):
    """Roll about the line through points a and b (both lowest), or pivot on an end the CoM lies beyond."""
    e = d[a] - d[b]  # p_b - p_a
    length = np.linalg.norm(e)
    e = e / length
    foot = d[a] @ e  # CoM foot on the line, m from a toward b
    if foot < -tol_m:
        return _pivot(d, a, u)
    if foot > length + tol_m:
        return _pivot(d, b, u)
    w = d[a] - foot * e  # from the line to the CoM
    t = _cross(e, u)
    t /= np.linalg.norm(t)
    if w @ t > 0:
        t = -t
    elif w @ t == 0.0:  # balanced on the edge: fall to the side of the lower index
        t = t if a < b else -t
    return _rotate(u, t, _first_touch(d, a, u, t))


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
    u, face, settled = _kernels.rest(d, u, tol_m, _MAX_MOVES)
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


def _rest(d, u, tol_m):
    """NumPy reference of :func:`rest_face` (and of ``_kernels.rest``) on the vectors d = c - p."""
    for _ in range(_MAX_MOVES):
        u, face = _roll_step(d, u, tol_m)
        if face is not None:
            return _face_up(d, face, u), face
    raise RuntimeError(NOT_SETTLED)


def _face_up(d, face, u_hint):
    """The up-direction resting on the plane through a face's corners (the one nearest u_hint)."""
    q = d[face] - d[face[0]]
    q2 = np.concatenate([q[1:], q[:1]])
    n = np.array(
        [
            q[:, 1] @ q2[:, 2] - q[:, 2] @ q2[:, 1],
            q[:, 2] @ q2[:, 0] - q[:, 0] @ q2[:, 2],
            q[:, 0] @ q2[:, 1] - q[:, 1] @ q2[:, 0],
        ]
    )
    n /= np.linalg.norm(n)
    return n if n @ u_hint >= 0 else -n


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


def _pattern_descent(pose: Pose, pitch_deg: float, roll_deg: float) -> tuple[float, float]:
    """The former start search, kept as the benchmark baseline: pattern search of h to 0.03 deg.

    Moves to the lowest of 8 neighbours at a shrinking step from 2 deg, so it can jump a ridge narrower
    than the step (issue #12).
    """
    p, r = float(pitch_deg), float(roll_deg)
    h = float(height_at(pose, p, r))
    for step in _PATTERN_STEPS_DEG:
        while True:
            cand = np.array([p, r]) + step * _DIRS
            hc = height_at(pose, cand[:, 0], cand[:, 1])
            k = int(np.argmin(hc))
            if hc[k] < h - 1e-15:
                p, r, h = float(cand[k, 0]), float(cand[k, 1]), float(hc[k])
            else:
                break
    return canonical_pitch_roll_deg(p, r)


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

    ``d_at`` gives c - p for every part's hull point at a step (the NumPy reference); the kernel path takes the
    link-frame points, their part index and the per-step rotations, translations and CoM instead.
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


def _still_rests(d, face, u_prev, tol_m):
    """The up-direction resting on ``face`` if it is still a strict minimum reached from u_prev, else None.

    The face (the same points, moved with their links) must bound the hull from below, hold the CoM's
    projection strictly inside, and the body at the previous orientation must stand on one of its points.
    NumPy reference of ``_kernels.still_rests``.
    """
    u = _face_up(d, face, u_prev)
    hv = d @ u
    h = hv[face]
    if h.max() - h.min() > tol_m:  # no longer flat
        return None, None
    top = hv.max()
    if top > h.max() + tol_m:  # another point pokes below the face's plane
        return None, None
    active, xy, poly = _contact(d, u, tol_m)
    if len(poly) < 3 or _polygon_margin(xy, poly)[0] <= tol_m:
        return None, None
    face = active[poly]
    lowest = np.flatnonzero(d @ u_prev >= (d @ u_prev).max() - tol_m)
    if not np.isin(lowest, face).any():
        return None, None
    return u, face


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
    strict minimum (``_kernels.still_rests``), and rolls again from where it was only where the face is lost.
    Returns the canonical (pitch, roll) at every point of the path, degrees. The whole walk runs in one
    compiled kernel (``_kernels.follow_path``); :func:`_follow_minimum_numpy` is its NumPy reference.
    """
    if not path_deg:
        return []
    if not (np.isfinite(pitch_deg) and np.isfinite(roll_deg)):
        raise UsageError(f"start pitch and roll must be finite degrees; got ({pitch_deg!r}, {roll_deg!r})")
    bodies = _PathBodies(robot, path_deg)
    u = up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    if bodies.fast:
        ups, settled = _kernels.follow_path(
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
            ok, u_new, f_new = _kernels.still_rests(d, face, u, tol_m)
            if ok:
                u, face = u_new, f_new
        if not ok:
            u, face, settled = _kernels.rest(d, u, tol_m, _MAX_MOVES)
            if not settled:
                raise RuntimeError(NOT_SETTLED)
        ups[i] = u
    return _degs(ups)


def _follow_minimum_numpy(
    robot: Robot, path_deg: list[tuple[float, float]], *, pitch_deg: float = 0.0, roll_deg: float = 0.0
) -> list[tuple[float, float]]:
    """NumPy reference of :func:`follow_minimum` (the code before the kernels, issue #12): same moves, same
    tolerances, one NumPy call per test."""
    if not path_deg:
        return []
    bodies = _PathBodies(robot, path_deg)
    u = up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    face = None
    out = []
    for i in range(len(path_deg)):
        d = bodies.d_at(i)
        tol_m = bodies.tol_at(d)
        new = (None, None) if face is None else _still_rests(d, face, u, tol_m)
        if new[0] is None:
            new = _rest(d, u, tol_m)
        u, face = new
        out.append(_deg(u))
    return out


def _follow_minimum_grid(
    robot: Robot, path_deg: list[tuple[float, float]], *, pitch_deg: float = 0.0, roll_deg: float = 0.0
) -> list[tuple[float, float]]:
    """The former continuation (benchmark baseline): pose the robot and pattern-search at every step."""
    out = []
    p, r = pitch_deg, roll_deg
    for tw, tl in path_deg:
        p, r = _pattern_descent(robot.pose(tw, tl), p, r)
        out.append((p, r))
    return out


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


def metastable_orientation(
    robot: Robot, theta_w_deg: float, theta_l_deg: float, *, baseline: bool = False
) -> tuple[float, float]:
    """Where the robot rests after opening its wings slowly from rest on its back (pitch, roll in degrees).

    Starts at pitch = roll = 0 with theta_w = theta_l = 0, and follows the minimum as theta_w, then theta_l,
    grow in 1 deg steps (:func:`follow_minimum`). A robot without joints rolls down from pitch = roll = 0.
    ``baseline=True`` runs the former grid pattern search at every step instead (for benchmarks).
    """
    if not robot.has_joints:
        pose = robot.pose()
        return _pattern_descent(pose, 0.0, 0.0) if baseline else local_descent(pose, 0.0, 0.0)
    robot.joint_values_rad(theta_w_deg, theta_l_deg)  # validate before the long walk
    follow = _follow_minimum_grid if baseline else follow_minimum
    return follow(robot, opening_path(theta_w_deg, theta_l_deg))[-1]


def grid_minimum(landscape: Landscape, pitch_deg: float, roll_deg: float) -> tuple[int, int]:
    """The grid cell reached by 8-neighbour steepest descent from the cell nearest an orientation."""
    i, j = nearest_cell(pitch_deg, roll_deg, landscape.step_deg)
    i, j = _kernels.descend(landscape.energy_j, i, j)
    return int(i), int(j)


def as_minimum(landscape: Landscape, i: int, j: int, g_m_s2: float = G_M_S2) -> Minimum:
    e = landscape.at(i, j)
    p, r = canonical_pitch_roll_deg(landscape.angles_deg[i], landscape.angles_deg[j])
    return Minimum(p, r, e, e / (landscape.mass_kg * landscape.g_m_s2))
