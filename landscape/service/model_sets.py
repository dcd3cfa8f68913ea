"""The ``model`` parameter of the service: a model set shipped with the package (``sim/models/``), by name only.

A set poses the wings as ``landscape compute --model NAME`` does (:meth:`sim.model_set.ModelSet.wing_joints_deg`):
a measured set holds each wing servo at its own plateau, an idealised one every wing joint at theta_w. The
service never reads a model file named by a request: anything but a shipped name is refused. :mod:`sim.model_set`
(and with it pybullet) is imported only when a request names a set.
"""

from __future__ import annotations

from functools import lru_cache

from geometry.errors import UsageError

_SHOWN_CHARS = 40
"""Longest refused value repeated in the message, characters."""


def shipped_model_set(model: str | None):
    """The shipped :class:`sim.model_set.ModelSet` named ``model``; None without a name.

    Raises
    ------
    UsageError
        If ``model`` is not the name of a shipped set (a file path included).
    """
    if model is None:
        return None
    from sim.model_set import shipped_model_sets

    names = shipped_model_sets()
    if model not in names:
        shown = model if len(model) <= _SHOWN_CHARS else model[:_SHOWN_CHARS] + "..."
        raise UsageError(
            f"model must be a shipped model set ({', '.join(names)}); got {shown!r}: "
            "the service reads no model files"
        )
    from sim.model_set import MODELS_DIR

    return _load(model, (MODELS_DIR / f"{model}.toml").stat().st_mtime_ns)


@lru_cache(maxsize=32)
def _load(name: str, mtime_ns: int):
    """The shipped set ``name`` as its file was at ``mtime_ns``: every request that names a set (its key, its
    wing joints, its CoM) reads the file once, and an edited file is read again."""
    from sim.model_set import load_model_set

    return load_model_set(name)


def model_set_list() -> list[dict]:
    """Every shipped set, by name, as ``GET /api/model-sets`` answers it: :meth:`sim.model_set.ModelSet.summary`
    of each (the list ``landscape models --json`` prints)."""
    from sim.model_set import shipped_model_sets

    return [shipped_model_set(name).summary() for name in shipped_model_sets()]


def map_wing_joints_deg(model: str | None, robot, theta_w_deg: list[float]) -> dict[float, dict] | None:
    """:func:`set_wing_joints_deg` per theta_w of a barrier map (its ``wing_joints_deg``); None when the set poses
    every wing joint at theta_w (no set, or an idealised one)."""
    ms = shipped_model_set(model)
    if ms is None:
        return None
    return ms.wing_joints_by_theta_w(robot.joint_map.wing if robot.has_joints else (), theta_w_deg)


def robot_for(model: str | None, robot):
    """``robot`` as the shipped set ``model`` models it (:meth:`sim.model_set.ModelSet.robot_for`: its CoM moved by
    the set's ``[mass]`` offset, if any), or ``robot`` itself without a set."""
    ms = shipped_model_set(model)
    return robot if ms is None else ms.robot_for(robot)


def set_wing_joints_deg(ms, robot, theta_w_deg: float) -> dict[str, float] | None:
    """The wing joints' angles (degrees) the loaded shipped set ``ms`` (:func:`shipped_model_set`) holds at the
    wing command ``theta_w_deg``; None without a set or for an idealised one (every wing joint at theta_w).

    Raises
    ------
    UsageError
        If ``theta_w_deg`` lies outside the set's measured commands, or the robot has not the wing joints the
        set measures (:class:`sim.model_set.ModelSetError`).
    """
    if ms is None:
        return None
    names = robot.joint_map.wing if robot.has_joints else ()
    return ms.wing_joints_deg(names, theta_w_deg)
