"""The outcome rule: when a recorded trial has righted, and each trial's outcome.

Times are from the start of the first wing opening.

- an *upright stretch* is a run of samples with ``u_z < 0`` lasting at least ``UPRIGHT_HOLD_S`` (the
  simulator's rule) or reaching the end of the recording, and reaching ``u_z <= UPRIGHT_DEPTH``; its *direction*
  is the sign of the roll at its first sample (+1: the robot rolled to positive roll);
- a trial *succeeds* when it ends in an upright stretch (the lab's README: "ends upright and stays"); its time to
  right is the start of that stretch, and its ``attempts`` the number of wing openings started by then (all
  openings when it fails).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from landscape.analysis.physical.recording import (
    PhysicalDataError,
    Recording,
    measured_plateaus_deg,
    read_recording,
    trial_files,
    up_z_mounted,
)

UPRIGHT_HOLD_S = 0.3
"""Shortest upright stretch that counts as righted, s (the simulator's ``sim.trial.UPRIGHT_HOLD_S``)."""
UPRIGHT_DEPTH = -0.5
"""An upright stretch must reach ``u_z <= UPRIGHT_DEPTH`` (body tilted more than 120 deg from lying on its back):
near the pole the wings hold the body at u_z ~ 0 and sensor noise alone crosses 0, while a righting goes on to
lie on the belly (u_z near -1)."""
MAX_IMU_MOUNT_DEG = 45.0


def upright_stretches(
    t_s, up_z, *, hold_s: float = UPRIGHT_HOLD_S, depth: float = UPRIGHT_DEPTH
) -> list[tuple[int, int]]:
    """Index ranges ``(first, last)`` of the runs with ``up_z < 0`` lasting at least ``hold_s`` or reaching the
    end of the record, that reach ``up_z <= depth``.

    Examples
    --------
    >>> t = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]
    >>> upright_stretches(t, [1, -1, 1, -1, -1, -1, -1, 1])
    [(3, 6)]
    >>> upright_stretches(t, [1, 1, 1, 1, 1, 1, 1, -1])
    [(7, 7)]
    >>> upright_stretches(t, [1, 1, 1, -0.2, -0.3, -0.2, -0.1, 1])
    []
    """
    t = np.asarray(t_s, dtype=np.float64)
    u = np.asarray(up_z, dtype=np.float64)
    up = u < 0
    out = []
    i, n = 0, len(up)
    while i < n:
        if not up[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and up[j + 1]:
            j += 1
        if (t[j] - t[i] >= hold_s - 1e-12 or j == n - 1) and u[i : j + 1].min() <= depth:
            out.append((i, j))
        i = j + 1
    return out


@dataclass(frozen=True)
class PhysicalTrial:
    """One physical trial's outcome.

    Attributes
    ----------
    name : str
    theta_w_cmd_deg, theta_w_measured_deg, theta_l_deg : float
        Commanded and measured (servo plateau) wing angle, leg amplitude, degrees.
    trial : int
    success : bool
        Ends upright and stays.
    time_to_right_s : float
        From the first wing opening to the start of the final upright stretch, s (nan if it fails).
    attempts : int
        Wing openings started until it righted (all openings of the recording if it fails).
    direction : int
        Sign of the roll when it rights (+1 or -1; 0 if it fails).
    upright_directions : tuple of int
        Sign of the roll at the start of every upright stretch (a robot that rights and falls back has one
        more than its successes).
    first_upright_attempt : int
        Opening during which it first became upright (0 if never).
    duration_s : float
        Recording length after the first opening, s.
    """

    name: str
    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    theta_l_deg: float
    trial: int
    success: bool
    time_to_right_s: float
    attempts: int
    direction: int
    upright_directions: tuple[int, ...]
    first_upright_attempt: int
    duration_s: float

    CSV_COLUMNS = (
        "name",
        "theta_w_cmd_deg",
        "theta_w_measured_deg",
        "theta_l_deg",
        "trial",
        "success",
        "time_to_right_s",
        "attempts",
        "direction",
        "first_upright_attempt",
        "duration_s",
    )


def trial_outcome(rec: Recording, *, theta_w_measured_deg: float = math.nan) -> PhysicalTrial:
    """The outcome of one recording (rules in the module docstring)."""
    st = upright_stretches(rec.t_s, rec.up_z)
    dirs = tuple(int(np.sign(rec.roll_deg[i])) or 1 for i, _ in st)
    success = bool(st) and st[-1][1] == len(rec.t_s) - 1
    t_right = float(rec.t_s[st[-1][0]]) if success else math.nan
    n_open = len(rec.openings_s)
    attempts = int(np.searchsorted(rec.openings_s, t_right, side="right")) if success else n_open
    first = int(np.searchsorted(rec.openings_s, rec.t_s[st[0][0]], side="right")) if st else 0
    return PhysicalTrial(
        rec.name,
        rec.theta_w_cmd_deg,
        float(theta_w_measured_deg),
        rec.theta_l_deg,
        rec.trial,
        success,
        t_right,
        attempts,
        dirs[-1] if success else 0,
        dirs,
        first,
        float(rec.t_s[-1]),
    )


def physical_trials(data_dir: str | Path, *, imu_mount_deg: float = 0.0) -> list[PhysicalTrial]:
    """Every trial of a data directory (measured wing plateau from ``robot_attempts.mat`` when present).

    ``imu_mount_deg``: judge uprightness (success, time to right, attempts) in a body frame pitched that much
    below the IMU's (:func:`up_z_mounted`); at the 90 deg wing command the robot stands near 90 deg of pitch and
    its IMU's frame counts it upright as soon as the IMU's pitch passes 90 deg.

    Raises
    ------
    PhysicalDataError
        If the directory or a file is not in the lab's format.
    """
    if not (math.isfinite(imu_mount_deg) and abs(imu_mount_deg) <= MAX_IMU_MOUNT_DEG):
        raise PhysicalDataError(
            f"the IMU's mounting must lie within ±{MAX_IMU_MOUNT_DEG:g} degrees; got {imu_mount_deg!r}"
        )
    files = trial_files(data_dir)
    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:
        plateau = {}
    recs = map(read_recording, files)
    if imu_mount_deg:
        recs = (replace(r, up_z=up_z_mounted(r.quat_xyzw, imu_mount_deg)) for r in recs)
    return [
        trial_outcome(rec, theta_w_measured_deg=plateau.get(rec.theta_w_cmd_deg, math.nan)) for rec in recs
    ]
