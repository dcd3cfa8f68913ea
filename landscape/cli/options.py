"""Option parsing shared by the command modules: value lists, finite numbers, the robot options.

Bad input raises :class:`geometry.errors.UsageError` (re-exported here), which :func:`landscape.cli.main`
turns into one line on stderr and exit status 2.
"""

from __future__ import annotations

import math

import click

from geometry.errors import UsageError
from landscape.params import parse_values

MJ = 1e3
MM = 1e3
DEFAULT_MESH_MASS_KG = 1.0
"""Mass of a ``--mesh`` body when ``--mass`` is not given, kg (said beside it in the output)."""
PLAUSIBLE_SIZE_M = (0.005, 5.0)
"""A ``--mesh`` body outside this size range (largest extent, m) gets a ``--units`` warning."""

__all__ = ["MJ", "MM", "UsageError", "finite", "load_robot", "method_option", "parse_values", "robot_from",
           "robot_options"]


def finite(value: float | None, name: str) -> float | None:
    """``value`` unchanged if it is None or finite, else a :class:`UsageError` naming the option ``--name``."""
    if value is not None and not math.isfinite(value):
        raise UsageError(f"--{name} must be a finite number; got {value!r}")
    return value


def memory_budget_bytes() -> float:
    """The memory budget of one landscape computation: ``LANDSCAPE_MEMORY_GIB`` GiB if set, else the library's
    default (:data:`landscape.computation.MEMORY_BUDGET_BYTES`)."""
    import os

    text = os.environ.get("LANDSCAPE_MEMORY_GIB")
    if not text:
        from landscape.computation import MEMORY_BUDGET_BYTES

        return MEMORY_BUDGET_BYTES
    try:
        gib = float(text)
    except ValueError:
        raise UsageError(f"LANDSCAPE_MEMORY_GIB must be a number of GiB; got {text!r}") from None
    if not (math.isfinite(gib) and gib > 0):
        raise UsageError(f"LANDSCAPE_MEMORY_GIB must be a positive number of GiB; got {text!r}")
    return gib * 2**30


def grid_step(step_deg: float) -> float:
    """``--step`` checked before any robot is loaded: finite and dividing 360 (:func:`landscape.grid.cells_per_turn`)."""
    from landscape.computation import check_memory
    from landscape.grid import cells_per_turn

    finite(step_deg, "step")
    cells_per_turn(step_deg)
    check_memory(step_deg, memory_budget_bytes())
    return step_deg


def load_robot(robot: str | None, mesh: str | None, *, com: str | None = None, mass: float = 1.0,
               units: str = "m", com_model: str = "auto", joints: str | None = None):
    """The robot the options describe: a URDF, a single mesh, or the built-in robot
    (:func:`geometry.robot.load_robot`)."""
    from geometry.robots import load_robot as _load

    c = None
    if com is not None:
        try:
            c = [float(x) for x in com.split(",")]
        except ValueError:
            raise UsageError(f"--com must be X,Y,Z in the mesh's units; got {com!r}") from None
        if len(c) != 3 or not all(math.isfinite(x) for x in c):
            raise UsageError(f"--com must be three finite numbers X,Y,Z; got {com!r}")
    finite(mass, "mass")
    return _load(robot, mesh=mesh, com=c, mass_kg=mass, units=units, com_model=com_model, joints=joints)


METHOD_HELP = ("Barrier method (landscape.barriers): exact: no discretisation error (hull face-edge graph); grid: "
               "the paper's grid search on the pitch-roll torus; sphere: the same search on an icosphere spaced "
               "about --step apart.")


def method_option(f):
    """``--method``: a barrier method of the registry (:data:`landscape.barriers.METHODS`)."""
    from landscape.barriers import DEFAULT_METHOD, METHODS

    return click.option("--method", type=click.Choice(list(METHODS)), default=DEFAULT_METHOD, show_default=True,
                        help=METHOD_HELP)(f)


def robot_options(f):
    """Options shared by every command that takes a robot."""
    opts = [
        click.option("--robot", type=str, default=None, help="URDF file (default: the built-in robot)."),
        click.option("--mesh", type=str, default=None, help="A single rigid body: any mesh file trimesh reads."),
        click.option("--com", type=str, default=None, help="With --mesh: CoM X,Y,Z in the mesh's units."),
        click.option("--mass", type=float, default=None,
                     help=f"With --mesh: mass, kg [default: {DEFAULT_MESH_MASS_KG:g}]."),
        click.option("--units", type=click.Choice(["mm", "cm", "m"]), default=None,
                     help="With --mesh: units of the mesh file [default: m]."),
        click.option("--com-model", type=click.Choice(["auto", "solid", "shell"]), default=None,
                     help="With --mesh and no --com: solid (closed mesh), shell (thin surface) or auto "
                          "[default: auto]."),
        click.option("--joints", type=str, default=None,
                     help="Joint map 'wing=J1,J2,...;leg=J' for a URDF whose joint names differ."),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def robot_from(kw: dict):
    """The robot of a command's :func:`robot_options` keywords.

    Mesh-only options without ``--mesh`` are refused (they would be ignored). A mesh whose size is implausible
    in its assumed units gets a warning on stderr naming the ``--units`` fix.
    """
    if kw["mesh"] is None:
        given = [f"--{k.replace('_', '-')}" for k in ("com", "mass", "units", "com_model") if kw[k] is not None]
        if given:
            raise UsageError(f"{', '.join(given)} only apply to a single body given with --mesh FILE; "
                             "a URDF robot takes its masses and CoM from its <inertial> elements")
        return load_robot(kw["robot"], None, joints=kw["joints"])
    mass = DEFAULT_MESH_MASS_KG if kw["mass"] is None else kw["mass"]
    units = kw["units"] or "m"
    robot = load_robot(kw["robot"], kw["mesh"], com=kw["com"], mass=mass, units=units,
                       com_model=kw["com_model"] or "auto", joints=kw["joints"])
    import numpy as np

    size_m = max((float(np.ptp(p.hull_link_m, axis=0).max()) for p in robot.parts if len(p.hull_link_m)),
                 default=0.0)
    if kw["units"] is None and not PLAUSIBLE_SIZE_M[0] <= size_m <= PLAUSIBLE_SIZE_M[1]:
        guess = "mm" if size_m > PLAUSIBLE_SIZE_M[1] else None
        click.echo(f"landscape: warning: the mesh is {size_m:.3g} m across, read in metres (the default); "
                   + (f"if it was saved in millimetres (CAD exports usually are), add --units {guess}"
                      if guess else "give its --units if it was not saved in metres"), err=True)
    return robot


def writable_dir(path, option: str) -> None:
    """Refuse up front an output directory that cannot be created or written (before any long computation)."""
    import os
    from pathlib import Path

    p = Path(path)
    probe = p
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise UsageError(f"{option} {path}: {probe} is a file, not a directory; choose another {option}")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise UsageError(f"{option} {path} is not writable ({probe} is read-only); choose another {option}")


def writable_file(path, option: str, *, inputs=()) -> None:
    """Refuse up front an output file that cannot be written, or that is one of the command's ``inputs``."""
    from pathlib import Path

    p = Path(path)
    for src in inputs:
        if src is not None and Path(src).exists() and p.exists() and p.resolve() == Path(src).resolve():
            raise UsageError(f"{option} {path} is also an input of this command; writing it would destroy the "
                             "input. Choose another file name")
    if p.is_dir():
        raise UsageError(f"{option} {path} is a directory; give a file name")
    writable_dir(p.parent if str(p.parent) else ".", option)
