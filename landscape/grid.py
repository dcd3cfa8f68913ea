"""The pitch-roll grid: -180..180 deg inclusive on both axes, a step that divides 360."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from geometry.bounds import Bounds
from geometry.errors import UsageError

DEFAULT_STEP_DEG = 1.0
"""The grid step of every interface when none is given, degrees: the Python API, the command line, the service
and its page, the report and the renderings all use it, so one pose gets one answer wherever it is asked."""
STEP_MIN_DEG = 0.05
STEP_MAX_DEG = 90.0
"""The coarsest grid that still has four cells a turn, degrees."""
STEP_DEG_BOUNDS = Bounds(STEP_MIN_DEG, STEP_MAX_DEG, unit="deg", meaning="the grid step, which divides 360")
"""The grid steps the interfaces accept (each must also divide 360: :func:`cells_per_turn`)."""
STEP_NOT_DIVIDING = "step {got:g} deg does not divide 360; use e.g. 0.1, 0.25, 0.5, 1, 2, 3, 4, 5"


class GridError(UsageError):
    """A grid step that cannot tile the pitch-roll torus."""


def cells_per_turn(step_deg: float) -> int:
    """Number of distinct cells along one axis, 360 / step.

    Raises
    ------
    GridError
        If the step is not finite, not positive, below 0.05 deg, or does not divide 360.

    Examples
    --------
    >>> cells_per_turn(1.0), cells_per_turn(0.25)
    (360, 1440)
    """
    if not np.isfinite(step_deg) or step_deg <= 0:
        raise GridError(f"step must be a positive number of degrees; got {step_deg!r}")
    if step_deg < STEP_MIN_DEG:
        raise GridError(f"step {step_deg:g} deg is below the smallest supported {STEP_MIN_DEG} deg")
    n = round(360.0 / step_deg)
    if n < 4 or abs(n * step_deg - 360.0) > 1e-9 * 360.0:
        raise GridError(STEP_NOT_DIVIDING.format(got=step_deg))
    return int(n)


def torus_angles_deg(step_deg: float) -> NDArray[np.float64]:
    """The N distinct angles -180, -180 + step, ..., 180 - step (degrees)."""
    n = cells_per_turn(step_deg)
    return -180.0 + np.arange(n) * (360.0 / n)


def grid_angles_deg(step_deg: float) -> NDArray[np.float64]:
    """The N + 1 angles -180 ... 180 inclusive (degrees), as the landscape is reported."""
    n = cells_per_turn(step_deg)
    return -180.0 + np.arange(n + 1) * (360.0 / n)


def wrap_deg(angle_deg):
    """Wrap degrees to [-180, 180)."""
    return (np.asarray(angle_deg, dtype=np.float64) + 180.0) % 360.0 - 180.0


def nearest_cell(pitch_deg: float, roll_deg: float, step_deg: float) -> tuple[int, int]:
    """Torus cell (i, j) nearest to an orientation."""
    n = cells_per_turn(step_deg)
    i = int(round((float(wrap_deg(pitch_deg)) + 180.0) / (360.0 / n))) % n
    j = int(round((float(wrap_deg(roll_deg)) + 180.0) / (360.0 / n))) % n
    return i, j
