"""The hold pitch of first openings with the leg still, in the model's frame and in the IMU's.

The recorded pitch is the IMU's, whose mounting on the body is not known; the simulated pitch is the body
frame's. :func:`hold_pitch_frames` therefore compares the recorded hold with the model's in two ways: relative to
the rest before the first opening (which assumes the model rests where the robot rests with its wings closed), and
in the IMU's own frame with its mounting offset fitted as one constant (each command's residual also with the offset
fitted on the other commands only). :func:`landscape.analysis.physical.mounting.mounting_from_rests` measures that
mounting without the hold, from the two rests every righted trial records.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from landscape.analysis.physical.recording import (
    PhysicalDataError,
    measured_plateaus_deg,
)
from landscape.analysis.physical.response import recorded_first_openings


@dataclass(frozen=True)
class HoldFrame:
    """The hold pitch of first openings with the leg still, per wing command, in two frames.

    Attributes
    ----------
    theta_w_cmd_deg : float
    n : int
        First openings with the leg still.
    recorded_deg, recorded_sd_deg : float
        Median and standard deviation of the recorded hold pitch in the IMU frame, degrees.
    relative_deg, relative_sd_deg : float
        The same minus each trial's rest before the opening (the reference of :mod:`landscape.analysis.physical.resting`), degrees.
    rest_sd_deg : float
        Standard deviation of that rest between trials, degrees.
    model_deg, model_rest_deg : float
        The model's metastable pitch at the command and its rest with the wings closed, body frame, degrees.
    offset_deg : float
        The IMU's mounting (recorded minus model), fitted as one constant over every command, degrees.
    residual_deg, residual_held_out_deg : float
        Recorded minus offset minus model: with the offset fitted on every command, and on the other commands
        only, degrees.
    """

    theta_w_cmd_deg: float
    n: int
    recorded_deg: float
    recorded_sd_deg: float
    relative_deg: float
    relative_sd_deg: float
    rest_sd_deg: float
    model_deg: float
    model_rest_deg: float
    offset_deg: float
    residual_deg: float
    residual_held_out_deg: float


def hold_pitch_frames(
    data_dir: str | Path, model_hold_deg: dict[float, float], model_rest_deg: float
) -> list[HoldFrame]:
    """Compare the recorded hold pitch of first openings (leg still) with the model's, per wing command.

    Parameters
    ----------
    data_dir : path
        The lab's physical_robot folder.
    model_hold_deg : dict of float to float
        The model's metastable pitch per wing command, body frame, degrees (e.g. every wing servo at its
        measured plateau).
    model_rest_deg : float
        The model's rest with the wings closed, degrees.

    Raises
    ------
    PhysicalDataError
        If no trial with the leg still has a command of ``model_hold_deg``.
    """
    hold: dict[float, list[float]] = defaultdict(list)
    rest: dict[float, list[float]] = defaultdict(list)
    for o in recorded_first_openings(data_dir):
        r = o.response
        if o.theta_l_deg == 0.0 and o.theta_w_cmd_deg in model_hold_deg and np.isfinite(r.hold_pitch_deg):
            hold[o.theta_w_cmd_deg].append(r.hold_pitch_deg)
            rest[o.theta_w_cmd_deg].append(r.rest_pitch_deg)
    cmds = sorted(hold)
    if not cmds:
        raise PhysicalDataError(
            f"no first opening with the leg still at wing commands {sorted(model_hold_deg)} deg in '{data_dir}'"
        )
    recorded = {c: float(np.median(hold[c])) for c in cmds}
    diff = {c: recorded[c] - model_hold_deg[c] for c in cmds}
    offset = float(np.mean(list(diff.values())))
    out = []
    for c in cmds:
        h, s = np.asarray(hold[c]), np.asarray(rest[c])
        others = [diff[k] for k in cmds if k != c]
        held_out = diff[c] - float(np.mean(others)) if others else math.nan
        out.append(
            HoldFrame(
                c, len(h), recorded[c], float(h.std()), float(np.median(h - s)), float((h - s).std()),
                float(s.std()), model_hold_deg[c], model_rest_deg, offset, diff[c] - offset, held_out,
            )
        )  # fmt: skip
    return out


def per_servo_hold_deg(robot, measured, commands_deg: Sequence[float]) -> dict[float, float]:
    """The model's metastable pitch with each wing servo at its own measured plateau
    (:meth:`sim.actuation.MeasuredActuation.wing_plateaus_deg`), degrees: the start of
    :func:`landscape.computation.compute` with those ``wing_joints_deg`` (a slow opening to the smallest
    plateau, then descent)."""
    from landscape.computation import posed, start_orientation

    out = {}
    for c in commands_deg:
        vals = dict(zip(robot.joint_map.wing, measured.wing_plateaus_deg(c).tolist(), strict=True))
        pose = posed(robot, c, 0.0, vals)
        out[float(c)] = float(start_orientation(robot, pose, c, 0.0, wing_joints_deg=vals)[0])
    return out


def plateau_hold_deg(robot, data_dir: str | Path, commands_deg: Sequence[float]) -> dict[float, float]:
    """The model's metastable pitch with every wing joint at the measured plateau of each command, degrees."""
    from landscape.minima import metastable_orientation

    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:  # no per-attempt record: the command itself, as resting_pitch_table does
        plateau = {}
    return {float(c): float(metastable_orientation(robot, plateau.get(c, c), 0.0)[0]) for c in commands_deg}


def support_links(pose, pitch_deg: float, roll_deg: float, *, tol_m: float = 2e-4) -> list[str]:
    """The links of a posed robot (:class:`geometry.Pose`) whose hull vertices touch flat ground at this body
    orientation: within ``tol_m`` of the lowest hull point, in the pose's part order.

    Examples
    --------
    >>> from geometry.robots import load_robot
    >>> from landscape.minima import metastable_orientation
    >>> robot = load_robot(None)  # the built-in robot, held open at 74 deg: on its head and both wing edges
    >>> support_links(robot.pose(74.0, 0.0), *metastable_orientation(robot, 74.0, 0.0))
    ['head', 'wing2', 'wing1']
    """
    from geometry.frames import up_vector

    u = up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    low = float((pose.hull_points_m @ u).min())
    out = []
    for part in pose.parts:
        if not len(part.hull_link_m):
            continue
        T = pose.link_transforms[part.link]
        heights = (part.hull_link_m @ T[:3, :3].T + T[:3, 3]) @ u
        if heights.min() - low <= tol_m:
            out.append(part.link)
    return out
