"""Wing and leg actuation profiles (pure numpy).

Times are seconds from the start of actuation (after the robot has settled on its back).

Wings (every wing joint = theta_w(t)): attempt ``k`` opens at ``t_k``. The wings open at
``wing_open_deg_s`` (300 deg/s) to theta_w, start closing ``wing_close_start_s`` (1.05 s) after ``t_k``, close at
``wing_close_deg_s`` (250 deg/s) to 0 and stay closed until the next attempt. With no noise the attempts repeat
every ``wing_period_s`` (Tw = 2 s), so the nominal closed hold is ``Tw - close_start - theta_w / close_speed``.

Randomness: the closed hold after attempt ``k`` gets Gaussian noise ``delta_k ~ N(0, sigma^2)``,
``sigma = cv * leg_period_s`` (Cv = sigma / Tl). A negative hold is avoided by clipping the hold at 0 (the
wings reopen the moment they are closed); with the paper's largest Cv = 0.25 (sigma = 0.2 s) and theta_w = 76 deg
the nominal hold is 0.65 s, so clipping happens with probability 6e-4 per attempt. The first attempt opens at
``t_1 = phase * leg_period_s`` (phase phi_1 = Delta t_1 / Tl); each attempt's phase is
``phi_k = (t_k mod Tl) / Tl``.

Leg (the leg joint = theta_l(t)): a periodic trapezoid between -theta_l and +theta_l with period Tl = 0.8 s that
crosses from one side to the other in ``leg_cross_s`` (0.15 s) at constant speed ``2 theta_l / leg_cross_s``.
At t = 0 it is on the midline moving towards **+theta_l** first (for the lab robot the pendulum's sphere then
swings to -y, the ``wing1`` side); it reaches +theta_l at ``leg_cross_s / 2``, passes the midline again at
``Tl / 2`` and ``Tl``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from geometry.errors import UsageError

from .protocol import PAPER_LEG_PERIOD_S, PAPER_WING_PERIOD_S


@dataclass(frozen=True)
class MeasuredActuation:
    """Piecewise-linear per-joint profiles fitted to the physical robot (:mod:`landscape.analysis.physical.measured`).

    Attributes
    ----------
    wing_command_deg : tuple of float, shape (C,)
        Wing commands the profiles were measured at, deg (increasing).
    wing_knots_s, wing_knots_deg : tuple, shape (4, C, K)
        Per wing servo (LP, RP, LR, RR: the joint map's wing joints in order) and command: knot times since the
        opening command, s, and joint angles, deg. The first and last knots hold the closed angle.
    leg_command_deg : tuple of float, shape (L,)
        Leg amplitude commands, deg (increasing).
    leg_knots_s, leg_knots_deg : tuple, shape (L, M)
        One period of the leg angle per command, from its upward midline crossing (0 deg at both ends), s and deg.
    """

    wing_command_deg: tuple
    wing_knots_s: tuple
    wing_knots_deg: tuple
    leg_command_deg: tuple
    leg_knots_s: tuple
    leg_knots_deg: tuple

    @property
    def leg_period_s(self) -> float:
        return float(self.leg_knots_s[0][-1])

    def check(self, theta_w_deg: float, theta_l_deg: float, leg_period_s: float) -> None:
        """Refuse commands outside the measured ranges and a leg period other than the measured one."""
        lo, hi = self.wing_command_deg[0], self.wing_command_deg[-1]
        if not lo <= theta_w_deg <= hi:
            raise UsageError(
                f"theta_w = {theta_w_deg:g} deg is outside the measured wing commands [{lo:g}, {hi:g}] deg; "
                "choose a wing angle inside or an idealised model set"
            )
        if not 0.0 <= theta_l_deg <= self.leg_command_deg[-1]:
            raise UsageError(
                f"theta_l = {theta_l_deg:g} deg is outside the measured leg commands [0, "
                f"{self.leg_command_deg[-1]:g}] deg; choose a leg amplitude inside or an idealised model set"
            )
        if abs(leg_period_s - self.leg_period_s) > 1e-9:
            raise UsageError(
                f"the measured leg profile has a period of {self.leg_period_s:g} s; got leg period "
                f"{leg_period_s:g} s: use {self.leg_period_s:g} s or an idealised model set"
            )

    def wing_knots(self, theta_w_deg: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Knot times (s) and angles (deg) of each wing servo at this command, shape (4, K) each: linear in the
        command between the measured ones (each knot's time and angle)."""
        c = np.asarray(self.wing_command_deg, dtype=np.float64)
        i = int(np.clip(np.searchsorted(c, theta_w_deg, side="right") - 1, 0, len(c) - 2))
        f = (theta_w_deg - c[i]) / (c[i + 1] - c[i])
        ks, kd = np.asarray(self.wing_knots_s, float), np.asarray(self.wing_knots_deg, float)
        return (1 - f) * ks[:, i] + f * ks[:, i + 1], (1 - f) * kd[:, i] + f * kd[:, i + 1]

    def wing_plateaus_deg(self, theta_w_deg: float) -> NDArray[np.float64]:
        """Where each wing servo (LP, RP, LR, RR) holds while open at this command: the largest knot angle of
        :meth:`wing_knots`, deg, shape (4,).

        Raises
        ------
        UsageError
            If the command lies outside the measured ones.
        """
        lo, hi = self.wing_command_deg[0], self.wing_command_deg[-1]
        if not (np.isfinite(theta_w_deg) and lo <= theta_w_deg <= hi):
            raise UsageError(
                f"theta_w = {theta_w_deg:g} deg is outside the measured wing commands [{lo:g}, {hi:g}] deg; "
                "choose a wing command inside or an idealised model set"
            )
        return self.wing_knots(theta_w_deg)[1].max(axis=1)

    def leg_knots(self, theta_l_deg: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Knot times (s) and angles (deg) of the leg at this amplitude command: linear in the command between
        the measured ones, and from the smallest down to a still leg at 0."""
        c = np.concatenate([[0.0], np.asarray(self.leg_command_deg, dtype=np.float64)])
        ks = np.asarray(self.leg_knots_s, float)
        kd = np.concatenate([np.zeros((1, ks.shape[1])), np.asarray(self.leg_knots_deg, float)])
        ks = np.concatenate([ks[:1], ks])
        i = int(np.clip(np.searchsorted(c, theta_l_deg, side="right") - 1, 0, len(c) - 2))
        f = (theta_l_deg - c[i]) / (c[i + 1] - c[i])
        return (1 - f) * ks[i] + f * ks[i + 1], (1 - f) * kd[i] + f * kd[i + 1]


def _pwl_and_slope(tau, knots_s, knots_deg):
    """A piecewise-linear profile and its slope at ``tau`` (flat outside the knots)."""
    angle = np.interp(tau, knots_s, knots_deg)
    seg = np.clip(np.searchsorted(knots_s, tau, side="right") - 1, 0, len(knots_s) - 2)
    dt = knots_s[seg + 1] - knots_s[seg]
    slope = np.where(dt > 0, (knots_deg[seg + 1] - knots_deg[seg]) / np.where(dt > 0, dt, 1.0), 0.0)
    inside = (tau >= knots_s[0]) & (tau < knots_s[-1])
    return angle, np.where(inside, slope, 0.0)


@dataclass(frozen=True)
class Actuation:
    """Actuation profile parameters (the paper's values by default).

    Attributes
    ----------
    theta_w_deg, theta_l_deg : float
        Wing opening angle and leg amplitude, degrees (>= 0).
    wing_period_s : float
        Tw, the nominal time between wing openings, s.
    wing_open_deg_s, wing_close_deg_s : float
        Wing opening and closing speeds, deg/s.
    wing_close_start_s : float
        Time from the start of an opening to the start of the closing, s.
    leg_period_s : float
        Tl, leg oscillation period, s.
    leg_cross_s : float
        Time the leg takes to cross from -theta_l to +theta_l, s.
    """

    theta_w_deg: float
    theta_l_deg: float
    wing_period_s: float = PAPER_WING_PERIOD_S
    wing_open_deg_s: float = 300.0
    wing_close_deg_s: float = 250.0
    wing_close_start_s: float = 1.05
    leg_period_s: float = PAPER_LEG_PERIOD_S
    leg_cross_s: float = 0.15
    measured: MeasuredActuation | None = None
    """Measured per-joint profiles (``profile = "measured"``); they replace the idealised timing above."""

    def __post_init__(self) -> None:
        if self.measured is not None:
            self.measured.check(self.theta_w_deg, self.theta_l_deg, self.leg_period_s)
        for name in ("theta_w_deg", "theta_l_deg"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise UsageError(f"{name} must be a finite angle >= 0 degrees; got {v!r}")
        for name in (
            "wing_period_s",
            "wing_open_deg_s",
            "wing_close_deg_s",
            "wing_close_start_s",
            "leg_period_s",
            "leg_cross_s",
        ):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise UsageError(f"{name} must be a finite number > 0; got {v!r}")
        if self.leg_cross_s > self.leg_period_s / 2:
            raise UsageError(
                f"leg_cross_s = {self.leg_cross_s:g} s must be at most half the leg period "
                f"({self.leg_period_s / 2:g} s)"
            )
        if self.wing_closed_s > self.wing_period_s:
            raise UsageError(
                f"the wing cycle (open, hold, close) lasts {self.wing_closed_s:g} s, longer than "
                f"wing_period_s = {self.wing_period_s:g} s; open or close faster"
            )

    @property
    def wing_open_s(self) -> float:
        if self.measured is not None:
            return float(self.measured.wing_knots(self.theta_w_deg)[0][:, 4].max())
        """Time to open fully, s."""
        return self.theta_w_deg / self.wing_open_deg_s

    @property
    def wing_peak_deg(self) -> float:
        """Wing angle when closing starts (theta_w unless closing starts before the wings are open), deg."""
        return min(self.theta_w_deg, self.wing_open_deg_s * self.wing_close_start_s)

    @property
    def wing_closed_s(self) -> float:
        """Time from the start of an opening until the wings are closed again, s."""
        if self.measured is not None:
            return float(self.measured.wing_knots(self.theta_w_deg)[0][:, -1].max())
        return self.wing_close_start_s + self.wing_peak_deg / self.wing_close_deg_s

    @property
    def wing_hold_s(self) -> float:
        """Nominal closed hold between attempts, s."""
        return self.wing_period_s - self.wing_closed_s


def attempt_starts_s(
    act: Actuation, *, phase: float, cv: float, rng: np.random.Generator, duration_s: float
) -> NDArray[np.float64]:
    """Opening times of every attempt that starts before ``duration_s``.

    One normal deviate is drawn per closed hold, in order, so a longer duration extends the same sequence.

    Parameters
    ----------
    act : Actuation
    phase : float
        phi_1 in [0, 1): the first opening is at ``phase * act.leg_period_s``.
    cv : float
        Cv = sigma / Tl (>= 0).
    rng : numpy.random.Generator
    duration_s : float
        Trial length, s.

    Returns
    -------
    starts_s : ndarray of shape (K,)

    Examples
    --------
    >>> act = Actuation(74.0, 30.0)
    >>> attempt_starts_s(act, phase=0.25, cv=0.0, rng=np.random.default_rng(0), duration_s=6.0).tolist()
    [0.2, 2.2, 4.2]
    """
    sigma_s = cv * act.leg_period_s
    starts = [phase * act.leg_period_s]
    while True:
        delta = float(rng.normal(0.0, sigma_s)) if sigma_s > 0 else 0.0
        nxt = starts[-1] + act.wing_closed_s + max(0.0, act.wing_hold_s + delta)
        if nxt >= duration_s:
            break
        starts.append(nxt)
    return np.asarray([s for s in starts if s < duration_s], dtype=np.float64)


def attempt_phases(starts_s: ArrayLike, act: Actuation) -> NDArray[np.float64]:
    """Phase of each attempt, ``(t_k mod Tl) / Tl`` in [0, 1).

    Examples
    --------
    >>> attempt_phases([0.2, 2.2, 4.2], Actuation(74.0, 30.0)).round(12).tolist()
    [0.25, 0.75, 0.25]
    """
    t = np.asarray(starts_s, dtype=np.float64)
    return np.mod(t, act.leg_period_s) / act.leg_period_s


def wing_profile_deg(
    t_s: ArrayLike, starts_s: ArrayLike, act: Actuation
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Commanded wing angle and angular speed at times ``t_s``.

    Returns
    -------
    angle_deg, speed_deg_s : ndarray, shape of ``t_s``

    Examples
    --------
    >>> act = Actuation(75.0, 30.0)
    >>> a, w = wing_profile_deg([0.0, 0.1, 0.25, 1.0, 1.15, 1.35, 1.9], [0.0], act)
    >>> a.round(9).tolist()
    [0.0, 30.0, 75.0, 75.0, 50.0, 0.0, 0.0]
    >>> w.tolist()
    [300.0, 300.0, 0.0, 0.0, -250.0, 0.0, 0.0]
    """
    if act.measured is not None:
        a, w = wing_joint_profiles_deg(t_s, starts_s, act, n_wing=4)
        return a.mean(axis=-1), w.mean(axis=-1)
    t = np.asarray(t_s, dtype=np.float64)
    starts = np.asarray(starts_s, dtype=np.float64)
    if len(starts) == 0:
        return np.zeros_like(t), np.zeros_like(t)
    k = np.searchsorted(starts, t, side="right") - 1
    tau = np.where(k >= 0, t - starts[np.clip(k, 0, None)], -1.0)
    c = act.wing_close_start_s
    opening = (tau >= 0) & (tau < c)
    closing = tau >= c
    open_deg = np.minimum(act.theta_w_deg, act.wing_open_deg_s * np.maximum(tau, 0.0))
    close_deg = np.maximum(0.0, act.wing_peak_deg - act.wing_close_deg_s * (tau - c))
    angle = np.where(opening, open_deg, np.where(closing, close_deg, 0.0))
    speed = np.where(opening & (tau * act.wing_open_deg_s < act.theta_w_deg), act.wing_open_deg_s, 0.0)
    speed = np.where(closing & (close_deg > 0.0), -act.wing_close_deg_s, speed)
    return angle, speed


def leg_profile_deg(t_s: ArrayLike, act: Actuation) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Commanded leg angle and angular speed at times ``t_s`` (see the module docstring).

    Returns
    -------
    angle_deg, speed_deg_s : ndarray, shape of ``t_s``

    Examples
    --------
    >>> act = Actuation(75.0, 30.0)
    >>> a, w = leg_profile_deg([0.0, 0.0375, 0.2, 0.4, 0.6, 0.8], act)
    >>> a.round(9).tolist()
    [0.0, 15.0, 30.0, 0.0, -30.0, 0.0]
    >>> w.round(9).tolist()
    [400.0, 400.0, 0.0, -400.0, 0.0, 400.0]
    """
    t = np.asarray(t_s, dtype=np.float64)
    if act.measured is not None:
        ks, kd = act.measured.leg_knots(act.theta_l_deg)
        a, w = _pwl_and_slope(np.mod(t, act.leg_period_s), ks, kd)
        return a + 0.0, w
    period, half_cross = act.leg_period_s, act.leg_cross_s / 2
    tau = np.mod(t, period)
    first = tau < period / 2
    dist = np.where(first, np.minimum(tau, period / 2 - tau), np.minimum(tau - period / 2, period - tau))
    sign = np.where(first, 1.0, -1.0)
    angle = sign * act.theta_l_deg * np.minimum(dist / half_cross, 1.0) + 0.0  # no -0.0
    rate = act.theta_l_deg / half_cross
    # moving when within half a crossing of a midline passage: +rate around tau = 0 (and Tl), -rate around Tl/2
    near_zero = (tau < half_cross) | (tau >= period - half_cross)
    near_half = np.abs(tau - period / 2) < half_cross
    speed = np.where(near_zero, rate, np.where(near_half, -rate, 0.0))
    return angle, speed


def wing_joint_profiles_deg(
    t_s: ArrayLike, starts_s: ArrayLike, act: Actuation, *, n_wing: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Commanded angle and speed of each wing joint, shape ``t_s.shape + (n_wing,)``.

    The idealised profile drives every wing joint alike (:func:`wing_profile_deg`); the measured one drives
    each of the four joints (LP, RP, LR, RR: the joint map's wing joints in order) by its own servo's profile,
    restarted at every attempt and at its closed angle before the first.

    Raises
    ------
    UsageError
        If the profile is measured and ``n_wing`` is not 4.
    """
    if act.measured is None:
        a, w = wing_profile_deg(t_s, starts_s, act)
        return np.repeat(a[..., None], n_wing, -1), np.repeat(w[..., None], n_wing, -1)
    if n_wing != 4:
        raise UsageError(
            f"the measured profile drives 4 wing joints (left pitch, right pitch, left roll, right roll); "
            f"this robot's joint map has {n_wing}: use an idealised model set"
        )
    t = np.asarray(t_s, dtype=np.float64)
    starts = np.asarray(starts_s, dtype=np.float64)
    ks, kd = act.measured.wing_knots(act.theta_w_deg)
    padded = np.concatenate([starts, [np.inf]])  # no attempt yet: closed
    k = np.searchsorted(starts, t, side="right") - 1
    tau = np.where(k >= 0, t - padded[np.clip(k, 0, None)], ks[:, -1].max() + 1.0)
    out = [_pwl_and_slope(tau, ks[j], kd[j]) for j in range(4)]
    return np.stack([o[0] for o in out], -1), np.stack([o[1] for o in out], -1)
