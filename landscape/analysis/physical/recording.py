"""One recorded trial as data: the file format, the reader and the IMU's frame.

A trial file ``run5_W_W_W_W_L_K.bag.mat`` (MATLAB v7.3, i.e. HDF5, arrays transposed) holds ``quat`` (time, x,
y, z, w, Unix time), ``servo`` (time, leg command, wing command, ...) and optionally ``gyro`` (time, x, y, z
angular rate in the IMU's frame). :func:`read_recording` turns one into a :class:`Recording`, times from the start
of the first wing opening (the first rise of the wing command); samples whose quaternion norm differs from 1 by
more than ``QUAT_NORM_TOL`` are dropped, as the lab does. ``robot_attempts.mat`` (MATLAB v5) holds the lab's
per-attempt outcomes per wing command and the measured wing trace (:func:`measured_plateaus_deg`).

Body pitch and roll are the ZYX Euler angles of the recorded quaternion taken as body-to-world
(``geometry/frames.py``'s convention); world-up's body-z component is ``u_z = 1 - 2 (x^2 + y^2)``.

A reader for another file format is one function ``path -> Recording`` registered for its file suffix with
:func:`register_reader`; every analysis of :mod:`landscape.analysis.physical` reads through
:func:`read_recording` and lists files with :func:`trial_files`, so it then reads that format too.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from geometry.errors import UsageError
from geometry.frames import pitch_roll_from_up

_TRIAL_STEM = r"run5_(\d+)_(\d+)_(\d+)_(\d+)_(\d+)_(\d+)"
TRIAL_RE = re.compile(_TRIAL_STEM + r"\.bag\.mat$")
"""Name of the lab's trial files: wing command of the four servos, leg amplitude (degrees) and trial number."""
QUAT_NORM_TOL = 0.01
"""Samples whose quaternion norm differs from 1 by more than this are dropped."""
WING_COMMANDS_DEG = (60.0, 75.0, 90.0)
"""The wing commands the lab recorded, degrees, in the order of ``robot_attempts.mat``'s entries."""


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
    :func:`landscape.analysis.physical.mounting.nose_pitch_deg` (the x axis's elevation, at most 90 deg, what the rests on
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


RecordingReader = Callable[[Path], Recording]
"""A reader: one trial file in, its cleaned :class:`Recording` out (times from the first wing opening); it raises
:class:`PhysicalDataError` when the file is not in its format."""

_READERS: dict[str, RecordingReader] = {}


def register_reader(suffix: str, reader: RecordingReader) -> None:
    """Read trial files named ``run5_W_W_W_W_L_K<suffix>`` (W: wing command, L: leg amplitude, degrees; K: trial)
    with ``reader``, from then on in every analysis that reads recordings (:func:`read_recording`,
    :func:`trial_files`). The lab's ``.bag.mat`` files are read by :func:`read_bag_mat`.

    Parameters
    ----------
    suffix : str
        File name ending, starting with a dot (``".bag.mat"``, ``".csv"``).
    reader : callable
        ``reader(path) -> Recording``.

    Raises
    ------
    ValueError
        If ``suffix`` does not start with a dot.

    Examples
    --------
    >>> register_reader(".bag.mat", read_bag_mat)  # the default, registered on import
    >>> trial_cell("run5_75_75_75_75_15_3.bag.mat")
    (75.0, 15.0)
    """
    if not suffix.startswith("."):
        raise ValueError(f"suffix must start with a dot, as '.bag.mat'; got {suffix!r}")
    _READERS[suffix] = reader


def _trial_match(name: str) -> tuple[re.Match | None, RecordingReader | None]:
    for suffix, reader in _READERS.items():
        m = re.search(_TRIAL_STEM + re.escape(suffix) + "$", name)
        if m:
            return m, reader
    return None, None


def _trial_names(k: str = "K") -> str:
    return " or ".join(f"run5_W_W_W_W_L_{k}{suffix}" for suffix in _READERS)


def trial_files(data_dir: str | Path) -> list[Path]:
    """The trial files (``run5_W_W_W_W_L_K.bag.mat``, or another registered format: :func:`register_reader`) of
    a data directory, sorted by (wing, leg, trial).

    Raises
    ------
    PhysicalDataError
        If the directory is absent or holds no trial file.
    """
    d = _data_dir(data_dir)
    files = [p for p in d.iterdir() if _trial_match(p.name)[0]]
    if not files:
        raise PhysicalDataError(
            f"'{d}' holds no trial file {_trial_names()}; give --data the lab's data-robot folder"
        )
    return sorted(files, key=lambda p: tuple(int(x) for x in _trial_match(p.name)[0].groups()[3:]))


def trial_cell(path: str | Path) -> tuple[float, float]:
    """The commanded wing angle and leg amplitude (degrees) a trial file's name gives (:func:`trial_files`).

    Examples
    --------
    >>> trial_cell("run5_60_60_60_60_30_2.bag.mat")
    (60.0, 30.0)
    """
    m = _trial_match(Path(path).name)[0]
    if m is None:
        raise PhysicalDataError(f"{Path(path).name} is not a trial file of the lab's ({_trial_names('N')})")
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
    """Read and clean one trial file with the reader registered for its name (:func:`register_reader`; the lab's
    ``.bag.mat`` files: :func:`read_bag_mat`).

    Raises
    ------
    PhysicalDataError
        If the file name is not ``run5_W_W_W_W_L_K`` with a registered suffix, or the reader refuses the file.
    """
    path = Path(path)
    reader = _trial_match(path.name)[1]
    if reader is None:
        raise PhysicalDataError(f"'{path.name}' is not a trial file name {_trial_names()}")
    return reader(path)


def read_bag_mat(path: str | Path) -> Recording:
    """Read and clean one of the lab's ``run5_W_W_W_W_L_K.bag.mat`` files (see the module docstring).

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


register_reader(".bag.mat", read_bag_mat)


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


def read_attempt_table(data_dir: str | Path):
    """The ``attempt`` struct array of the lab's ``robot_attempts.mat``, one entry per wing command.

    Raises
    ------
    PhysicalDataError
        If the file is absent or not the lab's.
    """
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


def attempt_plateau_deg(entry) -> float:
    """The median over attempts of the peak of one wing command's measured wing trace (an entry of
    :func:`read_attempt_table`), degrees; nan without a trace."""
    vals = [
        float(np.nanmax(w))
        for w in np.atleast_1d(entry.wing_angle)
        if np.size(w) and np.isfinite(np.asarray(w, dtype=np.float64)).any()
    ]
    return float(np.median(vals)) if vals else math.nan


def measured_plateaus_deg(data_dir: str | Path) -> dict[float, float]:
    """Measured wing plateau per wing command, degrees: the median over attempts of the peak of the lab's
    measured wing trace in ``robot_attempts.mat``."""
    att = read_attempt_table(data_dir)
    return {tw: attempt_plateau_deg(e) for tw, e in zip(WING_COMMANDS_DEG, att, strict=True)}
