"""How a posed robot moves when one of its joint groups turns: the body-frame velocity of every hull point and of
the CoM per radian of theta_w or theta_l (the posed body's joint Jacobian, in closed form).

A revolute joint turning at rate ``q'`` moves every point ``x`` of the links it carries by ``q' w x (x - o)``, with
``w`` its unit axis and ``o`` its origin in the body frame at the pose; a prismatic joint by ``q' a`` (its axis as
written, as :func:`geometry.kinematics.joint_motion` applies it). Every joint of the group turns at rate 1 (each
is set to theta), a joint mimicking one of them at ``multiplier``, as :meth:`geometry.Robot.link_transforms`
sets them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .joint_map import _GROUPS
from .kinematics import MOVABLE_JOINT_TYPES

__all__ = ["PoseRate", "pose_rates"]


@dataclass(frozen=True)
class PoseRate:
    """The posed body's motion per radian of one joint-group angle.

    Attributes
    ----------
    angle : str
        ``"theta_w"`` or ``"theta_l"``.
    hull_points_m_per_rad : ndarray of shape (M, 3)
        Velocity of each row of :attr:`geometry.Pose.hull_points_m`, body frame, m/rad.
    com_m_per_rad : ndarray of shape (3,)
        Velocity of the whole body's CoM, body frame, m/rad.
    """

    angle: str
    hull_points_m_per_rad: NDArray[np.float64]
    com_m_per_rad: NDArray[np.float64]


def pose_rates(robot, pose) -> dict[str, PoseRate]:
    """Velocities of a posed body's hull points and CoM per radian of each angle its joints take.

    Parameters
    ----------
    robot : geometry.Robot
    pose : geometry.Pose
        The robot posed (:meth:`geometry.Robot.pose`, or :meth:`geometry.Robot.pose_joints` with each wing joint at
        its own angle: the derivative is then that of turning every wing joint together).

    Returns
    -------
    dict of str to PoseRate
        One entry per angle some joint takes (``"theta_w"``, ``"theta_l"``); empty for a rigid body.

    Examples
    --------
    Turning the built-in robot's leg swings its CoM sideways (-y), not up or along the body:

    >>> from geometry.robots import load_robot
    >>> robot = load_robot()
    >>> pose = robot.pose(74.0, 0.0)
    >>> r = pose_rates(robot, pose)
    >>> sorted(r), r["theta_w"].hull_points_m_per_rad.shape == pose.hull_points_m.shape
    (['theta_l', 'theta_w'], True)
    >>> (r["theta_l"].com_m_per_rad * 1e3).round(2).tolist()
    [0.0, -13.35, 0.0]
    """
    if not robot.has_joints:
        return {}
    T = pose.link_transforms
    actuated = {j.name for j in robot.joints if j.actuated}
    chains = robot.kinematic_chains()
    out = {}
    for angle, group in _GROUPS.items():
        names = set(getattr(robot.joint_map, group))
        if not names:
            continue
        screws = {}  # joint -> (spin, shift) per radian of the group, body frame
        for j in robot.joints:
            rate = _rate(j, names, actuated)
            if not rate or j.type not in (*MOVABLE_JOINT_TYPES, "prismatic"):
                continue
            frame = T[j.parent] @ j.origin
            if j.type == "prismatic":
                screws[j.name] = (np.zeros(3), rate * (frame[:3, :3] @ j.axis))
            else:
                w = rate * (frame[:3, :3] @ (j.axis / np.linalg.norm(j.axis)))
                screws[j.name] = (w, -_cross(w, frame[:3, 3]))
        spins, shifts, counts = [], [], []
        com, mass = np.zeros(3), 0.0
        for part in pose.parts:
            moving = [screws[j.name] for j in chains[part.link] if j.name in screws]
            spin = np.sum([m[0] for m in moving], axis=0) if moving else np.zeros(3)
            shift = np.sum([m[1] for m in moving], axis=0) if moving else np.zeros(3)
            if len(part.hull_link_m):
                spins.append(spin)
                shifts.append(shift)
                counts.append(len(part.hull_link_m))
            if part.mass.mass_kg > 0:
                Tl = T[part.link]
                c = Tl[:3, :3] @ part.mass.com_m + Tl[:3, 3]
                com += part.mass.mass_kg * (_cross(spin, c) + shift)
                mass += part.mass.mass_kg
        counts = np.array(counts)
        spin_of = np.repeat(np.array(spins), counts, axis=0)
        shift_of = np.repeat(np.array(shifts), counts, axis=0)
        points = _cross(spin_of, np.asarray(pose.hull_points_m, dtype=np.float64)) + shift_of
        out[angle] = PoseRate(angle, points, com / mass if mass > 0 else com)
    return out


def _rate(j, names: set[str], actuated: set[str]) -> float:
    """How fast joint j turns per radian of the group ``names`` (yourdfpy's mimic rule, as
    :meth:`geometry.Robot.link_transforms` applies it)."""
    if j.mimic:
        return j.multiplier if j.mimic in actuated and j.mimic in names else 0.0
    return 1.0 if j.name in names else 0.0


def _cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``np.cross`` of 3-vectors (or rows of them), without its axis handling."""
    out = np.empty(np.broadcast_shapes(np.shape(a), np.shape(b)))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out
