"""The seam between a trial and a physics engine: the :class:`EngineWorld` protocol every engine's world
implements, the engines' names, MuJoCo's parameters (part of a model set's identity) and :func:`open_world`.

Pure (no engine is imported here): :func:`open_world` imports the chosen engine's world module when it is
called, so a run that never asks for MuJoCo never loads it, and ``sim.engine`` loads without either engine.

- ``pybullet`` (the default): :class:`sim.world.World`, the only module importing pybullet.
- ``mujoco``: :class:`sim.mujoco_world.MujocoWorld`, the only module importing mujoco (the optional extra
  ``selfrighting-landscape[mujoco]``).

Everything above the world (:mod:`sim.trial`, the model sets and their modifiers, traces, the store, sweeps) talks
to the protocol only. The engine and its parameters are part of a model set's identity
(:meth:`sim.model_set.ModelSet.with_engine`), so the store keys of two engines' trials differ.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import asdict, dataclass
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from geometry.errors import UsageError

ENGINES = ("pybullet", "mujoco")
"""The physics engines a trial can run in; the first is the default."""
DEFAULT_ENGINE = ENGINES[0]
MUJOCO_EXTRA = "the mujoco engine needs the optional extra: pip install 'selfrighting-landscape[mujoco]'"
"""The one line a MuJoCo run without the ``mujoco`` package gets."""
MUJOCO_CONES = ("elliptic", "pyramidal")
"""MuJoCo's friction cones: elliptic (isotropic, the default) or pyramidal (its faces fixed in the contact frame)."""
MUJOCO_INTEGRATORS = ("implicitfast", "implicit", "Euler", "RK4")
"""MuJoCo's integrators a set may choose."""


class SimulationDiverged(RuntimeError):
    """The physics blew up: a state became non-finite or left any plausible range."""


class EngineError(UsageError):
    """An engine that is unknown, not installed, or cannot express what a model set asks of it."""


class EngineMissingError(EngineError):
    """The chosen engine's package is not installed."""


def check_engine(engine: str) -> str:
    """``engine`` if it is one of :data:`ENGINES`.

    Raises
    ------
    EngineError
        Naming the engines there are.

    Examples
    --------
    >>> check_engine("mujoco")
    'mujoco'
    >>> check_engine("bullet")
    Traceback (most recent call last):
    ...
    sim.engine.EngineError: unknown engine 'bullet'; choose one of pybullet, mujoco
    """
    if engine not in ENGINES:
        raise EngineError(f"unknown engine {engine!r}; choose one of {', '.join(ENGINES)}")
    return engine


def require_engine(engine: str) -> None:
    """Check that ``engine`` is known and installed (imports its world module), before any trial is set up.

    Raises
    ------
    EngineError
        If it is unknown.
    EngineMissingError
        If its package is not installed (:data:`MUJOCO_EXTRA`).
    """
    _world_module(check_engine(engine))


def _world_module(engine: str):
    if engine == "pybullet":
        return importlib.import_module("sim.world")
    try:
        return importlib.import_module("sim.mujoco_world")
    except ImportError as exc:
        if exc.name is not None and exc.name.split(".")[0] == "mujoco":
            raise EngineMissingError(MUJOCO_EXTRA) from None
        raise


def _finite(v) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v)


@dataclass(frozen=True)
class MujocoParams:
    """MuJoCo's contact, solver and servo parameters: part of a model set's identity when it runs in MuJoCo
    (the ``[mujoco]`` table overrides any of them; :data:`MUJOCO_DEFAULTS` are the measured defaults,
    ``benchmarks/mujoco_parameters.py``).

    Attributes
    ----------
    solref_time_s : float
        Contact ``solref`` time constant, s (> 0): how fast a penetration is pushed out. MuJoCo raises it to twice
        the time step if smaller.
    solref_dampratio : float
        Contact ``solref`` damping ratio (> 0): 1 is critical (no bounce); smaller ratios bounce (MuJoCo has no
        restitution coefficient).
    solimp : tuple of 5 floats
        Contact ``solimp`` (dmin, dmax, width in m, midpoint, power): the impedance rising from dmin to dmax over
        ``width`` of penetration.
    margin_m : float
        Contact margin, m (>= 0): contacts are made this far before the surfaces touch.
    servo_kv_n_m_s_rad : float
        Velocity gain of the servos, N m s/rad (> 0). A servo is the first-order tracker of pybullet's world
        (desired speed = feed-forward speed + error / tau, tau the servo time constant), realised as a MuJoCo
        position actuator with ``kv`` = this and ``kp = kv / tau``, capped at the joint's effort limit.
    cone : {"elliptic", "pyramidal"}
        Friction cone; elliptic is isotropic (no dependence on the robot's heading).
    integrator : {"implicitfast", "implicit", "Euler", "RK4"}
    impratio : float
        Ratio of frictional to normal constraint impedance (>= 1 usually; > 0).
    solver_iterations : int
        Most iterations of MuJoCo's Newton solver (>= 1).
    """

    solref_time_s: float = 0.003
    solref_dampratio: float = 1.0
    solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
    margin_m: float = 0.0
    servo_kv_n_m_s_rad: float = 0.1
    cone: str = "elliptic"
    integrator: str = "implicitfast"
    impratio: float = 1.0
    solver_iterations: int = 100

    def __post_init__(self) -> None:
        for name in ("solref_time_s", "solref_dampratio", "servo_kv_n_m_s_rad", "impratio"):
            v = getattr(self, name)
            if not _finite(v) or v <= 0:
                raise EngineError(f"mujoco {name} must be a finite number > 0; got {v!r}")
        if not _finite(self.margin_m) or not 0 <= self.margin_m <= 0.01:
            raise EngineError(f"mujoco margin_m must be in [0, 0.01] m; got {self.margin_m!r}")
        s = self.solimp
        ok = isinstance(s, tuple) and len(s) == 5 and all(_finite(x) for x in s)
        if not ok or not (0 < s[0] <= s[1] < 1 and s[2] > 0 and 0 < s[3] < 1 and s[4] >= 1):
            raise EngineError(
                "mujoco solimp must be five numbers (dmin, dmax, width_m, midpoint, power) with "
                f"0 < dmin <= dmax < 1, width > 0, 0 < midpoint < 1, power >= 1; got {s!r}"
            )
        if self.cone not in MUJOCO_CONES:
            raise EngineError(f"mujoco cone must be one of {', '.join(MUJOCO_CONES)}; got {self.cone!r}")
        if self.integrator not in MUJOCO_INTEGRATORS:
            raise EngineError(
                f"mujoco integrator must be one of {', '.join(MUJOCO_INTEGRATORS)}; got {self.integrator!r}"
            )
        n = self.solver_iterations
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise EngineError(f"mujoco solver_iterations must be a whole number >= 1; got {n!r}")

    def canonical(self) -> dict:
        """Every parameter, as a set's hash sees it (JSON-able)."""
        d = asdict(self)
        d["solimp"] = list(self.solimp)
        return d


MUJOCO_KEYS = frozenset(MujocoParams.__dataclass_fields__)
"""The keys a ``[mujoco]`` table may hold."""
MUJOCO_DEFAULTS = MujocoParams()
"""MuJoCo's parameters when a set gives none (chosen by ``benchmarks/mujoco_parameters.py``; docs/sim.md)."""


@runtime_checkable
class EngineWorld(Protocol):
    """What a trial, its modifiers and the tests ask of one engine's world (one engine instance per trial, a
    context manager; :class:`sim.world.World` and :class:`sim.mujoco_world.MujocoWorld`).

    Joints and links are the engine's own indices; :attr:`driven` lists the wing joints then the leg joints, in
    the joint map's order. Angles are radians, lengths m, forces N, torques N m.
    """

    dt_s: float
    substeps: int
    driven: list[int]
    wing_joints: list[int]
    leg_joints: list[int]
    links: list[int]
    mass_kg: float

    def __enter__(self) -> EngineWorld: ...

    def __exit__(self, *exc) -> None: ...

    def close(self) -> None:
        """Release the engine (idempotent)."""

    def place(
        self,
        pitch_rad: float,
        roll_rad: float,
        *,
        joints_rad: NDArray[np.float64],
        clearance_m: float = 1e-4,
        heading_rad: float = 0.0,
    ) -> None:
        """Put the robot at rest at (pitch, roll), turned by ``heading_rad`` about world z, joints at
        ``joints_rad``, its lowest point ``clearance_m`` above the ground."""

    def drive(self, target_rad, speed_rad_s, *, kp: float, kd: float) -> None:
        """Command the driven joints: the servo's desired speed is ``kd * speed + (kp / dt) * (target - q)``
        within each joint's effort limit (``kp = dt / tau``); soft joints get their modifier's torque instead."""

    def advance(self, n_steps: int) -> None:
        """Advance ``n_steps`` physics steps of ``dt_s`` (a multiple of ``substeps``)."""

    def base_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """Position (m) and orientation quaternion (x, y, z, w) of the base's inertial frame (its CoM)."""

    def base_velocity(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The base's CoM velocity (m/s) and angular velocity (rad/s), world frame."""

    def up_in_body(self) -> NDArray[np.float64]:
        """World-up in the base link's frame."""

    def heading_rad(self) -> float:
        """The base link's heading (yaw of its ZYX Euler angles), rad in (-pi, pi]."""

    def angular_velocity_in_body(self) -> NDArray[np.float64]:
        """The base link's angular velocity in its own frame, rad/s."""

    def com_velocity_m_s(self) -> NDArray[np.float64]:
        """The whole robot's CoM velocity, world frame, m/s."""

    def joint_positions_rad(self) -> NDArray[np.float64]:
        """Positions of the driven joints, rad."""

    def com_height_m(self) -> float:
        """Height of the whole robot's CoM, m."""

    def check_finite(self, t_s: float, *, max_speed_m_s: float = 50.0, max_dist_m: float = 100.0) -> None:
        """Raise :class:`SimulationDiverged` if the base state is non-finite or implausible."""

    def snapshot(self) -> object | None:
        """The world's whole state, from which :meth:`restore` continues exactly as this world would, or None
        if the engine cannot (pybullet)."""

    def restore(self, snapshot: object) -> None:
        """Continue from a :meth:`snapshot` of a world of the same engine, model, step and parameters."""

    def joint_index(self, name: str) -> int | None:
        """The engine's index of the (movable) joint ``name``, or None."""

    def add_soft_joints(self, indices, gains) -> None:
        """Drive the driven joints ``indices`` with ``k e + c de/dt + ki integral(e)`` (one (k, c, ki) each)."""

    def add_spring(self, joint: int, stiffness: float, damping: float) -> None:
        """Drive the passive joint ``joint`` with ``-k q - c dq/dt``."""

    def link_mass_kg_of(self, joint: int) -> float:
        """The mass of the joint's child link, kg."""

    def effective_inertia_kg_m2(self, joint: int) -> float:
        """Effective moment of inertia about a joint (base free, current pose), kg m²."""

    def child_inertia_kg_m2(self, joints: list[int]) -> float:
        """The smallest moment of inertia of the joints' child links about each joint's axis, kg m²."""


def open_world(
    engine: str,
    model,
    *,
    dt_s: float,
    substeps: int = 1,
    contact=None,
    modifiers: tuple | None = None,
    mujoco: MujocoParams | None = None,
) -> EngineWorld:
    """The world of ``engine`` for ``model`` (not yet entered: use it as a context manager).

    Parameters
    ----------
    engine : {"pybullet", "mujoco"}
    model : sim.model.SimModel
    dt_s : float
        Physics time step, s.
    substeps : int
        Physics steps per engine call (pybullet sub-stepping; MuJoCo steps ``substeps`` at once).
    contact : sim.world.Contact, optional
        The set's contact: pybullet uses all of it, MuJoCo its friction coefficients.
    modifiers : tuple of sim.modifier.Modifier, optional
        Default: the model's.
    mujoco : MujocoParams, optional
        MuJoCo's parameters (default :data:`MUJOCO_DEFAULTS`); ignored by pybullet.

    Raises
    ------
    EngineError
        If the engine is unknown.
    EngineMissingError
        If it is MuJoCo and the ``mujoco`` package is not installed.
    """
    module = _world_module(check_engine(engine))
    if engine == "pybullet":
        return module.World(model, dt_s=dt_s, substeps=substeps, contact=contact, modifiers=modifiers)
    return module.MujocoWorld(
        model, dt_s=dt_s, substeps=substeps, contact=contact, modifiers=modifiers, params=mujoco
    )


class WorldBase:
    """What every engine's world holds apart from its engine: the model, the modifiers it attaches (those that edit
    the URDF must be the ones the model was built with), the time step, the soft servos the modifiers register
    (:meth:`add_soft_joints`), and the context manager around the engine's ``_open`` and ``close``.

    Raises
    ------
    ValueError
        If ``modifiers`` that edit the URDF differ from those the model was built with.
    """

    def __init__(self, model, *, dt_s: float, substeps: int = 1, modifiers: tuple | None = None):
        self.model = model
        self.modifiers = tuple(model.modifiers if modifiers is None else modifiers)
        built = {m for m in self.modifiers if m.EDITS_URDF}
        edited = {m for m in model.modifiers if m.EDITS_URDF}
        if built != edited:
            have = ", ".join(sorted(m.TABLE for m in edited)) or "none"
            want = ", ".join(sorted(m.TABLE for m in built)) or "none"
            raise ValueError(
                f"the World's modifiers that edit the URDF ({want}) must be those the model was built with "
                f"({have}); build the model with sim_model(..., modifiers=) the same"
            )
        self.dt_s = float(dt_s)
        self.substeps = int(substeps)
        self._soft: list[int] = []
        self._soft_gains: list[tuple[float, float, float]] = []

    def __enter__(self):
        try:
            self._open()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _open(self) -> None:
        """Start the engine and build the world (the engine's own; :meth:`close` undoes it, also half-way)."""
        raise NotImplementedError

    def close(self) -> None:
        """Release the engine (idempotent)."""
        raise NotImplementedError

    def add_soft_joints(self, indices, gains) -> None:
        """Drive the driven joints ``indices`` (positions in :attr:`driven`) with the torque
        ``k (target - q) + c (speed - dq/dt) + ki * integral(target - q) dt`` instead of the stiff servo;
        ``gains``: one (k, c, ki) per joint. Only while the world is being built (from a modifier's ``attach``)."""
        indices = list(indices)
        if len(indices) != len(gains) or set(indices) & set(self._soft):
            raise ValueError(f"soft joints {indices} need one gain each and no joint twice; got {len(gains)}")
        self._soft += indices
        self._soft_gains += [tuple(float(v) for v in g) for g in gains]

    def snapshot(self) -> object | None:
        """None: this engine's state cannot be restored exactly (each trial settles afresh)."""
        return None

    def restore(self, snapshot: object) -> None:
        raise NotImplementedError(f"{type(self).__name__} cannot restore a snapshot")

    def _check_base(
        self, t_s: float, pos, speed_m_s: float, finite: bool, max_speed_m_s: float, max_dist_m: float
    ):
        """Raise :class:`SimulationDiverged` if the base at ``pos`` (m) moving at ``speed_m_s`` is not ``finite``,
        faster than ``max_speed_m_s`` or further than ``max_dist_m`` from the origin."""
        dist = math.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
        if not (speed_m_s <= max_speed_m_s and dist <= max_dist_m and finite):
            raise SimulationDiverged(
                f"simulation diverged at t = {t_s:.4f} s (dt = {self.dt_s:g} s): base position {np.round(pos, 3)}"
                f" m, speed {speed_m_s:.3g} m/s; try a smaller --dt"
            )


def schur_inertia_kg_m2(mass_matrix, i: int) -> float:
    """The effective inertia of coordinate ``i`` with every other one free: the Schur complement of its entry of
    the joint-space mass matrix, kg m² (for a hinge).

    Examples
    --------
    >>> schur_inertia_kg_m2(np.array([[2.0, 1.0], [1.0, 2.0]]), 0)  # 2 - 1 * 1 / 2
    1.5
    """
    m = np.asarray(mass_matrix, dtype=np.float64)
    rest = [k for k in range(m.shape[0]) if k != i]
    coupling = m[i, rest]
    return float(m[i, i] - coupling @ np.linalg.solve(m[np.ix_(rest, rest)], coupling))


def axis_inertia_kg_m2(mass_kg: float, com_m, rot, principal_kg_m2, axis) -> float:
    """A link's moment of inertia about an axis through the joint frame's origin, kg m²: its principal moments
    ``principal_kg_m2`` turned by ``rot`` (principal axes in the joint frame) about the unit ``axis``, plus
    ``mass_kg`` at ``com_m`` (the CoM in the joint frame, m) off the axis.

    Examples
    --------
    >>> axis_inertia_kg_m2(2.0, [0.0, 3.0, 0.0], np.eye(3), [1.0, 1.0, 1.0], np.array([1.0, 0.0, 0.0]))  # 1 + 2 * 9
    19.0
    """
    r = np.asarray(com_m, dtype=np.float64)
    return float(axis @ rot @ np.diag(principal_kg_m2) @ rot.T @ axis + mass_kg * (r @ r - (r @ axis) ** 2))


class SoftServos:
    """The soft servos a model set's modifiers attach (:meth:`EngineWorld.add_soft_joints`), engine-independent:
    per joint the torque ``k (target - q) + c (speed - dq/dt) + ki * integral``, capped at the effort limit.

    The integral is of the error at the last command, held since then (left rectangles), and clamped so its torque
    never exceeds the effort limit (no wind-up); joints without an integral gain keep theirs at 0.

    Parameters
    ----------
    gains : array_like of shape (N, 3)
        (k N m/rad, c N m s/rad, ki N m/(rad s)) per soft joint.
    limit_n_m : array_like of shape (N,)
        Effort limits, N m.

    Examples
    --------
    >>> s = SoftServos([(2.0, 0.5, 0.0)], [1.0])
    >>> s.torques([0.25], [0.5], [0.75], [1.5], elapsed_s=0.0)  # 2 * 0.5 + 0.5 * 1, capped at 1
    [1.0]
    >>> s.torques([0.25], [0.5], [0.5], [0.5], elapsed_s=0.0)  # 2 * 0.25 + 0.5 * 0
    [0.5]
    """

    def __init__(self, gains, limit_n_m):
        self.k, self.c, self.ki = np.array(gains, dtype=np.float64).reshape(-1, 3).T
        self.limit_n_m = np.asarray(limit_n_m, dtype=np.float64)
        self.integral = np.zeros(len(self.k))  # the integrated error per soft joint, rad s
        self.last_err = np.zeros(len(self.k))
        self.last_s = 0.0

    def torques(self, q_rad, dq_rad_s, target_rad, speed_rad_s, *, elapsed_s: float) -> list[float]:
        """The torque of each soft joint (N m) at joint positions ``q_rad`` and speeds ``dq_rad_s`` towards
        ``target_rad`` and ``speed_rad_s``, at the world's time ``elapsed_s``."""
        lim, ki = self.limit_n_m, self.ki
        err = np.array([t - q for t, q in zip(target_rad, q_rad, strict=True)])
        torque = self.k * err + self.c * np.array([s - v for s, v in zip(speed_rad_s, dq_rad_s, strict=True)])
        if ki.any():
            dt = elapsed_s - self.last_s
            bound = np.divide(lim, ki, out=np.zeros_like(lim), where=ki > 0)
            self.integral = np.clip(self.integral + self.last_err * dt, -bound, bound)
            torque = torque + ki * self.integral
        self.last_s, self.last_err = elapsed_s, err
        return np.clip(torque, -lim, lim).tolist()
