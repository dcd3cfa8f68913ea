"""Measured actuation: piecewise-linear profiles fitted to the physical robot's servo and leg traces.

The lab's recordings (``motor_pulse_v2.mat``, ``vib_pulse_v2.mat``; described in the data directory's
README) are not shipped: these functions turn them into a few knots per joint, which a model set carries as
``profile = "measured"`` (:class:`sim.actuation.MeasuredActuation`). Anyone with the data reruns
:func:`measured_actuation_toml` to regenerate the ``[actuation]`` block of ``sim/models/physical.toml``.

Wings. For each wing servo (``LP``, ``RP``, ``LR``, ``RR``: left/right pitch, left/right roll) and each wing
command (60, 75, 90 deg) the first cycle (``Start``) and one period of the periodic part (``Repeat``; period
2 s) are fitted together, as functions of the time since the opening command, by one piecewise-linear profile of
``WING_KNOTS`` knots: closed at the command (t = 0), still closed at the end of the servo's delay, a curved rise
(three segments), the plateau, the closing (two segments) and closed again; the closed angle is the same at both
ends (the hold between attempts). Knot times and angles are least-squares fits; the shipped knots are rounded
(0.1 ms, 0.01 deg) and the errors are those of the rounded knots.

Leg. For each commanded amplitude (15, 30, 45 deg) one period (0.8 s) of the measured leg angle is fitted by a
periodic piecewise-linear profile of ``LEG_KNOTS`` knots. The recording's own time origin is replaced by the
model's convention (:mod:`sim.actuation`): t = 0 is the leg's upward midline crossing, so the profile starts at
0 moving towards positive angles, as the idealised trapezoid does. Only the shape changes: the true amplitudes
(overshoot included), the crossing times and any asymmetry between the two sides.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from geometry.errors import UsageError
from sim.model_set import MIRRORED, SERVO_SIDES

WING_SERVOS = ("LP", "RP", "LR", "RR")
"""The lab's wing servos, in the order of the default joint map's wing joints (wing_pitch_left,
wing_pitch_right, wing_roll_left, wing_roll_right)."""
WING_COMMANDS_DEG = (60.0, 75.0, 90.0)
LEG_COMMANDS_DEG = (15.0, 30.0, 45.0)
WING_PERIOD_S = 2.0
"""Period of the recorded wing cycles, s."""
LEG_PERIOD_S = 0.8
"""Period of the recorded leg oscillation, s."""
WING_PULSE_FILE = "motor_pulse_v2.mat"
"""The lab's recording of the wing servos' pulses, in its data directory."""
LEG_PULSE_FILE = "vib_pulse_v2.mat"
"""The lab's recording of the leg's swing, in its data directory."""
WING_KNOTS = 10
LEG_KNOTS = 14
_T_DECIMALS, _DEG_DECIMALS = 4, 2


class MeasuredDataError(UsageError):
    """A data file that is missing or does not hold the traces expected."""


def _loadmat(mat_path: str | Path) -> dict:
    from scipy.io import loadmat

    path = Path(mat_path)
    if not path.is_file():
        raise MeasuredDataError(
            f"data file '{path}' not found; give the physical robot's data directory "
            "(the one holding motor_pulse_v2.mat and vib_pulse_v2.mat)"
        )
    try:
        return loadmat(path, squeeze_me=True, struct_as_record=False)
    except (ValueError, OSError, NotImplementedError) as exc:
        raise MeasuredDataError(f"'{path}' is not a readable MATLAB file: {exc}") from None


def _pwl(tau: NDArray, knots_s: NDArray, knots_deg: NDArray) -> NDArray:
    return np.interp(tau, knots_s, knots_deg)


def _hats(tau: NDArray, knots_s: NDArray) -> NDArray:
    """(N, K) matrix: column k is the piecewise-linear profile that is 1 at knot k and 0 at the others."""
    eye = np.eye(len(knots_s))
    return np.stack([np.interp(tau, knots_s, eye[k]) for k in range(len(knots_s))], axis=1)


def _fit(tau, y, init_s, *, tied, ends_s=None, max_gap_s=1.0):
    """Least-squares piecewise-linear profile through the samples (tau, y): knot times by nonlinear least
    squares, knot angles by linear least squares at each set of times (variable projection).

    Knot 0 is at t = 0 and, if ``ends_s`` is given, the last knot at ``ends_s``. ``tied`` marks the knots that
    share one angle: the fitted closed hold (``ends_s`` None) or 0 (``ends_s`` given: the leg's crossings)."""
    from scipy.optimize import least_squares

    init_s = np.asarray(init_s, float)
    n = len(init_s)
    tied = np.asarray(tied, bool)
    free_idx = np.flatnonzero(~tied)
    last_fixed = ends_s is not None
    n_t = n - 1 - (1 if last_fixed else 0)

    def times(gaps):
        ks = np.concatenate([[0.0], np.cumsum(gaps)])
        return np.append(ks, ends_s) if last_fixed else ks

    def angles(ks):
        h = _hats(tau, ks)
        cols = [h[:, free_idx]] + ([] if last_fixed else [h[:, tied].sum(axis=1, keepdims=True)])
        a = np.linalg.lstsq(np.concatenate(cols, axis=1), y, rcond=None)[0]
        kd = np.zeros(n)
        kd[free_idx] = a[: len(free_idx)]
        if not last_fixed:
            kd[tied] = a[-1]
        return kd

    def residual(gaps):
        ks = times(gaps)
        if last_fixed and ks[-2] >= ks[-1] - 1e-3:
            return np.full(len(tau), 1e3)
        return _pwl(tau, ks, angles(ks)) - y

    gaps0 = np.clip(np.diff(init_s)[:n_t], 2e-3, max_gap_s - 1e-3)
    sol = least_squares(residual, gaps0, bounds=(1e-3, max_gap_s), diff_step=1e-4, method="trf")
    ks = times(sol.x)
    kd = angles(ks)
    return np.round(ks, _T_DECIMALS), np.round(kd, _DEG_DECIMALS)


def _wing_samples(pulse, cmd: int, servo: str):
    """(tau_s, angle_deg) of the Start cycle and one Repeat period, tau = time since the opening command."""
    out_t, out_y, parts = [], [], {}
    for kind in ("Start", "Repeat"):
        name = f"{kind}{cmd}{servo}"
        if name not in getattr(pulse, "_fieldnames", ()):
            raise MeasuredDataError(f"motor_pulse_v2.mat: struct pulse has no field {name!r}")
        a = np.asarray(getattr(pulse, name), dtype=np.float64)
        t, y = a[0], a[1]
        tau = np.mod(t, WING_PERIOD_S) if kind == "Repeat" else t
        # Start: the first cycle; Repeat: its first period (the later ones repeat it sample for sample)
        keep = np.isfinite(y) & (t < (2 if kind == "Repeat" else 1) * WING_PERIOD_S - 1e-9)
        parts[kind] = (tau[keep], y[keep])
        out_t.append(tau[keep])
        out_y.append(y[keep])
    return np.concatenate(out_t), np.concatenate(out_y), parts


def _wing_init(tau, y):
    """Initial knot times from the 5/50/95 % crossings of the rise and the fall."""
    c = float(np.median(y[tau > 1.5]))
    plateau = float(np.median(y[(tau > 0.5) & (tau < 0.9)]))
    amp = plateau - c
    order = np.argsort(tau)
    tau, y = tau[order], y[order]
    mid = 0.7

    def rise(frac):
        return float(tau[np.flatnonzero((tau < mid) & (y > c + frac * amp))[0]])

    def fall(frac):
        return float(tau[np.flatnonzero((tau > mid) & (y > c + frac * amp))[-1]])

    r = [rise(f) for f in (0.05, 0.3, 0.7, 0.95)]
    f = [fall(x) for x in (0.95, 0.75, 0.3, 0.05)]
    return [0.0, r[0] - 0.01, r[1], r[2], r[3], *f, f[3] + 0.05]


def wing_profile_summary(knots_s, knots_deg) -> dict:
    """Plateau, opening and closing speed of one piecewise-linear wing profile.

    The plateau is the profile's mean where it is within 5 % (of the opening) of its maximum; the speeds are
    80 % of the opening divided by the time between 10 % and 90 % of it, on the rise and on the fall.

    Returns
    -------
    dict with ``plateau_deg``, ``open_deg_s``, ``close_deg_s``, ``closed_deg``

    Examples
    --------
    >>> s = wing_profile_summary([0.0, 0.0, 0.25, 1.0, 1.2], [0.0, 0.0, 75.0, 75.0, 0.0])
    >>> round(s["plateau_deg"], 1), round(s["open_deg_s"]), round(s["close_deg_s"])
    (74.9, 300, 375)
    """
    ks, kd = np.asarray(knots_s, float), np.asarray(knots_deg, float)
    t = np.linspace(ks[0], ks[-1], 200001)
    a = np.interp(t, ks, kd)
    closed, top = float(kd[0]), float(a.max())
    amp = top - closed
    i_top = int(np.argmax(a))
    rise, fall = slice(0, i_top + 1), slice(i_top, None)

    def cross(sl, frac):
        seg_t, seg_a = t[sl], a[sl]
        lvl = closed + frac * amp
        i = np.flatnonzero(seg_a >= lvl) if sl is rise else np.flatnonzero(seg_a <= lvl)
        return float(seg_t[i[0]])

    open_s = cross(rise, 0.9) - cross(rise, 0.1)
    close_s = cross(fall, 0.1) - cross(fall, 0.9)
    near = a >= top - 0.05 * amp
    return {
        "plateau_deg": float(a[near].mean()),
        "open_deg_s": 0.8 * amp / open_s,
        "close_deg_s": 0.8 * amp / close_s,
        "closed_deg": closed,
    }


def fit_wing_profiles(mat_path: str | Path) -> dict:
    """Fit one piecewise-linear profile per wing servo and wing command to ``motor_pulse_v2.mat``.

    Parameters
    ----------
    mat_path : path
        The lab's ``motor_pulse_v2.mat`` (struct ``pulse`` with ``Start{60,75,90}{LP,RP,LR,RR}`` and
        ``Repeat{...}``, each 2 x N: time in s, servo angle in deg).

    Returns
    -------
    dict
        ``command_deg`` (3 wing commands, deg); ``servos``: for each of ``WING_SERVOS`` a dict with
        ``knots_s`` and ``knots_deg`` (one list of ``WING_KNOTS`` knots per command: time since the opening
        command, s; servo angle, deg), ``max_error_deg`` (per command, over the Start and Repeat samples) and
        ``summary`` (per command, :func:`wing_profile_summary`); ``summary`` (per command, the mean over the four
        servos); ``max_error_deg`` (the largest of all).

    Raises
    ------
    MeasuredDataError
        If the file is missing or lacks a trace.
    """
    data = _loadmat(mat_path)
    if "pulse" not in data:
        raise MeasuredDataError(f"'{mat_path}' has no struct 'pulse'; give the lab's motor_pulse_v2.mat")
    pulse = data["pulse"]
    out: dict = {"command_deg": list(WING_COMMANDS_DEG), "servos": {}}
    for servo in WING_SERVOS:
        rec = {"knots_s": [], "knots_deg": [], "max_error_deg": [], "summary": []}
        for cmd in WING_COMMANDS_DEG:
            tau, y, parts = _wing_samples(pulse, int(cmd), servo)
            tied = np.zeros(WING_KNOTS, bool)
            tied[[0, 1, -1]] = True  # closed at the command, through the delay, and after closing
            ks, kd = _fit(tau, y, _wing_init(tau, y), tied=tied)
            err = max(float(np.abs(_pwl(pt, ks, kd) - py).max()) for pt, py in parts.values())
            rec["knots_s"].append(ks.tolist())
            rec["knots_deg"].append(kd.tolist())
            rec["max_error_deg"].append(round(err, 3))
            rec["summary"].append(wing_profile_summary(ks, kd))
        out["servos"][servo] = rec
    out["summary"] = [
        {
            key: float(np.mean([out["servos"][s]["summary"][i][key] for s in WING_SERVOS]))
            for key in ("plateau_deg", "open_deg_s", "close_deg_s", "closed_deg")
        }
        for i in range(len(WING_COMMANDS_DEG))
    ]
    out["max_error_deg"] = max(max(out["servos"][s]["max_error_deg"]) for s in WING_SERVOS)
    return out


def _leg_trace(data: dict, amp: int):
    name = f"Vib{amp}"
    if "tVib" not in data or name not in data:
        raise MeasuredDataError(f"vib_pulse_v2.mat has no {'tVib' if 'tVib' not in data else name!r}")
    t = np.asarray(data["tVib"], dtype=np.float64).ravel()
    y = np.asarray(data[name], dtype=np.float64).ravel()
    keep = np.isfinite(t) & np.isfinite(y)
    t, y = t[keep], y[keep]
    up = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    if len(up) < 2:
        raise MeasuredDataError(
            f"vib_pulse_v2.mat: {name} does not cross 0 upwards twice; not a leg oscillation"
        )
    t_up = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    # the recording starts from rest (half a cycle of start-up): keep the periodic part, from the first upward
    # crossing on
    keep = t >= t_up[0]
    return np.mod(t[keep] - t_up[0], LEG_PERIOD_S), y[keep]


def leg_crossing_lag_s(mat_path: str | Path) -> dict[float, float]:
    """How long after its command changes side the measured leg crosses the midline, per leg amplitude command,
    s: the median over every midline crossing of its time modulo half the period. The recording starts as a
    command does (the leg at rest at 0 deg, ``tVib`` = 0) and the command changes side every half period.

    Raises
    ------
    MeasuredDataError
        If the file is missing or a trace crosses the midline fewer than four times.
    """
    data = _loadmat(mat_path)
    out = {}
    for amp in LEG_COMMANDS_DEG:
        name = f"Vib{int(amp)}"
        if "tVib" not in data or name not in data:
            raise MeasuredDataError(f"vib_pulse_v2.mat has no {'tVib' if 'tVib' not in data else name!r}")
        t = np.asarray(data["tVib"], dtype=np.float64).ravel()
        y = np.asarray(data[name], dtype=np.float64).ravel()
        i = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
        if len(i) < 4:
            raise MeasuredDataError(
                f"vib_pulse_v2.mat: {name} crosses 0 {len(i)} times; not a leg oscillation"
            )
        t_cross = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
        out[float(amp)] = float(np.median(np.mod(t_cross, LEG_PERIOD_S / 2)))
    return out


def _leg_init(tau, y):
    """Initial knot times: around the upward crossing (t = 0) and the downward one, and along each side."""
    order = np.argsort(tau)
    tau, y = tau[order], y[order]
    t_down = float(tau[np.flatnonzero(y > 0)[-1]])  # the last positive sample before the period ends
    one = np.array([0.02, 0.04, 0.06, 0.09])
    return [
        0.0,
        *one,
        0.6 * t_down,
        t_down - 0.02,
        t_down,
        *(t_down + one),
        t_down + 0.5 * (LEG_PERIOD_S - t_down),
        LEG_PERIOD_S - 0.02,
        LEG_PERIOD_S,
    ][:LEG_KNOTS]


def fit_leg_profiles(mat_path: str | Path) -> dict:
    """Fit one periodic piecewise-linear profile per leg amplitude command to ``vib_pulse_v2.mat``.

    Parameters
    ----------
    mat_path : path
        The lab's ``vib_pulse_v2.mat`` (``tVib`` in s, ``Vib15``, ``Vib30``, ``Vib45``: leg angle in deg).

    Returns
    -------
    dict
        ``command_deg`` (3 leg commands, deg), ``period_s``, ``knots_s`` and ``knots_deg`` (one list of
        ``LEG_KNOTS`` knots per command over one period, from the upward midline crossing), ``max_error_deg`` (per
        command, over every recorded sample), ``amplitude_deg`` (per command, the profile's largest and
        smallest angle) and ``cross_s`` (per command, the time from -90 % to +90 % of the amplitude divided by
        0.8: the equivalent of the idealised ``leg_cross_s``), and ``max_error_deg_all``.

    Raises
    ------
    MeasuredDataError
        If the file is missing or lacks a trace.
    """
    data = _loadmat(mat_path)
    out: dict = {
        "command_deg": list(LEG_COMMANDS_DEG),
        "period_s": LEG_PERIOD_S,
        "knots_s": [],
        "knots_deg": [],
        "max_error_deg": [],
        "amplitude_deg": [],
        "cross_s": [],
    }
    for amp in LEG_COMMANDS_DEG:
        tau, y = _leg_trace(data, int(amp))
        tied = np.zeros(LEG_KNOTS, bool)
        tied[[0, -1]] = True  # the upward midline crossing, one period apart
        # fitted to the mean over the recorded periods in 2 ms phase bins; the error is over every sample
        bins = np.minimum((tau / 2e-3).astype(int), int(round(LEG_PERIOD_S / 2e-3)) - 1)
        count = np.bincount(bins)
        keep = count > 0
        tau_m = ((np.arange(len(count)) + 0.5) * 2e-3)[keep]
        y_m = (np.bincount(bins, weights=y) / np.maximum(count, 1))[keep]
        ks, kd = _fit(
            tau_m, y_m, _leg_init(tau_m, y_m), tied=tied, ends_s=LEG_PERIOD_S, max_gap_s=LEG_PERIOD_S / 2
        )
        out["knots_s"].append(ks.tolist())
        out["knots_deg"].append(kd.tolist())
        out["max_error_deg"].append(round(float(np.abs(_pwl(tau, ks, kd) - y).max()), 3))
        out["amplitude_deg"].append([float(kd.max()), float(kd.min())])
        t = np.linspace(0.0, LEG_PERIOD_S, 80001)
        a = np.interp(t, ks, kd)
        # the downward crossing: from the last time at +80 % of the largest angle to the first at -80 % of the
        # smallest, scaled to the full swing
        i_lo = int(np.argmin(a))
        t_a = t[: i_lo + 1][np.flatnonzero(a[: i_lo + 1] >= 0.8 * kd.max())[-1]]
        t_b = t[np.flatnonzero((t > t_a) & (a <= 0.8 * kd.min()))[0]]
        out["cross_s"].append(float((t_b - t_a) / 0.8))
    out["max_error_deg_all"] = max(out["max_error_deg"])
    return out


def _row(values) -> str:
    return "[" + ", ".join(f"{v:g}" for v in values) + "]"


def measured_actuation_toml(data_dir: str | Path, *, servo_sides: str = "as-labelled") -> str:
    """The ``[actuation]`` block of a ``profile = "measured"`` model set, fitted to the lab's traces.

    Parameters
    ----------
    data_dir : path
        Directory holding ``motor_pulse_v2.mat`` and ``vib_pulse_v2.mat`` (the physical robot's data).
    servo_sides : {"as-labelled", "mirrored"}
        Which wing joints the lab's left servos drive (``sim.model_set.SERVO_SIDES``); "mirrored" writes
        ``servo_sides = "mirrored"``.

    Returns
    -------
    str
        TOML text: ``[actuation]`` with ``profile``, ``wing_command_deg`` and ``leg_command_deg``, then
        ``[actuation.wing.LP]`` ... ``[actuation.wing.RR]`` and ``[actuation.leg]``, each with ``knots_s`` and
        ``knots_deg`` (one row per command), with the fit errors as comments.

    Raises
    ------
    MeasuredDataError
        If a file is missing or lacks a trace.
    """
    d = Path(data_dir)
    wing = fit_wing_profiles(d / WING_PULSE_FILE)
    leg = fit_leg_profiles(d / LEG_PULSE_FILE)
    lines = [
        # the shipped sets carry this comment as generated; it names the module's former path
        "# Generated by landscape.analysis.measured.measured_actuation_toml(DATA_DIR) from motor_pulse_v2.mat and",
        "# vib_pulse_v2.mat; rerun it to regenerate this block. Per joint: one row of knots per command.",
        "[actuation]",
        'profile = "measured"',
        f"wing_command_deg = {_row(wing['command_deg'])}",
        f"leg_command_deg = {_row(leg['command_deg'])}",
    ]
    if servo_sides not in SERVO_SIDES:
        raise ValueError(f"servo_sides must be one of {', '.join(SERVO_SIDES)}; got {servo_sides!r}")
    joints = ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right")
    if servo_sides == "mirrored":
        lines.append("servo_sides = \"mirrored\"  # the lab's left servos drive the model's right joints")
        joints = tuple(joints[MIRRORED.index(k)] for k in range(len(joints)))  # servo k drives this joint
    joints = dict(zip(WING_SERVOS, joints, strict=True))
    for servo in WING_SERVOS:
        rec = wing["servos"][servo]
        errs = ", ".join(f"{e:.2f}" for e in rec["max_error_deg"])
        lines += ["", f"[actuation.wing.{servo}]  # {joints[servo]}; max fit error {errs} deg"]
        lines.append("knots_s = [" + ", ".join(_row(r) for r in rec["knots_s"]) + "]")
        lines.append("knots_deg = [" + ", ".join(_row(r) for r in rec["knots_deg"]) + "]")
    errs = ", ".join(f"{e:.2f}" for e in leg["max_error_deg"])
    lines += [
        "",
        f"[actuation.leg]  # period {leg['period_s']:g} s from the upward crossing; max fit error {errs} deg",
    ]
    lines.append("knots_s = [" + ", ".join(_row(r) for r in leg["knots_s"]) + "]")
    lines.append("knots_deg = [" + ", ".join(_row(r) for r in leg["knots_deg"]) + "]")
    return "\n".join(lines) + "\n"
