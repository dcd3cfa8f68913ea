"""One call from a robot and its joint angles to landscape, start minimum and barriers.

It is one concept, the call from a robot and its joint angles to a landscape and its barriers (one pose, a map
of poses, the start continuation), hence its length.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from geometry import Pose, Robot
from geometry.errors import UsageError
from geometry.frames import canonical_pitch_roll_deg, cos_sin

from . import _computation_kernels
from .barriers import DEFAULT_METHOD, Barrier, Exit
from .barriers import method as barrier_method
from .barriers.grid import _exit as _grid_exit
from .barriers.grid import grid_barrier
from .energy import G_M_S2, Landscape, _support_inputs, energy_landscape
from .grid import DEFAULT_STEP_DEG, cells_per_turn, nearest_cell, torus_angles_deg, wrap_deg
from .minima import (
    Minimum,
    follow_minimum,
    grid_minimum,
    local_descent,
    metastable_orientation,
    ramp_deg,
)


@dataclass(frozen=True)
class Computation:
    """Everything ``landscape compute`` reports for one robot pose.

    Attributes
    ----------
    theta_w_deg, theta_l_deg : float or None
        Joint angles, degrees (None for a single rigid mesh).
    step_deg : float
        Grid step, degrees.
    method : str
        Barrier method.
    mass_kg : float
        Total mass, kg.
    com_m : ndarray of shape (3,)
        CoM in the body frame, m.
    start_deg : (float, float)
        Orientation the start was sought from (the metastable continuation or the user's start), degrees.
    minimum : Minimum
        The start minimum on the grid.
    barrier : Barrier
        Righting, pitch-wise, roll-wise and escape exits.
    landscape : Landscape or None
        The pitch-roll grid (None when ``compute`` skipped it, ``landscape_grid=False``).
    timing_s : dict
        Wall time of each stage, s.
    """

    theta_w_deg: float | None
    theta_l_deg: float | None
    step_deg: float
    method: str
    mass_kg: float
    com_m: NDArray[np.float64]
    start_deg: tuple[float, float]
    minimum: Minimum
    barrier: Barrier
    landscape: Landscape = field(repr=False)
    pose: Pose = field(repr=False)
    timing_s: dict = field(default_factory=dict)


_WARM = []


def _in_sector(path_deg: NDArray[np.float64], kind: str) -> bool:
    """Whether a torus path stays in the sector |d roll| <= |d pitch| ("pitch") or the reverse ("roll")."""
    d = np.abs(wrap_deg(np.asarray(path_deg) - np.asarray(path_deg)[0]))
    return bool(np.all(d[:, 1] <= d[:, 0] + 1e-9) if kind == "pitch" else np.all(d[:, 0] <= d[:, 1] + 1e-9))


def warm_up() -> None:
    """Load the compiled kernels (from numba's cache) so that later timings measure only the work."""
    if _WARM:
        return
    corners = np.array([(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    cube = Pose(None, None, 1.0, np.zeros(3), corners, {}, ())  # a unit cube, built without trimesh
    ls = energy_landscape(cube, step_deg=90.0)
    grid_barrier(ls, grid_minimum(ls, 0.0, 0.0))
    grid = _SectorGrid(cube, 90.0, G_M_S2)
    grid.sector_exit(grid.minimum_cell(0.0, 0.0), "pitch", 8)
    _WARM.append(True)


class _SectorGrid:
    """A pose's pitch-roll grid for the sector searches: the landscape's energies where it was computed,
    else each cell's energy computed on first use, exactly as :func:`~landscape.energy.energy_landscape`
    computes it (the same hill climb, times m g), so that a barrier map's poses need no whole grid: a sector
    flood computes only the cells it reaches."""

    def __init__(self, pose: Pose, step_deg: float, g_m_s2: float, ls: Landscape | None = None) -> None:
        angles = torus_angles_deg(step_deg)
        n = len(angles)
        self.step_deg, self.angles_deg, self.mass_kg, self.g_m_s2 = (
            float(step_deg),
            angles,
            pose.mass_kg,
            g_m_s2,
        )
        self.cos, self.sin = cos_sin(np.deg2rad(angles))
        self.d, self.ptr, self.idx = _support_inputs(pose)
        self.scale = pose.mass_kg * g_m_s2  # energy_landscape's factor, in its order
        # energy and vert are read only where known (uninitialised elsewhere: no page is touched in vain)
        if ls is None:
            self.energy = np.empty((n, n))
            self.known = np.zeros((n, n), dtype=np.bool_)
        else:
            self.energy = np.ascontiguousarray(ls.energy_j, dtype=np.float64)
            self.known = np.ones((n, n), dtype=np.bool_)
        self.vert = np.empty(n * n, dtype=np.int64)

    def _args(self):
        return (
            self.energy,
            self.known,
            self.vert,
            self.d,
            self.ptr,
            self.idx,
            self.cos,
            self.sin,
            self.scale,
        )

    def minimum_cell(self, pitch_deg: float, roll_deg: float) -> tuple[int, int]:
        """:func:`~landscape.minima.grid_minimum` on this grid."""
        i, j = nearest_cell(pitch_deg, roll_deg, self.step_deg)
        i, j = _computation_kernels.lazy_descend(*self._args(), i, j)
        return int(i), int(j)

    def landscape(self) -> Landscape:
        """The grid as a Landscape (its energies are valid only where ``known``)."""
        return Landscape(self.step_deg, self.angles_deg, self.energy, self.mass_kg, self.g_m_s2)

    def sector_exit(self, cell: tuple[int, int], kind: str, connectivity: int) -> Exit | None:
        """The pitch-wise or roll-wise exit of :func:`~landscape.barriers.grid.grid_barrier` alone: one flood
        with the path kept in the sector, to the upright set (the other exits' floods are not needed)."""
        n = len(self.angles_deg)
        i0, j0 = cell[0] % n, cell[1] % n
        a0 = self.angles_deg
        if self.cos[i0] * self.cos[j0] < 0:  # already upright (u_z = cos p cos r, as up_vector computes it)
            return Exit(0.0, *canonical_pitch_roll_deg(a0[i0], a0[j0]), "roll", np.array([[a0[i0], a0[j0]]]))
        dist_p = np.ascontiguousarray(np.abs(wrap_deg(a0 - a0[i0])))
        dist_r = np.ascontiguousarray(np.abs(wrap_deg(a0 - a0[j0])))
        level, c, parent = _computation_kernels.lazy_sector_flood(
            *self._args(), i0, j0, dist_p, dist_r, kind == "pitch", connectivity
        )
        return _grid_exit(self.landscape(), level, int(c), parent, float(self.energy[i0, j0]), kind)


def _with_sectors(barrier: Barrier, minimum: Minimum, grid: _SectorGrid, connectivity: int) -> Barrier:
    """Fill the pitch-wise and roll-wise exits of a non-grid method.

    Sector-restricted barriers live on the torus (a path over the pole changes sheet), so neither the exact
    face-edge graph (landscape/barriers/exact.py gives only an upper bound) nor the icosphere has them. Where the method's
    righting path stays inside a sector, it is that sector's barrier; otherwise the grid's sector search gives
    it: the grid's bottleneck level minus the method's start energy. Only the sectors the righting path leaves
    are searched (each by one flood, :meth:`_SectorGrid.sector_exit`, as :func:`grid_barrier` would find it),
    and on a grid without energies (a barrier map's pose) only the cells those floods reach are computed.
    """
    r = barrier.righting
    need = [not (r is not None and _in_sector(r.path_deg, kind)) for kind in ("pitch", "roll")]
    if any(need):
        cell = grid.minimum_cell(minimum.pitch_deg, minimum.roll_deg)
        shift = float(grid.energy[cell]) - minimum.energy_j
    sectors = []
    for kind, search in zip(("pitch", "roll"), need, strict=True):
        if not search:
            sectors.append(replace(r, direction=kind))
            continue
        x = grid.sector_exit(cell, kind, connectivity)
        sectors.append(None if x is None else replace(x, barrier_j=x.barrier_j + shift))
    return replace(barrier, pitch_wise=sectors[0], roll_wise=sectors[1])


def posed(robot: Robot, theta_w_deg, theta_l_deg, wing_joints_deg: dict[str, float] | None) -> Pose:
    """The robot at (theta_w, theta_l), or with each wing joint at its own angle (``wing_joints_deg``, the leg
    joints at theta_l), labelled with theta_w and theta_l."""
    if not wing_joints_deg:
        return robot.pose(theta_w_deg, theta_l_deg)
    values = dict(wing_joints_deg) | {j: float(theta_l_deg or 0.0) for j in robot.joint_map.leg}
    return replace(robot.pose_joints(values), theta_w_deg=theta_w_deg, theta_l_deg=theta_l_deg)


def start_orientation(
    robot: Robot,
    pose: Pose,
    theta_w_deg: float | None,
    theta_l_deg: float | None,
    *,
    start_pitch_deg: float | None = None,
    start_roll_deg: float | None = None,
    wing_joints_deg: dict[str, float] | None = None,
) -> tuple[float, float]:
    """The orientation barrier searches start from, degrees.

    With ``start_pitch_deg``/``start_roll_deg``: the minimum reached by descent from there. Otherwise the
    metastable state of a slow opening from rest (a robot with joints), or descent from pitch = roll = 0. A pose
    with each wing joint at its own angle (``wing_joints_deg``) opens slowly to the smallest of them, then
    descends on ``pose``.
    """
    if start_pitch_deg is not None or start_roll_deg is not None:
        p = 0.0 if start_pitch_deg is None else float(start_pitch_deg)
        r = 0.0 if start_roll_deg is None else float(start_roll_deg)
        if not (np.isfinite(p) and np.isfinite(r)) or abs(p) > 180 or abs(r) > 180:
            raise UsageError(
                f"start pitch and roll must be finite degrees in [-180, 180]; got ({p!r}, {r!r})"
            )
        return local_descent(pose, p, r)
    if wing_joints_deg:
        return local_descent(pose, *metastable_orientation(robot, min(wing_joints_deg.values()), theta_l_deg))
    if robot.has_joints:
        return metastable_orientation(robot, theta_w_deg, theta_l_deg)
    return local_descent(pose, 0.0, 0.0)


def check_angles(
    robot: Robot,
    *,
    theta_w_deg: float | None = None,
    theta_l_deg: float | None = None,
    wing_joints_deg: dict[str, float] | None = None,
) -> None:
    """Refuse an angle no joint of ``robot`` takes: ``theta_w_deg`` or ``theta_l_deg`` other than None or 0, or
    ``wing_joints_deg``, given a single rigid body, a URDF without a joint map or a joint map leaving that
    group out; the error names the robot's movable joints and the ``joints=`` of
    :func:`geometry.robots.load_robot` that would drive them (:meth:`geometry.Robot.undriven`).

    Raises
    ------
    UnknownJointError
        If an angle is given that no joint takes.

    Examples
    --------
    >>> from geometry.robots import load_robot
    >>> check_angles(load_robot(), theta_w_deg=74.0, theta_l_deg=0.0)
    """
    for angle, value in (("theta_w", theta_w_deg), ("theta_l", theta_l_deg)):
        if value is not None and value != 0 and not robot.drives(angle):
            raise robot.undriven(angle, option=f"{angle}_deg", joints_option="joints=")
    if wing_joints_deg and not robot.drives("theta_w"):
        raise robot.undriven("theta_w", option="wing_joints_deg", joints_option="joints=")


MIRROR_TOL = 1e-9
"""Relative tolerance (of the body's size) of :func:`is_roll_mirror_symmetric`."""


def is_roll_mirror_symmetric(pose: Pose, *, rel_tol: float = MIRROR_TOL) -> bool:
    """Whether the posed body is its own mirror image in its x-z plane (y -> -y): the CoM has y = 0 and every
    hull vertex has a mirror twin, both within ``rel_tol`` times the body's size. Then E(pitch, -roll) =
    E(pitch, roll) (roll -> -roll mirrors world-up in y, geometry/frames.py).

    Examples
    --------
    >>> corners = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 2)], float)
    >>> box = Pose(None, None, 1.0, np.zeros(3), corners, {}, ())
    >>> is_roll_mirror_symmetric(box), is_roll_mirror_symmetric(replace(box, com_m=np.array([0, 0.1, 0])))
    (True, False)
    """
    from scipy.spatial import cKDTree

    pts = np.asarray(pose.hull_points_m, dtype=np.float64)
    if not len(pts):
        return False
    tol = rel_tol * max(float(np.ptp(pts, axis=0).max()), np.finfo(float).tiny)
    if abs(float(pose.com_m[1])) > tol:
        return False
    dist, _ = cKDTree(pts).query(pts * np.array([1.0, -1.0, 1.0]))
    return bool(dist.max() <= tol)


def _mirrored(x: Exit) -> Exit:
    """The mirror twin of an exit: saddle and path at the opposite roll, the same barrier."""
    path = np.array(x.path_deg, dtype=np.float64, copy=True)
    if path.ndim == 2 and path.shape[1] == 2:
        path[:, 1] = -path[:, 1]
    return replace(
        x, saddle_roll_deg=canonical_pitch_roll_deg(x.saddle_pitch_deg, -x.saddle_roll_deg)[1], path_deg=path
    )


def positive_roll_twins(pose: Pose, minimum: Minimum, barrier: Barrier) -> Barrier:
    """The tie rule between mirror saddles: on a body mirror-symmetric in its x-z plane
    (:func:`is_roll_mirror_symmetric`) with the start minimum on that plane (roll 0 or 180 deg), every exit has a
    mirror twin at the opposite roll with the same barrier; the twin reported is the one at non-negative saddle
    roll (0 to 180 deg), so the answer does not depend on which of two equal saddles a search met first.
    Elsewhere the barrier is returned unchanged.

    Examples
    --------
    >>> from landscape.barriers import Exit
    >>> corners = np.array([(x, y, z) for x in (-1, 1) for y in (-2, 2) for z in (-1, 1)], float)
    >>> box = Pose(None, None, 1.0, np.zeros(3), corners, {}, ())
    >>> x = Exit(0.4, 0.0, -45.0, "roll", np.array([[0.0, 0.0], [0.0, -45.0]]))
    >>> b = positive_roll_twins(box, Minimum(0.0, 0.0, 1.0, 1.0), Barrier(x, None, x, x))
    >>> b.righting.saddle_roll_deg, b.righting.path_deg[-1].tolist()
    (45.0, [0.0, 45.0])
    """
    start_roll = abs(float(wrap_deg(minimum.roll_deg)))
    if min(start_roll, 180.0 - start_roll) > 1e-9 or not is_roll_mirror_symmetric(pose):
        return barrier
    fields = {}
    for name in ("righting", "pitch_wise", "roll_wise", "escape"):
        x = getattr(barrier, name)
        if x is not None and -180.0 < canonical_pitch_roll_deg(x.saddle_pitch_deg, x.saddle_roll_deg)[1] < 0:
            fields[name] = _mirrored(x)
    return replace(barrier, **fields) if fields else barrier


BYTES_PER_CELL = 72
"""Peak memory of :func:`compute` per landscape grid cell, bytes: the grid method's (energies, the flood's
levels, parents and heap), the largest of the methods (exact needs about half); tracemalloc, checked by
tests/landscape/test_computation.py."""
MEMORY_BUDGET_BYTES = 2 * 2**30
"""Default memory budget of one computation, bytes (2 GiB: a 0.05 deg grid needs about 3.7 GB)."""


def landscape_memory_bytes(step_deg: float) -> float:
    """Estimated peak memory of :func:`compute` on a grid of ``step_deg``, bytes.

    Examples
    --------
    >>> round(landscape_memory_bytes(0.1) / 2**20)
    890
    """
    return BYTES_PER_CELL * cells_per_turn(step_deg) ** 2


def check_memory(step_deg: float, budget_bytes: float = MEMORY_BUDGET_BYTES) -> None:
    """Refuse up front a grid whose estimated memory exceeds ``budget_bytes``, saying what it would need."""
    need = landscape_memory_bytes(step_deg)
    if need > budget_bytes:
        n = cells_per_turn(step_deg)
        raise UsageError(
            f"a {step_deg:g} deg grid needs about {need / 1e9:.1f} GB ({n} x {n} cells x "
            f"{BYTES_PER_CELL} bytes), more than the {budget_bytes / 2**30:.3g} GiB budget; use a coarser "
            "--step or raise the budget (LANDSCAPE_MEMORY_GIB)"
        )


COM_OUTSIDE_HULL = (
    "the CoM {com} m lies {dist:.3g} m outside the convex hull of the body, so it would rest "
    "below the ground; check the masses and <inertial> origins (or --com)"
)


def _check_com_inside(pose: Pose) -> None:
    """Refuse a CoM outside the hull (every method: the energies would be meaningless, even negative)."""
    from geometry.hull import depth_inside_m

    hull = pose.hull
    if not len(hull.simplices):
        return  # a flat body: the exact method refuses it; the grid treats it as a plate
    size = float(np.ptp(hull.vertices_m, axis=0).max())
    depth = depth_inside_m(hull, pose.com_m)
    if depth < -1e-9 * size:
        raise UsageError(COM_OUTSIDE_HULL.format(com=np.round(pose.com_m, 6).tolist(), dist=-depth))


def compute(
    robot: Robot,
    *,
    theta_w_deg: float | None = 0.0,
    theta_l_deg: float | None = 0.0,
    step_deg: float = DEFAULT_STEP_DEG,
    start_pitch_deg: float | None = None,
    start_roll_deg: float | None = None,
    connectivity: int = 8,
    method: str = DEFAULT_METHOD,
    g_m_s2: float = G_M_S2,
    start_deg: tuple[float, float] | None = None,
    memory_budget_bytes: float = MEMORY_BUDGET_BYTES,
    landscape_grid: bool = True,
    sector_exits: bool | None = None,
    wing_joints_deg: dict[str, float] | None = None,
) -> Computation:
    """Landscape, start minimum and barriers of a robot at (theta_w, theta_l).

    Parameters
    ----------
    robot : Robot
    theta_w_deg, theta_l_deg : float
        Wing and leg angle, degrees, anywhere within the joints' limits; an angle no joint takes (a single
        rigid mesh, a joint map without that group) must be None or 0.
    step_deg : float
        Grid step, degrees (divides 360).
    start_pitch_deg, start_roll_deg : float, optional
        Seek the start minimum by descent from here instead of the metastable continuation.
    connectivity : {8, 4}
        Grid neighbours (method "grid").
    method : str
        A barrier method of :data:`landscape.barriers.METHODS`:
        "exact": righting and escape barriers on the hull's face-edge graph, no discretisation error
        (landscape/barriers/exact.py); pitch-wise and roll-wise are the exact righting barrier when its path stays
        in that sector, else the grid's sector search at ``step_deg`` referenced to the exact start energy;
        "grid": the source paper's graph search on the pitch-roll grid. The landscape grid is computed either
        way (for files and figures);
        "sphere": the same search on an icosphere of up-directions spaced about ``step_deg`` apart
        (landscape/barriers/sphere.py).
    start_deg : (float, float), optional
        A start orientation already found (used by sweeps that continue along theta); skips the search.
    memory_budget_bytes : float
        Refuse a grid whose estimated peak memory (:func:`landscape_memory_bytes`) exceeds this, bytes.
    landscape_grid : bool
        Build the pitch-roll landscape grid (the default). False, with a method that does not search the grid
        ("exact", "sphere"), skips it and the grid's sector searches: ``landscape`` is then None and the
        pitch-wise and roll-wise exits None; the start minimum and the righting and escape exits are unchanged
        (a barrier map that reports only those, :func:`barrier_map` with ``sector_exits=False``).
    sector_exits : bool, optional
        For a method that does not find the pitch-wise and roll-wise exits itself ("exact", "sphere"): search
        them on the grid. Default: as ``landscape_grid``. True with ``landscape_grid=False`` computes the grid's
        energies only on the cells the sector searches reach (the same exits, without the whole grid: what
        :func:`barrier_map` does at each pose).
    wing_joints_deg : dict of str to float, optional
        Each wing joint at its own angle, degrees (e.g. a model set's measured servo plateaus at the wing
        command ``theta_w_deg``, which then only labels the result). The start follows a slow opening to the
        smallest of them, then descends on this pose (unless a start is given).

    Returns
    -------
    Computation
        On a body mirror-symmetric in its x-z plane with the start on that plane, each exit is the mirror twin at
        non-negative saddle roll (:func:`positive_roll_twins`), whichever twin the search met first.

    Raises
    ------
    JointLimitError, GridError, ValueError
        For angles outside the joint limits, a step not dividing 360, or a non-finite start.
    UnknownJointError
        For an angle other than None or 0, or ``wing_joints_deg``, that no joint of the robot takes
        (:func:`check_angles`).
    UsageError
        If ``landscape_grid`` is False with the method "grid".
    """
    check_angles(robot, theta_w_deg=theta_w_deg, theta_l_deg=theta_l_deg, wing_joints_deg=wing_joints_deg)
    solver = barrier_method(method)
    if not landscape_grid and solver.SECTORS:
        raise UsageError(
            f"the {method!r} method searches the landscape grid, so it cannot be skipped; "
            "keep landscape_grid=True or use method 'exact'"
        )
    check_memory(step_deg, memory_budget_bytes)
    warm_up()
    timing = {}
    t0 = time.perf_counter()
    pose = posed(robot, theta_w_deg, theta_l_deg, wing_joints_deg)
    _check_com_inside(pose)
    timing["pose"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    if start_deg is None:
        start_deg = start_orientation(
            robot,
            pose,
            theta_w_deg,
            theta_l_deg,
            start_pitch_deg=start_pitch_deg,
            start_roll_deg=start_roll_deg,
            wing_joints_deg=wing_joints_deg,
        )
    timing["start"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    ls = energy_landscape(pose, step_deg=step_deg, g_m_s2=g_m_s2) if landscape_grid else None
    timing["landscape"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    minimum, barrier = solver.solve(
        pose, ls, start_deg, step_deg=step_deg, connectivity=connectivity, g_m_s2=g_m_s2
    )
    if not solver.SECTORS and (landscape_grid if sector_exits is None else sector_exits):
        grid = _SectorGrid(pose, step_deg, g_m_s2, ls)
        barrier = _with_sectors(barrier, minimum, grid, connectivity)
    barrier = positive_roll_twins(pose, minimum, barrier)
    timing["barrier"] = time.perf_counter() - t0
    return Computation(
        pose.theta_w_deg,
        pose.theta_l_deg,
        float(step_deg),
        method,
        pose.mass_kg,
        pose.com_m,
        canonical_pitch_roll_deg(*start_deg),
        minimum,
        barrier,
        ls,
        pose,
        timing,
    )


def sweep_starts(
    robot: Robot, theta_w_deg: list[float], theta_l_deg: list[float]
) -> dict[tuple[float, float], tuple[float, float]]:
    """Metastable orientations over a theta_w x theta_l grid by one shared continuation.

    theta_w rises from 0 through every requested value (1 deg steps or finer) in one continuation (one kernel
    call per sign of theta_w), and at each requested theta_w a branch raises theta_l from 0. Equivalent to
    :func:`metastable_orientation` per pair, far cheaper.
    """
    out: dict[tuple[float, float], tuple[float, float]] = {}
    ws = sorted(set(float(w) for w in theta_w_deg))
    ls = sorted(set(float(x) for x in theta_l_deg))
    for sign_ws in ([w for w in ws if w >= 0], sorted([w for w in ws if w < 0], reverse=True)):
        if not sign_ws:
            continue
        # one walk from rest through every requested theta_w (the face carried along), then the theta_l branches
        path, reach, at = [(0.0, 0.0)], [], 0.0
        for w in sign_ws:
            path += [(x, 0.0) for x in ramp_deg(at, w)]
            reach.append(len(path) - 1)
            at = w
        walk = follow_minimum(robot, path)
        for w, k in zip(sign_ws, reach, strict=True):
            p, r = walk[k]
            for tl in ls:
                if tl == 0.0:
                    out[(w, tl)] = (p, r)
                    continue
                lpath = [(w, x) for x in ramp_deg(0.0, tl)]
                out[(w, tl)] = follow_minimum(robot, lpath, pitch_deg=p, roll_deg=r)[-1]
    return out


@dataclass(frozen=True)
class BarrierMap:
    """Start minima and barriers over a theta_w x theta_l grid (the source paper's Fig. 5).

    Attributes
    ----------
    theta_w_deg, theta_l_deg : tuple of float
        The grid's axes, degrees.
    computations : tuple of Computation
        One per (theta_w, theta_l), theta_l varying fastest, without their landscape grids and poses (a map
        of many poses would otherwise hold every grid in memory).
    righting_j : ndarray of shape (W, L)
        Minimal righting barrier, J (nan where the robot cannot right).
    """

    theta_w_deg: tuple[float, ...]
    theta_l_deg: tuple[float, ...]
    computations: tuple[Computation, ...] = field(repr=False)
    righting_j: NDArray[np.float64] = field(repr=False)


MAP_POSES_PER_WORKER = 16
"""Fewest poses per worker process :func:`barrier_map` starts on its own (``workers=None``)."""

_MAP_TASK: dict = {}  # in a forked worker process only: the robot and options of its barrier map


def _map_pose(task: dict, w: float, leg: float, start: tuple[float, float]) -> Computation:
    """One pose of a barrier map, without its landscape grid and pose."""
    c = compute(
        task["robot"],
        theta_w_deg=w,
        theta_l_deg=leg,
        step_deg=task["step_deg"],
        start_deg=start,
        method=task["method"],
        memory_budget_bytes=task["memory_budget_bytes"],
        landscape_grid=task["grid"],
        sector_exits=task["sectors"],
        wing_joints_deg=task.get("joints", {}).get(w),
    )
    return replace(c, landscape=None, pose=None)


def _map_worker_init(task: dict) -> None:
    """Start of a forked worker: keep the map's robot and options (inherited, not pickled)."""
    _MAP_TASK.update(task)


def _map_pose_in_worker(args) -> Computation:
    return _map_pose(_MAP_TASK, *args)


def map_workers(n_poses: int, workers: int | None = None) -> int:
    """Worker processes :func:`barrier_map` uses for ``n_poses`` poses.

    ``workers=None`` chooses: one per CPU this process may run on, at most one per
    :data:`MAP_POSES_PER_WORKER` poses, and 1 (no workers) unless this is the main thread and the only one
    (workers are forked, which is unsafe in a process running other threads, e.g. the service) and the
    ``fork`` start method exists. An explicit ``workers`` is used as given (capped at ``n_poses``).

    Raises
    ------
    UsageError
        If ``workers`` is below 1.

    Examples
    --------
    >>> map_workers(5, 1), map_workers(1, 4), map_workers(3, 2)
    (1, 1, 2)
    """
    import multiprocessing
    import os
    import threading

    if workers is not None:
        if int(workers) != workers or workers < 1:
            raise UsageError(f"workers must be a whole number >= 1; got {workers!r}")
        return max(1, min(int(workers), n_poses))
    if "fork" not in multiprocessing.get_all_start_methods():
        return 1
    if threading.current_thread() is not threading.main_thread() or threading.active_count() > 1:
        return 1
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(cpus, n_poses // MAP_POSES_PER_WORKER))


def barrier_map(
    robot: Robot,
    theta_w_deg: list[float],
    theta_l_deg: list[float],
    *,
    step_deg: float = DEFAULT_STEP_DEG,
    method: str = DEFAULT_METHOD,
    progress=None,
    memory_budget_bytes: float = MEMORY_BUDGET_BYTES,
    workers: int | None = None,
    sector_exits: bool = True,
    wing_joints_deg: dict[float, dict[str, float]] | None = None,
) -> BarrierMap:
    """Start minimum and barriers at every (theta_w, theta_l), the starts from one shared continuation.

    Parameters
    ----------
    robot : Robot
        A robot with joints.
    theta_w_deg, theta_l_deg : list of float
        Wing and leg angles, degrees.
    step_deg, method : float, str
        As in :func:`compute`.
    progress : callable, optional
        Called with 1 after each pose (e.g. a progress bar's ``update``), in the calling process.
    workers : int, optional
        Worker processes (forked) the poses are spread over; the results are the same, in the same order.
        Default: :func:`map_workers` chooses (several only on a multi-core machine, from a process's main and
        only thread, for at least :data:`MAP_POSES_PER_WORKER` poses per worker); 1 computes in this process.
    sector_exits : bool
        Also find the pitch-wise and roll-wise exits (the default). A method that does not find them itself
        ("exact", "sphere") then searches them on the grid, computing its energies only on the cells those
        searches reach (``compute``'s ``landscape_grid=False, sector_exits=True``; no pose keeps a landscape
        grid either way). False skips them: those two exits are then None; minima, righting and escape are
        unchanged.
    wing_joints_deg : dict, optional
        Per theta_w (a key for each), each wing joint at its own angle (:func:`compute`'s ``wing_joints_deg``);
        those poses start from a slow opening to the smallest of the angles, then descend.

    Raises
    ------
    UsageError
        If no joint map drives the robot's joints (:meth:`geometry.Robot.undriven` names them), or a grid is
        empty.
    JointLimitError, GridError
        For angles outside the joint limits (checked before any work) or a step not dividing 360.
    """
    from geometry.errors import UsageError

    if not robot.has_joints:
        if robot.movable_joints:
            raise robot.undriven("theta_w", option="theta_w_deg", joints_option="joints=", drop=False)
        raise UsageError(
            f"a barrier map sweeps joint angles, and {robot.name} is a single rigid body without joints; "
            "compute() gives its landscape and barriers"
        )
    ws, ls_ = [float(w) for w in theta_w_deg], [float(x) for x in theta_l_deg]
    if not ws or not ls_:
        raise UsageError("a barrier map needs at least one theta_w and one theta_l")
    for w in ws:
        for leg in ls_:
            robot.joint_values_rad(w, leg)
    grid = barrier_method(method).SECTORS  # only the grid method needs each pose's whole grid
    check_memory(step_deg, memory_budget_bytes)
    n_workers = map_workers(len(ws) * len(ls_), workers)
    joints = wing_joints_deg or {}
    if joints and set(joints) != set(ws):
        raise UsageError(f"wing_joints_deg needs one entry per theta_w {ws}; got {sorted(joints)}")
    starts = {} if joints else sweep_starts(robot, ws, ls_)  # wing joints of their own: compute's own starts
    tasks = [(w, leg, starts.get((w, leg))) for w in ws for leg in ls_]
    warm_up()  # load the kernels once, before any fork, so the workers inherit them
    task = dict(
        robot=robot,
        step_deg=step_deg,
        method=method,
        memory_budget_bytes=memory_budget_bytes,
        grid=grid,
        sectors=bool(sector_exits),
        joints=joints,
    )
    if n_workers == 1:
        out = _collect((_map_pose(task, *t) for t in tasks), progress)
    else:
        import multiprocessing

        with multiprocessing.get_context("fork").Pool(n_workers, _map_worker_init, (task,)) as pool:
            out = _collect(pool.imap(_map_pose_in_worker, tasks, chunksize=1), progress)
    righting = np.full((len(ws), len(ls_)), np.nan)
    for k, c in enumerate(out):
        if c.barrier.righting is not None:
            righting[k // len(ls_), k % len(ls_)] = c.barrier.righting.barrier_j
    return BarrierMap(tuple(ws), tuple(ls_), tuple(out), righting)


def _collect(results, progress) -> list[Computation]:
    out = []
    for c in results:
        out.append(c)
        if progress is not None:
            progress(1)
    return out
