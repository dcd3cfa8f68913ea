"""Robot descriptions, kinematics and mass properties: the base layer (no I/O beyond reading descriptions)."""

from .errors import (
    GeometryError,
    JointLimitError,
    NotAVolumeError,
    RobotDescriptionError,
    UnknownJointError,
)
from .frames import body_to_world, canonical_pitch_roll_deg, pitch_roll_from_up, up_vector
from .hull import Hull, convex_hull
from .mass import MassProperties, mesh_mass_properties, shell_mass_properties, solid_mass_properties
from .robot import JointMap, Part, Pose, Robot

__all__ = [
    "GeometryError", "JointLimitError", "NotAVolumeError", "RobotDescriptionError", "UnknownJointError",
    "body_to_world", "canonical_pitch_roll_deg", "pitch_roll_from_up", "up_vector",
    "Hull", "convex_hull", "MassProperties", "mesh_mass_properties", "shell_mass_properties",
    "solid_mass_properties", "JointMap", "Part", "Pose", "Robot",
]
