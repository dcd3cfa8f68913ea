"""The first wing opening, robot against simulation: does the model move like the robot? (issue #15)

Per physical cell (wing command x leg amplitude), the first opening of each recorded trial beside simulated
first openings of each model set (random first-attempt phases, the validation's, no noise), measured by the same
code (``landscape.analysis.physical.response``): the pitch overshoot past the hold, the rise time, and the lateral tilt of
largest magnitude 0.2-0.6 s after the opening starts (``asin(cos p sin r)``, degrees; positive towards positive
roll). Medians over the trials; in brackets, the median |tilt|. A second table gives the hold's wobble: the
standard deviations of pitch and tilt 0.5-0.95 s after the opening starts, while the wings are held open. A
third gives, for the robot and every set and variant, where the hold has left the body when the wings start
closing: the median signed tilt 0.95-1.05 s after the opening starts (in brackets the median |tilt|) and how many
first openings rolled past a tilt of 45 deg within 1.4 s, with the median time; beside them the rigid model's
roll-wise saddle as a tilt (``landscape.compute`` at the measured plateau, leg centred) and the difference between
the robot's recorded tilt and the tilt its gyro alone gives (``gyro_tilt_deviation_deg``, median and largest:
whether the recorded rocking is the body's or the IMU fusion's).

With ``--phase P`` every simulated first opening starts at leg phase P (the lab's protocol fixes it; ``landscape
physical kinematics`` times it at about 0.17) instead of the validation's random phases (without noise the
openings of a cell are then alike: ``--trials 1``).

With ``--vary TABLE.KEY=V1,V2`` (repeatable) each value is also tried on its own in a copy of the first set
(``landscape.analysis.physical.calibration.variant_sets``), one key at a time, and a last table gives each variant's
median |tilt| and hold wobble per cell beside the robot's; ``--with TABLE.KEY=V`` (repeatable) sets a key in
every variant (e.g. a damping while the stiffness varies); ``--cells 60:30,60:45`` limits the cells.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/opening_transient.py [--data DIR] [--robot URDF]
      [--models paper,physical] [--trials 5] [--seed 0] [--cells W:L,...] [--phase P]
      [--vary TABLE.KEY=V1,V2 ...] [--with TABLE.KEY=V ...]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np
from tqdm import tqdm

from geometry.errors import UsageError
from landscape.analysis.physical.calibration import add_set_options, variant_sets
from landscape.analysis.physical.recording import measured_plateaus_deg
from landscape.analysis.physical.response import recorded_first_openings, simulated_opening
from landscape.analysis.physical.validation import cell_phases, parse_cells, simulates_commands

ROOT = Path(__file__).resolve().parents[2]


def summary(responses) -> str:
    over = np.median([r.overshoot_deg for r in responses])
    tilt = np.array([r.tilt_deg for r in responses])
    return f"{over:+.1f}° / {np.median(tilt):+.1f}° ({np.median(np.abs(tilt)):.1f}°)"


def wobble(responses) -> str:
    p = np.median([r.wobble_pitch_deg for r in responses])
    t = np.median([r.wobble_tilt_deg for r in responses])
    return f"{p:.1f}° / {t:.1f}°"


def closing(responses) -> str:
    """Tilt at closing (median, median |tilt|) over the openings with a sample in the window, and how many rolled;
    an opening whose trace ends before the window (a simulated trial stops once the body has righted) has none."""
    c = np.array([r.closing_tilt_deg for r in responses])
    c = c[np.isfinite(c)]
    rolled = [r.rolled_s for r in responses if np.isfinite(r.rolled_s)]
    at = f" at {np.median(rolled):.2f} s" if rolled else ""
    tilt = f"{np.median(c):+.1f}° ({np.median(np.abs(c)):.1f}°)" if len(c) else "–"
    missing = len(responses) - len(c)
    gone = f" ({missing} without a sample)" if missing else ""
    return f"{tilt}; {len(rolled)}/{len(responses)}{at}{gone}"


def saddle_tilt_deg(robot: str, theta_w_deg: float) -> float:
    """The rigid model's roll-wise saddle as a lateral tilt, degrees (every wing joint at ``theta_w_deg``)."""
    import landscape
    from geometry.robots import load_robot
    from landscape.analysis.physical.response import lateral_tilt_deg

    b = landscape.compute(load_robot(robot), theta_w_deg=theta_w_deg, method="exact").barrier.righting
    return float(lateral_tilt_deg(b.saddle_pitch_deg, b.saddle_roll_deg))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--trials", type=int, default=5, help="simulated first openings per cell and set")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cells", default=None, help="only these cells, WING:LEG,... [default: all]")
    ap.add_argument(
        "--phase", type=float, default=None, help="every first opening at this leg phase in [0, 1)"
    )
    add_set_options(ap, "paper,physical")
    args = ap.parse_args(argv)
    if args.phase is not None and not 0.0 <= args.phase < 1.0:
        ap.exit(2, f"{ap.prog}: error: --phase must lie in [0, 1); got {args.phase!r}\n")
    models = args.models.split(",")
    with tempfile.TemporaryDirectory(prefix="opening_transient_") as tmp:
        try:
            return _run(args, models, Path(tmp))
        except UsageError as exc:  # bad cells, sets or --vary: one line, as the landscape command does
            ap.exit(2, f"{ap.prog}: error: {exc}\n")


def _run(args, models: list[str], tmp: Path) -> int:
    variants = dict(variant_sets(models[0], models[0], args.vary, args.fixed, tmp))
    plateau = measured_plateaus_deg(args.data)
    openings = recorded_first_openings(args.data)
    available = {(o.theta_w_cmd_deg, o.theta_l_deg) for o in openings}
    wanted = set(parse_cells(args.cells, available))
    cells, gyro = defaultdict(list), defaultdict(list)
    for o in openings:
        if (o.theta_w_cmd_deg, o.theta_l_deg) in wanted:
            cells[(o.theta_w_cmd_deg, o.theta_l_deg)].append(o.response)
            gyro[(o.theta_w_cmd_deg, o.theta_l_deg)].append(o.gyro_deviation_deg)
    runs = {m: m for m in models} | variants
    jobs = [(c, m) for c in sorted(cells) for m in runs]
    sims = defaultdict(list)
    with tqdm(total=len(jobs) * args.trials, unit="trial", file=sys.stderr) as bar:
        for (w, leg), m in jobs:
            wing = w if simulates_commands(runs[m]) else plateau[w]
            phases = (
                cell_phases(w, leg, args.trials, args.seed)
                if args.phase is None
                else [args.phase] * args.trials
            )
            for k, ph in enumerate(phases):
                sims[(w, leg, m)].append(
                    simulated_opening(
                        wing, leg, phase=ph, seed=args.seed + k, robot=args.robot, model_set=runs[m]
                    )
                )
                bar.update()
    at = "the validation's random phases" if args.phase is None else f"phase {args.phase:g}"
    print(f"robot {Path(args.robot).name}; {args.trials} simulated first openings a cell and set at {at}; "
          "overshoot / signed tilt (median |tilt|), medians")  # fmt: skip
    head = ["wing cmd", "leg", "robot (n)"] + models
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    ratio = defaultdict(list)
    for (w, leg), rec in sorted(cells.items()):
        row = [f"{w:g}°", f"{leg:g}°", f"{summary(rec)} ({len(rec)})"]
        for m in models:
            row.append(summary(sims[(w, leg, m)]))
            if leg > 0:
                ratio[m].append(
                    np.median(np.abs([r.tilt_deg for r in rec]))
                    / max(np.median(np.abs([r.tilt_deg for r in sims[(w, leg, m)]])), 1e-9)
                )
        print("| " + " | ".join(row) + " |")
    for m in models:
        if ratio[m]:
            print(f"{m}: robot's median |tilt| / simulated, cells with the leg moving: median "
                  f"{np.median(ratio[m]):.1f}x (range {min(ratio[m]):.1f}-{max(ratio[m]):.1f}x)")  # fmt: skip
    print("\nhold wobble, 0.5-0.95 s: standard deviation of pitch / of tilt, medians")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for (w, leg), rec in sorted(cells.items()):
        row = [f"{w:g}°", f"{leg:g}°", f"{wobble(rec)} ({len(rec)})"] + [
            wobble(sims[(w, leg, m)]) for m in models
        ]
        print("| " + " | ".join(row) + " |")
    keys = sorted(cells)
    saddle = {w: saddle_tilt_deg(args.robot, plateau[w]) for w in sorted({w for w, _ in keys})}
    print("\nwhen the wings start closing: signed tilt 0.95-1.05 s, median (median |tilt|); first openings rolled "
          "past 45° within 1.4 s, median time; robot's recorded tilt against its gyro's, -0.3 to 1.05 s, median "
          "(largest) difference; the rigid model's roll-wise saddle as a tilt (leg centred, every wing joint at "
          "the measured plateau)")  # fmt: skip
    head3 = ["wing cmd", "leg", "saddle", "robot (n)", "gyro", *runs]
    print("| " + " | ".join(head3) + " |")
    print("|" + "---|" * len(head3))
    for w, leg in keys:
        g = gyro[(w, leg)]
        row = [f"{w:g}°", f"{leg:g}°", f"{saddle[w]:.1f}°", f"{closing(cells[(w, leg)])} ({len(cells[(w, leg)])})",
               f"{np.nanmedian(g):.1f}° ({np.nanmax(g):.1f}°)"] + [closing(sims[(w, leg, m)]) for m in runs]  # fmt: skip
        print("| " + " | ".join(row) + " |")
    if variants:
        print(
            "\nmedian |tilt| of the first opening; hold wobble: pitch / tilt standard deviation; robot and variants"
        )
        print("| set | " + " | ".join(f"{w:g}°/{leg:g}°" for w, leg in keys) + " |")
        print("|" + "---|" * (len(keys) + 1))
        rows = {"robot": cells} | {m: {c: sims[(*c, m)] for c in keys} for m in [models[0], *variants]}
        for m, by_cell in rows.items():
            vals = [
                f"{np.median(np.abs([r.tilt_deg for r in by_cell[c]])):.1f}°; {wobble(by_cell[c])}"
                for c in keys
            ]
            print(f"| {m} | " + " | ".join(vals) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
