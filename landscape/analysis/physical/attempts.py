"""Attempts: the wing openings of a trial, counted by the lab's rule and as body pitch-roll paths.

The lab's per-attempt count (``robot_attempts.mat``) takes the first ``LAB_ATTEMPTS_PER_TRIAL`` openings of each
trial (the paper's 10 s trial) and counts an attempt a success when the robot becomes upright during it, even if it
falls back later: :func:`attempt_outcomes` applies that rule to the trials and reproduces the file's counts.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from landscape.analysis.physical.outcome import UPRIGHT_HOLD_S, PhysicalTrial, upright_stretches
from landscape.analysis.physical.recording import (
    WING_COMMANDS_DEG,
    PhysicalDataError,
    Recording,
    attempt_plateau_deg,
    measured_plateaus_deg,
    read_attempt_table,
    read_recording,
    trial_cell,
    trial_files,
)
from landscape.analysis.trials import wilson_interval

LAB_ATTEMPTS_PER_TRIAL = 5
"""Openings per trial the lab's per-attempt table counts (the paper's 10 s trials at Tw = 2 s)."""


@dataclass(frozen=True)
class AttemptCount:
    """Per-attempt outcomes at one wing command, pooled over leg amplitudes.

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_measured_deg : float
    attempts, successes : int
    p, ci_low, ci_high : float
        Per-attempt success rate and its Wilson 95 % interval.
    """

    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    attempts: int
    successes: int
    p: float
    ci_low: float
    ci_high: float


def _count(tw: float, measured: float, k: int, n: int) -> AttemptCount:
    lo, hi = wilson_interval(k, n)
    return AttemptCount(tw, measured, n, k, k / n if n else math.nan, lo, hi)


def recorded_attempt_counts(data_dir: str | Path) -> list[AttemptCount]:
    """The lab's per-attempt outcomes (``robot_attempts.mat``) per wing command."""
    att = read_attempt_table(data_dir)
    out = []
    for tw, e in zip(WING_COMMANDS_DEG, att, strict=True):
        res = np.atleast_1d(np.asarray(e.result, dtype=np.float64))
        out.append(_count(tw, attempt_plateau_deg(e), int(np.sum(res == 1)), len(res)))
    return out


def attempt_outcomes(
    trials: Iterable[PhysicalTrial], *, max_attempts: int = LAB_ATTEMPTS_PER_TRIAL
) -> list[AttemptCount]:
    """Per-attempt outcomes per wing command by the lab's rule: the first ``max_attempts`` openings of each
    trial; an attempt succeeds when the robot first becomes upright during it.

    Examples
    --------
    >>> t = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 2.0, 2, 1, (1,), 2, 5.0)
    >>> f = PhysicalTrial("b", 60.0, 59.1, 0.0, 1, False, float("nan"), 9, 0, (), 0, 18.0)
    >>> c = attempt_outcomes([t, f])[0]
    >>> c.attempts, c.successes
    (7, 1)
    """
    acc: dict[float, list] = defaultdict(lambda: [0, 0, math.nan])
    for t in trials:
        a = acc[t.theta_w_cmd_deg]
        a[2] = t.theta_w_measured_deg
        if 0 < t.first_upright_attempt <= max_attempts:
            a[0] += 1
            a[1] += t.first_upright_attempt
        else:
            a[1] += min(t.attempts, max_attempts)
    return [_count(tw, m, k, n) for tw, (k, n, m) in sorted(acc.items())]


@dataclass(frozen=True)
class PhysicalAttempt:
    """One self-righting attempt of the physical robot (one wing opening) as a body pitch-roll path.

    Attributes
    ----------
    name : str
        Trial file.
    theta_w_cmd_deg, theta_w_measured_deg, theta_l_deg : float
        Commanded and measured (plateau) wing angle, leg amplitude, degrees.
    trial, attempt : int
        Trial number K and the opening's number in it (1 = the first).
    t_s : ndarray of shape (L,)
        Time from the trial's first opening, s.
    pitch_deg, roll_deg : ndarray of shape (L,)
        Recorded body pitch and roll over the attempt, degrees (ZYX Euler, ``geometry/frames.py``).
    righted : bool
        The robot became upright during this attempt (the lab's per-attempt rule, :func:`attempt_outcomes`).
    """

    name: str
    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    theta_l_deg: float
    trial: int
    attempt: int
    t_s: NDArray[np.float64]
    pitch_deg: NDArray[np.float64]
    roll_deg: NDArray[np.float64]
    righted: bool


def recording_attempts(
    rec: Recording, *, theta_w_measured_deg: float = math.nan, max_attempts: int | None = None
) -> list[PhysicalAttempt]:
    """The attempts of one recording, by the lab's rule: every wing opening until the robot first becomes upright
    (the one in which it does is the last, ``righted``), all openings if it never does; at most the first
    ``max_attempts`` openings (``LAB_ATTEMPTS_PER_TRIAL``: the lab's per-attempt table; None: all).

    An attempt runs from the start of its opening to the start of the next; the righting attempt ends
    ``UPRIGHT_HOLD_S`` after the robot becomes upright (its path reaches the upright side and stops there).
    Openings that start after the recording's last sample have no samples and are left out.
    """
    st = upright_stretches(rec.t_s, rec.up_z)
    t_up = float(rec.t_s[st[0][0]]) if st else math.inf
    ends = np.concatenate([rec.openings_s[1:], [math.inf]])
    out = []
    for k, (start, end) in enumerate(zip(rec.openings_s, ends, strict=True), start=1):
        if start > t_up or (max_attempts is not None and k > max_attempts):
            break
        righted = bool(start <= t_up < end)
        stop = min(end, t_up + UPRIGHT_HOLD_S) if righted else end
        sel = (rec.t_s >= start) & (rec.t_s < stop)
        if not sel.any():
            continue
        out.append(
            PhysicalAttempt(
                rec.name,
                rec.theta_w_cmd_deg,
                float(theta_w_measured_deg),
                rec.theta_l_deg,
                rec.trial,
                k,
                rec.t_s[sel],
                rec.pitch_deg[sel],
                rec.roll_deg[sel],
                righted,
            )
        )
    return out


def physical_attempts(
    data_dir: str | Path,
    *,
    theta_w_cmd_deg: float | None = None,
    theta_l_deg: float | None = None,
    max_attempts: int | None = None,
) -> list[PhysicalAttempt]:
    """Every attempt (:func:`recording_attempts`, up to ``max_attempts`` per trial) of the trials of a data
    directory, optionally only those at one commanded wing angle and leg amplitude, in file order.

    Raises
    ------
    PhysicalDataError
        If the directory or a file is not in the lab's format, or no trial has the wing angle and leg amplitude
        asked for (the message lists those recorded).
    """
    commands = {f: trial_cell(f) for f in trial_files(data_dir)}
    chosen = [
        f
        for f, (w, leg) in commands.items()
        if (theta_w_cmd_deg is None or w == theta_w_cmd_deg) and (theta_l_deg is None or leg == theta_l_deg)
    ]
    if not chosen:
        have = ", ".join(f"{w:g}/{leg:g}" for w, leg in sorted(set(commands.values())))
        raise PhysicalDataError(
            f"no physical trial at wing {theta_w_cmd_deg if theta_w_cmd_deg is not None else 'any'} deg, leg "
            f"{theta_l_deg if theta_l_deg is not None else 'any'} deg in '{data_dir}'; the recorded wing/leg "
            f"commands are {have} deg"
        )
    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:
        plateau = {}
    out = []
    for rec in map(read_recording, chosen):
        out += recording_attempts(
            rec, theta_w_measured_deg=plateau.get(rec.theta_w_cmd_deg, math.nan), max_attempts=max_attempts
        )
    return out
