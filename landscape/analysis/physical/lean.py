"""The held body's lean with the leg swinging, recorded and simulated, and when an opening that rolls over left
the level.

- *lean*: with the leg swinging, the median lateral tilt (:func:`landscape.analysis.physical.response.lateral_tilt_deg`)
  of each window in which the leg has settled on one side (:func:`hold_leans_deg`: from ``LEAN_SETTLE_S`` after
  the leg reaches a side until it leaves it, within ``LEAN_WINDOW_S`` after the opening starts, and
  ``LEAN_DEPART_MARGIN_S`` before the body leaves the hold), one value for that side; the robot's leg reaches its
  side ``LEG_LAG_S`` after its command;
- *departure*: when an opening that rolls over last left the level (:func:`departure_s`: the tilt rising
  through ``LEVEL_TILT_DEG`` on the side it rolls to, before passing ``ROLLED_TILT_DEG``).
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from landscape.analysis.physical.outcome import upright_stretches
from landscape.analysis.physical.recording import (
    read_recording,
    trial_files,
)
from landscape.analysis.physical.response import (
    PROTOCOL_PHASE,
    ROLLED_TILT_DEG,
    SIM_OPENING_S,
    lateral_tilt_deg,
    simulated_openings,
)
from landscape.analysis.physical.resting import median_or_nan

LEAN_WINDOW_S = (0.4, 1.0)
"""Window after an opening's start in which the lean of the held body is read, s (the wings are open)."""
LEAN_SETTLE_S = 0.2
"""Time the body is given to settle after the leg reaches its new side before its lean is read, s."""
LEG_LAG_S = 0.1
"""How long after the robot's leg command changes sign the leg reaches its new side, s."""
LEAN_DEPART_DEG = 40.0
"""Lateral tilt past which the body has left the hold: no lean is read after it, degrees."""
LEAN_DEPART_MARGIN_S = 0.3
"""A lean window ends this long before the body passes ``LEAN_DEPART_DEG`` or becomes upright, s."""
LEAN_MIN_WINDOW_S = 0.08
"""Shortest window whose median counts as a lean, s."""
LEVEL_TILT_DEG = 5.0
"""Lateral tilt within which the body counts as level: :func:`departure_s` times its last leaving, degrees."""
LEG_HALF_PERIOD_S = 0.4
"""How long the lab's leg command stays on one side (half its period), s."""


def hold_leans_deg(
    t_s: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    start_s: float,
    leg_sign_changes_s: ArrayLike,
    leg_sign_after: ArrayLike,
    *,
    lag_s: float = 0.0,
) -> list[tuple[int, float]]:
    """The lean of the held body with the leg on each side: the median lateral tilt of each settled window of
    the opening that starts at ``start_s``.

    The leg changes side at ``leg_sign_changes_s + lag_s``. Window ``k`` runs from ``LEAN_SETTLE_S`` after
    change ``k`` to change ``k + 1`` (the last change's to the series' end), intersected with ``LEAN_WINDOW_S``
    after the opening's start, and ends ``LEAN_DEPART_MARGIN_S`` before the body leaves the hold: its first
    passing a tilt of ``LEAN_DEPART_DEG`` at or after the start, or the start of an upright stretch
    (:func:`landscape.analysis.physical.outcome.upright_stretches` of ``u_z = cos p cos r``) that has not ended
    before the opening starts. Windows shorter than ``LEAN_MIN_WINDOW_S`` or without samples are dropped.

    Parameters
    ----------
    t_s, pitch_deg, roll_deg : array_like of shape (N,)
        Times (s, increasing) and body pitch and roll (degrees) of one trial.
    start_s : float
        Start of the opening (the wing command's rise), s on the clock of ``t_s``.
    leg_sign_changes_s : array_like of shape (K,)
        When the leg's side changes, s on the clock of ``t_s``, increasing: every change of the trial (or at
        least every one from the last before ``start_s + LEAN_WINDOW_S[1]``).
    leg_sign_after : array_like of shape (K,)
        The leg's side after each change, +1 or -1 (the sign of the leg command or angle).
    lag_s : float
        Delay added to every change: how long the leg takes to reach its new side, s (``LEG_LAG_S`` for the
        robot's command, 0 for a measured leg angle).

    Returns
    -------
    leans : list of (int, float)
        ``(side, median tilt)`` of each window in time order: the leg's side (+1 or -1) and the median
        :func:`lateral_tilt_deg` over the window, degrees.

    Raises
    ------
    ValueError
        If the arrays' lengths differ, a side is not +1 or -1, or the changes are not increasing.

    Examples
    --------
    A body that leans +3 deg with the leg on + and -1 deg with it on -, the leg changing side every 0.4 s:

    >>> t = np.arange(-0.5, 1.5, 0.01).round(2)
    >>> changes = np.array([-0.2, 0.2, 0.6, 1.0])
    >>> sides = np.array([1, -1, 1, -1])
    >>> side_now = sides[np.searchsorted(changes, t, side="right") - 1]
    >>> leans = hold_leans_deg(t, np.zeros_like(t), np.where(side_now > 0, 3.0, -1.0), 0.0, changes, sides)
    >>> [(s, round(v, 6)) for s, v in leans]
    [(-1, -1.0), (1, 3.0)]

    The same with the leg 0.1 s late: the windows are 0.5-0.7 s and 0.9-1.0 s after the start.

    >>> lagged = np.where(sides[np.searchsorted(changes + 0.1, t, side="right") - 1] > 0, 3.0, -1.0)
    >>> [(s, round(v, 6)) for s, v in hold_leans_deg(t, 0 * t, lagged, 0.0, changes, sides, lag_s=0.1)]
    [(-1, -1.0), (1, 3.0)]
    """
    t = np.asarray(t_s, dtype=np.float64) - float(start_s)
    p = np.asarray(pitch_deg, dtype=np.float64)
    r = np.asarray(roll_deg, dtype=np.float64)
    ch = np.atleast_1d(np.asarray(leg_sign_changes_s, dtype=np.float64))
    sides = np.atleast_1d(np.asarray(leg_sign_after, dtype=np.float64))
    if not len(t) == len(p) == len(r):
        raise ValueError(
            f"t_s, pitch_deg and roll_deg must have one length; got {len(t)}, {len(p)}, {len(r)}"
        )
    if len(ch) != len(sides):
        raise ValueError(
            f"leg_sign_changes_s and leg_sign_after must have one length; got {len(ch)} and {len(sides)}"
        )
    if not np.isin(sides, (-1.0, 1.0)).all():
        raise ValueError(
            f"leg_sign_after must hold +1 or -1; got {float(sides[~np.isin(sides, (-1.0, 1.0))][0])!r}"
        )
    if np.any(np.diff(ch) <= 0):
        raise ValueError("leg_sign_changes_s must be increasing; sort the changes and drop repeated ones")
    if not len(t) or not len(ch):
        return []
    tilt = lateral_tilt_deg(p, r)
    end = min(_departed_s(t, p, r, tilt) - LEAN_DEPART_MARGIN_S, LEAN_WINDOW_S[1], float(t[-1]))
    ch = ch - float(start_s) + float(lag_s)
    nxt = np.concatenate([ch[1:], [math.inf]])
    eps = 1e-9
    out = []
    for c, c_next, side in zip(ch, nxt, sides, strict=True):
        lo, hi = max(c + LEAN_SETTLE_S, LEAN_WINDOW_S[0]), min(c_next, end)
        if hi - lo < LEAN_MIN_WINDOW_S - eps:
            continue
        sel = (t >= lo - eps) & (t <= hi + eps)
        if sel.any():
            out.append((int(side), float(np.median(tilt[sel]))))
    return out


def _departed_s(t, pitch_deg, roll_deg, tilt_deg) -> float:
    """When the body left the hold (``t``: times from the opening's start, s): the first sample at or after the
    start past ``LEAN_DEPART_DEG`` of tilt, or the start of an upright stretch not over before the start; inf if
    neither."""
    past = np.flatnonzero((t >= 0) & (np.abs(tilt_deg) >= LEAN_DEPART_DEG))
    out = float(t[past[0]]) if len(past) else math.inf
    up_z = np.cos(np.deg2rad(pitch_deg)) * np.cos(np.deg2rad(roll_deg))
    for first, last in upright_stretches(t, up_z):
        if t[last] >= 0:
            return min(out, float(t[first]))
    return out


def departure_s(t_s: ArrayLike, pitch_deg: ArrayLike, roll_deg: ArrayLike, start_s: float) -> float:
    """When the body left the level on its way to rolling over in the opening that starts at ``start_s``, s
    after the start.

    The lateral tilt's first passing ``ROLLED_TILT_DEG`` within ``SIM_OPENING_S`` after the start (as
    ``OpeningResponse.rolled_s``) marks a roll-over; its departure is the last time before it that the tilt, on
    the side it rolls to, rose through ``LEVEL_TILT_DEG`` (linear between samples). 0 if the tilt stayed
    beyond ``LEVEL_TILT_DEG`` from the start to the roll-over.

    Parameters
    ----------
    t_s, pitch_deg, roll_deg : array_like of shape (N,)
        Times (s, increasing) and body pitch and roll (degrees).
    start_s : float
        Start of the opening, s on the clock of ``t_s``.

    Returns
    -------
    departure_s : float
        s after ``start_s``; nan if the body does not roll over.

    Raises
    ------
    ValueError
        If the arrays' lengths differ.

    Examples
    --------
    Level at pitch 0, a rock to -10 deg and back, then a roll to + at 100 deg/s from 0.6 s: it leaves 5 deg
    at 0.6 + 5 / 100 s.

    >>> t = np.arange(-0.5, 2.0, 0.01)
    >>> roll = np.where(t < 0.6, 0.0, 100.0 * (t - 0.6)) - 10.0 * ((t > 0.2) & (t < 0.3))
    >>> round(departure_s(t, np.zeros_like(t), roll, 0.0), 6)
    0.65
    >>> departure_s(t, np.zeros_like(t), np.zeros_like(t), 0.0)
    nan
    """
    t = np.asarray(t_s, dtype=np.float64) - float(start_s)
    tilt = lateral_tilt_deg(pitch_deg, roll_deg)
    if not len(t) == len(tilt):
        raise ValueError(f"t_s, pitch_deg and roll_deg must have one length; got {len(t)} and {len(tilt)}")
    over = np.flatnonzero((t >= 0) & (t <= SIM_OPENING_S) & (np.abs(tilt) >= ROLLED_TILT_DEG))
    if not len(over):
        return math.nan
    i = int(over[0])
    side_tilt = np.sign(tilt[i]) * tilt
    level = np.flatnonzero((t[:i] >= 0) & (side_tilt[:i] <= LEVEL_TILT_DEG))
    if not len(level):
        return 0.0
    j = int(level[-1])
    a, b = side_tilt[j], side_tilt[j + 1]
    return float(t[j] + (t[j + 1] - t[j]) * (LEVEL_TILT_DEG - a) / (b - a))


@dataclass(frozen=True)
class HoldLeans:
    """The leans of the held body over several openings, and their departures.

    Attributes
    ----------
    plus_deg, minus_deg : tuple of float
        :func:`hold_leans_deg` of every window with the leg on + and on -, degrees.
    departures_s : tuple of float
        :func:`departure_s` of every opening analysed, s after its start (nan where it did not roll over).
    """

    plus_deg: tuple[float, ...] = ()
    minus_deg: tuple[float, ...] = ()
    departures_s: tuple[float, ...] = ()


def _opening_leans(t_s, pitch_deg, roll_deg, starts_s, changes_s, sides, *, lag_s: float) -> HoldLeans:
    """:class:`HoldLeans` of the openings starting at ``starts_s`` of one series."""
    plus, minus, dep = [], [], []
    for start in starts_s:
        for side, lean in hold_leans_deg(t_s, pitch_deg, roll_deg, start, changes_s, sides, lag_s=lag_s):
            (plus if side > 0 else minus).append(lean)
        dep.append(departure_s(t_s, pitch_deg, roll_deg, start))
    return HoldLeans(tuple(plus), tuple(minus), tuple(dep))


def recorded_leans(data_dir: str | Path) -> dict[tuple[float, float], HoldLeans]:
    """:func:`hold_leans_deg` and :func:`departure_s` of the recorded openings with the leg moving, per cell.

    The leg command turns + at ``Recording.leg_up_s`` and - ``LEG_HALF_PERIOD_S`` later; the leg follows
    ``LEG_LAG_S`` after it. Every opening of a trial until the robot first becomes upright (the lab's rule,
    :func:`landscape.analysis.physical.attempts.recording_attempts`: the opening in which it rights is the last) counts;
    an upright robot's lateral tilt (roll near 180 deg) is no lean.

    Parameters
    ----------
    data_dir : path
        The lab's physical_robot folder.

    Returns
    -------
    leans : dict of (float, float) to HoldLeans
        Per cell ``(theta_w_cmd_deg, theta_l_deg)``, degrees, with the leg moving.

    Raises
    ------
    PhysicalDataError
        If the directory or a file is not in the lab's format.
    """
    acc: dict[tuple[float, float], list[HoldLeans]] = defaultdict(list)
    for f in trial_files(data_dir):
        rec = read_recording(f)
        if rec.theta_l_deg == 0 or not len(rec.leg_up_s):
            continue
        changes, sides = leg_command_changes(rec.leg_up_s)
        st = upright_stretches(rec.t_s, rec.up_z)
        t_up = float(rec.t_s[st[0][0]]) if st else math.inf
        starts = [s for s in rec.openings_s if s <= t_up]
        acc[(rec.theta_w_cmd_deg, rec.theta_l_deg)].append(
            _opening_leans(rec.t_s, rec.pitch_deg, rec.roll_deg, starts, changes, sides, lag_s=LEG_LAG_S)
        )
    return {cell: _joined(parts) for cell, parts in sorted(acc.items())}


def leg_command_changes(leg_up_s) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """When the robot's leg command changes side, from its servo log: + at each upward command
    (``Recording.leg_up_s``), - ``LEG_HALF_PERIOD_S`` later; ``(times, sides)``, sorted by time. The leg itself
    follows ``LEG_LAG_S`` later.

    Examples
    --------
    >>> leg_command_changes([0.2, 1.0])
    (array([0.2, 0.6, 1. , 1.4]), array([ 1., -1.,  1., -1.]))
    """
    up = np.asarray(leg_up_s, dtype=np.float64)
    changes = np.concatenate([up, up + LEG_HALF_PERIOD_S])
    sides = np.concatenate([np.ones(len(up)), -np.ones(len(up))])
    order = np.argsort(changes, kind="stable")
    return changes[order], sides[order]


def _joined(parts: Sequence[HoldLeans]) -> HoldLeans:
    return HoldLeans(
        tuple(x for h in parts for x in h.plus_deg),
        tuple(x for h in parts for x in h.minus_deg),
        tuple(x for h in parts for x in h.departures_s),
    )


def leg_sides(t_s, leg_deg, *, band_deg: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """When a measured leg angle changes side (the first sample of the run of one sign that reaches
    ``band_deg`` past the midline, so a leg held on the midline changes no side), s, and the side after, +-1.

    Examples
    --------
    >>> t = np.arange(0.0, 1.0, 0.1).round(1)
    >>> leg_sides(t, [0.0, 15.0, 30.0, 30.0, 10.0, -20.0, -30.0, -0.1, 0.2, 0.0], band_deg=15.0)
    (array([0.1, 0.5]), array([ 1., -1.]))
    """
    t = np.asarray(t_s, dtype=np.float64)
    leg = np.asarray(leg_deg, dtype=np.float64)
    sign = np.sign(leg)
    changes, sides = [], []
    side, run_start = 0.0, -1
    for k in range(len(leg)):
        if sign[k] == 0:
            run_start = -1
            continue
        if run_start < 0 or sign[k] != sign[k - 1]:
            run_start = k
        if sign[k] != side and abs(leg[k]) >= band_deg:
            side = float(sign[k])
            changes.append(float(t[run_start]))
            sides.append(side)
    return np.asarray(changes, dtype=np.float64), np.asarray(sides, dtype=np.float64)


def simulated_leans(
    theta_w_deg: float,
    theta_l_deg: float,
    *,
    model_set: str | Path,
    robot: str | Path | None,
    seed: int,
    attempts: int = 3,
    phase: float = PROTOCOL_PHASE,
) -> HoldLeans:
    """:func:`hold_leans_deg` and :func:`departure_s` of the openings of one simulated trial (no noise).

    The trial (:func:`sim.trial.run_trial` with a trace) makes ``attempts`` openings, the first at leg phase
    ``phase``, and ends ``SIM_OPENING_S`` after the last (or once the body has righted). Openings ``Tw = 2 s``
    apart alternate the leg's phase (Tl = 0.8 s), so three sample both sides. The leg's side is the sign of the
    simulated leg angle (its first sample past the midline, of a swing reaching half the amplitude), with no lag.

    Parameters
    ----------
    theta_w_deg, theta_l_deg : float
        What the set simulates (the command for a measured profile, the wing angle otherwise) and the leg
        amplitude, degrees; with ``theta_l_deg`` 0 there is no side and no lean.
    model_set : str or path
        Model parameter set (:func:`sim.model_set.load_model_set`).
    robot : path or None
        URDF file (None: the built-in robot).
    seed : int
        The trial's seed.
    attempts : int
        Openings simulated (>= 1).
    phase : float
        Leg phase of the first opening, in [0, 1).

    Returns
    -------
    HoldLeans

    Raises
    ------
    ValueError
        If ``attempts`` < 1 (and :func:`sim.trial.run_trial`'s errors for bad inputs).
    """
    if attempts < 1:
        raise ValueError(f"attempts must be >= 1; got {attempts!r}")
    tr, starts = simulated_openings(
        theta_w_deg, theta_l_deg, model_set=model_set, robot=robot, seed=seed, phase=phase, attempts=attempts
    )
    if theta_l_deg > 0:
        changes, sides = leg_sides(tr.t_s, tr.leg_deg, band_deg=0.5 * theta_l_deg)
    else:
        changes, sides = np.zeros(0), np.zeros(0)
    return _opening_leans(tr.t_s, tr.pitch_deg, tr.roll_deg, starts, changes, sides, lag_s=0.0)


@dataclass(frozen=True)
class CellLean:
    """One cell's lean of the held body with the leg on each side, and its roll-overs' departures.

    Attributes
    ----------
    theta_w_cmd_deg, theta_l_deg : float
        Wing command and leg amplitude, degrees.
    plus_deg, minus_deg : float
        Median lean with the leg on + and on -, degrees (nan without a window).
    n_plus, n_minus : int
        Windows behind each median.
    departure_s : float
        Median :func:`departure_s` of the openings that rolled over, s (nan if none did).
    n_rolled, n_openings : int
        Openings that rolled over, and openings analysed.
    """

    theta_w_cmd_deg: float
    theta_l_deg: float
    plus_deg: float
    n_plus: int
    minus_deg: float
    n_minus: int
    departure_s: float = math.nan
    n_rolled: int = 0
    n_openings: int = 0

    @property
    def difference_deg(self) -> float:
        """``plus_deg - minus_deg``: how much further the body leans to + with the leg on +, degrees."""
        return self.plus_deg - self.minus_deg


def cell_lean(theta_w_cmd_deg: float, theta_l_deg: float, leans: HoldLeans) -> CellLean:
    """Summarise one cell's :class:`HoldLeans` into medians and counts.

    Examples
    --------
    >>> c = cell_lean(60.0, 30.0, HoldLeans((8.0, 7.0, 9.0), (-1.0, 0.0), (1.1, math.nan, 0.9)))
    >>> c.plus_deg, c.n_plus, c.minus_deg, c.n_minus, c.difference_deg
    (8.0, 3, -0.5, 2, 8.5)
    >>> round(c.departure_s, 6), c.n_rolled, c.n_openings
    (1.0, 2, 3)
    """
    dep = np.asarray(leans.departures_s, dtype=np.float64)
    rolled = dep[np.isfinite(dep)]
    return CellLean(
        float(theta_w_cmd_deg),
        float(theta_l_deg),
        median_or_nan(leans.plus_deg),
        len(leans.plus_deg),
        median_or_nan(leans.minus_deg),
        len(leans.minus_deg),
        median_or_nan(rolled),
        len(rolled),
        len(dep),
    )
