"""The model set's compliant joints, each a :class:`sim.modifier.Modifier`: wings whose joints yield like a spring
and damper or a soft servo that also integrates its error (:class:`Compliance`, ``[compliance]``); a body that
twists (:class:`BodyTorsion`), a leg whose swing gives (:class:`LegCompliance`), a leg that bends out of its swing
plane (:class:`LegBend`); a head whose attachment gives is :mod:`sim.head_compliance`.

The source paper suspected that the thin wings and their mounts deform under the body's weight and make the
physical robot easier to right. With a :class:`Compliance`, the wing joints (the pitch and the roll servo of each
wing) are driven not by the stiff position servo but by the torque ``k (target - q) + c (speed - dq/dt)`` towards the same commanded profile (:meth:`sim.world.World.drive`),
capped at the servo's effort limit: the wing gives about its hinge line under load by ``load / k`` and springs
back. The torque is computed once per servo command period and held through pybullet's sub-steps, an explicit
update that stays accurate while ``sqrt(k / I) * period`` and ``c * period / I`` stay below ``MAX_OMEGA_PERIOD``
(``I``: the moment of inertia of the joint's child link about its axis, a lower bound on what it moves), which :func:`check_stability` enforces. Without a
compliance the model is exactly the rigid one.

With ``wing_integral_time_s`` (``T_i``) the joint is a proportional-integral servo, as position servos with an
integral gain are: the torque adds ``(k / T_i) * integral(target - q) dt``, so a steady load no longer sags the
wing by ``load / k`` (the integral takes it over within a few ``T_i``) while a load that changes faster than
that still meets the soft spring ``k``. The integral is clamped so that its torque never exceeds the effort limit
(no wind-up while the servo is saturated).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from geometry.errors import RobotDescriptionError, UsageError

from . import urdf_edits
from .modifier import ModelSetError, Modifier, check_keys, number, register

MAX_OMEGA_PERIOD = 0.5
"""Largest ``sqrt(k / I) * period`` (and ``c * period / I``) allowed: the held explicit torque stays accurate."""


class ComplianceError(UsageError):
    """A compliance value out of range or a stiffness too high for the servo command period."""


@register
@dataclass(frozen=True)
class Compliance(Modifier):
    """Spring and damper of every wing joint (servo and mount together): the ``[compliance]`` table.

    Attributes
    ----------
    wing_stiffness_n_m_rad : float
        Rotational stiffness, N·m/rad (> 0).
    wing_damping_n_m_s_rad : float
        Rotational damping, N·m·s/rad (>= 0).
    wing_integral_time_s : float or None
        Integral time ``T_i`` of a proportional-integral servo, s (> 0); None: no integral (a spring).
    wing_scale : tuple of float or None
        One factor (> 0) per wing joint, in the joint map's order (the lab robot's: pitch left, pitch right, roll
        left, roll right), that multiplies that joint's stiffness, damping and integral gain: a wing mount or
        servo softer on one side than the other. None: every wing joint alike.
    """

    wing_stiffness_n_m_rad: float
    wing_damping_n_m_s_rad: float = 0.0
    wing_integral_time_s: float | None = None
    wing_scale: tuple[float, ...] | None = None

    TABLE: ClassVar[str] = "compliance"
    KEYS: ClassVar[frozenset[str]] = frozenset(
        {"wing_stiffness_n_m_rad", "wing_damping_n_m_s_rad", "wing_integral_time_s", "wing_scale"}
    )

    @classmethod
    def from_toml(cls, table: dict, where: str) -> Compliance:
        """``wing_stiffness_n_m_rad``, optional ``wing_damping_n_m_s_rad``, ``wing_integral_time_s`` and
        ``wing_scale`` (a list of factors > 0; the World checks their count).

        Raises
        ------
        ModelSetError
            If a key is unknown or missing, or a value is out of range.
        """
        comp = check_keys(table, cls.KEYS, {"wing_stiffness_n_m_rad"}, where)
        scale = None
        if "wing_scale" in comp:
            v = comp["wing_scale"]
            if not isinstance(v, list) or not v:
                raise ModelSetError(
                    f"{where}: wing_scale must be a list of numbers > 0, one per wing joint (e.g. [1, 0.5, 1, 0.5]); "
                    f"got {v!r}"
                )
            scale = tuple(number({"wing_scale": x}, "wing_scale", where) for x in v)
        try:
            return cls(
                number(comp, "wing_stiffness_n_m_rad", where),
                number(comp, "wing_damping_n_m_s_rad", where, allow_zero=True)
                if "wing_damping_n_m_s_rad" in comp
                else 0.0,
                number(comp, "wing_integral_time_s", where) if "wing_integral_time_s" in comp else None,
                scale,
            )
        except ComplianceError as exc:
            raise ModelSetError(f"{where}: {exc}") from None

    def canonical(self) -> dict:
        """Stiffness and damping; the integral time and the scales only when given."""
        out: dict = {
            "wing_stiffness_n_m_rad": self.wing_stiffness_n_m_rad,
            "wing_damping_n_m_s_rad": self.wing_damping_n_m_s_rad,
        }
        if self.wing_integral_time_s is not None:
            out["wing_integral_time_s"] = self.wing_integral_time_s
        if self.wing_scale is not None:
            out["wing_scale"] = list(self.wing_scale)
        return out

    def attach(self, world) -> None:
        """Drive every wing joint through its spring, damper and integral instead of the stiff servo."""
        n_wing = len(world.wing_joints)
        k, c, ti = self.wing_stiffness_n_m_rad, self.wing_damping_n_m_s_rad, self.wing_integral_time_s
        ki = k / ti if ti is not None else 0.0
        world.add_soft_joints(range(n_wing), [(k * f, c * f, ki * f) for f in self.joint_scales(n_wing)])

    def inertia_kg_m2(self, world) -> float:
        """The smallest moment of inertia of a wing joint's child link about the joint's axis, kg m² (a lower
        bound on what the joint moves)."""
        return world.child_inertia_kg_m2(world.wing_joints)

    def check_stability(self, world, period_s: float) -> None:
        """:func:`check_stability` with the wings' :meth:`inertia_kg_m2`."""
        check_stability(self, self.inertia_kg_m2(world), period_s)

    def __post_init__(self):
        k, c, ti = self.wing_stiffness_n_m_rad, self.wing_damping_n_m_s_rad, self.wing_integral_time_s
        checks = [("wing_stiffness_n_m_rad", k), ("wing_damping_n_m_s_rad", c)]
        for name, v in checks + ([("wing_integral_time_s", ti)] if ti is not None else []):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ComplianceError(f"{name} must be a finite number; got {v!r}")
        if ti is not None and ti <= 0:
            raise ComplianceError(
                f"wing_integral_time_s must be > 0 (omit it for a spring without integral); got {ti!r}"
            )
        if k <= 0:
            raise ComplianceError(
                f"wing_stiffness_n_m_rad must be > 0 (omit [compliance] for rigid wings); got {k!r}"
            )
        if c < 0:
            raise ComplianceError(f"wing_damping_n_m_s_rad must be >= 0; got {c!r}")
        sc = self.wing_scale
        if sc is not None and (
            not isinstance(sc, tuple)
            or not sc
            or not all(
                not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v) and v > 0
                for v in sc
            )
        ):
            raise ComplianceError(
                f"wing_scale must be a list of numbers > 0, one per wing joint in the joint map's order; got {sc!r}"
            )

    def joint_scales(self, n_wing: int) -> tuple[float, ...]:
        """The factor of each of ``n_wing`` wing joints (all 1 without ``wing_scale``).

        Raises
        ------
        ComplianceError
            If ``wing_scale`` does not give one factor per wing joint.

        Examples
        --------
        >>> Compliance(1.0, wing_scale=(1.0, 0.5, 1.0, 0.5)).joint_scales(4)
        (1.0, 0.5, 1.0, 0.5)
        >>> Compliance(1.0).joint_scales(2)
        (1.0, 1.0)
        """
        if self.wing_scale is None:
            return (1.0,) * n_wing
        if len(self.wing_scale) != n_wing:
            raise ComplianceError(
                f"wing_scale has {len(self.wing_scale)} factors for the robot's {n_wing} wing joints; give one per "
                "wing joint, in the joint map's order"
            )
        return tuple(float(v) for v in self.wing_scale)


def check_stability(comp: Compliance, inertia_kg_m2: float, period_s: float) -> None:
    """Refuse a spring or damper the held explicit update cannot follow at ``period_s``.

    Raises
    ------
    ComplianceError
        If ``sqrt(k / I) * period`` or ``c * period / I`` exceeds :data:`MAX_OMEGA_PERIOD`.

    Examples
    --------
    >>> check_stability(Compliance(1.0, 0.01), 4.7e-5, 1e-3)
    >>> check_stability(Compliance(1000.0), 4.7e-5, 1e-3)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: wing_stiffness_n_m_rad 1000 is too stiff for the 1 ms servo period: sqrt(k/I)*period = 4.61 > 0.5 with the wing's I = 4.7e-05 kg m^2; give k <= 11.8 N m/rad
    """
    top = max(comp.wing_scale) if comp.wing_scale is not None else 1.0  # the stiffest joint decides
    check_spring(
        ("wing_stiffness_n_m_rad", comp.wing_stiffness_n_m_rad * top),
        ("wing_damping_n_m_s_rad", comp.wing_damping_n_m_s_rad * top),
        "the wing's",
        inertia_kg_m2,
        period_s,
    )
    ti = comp.wing_integral_time_s
    if ti is not None and period_s / ti > MAX_OMEGA_PERIOD:
        raise ComplianceError(
            f"wing_integral_time_s {ti:g} is too short for the {period_s * 1e3:g} ms servo period; "
            f"give at least {period_s / MAX_OMEGA_PERIOD:.3g} s"
        )


def check_spring(
    stiffness,
    damping,
    whose: str,
    inertia_kg_m2: float,
    period_s: float,
    *,
    units: tuple[str, str, str, str] = ("I", "kg m^2", "N m/rad", "N m s/rad"),
) -> None:
    """Refuse ``(name, k)`` and ``(name, c)`` on a body of ``inertia_kg_m2`` (``whose``: "the wing's") that the
    explicit update held for ``period_s`` cannot follow (:data:`MAX_OMEGA_PERIOD`), or that gains energy under it;
    ``units``: the inertia's symbol and unit and the stiffness's and damping's units (a slide's: "m", "kg", "N/m",
    "N s/m").

    The force ``-k x - c v`` is computed at the start of a period and held through it (pybullet: every spring;
    MuJoCo: the soft wing servos, while its passive springs act every step, where this bound is on the safe
    side). Over one period the oscillator's state maps by a matrix of determinant ``1 - c T / I + k T^2 / (2
    I)``: the held spring feeds energy in at the rate its damping takes it out when ``c = k T / 2``, and more
    below. So ``c >= k T / 2``, whatever the inertia (an undamped spring is refused too); below it the motion
    grows at ``(k T / 2 - c) / (2 I)`` per second (4 N·m/rad with 0.001 N·m·s/rad and I = 4.7e-5 kg m²: 11 /s),
    unless the rest of the model happens to damp it. On the lab robot's wings that pair spun the body over
    within 0.4 s of its first opening (docs/physical/time-to-right.md).

    Examples
    --------
    >>> check_spring(("k", 2.0), ("c", 0.001), "the wing's", 4.7e-5, 1e-3)
    >>> check_spring(("k", 4.0), ("c", 0.001), "the wing's", 4.7e-5, 1e-3)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: k 4 with c 0.001 gains energy: a spring held through the 1 ms servo period needs c >= k*period/2 = 0.002 N m s/rad; give c >= 0.002 N m s/rad or k <= 2 N m/rad
    """
    (k_name, k), (c_name, c) = stiffness, damping
    sym, i_unit, k_unit, c_unit = units
    wt = math.sqrt(k / inertia_kg_m2) * period_s
    if wt > MAX_OMEGA_PERIOD:
        k_max = (MAX_OMEGA_PERIOD / period_s) ** 2 * inertia_kg_m2
        raise ComplianceError(
            f"{k_name} {k:g} is too stiff for the {period_s * 1e3:g} ms servo period: sqrt(k/{sym})*period = "
            f"{wt:.3g} > {MAX_OMEGA_PERIOD:g} with {whose} {sym} = {inertia_kg_m2:.2g} {i_unit}; give k <= {k_max:.3g} {k_unit}"
        )
    if c * period_s / inertia_kg_m2 > MAX_OMEGA_PERIOD:
        c_max = MAX_OMEGA_PERIOD * inertia_kg_m2 / period_s
        raise ComplianceError(
            f"{c_name} {c:g} is too high for the {period_s * 1e3:g} ms servo period with {whose} {sym} = "
            f"{inertia_kg_m2:.2g} {i_unit}; give c <= {c_max:.3g} {c_unit}"
        )
    c_min = k * period_s / 2
    if c < c_min:
        fix = f"give c >= {c_min:.3g} {c_unit}" + (
            f" or k <= {2 * c / period_s:.3g} {k_unit}" if c > 0 else ""
        )
        raise ComplianceError(
            f"{k_name} {k:g} with {c_name} {c:g} gains energy: a spring held through the {period_s * 1e3:g} ms "
            f"servo period needs c >= k*period/2 = {c_min:.3g} {c_unit}; {fix}"
        )


@dataclass(frozen=True)
class Spring(Modifier):
    """A spring and damper of a model set's table (``[TABLE] stiffness_n_m_rad, damping_n_m_s_rad``); the
    subclasses say which joint it acts on.

    Attributes
    ----------
    stiffness_n_m_rad : float
        Stiffness, N·m/rad (> 0).
    damping_n_m_s_rad : float
        Damping, N·m·s/rad (>= 0).
    """

    stiffness_n_m_rad: float
    damping_n_m_s_rad: float = 0.0

    KEYS: ClassVar[frozenset[str]] = frozenset({"stiffness_n_m_rad", "damping_n_m_s_rad"})
    WITHOUT: ClassVar[str] = ""
    """What omitting the table gives."""
    WHOSE: ClassVar[str] = ""
    """Whose inertia the stability check names ("the leg's")."""

    def __post_init__(self):
        k, c = self.stiffness_n_m_rad, self.damping_n_m_s_rad
        for name, v in (("stiffness_n_m_rad", k), ("damping_n_m_s_rad", c)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ComplianceError(f"{self.TABLE} {name} must be a finite number; got {v!r}")
        if k <= 0:
            raise ComplianceError(
                f"{self.TABLE} stiffness_n_m_rad must be > 0 (omit [{self.TABLE}] for {self.WITHOUT}); got {k!r}"
            )
        if c < 0:
            raise ComplianceError(f"{self.TABLE} damping_n_m_s_rad must be >= 0; got {c!r}")

    @classmethod
    def from_toml(cls, table: dict, where: str) -> Spring:
        """``stiffness_n_m_rad`` and optional ``damping_n_m_s_rad``.

        Raises
        ------
        ModelSetError
            If a key is unknown or missing, or a value is out of range.
        """
        tab = check_keys(table, cls.KEYS, {"stiffness_n_m_rad"}, where)
        try:
            return cls(
                number(tab, "stiffness_n_m_rad", where),
                number(tab, "damping_n_m_s_rad", where, allow_zero=True)
                if "damping_n_m_s_rad" in tab
                else 0.0,
            )
        except ComplianceError as exc:
            raise ModelSetError(f"{where}: {exc}") from None

    def canonical(self) -> dict:
        """Stiffness and damping."""
        return {"stiffness_n_m_rad": self.stiffness_n_m_rad, "damping_n_m_s_rad": self.damping_n_m_s_rad}

    def inertia_kg_m2(self, world) -> float:
        """What the spring moves in ``world``, kg m² (nan without its joint)."""
        raise NotImplementedError

    def check_stability(self, world, period_s: float) -> None:
        """:func:`check_spring_stability` with :meth:`inertia_kg_m2`."""
        check_spring_stability(self, self.inertia_kg_m2(world), period_s)


def passive_joint(world, spring: Modifier, joint: str) -> int:
    """The index of the joint ``spring`` drives (one its :meth:`Modifier.edit_urdf` inserted or turned)."""
    j = world.joint_index(joint)
    if j is None:
        raise ValueError(
            f"a {type(spring).__name__} needs a model built with it (sim_model(..., modifiers=(...))); the model "
            f"has no joint {joint!r}"
        )
    return j


@register
class BodyTorsion(Spring):
    """A body that twists about its long axis: the links that carry the wings turn against the rest of the body
    (head, leg and base) about the base frame's x axis through its origin, on a spring and damper.

    The robot's shell is thin. Under the body's weight the two wings carry equal and opposite moments about the
    long axis, which cancel across the body, so a torsion spring does not sag the resting pose as a spring in
    each wing joint does (docs/physical/resting-pose.md); a load that differs between the sides, such as the
    leg's swing, twists it. :func:`sim.urdf_edits.add_body_torsion` inserts the joint (``TORSION_JOINT``) and
    :class:`sim.world.World` drives it with the torque ``-k q - c dq/dt``, renewed before every
    ``stepSimulation`` call (settling included).

    Examples
    --------
    >>> BodyTorsion(0.05, 0.002).stiffness_n_m_rad
    0.05
    >>> BodyTorsion(0.0)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: body_torsion stiffness_n_m_rad must be > 0 (omit [body_torsion] for a rigid body); got 0.0
    """

    TABLE, WITHOUT, WHOSE = "body_torsion", "a rigid body", "the twist's"
    EDITS_URDF, URDF_ORDER = True, 20

    def edit_urdf(self, root, robot) -> None:
        """Insert the twist's hinge (:func:`sim.urdf_edits.add_body_torsion`)."""
        urdf_edits.add_body_torsion(root, robot.joint_map.wing)

    def attach(self, world) -> None:
        """Drive the twist with ``-k q - c dq/dt`` before every step."""
        world.add_spring(
            passive_joint(world, self, urdf_edits.TORSION_JOINT),
            self.stiffness_n_m_rad,
            self.damping_n_m_s_rad,
        )

    def inertia_kg_m2(self, world) -> float:
        """Effective moment of inertia of the body's twist, kg m² (:meth:`sim.world.World.effective_inertia_kg_m2`)."""
        j = world.joint_index(urdf_edits.TORSION_JOINT)
        return math.nan if j is None else world.effective_inertia_kg_m2(j)


@register
class LegCompliance(Spring):
    """A leg whose swing gives: the leg joint is driven through a spring and damper towards its commanded profile
    (``k (target - q) + c (speed - dq/dt)``, held through the servo command period and capped at the effort
    limit, as :class:`Compliance` drives the wing joints) instead of the stiff servo.

    A pendulum leg is a light rod carrying a mass at its end: a rod that bends in its swing, or a servo horn
    that gives, lets the mass lag its command and swing past it, ringing at ``sqrt(k / I)`` (``I``: the leg's
    moment of inertia about its joint). Without it the leg follows its profile exactly.

    Examples
    --------
    >>> LegCompliance(0.08, 0.001).stiffness_n_m_rad
    0.08
    >>> LegCompliance(0.08, -1.0)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: leg_compliance damping_n_m_s_rad must be >= 0; got -1.0
    """

    TABLE, WITHOUT, WHOSE = "leg_compliance", "a stiff leg", "the leg's"

    def attach(self, world) -> None:
        """Drive every leg joint through the spring and damper instead of the stiff servo."""
        n_wing, n_leg = len(world.wing_joints), len(world.leg_joints)
        world.add_soft_joints(
            range(n_wing, n_wing + n_leg), [(self.stiffness_n_m_rad, self.damping_n_m_s_rad, 0.0)] * n_leg
        )

    def inertia_kg_m2(self, world) -> float:
        """The smallest moment of inertia of a leg joint's child link about the joint's axis, kg m²."""
        return world.child_inertia_kg_m2(world.leg_joints)


@register
class LegBend(Spring):
    """A leg that bends out of its swing plane: the leg turns against its joint about the axis across it
    (:func:`sim.urdf_edits.add_leg_bend`), on a spring and damper, so its end bobs; :class:`sim.world.World` drives the
    joint with the torque ``-k q - c dq/dt``, renewed before every ``stepSimulation`` call.

    A leg that is a thin plate carrying a mass at its end is stiff in its swing and soft out of it. A body that
    rings in pitch at ``f`` after every leg step (``benchmarks/physical/imu_ringing.py`` measures it) gives
    ``k = I (2 pi f)^2``, with the leg's moment of inertia ``I`` about the bending axis.

    Examples
    --------
    >>> LegBend(0.135, 0.00055).stiffness_n_m_rad
    0.135
    """

    TABLE, WITHOUT, WHOSE = "leg_bend", "a rigid leg", "the leg's"
    EDITS_URDF, URDF_ORDER = True, 30

    def edit_urdf(self, root, robot) -> None:
        """Insert the bend's hinge (:func:`sim.urdf_edits.add_leg_bend`).

        Raises
        ------
        geometry.errors.RobotDescriptionError
            If the robot drives more than one leg joint.
        """
        leg = robot.joint_map.leg
        if len(leg) != 1:
            raise RobotDescriptionError(
                f"[leg_bend] bends one leg; '{robot.urdf_file.path.name}' drives {len(leg)} leg joints "
                f"({', '.join(leg)}): drop [leg_bend] or map one leg joint"
            )
        urdf_edits.add_leg_bend(root, leg[0])

    def attach(self, world) -> None:
        """Drive the bend with ``-k q - c dq/dt`` before every step."""
        world.add_spring(
            passive_joint(world, self, urdf_edits.BEND_JOINT), self.stiffness_n_m_rad, self.damping_n_m_s_rad
        )

    def inertia_kg_m2(self, world) -> float:
        """The leg's moment of inertia about its bending axis, kg m² (nan without the bend's joint)."""
        j = world.joint_index(urdf_edits.BEND_JOINT)
        return math.nan if j is None else world.child_inertia_kg_m2([j])


def check_spring_stability(spring: Spring, inertia_kg_m2: float, period_s: float) -> None:
    """Refuse a spring or damper the explicit update renewed every ``period_s`` cannot follow (``inertia_kg_m2``:
    what it moves: the spring's :meth:`Spring.inertia_kg_m2` in a world).

    Raises
    ------
    ComplianceError
        If ``sqrt(k / I) * period`` or ``c * period / I`` exceeds :data:`MAX_OMEGA_PERIOD`.

    Examples
    --------
    >>> check_spring_stability(BodyTorsion(0.1, 0.002), 3e-5, 1e-3)
    >>> check_spring_stability(BodyTorsion(100.0), 3e-5, 1e-3)
    Traceback (most recent call last):
    ...
    sim.compliance.ComplianceError: body_torsion stiffness_n_m_rad 100 is too stiff for the 1 ms servo period: sqrt(k/I)*period = 1.83 > 0.5 with the twist's I = 3e-05 kg m^2; give k <= 7.5 N m/rad
    """
    check_spring(
        (f"{spring.TABLE} stiffness_n_m_rad", spring.stiffness_n_m_rad),
        (f"{spring.TABLE} damping_n_m_s_rad", spring.damping_n_m_s_rad),
        spring.WHOSE,
        inertia_kg_m2,
        period_s,
    )
