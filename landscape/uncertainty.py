"""Barrier intervals under an uncertain CoM and mass: a first-order band from the gradients, and a Monte-Carlo range
that recomputes the barriers.

Both bound the barrier over the same set: every CoM within ``r`` of the nominal one (any direction) and every mass
within ``+-dm`` of the nominal one. Each is labelled as what it is (:data:`FIRST_ORDER`, :data:`MONTE_CARLO`):

- *first order*: ``B -+ (r |dB/dc| + dm |dB/dm|)``, the extremes of the linearised barrier over that set
  (:mod:`landscape.gradient`). Where the CoM gradient does not exist (equal saddles, a switch at this CoM) there is
  none, and the Monte-Carlo range stands in (:data:`DEFAULT_SAMPLES` samples unless more are asked for). Beyond the
  gradient's reach (``BarrierGradient.reach_m``) another saddle or basin may take over, and the band says so;
- *Monte-Carlo*: the barrier recomputed by the same method (the start found by descent from the nominal start
  orientation, so a start face that stops being a minimum shows as a change of basin) at ``N`` CoMs at distance
  ``r`` in uniformly random directions (seeded), each at the lightest and the heaviest mass (at a fixed CoM the
  barrier is proportional to the mass): their lowest and highest values. The samples lie on the sphere of radius
  ``r`` because a barrier made of pieces linear in the CoM (each saddle and start face contributes one) takes its
  extremes over the ball on its surface; only the pieces' curvature (second order) moves them inside.

On a smooth case the two agree up to the sampling (``N`` directions miss the extreme one by an angle of order
``N^(-1/2)``) and the second-order term; where a second saddle lies within reach of the uncertainty, the Monte-Carlo
range shows how far the first order is off.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from geometry.bounds import (  # noqa: F401  (the ranges of an Uncertainty's inputs, read here too)
    COM_UNCERTAINTY_MM_BOUNDS,
    MASS_UNCERTAINTY_G_BOUNDS,
    MC_SEED_BOUNDS,
    SAMPLES_BOUNDS,
)
from geometry.errors import UsageError

from .barriers import method as barrier_method
from .computation import _SectorGrid, _with_sectors
from .energy import energy_landscape
from .gradient import EXIT_NAMES

DEFAULT_SAMPLES = 64
"""Monte-Carlo samples where a first-order band does not exist and none were asked for."""
MAX_SAMPLES = int(SAMPLES_BOUNDS.hi)
"""Most Monte-Carlo samples one interval takes."""
FIRST_ORDER = "first order: B -+ (r |dB/dCoM| + dm |dB/dmass|), the linearised barrier's extremes"
MONTE_CARLO = (
    "Monte-Carlo: lowest and highest barrier recomputed with the CoM r off in N random directions (seeded), "
    "at the lightest and heaviest mass"
)


@dataclass(frozen=True)
class Uncertainty:
    """How uncertain the mass properties are.

    Attributes
    ----------
    com_m : float
        The CoM lies anywhere within this distance of its nominal position, m (>= 0).
    mass_kg : float
        The mass lies anywhere within +- this of its nominal value, kg (>= 0).
    samples : int or None
        Monte-Carlo samples (>= 1); None: the first-order band alone, and :data:`DEFAULT_SAMPLES` where it does
        not exist.
    seed : int
        Seed of the Monte-Carlo directions (>= 0).
    """

    com_m: float = 0.0
    mass_kg: float = 0.0
    samples: int | None = None
    seed: int = 0

    def check(self, pose=None) -> Uncertainty:
        """This uncertainty, checked (and against the posed body when given: the CoM must stay inside its hull,
        the mass above zero).

        Raises
        ------
        UsageError
            If a value is not finite, negative, ``samples`` below 1 or above :data:`MAX_SAMPLES`, the CoM
            uncertainty reaches outside the body or the mass uncertainty is not below the mass.
        """
        for name, v in (("com_m", self.com_m), ("mass_kg", self.mass_kg)):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise UsageError(f"the {name} uncertainty must be a finite number >= 0; got {v!r}")
        if self.samples is not None and not (
            int(self.samples) == self.samples and 1 <= self.samples <= MAX_SAMPLES
        ):
            raise UsageError(f"samples must be a whole number in [1, {MAX_SAMPLES}]; got {self.samples!r}")
        if not (int(self.seed) == self.seed and self.seed >= 0):
            raise UsageError(f"seed must be a whole number >= 0; got {self.seed!r}")
        if pose is not None:
            from geometry.hull import depth_inside_m

            depth = depth_inside_m(pose.hull, pose.com_m)
            if self.com_m >= depth:
                raise UsageError(
                    f"a CoM uncertainty of {self.com_m * 1e3:g} mm is larger than the body: the CoM lies only "
                    f"{depth * 1e3:.3g} mm inside its hull, so it could leave it; give less than {depth * 1e3:.3g} mm"
                )
            if self.mass_kg >= pose.mass_kg:
                raise UsageError(
                    f"a mass uncertainty of {self.mass_kg * 1e3:g} g is not below the mass ({pose.mass_kg * 1e3:g} g); "
                    "give a smaller one"
                )
        return self

    @property
    def given(self) -> bool:
        """Whether there is any uncertainty to bound."""
        return self.com_m > 0 or self.mass_kg > 0


@dataclass(frozen=True)
class BarrierInterval:
    """One exit's barrier under an :class:`Uncertainty`.

    Attributes
    ----------
    barrier_j : float
        The nominal barrier, J.
    first_order_j : (float, float) or None
        The first-order band (:data:`FIRST_ORDER`), J; None where the CoM gradient does not exist.
    monte_carlo_j : (float, float) or None
        The Monte-Carlo range (:data:`MONTE_CARLO`), J; None when not computed.
    note : str or None
        Why there is no first-order band, or that it reaches beyond the gradient's reach.
    """

    barrier_j: float
    first_order_j: tuple[float, float] | None
    monte_carlo_j: tuple[float, float] | None
    note: str | None = None


@dataclass(frozen=True)
class BarrierIntervals:
    """Every exit's :class:`BarrierInterval` under one :class:`Uncertainty`.

    Attributes
    ----------
    uncertainty : Uncertainty
    samples : int
        Monte-Carlo samples drawn (0: none).
    exits : dict of str to BarrierInterval or None
        Keyed ``righting``, ``pitch_wise``, ``roll_wise``, ``escape``; None for an exit that does not exist.
    seconds_per_sample : float
        Wall time of one Monte-Carlo sample (a recomputation of every exit), s; nan without samples.
    """

    uncertainty: Uncertainty
    samples: int
    exits: dict = field(default_factory=dict)
    seconds_per_sample: float = math.nan

    def to_dict(self) -> dict:
        """In JSON types (SI): the uncertainty (``com_m``, ``mass_kg``), the Monte-Carlo ``samples`` and ``seed``,
        the two labels, and per exit ``first_order_j`` and ``monte_carlo_j`` ([low, high]
        or None) and ``note``."""
        u = self.uncertainty
        return {
            "com_m": u.com_m,
            "mass_kg": u.mass_kg,
            "samples": self.samples,
            "seed": u.seed,
            "first_order": FIRST_ORDER,
            "monte_carlo": MONTE_CARLO,
            **{
                k: None
                if x is None
                else {
                    "first_order_j": None if x.first_order_j is None else list(x.first_order_j),
                    "monte_carlo_j": None if x.monte_carlo_j is None else list(x.monte_carlo_j),
                    "note": x.note,
                }
                for k, x in self.exits.items()
            },
        }


def com_offsets_m(n: int, radius_m: float, seed: int) -> NDArray[np.float64]:
    """``n`` CoM offsets of length ``radius_m`` in uniformly random directions (normalised Gaussian vectors of
    ``numpy.random.default_rng(seed)``), body frame, m.

    Examples
    --------
    >>> d = com_offsets_m(4, 1e-3, 0)
    >>> d.shape, bool(np.allclose(np.linalg.norm(d, axis=1), 1e-3))
    ((4, 3), True)
    """
    v = np.random.default_rng(seed).standard_normal((n, 3))
    return radius_m * v / np.linalg.norm(v, axis=1, keepdims=True)


def recomputed_barriers(c, offsets_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """The exits' barriers recomputed with the CoM moved by each offset: the computation's method, step and
    connectivity, its start orientation (the body descends from it), its sector exits if it had them.

    Parameters
    ----------
    c : landscape.computation.Computation
        With its pose (a barrier map's poses keep none).
    offsets_m : ndarray of shape (N, 3)
        CoM offsets, body frame, m.

    Returns
    -------
    barrier_j : ndarray of shape (N, 4)
        Righting, pitch-wise, roll-wise and escape barriers, J (nan where an exit does not exist).
    """
    solver = barrier_method(c.method)
    sectors = not solver.SECTORS and (c.barrier.pitch_wise is not None or c.barrier.roll_wise is not None)
    pose = c.pose
    hull = pose.hull
    out = np.full((len(offsets_m), len(EXIT_NAMES)), np.nan)
    for i, d in enumerate(np.asarray(offsets_m, dtype=np.float64)):
        p = replace(pose, com_m=pose.com_m + d)
        p.__dict__["hull"] = hull  # the same points: the same hull (cached_property's slot)
        ls = energy_landscape(p, step_deg=c.step_deg, g_m_s2=c.g_m_s2) if solver.SECTORS else None
        minimum, barrier = solver.solve(
            p, ls, c.start_deg, step_deg=c.step_deg, connectivity=c.connectivity, g_m_s2=c.g_m_s2
        )
        if sectors:
            barrier = _with_sectors(
                barrier, minimum, _SectorGrid(p, c.step_deg, c.g_m_s2, ls), c.connectivity
            )
        for k, name in enumerate(EXIT_NAMES):
            x = getattr(barrier, name)
            if x is not None:
                out[i, k] = x.barrier_j
    return out


def first_order_interval(
    barrier_j: float, gradient, u: Uncertainty
) -> tuple[tuple[float, float] | None, str | None]:
    """The first-order band of one exit (:data:`FIRST_ORDER`), J, and a note (why there is none, or that it
    reaches beyond the gradient's reach)."""
    if u.com_m > 0 and gradient.com_j_per_m is None:
        return None, f"no first order: {gradient.reason}"
    half = u.mass_kg * abs(gradient.mass_j_per_kg)
    if u.com_m > 0:
        half += u.com_m * float(np.linalg.norm(gradient.com_j_per_m))
    note = None
    if u.com_m > 0 and math.isnan(gradient.reach_m):
        note = "the saddle is a grid cell: how far first order holds is not known"
    elif u.com_m > gradient.reach_m:
        note = (
            f"first order holds only within {gradient.reach_m * 1e3:.2g} mm: a second saddle or basin lies within "
            "the uncertainty"
        )
    return (barrier_j - half, barrier_j + half), note


def barrier_intervals(c, u: Uncertainty) -> BarrierIntervals:
    """Every exit's barrier interval under an uncertainty (module docstring).

    Parameters
    ----------
    c : landscape.computation.Computation
        With its gradients (``compute(..., gradients=True)``) and its pose.
    u : Uncertainty

    Returns
    -------
    BarrierIntervals

    Raises
    ------
    UsageError
        For an uncertainty :meth:`Uncertainty.check` refuses on this body.

    Examples
    --------
    A box 4 x 2 x 1 m with its CoM 0.1 m towards +y: its righting barrier rolls over that edge, at
    ``norm(dB/dc) = m g norm(u_s - u_0)``, so a 1 cm CoM uncertainty gives it +- 1 cm times that:

    >>> import trimesh
    >>> from geometry import Robot
    >>> from landscape.computation import compute
    >>> box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0, com=(0, 0.1, 0))
    >>> c = compute(box, g_m_s2=1.0, landscape_grid=False)
    >>> i = barrier_intervals(c, Uncertainty(com_m=0.01, samples=200)).exits["righting"]
    >>> [round(x, 4) for x in i.first_order_j], [round(x, 4) for x in i.monte_carlo_j]
    ([0.5194, 0.5397], [0.5196, 0.5397])
    """
    u.check(c.pose)
    if not c.gradient:
        raise UsageError("barrier intervals need the gradients: compute with gradients=True")
    bands, notes = {}, {}
    for name in EXIT_NAMES:
        x, g = getattr(c.barrier, name), c.gradient.get(name)
        if x is None or g is None:
            continue
        bands[name], notes[name] = first_order_interval(x.barrier_j, g, u)
    n = u.samples
    if n is None and u.com_m > 0 and any(b is None for b in bands.values()):
        n = DEFAULT_SAMPLES
    mc, per_sample = None, math.nan
    if n:
        t0 = time.perf_counter()
        values = recomputed_barriers(c, com_offsets_m(n, u.com_m, u.seed)) if u.com_m > 0 else None
        per_sample = (time.perf_counter() - t0) / n if u.com_m > 0 else math.nan
        mc = {}
        for k, name in enumerate(EXIT_NAMES):
            x = getattr(c.barrier, name)
            if x is None:
                continue
            b = values[:, k] if values is not None else np.array([x.barrier_j])
            lo, hi = (1 - u.mass_kg / c.mass_kg), (1 + u.mass_kg / c.mass_kg)
            mc[name] = (float(np.nanmin(b) * lo), float(np.nanmax(b) * hi))
    exits = {}
    for name in EXIT_NAMES:
        x = getattr(c.barrier, name)
        exits[name] = (
            None
            if x is None or name not in bands
            else BarrierInterval(x.barrier_j, bands[name], None if mc is None else mc.get(name), notes[name])
        )
    return BarrierIntervals(u, int(n or 0) if u.com_m > 0 else 0, exits, per_sample)


def with_intervals(c, u: Uncertainty):
    """The computation with its :attr:`~landscape.computation.Computation.intervals` under ``u``
    (:func:`barrier_intervals`), and the time they took in its ``timing_s`` (``intervals``, and with samples
    ``monte_carlo_sample``, one sample's); a barrier map's ``per_pose`` hook."""
    t0 = time.perf_counter()
    iv = barrier_intervals(c, u)
    timing = dict(c.timing_s) | {"intervals": time.perf_counter() - t0}
    if iv.samples:
        timing["monte_carlo_sample"] = iv.seconds_per_sample
    return replace(c, intervals=iv, timing_s=timing)


@dataclass(frozen=True)
class ComChange:
    """How the barriers change between two computations of one pose whose CoMs differ (a model set that moves
    the CoM, or a part with its mass).

    Attributes
    ----------
    com_m : ndarray of shape (3,)
        The CoM's move, body frame, m.
    first_order_j : dict of str to float or None
        Per exit, ``dB/dc . dc`` from the first computation's gradient, J (None where it does not exist).
    com_only_j : dict of str to float or None
        Per exit, the barrier recomputed on the first body with only its CoM moved, minus its own, J.
    recomputed_j : dict of str to float or None
        Per exit, the second computation's barrier minus the first's, J (its geometry may differ too).
    """

    com_m: NDArray[np.float64]
    first_order_j: dict
    com_only_j: dict
    recomputed_j: dict

    def to_dict(self) -> dict:
        """In JSON types (SI): ``com_m`` and, per kind, the change of each exit's barrier, J."""
        return {
            "com_m": [float(x) for x in self.com_m],
            "first_order_j": dict(self.first_order_j),
            "com_only_j": dict(self.com_only_j),
            "recomputed_j": dict(self.recomputed_j),
        }


def com_change(base, moved) -> ComChange:
    """The barriers' change from ``base`` to ``moved`` (two computations of one pose, e.g. a robot and the same
    robot as a model set edits it): to first order in the CoM's move, recomputed with only the CoM moved, and
    recomputed whole.

    Parameters
    ----------
    base : landscape.computation.Computation
        With its gradients and pose.
    moved : landscape.computation.Computation

    Raises
    ------
    UsageError
        If the move would take the CoM outside ``base``'s body.

    Examples
    --------
    A box 4 x 2 x 1 m (m g = 1 J/m) with its CoM moved 1 cm further towards +y: its righting barrier over the +y
    edge falls about 0.9 cm times m g (the gradient's y component):

    >>> import trimesh
    >>> from geometry import Robot
    >>> from landscape.computation import compute
    >>> def box(y):
    ...     body = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), com=(0, y, 0))
    ...     return compute(body, g_m_s2=1.0, landscape_grid=False)
    >>> ch = com_change(box(0.1), box(0.11))
    >>> round(ch.first_order_j["righting"], 5), round(ch.recomputed_j["righting"], 5), ch.com_only_j == ch.recomputed_j
    (-0.00874, -0.00873, True)
    """
    dc = np.asarray(moved.com_m, dtype=np.float64) - np.asarray(base.com_m, dtype=np.float64)
    Uncertainty(com_m=float(np.linalg.norm(dc))).check(base.pose)
    alone = recomputed_barriers(base, dc[None, :])[0]
    first, only, whole = {}, {}, {}
    for k, name in enumerate(EXIT_NAMES):
        b, m, g = getattr(base.barrier, name), getattr(moved.barrier, name), base.gradient.get(name)
        first[name] = None if g is None or g.com_j_per_m is None else float(g.com_j_per_m @ dc)
        only[name] = None if b is None or not np.isfinite(alone[k]) else float(alone[k] - b.barrier_j)
        whole[name] = None if b is None or m is None else float(m.barrier_j - b.barrier_j)
    return ComChange(dc, first, only, whole)
