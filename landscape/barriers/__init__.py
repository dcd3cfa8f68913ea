"""Barrier methods behind one registry: one module per method in this package.

A method is a public module ``landscape/barriers/<name>.py`` that defines (private ones, a method's compiled
kernels among them, start with ``_``)::

    SECTORS: bool   # True if the method finds the pitch-wise and roll-wise exits itself
    def solve(pose, landscape, start_deg, *, step_deg, connectivity, g_m_s2) -> tuple[Minimum, Barrier]

Adding a method is adding that one file: :data:`METHODS` lists the modules found here (without importing
them, so the command line can offer the names cheaply) and :func:`method` imports one on demand.
"""

from __future__ import annotations

import importlib
import pkgutil
from types import ModuleType

from geometry.errors import UsageError

#: names of the barrier methods, one per module of this package
METHODS: tuple[str, ...] = tuple(
    sorted(m.name for m in pkgutil.iter_modules(__path__) if not m.name.startswith("_"))
)
DEFAULT_METHOD = "exact"
#: exit names at the interfaces -> fields of :class:`Barrier`
EXITS = {"righting": "righting", "pitch-wise": "pitch_wise", "roll-wise": "roll_wise", "escape": "escape"}

__all__ = ["Barrier", "Contact", "Contacts", "DEFAULT_METHOD", "EXITS", "Exit", "METHODS", "method"]


def __getattr__(name: str):
    # the result types load numpy; the registry itself stays import-light for the command line
    if name in ("Barrier", "Contact", "Contacts", "Exit"):
        from . import _base

        return getattr(_base, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def method(name: str) -> ModuleType:
    """The module of barrier method ``name`` (its ``solve`` and ``SECTORS``).

    Raises
    ------
    UsageError
        If no such method exists.

    Examples
    --------
    >>> method("grid").__name__
    'landscape.barriers.grid'
    >>> method("gird")
    Traceback (most recent call last):
    ...
    geometry.errors.UsageError: unknown barrier method 'gird'; choose one of exact, grid, sphere
    """
    if name not in METHODS:
        raise UsageError(f"unknown barrier method {name!r}; choose one of {', '.join(METHODS)}")
    return importlib.import_module(f"{__name__}.{name}")
