"""What a model set adds to the rigid robot: the :class:`Modifier` protocol, its registry and the table readers.

A modifier is one physical element a set switches on with one TOML table (a compliant joint, a spring-driven
hinge, a moved CoM, a moved joint). It goes through the model-then-physics split of dm_control in five steps, each
a method, so no other signature names it:

1. :meth:`Modifier.from_toml` reads and validates its table (:func:`sim.model_set.load_model_set` calls it for
   each registered table the file has);
2. :meth:`Modifier.canonical` is its part of the set's ``model_set_hash``;
3. :meth:`Modifier.edit_robot` and :meth:`Modifier.edit_urdf` change the robot the landscapes pose and the URDF
   the simulation loads (:func:`sim.model.sim_model`);
4. :meth:`Modifier.attach` tells the world (:class:`sim.engine.EngineWorld`, either engine's) which joints it
   drives and how;
5. :meth:`Modifier.check_stability` refuses values the held explicit update cannot follow, once the world is
   loaded (:func:`sim.trial.simulate_trial`).

A new element is one module: a frozen dataclass subclassing :class:`Modifier`, decorated with :func:`register`,
and its module named in :data:`MODULES` (docs/concepts/model_sets.md shows a whole one).
"""

from __future__ import annotations

import importlib
import math
from typing import ClassVar

from geometry.errors import UsageError

from .engine import ENGINES

MODULES = ("sim.compliance", "sim.head_compliance", "sim.mass", "sim.joint_shift")
"""The modules that define the registered modifiers, imported on first use of :func:`registered`."""

MERGE_ORDER = 50
"""Where :func:`sim.urdf_edits.merge_fixed_links` runs among the URDF edits (:attr:`Modifier.URDF_ORDER`)."""

_REGISTRY: dict[str, type[Modifier]] = {}


class ModelSetError(UsageError):
    """A model set that cannot be found or read, or holds a bad value."""


class Modifier:
    """One element a model set adds to the rigid robot, read from one optional table (see the module docstring).

    Subclasses are frozen (hashable) dataclasses: a model is cached by the modifiers that edit its URDF.
    Every method but :meth:`from_toml` and :meth:`canonical` has a default that does nothing.
    """

    TABLE: ClassVar[str] = ""
    """The model-set table that switches it on, named in every error."""
    KEYS: ClassVar[frozenset[str]] = frozenset()
    """Every key the table may hold (the rest are refused)."""
    EDITS_URDF: ClassVar[bool] = False
    """Whether :meth:`edit_urdf` changes the URDF (then the model, its hash and its cache key depend on it)."""
    URDF_ORDER: ClassVar[int] = 0
    """Edits apply in increasing order; :func:`sim.urdf_edits.merge_fixed_links` runs at :data:`MERGE_ORDER`."""
    ENGINES: ClassVar[tuple[str, ...]] = ENGINES
    """The engines that can express it (:data:`sim.engine.ENGINES`: every one, unless a subclass says otherwise);
    :meth:`sim.model_set.ModelSet.with_engine` refuses a set with a modifier its engine cannot express."""

    @classmethod
    def from_toml(cls, table: dict, where: str) -> Modifier:
        """The modifier a set's table describes; ``where`` (``"model set 'x.toml' [TABLE]"``) starts each error.

        Raises
        ------
        ModelSetError
            If a key is unknown or missing, or a value is out of range.
        """
        raise NotImplementedError

    def canonical(self) -> dict:
        """The table's parsed values, as the set's hash sees them (JSON-able)."""
        raise NotImplementedError

    @property
    def active(self) -> bool:
        """Whether it changes the robot at all (a set lists it among its elements only then)."""
        return True

    def edit_robot(self, robot):
        """``robot`` (a :class:`geometry.Robot`) as this modifier changes every landscape the set poses."""
        return robot

    def edit_urdf(self, root, robot) -> None:
        """Edit the URDF element tree ``root`` of ``robot`` in place (only when :attr:`EDITS_URDF`).

        Raises
        ------
        geometry.errors.RobotDescriptionError
            If the robot lacks what the modifier needs.
        """

    def attach(self, world) -> None:
        """Register what it drives with a loaded world (:class:`sim.engine.EngineWorld`: soft servos, passive
        springs)."""

    def check_stability(self, world, period_s: float) -> None:
        """Refuse values the explicit update renewed every ``period_s`` cannot follow in ``world``.

        Raises
        ------
        sim.compliance.ComplianceError
            If a spring or damper is too stiff for the period.
        """


def register(cls: type[Modifier]) -> type[Modifier]:
    """Class decorator: make ``cls`` the modifier of its table.

    Raises
    ------
    ValueError
        If another class already holds the table.
    """
    other = _REGISTRY.get(cls.TABLE)
    if other is not None and other is not cls:
        raise ValueError(
            f"the table [{cls.TABLE}] is already {other.__qualname__}'s; give {cls.__qualname__} another"
        )
    _REGISTRY[cls.TABLE] = cls
    return cls


def registered() -> dict[str, type[Modifier]]:
    """Table name -> modifier class, in the order sets are read, attached and checked.

    Examples
    --------
    >>> list(registered())
    ['compliance', 'body_torsion', 'leg_compliance', 'leg_bend', 'head_compliance', 'mass', 'geometry']
    """
    for name in MODULES:
        importlib.import_module(name)
    # by module, then a module's own modifiers in the order it defines them
    rank = {name: i for i, name in enumerate(MODULES)}
    ordered = sorted(_REGISTRY.values(), key=lambda cls: rank.get(cls.__module__, len(rank)))
    return {cls.TABLE: cls for cls in ordered}


def with_modifier(modifiers: tuple[Modifier, ...], modifier: Modifier) -> tuple[Modifier, ...]:
    """``modifiers`` with ``modifier`` in place of the one of its table (or added), in :func:`registered` order.

    Examples
    --------
    >>> from sim.compliance import BodyTorsion, Compliance
    >>> with_modifier((BodyTorsion(0.05),), Compliance(1.0))
    (Compliance(wing_stiffness_n_m_rad=1.0, wing_damping_n_m_s_rad=0.0, wing_integral_time_s=None, wing_scale=None), BodyTorsion(stiffness_n_m_rad=0.05, damping_n_m_s_rad=0.0))
    """
    order = list(registered())
    rest = [m for m in modifiers if m.TABLE != modifier.TABLE]
    return tuple(sorted([*rest, modifier], key=lambda m: order.index(m.TABLE)))


def check_keys(section, allowed: set[str] | frozenset[str], required: set[str], where: str) -> dict:
    """``section`` if it is a table with only ``allowed`` keys and every ``required`` one.

    Raises
    ------
    ModelSetError
        Naming the first unknown or missing key.
    """
    if not isinstance(section, dict):
        raise ModelSetError(f"{where} must be a table; got {section!r}")
    unknown = sorted(set(section) - set(allowed))
    if unknown:
        raise ModelSetError(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(sorted(allowed))}")
    missing = sorted(required - set(section))
    if missing:
        raise ModelSetError(f"{where}: missing key {missing[0]!r}")
    return section


def number(section: dict, key: str, where: str, *, positive: bool = True, allow_zero: bool = False) -> float:
    """``section[key]`` as a float: finite, and > 0 (>= 0 with ``allow_zero``) unless not ``positive``.

    Raises
    ------
    ModelSetError
        If it is not such a number.
    """
    v = section.get(key)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ModelSetError(f"{where}: {key} must be a finite number; got {v!r}")
    if positive and not (v > 0 or (allow_zero and v == 0)):
        raise ModelSetError(f"{where}: {key} must be {'>= 0' if allow_zero else '> 0'}; got {v!r}")
    return float(v)
