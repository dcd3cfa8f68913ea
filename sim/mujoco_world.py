"""The MuJoCo world of one trial: a flat ground plane and the robot, behind the same protocol as pybullet's
(:class:`sim.engine.EngineWorld`); the only module that imports ``mujoco`` (the optional extra
``selfrighting-landscape[mujoco]``).

Model (docs/sim.md, "The MuJoCo engine"):

- The robot is the same exported URDF pybullet loads (:func:`sim.world.model_urdf_file`: the simplified convex
  hulls, the model set's URDF edits), read by ``mujoco.MjSpec.from_file``, with a free joint on the base link.
  Every URDF link stays one body (``fusestatic`` off, as pybullet keeps them); masses, CoMs and inertias are the
  URDF's (``inertiafromgeom`` off); MuJoCo collides a mesh by its convex hull, which the meshes already are.
- Gravity 9.81 m/s^2 along -z; ground = a plane at z = 0. Only robot-ground contacts exist (the robot's geoms
  have ``conaffinity`` 0, the plane ``contype`` 0): self-collision is off, as in pybullet.
- Contact: friction mu from the set on both sides (MuJoCo takes the larger), torsional and rolling friction from
  the set's ``spinning_friction`` and ``rolling_friction`` (``condim`` 6 when either is set, else 3), and the
  set's :class:`sim.engine.MujocoParams` (cone, ``solref``, ``solimp``, margin, integrator, solver iterations,
  ``impratio``). The elliptic cone is isotropic, so no trial depends on the robot's heading. pybullet's own
  contact keys (restitution, the soft contact spring, its solver iterations, its friction axes) do not apply;
  the wings' own soft contact has no MuJoCo counterpart here and is refused.
- Servos: one position actuator per driven joint, ``kv = servo_kv_n_m_s_rad`` and ``kp = kv / tau`` with
  ``tau = dt / kp_cmd`` (the command's position gain, :meth:`MujocoWorld.drive`), its control the target plus
  ``tau`` times the feed-forward speed: the force is ``kv (speed + (target - q) / tau - dq/dt)``, the first-order
  tracker pybullet's motor is, capped at the URDF's effort limit.
- Soft servos (:meth:`MujocoWorld.add_soft_joints`) get the same torque as in pybullet's world
  (:class:`sim.engine.SoftServos`), held through each command period; passive springs
  (:meth:`MujocoWorld.add_spring`) are MuJoCo's own joint stiffness and damping about 0, which act every step.
"""

from __future__ import annotations

import copy
import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from .engine import (
    MUJOCO_DEFAULTS,
    EngineError,
    MujocoParams,
    SoftServos,
    WorldBase,
    axis_inertia_kg_m2,
    schur_inertia_kg_m2,
)
from .model import SimModel
from .world import G_M_S2, Contact, model_urdf_file

__all__ = ["MujocoWorld", "apply_params", "mujoco_version"]

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
"""What :meth:`MujocoWorld.snapshot` keeps: everything ``mj_step`` reads (MuJoCo's own definition)."""
_CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}
_INTEGRATORS = {
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "Euler": mujoco.mjtIntegrator.mjINT_EULER,
    "RK4": mujoco.mjtIntegrator.mjINT_RK4,
}
ROBOT_CONTYPE = 1
"""``contype`` of the robot's geoms (``conaffinity`` 0): they touch the ground, never each other."""


def mujoco_version() -> str:
    """The installed MuJoCo's version."""
    return mujoco.__version__


def apply_params(spec, params: MujocoParams, *, dt_s: float, contact: Contact) -> None:
    """Set ``spec``'s options (time step, gravity, cone, integrator, solver) and every geom's contact (friction,
    ``condim``, ``solref``, ``solimp``, margin) from ``params`` and ``contact``; the robot's geoms touch only the
    ground (``contype`` 1, ``conaffinity`` 0), other geoms (the ground's) only the robot.

    Parameters
    ----------
    spec : mujoco.MjSpec
    params : MujocoParams
    dt_s : float
        Time step, s.
    contact : sim.world.Contact
        Its friction coefficients.
    """
    opt = spec.option
    opt.timestep = float(dt_s)
    opt.gravity = [0.0, 0.0, -G_M_S2]
    opt.cone = _CONES[params.cone]
    opt.integrator = _INTEGRATORS[params.integrator]
    opt.iterations = int(params.solver_iterations)
    opt.impratio = float(params.impratio)
    rolling = contact.rolling_friction > 0 or contact.spinning_friction > 0
    for g in spec.geoms:
        g.friction = [contact.friction, contact.spinning_friction, contact.rolling_friction]
        g.condim = 6 if rolling else 3
        g.solref = [params.solref_time_s, params.solref_dampratio]
        g.solimp = list(params.solimp)
        g.margin = float(params.margin_m)


class MujocoWorld(WorldBase):
    """One MuJoCo model and data holding the ground and the robot; use as a context manager.

    Parameters
    ----------
    model : SimModel
    dt_s : float
        Physics time step, s.
    substeps : int
        Physics steps per :meth:`advance` unit (as pybullet's sub-steps; MuJoCo steps them in one call).
    contact : Contact, optional
        The set's contact; MuJoCo uses its friction coefficients.
    modifiers : tuple of sim.modifier.Modifier, optional
        Default: the model's (those that edit the URDF must be the model's).
    params : MujocoParams, optional
        Default :data:`sim.engine.MUJOCO_DEFAULTS`.

    Raises
    ------
    EngineError
        If the contact asks for what MuJoCo cannot express here (the wings' own soft contact).
    ValueError
        If ``modifiers`` that edit the URDF differ from those the model was built with.
    """

    def __init__(
        self,
        model: SimModel,
        *,
        dt_s: float,
        substeps: int = 1,
        contact: Contact | None = None,
        modifiers: tuple | None = None,
        params: MujocoParams | None = None,
    ):
        super().__init__(model, dt_s=dt_s, substeps=substeps, modifiers=modifiers)
        self.contact = contact or Contact()
        if self.contact.wing_stiffness_n_m is not None:
            raise EngineError(
                "the mujoco engine cannot express [contact] wing_stiffness_n_m and wing_damping_n_s_m (the wings' "
                "own soft contact): drop them from the set or use --engine pybullet"
            )
        self.params = params or MUJOCO_DEFAULTS
        self.m = self.d = None

    # ------------------------------------------------------------------ lifecycle
    def close(self) -> None:
        self.m = self.d = None

    def _open(self) -> None:
        spec = mujoco.MjSpec.from_file(str(model_urdf_file(self.model)))
        spec.compiler.fusestatic = False  # every URDF link one body, as pybullet keeps them
        spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
        spec.compiler.balanceinertia = False
        spec.compiler.discardvisual = True
        base = spec.worldbody.first_body()
        base.add_freejoint(name="base_free")
        for g in spec.geoms:
            g.contype, g.conaffinity = ROBOT_CONTYPE, 0
        spec.worldbody.add_geom(
            name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.0, 0.0, 1.0], contype=0, conaffinity=1
        )
        apply_params(spec, self.params, dt_s=self.dt_s, contact=self.contact)
        jm = self.model.joint_map
        names = [*jm.wing, *jm.leg]
        for n in names:
            a = spec.add_actuator(name=f"servo_{n}", target=n, trntype=mujoco.mjtTrn.mjTRN_JOINT)
            a.set_to_position(kp=0.0, kv=0.0)
        self.m = m = spec.compile()
        self.d = mujoco.MjData(m)
        self._base_body = base_id = 1
        self.links = list(range(base_id, m.nbody))
        self._jid = {
            mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j): j
            for j in range(m.njnt)
            if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE
        }
        self.wing_joints = [self._jid[n] for n in jm.wing]
        self.leg_joints = [self._jid[n] for n in jm.leg]
        self.driven = self.wing_joints + self.leg_joints
        self._qadr = np.array([m.jnt_qposadr[j] for j in self.driven])
        self._dadr = np.array([m.jnt_dofadr[j] for j in self.driven])
        self.link_mass_kg = np.array(m.body_mass[base_id:], dtype=np.float64)
        self.mass_kg = float(self.link_mass_kg.sum())
        # the URDF's effort limit of each driven joint (1 N m when it gives none), the actuators' force range
        lim = np.array([m.jnt_actfrcrange[j][1] if m.jnt_actfrclimited[j] else 0.0 for j in self.driven])
        self.max_force_n_m = np.where(lim > 0, lim, 1.0)
        m.actuator_forcelimited[:] = 1
        m.actuator_forcerange[:, 0] = -self.max_force_n_m
        m.actuator_forcerange[:, 1] = self.max_force_n_m
        self._soft, self._soft_gains = [], []
        for mod in self.modifiers:
            mod.attach(self)
        self._stiff = [k for k in range(len(self.driven)) if k not in self._soft]
        self._soft_servos = SoftServos(self._soft_gains, self.max_force_n_m[self._soft])
        self._soft_dofs = self._dadr[self._soft]
        self._elapsed_s = 0.0
        self._gains: tuple[float, float] | None = None
        self._tau_s = 0.0
        self._kd = 1.0
        self._fresh = False
        self._geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] >= base_id]
        mujoco.mj_forward(m, self.d)

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
        Euler angles), joints at ``joints_rad``, its lowest hull vertex ``clearance_m`` above the ground."""
        m, d = self.m, self.d
        mujoco.mj_resetData(m, d)
        q = np.zeros(4)
        mujoco.mju_euler2Quat(q, np.array([roll_rad, pitch_rad, heading_rad]), "XYZ")
        d.qpos[0:3] = (0.0, 0.0, 0.5)
        d.qpos[3:7] = q
        d.qpos[self._qadr] = np.asarray(joints_rad, dtype=np.float64)
        mujoco.mj_kinematics(m, d)
        d.qpos[2] += clearance_m - self._lowest_z()
        d.qvel[:] = 0.0
        self._soft_servos = SoftServos(self._soft_gains, self.max_force_n_m[self._soft])
        self._elapsed_s = 0.0
        mujoco.mj_forward(m, d)
        self._fresh = True

    def _lowest_z(self) -> float:
        """The lowest point of the robot's collision geometry, m (after :func:`mujoco.mj_kinematics`)."""
        m, d = self.m, self.d
        z = math.inf
        for g in self._geoms:
            mesh = m.geom_dataid[g]
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH and mesh >= 0:
                a, n = m.mesh_vertadr[mesh], m.mesh_vertnum[mesh]
                v = m.mesh_vert[a : a + n] @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g]
                z = min(z, float(v[:, 2].min()))
            else:  # a primitive: its bounding sphere
                z = min(z, float(d.geom_xpos[g][2] - m.geom_rbound[g]))
        return z

    def drive(self, target_rad, speed_rad_s, *, kp: float, kd: float) -> None:
        """Command the driven joints: each stiff servo's force is ``kv (kd speed + (target - q) / tau - dq/dt)``
        with ``tau = dt / kp`` (``kp`` is pybullet's per-step position gain), held until the next call and capped
        at the effort limit; the soft joints a modifier attached get the torque ``k (target - q) + c (speed -
        dq/dt)`` (plus the integral's) instead, held until the next call."""
        m, d = self.m, self.d
        if self._gains != (kp, kd):
            self._gains = (kp, kd)
            self._tau_s = self.dt_s / kp
            self._kd = kd
            kv = self.params.servo_kv_n_m_s_rad
            stiff_kp = kv / self._tau_s
            for k in range(len(self.driven)):
                on = k in self._stiff
                m.actuator_gainprm[k, 0] = stiff_kp if on else 0.0
                m.actuator_biasprm[k, 1] = -stiff_kp if on else 0.0
                m.actuator_biasprm[k, 2] = -kv if on else 0.0
        ff = self._tau_s * self._kd
        d.ctrl[:] = [t + ff * v for t, v in zip(target_rad, speed_rad_s, strict=True)]
        if self._soft:
            d.qfrc_applied[self._soft_dofs] = self._soft_servos.torques(
                d.qpos[self._qadr[self._soft]].tolist(),
                d.qvel[self._soft_dofs].tolist(),
                [target_rad[i] for i in self._soft],
                [speed_rad_s[i] for i in self._soft],
                elapsed_s=self._elapsed_s,
            )

    def snapshot(self) -> tuple:
        """The whole state: MuJoCo's integration state (``mjSTATE_INTEGRATION``: positions, velocities, controls,
        applied forces and the solver's warm start, all ``mj_step`` reads) and this world's own (the soft servos'
        integrals, the elapsed time); :meth:`restore` continues from it bit for bit as this world would."""
        m, d = self.m, self.d
        state = np.empty(mujoco.mj_stateSize(m, _STATE))
        mujoco.mj_getState(m, d, state, _STATE)
        return state, copy.deepcopy(self._soft_servos), self._elapsed_s

    def restore(self, snapshot: tuple) -> None:
        """Continue from a :meth:`snapshot` of a world of the same model, step and parameters."""
        state, soft, elapsed_s = snapshot
        mujoco.mj_setState(self.m, self.d, state, _STATE)
        self._soft_servos, self._elapsed_s = copy.deepcopy(soft), elapsed_s
        self._gains = None  # the next drive() sets the servos' gains in this world's model
        self._fresh = False

    # ------------------------------------------------------------------ what modifiers attach
    def joint_index(self, name: str) -> int | None:
        """MuJoCo's index of the movable joint ``name``, or None (a fixed URDF joint is no MuJoCo joint)."""
        return self._jid.get(name)

    def add_spring(self, joint: int, stiffness: float, damping: float) -> None:
        """Drive the (passive) joint ``joint`` with ``-k q - c dq/dt``: MuJoCo's joint stiffness (about 0) and
        damping, acting at every step."""
        m = self.m
        m.jnt_stiffness[joint] = float(stiffness)
        m.qpos_spring[m.jnt_qposadr[joint]] = 0.0
        m.dof_damping[m.jnt_dofadr[joint]] = float(damping)

    def link_mass_kg_of(self, joint: int) -> float:
        """The mass of the joint's child link, kg."""
        return float(self.m.body_mass[self.m.jnt_bodyid[joint]])

    def effective_inertia_kg_m2(self, joint: int) -> float:
        """Effective moment of inertia about a joint, kg m²: the Schur complement of its entry of the joint-space
        mass matrix, base free, at the current pose."""
        m, d = self.m, self.d
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, full)
        return schur_inertia_kg_m2(full, int(m.jnt_dofadr[joint]))

    def child_inertia_kg_m2(self, joints: list[int]) -> float:
        """The smallest moment of inertia of the joints' child links about each joint's axis, kg m² (nan for no
        joint)."""
        m, out = self.m, []
        for j in joints:
            b = m.jnt_bodyid[j]
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, m.body_iquat[b])
            rot = rot.reshape(3, 3)
            axis = np.asarray(m.jnt_axis[j], dtype=np.float64)
            axis = axis / np.linalg.norm(axis)
            com = m.body_ipos[b] - m.jnt_pos[j]  # the CoM from the joint, body frame
            out.append(axis_inertia_kg_m2(float(m.body_mass[b]), com, rot, m.body_inertia[b], axis))
        return min(out) if out else math.nan

    # ------------------------------------------------------------------ stepping and reading
    def advance(self, n_steps: int) -> None:
        """Advance ``n_steps`` physics steps of ``dt_s`` (a multiple of ``substeps``)."""
        assert n_steps % self.substeps == 0, (n_steps, self.substeps)
        self._elapsed_s += n_steps * self.dt_s
        self._step(int(n_steps))
        self._fresh = False

    def _step(self, n_steps: int) -> None:
        mujoco.mj_step(self.m, self.d, nstep=n_steps)

    def _sync(self) -> None:
        """Positions, CoMs and velocities of the current state (``mj_step`` leaves those of the one before)."""
        if not self._fresh:
            m, d = self.m, self.d
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            mujoco.mj_comVel(m, d)
            mujoco.mj_subtreeVel(m, d)
            self._fresh = True

    def _rotation(self) -> NDArray[np.float64]:
        """The base link's rotation matrix (body to world) from its free joint."""
        r = np.zeros(9)
        mujoco.mju_quat2Mat(r, self.d.qpos[3:7])
        return r.reshape(3, 3)

    def base_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """Position (m) and orientation quaternion (x, y, z, w) of the base's inertial frame (its CoM)."""
        self._sync()
        b, d = self._base_body, self.d
        q = np.zeros(4)
        mujoco.mju_mat2Quat(q, d.ximat[b])
        return tuple(float(x) for x in d.xipos[b]), (float(q[1]), float(q[2]), float(q[3]), float(q[0]))

    def base_velocity(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The base's CoM velocity (m/s) and angular velocity (rad/s), world frame."""
        self._sync()
        v = np.zeros(6)
        mujoco.mj_objectVelocity(self.m, self.d, mujoco.mjtObj.mjOBJ_BODY, self._base_body, v, 0)
        return tuple(float(x) for x in v[3:]), tuple(float(x) for x in v[:3])

    def up_in_body(self) -> NDArray[np.float64]:
        """World-up expressed in the base link's frame, ``R.T @ e_z`` (the third row of R)."""
        return self._rotation()[2].copy()

    def heading_rad(self) -> float:
        """The base link's heading: the yaw of its ZYX Euler angles, the angle about world z from world x to its
        x axis projected on the ground, rad in (-pi, pi]."""
        r = self._rotation()
        return float(math.atan2(r[1, 0], r[0, 0]))

    def angular_velocity_in_body(self) -> NDArray[np.float64]:
        """The base link's angular velocity expressed in the base link's frame (the body frame), rad/s."""
        return np.array(self.d.qvel[3:6], dtype=np.float64)

    def com_velocity_m_s(self) -> NDArray[np.float64]:
        """Velocity of the robot's mass-weighted CoM in the world frame, m/s."""
        self._sync()
        return np.array(self.d.subtree_linvel[self._base_body], dtype=np.float64)

    def joint_positions_rad(self) -> NDArray[np.float64]:
        """Positions of the driven joints, rad."""
        return np.array(self.d.qpos[self._qadr], dtype=np.float64)

    def com_height_m(self) -> float:
        """Height of the robot's mass-weighted CoM, m."""
        self._sync()
        return float(self.d.subtree_com[self._base_body][2])

    def penetration_m(self) -> float:
        """The deepest robot-ground penetration of the last step's contacts, m (0 without contact)."""
        d = self.d
        return max(0.0, -float(d.contact.dist[: d.ncon].min())) if d.ncon else 0.0

    def check_finite(self, t_s: float, *, max_speed_m_s: float = 50.0, max_dist_m: float = 100.0) -> None:
        """Raise :class:`sim.engine.SimulationDiverged` if the base state is non-finite or implausible."""
        d = self.d
        v = d.qvel[0:3]
        speed = math.sqrt(float(v @ v))
        self._check_base(t_s, d.qpos[0:3], speed, bool(np.isfinite(d.qpos).all()), max_speed_m_s, max_dist_m)
