"""Potential-energy landscapes over body pitch and roll, start minima and minimal self-righting barriers."""

from .barrier import Exit, GridBarrier, grid_barrier
from .compute import Computation, compute, sweep_starts
from .energy import Landscape, brute_force_landscape, energy_landscape, height_at
from .grid import GridError
from .minima import Minimum, metastable_orientation

__all__ = [
    "Exit", "GridBarrier", "grid_barrier", "Computation", "compute", "sweep_starts", "Landscape",
    "brute_force_landscape", "energy_landscape", "height_at", "GridError", "Minimum", "metastable_orientation",
]
