"""Errors raised for bad robot descriptions and bad input.

All subclass :class:`ValueError` (rasterio's ``CRSError(ValueError)`` pattern) so callers can catch either.
The command line turns any of them into one line on stderr and exit status 2.
"""

from __future__ import annotations


class GeometryError(ValueError):
    """Base class for every bad-input error of the geometry layer."""


class NotAVolumeError(GeometryError):
    """A solid's volume or CoM was asked of a mesh that does not bound a volume."""


class RobotDescriptionError(GeometryError):
    """A robot description (URDF or mesh file) is missing, unreadable or inconsistent."""


class UnknownJointError(GeometryError):
    """A joint named in a joint mapping does not exist in the robot."""


class JointLimitError(GeometryError):
    """A joint value lies outside the joint's limits."""


JOINT_OUT_OF_RANGE = (
    "{what} = {got:g} deg is outside joint '{joint}' limits [{lo:g}, {hi:g}] deg; choose a value inside them"
)
