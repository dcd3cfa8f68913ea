"""Exact barriers of a convex body on flat ground: critical points in closed form, bottleneck paths on faces.

The CoM height over the up-direction ``u`` (world-up in the body frame, geometry/frames.py) is the support
function ``h(u) = max_k (c - v_k).u`` over hull vertices ``v_k`` seen from the CoM ``c``. It is smooth inside
the *cell* of each vertex (the up-directions for which that vertex is lowest) and its structure is closed-form:

- a *minimum* at ``u_F = -n_F`` for each (merged, coplanar) face ``F`` whose plane the CoM projects strictly
  inside: the body rests on ``F``; ``h`` = distance from the CoM to the face plane;
- a *saddle* on the arc of each hull edge ``ab`` (the great-circle arc from ``u_F`` to ``u_G`` between its two
  faces, where ``a`` and ``b`` are both lowest) when the foot of the perpendicular from the CoM onto the edge
  line lies inside the edge and its direction lies on the arc: the body rocks on the edge; ``h`` = distance
  from the CoM to the edge line;
- a *maximum* at ``u = (c - v_k) / |c - v_k|`` when that direction lies in vertex ``k``'s cell.

Inside a cell ``h = (c - v_k).u`` and the region above any level is a spherical cap, which is convex. Any path
crossing a cell can therefore be pushed onto the cell's boundary without raising its maximum, so the lowest
possible maximum along *continuous* paths (the barrier) is a bottleneck path on the face-edge graph: nodes are
the face directions ``u_F``, links the edge arcs, each weighted by the highest ``h`` along the arc, which on an
arc is ``w.u`` with ``w`` the perpendicular from the edge line to the CoM. For righting, arcs are cut where they
cross ``u_z = 0`` and the crossing is the target (the upright set is ``u_z < 0``; its closure is reached at the
same level, so the infimum over paths is taken). No grid, so no discretisation error, in milliseconds.

Definitions shared with the grid method (landscape/barriers/grid.py):

- *escape*: reach another minimum (the lowest maximum along any path to any other face minimum).
- *righting*: reach ``u_z <= 0``.
- *pitch-wise* and *roll-wise*: the grid keeps the whole path inside the sector ``|d roll| <= |d pitch|``
  (resp. the reverse) around the start in torus coordinates. A sector is not a union of cells, so the graph
  reduction is not exact inside it; here the search keeps to the arcs (cut at the upright boundary) that lie
  wholly inside the sector, sampled every ``PATH_STEP_DEG`` (a point is inside when either of its two torus
  representatives is). This is an upper bound on the continuous sector-restricted barrier and the grid's
  sector barrier may lie below it by more than grid error (a continuous path may cut through a cell along the
  sector boundary, and a long arc that pokes out of the sector is dropped whole). The sector boundary and the
  poles (where roll is undefined) are ``SECTOR_TOL_DEG`` wide: a point within that angle of them counts as
  inside. Being restricted to arcs, these two exits are not continuous in the geometry: a facet added near a
  pole may change which arcs there are. (Classifying routes by the
  sector of their highest point instead is not useful: a detour through a slightly higher pitch-sector point
  then counts as "pitch-wise" though the body goes over the side.)
- *direction*: "pitch" when the saddle lies at least as far from the start in pitch as in roll, else "roll",
  using the saddle's torus representative nearest the start ((p, r) or (180 - p, r + 180); at the poles the roll
  is that of the start).

Tolerance (documented and deterministic): lengths within ``LENGTH_RTOL`` (1e-6) times the hull diameter are
equal. The hull is first rebuilt with Qhull merging every facet whose centrum lies within that length of its
neighbour's plane, so the facets and edges the method sees are convex by more than the tolerance: rounding
noise below it (a CAD export's finely triangulated flat faces, single-precision coordinates, a unit
conversion) leaves no sliver facets or kinked edges that would create or hide a saddle. The merged hull lies
within about the tolerance of the input's, so an energy is exact to about ``2 m g LENGTH_RTOL`` times the
diameter and a saddle's direction to about the tolerance over the CoM's distance to the hull;
``benchmarks/accuracy.py --cad`` checks this on CAD-like families. A body with features smaller than that
tolerance is treated as the body without them. Faces closer than that to coplanar are merged; a CoM that
projects within that distance of a face's boundary is *above the edge or vertex*: the face is not a minimum
(the body tips over, as a marginal equilibrium would under any disturbance); a start exactly on a saddle rolls
to the lower of the two faces (ties: the lower face index) and a start exactly on a vertex maximum to the lowest
face at that vertex.

Equal saddles (the tie rule): an exit's saddle is the pass by which its path leaves the start's basin (the
nodes the search reaches below the barrier level minus the tolerance), and of several passes at the barrier
level, equal within the tolerance, the one with the largest canonical roll is reported, then the smallest
canonical pitch (coordinates within ``TIE_DEG`` equal). For a body symmetric left to right that is the
mirror-image saddle on the positive-roll side. Escape prefers a pass that is a saddle between the start's
basin and another. The rule is on geometry alone, not on Qhull's face numbering or the vertices' order.

It is one concept, the exact method (the face-edge graph, its critical points and its bottleneck searches),
hence its length; its compiled kernels are in :mod:`landscape.barriers._exact_kernels`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from geometry import Pose
from geometry.errors import UsageError
from geometry.frames import canonical_pitch_roll_deg, pitch_roll_from_up, up_vector
from geometry.hull import Hull, convex_hull
from landscape.barriers import _exact_kernels
from landscape.barriers._base import Barrier, Contact, Contacts, Exit
from landscape.energy import G_M_S2
from landscape.grid import wrap_deg
from landscape.minima import Minimum

log = logging.getLogger(__name__)

LENGTH_RTOL = 1e-6  # lengths below LENGTH_RTOL * hull diameter count as zero
ANGLE_TOL_RAD = 1e-9  # face normals closer than this (and within the length tolerance) are one face
UPRIGHT_Z_TOL = 1e-12  # u_z <= this counts as reached the upright set
PATH_STEP_DEG = 1.0  # sampling of reported paths along arcs, degrees
SECTOR_TOL_DEG = 1e-3  # sector boundaries and poles are this wide, degrees (module docstring)
TIE_DEG = 1e-9  # saddle coordinates closer than this are equal in the tie rule, degrees

NOT_A_SOLID = (
    "the exact method needs a solid body: the hull of {n} points is flat or degenerate "
    "(all points within {tol:.3g} m of a plane or line); use method='grid'"
)
COM_OUTSIDE = (
    "the CoM {com} m lies {dist:.3g} m outside the convex hull; the exact method needs it inside "
    "(check the masses and <inertial> origins)"
)


class ExactMethodError(UsageError):
    """A body the exact method cannot treat (flat hull, CoM outside the hull)."""


@dataclass(frozen=True)
class CriticalPoints:
    """Minima, saddles and maxima of the energy on the sphere of up-directions.

    Attributes
    ----------
    minima_face : ndarray of shape (M,) of int64
        Face resting on the ground (index into ``ExactLandscape.face_up``).
    minima_deg, saddles_deg, maxima_deg : ndarray of shape (M, 2), (S, 2), (X, 2)
        Canonical (pitch, roll), degrees.
    minima_energy_j, saddles_energy_j, maxima_energy_j : ndarray
        m g h, J.
    saddles_arc : ndarray of shape (S,) of int64
        Edge arc the saddle lies on (index into ``ExactLandscape.arc_faces``).
    saddles_joins : ndarray of shape (S, 2) of int64
        The minima (rows of ``minima_*``) reached by rolling down from either side of each saddle (computed on
        first use: the barrier searches roll down only from the saddles they meet).
    maxima_vertex : ndarray of shape (X,) of int64
        Hull vertex the body balances on.
    """

    minima_face: NDArray[np.int64]
    minima_deg: NDArray[np.float64]
    minima_energy_j: NDArray[np.float64]
    saddles_arc: NDArray[np.int64]
    saddles_deg: NDArray[np.float64]
    saddles_energy_j: NDArray[np.float64]
    maxima_vertex: NDArray[np.int64]
    maxima_deg: NDArray[np.float64]
    maxima_energy_j: NDArray[np.float64]
    _landscape: ExactLandscape = field(repr=False, compare=False)

    @cached_property
    def saddles_joins(self) -> NDArray[np.int64]:
        return _joins(self._landscape, self.minima_face, self.saddles_arc)


@dataclass(frozen=True)
class ExactLandscape:
    """The face-edge graph of a convex hull seen from the CoM, with everything the exact barriers need.

    Attributes
    ----------
    mass_kg, g_m_s2 : float
        Mass, kg, and gravity, m/s^2.
    com_m : ndarray of shape (3,)
        CoM, body frame, m.
    vertices_m : ndarray of shape (K, 3)
        Hull vertices, m.
    tol_m : float
        Length tolerance, m (``LENGTH_RTOL`` times the hull diameter).
    face_up : ndarray of shape (F, 3)
        Up-direction at which each merged face rests on the ground (minus its outward normal).
    face_height_m : ndarray of shape (F,)
        CoM height when resting on the face (distance from the CoM to its plane), m.
    face_margin_m : ndarray of shape (F,)
        Distance of the CoM's projection inside the face's boundary, m (negative: outside).
    arc_faces, arc_vertices : ndarray of shape (A, 2) of int64
        The two faces and the two end vertices of each edge (collinear sub-edges joined).
    arc_max_m : ndarray of shape (A,)
        Highest CoM height along each edge arc, m.
    arc_peak_up : ndarray of shape (A, 3)
        Where on the arc that height is reached.
    critical : CriticalPoints
    """

    mass_kg: float
    g_m_s2: float
    com_m: NDArray[np.float64]
    vertices_m: NDArray[np.float64] = field(repr=False)
    tol_m: float
    face_up: NDArray[np.float64] = field(repr=False)
    face_height_m: NDArray[np.float64] = field(repr=False)
    face_margin_m: NDArray[np.float64] = field(repr=False)
    arc_faces: NDArray[np.int64] = field(repr=False)
    arc_vertices: NDArray[np.int64] = field(repr=False)
    arc_max_m: NDArray[np.float64] = field(repr=False)
    arc_peak_up: NDArray[np.float64] = field(repr=False)
    critical: CriticalPoints = field(repr=False)
    _g: _Graph = field(repr=False, compare=False)

    @property
    def energy_scale_j(self) -> float:
        """m g, J/m."""
        return self.mass_kg * self.g_m_s2


@dataclass(frozen=True)
class ExactBarrier:
    """Exact barriers out of the basin that contains a start orientation.

    Attributes
    ----------
    start : landscape.minima.Minimum
        The exact start minimum (canonical pitch, roll in degrees; energy, J; CoM height, m).
    start_face : int
        The face the body rests on there (index into ``landscape.face_up``).
    barrier : landscape.barriers.Barrier
        Righting, pitch-wise, roll-wise and escape exits, as the grid method reports them.
    landscape : ExactLandscape
    """

    start: Minimum
    start_face: int
    barrier: Barrier
    landscape: ExactLandscape = field(repr=False)


@dataclass(frozen=True)
class _Graph:
    """Private per-arc geometry: arc ``i`` runs ``cos(s) u0 + sin(s) t`` for s in [0, theta], from face 0 to 1."""

    d: NDArray[np.float64]  # (K, 3) c - v_k
    nbr_ptr: NDArray[np.int64]
    nbr_idx: NDArray[np.int64]
    face_ptr: NDArray[np.int64]  # faces' vertices, CSR
    face_idx: NDArray[np.int64]
    vface_ptr: NDArray[np.int64]  # faces at each vertex, CSR
    vface_idx: NDArray[np.int64]
    face_proj: NDArray[np.float64]  # (F, 3) CoM projected onto each face plane
    half_ptr: NDArray[np.int64]  # face boundary half-edges by face (CSR): arc, vertices a b (segment ends)
    half_arc: NDArray[np.int64]
    half_a: NDArray[np.int64]
    half_b: NDArray[np.int64]
    arc_t: NDArray[np.float64]  # (A, 3)
    arc_theta: NDArray[np.float64]  # (A,)
    arc_w: NDArray[np.float64]  # (A, 3) perpendicular from the edge line to the CoM
    arc_peak_s: NDArray[np.float64]  # (A,) where w.u peaks along the arc (may lie outside [0, theta])
    arc_foot: NDArray[np.float64]  # (A,) foot of the perpendicular along the edge, m from vertex 0
    arc_len: NDArray[np.float64]  # (A,) edge length, m
    pair_arc: tuple  # (sorted keys min * K + max of vertex pairs, arc of each)
    face_next: NDArray[np.int64]  # where a face that is no minimum tips: face >= 0, or -2 - vertex
    descended: dict = field(default_factory=dict)  # face -> minimum face it rolls down to (filled on demand)


# --------------------------------------------------------------------------------------------- construction
def _faces(hull: Hull, tol_m: float):
    """Merged faces of the hull: (outward normals, triangle -> face, triangles, triangle neighbours), from the
    Qhull output the hull already carries (no second Qhull run: the choice between equal saddles does not
    depend on Qhull's numbering, see the module docstring)."""
    if hull.equations is None or not len(hull.simplices):
        raise ExactMethodError(NOT_A_SOLID.format(n=len(hull.vertices_m), tol=tol_m))
    tri = np.ascontiguousarray(hull.simplices, dtype=np.int64)
    eq = np.ascontiguousarray(hull.equations, dtype=np.float64)
    nb = np.ascontiguousarray(hull.neighbors, dtype=np.int64)
    tri_face = _exact_kernels.merge_coplanar(
        np.ascontiguousarray(hull.vertices_m, dtype=np.float64), tri, eq, nb, float(tol_m), ANGLE_TOL_RAD
    )
    return eq, tri, nb, tri_face


def _csr(n: int, rows: NDArray[np.int64], cols: NDArray[np.int64]):
    """The distinct (row, col) pairs as CSR: pointer per row and columns, sorted within each row."""
    span = int(cols.max()) + 1 if len(cols) else 1
    key = np.sort(rows.astype(np.int64) * span + cols)
    keep = np.ones(len(key), dtype=bool)
    keep[1:] = key[1:] != key[:-1]
    key = key[keep]
    rows, cols = key // span, key % span
    ptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n), out=ptr[1:])
    return ptr, cols.astype(np.int64)


def exact_landscape(pose: Pose, *, g_m_s2: float = G_M_S2) -> ExactLandscape:
    """The face-edge graph and critical points of a posed body's energy.

    Parameters
    ----------
    pose : geometry.Pose
        The rigid body: hull vertices and CoM in the body frame, m; mass, kg.
    g_m_s2 : float
        Gravitational acceleration, m/s^2.

    Returns
    -------
    ExactLandscape

    Raises
    ------
    ExactMethodError
        If the hull is flat or degenerate, or the CoM lies outside it.

    Examples
    --------
    >>> import trimesh
    >>> from geometry import Robot
    >>> box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0)
    >>> ex = exact_landscape(box.pose(), g_m_s2=1.0)
    >>> len(ex.critical.minima_face), len(ex.critical.saddles_arc), len(ex.critical.maxima_vertex)
    (6, 12, 8)
    >>> float(ex.critical.minima_energy_j.min()), round(float(ex.critical.saddles_energy_j.min()), 6)
    (0.5, 1.118034)
    """
    return _build(
        pose.hull,
        np.asarray(pose.com_m, dtype=np.float64),
        float(pose.mass_kg),
        float(g_m_s2),
    )


def _merged_faces(hull: Hull, com: NDArray[np.float64], tol_m: float):
    """The hull's merged faces: triangles, neighbours, face of each triangle, outward normals, and the CoM
    checked inside (:data:`COM_OUTSIDE`)."""
    pts = hull.vertices_m
    eq, tri, nb, tri_face = _faces(hull, tol_m)
    n_f = int(tri_face.max()) + 1
    # outward normal of each merged face: area-weighted mean of its triangles' normals
    a, b = pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]]
    cross = np.empty_like(a)  # np.cross(a, b) with its arithmetic, without its axis handling
    cross[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    cross[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    cross[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    area = 0.5 * np.linalg.norm(cross, axis=1)
    normal = np.zeros((n_f, 3))
    np.add.at(normal, tri_face, eq[:, :3] * (area[:, None] + 1e-300))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    inside = -(eq[:, :3] @ com + eq[:, 3])  # distance of the CoM inside each triangle plane
    if inside.min() < -tol_m:
        k = int(np.argmin(inside))
        raise ExactMethodError(COM_OUTSIDE.format(com=np.round(com, 6).tolist(), dist=-float(inside[k])))
    return tri, nb, tri_face, n_f, normal


def _arcs(pts: NDArray[np.float64], tri, nb, tri_face, n_f: int):
    """Boundary edges between different faces (each once), grouped by face pair into arcs; each arc's full
    segment of collinear sub-edges (its extreme vertices), and the (vertex pair -> arc) lookup.
    Compiled (``_exact_kernels.arcs``); the tests hold its reference twin."""
    arc_faces, arc_a, arc_b, keys, arc_of = _exact_kernels.arcs(
        np.ascontiguousarray(pts, dtype=np.float64),
        np.ascontiguousarray(tri, dtype=np.int64),
        np.ascontiguousarray(nb, dtype=np.int64),
        np.ascontiguousarray(tri_face, dtype=np.int64),
        int(n_f),
    )
    return arc_faces, arc_a, arc_b, (keys, arc_of)


def _arc_geometry(pts, com, face_up, face_h, arc_faces, arc_a, arc_b):
    """Each arc between two face normals: its angle, tangent, the CoM height along it (amplitude and phase of a
    sinusoid), where it peaks, and the peak's height and up-direction.
    Compiled (``_exact_kernels.arc_geometry``); the tests hold its reference twin."""
    return _exact_kernels.arc_geometry(pts, com, face_up, face_h, arc_faces, arc_a, arc_b)


def _half_edges(arc_faces, arc_a, arc_b, n_f: int):
    """Faces' boundaries as half-edges sorted by face (CSR): pointer, arc and end vertices of each."""
    n_a = len(arc_faces)
    half_face = np.concatenate([arc_faces[:, 0], arc_faces[:, 1]])
    half_arc = np.concatenate([np.arange(n_a), np.arange(n_a)])
    half_a = np.concatenate([arc_a, arc_a])
    half_b = np.concatenate([arc_b, arc_b])
    order = np.argsort(half_face, kind="stable")
    half_face, half_arc, half_a, half_b = half_face[order], half_arc[order], half_a[order], half_b[order]
    half_ptr = np.zeros(n_f + 1, dtype=np.int64)
    np.cumsum(np.bincount(half_face, minlength=n_f), out=half_ptr[1:])
    return half_ptr, half_face, half_arc, half_a, half_b


def _critical_points(
    partial: ExactLandscape, d, nbr_ptr, nbr_idx, margin, peak_s, theta, foot, seg_len, ang_tol: float
) -> CriticalPoints:
    """Minima (faces the CoM projects strictly inside), saddles (arc peaks strictly inside their arc and
    edge), maxima (vertices higher than all their neighbours), and the two minima each saddle joins (on first
    use)."""
    tol_m, scale, k_v = partial.tol_m, partial.mass_kg * partial.g_m_s2, len(d)
    face_up, face_h, arc_max, peak_up = (
        partial.face_up,
        partial.face_height_m,
        partial.arc_max_m,
        partial.arc_peak_up,
    )
    minima_face = np.flatnonzero(margin > tol_m).astype(np.int64)
    saddle = (peak_s > ang_tol) & (peak_s < theta - ang_tol) & (foot > tol_m) & (foot < seg_len - tol_m)
    saddles_arc = np.flatnonzero(saddle).astype(np.int64)
    dn = d / np.linalg.norm(d, axis=1, keepdims=True)
    src = np.repeat(np.arange(k_v), np.diff(nbr_ptr))
    gap = np.einsum("ij,ij->i", d[src] - d[nbr_idx], dn[src])  # vertex k vs its neighbour at u = d_k/|d_k|
    worst = np.minimum.reduceat(gap, nbr_ptr[:-1])  # every hull vertex has neighbours
    maxima_vertex = np.flatnonzero(worst > tol_m).astype(np.int64)
    return CriticalPoints(
        minima_face,
        _deg(face_up[minima_face]),
        scale * face_h[minima_face],
        saddles_arc,
        _deg(peak_up[saddles_arc]),
        scale * arc_max[saddles_arc],
        maxima_vertex,
        _deg(dn[maxima_vertex]),
        scale * np.linalg.norm(d[maxima_vertex], axis=1),
        partial,
    )


def _joins(ex: ExactLandscape, minima_face: NDArray[np.int64], arcs: NDArray[np.int64]) -> NDArray[np.int64]:
    """The minima (rows of ``minima_face``) reached by rolling down from either face of each arc, (len, 2)."""
    row = np.full(len(ex.face_up), -1, dtype=np.int64)
    row[minima_face] = np.arange(len(minima_face))
    faces, where = np.unique(ex.arc_faces[arcs], return_inverse=True)  # roll down from each face once
    reached = np.array([row[_descend_face(ex, int(f))] for f in faces.tolist()], dtype=np.int64)
    return reached[where.reshape(-1)].reshape(-1, 2)


def _build(hull: Hull, com: NDArray[np.float64], mass_kg: float, g_m_s2: float) -> ExactLandscape:
    pts = np.ascontiguousarray(hull.vertices_m, dtype=np.float64)
    diam = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    tol_m = LENGTH_RTOL * max(diam, np.finfo(float).tiny)
    if len(hull.simplices):
        # the hull again with facets within the tolerance merged, so that every predicate below sees facets
        # and edges convex by more than the tolerance (rounding noise leaves no slivers; module docstring)
        hull = convex_hull(pts, merge_tol_m=tol_m)
        pts = np.ascontiguousarray(hull.vertices_m, dtype=np.float64)
    k_v = len(pts)
    tri, nb, tri_face, n_f, normal = _merged_faces(hull, com, tol_m)
    d = com[None, :] - pts
    face_up = -normal
    # faces' vertices and the faces at each vertex
    fr = np.repeat(tri_face, 3)
    face_ptr, face_idx = _csr(n_f, fr, tri.ravel())
    # CoM height resting on each face: its vertices are the lowest there
    face_h = np.maximum.reduceat(
        np.einsum("ij,ij->i", face_up[np.repeat(np.arange(n_f), np.diff(face_ptr))], d[face_idx]),
        face_ptr[:-1],
    )
    vface_ptr, vface_idx = _csr(k_v, tri.ravel(), fr)
    arc_faces, arc_a, arc_b, pair_arc = _arcs(pts, tri, nb, tri_face, n_f)
    theta, t, seg_len, foot, w, peak_s, arc_max, peak_up = _arc_geometry(
        pts, com, face_up, face_h, arc_faces, arc_a, arc_b
    )
    half_ptr, half_face, half_arc, half_a, half_b = _half_edges(arc_faces, arc_a, arc_b, n_f)
    face_proj = com[None, :] - face_h[:, None] * face_up  # c + h n: the foot on the face plane
    margin = _face_margins(pts, normal, face_proj, face_ptr, face_idx, half_ptr, half_a, half_b)
    nbr_ptr, nbr_idx = hull.neighbor_ptr, hull.neighbor_idx  # the triangles' edges, neighbours sorted
    face_next = _face_exits(pts, face_proj, half_ptr, half_arc, half_a, half_b, arc_faces, margin, tol_m)
    g = _Graph(
        d,
        nbr_ptr,
        nbr_idx,
        face_ptr,
        face_idx,
        vface_ptr,
        vface_idx,
        face_proj,
        half_ptr,
        half_arc,
        half_a,
        half_b,
        t,
        theta,
        w,
        peak_s,
        foot,
        seg_len,
        pair_arc,
        face_next,
    )
    ang_tol = tol_m / max(float(np.linalg.norm(d, axis=1).max()), tol_m)
    arcs_ab = np.stack([arc_a, arc_b], axis=1)
    partial = ExactLandscape(
        mass_kg,
        g_m_s2,
        com,
        pts,
        tol_m,
        face_up,
        face_h,
        margin,
        arc_faces,
        arcs_ab,
        arc_max,
        peak_up,
        None,
        g,
    )
    crit = _critical_points(partial, d, nbr_ptr, nbr_idx, margin, peak_s, theta, foot, seg_len, ang_tol)
    return replace(partial, critical=crit)


def _face_margins(pts, normal, proj, face_ptr, face_idx, half_ptr, half_a, half_b):
    """Signed distance of each face's CoM projection inside its boundary, m (min over boundary edges).
    Compiled (``_exact_kernels.face_margins``); the tests hold its reference twin."""
    return _exact_kernels.face_margins(pts, normal, proj, face_ptr, face_idx, half_ptr, half_a, half_b)


def _deg(u: NDArray[np.float64]) -> NDArray[np.float64]:
    p, r = pitch_roll_from_up(u.reshape(-1, 3))
    return np.stack([np.rad2deg(p), np.rad2deg(r)], axis=-1).reshape(-1, 2)


# --------------------------------------------------------------------------------------------- rolling down
def _cell_step(ex: ExactLandscape, k: int, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """Steepest descent inside vertex k's cell: along the great circle away from d_k to the cell's boundary.

    Compiled (``_exact_kernels.cell_step``); the tests hold its reference twin.
    """
    g = ex._g
    out, moved = _exact_kernels.cell_step(g.d, int(k), np.ascontiguousarray(u, dtype=np.float64))
    if moved:
        return out
    faces = g.vface_idx[
        g.vface_ptr[k] : g.vface_ptr[k + 1]
    ]  # balanced on the vertex: fall onto its lowest face
    f = int(faces[np.argmin(ex.face_height_m[faces])])
    return ex.face_up[f].copy()


def _node_face(ex: ExactLandscape, top: int, u: NDArray[np.float64]) -> int:
    g = ex._g
    faces = g.vface_idx[g.vface_ptr[top] : g.vface_ptr[top + 1]]
    return int(faces[np.argmax(ex.face_up[faces] @ u)])


def _face_exits(pts, proj, half_ptr, half_arc, half_a, half_b, arc_faces, margin, tol_m):
    """Where each face that is no minimum tips: over the boundary feature nearest the CoM's projection.

    Returns, per face, -1 (a minimum), the next face (tipping over an edge) or -2 - k (pivoting on vertex k).
    Compiled (``_exact_kernels.face_exits``); the tests hold its reference twin.
    """
    return _exact_kernels.face_exits(
        pts, proj, half_ptr, half_arc, half_a, half_b, arc_faces, margin, float(tol_m)
    )


def _descend_face(ex: ExactLandscape, f: int) -> int:
    """The minimum face reached by quasi-static rolling from resting on face f."""
    nxt = ex._g.face_next
    memo = ex._g.descended  # a deterministic function of the face: each face is rolled down from once
    seen = []
    for _ in range(len(nxt) + 1):
        if f in memo:
            out = memo[f]
            break
        seen.append(f)
        if nxt[f] == -1:
            out = f
            break
        if nxt[f] >= 0:
            f = int(nxt[f])
        else:
            out = _descend_from(ex, _cell_step(ex, int(-2 - nxt[f]), ex.face_up[f]))
            break
    else:
        raise RuntimeError(f"rolling down from face {f} did not settle; please report this body")
    for x in seen:
        memo[x] = out
    return out


def _descend_from(ex: ExactLandscape, u: NDArray[np.float64]) -> int:
    """The minimum face reached by quasi-static rolling (steepest descent of h) from up-direction u."""
    g = ex._g
    u = np.asarray(u, dtype=np.float64)
    u = np.ascontiguousarray(u / np.linalg.norm(u))
    budget = 4 * (len(ex.face_up) + len(ex.vertices_m)) + 8
    while budget > 0:
        # the steps inside single vertices' cells, compiled: u, the top vertex, the active ones (within tol)
        u, top, a0, a1, n_act, steps = _exact_kernels.roll_in_cells(g.d, u, float(ex.tol_m), budget)
        budget -= steps + 1
        if n_act == 0:
            break
        top = int(top)
        if n_act == 1:  # balanced on the vertex: fall onto its lowest face
            u = _cell_step(ex, top, u)
            continue
        if n_act == 2:
            key = int(a0) * len(g.d) + int(a1)
            i = int(np.searchsorted(g.pair_arc[0], key))
            arc = int(g.pair_arc[1][i]) if i < len(g.pair_arc[0]) and g.pair_arc[0][i] == key else None
            if arc is not None:
                f0, f1 = (int(x) for x in ex.arc_faces[arc])
                foot, L = g.arc_foot[arc], g.arc_len[arc]
                if foot < -ex.tol_m or foot > L + ex.tol_m:  # CoM beyond an end: pivot onto that vertex
                    k = int(ex.arc_vertices[arc, 0] if foot < 0 else ex.arc_vertices[arc, 1])
                    u = _cell_step(ex, k, u)
                    continue
                s = np.arctan2(u @ g.arc_t[arc], u @ ex.face_up[f0])
                ang_tol = ex.tol_m / max(np.linalg.norm(g.arc_w[arc]), ex.tol_m)
                if s < g.arc_peak_s[arc] - ang_tol:
                    f = f0
                elif s > g.arc_peak_s[arc] + ang_tol:
                    f = f1
                else:  # on the saddle: the lower side, ties to the lower face index
                    f = f0 if (ex.face_height_m[f0], f0) <= (ex.face_height_m[f1], f1) else f1
                return _descend_face(ex, f)
        return _descend_face(ex, _node_face(ex, top, u))
    raise RuntimeError("rolling down did not settle; please report this body")


# --------------------------------------------------------------------------------------------- searches
def _adjacency(n: int, eu, ev, ew):
    """The undirected graph's adjacency in CSR form: pointer, neighbour, edge index and weight of each entry
    (neighbours of a node in edge order, the ``eu`` ends before the ``ev`` ends)."""
    ptr = np.zeros(n + 1, dtype=np.int64)
    ends = np.concatenate([eu, ev])
    order = np.argsort(ends, kind="stable")
    np.cumsum(np.bincount(ends, minlength=n), out=ptr[1:])
    m = len(eu)
    edge = order % m
    other = np.concatenate([ev, eu])[order].astype(np.int64)
    return ptr, other, edge.astype(np.int64), np.asarray(ew, dtype=np.float64)[edge]


def _chain(parent, eu, ev, x: int) -> list[tuple[int, int]]:
    """(edge, node reached) pairs from the source to x along the search tree."""
    out = []
    while parent[x] >= 0:
        e = int(parent[x])
        out.append((e, x))
        x = int(eu[e] if ev[e] == x else ev[e])
    return out[::-1]


def _pieces_points(ex: ExactLandscape, pieces: list[tuple]) -> NDArray[np.float64]:
    """Up-directions along each piece's arc, at most ``PATH_STEP_DEG`` apart, without each piece's first point,
    in one array (``np.linspace(s0, s1, n)``'s arithmetic, done for all pieces at once)."""
    g = ex._g
    arcs = np.array([pc[0] for pc in pieces], dtype=np.int64)
    s0 = np.array([pc[1] for pc in pieces], dtype=np.float64)
    s1 = np.array([pc[2] for pc in pieces], dtype=np.float64)
    n = np.maximum(2, np.ceil(np.abs(s1 - s0) / np.deg2rad(PATH_STEP_DEG)).astype(np.int64) + 1)
    div = (n - 1).astype(np.float64)
    delta = s1 - s0
    step = delta / div
    owner = np.repeat(np.arange(len(arcs)), n - 1)
    i = (np.arange(len(owner)) - np.repeat(np.cumsum(n - 1) - (n - 1), n - 1) + 1).astype(np.float64)
    s = np.where(step[owner] == 0, i / div[owner] * delta[owner], i * step[owner]) + s0[owner]
    last = np.cumsum(n - 1) - 1
    s[last] = s1
    u0 = ex.face_up[ex.arc_faces[arcs[owner], 0]]
    return np.cos(s)[:, None] * u0 + np.sin(s)[:, None] * g.arc_t[arcs[owner]]


def _wrap(x: float) -> float:
    return (x + 180.0) % 360.0 - 180.0


def _nearest_rep(p: float, r: float, p_ref: float, r_ref: float) -> tuple[float, float]:
    """The torus representative of (p, r), shifted by whole turns, nearest to (p_ref, r_ref), degrees.

    Nearest in the larger of the pitch and roll differences; ties keep (p, r).
    """
    pole = abs(abs(p) - 90.0) < 1e-9  # at a pole any roll is the same orientation
    p1, r1 = p_ref + _wrap(p - p_ref), r_ref if pole else r_ref + _wrap(r - r_ref)
    p2, r2 = p_ref + _wrap(180.0 - p - p_ref), r_ref if pole else r_ref + _wrap(r + 180.0 - r_ref)
    if max(abs(p2 - p_ref), abs(r2 - r_ref)) < max(abs(p1 - p_ref), abs(r1 - r_ref)) - 1e-12:
        return p2, r2
    return p1, r1


def _torus_path(us: NDArray[np.float64], start_deg: tuple[float, float]) -> NDArray[np.float64]:
    """A continuous torus path through up-directions: each point's representative nearest the previous one
    (:func:`_nearest_rep`, compiled as ``_exact_kernels.torus_path``)."""
    return _exact_kernels.torus_path(np.ascontiguousarray(_deg(us)), float(start_deg[0]), float(start_deg[1]))


def _in_sectors(us: NDArray[np.float64], start_deg: tuple[float, float]):
    """Whether points lie in the pitch sector (|d roll| <= |d pitch|) and the roll sector around the start.

    Uses each point's torus representative nearest the start (as :func:`_nearest_rep`). Within
    ``SECTOR_TOL_DEG`` of a pole a point is in both sectors (its roll is undefined there), and so is a point
    within that angle of the sectors' boundary.
    """
    pr = _deg(us)
    pole = np.abs(np.abs(pr[:, 0]) - 90.0) < SECTOR_TOL_DEG
    d = []
    for p, r in ((pr[:, 0], pr[:, 1]), (180.0 - pr[:, 0], pr[:, 1] + 180.0)):
        dp = np.abs(wrap_deg(p - start_deg[0]))
        dr = np.where(pole, 0.0, np.abs(wrap_deg(r - start_deg[1])))
        d.append((dp, dr))
    second = np.maximum(*d[1]) < np.maximum(*d[0]) - 1e-12
    dp = np.where(second, d[1][0], d[0][0])
    dr = np.where(second, d[1][1], d[0][1])
    return dr <= dp + SECTOR_TOL_DEG, dp <= dr + SECTOR_TOL_DEG


def _direction(u: NDArray[np.float64], start_deg: tuple[float, float]) -> str:
    p, r = _deg(u)[0]
    pp, rr = _nearest_rep(float(p), float(r), *start_deg)
    return "pitch" if abs(pp - start_deg[0]) >= abs(rr - start_deg[1]) else "roll"


def _exit(
    ex: ExactLandscape,
    level_m: float,
    start_h: float,
    start_deg,
    pieces,
    kind: str | None,
    *,
    peak: int | None = None,
    contacts: Contacts | None = None,
) -> Exit:
    """pieces: list of (arc, s0, s1, peak_h, peak_up) traversed in order; the saddle is the highest piece's
    peak (the first of equals) unless ``peak`` names the piece."""
    us = [up_vector(*np.deg2rad(start_deg))[None, :]]
    if pieces:
        us.append(_pieces_points(ex, pieces))
    path = _torus_path(np.concatenate(us), start_deg)
    k = peak if peak is not None else int(np.argmax([ph for *_, ph, _ in pieces])) if pieces else -1
    saddle_up = pieces[k][4] if pieces else up_vector(*np.deg2rad(start_deg))
    sp, sr = canonical_pitch_roll_deg(*_deg(saddle_up)[0])
    direction = kind or _direction(saddle_up, start_deg)
    return Exit(float(ex.energy_scale_j * (level_m - start_h)), sp, sr, direction, path, contacts)


def _pieces(ex: ExactLandscape, arcs, s0, s1) -> list[tuple]:
    """Traversals of arcs from s0 to s1: (arc, s0, s1, highest CoM height m, where it is reached).

    On an arc ``h(s) = w.u(s) = A cos s + B sin s``, highest at an end or at the peak ``atan2(B, A)``.
    """
    g = ex._g
    arcs = np.atleast_1d(np.asarray(arcs, dtype=np.int64))
    s0 = np.broadcast_to(np.asarray(s0, dtype=np.float64), arcs.shape)
    s1 = np.broadcast_to(np.asarray(s1, dtype=np.float64), arcs.shape)
    u0 = ex.face_up[ex.arc_faces[arcs, 0]]
    t = g.arc_t[arcs]
    amp_a = np.einsum("ij,ij->i", g.arc_w[arcs], u0)
    amp_b = np.einsum("ij,ij->i", g.arc_w[arcs], t)
    lo, hi = np.minimum(s0, s1), np.maximum(s0, s1)
    peak = g.arc_peak_s[arcs]
    cand = np.stack([lo, hi, np.where((lo < peak) & (peak < hi), peak, lo)], axis=1)
    h = amp_a[:, None] * np.cos(cand) + amp_b[:, None] * np.sin(cand)
    k = np.argmax(h, axis=1)
    s_pk = cand[np.arange(len(arcs)), k]
    up = np.cos(s_pk)[:, None] * u0 + np.sin(s_pk)[:, None] * t
    h_pk = h[np.arange(len(arcs)), k]
    return [
        (int(a_), float(x0), float(x1), float(hh), uu)
        for a_, x0, x1, hh, uu in zip(arcs.tolist(), s0.tolist(), s1.tolist(), h_pk.tolist(), up, strict=True)
    ]


def _whole_pieces(ex: ExactLandscape, arcs, forward) -> list[tuple]:
    """Whole arcs as pieces (:func:`_pieces`) in one call, forward (face 0 -> face 1) or back."""
    arcs = np.asarray(arcs, dtype=np.int64)
    forward = np.asarray(forward, dtype=bool)
    if not len(arcs):
        return []
    theta = ex._g.arc_theta[arcs]
    return _pieces(ex, arcs, np.where(forward, 0.0, theta), np.where(forward, theta, 0.0))


def _joins_start_basin(ex: ExactLandscape, piece: tuple, start_row: int) -> bool:
    """Whether a piece's highest point is a saddle (an edge-arc peak with the CoM's foot inside the edge) whose
    two sides roll down into different basins, one of them the start's (row ``start_row`` of the minima)."""
    crit = ex.critical
    hit = np.flatnonzero(crit.saddles_arc == piece[0])
    if not len(hit) or np.linalg.norm(piece[4] - ex.arc_peak_up[piece[0]]) > 1e-9:
        return False
    joins = _joins(ex, crit.minima_face, crit.saddles_arc[hit[:1]])[0]
    return bool(joins[0] != joins[1] and start_row in joins)


def _escape_saddle(ex: ExactLandscape, pieces: list[tuple], f0: int, level_m: float) -> int:
    """Check that the escape path's highest point is a saddle between the start's basin and another one.

    The bottleneck level is a critical value (mountain pass), but a path may touch it at several points; the
    reported saddle must be a critical point (an edge-arc peak with the CoM's foot inside the edge) whose two
    sides roll down into different basins, one of them the start's. Returns the index of the first piece
    whose peak is such a saddle.

    Raises
    ------
    RuntimeError
        If no point of the path at the bottleneck level is such a saddle (a bug: please report the body).
    """
    start_row = int(np.flatnonzero(ex.critical.minima_face == f0)[0])
    for k, pc in enumerate(pieces):
        if pc[3] >= level_m - ex.tol_m and _joins_start_basin(ex, pc, start_row):
            return k
    raise RuntimeError(
        f"the escape path's highest point (level {level_m:.9g} m) is no saddle between the start's "
        "basin and another; please report this body"
    )


def exact_barrier(
    pose: Pose | ExactLandscape,
    start_pitch_deg: float,
    start_roll_deg: float,
    *,
    g_m_s2: float = G_M_S2,
    sectors: bool = True,
) -> ExactBarrier:
    """Exact righting, pitch-wise, roll-wise and escape barriers from the basin containing a start.

    Parameters
    ----------
    pose : geometry.Pose or ExactLandscape
        The posed body (or its exact landscape, to reuse it across starts).
    start_pitch_deg, start_roll_deg : float
        Start orientation, degrees; the body rolls down from it (quasi-statically) to the face it settles on.
    g_m_s2 : float
        Gravitational acceleration, m/s^2 (ignored when an ExactLandscape is given).
    sectors : bool
        Also search the pitch-wise and roll-wise sectors (upper bounds, see the module docstring); with False
        those two exits are None (``landscape.computation`` fills them its own way and skips this cost).

    Returns
    -------
    ExactBarrier
        The start minimum and a Barrier of exits, with the grid method's meaning (module docstring).

    Raises
    ------
    ExactMethodError
        If the hull is flat or the CoM lies outside it.
    ValueError
        If the start angles are not finite.

    Examples
    --------
    >>> import trimesh
    >>> from geometry import Robot
    >>> cube = Robot.from_trimesh(trimesh.creation.box(extents=(2.0, 2.0, 2.0)), mass_kg=1.0)
    >>> b = exact_barrier(cube.pose(), 0.0, 0.0, g_m_s2=1.0)
    >>> bool(abs(b.barrier.righting.barrier_j - (np.sqrt(2) - 1)) < 1e-12), b.barrier.righting.saddle_roll_deg
    (True, 45.0)
    >>> box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0)
    >>> b = exact_barrier(box.pose(), 3.0, -2.0, g_m_s2=1.0)
    >>> b.start.pitch_deg, b.start.roll_deg, round(b.barrier.roll_wise.barrier_j, 6), b.barrier.righting.direction
    (0.0, 0.0, 0.618034, 'roll')
    """
    if not (np.isfinite(start_pitch_deg) and np.isfinite(start_roll_deg)):
        raise UsageError(
            f"start pitch and roll must be finite degrees; got ({start_pitch_deg!r}, {start_roll_deg!r})"
        )
    ex = pose if isinstance(pose, ExactLandscape) else exact_landscape(pose, g_m_s2=g_m_s2)
    u = up_vector(np.deg2rad(start_pitch_deg), np.deg2rad(start_roll_deg))
    f0 = _descend_from(ex, u)
    h0 = float(ex.face_height_m[f0])
    p0, r0 = (float(x) for x in _deg(ex.face_up[f0])[0])
    p0, r0 = canonical_pitch_roll_deg(p0, r0)
    start = Minimum(p0, r0, ex.energy_scale_j * h0, h0)
    start_deg = (p0, r0)
    escape = _escape_exit(ex, int(f0), h0, start_deg)
    upright = ex.face_up[:, 2] <= UPRIGHT_Z_TOL  # faces with u_z <= tol are upright
    if upright[f0]:
        still = Contacts(_face_contact(ex, int(f0)), (), np.inf)  # upright already: the barrier stays 0
        zero = Exit(0.0, p0, r0, "roll", np.array([start_deg], dtype=np.float64), still)
        return ExactBarrier(start, int(f0), Barrier(zero, zero, zero, escape), ex)
    rg = _righting_graph(ex, upright)
    righting = rg.exit(ex, np.ones(len(rg.eu), dtype=bool), int(f0), h0, start_deg, None)
    if not sectors:
        return ExactBarrier(start, int(f0), Barrier(righting, None, None, escape), ex)
    pitch_wise, roll_wise = _sector_exits(ex, rg, int(f0), h0, start_deg)
    return ExactBarrier(start, int(f0), Barrier(righting, pitch_wise, roll_wise, escape), ex)


def _escape_exit(ex: ExactLandscape, f0: int, h0: float, start_deg) -> Exit | None:
    """Escape: the bottleneck path from the start face to any other minimum over the whole graph."""
    n_f = len(ex.face_up)
    fa, fb = ex.arc_faces[:, 0], ex.arc_faces[:, 1]
    goal = np.zeros(n_f, dtype=bool)
    goal[ex.critical.minima_face] = True
    goal[f0] = False
    start_row = int(np.flatnonzero(ex.critical.minima_face == f0)[0])
    found = _pass_path(
        ex,
        n_f,
        fa,
        fb,
        ex.arc_max_m,
        f0,
        goal,
        lambda arcs, toward: _whole_pieces(ex, arcs, fb[arcs] == toward),
        lambda pieces: [_joins_start_basin(ex, pc, start_row) for pc in pieces],
    )
    if found is None:
        return None
    level, routes = found.level_m, []
    for chain, k_pass in found.chains:
        pieces = _whole_pieces(ex, [e for e, _ in chain], [fb[e] == x for e, x in chain])
        try:
            k = _escape_saddle(ex, pieces, f0, level)
        except RuntimeError:
            if routes:  # a tied route whose pass is no saddle between basins: its pass is its contact
                routes.append((pieces, k_pass))
                continue
            raise
        routes.append((pieces, k))
    pieces, k = routes[0]
    contacts = _contacts(ex, f0, level, routes, found)
    return _exit(ex, level, h0, start_deg, pieces, None, peak=k, contacts=contacts)


@dataclass(frozen=True)
class _Found:
    """A bottleneck search's answer: the level, m; each route out at it (chain of (edge, node reached) from the
    start and the index of its pass in the chain), the reported one first; whether each route rises to the level
    again after its pass; and the first-order gap (:attr:`Contacts.gap_m`), m."""

    level_m: float
    chains: list
    again: list
    gap_m: float


def _pass_path(
    ex: ExactLandscape, n: int, eu, ev, ew, f0: int, goal, pieces_of, prefer=None
) -> _Found | None:
    """The bottleneck path from ``f0`` to a goal node, through the pass the tie rule picks (module docstring).

    The start's basin is the set of nodes the search reaches below the bottleneck level minus the length
    tolerance; its passes are the edges out of it at the level (within the tolerance). With several, each is
    tried in the rule's order (first those ``prefer(pieces)`` marks), the others closed; those through which the
    goal stays at the level are the routes (the first is reported). ``pieces_of(edges, toward)`` gives the
    traversals of edges toward the given nodes.

    For first-order changes (:class:`landscape.barriers.Contacts`) it also finds the next route's level (every
    pass closed) and, per route, the lowest level from its pass's far side to the goal: at the level again (within
    the tolerance), the route rises to it twice.

    Returns None when no goal is reachable.
    """
    ptr, other, edge, weight = _adjacency(n, eu, ev, ew)
    sources = np.array([f0], dtype=np.int64)
    goal = np.ascontiguousarray(goal, dtype=np.bool_)
    lev, par, first = _exact_kernels.minimax_graph(ptr, other, edge, weight, sources, goal, True)
    if first < 0:
        return None
    level, tol = float(lev[first]), ex.tol_m
    basin = lev < level - tol  # settled below the level: reached before the goal, so exact
    passes = np.flatnonzero((basin[eu] != basin[ev]) & (ew <= level + tol))
    trees = [(par, first)]
    if len(passes) > 1:
        toward = np.where(basin[eu[passes]], ev[passes], eu[passes])
        pieces = pieces_of(passes, toward)
        preferred = np.ones(len(passes), dtype=bool) if prefer is None else np.asarray(prefer(pieces), bool)
        working = []
        for i in _tie_order(np.array([pc[4] for pc in pieces]), preferred):
            w = weight.copy()
            w[np.isin(edge, np.delete(passes, i))] = np.inf  # closed: never relaxed
            lev2, par2, first2 = _exact_kernels.minimax_graph(ptr, other, edge, w, sources, goal, True)
            if first2 >= 0 and lev2[first2] <= level + tol:
                working.append((par2, first2))
        trees = working or trees
    chains, again, gap = [], [], np.inf
    w = weight.copy()
    w[np.isin(edge, passes)] = np.inf
    lev3, _, first3 = _exact_kernels.minimax_graph(ptr, other, edge, w, sources, goal, True)
    if first3 >= 0:
        gap = float(lev3[first3]) - level  # the next route, above the level
    for par_, first_ in trees:
        chain = _chain(par_, eu, ev, int(first_))
        k = int(np.argmin(basin[[x for _, x in chain]]))  # the path leaves the basin once
        near = f0 if k == 0 else chain[k - 1][1]
        gap = min(gap, level - float(lev[near]))  # the start's side of the pass, below the level
        far = chain[k][1]
        beyond = -np.inf
        if not goal[far]:
            lev4, _, first4 = _exact_kernels.minimax_graph(
                ptr, other, edge, weight, np.array([far], dtype=np.int64), goal, True
            )
            beyond = float(lev4[first4]) if first4 >= 0 else np.inf
        again.append(beyond >= level - tol)
        if beyond < level - tol:
            gap = min(gap, level - beyond)  # the goal's side of the pass, below the level
        chains.append((chain, k))
    return _Found(level, chains, again, gap)


def _tie_order(up: NDArray[np.float64], preferred: NDArray[np.bool_]) -> list[int]:
    """Indices of up-directions in the tie rule's order: preferred ones first, then the largest canonical roll,
    then the smallest canonical pitch (coordinates within ``TIE_DEG`` equal), then the first given."""
    pr = np.array([canonical_pitch_roll_deg(p, r) for p, r in _deg(up).tolist()]).reshape(-1, 2)
    left, out = list(range(len(pr))), []
    while left:
        pool = [i for i in left if preferred[i]] or left
        top = max(pr[i, 1] for i in pool)
        pool = [i for i in pool if pr[i, 1] >= top - TIE_DEG]
        low = min(pr[i, 0] for i in pool)
        best = next(i for i in pool if pr[i, 0] <= low + TIE_DEG)
        out.append(best)
        left.remove(best)
    return out


@dataclass(frozen=True)
class _RightingGraph:
    """The face graph above the equator plus one target node: arcs between two faces above it (``arcs_in``),
    and arcs leaving it, cut where they cross the equator and joined to the target (``arcs_out``)."""

    eu: NDArray[np.int64]
    ev: NDArray[np.int64]
    ew: NDArray[np.float64]
    goal: NDArray[np.bool_]
    arcs_in: NDArray[np.int64]
    arcs_out: NDArray[np.int64]
    pieces_out: list

    @property
    def target(self) -> int:
        return len(self.goal) - 1

    def exit(
        self, ex: ExactLandscape, keep: NDArray[np.bool_], f0: int, h0: float, start_deg, kind: str | None
    ) -> Exit | None:
        """The bottleneck exit to upright over the edges ``keep``; None if upright is out of reach."""
        idx = np.flatnonzero(keep)
        eu, ev, ew = self.eu[idx], self.ev[idx], self.ew[idx]
        found = _pass_path(
            ex, len(self.goal), eu, ev, ew, f0, self.goal, lambda e, toward: self.pieces(ex, idx[e], toward)
        )
        if found is None:
            return None
        routes = []
        for chain, k in found.chains:
            chain = [(int(idx[e]), x) for e, x in chain]
            pieces = self.pieces(ex, np.array([e for e, _ in chain], dtype=np.int64), [x for _, x in chain])
            routes.append((pieces, k))
        contacts = _contacts(ex, f0, found.level_m, routes, found)
        return _exit(
            ex, found.level_m, h0, start_deg, routes[0][0], kind, peak=routes[0][1], contacts=contacts
        )

    def pieces(self, ex: ExactLandscape, edges, toward) -> list[tuple]:
        """Traversals of edges toward the given nodes: whole arcs above the equator, cut ones to the target."""
        edges = np.asarray(edges, dtype=np.int64)
        toward = np.asarray(toward, dtype=np.int64)
        n_in = len(self.arcs_in)
        inner = edges < n_in
        arcs = self.arcs_in[edges[inner]]
        whole = iter(_whole_pieces(ex, arcs, ex.arc_faces[arcs, 1] == toward[inner]))
        return [next(whole) if e < n_in else self.pieces_out[e - n_in] for e in edges.tolist()]


def _righting_graph(ex: ExactLandscape, upright: NDArray[np.bool_]) -> _RightingGraph:
    g = ex._g
    n_f = len(ex.face_up)
    fa, fb = ex.arc_faces[:, 0], ex.arc_faces[:, 1]
    arcs_in = np.flatnonzero(~upright[fa] & ~upright[fb])
    arcs_out = np.flatnonzero(upright[fa] != upright[fb])
    src = np.where(upright[fa[arcs_out]], fb[arcs_out], fa[arcs_out])  # the face above the equator
    fwd = ~upright[fa[arcs_out]]  # leaving from face 0 toward face 1
    u0z = ex.face_up[fa[arcs_out], 2]
    tz = g.arc_t[arcs_out, 2]
    theta_out = g.arc_theta[arcs_out]
    # z(s) = u0_z cos s + t_z sin s crosses 0 at s_c; forward arcs run 0 -> s_c, backward ones theta -> s_c
    s_c = np.clip(np.where(fwd, np.arctan2(u0z, -tz), np.arctan2(-u0z, tz)), 0.0, theta_out)
    pieces_out = _pieces(ex, arcs_out, np.where(fwd, 0.0, theta_out), s_c)
    eu = np.concatenate([fa[arcs_in], src]).astype(np.int64)
    ev = np.concatenate([fb[arcs_in], np.full(len(arcs_out), n_f)]).astype(np.int64)
    ew = np.concatenate([ex.arc_max_m[arcs_in], [pc[3] for pc in pieces_out]]).astype(np.float64)
    goal = np.zeros(n_f + 1, dtype=bool)
    goal[n_f] = True
    goal[:n_f] = upright  # never entered: isolated, all their arcs are cut
    return _RightingGraph(eu, ev, ew, goal, arcs_in, arcs_out, pieces_out)


def _sector_exits(ex: ExactLandscape, rg: _RightingGraph, f0: int, h0: float, start_deg):
    """Pitch-wise and roll-wise: the righting search on the arcs lying wholly inside the sector around the
    start (sampled every ``PATH_STEP_DEG``)."""
    g = ex._g
    fa = ex.arc_faces[:, 0]
    lo = np.concatenate([np.zeros(len(rg.arcs_in)), [min(pc[1], pc[2]) for pc in rg.pieces_out]])
    hi = np.concatenate([g.arc_theta[rg.arcs_in], [max(pc[1], pc[2]) for pc in rg.pieces_out]])
    arc_of = np.concatenate([rg.arcs_in, rg.arcs_out]).astype(np.int64)
    n_s = np.maximum(2, np.ceil((hi - lo) / np.deg2rad(PATH_STEP_DEG)).astype(np.int64) + 1)
    owner = np.repeat(np.arange(len(arc_of)), n_s)
    frac = (np.arange(len(owner)) - np.repeat(np.cumsum(n_s) - n_s, n_s)) / np.repeat(n_s - 1, n_s)
    s_all = lo[owner] + frac * (hi - lo)[owner]
    u_all = (
        np.cos(s_all)[:, None] * ex.face_up[fa[arc_of[owner]]]
        + np.sin(s_all)[:, None] * g.arc_t[arc_of[owner]]
    )
    in_pitch, in_roll = _in_sectors(u_all, start_deg)
    out = []
    for kind, inside in (("pitch", in_pitch), ("roll", in_roll)):
        ok = np.ones(len(arc_of), dtype=bool)
        np.logical_and.at(ok, owner, inside)
        out.append(rg.exit(ex, ok, f0, h0, start_deg, kind))
    return out[0], out[1]


# --------------------------------------------------------------------------------------------- first order
def _face_contact(ex: ExactLandscape, f: int) -> Contact:
    """Resting on face f: its vertices; the margin is the CoM projection's distance inside the face."""
    g = ex._g
    pts = ex.vertices_m[g.face_idx[g.face_ptr[f] : g.face_ptr[f + 1]]]
    return Contact("face", ex.face_up[f].copy(), pts, float(ex.face_margin_m[f]))


def _edge_points(ex: ExactLandscape, arc: int) -> NDArray[np.float64]:
    """The vertices of an arc's edge: its two ends first, then any collinear ones between them."""
    g = ex._g
    fa, fb = (int(x) for x in ex.arc_faces[arc])
    common = np.intersect1d(
        g.face_idx[g.face_ptr[fa] : g.face_ptr[fa + 1]], g.face_idx[g.face_ptr[fb] : g.face_ptr[fb + 1]]
    )
    ends = [int(x) for x in ex.arc_vertices[arc]]
    return ex.vertices_m[ends + [int(k) for k in common if k not in ends]]


def _contact(ex: ExactLandscape, piece: tuple) -> Contact:
    """The contact at a piece's highest point: the edge's saddle (its arc's peak, strictly inside the piece), a
    face node (an end of the arc), or the cut where a righting arc meets u_z = 0.

    Margins (:attr:`Contact.margin_m`): a CoM move of d turns the perpendicular ``w`` from the edge line by at
    most about d / |w|, so the arc's peak moves along the arc by at most that angle; a saddle's foot moves along
    its edge by at most d.
    """
    g = ex._g
    arc, s0, s1, _, up = piece
    u0 = ex.face_up[ex.arc_faces[arc, 0]]
    s = float(np.arctan2(up @ g.arc_t[arc], up @ u0))
    theta, peak = float(g.arc_theta[arc]), float(g.arc_peak_s[arc])
    wn = float(np.linalg.norm(g.arc_w[arc]))
    lo, hi = min(s0, s1), max(s0, s1)
    eps = 1e-12
    if lo < peak < hi and abs(s - peak) <= eps:
        foot, length = float(g.arc_foot[arc]), float(g.arc_len[arc])
        margin = min(foot, length - foot, (peak - lo) * wn, (hi - peak) * wn)
        return Contact("edge", np.asarray(up, dtype=np.float64), _edge_points(ex, arc), margin)
    if abs(s) <= eps or abs(s - theta) <= eps:
        c = _face_contact(ex, int(ex.arc_faces[arc, 0 if abs(s) <= eps else 1]))
        return replace(c, margin_m=abs(peak - s) * wn)  # the arc's peak reaching the node
    return Contact("cut", np.asarray(up, dtype=np.float64), _edge_points(ex, arc), abs(peak - s) * wn)


def _contacts(ex: ExactLandscape, f0: int, level_m: float, routes: list, found: _Found) -> Contacts:
    """The exit's :class:`Contacts`: each route's pass, and the later pieces at the level where the route rises
    to it again (``found.again``)."""
    out = []
    for (pieces, k), again in zip(routes, found.again, strict=True):
        later = [pc for pc in pieces[k + 1 :] if pc[3] >= level_m - ex.tol_m] if again else []
        out.append(tuple(_contact(ex, pc) for pc in [pieces[k], *later]))
    return Contacts(_face_contact(ex, f0), tuple(out), found.gap_m)


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
    """The registry's entry (:mod:`landscape.barriers`): exact start minimum, righting and escape exits."""
    ex = exact_barrier(pose, *start_deg, g_m_s2=g_m_s2, sectors=False)
    return ex.start, ex.barrier
