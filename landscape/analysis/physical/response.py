"""The first wing opening, recorded and simulated: where the body holds, and how it gets there.

Every quantity is taken from one pitch-roll time series and the start of a wing opening (the first rise of the
wing command), so the physical robot's recordings and the simulation's traces are measured by the same code. The
rest, hold, overshoot, rise and pitch wobble read the nose's pitch
(:func:`landscape.analysis.physical.recording.sagittal_pitch_deg`), which goes on past 90 deg where the ZYX pitch
folds back: at the 90 deg command the robot's opening carries its nose past vertical.

- *rest*: the median pitch in the ``REST_WINDOW_S`` before the opening;
- *hold*: the median pitch ``HOLD_WINDOW_S`` after it, while the wings are held open;
- *overshoot*: the largest pitch in ``TRANSIENT_WINDOW_S`` minus the hold: how far the body is thrown past where
  it comes to rest;
- *rise*: the time from the opening's start until the pitch first passes halfway from the rest to the hold;
- *tilt*: the signed lateral tilt ``asin(u_y) = asin(cos p sin r)`` of largest magnitude in
  ``TRANSIENT_WINDOW_S``, degrees (``u``: world-up in the body frame, ``geometry/frames.py``). Unlike the Euler
  roll it stays a tilt near pitch 90 deg, where the roll angle is ill-defined; positive towards positive roll;
- *wobble*: the standard deviation of the pitch and of the tilt in the hold window;
- *tilt at closing*: the median signed tilt in ``CLOSING_WINDOW_S``, just before the wings start closing: how far
  the hold has rocked the body sideways when the wings take their support away;
- *rolled*: the first time after the opening's start at which the lateral tilt reaches ``ROLLED_TILT_DEG``,
  within ``SIM_OPENING_S``: past the roll-wise saddle, the body is rolling over. Not world-up's sign: at the 90 deg
  command the held body stands near pitch 90 deg, where that sign turns on a few degrees of pitch.
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

from landscape.analysis.physical.recording import (
    PhysicalDataError,
    Recording,
    read_recording,
    sagittal_pitch_deg,
    trial_files,
)
from landscape.analysis.physical.resting import HOLD_WINDOW_S, REST_WINDOW_S

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
"""The first attempt's leg phase under the lab's protocol, one number for every leg amplitude, as a fraction of the
leg period: the recordings' phase (``landscape physical kinematics`` shows it; :func:`protocol_phases` gives one
per leg amplitude)."""
OPENING_SD_FLOOR_DEG = 1.0
"""Smallest spread of a recorded measure in :func:`opening_log_likelihood`, degrees: five trials can agree more
closely than the model can be asked to."""
OPENING_Z_CAP = 4.0
"""Largest deviation, in standard deviations, that one measure of one opening counts in
:func:`opening_log_likelihood`."""
SIM_OPENING_S = 1.4
"""Time after the opening's start that is simulated and searched for the body rolling over: the transient, the
hold and the wings' closing lie inside it, s."""


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
    that amplitude (:func:`landscape.analysis.physical.measured.leg_crossing_lag_s`, ``vib_pulse_v2.mat``): the leg's
    upward crossing precedes the opening by ``lead - lag``, as the simulation's phase counts (rounded to 1e-6,
    so that a store keyed by phase resumes).

    Raises
    ------
    PhysicalDataError
        If no recorded first opening has the leg moving.
    """
    from landscape.analysis.physical.measured import LEG_PERIOD_S, LEG_PULSE_FILE, leg_crossing_lag_s

    lag = leg_crossing_lag_s(Path(data_dir) / LEG_PULSE_FILE)
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
    engine: str = "pybullet",
) -> OpeningResponse:
    """:func:`opening_response` of a simulated first opening (one attempt, ``SIM_OPENING_S`` after it starts;
    ``theta_w_deg`` is what the set simulates: the command for a measured profile, the wing angle otherwise) in
    ``engine``."""
    tr, starts = simulated_openings(
        theta_w_deg,
        theta_l_deg,
        model_set=model_set,
        robot=robot,
        seed=seed,
        phase=phase,
        cv=cv,
        attempts=1,
        engine=engine,
    )
    return opening_response(tr.t_s, tr.pitch_deg, tr.roll_deg, starts[0])


def simulated_openings(
    theta_w_deg, theta_l_deg, *, model_set, robot, seed, phase, cv=0.0, attempts=1, engine="pybullet"
):
    """A traced simulated trial (in ``engine``) of ``attempts`` openings, the first at leg phase ``phase``, that
    ends ``SIM_OPENING_S`` after the last one starts (or once the body has righted): ``(trace, attempt
    starts)``."""
    from sim.model_set import load_model_set
    from sim.trial import run_trial

    ms = load_model_set(model_set).with_engine(engine)
    act = ms.actuation(theta_w_deg, theta_l_deg)
    last = phase * act.leg_period_s + (attempts - 1) * act.wing_period_s  # the openings: sim.actuation
    res = run_trial(
        theta_w_deg, theta_l_deg, phase=phase, cv=cv, rng=seed, robot=robot, model_set=ms, trace=True,
        attempts=attempts, duration_s=last + SIM_OPENING_S,
    )  # fmt: skip
    return res.trace, res.attempt_starts_s
