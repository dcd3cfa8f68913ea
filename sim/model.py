"""The robot as pybullet should see it: a URDF string with simplified convex collision hulls
(:mod:`sim.hulls`), edited by a model set's modifiers (:mod:`sim.modifier`, :mod:`sim.urdf_edits`); pure, no I/O
beyond reading the source URDF and its meshes.

Visual elements are dropped (DIRECT mode renders nothing); primitive geometry (box, sphere, cylinder) is kept.
The URDF text is returned with placeholder mesh file names; :mod:`sim.world` writes the hull meshes to a cache
directory and loads the result.
"""

from __future__ import annotations

import copy
import hashlib
import logging
from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path

import numpy as np
from lxml import etree as ET

from geometry import JointMap, Robot
from geometry.errors import RobotDescriptionError
from geometry.urdf import read_urdf

from .hulls import HULL_MAX_VERTICES, HULL_TOL_M, hull_obj_text, simplified_hull
from .modifier import MERGE_ORDER
from .urdf_edits import merge_fixed_links

log = logging.getLogger(__name__)

MESH_PLACEHOLDER = "@HULL:{name}@"


def default_robot_urdf() -> Path:
    """The robot simulated when none is given.

    The built-in robot's generated URDF (``geometry.builtin.builtin_urdf_path``) when that module exists,
    else the lab robot in ``../shared/ref/lab_robot/lab_robot.urdf`` next to the repository.

    Examples
    --------
    >>> default_robot_urdf().suffix
    '.urdf'
    """
    try:
        from geometry.builtin import builtin_urdf_path  # type: ignore[import-not-found]
    except ImportError:
        return Path(__file__).resolve().parents[1].parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
    return Path(builtin_urdf_path())


@dataclass(frozen=True)
class SimModel:
    """A URDF rewritten for simulation.

    Attributes
    ----------
    urdf_text : str
        URDF with visuals dropped and each collision mesh pointing at ``MESH_PLACEHOLDER`` names.
    meshes : dict[str, str]
        Placeholder name -> OBJ text of its simplified hull (units of the original mesh file; the URDF keeps
        the original ``scale``).
    joint_map : JointMap
        Which joints theta_w and theta_l drive.
    description_hash : str
        ``Robot.description_hash`` of the source URDF (the URDF and every mesh file it uses).
    robot_hash : str
        ``Robot.robot_hash``: the description hash, with the joint map folded in when it is not the default.
    model_hash : str
        Hash of the rewritten URDF and its meshes (names the cache directory).
    max_gap_m : float
        Largest support gap of any simplified hull, m.
    vertex_counts : dict[str, tuple[int, int]]
        Placeholder name -> (full hull vertices, kept vertices).
    rest_pitch_deg : float
        Pitch of the lowest-energy resting orientation at roll 0 with the wings closed and the leg centred.
    theta_limits_deg : dict[str, tuple[float, float]]
        ``{"theta_w": (lo, hi), "theta_l": (lo, hi)}``: the range every mapped joint allows, degrees.
    source : Path
    modifiers : tuple of sim.modifier.Modifier
        The model set's modifiers it was built with, as given: those that edit the URDF
        (:attr:`sim.modifier.Modifier.EDITS_URDF`) did; the others act in the world (:class:`sim.world.World`).
    """

    urdf_text: str = field(repr=False)
    meshes: dict[str, str] = field(repr=False)
    joint_map: JointMap
    description_hash: str
    robot_hash: str
    model_hash: str
    max_gap_m: float
    vertex_counts: dict[str, tuple[int, int]] = field(repr=False)
    rest_pitch_deg: float
    theta_limits_deg: dict[str, tuple[float, float]] = field(repr=False)
    source: Path
    modifiers: tuple = ()


def rest_pitch_deg(robot: Robot) -> float:
    """Pitch (degrees) of the lowest CoM at roll 0 near the upside-down pose, wings closed, leg centred.

    Searched on a 0.1-degree grid over [-45, 45] degrees using the pose's hull (geometry layer).
    """
    from geometry import up_vector

    pose = robot.pose(0.0, 0.0) if robot.has_joints else robot.pose()
    pitch = np.deg2rad(np.arange(-45.0, 45.0 + 1e-9, 0.1))
    u = up_vector(pitch, np.zeros_like(pitch))
    h = u @ pose.com_m - (u @ pose.hull_points_m.T).min(axis=1)
    return float(np.rad2deg(pitch[int(np.argmin(h))]))


TRIAL_NEEDS = (
    "a trial opens the wings (theta_w) and swings the leg (theta_l), so it needs both joint groups; '{name}' "
    "{lacks}; movable joints: {movable}: give a joint map with both, e.g. '{example}'"
)
"""What a trial needs of a robot's joints, said when a group is missing."""


def check_trial_joints(robot: Robot, name: str) -> None:
    """Refuse a robot a trial cannot drive: one whose joint map leaves out the wing or the leg group.

    Raises
    ------
    RobotDescriptionError
        If no joint takes theta_w or none takes theta_l (:data:`TRIAL_NEEDS` says what to give).
    """
    if robot.drives("theta_w") and robot.drives("theta_l"):
        return
    if not robot.has_joints:
        lacks = "has none of the default wing/leg joints, so it would be a rigid body"
    else:
        groups = " and ".join(g for a, g in (("theta_w", "wing"), ("theta_l", "leg")) if not robot.drives(a))
        lacks = f"maps no {groups} joint (its joint map is '{robot.joint_map.text()}')"
    movable = robot.movable_joints
    wing, leg = (list(robot.joint_map.wing), list(robot.joint_map.leg)) if robot.has_joints else ([], [])
    rest = [n for n in movable if n not in wing and n not in leg]
    example = f"wing={','.join(wing or rest[:-1] or ['A', 'B'])};leg={','.join(leg or rest[-1:] or ['C'])}"
    raise RobotDescriptionError(
        TRIAL_NEEDS.format(name=name, lacks=lacks, movable=", ".join(movable) or "none", example=example)
    )


@lru_cache(maxsize=8)
def _build(
    path_str: str,
    description_hash: str,
    tol_m: float,
    max_vertices: int,
    joint_map: JointMap | None,
    merge_fixed: bool,
    modifiers: tuple = (),
) -> SimModel:
    """The model (cached by the robot's description hash, so an edited URDF or mesh file is rebuilt)."""
    path = Path(path_str)
    robot = Robot.from_urdf(path, joint_map=joint_map)
    edits = sorted(modifiers, key=lambda m: m.URDF_ORDER)
    # the set's variant (its rest pitch); the file's hashes stay the model's
    variant = robot
    for m in edits:
        variant = m.edit_robot(variant)
    check_trial_joints(robot, path.name)
    urdf_file = robot.urdf_file
    root = copy.deepcopy(urdf_file.root)
    meshes: dict[str, str] = {}
    counts: dict[str, tuple[int, int]] = {}
    max_gap = 0.0
    for link in root.iter("link"):
        for vis in list(link.findall("visual")):
            link.remove(vis)
        for i, col in enumerate(link.findall("collision")):
            mesh_el = col.find("geometry/mesh")
            if mesh_el is None:
                continue
            ref = urdf_file.mesh(link.get("name"), "collision", i)
            vertices = robot.element_vertices[(ref.link, ref.kind, ref.index)]
            scale = float(np.abs(ref.scale).max())
            hull = simplified_hull(
                vertices, tol=tol_m / scale if tol_m > 0 else 0.0, max_vertices=max_vertices
            )
            name = f"{link.get('name')}_{i}"
            meshes[name] = hull_obj_text(hull)
            counts[name] = (hull.n_full, len(hull.vertices))
            max_gap = max(max_gap, hull.gap * scale)
            mesh_el.set("filename", MESH_PLACEHOLDER.format(name=name))
    merged = None  # fixed links merge between the edits ordered before MERGE_ORDER and those after
    for m in edits:
        if merge_fixed and merged is None and m.URDF_ORDER > MERGE_ORDER:
            merged = merge_fixed_links(root)
        m.edit_urdf(root, robot)
    if merge_fixed and merged is None:
        merged = merge_fixed_links(root)
    text = ET.tostring(root, encoding="unicode")
    h = hashlib.sha256(text.encode())
    for k in sorted(meshes):
        h.update(k.encode() + meshes[k].encode())
    model = SimModel(
        text,
        meshes,
        robot.joint_map,
        robot.description_hash,
        robot.robot_hash,
        h.hexdigest()[:16],
        max_gap,
        counts,
        rest_pitch_deg(variant),
        robot.theta_limits_deg(),
        path,
        tuple(modifiers),
    )
    log.info(
        "sim model %s: hulls %s, max support gap %.3g mm, merged links %s, modifiers %s",
        path.name,
        counts,
        max_gap * 1e3,
        merged,
        [m.TABLE for m in edits],
    )
    return model


def sim_model(
    urdf: str | Path | None = None,
    *,
    tol_m: float = HULL_TOL_M,
    max_vertices: int = HULL_MAX_VERTICES,
    joint_map: JointMap | None = None,
    merge_fixed: bool = False,
    modifiers: tuple = (),
) -> SimModel:
    """The simulation model of a URDF robot (cached per process).

    Parameters
    ----------
    urdf : path, optional
        URDF file; default :func:`default_robot_urdf`.
    tol_m : float
        Largest support gap of a simplified collision hull, m; ``0`` keeps every hull vertex (the unsimplified
        baseline of the benchmarks).
    max_vertices : int
        Vertex budget per simplified hull.
    joint_map : JointMap, optional
        Joints driven by theta_w and theta_l (default: the lab robot's names).
    merge_fixed : bool
        Merge links on fixed joints into their parents (:func:`sim.urdf_edits.merge_fixed_links`): the same
        rigid body with fewer links, so each physics step is cheaper.
    modifiers : tuple of sim.modifier.Modifier
        A model set's modifiers (``ModelSet.modifiers``); those that edit the URDF do, in their
        :attr:`~sim.modifier.Modifier.URDF_ORDER`; the rest act in the world, which takes them all from
        ``SimModel.modifiers``.

    Raises
    ------
    RobotDescriptionError
        If the file or a mesh is missing or the description is bad (:meth:`geometry.Robot.from_urdf`), the
        robot has no wing/leg joints, or a modifier needs a part the robot lacks.
    UnknownJointError
        If the joint map or a modifier names a joint the robot lacks or cannot move, or only some default joint
        names exist.

    Examples
    --------
    >>> from sim.mass import ComOffset
    >>> sim_model(modifiers=(ComOffset(-1.5),)).modifiers
    (ComOffset(com_offset_y_mm=-1.5),)
    """
    path = Path(urdf) if urdf is not None else default_robot_urdf()
    description_hash = read_urdf(path).description_hash  # the cache key: any edited file is rebuilt
    model = _build(
        str(path.resolve()),
        description_hash,
        float(tol_m),
        int(max_vertices),
        joint_map,
        bool(merge_fixed),
        tuple(
            m for m in modifiers if m.EDITS_URDF
        ),  # the others leave the URDF, so they share its cache entry
    )
    return model if model.modifiers == tuple(modifiers) else replace(model, modifiers=tuple(modifiers))
