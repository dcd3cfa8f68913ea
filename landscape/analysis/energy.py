"""The energy budget of self-righting attempts: the body's kinetic energy against the barrier it faces, one code
path for simulated traces and the physical robot's recordings (edge layer: joins sim, recordings and landscapes).

A trace becomes a :class:`Motion` (time, body orientation, wing and leg angle, the body's angular velocity in the
body frame, the CoM's velocity when known, and the attempts with their outcome): :func:`simulated_motion` from a
trial run with ``trace=True`` (velocities from the engine), :func:`landscape.analysis.physical.motion.recorded_motion` from a
recording (angular
velocity from the gyro, or from the differentiated quaternions, turned into the body frame by the IMU's mounting).
:func:`energy_trace` then measures every sample the same way:

- **barrier** at the appendage pose held at the time, interpolated (bilinear in theta_w and signed theta_l) in a
  :class:`BarrierTable`: a barrier map (:func:`landscape.computation.barrier_map`, exact method) over the poses
  the traces visit; its direction ("roll" or "pitch") and side (the sign of the saddle's roll for a roll-over,
  of its pitch for a somersault) are the nearest mapped pose's;
- **height** above the current basin's minimum: ``m g z_com`` at the sample's orientation and pose
  (:func:`landscape.energy.height_at`) minus the start minimum's energy at that pose (interpolated as the
  barrier), so both are measured from the same minimum;
- **kinetic energy** of rotation about the CoM with the posed robot's inertia ``I`` (body frame), split into the
  body-axis shares ``0.5 omega_i (I omega)_i`` (x: roll, y: pitch, z: yaw), which sum to ``0.5 omega^T I omega``;
  plus the CoM's translation ``0.5 m |v|^2``. A recording has no CoM velocity: it is taken as the body's rolling
  about its lowest hull point, ``v = omega x (com - pivot)`` (no slip, no bounce).

Per attempt (:func:`attempt_energies`), over the samples from its opening until its wings start closing, the next
opening or the body first turns upright (:func:`attempt_window`): the largest kinetic energy in the barrier's
direction (the body-axis share: roll for a roll-over, pitch for a somersault) and when it peaks, the lowest barrier
the attempt meets (with its direction and side), and the energy margin, the largest
value of that kinetic energy plus height above the basin minus that barrier (``margin_total_mj``: the same with
the whole kinetic energy). Energies in the rows are mJ.

The module is longer than the others because it is one computation, the budget, with the types it passes along
(body, barrier table, motion, trace, per-attempt rows); the recordings' side is
:mod:`landscape.analysis.physical.motion`.

It is one concept, the energy budget of an attempt (barrier, height, kinetic energy, per-attempt rows), hence
its length.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from geometry.errors import UsageError
from geometry.frames import up_vector
from landscape.energy import G_M_S2, height_at

WING_STEP_DEG = 5.0
"""Spacing of the barrier table along theta_w, degrees."""
LEG_STEP_DEG = 7.5
"""Spacing of the barrier table along the signed leg angle, degrees."""
POSE_ROUND_DEG = 0.5
"""Joint angles are rounded to this before posing the robot for inertia and height, degrees (poses are cached)."""
SOURCES = ("simulated", "recorded")


# ------------------------------------------------------------------------------------------------ kinetic energy
def rotational_shares_j(omega_body_rad_s: ArrayLike, inertia_kg_m2: ArrayLike) -> NDArray[np.float64]:
    """Body-axis shares ``0.5 omega_i (I omega)_i`` of the rotational kinetic energy about the CoM, J.

    Parameters
    ----------
    omega_body_rad_s : array_like of shape (..., 3)
        Angular velocity in the body frame, rad/s.
    inertia_kg_m2 : array_like of shape (3, 3) or (..., 3, 3)
        Inertia tensor about the CoM in the body frame, kg m^2.

    Returns
    -------
    shares_j : ndarray of shape (..., 3)
        Roll (x), pitch (y) and yaw (z) shares, J; they sum to ``0.5 omega^T I omega``.

    Examples
    --------
    >>> I = np.diag([1.0, 2.0, 3.0])
    >>> rotational_shares_j([1.0, 1.0, 0.0], I).tolist()
    [0.5, 1.0, 0.0]
    """
    w = np.asarray(omega_body_rad_s, dtype=np.float64)
    inertia = np.asarray(inertia_kg_m2, dtype=np.float64)
    iw = np.einsum("...ij,...j->...i", inertia, w)
    return 0.5 * w * iw


def translational_energy_j(mass_kg: float, velocity_m_s: ArrayLike) -> NDArray[np.float64]:
    """Kinetic energy of the CoM's translation ``0.5 m |v|^2``, J (``velocity_m_s`` of shape (..., 3), m/s).

    Examples
    --------
    >>> float(translational_energy_j(2.0, [3.0, 4.0, 0.0]))
    25.0
    """
    v = np.asarray(velocity_m_s, dtype=np.float64)
    return 0.5 * float(mass_kg) * np.einsum("...i,...i->...", v, v)


# ------------------------------------------------------------------------------------------------ the body
@dataclass(frozen=True)
class BodyModel:
    """The robot as a model set poses it along a trace: every wing joint at theta_w (idealised sets) or each at
    its own share of it (a measured set: joint ``j`` at ``theta_w * wing_shares[j]``, the shares of the set's
    measured plateaus, mean 1), the leg joints at the signed leg angle.

    Attributes
    ----------
    robot : geometry.Robot
        The robot as the set models it (:meth:`sim.model_set.ModelSet.robot_for`).
    wing_shares : tuple of float or None
        Per wing joint (the joint map's order); None: every wing joint at theta_w.
    """

    robot: object
    wing_shares: tuple[float, ...] | None = None
    _poses: dict = field(default_factory=dict, repr=False, compare=False)

    def wing_joints_deg(self, theta_w_deg: float) -> dict[str, float] | None:
        """Each wing joint's angle at ``theta_w_deg`` (None: every joint at theta_w), degrees."""
        if self.wing_shares is None:
            return None
        names = self.robot.joint_map.wing
        return {n: float(theta_w_deg) * s for n, s in zip(names, self.wing_shares, strict=True)}

    @cached_property
    def limits_deg(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """The theta_w range that keeps every wing joint within its limits, and the leg's range, degrees."""
        lim = self.robot.theta_limits_deg()
        top_share = max(self.wing_shares) if self.wing_shares else 1.0
        return (lim["theta_w"][0] / top_share, lim["theta_w"][1] / top_share), lim["theta_l"]

    def pose(self, theta_w_deg: float, theta_l_deg: float):
        """The posed rigid body (:class:`geometry.Pose`) at the angles rounded to ``POSE_ROUND_DEG`` and held within
        the joints' limits (a measured profile can dip a degree below a closed wing), cached."""
        (w_lo, w_hi), (l_lo, l_hi) = self.limits_deg
        key = (_round(min(max(theta_w_deg, w_lo), w_hi)), _round(min(max(theta_l_deg, l_lo), l_hi)))
        if key not in self._poses:
            from landscape.computation import posed

            self._poses[key] = posed(self.robot, key[0], key[1], self.wing_joints_deg(key[0]))
        return self._poses[key]


def _round(x: float) -> float:
    return float(np.round(float(x) / POSE_ROUND_DEG) * POSE_ROUND_DEG) + 0.0


def body_model(robot, model_set=None, *, theta_w_cmd_deg: float | None = None) -> BodyModel:
    """The robot as ``model_set`` (a :class:`sim.model_set.ModelSet`, None: as it is) poses it; a set with a
    measured actuation holds each wing servo at its share of its measured plateaus at the command
    ``theta_w_cmd_deg`` (default: the set's first measured command)."""
    if model_set is None:
        return BodyModel(robot)
    robot = model_set.robot_for(robot)
    if model_set.measured is None:
        return BodyModel(robot)
    cmd = float(model_set.measured.wing_command_deg[0]) if theta_w_cmd_deg is None else float(theta_w_cmd_deg)
    plateaus = np.asarray(
        list(model_set.wing_joints_deg(robot.joint_map.wing, cmd).values()), dtype=np.float64
    )
    return BodyModel(robot, tuple((plateaus / plateaus.mean()).tolist()))


# ------------------------------------------------------------------------------------------------ barrier table
@dataclass(frozen=True)
class BarrierTable:
    """Minimal righting barrier and start-minimum energy over a grid of poses, for interpolation.

    Attributes
    ----------
    theta_w_deg : ndarray of shape (W,)
        Wing angles, degrees, increasing.
    theta_l_deg : ndarray of shape (L,)
        Signed leg angles, degrees, increasing.
    barrier_j, minimum_j : ndarray of shape (W, L)
        Minimal righting barrier (nan where the robot cannot right) and the start minimum's potential energy, J.
    direction : ndarray of shape (W, L) of str
        "roll" or "pitch" ("" where no barrier).
    side : ndarray of shape (W, L) of int
        +1 or -1: the sign of the saddle's roll (roll-over) or pitch (somersault); 0 where no barrier.
    """

    theta_w_deg: NDArray[np.float64]
    theta_l_deg: NDArray[np.float64]
    barrier_j: NDArray[np.float64]
    minimum_j: NDArray[np.float64]
    direction: NDArray[np.str_]
    side: NDArray[np.int64]

    def at(self, theta_w_deg: ArrayLike, theta_l_deg: ArrayLike):
        """Barrier (J), minimum energy (J), direction and side at the poses ``(theta_w_deg, theta_l_deg)`` (arrays
        of one shape), bilinear in the two angles (clipped to the table), direction and side of the nearest
        mapped pose. A barrier next to an unmapped (nan) node is nan.

        Examples
        --------
        >>> t = BarrierTable(np.array([0.0, 10.0]), np.array([-5.0, 5.0]), np.array([[4.0, 4.0], [2.0, 2.0]]),
        ...                  np.zeros((2, 2)), np.array([["pitch"] * 2, ["roll"] * 2]), np.ones((2, 2), int))
        >>> b, m, d, s = t.at([2.5, 10.0], [0.0, 0.0])
        >>> b.tolist(), d.tolist()
        ([3.5, 2.0], ['pitch', 'roll'])
        """
        w = np.asarray(theta_w_deg, dtype=np.float64)
        leg = np.asarray(theta_l_deg, dtype=np.float64)
        i, fi = _cell(self.theta_w_deg, w)
        j, fj = _cell(self.theta_l_deg, leg)

        def lerp(a):
            i1 = np.minimum(i + 1, len(self.theta_w_deg) - 1)
            j1 = np.minimum(j + 1, len(self.theta_l_deg) - 1)
            return (
                a[i, j] * (1 - fi) * (1 - fj)
                + a[i1, j] * fi * (1 - fj)
                + a[i, j1] * (1 - fi) * fj
                + a[i1, j1] * fi * fj
            )

        with np.errstate(invalid="ignore"):
            b, m = lerp(self.barrier_j), lerp(self.minimum_j)
        ni = np.where(fi >= 0.5, np.minimum(i + 1, len(self.theta_w_deg) - 1), i)
        nj = np.where(fj >= 0.5, np.minimum(j + 1, len(self.theta_l_deg) - 1), j)
        return b, m, self.direction[ni, nj], self.side[ni, nj]


def _cell(axis: NDArray[np.float64], x: NDArray[np.float64]):
    """Lower node index and fraction along a sorted axis, clipped to it."""
    if len(axis) == 1:
        return np.zeros(x.shape, dtype=np.int64), np.zeros(x.shape)
    xc = np.clip(x, axis[0], axis[-1])
    i = np.clip(np.searchsorted(axis, xc, side="right") - 1, 0, len(axis) - 2)
    f = (xc - axis[i]) / (axis[i + 1] - axis[i])
    return i, f


def table_axes(
    wing_deg: ArrayLike,
    leg_deg: ArrayLike,
    *,
    wing_limits_deg: tuple[float, float] = (-math.inf, math.inf),
    leg_limits_deg: tuple[float, float] = (-math.inf, math.inf),
    wing_step_deg: float = WING_STEP_DEG,
    leg_step_deg: float = LEG_STEP_DEG,
) -> tuple[list[float], list[float]]:
    """The grid of a barrier table that covers the poses a trace visits: theta_w from 0 (or the smallest visited)
    to the largest, the signed leg angle symmetric about 0, on ``*_step_deg`` multiples clipped to the limits.

    Examples
    --------
    >>> table_axes([0.0, 71.0], [-29.0, 30.0])
    ([0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0], [-30.0, -22.5, -15.0, -7.5, 0.0, 7.5, 15.0, 22.5, 30.0])
    """
    w = np.asarray(wing_deg, dtype=np.float64)
    leg = np.asarray(leg_deg, dtype=np.float64)
    lo = min(0.0, math.floor(float(np.nanmin(w)) / wing_step_deg) * wing_step_deg)
    hi = math.ceil(float(np.nanmax(w)) / wing_step_deg - 1e-9) * wing_step_deg
    ws = sorted(
        {
            float(min(max(x, wing_limits_deg[0]), wing_limits_deg[1]))
            for x in np.arange(lo, hi + 1e-9, wing_step_deg)
        }
    )
    span = math.ceil(float(np.nanmax(np.abs(leg))) / leg_step_deg - 1e-9) * leg_step_deg
    ls = np.arange(-span, span + 1e-9, leg_step_deg) if span > 0 else np.zeros(1)
    ls = sorted({float(min(max(x, leg_limits_deg[0]), leg_limits_deg[1])) + 0.0 for x in ls})
    return ws, ls


def barrier_table(
    body: BodyModel, theta_w_deg: Sequence[float], theta_l_deg: Sequence[float], *, progress=None
) -> BarrierTable:
    """The barrier map (exact method, no sector exits) of ``body`` over ``theta_w_deg x theta_l_deg``.

    Raises
    ------
    UsageError, JointLimitError
        If the robot has no joints or an angle lies outside its joint limits.
    """
    from landscape.computation import barrier_map

    ws, ls = [float(x) for x in theta_w_deg], [float(x) for x in theta_l_deg]
    joints = None if body.wing_shares is None else {w: body.wing_joints_deg(w) for w in ws}
    bm = barrier_map(
        body.robot, ws, ls, method="exact", sector_exits=False, progress=progress, wing_joints_deg=joints
    )
    shape = (len(ws), len(ls))
    minimum = np.zeros(shape)
    direction = np.full(shape, "", dtype=object)
    side = np.zeros(shape, dtype=np.int64)
    for k, c in enumerate(bm.computations):
        i, j = divmod(k, len(ls))
        minimum[i, j] = c.minimum.energy_j
        r = c.barrier.righting
        if r is not None:
            direction[i, j] = r.direction
            s = r.saddle_roll_deg if r.direction == "roll" else r.saddle_pitch_deg
            side[i, j] = 1 if s >= 0 else -1
    return BarrierTable(
        np.asarray(ws), np.asarray(ls), bm.righting_j.copy(), minimum, direction.astype(str), side
    )


# ------------------------------------------------------------------------------------------------ motions
@dataclass(frozen=True)
class Motion:
    """One trace of the body, simulated or recorded, with its attempts.

    Attributes
    ----------
    source : {"simulated", "recorded"}
    trial : str
        The trial's name (a recording's file, a simulated trial's number or seed).
    theta_w_deg, theta_l_deg : float
        The commanded wing angle and leg amplitude, degrees.
    t_s, pitch_deg, roll_deg, wing_deg, leg_deg : ndarray of shape (N,)
        Time (s), body pitch and roll (degrees, ``geometry/frames.py``), wing angle (mean of the wing joints)
        and signed leg angle (degrees) at each sample.
    omega_body_rad_s : ndarray of shape (N, 3)
        The body's angular velocity in the body frame, rad/s.
    com_velocity_m_s : ndarray of shape (N, 3) or None
        The CoM's velocity, m/s; None: rolling about the lowest hull point (see the module docstring).
    attempt_starts_s : ndarray of shape (K,)
        When each attempt (wing opening) starts, s.
    attempt_success : ndarray of shape (K,) of bool
        Whether the body turned upright during the attempt.
    phases : ndarray of shape (K,)
        The leg's phase at each opening, a fraction of its period (nan with the leg still).
    """

    source: str
    trial: str
    theta_w_deg: float
    theta_l_deg: float
    t_s: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    wing_deg: NDArray[np.float64]
    leg_deg: NDArray[np.float64]
    omega_body_rad_s: NDArray[np.float64]
    com_velocity_m_s: NDArray[np.float64] | None
    attempt_starts_s: NDArray[np.float64]
    attempt_success: NDArray[np.bool_]
    phases: NDArray[np.float64]

    @property
    def up_z(self) -> NDArray[np.float64]:
        """World-up's body-z component, ``cos(pitch) cos(roll)``."""
        return np.cos(np.deg2rad(self.pitch_deg)) * np.cos(np.deg2rad(self.roll_deg))


def simulated_motion(result, *, trial: str | None = None) -> Motion:
    """The :class:`Motion` of a trial run with ``trace=True`` (:class:`sim.trial.TrialResult`).

    Raises
    ------
    UsageError
        If the result has no trace or its trace no velocities.
    """
    tr = result.trace
    if tr is None or tr.omega_body_rad_s is None:
        raise UsageError("the trial has no trace with velocities; run it with run_trial(..., trace=True)")
    starts = np.asarray(result.attempt_starts_s, dtype=np.float64)
    success = np.array([result.success and k + 1 == result.attempt for k in range(len(starts))], dtype=bool)
    return Motion(
        "simulated",
        str(result.seed if trial is None else trial),
        float(result.theta_w_deg),
        float(result.theta_l_deg),
        tr.t_s,
        tr.pitch_deg,
        tr.roll_deg,
        tr.wing_deg,
        tr.leg_deg,
        tr.omega_body_rad_s,
        tr.com_velocity_m_s,
        starts,
        success,
        np.asarray(result.phases, dtype=np.float64),
    )


# ------------------------------------------------------------------------------------------------ the budget
@dataclass(frozen=True)
class EnergyTrace:
    """The energy budget of one :class:`Motion` at each sample, J.

    Attributes
    ----------
    t_s : ndarray of shape (N,)
    ke_body_j : ndarray of shape (N, 3)
        Roll, pitch and yaw shares of the rotational kinetic energy about the CoM, J.
    ke_trans_j : ndarray of shape (N,)
        The CoM's translation, J.
    height_j : ndarray of shape (N,)
        Potential energy above the current basin's minimum, J.
    barrier_j : ndarray of shape (N,)
        Minimal righting barrier at the pose held, J (nan where none).
    direction : ndarray of shape (N,) of str
    side : ndarray of shape (N,) of int
        The barrier's direction and side (:class:`BarrierTable`).
    """

    t_s: NDArray[np.float64]
    ke_body_j: NDArray[np.float64]
    ke_trans_j: NDArray[np.float64]
    height_j: NDArray[np.float64]
    barrier_j: NDArray[np.float64]
    direction: NDArray[np.str_]
    side: NDArray[np.int64]

    def ke_along_j(self, direction: NDArray[np.str_] | None = None) -> NDArray[np.float64]:
        """Kinetic energy in the barrier's direction, J: the roll (x) share for a roll barrier, the pitch (y)
        share for a somersault, the whole rotation where there is no barrier (``direction`` default: the
        barrier's at each sample)."""
        d = self.direction if direction is None else np.asarray(direction)
        rot = self.ke_rot_j
        return np.where(d == "roll", self.ke_body_j[:, 0], np.where(d == "pitch", self.ke_body_j[:, 1], rot))

    @property
    def ke_rot_j(self) -> NDArray[np.float64]:
        """Rotational kinetic energy about the CoM, J."""
        return self.ke_body_j.sum(axis=1)

    @property
    def ke_j(self) -> NDArray[np.float64]:
        """Total kinetic energy, J."""
        return self.ke_rot_j + self.ke_trans_j


def energy_trace(motion: Motion, body: BodyModel, table: BarrierTable) -> EnergyTrace:
    """Kinetic energy, height above the basin and barrier at every sample of ``motion`` (module docstring)."""
    n = len(motion.t_s)
    shares = np.zeros((n, 3))
    height = np.zeros(n)
    trans = np.zeros(n)
    keys: dict[tuple[float, float], list[int]] = {}
    for k, (w, leg) in enumerate(zip(motion.wing_deg, motion.leg_deg, strict=True)):
        keys.setdefault((_round(w), _round(leg)), []).append(k)
    up = up_vector(np.deg2rad(motion.pitch_deg), np.deg2rad(motion.roll_deg))
    for (w, leg), idx in keys.items():
        idx = np.asarray(idx)
        pose = body.pose(w, leg)
        omega = motion.omega_body_rad_s[idx]
        shares[idx] = rotational_shares_j(omega, pose.inertia_kg_m2)
        height[idx] = height_at(pose, motion.pitch_deg[idx], motion.roll_deg[idx]) * pose.mass_kg * G_M_S2
        if motion.com_velocity_m_s is not None:
            trans[idx] = translational_energy_j(pose.mass_kg, motion.com_velocity_m_s[idx])
        else:
            pts = pose.hull_points_m
            pivot = pts[np.argmax(-(up[idx] @ pts.T), axis=1)]
            trans[idx] = translational_energy_j(pose.mass_kg, np.cross(omega, pose.com_m - pivot))
    b, m, d, s = table.at(motion.wing_deg, motion.leg_deg)
    return EnergyTrace(motion.t_s, shares, trans, height - m, b, d, s)


@dataclass(frozen=True)
class AttemptEnergy:
    """The energy budget of one attempt (energies in mJ).

    Attributes
    ----------
    source, trial : str
    theta_w_deg, theta_l_deg : float
        The commands, degrees.
    attempt : int
        1-based.
    success : bool
        The body turned upright during the attempt.
    phase : float
        The leg's phase at the opening (nan with the leg still).
    start_s : float
        When the attempt opens, s.
    ke_roll_mj, ke_pitch_mj, ke_yaw_mj, ke_trans_mj : float
        The largest value of each share over the attempt, mJ.
    ke_peak_mj : float
        The largest kinetic energy in the barrier's direction (its body-axis share), mJ.
    ke_peak_t_s : float
        When it peaks, s after the opening.
    barrier_mj : float
        The lowest barrier the attempt meets, mJ (nan if none).
    direction : str
        Its direction ("roll", "pitch"; "" if none).
    side : int
        Its side (+1, -1; 0 if none).
    margin_mj : float
        The energy margin: the largest value of kinetic energy in the barrier's direction plus height above the
        basin minus the barrier, mJ.
    margin_total_mj : float
        The same with the whole kinetic energy (rotation and translation), mJ.
    """

    source: str
    trial: str
    theta_w_deg: float
    theta_l_deg: float
    attempt: int
    success: bool
    phase: float
    start_s: float
    ke_roll_mj: float
    ke_pitch_mj: float
    ke_yaw_mj: float
    ke_trans_mj: float
    ke_peak_mj: float
    ke_peak_t_s: float
    barrier_mj: float
    direction: str
    side: int
    margin_mj: float
    margin_total_mj: float

    CSV_COLUMNS = (
        "source",
        "theta_w_deg",
        "theta_l_deg",
        "trial",
        "attempt",
        "success",
        "phase",
        "start_s",
        "ke_roll_mj",
        "ke_pitch_mj",
        "ke_yaw_mj",
        "ke_trans_mj",
        "ke_peak_mj",
        "ke_peak_t_s",
        "barrier_mj",
        "direction",
        "side",
        "margin_mj",
        "margin_total_mj",
    )

    def row(self) -> dict:
        """The CSV row (``CSV_COLUMNS``; success as 0/1)."""
        d = {c: getattr(self, c) for c in self.CSV_COLUMNS}
        d["success"] = int(self.success)
        return d


CLOSING_FRACTION = 0.95
"""An attempt's wings start closing when, after reaching this fraction of the attempt's largest wing angle, they
fall below it again."""


def attempt_window(
    t_s: NDArray[np.float64],
    wing_deg: NDArray[np.float64],
    up_z: NDArray[np.float64],
    start_s: float,
    end_s: float,
) -> NDArray[np.int64]:
    """Sample indices of one attempt while it can right: from its opening at ``start_s`` until the wings start
    closing (:data:`CLOSING_FRACTION`), the next opening ``end_s`` or the body first turns upright (u_z < 0),
    whichever comes first.

    Examples
    --------
    >>> t = np.arange(8) * 0.1
    >>> attempt_window(t, np.array([0, 30, 60, 60, 59, 40, 0, 0.0]), np.ones(8), 0.05, 1.0).tolist()
    [1, 2, 3, 4]
    """
    sel = np.flatnonzero((t_s >= start_s) & (t_s < end_s))
    if not len(sel):
        return sel
    w = wing_deg[sel]
    top = float(w.max())
    reached = np.flatnonzero(w >= CLOSING_FRACTION * top)
    if top > 0 and len(reached):
        closing = np.flatnonzero((np.arange(len(sel)) > reached[0]) & (w < CLOSING_FRACTION * top))
        if len(closing):
            sel = sel[: closing[0]]
    up = np.flatnonzero(up_z[sel] < 0)
    return sel[: up[0]] if len(up) else sel


def attempt_energies(motion: Motion, et: EnergyTrace) -> list[AttemptEnergy]:
    """One :class:`AttemptEnergy` per attempt of ``motion``, over its :func:`attempt_window` (attempts without a
    sample in it are left out)."""
    t = motion.t_s
    up_z = motion.up_z
    starts = motion.attempt_starts_s
    ends = np.concatenate([starts[1:], [np.inf]])
    along = et.ke_along_j()
    out = []
    for k, (t0, t1) in enumerate(zip(starts, ends, strict=True)):
        idx = attempt_window(t, motion.wing_deg, up_z, float(t0), float(t1))
        if not len(idx):
            continue
        b = et.barrier_j[idx]
        finite = np.isfinite(b)
        if finite.any():
            kb = idx[np.flatnonzero(finite)[np.argmin(b[finite])]]
            barrier, direction, side = float(et.barrier_j[kb]), str(et.direction[kb]), int(et.side[kb])
        else:
            barrier, direction, side = math.nan, "", 0
        kp = int(np.argmax(along[idx]))
        with np.errstate(invalid="ignore"):
            margin = along[idx] + et.height_j[idx] - et.barrier_j[idx]
            total = et.ke_j[idx] + et.height_j[idx] - et.barrier_j[idx]
        out.append(
            AttemptEnergy(
                motion.source,
                motion.trial,
                motion.theta_w_deg,
                motion.theta_l_deg,
                k + 1,
                bool(motion.attempt_success[k]),
                float(motion.phases[k]) if k < len(motion.phases) else math.nan,
                float(t0),
                *(float(et.ke_body_j[idx, a].max()) * 1e3 for a in range(3)),
                float(et.ke_trans_j[idx].max()) * 1e3,
                float(along[idx][kp]) * 1e3,
                float(t[idx[kp]] - t0),
                barrier * 1e3,
                direction,
                side,
                _nanmax(margin) * 1e3,
                _nanmax(total) * 1e3,
            )
        )
    return out


def _nanmax(a: NDArray[np.float64]) -> float:
    return float(np.nanmax(a)) if np.isfinite(a).any() else math.nan


def energy_budget(
    motions: Sequence[Motion], body: BodyModel, *, table: BarrierTable | None = None, progress=None
) -> tuple[BarrierTable, list[EnergyTrace], list[AttemptEnergy]]:
    """The energy budget of several motions of one robot: one barrier table over every pose they visit (unless
    ``table`` is given), each motion's :class:`EnergyTrace` and all their attempts.

    Raises
    ------
    UsageError
        If ``motions`` is empty.
    """
    if not motions:
        raise UsageError("no trace to measure: give at least one simulated or recorded trial")
    if table is None:
        wing_lim, leg_lim = body.limits_deg  # the joint driven furthest stays within its limit
        ws, ls = table_axes(
            np.concatenate([m.wing_deg for m in motions]),
            np.concatenate([m.leg_deg for m in motions]),
            wing_limits_deg=wing_lim,
            leg_limits_deg=leg_lim,
        )
        table = barrier_table(body, ws, ls, progress=progress)
    traces = [energy_trace(m, body, table) for m in motions]
    rows = [a for m, et in zip(motions, traces, strict=True) for a in attempt_energies(m, et)]
    return table, traces, rows


@dataclass(frozen=True)
class SignAgreement:
    """How often a predictor's sign matches the attempts' outcomes.

    Attributes
    ----------
    name : str
    attempts, correct : int
    accuracy, ci_low, ci_high : float
        ``correct / attempts`` and its Wilson 95 % interval.
    """

    name: str
    attempts: int
    correct: int
    accuracy: float
    ci_low: float
    ci_high: float


def sign_agreement(rows: Sequence[AttemptEnergy]) -> list[SignAgreement]:
    """Predictors of each attempt's outcome, scored on the ``rows`` with a finite barrier and margin: the energy
    margin's sign (righted when ``margin_mj > 0``; nothing fitted), the same with the whole kinetic energy
    (``margin_total_mj``), and the barrier alone (righted when
    the barrier lies below a threshold: the one that scores best on these same rows, so the baseline's accuracy
    is an upper bound for any barrier threshold).

    Examples
    --------
    >>> mk = lambda b, m, s: AttemptEnergy("recorded", "t", 60.0, 0.0, 1, s, 0.0, 0.0, 0, 0, 0, 0, 0, 0, b, "roll", 1, m, m)
    >>> [(a.name, a.correct) for a in sign_agreement([mk(1.0, 1.0, True), mk(5.0, -1.0, False), mk(2.0, 1.0, False)])]
    [('margin > 0', 2), ('whole-KE margin > 0', 2), ('barrier < 1.5 mJ', 3)]
    """
    from landscape.analysis.trials import wilson_interval

    ok = [r for r in rows if math.isfinite(r.barrier_mj) and math.isfinite(r.margin_mj)]
    out = []
    if not ok:
        return out
    y = np.array([r.success for r in ok])
    b = np.array([r.barrier_mj for r in ok])
    levels = np.unique(b)
    cands = np.concatenate([[levels[0] - 1.0], 0.5 * (levels[1:] + levels[:-1]), [levels[-1] + 1.0]])
    cut = float(max(cands, key=lambda c: (int(((b < c) == y).sum()), -c)))
    for name, pred in (
        ("margin > 0", np.array([r.margin_mj > 0 for r in ok])),
        ("whole-KE margin > 0", np.array([r.margin_total_mj > 0 for r in ok])),
        (f"barrier < {cut:.3g} mJ", np.array([r.barrier_mj < cut for r in ok])),
    ):
        k = int((pred == y).sum())
        lo, hi = wilson_interval(k, len(ok))
        out.append(SignAgreement(name, len(ok), k, k / len(ok), lo, hi))
    return out
