"""Option parsing shared by the command modules: value lists, finite numbers, the robot options.

Bad input raises :class:`geometry.errors.UsageError` (re-exported here), which :func:`landscape.cli.main`
turns into one line on stderr and exit status 2.
"""

from __future__ import annotations

import math

import click

from geometry.errors import UsageError
from landscape.viz.files import parse_values

MJ = 1e3
MM = 1e3

__all__ = ["MJ", "MM", "UsageError", "finite", "load_robot", "method_option", "parse_values", "robot_from",
           "robot_options"]


def finite(value: float | None, name: str) -> float | None:
    """``value`` unchanged if it is None or finite, else a :class:`UsageError` naming the option ``--name``."""
    if value is not None and not math.isfinite(value):
        raise UsageError(f"--{name} must be a finite number; got {value!r}")
    return value


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
        if len(c) != 3:
            raise UsageError(f"--com must be three numbers X,Y,Z; got {com!r}")
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
        click.option("--mass", type=float, default=1.0, show_default=True, help="With --mesh: mass, kg."),
        click.option("--units", type=click.Choice(["mm", "cm", "m"]), default="m", show_default=True,
                     help="With --mesh: units of the mesh file."),
        click.option("--com-model", type=click.Choice(["auto", "solid", "shell"]), default="auto",
                     show_default=True,
                     help="With --mesh and no --com: solid (closed mesh), shell (thin surface) or auto."),
        click.option("--joints", type=str, default=None,
                     help="Joint map 'wing=J1,J2,...;leg=J' for a URDF whose joint names differ."),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def robot_from(kw: dict):
    """The robot of a command's :func:`robot_options` keywords."""
    return load_robot(kw["robot"], kw["mesh"], com=kw["com"], mass=kw["mass"], units=kw["units"],
                      com_model=kw["com_model"], joints=kw["joints"])
