"""Robot descriptions: URDF (via yourdfpy) or a single rigid mesh, posed at (theta_w, theta_l).

The body frame is the URDF's base link. A pose puts every link where the joints say, then keeps only what the
landscape needs: the total mass, the mass-weighted CoM and the convex hull of all geometry.
"""

from __future__ import annotations

import hashlib
import logging
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np
import trimesh
import yourdfpy
from numpy.typing import ArrayLike, NDArray

from .errors import (
    JOINT_OUT_OF_RANGE,
    GeometryError,
    JointLimitError,
    RobotDescriptionError,
    UnknownJointError,
)
from .hull import Hull, convex_hull
from .mass import MassProperties, combine, mesh_mass_properties

log = logging.getLogger(__name__)

UNITS_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}


@dataclass(frozen=True)
class JointMap:
    """Which joints the wing angle theta_w and the leg angle theta_l drive.

    Every joint in ``wing`` is set to theta_w (each wing's pitch and roll joints), every joint in ``leg`` to
    theta_l. The default names are those of the lab robot's URDF. A robot whose joints are named otherwise
    declares its own map: ``JointMap.parse("wing=a,b,c,d;leg=e")`` in Python, ``--joints "wing=a,b,c,d;leg=e"``
    on the command line.

    Examples
    --------
    >>> JointMap.parse("wing=wl,wr;leg=tail").leg
    ('tail',)
    """

    wing: tuple[str, ...] = ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right")
    leg: tuple[str, ...] = ("leg",)

    @classmethod
    def parse(cls, text: str) -> JointMap:
        groups: dict[str, tuple[str, ...]] = {}
        for item in filter(None, (s.strip() for s in text.split(";"))):
            key, sep, names = item.partition("=")
            key = key.strip()
            if not sep or key not in ("wing", "leg"):
                raise GeometryError(
                    f"joint map entry {item!r} is not 'wing=NAME,...' or 'leg=NAME,...'; e.g. 'wing=a,b,c,d;leg=e'"
                )
            groups[key] = tuple(n.strip() for n in names.split(",") if n.strip())
        return cls(**groups)


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

    def all_points_m(self) -> NDArray[np.float64]:
        """Every mesh vertex of every part in the body frame, m (the lab's brute-force input)."""
        out = [_apply(self.link_transforms[p.link], p.points_link_m) for p in self.parts if len(p.points_link_m)]
        return np.concatenate(out) if out else np.zeros((0, 3))


def _apply(T: NDArray[np.float64], pts: NDArray[np.float64]) -> NDArray[np.float64]:
    return pts @ T[:3, :3].T + T[:3, 3]


def _geometry_mesh(geom: yourdfpy.Geometry, urdf_dir: Path, link: str) -> trimesh.Trimesh | None:
    if geom.mesh is not None:
        path = Path(yourdfpy.filename_handler_magic(geom.mesh.filename, dir=str(urdf_dir)))
        if not path.is_file():
            raise RobotDescriptionError(
                f"link '{link}': mesh file '{geom.mesh.filename}' not found (looked for {path}); "
                "put it next to the URDF or fix the filename"
            )
        try:
            mesh = trimesh.load(str(path), force="mesh", process=False)
        except Exception as exc:  # trimesh raises many types for unreadable files
            raise RobotDescriptionError(f"link '{link}': cannot read mesh '{path}': {exc}") from None
        scale = np.ones(3) if geom.mesh.scale is None else np.broadcast_to(np.asarray(geom.mesh.scale, float), 3)
        mesh.apply_scale(scale) if np.allclose(scale, scale[0]) else mesh.apply_transform(np.diag([*scale, 1.0]))
        return mesh
    if geom.box is not None:
        return trimesh.creation.box(extents=np.asarray(geom.box.size, float))
    if geom.cylinder is not None:
        return trimesh.creation.cylinder(radius=geom.cylinder.radius, height=geom.cylinder.length, sections=64)
    if geom.sphere is not None:
        return trimesh.creation.icosphere(subdivisions=3, radius=geom.sphere.radius)
    return None


class Robot:
    """A robot: rigid parts joined by joints, with a map from (theta_w, theta_l) to joint values.

    Build one with :meth:`from_urdf` or :meth:`from_mesh`; call :meth:`pose` for the rigid body at given angles.
    """

    def __init__(self, name: str, parts: tuple[Part, ...], *, urdf: yourdfpy.URDF | None = None,
                 joint_map: JointMap | None = None, source: Path | None = None, description_hash: str = ""):
        self.name = name
        self.parts = parts
        self.urdf = urdf
        self.joint_map = joint_map
        self.source = source
        self.description_hash = description_hash
        self._part_by_link = {p.link: p for p in parts}

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_urdf(cls, path: str | Path, *, joint_map: JointMap | None = None) -> Robot:
        """Load a URDF: links' collision geometry (visual where a link has none) and ``<inertial>`` masses.

        Raises
        ------
        RobotDescriptionError
            If the file is missing or unreadable, a mesh is missing, or the robot has no mass.
        UnknownJointError
            If an explicit joint map names a joint the robot lacks. Without a map, the lab robot's joint names
            are used when all are present; otherwise the robot is rigid at its zero configuration.
        """
        path = Path(path)
        if not path.is_file():
            raise RobotDescriptionError(f"robot file '{path}' not found; give the path to a .urdf file")
        try:
            urdf = yourdfpy.URDF.load(str(path), load_meshes=False, build_scene_graph=True,
                                      build_collision_scene_graph=False)
        except Exception as exc:
            raise RobotDescriptionError(f"cannot parse '{path}' as URDF: {str(exc).splitlines()[0]}") from None
        explicit = joint_map is not None
        joint_map = joint_map or JointMap()
        missing = [n for n in (*joint_map.wing, *joint_map.leg) if n not in urdf.joint_map]
        if missing and explicit:
            movable = ", ".join(urdf.actuated_joint_names) or "none"
            raise UnknownJointError(
                f"joint '{missing[0]}' is not in '{path.name}' (movable joints: {movable}); "
                "declare the mapping with --joints 'wing=NAME,...;leg=NAME'"
            )
        if missing:  # no theta joints under the default names: a rigid robot at its zero configuration
            log.info("%s: default joints %s absent; treating the robot as rigid", path.name, missing)
            joint_map = None
        parts = []
        for link in urdf.robot.links:
            geoms = link.collisions or link.visuals
            meshes = []
            for g in geoms:
                m = _geometry_mesh(g.geometry, path.parent, link.name)
                if m is not None:
                    if g.origin is not None:
                        m.apply_transform(g.origin)
                    meshes.append(m)
            points = np.concatenate([np.asarray(m.vertices, float) for m in meshes]) if meshes else np.zeros((0, 3))
            hull = convex_hull(points).vertices_m if len(points) else np.zeros((0, 3))
            if link.inertial is not None and link.inertial.mass:
                T = np.eye(4) if link.inertial.origin is None else link.inertial.origin
                inertia = np.zeros((3, 3)) if link.inertial.inertia is None else np.asarray(link.inertial.inertia)
                mp = MassProperties(float(link.inertial.mass), T[:3, 3].copy(),
                                    T[:3, :3] @ inertia @ T[:3, :3].T, "given")
            else:
                mp = MassProperties(0.0, np.zeros(3), np.zeros((3, 3)), "given")
            parts.append(Part(link.name, mp, hull, points))
        if not sum(p.mass.mass_kg for p in parts) > 0:
            raise RobotDescriptionError(f"'{path}' gives no link a mass; add <inertial><mass .../></inertial>")
        if not any(len(p.hull_link_m) for p in parts):
            raise RobotDescriptionError(f"'{path}' has no geometry; add <collision> or <visual> elements")
        digest = hashlib.sha256(path.read_bytes()).hexdigest()[:16]
        return cls(urdf.robot.name or path.stem, tuple(parts), urdf=urdf, joint_map=joint_map, source=path,
                   description_hash=digest)

    @classmethod
    def from_mesh(cls, path: str | Path, *, mass_kg: float = 1.0, com: ArrayLike | None = None,
                  units: str = "m", com_model: str = "auto") -> Robot:
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
        try:
            mesh = trimesh.load(str(path), force="mesh")
        except Exception as exc:
            raise RobotDescriptionError(f"cannot read mesh '{path}': {exc}") from None
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.vertices) == 0:
            raise RobotDescriptionError(f"'{path}' holds no triangle mesh; give a mesh file (STL, OBJ, PLY, ...)")
        return cls.from_trimesh(mesh, mass_kg=mass_kg, com=com, units=units, com_model=com_model,
                                name=path.stem, source=path)

    @classmethod
    def from_trimesh(cls, mesh: trimesh.Trimesh, *, mass_kg: float = 1.0, com: ArrayLike | None = None,
                     units: str = "m", com_model: str = "auto", name: str = "mesh",
                     source: Path | None = None) -> Robot:
        """A single rigid body from a trimesh object (see :meth:`from_mesh`)."""
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
            mp = mesh_mass_properties(mesh, mass_kg=mass_kg, com_model=com_model, name=name)
        pts = np.asarray(mesh.vertices, dtype=np.float64)
        part = Part(name, mp, convex_hull(pts).vertices_m, pts)
        digest = hashlib.sha256(pts.tobytes() + mp.com_m.tobytes()).hexdigest()[:16]
        return cls(name, (part,), source=source, description_hash=digest)

    # ------------------------------------------------------------------ joints
    @property
    def has_joints(self) -> bool:
        return self.urdf is not None and self.joint_map is not None

    def joint_limits_deg(self, joint: str) -> tuple[float, float]:
        """Lower and upper limit of a joint, degrees (+-inf where the URDF sets none)."""
        j = self.urdf.joint_map[joint]
        if j.type == "continuous" or j.limit is None or (j.limit.lower is None and j.limit.upper is None):
            return -np.inf, np.inf
        lo = -np.inf if j.limit.lower is None else np.rad2deg(j.limit.lower)
        hi = np.inf if j.limit.upper is None else np.rad2deg(j.limit.upper)
        return float(lo), float(hi)

    def theta_limits_deg(self) -> dict[str, tuple[float, float]]:
        """The range of theta_w and theta_l that every mapped joint allows, degrees."""
        out = {}
        for key, names in (("theta_w", self.joint_map.wing), ("theta_l", self.joint_map.leg)):
            lims = [self.joint_limits_deg(n) for n in names]
            out[key] = (max((lo for lo, _ in lims), default=-np.inf), min((hi for _, hi in lims), default=np.inf))
        return out

    def joint_values_rad(self, theta_w_deg: float, theta_l_deg: float) -> dict[str, float]:
        """Joint values for (theta_w, theta_l), radians, after checking the joint limits.

        Raises
        ------
        JointLimitError
            If an angle is not finite or lies outside a mapped joint's limits.
        """
        values = {}
        for what, val, names in (("theta_w", theta_w_deg, self.joint_map.wing),
                                 ("theta_l", theta_l_deg, self.joint_map.leg)):
            if not np.isfinite(val):
                raise JointLimitError(f"{what} must be a finite angle in degrees; got {val!r}")
            for n in names:
                lo, hi = self.joint_limits_deg(n)
                if not lo - 1e-9 <= val <= hi + 1e-9:
                    raise JointLimitError(JOINT_OUT_OF_RANGE.format(what=what, got=val, joint=n, lo=lo, hi=hi))
                values[n] = float(np.deg2rad(val))
        return values

    # ------------------------------------------------------------------ posing
    def link_transforms(self, joint_values_rad: dict[str, float]) -> dict[str, NDArray[np.float64]]:
        """Link-to-body transforms for joint values (radians); unmentioned joints stay at 0."""
        if self.urdf is None:
            return {p.link: np.eye(4) for p in self.parts}
        cfg = np.zeros(len(self.urdf.actuated_joint_names))
        for i, n in enumerate(self.urdf.actuated_joint_names):
            cfg[i] = joint_values_rad.get(n, 0.0)
        self.urdf.update_cfg(cfg)
        base = self.urdf.base_link
        return {p.link: np.asarray(self.urdf.get_transform(p.link, base), dtype=np.float64) for p in self.parts}

    def pose(self, theta_w_deg: float | None = 0.0, theta_l_deg: float | None = 0.0) -> Pose:
        """The rigid body at wing angle theta_w and leg angle theta_l (degrees).

        For a single rigid mesh the angles are ignored and reported as None.

        Raises
        ------
        JointLimitError
            If an angle is not finite or outside the joint limits.
        """
        if not self.has_joints:
            T = self.link_transforms({})
            theta_w_deg = theta_l_deg = None
        else:
            T = self.link_transforms(self.joint_values_rad(float(theta_w_deg), float(theta_l_deg)))
        masses = [MassProperties(p.mass.mass_kg, _apply(T[p.link], p.mass.com_m[None])[0],
                                 T[p.link][:3, :3] @ p.mass.inertia_kg_m2 @ T[p.link][:3, :3].T, p.mass.model)
                  for p in self.parts if p.mass.mass_kg > 0]
        total = combine(masses)
        hull_pts = np.concatenate([_apply(T[p.link], p.hull_link_m) for p in self.parts if len(p.hull_link_m)])
        return Pose(theta_w_deg, theta_l_deg, total.mass_kg, total.com_m, hull_pts, T, self.parts)

    @property
    def com_source(self) -> str:
        """How the CoM was obtained: "urdf <inertial>", "solid volume centroid", "thin-shell area centroid" or
        "given"."""
        if self.urdf is not None:
            return "urdf <inertial>"
        model = self.parts[0].mass.model
        return {"solid": "solid volume centroid", "shell": "thin-shell area centroid"}.get(model, "given")

    @cached_property
    def total_mass_kg(self) -> float:
        return float(sum(p.mass.mass_kg for p in self.parts))
