"""The robot's recordings as motions for the energy budget (:mod:`landscape.analysis.energy`): orientation,
angular velocity in the body frame, the wing and leg angles the model set's actuation gives, and the lab's attempts.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from geometry.frames import pitch_roll_from_up
from landscape.analysis.energy import BodyModel, Motion, body_model

GYRO_MEDIAN_SAMPLES = 3
"""The gyro, and the rates from differentiated quaternions, are median-filtered over this many samples (the
recorded gyro has single-sample spikes)."""


def _median3(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """Running median over ``GYRO_MEDIAN_SAMPLES`` samples along axis 0 (the ends kept)."""
    k = GYRO_MEDIAN_SAMPLES // 2
    if len(a) < GYRO_MEDIAN_SAMPLES:
        return a.copy()
    win = np.stack([a[i : len(a) - 2 * k + i] for i in range(2 * k + 1)])
    out = a.copy()
    out[k : len(a) - k] = np.median(win, axis=0)
    return out


def quaternion_rates_rad_s(
    t_s: ArrayLike, quat_xyzw: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Angular velocity in the rotating frame from body-to-world quaternions: the rotation between consecutive
    samples, ``2 log(q_k^-1 q_k+1) / dt``, at the midpoints of the sample times.

    Returns
    -------
    t_mid_s : ndarray of shape (N - 1,)
    omega_rad_s : ndarray of shape (N - 1, 3)
        In the frame the quaternions rotate from, rad/s.

    Examples
    --------
    >>> t = np.array([0.0, 0.1])
    >>> h = 0.5 * np.deg2rad(9.0)   # 9 deg about z in 0.1 s: 90 deg/s
    >>> q = np.array([[0, 0, 0, 1.0], [0, 0, np.sin(h), np.cos(h)]])
    >>> np.rad2deg(quaternion_rates_rad_s(t, q)[1]).round(9).tolist()
    [[0.0, 0.0, 90.0]]
    """
    t = np.asarray(t_s, dtype=np.float64)
    q = np.asarray(quat_xyzw, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    a, b = q[:-1], q[1:]
    # conj(a) * b, quaternions (x, y, z, w)
    av, aw = -a[:, :3], a[:, 3]
    bv, bw = b[:, :3], b[:, 3]
    w = aw * bw - np.einsum("ij,ij->i", av, bv)
    v = aw[:, None] * bv + bw[:, None] * av + np.cross(av, bv)
    sign = np.where(w < 0, -1.0, 1.0)  # the short way round
    w, v = w * sign, v * sign[:, None]
    s = np.linalg.norm(v, axis=1)
    angle = 2.0 * np.arctan2(s, w)
    axis = np.divide(v, s[:, None], out=np.zeros_like(v), where=s[:, None] > 0)
    dt = np.diff(t)
    return 0.5 * (t[:-1] + t[1:]), axis * (angle / dt)[:, None]


def recorded_motion(
    rec, *, mount_deg: float, actuation, use_gyro: bool = True, leg_lag_s: float | None = None
) -> Motion:
    """The :class:`Motion` of a recording (:class:`landscape.analysis.physical.recording.Recording`).

    Orientation and angular velocity are turned into the body frame ``mount_deg`` below the IMU's
    (:func:`landscape.analysis.physical.recording.imu_to_body`). The angular velocity is the gyro's (``use_gyro`` and the
    recording has one), else the differentiated quaternions' (:func:`quaternion_rates_rad_s`), either
    median-filtered over ``GYRO_MEDIAN_SAMPLES`` samples and interpolated to the orientation's times. The wing
    angle follows ``actuation`` (:class:`sim.actuation.Actuation`, a model set's at the recording's commands)
    from every recorded opening; the leg follows its profile from each rise of the leg command, ``leg_lag_s``
    late (default :data:`landscape.analysis.physical.lean.LEG_LAG_S`). Attempts and their outcomes are the lab's
    (:func:`landscape.analysis.physical.attempts.recording_attempts`).
    """
    from landscape.analysis.physical.attempts import recording_attempts
    from landscape.analysis.physical.lean import LEG_LAG_S
    from landscape.analysis.physical.recording import imu_to_body, up_in_body
    from sim.actuation import leg_profile_deg, wing_profile_deg

    lag = LEG_LAG_S if leg_lag_s is None else float(leg_lag_s)
    t = rec.t_s
    up = up_in_body(rec.quat_xyzw, mount_deg)
    pitch, roll = np.rad2deg(pitch_roll_from_up(up))
    if use_gyro and len(rec.gyro_t_s) >= GYRO_MEDIAN_SAMPLES:
        tg, wg = rec.gyro_t_s, _median3(rec.gyro_rad_s)
    else:
        tg, wg = quaternion_rates_rad_s(t, rec.quat_xyzw)
        wg = _median3(wg)
    omega = np.stack([np.interp(t, tg, wg[:, k]) for k in range(3)], axis=1)
    omega = imu_to_body(omega, mount_deg)
    wing, _ = wing_profile_deg(t, rec.openings_s, actuation)
    rises = np.asarray(rec.leg_up_s, dtype=np.float64) + lag
    period = actuation.leg_period_s
    if rec.theta_l_deg and len(rises):
        k = np.searchsorted(rises, t, side="right") - 1
        since = np.where(k >= 0, t - rises[np.clip(k, 0, None)], np.nan)
        leg = np.where(k >= 0, leg_profile_deg(np.nan_to_num(since), actuation)[0], 0.0)
        kk = np.searchsorted(rises, rec.openings_s, side="right") - 1
        phases = np.where(
            kk >= 0, np.mod(rec.openings_s - rises[np.clip(kk, 0, None)], period) / period, np.nan
        )
    else:
        leg = np.zeros_like(t)
        phases = np.full(len(rec.openings_s), np.nan)
    att = recording_attempts(rec)
    idx = [a.attempt - 1 for a in att]
    return Motion(
        "recorded",
        rec.name,
        float(rec.theta_w_cmd_deg),
        float(rec.theta_l_deg),
        t,
        pitch,
        roll,
        wing,
        leg,
        omega,
        None,
        np.asarray(rec.openings_s, dtype=np.float64)[idx],
        np.array([a.righted for a in att], dtype=bool),
        phases[idx],
    )


DEFAULT_PHYSICAL_SET = "physical-head"
"""The model set the robot's recordings are measured with by default: of the shipped sets, the one whose hold
matches the robot's (its head placed where the real one touches the ground)."""


@dataclass(frozen=True)
class RecordedMotions:
    """The robot's recorded trials as motions, and how they were read.

    Attributes
    ----------
    motions : list of Motion
    body : BodyModel
        The robot as the model set poses it.
    mount_deg : float
        The IMU's mounting pitch the two rests measure (:func:`landscape.analysis.physical.mounting.mounting_from_rests`),
        degrees.
    model_set : str
        The set's label.
    """

    motions: list
    body: BodyModel
    mount_deg: float
    model_set: str


def recorded_motions(data_dir, robot, model_set, *, use_gyro: bool = True) -> RecordedMotions:
    """Every recorded trial of a data directory as a :class:`Motion` (:func:`recorded_motion`), the wings and leg
    following ``model_set``'s actuation at each trial's commands, in the body frame the two rests measure.

    Raises
    ------
    landscape.analysis.physical.recording.PhysicalDataError
        If the directory holds no trial or a file is not in the lab's format.
    """
    from landscape.analysis.physical.mounting import mounting_from_rests
    from landscape.analysis.physical.recording import read_recording, trial_cell, trial_files

    files = trial_files(data_dir)
    commands = sorted({trial_cell(f)[0] for f in files})
    body = body_model(
        robot, model_set, theta_w_cmd_deg=float(np.median(commands)) if model_set.measured else None
    )
    mount = mounting_from_rests(data_dir, body.robot).mount_deg
    motions = []
    for f in files:
        rec = read_recording(f)
        act = model_set.actuation(rec.theta_w_cmd_deg, rec.theta_l_deg)
        motions.append(recorded_motion(rec, mount_deg=mount, actuation=act, use_gyro=use_gyro))
    return RecordedMotions(motions, body, float(mount), model_set.label)
