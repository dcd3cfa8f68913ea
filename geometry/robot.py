"""Robot descriptions: URDF (via yourdfpy) or a single rigid mesh, posed at (theta_w, theta_l).

The body frame is the URDF's base link. A pose puts every link where the joints say, then keeps only what the
landscape needs: the total mass, the mass-weighted CoM and the convex hull of all geometry.
"""

from __future__ import annotations

import hashlib
import io
import logging
import os
from dataclasses import dataclass, field, replace
from functools import cache, cached_property, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import (
    JOINT_OUT_OF_RANGE,
    GeometryError,
    JointLimitError,
    RobotDescriptionError,
    UnknownJointError,
    UsageError,
)
from .hull import Hull, convex_hull
from .mass import MassProperties, combine
from .urdf import MeshRef, UrdfFile, origin_matrix, read_urdf

if TYPE_CHECKING:  # trimesh and yourdfpy load only where meshes are read (not for a cached robot)
    import trimesh
    import yourdfpy

log = logging.getLogger(__name__)

UNITS_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}

MOVABLE_JOINT_TYPES = ("revolute", "continuous")
"""Joint types a joint map may drive (theta_w and theta_l are angles)."""
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_JOINTS_HINT = (
    "declare the mapping 'wing=NAME,...;leg=NAME,...' (either group may be left out) with --joints on the command "
    "line, joints= in Python"
)
_GROUPS = {"theta_w": "wing", "theta_l": "leg"}
"""Each angle and the joint-map group it drives."""


@dataclass(frozen=True)
class JointMap:
    """Which joints the wing angle theta_w and the leg angle theta_l drive.

    Every joint in ``wing`` is set to theta_w (each wing's pitch and roll joints), every joint in ``leg`` to
    theta_l. The default names are those of the lab robot's URDF. A robot whose joints are named otherwise
    declares its own map: ``JointMap.parse("wing=a,b,c,d;leg=e")`` in Python, ``--joints "wing=a,b,c,d;leg=e"``
    on the command line. Either group may be left out (a body with wings and no leg, ``"wing=a,b"``, or a leg
    and no wings); then nothing drives that angle. At least one group names a joint.

    Examples
    --------
    >>> JointMap.parse("wing=wl,wr;leg=tail").leg
    ('tail',)
    >>> JointMap.parse("wing=wl,wr").leg
    ()
    """

    wing: tuple[str, ...] = ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right")
    leg: tuple[str, ...] = ("leg",)

    def __post_init__(self):
        seen: set[str] = set()
        for key in ("wing", "leg"):
            names = getattr(self, key)
            if isinstance(names, str) or not all(isinstance(n, str) for n in names):
                raise GeometryError(f"joint map {key} must be a tuple of joint names; got {names!r}")
            object.__setattr__(self, key, tuple(names))
            if not all(n.strip() for n in names):
                raise GeometryError(
                    f"joint map group '{key}' has an empty name ({','.join(names)!r}); name each joint, "
                    "e.g. 'wing=a,b,c,d;leg=e'"
                )
            for n in names:
                if n in seen:
                    raise GeometryError(
                        f"joint '{n}' is named twice in the joint map; each joint is driven by theta_w or theta_l, "
                        "not both: name it once"
                    )
                seen.add(n)
        if not seen:
            raise GeometryError(
                "the joint map names no joint; name the joints theta_w or theta_l drives, e.g. 'wing=a,b' "
                "or 'wing=a,b,c,d;leg=e'"
            )

    @classmethod
    def parse(cls, text: str) -> JointMap:
        """Parse ``'wing=NAME,...;leg=NAME,...'``; either group may be left out (nothing drives that angle),
        but at least one joint is named and none twice.

        Raises
        ------
        GeometryError
            If the text is not of that form.
        """
        groups: dict[str, tuple[str, ...]] = {}
        for item in filter(None, (s.strip() for s in text.split(";"))):
            key, sep, names = item.partition("=")
            key = key.strip()
            if not sep or key not in ("wing", "leg"):
                raise GeometryError(
                    f"joint map entry {item!r} is not 'wing=NAME,...' or 'leg=NAME,...'; e.g. 'wing=a,b,c,d;leg=e'"
                )
            if key in groups:
                raise GeometryError(f"joint map {text!r} gives '{key}=' twice; give each group once")
            groups[key] = tuple(n.strip() for n in names.split(","))
            if groups[key] == ("",):
                groups[key] = ()
        return cls(wing=groups.get("wing", ()), leg=groups.get("leg", ()))

    def text(self) -> str:
        """The map as ``'wing=NAME,...;leg=NAME,...'`` (what :meth:`parse` reads; an empty group left out).

        Examples
        --------
        >>> JointMap().text()
        'wing=wing_pitch_left,wing_pitch_right,wing_roll_left,wing_roll_right;leg=leg'
        >>> JointMap(leg=()).text()
        'wing=wing_pitch_left,wing_pitch_right,wing_roll_left,wing_roll_right'
        """
        return ";".join(
            f"{key}={','.join(names)}" for key, names in (("wing", self.wing), ("leg", self.leg)) if names
        )


@dataclass(frozen=True)
class Part:
    """One link's geometry and inertial, in the link frame.

    Attributes
    ----------
    link : str
        Link name.
    mass : MassProperties
        Mass, CoM (m, link frame) and inertia of the link.
    hull_link_m : ndarray of shape (K, 3)
        Convex hull vertices of all the link's collision geometry, link frame, m (may be empty).
    points_link_m : ndarray of shape (N, 3)
        Every vertex of the link's meshes, link frame, m (only for the brute-force reference method).
    """

    link: str
    mass: MassProperties
    hull_link_m: NDArray[np.float64]
    points_link_m: NDArray[np.float64]


@dataclass(frozen=True)
class Pose:
    """The rigid body a robot is at fixed joint angles, in the body (base-link) frame.

    Attributes
    ----------
    theta_w_deg, theta_l_deg : float or None
        Wing and leg angle, degrees (None for a single rigid mesh).
    mass_kg : float
        Total mass, kg.
    com_m : ndarray of shape (3,)
        Mass-weighted CoM, m.
    hull_points_m : ndarray of shape (M, 3)
        Every part's own hull vertices in the body frame, m; ``hull`` is their convex hull.
    link_transforms : dict[str, ndarray of shape (4, 4)]
        Link-to-body transforms.
    """

    theta_w_deg: float | None
    theta_l_deg: float | None
    mass_kg: float
    com_m: NDArray[np.float64]
    hull_points_m: NDArray[np.float64] = field(repr=False)
    link_transforms: dict[str, NDArray[np.float64]] = field(repr=False)
    parts: tuple[Part, ...] = field(repr=False)

    @cached_property
    def hull(self) -> Hull:
        """Convex hull of every part's geometry, m (computed on first use)."""
        return convex_hull(self.hull_points_m)

    @cached_property
    def inertia_kg_m2(self) -> NDArray[np.float64]:
        """Inertia tensor about the CoM in the body frame, kg m^2: the posed parts' own, combined by the
        parallel-axis theorem (computed on first use; zero for a pose built without parts).

        Examples
        --------
        >>> from geometry.robots import load_robot
        >>> pose = load_robot("builtin").pose(74.0, 30.0)
        >>> bool(np.allclose(pose.inertia_kg_m2, pose.inertia_kg_m2.T) and (np.linalg.eigvalsh(pose.inertia_kg_m2) > 0).all())
        True
        """
        masses = _posed_masses(self.link_transforms, self.parts)
        return combine(masses).inertia_kg_m2 if masses else np.zeros((3, 3))

    def all_points_m(self) -> NDArray[np.float64]:
        """Every mesh vertex of every part in the body frame, m (the lab's brute-force input)."""
        out = [
            _apply(self.link_transforms[p.link], p.points_link_m) for p in self.parts if len(p.points_link_m)
        ]
        return np.concatenate(out) if out else np.zeros((0, 3))


def _apply(T: NDArray[np.float64], pts: NDArray[np.float64]) -> NDArray[np.float64]:
    return pts @ T[:3, :3].T + T[:3, 3]


def _posed_masses(T: dict, parts) -> list[MassProperties]:
    """The parts with mass, their CoM and inertia turned into the body frame by the link transforms ``T``."""
    return [
        MassProperties(
            p.mass.mass_kg,
            _apply(T[p.link], p.mass.com_m[None])[0],
            T[p.link][:3, :3] @ p.mass.inertia_kg_m2 @ T[p.link][:3, :3].T,
            p.mass.model,
        )
        for p in parts
        if p.mass.mass_kg > 0
    ]


def _check_vertices(verts: NDArray[np.float64], what: str) -> None:
    if not np.isfinite(verts).all():
        i = int(np.flatnonzero(~np.isfinite(verts).all(axis=1))[0])
        raise RobotDescriptionError(f"{what}: vertex {i} is not finite ({verts[i].tolist()}); fix the mesh")


def _load_mesh_bytes(data: bytes, path: Path, prefix: str = "") -> trimesh.Trimesh:
    """A mesh file's bytes as an unprocessed trimesh (nothing merged or dropped), vertices checked finite;
    ``prefix`` (e.g. ``"link 'head': "``) starts the error messages."""
    import trimesh

    try:
        mesh = trimesh.load(
            io.BytesIO(data),
            file_type=path.suffix.lstrip(".").lower(),
            force="mesh",
            process=False,
            resolver=trimesh.resolvers.FilePathResolver(str(path.parent)),
        )
    except Exception as exc:  # trimesh's loaders raise many types (ValueError, KeyError, IndexError, ...)
        raise RobotDescriptionError(
            f"{prefix}cannot read mesh '{path}': {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}; "
            "give a mesh file (STL, OBJ, PLY, ...)"
        ) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.vertices) == 0:
        raise RobotDescriptionError(
            f"{prefix}'{path}' holds no triangle mesh; give a mesh file (STL, OBJ, PLY, ...)"
        )
    _check_vertices(np.asarray(mesh.vertices, dtype=np.float64), f"{prefix}mesh '{path.name}'")
    return mesh


def _geometry_mesh(geom: yourdfpy.Geometry, ref: MeshRef | None, link: str) -> trimesh.Trimesh | None:
    import trimesh

    if geom.mesh is not None:
        mesh = _load_mesh_bytes(ref.data, ref.path, f"link '{link}': ")
        scale = ref.scale
        mesh.apply_scale(scale[0]) if np.allclose(scale, scale[0]) else mesh.apply_transform(
            np.diag([*scale, 1.0])
        )
        return mesh
    if geom.box is not None:
        return trimesh.creation.box(extents=np.asarray(geom.box.size, float))
    if geom.cylinder is not None:
        return trimesh.creation.cylinder(
            radius=geom.cylinder.radius, height=geom.cylinder.length, sections=64
        )
    if geom.sphere is not None:
        return trimesh.creation.icosphere(subdivisions=3, radius=geom.sphere.radius)
    return None


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


def _checked_joint_map(joints, joint_map: JointMap | None, name: str) -> JointMap | None:
    """The joint map to use: an explicit one checked, else the default names if all are there, else None (rigid).

    Raises UnknownJointError if a named joint is absent or not movable, or only some default names are present.
    """
    types = {j.name: j.type for j in joints}
    movable = ", ".join(n for n, t in types.items() if t in MOVABLE_JOINT_TYPES) or "none"
    if joint_map is None:
        default = JointMap()
        wanted = (*default.wing, *default.leg)
        missing = [n for n in wanted if n not in types]
        if len(missing) == len(wanted):  # none of the default names: a rigid robot at its zero configuration
            log.info("%s: none of the default joints %s; treating the robot as rigid", name, wanted)
            return None
        if missing:
            raise UnknownJointError(
                f"'{name}' has {len(wanted) - len(missing)} of the {len(wanted)} default joints; missing: "
                f"{', '.join(missing)} (movable joints: {movable}); rename them in the URDF or {_JOINTS_HINT}"
            )
        joint_map = default
    for n in (*joint_map.wing, *joint_map.leg):
        if n not in types:
            raise UnknownJointError(
                f"joint '{n}' is not in '{name}' (movable joints: {movable}); {_JOINTS_HINT}"
            )
        if types[n] not in MOVABLE_JOINT_TYPES:
            raise UnknownJointError(
                f"joint '{n}' is {types[n]}, not movable (revolute or continuous), in '{name}' "
                f"(movable joints: {movable}); {_JOINTS_HINT}"
            )
    return joint_map


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


# ------------------------------------------------------------------ robot cache (per-part hulls and masses)
ROBOT_CACHE_VERSION = "1"


def robot_cache_dir() -> Path | None:
    """Where :meth:`Robot.from_urdf` keeps parsed robots: ``$LANDSCAPE_CACHE/robots`` or
    ``~/.cache/selfrighting-landscape/robots``; None (no cache) when ``LANDSCAPE_CACHE`` is ``off``."""
    env = os.environ.get("LANDSCAPE_CACHE")
    if env == "off":
        return None
    return (Path(env) if env else Path.home() / ".cache" / "selfrighting-landscape") / "robots"


def _payload_digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for key in sorted(arrays):
        if key == "payload_sha256":
            continue
        a = np.ascontiguousarray(arrays[key])
        h.update(f"{key}\0{a.dtype.str}\0{a.shape}\0".encode())
        h.update(a.tobytes())
    return h.hexdigest()


@cache
def installed_version(dist: str) -> str:
    """Version of an installed distribution from its ``*.dist-info`` directory name on ``sys.path`` (a directory
    listing, not ``importlib.metadata``'s scan, which costs tens of ms); "unknown" if none is found."""
    import sys

    prefix = dist.lower().replace("-", "_") + "-"
    for entry in sys.path:
        try:
            names = os.listdir(entry or ".")
        except OSError:
            continue
        for name in names:
            if name.endswith(".dist-info") and name.lower().startswith(prefix):
                return name[len(prefix) : -len(".dist-info")]
    return "unknown"


@lru_cache(maxsize=1)
def _code_key() -> str:
    """What a cached robot depends on besides its files: this reader's source and the versions of the libraries
    that load meshes and take hulls (12 hex digits of SHA-256), so a change to either misses old caches."""
    h = hashlib.sha256(f"v{ROBOT_CACHE_VERSION}".encode())
    for dist in ("trimesh", "yourdfpy", "scipy", "numpy"):
        h.update(f"\0{dist}={installed_version(dist)}".encode())
    for name in ("robot.py", "hull.py", "mass.py", "urdf.py"):
        h.update(f"\0{name}\0".encode() + (Path(__file__).parent / name).read_bytes())
    return h.hexdigest()[:12]


def _cache_path(cache_dir: Path, description_hash: str) -> Path:
    return Path(cache_dir) / f"robot-{description_hash}-{_code_key()}.npz"


def _save_cache(cache_dir: Path, robot: Robot, base_link: str) -> None:
    """Write the robot's parts and joints (atomically; a failure to write only logs)."""
    parts = robot.parts
    joints = robot.joints
    arrays = {
        "description_hash": np.array(robot.description_hash),
        "code_key": np.array(_code_key()),
        "name": np.array(robot.name),
        "base_link": np.array(base_link),
        "link": np.array([p.link for p in parts], dtype=str),
        "mass_kg": np.array([p.mass.mass_kg for p in parts], dtype=np.float64),
        "com_m": np.array([p.mass.com_m for p in parts], dtype=np.float64).reshape(-1, 3),
        "inertia_kg_m2": np.array([p.mass.inertia_kg_m2 for p in parts], dtype=np.float64).reshape(-1, 3, 3),
        "mass_model": np.array([p.mass.model for p in parts], dtype=str),
        "hull_ptr": np.cumsum([0] + [len(p.hull_link_m) for p in parts]).astype(np.int64),
        "hull_m": np.concatenate([p.hull_link_m.reshape(-1, 3) for p in parts]).astype(np.float64),
        "points_ptr": np.cumsum([0] + [len(p.points_link_m) for p in parts]).astype(np.int64),
        "points_m": np.concatenate([p.points_link_m.reshape(-1, 3) for p in parts]).astype(np.float64),
        "joint_text": np.array(
            [[j.name, j.type, j.parent, j.child, j.mimic] for j in joints], dtype=str
        ).reshape(-1, 5),
        "joint_origin": np.array([j.origin for j in joints], dtype=np.float64).reshape(-1, 4, 4),
        "joint_axis": np.array([j.axis for j in joints], dtype=np.float64).reshape(-1, 3),
        "joint_values": np.array(
            [[j.lower_rad, j.upper_rad, j.multiplier, j.offset] for j in joints], dtype=np.float64
        ).reshape(-1, 4),
    }
    arrays["payload_sha256"] = np.array(_payload_digest(arrays))
    path = _cache_path(cache_dir, robot.description_hash)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, path)
    except OSError as exc:
        log.info("robot cache not written (%s): %s", path, exc)
        tmp.unlink(missing_ok=True)


def _load_cache(cache_dir: Path, description_hash: str):
    """(name, base_link, parts, joints) from the cache if it holds this description, verified, else None."""
    path = _cache_path(cache_dir, description_hash)
    try:
        with np.load(path, allow_pickle=False) as z:
            a = {k: z[k] for k in z.files}
    except (OSError, ValueError, KeyError, EOFError) as exc:
        if path.exists():
            log.info("robot cache %s unreadable (%s); rebuilding", path, exc)
        return None
    try:
        ok = (
            str(a["description_hash"]) == description_hash
            and str(a["code_key"]) == _code_key()
            and str(a["payload_sha256"]) == _payload_digest(a)
        )
    except KeyError:
        ok = False
    if not ok:
        log.info("robot cache %s does not match its description or contents; rebuilding", path)
        return None
    parts = []
    for i, link in enumerate(a["link"]):
        h0, h1 = a["hull_ptr"][i], a["hull_ptr"][i + 1]
        p0, p1 = a["points_ptr"][i], a["points_ptr"][i + 1]
        mp = MassProperties(
            float(a["mass_kg"][i]),
            a["com_m"][i].copy(),
            a["inertia_kg_m2"][i].copy(),
            str(a["mass_model"][i]),
        )
        parts.append(Part(str(link), mp, a["hull_m"][h0:h1].copy(), a["points_m"][p0:p1].copy()))
    joints = tuple(
        JointSpec(
            str(t[0]),
            str(t[1]),
            str(t[2]),
            str(t[3]),
            o.copy(),
            ax.copy(),
            float(v[0]),
            float(v[1]),
            str(t[4]),
            float(v[2]),
            float(v[3]),
        )
        for t, o, ax, v in zip(
            a["joint_text"], a["joint_origin"], a["joint_axis"], a["joint_values"], strict=True
        )
    )
    return str(a["name"]), str(a["base_link"]), tuple(parts), joints


class Robot:
    """A robot: rigid parts joined by joints, with a map from (theta_w, theta_l) to joint values.

    Build one with :meth:`from_urdf` or :meth:`from_mesh`; call :meth:`pose` for the rigid body at given angles.
    """

    def __init__(
        self,
        name: str,
        parts: tuple[Part, ...],
        *,
        urdf: yourdfpy.URDF | None = None,
        joint_map: JointMap | None = None,
        source: Path | None = None,
        description_hash: str = "",
        urdf_file: UrdfFile | None = None,
        element_vertices: dict[tuple[str, str, int], NDArray[np.float64]] | None = None,
        joints: tuple[JointSpec, ...] | None = None,
        base_link: str | None = None,
    ):
        self.name = name
        self.parts = parts
        self._urdf = urdf
        self.joint_map = joint_map
        self.source = source
        self.description_hash = description_hash
        self.urdf_file = urdf_file
        self._element_vertices = element_vertices
        if joints is None and urdf is not None:
            joints = _joint_specs(urdf.robot)
        self.joints: tuple[JointSpec, ...] = joints or ()
        if base_link is None:
            base_link = urdf.base_link if urdf is not None else None
        self.base_link = base_link
        self._joint_by_name = {j.name: j for j in self.joints}
        self._part_by_link = {p.link: p for p in parts}
        self._chains = None

    @property
    def urdf(self) -> yourdfpy.URDF | None:
        """yourdfpy's model of the URDF (built on first use for a robot read from the cache; None for a mesh)."""
        if self._urdf is None and self.urdf_file is not None:
            self._urdf = _yourdfpy_model(_parse_structure(self.urdf_file), self.urdf_file.path)
        return self._urdf

    @property
    def element_vertices(self) -> dict[tuple[str, str, int], NDArray[np.float64]]:
        """Raw vertices of every mesh element, keyed by (link, kind, index), file units (read on first use)."""
        if self._element_vertices is None:
            out = {}
            if self.urdf_file is not None:
                for ref in self.urdf_file.meshes:
                    raw = _load_mesh_bytes(ref.data, ref.path, f"link '{ref.link}': ")
                    out[(ref.link, ref.kind, ref.index)] = np.asarray(raw.vertices, dtype=np.float64)
            self._element_vertices = out
        return self._element_vertices

    @property
    def robot_hash(self) -> str:
        """What identifies the robot *and how it moves*: ``description_hash`` when the joints are the default
        names or there are none, else 16 hex digits of SHA-256 over ``description_hash`` and the joint map's text.
        """
        if self.joint_map is None or self.joint_map == JointMap():
            return self.description_hash
        return hashlib.sha256(f"{self.description_hash}|{self.joint_map.text()}".encode()).hexdigest()[:16]

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_urdf(
        cls, path: str | Path, *, joint_map: JointMap | None = None, cache_dir: str | Path | None = None
    ) -> Robot:
        """Load a URDF: links' collision geometry (visual where a link has none) and ``<inertial>`` masses.

        The file is read by :func:`geometry.urdf.read_urdf` (strict XML; ``description_hash`` covers the URDF and
        every mesh file its geometry uses).

        With ``cache_dir`` (e.g. :func:`robot_cache_dir`), the parsed robot (each link's hull vertices, mesh
        points, mass properties and the joints) is kept there as ``robot-<description_hash>-<code key>.npz`` after
        a successful load, and a later load of the same description (the URDF and every mesh file hashed afresh)
        reads it instead of the meshes, without importing trimesh or yourdfpy. The code key covers this reader's
        source and the mesh and hull libraries' versions. The file is used only if it names this description hash
        and code key and its arrays' SHA-256 matches the one stored with them; otherwise the robot is rebuilt and
        the file rewritten (atomically).

        Raises
        ------
        RobotDescriptionError
            If the file is missing or malformed (line and column given), a mesh is missing or has a non-finite
            vertex, a link's mass, CoM or inertia is not finite or a mass is negative, the joints do not form a
            tree, or the robot has no mass or no geometry.
        UnknownJointError
            If a joint map names a joint the robot lacks or one that is not revolute/continuous, or, without a
            map, if only some of the default joint names are present. A robot with none of the default names and
            no map is rigid at its zero configuration.
        """
        uf = read_urdf(path)
        path = uf.path
        if cache_dir is not None:
            hit = _load_cache(Path(cache_dir), uf.description_hash)
            if hit is not None:
                name, base_link, parts, joints = hit
                return cls(
                    name,
                    parts,
                    joint_map=_checked_joint_map(joints, joint_map, path.name),
                    source=path,
                    description_hash=uf.description_hash,
                    urdf_file=uf,
                    joints=joints,
                    base_link=base_link,
                )
        robot = _parse_structure(uf)
        joint_map = _checked_joint_map(robot.joints, joint_map, path.name)
        urdf = _yourdfpy_model(robot, path)
        parts = []
        element_vertices: dict[tuple[str, str, int], NDArray[np.float64]] = {}
        for link in urdf.robot.links:
            kind = "collision" if link.collisions else "visual"
            meshes = []
            for i, g in enumerate(link.collisions or link.visuals):
                ref = uf.mesh(link.name, kind, i) if g.geometry.mesh is not None else None
                if ref is not None:
                    raw = _load_mesh_bytes(ref.data, ref.path, f"link '{link.name}': ")
                    element_vertices[(link.name, kind, i)] = np.asarray(raw.vertices, dtype=np.float64)
                m = _geometry_mesh(g.geometry, ref, link.name)
                if m is not None:
                    if g.origin is not None:
                        m.apply_transform(g.origin)
                    meshes.append(m)
            points = (
                np.concatenate([np.asarray(m.vertices, float) for m in meshes])
                if meshes
                else np.zeros((0, 3))
            )
            hull = convex_hull(points).vertices_m if len(points) else np.zeros((0, 3))
            parts.append(Part(link.name, _link_mass(link, path.name), hull, points))
        if not sum(p.mass.mass_kg for p in parts) > 0:
            raise RobotDescriptionError(
                f"'{path}' gives no link a mass; add <inertial><mass .../></inertial>"
            )
        if not any(len(p.hull_link_m) for p in parts):
            raise RobotDescriptionError(f"'{path}' has no geometry; add <collision> or <visual> elements")
        out = cls(
            urdf.robot.name or path.stem,
            tuple(parts),
            urdf=urdf,
            joint_map=joint_map,
            source=path,
            description_hash=uf.description_hash,
            urdf_file=uf,
            element_vertices=element_vertices,
        )
        if cache_dir is not None:
            _save_cache(Path(cache_dir), out, urdf.base_link)
        return out

    @classmethod
    def from_mesh(
        cls,
        path: str | Path,
        *,
        mass_kg: float = 1.0,
        com: ArrayLike | None = None,
        units: str = "m",
        com_model: str = "auto",
    ) -> Robot:
        """A single rigid body from any mesh file trimesh reads.

        Parameters
        ----------
        path : path
            Mesh file.
        mass_kg : float
            Mass, kg.
        com : array_like of shape (3,), optional
            CoM in the mesh's own units; default: computed (solid if the mesh is closed, else thin shell).
        units : {"mm", "cm", "m"}
            Units of the mesh file.
        com_model : {"auto", "solid", "shell"}
            How to compute the CoM when ``com`` is not given.
        """
        path = Path(path)
        if units not in UNITS_M:
            raise GeometryError(f"units must be one of {', '.join(UNITS_M)}; got {units!r}")
        if not path.is_file():
            raise RobotDescriptionError(f"mesh file '{path}' not found; check the path")
        data = path.read_bytes()
        mesh = _load_mesh_bytes(data, path)  # raw vertices checked before trimesh's processing drops any
        mesh.process()
        return cls.from_trimesh(
            mesh,
            mass_kg=mass_kg,
            com=com,
            units=units,
            com_model=com_model,
            name=path.stem,
            source=path,
            file_bytes=data,
        )

    @classmethod
    def from_trimesh(
        cls,
        mesh: trimesh.Trimesh,
        *,
        mass_kg: float = 1.0,
        com: ArrayLike | None = None,
        units: str = "m",
        com_model: str = "auto",
        name: str = "mesh",
        source: Path | None = None,
        file_bytes: bytes | None = None,
    ) -> Robot:
        """A single rigid body from a trimesh object (see :meth:`from_mesh`).

        ``description_hash`` covers the mesh (``file_bytes``, the file's contents, when given; else its vertex and
        face arrays), ``units``, ``mass_kg``, ``com`` and ``com_model``: everything that changes the body.
        """
        verts = np.asarray(mesh.vertices, dtype=np.float64)
        if not np.isfinite(verts).all():
            i = int(np.flatnonzero(~np.isfinite(verts).all(axis=1))[0])
            raise GeometryError(f"{name}: vertex {i} is not finite ({verts[i].tolist()}); fix the mesh")
        scale = UNITS_M[units]
        mesh = mesh.copy()
        mesh.apply_scale(scale)
        if com is not None:
            c = np.asarray(com, dtype=np.float64).reshape(-1)
            if c.shape != (3,) or not np.isfinite(c).all():
                raise GeometryError(f"com must be three finite numbers X,Y,Z; got {np.asarray(com).tolist()}")
            if not (np.isfinite(mass_kg) and mass_kg > 0):
                raise GeometryError(f"mass must be a positive number of kg; got {mass_kg!r}")
            mp = MassProperties(float(mass_kg), c * scale, np.zeros((3, 3)), "given")
        else:
            from .mass import mesh_mass_properties

            mp = mesh_mass_properties(mesh, mass_kg=mass_kg, com_model=com_model, name=name)
        pts = np.asarray(mesh.vertices, dtype=np.float64)
        part = Part(name, mp, convex_hull(pts).vertices_m, pts)
        h = hashlib.sha256()
        if file_bytes is not None:
            h.update(b"file\0" + file_bytes)
        else:
            h.update(b"arrays\0" + verts.tobytes() + np.asarray(mesh.faces, dtype=np.int64).tobytes())
        com_text = (
            "auto" if com is None else ",".join(repr(float(x)) for x in np.asarray(com, float).reshape(-1))
        )
        h.update(
            f"\0units={units}\0mass_kg={float(mass_kg)!r}\0com={com_text}\0com_model={com_model}".encode()
        )
        return cls(name, (part,), source=source, description_hash=h.hexdigest()[:16])

    # ------------------------------------------------------------------ joints
    @property
    def has_joints(self) -> bool:
        return bool(self.joints) and self.joint_map is not None

    @property
    def movable_joints(self) -> tuple[str, ...]:
        """Names of the joints a joint map may drive (revolute or continuous, not mimics), in URDF order."""
        return tuple(j.name for j in self.joints if j.type in MOVABLE_JOINT_TYPES and not j.mimic)

    def drives(self, angle: str) -> bool:
        """Whether some joint of this robot is driven by ``angle``, ``"theta_w"`` or ``"theta_l"``.

        Examples
        --------
        >>> from geometry.robots import load_robot
        >>> r = load_robot()
        >>> r.drives("theta_w"), r.drives("theta_l")
        (True, True)
        """
        if angle not in _GROUPS:
            raise ValueError(f"angle must be one of {', '.join(_GROUPS)}; got {angle!r}")
        return self.has_joints and bool(getattr(self.joint_map, _GROUPS[angle]))

    def undriven(
        self, angle: str, *, option: str, joints_option: str = "--joints", drop: bool = True
    ) -> UnknownJointError:
        """The error for a value of ``angle`` (``"theta_w"`` or ``"theta_l"``) that no joint of this robot
        takes: it names the robot's movable joints and the joint map that would drive them.

        ``option`` and ``joints_option`` name the angle and the joint map where the value came in: the command
        line's ``--theta-w`` and ``--joints``, or Python's ``theta_w_deg`` and ``joints=``. ``drop``: also offer
        to drop the angle (not where sweeping it is the point, as in a barrier map).

        Examples
        --------
        >>> import trimesh
        >>> box = Robot.from_trimesh(trimesh.creation.box(extents=(0.2, 0.1, 0.05)), name="box")
        >>> str(box.undriven("theta_w", option="--theta-w"))
        'box is a single rigid body without joints: nothing takes --theta-w; drop it'
        """
        what = {"theta_w": "the wing angle", "theta_l": "the leg angle"}[angle]
        movable = self.movable_joints
        drop_it = "; drop it" if drop else ""
        if not movable:
            return UnknownJointError(
                f"{self.name} is a single rigid body without joints: nothing takes {option}{drop_it}"
                if not self.joints
                else f"{self.name} has no movable joint (revolute or continuous): nothing takes {option}{drop_it}"
            )
        sep = "" if joints_option.endswith("=") else " "
        current = self.joint_map if self.has_joints else None
        mapped = "no joint map" if current is None else f"joint map '{current.text()}'"
        if current is not None and set(movable) <= {*current.wing, *current.leg}:
            return UnknownJointError(
                f"{option}: no joint of {self.name} is driven by {what} ({mapped}; every movable joint is "
                f"mapped)" + (f"; drop {option}" if drop else "")
            )
        return UnknownJointError(
            f"{option}: no joint of {self.name} is driven by {what} ({mapped}; movable joints: "
            f"{', '.join(movable)}); map them with {joints_option}{sep}'{self._map_example(angle)}' (each group "
            f"holding the joints its angle drives)" + (f", or drop {option}" if drop else "")
        )

    def _map_example(self, angle: str) -> str:
        """A joint map for :meth:`undriven`: the mapped joints where they are; of the others, a name with "leg"
        or "tail" in it in the leg group, with "wing" in it in the wing group, the rest in the group no name
        chose (the group of ``angle`` when neither or both were chosen)."""
        groups = {"wing": [], "leg": []}
        if self.has_joints:
            groups["wing"] += self.joint_map.wing
            groups["leg"] += self.joint_map.leg
        taken = set(groups["wing"]) | set(groups["leg"])
        rest = []
        for n in self.movable_joints:
            low = n.lower()
            if n in taken:
                continue
            if "leg" in low or "tail" in low:
                groups["leg"].append(n)
            elif "wing" in low:
                groups["wing"].append(n)
            else:
                rest.append(n)
        empty = [k for k, v in groups.items() if not v]
        groups[empty[0] if len(empty) == 1 else _GROUPS[angle]] += rest
        return ";".join(f"{k}={','.join(v)}" for k, v in groups.items() if v)

    def joint_limits_deg(self, joint: str) -> tuple[float, float]:
        """Lower and upper limit of a joint, degrees (+-inf where the URDF sets none)."""
        j = self._joint_by_name[joint]
        if j.type == "continuous" or (np.isnan(j.lower_rad) and np.isnan(j.upper_rad)):
            return -np.inf, np.inf
        lo = -np.inf if np.isnan(j.lower_rad) else np.rad2deg(j.lower_rad)
        hi = np.inf if np.isnan(j.upper_rad) else np.rad2deg(j.upper_rad)
        return float(lo), float(hi)

    def theta_limits_deg(self) -> dict[str, tuple[float, float]]:
        """The range of theta_w and theta_l that every mapped joint allows, degrees ((0, 0) for an angle that
        no joint takes: it stays 0)."""
        out = {}
        wing, leg = (self.joint_map.wing, self.joint_map.leg) if self.has_joints else ((), ())
        for key, names in (("theta_w", wing), ("theta_l", leg)):
            if not names:
                out[key] = (0.0, 0.0)
                continue
            lims = [self.joint_limits_deg(n) for n in names]
            out[key] = (max(lo for lo, _ in lims), min(hi for _, hi in lims))
        return out

    def joint_values_rad(self, theta_w_deg: float | None, theta_l_deg: float | None) -> dict[str, float]:
        """Joint values for (theta_w, theta_l), radians, after checking the joint limits. An angle that no
        joint takes (a group the joint map leaves out) must be None or 0.

        Raises
        ------
        JointLimitError
            If an angle is not finite or lies outside a mapped joint's limits.
        UnknownJointError
            If an angle other than None or 0 is given that no joint takes.
        """
        values = {}
        wing, leg = (self.joint_map.wing, self.joint_map.leg) if self.has_joints else ((), ())
        for what, val, names in (("theta_w", theta_w_deg, wing), ("theta_l", theta_l_deg, leg)):
            if not names:
                if val is not None and val != 0:
                    raise self.undriven(what, option=f"{what}_deg", joints_option="joints=")
                continue
            if val is None or not np.isfinite(val):
                raise JointLimitError(f"{what}_deg must be a finite angle in degrees; got {val!r}")
            for n in names:
                lo, hi = self.joint_limits_deg(n)
                if not lo - 1e-9 <= val <= hi + 1e-9:
                    raise JointLimitError(
                        JOINT_OUT_OF_RANGE.format(what=what, got=val, joint=n, lo=lo, hi=hi)
                    )
                values[n] = float(np.deg2rad(val))
        return values

    # ------------------------------------------------------------------ posing
    def kinematic_chains(self) -> dict[str, tuple[JointSpec, ...]]:
        """Per part's link, the joints from the base link down to it (base first); computed once."""
        if self._chains is None:
            by_child = {j.child: j for j in self.joints}
            chains = {}
            for p in self.parts:
                chain, link = [], p.link
                while link in by_child:
                    chain.append(by_child[link])
                    link = by_child[link].parent
                chains[p.link] = tuple(chain[::-1])
            self._chains = chains
        return self._chains

    def link_transforms(self, joint_values_rad: dict[str, float]) -> dict[str, NDArray[np.float64]]:
        """Link-to-body transforms for joint values (radians); unmentioned joints stay at 0.

        Each link's transform is the product of its chain's ``origin @ motion(q)`` from the base link, with
        yourdfpy's rules: a mimic joint takes ``multiplier * q + offset`` of the joint it mimics when that joint is
        set by the configuration, else ``offset``.
        """
        if not self.joints:
            return {p.link: np.eye(4) for p in self.parts}
        actuated = {j.name for j in self.joints if j.actuated}

        def value(j: JointSpec) -> float:
            if j.mimic:
                q = float(joint_values_rad.get(j.mimic, 0.0)) if j.mimic in actuated else 0.0
                return q * j.multiplier + j.offset if j.mimic in actuated else j.offset
            return float(joint_values_rad.get(j.name, 0.0))

        out = {}
        for link, chain in self.kinematic_chains().items():
            out[link] = _chain_product(
                [
                    j.origin @ joint_motion(j.type, j.axis, value(j))
                    if j.type in MOVABLE_JOINT_TYPES or j.type == "prismatic"
                    else j.origin
                    for j in chain
                ]
            )
        return out

    def pose(self, theta_w_deg: float | None = 0.0, theta_l_deg: float | None = 0.0) -> Pose:
        """The rigid body at wing angle theta_w and leg angle theta_l (degrees).

        For a single rigid mesh the angles are ignored and reported as None; so is an angle no joint takes (a
        group the joint map leaves out), which must then be None or 0.

        Raises
        ------
        JointLimitError
            If an angle is not finite or outside the joint limits.
        UnknownJointError
            If an angle other than None or 0 is given that no joint takes.
        """
        if not self.has_joints:
            T = self.link_transforms({})
            theta_w_deg = theta_l_deg = None
        else:
            tw = None if theta_w_deg is None else float(theta_w_deg)
            tl = None if theta_l_deg is None else float(theta_l_deg)
            T = self.link_transforms(self.joint_values_rad(tw, tl))
            theta_w_deg = tw if self.joint_map.wing else None
            theta_l_deg = tl if self.joint_map.leg else None
        return self._pose_from(T, theta_w_deg, theta_l_deg)

    def pose_joints(self, joint_values_deg: dict[str, float]) -> Pose:
        """The rigid body with each named joint at its own angle (degrees; unnamed joints at 0), e.g. the four
        wing servos at their measured plateaus. ``theta_w_deg``/``theta_l_deg`` of the pose are None.

        Raises
        ------
        UnknownJointError
            If a name is not one of the robot's movable joints.
        JointLimitError
            If an angle is not finite or outside its joint's limits.
        """
        movable = {j.name for j in self.joints if j.actuated}
        values = {}
        for name, val in joint_values_deg.items():
            if name not in movable:
                raise UnknownJointError(
                    f"joint {name!r} is not a movable joint of {self.name}; its movable joints are "
                    f"{', '.join(sorted(movable)) or 'none'}"
                )
            lo, hi = self.joint_limits_deg(name)
            if not np.isfinite(val) or not lo - 1e-9 <= val <= hi + 1e-9:
                raise JointLimitError(JOINT_OUT_OF_RANGE.format(what=name, got=val, joint=name, lo=lo, hi=hi))
            values[name] = float(np.deg2rad(val))
        return self._pose_from(self.link_transforms(values), None, None)

    def _pose_from(self, T: dict, theta_w_deg, theta_l_deg) -> Pose:
        total = combine(_posed_masses(T, self.parts))
        hull_pts = np.concatenate(
            [_apply(T[p.link], p.hull_link_m) for p in self.parts if len(p.hull_link_m)]
        )
        return Pose(theta_w_deg, theta_l_deg, total.mass_kg, total.com_m, hull_pts, T, self.parts)

    @property
    def com_source(self) -> str:
        """How the CoM was obtained: "urdf <inertial>", "solid volume centroid", "thin-shell area centroid" or
        "given"."""
        if self.urdf_file is not None:
            return "urdf <inertial>"
        model = self.parts[0].mass.model
        return {"solid": "solid volume centroid", "shell": "thin-shell area centroid"}.get(model, "given")

    @cached_property
    def total_mass_kg(self) -> float:
        return float(sum(p.mass.mass_kg for p in self.parts))

    def with_com_offset(self, offset_m: ArrayLike) -> Robot:
        """The same robot with its whole-body CoM moved by ``offset_m`` (body frame, m) at every pose: the base
        link's CoM moves by ``offset_m * M / m_base`` (M the total mass); masses, inertias about each CoM,
        geometry and joints stay. It stands for mass the description lacks or misplaces (cables, glue, a tether).
        ``description_hash`` (so ``robot_hash`` and every cache key) folds the offset in.

        Raises
        ------
        UsageError
            If the offset is not three finite numbers, or the base link has no mass to move.
        """
        d = np.asarray(offset_m, dtype=np.float64)
        if d.shape != (3,) or not np.all(np.isfinite(d)):
            raise UsageError(f"a CoM offset must be three finite numbers (m); got {offset_m!r}")
        if not np.any(d):
            return self
        base = self._part_by_link.get(self.base_link, self.parts[0])
        if base.mass.mass_kg <= 0:
            raise UsageError(
                f"{self.name}: its base link '{base.link}' has no mass, so there is none to move for a CoM offset"
            )
        moved = MassProperties(
            base.mass.mass_kg,
            base.mass.com_m + d * self.total_mass_kg / base.mass.mass_kg,
            base.mass.inertia_kg_m2,
            base.mass.model,
        )
        parts = tuple(
            Part(p.link, moved, p.hull_link_m, p.points_link_m) if p is base else p for p in self.parts
        )
        key = ",".join(f"{v:.17g}" for v in d)
        digest = hashlib.sha256(f"{self.description_hash}|com_offset_m={key}".encode()).hexdigest()[:16]
        return self._variant(parts, self.joints, digest)

    def with_joint_shift(self, joint: str, offset_m: ArrayLike) -> Robot:
        """The same robot with one joint's origin moved by ``offset_m`` (m, in its parent link's frame): the
        joint's child link and everything it carries move with it, geometry and mass alike. It stands for a part
        the description places where the real one does not touch the ground, e.g. the lab robot's head
        (``head_mount``; docs/physical/resting-pose.md). ``description_hash`` folds the shift in.

        Raises
        ------
        UnknownJointError
            If the robot has no joint of that name.
        UsageError
            If the offset is not three finite numbers.

        Examples
        --------
        >>> from geometry.robots import load_robot
        >>> robot = load_robot(None)
        >>> moved = robot.with_joint_shift("head_mount", [-0.01, 0.0, 0.0])
        >>> float(robot.pose(0, 0).com_m[0] - moved.pose(0, 0).com_m[0]) > 0, moved.robot_hash != robot.robot_hash
        (True, True)
        """
        d = np.asarray(offset_m, dtype=np.float64)
        if d.shape != (3,) or not np.all(np.isfinite(d)):
            raise UsageError(f"a joint shift must be three finite numbers (m); got {offset_m!r}")
        if joint not in self._joint_by_name:
            names = ", ".join(sorted(self._joint_by_name)) or "none"
            raise UnknownJointError(f"{self.name} has no joint {joint!r} to shift; its joints are {names}")
        if not np.any(d):
            return self
        joints = []
        for j in self.joints:
            if j.name == joint:
                origin = j.origin.copy()
                origin[:3, 3] += d
                j = replace(j, origin=origin)
            joints.append(j)
        key = ",".join(f"{v:.17g}" for v in d)
        digest = hashlib.sha256(f"{self.description_hash}|shift {joint}={key}".encode()).hexdigest()[:16]
        return self._variant(self.parts, tuple(joints), digest)

    def _variant(
        self, parts: tuple[Part, ...], joints: tuple[JointSpec, ...], description_hash: str
    ) -> Robot:
        """This robot with other parts or joints (a CoM offset, a joint shift) under a new description hash. The
        yourdfpy model stays the file's."""
        return Robot(
            self.name,
            parts,
            urdf=self._urdf,
            joint_map=self.joint_map,
            source=self.source,
            description_hash=description_hash,
            urdf_file=self.urdf_file,
            element_vertices=self._element_vertices,
            joints=joints,
            base_link=self.base_link,
        )
