"""What every barrier method returns: the exits out of the start minimum, and what sets each barrier's level to
first order (:class:`Contacts`, read by :mod:`landscape.gradient`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class Contact:
    """Where the body touches the ground at a point of the landscape whose height sets a barrier level.

    Attributes
    ----------
    kind : str
        "face": resting on a face (the start minimum, or a face node where a path peaks); "edge": rocking on an
        edge at the highest point of its arc (a saddle; the CoM's height is its distance to the edge's line);
        "cut": on an edge arc where it crosses the upright boundary u_z = 0 (a righting path's end); "direction":
        a fixed up-direction, a grid cell or icosphere vertex (the CoM's height over the lowest hull point).
    up : ndarray of shape (3,)
        World-up in the body frame there (geometry/frames.py).
    points_m : ndarray of shape (N, 3)
        The hull vertices touching the ground, body frame, m (an edge's two ends first); empty for "direction",
        whose touching points follow from ``up``.
    margin_m : float
        How far the CoM may move before this contact changes kind (the start face stops being a minimum, a
        saddle's foot leaves its edge or its peak its arc), a conservative bound, m; nan where not known.
    """

    kind: str
    up: NDArray[np.float64]
    points_m: NDArray[np.float64] = field(repr=False)
    margin_m: float = np.nan


@dataclass(frozen=True)
class Contacts:
    """What sets an exit's barrier level to first order: the lowest of its routes' highest contacts, minus the start.

    Attributes
    ----------
    start : Contact
        The start minimum.
    routes : tuple of tuple of Contact
        The ways out at the barrier level: the level is the lowest route's highest contact. One route with one
        contact is the smooth case; several routes (equal saddles, e.g. mirror images) or a route with several
        contacts (a path that rises to the level twice) are ties, where one-sided derivatives differ. Empty when
        the start is already upright (the barrier is 0).
    gap_m : float
        Height between the level and the nearest other configuration that could take over (the next route's
        level above it, the path's highest point after the pass below it), m; inf if none, nan if not known.
    """

    start: Contact
    routes: tuple[tuple[Contact, ...], ...]
    gap_m: float = np.nan


@dataclass(frozen=True)
class Exit:
    """The lowest way out to one kind of target.

    Attributes
    ----------
    barrier_j : float
        Bottleneck level minus the start energy, J (inf if unreachable).
    saddle_pitch_deg, saddle_roll_deg : float
        Highest point of the path, degrees (canonical branch).
    direction : str
        "pitch" (somersault) or "roll" (to one side), from where the path leaves.
    path_deg : ndarray of shape (L, 2)
        Grid path (pitch, roll) from the start, degrees, on the torus (not canonicalised, so it is continuous).
    contacts : Contacts or None
        What sets the level to first order (the exact method fills it; None: the saddle and the start minimum are
        fixed up-directions, a grid cell or an icosphere vertex).
    """

    barrier_j: float
    saddle_pitch_deg: float
    saddle_roll_deg: float
    direction: str
    path_deg: NDArray[np.float64]
    contacts: Contacts | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class Barrier:
    """Barriers out of a start minimum (every method returns one).

    Attributes
    ----------
    righting, pitch_wise, roll_wise, escape : Exit or None
        Lowest exit to upright (either way), pitch-wise upright, roll-wise upright, and to another basin
        (None where no such path exists, e.g. escape on a flat landscape).
    """

    righting: Exit | None
    pitch_wise: Exit | None
    roll_wise: Exit | None
    escape: Exit | None
