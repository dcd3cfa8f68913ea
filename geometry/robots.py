"""Where a robot comes from: the registry of named robots and the one function every front end loads with.

``load_robot`` is the single place that resolves "no robot given" (the built-in robot), a registered name,
a URDF path or a single mesh; the command line, the service and ``sim`` all call it. Adding a named robot is
one :func:`register` call (dm_control's ``suite`` registry pattern).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from .errors import RobotDescriptionError, UsageError

#: name -> function returning the robot's URDF path (files written on demand)
ROBOTS: dict[str, Callable[[], Path]] = {}

DEFAULT_ROBOT = "builtin"


def register(name: str, urdf_path: Callable[[], Path]) -> None:
    """Make ``name`` a robot that ``load_robot(name)`` and ``--robot NAME`` find."""
    ROBOTS[name] = urdf_path


def _builtin_urdf() -> Path:
    from .builtin import builtin_urdf_path

    return builtin_urdf_path()


register(DEFAULT_ROBOT, _builtin_urdf)


def robot_urdf_path(robot: str | Path | None = None) -> Path:
    """The URDF file of a registered robot name or a path; None: the default (built-in) robot.

    Examples
    --------
    >>> robot_urdf_path().name
    'robot.urdf'
    """
    if robot is None or str(robot) in ROBOTS:
        return ROBOTS[DEFAULT_ROBOT if robot is None else str(robot)]()
    return Path(robot)


def load_robot(
    robot: str | Path | None = None,
    *,
    mesh: str | Path | None = None,
    com: Sequence[float] | None = None,
    mass_kg: float = 1.0,
    units: str = "m",
    com_model: str = "auto",
    joints: str | None = None,
):
    """A :class:`geometry.Robot` from a registered name or URDF path, or one rigid ``mesh``.

    Parameters
    ----------
    robot : str or path, optional
        A registered name (``"builtin"``) or a URDF file; None: the built-in robot.
    mesh : path, optional
        A single rigid body instead (any mesh file trimesh reads); then ``com`` (in the mesh's ``units``),
        ``mass_kg`` and ``com_model`` apply.
    joints : str, optional
        Joint map ``'wing=J1,J2,...;leg=J'`` for a URDF whose joint names differ from the lab robot's.

    Raises
    ------
    UsageError
        If both ``robot`` and ``mesh`` are given, or mesh-only options come without a mesh.
    RobotDescriptionError
        If a file is missing or unreadable.

    Examples
    --------
    >>> round(load_robot().pose(0.0, 0.0).mass_kg, 3)
    0.26
    """
    from .robot import JointMap, Robot, robot_cache_dir

    for what, given in (("--robot", robot), ("--mesh", mesh)):
        if given is not None and str(given) not in ROBOTS and Path(given).is_dir():
            raise RobotDescriptionError(
                f"{what} {given} is a directory; give the file inside it "
                f"({'the .urdf' if what == '--robot' else 'a mesh file'})"
            )
    if robot is not None and mesh is not None:
        raise UsageError("give either --robot FILE.urdf or --mesh FILE, not both")
    if mesh is not None:
        if joints:
            raise UsageError("--joints applies to a URDF robot, not to a single --mesh body")
        return Robot.from_mesh(mesh, mass_kg=mass_kg, com=com, units=units, com_model=com_model)
    jm = JointMap.parse(joints) if joints else None
    return Robot.from_urdf(robot_urdf_path(robot), joint_map=jm, cache_dir=robot_cache_dir())
