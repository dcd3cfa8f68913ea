"""Tables of trial outcomes: success and time to right per (wing command, leg amplitude), and the side the robot
rolls to."""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from landscape.analysis.physical.outcome import PhysicalTrial, physical_trials
from landscape.analysis.trials import wilson_interval


@dataclass(frozen=True)
class PhysicalCell:
    """Outcomes of the trials at one (theta_w, theta_l).

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_measured_deg, theta_l_deg : float
    n, successes : int
    p, ci_low, ci_high : float
        Success fraction and its Wilson 95 % interval.
    median_time_to_right_s : float
        Over the successes (nan without).
    """

    theta_w_cmd_deg: float
    theta_w_measured_deg: float
    theta_l_deg: float
    n: int
    successes: int
    p: float
    ci_low: float
    ci_high: float
    median_time_to_right_s: float

    CSV_COLUMNS = (
        "theta_w_cmd_deg",
        "theta_w_measured_deg",
        "theta_l_deg",
        "n",
        "successes",
        "p",
        "ci_low",
        "ci_high",
        "median_time_to_right_s",
    )


def physical_cells(trials: Iterable[PhysicalTrial]) -> list[PhysicalCell]:
    """Success with Wilson 95 % intervals and median time to right per (theta_w, theta_l).

    Examples
    --------
    >>> t = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 2.0, 2, 1, (1,), 2, 5.0)
    >>> c = physical_cells([t, t.__class__(**{**t.__dict__, "success": False, "time_to_right_s": float("nan")})])
    >>> c[0].n, c[0].successes, c[0].median_time_to_right_s, round(c[0].ci_low, 4)
    (2, 1, 2.0, 0.0945)
    """
    groups: dict[tuple[float, float], list[PhysicalTrial]] = defaultdict(list)
    for t in trials:
        groups[(t.theta_w_cmd_deg, t.theta_l_deg)].append(t)
    out = []
    for (tw, tl), ts in sorted(groups.items()):
        k, n = sum(t.success for t in ts), len(ts)
        lo, hi = wilson_interval(k, n)
        times = [t.time_to_right_s for t in ts if t.success]
        out.append(
            PhysicalCell(
                tw,
                ts[0].theta_w_measured_deg,
                tl,
                n,
                k,
                k / n,
                lo,
                hi,
                float(np.median(times)) if times else math.nan,
            )
        )
    return out


@dataclass(frozen=True)
class Lateralisation:
    """To which side the robot rolls when it becomes upright.

    Attributes
    ----------
    positive, negative : int
        Upright events (every upright stretch, falls-back included) with positive and negative roll.
    p_positive, ci_low, ci_high : float
        Fraction to positive roll and its Wilson 95 % interval.
    """

    positive: int
    negative: int
    p_positive: float
    ci_low: float
    ci_high: float


def lateralisation(trials: Iterable[PhysicalTrial]) -> Lateralisation:
    """Count upright events by the sign of the roll (all cells together).

    Examples
    --------
    >>> t = PhysicalTrial("a", 60.0, 59.1, 15.0, 1, True, 2.0, 2, 1, (1, 1), 1, 5.0)
    >>> lateralisation([t]).positive
    2
    """
    dirs = [d for t in trials for d in t.upright_directions]
    pos, n = sum(d > 0 for d in dirs), len(dirs)
    lo, hi = wilson_interval(pos, n)
    return Lateralisation(pos, n - pos, pos / n if n else math.nan, lo, hi)


@dataclass(frozen=True)
class OutcomeTables:
    """The outcome tables of a data directory (``landscape physical table``).

    Attributes
    ----------
    trials : list of PhysicalTrial
        One per recorded trial.
    cells : list of PhysicalCell
        One per (wing command, leg amplitude).
    attempts : list of AttemptCount
        Per-attempt outcomes per wing command by the lab's rule.
    lateralisation : Lateralisation
        To which side the robot rolls when it becomes upright.
    """

    trials: list[PhysicalTrial]
    cells: list[PhysicalCell]
    attempts: list
    lateralisation: Lateralisation


def outcome_tables(data_dir: str | Path) -> OutcomeTables:
    """Every trial of a data directory, its cells, the per-attempt outcomes and the side the robot rolls to.

    Raises
    ------
    landscape.analysis.physical.recording.PhysicalDataError
        If the directory or a file is not in the lab's format.
    """
    from landscape.analysis.physical.attempts import attempt_outcomes

    trials = physical_trials(data_dir)
    return OutcomeTables(trials, physical_cells(trials), attempt_outcomes(trials), lateralisation(trials))
