"""The robot drawn at an orientation: its part meshes posed by the library
(:meth:`geometry.Robot.pose`, :func:`landscape.viz.scene.posed_meshes_world`), resting on the ground, as plain
vertex and face arrays for the page, kept in a small LRU by (robot hash, theta_w, theta_l, pitch, roll, model set
name, its hash, the wing joints' angles it gives).

With a shipped model set (``model``) the robot is the one the set models, as in ``GET /api/landscape?model=``:
its wing joints held where the set holds them (:func:`.model_sets.set_wing_joints_deg`) and its CoM moved by the
set's offset (:func:`.model_sets.robot_for`)."""

from __future__ import annotations

import json
import math
import threading
from collections import OrderedDict

import numpy as np

from geometry.bounds import ORIENTATION_DEG_BOUNDS
from geometry.errors import UsageError

VERTEX_DECIMALS = 7
"""Vertices and CoM are answered rounded to 0.1 um (metres to 7 decimals)."""


def check_pose_request(
    entry,
    theta_w_deg: float,
    theta_l_deg: float,
    pitch_deg: float,
    roll_deg: float,
    *,
    model: str | None = None,
) -> tuple:
    """Validate a pose request and return its key (robot hash, theta_w, theta_l, pitch, roll, model, set hash,
    wing joints).

    Rigid robots ignore the joint angles (None in the key); robots with joints check them against the joint
    limits. ``model`` names a shipped model set (None: every wing joint at theta_w, the CoM the robot's own); the
    key holds its name, its hash (a set whose content changes is not answered from the cache) and the wing
    joints' angles it holds at theta_w (None for an idealised set).

    Raises
    ------
    UsageError
        If an angle is not finite, pitch or roll is outside
        :data:`geometry.bounds.ORIENTATION_DEG_BOUNDS` ([-360, 360] degrees), a joint angle is outside its
        joint's limits (:class:`geometry.errors.JointLimitError`), ``model`` is not a shipped set's name, or the
        set cannot pose this robot at theta_w (:func:`.model_sets.set_wing_joints_deg`).
    """
    from .model_sets import set_wing_joints_deg, shipped_model_set

    for name, v in (
        ("theta_w", theta_w_deg),
        ("theta_l", theta_l_deg),
        ("pitch", pitch_deg),
        ("roll", roll_deg),
    ):
        if not math.isfinite(v):
            raise UsageError(f"{name} must be a finite number of degrees; got {v!r}")
    for name, v in (("pitch", pitch_deg), ("roll", roll_deg)):
        ORIENTATION_DEG_BOUNDS.check(v, name)
    robot = entry.robot
    if robot.has_joints:
        robot.joint_values_rad(theta_w_deg, theta_l_deg)
        tw, tl = float(theta_w_deg), float(theta_l_deg)
    else:
        tw = tl = None
    ms = shipped_model_set(model)
    joints = set_wing_joints_deg(ms, robot, theta_w_deg)
    return (
        robot.description_hash,
        tw,
        tl,
        float(pitch_deg),
        float(roll_deg),
        model,
        None if ms is None else ms.model_set_hash,
        None if joints is None else tuple(joints.items()),
    )


def pose_answer(entry, key: tuple) -> dict:
    """The posed robot of a checked key, resting on the ground.

    Returns
    -------
    answer : dict
        ``robot``, ``description_hash``, ``theta_w_deg``, ``theta_l_deg`` (None for a rigid robot),
        ``pitch_deg``, ``roll_deg``; ``model_set``, ``model_set_hash`` and ``wing_joints_deg`` (the set's
        name, hash and wing joints' angles, degrees; all None without a set, the joints None for an idealised
        set); ``parts``: one ``{"vertices_m": (V, 3), "faces": (F, 3)}`` per part (its convex hull, world frame,
        m; faces index the part's vertices); ``com_m`` (3,) the CoM in the world frame, m, above the origin;
        ``com_height_m`` its height above the ground, m; ``com_body_m`` (3,) the CoM in the body frame, m.
    """
    from landscape.computation import posed
    from landscape.viz.scene import posed_meshes_world

    from .model_sets import robot_for

    _, tw, tl, pitch, roll, model, set_hash, joints_key = key
    joints = None if joints_key is None else dict(joints_key)
    robot = robot_for(model, entry.robot)  # a set may move the CoM, as in its landscape
    with entry.lock:  # posing moves the robot's shared URDF model
        pose = posed(robot, tw, tl, joints)
    meshes, com_m = posed_meshes_world(pose, pitch, roll)
    return {
        "robot": entry.id,
        "description_hash": entry.robot.description_hash,
        "theta_w_deg": tw,
        "theta_l_deg": tl,
        "pitch_deg": pitch,
        "roll_deg": roll,
        "model_set": model,
        "model_set_hash": set_hash,
        "wing_joints_deg": joints,
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
        "com_body_m": np.round(pose.com_m, VERTEX_DECIMALS).tolist(),
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
