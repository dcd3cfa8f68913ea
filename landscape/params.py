"""Value lists and ranges as people type them ("70,72,74", "70:76:2"): one parser for the command line and the
service, bounded so that a typo cannot ask for a billion values."""

from __future__ import annotations

import math

from geometry.errors import UsageError

MAX_VALUES = 100_000
"""Most values one list or range may expand to (a typo like 0:90:1e-7 would be 9e8)."""


def parse_values(text: str, what: str) -> list[float]:
    """'70,72,74' or '70:76:2' (inclusive) or '70' -> list of floats.

    Examples
    --------
    >>> parse_values("70:76:2", "theta-w"), parse_values("20, 30", "theta-l")
    ([70.0, 72.0, 74.0, 76.0], [20.0, 30.0])
    >>> parse_values("0:90:1e-7", "theta-w")
    Traceback (most recent call last):
    ...
    geometry.errors.UsageError: --theta-w range '0:90:1e-7' has 9e+08 values, more than the 100000 allowed; use a larger STEP
    """
    text = text.strip()
    if not text:
        raise UsageError(f"--{what} is empty; give values like 70,72,74 or a range START:STOP:STEP")
    try:
        if ":" in text:
            parts = [float(x) for x in text.split(":")]
            if len(parts) != 3 or not parts[2] > 0 or not all(math.isfinite(x) for x in parts):
                raise UsageError(f"--{what} range {text!r} must be START:STOP:STEP with STEP > 0")
            count = (parts[1] - parts[0]) / parts[2] + 1e-9
            if not math.isfinite(count) or count + 1 > MAX_VALUES:
                raise UsageError(
                    f"--{what} range {text!r} has {count + 1:.3g} values, more than the "
                    f"{MAX_VALUES} allowed; use a larger STEP"
                )
            n = math.floor(count) + 1
            if n < 1:
                raise UsageError(f"--{what} range {text!r} is empty (STOP < START)")
            vals = [round(parts[0] + k * parts[2], 10) for k in range(n)]
        else:
            vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError as exc:
        if isinstance(exc, UsageError):
            raise
        raise UsageError(f"--{what} {text!r} is not a list of numbers (e.g. 70,72,74 or 70:76:2)") from None
    if not vals:
        raise UsageError(f"--{what} is empty; give at least one value")
    if len(vals) > MAX_VALUES:
        raise UsageError(f"--{what} has {len(vals)} values, more than the {MAX_VALUES} allowed")
    bad = [v for v in vals if not math.isfinite(v)]
    if bad:
        raise UsageError(f"--{what} must be finite numbers; got {bad[0]!r}")
    return vals
