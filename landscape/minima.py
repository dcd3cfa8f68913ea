"""Start states: grid minima by steepest descent, and the metastable state by quasi-static continuation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geometry import Pose, Robot
from geometry.frames import canonical_pitch_roll_deg

from . import _kernels
from .energy import G_M_S2, Landscape, height_at
from .grid import nearest_cell

CONTINUATION_STEP_DEG = 1.0   # joint-angle increment of the quasi-static continuation
_PATTERN_STEPS_DEG = (2.0, 1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125)
_DIRS = np.array([(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)], dtype=np.float64)


@dataclass(frozen=True)
class Minimum:
    """A local minimum of the landscape.

    Attributes
    ----------
    pitch_deg, roll_deg : float
        Orientation, degrees, on the branch |pitch| <= 90.
    energy_j, height_m : float
        Potential energy m g h, J, and CoM height h, m.
    """

    pitch_deg: float
    roll_deg: float
    energy_j: float
    height_m: float


def local_descent(pose: Pose, pitch_deg: float, roll_deg: float) -> tuple[float, float]:
    """Pattern-search descent of h from an orientation, continuous in angle (to 0.03 deg).

    Moves to the lowest of 8 neighbours at a shrinking step; deterministic; returns canonical (pitch, roll).
    """
    p, r = float(pitch_deg), float(roll_deg)
    h = float(height_at(pose, p, r))
    for step in _PATTERN_STEPS_DEG:
        while True:
            cand = np.array([p, r]) + step * _DIRS
            hc = height_at(pose, cand[:, 0], cand[:, 1])
            k = int(np.argmin(hc))
            if hc[k] < h - 1e-15:
                p, r, h = float(cand[k, 0]), float(cand[k, 1]), float(hc[k])
            else:
                break
    return canonical_pitch_roll_deg(p, r)


def follow_minimum(robot: Robot, path_deg: list[tuple[float, float]], *, pitch_deg: float = 0.0,
                   roll_deg: float = 0.0) -> list[tuple[float, float]]:
    """Quasi-static continuation: descend at each (theta_w, theta_l) of a path, starting where the last ended.

    Returns the (pitch, roll) reached at every point of the path, degrees.
    """
    out = []
    p, r = pitch_deg, roll_deg
    for tw, tl in path_deg:
        p, r = local_descent(robot.pose(tw, tl), p, r)
        out.append((p, r))
    return out


def ramp_deg(a: float, b: float) -> list[float]:
    """Angles from a (excluded) to b (included) in steps of at most CONTINUATION_STEP_DEG; [] when a == b.

    Examples
    --------
    >>> ramp_deg(0.0, 2.5), ramp_deg(3.0, 3.0)
    ([0.8333333333333334, 1.6666666666666667, 2.5], [])
    """
    n = int(np.ceil(abs(b - a) / CONTINUATION_STEP_DEG))
    return [float(x) for x in np.linspace(a, b, n + 1)[1:]] if n else []


def opening_path(theta_w_deg: float, theta_l_deg: float) -> list[tuple[float, float]]:
    """Joint path of a slow opening from rest: theta_w from 0, then theta_l from 0, in <= 1 deg steps."""
    path = [(0.0, 0.0)]
    path += [(w, 0.0) for w in ramp_deg(0.0, theta_w_deg)]
    path += [(theta_w_deg, l_) for l_ in ramp_deg(0.0, theta_l_deg)]
    return path


def metastable_orientation(robot: Robot, theta_w_deg: float, theta_l_deg: float) -> tuple[float, float]:
    """Where the robot rests after opening its wings slowly from rest on its back (pitch, roll in degrees).

    Starts at pitch = roll = 0 with theta_w = theta_l = 0, and follows the local minimum as theta_w, then
    theta_l, grow in 1 deg steps. A robot without joints descends from pitch = roll = 0.
    """
    if not robot.has_joints:
        return local_descent(robot.pose(), 0.0, 0.0)
    robot.joint_values_rad(theta_w_deg, theta_l_deg)  # validate before the long walk
    return follow_minimum(robot, opening_path(theta_w_deg, theta_l_deg))[-1]


def grid_minimum(landscape: Landscape, pitch_deg: float, roll_deg: float) -> tuple[int, int]:
    """The grid cell reached by 8-neighbour steepest descent from the cell nearest an orientation."""
    i, j = nearest_cell(pitch_deg, roll_deg, landscape.step_deg)
    i, j = _kernels.descend(landscape.energy_j, i, j)
    return int(i), int(j)


def as_minimum(landscape: Landscape, i: int, j: int, g_m_s2: float = G_M_S2) -> Minimum:
    e = landscape.at(i, j)
    p, r = canonical_pitch_roll_deg(landscape.angles_deg[i], landscape.angles_deg[j])
    return Minimum(p, r, e, e / (landscape.mass_kg * landscape.g_m_s2))
