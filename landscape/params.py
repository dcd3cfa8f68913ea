"""Value lists and ranges as people type them ("70,72,74", "70:76:2"): one parser for the command line and the
service, bounded so that a typo cannot ask for a billion values, and each value checked against its stated
range (:class:`geometry.bounds.Bounds`)."""

from __future__ import annotations

import math
import re
from decimal import Decimal

from geometry.bounds import NOT_FINITE, Bounds, percent_to_fraction
from geometry.errors import UsageError

MAX_VALUES = 100_000
"""Most values one list or range may expand to (a typo like 0:90:1e-7 would be 9e8)."""


def parse_values(text: str, what: str, *, name: str | None = None) -> list[float]:
    """'70,72,74' or '70:76:2' (inclusive) or '70' -> list of floats; messages name the option ``--what`` (or
    ``name`` as given, e.g. a query parameter's ``theta_w``).

    Examples
    --------
    >>> parse_values("70:76:2", "theta-w"), parse_values("20, 30", "theta-l")
    ([70.0, 72.0, 74.0, 76.0], [20.0, 30.0])
    >>> parse_values("0:90:1e-7", "theta-w")
    Traceback (most recent call last):
    ...
    geometry.errors.UsageError: --theta-w range '0:90:1e-7' has 9e+08 values, more than the 100000 allowed; use a larger STEP
    """
    label = name or f"--{what}"
    text = text.strip()
    if not text:
        raise UsageError(f"{label} is empty; give values like 70,72,74 or a range START:STOP:STEP")
    try:
        if ":" in text:
            parts = [float(x) for x in text.split(":")]
            if len(parts) != 3 or not parts[2] > 0 or not all(math.isfinite(x) for x in parts):
                raise UsageError(f"{label} range {text!r} must be START:STOP:STEP with STEP > 0")
            count = (parts[1] - parts[0]) / parts[2] + 1e-9
            if not math.isfinite(count) or count + 1 > MAX_VALUES:
                raise UsageError(
                    f"{label} range {text!r} has {count + 1:.3g} values, more than the "
                    f"{MAX_VALUES} allowed; use a larger STEP"
                )
            n = math.floor(count) + 1
            if n < 1:
                raise UsageError(f"{label} range {text!r} is empty (STOP < START)")
            vals = [round(parts[0] + k * parts[2], 10) for k in range(n)]
        else:
            vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError as exc:
        if isinstance(exc, UsageError):
            raise
        raise UsageError(f"{label} {text!r} is not a list of numbers (e.g. 70,72,74 or 70:76:2)") from None
    if not vals:
        raise UsageError(f"{label} is empty; give at least one value")
    if len(vals) > MAX_VALUES:
        raise UsageError(f"{label} has {len(vals)} values, more than the {MAX_VALUES} allowed")
    bad = [v for v in vals if not math.isfinite(v)]
    if bad:
        raise UsageError(NOT_FINITE.format(name=label, got=bad[0]))
    return vals


_NUMBER_TOKEN = re.compile(r"[^,:]+")


def parse_bounded(text, bounds: Bounds, name: str) -> list:
    """Values as typed ('70,72', '70:76:2', and where ``bounds.percent`` also '10%,20%' or '0%:25%:5%'), each
    inside ``bounds``; messages name the input as ``name`` ('--cv', or 'cv' in the service).

    A list of numbers (a request's JSON list, a default) is checked as it is.

    Examples
    --------
    >>> cv = Bounds(0.0, 1.0, meaning="Cv is sigma / Tl as a fraction", percent=True)
    >>> parse_bounded("0%:10%:5%", cv, "--cv"), parse_bounded("0,0.05,0.1", cv, "--cv")
    ([0.0, 0.05, 0.1], [0.0, 0.05, 0.1])
    >>> parse_bounded("0,10", cv, "--cv")
    Traceback (most recent call last):
    ...
    geometry.errors.UsageError: --cv 10 is outside [0, 1]: Cv is sigma / Tl as a fraction; for 10 % give 0.1 or '10%'
    """
    if isinstance(text, (list, tuple)):
        vals = [float(v) for v in text]
    else:
        text = str(text)
        if bounds.percent and "%" in text:
            tokens = _NUMBER_TOKEN.findall(text)
            if not all(t.strip().endswith("%") for t in tokens if t.strip()):
                raise UsageError(
                    f"{name} {text!r} mixes percentages and fractions; write every value with '%' "
                    "(0%:25%:5%) or none (0:0.25:0.05)"
                )
            text = _NUMBER_TOKEN.sub(
                lambda m: (
                    format(Decimal(str(percent_to_fraction(m.group(0), name))), "f")
                    if m.group(0).strip()
                    else m.group(0)
                ),
                text,
            )
        vals = parse_values(text, name.lstrip("-"), name=name)
    return bounds.check_all(vals, name)
