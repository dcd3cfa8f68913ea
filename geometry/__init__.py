"""Robot descriptions, kinematics and mass properties: the base layer (no I/O beyond reading descriptions).

Names below load on first use (PEP 562), so importing one light module (``geometry.errors``) does not load
trimesh and scipy.
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    **dict.fromkeys(
        (
            "GeometryError",
            "JointLimitError",
            "NotAVolumeError",
            "RobotDescriptionError",
            "UnknownJointError",
            "UsageError",
        ),
        "geometry.errors",
    ),
    **dict.fromkeys(
        ("body_to_world", "canonical_pitch_roll_deg", "pitch_roll_from_up", "up_vector"), "geometry.frames"
    ),
    **dict.fromkeys(("Hull", "convex_hull"), "geometry.hull"),
    **dict.fromkeys(
        ("MassProperties", "mesh_mass_properties", "shell_mass_properties", "solid_mass_properties"),
        "geometry.mass",
    ),
    "JointMap": "geometry.joint_map",
    **dict.fromkeys(("Part", "Pose"), "geometry.pose"),
    "Robot": "geometry.robot",
    **dict.fromkeys(("load_robot", "robot_urdf_path"), "geometry.robots"),
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'geometry' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
