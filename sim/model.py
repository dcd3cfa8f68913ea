"""The robot as pybullet should see it: a URDF string with simplified convex collision hulls (pure, no I/O
beyond reading the source URDF and its meshes).

Contact with flat ground only ever touches the convex hull of a link, so each ``<collision>`` mesh is replaced
by its convex hull, and a hull with more than a few dozen vertices is simplified by *support-gap refinement*:
starting from the six axis-extreme vertices, the vertex that sticks out furthest beyond the current subset,
measured along ``N_DIRECTIONS`` evenly spread directions, is added until no direction sees a gap above
``tol_m`` (default 0.1 mm) or ``max_vertices`` is reached. The support function ``h(d) = max_v v.d`` is the
height of the lowest point of the link above the ground when ``d`` points down, so the gap bounds how much
higher the simplified link rests than the original in any of those directions. Primitive geometry (box,
sphere, cylinder) is kept. Visual elements are dropped (DIRECT mode renders nothing). The lab robot's
3325-vertex head comes out at under 100 vertices; ``benchmarks/sim_convergence.py`` checks that outcomes do not
change.

The URDF text is returned with placeholder mesh file names; :mod:`sim.world` writes the hull meshes to a cache
directory and loads the result.
"""

from __future__ import annotations

import copy
import hashlib
import logging
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import trimesh
from lxml import etree as ET
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull

from geometry import JointMap, Robot
from geometry.errors import RobotDescriptionError, UnknownJointError
from geometry.frames import rpy_from_matrix
from geometry.urdf import origin_matrix, read_urdf

log = logging.getLogger(__name__)

N_DIRECTIONS = 2000
"""Directions on which the support gap of a simplified hull is measured (Fibonacci sphere)."""

HULL_TOL_M = 1e-4
"""Default largest support gap of a simplified hull, m."""

HULL_MAX_VERTICES = 96
"""Default vertex budget of a simplified hull (Bullet's advice: keep convex hulls under ~100 vertices)."""

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


def fibonacci_directions(n: int) -> NDArray[np.float64]:
    """``n`` unit vectors spread evenly over the sphere.

    Examples
    --------
    >>> d = fibonacci_directions(100)
    >>> d.shape, bool(np.allclose(np.linalg.norm(d, axis=1), 1.0))
    ((100, 3), True)
    """
    k = np.arange(n, dtype=np.float64) + 0.5
    z = 1.0 - 2.0 * k / n
    rho = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k
    return np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=1)


@dataclass(frozen=True)
class SimplifiedHull:
    """A convex hull reduced to the vertices that matter for contact.

    Attributes
    ----------
    vertices : ndarray of shape (K, 3)
        Kept vertices, in the units of the input points.
    faces : ndarray of shape (F, 3) of int64
        Outward triangles of the hull of ``vertices``.
    n_full : int
        Vertex count of the full convex hull.
    gap : float
        Largest support gap over the test directions, input units (0 when nothing was dropped).
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    n_full: int
    gap: float


def simplified_hull(
    points: ArrayLike, *, tol: float, max_vertices: int = HULL_MAX_VERTICES
) -> SimplifiedHull:
    """Convex hull of ``points``, simplified by support-gap refinement (see the module docstring).

    Parameters
    ----------
    points : array_like of shape (N, 3)
        Vertices, any length unit.
    tol : float
        Largest support gap allowed, same unit as ``points``; ``0`` keeps the full hull.
    max_vertices : int
        Vertex budget (>= 4); refinement stops there even if the gap is larger.

    Returns
    -------
    SimplifiedHull

    Examples
    --------
    >>> s = simplified_hull(trimesh.creation.icosphere(subdivisions=4).vertices, tol=0.02, max_vertices=200)
    >>> s.n_full, len(s.vertices) < 200, s.gap <= 0.02
    (2562, True, True)
    """
    pts = np.unique(np.asarray(points, dtype=np.float64).reshape(-1, 3), axis=0)
    full = pts[ConvexHull(pts).vertices]
    dirs = fibonacci_directions(N_DIRECTIONS)
    proj = full @ dirs.T  # (K, D)
    h_full = proj.max(axis=0)
    if tol <= 0 or len(full) <= max(4, min(max_vertices, 24)):
        keep = np.arange(len(full))
    else:
        seed = {int(np.argmax(full[:, a] * s)) for a in range(3) for s in (1.0, -1.0)}
        keep = sorted(seed)
        h = proj[keep].max(axis=0)
        while len(keep) < max_vertices:
            gap = h_full - h
            j = int(np.argmax(gap))
            if gap[j] <= tol:
                break
            v = int(np.argmax(proj[:, j]))
            keep.append(v)
            h = np.maximum(h, proj[v])
        keep = np.asarray(keep)
    verts = full[keep]
    gap = float((h_full - (verts @ dirs.T).max(axis=0)).max())
    tri = trimesh.Trimesh(verts, ConvexHull(verts).simplices, process=True)
    trimesh.repair.fix_normals(tri)
    return SimplifiedHull(
        np.asarray(tri.vertices), np.asarray(tri.faces, dtype=np.int64), len(full), max(gap, 0.0)
    )


def hull_obj_text(hull: SimplifiedHull) -> str:
    """Wavefront OBJ text of a hull (vertices and 1-based faces)."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in hull.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in hull.faces]
    return "\n".join(lines) + "\n"


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
    head_joint : str or None
        The head's attachment when it gives (:func:`add_head_compliance`), else None.
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
    head_joint: str | None = None


def _origin(el: ET._Element | None) -> NDArray[np.float64]:
    """4x4 transform of an element's ``<origin xyz rpy>`` (:func:`geometry.urdf.origin_matrix`)."""
    return origin_matrix(el)


def _set_origin(el: ET._Element, t: NDArray[np.float64]) -> None:
    o = el.find("origin")
    if o is None:
        o = ET.Element("origin")
        el.insert(0, o)
    rpy = np.zeros(3)
    if not np.allclose(t[:3, :3], np.eye(3), rtol=0.0, atol=1e-15):
        rpy = rpy_from_matrix(t[:3, :3])
    o.set("xyz", " ".join(f"{x:.17g}" for x in t[:3, 3]))
    o.set("rpy", " ".join(f"{x:.17g}" for x in rpy))


def _axis_text(v) -> str:
    """A unit axis as a URDF ``xyz`` attribute (components below 1e-12 written as 0)."""
    return " ".join(f"{x:.17g}" if abs(x) > 1e-12 else "0" for x in v)


def _joint(root: ET._Element, joint: str, purpose: str) -> ET._Element:
    """The URDF's joint element named ``joint``; ``purpose`` ("to shift") ends the error's first clause.

    Raises
    ------
    UnknownJointError
        Naming the robot's joints, if it has none of that name.
    """
    el = next((j for j in root.findall("joint") if j.get("name") == joint), None)
    if el is None:
        names = ", ".join(sorted(j.get("name") for j in root.findall("joint"))) or "none"
        raise UnknownJointError(f"the robot has no joint {joint!r} {purpose}; its joints are {names}")
    return el


def _inertial(link: ET._Element) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """(mass kg, CoM m, 3x3 inertia about the CoM kg m^2) of a link in its own frame."""
    el = link.find("inertial")
    if el is None or el.find("mass") is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    t = _origin(el)
    i = el.find("inertia")
    g = {
        k: float(i.get(k, "0")) if i is not None else 0.0 for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    }
    tensor = np.array(
        [[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]]
    )
    return float(el.find("mass").get("value")), t[:3, 3], t[:3, :3] @ tensor @ t[:3, :3].T


def _principal_frame(tensor: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Principal moments and axes (columns, a proper rotation as close to the identity as the axes allow)."""
    if np.abs(tensor - np.diag(np.diag(tensor))).max() <= 1e-12 * max(np.abs(tensor).max(), 1e-300):
        return np.diag(tensor).copy(), np.eye(3)
    w, v = np.linalg.eigh(tensor)
    order = np.argsort([int(np.argmax(np.abs(v[:, k]))) for k in range(3)])  # axis k ~ link axis k
    if sorted(int(np.argmax(np.abs(v[:, k]))) for k in range(3)) != [0, 1, 2]:
        order = np.arange(3)
    w, v = w[order], v[:, order]
    v = v * np.where(np.diag(v) < 0, -1.0, 1.0)
    if np.linalg.det(v) < 0:
        v[:, 2] *= -1
    return w, v


def merge_fixed_links(root: ET._Element) -> list[str]:
    """Merge every link hanging on a ``fixed`` joint into its parent, in place; return the merged link names.

    The parent gets the children's collision elements (origins composed with the joint's) and their joints
    (re-parented), and one ``<inertial>``: total mass, mass-weighted CoM, and the inertia about that CoM
    (parallel-axis theorem), written in its principal axes. pybullet's own ``URDF_MERGE_FIXED_LINKS`` puts a
    child's mass at the child's link origin, ignoring its ``<inertial><origin>`` (pybullet 3.2.7), so it is
    not used.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/>'
    ...         '</inertial></link><link name="b"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>'
    ...         '<inertia ixx="1" iyy="1" izz="1"/></inertial></link><joint name="j" type="fixed">'
    ...         '<parent link="a"/><child link="b"/><origin xyz="0.5 0 0"/></joint></robot>')
    >>> root = ET.fromstring(urdf)
    >>> merge_fixed_links(root)
    ['b']
    >>> el = root.find("link/inertial")
    >>> el.find("origin").get("xyz"), el.find("mass").get("value"), el.find("inertia").get("izz")
    ('0.5 0 0', '2', '2.5')
    """
    links = {lk.get("name"): lk for lk in root.findall("link")}
    merged: list[str] = []
    while True:
        fixed = next((j for j in root.findall("joint") if j.get("type") == "fixed"), None)
        if fixed is None:
            return merged
        parent = links[fixed.find("parent").get("link")]
        child = links.pop(fixed.find("child").get("link"))
        t_pc = _origin(fixed)
        for col in child.findall("collision"):
            _set_origin(col, t_pc @ _origin(col))
            parent.append(col)
        for j in root.findall("joint"):
            if j is not fixed and j.find("parent").get("link") == child.get("name"):
                j.find("parent").set("link", parent.get("name"))
                _set_origin(j, t_pc @ _origin(j))
        m_p, c_p, i_p = _inertial(parent)
        m_c, c_c, i_c = _inertial(child)
        c_c = t_pc[:3, :3] @ c_c + t_pc[:3, 3]
        i_c = t_pc[:3, :3] @ i_c @ t_pc[:3, :3].T
        mass = m_p + m_c
        if mass > 0:
            com = (m_p * c_p + m_c * c_c) / mass
            tensor = i_p + i_c
            for m, c in ((m_p, c_p), (m_c, c_c)):
                d = c - com
                tensor = tensor + m * (d @ d * np.eye(3) - np.outer(d, d))
            moments, axes = _principal_frame(tensor)
            old = parent.find("inertial")
            if old is not None:
                parent.remove(old)
            el = ET.SubElement(parent, "inertial")
            t = np.eye(4)
            t[:3, :3], t[:3, 3] = axes, com
            _set_origin(el, t)
            ET.SubElement(el, "mass", value=f"{mass:.17g}")
            ET.SubElement(
                el,
                "inertia",
                ixx=f"{moments[0]:.17g}",
                ixy="0",
                ixz="0",
                iyy=f"{moments[1]:.17g}",
                iyz="0",
                izz=f"{moments[2]:.17g}",
            )
        root.remove(fixed)
        root.remove(child)
        merged.append(child.get("name"))


TORSION_JOINT = "body_torsion"
"""Name of the revolute joint :func:`add_body_torsion` inserts (:class:`sim.compliance.BodyTorsion`)."""

TORSION_LINK = "body_torsion_frame"
"""Name of the massless link that carries the wing mounts behind ``TORSION_JOINT``."""

TORSION_LIMIT_RAD = 0.6
"""The inserted joint's range, +- rad: a twist beyond it means a broken body, not a soft one."""


def _base_link(root: ET._Element) -> ET._Element:
    """The URDF's root link: the one no joint has as its child."""
    children = {j.find("child").get("link") for j in root.findall("joint")}
    return next(lk for lk in root.findall("link") if lk.get("name") not in children)


def _add_hinge(
    root: ET._Element,
    link: str,
    joint: str,
    parent: str,
    child: str,
    axis_xyz: str,
    limit_rad: float,
    *,
    mass_kg: float = 0.0,
) -> None:
    """Append a new link ``link`` (``mass_kg``, inertia ``mass_kg * 1e-6`` about each axis; 0: massless) and a
    revolute joint ``joint`` from ``parent`` to ``child`` at the parent's frame, about ``axis_xyz``, within
    ``±limit_rad``: the hinge of :func:`add_body_torsion` and :func:`add_leg_bend`, which a spring drives."""
    frame = ET.Element("link", name=link)
    inertial = ET.SubElement(frame, "inertial")
    i = mass_kg * 1e-6
    ET.SubElement(inertial, "mass", value=f"{mass_kg:.17g}")
    ET.SubElement(
        inertial, "inertia", ixx=f"{i:.17g}", ixy="0", ixz="0", iyy=f"{i:.17g}", iyz="0", izz=f"{i:.17g}"
    )
    hinge = ET.Element("joint", name=joint, type="revolute")
    ET.SubElement(hinge, "parent", link=parent)
    ET.SubElement(hinge, "child", link=child)
    ET.SubElement(hinge, "origin", xyz="0 0 0", rpy="0 0 0")
    ET.SubElement(hinge, "axis", xyz=axis_xyz)
    lim = f"{limit_rad:g}"
    ET.SubElement(hinge, "limit", lower=f"-{lim}", upper=lim, effort="1000", velocity="1000")
    root.append(frame)
    root.append(hinge)


def add_body_torsion(root: ET._Element, wing_joints: tuple[str, ...]) -> list[str]:
    """Let the part of the body that carries the wings twist against the rest, in place; return the re-hung
    joints.

    Every joint between the base link and a wing joint that starts at the base (the wing mounts; a wing joint
    itself if it starts at the base) is re-hung from a new massless link ``TORSION_LINK``, which a revolute
    joint ``TORSION_JOINT`` about the base frame's x axis, through its origin, carries. At zero twist every link
    sits where it did, so geometry, mass and CoM are unchanged. The base keeps everything else (head, leg and
    whatever is fixed to it).

    Raises
    ------
    RobotDescriptionError
        If the names are taken, or no wing joint hangs below the base.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="base"/><link name="m"/><link name="w"/><link name="h"/>'
    ...         '<joint name="mount" type="fixed"><parent link="base"/><child link="m"/></joint>'
    ...         '<joint name="wing" type="revolute"><parent link="m"/><child link="w"/></joint>'
    ...         '<joint name="head" type="fixed"><parent link="base"/><child link="h"/></joint></robot>')
    >>> root = ET.fromstring(urdf)
    >>> add_body_torsion(root, ("wing",))
    ['mount']
    >>> j = root.find("joint[@name='body_torsion']")
    >>> j.find("parent").get("link"), j.find("child").get("link"), j.find("axis").get("xyz")
    ('base', 'body_torsion_frame', '1 0 0')
    >>> root.find("joint[@name='mount']/parent").get("link"), root.find("joint[@name='head']/parent").get("link")
    ('body_torsion_frame', 'base')
    """
    joints = {j.get("name"): j for j in root.findall("joint")}
    links = {lk.get("name") for lk in root.findall("link")}
    if TORSION_JOINT in joints or TORSION_LINK in links:
        raise RobotDescriptionError(
            f"the robot already has a joint '{TORSION_JOINT}' or link '{TORSION_LINK}'; rename it to use "
            "[body_torsion]"
        )
    by_child = {j.find("child").get("link"): j for j in joints.values()}
    base = _base_link(root).get("name")
    rehang: list[str] = []
    for name in wing_joints:
        j = joints.get(name)
        while j is not None and j.find("parent").get("link") != base:
            j = by_child.get(j.find("parent").get("link"))
        if j is not None and j.get("name") not in rehang:
            rehang.append(j.get("name"))
    if not rehang:
        raise RobotDescriptionError(
            f"no wing joint hangs below the base link '{base}'; [body_torsion] needs one"
        )
    _add_hinge(root, TORSION_LINK, TORSION_JOINT, base, TORSION_LINK, "1 0 0", TORSION_LIMIT_RAD)
    for name in rehang:
        joints[name].find("parent").set("link", TORSION_LINK)
    return rehang


BEND_JOINT = "leg_bend"
"""Name of the revolute joint :func:`add_leg_bend` inserts (:class:`sim.compliance.LegBend`)."""
BEND_LINK = "leg_bend_root"
"""Name of the (nearly) massless link between the leg joint and the leg behind ``BEND_JOINT``."""
BEND_LIMIT_RAD = 0.6
"""The bend's joint limit, rad (a stop far beyond any sag or ringing of a sensible spring)."""


def add_leg_bend(root: ET._Element, leg_joint: str) -> str:
    """Let the leg bend out of its swing plane, in place; return the name of the leg's link.

    The leg joint's child link (the leg) is re-hung from a new link ``BEND_LINK`` at the leg joint's frame, on a
    revolute joint ``BEND_JOINT`` through the leg's pivot about the axis perpendicular to both the leg joint's
    axis and the pivot-to-CoM line of the leg (for the lab robot: the horizontal axis across the rod, so the
    leg's end bobs up and down). At zero bend every link sits where it did, so geometry, mass and CoM are
    unchanged. ``BEND_LINK`` carries 1e-6 of the leg's mass (pybullet needs a mass on a moving link).

    Raises
    ------
    RobotDescriptionError
        If the names are taken, the leg joint is missing, or the leg's CoM lies on the leg joint's axis.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="b"/><link name="leg"><inertial><origin xyz="-0.06 0 0"/>'
    ...         '<mass value="0.05"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6"/></inertial></link>'
    ...         '<joint name="swing" type="revolute"><parent link="b"/><child link="leg"/>'
    ...         '<axis xyz="0 0 1"/></joint></robot>')
    >>> root = ET.fromstring(urdf)
    >>> add_leg_bend(root, "swing")
    'leg'
    >>> j = root.find("joint[@name='leg_bend']")
    >>> j.find("parent").get("link"), j.find("child").get("link"), j.find("axis").get("xyz")
    ('leg_bend_root', 'leg', '0 -1 0')
    >>> root.find("joint[@name='swing']/child").get("link")
    'leg_bend_root'
    """
    joints = {j.get("name"): j for j in root.findall("joint")}
    links = {lk.get("name"): lk for lk in root.findall("link")}
    if BEND_JOINT in joints or BEND_LINK in links:
        raise RobotDescriptionError(
            f"the robot already has a joint '{BEND_JOINT}' or link '{BEND_LINK}'; rename it to use [leg_bend]"
        )
    j = joints.get(leg_joint)
    if j is None:
        raise RobotDescriptionError(f"the robot has no leg joint '{leg_joint}'; [leg_bend] needs one")
    leg = str(j.find("child").get("link"))
    mass, com, _ = _inertial(links[leg])
    ax_el = j.find("axis")
    axis = (
        np.array([float(v) for v in ax_el.get("xyz").split()]) if ax_el is not None else np.array([1.0, 0, 0])
    )
    bend = np.cross(axis / np.linalg.norm(axis), com)
    if mass <= 0 or np.linalg.norm(bend) < 1e-9:
        raise RobotDescriptionError(
            f"the leg link '{leg}' has no mass off its joint's axis, so it has no bending axis; [leg_bend] needs one"
        )
    bend /= np.linalg.norm(bend)
    j.find("child").set("link", BEND_LINK)
    _add_hinge(
        root, BEND_LINK, BEND_JOINT, BEND_LINK, leg, _axis_text(bend), BEND_LIMIT_RAD, mass_kg=mass * 1e-6
    )
    return leg


def shift_com(root: ET._Element, offset_m: ArrayLike) -> str:
    """Move the whole robot's CoM by ``offset_m`` (base frame, m), in place, as
    :meth:`geometry.Robot.with_com_offset` does: the base link's inertial origin moves by ``offset_m * M / m_base``
    (M the total mass of every link); masses and inertias about each CoM stay. Return the base link's name.

    Raises
    ------
    RobotDescriptionError
        If the base link has no mass to move.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/>'
    ...         '</inertial></link><link name="b"><inertial><mass value="3"/><inertia ixx="1" iyy="1" izz="1"/>'
    ...         '</inertial></link><joint name="j" type="revolute"><parent link="a"/><child link="b"/></joint>'
    ...         '</robot>')
    >>> root = ET.fromstring(urdf)
    >>> shift_com(root, [0.0, 0.001, 0.0]), root.find("link/inertial/origin").get("xyz")
    ('a', '0 0.0040000000000000001 0')
    """
    d = np.asarray(offset_m, dtype=np.float64)
    base = _base_link(root)
    total = sum(_inertial(lk)[0] for lk in root.findall("link"))
    m_base = _inertial(base)[0]
    if m_base <= 0:
        raise RobotDescriptionError(
            f"the base link '{base.get('name')}' has no mass, so there is none to move for a CoM offset"
        )
    el = base.find("inertial")
    t = _origin(el)
    t[:3, 3] += d * total / m_base
    _set_origin(el, t)
    return str(base.get("name"))


def shift_joint(root: ET._Element, joint: str, offset_m: ArrayLike) -> None:
    """Move one joint's origin by ``offset_m`` (m, in its parent link's frame), in place, as
    :meth:`geometry.Robot.with_joint_shift` does: its child link and everything below move with it.

    Raises
    ------
    UnknownJointError
        If the URDF has no joint of that name.

    Examples
    --------
    >>> root = ET.fromstring('<robot name="r"><joint name="j" type="fixed"><origin xyz="0.05 0 0.008"/></joint></robot>')
    >>> shift_joint(root, "j", [-0.018, 0.0, 0.0]); root.find("joint/origin").get("xyz")
    '0.032000000000000001 0 0.0080000000000000002'
    """
    el = _joint(root, joint, "to shift")
    t = _origin(el)
    t[:3, 3] += np.asarray(offset_m, dtype=np.float64)
    _set_origin(el, t)


def add_head_compliance(root: ET._Element, joint: str, *, slide: bool, axis: ArrayLike, travel: float) -> str:
    """Make the fixed joint that attaches the head give, in place (:class:`sim.compliance.HeadCompliance`): it
    becomes a slide along ``axis`` (``slide``, ``travel`` in m) or a hinge about it (``travel`` in rad), through
    its origin, stopped at ``±travel``; ``axis`` is in the joint's parent frame. At zero deflection every link sits
    where it did. Return the head's link name.

    Raises
    ------
    UnknownJointError
        If the URDF has no joint of that name.
    RobotDescriptionError
        If the joint is not fixed (it already moves: a wing or leg joint, say).

    Examples
    --------
    >>> root = ET.fromstring('<robot name="r"><link name="b"/><link name="h"/><joint name="head_mount" '
    ...                      'type="fixed"><parent link="b"/><child link="h"/><origin xyz="0.05 0 0"/></joint></robot>')
    >>> add_head_compliance(root, "head_mount", slide=True, axis=[1, 0, 0], travel=0.017)
    'h'
    >>> j = root.find("joint")
    >>> j.get("type"), j.find("axis").get("xyz"), j.find("limit").get("lower")
    ('prismatic', '1 0 0', '-0.017000000000000001')
    """
    try:
        el = _joint(root, joint, "for [head_compliance]")
    except UnknownJointError as exc:
        raise UnknownJointError(
            f"{exc}: give the joint that attaches the head as [head_compliance] joint"
        ) from None
    if el.get("type") != "fixed":
        raise RobotDescriptionError(
            f"[head_compliance] joint {joint!r} is {el.get('type')}, not fixed; give the fixed joint that attaches "
            "the head"
        )
    a = np.asarray(axis, dtype=np.float64).reshape(3)
    a = _origin(el)[:3, :3].T @ (a / np.linalg.norm(a))  # URDF axes are in the joint's own frame
    el.set("type", "prismatic" if slide else "revolute")
    for old in el.findall("axis") + el.findall("limit"):
        el.remove(old)
    ET.SubElement(el, "axis", xyz=_axis_text(a))
    t = f"{float(travel):.17g}"
    ET.SubElement(el, "limit", lower=f"-{t}", upper=t, effort="1000", velocity="1000")
    return str(el.find("child").get("link"))


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
    body_torsion: bool = False,
    com_offset_m: tuple[float, float, float] = (0.0, 0.0, 0.0),
    leg_bend: bool = False,
    joint_shift: tuple[str, tuple[float, float, float]] | None = None,
    head: tuple[str, bool, tuple[float, float, float], float] | None = None,
) -> SimModel:
    """The model (cached by the robot's description hash, so an edited URDF or mesh file is rebuilt)."""
    path = Path(path_str)
    robot = Robot.from_urdf(path, joint_map=joint_map)
    # the set's variant (its rest pitch); the file's hashes stay the model's, as for a CoM offset
    variant = robot.with_joint_shift(*joint_shift) if joint_shift is not None else robot
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
    if joint_shift is not None:
        shift_joint(root, *joint_shift)
    if head is not None:
        add_head_compliance(root, head[0], slide=head[1], axis=head[2], travel=head[3])
    rehung = add_body_torsion(root, robot.joint_map.wing) if body_torsion else []
    if leg_bend:
        if len(robot.joint_map.leg) != 1:
            raise RobotDescriptionError(
                f"[leg_bend] bends one leg; '{path.name}' drives {len(robot.joint_map.leg)} leg joints "
                f"({', '.join(robot.joint_map.leg)}): drop [leg_bend] or map one leg joint"
            )
        add_leg_bend(root, robot.joint_map.leg[0])
    merged = merge_fixed_links(root) if merge_fixed else []
    if any(com_offset_m):
        shift_com(root, com_offset_m)
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
        rest_pitch_deg(variant.with_com_offset(com_offset_m)),
        robot.theta_limits_deg(),
        path,
        None if head is None else head[0],
    )
    log.info(
        "sim model %s: hulls %s, max support gap %.3g mm, merged links %s, twisting on %s",
        path.name,
        counts,
        max_gap * 1e3,
        merged,
        rehung,
    )
    return model


def sim_model(
    urdf: str | Path | None = None,
    *,
    tol_m: float = HULL_TOL_M,
    max_vertices: int = HULL_MAX_VERTICES,
    joint_map: JointMap | None = None,
    merge_fixed: bool = False,
    body_torsion: bool = False,
    com_offset_m: ArrayLike = (0.0, 0.0, 0.0),
    leg_bend: bool = False,
    joint_shift: tuple[str, ArrayLike] | None = None,
    head_compliance=None,
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
        Merge links on fixed joints into their parents (:func:`merge_fixed_links`): the same rigid body with
        fewer links, so each physics step is cheaper.
    body_torsion : bool
        Let the wing mounts twist against the rest of the body about the base's x axis
        (:func:`add_body_torsion`; :class:`sim.compliance.BodyTorsion` gives the spring).
    com_offset_m : array_like of 3 floats
        Move the whole robot's CoM by this much (base frame, m; :func:`shift_com`), e.g. a model set's
        ``[mass] com_offset_y_mm``.
    leg_bend : bool
        Let the leg bend out of its swing plane (:func:`add_leg_bend`; :class:`sim.compliance.LegBend` gives the
        spring).
    joint_shift : (str, array_like of 3 floats), optional
        Move one joint's origin (parent frame, m; :func:`shift_joint`), e.g. a model set's ``[geometry]``.
    head_compliance : sim.compliance.HeadCompliance, optional
        Let the head's attachment give (:func:`add_head_compliance`; the spring itself drives it in
        :class:`sim.world.World`), e.g. a model set's ``[head_compliance]``.

    Raises
    ------
    RobotDescriptionError
        If the file or a mesh is missing or the description is bad (:meth:`geometry.Robot.from_urdf`), or the
        robot has no wing/leg joints.
    UnknownJointError
        If the joint map names a joint the robot lacks or cannot move, or only some default joint names exist.
    """
    path = Path(urdf) if urdf is not None else default_robot_urdf()
    description_hash = read_urdf(path).description_hash  # the cache key: any edited file is rebuilt
    return _build(
        str(path.resolve()),
        description_hash,
        float(tol_m),
        int(max_vertices),
        joint_map,
        bool(merge_fixed),
        bool(body_torsion),
        tuple(float(v) for v in np.asarray(com_offset_m, dtype=np.float64).reshape(3)),
        bool(leg_bend),
        None
        if joint_shift is None
        else (
            str(joint_shift[0]),
            tuple(float(v) for v in np.asarray(joint_shift[1], dtype=np.float64).reshape(3)),
        ),
        None
        if head_compliance is None
        else (head_compliance.joint, head_compliance.slide, head_compliance.axis, head_compliance.travel),
    )
