"""Robots: a URDF (via yourdfpy) or a single rigid mesh, posed at (theta_w, theta_l).

The body frame is the URDF's base link. A pose puts every link where the joints say, then keeps only what the
landscape needs: the total mass, the mass-weighted CoM and the convex hull of all geometry.

This module holds one concept, :class:`Robot` (its construction from files, its joints and their limits, posing,
and its variants), which is why it runs past 600 lines. What it is built from lives beside it: the value types
in :mod:`geometry.pose` and :mod:`geometry.joint_map`, URDF to kinematics in :mod:`geometry.kinematics`, mesh
reading in :mod:`geometry.meshes` and the per-user disk cache in :mod:`geometry.cache`. The names that lived here
before the split (``JointMap``, ``Part``, ``Pose``, ``JointSpec``, ``joint_motion``, ``robot_cache_dir``, ...)
are still importable from here.
"""

from __future__ import annotations

import hashlib
from dataclasses import replace
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .cache import ROBOT_CACHE_VERSION as ROBOT_CACHE_VERSION
from .cache import _load_cache, _save_cache
from .cache import installed_version as installed_version
from .cache import robot_cache_dir as robot_cache_dir
from .errors import (
    JOINT_OUT_OF_RANGE,
    GeometryError,
    JointLimitError,
    RobotDescriptionError,
    UnknownJointError,
    UsageError,
)
from .hull import convex_hull
from .joint_map import _GROUPS, _checked_joint_map
from .joint_map import JointMap as JointMap
from .kinematics import JOINT_TYPES as JOINT_TYPES
from .kinematics import MOVABLE_JOINT_TYPES as MOVABLE_JOINT_TYPES
from .kinematics import JointSpec as JointSpec
from .kinematics import _chain_product, _joint_specs, _link_mass, _parse_structure, _yourdfpy_model
from .kinematics import joint_motion as joint_motion
from .mass import MassProperties, combine
from .meshes import _geometry_mesh, _load_mesh_bytes
from .pose import Part as Part
from .pose import Pose as Pose
from .pose import _apply, _posed_masses
from .urdf import UrdfFile, read_urdf

if TYPE_CHECKING:  # trimesh and yourdfpy load only where meshes are read (not for a cached robot)
    import trimesh
    import yourdfpy

UNITS_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}


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

        With ``cache_dir`` (e.g. :func:`geometry.cache.robot_cache_dir`), the parsed robot (each link's hull vertices, mesh
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
            _save_cache(
                Path(cache_dir),
                name=out.name,
                description_hash=out.description_hash,
                base_link=urdf.base_link,
                parts=out.parts,
                joints=out.joints,
            )
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
