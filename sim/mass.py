"""A model set's ``[mass]`` table: the whole body's CoM moved along the body's y axis (a :class:`sim.modifier.Modifier`).

Mass the robot's description lacks or misplaces (cables, glue, a tether) moves the CoM. The offset applies to the
simulation (:func:`sim.urdf_edits.shift_com`, after fixed links are merged) and to every landscape the set poses
(:meth:`geometry.Robot.with_com_offset`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from . import urdf_edits
from .modifier import MERGE_ORDER, ModelSetError, Modifier, check_keys, number, register

MAX_COM_OFFSET_MM = 10.0
"""Largest ``[mass] com_offset_y_mm`` (either way), mm: a correction for mass the description misplaces, not a
new robot."""


@register
@dataclass(frozen=True)
class ComOffset(Modifier):
    """The whole body's CoM moved along the body's y axis (y = z x x).

    Attributes
    ----------
    com_offset_y_mm : float
        The offset, mm, within ±``MAX_COM_OFFSET_MM``; 0 moves nothing (but still enters the set's hash).

    Examples
    --------
    >>> ComOffset.from_toml({"com_offset_y_mm": -1.5}, "[mass]").offset_m
    (0.0, -0.0015, 0.0)
    >>> ComOffset.from_toml({"com_offset_y_mm": 12}, "[mass]")
    Traceback (most recent call last):
    ...
    sim.modifier.ModelSetError: [mass]: com_offset_y_mm must be in [-10, 10] mm; got 12.0
    """

    com_offset_y_mm: float

    TABLE: ClassVar[str] = "mass"
    KEYS: ClassVar[frozenset[str]] = frozenset({"com_offset_y_mm"})
    EDITS_URDF: ClassVar[bool] = True
    URDF_ORDER: ClassVar[int] = MERGE_ORDER + 10

    @classmethod
    def from_toml(cls, table: dict, where: str) -> ComOffset:
        """``com_offset_y_mm``, a number within ±``MAX_COM_OFFSET_MM``.

        Raises
        ------
        ModelSetError
            If the key is missing or unknown, or the value is out of range.
        """
        mass = check_keys(table, cls.KEYS, set(cls.KEYS), where)
        mm = number(mass, "com_offset_y_mm", where, positive=False)
        if abs(mm) > MAX_COM_OFFSET_MM:
            raise ModelSetError(
                f"{where}: com_offset_y_mm must be in [-{MAX_COM_OFFSET_MM:g}, {MAX_COM_OFFSET_MM:g}] mm; "
                f"got {mm!r}"
            )
        return cls(mm)

    def canonical(self) -> dict:
        """The offset, mm."""
        return {"com_offset_y_mm": self.com_offset_y_mm}

    @property
    def active(self) -> bool:
        """Whether it moves the CoM at all."""
        return bool(self.com_offset_y_mm)

    @property
    def offset_m(self) -> tuple[float, float, float]:
        """The offset as a body-frame vector, m."""
        return (0.0, self.com_offset_y_mm * 1e-3, 0.0)

    def edit_robot(self, robot):
        """``robot`` with its CoM moved (:meth:`geometry.Robot.with_com_offset`), or itself at 0."""
        return robot.with_com_offset(self.offset_m) if self.com_offset_y_mm else robot

    def edit_urdf(self, root, robot) -> None:
        """Move the base link's mass so the whole CoM moves (:func:`sim.urdf_edits.shift_com`)."""
        if self.com_offset_y_mm:
            urdf_edits.shift_com(root, self.offset_m)
