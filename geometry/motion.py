"""How a posed robot moves when one of its joint groups turns: the body-frame velocity of every hull point and of
the CoM per radian of theta_w or theta_l (the posed body's joint Jacobian, in closed form).

A revolute joint turning at rate ``q'`` moves every point ``x`` of the links it carries by ``q' w x (x - o)``, with
``w`` its unit axis and ``o`` its origin in the body frame at the pose; a prismatic joint by ``q' a`` (its axis as
written, as :func:`geometry.kinematics.joint_motion` applies it). Every joint of the group turns at rate 1 (each
is set to theta), a joint mimicking one of them at ``multiplier``, as :meth:`geometry.Robot.link_transforms`
sets them.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from functools import cached_property

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
    com_m_per_rad: NDArray[np.float64]
    _spin: NDArray[np.float64] = field(repr=False)  # (P, 3) per part: v(x) = spin x x + shift
    _shift: NDArray[np.float64] = field(repr=False)
    _part_of_row: NDArray[np.int64] = field(repr=False)  # (M,) the part of each hull point
    _points: NDArray[np.float64] = field(repr=False)  # (M, 3) the hull points

    @cached_property
    def hull_points_m_per_rad(self) -> NDArray[np.float64]:
        return self.at(np.arange(len(self._points)))

    def at(self, rows) -> NDArray[np.float64]:
        """Velocities of the hull points of these rows of :attr:`geometry.Pose.hull_points_m`, shape (N, 3),
        m/rad (computed for them alone)."""
        part = self._part_of_row[rows]
        return _cross(self._spin[part], self._points[rows]) + self._shift[part]


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
    plan = _plan(robot, pose.parts)
    coms = np.array([T[link][:3, :3] @ c + T[link][:3, 3] for link, c in plan.heavy_coms])
    points = np.asarray(pose.hull_points_m, dtype=np.float64)
    out = {}
    for angle, (joints, rates, carried) in plan.groups.items():
        spins, shifts = np.zeros((len(joints), 3)), np.zeros((len(joints), 3))
        for k, (j, rate) in enumerate(zip(joints, rates, strict=True)):
            frame = T[j.parent] @ j.origin
            if j.type == "prismatic":
                shifts[k] = rate * (frame[:3, :3] @ j.axis)
            else:
                spins[k] = rate * (frame[:3, :3] @ (j.axis / np.linalg.norm(j.axis)))
                shifts[k] = -_cross(spins[k], frame[:3, 3])
        spin, shift = carried @ spins, carried @ shifts  # (P, 3): each part's v(x) = spin x x + shift
        h = plan.heavy
        com = plan.masses @ (_cross(spin[h], coms) + shift[h]) / plan.masses.sum() if len(h) else np.zeros(3)
        out[angle] = PoseRate(angle, com, spin, shift, plan.part_of_row, points)
    return out


@dataclass(frozen=True)
class _Plan:
    """What of a robot's structure :func:`pose_rates` needs, the same at every pose: per joint group the joints it
    turns, their rates and which parts each carries; the parts with mass; the part of each hull point."""

    groups: dict
    heavy: NDArray[np.int64]
    masses: NDArray[np.float64]
    heavy_coms: list
    part_of_row: NDArray[np.int64]


_PLANS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _plan(robot, parts) -> _Plan:
    plan = _PLANS.get(robot)
    if plan is not None and plan[0] is parts:
        return plan[1]
    actuated = {j.name for j in robot.joints if j.actuated}
    chain_names = {link: {j.name for j in chain} for link, chain in robot.kinematic_chains().items()}
    groups = {}
    for angle, group in _GROUPS.items():
        names = set(getattr(robot.joint_map, group))
        if not names:
            continue
        moving = [
            (j, _rate(j, names, actuated))
            for j in robot.joints
            if _rate(j, names, actuated) and j.type in (*MOVABLE_JOINT_TYPES, "prismatic")
        ]
        carried = np.array([[j.name in chain_names[p.link] for j, _ in moving] for p in parts], float)
        groups[angle] = ([j for j, _ in moving], [r for _, r in moving], carried.reshape(len(parts), -1))
    heavy = np.array([k for k, p in enumerate(parts) if p.mass.mass_kg > 0], dtype=np.int64)
    made = _Plan(
        groups,
        heavy,
        np.array([parts[k].mass.mass_kg for k in heavy]),
        [(parts[k].link, parts[k].mass.com_m) for k in heavy],
        np.repeat(np.arange(len(parts)), [len(p.hull_link_m) for p in parts]),
    )
    _PLANS[robot] = (parts, made)
    return made


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
