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


MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf", ".3mf", ".dae")
"""File suffixes read as a single rigid mesh when given where a robot is expected (trimesh reads them)."""
DEFAULT_MESH_MASS_KG = 1.0
"""Mass of a mesh body whose mass is not given, kg (every front end says so beside it)."""
PLAUSIBLE_SIZE_M = (0.005, 5.0)
"""A mesh body outside this size range (largest extent, m) gets a warning naming its units option."""


class ImplausibleUnitsWarning(UserWarning):
    """A mesh body is implausibly large or small in the units it was read in."""


def is_mesh_file(path: str | Path) -> bool:
    """Whether ``path`` names a mesh file by its suffix (:data:`MESH_SUFFIXES`), not a URDF.

    Examples
    --------
    >>> is_mesh_file("box.STL"), is_mesh_file("robot.urdf")
    (True, False)
    """
    return Path(str(path)).suffix.lower() in MESH_SUFFIXES


def mesh_size_m(robot) -> float:
    """Largest extent of a robot's geometry along a body axis, m (0 without geometry)."""
    import numpy as np

    return max(
        (float(np.ptp(p.hull_link_m, axis=0).max()) for p in robot.parts if len(p.hull_link_m)), default=0.0
    )


def units_warning(size_m: float, units: str, *, units_as: str) -> str | None:
    """What to say of a mesh body ``size_m`` across when read in ``units`` (None when plausible).

    ``units_as`` names the units setting where it was given (``--units``, ``units=``), so the fix is named as the
    user types it.

    Examples
    --------
    >>> units_warning(100.0, "m", units_as="--units")
    'the mesh is 100 m across, read in metres; if it was saved in millimetres (CAD exports usually are), give --units mm'
    >>> units_warning(0.1, "m", units_as="units=") is None
    True
    """
    lo, hi = PLAUSIBLE_SIZE_M
    if lo <= size_m <= hi:
        return None
    names = {"m": "metres", "cm": "centimetres", "mm": "millimetres"}
    mm = f"{units_as}'mm'" if units_as.endswith("=") else f"{units_as} mm"
    text = f"the mesh is {size_m:.3g} m across, read in {names.get(units, units)}; "
    if size_m > hi and units != "mm":
        return text + f"if it was saved in millimetres (CAD exports usually are), give {mm}"
    return text + f"give its {units_as.rstrip('=')} if it was not saved in {names.get(units, units)}"


def load_robot(
    robot: str | Path | None = None,
    *,
    mesh: str | Path | None = None,
    com: Sequence[float] | None = None,
    mass_kg: float | None = None,
    units: str | None = None,
    com_model: str | None = None,
    joints: str | None = None,
):
    """A :class:`geometry.Robot` from a registered name or URDF path, or one rigid ``mesh``.

    Parameters
    ----------
    robot : str or path, optional
        A registered name (``"builtin"``), a URDF file, or a mesh file (recognised by its suffix,
        :data:`MESH_SUFFIXES`; the same as ``mesh=``); None: the built-in robot.
    mesh : path, optional
        A single rigid body instead (any mesh file trimesh reads); then ``com`` (in the mesh's ``units``),
        ``mass_kg`` and ``com_model`` apply.
    com : sequence of 3 float, optional
        A mesh body's CoM in the mesh's units; default: computed as ``com_model`` says.
    mass_kg : float, optional
        A mesh body's mass, kg; default :data:`DEFAULT_MESH_MASS_KG`.
    units : {"m", "cm", "mm"}, optional
        A mesh file's units; default metres. A body implausibly large or small in them
        (:data:`PLAUSIBLE_SIZE_M`) gets an :class:`ImplausibleUnitsWarning` naming the fix.
    com_model : {"auto", "solid", "shell"}, optional
        How a mesh body's CoM is computed when ``com`` is not given; default "auto".
    joints : str, optional
        Joint map ``'wing=J1,J2,...;leg=J'`` for a URDF whose joint names differ from the lab robot's (either
        group may be left out).

    Raises
    ------
    UsageError
        If both ``robot`` and ``mesh`` are given, mesh-only arguments come with a URDF, or ``joints`` with a mesh.
    RobotDescriptionError
        If a file is missing or unreadable.

    Examples
    --------
    >>> round(load_robot().pose(0.0, 0.0).mass_kg, 3)
    0.26
    """
    import warnings

    from .cache import robot_cache_dir
    from .joint_map import JointMap
    from .robot import Robot

    if robot is not None and mesh is not None:
        raise UsageError(
            f"give either robot (a robot name or URDF file) or mesh= (a mesh file), not both; got robot={robot!r}, "
            f"mesh={mesh!r}"
        )
    if robot is not None and str(robot) not in ROBOTS and is_mesh_file(robot):
        robot, mesh = None, robot
    for what, given in (("robot", robot), ("mesh", mesh)):
        if given is not None and str(given) not in ROBOTS and Path(given).is_dir():
            raise RobotDescriptionError(
                f"{what}={str(given)!r} is a directory; give the file inside it "
                f"({'the .urdf' if what == 'robot' else 'a mesh file'})"
            )
    if mesh is not None:
        if joints:
            raise UsageError("joints= applies to a URDF robot, not to a single mesh body; drop it")
        units = units or "m"
        body = Robot.from_mesh(
            mesh,
            mass_kg=DEFAULT_MESH_MASS_KG if mass_kg is None else mass_kg,
            com=com,
            units=units,
            com_model=com_model or "auto",
        )
        text = units_warning(mesh_size_m(body), units, units_as="units=")
        if text is not None:
            warnings.warn(text, ImplausibleUnitsWarning, stacklevel=2)
        return body
    given = [
        name
        for name, v in (("com", com), ("mass_kg", mass_kg), ("units", units), ("com_model", com_model))
        if v is not None
    ]
    if given:
        raise UsageError(
            f"{', '.join(given)} {'apply' if len(given) > 1 else 'applies'} only to a single mesh body (mesh= or a mesh file); a URDF robot takes its "
            "masses and CoM from its <inertial> elements: drop them"
        )
    jm = JointMap.parse(joints) if joints else None
    return Robot.from_urdf(robot_urdf_path(robot), joint_map=jm, cache_dir=robot_cache_dir())
