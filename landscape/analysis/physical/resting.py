"""Resting pitch: where the body holds while the wings are open, relative to its rest before the first opening.

Per wing opening of a trial with the leg still, the median pitch (the nose's, :func:`sagittal_pitch_deg`, which
does not fold back past 90 deg as the ZYX pitch does) between ``HOLD_WINDOW_S`` after the opening starts, minus
the median pitch in the ``REST_WINDOW_S`` before the first opening (this removes the IMU's mounting); only openings
that end before the robot first becomes upright (the attempt that rights, or rights and falls back, is left out)
and whose window lies inside the recording.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from landscape.analysis.physical.outcome import upright_stretches
from landscape.analysis.physical.recording import (
    PhysicalDataError,
    Recording,
    measured_plateaus_deg,
    read_recording,
    sagittal_pitch_deg,
    trial_files,
)

HOLD_WINDOW_S = (0.5, 0.95)
"""Window after the start of an opening where the wings are held open (the servo near its plateau), s."""
REST_WINDOW_S = 0.3
"""Length of the resting window before the first opening, s."""
CLOSED_WINDOW_S = (1.7, 1.95)
"""Window after the start of an opening where the wings are closed again, s."""


@dataclass(frozen=True)
class RestingPitch:
    """The body pitch while the wings are held open, relative to the rest before the first opening.

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_measured_deg : float
    pitch_deg : ndarray of shape (n,)
        One value per opening (median over the hold window), degrees.
    median_deg, q25_deg, q75_deg : float
    n : int
    first_opening_median_deg : float
        Median over the trials' first openings only (no earlier opening has moved the body), degrees.
    closed_median_deg : float
        Median pitch ``CLOSED_WINDOW_S`` after the openings (wings closed again), same reference, degrees: 0 if
        the body returns to where it rested before the first opening.
    """

    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    pitch_deg: NDArray[np.float64]
    median_deg: float
    q25_deg: float
    q75_deg: float
    n: int
    first_opening_median_deg: float = math.nan
    closed_median_deg: float = math.nan


def opening_pitches_deg(
    rec: Recording, *, window_s: tuple[float, float] = HOLD_WINDOW_S, rest_s: float = REST_WINDOW_S
) -> NDArray[np.float64]:
    """Resting pitch of each opening of one recording (rules in the module docstring), degrees; nan for an
    opening left out (the robot became upright during it or later, or the window passes the recording's end)."""
    t = rec.t_s
    rest = (t >= -rest_s) & (t < 0)
    if not rest.any():
        return np.full(len(rec.openings_s), math.nan)
    pitch = sagittal_pitch_deg(rec.pitch_deg, rec.roll_deg)  # past vertical at 90 deg: not folded back
    ref = float(np.median(pitch[rest]))
    st = upright_stretches(t, rec.up_z)
    t_up = float(t[st[0][0]]) if st else math.inf
    ends = np.concatenate([rec.openings_s[1:], [math.inf]])
    out = []
    for start, end in zip(rec.openings_s, ends, strict=True):
        sel = (t >= start + window_s[0]) & (t <= start + window_s[1])
        if start + window_s[1] > t[-1] or min(end, t[-1]) >= t_up or not sel.any():
            out.append(math.nan)
        else:
            out.append(float(np.median(pitch[sel])) - ref)
    return np.asarray(out, dtype=np.float64)


def resting_pitch_table(data_dir: str | Path, *, theta_l_deg: float = 0.0) -> list[RestingPitch]:
    """Resting pitch per wing command over the trials with leg amplitude ``theta_l_deg`` (0: leg still)."""
    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:
        plateau = {}
    vals: dict[float, list[float]] = defaultdict(list)
    first: dict[float, list[float]] = defaultdict(list)
    closed: dict[float, list[float]] = defaultdict(list)
    for f in trial_files(data_dir):
        rec = read_recording(f)
        if rec.theta_l_deg == theta_l_deg:
            held = opening_pitches_deg(rec)
            vals[rec.theta_w_cmd_deg].extend(held[np.isfinite(held)].tolist())
            first[rec.theta_w_cmd_deg].extend(held[:1][np.isfinite(held[:1])].tolist())
            after = opening_pitches_deg(rec, window_s=CLOSED_WINDOW_S)
            closed[rec.theta_w_cmd_deg].extend(after[np.isfinite(after)].tolist())
    if not vals:
        raise PhysicalDataError(f"no trial with leg amplitude {theta_l_deg:g} deg in '{data_dir}'")
    out = []
    for tw, v in sorted(vals.items()):
        a = np.asarray(v, dtype=np.float64)
        q25, med, q75 = np.percentile(a, [25, 50, 75]) if len(a) else (math.nan,) * 3
        out.append(
            RestingPitch(
                tw,
                plateau.get(tw, math.nan),
                a,
                float(med),
                float(q25),
                float(q75),
                len(a),
                median_or_nan(first[tw]),
                median_or_nan(closed[tw]),
            )
        )
    return out


def median_or_nan(v: Sequence[float]) -> float:
    """The median of ``v``, nan when it is empty."""
    return float(np.median(v)) if len(v) else math.nan
