"""Pictures of a recorded trial: the trace replayed pose by pose in a pybullet DIRECT client and photographed with
pybullet's software renderer (``ER_TINY_RENDERER``: no display, no OpenGL).

The replay is kinematic: each frame puts the robot at the trace's body pitch and roll, its wing joints at the
measured wing angle and its leg joint at the measured leg angle, and its CoM at the recorded height above the
ground. The trace does not record the robot's heading or where it slid to, so every frame shows it with yaw 0 and
its CoM above the origin. The robot is drawn with its simulated collision hulls (what touched the ground).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from geometry import JointMap
from geometry.errors import UsageError

from .model import sim_model
from .world import World, pb

__all__ = ["MAX_FPS", "frame_rows", "replay_frames"]

MAX_FPS = 100.0
"""Highest frame rate, frames/s: the trace's own rate (``sim.trial.TRACE_EVERY_S`` = 10 ms)."""
PALETTE_RGBA = (
    (0.55, 0.63, 0.80, 1.0),
    (0.40, 0.76, 0.65, 1.0),
    (0.99, 0.55, 0.38, 1.0),
    (0.91, 0.54, 0.76, 1.0),
    (0.65, 0.85, 0.33, 1.0),
    (1.00, 0.85, 0.18, 1.0),
    (0.90, 0.77, 0.58, 1.0),
    (0.70, 0.70, 0.70, 1.0),
)


def frame_rows(t_s: ArrayLike, fps: float) -> NDArray[np.int64]:
    """Rows of a trace shown by a video at ``fps``: frame k shows time ``t_s[0] + k / fps`` (the nearest row), for
    every such time up to the trace's last.

    Parameters
    ----------
    t_s : array_like of shape (N,)
        Trace times, s, increasing.
    fps : float
        Frames per second, in (0, ``MAX_FPS``].

    Returns
    -------
    rows : ndarray of int, shape (K,)
        ``K = floor((t_s[-1] - t_s[0]) * fps) + 1``; the video lasts ``K / fps`` s.

    Raises
    ------
    UsageError
        If ``fps`` is out of range or the trace is empty or not increasing.

    Examples
    --------
    >>> frame_rows(np.arange(1, 101) * 0.01, 25.0)[:4].tolist(), len(frame_rows(np.arange(1, 101) * 0.01, 25.0))
    ([0, 4, 8, 12], 25)
    """
    t = np.asarray(t_s, dtype=np.float64).reshape(-1)
    if not (np.isfinite(fps) and 0 < fps <= MAX_FPS):
        raise UsageError(
            f"fps must be in (0, {MAX_FPS:g}] frames/s (the trace has {MAX_FPS:g} rows/s); got {fps!r}"
        )
    if len(t) == 0 or not np.isfinite(t).all() or (len(t) > 1 and not (np.diff(t) > 0).all()):
        raise UsageError("the trace must have at least one row and strictly increasing finite times t_s")
    n = int(np.floor((t[-1] - t[0]) * fps + 1e-9)) + 1
    if len(t) == 1:
        return np.zeros(n, dtype=np.int64)
    at = t[0] + np.arange(n) / fps
    i = np.clip(np.searchsorted(t, at), 1, len(t) - 1)
    return np.where(at - t[i - 1] <= t[i] - at, i - 1, i).astype(np.int64)


def replay_frames(
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    com_height_m: ArrayLike,
    wing_deg: ArrayLike,
    leg_deg: ArrayLike,
    *,
    robot: str | Path | None = None,
    joint_map: JointMap | None = None,
    width_px: int = 480,
    height_px: int = 352,
    distance_m: float | None = None,
    yaw_deg: float = 35.0,
    elevation_deg: float = 25.0,
) -> Iterator[NDArray[np.uint8]]:
    """RGB images of the robot at each recorded state, one per row of the given arrays.

    Parameters
    ----------
    pitch_deg, roll_deg : array_like of shape (K,)
        Body pitch and roll, degrees (``geometry/frames.py``).
    com_height_m : array_like of shape (K,)
        CoM height above the ground, m.
    wing_deg, leg_deg : array_like of shape (K,)
        Wing angle (every wing joint) and leg angle, degrees.
    robot : path, optional
        URDF the trial ran (default: the built-in robot); ``joint_map`` as for :func:`sim.trial.run_trial`.
    width_px, height_px : int
        Image size, pixels (multiples of 16 keep video encoders from resizing).
    distance_m : float, optional
        Camera distance from the CoM's resting height above the origin, m; default 2.2 times the robot's size.
    yaw_deg, elevation_deg : float
        Camera direction round the vertical and above the ground, degrees.

    Yields
    ------
    rgb : ndarray of uint8, shape (height_px, width_px, 3)

    Raises
    ------
    UsageError
        If the arrays differ in length or hold a non-finite value, or the image size is not positive.
    RobotDescriptionError
        If the robot cannot be loaded.
    """
    cols = [
        np.asarray(a, dtype=np.float64).reshape(-1)
        for a in (pitch_deg, roll_deg, com_height_m, wing_deg, leg_deg)
    ]
    if len({len(c) for c in cols}) != 1:
        raise UsageError(
            f"pitch, roll, CoM height, wing and leg arrays must have one length; got {[len(c) for c in cols]}"
        )
    if not all(np.isfinite(c).all() for c in cols):
        raise UsageError("the replayed trace holds a non-finite value; check the trace")
    if int(width_px) < 16 or int(height_px) < 16:
        raise UsageError(f"image size must be at least 16 x 16 pixels; got {width_px} x {height_px}")
    p_rad, r_rad = np.deg2rad(cols[0]), np.deg2rad(cols[1])
    h_m, wing_rad, leg_rad = cols[2], np.deg2rad(cols[3]), np.deg2rad(cols[4])
    model = sim_model(robot, joint_map=joint_map)
    with World(model, dt_s=1e-3) as world:
        cid, body = world.cid, world.body
        for k, link in enumerate(world.links):
            pb.changeVisualShape(
                body, link, rgbaColor=PALETTE_RGBA[k % len(PALETTE_RGBA)], physicsClientId=cid
            )
        n_wing = len(world.wing_joints)
        zeros = np.zeros(len(world.driven))
        world.place(0.0, 0.0, joints_rad=zeros)
        lo = np.min([pb.getAABB(body, k, physicsClientId=cid)[0] for k in world.links], axis=0)
        hi = np.max([pb.getAABB(body, k, physicsClientId=cid)[1] for k in world.links], axis=0)
        size_m = float(np.max(hi - lo))
        target = [0.0, 0.0, float(np.median(h_m)) if len(h_m) else 0.0]
        view = pb.computeViewMatrixFromYawPitchRoll(
            cameraTargetPosition=target,
            distance=distance_m or 2.2 * size_m,
            yaw=yaw_deg,
            pitch=-elevation_deg,
            roll=0.0,
            upAxisIndex=2,
            physicsClientId=cid,
        )
        proj = pb.computeProjectionMatrixFOV(
            fov=40.0,
            aspect=width_px / height_px,
            nearVal=0.01 * size_m,
            farVal=100.0 * size_m,
            physicsClientId=cid,
        )
        for k in range(len(h_m)):
            joints = np.concatenate(
                [np.full(n_wing, wing_rad[k]), np.full(len(world.driven) - n_wing, leg_rad[k])]
            )
            world.place(p_rad[k], r_rad[k], joints_rad=joints)
            pos, q = pb.getBasePositionAndOrientation(body, physicsClientId=cid)
            com = _com_m(world)
            # the CoM above the origin at the recorded height
            pb.resetBasePositionAndOrientation(
                body, [pos[0] - com[0], pos[1] - com[1], pos[2] + h_m[k] - com[2]], q, physicsClientId=cid
            )
            img = pb.getCameraImage(
                int(width_px),
                int(height_px),
                view,
                proj,
                renderer=pb.ER_TINY_RENDERER,
                shadow=1,
                lightDirection=[0.4, -0.6, 1.0],
                physicsClientId=cid,
            )
            rgba = np.asarray(img[2], dtype=np.uint8).reshape(int(height_px), int(width_px), 4)
            yield np.ascontiguousarray(rgba[:, :, :3])


def _com_m(world: World) -> NDArray[np.float64]:
    """The whole robot's CoM in the world frame, m (mass-weighted link CoMs)."""
    cid = world.cid
    pts = [pb.getBasePositionAndOrientation(world.body, physicsClientId=cid)[0]]
    pts += [s[0] for s in pb.getLinkStates(world.body, list(range(world.n_joints)), physicsClientId=cid)]
    return world.link_mass_kg @ np.asarray(pts, dtype=np.float64) / world.mass_kg
