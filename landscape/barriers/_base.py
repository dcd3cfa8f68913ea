"""What every barrier method returns: the exits out of the start minimum."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


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
    """

    barrier_j: float
    saddle_pitch_deg: float
    saddle_roll_deg: float
    direction: str
    path_deg: NDArray[np.float64]


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
