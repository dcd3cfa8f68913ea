"""The physical robot's recorded trials as data (edge layer: reads the lab's files; no click, no plotting).

The data directory is the lab's ``data-robot`` folder as described in ``../shared/ref/physical_robot/README.md``
(always passed in; nothing of it is in this repository):

- ``run5_W_W_W_W_L_K.bag.mat`` (HDF5, arrays transposed): ``quat`` (time, x, y, z, w, Unix time) and ``servo``
  (time, leg command, wing command, ...). Samples whose quaternion norm differs from 1 by more than
  ``QUAT_NORM_TOL`` are dropped, as the lab does.
- ``robot_attempts.mat``: the lab's per-attempt outcomes per wing command (and the measured wing trace).

Definitions (times from the start of the first wing opening, the first rise of the wing command):

- body pitch and roll are the ZYX Euler angles of the recorded quaternion taken as body-to-world
  (``geometry/frames.py``'s convention); world-up's body-z component is ``u_z = 1 - 2 (x^2 + y^2)``;
- an *upright stretch* is a run of samples with ``u_z < 0`` lasting at least ``UPRIGHT_HOLD_S`` (0.3 s, the
  simulator's rule) or reaching the end of the recording, and reaching ``u_z <= UPRIGHT_DEPTH``; its *direction* is the sign of the roll at its first
  sample (+1: the robot rolled to positive roll);
- a trial *succeeds* when it ends in an upright stretch (README: "ends upright and stays"); its time to right is
  the start of that stretch, and its ``attempts`` the number of wing openings started by then (all openings
  when it fails);
- the lab's per-attempt count (``robot_attempts.mat``) takes the first ``LAB_ATTEMPTS_PER_TRIAL`` openings of each
  trial (the paper's 10 s trial) and counts an attempt a success when the robot becomes upright during it, even
  if it falls back later: :func:`attempt_outcomes` applies that rule to the trials and reproduces the file's
  counts (12/58, 15/42, 17/34).

Resting pitch (issue #15, section 0): per wing opening of a trial with the leg still, the median pitch (the nose's,
:func:`sagittal_pitch_deg`, which does not fold back past 90 deg as the ZYX pitch does) between
``HOLD_WINDOW_S`` (0.5-0.95 s) after the opening starts, minus the median pitch in the ``REST_WINDOW_S`` (0.3 s)
before the first opening (this removes the IMU's mounting); only openings that end before the robot first
becomes upright (the attempt that rights, or rights and falls back, is left out) and whose window lies inside the
recording.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from geometry.errors import UsageError
from geometry.frames import pitch_roll_from_up
from landscape.analysis.trials import wilson_interval

TRIAL_RE = re.compile(r"run5_(\d+)_(\d+)_(\d+)_(\d+)_(\d+)_(\d+)\.bag\.mat$")
QUAT_NORM_TOL = 0.01
UPRIGHT_HOLD_S = 0.3
"""Shortest upright stretch that counts as righted, s (the simulator's ``sim.trial.UPRIGHT_HOLD_S``)."""
UPRIGHT_DEPTH = -0.5
"""An upright stretch must reach ``u_z <= UPRIGHT_DEPTH`` (body tilted more than 120 deg from lying on its back):
near the pole the wings hold the body at u_z ~ 0 and sensor noise alone crosses 0 (run5_90_90_90_90_0_5 stays
0.68 s at u_z > -0.3 and falls back; every righting reaches u_z < -0.95)."""
MAX_IMU_MOUNT_DEG = 45.0
"""Largest IMU mounting pitch :func:`physical_trials` takes, degrees."""
LAB_ATTEMPTS_PER_TRIAL = 5
"""Openings per trial the lab's per-attempt table counts (the paper's 10 s trials at Tw = 2 s)."""
HOLD_WINDOW_S = (0.5, 0.95)
"""Window after the start of an opening where the wings are held open, s (the servo stays within 5 % of its
plateau from about 0.34 s to 1.06 s)."""
REST_WINDOW_S = 0.3
"""Length of the resting window before the first opening, s."""
CLOSED_WINDOW_S = (1.7, 1.95)
"""Window after the start of an opening where the wings are closed again (they close by about 1.3 s), s."""
WING_COMMANDS_DEG = (60.0, 75.0, 90.0)


class PhysicalDataError(UsageError):
    """The physical data directory or one of its files is absent or not in the lab's format."""


# ------------------------------------------------------------------------------------------------- reading
@dataclass(frozen=True)
class Recording:
    """One recorded trial, cleaned.

    Attributes
    ----------
    name : str
        File name.
    theta_w_cmd_deg, theta_l_deg : float
        Commanded wing angle and leg amplitude, degrees (from the file name).
    trial : int
        Trial number K.
    t_s, pitch_deg, roll_deg, up_z : ndarray of shape (N,)
        Time from the first wing opening (s), body pitch and roll (deg), world-up's body-z component.
    openings_s : ndarray of shape (K,)
        Start of every wing opening, s from the first (``openings_s[0] == 0``).
    leg_up_s : ndarray of shape (J,)
        When the leg command turns positive (servo column 1 rises above 0), s from the first opening; empty
        with the leg still. The servo log is written at 10 Hz, so these times are known to 0.1 s.
    quat_xyzw : ndarray of shape (N, 4)
        The orientation quaternions behind ``pitch_deg`` and ``roll_deg`` (body to world, x, y, z, w).
    gyro_t_s, gyro_rad_s : ndarray of shape (G,) and (G, 3)
        The IMU's angular rate in its own frame and its times from the first opening; empty without ``gyro``.
    """

    name: str
    theta_w_cmd_deg: float
    theta_l_deg: float
    trial: int
    t_s: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    up_z: NDArray[np.float64]
    openings_s: NDArray[np.float64]
    leg_up_s: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    quat_xyzw: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 4)))
    gyro_t_s: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    gyro_rad_s: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))


def sagittal_pitch_deg(pitch_deg, roll_deg) -> NDArray[np.float64]:
    """How far the body's nose has pitched over, degrees: the angle of world-up in the body's x-z plane,
    ``atan2(-u_x, u_z) = atan2(sin p, cos p cos r)``. It equals the ZYX pitch at zero roll (for rolls within 10 deg
    it lies less than 0.5 deg above it) and goes on past 90 deg where the ZYX pitch folds back (a body whose nose
    has gone 5 deg past vertical reads pitch 85 deg, roll +-180 deg): at the 90 deg wing command the robot's
    opening carries it past vertical, so a hold, an overshoot or a rise read from the ZYX pitch comes out low
    there. The same for either of the two (pitch, roll) pairs of one orientation. Unlike
    :func:`landscape.analysis.opening.nose_pitch_deg` (the x axis's elevation, at most 90 deg, what the rests on
    the back and upright are read in), an upright body reads near 180 deg here.

    Examples
    --------
    >>> sagittal_pitch_deg([60.0, 85.0, 85.0], [0.0, 180.0, -180.0]).round(9).tolist()
    [60.0, 95.0, 95.0]
    """
    p = np.deg2rad(np.asarray(pitch_deg, dtype=np.float64))
    r = np.deg2rad(np.asarray(roll_deg, dtype=np.float64))
    return np.rad2deg(np.arctan2(np.sin(p), np.cos(p) * np.cos(r)))


def _data_dir(data_dir: str | Path) -> Path:
    d = Path(data_dir)
    if not d.is_dir():
        raise PhysicalDataError(
            f"physical data directory '{d}' does not exist; give --data the lab's data-robot "
            "folder (e.g. ../shared/ref/physical_robot)"
        )
    return d


def trial_files(data_dir: str | Path) -> list[Path]:
    """The ``run5_*.bag.mat`` trial files of a data directory, sorted by (wing, leg, trial).

    Raises
    ------
    PhysicalDataError
        If the directory is absent or holds no trial file.
    """
    d = _data_dir(data_dir)
    files = [p for p in d.iterdir() if TRIAL_RE.search(p.name)]
    if not files:
        raise PhysicalDataError(
            f"'{d}' holds no trial file run5_W_W_W_W_L_K.bag.mat; give --data the lab's data-robot folder"
        )
    return sorted(files, key=lambda p: tuple(int(x) for x in TRIAL_RE.search(p.name).groups()[3:]))


def trial_cell(path: str | Path) -> tuple[float, float]:
    """The commanded wing angle and leg amplitude (degrees) a trial file's name gives (:func:`trial_files`).

    Examples
    --------
    >>> trial_cell("run5_60_60_60_60_30_2.bag.mat")
    (60.0, 30.0)
    """
    m = TRIAL_RE.search(Path(path).name)
    if m is None:
        raise PhysicalDataError(
            f"{Path(path).name} is not a trial file of the lab's (run5_W_W_W_W_L_N.bag.mat)"
        )
    return float(m.group(1)), float(m.group(5))


def pitch_roll_from_quat_deg(quat_xyzw) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """ZYX Euler pitch and roll (degrees) of body-to-world quaternions (x, y, z, w).

    Examples
    --------
    >>> import numpy as np
    >>> h = np.deg2rad(30.0) / 2  # 30 deg about body y: pitch 30
    >>> p, r = pitch_roll_from_quat_deg([[0.0, np.sin(h), 0.0, np.cos(h)]])
    >>> float(p[0].round(9)), float(r[0].round(9))
    (30.0, 0.0)
    """
    pitch, roll = pitch_roll_from_up(up_in_body(quat_xyzw))
    return np.rad2deg(pitch), np.rad2deg(roll)


def read_recording(path: str | Path) -> Recording:
    """Read and clean one trial file (see the module docstring).

    Raises
    ------
    PhysicalDataError
        If the file name is not ``run5_W_W_W_W_L_K.bag.mat``, the file is not HDF5, lacks ``quat`` or ``servo``,
        or has no wing opening.
    """
    import h5py

    path = Path(path)
    m = TRIAL_RE.search(path.name)
    if not m:
        raise PhysicalDataError(f"'{path.name}' is not a trial file name run5_W_W_W_W_L_K.bag.mat")
    w = [int(x) for x in m.groups()[:4]]
    theta_l, trial = int(m.group(5)), int(m.group(6))
    try:
        with h5py.File(path, "r") as f:
            quat = np.asarray(f["quat"][()], dtype=np.float64).T
            servo = np.asarray(f["servo"][()], dtype=np.float64).T
            gyro = np.asarray(f["gyro"][()], dtype=np.float64).T if "gyro" in f else np.zeros((0, 5))
    except (OSError, KeyError) as exc:
        raise PhysicalDataError(
            f"'{path}' is not a lab trial file (HDF5 with 'quat' and 'servo'): {exc}"
        ) from None
    if quat.ndim != 2 or quat.shape[1] < 5 or servo.ndim != 2 or servo.shape[1] < 3:
        raise PhysicalDataError(
            f"'{path}': quat must be N x 6 and servo M x 5 after transposing; got "
            f"{quat.shape} and {servo.shape}"
        )
    keep = np.abs(np.linalg.norm(quat[:, 1:5], axis=1) - 1.0) <= QUAT_NORM_TOL
    quat = quat[keep]
    wing_cmd = servo[:, 2]
    rises = servo[1:, 0][(wing_cmd[1:] > 0) & (wing_cmd[:-1] <= 0)]
    if wing_cmd[0] > 0:
        rises = np.concatenate([[servo[0, 0]], rises])
    if not len(rises) or not len(quat):
        raise PhysicalDataError(
            f"'{path}' has no wing opening (servo column 2 never rises) or no valid orientation sample"
        )
    t0 = float(rises[0])
    leg_cmd = servo[:, 1]
    leg_up = servo[1:, 0][(leg_cmd[1:] > 0) & (leg_cmd[:-1] <= 0)]
    pitch, roll = pitch_roll_from_quat_deg(quat[:, 1:5])
    up_z = 1.0 - 2.0 * (quat[:, 1] ** 2 + quat[:, 2] ** 2)
    if gyro.ndim != 2 or gyro.shape[1] < 4:
        gyro = np.zeros((0, 5))
    return Recording(
        path.name, float(w[0]), float(theta_l), trial, quat[:, 0] - t0, pitch, roll, up_z, rises - t0,
        leg_up - t0, quat[:, 1:5], gyro[:, 0] - t0, gyro[:, 1:4],
    )  # fmt: skip


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


# ------------------------------------------------------------------------------------------------- trials
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


def imu_to_body(v, mount_deg: float) -> NDArray[np.float64]:
    """Vectors in the IMU's frame ((..., 3)) expressed in a body frame pitched ``mount_deg`` below it (a rotation
    about the shared y axis): world-up, or the gyro's angular velocity.

    Examples
    --------
    >>> imu_to_body([0.0, 0.0, 1.0], 90.0).round(12).tolist()
    [1.0, 0.0, 0.0]
    """
    v = np.asarray(v, dtype=np.float64)
    c, s = math.cos(math.radians(mount_deg)), math.sin(math.radians(mount_deg))
    return np.stack([v[..., 0] * c + v[..., 2] * s, v[..., 1], -v[..., 0] * s + v[..., 2] * c], axis=-1)


def up_in_body(quat_xyzw, mount_deg: float = 0.0) -> NDArray[np.float64]:
    """World-up in a body frame pitched ``mount_deg`` below the IMU's frame (``quat_xyzw``: the IMU-to-world
    rotations, (N, 4) as x, y, z, w), (N, 3); 0 gives it in the IMU's own frame. The body's pitch and roll are
    :func:`geometry.frames.pitch_roll_from_up` of it: the IMU reads the body's pitch plus the mounting.

    Examples
    --------
    >>> q = np.array([[0.0, np.sin(np.radians(20)), 0.0, np.cos(np.radians(20))]])  # the IMU pitched 40 deg
    >>> round(float(np.rad2deg(pitch_roll_from_up(up_in_body(q, 2.6))[0][0])), 6)
    37.4
    """
    q = np.asarray(quat_xyzw, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    u = np.stack([2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)], axis=-1)
    return imu_to_body(u, mount_deg) if mount_deg else u


def up_z_mounted(quat_xyzw, mount_deg: float) -> NDArray[np.float64]:
    """World-up's z component in a body frame pitched ``mount_deg`` below the IMU's frame (:func:`up_in_body`);
    0 gives the recorded ``up_z``.

    Examples
    --------
    >>> q = np.array([[0.0, np.sin(np.radians(45)), 0.0, np.cos(np.radians(45))]])  # the IMU pitched 90 deg
    >>> round(float(up_z_mounted(q, 0.0)[0]), 6), round(float(up_z_mounted(q, 10.0)[0]), 4)
    (0.0, 0.1736)
    """
    return up_in_body(quat_xyzw, mount_deg)[..., 2]


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


@dataclass(frozen=True)
class PhysicalCell:
    """Outcomes of the trials at one (theta_w, theta_l).

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_measured_deg, theta_l_deg : float
    n, successes : int
    p, ci_low, ci_high : float
        Success fraction and its Wilson 95 % interval.
    median_time_to_right_s : float
        Over the successes (nan without).
    """

    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    theta_l_deg: float
    n: int
    successes: int
    p: float
    ci_low: float
    ci_high: float
    median_time_to_right_s: float

    CSV_COLUMNS = (
        "theta_w_cmd_deg",
        "theta_w_measured_deg",
        "theta_l_deg",
        "n",
        "successes",
        "p",
        "ci_low",
        "ci_high",
        "median_time_to_right_s",
    )


def physical_cells(trials: Iterable[PhysicalTrial]) -> list[PhysicalCell]:
    """Success with Wilson 95 % intervals and median time to right per (theta_w, theta_l).

    Examples
    --------
    >>> t = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 2.0, 2, 1, (1,), 2, 5.0)
    >>> c = physical_cells([t, t.__class__(**{**t.__dict__, "success": False, "time_to_right_s": float("nan")})])
    >>> c[0].n, c[0].successes, c[0].median_time_to_right_s, round(c[0].ci_low, 4)
    (2, 1, 2.0, 0.0945)
    """
    groups: dict[tuple[float, float], list[PhysicalTrial]] = defaultdict(list)
    for t in trials:
        groups[(t.theta_w_cmd_deg, t.theta_l_deg)].append(t)
    out = []
    for (tw, tl), ts in sorted(groups.items()):
        k, n = sum(t.success for t in ts), len(ts)
        lo, hi = wilson_interval(k, n)
        times = [t.time_to_right_s for t in ts if t.success]
        out.append(
            PhysicalCell(
                tw,
                ts[0].theta_w_measured_deg,
                tl,
                n,
                k,
                k / n,
                lo,
                hi,
                float(np.median(times)) if times else math.nan,
            )
        )
    return out


# ------------------------------------------------------------------------------------------------- attempts
@dataclass(frozen=True)
class AttemptCount:
    """Per-attempt outcomes at one wing command, pooled over leg amplitudes.

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_measured_deg : float
    attempts, successes : int
    p, ci_low, ci_high : float
        Per-attempt success rate and its Wilson 95 % interval.
    """

    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    attempts: int
    successes: int
    p: float
    ci_low: float
    ci_high: float


def _count(tw: float, measured: float, k: int, n: int) -> AttemptCount:
    lo, hi = wilson_interval(k, n)
    return AttemptCount(tw, measured, n, k, k / n if n else math.nan, lo, hi)


def _load_attempts(data_dir: str | Path):
    from scipy.io import loadmat

    path = _data_dir(data_dir) / "robot_attempts.mat"
    if not path.is_file():
        raise PhysicalDataError(f"'{path}' not found; the lab's data-robot folder has robot_attempts.mat")
    try:
        att = loadmat(path, squeeze_me=True, struct_as_record=False)["attempt"]
    except (ValueError, KeyError, OSError) as exc:
        raise PhysicalDataError(
            f"'{path}' is not the lab's robot_attempts.mat (struct array 'attempt'): {exc}"
        ) from None
    if np.size(att) != len(WING_COMMANDS_DEG):
        raise PhysicalDataError(
            f"'{path}': 'attempt' must have one entry per wing command "
            f"{WING_COMMANDS_DEG}; got {np.size(att)}"
        )
    return att


def _plateau(entry) -> float:
    vals = [
        float(np.nanmax(w))
        for w in np.atleast_1d(entry.wing_angle)
        if np.size(w) and np.isfinite(np.asarray(w, dtype=np.float64)).any()
    ]
    return float(np.median(vals)) if vals else math.nan


def measured_plateaus_deg(data_dir: str | Path) -> dict[float, float]:
    """Measured wing plateau per wing command, degrees: the median over attempts of the peak of the lab's
    measured wing trace in ``robot_attempts.mat`` (about 59.1, 73.6 and 82.1 deg)."""
    att = _load_attempts(data_dir)
    return {tw: _plateau(e) for tw, e in zip(WING_COMMANDS_DEG, att, strict=True)}


def recorded_attempt_counts(data_dir: str | Path) -> list[AttemptCount]:
    """The lab's per-attempt outcomes (``robot_attempts.mat``) per wing command."""
    att = _load_attempts(data_dir)
    out = []
    for tw, e in zip(WING_COMMANDS_DEG, att, strict=True):
        res = np.atleast_1d(np.asarray(e.result, dtype=np.float64))
        out.append(_count(tw, _plateau(e), int(np.sum(res == 1)), len(res)))
    return out


def attempt_outcomes(
    trials: Iterable[PhysicalTrial], *, max_attempts: int = LAB_ATTEMPTS_PER_TRIAL
) -> list[AttemptCount]:
    """Per-attempt outcomes per wing command by the lab's rule: the first ``max_attempts`` openings of each
    trial; an attempt succeeds when the robot first becomes upright during it.

    Examples
    --------
    >>> t = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 2.0, 2, 1, (1,), 2, 5.0)
    >>> f = PhysicalTrial("b", 60.0, 59.1, 0.0, 1, False, float("nan"), 9, 0, (), 0, 18.0)
    >>> c = attempt_outcomes([t, f])[0]
    >>> c.attempts, c.successes
    (7, 1)
    """
    acc: dict[float, list] = defaultdict(lambda: [0, 0, math.nan])
    for t in trials:
        a = acc[t.theta_w_cmd_deg]
        a[2] = t.theta_w_measured_deg
        if 0 < t.first_upright_attempt <= max_attempts:
            a[0] += 1
            a[1] += t.first_upright_attempt
        else:
            a[1] += min(t.attempts, max_attempts)
    return [_count(tw, m, k, n) for tw, (k, n, m) in sorted(acc.items())]


# ------------------------------------------------------------------------------------------------- attempt paths
@dataclass(frozen=True)
class PhysicalAttempt:
    """One self-righting attempt of the physical robot (one wing opening) as a body pitch-roll path.

    Attributes
    ----------
    name : str
        Trial file.
    theta_w_cmd_deg, theta_w_measured_deg, theta_l_deg : float
        Commanded and measured (plateau) wing angle, leg amplitude, degrees.
    trial, attempt : int
        Trial number K and the opening's number in it (1 = the first).
    t_s : ndarray of shape (L,)
        Time from the trial's first opening, s.
    pitch_deg, roll_deg : ndarray of shape (L,)
        Recorded body pitch and roll over the attempt, degrees (ZYX Euler, ``geometry/frames.py``).
    righted : bool
        The robot became upright during this attempt (the lab's per-attempt rule, :func:`attempt_outcomes`).
    """

    name: str
    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    theta_l_deg: float
    trial: int
    attempt: int
    t_s: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    righted: bool


def recording_attempts(
    rec: Recording, *, theta_w_measured_deg: float = math.nan, max_attempts: int | None = None
) -> list[PhysicalAttempt]:
    """The attempts of one recording, by the lab's rule: every wing opening until the robot first becomes upright
    (the one in which it does is the last, ``righted``), all openings if it never does; at most the first
    ``max_attempts`` openings (``LAB_ATTEMPTS_PER_TRIAL``: the lab's per-attempt table; None: all).

    An attempt runs from the start of its opening to the start of the next; the righting attempt ends
    ``UPRIGHT_HOLD_S`` after the robot becomes upright (its path reaches the upright side and stops there).
    Openings that start after the recording's last sample have no samples and are left out.
    """
    st = upright_stretches(rec.t_s, rec.up_z)
    t_up = float(rec.t_s[st[0][0]]) if st else math.inf
    ends = np.concatenate([rec.openings_s[1:], [math.inf]])
    out = []
    for k, (start, end) in enumerate(zip(rec.openings_s, ends, strict=True), start=1):
        if start > t_up or (max_attempts is not None and k > max_attempts):
            break
        righted = bool(start <= t_up < end)
        stop = min(end, t_up + UPRIGHT_HOLD_S) if righted else end
        sel = (rec.t_s >= start) & (rec.t_s < stop)
        if not sel.any():
            continue
        out.append(
            PhysicalAttempt(
                rec.name,
                rec.theta_w_cmd_deg,
                float(theta_w_measured_deg),
                rec.theta_l_deg,
                rec.trial,
                k,
                rec.t_s[sel],
                rec.pitch_deg[sel],
                rec.roll_deg[sel],
                righted,
            )
        )
    return out


def physical_attempts(
    data_dir: str | Path,
    *,
    theta_w_cmd_deg: float | None = None,
    theta_l_deg: float | None = None,
    max_attempts: int | None = None,
) -> list[PhysicalAttempt]:
    """Every attempt (:func:`recording_attempts`, up to ``max_attempts`` per trial) of the trials of a data
    directory, optionally only those at one commanded wing angle and leg amplitude, in file order.

    Raises
    ------
    PhysicalDataError
        If the directory or a file is not in the lab's format, or no trial has the wing angle and leg amplitude
        asked for (the message lists those recorded).
    """
    commands = {f: trial_cell(f) for f in trial_files(data_dir)}
    chosen = [
        f
        for f, (w, leg) in commands.items()
        if (theta_w_cmd_deg is None or w == theta_w_cmd_deg) and (theta_l_deg is None or leg == theta_l_deg)
    ]
    if not chosen:
        have = ", ".join(f"{w:g}/{leg:g}" for w, leg in sorted(set(commands.values())))
        raise PhysicalDataError(
            f"no physical trial at wing {theta_w_cmd_deg if theta_w_cmd_deg is not None else 'any'} deg, leg "
            f"{theta_l_deg if theta_l_deg is not None else 'any'} deg in '{data_dir}'; the recorded wing/leg "
            f"commands are {have} deg"
        )
    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:
        plateau = {}
    out = []
    for rec in map(read_recording, chosen):
        out += recording_attempts(
            rec, theta_w_measured_deg=plateau.get(rec.theta_w_cmd_deg, math.nan), max_attempts=max_attempts
        )
    return out


# ------------------------------------------------------------------------------------------------- kinematics
@dataclass(frozen=True)
class RestingPitch:
    """The body pitch while the wings are held open, relative to the rest before the first opening.

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_measured_deg : float
    pitch_deg : ndarray of shape (n,)
        One value per opening (median over the hold window), degrees.
    median_deg, q25_deg, q75_deg : float
    n : int
    first_opening_median_deg : float
        Median over the trials' first openings only (no earlier opening has moved the body), degrees.
    closed_median_deg : float
        Median pitch ``CLOSED_WINDOW_S`` after the openings (wings closed again), same reference, degrees: 0 if
        the body returns to where it rested before the first opening.
    """

    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    pitch_deg: NDArray[np.float64]
    median_deg: float
    q25_deg: float
    q75_deg: float
    n: int
    first_opening_median_deg: float = math.nan
    closed_median_deg: float = math.nan


def opening_pitches_deg(
    rec: Recording, *, window_s: tuple[float, float] = HOLD_WINDOW_S, rest_s: float = REST_WINDOW_S
) -> NDArray[np.float64]:
    """Resting pitch of each opening of one recording (rules in the module docstring), degrees; nan for an
    opening left out (the robot became upright during it or later, or the window passes the recording's end)."""
    t = rec.t_s
    rest = (t >= -rest_s) & (t < 0)
    if not rest.any():
        return np.full(len(rec.openings_s), math.nan)
    pitch = sagittal_pitch_deg(rec.pitch_deg, rec.roll_deg)  # past vertical at 90 deg: not folded back
    ref = float(np.median(pitch[rest]))
    st = upright_stretches(t, rec.up_z)
    t_up = float(t[st[0][0]]) if st else math.inf
    ends = np.concatenate([rec.openings_s[1:], [math.inf]])
    out = []
    for start, end in zip(rec.openings_s, ends, strict=True):
        sel = (t >= start + window_s[0]) & (t <= start + window_s[1])
        if start + window_s[1] > t[-1] or min(end, t[-1]) >= t_up or not sel.any():
            out.append(math.nan)
        else:
            out.append(float(np.median(pitch[sel])) - ref)
    return np.asarray(out, dtype=np.float64)


def resting_pitch_table(data_dir: str | Path, *, theta_l_deg: float = 0.0) -> list[RestingPitch]:
    """Resting pitch per wing command over the trials with leg amplitude ``theta_l_deg`` (0: leg still)."""
    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:
        plateau = {}
    vals: dict[float, list[float]] = defaultdict(list)
    first: dict[float, list[float]] = defaultdict(list)
    closed: dict[float, list[float]] = defaultdict(list)
    for f in trial_files(data_dir):
        rec = read_recording(f)
        if rec.theta_l_deg == theta_l_deg:
            held = opening_pitches_deg(rec)
            vals[rec.theta_w_cmd_deg].extend(held[np.isfinite(held)].tolist())
            first[rec.theta_w_cmd_deg].extend(held[:1][np.isfinite(held[:1])].tolist())
            after = opening_pitches_deg(rec, window_s=CLOSED_WINDOW_S)
            closed[rec.theta_w_cmd_deg].extend(after[np.isfinite(after)].tolist())
    if not vals:
        raise PhysicalDataError(f"no trial with leg amplitude {theta_l_deg:g} deg in '{data_dir}'")
    out = []
    for tw, v in sorted(vals.items()):
        a = np.asarray(v, dtype=np.float64)
        q25, med, q75 = np.percentile(a, [25, 50, 75]) if len(a) else (math.nan,) * 3
        out.append(
            RestingPitch(
                tw,
                plateau.get(tw, math.nan),
                a,
                float(med),
                float(q25),
                float(q75),
                len(a),
                _median(first[tw]),
                _median(closed[tw]),
            )
        )
    return out


def _median(v: Sequence[float]) -> float:
    return float(np.median(v)) if len(v) else math.nan


@dataclass(frozen=True)
class Lateralisation:
    """To which side the robot rolls when it becomes upright.

    Attributes
    ----------
    positive, negative : int
        Upright events (every upright stretch, falls-back included) with positive and negative roll.
    p_positive, ci_low, ci_high : float
        Fraction to positive roll and its Wilson 95 % interval.
    """

    positive: int
    negative: int
    p_positive: float
    ci_low: float
    ci_high: float


def lateralisation(trials: Iterable[PhysicalTrial]) -> Lateralisation:
    """Count upright events by the sign of the roll (all cells together).

    Examples
    --------
    >>> t = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 2.0, 2, 1, (1, 1), 1, 5.0)
    >>> lateralisation([t]).positive
    2
    """
    dirs = [d for t in trials for d in t.upright_directions]
    pos, n = sum(d > 0 for d in dirs), len(dirs)
    lo, hi = wilson_interval(pos, n)
    return Lateralisation(pos, n - pos, pos / n if n else math.nan, lo, hi)
