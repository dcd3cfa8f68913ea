"""The IMU's mounting on the body, measured from the two rests every righted trial records: on its back before the
first opening and upright after it rights, each compared with the model's rest."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from landscape.analysis.physical.outcome import trial_outcome
from landscape.analysis.physical.recording import (
    PhysicalDataError,
    read_recording,
    trial_files,
)
from landscape.analysis.physical.resting import REST_WINDOW_S

UPRIGHT_SETTLE_S = 0.5
"""Time after a trial rights before its upright rest is read, s."""
UPRIGHT_UP_Z = -0.85
"""World-up's recorded body-z component below which a sample counts as resting upright."""
MIN_UPRIGHT_SAMPLES = 10
"""Fewest upright samples (0.2 s at 50 Hz) a righted trial needs to give its upright rest."""


@dataclass(frozen=True)
class RestMounting:
    """The IMU's mounting pitch, measured from the robot's two rests (:func:`mounting_from_rests`).

    Attributes
    ----------
    n : int
        Righted trials with both rests.
    recorded_back_deg, recorded_upright_deg : float
        Medians of the recorded (IMU) pitch on the robot's back before its first opening and upright after it
        rights, degrees.
    model_back_deg, model_upright_deg : float
        The model's pitch at the same two rests (wings closed, leg centred), degrees.
    mount_deg, mount_q25_deg, mount_q75_deg : float
        Median and quartiles of the per-trial mountings, degrees: the IMU's x axis pitched this far (nose up on
        the robot's back) against the body's.
    """

    n: int
    recorded_back_deg: float
    recorded_upright_deg: float
    model_back_deg: float
    model_upright_deg: float
    mount_deg: float
    mount_q25_deg: float
    mount_q75_deg: float


def nose_pitch_deg(pitch_deg: float, roll_deg: float) -> float:
    """The pitch of the body's x axis above the horizontal, degrees: the ZYX pitch of whichever of the two
    (pitch, roll) pairs that describe one orientation has ``|pitch| <= 90`` (``asin(-u_x)``).

    Examples
    --------
    >>> round(nose_pitch_deg(-174.0, -180.0), 9), round(nose_pitch_deg(0.5, -178.0), 9)
    (-6.0, 0.5)
    """
    from geometry.frames import up_vector

    u = up_vector(math.radians(pitch_deg), math.radians(roll_deg))
    return math.degrees(math.asin(max(-1.0, min(1.0, -float(u[0])))))


def upright_rest_deg(robot) -> tuple[float, float]:
    """The model's lowest upright rest (world-up's body-z component negative), wings closed and leg centred:
    (pitch, roll) in degrees, the lowest cell of a 1-degree landscape refined by descent."""
    from landscape.energy import energy_landscape
    from landscape.minima import local_descent

    pose = robot.pose(0.0, 0.0) if robot.has_joints else robot.pose()
    ls = energy_landscape(pose)  # the default grid of every interface
    a = np.deg2rad(ls.angles_deg)
    upright = np.cos(a)[:, None] * np.cos(a)[None, :] < 0  # u_z = cos p cos r
    i, j = np.unravel_index(np.argmin(np.where(upright, ls.energy_j, np.inf)), ls.energy_j.shape)
    return local_descent(pose, float(ls.angles_deg[i]), float(ls.angles_deg[j]))


def rest_mounting_deg(back_deg, upright_deg, model_back_deg: float, model_upright_deg: float):
    """The IMU's mounting pitch from its readings on the robot's back and upright (scalars or arrays), given the
    model's pitch at the same two rests, degrees: the IMU reads the body's pitch plus the mounting on its back
    and minus it upright (rolled half a turn about x, its pitch axis is reversed).

    Examples
    --------
    >>> float(rest_mounting_deg(1.0, -5.5, -6.0, 1.5))
    7.0
    """
    return ((np.asarray(back_deg) - upright_deg) - (model_back_deg - model_upright_deg)) / 2.0


def mounting_from_rests(
    data_dir: str | Path, robot, *, settle_s: float = UPRIGHT_SETTLE_S, up_z_below: float = UPRIGHT_UP_Z
) -> RestMounting:
    """The IMU's mounting pitch from the two rests every righted trial records: on its back before the first
    opening (the median of ``REST_WINDOW_S``) and upright after it rights (from ``settle_s`` after, the samples
    with world-up's body-z component below ``up_z_below``).

    An IMU pitched ``d`` against the body reads the body's pitch plus ``d`` on its back and minus ``d`` upright
    (rolled half a turn about x, its pitch axis is reversed), so each trial gives
    ``d = ((back - upright) - (model's back - model's upright)) / 2`` without assuming either rest alone.
    Both rests have the wings closed; the model's are the lowest rests of its hull (:func:`upright_rest_deg`,
    :func:`landscape.minima.metastable_orientation` at 0).

    Raises
    ------
    PhysicalDataError
        If no righted trial has both rests.
    """
    from landscape.minima import metastable_orientation

    model_back = nose_pitch_deg(*metastable_orientation(robot, 0.0, 0.0))
    model_upright = nose_pitch_deg(*upright_rest_deg(robot))
    back, upright = [], []
    for f in trial_files(data_dir):
        rec = read_recording(f)
        out = trial_outcome(rec)
        if not out.success:
            continue
        before = (rec.t_s >= -REST_WINDOW_S) & (rec.t_s < 0.0)
        after = (rec.t_s > out.time_to_right_s + settle_s) & (rec.up_z < up_z_below)
        if before.any() and after.sum() >= MIN_UPRIGHT_SAMPLES:
            back.append(float(np.median(rec.pitch_deg[before])))
            upright.append(float(np.median(rec.pitch_deg[after])))
    if not back:
        raise PhysicalDataError(
            f"no righted trial in '{data_dir}' records both rests (on its back and upright)"
        )
    b, u = np.asarray(back), np.asarray(upright)
    d = rest_mounting_deg(b, u, model_back, model_upright)
    q25, q50, q75 = np.percentile(d, [25, 50, 75])
    return RestMounting(
        len(d),
        float(np.median(b)),
        float(np.median(u)),
        model_back,
        model_upright,
        float(q50),
        float(q25),
        float(q75),
    )
