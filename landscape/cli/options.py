"""Option parsing shared by the command-line modules (edge layer)."""

from __future__ import annotations

import numpy as np


class InputError(ValueError):
    """Bad command-line input."""


def parse_values(text: str, what: str) -> list[float]:
    """'70,72,74' or '70:76:2' (inclusive) or '70' -> list of floats.

    Examples
    --------
    >>> parse_values("70:76:2", "theta-w"), parse_values("20, 30", "theta-l")
    ([70.0, 72.0, 74.0, 76.0], [20.0, 30.0])
    """
    text = text.strip()
    if not text:
        raise InputError(f"--{what} is empty; give values like 70,72,74 or a range START:STOP:STEP")
    try:
        if ":" in text:
            parts = [float(x) for x in text.split(":")]
            if len(parts) != 3 or not parts[2] > 0 or not np.isfinite(parts).all():
                raise InputError(f"--{what} range {text!r} must be START:STOP:STEP with STEP > 0")
            n = int(np.floor((parts[1] - parts[0]) / parts[2] + 1e-9)) + 1
            if n < 1:
                raise InputError(f"--{what} range {text!r} is empty (STOP < START)")
            vals = [round(parts[0] + k * parts[2], 10) for k in range(n)]
        else:
            vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"--{what} {text!r} is not a list of numbers (e.g. 70,72,74 or 70:76:2)") from None
    if not vals:
        raise InputError(f"--{what} is empty; give at least one value")
    bad = [v for v in vals if not np.isfinite(v)]
    if bad:
        raise InputError(f"--{what} must be finite numbers of degrees; got {bad[0]!r}")
    return vals
