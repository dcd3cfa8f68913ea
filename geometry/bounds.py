"""Stated ranges of the numbers people give: one check, one message and one help text per range.

A :class:`Bounds` says which values an input may take, in its unit, and why. Every interface reads its
numbers through one: the command line's options (:mod:`landscape.cli.options`) and the service's query
parameters and request fields (:mod:`landscape.service.inputs`) name the value as their user typed it
(``--cv`` on the command line, ``cv`` in the service) and refuse a value outside it with the same words
(:class:`geometry.errors.UsageError`: exit status 2, HTTP 422), and their help states the range in the same
words too. Each range lives with the concept it bounds: joint angles, orientations and masses here, the grid
step in :mod:`landscape.grid`, the trials' timing and noise in :mod:`sim.protocol`.

A value inside its range can still be a slip of units; :func:`radians_slip` and :func:`mass_slip` say so in
one line (the interfaces print it, or answer it in a ``warnings`` list) and the value is used as given.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation

from geometry.errors import UsageError

__all__ = [
    "JOINT_ANGLE_DEG_BOUNDS",
    "MASS_KG_BOUNDS",
    "ORIENTATION_DEG_BOUNDS",
    "NOT_FINITE",
    "PLAUSIBLE_MAX_MASS_KG",
    "Bounds",
    "joint_angle_slips",
    "mass_slip",
    "percent_to_fraction",
    "radians_slip",
]

NOT_FINITE = "{name} must be a finite number; got {got}"
"""The one message of a value that is not a finite number (nan, inf)."""


def _num(x: float) -> str:
    """A bound or value as people write it: 1, 0.25, 1e-06, 1000000 (whole numbers below 1e15 in full)."""
    if float(x).is_integer() and abs(x) < 1e15:
        return str(int(x))
    return f"{x:g}"


@dataclass(frozen=True)
class Bounds:
    """The values one input may take: an interval (open or closed at each end, whole numbers or not) in a unit.

    Attributes
    ----------
    lo, hi : float
        The interval's ends (``-inf``/``inf`` for none), in ``unit``.
    unit : str
        The unit written after numbers ("deg", "s", "kg"; "" for a pure number).
    lo_open, hi_open : bool
        Whether ``lo`` (``hi``) itself is outside.
    integer : bool
        Only whole numbers.
    meaning : str
        What the value is, said when one is refused ("Cv is sigma / Tl as a fraction").
    percent : bool
        A fraction that may also be written as a percentage with '%' ('10%' is 0.1); a bare number is always a
        fraction.
    words : tuple of str
        Words accepted besides numbers (e.g. 'protocol'), returned as given.
    hi_text : str or None
        How to write ``hi`` when its digits say less than a name (2^63 - 1).

    Examples
    --------
    >>> cv = Bounds(0.0, 1.0, meaning="Cv is sigma / Tl as a fraction", percent=True)
    >>> cv.text
    "in [0, 1], or a percentage written as '10%'"
    >>> cv.parse("10%", "--cv"), cv.parse("0.25", "--cv")
    (0.1, 0.25)
    >>> cv.parse("10", "--cv")
    Traceback (most recent call last):
    ...
    geometry.errors.UsageError: --cv 10 is outside [0, 1]: Cv is sigma / Tl as a fraction; for 10 % give 0.1 or '10%'
    """

    lo: float = -math.inf
    hi: float = math.inf
    unit: str = ""
    lo_open: bool = False
    hi_open: bool = False
    integer: bool = False
    meaning: str = ""
    percent: bool = False
    words: tuple[str, ...] = ()
    hi_text: str | None = None

    def __post_init__(self):
        if not self.lo <= self.hi or (math.isinf(self.lo) and math.isinf(self.hi)):
            raise ValueError(f"Bounds need lo <= hi and at least one finite end; got [{self.lo}, {self.hi}]")

    # ------------------------------------------------------------------ words
    @property
    def interval(self) -> str:
        """The interval as written in messages and help: '[0, 1)', '(0, 600]', '>= 1', '> 0'."""
        hi = self.hi_text or _num(self.hi)
        if math.isinf(self.hi):
            return f"{'>' if self.lo_open else '>='} {_num(self.lo)}"
        if math.isinf(self.lo):
            return f"{'<' if self.hi_open else '<='} {hi}"
        return f"{'(' if self.lo_open else '['}{_num(self.lo)}, {hi}{')' if self.hi_open else ']'}"

    @property
    def _unit(self) -> str:
        return f" {self.unit}" if self.unit else ""

    @property
    def text(self) -> str:
        """The range as the help of an option or parameter states it: 'in [0, 1) s', '>= 1, a whole number',
        with the percentage and word forms it also takes."""
        core = f"in {self.interval}" if not self.interval.startswith(("<", ">")) else self.interval
        out = core + self._unit + (", a whole number" if self.integer else "")
        if self.percent:
            out += ", or a percentage written as '10%'"
        for w in self.words:
            out += f", or '{w}'"
        return out

    def json_schema(self) -> dict:
        """The range as JSON Schema keywords (OpenAPI's ``minimum``/``exclusiveMinimum``...), plus ``x-unit``."""
        s: dict = {}
        if not math.isinf(self.lo):
            s["exclusiveMinimum" if self.lo_open else "minimum"] = self.lo
        if not math.isinf(self.hi):
            s["exclusiveMaximum" if self.hi_open else "maximum"] = self.hi
        if self.unit:
            s["x-unit"] = self.unit
        return s

    # ------------------------------------------------------------------ checks
    def contains(self, value: float) -> bool:
        """Whether ``value`` lies in the interval (and is whole where it must be)."""
        if not math.isfinite(value):
            return False
        if self.integer and not float(value).is_integer():
            return False
        above = value > self.lo if self.lo_open else value >= self.lo
        below = value < self.hi if self.hi_open else value <= self.hi
        return above and below

    def outside_message(self, value: float, name: str) -> str:
        """The one line that refuses ``value`` given as ``name`` (e.g. ``--cv``)."""
        if not math.isfinite(value):
            return NOT_FINITE.format(name=name, got=value)
        if self.integer and not float(value).is_integer():
            return f"{name} must be a whole number in {self.interval}{self._unit}; got {value:g}"
        if math.isinf(self.lo) or math.isinf(self.hi):  # one end: say what it must be
            what = f", {self.meaning}" if self.meaning else ""
            return f"{name} must be {self.interval}{self._unit}{what}; got {_num(value)}"
        head = f"{name} {_num(value)}{self._unit} is outside {self.interval}{self._unit}"
        head += f": {self.meaning}" if self.meaning else ""
        if self.percent and 1 < value <= 100:
            return f"{head}; for {_num(value)} % give {_num(value / 100)} or '{_num(value)}%'"
        what = "a whole number" if self.integer else "a value"
        return f"{head}; choose {what} inside it" + (" or a percentage like '10%'" if self.percent else "")

    def check(self, value, name: str):
        """``value`` if it lies in the range, else :class:`UsageError` with :meth:`outside_message`; whole
        numbers come back as ``int`` where ``integer``."""
        if isinstance(value, str) and value in self.words:
            return value
        v = float(value)
        if not self.contains(v):
            raise UsageError(self.outside_message(v, name))
        return int(v) if self.integer else v

    def parse(self, text, name: str):
        """A value as typed (a number, a percentage if ``percent``, one of ``words``), checked (:meth:`check`).

        Raises
        ------
        UsageError
            If the text is not a number (naming what it takes), or the number is outside the range.
        """
        if not isinstance(text, str):
            return self.check(text, name)
        s = text.strip()
        for w in self.words:
            if s.lower() == w.lower():
                return w
        if self.percent and s.endswith("%"):
            return self.check(percent_to_fraction(s, name), name)
        try:
            v = float(s)
        except ValueError:
            kind = "a whole number" if self.integer else "a number"
            core = self.interval if self.interval.startswith(("<", ">")) else f"in {self.interval}"
            alt = "".join(f" or '{w}'" for w in self.words)
            raise UsageError(f"{name} must be {kind} {core}{self._unit}{alt}; got {text!r}") from None
        return self.check(v, name)

    def check_all(self, values: Sequence[float], name: str) -> list:
        """Every value of a list checked (:meth:`check`); the first outside the range is refused."""
        return [self.check(v, name) for v in values]


def percent_to_fraction(text: str, name: str) -> float:
    """'10%' -> 0.1, exactly the float that '0.1' reads as (the decimal divided, then rounded once).

    Examples
    --------
    >>> percent_to_fraction("10%", "--cv"), percent_to_fraction("0.3%", "--cv") == 0.003
    (0.1, True)
    """
    try:
        d = Decimal(text.strip().removesuffix("%").strip())
    except InvalidOperation:
        raise UsageError(f"{name} percentage {text!r} is not a number followed by '%'") from None
    if not d.is_finite():
        raise UsageError(NOT_FINITE.format(name=name, got=text))
    return float(d / 100)


# ---------------------------------------------------------------------------------------------- the ranges
JOINT_ANGLE_DEG_BOUNDS = Bounds(-360.0, 360.0, unit="deg", meaning="a joint angle within one turn")
"""theta_w and theta_l as given: within one turn either way; each robot's joint limits then bound them further
(:meth:`geometry.Robot.joint_values_rad`)."""
ORIENTATION_DEG_BOUNDS = Bounds(-360.0, 360.0, unit="deg", meaning="a body orientation within one turn")
"""Body pitch and roll as given: every orientation is reached within one turn either way."""
MASS_KG_BOUNDS = Bounds(0.0, math.inf, unit="kg", lo_open=True, meaning="a body's mass")
"""A body's mass, kg."""
PLAUSIBLE_MAX_MASS_KG = 1000.0
"""A mass above this is probably given in grams (a warning, not a refusal)."""
RADIANS_SLIP_MIN_SPAN_DEG = 20.0
"""A joint whose limits span at least this many degrees ranges over tens of degrees: a wing or leg angle of at
most 2 pi given for it is probably in radians (a warning, not a refusal)."""


def radians_slip(values_deg, limits_deg: tuple[float, float], name: str) -> str | None:
    """What to say of joint angles that look like radians given as degrees, or None.

    Said when every given value is at most 2 pi in size, at least one is not 0, the joint's limits
    ``limits_deg`` span tens of degrees (:data:`RADIANS_SLIP_MIN_SPAN_DEG`), and every value read in radians
    would lie within them: 1.3 for a wing that opens to 95 deg is 1.3 deg, or 74.5 deg meant in radians.

    Examples
    --------
    >>> radians_slip(1.3, (-10.0, 95.0), "--theta-w")
    '--theta-w 1.3 is taken in degrees, as every angle is; if you meant 1.3 rad, give --theta-w 74.48'
    >>> radians_slip(0.0, (-10.0, 95.0), "--theta-w") is None, radians_slip(30.0, (-10.0, 95.0), "--theta-w") is None
    (True, True)
    >>> radians_slip(2.0, (-10.0, 95.0), "--theta-w") is None  # 114.6 deg: past the joint's limit
    True
    """
    vals = [float(v) for v in (values_deg if isinstance(values_deg, (list, tuple)) else [values_deg])]
    lo, hi = limits_deg
    nonzero = [v for v in vals if v != 0.0]
    if not nonzero or hi - lo < RADIANS_SLIP_MIN_SPAN_DEG:
        return None
    if any(abs(v) > 2 * math.pi or not lo <= math.degrees(v) <= hi for v in vals):
        return None
    v = nonzero[0]
    deg = f"{math.degrees(v):.4g}"
    if len(vals) == 1:
        return (
            f"{name} {v:g} is taken in degrees, as every angle is; if you meant {v:g} rad, give {name} {deg}"
        )
    return (
        f"{name} values of at most {max(abs(x) for x in vals):g} are taken in degrees, as every angle is; if you "
        f"meant radians, give them in degrees ({v:g} rad is {deg} deg)"
    )


def joint_angle_slips(robot, angles_deg: dict, names: dict[str, str]) -> list[str]:
    """What to say of each wing or leg angle (``{"theta_w": value or list, ...}``) that looks like radians for
    ``robot``'s joints (:func:`radians_slip`), naming it as ``names`` spells it (``--theta-w``, ``theta_w``);
    angles that are None or that no joint of the robot takes are left out."""
    if not robot.has_joints:
        return []
    limits = robot.theta_limits_deg()
    slips = (
        radians_slip(v, limits[a], names[a])
        for a, v in angles_deg.items()
        if v is not None and robot.drives(a)
    )
    return [s for s in slips if s]


def mass_slip(mass_kg: float | None, name: str) -> str | None:
    """What to say of a mass that is probably in grams (above :data:`PLAUSIBLE_MAX_MASS_KG`), or None.

    Examples
    --------
    >>> mass_slip(260.0, "--mass") is None
    True
    >>> mass_slip(2600.0, "--mass")
    '--mass 2600 kg is more than 1000 kg; if you meant grams, give --mass 2.6'
    """
    if mass_kg is None or not mass_kg > PLAUSIBLE_MAX_MASS_KG:
        return None
    return (
        f"{name} {_num(mass_kg)} kg is more than {_num(PLAUSIBLE_MAX_MASS_KG)} kg; if you meant grams, "
        f"give {name} {_num(mass_kg / 1000)}"
    )
