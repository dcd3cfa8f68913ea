"""Does the physical robot's pendulum leg ring like a spring?  The IMU's answer to a leg step, and the leg's own.

The robot's gyro (``gyro``: body roll, pitch and yaw rate about x, y, z, rad/s, ~60 Hz) after the first leg
command step 0 -> -A of each trial with the leg moving, taken from the servo log while the robot rests on its
back with the wings closed (about 0.6 s before the first opening). Each axis's rate, resampled at 60 Hz and
signed so the step is positive, is fitted by a damped cosine ``a exp(-zeta wn t) cos(2 pi f t + phi) + c``
(``f`` the damped frequency, best of 20 starts) from 0.1 s after the step to the next event: the next leg
step + 0.06 s or the first opening + 0.08 s (the body answers a command that late). Per amplitude and axis:
the events, the median ``f``, ``zeta`` and R², how many "ring" (R² > 0.6, zeta < 0.3, at least one cycle),
and the rms of the mean response late (0.2 s to the median end) over its rms early (0.05-0.2 s, the swing).
A soft leg spring would ring in roll and yaw after every leg step.

The second table is the lab's measured leg angle (``vib_pulse_v2.mat``), one -A -> +A swing per command (the
fourth upward zero crossing): peak and plateau (median 0.2-0.27 s after the crossing), overshoot as a share
of the swing, time from the peak until the angle stays within 2 % of the swing of the plateau, and the
damping ratio of the second-order system with that overshoot.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/imu_ringing.py [--data DIR]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import h5py
import numpy as np
from scipy.io import loadmat
from scipy.optimize import curve_fit

from geometry.errors import UsageError
from landscape.analysis.physical.recording import read_recording, trial_files

ROOT = Path(__file__).resolve().parents[2]
FS_HZ = 60.0
LEG_LAG_S, WING_LAG_S = 0.06, 0.08
AXES = ("roll (x)", "pitch (y)", "yaw (z)")
LEGS_DEG = (15.0, 30.0, 45.0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    args = ap.parse_args(argv)
    try:
        return _run(Path(args.data))
    except UsageError as exc:  # bad data: one line, as the landscape command does
        ap.exit(2, f"{ap.prog}: error: {exc}\n")


def _rest_step(path: Path) -> tuple[float, float, float] | None:
    """The first 0 -> -A leg step before the first opening: (time from the opening s, sign, end s)."""
    with h5py.File(path, "r") as f:
        servo = np.asarray(f["servo"][()], dtype=np.float64).T
    wing, leg = servo[:, 2], servo[:, 1]
    rises = servo[1:, 0][(wing[1:] > 0) & (wing[:-1] <= 0)]
    t = servo[:, 0] - (servo[0, 0] if wing[0] > 0 else rises[0])  # as read_recording times the first opening
    steps = [(float(t[i]), leg[i - 1], leg[i]) for i in np.flatnonzero(np.diff(leg) != 0) + 1]
    for t_s, old, new in steps:
        if t_s < 0 and old == 0:
            nxt = min([x for x, _, _ in steps if x > t_s + 0.05] + [math.inf])
            return t_s, float(np.sign(new - old)), min(nxt + LEG_LAG_S, WING_LAG_S)
    return None


def _resample(t, y, lo: float, hi: float):
    tt = np.arange(lo, hi + 1e-9, 1 / FS_HZ)
    sel = (t >= lo - 0.05) & (t <= hi + 0.05)
    if sel.sum() < 0.8 * len(tt) or t[sel].min() > lo + 0.02 or t[sel].max() < hi - 0.02:
        return None
    return tt, np.interp(tt, t[sel], y[sel])


def _damped(t, a, f_hz, zeta, phi, c):
    wn = 2 * np.pi * f_hz / np.sqrt(max(1 - zeta**2, 1e-6))
    return a * np.exp(-zeta * wn * t) * np.cos(2 * np.pi * f_hz * t + phi) + c


def _fit_damped(t, y) -> tuple[float, float, float, float] | None:
    """Best damped-cosine fit over 20 starts: (f Hz, zeta, R², cycles), or None."""
    t = t - t[0]
    best = None
    for f0 in (1.5, 2.5, 3.5, 5.0, 7.0):
        for phi0 in (0.0, np.pi / 2, np.pi, -np.pi / 2):
            try:
                p, _ = curve_fit(
                    _damped, t, y, p0=[np.ptp(y) / 2 + 1e-3, f0, 0.2, phi0, float(np.mean(y))],
                    bounds=([0, 0.8, 0.0, -10, -50], [100, 15, 0.95, 10, 50]), maxfev=4000,
                )  # fmt: skip
            except (RuntimeError, ValueError):
                continue
            sse = float(np.sum((_damped(t, *p) - y) ** 2))
            if best is None or sse < best[0]:
                best = (sse, p)
    if best is None:
        return None
    sst = float(np.sum((y - y.mean()) ** 2)) or 1e-12
    return best[1][1], best[1][2], 1 - best[0] / sst, best[1][1] * t[-1]


def _leg_steps(data: Path) -> dict:
    """Per leg amplitude: the fits per axis and the late/early rms of the mean response per axis."""
    events: dict = {a: [] for a in LEGS_DEG}
    for path in trial_files(data):
        rec = read_recording(path)
        step = _rest_step(path) if rec.theta_l_deg in events else None
        if step is None:
            continue
        t_s, sign, end = step
        rs = [_resample(rec.gyro_t_s, rec.gyro_rad_s[:, k], t_s - 0.1, t_s + 0.6) for k in range(3)]
        if all(r is not None for r in rs):
            events[rec.theta_l_deg].append((rs[0][0] - t_s, sign * np.array([y for _, y in rs]), end - t_s))
    out = {}
    for leg, ev in events.items():
        fits = [[] for _ in range(3)]
        for tt, y, end in ev:
            m = (tt >= 0.1) & (tt <= end)
            for k in range(3):
                if m.sum() > 6 and (r := _fit_damped(tt[m], y[k][m])) is not None:
                    fits[k].append(r)
        tt, mean = ev[0][0], np.mean([y for _, y, _ in ev], axis=0)
        early = (tt >= 0.05) & (tt < 0.2)
        late = (tt >= 0.2) & (tt <= float(np.median([e for _, _, e in ev])))
        rms = [math.sqrt(np.mean(mean[k][late] ** 2) / np.mean(mean[k][early] ** 2)) for k in range(3)]
        out[leg] = (fits, rms)
    return out


def _leg_angle(data: Path) -> dict:
    """Per leg command: peak deg, plateau deg, overshoot (share of the swing), settle s, zeta."""
    path = data / "vib_pulse_v2.mat"
    if not path.is_file():
        raise UsageError(f"'{path}' not found; give --data the lab's data-robot folder")
    vib = loadmat(path, squeeze_me=True)
    out = {}
    for leg in LEGS_DEG:
        y = np.asarray(vib[f"Vib{leg:.0f}"], dtype=np.float64)
        k = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))[3]
        sel = slice(k - 150, k + 250)  # -0.3 .. +0.5 s at 2 ms
        tt, yy = vib["tVib"][sel] - vib["tVib"][k], y[sel]
        before = np.median(yy[(tt > -0.25) & (tt < -0.12)])
        plateau = np.median(yy[(tt > 0.2) & (tt < 0.27)])  # the next swing starts ~0.3 s after the crossing
        swing = plateau - before
        post = (tt > 0) & (tt < 0.27)
        peak, t_peak = yy[post].max(), tt[post][np.argmax(yy[post])]
        over = (peak - plateau) / swing
        zeta = -math.log(over) / math.sqrt(math.pi**2 + math.log(over) ** 2) if over > 0 else 1.0
        out_2 = tt[(tt > t_peak) & (tt < 0.27) & (np.abs(yy - plateau) > 0.02 * abs(swing))]
        out[leg] = (peak, plateau, over, (out_2.max() - t_peak) if len(out_2) else 0.0, zeta)
    return out


def _run(data: Path) -> int:
    steps = _leg_steps(data)
    vib = _leg_angle(data)
    print("leg step 0 -> -A at rest (on the back, wings closed): damped-cosine fit to the body rate from +0.1 s to "
          "the next event, medians over the events; ringing = R² > 0.6, ζ < 0.3, ≥ 1 cycle")  # fmt: skip
    head = ["leg", "axis", "events", "f (Hz)", "ζ", "R²", "ringing", "late/early rms"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for leg, (fits, rms) in steps.items():
        for k, axis in enumerate(AXES):
            f_hz, zeta, r2, cyc = np.array(fits[k]).T
            ring = int(np.sum((r2 > 0.6) & (zeta < 0.3) & (cyc >= 1.0)))
            row = [f"{leg:g}°", axis, str(len(fits[k])), f"{np.median(f_hz):.2f}", f"{np.median(zeta):.2f}",
                   f"{np.median(r2):.2f}", str(ring), f"{rms[k]:.2f}"]  # fmt: skip
            print("| " + " | ".join(row) + " |")
    print("\nmeasured leg angle (vib_pulse_v2.mat), one -A -> +A swing: overshoot as a share of the swing, "
          "settling = peak until within 2 % of the swing of the plateau, ζ of a 2nd-order system")  # fmt: skip
    head = ["leg cmd", "peak", "plateau", "overshoot", "settling (ms)", "ζ (2nd order)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for leg, (peak, plateau, over, settle_s, zeta) in vib.items():
        row = [f"{leg:g}°", f"{peak:.1f}°", f"{plateau:.1f}°", f"{100 * over:.1f} %", f"{1000 * settle_s:.0f}",
               f"{zeta:.2f}"]  # fmt: skip
        print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
