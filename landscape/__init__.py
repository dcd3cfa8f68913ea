"""Potential-energy landscapes over body pitch and roll, start minima and minimal self-righting barriers.

The numerics (this package's modules and :mod:`landscape.barriers`) import only :mod:`geometry`; the edge
lives in subpackages of its own: :mod:`landscape.cli` (the ``landscape`` command), :mod:`landscape.analysis`
(analyses of trial databases), :mod:`landscape.viz` (plots, rendering, files, the report). Names below are
loaded on first use, so ``import landscape.cli`` does not pay for the numerics.

The compiled kernels are cached per user, in ``$LANDSCAPE_CACHE/numba`` or
``~/.cache/selfrighting-landscape/numba`` (``NUMBA_CACHE_DIR``, when set, takes precedence), never beside the
installed sources: a cache there would outlive an uninstall and turn a later editable install's ``landscape``
into an empty namespace package.

Examples
--------
>>> import landscape
>>> c = landscape.compute(landscape.load_robot(), theta_w_deg=74.0)
>>> c.barrier.righting.direction
'roll'
"""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path


def _numba_cache_dir() -> Path:
    """Where numba caches the kernels of this package: ``$LANDSCAPE_CACHE/numba``, else
    ``~/.cache/selfrighting-landscape/numba`` (also when ``LANDSCAPE_CACHE`` is ``off``, which turns off only
    the robot cache); a directory under the temporary directory if that cannot be created."""
    import tempfile

    env = os.environ.get("LANDSCAPE_CACHE")
    user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    candidates = [Path(tempfile.gettempdir()) / f"selfrighting-landscape-{user}" / "numba"]
    try:
        root = Path(env) if env and env != "off" else Path.home() / ".cache" / "selfrighting-landscape"
        candidates.insert(0, (root / "numba").expanduser().absolute())
    except RuntimeError:  # no home directory
        pass
    for path in candidates:
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(path, os.W_OK | os.X_OK):
            return path
    return path


def _use_user_numba_cache() -> None:
    """Point numba's cache (``@numba.njit(cache=True)``) at :func:`_numba_cache_dir` unless the user chose one
    with ``NUMBA_CACHE_DIR``. Runs before any kernel module is imported (they all live in this package);
    numba reads the variable when it is imported, or, if it already was, when its configuration is reloaded."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    os.environ["NUMBA_CACHE_DIR"] = str(_numba_cache_dir())
    if "numba" in sys.modules:
        from numba.core import config

        config.reload_config()


_use_user_numba_cache()

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
