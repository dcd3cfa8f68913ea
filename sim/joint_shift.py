"""A model set's ``[geometry]`` table: one joint's origin moved, with everything it carries (a
:class:`sim.modifier.Modifier`).

A part the robot's description places where the real one does not touch the ground. The shift applies to the
simulation (:func:`sim.urdf_edits.shift_joint`) and to every landscape the set poses
(:meth:`geometry.Robot.with_joint_shift`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from . import urdf_edits
from .modifier import ModelSetError, Modifier, check_keys, register

MAX_JOINT_SHIFT_MM = 30.0
"""Largest ``[geometry] shift_mm`` component (either way), mm: a correction for a part the description places
where the real one does not touch the ground, not a new robot."""


@register
@dataclass(frozen=True)
class JointShift(Modifier):
    """One joint's origin moved in its parent link's frame.

    Attributes
    ----------
    joint : str
        The joint's name.
    shift_mm : tuple of 3 floats
        x, y, z in the joint's parent frame, mm, each within ±``MAX_JOINT_SHIFT_MM``.

    Examples
    --------
    >>> JointShift.from_toml({"shift_joint": "head_mount", "shift_mm": [-17, 0, 0]}, "[geometry]").shift_m
    ('head_mount', (-0.017, 0.0, 0.0))
    """

    joint: str
    shift_mm: tuple[float, float, float]

    TABLE: ClassVar[str] = "geometry"
    KEYS: ClassVar[frozenset[str]] = frozenset({"shift_joint", "shift_mm"})
    EDITS_URDF: ClassVar[bool] = True
    URDF_ORDER: ClassVar[int] = 0

    @classmethod
    def from_toml(cls, table: dict, where: str) -> JointShift:
        """``shift_joint`` (a joint's name) and ``shift_mm`` (three numbers, each within
        ``MAX_JOINT_SHIFT_MM``).

        Raises
        ------
        ModelSetError
            If a key is unknown or missing, or a value is out of range.
        """
        geo = check_keys(table, cls.KEYS, set(cls.KEYS), where)
        name, v = geo["shift_joint"], geo["shift_mm"]
        if not isinstance(name, str) or not name:
            raise ModelSetError(f"{where}: shift_joint must be a joint's name; got {name!r}")
        ok = isinstance(v, list) and len(v) == 3
        ok = ok and all(
            not isinstance(x, bool) and isinstance(x, (int, float)) and math.isfinite(x) for x in v
        )
        if not ok or max(abs(x) for x in v) > MAX_JOINT_SHIFT_MM:
            raise ModelSetError(
                f"{where}: shift_mm must be three numbers (x, y, z in the joint's parent frame, mm), each within "
                f"±{MAX_JOINT_SHIFT_MM:g}; got {v!r}"
            )
        return cls(name, (float(v[0]), float(v[1]), float(v[2])))

    def canonical(self) -> dict:
        """The joint and its shift, mm."""
        return {"shift_joint": self.joint, "shift_mm": list(self.shift_mm)}

    @property
    def shift_m(self) -> tuple[str, tuple[float, float, float]]:
        """(joint, parent-frame vector in m)."""
        mm = self.shift_mm
        return self.joint, (mm[0] * 1e-3, mm[1] * 1e-3, mm[2] * 1e-3)

    def edit_robot(self, robot):
        """``robot`` with the joint moved (:meth:`geometry.Robot.with_joint_shift`).

        Raises
        ------
        geometry.errors.UnknownJointError
            If the robot lacks the joint.
        """
        return robot.with_joint_shift(*self.shift_m)

    def edit_urdf(self, root, robot) -> None:
        """Move the joint's origin (:func:`sim.urdf_edits.shift_joint`)."""
        urdf_edits.shift_joint(root, *self.shift_m)
