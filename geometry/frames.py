"""The body-orientation convention, written once.

Body pitch ``p`` and roll ``r`` are ZYX Euler angles with yaw 0: the body-to-world rotation is
``R = Ry(p) @ Rx(r)``. World-up expressed in the body frame is

    u = R.T @ e_z = (-sin p, cos p sin r, cos p cos r).

At ``p = r = 0`` the robot lies upside down on its back (``u = +z``); it is upright when ``u_z < 0``.
Pitch and roll each span -180..180 deg: a torus that covers the sphere of up-directions twice, since
``(p, r)`` and ``(180 - p, r + 180)`` give the same ``u``. pybullet's ``getQuaternionFromEuler([r, p, 0])``
uses the same convention.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def _cos_sin(angle_rad: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """cos and sin that are exactly 0 and +-1 at multiples of 90 deg (so the pole rows are one orientation)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    quarter = angle_rad / (np.pi / 2)
    exact = np.abs(quarter - np.round(quarter)) < 1e-12
    k = np.round(quarter).astype(np.int64) % 4
    c = np.where(exact, np.array([1.0, 0.0, -1.0, 0.0])[k], c)
    s = np.where(exact, np.array([0.0, 1.0, 0.0, -1.0])[k], s)
    return c, s


def cos_sin(angle_rad: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Cosine and sine of angles in radians, exact at multiples of 90 deg.

    Examples
    --------
    >>> c, s = cos_sin(np.deg2rad([0.0, 90.0, 180.0]))
    >>> c.tolist(), s.tolist()
    ([1.0, 0.0, -1.0], [0.0, 1.0, 0.0])
    """
    return _cos_sin(np.asarray(angle_rad, dtype=np.float64))


def up_vector(pitch_rad: ArrayLike, roll_rad: ArrayLike) -> NDArray[np.float64]:
    """World-up in the body frame for body pitch and roll.

    Parameters
    ----------
    pitch_rad, roll_rad : array_like, broadcastable
        Body pitch and roll, radians.

    Returns
    -------
    u : ndarray of shape (..., 3)
        Unit vector ``(-sin p, cos p sin r, cos p cos r)``.

    Examples
    --------
    >>> (up_vector(0.0, 0.0) + 0.0).tolist()
    [0.0, 0.0, 1.0]
    >>> up_vector(np.pi / 2, 0.3).round(12).tolist()
    [-1.0, 0.0, 0.0]
    """
    cp, sp = cos_sin(pitch_rad)
    cr, sr = cos_sin(roll_rad)
    cp, sp, cr, sr = np.broadcast_arrays(cp, sp, cr, sr)
    return np.stack([-sp, cp * sr, cp * cr], axis=-1)


def pitch_roll_from_up(u: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pitch and roll (radians) of an up-direction, on the branch with ``|pitch| <= 90 deg``.

    At the poles ``u = (-+1, 0, 0)`` the roll is arbitrary and returned as 0.

    Examples
    --------
    >>> p, r = pitch_roll_from_up(up_vector(np.deg2rad(30.0), np.deg2rad(-120.0)))
    >>> float(np.rad2deg(p).round(9)), float(np.rad2deg(r).round(9))
    (30.0, -120.0)
    """
    u = np.asarray(u, dtype=np.float64)
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    pitch = np.arcsin(np.clip(-u[..., 0], -1.0, 1.0))
    roll = np.arctan2(u[..., 1], u[..., 2])
    roll = np.where(np.hypot(u[..., 1], u[..., 2]) < 1e-15, 0.0, roll)
    return pitch, roll


def canonical_pitch_roll_deg(pitch_deg: float, roll_deg: float) -> tuple[float, float]:
    """The same orientation on the branch ``|pitch| <= 90``, roll wrapped to [-180, 180).

    Examples
    --------
    >>> canonical_pitch_roll_deg(100.0, 0.0)
    (80.0, -180.0)
    """
    p = (pitch_deg + 180.0) % 360.0 - 180.0
    r = roll_deg
    if p > 90.0:
        p, r = 180.0 - p, r + 180.0
    elif p < -90.0:
        p, r = -180.0 - p, r + 180.0
    r = (r + 180.0) % 360.0 - 180.0
    return float(p), float(r)


def body_to_world(pitch_rad: float, roll_rad: float) -> NDArray[np.float64]:
    """Rotation matrix ``R = Ry(p) @ Rx(r)`` taking body-frame vectors to the world frame.

    Examples
    --------
    >>> R = body_to_world(0.4, -1.1)
    >>> np.allclose(R.T @ [0.0, 0.0, 1.0], up_vector(0.4, -1.1))
    True
    """
    (cp, sp), (cr, sr) = cos_sin(pitch_rad), cos_sin(roll_rad)
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return ry @ rx


def rpy_matrix(rpy_rad: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrix of a URDF ``rpy`` triple: fixed axes x, y, z, ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``.

    The one implementation of the URDF rotation (geometry reads every ``<origin>`` through it).

    Parameters
    ----------
    rpy_rad : array_like of shape (3,)
        Roll, pitch and yaw, radians.

    Returns
    -------
    R : ndarray of shape (3, 3)

    Examples
    --------
    >>> (rpy_matrix([0.0, 0.0, np.pi / 2]) @ [1.0, 0.0, 0.0]).round(12).tolist()
    [0.0, 1.0, 0.0]
    """
    r, p, y = np.asarray(rpy_rad, dtype=np.float64).reshape(3)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


def rpy_from_matrix(rot: ArrayLike) -> NDArray[np.float64]:
    """The URDF ``rpy`` triple (radians) of a rotation matrix, inverse of :func:`rpy_matrix`.

    Pitch lies in [-90, 90] deg; at pitch +-90 deg (gimbal lock) the yaw is returned as 0.

    Examples
    --------
    >>> rpy_from_matrix(rpy_matrix([0.1, -0.2, 0.3])).round(12).tolist()
    [0.1, -0.2, 0.3]
    """
    m = np.asarray(rot, dtype=np.float64).reshape(3, 3)
    cp = float(np.hypot(m[0, 0], m[1, 0]))
    pitch = float(np.arctan2(-m[2, 0], cp))
    if cp > 1e-8:  # below, roll and yaw are not separable to better than ~1e-8 rad anyway
        return np.array([np.arctan2(m[2, 1], m[2, 2]), pitch, np.arctan2(m[1, 0], m[0, 0])])
    roll = np.arctan2(m[0, 1], m[1, 1]) if m[2, 0] < 0 else np.arctan2(-m[0, 1], m[1, 1])
    return np.array([roll, pitch, 0.0])
