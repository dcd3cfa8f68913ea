"""Errors raised for bad robot descriptions and bad input.

Every bad-input error of the project derives from :class:`UsageError`, itself a :class:`ValueError`
(rasterio's ``CRSError(ValueError)`` pattern), so callers can catch either. The command line and the service
turn a :class:`UsageError` into one line (exit status 2, HTTP 4xx); any other exception is a bug and is
reported as one.
"""

from __future__ import annotations


class UsageError(ValueError):
    """Bad input from the user: the message says what is wrong and how to fix it (the one family the command
    line reports as a one-line error with exit status 2)."""


class GeometryError(UsageError):
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
