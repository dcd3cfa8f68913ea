"""The first wing opening, recorded and simulated: where the body holds, and how it gets there (issue #15).

Every quantity is taken from one pitch-roll time series and the start of a wing opening (the first rise of the
wing command), so the physical robot's recordings and the simulation's traces are measured by the same code. The
rest, hold, overshoot, rise and pitch wobble read the nose's pitch (:func:`landscape.analysis.physical.sagittal_pitch_deg`),
which goes on past 90 deg where the ZYX pitch folds back: at the 90 deg command the robot's opening carries its
nose past vertical.

- *rest*: the median pitch in the ``REST_WINDOW_S`` before the opening;
- *hold*: the median pitch ``HOLD_WINDOW_S`` (0.5-0.95 s) after it, while the wings are held open;
- *overshoot*: the largest pitch in ``TRANSIENT_WINDOW_S`` (0.2-0.6 s) minus the hold: how far the body is
  thrown past where it comes to rest;
- *rise*: the time from the opening's start until the pitch first passes halfway from the rest to the hold;
- *tilt*: the signed lateral tilt ``asin(u_y) = asin(cos p sin r)`` of largest magnitude in
  ``TRANSIENT_WINDOW_S``, degrees (``u``: world-up in the body frame, ``geometry/frames.py``). Unlike the Euler
  roll it stays a tilt near pitch 90 deg, where the roll angle is ill-defined; positive towards positive roll;
- *wobble*: the standard deviation of the pitch and of the tilt in the hold window;
- *tilt at closing*: the median signed tilt in ``CLOSING_WINDOW_S`` (0.95-1.05 s), just before the wings start
  closing (the measured profiles start closing 1.04-1.06 s after the opening starts): how far the hold has
  rocked the body sideways when the wings take their support away;
- *rolled*: the first time after the opening's start at which the lateral tilt reaches ``ROLLED_TILT_DEG``
  (45 deg), within ``SIM_OPENING_S``: past the roll-wise saddle (the lab URDF's lies at a tilt of 29, 17 and
  10 deg at the measured plateaus 59.1, 73.6 and 82.1 deg), the body is rolling over. Not world-up's sign: at the
  90 deg command the held body stands near pitch 90 deg, where that sign turns on a few degrees of pitch;
- *lean*: with the leg swinging, the median tilt of each window in which the leg has settled on one side
  (:func:`hold_leans_deg`: from ``LEAN_SETTLE_S`` after the leg reaches a side until it leaves it, within
  ``LEAN_WINDOW_S``, 0.4-1.0 s after the opening starts, and ``LEAN_DEPART_MARGIN_S`` before the body leaves the
  hold), one value for that side; the robot's leg reaches its side ``LEG_LAG_S`` after its command;
- *departure*: when an opening that rolls over last left the level (:func:`departure_s`: the tilt rising
  through ``LEVEL_TILT_DEG`` on the side it rolls to, before passing ``ROLLED_TILT_DEG``).

The recorded pitch is the IMU's, whose mounting on the body is not known; the simulated pitch is the body
frame's. :func:`hold_pitch_frames` therefore compares the recorded hold with the model's in two ways: relative
to the rest before the first opening (issue #15's table, which assumes the model rests where the robot rests
with its wings closed), and in the IMU's own frame with its mounting offset fitted as one constant (each
command's residual also with the offset fitted on the other commands only). :func:`mounting_from_rests` measures
that mounting without the hold, from the two rests every righted trial records (on its back and upright): 2.6 deg
on the lab's data, so the 11.5 deg the hold fit asks of the lab's CAD is a real pose, not the IMU.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from landscape.analysis.physical import (
    HOLD_WINDOW_S,
    REST_WINDOW_S,
    PhysicalDataError,
    Recording,
    _median,
    measured_plateaus_deg,
    read_recording,
    sagittal_pitch_deg,
    trial_files,
    trial_outcome,
    upright_stretches,
)

TRANSIENT_WINDOW_S = (0.2, 0.6)
"""Window after an opening's start in which the overshoot and the tilt are read, s."""
SWING_WINDOW_S = 0.35
"""Window before an opening in which the body's fastest roll times the leg's last swing, s."""
LEG_HELD_S = (0.45, 0.25)
"""Window before the first opening while the lab's protocol holds the leg at its first command, s."""
LEG_STILL_S = (1.1, 0.8)
"""Window before the first opening before the lab's protocol starts the leg, s."""
ROLLED_TILT_DEG = 45.0
"""Lateral tilt beyond which the body counts as rolling over, degrees."""
CLOSING_WINDOW_S = (0.95, 1.05)
"""Window after an opening's start, just before the wings start closing, in which the tilt at closing is read, s."""
PROTOCOL_PHASE = 0.17
"""The first attempt's leg phase under the lab's protocol, one number (``landscape physical kinematics``: the leg's
midline crossing about 0.13 s before the first opening, phi_1 about 0.16, IQR 0.14-0.17); per leg amplitude
:func:`protocol_phases` gives 0.195, 0.166 and 0.129 at 15, 30 and 45 deg."""
OPENING_SD_FLOOR_DEG = 1.0
"""Smallest spread of a recorded measure in :func:`opening_log_likelihood`, degrees: five trials can agree more
closely than the model can be asked to."""
OPENING_Z_CAP = 4.0
"""Largest deviation, in standard deviations, that one measure of one opening counts in
:func:`opening_log_likelihood`."""
SIM_OPENING_S = 1.4
"""Time after the opening's start that is simulated and searched for the body rolling over: the transient, the
hold and the wings' closing (the robot's first-attempt roll-overs at 60 deg pass a tilt of 45 deg about 1.1 s after
the opening starts) lie inside it, s."""


@dataclass(frozen=True)
class OpeningResponse:
    """How the body moves in one wing opening (definitions in the module docstring).

    Attributes
    ----------
    rest_pitch_deg, hold_pitch_deg : float
        Median pitch before the opening and while the wings are held open, degrees (the series' own frame).
    overshoot_deg : float
        Largest pitch in the transient window minus the hold, degrees.
    rise_s : float
        Time to pass halfway from the rest to the hold, s.
    tilt_deg : float
        Signed lateral tilt of largest magnitude in the transient window, degrees.
    wobble_pitch_deg, wobble_tilt_deg : float
        Standard deviation of the pitch and of the lateral tilt in the hold window, degrees.
    closing_tilt_deg : float
        Median signed lateral tilt in ``CLOSING_WINDOW_S``, degrees.
    rolled_s : float
        First time after the start at which the lateral tilt reaches ``ROLLED_TILT_DEG``, within
        ``SIM_OPENING_S``, s; nan if it does not.
    """

    rest_pitch_deg: float
    hold_pitch_deg: float
    overshoot_deg: float
    rise_s: float
    tilt_deg: float
    wobble_pitch_deg: float = math.nan
    wobble_tilt_deg: float = math.nan
    closing_tilt_deg: float = math.nan
    rolled_s: float = math.nan


def lateral_tilt_deg(pitch_deg: ArrayLike, roll_deg: ArrayLike) -> NDArray[np.float64]:
    """Signed lateral tilt ``asin(cos p sin r)`` of world-up in the body frame, degrees.

    Examples
    --------
    >>> lateral_tilt_deg([0.0, 60.0, 89.0], [30.0, 30.0, 30.0]).round(2)
    array([30.  , 14.48,  0.5 ])
    """
    p = np.deg2rad(np.asarray(pitch_deg, dtype=np.float64))
    r = np.deg2rad(np.asarray(roll_deg, dtype=np.float64))
    return np.rad2deg(np.arcsin(np.clip(np.cos(p) * np.sin(r), -1.0, 1.0)))


def opening_response(
    t_s: ArrayLike, pitch_deg: ArrayLike, roll_deg: ArrayLike, start_s: float
) -> OpeningResponse:
    """Rest, hold, overshoot, rise, tilt, wobble, tilt at closing and the time rolled over of the opening that starts
    at ``start_s`` (module docstring); nan where a window holds no sample.

    Examples
    --------
    >>> t = np.linspace(-0.5, 1.0, 151)
    >>> pitch = np.where(t < 0, 0.0, 60.0 * np.clip(t / 0.3, 0.0, 1.0)) + 10.0 * ((t > 0.3) & (t < 0.4))
    >>> r = opening_response(t, pitch, np.zeros_like(t), 0.0)
    >>> round(r.hold_pitch_deg, 9), round(r.overshoot_deg, 9), round(r.rise_s, 2), r.tilt_deg, r.wobble_pitch_deg
    (60.0, 10.0, 0.15, 0.0, 0.0)
    >>> r.closing_tilt_deg, r.rolled_s
    (0.0, nan)
    """
    t = np.asarray(t_s, dtype=np.float64) - float(start_s)
    r = np.asarray(roll_deg, dtype=np.float64)
    zyx_pitch = np.asarray(pitch_deg, dtype=np.float64)
    # the nose's pitch, on past vertical (the ZYX pitch folds back at 90), unwrapped so that a body rolling on to
    # upright (where it passes 180) does not jump by a turn
    p = np.rad2deg(np.unwrap(np.deg2rad(sagittal_pitch_deg(zyx_pitch, r)))) if len(zyx_pitch) else zyx_pitch
    rest = _median_between(t, p, -REST_WINDOW_S, -1e-12)
    hold = _median_between(t, p, *HOLD_WINDOW_S)
    win = (t >= TRANSIENT_WINDOW_S[0]) & (t <= TRANSIENT_WINDOW_S[1])
    overshoot = float(p[win].max()) - hold if win.any() else math.nan
    tilt = math.nan
    if win.any():
        tl = lateral_tilt_deg(zyx_pitch[win], r[win])
        tilt = float(tl[np.argmax(np.abs(tl))])
    held = (t >= HOLD_WINDOW_S[0]) & (t <= HOLD_WINDOW_S[1])
    wobble_p = wobble_t = math.nan
    if held.sum() >= 2:
        wobble_p = float(np.std(p[held]))
        wobble_t = float(np.std(lateral_tilt_deg(zyx_pitch[held], r[held])))
    tilt_all = lateral_tilt_deg(zyx_pitch, r)
    closing = _median_between(t, tilt_all, *CLOSING_WINDOW_S)
    over = (t >= 0) & (t <= SIM_OPENING_S) & (np.abs(tilt_all) >= ROLLED_TILT_DEG)
    rolled = float(t[np.flatnonzero(over)[0]]) if over.any() else math.nan
    rise = math.nan
    if np.isfinite(rest) and np.isfinite(hold):
        half = rest + 0.5 * (hold - rest)
        after = (t >= 0) & ((p >= half) if hold >= rest else (p <= half))
        if after.any():
            rise = float(t[np.flatnonzero(after)[0]])
    return OpeningResponse(rest, hold, overshoot, rise, tilt, wobble_p, wobble_t, closing, rolled)


def opening_log_likelihood(recorded: Sequence[OpeningResponse], simulated: OpeningResponse) -> float:
    """Log-likelihood of one simulated opening under one cell's recorded openings: how the body moves, where
    the outcome likelihood only asks whether it rights.

    Three continuous measures, each a normal density with the recorded trials' mean and standard deviation
    (at least ``OPENING_SD_FLOOR_DEG``): the hold's pitch wobble, the hold's tilt wobble and the magnitude of the
    tilt at closing (the side is the validation's to judge: one simulated opening at one phase goes to one
    side). Each measure's squared deviation counts at most ``OPENING_Z_CAP`` standard deviations, so that one
    opening far off in one cell cannot outweigh every other cell and the outcomes. One binary measure: whether
    the body rolled past ``ROLLED_TILT_DEG`` within ``SIM_OPENING_S``, with the recorded fraction (Laplace's
    rule, ``(k + 1) / (n + 2)``). A measure the simulation leaves nan (a body that rolled over and righted
    before the window) counts as ``OPENING_Z_CAP`` off; a measure nan in every recorded trial is skipped.

    Examples
    --------
    >>> still = OpeningResponse(0.0, 60.0, 1.0, 0.2, 1.0, 0.5, 0.3, 0.0)
    >>> rocking = OpeningResponse(0.0, 60.0, 5.0, 0.2, 8.0, 2.5, 6.8, 21.0, 1.1)
    >>> opening_log_likelihood([still] * 5, still) > opening_log_likelihood([still] * 5, rocking)
    True
    """
    ll = 0.0
    measures = (
        lambda r: r.wobble_pitch_deg,
        lambda r: r.wobble_tilt_deg,
        lambda r: abs(r.closing_tilt_deg),
    )
    for get in measures:
        values = np.array([get(r) for r in recorded], dtype=np.float64)
        values = values[np.isfinite(values)]
        if not len(values):
            continue
        mu, sd = float(values.mean()), max(float(values.std()), OPENING_SD_FLOOR_DEG)
        x = get(simulated)
        z2 = min(((x - mu) / sd) ** 2, OPENING_Z_CAP**2) if math.isfinite(x) else OPENING_Z_CAP**2
        ll += -0.5 * z2 - math.log(sd * math.sqrt(2 * math.pi))
    k = sum(math.isfinite(r.rolled_s) for r in recorded)
    p = (k + 1) / (len(recorded) + 2)
    ll += math.log(p if math.isfinite(simulated.rolled_s) else 1 - p)
    return float(ll)


@dataclass(frozen=True)
class RecordedOpening:
    """The first opening of one recorded trial.

    Attributes
    ----------
    leg_lead_s : float
        How long before the opening the leg command last turned positive, s (nan with the leg still; the servo
        log's 10 Hz resolution). The lab's protocol starts the leg and the wings at fixed times, so this lead,
        and with it the phase of the first attempt, is the same in every trial: the first attempt's phase is
        not random on the robot.
    gyro_deviation_deg : float
        :func:`gyro_tilt_deviation_deg` of the opening: how far the recorded tilt strays from the gyro's.
    leg_hold_roll_deg : float
        How far the body's roll moved while the leg was held at its first command (negative) before the opening:
        the median roll ``LEG_HELD_S`` before the opening minus the median ``LEG_STILL_S`` before it, before the
        leg started, degrees; nan with the leg still. A body resting on a curved back rolls with its CoM; one
        resting on a flat face does not.
    leg_swing_s : float
        When the body rolled fastest in the ``SWING_WINDOW_S`` before the opening, s before it (positive): the
        body's reaction to the leg's last swing, which times the swing itself to the IMU's 50 Hz rather than the
        servo log's 10 Hz; nan with the leg still.
    """

    name: str
    theta_w_cmd_deg: float
    theta_l_deg: float
    trial: int
    response: OpeningResponse
    leg_lead_s: float = math.nan
    leg_swing_s: float = math.nan
    leg_hold_roll_deg: float = math.nan
    gyro_deviation_deg: float = math.nan


def recorded_first_openings(data_dir: str | Path) -> list[RecordedOpening]:
    """:func:`opening_response` of every recorded trial's first opening, in file order. Computed once per version
    of the files (``kinematics``, the report and a calibration ask for them several times; an edited file is read
    again).

    Raises
    ------
    PhysicalDataError
        If the directory or a file is not in the lab's format.
    """
    files = trial_files(data_dir)
    return list(_first_openings(tuple((str(f.resolve()), f.stat().st_mtime_ns) for f in files)))


@lru_cache(maxsize=4)
def _first_openings(files: tuple[tuple[str, int], ...]) -> tuple[RecordedOpening, ...]:
    """:func:`recorded_first_openings` of these files (path, modification time)."""
    out = []
    for f, _ in files:
        rec = read_recording(f)
        start = float(rec.openings_s[0])
        resp = opening_response(rec.t_s, rec.pitch_deg, rec.roll_deg, start)
        ups = rec.leg_up_s[rec.leg_up_s <= start + 1e-9]
        lead = start - float(ups[-1]) if len(ups) else math.nan
        swing = held = math.nan
        if rec.theta_l_deg > 0:
            t = rec.t_s - start
            swing = _fastest_roll_before_s(t, rec.roll_deg)
            held = _median_between(t, rec.roll_deg, -LEG_HELD_S[0], -LEG_HELD_S[1]) - _median_between(
                t, rec.roll_deg, -LEG_STILL_S[0], -LEG_STILL_S[1]
            )
        out.append(
            RecordedOpening(
                rec.name,
                rec.theta_w_cmd_deg,
                rec.theta_l_deg,
                rec.trial,
                resp,
                lead,
                swing,
                held,
                gyro_tilt_deviation_deg(rec, start),
            )
        )
    return tuple(out)


def gyro_tilt_deviation_deg(
    rec: Recording, start_s: float, *, window_s: tuple[float, float] = (-REST_WINDOW_S, CLOSING_WINDOW_S[1])
) -> float:
    """Largest difference between the recorded lateral tilt and the tilt of the orientation the gyro alone
    gives, over ``window_s`` after ``start_s`` (degrees; nan without gyro samples there).

    The recorded orientation is the IMU's fusion, which leans on the accelerometer for gravity's direction; the
    leg's swing accelerates the body, and a fused tilt could follow that rather than the body. Integrating the
    IMU's own angular rates from the recorded orientation at the window's start gives the rotation the body
    made, free of that: a small deviation says the recorded rocking is the body's.

    Examples
    --------
    A body rolling at 1 rad/s about its x axis, recorded and measured alike:

    >>> from scipy.spatial.transform import Rotation
    >>> t = np.arange(-0.3, 1.06, 0.01)
    >>> q = Rotation.from_rotvec(np.outer(t + 0.3, [1.0, 0.0, 0.0])).as_quat()
    >>> rec = Recording("x", 60.0, 0.0, 1, t, np.zeros_like(t), np.degrees(t + 0.3), np.cos(t + 0.3),
    ...                 np.zeros(1), quat_xyzw=q, gyro_t_s=t, gyro_rad_s=np.tile([1.0, 0.0, 0.0], (len(t), 1)))
    >>> round(gyro_tilt_deviation_deg(rec, 0.0), 6)
    0.0
    """
    from scipy.spatial.transform import Rotation

    lo, hi = start_s + window_s[0], start_s + window_s[1]
    gt, w = rec.gyro_t_s, rec.gyro_rad_s
    sel = np.flatnonzero((gt >= lo) & (gt <= hi))
    qsel = np.flatnonzero((rec.t_s >= lo) & (rec.t_s <= hi))
    if len(sel) < 2 or len(qsel) < 2:
        return math.nan
    rot = Rotation.from_quat(rec.quat_xyzw[qsel[0]])
    t_prev = float(rec.t_s[qsel[0]])
    gyro_t, gyro_up = [t_prev], [rot.inv().apply([0.0, 0.0, 1.0])]
    for k in sel:  # each rate held from the previous sample's time to its own
        rot = rot * Rotation.from_rotvec(w[k] * (float(gt[k]) - t_prev))
        t_prev = float(gt[k])
        gyro_t.append(t_prev)
        gyro_up.append(rot.inv().apply([0.0, 0.0, 1.0]))
    gyro_tilt = np.degrees(np.arcsin(np.clip(np.array(gyro_up)[:, 1], -1.0, 1.0)))
    rec_tilt = lateral_tilt_deg(rec.pitch_deg[qsel], rec.roll_deg[qsel])
    return float(np.abs(rec_tilt - np.interp(rec.t_s[qsel], gyro_t, gyro_tilt)).max())


def _median_between(t, values, lo: float, hi: float) -> float:
    """Median of ``values`` at the times ``t`` in [lo, hi] (times from the opening's start, s); nan if none."""
    sel = (t >= lo) & (t <= hi)
    return float(np.median(np.asarray(values, dtype=np.float64)[sel])) if sel.any() else math.nan


def _fastest_roll_before_s(t, roll_deg) -> float:
    """How long before the opening (``t``: times from its start, s) the roll changed fastest within
    ``SWING_WINDOW_S`` (midpoint of the steepest sample pair), s; nan with fewer than three samples there.

    Examples
    --------
    >>> t = np.arange(-0.5, 0.0, 0.02)
    >>> round(_fastest_roll_before_s(t, np.where(t < -0.13, 0.0, 1.0)), 3)
    0.13
    """
    sel = (t >= -SWING_WINDOW_S) & (t < 0)
    if sel.sum() < 3:
        return math.nan
    ts, rs = t[sel], np.asarray(roll_deg, dtype=np.float64)[sel]
    i = int(np.argmax(np.abs(np.diff(rs) / np.diff(ts))))
    return float(-(ts[i] + ts[i + 1]) / 2)


def protocol_phases(data_dir: str | Path) -> dict[tuple[float, float], float]:
    """The first attempt's leg phase under the lab's protocol, per recorded cell with the leg moving:
    ``(lead - lag) / period``, where ``lead`` is the cell's median time from the leg command's last rise to the
    first opening (servo log) and ``lag`` how long the measured leg takes from its command to the midline at
    that amplitude (:func:`landscape.analysis.measured.leg_crossing_lag_s`, ``vib_pulse_v2.mat``): the leg's
    upward crossing precedes the opening by ``lead - lag``, as the simulation's phase counts (rounded to 1e-6,
    so that a store keyed by phase resumes).

    Raises
    ------
    PhysicalDataError
        If no recorded first opening has the leg moving.
    """
    from landscape.analysis.measured import LEG_PERIOD_S, leg_crossing_lag_s

    lag = leg_crossing_lag_s(Path(data_dir) / "vib_pulse_v2.mat")
    leads: dict[tuple[float, float], list[float]] = defaultdict(list)
    for o in recorded_first_openings(data_dir):
        if o.theta_l_deg > 0 and np.isfinite(o.leg_lead_s):
            leads[(o.theta_w_cmd_deg, o.theta_l_deg)].append(o.leg_lead_s)
    if not leads:
        raise PhysicalDataError(f"no first opening with the leg moving in '{data_dir}'")
    return {
        cell: round(float(np.mod((np.median(v) - lag[cell[1]]) / LEG_PERIOD_S, 1.0)), 6)
        for cell, v in sorted(leads.items())
    }


def simulated_opening(
    theta_w_deg: float,
    theta_l_deg: float,
    *,
    phase: float,
    seed: int,
    robot: str | Path | None = None,
    model_set="paper",
    cv: float = 0.0,
) -> OpeningResponse:
    """:func:`opening_response` of a simulated first opening (one attempt, ``SIM_OPENING_S`` after it starts;
    ``theta_w_deg`` is what the set simulates: the command for a measured profile, the wing angle otherwise)."""
    tr, starts = simulated_openings(
        theta_w_deg, theta_l_deg, model_set=model_set, robot=robot, seed=seed, phase=phase, cv=cv, attempts=1
    )
    return opening_response(tr.t_s, tr.pitch_deg, tr.roll_deg, starts[0])


def simulated_openings(theta_w_deg, theta_l_deg, *, model_set, robot, seed, phase, cv=0.0, attempts=1):
    """A traced simulated trial of ``attempts`` openings, the first at leg phase ``phase``, that ends
    ``SIM_OPENING_S`` after the last one starts (or once the body has righted): ``(trace, attempt starts)``."""
    from sim.model_set import load_model_set
    from sim.trial import run_trial

    ms = load_model_set(model_set)
    act = ms.actuation(theta_w_deg, theta_l_deg)
    last = phase * act.leg_period_s + (attempts - 1) * act.wing_period_s  # the openings: sim.actuation
    res = run_trial(
        theta_w_deg, theta_l_deg, phase=phase, cv=cv, rng=seed, robot=robot, model_set=ms, trace=True,
        attempts=attempts, duration_s=last + SIM_OPENING_S,
    )  # fmt: skip
    return res.trace, res.attempt_starts_s


# ------------------------------------------------------------------------------------------------- hold lean
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
"""How long the lab's leg command stays on one side, s (period 0.8 s; in the servo logs the command falls
0.396-0.400 s after it rises)."""


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
    (:func:`landscape.analysis.physical.upright_stretches` of ``u_z = cos p cos r``) that has not ended
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
    :func:`landscape.analysis.physical.recording_attempts`: the opening in which it rights is the last) counts;
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
        _median(leans.plus_deg),
        len(leans.plus_deg),
        _median(leans.minus_deg),
        len(leans.minus_deg),
        _median(rolled),
        len(rolled),
        len(dep),
    )


@dataclass(frozen=True)
class HoldFrame:
    """The hold pitch of first openings with the leg still, per wing command, in two frames.

    Attributes
    ----------
    theta_w_cmd_deg : float
    n : int
        First openings with the leg still.
    recorded_deg, recorded_sd_deg : float
        Median and standard deviation of the recorded hold pitch in the IMU frame, degrees.
    relative_deg, relative_sd_deg : float
        The same minus each trial's rest before the opening (issue #15's reference), degrees.
    rest_sd_deg : float
        Standard deviation of that rest between trials, degrees.
    model_deg, model_rest_deg : float
        The model's metastable pitch at the command and its rest with the wings closed, body frame, degrees.
    offset_deg : float
        The IMU's mounting (recorded minus model), fitted as one constant over every command, degrees.
    residual_deg, residual_held_out_deg : float
        Recorded minus offset minus model: with the offset fitted on every command, and on the other commands
        only, degrees.
    """

    theta_w_cmd_deg: float
    n: int
    recorded_deg: float
    recorded_sd_deg: float
    relative_deg: float
    relative_sd_deg: float
    rest_sd_deg: float
    model_deg: float
    model_rest_deg: float
    offset_deg: float
    residual_deg: float
    residual_held_out_deg: float


def hold_pitch_frames(
    data_dir: str | Path, model_hold_deg: dict[float, float], model_rest_deg: float
) -> list[HoldFrame]:
    """Compare the recorded hold pitch of first openings (leg still) with the model's, per wing command.

    Parameters
    ----------
    data_dir : path
        The lab's physical_robot folder.
    model_hold_deg : dict of float to float
        The model's metastable pitch per wing command, body frame, degrees (e.g. every wing servo at its
        measured plateau).
    model_rest_deg : float
        The model's rest with the wings closed, degrees.

    Raises
    ------
    PhysicalDataError
        If no trial with the leg still has a command of ``model_hold_deg``.
    """
    hold: dict[float, list[float]] = defaultdict(list)
    rest: dict[float, list[float]] = defaultdict(list)
    for o in recorded_first_openings(data_dir):
        r = o.response
        if o.theta_l_deg == 0.0 and o.theta_w_cmd_deg in model_hold_deg and np.isfinite(r.hold_pitch_deg):
            hold[o.theta_w_cmd_deg].append(r.hold_pitch_deg)
            rest[o.theta_w_cmd_deg].append(r.rest_pitch_deg)
    cmds = sorted(hold)
    if not cmds:
        raise PhysicalDataError(
            f"no first opening with the leg still at wing commands {sorted(model_hold_deg)} deg in '{data_dir}'"
        )
    recorded = {c: float(np.median(hold[c])) for c in cmds}
    diff = {c: recorded[c] - model_hold_deg[c] for c in cmds}
    offset = float(np.mean(list(diff.values())))
    out = []
    for c in cmds:
        h, s = np.asarray(hold[c]), np.asarray(rest[c])
        others = [diff[k] for k in cmds if k != c]
        held_out = diff[c] - float(np.mean(others)) if others else math.nan
        out.append(
            HoldFrame(
                c, len(h), recorded[c], float(h.std()), float(np.median(h - s)), float((h - s).std()),
                float(s.std()), model_hold_deg[c], model_rest_deg, offset, diff[c] - offset, held_out,
            )
        )  # fmt: skip
    return out


def per_servo_hold_deg(robot, measured, commands_deg: Sequence[float]) -> dict[float, float]:
    """The model's metastable pitch with each wing servo at its own measured plateau
    (:meth:`sim.actuation.MeasuredActuation.wing_plateaus_deg`), degrees: the start of
    :func:`landscape.computation.compute` with those ``wing_joints_deg`` (a slow opening to the smallest
    plateau, then descent)."""
    from landscape.computation import posed, start_orientation

    out = {}
    for c in commands_deg:
        vals = dict(zip(robot.joint_map.wing, measured.wing_plateaus_deg(c).tolist(), strict=True))
        pose = posed(robot, c, 0.0, vals)
        out[float(c)] = float(start_orientation(robot, pose, c, 0.0, wing_joints_deg=vals)[0])
    return out


def plateau_hold_deg(robot, data_dir: str | Path, commands_deg: Sequence[float]) -> dict[float, float]:
    """The model's metastable pitch with every wing joint at the measured plateau of each command, degrees."""
    from landscape.minima import metastable_orientation

    try:
        plateau = measured_plateaus_deg(data_dir)
    except PhysicalDataError:  # no per-attempt record: the command itself, as resting_pitch_table does
        plateau = {}
    return {float(c): float(metastable_orientation(robot, plateau.get(c, c), 0.0)[0]) for c in commands_deg}


def support_links(pose, pitch_deg: float, roll_deg: float, *, tol_m: float = 2e-4) -> list[str]:
    """The links of a posed robot (:class:`geometry.Pose`) whose hull vertices touch flat ground at this body
    orientation: within ``tol_m`` of the lowest hull point, in the pose's part order.

    Examples
    --------
    >>> from geometry.robots import load_robot
    >>> from landscape.minima import metastable_orientation
    >>> robot = load_robot(None)  # the built-in robot, held open at 74 deg: on its head and both wing edges
    >>> support_links(robot.pose(74.0, 0.0), *metastable_orientation(robot, 74.0, 0.0))
    ['head', 'wing2', 'wing1']
    """
    from geometry.frames import up_vector

    u = up_vector(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    low = float((pose.hull_points_m @ u).min())
    out = []
    for part in pose.parts:
        if not len(part.hull_link_m):
            continue
        T = pose.link_transforms[part.link]
        heights = (part.hull_link_m @ T[:3, :3].T + T[:3, 3]) @ u
        if heights.min() - low <= tol_m:
            out.append(part.link)
    return out


UPRIGHT_SETTLE_S = 0.5
"""Time after a trial rights before its upright rest is read, s."""
UPRIGHT_UP_Z = -0.85
"""World-up's recorded body-z component below which a sample counts as resting upright."""
MIN_UPRIGHT_SAMPLES = 10
"""Fewest upright samples (0.2 s at 50 Hz) a righted trial needs to give its upright rest."""


@dataclass(frozen=True)
class RestMounting:
    """The IMU's mounting pitch, measured from the robot's two rests (:func:`mounting_from_rests`).

    Attributes
    ----------
    n : int
        Righted trials with both rests.
    recorded_back_deg, recorded_upright_deg : float
        Medians of the recorded (IMU) pitch on the robot's back before its first opening and upright after it
        rights, degrees.
    model_back_deg, model_upright_deg : float
        The model's pitch at the same two rests (wings closed, leg centred), degrees.
    mount_deg, mount_q25_deg, mount_q75_deg : float
        Median and quartiles of the per-trial mountings, degrees: the IMU's x axis pitched this far (nose up on
        the robot's back) against the body's.
    """

    n: int
    recorded_back_deg: float
    recorded_upright_deg: float
    model_back_deg: float
    model_upright_deg: float
    mount_deg: float
    mount_q25_deg: float
    mount_q75_deg: float


def nose_pitch_deg(pitch_deg: float, roll_deg: float) -> float:
    """The pitch of the body's x axis above the horizontal, degrees: the ZYX pitch of whichever of the two
    (pitch, roll) pairs that describe one orientation has ``|pitch| <= 90`` (``asin(-u_x)``).

    Examples
    --------
    >>> round(nose_pitch_deg(-174.0, -180.0), 9), round(nose_pitch_deg(0.5, -178.0), 9)
    (-6.0, 0.5)
    """
    from geometry.frames import up_vector

    u = up_vector(math.radians(pitch_deg), math.radians(roll_deg))
    return math.degrees(math.asin(max(-1.0, min(1.0, -float(u[0])))))


def upright_rest_deg(robot) -> tuple[float, float]:
    """The model's lowest upright rest (world-up's body-z component negative), wings closed and leg centred:
    (pitch, roll) in degrees, the lowest cell of a 1-degree landscape refined by descent."""
    from landscape.energy import energy_landscape
    from landscape.minima import local_descent

    pose = robot.pose(0.0, 0.0) if robot.has_joints else robot.pose()
    ls = energy_landscape(pose, step_deg=1.0)
    a = np.deg2rad(ls.angles_deg)
    upright = np.cos(a)[:, None] * np.cos(a)[None, :] < 0  # u_z = cos p cos r
    i, j = np.unravel_index(np.argmin(np.where(upright, ls.energy_j, np.inf)), ls.energy_j.shape)
    return local_descent(pose, float(ls.angles_deg[i]), float(ls.angles_deg[j]))


def rest_mounting_deg(back_deg, upright_deg, model_back_deg: float, model_upright_deg: float):
    """The IMU's mounting pitch from its readings on the robot's back and upright (scalars or arrays), given the
    model's pitch at the same two rests, degrees: the IMU reads the body's pitch plus the mounting on its back
    and minus it upright (rolled half a turn about x, its pitch axis is reversed).

    Examples
    --------
    >>> float(rest_mounting_deg(1.0, -5.5, -6.0, 1.5))
    7.0
    """
    return ((np.asarray(back_deg) - upright_deg) - (model_back_deg - model_upright_deg)) / 2.0


def mounting_from_rests(
    data_dir: str | Path, robot, *, settle_s: float = UPRIGHT_SETTLE_S, up_z_below: float = UPRIGHT_UP_Z
) -> RestMounting:
    """The IMU's mounting pitch from the two rests every righted trial records: on its back before the first
    opening (the median of ``REST_WINDOW_S``) and upright after it rights (from ``settle_s`` after, the samples
    with world-up's body-z component below ``up_z_below``).

    An IMU pitched ``d`` against the body reads the body's pitch plus ``d`` on its back and minus ``d`` upright
    (rolled half a turn about x, its pitch axis is reversed), so each trial gives
    ``d = ((back - upright) - (model's back - model's upright)) / 2`` without assuming either rest alone.
    Both rests have the wings closed; the model's are the lowest rests of its hull (:func:`upright_rest_deg`,
    :func:`landscape.minima.metastable_orientation` at 0).

    Raises
    ------
    PhysicalDataError
        If no righted trial has both rests.
    """
    from landscape.minima import metastable_orientation

    model_back = nose_pitch_deg(*metastable_orientation(robot, 0.0, 0.0))
    model_upright = nose_pitch_deg(*upright_rest_deg(robot))
    back, upright = [], []
    for f in trial_files(data_dir):
        rec = read_recording(f)
        out = trial_outcome(rec)
        if not out.success:
            continue
        before = (rec.t_s >= -REST_WINDOW_S) & (rec.t_s < 0.0)
        after = (rec.t_s > out.time_to_right_s + settle_s) & (rec.up_z < up_z_below)
        if before.any() and after.sum() >= MIN_UPRIGHT_SAMPLES:
            back.append(float(np.median(rec.pitch_deg[before])))
            upright.append(float(np.median(rec.pitch_deg[after])))
    if not back:
        raise PhysicalDataError(
            f"no righted trial in '{data_dir}' records both rests (on its back and upright)"
        )
    b, u = np.asarray(back), np.asarray(upright)
    d = rest_mounting_deg(b, u, model_back, model_upright)
    q25, q50, q75 = np.percentile(d, [25, 50, 75])
    return RestMounting(
        len(d),
        float(np.median(b)),
        float(np.median(u)),
        model_back,
        model_upright,
        float(q50),
        float(q25),
        float(q75),
    )
