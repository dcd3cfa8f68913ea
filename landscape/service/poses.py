"""The robot drawn at an orientation: its part meshes posed by the library
(:meth:`geometry.Robot.pose`, :func:`landscape.viz.scene.posed_meshes_world`), resting on the ground, as plain
vertex and face arrays for the page, kept in a small LRU by (robot hash, theta_w, theta_l, pitch, roll)."""

from __future__ import annotations

import json
import math
import threading
from collections import OrderedDict

import numpy as np

from geometry.errors import UsageError

MAX_ABS_ORIENTATION_DEG = 360.0
"""Largest |pitch| and |roll| accepted, degrees: every orientation is reached within one turn either way."""
VERTEX_DECIMALS = 7
"""Vertices and CoM are answered rounded to 0.1 um (metres to 7 decimals)."""


def check_pose_request(
    entry, theta_w_deg: float, theta_l_deg: float, pitch_deg: float, roll_deg: float
) -> tuple[str, float | None, float | None, float, float]:
    """Validate a pose request and return its key (robot hash, theta_w, theta_l, pitch, roll).

    Rigid robots ignore the joint angles (None in the key); robots with joints check them against the joint
    limits.

    Raises
    ------
    UsageError
        If an angle is not finite, pitch or roll is outside [-360, 360] degrees, or a joint angle is outside its
        joint's limits (:class:`geometry.errors.JointLimitError`).
    """
    for name, v in (
        ("theta_w", theta_w_deg),
        ("theta_l", theta_l_deg),
        ("pitch", pitch_deg),
        ("roll", roll_deg),
    ):
        if not math.isfinite(v):
            raise UsageError(f"{name} must be a finite number of degrees; got {v!r}")
    for name, v in (("pitch", pitch_deg), ("roll", roll_deg)):
        if abs(v) > MAX_ABS_ORIENTATION_DEG:
            raise UsageError(
                f"{name} = {v:g} deg is outside [-{MAX_ABS_ORIENTATION_DEG:g}, {MAX_ABS_ORIENTATION_DEG:g}]: "
                "give the body orientation within one turn"
            )
    robot = entry.robot
    if robot.has_joints:
        robot.joint_values_rad(theta_w_deg, theta_l_deg)
        tw, tl = float(theta_w_deg), float(theta_l_deg)
    else:
        tw = tl = None
    return (robot.description_hash, tw, tl, float(pitch_deg), float(roll_deg))


def pose_answer(entry, key: tuple) -> dict:
    """The posed robot of a checked key, resting on the ground.

    Returns
    -------
    answer : dict
        ``robot``, ``description_hash``, ``theta_w_deg``, ``theta_l_deg`` (None for a rigid robot),
        ``pitch_deg``, ``roll_deg``; ``parts``: one ``{"vertices_m": (V, 3), "faces": (F, 3)}`` per part (its
        convex hull, world frame, m; faces index the part's vertices); ``com_m`` (3,) the CoM in the world frame,
        m, above the origin; ``com_height_m`` its height above the ground, m.
    """
    from landscape.viz.scene import posed_meshes_world

    _, tw, tl, pitch, roll = key
    with entry.lock:  # posing moves the robot's shared URDF model
        pose = entry.robot.pose(tw, tl)
    meshes, com_m = posed_meshes_world(pose, pitch, roll)
    return {
        "robot": entry.id,
        "description_hash": entry.robot.description_hash,
        "theta_w_deg": tw,
        "theta_l_deg": tl,
        "pitch_deg": pitch,
        "roll_deg": roll,
        "frame": "world: z up, ground at z = 0, CoM above the origin",
        "parts": [
            {
                "vertices_m": np.round(v, VERTEX_DECIMALS).tolist(),
                "faces": np.asarray(f, dtype=np.int64).tolist(),
            }
            for v, f in meshes
        ],
        "com_m": np.round(com_m, VERTEX_DECIMALS).tolist(),
        "com_height_m": round(float(com_m[2]), VERTEX_DECIMALS),
    }


class PoseCache:
    """Encoded pose answers by key: a bounded LRU (the page asks for the same start and saddle again and again)."""

    def __init__(self, *, max_entries: int = 64):
        self.max_entries = max_entries
        self._bodies: OrderedDict[tuple, bytes] = OrderedDict()
        self._lock = threading.Lock()

    def body(self, entry, key: tuple) -> bytes:
        """The JSON answer of a checked key, from the cache or posed now."""
        with self._lock:
            b = self._bodies.get(key)
            if b is not None:
                self._bodies.move_to_end(key)
                return b
        b = json.dumps(pose_answer(entry, key)).encode()
        with self._lock:
            self._bodies[key] = b
            while len(self._bodies) > self.max_entries:
                self._bodies.popitem(last=False)
        return b
