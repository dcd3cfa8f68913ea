"""The pybullet world of one trial: a DIRECT client, a flat ground plane and the robot (the only module that
owns a pybullet client; :mod:`sim.trial` drives it).

Physics settings (measured in ``benchmarks/sim_convergence.py``; see ``docs/sim.md``):

- Gravity 9.81 m/s^2 along -z; ground = a static ``GEOM_PLANE`` at z = 0.
- Robot loaded with ``URDF_USE_INERTIA_FROM_FILE`` (inertias from the URDF, not from the collision shapes),
  self-collision off (pybullet's default without ``URDF_USE_SELF_COLLISION``; the lab geometry has parts that
  interpenetrate), collision = simplified convex hulls from :mod:`sim.model`.
- Contact: friction coefficient mu = 1 and restitution e = 0.1. pybullet multiplies the two bodies' values,
  so the plane gets mu = 1, e = 1 and every robot link mu = 1, e = 0.1. ``contactProcessingThreshold`` is set to
  0 on every body; with its default pybullet drops the restitution term. :class:`Contact` can also make the
  contact soft (``contactStiffness``/``contactDamping``). Bullet then computes ERP/CFM from the spring, and
  restitution no longer enters.
- Bullet's friction is not isotropic. Its friction cone is on (pybullet's default ``enableConeFriction``; with it
  off the force is clamped per direction, a pyramid), but Bullet solves the friction along two directions per
  contact that it derives from the contact normal alone, so on flat ground they are fixed in the world, each
  with its own effective mass; no pybullet setting removes that for a multibody. So the same trial turned about
  world z can end differently; a quarter turn does not change it. ``benchmarks/studies/heading.py`` measures how
  much; :class:`sim.trial.Trial` takes the heading. With ``Contact(friction_axes="body")`` (the default) the whole
  robot is turned back to heading 0 about the vertical through its base's CoM after every ``stepSimulation``
  call (positions, orientation and velocities rotated together, in float64: an exact symmetry of a flat floor),
  so the friction directions follow the robot and no trial depends on its heading. ``"world"`` is pybullet's own
  behaviour.
- ``numSolverIterations`` 20 (pybullet's default is 50) and a fixed time step ``dt_s``. With ``substeps`` > 1 one
  ``stepSimulation`` call advances ``substeps`` physics steps (``fixedTimeStep = substeps * dt_s``,
  ``numSubSteps = substeps``), and the motor force limits are divided by ``substeps``, because pybullet caps a
  motor's impulse per physics step at force x ``fixedTimeStep``. ``deterministicOverlappingPairs`` is on.
"""

from __future__ import annotations

import hashlib
import logging
import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .engine import SimulationDiverged as SimulationDiverged  # re-exported: sim.world.SimulationDiverged
from .engine import SoftServos, WorldBase, axis_inertia_kg_m2, schur_inertia_kg_m2
from .model import MESH_PLACEHOLDER, SimModel


def _quiet_import_pybullet():
    """Import pybullet without its "pybullet build time" banner, which its C code prints to stdout and stderr:
    it would corrupt ``--json`` output and turn one-line errors into two."""
    import ctypes
    import sys

    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        import pybullet

        ctypes.CDLL(None).fflush(None)
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)
    return pybullet


pb = _quiet_import_pybullet()


log = logging.getLogger(__name__)

G_M_S2 = 9.81
MAX_ROLLING_FRICTION = 0.1
"""Largest rolling or spinning friction accepted (pybullet's coefficients; 0.1 is already far above rubber
on a hard floor, about 0.01)."""


FRICTION_AXES = ("world", "body")
"""Where the friction directions are fixed (:class:`Contact`)."""
DEFAULT_FRICTION_AXES = "body"
"""The default of :attr:`Contact.friction_axes`: no trial depends on the robot's heading on the ground."""


@dataclass(frozen=True)
class Contact:
    """Contact model between the robot and the ground.

    Attributes
    ----------
    friction : float
        Coulomb friction coefficient mu.
    restitution : float
        Coefficient of restitution (rigid contact only).
    stiffness_n_m, damping_n_s_m : float or None
        Soft contact spring and damper, N/m and N s/m (default 1e4 N/m and 100 N s/m); None for pybullet's
        rigid contact.
    solver_iterations : int
        pybullet ``numSolverIterations`` (its default is 50). 20 passes the same convergence criterion as the
        time step at less cost per step (``benchmarks/sim_convergence.py``; docs/sim.md).
    rolling_friction, spinning_friction : float
        pybullet ``rollingFriction`` and ``spinningFriction`` of every robot link (and the ground: pybullet
        combines them as products, as for mu), dimensionless torque per normal force, in
        [0, ``MAX_ROLLING_FRICTION``]; 0 (the default) leaves them unset, pybullet's behaviour before.
    wing_stiffness_n_m, wing_damping_n_s_m : float or None
        Soft contact spring and damper of the links the wing joints carry (the wing plates and their roll
        motors), N/m and N s/m, instead of ``stiffness_n_m`` and ``damping_n_s_m`` there: a thin wing that bends
        where it touches the ground. None (the default): the wings touch like every other link.
    friction_axes : {"body", "world"}
        Where pybullet's two friction directions are fixed (module docstring): "body" (the default: the robot is
        kept at heading 0, so the directions turn with it and the heading does not matter) or "world" (pybullet's
        own: a trial's outcome depends on the robot's heading modulo 90 degrees).
    """

    friction: float = 1.0
    restitution: float = 0.1
    stiffness_n_m: float | None = 1e4
    damping_n_s_m: float | None = 100.0
    solver_iterations: int = 20
    rolling_friction: float = 0.0
    spinning_friction: float = 0.0
    wing_stiffness_n_m: float | None = None
    wing_damping_n_s_m: float | None = None
    friction_axes: str = DEFAULT_FRICTION_AXES

    def __post_init__(self) -> None:
        if self.friction_axes not in FRICTION_AXES:
            raise ValueError(
                f"friction_axes must be one of {', '.join(FRICTION_AXES)}; got {self.friction_axes!r}"
            )
        k, c = self.wing_stiffness_n_m, self.wing_damping_n_s_m
        if (k is None) != (c is None):
            raise ValueError("give both wing_stiffness_n_m and wing_damping_n_s_m, or neither")
        if k is not None and not (
            all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in (k, c))
            and k > 0
            and c >= 0
        ):
            raise ValueError(
                f"wing_stiffness_n_m must be > 0 and wing_damping_n_s_m >= 0 (N/m, N s/m); got {k!r}, {c!r}"
            )
        for name in ("rolling_friction", "spinning_friction"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and 0.0 <= v <= MAX_ROLLING_FRICTION):
                raise ValueError(
                    f"{name} must be a number in [0, {MAX_ROLLING_FRICTION:g}] (torque per normal force; 0: "
                    f"off); got {v!r}"
                )

    @classmethod
    def rigid(cls, **kw) -> Contact:
        """pybullet's rigid contact (restitution applies); does not converge with the time step here."""
        return cls(stiffness_n_m=None, damping_n_s_m=None, **kw)


def _turned_about_z(q, angle_rad: float) -> tuple[float, float, float, float]:
    """The quaternion (x, y, z, w) of the orientation ``q`` turned by ``angle_rad`` about world z, in float64."""
    x, y, z, w = (float(c) for c in q)
    s, c = math.sin(0.5 * angle_rad), math.cos(0.5 * angle_rad)
    return (c * x - s * y, c * y + s * x, c * z + s * w, c * w - s * z)


def _rotation_matrix(q) -> NDArray[np.float64]:
    """The rotation matrix of the unit quaternion ``q`` = (x, y, z, w), in float64."""
    x, y, z, w = (float(c) for c in q)
    return np.array(
        [
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w)],
            [2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w)],
            [2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)],
        ]
    )


def _cache_dir() -> Path:
    d = Path(os.environ.get("SELFRIGHTING_SIM_CACHE", Path(tempfile.gettempdir()) / "selfrighting-sim-cache"))
    d.mkdir(parents=True, exist_ok=True)
    return d


def _atomic_write(path: Path, text: str) -> None:
    if path.is_file() and path.read_text() == text:
        return
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def model_urdf_file(model: SimModel) -> Path:
    """Write the model's hull meshes and URDF into a content-addressed cache directory; return the URDF path.

    Safe when several processes write the same model at once (atomic renames of identical content).
    """
    d = _cache_dir() / model.model_hash
    d.mkdir(exist_ok=True)
    text = model.urdf_text
    for name, obj in model.meshes.items():
        digest = hashlib.sha256(obj.encode()).hexdigest()[:12]
        f = d / f"{name}_{digest}.obj"
        _atomic_write(f, obj)
        text = text.replace(MESH_PLACEHOLDER.format(name=name), str(f))
    urdf = d / "robot.urdf"
    _atomic_write(urdf, text)
    return urdf


class World(WorldBase):
    """One pybullet DIRECT client holding the ground and the robot; use as a context manager.

    Parameters
    ----------
    model : SimModel
    dt_s : float
        Fixed physics time step, s.
    substeps : int
        Physics steps per ``stepSimulation`` call (pybullet sub-stepping); :meth:`advance` moves in multiples.
    contact : Contact
    modifiers : tuple of sim.modifier.Modifier, optional
        What the model set adds, each attached in turn (:meth:`sim.modifier.Modifier.attach`): soft servos
        (:meth:`add_soft_joints`) and passive springs (:meth:`add_spring`). Default: the modifiers the model was
        built with (``model.modifiers``); those that edit the URDF must be the model's.

    Raises
    ------
    ValueError
        If ``modifiers`` that edit the URDF differ from those the model was built with.

    Examples
    --------
    >>> from sim.model import sim_model
    >>> with World(sim_model(), dt_s=1e-3) as w:  # doctest: +SKIP
    ...     w.advance(1)
    """

    def __init__(
        self,
        model: SimModel,
        *,
        dt_s: float,
        substeps: int = 1,
        contact: Contact | None = None,
        modifiers: tuple | None = None,
    ):
        super().__init__(model, dt_s=dt_s, substeps=substeps, modifiers=modifiers)
        self.contact = contact or Contact()
        self.cid: int | None = None
        self._gains: dict = {}

    # ------------------------------------------------------------------ lifecycle
    def _open(self) -> None:
        urdf = model_urdf_file(self.model)
        cid = pb.connect(pb.DIRECT)
        if cid < 0:
            raise RuntimeError("pybullet could not connect in DIRECT mode")
        self.cid = cid
        self._build(urdf)

    def close(self) -> None:
        if self.cid is not None:
            try:
                pb.disconnect(physicsClientId=self.cid)
            finally:
                self.cid = None

    def _build(self, urdf: Path) -> None:
        cid, c = self.cid, self.contact
        pb.setGravity(0.0, 0.0, -G_M_S2, physicsClientId=cid)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=self.dt_s * self.substeps,
            numSubSteps=self.substeps if self.substeps > 1 else 0,
            numSolverIterations=c.solver_iterations,
            deterministicOverlappingPairs=1,
            physicsClientId=cid,
        )
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid)
        self.ground = pb.createMultiBody(0.0, plane, physicsClientId=cid)
        self.body = pb.loadURDF(
            str(urdf), basePosition=[0.0, 0.0, 0.5], flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=cid
        )
        self.n_joints = pb.getNumJoints(self.body, physicsClientId=cid)
        names = {
            pb.getJointInfo(self.body, j, physicsClientId=cid)[1].decode(): j for j in range(self.n_joints)
        }
        jm = self.model.joint_map
        self._joint_names = names
        self.wing_joints = [names[n] for n in jm.wing]
        self.leg_joints = [names[n] for n in jm.leg]
        self.driven = self.wing_joints + self.leg_joints
        # what the modifiers attach: soft servos (index into driven; stiffness, damping, integral gain) and the
        # passive springs (stiffness, damping, joint) that advance() renews before every stepSimulation call
        self._soft: list[int] = []
        self._soft_gains: list[tuple[float, float, float]] = []
        self._springs: list[tuple[float, float, int]] = []
        for m in self.modifiers:
            m.attach(self)
        self._elapsed_s = 0.0
        self._stiff = [k for k in range(len(self.driven)) if k not in self._soft]
        self.max_force_n_m = np.array(
            [pb.getJointInfo(self.body, j, physicsClientId=cid)[10] for j in self.driven]
        )
        self.max_force_n_m = np.where(self.max_force_n_m > 0, self.max_force_n_m, 1.0)
        self._soft_servos = SoftServos(self._soft_gains, self.max_force_n_m[self._soft])
        self.links = [-1, *range(self.n_joints)]
        self.link_mass_kg = np.array(
            [pb.getDynamicsInfo(self.body, k, physicsClientId=cid)[0] for k in self.links]
        )
        self.mass_kg = float(self.link_mass_kg.sum())
        # pybullet's base pose is the base's inertial frame; the body frame is the base link's URDF frame
        info = pb.getDynamicsInfo(self.body, -1, physicsClientId=cid)
        r = np.array(pb.getMatrixFromQuaternion(info[4], physicsClientId=cid)).reshape(3, 3)
        self._inertial_rot = None if np.allclose(r, np.eye(3), rtol=0.0, atol=1e-12) else r
        offset = self._inertial_rot is not None or not np.allclose(info[3], 0.0, rtol=0.0, atol=1e-12)
        self._base_inertial = (tuple(info[3]), tuple(info[4])) if offset else None
        soft = (
            {}
            if c.stiffness_n_m is None
            else {"contactStiffness": c.stiffness_n_m, "contactDamping": c.damping_n_s_m}
        )
        # rolling/spinning friction only when set: the default calls pybullet exactly as before
        rolling = {
            k: v
            for k, v in (("rollingFriction", c.rolling_friction), ("spinningFriction", c.spinning_friction))
            if v > 0
        }
        pb.changeDynamics(
            self.ground,
            -1,
            lateralFriction=c.friction,
            restitution=1.0,
            contactProcessingThreshold=0.0,
            **({k: 1.0 for k in rolling}),
            physicsClientId=cid,
        )
        wing_soft = (
            {}
            if c.wing_stiffness_n_m is None
            else {"contactStiffness": c.wing_stiffness_n_m, "contactDamping": c.wing_damping_n_s_m}
        )
        self.wing_links = self._links_below(self.wing_joints)
        for k in self.links:
            pb.changeDynamics(
                self.body,
                k,
                lateralFriction=c.friction,
                restitution=c.restitution,
                contactProcessingThreshold=0.0,
                linearDamping=0.0,
                angularDamping=0.0,
                jointDamping=0.0,
                **(wing_soft if wing_soft and k in self.wing_links else soft),
                **rolling,
                physicsClientId=cid,
            )
        # free the non-driven joints (and the spring-driven ones) of pybullet's default velocity motors
        soft = {self.driven[k] for k in self._soft}
        for j in range(self.n_joints):
            if j not in self.driven or j in soft:
                pb.setJointMotorControl2(self.body, j, pb.VELOCITY_CONTROL, force=0.0, physicsClientId=cid)

    # ------------------------------------------------------------------ state
    def place(
        self,
        pitch_rad: float,
        roll_rad: float,
        *,
        joints_rad: NDArray[np.float64],
        clearance_m: float = 1e-4,
        heading_rad: float = 0.0,
    ) -> None:
        """Put the robot at rest at (pitch, roll), turned by ``heading_rad`` about world z (the yaw of its ZYX
        Euler angles), joints at ``joints_rad``, its lowest point ``clearance_m`` above the ground (by pybullet's
        own bounding boxes, which include the collision margin)."""
        cid = self.cid
        pos = [0.0, 0.0, 0.5]
        q = pb.getQuaternionFromEuler([roll_rad, pitch_rad, heading_rad], physicsClientId=cid)
        if self._base_inertial is not None:  # place the base link's frame, not its inertial frame
            pos, q = pb.multiplyTransforms(pos, q, *self._base_inertial, physicsClientId=cid)
        for j, v in zip(self.driven, joints_rad, strict=True):
            pb.resetJointState(self.body, j, float(v), 0.0, physicsClientId=cid)
        pb.resetBasePositionAndOrientation(self.body, pos, q, physicsClientId=cid)
        zmin = min(pb.getAABB(self.body, k, physicsClientId=cid)[0][2] for k in self.links)
        pos = [pos[0], pos[1], pos[2] - zmin + clearance_m]
        pb.resetBasePositionAndOrientation(self.body, pos, q, physicsClientId=cid)
        pb.resetBaseVelocity(self.body, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=cid)

    def drive(self, target_rad, speed_rad_s, *, kp: float, kd: float) -> None:
        """Position control of the driven joints (wing joints then leg joints) within their effort limits; the
        soft joints a modifier attached (:meth:`add_soft_joints`) get the torque ``k (target - q) + c (speed -
        dq/dt)`` (plus the integral's) instead, held until the next call and capped at their effort limits."""
        if self._soft:
            self._drive_soft(target_rad, speed_rad_s)
            target_rad = [target_rad[k] for k in self._stiff]
            speed_rad_s = [speed_rad_s[k] for k in self._stiff]
        gains = self._gains.get((kp, kd))
        if gains is None:
            n = len(self._stiff)
            # pybullet caps the motor impulse per substep at force * fixedTimeStep (the whole substepped step)
            gains = self._gains[(kp, kd)] = (
                [kp] * n,
                [kd] * n,
                (self.max_force_n_m[self._stiff] / self.substeps).tolist(),
            )
        pb.setJointMotorControlArray(
            self.body,
            [self.driven[k] for k in self._stiff],
            pb.POSITION_CONTROL,
            targetPositions=target_rad,
            targetVelocities=speed_rad_s,
            forces=gains[2],
            positionGains=gains[0],
            velocityGains=gains[1],
            physicsClientId=self.cid,
        )

    def _drive_soft(self, target_rad, speed_rad_s) -> None:
        joints = [self.driven[i] for i in self._soft]
        states = pb.getJointStates(self.body, joints, physicsClientId=self.cid)
        tau = self._soft_servos.torques(
            [s[0] for s in states],
            [s[1] for s in states],
            [target_rad[i] for i in self._soft],
            [speed_rad_s[i] for i in self._soft],
            elapsed_s=self._elapsed_s,
        )
        pb.setJointMotorControlArray(
            self.body, joints, pb.TORQUE_CONTROL, forces=tau, physicsClientId=self.cid
        )

    def _drive_spring(self, joint: int, k: float, c: float) -> None:
        q, dq = pb.getJointState(self.body, joint, physicsClientId=self.cid)[:2]
        pb.setJointMotorControl2(
            self.body, joint, pb.TORQUE_CONTROL, force=-k * q - c * dq, physicsClientId=self.cid
        )

    def _links_below(self, joints: list[int]) -> set[int]:
        """The links (pybullet indices) that any of ``joints`` carries: each joint's child and every link below."""
        parent = {
            j: pb.getJointInfo(self.body, j, physicsClientId=self.cid)[16] for j in range(self.n_joints)
        }
        below = set()
        for j in range(self.n_joints):
            k = j
            while k != -1 and k not in joints:
                k = parent[k]
            if k != -1:
                below.add(j)
        return below

    # ------------------------------------------------------------------ what modifiers attach
    def joint_index(self, name: str) -> int | None:
        """The pybullet index of the joint ``name``, or None if the model has none."""
        return self._joint_names.get(name)

    def add_spring(self, joint: int, stiffness: float, damping: float) -> None:
        """Drive the (passive) joint ``joint`` with ``-k q - c dq/dt``, renewed before every ``stepSimulation``
        call, settling's too."""
        self._springs.append((float(stiffness), float(damping), int(joint)))

    def link_mass_kg_of(self, joint: int) -> float:
        """The mass of the joint's child link, kg."""
        return float(pb.getDynamicsInfo(self.body, joint, physicsClientId=self.cid)[0])

    def effective_inertia_kg_m2(self, joint: int) -> float:
        """Effective moment of inertia about a joint, kg m²: the Schur complement of its entry of the joint-space
        mass matrix, base free, at the current pose."""
        cid = self.cid
        movable = [
            j
            for j in range(self.n_joints)
            if pb.getJointInfo(self.body, j, physicsClientId=cid)[2] != pb.JOINT_FIXED
        ]
        q = [pb.getJointState(self.body, j, physicsClientId=cid)[0] for j in movable]
        m = np.asarray(pb.calculateMassMatrix(self.body, q, physicsClientId=cid), dtype=np.float64)
        return schur_inertia_kg_m2(m, m.shape[0] - len(movable) + movable.index(joint))

    def child_inertia_kg_m2(self, joints: list[int]) -> float:
        """The smallest moment of inertia of the joints' child links about each joint's axis, kg m² (nan for no
        joint)."""
        return self._child_inertia(list(joints))

    def _child_inertia(self, joints: list[int]) -> float:
        cid, out = self.cid, []
        for j in joints:
            mass, _, diag, pos, orn = pb.getDynamicsInfo(self.body, j, physicsClientId=cid)[:5]
            axis = np.asarray(pb.getJointInfo(self.body, j, physicsClientId=cid)[13], dtype=np.float64)
            axis = axis / np.linalg.norm(axis)
            rot = np.array(pb.getMatrixFromQuaternion(orn, physicsClientId=cid)).reshape(3, 3)
            out.append(
                axis_inertia_kg_m2(mass, pos, rot, diag, axis)
            )  # pos: the CoM in the link (joint) frame
        return min(out) if out else math.nan

    def advance(self, n_steps: int) -> None:
        """Advance ``n_steps`` physics steps of ``dt_s`` (a multiple of ``substeps``)."""
        assert n_steps % self.substeps == 0, (n_steps, self.substeps)
        self._elapsed_s += n_steps * self.dt_s
        for _ in range(n_steps // self.substeps):
            # the modifiers' passive springs are renewed before every stepSimulation call, settling's too
            for k, c, joint in self._springs:
                self._drive_spring(joint, k, c)
            pb.stepSimulation(physicsClientId=self.cid)
            if self.contact.friction_axes == "body":
                self._turn_to_heading_zero()

    def _turn_to_heading_zero(self) -> None:
        """Turn the whole robot about the vertical through its base's CoM to heading 0: the base's orientation
        and both its velocities rotated by the same turn (the joints follow), its CoM kept in place."""
        pos, q = self.base_pose()
        psi = self._heading_of(q)
        if psi == 0.0:
            return
        cid = self.cid
        v, w = self.base_velocity()
        # in float64 (pybullet's own quaternion helpers compute in float32: the 1e-8 they leave in |q| at every
        # step would add up to a drift of the whole trajectory)
        q = _turned_about_z(q, -psi)
        c, s = math.cos(psi), math.sin(psi)
        v = [c * v[0] + s * v[1], -s * v[0] + c * v[1], v[2]]
        w = [c * w[0] + s * w[1], -s * w[0] + c * w[1], w[2]]
        pb.resetBasePositionAndOrientation(self.body, pos, q, physicsClientId=cid)
        pb.resetBaseVelocity(self.body, v, w, physicsClientId=cid)

    def base_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """Position (m) and orientation quaternion (x, y, z, w) of the base's inertial frame (its CoM)."""
        return pb.getBasePositionAndOrientation(self.body, physicsClientId=self.cid)

    def base_velocity(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Base linear (m/s) and angular (rad/s) velocity."""
        return pb.getBaseVelocity(self.body, physicsClientId=self.cid)

    def up_in_body(self) -> NDArray[np.float64]:
        """World-up expressed in the base link's frame, ``R.T @ e_z`` (the third row of R)."""
        _, q = self.base_pose()
        m = pb.getMatrixFromQuaternion(q, physicsClientId=self.cid)
        u = np.array([m[6], m[7], m[8]])  # in the base's inertial frame
        return u if self._inertial_rot is None else self._inertial_rot @ u

    def heading_rad(self) -> float:
        """The base link's heading: the yaw of its ZYX Euler angles, the angle about world z from world x to its
        x axis projected on the ground, rad in (-pi, pi]."""
        return self._heading_of(self.base_pose()[1])

    def _heading_of(self, q_inertial) -> float:
        """:meth:`heading_rad` of the base's inertial-frame orientation ``q_inertial``."""
        m = _rotation_matrix(q_inertial)
        if self._inertial_rot is not None:  # world-from-inertial times inertial-from-link
            m = m @ self._inertial_rot.T
        return float(math.atan2(m[1, 0], m[0, 0]))

    def angular_velocity_in_body(self) -> NDArray[np.float64]:
        """The base link's angular velocity expressed in the base link's frame (the body frame), rad/s."""
        _, q = self.base_pose()
        m = np.array(pb.getMatrixFromQuaternion(q, physicsClientId=self.cid)).reshape(3, 3)
        w = m.T @ np.asarray(self.base_velocity()[1], dtype=np.float64)  # in the base's inertial frame
        return w if self._inertial_rot is None else self._inertial_rot @ w

    def com_velocity_m_s(self) -> NDArray[np.float64]:
        """Velocity of the robot's mass-weighted CoM in the world frame, m/s (every link's CoM velocity)."""
        v = [self.base_velocity()[0]]
        if self.n_joints:
            states = pb.getLinkStates(
                self.body, list(range(self.n_joints)), computeLinkVelocity=1, physicsClientId=self.cid
            )
            v += [s[6] for s in states]
        return self.link_mass_kg @ np.asarray(v, dtype=np.float64) / self.mass_kg

    def joint_positions_rad(self) -> NDArray[np.float64]:
        """Positions of the driven joints, rad."""
        return np.array([s[0] for s in pb.getJointStates(self.body, self.driven, physicsClientId=self.cid)])

    def com_height_m(self) -> float:
        """Height of the robot's mass-weighted CoM, m."""
        z = [self.base_pose()[0][2]]
        z += [
            s[0][2] for s in pb.getLinkStates(self.body, list(range(self.n_joints)), physicsClientId=self.cid)
        ]
        return float(np.dot(self.link_mass_kg, z) / self.mass_kg)

    def check_finite(self, t_s: float, *, max_speed_m_s: float = 50.0, max_dist_m: float = 100.0) -> None:
        """Raise :class:`SimulationDiverged` if the base state is non-finite or implausible."""
        pos, q = self.base_pose()
        v, _ = self.base_velocity()
        speed = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        self._check_base(t_s, pos, speed, all(map(math.isfinite, q)), max_speed_m_s, max_dist_m)
