"""A model set's ``[head_compliance]`` table: a head whose attachment gives (a :class:`sim.modifier.Modifier`).

The fixed joint that attaches the head becomes a slide or a hinge with a stop either way
(:func:`sim.urdf_edits.add_head_compliance`), which a spring and damper drive in the world; simulation only, the
landscapes stay the rigid body's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from . import urdf_edits
from .compliance import ComplianceError, check_spring, passive_joint
from .modifier import ModelSetError, Modifier, check_keys, number, register

_HEAD_SLIDE = ("stiffness_n_m", "damping_n_s_m", "travel_mm")
_HEAD_HINGE = ("stiffness_n_m_rad", "damping_n_m_s_rad", "travel_deg")
HEAD_JOINT = "head_mount"
"""The joint that attaches the head, in the lab URDF and the built-in robot: ``[head_compliance]``'s default."""
MAX_HEAD_TRAVEL_MM = 30.0
"""Largest ``travel_mm`` of a sliding head, mm (as ``[geometry] shift_mm``): a head that gives, not a new robot."""
MAX_HEAD_TRAVEL_DEG = 45.0
"""Largest ``travel_deg`` of a hinged head, degrees."""
DEFAULT_HEAD_TRAVEL = 30.0
"""A head's stop when none is given: 30 mm for a slide, 30 degrees for a hinge."""


@register
@dataclass(frozen=True)
class HeadCompliance(Modifier):
    """A head whose attachment gives (the ``[head_compliance]`` table): the fixed joint that attaches the head becomes a slide along ``axis`` (``slide``; stiffness N/m, damping
    N·s/m, travel m) or a hinge about it (stiffness N·m/rad, damping N·m·s/rad, travel rad) through the joint's
    origin, driven by the torque (or force) ``-k q - c dq/dt`` renewed before every ``stepSimulation`` call, and
    stopped at ``±travel``.

    The source paper suspected that the thin head deforms under the load the ground puts on it when the wings
    hold the body up. The head carries no load on the robot's back and part of its weight in the hold, so a head
    that gives holds the body further over only while the wings are open. :func:`sim.urdf_edits.add_head_compliance`
    turns the joint; at zero deflection every link sits where it did. The landscape (``landscape compute``) stays
    the rigid body's, as it does for compliant wings.

    Attributes
    ----------
    stiffness : float
        N/m for a slide, N·m/rad for a hinge (> 0).
    damping : float
        N·s/m for a slide, N·m·s/rad for a hinge (>= 0).
    slide : bool
        A slide (True) or a hinge (False).
    axis : tuple of 3 floats
        Direction of the slide or the hinge's axis in the joint's parent frame (the body frame for the head:
        x towards the head, z out of the belly); normalised.
    travel : float or None
        The stop either way, m for a slide, rad for a hinge (> 0); None: ``DEFAULT_HEAD_TRAVEL`` mm or degrees.
    joint : str
        The fixed joint that attaches the head.

    Examples
    --------
    >>> HeadCompliance(25.0, 0.3, travel=0.017).keys()
    ('stiffness_n_m', 'damping_n_s_m', 'travel_mm')
    >>> h = HeadCompliance(0.5, slide=False, axis=(0.0, 2.0, 0.0))
    >>> h.axis, round(h.travel_as_written(), 9)
    ((0.0, 1.0, 0.0), 30.0)
    >>> HeadCompliance(25.0, travel=0.05)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: head_compliance travel_mm must be > 0 and at most 30 mm; got 50
    """

    stiffness: float
    damping: float = 0.0
    slide: bool = True
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    travel: float | None = None
    joint: str = HEAD_JOINT

    TABLE: ClassVar[str] = "head_compliance"
    KEYS: ClassVar[frozenset[str]] = frozenset({"joint", "axis", *_HEAD_SLIDE, *_HEAD_HINGE})
    EDITS_URDF: ClassVar[bool] = True
    URDF_ORDER: ClassVar[int] = 10

    @classmethod
    def from_toml(cls, table: dict, where: str) -> HeadCompliance:
        """A slide's keys (``stiffness_n_m``, ``damping_n_s_m``, ``travel_mm``) or a hinge's
        (``stiffness_n_m_rad``, ``damping_n_m_s_rad``, ``travel_deg``), never both; ``axis`` and ``joint``
        optional.

        Raises
        ------
        ModelSetError
            If a key is unknown or missing, the two kinds are mixed, or a value is out of range.
        """
        tab = check_keys(table, cls.KEYS, set(), where)
        slide_keys, hinge_keys = set(_HEAD_SLIDE) & set(tab), set(_HEAD_HINGE) & set(tab)
        if bool(slide_keys) == bool(hinge_keys) or (
            "stiffness_n_m" not in tab and "stiffness_n_m_rad" not in tab
        ):
            raise ModelSetError(
                f"{where}: give a slide (stiffness_n_m, optional damping_n_s_m and travel_mm) or a hinge "
                "(stiffness_n_m_rad, optional damping_n_m_s_rad and travel_deg), not both"
            )
        slide = bool(slide_keys)
        kn, cn, tn = _HEAD_SLIDE if slide else _HEAD_HINGE
        axis = tab.get("axis", [1.0, 0.0, 0.0])
        if not isinstance(axis, list):
            raise ModelSetError(
                f"{where}: axis must be a list of three numbers (x, y, z in the joint's parent frame)"
            )
        try:
            return cls(
                number(tab, kn, where),
                number(tab, cn, where, allow_zero=True) if cn in tab else 0.0,
                slide,
                tuple(axis),
                number(tab, tn, where) * (1e-3 if slide else math.pi / 180.0) if tn in tab else None,
                tab.get("joint", HEAD_JOINT),
            )
        except ComplianceError as exc:
            raise ModelSetError(f"{where}: {exc}") from None

    def canonical(self) -> dict:
        """Joint, stiffness, damping, axis and travel, under the table's names for this kind of joint."""
        kn, cn, tn = self.keys()
        return {
            "joint": self.joint,
            kn: self.stiffness,
            cn: self.damping,
            "axis": list(self.axis),
            tn: self.travel_as_written(),
        }

    def edit_urdf(self, root, robot) -> None:
        """Turn the head's fixed joint into a slide or a hinge (:func:`sim.urdf_edits.add_head_compliance`)."""
        urdf_edits.add_head_compliance(root, self.joint, slide=self.slide, axis=self.axis, travel=self.travel)

    def attach(self, world) -> None:
        """Drive the head's joint with ``-k q - c dq/dt`` before every step."""
        world.add_spring(passive_joint(world, self, self.joint), self.stiffness, self.damping)

    def inertia(self, world) -> float:
        """What the head's spring moves (nan without its joint): the head's mass, kg, for a slide; its moment of
        inertia about the hinge, kg m², for a hinge."""
        j = world.joint_index(self.joint)
        if j is None:
            return math.nan
        return world.link_mass_kg_of(j) if self.slide else world.child_inertia_kg_m2([j])

    def check_stability(self, world, period_s: float) -> None:
        """:func:`check_head_stability` with :meth:`inertia`."""
        check_head_stability(self, self.inertia(world), period_s)

    def keys(self) -> tuple[str, str, str]:
        """The table's names of stiffness, damping and travel for this kind of joint."""
        if self.slide:
            return ("stiffness_n_m", "damping_n_s_m", "travel_mm")
        return ("stiffness_n_m_rad", "damping_n_m_s_rad", "travel_deg")

    def travel_as_written(self) -> float:
        """The travel in the table's unit (mm or degrees)."""
        return self.travel * 1e3 if self.slide else math.degrees(self.travel)

    def __post_init__(self):
        if self.travel is None:
            d = DEFAULT_HEAD_TRAVEL
            object.__setattr__(self, "travel", d * 1e-3 if self.slide else math.radians(d))
        kn, cn, tn = self.keys()
        for name, v in ((kn, self.stiffness), (cn, self.damping), (tn, self.travel)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ComplianceError(f"{self.TABLE} {name} must be a finite number; got {v!r}")
        if self.stiffness <= 0:
            raise ComplianceError(
                f"{self.TABLE} {kn} must be > 0 (omit [{self.TABLE}] for a rigid head); got {self.stiffness!r}"
            )
        if self.damping < 0:
            raise ComplianceError(f"{self.TABLE} {cn} must be >= 0; got {self.damping!r}")
        top = MAX_HEAD_TRAVEL_MM if self.slide else MAX_HEAD_TRAVEL_DEG
        written = self.travel_as_written()
        if not 0 < written <= top + 1e-9:
            unit = "mm" if self.slide else "deg"
            raise ComplianceError(
                f"{self.TABLE} {tn} must be > 0 and at most {top:g} {unit}; got {written:g}"
            )
        a = self.axis
        ok = isinstance(a, tuple) and len(a) == 3
        ok = ok and all(
            not isinstance(x, bool) and isinstance(x, (int, float)) and math.isfinite(x) for x in a
        )
        norm = math.sqrt(sum(x * x for x in a)) if ok else 0.0
        if not ok or norm < 1e-9:
            raise ComplianceError(
                f"{self.TABLE} axis must be three finite numbers, not all zero (x, y, z in the joint's parent "
                f"frame); got {a!r}"
            )
        object.__setattr__(self, "axis", tuple(float(x) / norm for x in a))
        if not isinstance(self.joint, str) or not self.joint:
            raise ComplianceError(f"{self.TABLE} joint must be a joint's name; got {self.joint!r}")


def check_head_stability(head: HeadCompliance, inertia: float, period_s: float) -> None:
    """Refuse a head spring or damper the explicit update renewed every ``period_s`` cannot follow
    (``inertia``: the head's mass, kg, for a slide; its moment of inertia about the hinge, kg m², for a hinge).

    Examples
    --------
    >>> check_head_stability(HeadCompliance(25.0, 0.3), 0.0134, 1e-3)
    >>> check_head_stability(HeadCompliance(5000.0), 0.0134, 1e-3)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: head_compliance stiffness_n_m 5000 is too stiff for the 1 ms servo period: sqrt(k/m)*period = 0.611 > 0.5 with the head's m = 0.013 kg; give k <= 3.35e+03 N/m
    """
    kn, cn, _ = head.keys()
    units = ("m", "kg", "N/m", "N s/m") if head.slide else ("I", "kg m^2", "N m/rad", "N m s/rad")
    check_spring(
        (f"{head.TABLE} {kn}", head.stiffness),
        (f"{head.TABLE} {cn}", head.damping),
        "the head's",
        inertia,
        period_s,
        units=units,
    )
