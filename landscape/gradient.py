"""First-order changes of the barriers: their derivatives with respect to the CoM, the mass and the joint angles.

A barrier is ``B = m g (h(u_s) - h(u_0))``: the CoM's height over the lowest hull point at the saddle ``u_s`` minus
that at the start minimum ``u_0`` (``u`` is world-up in the body frame, geometry/frames.py). What sets each height
to first order is the body's contact with the ground there (:class:`landscape.barriers.Contact`):

- *face* (the start minimum; a face node where a path peaks): ``h`` is the distance from the CoM ``c`` to the
  face's plane, ``h = u.(c - p)`` with ``p`` the CoM's foot on it;
- *edge* (a saddle, the highest point of an edge's arc): ``h`` is the distance from ``c`` to the edge's line,
  ``u`` the unit perpendicular from the line to ``c``;
- *cut* (a righting path that ends where an edge's arc crosses ``u_z = 0``): ``h = u.(c - a)`` with
  ``u = +-(e x z) / |e x z|`` fixed by the edge's direction ``e`` and the vertical ``z``;
- *direction* (a grid cell or icosphere vertex): ``u`` fixed, ``h = u.(c - v)`` with ``v`` the lowest hull point.

**CoM.** In every case ``dh/dc = u``: at a face, an edge or a fixed direction because ``u`` does not depend on
``c``, at an edge's saddle because its height is the distance to a line (the envelope theorem: the saddle's own
move along the arc changes ``h`` only to second order). Hence ``dB/dc = m g (u_s - u_0)``, body frame.

**Mass.** At a fixed CoM every height is independent of the mass: ``dB/dm = B / m``.

**A joint angle.** Turning a joint group at rate 1 moves each hull point ``x`` at ``x'`` and the CoM at ``c'``
(links move, so the CoM moves too; :func:`geometry.motion.pose_rates`). For a face, ``h = u.(c - p)`` with ``p``
the material point at the CoM's foot; since ``c - p`` is parallel to ``u`` and ``u'`` is perpendicular to it,
``h' = u.(c' - p')``, where ``p'`` is the face's velocity at the foot: the face's normal velocities ``u.x'_k`` at
its vertices, fitted by an affine function of position in its plane, evaluated at the foot. For an edge the same
holds with the edge's velocity at the foot of the perpendicular (an affine fit along its line). For a cut ``u``
turns with the edge: ``h' = u.(c' - a') + (c - a).u'`` with ``u' = +-(1 - u u^T)(e' x z) / |e x z|`` and
``e' = (1 - e e^T)(b' - a') / |b - a|``. For a direction, ``h' = u.(c' - v')``. A face whose vertices'
normal velocities are not affine (within ``RIGID_RTOL``), or an edge whose vertices do not stay on one line, bends
under the motion: the contact splits into smaller ones and the one-sided derivatives differ.

**Where the derivative does not exist** (null in the output, with the reason):

- several routes at the barrier level (within the exact method's length tolerance): equal saddles, e.g. the mirror
  images of a body symmetric left to right. The barrier is the lowest route's highest contact, a minimum of maxima;
  a derivative exists only where every contact's agrees (the mirror saddles' derivatives along x and z, and along a
  symmetric joint motion, agree; along y they are opposite). The one-sided gradient of each single-contact route
  is kept (:attr:`BarrierGradient.one_sided_com_j_per_m`): moving the CoM along minus the steepest of them lowers
  the barrier fastest;
- a path that rises to the level twice (a second crest equal to the saddle);
- a contact that bends under the joint motion (that joint group's derivative only), or a direction whose lowest hull
  point is not unique (a grid cell on a ridge);
- a switch within the exact method's length tolerance (``SWITCH_LENGTHS``): the start face about to stop being a minimum (the body
  changes basin), a saddle's foot at an end of its edge, its peak at an end of its arc, or another route or crest
  that close to the level (:attr:`BarrierGradient.reach_m`).

Beyond ``reach_m`` (a conservative bound on the CoM move that keeps every contact and route) the barrier may switch
to another saddle or basin, so a first-order band wider than it is not guaranteed;
:mod:`landscape.uncertainty` recomputes the barrier there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from geometry import Pose
from geometry.motion import _cross
from landscape.barriers._base import Barrier, Contact, Contacts, Exit
from landscape.barriers.exact import LENGTH_RTOL
from landscape.minima import Minimum

EXIT_NAMES = ("righting", "pitch_wise", "roll_wise", "escape")
ANGLES = ("theta_w", "theta_l")
RIGID_RTOL = 1e-9
"""A contact's vertices bend when their velocities depart from one affine field by more than this times the
largest velocity."""
EQUAL_RTOL = 1e-7
"""Tied contacts' derivatives within this relative tolerance (of ``m g`` per metre, of ``m g`` times the body's size
per radian) are equal."""
SWITCH_LENGTHS = 1.0
"""A switch closer than this many length tolerances (``LENGTH_RTOL`` times the hull's size, the exact method's
resolution) makes the derivative undefined (flagged), as a tie does."""
_Z = np.array([0.0, 0.0, 1.0])
_KEY = np.array([1.0, np.sqrt(2.0), np.pi])  # hull points' sort key (equal points, equal keys)


@dataclass(frozen=True)
class BarrierGradient:
    """First-order change of one exit's barrier.

    Attributes
    ----------
    com_j_per_m : ndarray of shape (3,) or None
        dB/dc, body frame, J/m; None where it does not exist (``reason``).
    mass_j_per_kg : float
        dB/dm at a fixed CoM, J/kg (= B / m).
    theta_w_j_per_deg, theta_l_j_per_deg : float or None
        dB/dtheta, J/deg (every joint of the group turning together); None where the robot lacks that joint group
        or the derivative does not exist.
    differentiable : bool
        Whether every derivative the robot has exists.
    reason : str or None
        Why one does not.
    one_sided_com_j_per_m : ndarray of shape (R, 3)
        The CoM gradient of each route at the level that has one contact, the reported saddle's first: one row
        where the barrier is differentiable, one per equal saddle at a tie (where it is not). Empty if no route
        has a single contact.
    reach_m : float
        CoM moves below this keep every contact and route (a conservative bound from the start face's margin, the
        saddle's place on its edge and arc, and the next route's and crest's levels), m; nan where not known (a
        grid or icosphere direction).
    """

    com_j_per_m: NDArray[np.float64] | None
    mass_j_per_kg: float
    theta_w_j_per_deg: float | None
    theta_l_j_per_deg: float | None
    differentiable: bool
    reason: str | None
    one_sided_com_j_per_m: NDArray[np.float64]
    reach_m: float

    def to_dict(self) -> dict:
        """In JSON types (SI): ``com_j_per_m`` (three numbers, body frame), ``mass_j_per_kg``,
        ``theta_w_j_per_deg``, ``theta_l_j_per_deg`` (None where the robot lacks that joint group or the derivative
        does not exist), ``differentiable``, ``reason``, ``one_sided_com_j_per_m`` (each equal saddle's) and
        ``reach_m`` (None where not known)."""
        return {
            "com_j_per_m": None if self.com_j_per_m is None else [float(x) for x in self.com_j_per_m],
            "mass_j_per_kg": self.mass_j_per_kg,
            "theta_w_j_per_deg": self.theta_w_j_per_deg,
            "theta_l_j_per_deg": self.theta_l_j_per_deg,
            "differentiable": self.differentiable,
            "reason": self.reason,
            "one_sided_com_j_per_m": [[float(x) for x in row] for row in self.one_sided_com_j_per_m],
            "reach_m": None if math.isnan(self.reach_m) else float(self.reach_m),
        }

    def steepest_descent(self) -> tuple[NDArray[np.float64], float] | None:
        """The unit CoM direction that lowers the barrier fastest, and how fast, J/m (> 0); None without one.

        At a tie the barrier is the lowest of its routes, so moving along minus the steepest route's gradient
        lowers it at that route's rate (the others can only be lower); of equally steep ones (mirror images), the
        reported saddle's.
        """
        g = self.one_sided_com_j_per_m
        if not len(g):
            return None
        norms = np.linalg.norm(g, axis=1)
        k = int(np.flatnonzero(norms >= norms.max() * (1 - EQUAL_RTOL))[0])  # ties: the reported saddle's
        if norms[k] == 0.0:
            return None
        return -g[k] / norms[k], float(norms[k])


def direction_contact(pitch_deg: float, roll_deg: float) -> Contact:
    """A fixed up-direction (a grid cell or icosphere vertex) as a :class:`Contact`."""
    return Contact("direction", _up(pitch_deg, roll_deg), np.zeros((0, 3)))


def _up(pitch_deg: float, roll_deg: float) -> NDArray[np.float64]:
    """World-up in the body frame of one orientation in degrees, (-sin p, cos p sin r, cos p cos r) as
    :func:`geometry.frames.up_vector` gives it (exact at multiples of 90 deg), in scalar arithmetic."""
    cp, sp = _cos_sin_deg(pitch_deg)
    cr, sr = _cos_sin_deg(roll_deg)
    return np.array([-sp, cp * sr, cp * cr])


def _cos_sin_deg(a_deg: float) -> tuple[float, float]:
    quarter = a_deg / 90.0
    k = round(quarter)
    if abs(quarter - k) < 1e-12:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[k % 4]
    a = math.radians(a_deg)
    return math.cos(a), math.sin(a)


def start_contact(minimum: Minimum, barrier: Barrier) -> Contact:
    """The start minimum's contact: the exact method's start face (its righting or escape exit carries it), else
    the minimum's fixed up-direction (a grid cell or icosphere vertex)."""
    for x in (barrier.righting, barrier.escape):
        if x is not None and x.contacts is not None:
            return x.contacts.start
    return direction_contact(minimum.pitch_deg, minimum.roll_deg)


def mirrored_contact(c: Contact) -> Contact:
    """The contact of the body's mirror image in its x-z plane (y -> -y)."""
    flip = np.array([1.0, -1.0, 1.0])
    return Contact(c.kind, c.up * flip, c.points_m * flip, c.margin_m)


def barrier_gradients(
    pose: Pose,
    minimum: Minimum,
    barrier: Barrier,
    *,
    rates: dict | None = None,
    g_m_s2: float,
) -> dict[str, BarrierGradient | None]:
    """The first-order change of every exit of a barrier (module docstring).

    Parameters
    ----------
    pose : geometry.Pose
        The posed body the barrier was found on.
    minimum : Minimum
        Its start minimum (where the exits carry no contacts: a grid cell or icosphere vertex).
    barrier : Barrier
    rates : dict of str to geometry.motion.PoseRate, optional
        Velocities of the hull points and the CoM per radian of each joint group (:func:`geometry.motion.pose_rates`);
        without one, that angle's derivative is None.
    g_m_s2 : float
        Gravitational acceleration, m/s^2.

    Returns
    -------
    dict of str to BarrierGradient or None
        Keyed ``righting``, ``pitch_wise``, ``roll_wise``, ``escape``; None for an exit that does not exist.

    Examples
    --------
    A box 4 x 2 x 1 m on its largest face, CoM 0.1 m off centre towards +y, m g = 1 J/m: the righting barrier
    rolls over the +y edge (y = 1, z = -0.5), where world-up is the unit vector from the edge to the CoM,
    ``w / norm(w)`` with ``w = (0, -0.9, 0.5)``; at the start it is (0, 0, 1), so ``dB/dc = w / norm(w) - (0, 0, 1)``:

    >>> import trimesh
    >>> from geometry import Robot
    >>> from landscape.barriers.exact import exact_barrier
    >>> box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0, com=(0, 0.1, 0))
    >>> b = exact_barrier(box.pose(), 0.0, 0.0, g_m_s2=1.0)
    >>> g = barrier_gradients(box.pose(), b.start, b.barrier, g_m_s2=1.0)["righting"]
    >>> w = np.array([0.0, -0.9, 0.5])
    >>> bool(np.allclose(g.com_j_per_m, w / np.linalg.norm(w) - [0, 0, 1])), g.mass_j_per_kg == b.barrier.righting.barrier_j
    (True, True)
    """
    rates = rates or {}
    default_start = start_contact(minimum, barrier)
    geo = _Geometry(pose, rates)
    out, done = {}, {}
    for name in EXIT_NAMES:
        x = getattr(barrier, name)
        if x is None:
            out[name] = None
            continue
        key = _exit_key(x)  # exits through the same contacts (righting and roll-wise, often escape) share all
        if key not in done:  # but the mass derivative
            done[key] = exit_gradient(geo, x, default_start, g_m_s2=g_m_s2)
        out[name] = replace(done[key], mass_j_per_kg=float(x.barrier_j / geo.mass_kg))
    return out


def _exit_key(x: Exit) -> tuple:
    """What an exit's gradient depends on besides its barrier: its contacts' content (or its grid direction)."""
    c = x.contacts
    if c is None:
        return ("direction", x.saddle_pitch_deg, x.saddle_roll_deg)

    def one(ct):
        return (ct.kind, ct.up.tobytes(), ct.points_m.tobytes(), ct.margin_m)

    return (
        one(c.start),
        tuple(tuple(one(ct) for ct in r) for r in c.routes),
        c.gap_m,
        x.saddle_pitch_deg,
        x.saddle_roll_deg,
    )


class _Geometry:
    """The posed body's hull points, CoM and their rates, with the contact derivatives computed on them."""

    def __init__(self, pose: Pose, rates: dict):
        self.pose = pose
        self.pts = np.asarray(pose.hull_points_m, dtype=np.float64)
        self.com = np.asarray(pose.com_m, dtype=np.float64)
        self.mass_kg = float(pose.mass_kg)
        size = float(np.linalg.norm(np.ptp(self.pts, axis=0))) if len(self.pts) else 1.0  # as exact.py's
        self.size_m = max(size, np.finfo(float).tiny)
        self.tol_m = LENGTH_RTOL * self.size_m
        self.rates = {a: rates[a] for a in ANGLES if a in rates}
        self._memo: dict = {}
        self._key = None

    def rows(self, points_m: NDArray[np.float64]) -> NDArray[np.int64]:
        """The rows of ``pose.hull_points_m`` at these points: a hull vertex is one of them (found by a scalar
        key, then checked); a point that is none (a mirror image) gets the nearest row."""
        if self._key is None:
            self._key = self.pts @ _KEY
        out = np.zeros(len(points_m), dtype=np.int64)
        for i, p in enumerate(points_m):
            hit = np.flatnonzero(self._key == p @ _KEY)
            hit = [r for r in hit.tolist() if (self.pts[r] == p).all()]
            out[i] = hit[0] if hit else int(np.argmin(((self.pts - p) ** 2).sum(axis=1)))
        return out

    def height_rates(self, c: Contact) -> tuple[dict[str, float | None], str | None]:
        """dh/dtheta per radian of each joint group at a contact (None where it bends), and why (computed once
        per contact: exits share theirs)."""
        key = (c.kind, c.up.tobytes(), c.points_m.tobytes())
        if key not in self._memo:
            self._memo[key] = self._height_rates(c)
        return self._memo[key]

    def _height_rates(self, c: Contact) -> tuple[dict[str, float | None], str | None]:
        out: dict[str, float | None] = {}
        note = None
        if c.kind == "direction":
            h = (self.com - self.pts) @ c.up
            low = np.flatnonzero(h >= h.max() - self.tol_m)
            for a, r in self.rates.items():
                vals = c.up @ (r.com_m_per_rad[:, None] - r.hull_points_m_per_rad[low].T)
                if np.ptp(vals) > RIGID_RTOL * (np.abs(vals).max() + 1e-300) and np.ptp(vals) > 0:
                    out[a], note = None, "the lowest hull point is not unique at a grid direction"
                else:
                    out[a] = float(vals[0])
            return out, note
        rows = self.rows(c.points_m)
        x = self.pts[rows]
        for a, r in self.rates.items():
            v, cv = r.hull_points_m_per_rad[rows], r.com_m_per_rad
            scale = float(np.abs(v).max() + np.abs(cv).max()) + 1e-300
            if c.kind == "face":
                rate, bends = _face_rate(self.com, c.up, x, v, cv, scale)
                what = "face"
            elif c.kind == "edge":
                rate, bends = _edge_rate(self.com, c.up, x, v, cv, scale)
                what = "edge"
            else:
                rate, bends = _cut_rate(self.com, c.up, x, v, cv, scale)
                what = "edge"
            out[a] = None if bends else rate
            if bends:
                note = f"the {what} the body touches bends as {a} turns (the contact splits)"
        return out, note


def _fit(coords: NDArray[np.float64], y: NDArray[np.float64], scale: float) -> tuple[float, bool]:
    """Least-squares affine fit ``y ~ alpha + beta . coords``: alpha (the value at the origin) and whether the
    residual exceeds ``RIGID_RTOL * scale``."""
    A = np.column_stack([np.ones(len(y)), coords])
    if len(y) == A.shape[1]:  # as many points as unknowns: the fit is exact
        return float(np.linalg.solve(A, y)[0]), False
    sol, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = float(np.abs(A @ sol - y).max()) if len(y) else 0.0
    return float(sol[0]), resid > RIGID_RTOL * scale


def _face_rate(com, u, x, v, cv, scale) -> tuple[float, bool]:
    h = float(((com - x) @ u).max())
    foot = com - h * u
    e1 = _cross(u, np.array([1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0]))
    e1 /= np.linalg.norm(e1)
    e2 = _cross(u, e1)
    rel = x - foot
    alpha, bends = _fit(np.column_stack([rel @ e1, rel @ e2]), v @ u, scale)
    return float(u @ cv - alpha), bends


def _line(com, x):
    e = x[1] - x[0]
    length = float(np.linalg.norm(e))
    e = e / length
    foot = x[0] + ((com - x[0]) @ e) * e
    return e, length, foot


def _straight(u, e, x, v, foot, scale) -> tuple[float, bool]:
    """The line's normal velocity along ``u`` at ``foot`` (affine fit along it) and whether it bends."""
    t = ((x - foot) @ e)[:, None]
    if len(x) == 2:  # two ends: the line's velocity is their interpolation, exactly
        y = v @ u
        return float(y[0] + (y[1] - y[0]) * (0.0 - t[0, 0]) / (t[1, 0] - t[0, 0])), False
    alpha, bend1 = _fit(t, v @ u, scale)
    _, bend2 = _fit(t, v @ _cross(u, e), scale)
    return alpha, bend1 or bend2


def _edge_rate(com, u, x, v, cv, scale) -> tuple[float, bool]:
    e, _, foot = _line(com, x)
    alpha, bends = _straight(u, e, x, v, foot, scale)
    return float(u @ cv - alpha), bends


def _cut_rate(com, u, x, v, cv, scale) -> tuple[float, bool]:
    e, length, foot = _line(com, x)
    _, bends = _straight(u, e, x, v, foot, scale)
    n = _cross(e, _Z)
    nn = float(np.linalg.norm(n))
    sign = 1.0 if n @ u >= 0 else -1.0
    uc = sign * n / nn
    de = (v[1] - v[0] - ((v[1] - v[0]) @ e) * e) / length
    duc = sign * (_cross(de, _Z) - (_cross(de, _Z) @ uc) * uc) / nn
    return float(uc @ (cv - v[0]) + (com - x[0]) @ duc), bends


def exit_gradient(geo: _Geometry, x: Exit, default_start: Contact, *, g_m_s2: float) -> BarrierGradient:
    """The :class:`BarrierGradient` of one exit (:func:`barrier_gradients`)."""
    scale = geo.mass_kg * g_m_s2
    contacts = x.contacts or Contacts(
        default_start, ((direction_contact(x.saddle_pitch_deg, x.saddle_roll_deg),),)
    )
    routes = contacts.routes
    if len(routes) > 1:
        saddle_up = _up(x.saddle_pitch_deg, x.saddle_roll_deg)
        routes = sorted(routes, key=lambda r: -float(r[0].up @ saddle_up))  # the reported saddle's first
    reasons = []
    start_rates, note = geo.height_rates(contacts.start)
    if note:
        reasons.append(note.replace("the face", "the start face"))
    grads, theta = [], {a: [] for a in geo.rates}
    for route in routes:
        g_route, t_route = [], {a: [] for a in geo.rates}
        for c in route:
            g_route.append(scale * (c.up - contacts.start.up))
            r, note = geo.height_rates(c)
            if note:
                reasons.append(note)
            for a in geo.rates:
                if r[a] is None or start_rates[a] is None:
                    t_route[a].append(None)
                else:
                    t_route[a].append(scale * (r[a] - start_rates[a]))
        grads.append(g_route)
        for a in geo.rates:
            theta[a].append(t_route[a])
    if len(routes) > 1:
        reasons.append(f"{len(routes)} saddles at the barrier level (equal within the tolerance)")
    if any(len(r) > 1 for r in routes):
        reasons.append("the path rises to the barrier level twice")
    flat = [g for r in grads for g in r]
    com = None
    if flat:
        stack = np.array(flat)
        if np.ptp(stack, axis=0).max() <= EQUAL_RTOL * scale:
            com = stack.mean(axis=0)
    else:
        com = np.zeros(3)  # already upright: the barrier stays 0
    reach = _reach(contacts, routes)
    if reach < SWITCH_LENGTHS * geo.tol_m:
        reasons.append(f"the saddle or the start minimum switches within {reach * 1e6:.2g} um of this CoM")
        com = None
    derivs = {}
    for a in ANGLES:
        if a not in geo.rates:
            derivs[a] = None
            continue
        val = _tied(theta[a], EQUAL_RTOL * scale * geo.size_m) if routes else 0.0
        derivs[a] = None if val is None or reach < SWITCH_LENGTHS * geo.tol_m else val * math.pi / 180.0
    one_sided = np.array([g[0] for g in grads if len(g) == 1]).reshape(-1, 3)
    differentiable = com is not None and all(derivs[a] is not None for a in geo.rates)
    return BarrierGradient(
        com,
        float(x.barrier_j / geo.mass_kg),
        derivs["theta_w"],
        derivs["theta_l"],
        differentiable,
        None if differentiable else "; ".join(dict.fromkeys(reasons)) or "not differentiable",
        one_sided,
        reach,
    )


def _tied(values: list[list[float | None]], tol: float) -> float | None:
    """The derivative of a lowest-of-highest (min over routes of max over contacts) along one parameter: the
    one-sided derivatives ``min_R max_i d_i`` (increasing) and ``max_R min_i d_i`` (decreasing) must agree."""
    if any(v is None for r in values for v in r):
        return None
    up = min(max(r) for r in values)
    down = max(min(r) for r in values)
    return float(up) if abs(up - down) <= tol else None


def _reach(contacts: Contacts, routes) -> float:
    """How far the CoM may move keeping every contact and route (:attr:`BarrierGradient.reach_m`), m."""
    margins = [contacts.start.margin_m, *(c.margin_m for r in routes for c in r), contacts.gap_m / 2.0]
    known = [m for m in margins if not math.isnan(m)]
    if len(known) < len(margins):
        return math.nan
    return float(min(known))
