"""Potential-energy landscapes over body pitch and roll, start minima and minimal self-righting barriers.

The numerics (this package's modules and :mod:`landscape.barriers`) import only :mod:`geometry`; the edge
lives in subpackages of its own: :mod:`landscape.cli` (the ``landscape`` command), :mod:`landscape.analysis`
(analyses of trial databases), :mod:`landscape.viz` (plots, rendering, files, the report). Names below are
loaded on first use, so ``import landscape.cli`` does not pay for the numerics.

Examples
--------
>>> import landscape
>>> c = landscape.compute(landscape.load_robot(), theta_w_deg=74.0)
>>> c.barrier.righting.direction
'roll'
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    "Exit": "landscape.barriers",
    "Barrier": "landscape.barriers",
    "METHODS": "landscape.barriers",
    "grid_barrier": "landscape.barriers.grid",
    "exact_barrier": "landscape.barriers.exact",
    "sphere_barrier": "landscape.barriers.sphere",
    "Computation": "landscape.computation",
    "compute": "landscape.computation",
    "sweep_starts": "landscape.computation",
    "BarrierMap": "landscape.computation",
    "barrier_map": "landscape.computation",
    "Landscape": "landscape.energy",
    "brute_force_landscape": "landscape.energy",
    "energy_landscape": "landscape.energy",
    "height_at": "landscape.energy",
    "GridError": "landscape.grid",
    "Minimum": "landscape.minima",
    "metastable_orientation": "landscape.minima",
    "load_robot": "geometry.robots",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'landscape' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
