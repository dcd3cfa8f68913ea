"""Does the rigid landscape forbid the robot's roll-overs out of the hold, and how hard does the leg's swing throw
the held body? (issue #15: the cells at 60 and 75 deg where the robot rights and the model does not)

At 60 deg (leg 30-45) and 75 deg (leg 15-30) the robot leaves the hold 0.7-0.9 s after the opening starts, after
the leg's second swing, and rolls on while its wings are still open; the model sets sit level. Two questions,
answered from the recordings:

First table, *energy along the robot's roll-overs*: for every first opening that leaves the level
(``landscape.analysis.physical.lean.departure_s``: the tilt's last rise through 5 deg before it passes 45 deg) in the
hold (at or after 0.35 s), from its departure to the earlier of the wings' closing (``WING_CLOSE_S``) and a tilt
of 40 deg, on a model set's rigid landscape (its wing joints at the command, the leg held where the servo log
puts it then; ``landscape.energy.height_at``) along the recorded orientation (the IMU's, turned into the body
frame by the mounting the two rests measure): the departure's height above the set's hold, the rise from the
departure to the end (and the largest rise on the way), and the body's kinetic energy at both ends from the gyro
(``GYRO_SAMPLES``): rotation about the CoM with the set's inertia plus the CoM's translation were the lowest
point of the hull at rest, and in brackets the rotation alone, a lower bound. If the rise exceeds what the
kinetic energy can pay (the balance ``KE start - KE end - rise`` well below zero), the rigid landscape forbids
the path and the robot's support must differ; if not, the rigid geometry allows it and the question is where the
body's energy comes from. Below it, the set's righting barrier with the leg held on the side the robot rolls to,
and what one degree of pitch from the hold costs.

Second table, *the swing's throw in the hold*: per cell, the fastest lateral tilt rate (deg/s) and the range of
the tilt (deg; both from the orientation, the same measure for the robot and the simulation) within
``SWING_WINDOW_S`` after each change of the leg's side ``HOLD_SWINGS_S`` after the opening starts, until the body
tilts past 40 deg; the median over the swings of the robot's first openings (its leg's side from the servo log,
``LEG_LAG_S`` late) beside each set's in one simulated first opening at the protocol's phase (its leg's side
from its own leg angle, once a swing reaches half the amplitude: ``landscape.analysis.physical.lean.leg_sides``), no
noise.

With ``--vary TABLE.KEY=V1,V2`` (repeatable) each value is also tried on its own in a copy of the first set, with
``--with TABLE.KEY=V`` in every variant (as ``nose_over.py``).

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/hold_energy.py [--data DIR] [--robot URDF]
      [--models physical-head,physical-offset] [--cells 60:30,60:45,75:15,75:30] [--vary TABLE.KEY=V1,V2 ...]
      [--with TABLE.KEY=V ...]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from geometry.frames import pitch_roll_from_up
from landscape.analysis.energy import rotational_shares_j, translational_energy_j
from landscape.analysis.physical.calibration import add_set_options
from landscape.analysis.physical.recording import (
    imu_to_body,
    read_recording,
    trial_cell,
    trial_files,
    up_in_body,
)

ROOT = Path(__file__).resolve().parents[2]
WING_CLOSE_S = 1.04
"""When the wings start closing after the opening starts, s (the measured profiles' plateaus end at 1.04-1.06 s,
``[actuation.wing.*]`` of the measured sets)."""
HOLD_SWINGS_S = (0.25, 0.9)
"""Window after the opening starts in which a change of the leg's side counts as a swing of the hold, s (the
second and third swings of a first opening: the robot's leg reaches its side about 0.3 and 0.7 s after the start)."""
HOLD_DEPARTURE_S = 0.35
"""A roll-over that leaves the level this long after the opening starts or later leaves the hold, s; earlier ones
are thrown over in the opening (at 90 deg and 75/45 deg the robot's leave at 0.28-0.32 s)."""
SWING_WINDOW_S = 0.25
"""How long after a change of the leg's side its throw is read, s (the swing takes 0.10-0.14 s)."""
DEPART_TILT_DEG = 40.0
"""Lateral tilt past which the body has left the hold, degrees (``opening.LEAN_DEPART_DEG``)."""
GYRO_SAMPLES = 3
"""The gyro at a time is the median of this many samples nearest it (it runs at about 55 Hz and has
single-sample spikes: one of 35 rad/s at 60 deg / 45 deg, trial 4)."""
DEFAULT_CELLS = "60:30,60:45,75:15,75:30"


def kinetic_energy_j(pose, omega_body, up_body) -> float:
    """Kinetic energy of the rigid posed body turning at ``omega_body`` (rad/s, body frame) about its lowest hull
    point (at rest) in the orientation ``up_body`` (world-up in the body frame), J."""
    pts = pose.hull_points_m
    pivot = pts[np.argmin(pts @ np.asarray(up_body))]
    w = np.asarray(omega_body, dtype=np.float64)
    rotation = rotational_shares_j(w, pose.inertia_kg_m2).sum()
    return float(rotation + translational_energy_j(pose.mass_kg, np.cross(w, pose.com_m - pivot)))


def recorded_kinetic_energy_j(rec, time_s: float, pose, up_body, mount_deg: float) -> tuple[float, float]:
    """:func:`kinetic_energy_j` of the rigid ``pose`` turning at the recording's gyro rate at ``time_s`` (the
    median of the ``GYRO_SAMPLES`` samples nearest it, turned into the body frame ``mount_deg`` below the IMU's),
    and the rotation about the CoM alone (its lower bound, whatever the CoM does), J."""
    near = np.argsort(np.abs(rec.gyro_t_s - time_s))[:GYRO_SAMPLES]
    omega = imu_to_body(np.median(rec.gyro_rad_s[near], axis=0), mount_deg)
    return kinetic_energy_j(pose, omega, up_body), float(rotational_shares_j(omega, pose.inertia_kg_m2).sum())


def swing_throws(t_s, tilt_deg, start_s: float, changes_s) -> list[tuple[float, float]]:
    """Each swing's throw: ``(fastest |d tilt / dt|, deg/s; the tilt's range, deg)`` within ``SWING_WINDOW_S``
    after each change ``HOLD_SWINGS_S`` after ``start_s``, until the body first tilts past ``DEPART_TILT_DEG``
    (a window that reaches it is dropped).

    >>> t = np.arange(0.0, 1.2, 0.01)
    >>> tilt = np.where(t > 0.5, 10.0 * np.sin(2 * np.pi * (t - 0.5)), 0.0)  # thrown at 0.5 s
    >>> [(round(r), round(a, 1)) for r, a in swing_throws(t, tilt, 0.0, [0.1, 0.5, 1.0])]
    [(63, 10.0)]
    """
    t = np.asarray(t_s, dtype=np.float64) - start_s
    tilt = np.asarray(tilt_deg, dtype=np.float64)
    rate = np.gradient(tilt, t)
    past = np.flatnonzero((t >= 0) & (np.abs(tilt) >= DEPART_TILT_DEG))
    gone = t[past[0]] if len(past) else math.inf
    out = []
    for c in np.asarray(changes_s, dtype=np.float64) - start_s:
        if not HOLD_SWINGS_S[0] <= c <= HOLD_SWINGS_S[1] or c + SWING_WINDOW_S > gone:
            continue
        sel = (t >= c) & (t <= c + SWING_WINDOW_S)
        if sel.any():
            out.append((float(np.abs(rate[sel]).max()), float(np.ptp(tilt[sel]))))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--cells", default=DEFAULT_CELLS, help=f"WING:LEG,... [default: {DEFAULT_CELLS}]")
    add_set_options(ap, "physical-head,physical-offset")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="hold_energy_") as tmp:
        return _run(a, Path(tmp))


def _run(a, tmp: Path) -> int:
    from geometry.robots import load_robot
    from landscape.analysis.physical.calibration import sets_and_variants
    from landscape.analysis.physical.lean import LEG_LAG_S, departure_s, leg_command_changes, leg_sides
    from landscape.analysis.physical.mounting import mounting_from_rests
    from landscape.analysis.physical.response import (
        PROTOCOL_PHASE,
        lateral_tilt_deg,
        protocol_phases,
        simulated_openings,
    )
    from landscape.analysis.physical.validation import parse_cells
    from landscape.computation import compute, posed, start_orientation
    from landscape.energy import G_M_S2, height_at
    from sim.model_set import load_model_set

    try:
        names, labels = sets_and_variants(a.models, a.vary, a.fixed, tmp)
        lab = load_robot(a.robot)
        mount = mounting_from_rests(a.data, lab).mount_deg
        files = defaultdict(list)
        for f in trial_files(a.data):
            files[trial_cell(f)].append(f)
        cells = parse_cells(a.cells, files)
        recs = {cell: [read_recording(f) for f in files[cell]] for cell in cells}
        phases = protocol_phases(a.data)
        ref = load_model_set(names[0])
        robot = ref.robot_for(lab)
        poses = {}

        def pose(c, leg):
            """The set's posed robot, its hold's potential energy (J), the rise of the potential energy for one
            degree of pitch either way from the hold (J) and the righting barrier (J), the leg held at ``leg``."""
            if (c, leg) not in poses:
                wings = ref.wing_joints_deg(robot.joint_map.wing, c)
                p = posed(robot, c, leg, wings)
                hp, hr = start_orientation(robot, p, c, leg, wing_joints_deg=wings)
                e = height_at(p, [hp, hp - 1.0, hp + 1.0], [hr, hr, hr]) * p.mass_kg * G_M_S2
                comp = compute(
                    robot, theta_w_deg=c, theta_l_deg=leg, wing_joints_deg=wings, landscape_grid=False
                )
                poses[c, leg] = (p, float(e[0]), tuple(e[1:] - e[0]), comp.barrier.righting.barrier_j)
            return poses[c, leg]

        energy_rows, robot_rates = [], defaultdict(list)
        for cell in cells:
            for rec in recs[cell]:
                start = float(rec.openings_s[0])
                t = rec.t_s
                tilt = lateral_tilt_deg(rec.pitch_deg, rec.roll_deg)
                changes, sides = leg_command_changes(rec.leg_up_s)
                changes = changes + LEG_LAG_S
                robot_rates[cell] += swing_throws(t, tilt, start, changes)
                dep = departure_s(t, rec.pitch_deg, rec.roll_deg, start)
                if not math.isfinite(dep) or dep < HOLD_DEPARTURE_S:
                    continue  # no roll-over, or one thrown in the opening (not out of the hold)
                rel = t - start
                past = np.flatnonzero((rel > dep) & (np.abs(tilt) >= DEPART_TILT_DEG))
                end = min(WING_CLOSE_S, rel[past[0]] if len(past) else math.inf)
                sel = (rel >= dep) & (rel <= end)
                if sel.sum() < 3:
                    continue
                before = np.flatnonzero(changes <= start + dep)
                side = float(sides[before[-1]]) if len(before) else 1.0
                p_body, e_hold, _, _ = pose(cell[0], side * cell[1])
                up = up_in_body(rec.quat_xyzw[sel], mount)
                pb, rb = np.rad2deg(pitch_roll_from_up(up))
                e = height_at(p_body, pb, rb) * p_body.mass_kg * G_M_S2

                ts = rel[sel]
                energy_rows.append(
                    (cell, rec.trial, ts[0], ts[-1], tilt[sel][0], tilt[sel][-1], side, e[0] - e_hold,
                     e[-1] - e[0], e.max() - e[0], recorded_kinetic_energy_j(rec, start + ts[0], p_body, up[0], mount),
                     recorded_kinetic_energy_j(rec, start + ts[-1], p_body, up[-1], mount))
                )  # fmt: skip
        sim_rates = []
        for cell in cells:
            row = []
            for name in names:
                tr, starts = simulated_openings(
                    cell[0], cell[1], model_set=name, robot=a.robot, seed=0,
                    phase=phases.get(cell, PROTOCOL_PHASE),
                )  # fmt: skip
                # the leg's side as simulated_leans reads it: once a swing reaches half the amplitude
                ch = leg_sides(tr.t_s, tr.leg_deg, band_deg=0.5 * cell[1])[0] if cell[1] else []
                row.append(swing_throws(tr.t_s, lateral_tilt_deg(tr.pitch_deg, tr.roll_deg), starts[0], ch))
            sim_rates.append(row)
    except (UsageError, ValueError) as exc:  # PhysicalDataError, an unknown set, a bad number: one line
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(
        f"energy along the robot's roll-overs out of the hold (first openings), from the departure to the wings' "
        f"closing or a tilt of {DEPART_TILT_DEG:g} deg; {labels[0]}'s rigid landscape, the leg held on its side; "
        f"body frame (IMU minus the {mount:.1f} deg mounting); mJ"
    )
    print(
        "| wing cmd | leg | trial | window | tilt | leg side | departure above the hold | rigid climb (largest) "
        "| KE start (rotation) | KE end (rotation) | balance |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (w, leg), trial, t0, t1, a0, a1, side, above, climb, top, (k0, r0), (k1, r1) in energy_rows:
        print(
            f"| {w:g}° | {leg:g}° | {trial} | {t0:.2f}-{t1:.2f} s | {a0:+.1f}° to {a1:+.1f}° | {side:+.0f} | "
            f"{above * 1e3:.1f} | {climb * 1e3:+.1f} ({top * 1e3:.1f}) | {k0 * 1e3:.1f} ({r0 * 1e3:.1f}) | "
            f"{k1 * 1e3:.1f} ({r1 * 1e3:.1f}) | "
            f"{(k0 - k1 - climb) * 1e3:+.1f} |"
        )
    for (w, leg), (_, _, (down, up), barrier) in sorted(poses.items()):
        print(
            f"{labels[0]} at {w:g}° with the leg held at {leg:+g}°: righting barrier {barrier * 1e3:.1f} mJ; "
            f"one degree of pitch from the hold costs {down * 1e3:.1f} mJ down, {up * 1e3:.1f} mJ up"
        )
    print()
    print(
        f"the swing's throw in the hold: within {SWING_WINDOW_S:g} s after each change of the leg's side "
        f"{HOLD_SWINGS_S[0]:g}-{HOLD_SWINGS_S[1]:g} s after the first opening starts, the fastest lateral tilt "
        f"rate (deg/s) and the tilt's range (deg), medians (swings); in brackets against the robot's"
    )
    print(f"| wing cmd | leg | robot | {' | '.join(labels)} |")
    print("|---|---|---|" + "---|" * len(labels))
    for cell, row in zip(cells, sim_rates, strict=True):
        r = np.array(robot_rates[cell]).reshape(-1, 2)
        rm = np.median(r, axis=0) if len(r) else None
        cols = []
        for sw in row:
            if not sw:
                cols.append("– (0)")
                continue
            m = np.median(np.array(sw), axis=0)
            ratio = f"{m[0] / rm[0]:.2f}x, {m[1] / rm[1]:.2f}x; " if rm is not None else ""
            cols.append(f"{m[0]:.0f} °/s, {m[1]:.1f}° ({ratio}{len(sw)})")
        robot = f"{rm[0]:.0f} °/s, {rm[1]:.1f}° ({len(r)})" if rm is not None else "– (0)"
        print(f"| {cell[0]:g}° | {cell[1]:g}° | {robot} | {' | '.join(cols)} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
