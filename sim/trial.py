"""One self-righting trial: settle on the back, actuate wings and leg, stop as soon as the outcome is known.

Protocol
--------
1. The robot is placed on its back at roll 0 and the pitch of its lowest resting orientation
   (:func:`sim.model.rest_pitch_deg`), wings closed, leg centred, its lowest point 0.1 mm above the ground, and
   left to settle for ``SETTLE_S`` (0.5 s, a fixed time so that every time step starts actuating from the same
   physical state) with the motors holding 0; a warning is logged if the base still moves faster than 5 mm/s
   or 0.05 rad/s. Time t = 0 is the end of settling.
2. The joints track :mod:`sim.actuation`'s profiles by the engine's position servo (pybullet's position
   control, or MuJoCo's equivalent position actuator: :mod:`sim.mujoco_world`) within each joint's effort
   limit (the URDF's, 1 N m for the lab robot), with feed-forward of the profile speed (velocity gain 1) and a
   position gain ``dt / SERVO_TAU_S`` per physics step (a 10 ms servo time constant, so the servo does not
   change with ``dt``). The servos are commanded every ``CONTROL_PERIOD_S`` (1 ms, a whole number of physics
   steps; every step if ``dt`` is larger): each command holds the profile's angle at the middle of the period
   (so a ramp is tracked without lag) and its speed, and the engine sub-steps through the period in one call.
3. Outcome rule: the robot is **upright** when world-up in the body frame has ``u_z < 0``. The trial succeeds
   when it stays upright for ``UPRIGHT_HOLD_S`` (0.3 s) without interruption; ``time_to_right_s`` is the time the
   robot became upright at the start of that stretch, and the simulation stops there. Otherwise it runs for
   ``duration_s`` and fails. The succeeding attempt is the last wing opening that started at or before
   ``time_to_right_s``. The mode is ``"roll"`` when at that moment ``|u_y| >= |u_x|`` (the body turned about
   its long axis: roll-over) and ``"somersault"`` otherwise (it turned about its pitch axis, over head or tail).

Body pitch and roll follow ``geometry/frames.py``; the trace reports them on the ``|pitch| <= 90`` branch.

One concept, one trial: its spec (:class:`Trial`), the bounds it is checked against, the run and its result;
hence over 600 lines.
"""

from __future__ import annotations

import logging
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from geometry import JointMap, pitch_roll_from_up
from geometry.errors import GeometryError, JointLimitError

from .actuation import Actuation, attempt_phases, attempt_starts_s, leg_profile_deg, wing_joint_profiles_deg
from .engine import DEFAULT_ENGINE, EngineWorld, check_engine, open_world
from .hulls import HULL_MAX_VERTICES, HULL_TOL_M
from .model import sim_model
from .modifier import with_modifier
from .protocol import (
    DEFAULT_DT_S,
    DEFAULT_DURATION_S,
    MAX_DT_S,
    MAX_DURATION_S,
    MAX_STEPS,
    MIN_DT_S,
    MUJOCO_DT_S,
    MUJOCO_OTHER_ROBOT_DT_S,
    OTHER_ROBOT_DT_S,
)
from .world import G_M_S2, Contact, SimulationDiverged

log = logging.getLogger(__name__)

UPRIGHT_HOLD_S = 0.3
SETTLE_S = 0.5
SERVO_TAU_S = 0.01
CHECK_EVERY_S = 5e-3
"""The outcome, tracking error and divergence are checked at this interval (or every control period if longer)."""
TRACE_EVERY_S = 0.01
CONTROL_PERIOD_S = 1e-3
"""Servo command period, s: the commands are held for this many physics steps, which pybullet sub-steps in one
``stepSimulation`` call. The same at every ``dt`` that divides it, so it is part of the model, not the numerics."""
MAX_TRIAL_MEMORY_BYTES = 2**30
"""Most memory for one trial's precomputed command profiles, bytes (1 GiB; :func:`trial_cost` estimates it within
5 % of the peak tracemalloc measures)."""
_BYTES_PER_CONTROL_PERIOD = 40
_BYTES_PER_CONTROL_PERIOD_JOINT = 51

__all__ = [
    "DEFAULT_DT_S",
    "Numerics",
    "Trial",
    "simulate_trial",
    "OTHER_ROBOT_DT_S",
    "default_dt_s",
    "SimulationDiverged",
    "Trace",
    "TrialResult",
    "run_trial",
    "resolve_seed",
    "MAX_DURATION_S",
    "MIN_DT_S",
    "MAX_DT_S",
    "MAX_STEPS",
    "MAX_TRIAL_MEMORY_BYTES",
    "trial_cost",
    "check_trial_cost",
    "TrialInputError",
]


class TrialInputError(GeometryError):
    """Bad trial parameters (a ValueError: the command line reports it on one line, exit status 2)."""


@dataclass(frozen=True)
class Trace:
    """Time series sampled every ``TRACE_EVERY_S`` from t = 0 (end of settling).

    Attributes
    ----------
    t_s, pitch_deg, roll_deg, up_z, com_height_m, energy_j, wing_cmd_deg, wing_deg, leg_cmd_deg, leg_deg
        ndarray of shape (N,): time (s); body pitch and roll (deg); world-up's body-z component; CoM height (m);
        potential energy m g z_com (J); commanded and measured wing angle (mean of the wing joints) and leg
        angle (deg).
    omega_body_rad_s : ndarray of shape (N, 3) or None
        The body's (base link's) angular velocity in the body frame, rad/s, from the engine (not in
        ``COLUMNS``: a trace file holds the ten columns only).
    com_velocity_m_s : ndarray of shape (N, 3) or None
        Velocity of the whole robot's mass-weighted CoM in the world frame, m/s, from the engine.
    heading_deg : ndarray of shape (N,) or None
        The base link's heading on the ground (:meth:`sim.world.World.heading_rad`), degrees.
    """

    t_s: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    up_z: NDArray[np.float64]
    com_height_m: NDArray[np.float64]
    energy_j: NDArray[np.float64]
    wing_cmd_deg: NDArray[np.float64]
    wing_deg: NDArray[np.float64]
    leg_cmd_deg: NDArray[np.float64]
    leg_deg: NDArray[np.float64]
    omega_body_rad_s: NDArray[np.float64] | None = field(default=None, repr=False)
    com_velocity_m_s: NDArray[np.float64] | None = field(default=None, repr=False)
    heading_deg: NDArray[np.float64] | None = field(default=None, repr=False)

    COLUMNS = (
        "t_s",
        "pitch_deg",
        "roll_deg",
        "up_z",
        "com_height_m",
        "energy_j",
        "wing_cmd_deg",
        "wing_deg",
        "leg_cmd_deg",
        "leg_deg",
    )

    def as_array(self) -> NDArray[np.float64]:
        """Columns ``COLUMNS`` side by side, shape (N, 10)."""
        return np.stack([getattr(self, c) for c in self.COLUMNS], axis=1)


@dataclass(frozen=True)
class TrialResult:
    """Outcome of one trial.

    Attributes
    ----------
    theta_w_deg, theta_l_deg, phase, cv : float
        Inputs: wing angle, leg amplitude (deg), first-attempt phase phi_1, noise Cv = sigma / Tl.
    seed : int
        Seed of the trial's random generator (``np.random.default_rng(seed)`` reproduces the trial).
    duration_s, dt_s : float
        Trial length and time step, s.
    success : bool
    time_to_right_s : float or None
        Time from the start of actuation to becoming upright for good, s.
    attempt : int or None
        1-based index of the wing opening that righted the robot.
    phases : tuple of float
        Phase phi_k of every attempt that started before the trial ended.
    attempt_starts_s : tuple of float
        Opening time of those attempts, s.
    mode : {"roll", "somersault"} or None
    side : int or None
        Sign of the body roll (ZYX Euler, degrees) when the final upright stretch began: +1 or -1, the side the
        robot rolled over to (None if it did not right). The physical robot's records use the same sign.
    sim_s : float
        Simulated actuation time until the trial stopped, s.
    wall_s, cpu_s : float
        Wall-clock and process CPU time of the whole trial (model, settling, stepping), s.
    max_tracking_error_deg : float
        Largest ``|measured - commanded|`` driven-joint angle over the trial, deg.
    robot_hash, model_hash : str
        Hash of the robot (``geometry.Robot.robot_hash``: its files, and its joint map when not the default) and
        of the simulated model (hulls).
    trace : Trace or None
    model_set, model_set_hash : str
        Name and hash of the model parameter set (:mod:`sim.model_set`; "paper" by default).
    engine : str
        The physics engine it ran in (:data:`sim.engine.ENGINES`); ``model_set_hash`` is that engine's.
    """

    theta_w_deg: float
    theta_l_deg: float
    phase: float
    cv: float
    seed: int
    duration_s: float
    dt_s: float
    success: bool
    time_to_right_s: float | None
    attempt: int | None
    phases: tuple[float, ...]
    attempt_starts_s: tuple[float, ...]
    mode: str | None
    sim_s: float
    wall_s: float
    cpu_s: float
    max_tracking_error_deg: float
    robot_hash: str
    model_hash: str
    trace: Trace | None = field(default=None, repr=False)
    model_set: str = "paper"
    model_set_hash: str = ""
    side: int | None = None
    engine: str = DEFAULT_ENGINE

    def to_dict(self) -> dict:
        """Plain JSON-able dict without the trace."""
        d = asdict(self)
        d.pop("trace")
        d["phases"] = list(self.phases)
        d["attempt_starts_s"] = list(self.attempt_starts_s)
        return d


def resolve_seed(rng: np.random.Generator | int | None) -> tuple[int, np.random.Generator]:
    """A seed and the generator it makes: an int is the seed, a Generator draws one, None draws from the OS.

    Examples
    --------
    >>> seed, g = resolve_seed(7)
    >>> seed, float(g.random()) == float(np.random.default_rng(7).random())
    (7, True)
    """
    if isinstance(rng, np.random.Generator):
        seed = int(rng.integers(0, 2**63 - 1))
    elif rng is None:
        seed = int(np.random.SeedSequence().entropy % (2**63 - 1))
    elif isinstance(rng, (int, np.integer)) and not isinstance(rng, bool) and rng >= 0:
        seed = int(rng)
    else:
        raise TrialInputError(f"rng must be a numpy Generator, a seed int >= 0 or None; got {rng!r}")
    return seed, np.random.default_rng(seed)


def default_dt_s(robot: str | Path | None = None, engine: str = DEFAULT_ENGINE) -> float:
    """Default time step for a robot in an engine: for pybullet ``DEFAULT_DT_S`` for the built-in robot (also an
    exported copy of it, by its description hash, whatever its joint map), ``OTHER_ROBOT_DT_S`` for any other URDF;
    for MuJoCo ``MUJOCO_DT_S`` and ``MUJOCO_OTHER_ROBOT_DT_S``.

    Only the files are compared (:func:`geometry.urdf.read_urdf`), so no joint map is needed here.

    Raises
    ------
    RobotDescriptionError
        If the URDF or one of its meshes is missing or the XML is malformed.

    Examples
    --------
    >>> default_dt_s()
    0.000125
    """
    from geometry.urdf import read_urdf

    from .model import default_robot_urdf

    builtin, other = (
        (DEFAULT_DT_S, OTHER_ROBOT_DT_S)
        if check_engine(engine) == DEFAULT_ENGINE
        else (MUJOCO_DT_S, MUJOCO_OTHER_ROBOT_DT_S)
    )
    default = default_robot_urdf()
    if robot is None or Path(robot).resolve() == default.resolve():
        return builtin
    same = read_urdf(robot).description_hash == read_urdf(default).description_hash
    return builtin if same else other


def trial_cost(
    duration_s: float, dt_s: float, *, control_period_s: float | None = CONTROL_PERIOD_S, n_joints: int = 5
) -> tuple[int, int]:
    """Physics steps (settling included) and bytes of precomputed command profiles of one trial.

    The profiles hold, per control period, its time stamps and the wing and leg angles (float64), and per driven
    joint the held and end-of-period targets and speeds while they are built; the estimate is within 5 % of
    tracemalloc's peak with four wing joints and a leg, two and one, four and three
    (``tests/sim/test_sweep_robustness.py``). The trial converts them to Python floats a few hundred periods at
    a time.

    Examples
    --------
    >>> trial_cost(10.0, 5e-4, n_joints=5)
    (21000, 2950000)
    """
    dt_s = float(dt_s)
    sub = max(1, int(round(control_period_s / dt_s))) if control_period_s else 1
    n_ctrl = int(round(float(duration_s) / (sub * dt_s)))
    steps = int(round((SETTLE_S + float(duration_s)) / dt_s))
    return steps, n_ctrl * (_BYTES_PER_CONTROL_PERIOD + _BYTES_PER_CONTROL_PERIOD_JOINT * int(n_joints))


def check_trial_cost(
    duration_s: float, dt_s: float, *, control_period_s: float | None = CONTROL_PERIOD_S, n_joints: int = 5
) -> None:
    """Refuse a trial longer than ``MAX_DURATION_S``, with a step outside [``MIN_DT_S``, ``MAX_DT_S``], more
    than ``MAX_STEPS`` physics steps or profiles larger than ``MAX_TRIAL_MEMORY_BYTES``, before it starts.

    Raises
    ------
    TrialInputError
        Saying which bound is exceeded, the trial's estimated steps and memory, and what to change.

    Examples
    --------
    >>> check_trial_cost(1e6, 5e-4)
    Traceback (most recent call last):
    ...
    sim.trial.TrialInputError: duration 1e+06 s is longer than MAX_DURATION_S = 600 s (2e+09 physics steps, 275 GiB of command profiles); give --duration <= 600
    """
    for name, v in (("duration", duration_s), ("dt", dt_s)):
        if not np.isfinite(v):
            raise TrialInputError(f"{name} must be a finite number; got {v!r}")
    if control_period_s is not None and not (
        np.isfinite(control_period_s) and 0 < control_period_s <= MAX_DT_S
    ):
        raise TrialInputError(
            f"control_period_s must be in (0, {MAX_DT_S:g}] s or None; got {control_period_s!r}"
        )
    if not duration_s > 0:
        raise TrialInputError(f"duration must be > 0 s; got {duration_s!r}")
    if not MIN_DT_S <= dt_s <= MAX_DT_S:
        raise TrialInputError(
            f"dt must be in [MIN_DT_S, MAX_DT_S] = [{MIN_DT_S:g}, {MAX_DT_S:g}] s; got {dt_s!r}"
        )
    # the estimate in floats: a huge duration must be described, not computed
    sub = max(1, round(control_period_s / dt_s)) if control_period_s else 1
    steps = (SETTLE_S + float(duration_s)) / dt_s
    mem = (
        float(duration_s)
        / (sub * dt_s)
        * (_BYTES_PER_CONTROL_PERIOD + _BYTES_PER_CONTROL_PERIOD_JOINT * n_joints)
    )
    cost = (
        f"{steps:.3g} physics steps, {mem / 2**30:.3g} GiB of command profiles"
        if np.isfinite(mem)
        else "over 1e+308 physics steps and bytes of command profiles"
    )
    if duration_s > MAX_DURATION_S:
        raise TrialInputError(
            f"duration {duration_s:g} s is longer than MAX_DURATION_S = {MAX_DURATION_S:g} s "
            f"({cost}); give --duration <= {MAX_DURATION_S:g}"
        )
    if steps > MAX_STEPS:
        raise TrialInputError(
            f"duration {duration_s:g} s at dt {dt_s:g} s is {steps:,.0f} physics steps with "
            f"settling ({mem / 2**30:.3g} GiB of command profiles), more than MAX_STEPS = "
            f"{MAX_STEPS:,} (the default trial takes 21,000); give a larger --dt or a shorter "
            "--duration"
        )
    if mem > MAX_TRIAL_MEMORY_BYTES:
        raise TrialInputError(
            f"duration {duration_s:g} s at dt {dt_s:g} s needs {cost}, more than "
            "MAX_TRIAL_MEMORY_BYTES = "
            f"{MAX_TRIAL_MEMORY_BYTES / 2**30:g} GiB; give a shorter --duration or command the "
            "servos less often"
        )


def _check_inputs(
    theta_w_deg,
    theta_l_deg,
    phase,
    cv,
    duration_s,
    dt_s,
    limits,
    *,
    control_period_s=CONTROL_PERIOD_S,
    n_joints=5,
) -> None:
    for name, v in (
        ("theta_w_deg", theta_w_deg),
        ("theta_l_deg", theta_l_deg),
        ("phase", phase),
        ("cv", cv),
        ("duration_s", duration_s),
        ("dt_s", dt_s),
    ):
        if not np.isfinite(v):
            raise TrialInputError(f"{name} must be a finite number; got {v!r}")
    for name, v in (("theta_w", theta_w_deg), ("theta_l", theta_l_deg)):
        lo, hi = limits[name]
        lo = max(lo, 0.0) if name == "theta_w" else max(0.0, -hi, lo)
        if not lo - 1e-9 <= v <= hi + 1e-9:
            raise JointLimitError(
                f"{name} = {v:g} deg is outside [{lo:g}, {hi:g}] deg allowed by the robot's "
                "joints; choose a value inside"
            )
    if not 0.0 <= phase < 1.0:
        raise TrialInputError(f"phase must be in [0, 1) (fraction of the leg period); got {phase!r}")
    if cv < 0:
        raise TrialInputError(f"cv must be >= 0 (sigma / leg period); got {cv!r}")
    check_trial_cost(duration_s, dt_s, control_period_s=control_period_s, n_joints=n_joints)


@dataclass(frozen=True)
class Numerics:
    """How a trial is simulated, not what is simulated: collision hulls, servo command period, sub-stepping.

    Attributes
    ----------
    hull_tol_m, hull_max_vertices
        Collision hull simplification (:func:`sim.model.sim_model`, :mod:`sim.hulls`); ``hull_tol_m=0`` keeps full hulls.
    control_period_s : float or None
        Servo command period, s (rounded to a whole number of steps); None commands every physics step (the
        configuration before the speed-up, kept for the benchmarks).
    engine_substeps : bool
        Let pybullet sub-step through a control period in one call (default) rather than one call per step;
        the physics is identical (tested), only faster.
    merge_fixed_links : bool
        Merge links on fixed joints into their parents (:func:`sim.urdf_edits.merge_fixed_links`). Off by
        default: faster, but it fails the convergence criterion at the default dt (docs/sim.md).
    reuse_settled : bool
        Start a trial from the settled state an earlier trial of this process left with the same robot, model
        set, engine, step and heading (settling does not depend on the trial's angles, phase or noise), where the
        engine's world offers a snapshot (MuJoCo: :meth:`sim.mujoco_world.MujocoWorld.snapshot`; pybullet settles
        every trial). The physics is identical (tested), only faster.
    """

    hull_tol_m: float = HULL_TOL_M
    hull_max_vertices: int = HULL_MAX_VERTICES
    control_period_s: float | None = CONTROL_PERIOD_S
    engine_substeps: bool = True
    merge_fixed_links: bool = False
    reuse_settled: bool = True


@dataclass(frozen=True)
class Trial:
    """What one trial does (the experiment, apart from the model set and the numerics).

    Attributes
    ----------
    theta_w_deg, theta_l_deg : float
        Wing opening angle and leg oscillation amplitude, degrees.
    phase : float
        phi_1 = Delta t_1 / Tl in [0, 1): when the wings first open, as a fraction of the leg period.
    cv : float
        Coefficient of variation Cv = sigma / Tl (>= 0) of the closed-hold noise (see :mod:`sim.actuation`).
    rng : numpy.random.Generator, int or None
        Seed or generator of the noise; the seed used is kept in the result.
    duration_s : float
        Trial length, s.
    dt_s : float or None
        Time step, s; None: :func:`default_dt_s` of the robot.
    robot : path, optional
        URDF file (default :func:`sim.model.default_robot_urdf`).
    joint_map : JointMap, optional
    attempts : int, optional
        Make at most this many wing openings; the wings then stay closed, and the trial ends one wing period
        ``Tw`` after the last opening (or at ``duration_s`` if earlier). ``attempts=1`` is a single-attempt
        trial (the phase map). None: attempts until ``duration_s``.
    trace : bool
        Record a :class:`Trace`.
    actuation : Actuation, optional
        Profile timing instead of the model set's; its theta fields are replaced by ``theta_w_deg`` and
        ``theta_l_deg``.
    heading_deg : float
        The robot's heading on the ground when it is placed, degrees about world z (0: its x axis along world
        x). On an isotropic floor it would not matter; pybullet's friction is not isotropic (:mod:`sim.world`),
        so it can change the outcome there (``benchmarks/studies/heading.py``); MuJoCo's elliptic cone is.
    """

    theta_w_deg: float
    theta_l_deg: float
    phase: float
    cv: float
    rng: np.random.Generator | int | None = None
    duration_s: float = DEFAULT_DURATION_S
    dt_s: float | None = None
    robot: str | Path | None = None
    joint_map: JointMap | None = None
    attempts: int | None = None
    trace: bool = False
    actuation: Actuation | None = None
    heading_deg: float = 0.0


def run_trial(
    theta_w_deg: float,
    theta_l_deg: float,
    *,
    phase: float,
    cv: float,
    rng: np.random.Generator | int | None = None,
    duration_s: float = DEFAULT_DURATION_S,
    dt_s: float | None = None,
    robot: str | Path | None = None,
    joint_map: JointMap | None = None,
    actuation: Actuation | None = None,
    contact: Contact | None = None,
    trace: bool = False,
    attempts: int | None = None,
    model_set=None,
    numerics: Numerics = Numerics(),
    compliance=None,
    heading_deg: float = 0.0,
    engine: str | None = None,
) -> TrialResult:
    """Run one self-righting trial in a fresh engine instance: the keyword form of :func:`simulate_trial`.

    Parameters
    ----------
    theta_w_deg, theta_l_deg : float
        Wing opening angle and leg oscillation amplitude, degrees.
    phase, cv : float
        First-attempt phase phi_1 in [0, 1) and noise Cv = sigma / Tl (>= 0) (:class:`Trial`).
    rng : numpy.random.Generator, int or None
        Seed or generator of the noise; the seed used is kept in the result.
    duration_s, dt_s : float
        Trial length and time step, s; dt None: :func:`default_dt_s` of the robot.
    robot : path, optional
        URDF file (default :func:`sim.model.default_robot_urdf`).
    joint_map : JointMap, optional
    actuation : Actuation, optional
        Profile timing instead of the model set's (:class:`Trial`).
    contact : Contact, optional
        Instead of the model set's contact.
    trace : bool
        Record a :class:`Trace`.
    attempts : int, optional
        Make at most this many wing openings (:class:`Trial`); None: attempts until ``duration_s``.
    model_set : sim.model_set.ModelSet, optional
        Model parameter set (None: the shipped ``paper`` set, the same values as the defaults of
        :class:`Actuation` and :class:`Contact`). Its name and hash are kept in the result.
    numerics : Numerics
        Hulls, servo period and sub-stepping (defaults: the converged configuration).
    compliance : sim.compliance.Compliance, optional
        Compliant wing joints instead of the model set's (None in most shipped sets: rigid wings).
    heading_deg : float
        The robot's heading on the ground, degrees (:class:`Trial`).
    engine : {"pybullet", "mujoco"}, optional
        Run the model set in this engine (:meth:`sim.model_set.ModelSet.with_engine`); None: the set's own
        (pybullet for a set as loaded).

    Returns
    -------
    TrialResult

    Raises
    ------
    TrialInputError, JointLimitError, RobotDescriptionError, SimulationDiverged, EngineError
        As :func:`simulate_trial` does.
    """
    if model_set is None:
        from .model_set import load_model_set

        model_set = load_model_set()
    if engine is not None:
        model_set = model_set.with_engine(engine)
    if contact is not None:
        model_set = replace(model_set, contact=contact)
    if compliance is not None:
        model_set = replace(model_set, modifiers=with_modifier(model_set.modifiers, compliance))
    trial = Trial(
        theta_w_deg,
        theta_l_deg,
        phase,
        cv,
        rng=rng,
        duration_s=duration_s,
        dt_s=dt_s,
        robot=robot,
        joint_map=joint_map,
        attempts=attempts,
        trace=trace,
        actuation=actuation,
        heading_deg=heading_deg,
    )
    return simulate_trial(trial, model_set=model_set, numerics=numerics)


def simulate_trial(trial: Trial, *, model_set=None, numerics: Numerics = Numerics()) -> TrialResult:
    """Run ``trial`` with ``model_set`` and ``numerics`` in a fresh instance of the set's engine.

    The model set says what is simulated: its engine (``ModelSet.engine``, pybullet unless
    :meth:`~sim.model_set.ModelSet.with_engine` chose another) and its parameters, its actuation timing (unless
    ``trial.actuation``), its contact, and its modifiers (:mod:`sim.modifier`), which edit the model, attach to
    the world and check their stability before the robot settles.

    Parameters
    ----------
    trial : Trial
    model_set : sim.model_set.ModelSet, optional
        None: the shipped ``paper`` set. Its name and hash are kept in the result.
    numerics : Numerics
        Hulls, servo period and sub-stepping (defaults: the converged configuration).

    Returns
    -------
    TrialResult

    Raises
    ------
    TrialInputError, JointLimitError
        For bad parameters (both are ValueError).
    RobotDescriptionError
        If the robot cannot be loaded.
    sim.compliance.ComplianceError
        If a modifier's spring is too stiff for the servo command period.
    SimulationDiverged
        If the physics blows up.
    EngineError
        If the set's engine is not installed or cannot express what the set asks of it.
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    if model_set is None:
        from .model_set import load_model_set

        model_set = load_model_set()
    modifiers = model_set.modifiers
    model = sim_model(
        trial.robot,
        tol_m=numerics.hull_tol_m,
        max_vertices=numerics.hull_max_vertices,
        joint_map=trial.joint_map,
        merge_fixed=numerics.merge_fixed_links,
        modifiers=modifiers,
    )
    theta_w_deg, theta_l_deg = float(trial.theta_w_deg), float(trial.theta_l_deg)
    phase, cv, dt_s = float(trial.phase), float(trial.cv), trial.dt_s
    heading_deg = float(trial.heading_deg)
    if not np.isfinite(heading_deg):
        raise TrialInputError(f"the heading must be a finite number of degrees; got {trial.heading_deg!r}")
    engine = model_set.engine
    duration_s = float(trial.duration_s)
    dt_s = float(default_dt_s(model.source, engine) if dt_s is None else dt_s)
    _check_inputs(
        theta_w_deg,
        theta_l_deg,
        phase,
        cv,
        duration_s,
        dt_s,
        model.theta_limits_deg,
        control_period_s=numerics.control_period_s,
        n_joints=len(model.joint_map.wing) + len(model.joint_map.leg),
    )
    seed, gen = resolve_seed(trial.rng)
    act, starts, duration_s = _schedule(
        model_set,
        trial.actuation,
        theta_w_deg,
        theta_l_deg,
        phase=phase,
        cv=cv,
        gen=gen,
        duration_s=duration_s,
        attempts=trial.attempts,
    )
    cmd = _servo_commands(
        act,
        starts,
        dt_s=dt_s,
        duration_s=duration_s,
        control_period_s=numerics.control_period_s,
        n_wing=len(model.joint_map.wing),
        n_leg=len(model.joint_map.leg),
    )
    _check_wing_targets(cmd, model.theta_limits_deg["theta_w"], model_set, theta_w_deg)
    substeps = cmd.sub if numerics.engine_substeps else 1
    world = open_world(
        engine,
        model,
        dt_s=dt_s,
        substeps=substeps,
        contact=model_set.contact,
        modifiers=modifiers,
        mujoco=model_set.mujoco,
    )
    with world:
        for m in modifiers:
            m.check_stability(world, cmd.ctrl_s)
        key = None
        if numerics.reuse_settled:
            key = (engine, model.model_hash, repr(model_set.contact), repr(model_set.mujoco), repr(modifiers))
            key += (repr(numerics), dt_s, substeps, cmd.ctrl_s, heading_deg)
        _settle(world, model, cmd, heading_rad=np.deg2rad(heading_deg), reuse_key=key)
        run = _run(world, cmd, trace=trial.trace)
    started = starts[starts <= run.t_end]
    attempt = int(np.searchsorted(starts, run.t_right, side="right")) if run.success else None
    tr = None
    if trial.trace:
        n = len(Trace.COLUMNS)
        a = np.asarray(run.rows, dtype=np.float64).reshape(-1, n + 7)
        tr = Trace(
            *(a[:, k].copy() for k in range(n)),
            a[:, n : n + 3].copy(),
            a[:, n + 3 : n + 6].copy(),
            a[:, n + 6].copy(),
        )
    return TrialResult(
        theta_w_deg=theta_w_deg,
        theta_l_deg=theta_l_deg,
        phase=phase,
        cv=cv,
        seed=seed,
        duration_s=duration_s,
        dt_s=dt_s,
        success=run.success,
        time_to_right_s=run.t_right,
        attempt=attempt,
        phases=tuple(float(x) for x in attempt_phases(started, act)),
        attempt_starts_s=tuple(float(x) for x in started),
        mode=run.mode,
        sim_s=run.t_end,
        wall_s=time.perf_counter() - wall0,
        cpu_s=time.process_time() - cpu0,
        max_tracking_error_deg=float(np.rad2deg(run.max_err)),
        robot_hash=model.robot_hash,
        model_hash=model.model_hash,
        trace=tr,
        model_set=model_set.name,
        model_set_hash=model_set.model_set_hash,
        side=run.side,
        engine=engine,
    )


def _check_wing_targets(
    cmd: _Commands, limits_deg: tuple[float, float], model_set, theta_w_deg: float
) -> None:
    """Refuse wing targets outside the wing joints' range (a measured profile's knots, e.g. opened further by
    ``wing_extra_deg``, are not the command), rather than let pybullet's joint limit clamp them silently."""
    if not cmd.n_ctrl or not cmd.n_wing:
        return
    wing = np.rad2deg(cmd.target_rad[:, : cmd.n_wing])
    lo, hi = limits_deg
    top, bottom = float(wing.max()), float(wing.min())
    if top > hi + 1e-6 or bottom < lo - 1e-6:
        raise JointLimitError(
            f"model set '{model_set.name}' drives a wing joint to {top if top > hi else bottom:.2f} deg at wing "
            f"command {theta_w_deg:g} deg, outside the robot's wing joint range [{lo:g}, {hi:g}] deg; choose a "
            "smaller command or [actuation] wing_extra_deg"
        )


def _schedule(
    model_set,
    actuation: Actuation | None,
    theta_w_deg: float,
    theta_l_deg: float,
    *,
    phase: float,
    cv: float,
    gen: np.random.Generator,
    duration_s: float,
    attempts: int | None,
):
    """The actuation at these angles, the wing openings' start times (noise drawn from ``gen``), and the trial
    length (cut one wing period after the last allowed attempt)."""
    base = actuation or model_set.actuation(theta_w_deg, theta_l_deg)
    act = replace(base, theta_w_deg=theta_w_deg, theta_l_deg=theta_l_deg)
    starts = attempt_starts_s(act, phase=phase, cv=cv, rng=gen, duration_s=duration_s)
    if attempts is not None:
        if int(attempts) != attempts or attempts < 1:
            raise TrialInputError(f"attempts must be a whole number >= 1 (or None); got {attempts!r}")
        starts = starts[: int(attempts)]
        if len(starts) == int(attempts):
            duration_s = min(duration_s, float(starts[-1]) + act.wing_period_s)
    return act, starts, duration_s


@dataclass(frozen=True)
class _Commands:
    """The servo commands of a whole trial, one row per control period (``sub`` physics steps of ``dt_s``)."""

    dt_s: float
    duration_s: float
    sub: int
    ctrl_s: float
    target_rad: NDArray[np.float64]  # held command per control period and joint (the profile mid-period)
    speed_rad_s: NDArray[np.float64]
    end_rad: NDArray[np.float64]  # the profile at the end of each control period (tracking error)
    wing_deg: NDArray[np.float64]
    leg_deg: NDArray[np.float64]
    n_wing: int

    @property
    def n_ctrl(self) -> int:
        return len(self.target_rad)


def _servo_commands(
    act: Actuation,
    starts,
    *,
    dt_s: float,
    duration_s: float,
    control_period_s: float | None,
    n_wing: int,
    n_leg: int,
) -> _Commands:
    # the servos are commanded once per control period (CONTROL_PERIOD_S, a whole number of physics steps)
    sub = max(1, int(round(control_period_s / dt_s))) if control_period_s else 1
    ctrl_s = sub * dt_s
    n_ctrl = int(round(duration_s / ctrl_s))
    t_end_k = np.arange(1, n_ctrl + 1) * ctrl_s  # end of control period k
    t_hold = t_end_k - (
        ctrl_s / 2 if sub > 1 else 0.0
    )  # held command: the profile mid-period (exact on ramps)

    def joint_profiles(t):
        # each wing joint its own profile (the same for all under the idealised profile)
        wing, wing_v = wing_joint_profiles_deg(t, starts, act, n_wing=n_wing)
        leg, leg_v = leg_profile_deg(t, act)
        q = np.deg2rad(np.concatenate([wing, np.repeat(leg[:, None], n_leg, 1)], 1))
        v = np.deg2rad(np.concatenate([wing_v, np.repeat(leg_v[:, None], n_leg, 1)], 1))
        return (wing[:, 0] if act.measured is None else wing.mean(axis=1)), leg, q, v

    _, _, target, speed = joint_profiles(t_hold)
    wing_deg, leg_deg, target_end, _ = joint_profiles(t_end_k)
    return _Commands(
        dt_s,
        duration_s,
        sub,
        ctrl_s,
        target,
        speed,
        target_end,
        wing_deg,
        leg_deg,
        n_wing,
    )


_SETTLED: dict = {}
"""Settled states by what settling depends on (:attr:`Numerics.reuse_settled`), the newest ``_SETTLED_MAX``."""
_SETTLED_MAX = 16


def _settle(
    world: EngineWorld, model, cmd: _Commands, *, heading_rad: float = 0.0, reuse_key: tuple | None = None
) -> None:
    """Place the robot on its back with the joints at zero, turned by ``heading_rad``, and let it settle for
    ``SETTLE_S``; with ``reuse_key``, restore the state a world settled under the same key left, if any, and keep
    this one's otherwise (if the engine can restore it)."""
    snap = _SETTLED.get(reuse_key) if reuse_key is not None else None
    if snap is not None:
        world.restore(snap)
    else:
        zeros = np.zeros(len(world.driven))
        world.place(np.deg2rad(model.rest_pitch_deg), 0.0, joints_rad=zeros, heading_rad=heading_rad)
        world.drive(zeros, zeros, kp=min(1.0, cmd.dt_s / SERVO_TAU_S), kd=1.0)
        world.advance(cmd.sub * int(round(SETTLE_S / cmd.ctrl_s)))
        if reuse_key is not None and (snap := world.snapshot()) is not None:
            while len(_SETTLED) >= _SETTLED_MAX:
                del _SETTLED[next(iter(_SETTLED))]
            _SETTLED[reuse_key] = snap
    v, w = world.base_velocity()
    if np.linalg.norm(v) > 5e-3 or np.linalg.norm(w) > 0.05:
        log.warning(
            "robot still moving after %.1f s of settling (%.3g m/s, %.3g rad/s)",
            SETTLE_S,
            np.linalg.norm(v),
            np.linalg.norm(w),
        )
    world.check_finite(0.0)
    if world.up_in_body()[2] <= 0:
        raise SimulationDiverged("the robot did not settle on its back; check the robot and --dt")


@dataclass
class _Run:
    success: bool = False
    t_right: float | None = None
    mode: str | None = None
    side: int | None = None
    t_end: float = 0.0
    max_err: float = 0.0
    rows: list = field(default_factory=list)


_CHUNK = 250
"""Control periods whose commands :func:`_run` converts to Python floats at a time (most trials stop early)."""


def _run(world: EngineWorld, cmd: _Commands, *, trace: bool) -> _Run:
    """Drive the servos period by period; the trial succeeds once the body has stayed upright (u_z < 0) for
    ``UPRIGHT_HOLD_S``, checked every ``CHECK_EVERY_S``."""
    kp = min(1.0, cmd.dt_s / SERVO_TAU_S)
    check_every = max(1, int(round(CHECK_EVERY_S / cmd.ctrl_s)))
    trace_every = max(1, int(round(TRACE_EVERY_S / cmd.ctrl_s)))
    run = _Run(t_end=cmd.duration_s)
    upright_since, u_first = None, None
    for i in range(cmd.n_ctrl):
        k = i % _CHUNK
        if k == 0:  # the engines take Python floats; convert the commands as the trial reaches them
            target, speed, end = (
                a[i : i + _CHUNK].tolist() for a in (cmd.target_rad, cmd.speed_rad_s, cmd.end_rad)
            )
        world.drive(target[k], speed[k], kp=kp, kd=1.0)
        world.advance(cmd.sub)
        ti = (i + 1) * cmd.ctrl_s
        if trace and (i + 1) % trace_every == 0:
            run.rows.append(_trace_row(world, ti, cmd.wing_deg[i], cmd.leg_deg[i], cmd.n_wing))
        if (i + 1) % check_every:
            continue
        world.check_finite(ti)
        err = max(abs(a - b) for a, b in zip(world.joint_positions_rad(), end[k], strict=True))
        run.max_err = max(run.max_err, err)
        u = world.up_in_body()
        if u[2] < 0:
            if upright_since is None:
                upright_since, u_first = ti, u
            if ti - upright_since >= UPRIGHT_HOLD_S - 1e-12:
                run.success, run.t_right, run.t_end = True, upright_since, ti
                run.mode = "roll" if abs(u_first[1]) >= abs(u_first[0]) else "somersault"
                run.side = 1 if pitch_roll_from_up(u_first)[1] >= 0 else -1
                break
        else:
            upright_since = None
    return run


def _trace_row(
    world: EngineWorld, t_s: float, wing_cmd_deg: float, leg_cmd_deg: float, n_wing: int
) -> list[float]:
    u = world.up_in_body()
    p, r = pitch_roll_from_up(u)
    q = np.rad2deg(world.joint_positions_rad())
    h = world.com_height_m()
    return [
        t_s,
        float(np.rad2deg(p)),
        float(np.rad2deg(r)),
        float(u[2]),
        h,
        world.mass_kg * G_M_S2 * h,
        wing_cmd_deg,
        float(q[:n_wing].mean()),
        leg_cmd_deg,
        float(q[n_wing:].mean()),
        *world.angular_velocity_in_body().tolist(),
        *world.com_velocity_m_s().tolist(),
        float(np.rad2deg(world.heading_rad())),
    ]
