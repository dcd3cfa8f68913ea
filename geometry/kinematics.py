"""URDF to kinematics: the strictly parsed joint tree, each joint as a :class:`JointSpec`, the links' inertials,
and the transforms a joint's value makes.

yourdfpy reads the tree; the transforms are computed here with the arithmetic of yourdfpy's scene graph (trimesh's
``rotation_matrix`` and ``multi_dot`` over a chain), so they agree with it to the bit without building it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .errors import RobotDescriptionError
from .mass import MassProperties
from .urdf import UrdfFile, origin_matrix

if TYPE_CHECKING:  # yourdfpy loads only where a URDF's structure is parsed (not for a cached robot)
    import yourdfpy

MOVABLE_JOINT_TYPES = ("revolute", "continuous")
"""Joint types a joint map may drive (theta_w and theta_l are angles)."""
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
"""Joint types a URDF may hold (those of the URDF specification)."""


def _check_origins(uf: UrdfFile) -> None:
    """Every ``<origin>`` and joint ``<axis>`` holds finite numbers (before yourdfpy multiplies them)."""
    name = uf.path.name
    for kind in ("link", "joint"):
        for el in uf.root.findall(kind):
            label = f"'{name}': {kind} '{el.get('name')}'"
            holders = (
                [(el, "origin")] if kind == "joint" else [(el.find("inertial"), "inertial origin (CoM)")]
            )
            holders += [(c, f"{c.tag} origin") for c in (*el.findall("collision"), *el.findall("visual"))]
            for holder, what in holders:
                if holder is None:
                    continue
                t = origin_matrix(holder, f"{label}: {what}")
                if not np.isfinite(t).all():
                    o = holder.find("origin")
                    raise RobotDescriptionError(
                        f"{label}: {what} is not finite (xyz {o.get('xyz')!r}, rpy "
                        f"{o.get('rpy')!r}); fix its <origin>"
                    )
            axis = el.find("axis") if kind == "joint" else None
            if axis is not None and axis.get("xyz") is not None:
                try:
                    ok = np.isfinite([float(x) for x in axis.get("xyz").split()]).all()
                except ValueError:
                    ok = False
                if not ok:
                    raise RobotDescriptionError(
                        f"{label}: axis {axis.get('xyz')!r} is not three finite numbers; "
                        "fix its <axis xyz=.../>"
                    )


def _parse_structure(uf: UrdfFile) -> yourdfpy.Robot:
    """yourdfpy's model of the strictly parsed tree, its links and joints checked."""
    import yourdfpy

    name = uf.path.name
    _check_origins(uf)
    try:
        robot = yourdfpy.URDF._parse_robot(xml_element=uf.root)
    except KeyError as exc:
        raise RobotDescriptionError(
            f"cannot read '{name}' as URDF: an element lacks its required attribute {exc}; add it"
        ) from None
    except ValueError as exc:
        raise RobotDescriptionError(
            f"cannot read '{name}' as URDF: {str(exc).splitlines()[0]}; fix the value"
        ) from None
    except (AttributeError, TypeError):  # yourdfpy reads a missing child element as None and fails on it
        raise RobotDescriptionError(
            f"cannot read '{name}' as URDF: an element lacks a required child "
            "(e.g. a joint's <parent link=.../> or <child link=.../>); add it"
        ) from None
    links = {lk.name for lk in robot.links}
    children: dict[str, str] = {}
    for j in robot.joints:
        if j.type not in JOINT_TYPES:
            raise RobotDescriptionError(
                f"'{name}': joint '{j.name}' has type {j.type!r}; use one of {', '.join(JOINT_TYPES)}"
            )
        for what, link in (("parent", j.parent), ("child", j.child)):
            if link not in links:
                raise RobotDescriptionError(
                    f"'{name}': joint '{j.name}' {what} link {link!r} is not a link of the "
                    f"robot; fix its <{what} link=.../>"
                )
        if j.child in children:
            raise RobotDescriptionError(
                f"'{name}': link '{j.child}' is the child of joints '{children[j.child]}' "
                f"and '{j.name}'; a URDF is a tree: give it one parent joint"
            )
        children[j.child] = j.name
    roots = [lk for lk in links if lk not in children]
    if len(roots) != 1:
        raise RobotDescriptionError(
            f"'{name}': links {', '.join(sorted(roots))} have no parent joint; a URDF has "
            "one base link: connect the others by joints"
        )
    return robot


def _yourdfpy_model(robot: yourdfpy.Robot, path: Path) -> yourdfpy.URDF:
    import yourdfpy

    return yourdfpy.URDF(
        robot=robot,
        build_scene_graph=True,
        build_collision_scene_graph=False,
        load_meshes=False,
        mesh_dir=str(path.parent),
    )


def _link_mass(link: yourdfpy.Link, name: str) -> MassProperties:
    """A link's ``<inertial>`` as MassProperties in the link frame, every field checked."""
    inertial = link.inertial
    if inertial is None or inertial.mass is None:
        return MassProperties(0.0, np.zeros(3), np.zeros((3, 3)), "given")
    mass = float(inertial.mass)
    if not (np.isfinite(mass) and mass >= 0):
        raise RobotDescriptionError(
            f"'{name}': link '{link.name}': mass is {mass!r} kg; a mass must be a finite "
            "number >= 0: fix its <inertial><mass value=.../>"
        )
    T = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, dtype=np.float64)
    inertia = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia, dtype=np.float64)
    if not np.isfinite(inertia).all():
        raise RobotDescriptionError(
            f"'{name}': link '{link.name}': inertia is not finite "
            f"({inertia.tolist()}); fix its <inertial><inertia .../>"
        )
    return MassProperties(mass, T[:3, 3].copy(), T[:3, :3] @ inertia @ T[:3, :3].T, "given")


@dataclass(frozen=True)
class JointSpec:
    """One URDF joint as the kinematics use it (read once from the file, or from the robot cache).

    Attributes
    ----------
    name, type, parent, child : str
        As in the URDF.
    origin : ndarray of shape (4, 4)
        Parent-link-to-joint transform, m.
    axis : ndarray of shape (3,)
        Joint axis as written (default (1, 0, 0)).
    lower_rad, upper_rad : float
        Limits, rad or m (nan where the URDF gives none).
    mimic : str
        The joint this one mimics ("" for none); value = ``multiplier`` * that joint's value + ``offset``.
    """

    name: str
    type: str
    parent: str
    child: str
    origin: NDArray[np.float64] = field(repr=False)
    axis: NDArray[np.float64] = field(repr=False)
    lower_rad: float = np.nan
    upper_rad: float = np.nan
    mimic: str = ""
    multiplier: float = 1.0
    offset: float = 0.0

    @property
    def actuated(self) -> bool:
        """Set by a configuration value (yourdfpy's actuated joints: not fixed, not a mimic)."""
        return self.type != "fixed" and not self.mimic


def _joint_specs(robot: yourdfpy.Robot) -> tuple[JointSpec, ...]:
    out = []
    for j in robot.joints:
        lim = j.limit
        lo = np.nan if lim is None or lim.lower is None else float(lim.lower)
        hi = np.nan if lim is None or lim.upper is None else float(lim.upper)
        out.append(
            JointSpec(
                j.name,
                j.type,
                j.parent,
                j.child,
                np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=np.float64),
                np.array([1.0, 0.0, 0.0]) if j.axis is None else np.asarray(j.axis, dtype=np.float64),
                lo,
                hi,
                "" if j.mimic is None else str(j.mimic.joint),
                1.0 if j.mimic is None or j.mimic.multiplier is None else float(j.mimic.multiplier),
                0.0 if j.mimic is None or j.mimic.offset is None else float(j.mimic.offset),
            )
        )
    return tuple(out)


def joint_motion(kind: str, axis: NDArray[np.float64], q: float) -> NDArray[np.float64]:
    """The 4x4 motion of a joint at value q (rad or m): a rotation about the unit axis, a translation along the
    axis as written (prismatic), identity otherwise (fixed, floating and planar at rest). The arithmetic is that
    of ``trimesh.transformations.rotation_matrix``, which yourdfpy uses, so the transforms agree to the bit.

    Examples
    --------
    >>> joint_motion("revolute", np.array([0.0, 0.0, 2.0]), np.pi / 2)[:3, :3].round(12).tolist()
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    if kind == "prismatic":
        m = np.eye(4)
        m[:3, 3] = q * axis
        return m
    if kind not in MOVABLE_JOINT_TYPES:
        return np.eye(4)
    sina, cosa = np.sin(q), np.cos(q)
    d = np.array(axis[:3], dtype=np.float64)
    d /= np.sqrt(np.dot(d, d))
    m = np.diag([cosa, cosa, cosa, 1.0])
    m[:3, :3] += np.outer(d, d) * (1.0 - cosa)
    d = d * sina
    m[:3, :3] += np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]])
    return m


_IDENTITY = np.eye(4)


def _chain_product(matrices: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """The product of a chain's joint matrices as trimesh's scene graph forms it (identities dropped, then
    ``np.linalg.multi_dot``), so that poses equal yourdfpy's to the bit."""
    matrices = [m for m in matrices if np.abs(m - _IDENTITY).max() > 1e-8]
    if not matrices:
        return np.eye(4)
    if len(matrices) == 1:
        return matrices[0].copy()
    return np.linalg.multi_dot(matrices)
