"""The first wing opening, robot against simulation: does the model move like the robot? (issue #15)

Per physical cell (wing command x leg amplitude), the first opening of each recorded trial beside simulated
first openings of each model set (random first-attempt phases, the validation's, no noise), measured by the same
code (``landscape.analysis.opening``): the pitch overshoot past the hold, the rise time, and the lateral tilt of
largest magnitude 0.2-0.6 s after the opening starts (``asin(cos p sin r)``, degrees; positive towards positive
roll). Medians over the trials; in brackets, the median |tilt|.

With ``--vary TABLE.KEY=V1,V2`` (repeatable) each value is also tried on its own in a copy of the first set
(``landscape.analysis.calibration.candidate_set``), one key at a time, and a last table gives each variant's
median |tilt| per cell beside the robot's; ``--cells 60:30,60:45`` limits the cells.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/opening_transient.py [--data DIR] [--robot URDF]
      [--models paper,physical] [--trials 5] [--seed 0] [--cells W:L,...] [--vary TABLE.KEY=V1,V2 ...]
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
from landscape.analysis.calibration import candidate_set, parse_vary
from landscape.analysis.opening import recorded_first_openings, simulated_opening
from landscape.analysis.physical import measured_plateaus_deg
from landscape.analysis.validation import cell_phases, parse_cells, simulates_commands

ROOT = Path(__file__).resolve().parents[1]


def summary(responses) -> str:
    over = np.median([r.overshoot_deg for r in responses])
    tilt = np.array([r.tilt_deg for r in responses])
    return f"{over:+.1f}° / {np.median(tilt):+.1f}° ({np.median(np.abs(tilt)):.1f}°)"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--models", default="paper,physical")
    ap.add_argument("--trials", type=int, default=5, help="simulated first openings per cell and set")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cells", default=None, help="only these cells, WING:LEG,... [default: all]")
    ap.add_argument("--vary", action="append", default=[], help="TABLE.KEY=V1,V2: variants of the first set")
    args = ap.parse_args(argv)
    models = args.models.split(",")
    with tempfile.TemporaryDirectory(prefix="opening_transient_") as tmp:
        try:
            return _run(args, models, Path(tmp))
        except UsageError as exc:  # bad cells, sets or --vary: one line, as the landscape command does
            ap.exit(2, f"{ap.prog}: error: {exc}\n")


def _run(args, models: list[str], tmp: Path) -> int:
    variants = {}
    for key, values in (parse_vary(args.vary) if args.vary else {}).items():
        for v in values:
            name = f"{models[0]}+{key}={v:g}"
            variants[name] = str(
                candidate_set(models[0], {key: v}, name, tmp / f"v{len(variants)}.toml").source
            )
    plateau = measured_plateaus_deg(args.data)
    openings = recorded_first_openings(args.data)
    available = {(o.theta_w_cmd_deg, o.theta_l_deg) for o in openings}
    wanted = set(parse_cells(args.cells, available))
    cells = defaultdict(list)
    for o in openings:
        if (o.theta_w_cmd_deg, o.theta_l_deg) in wanted:
            cells[(o.theta_w_cmd_deg, o.theta_l_deg)].append(o.response)
    runs = {m: m for m in models} | variants
    jobs = [(c, m) for c in sorted(cells) for m in runs]
    sims = defaultdict(list)
    with tqdm(total=len(jobs) * args.trials, unit="trial", file=sys.stderr) as bar:
        for (w, leg), m in jobs:
            wing = w if simulates_commands(runs[m]) else plateau[w]
            for k, ph in enumerate(cell_phases(w, leg, args.trials, args.seed)):
                sims[(w, leg, m)].append(
                    simulated_opening(
                        wing, leg, phase=ph, seed=args.seed + k, robot=args.robot, model_set=runs[m]
                    )
                )
                bar.update()
    print(f"robot {Path(args.robot).name}; {args.trials} simulated first openings a cell and set; "
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
    if variants:
        keys = sorted(cells)
        print("\nmedian |tilt| of the first opening, robot and each variant")
        print("| set | " + " | ".join(f"{w:g}°/{leg:g}°" for w, leg in keys) + " |")
        print("|" + "---|" * (len(keys) + 1))
        print(
            "| robot | "
            + " | ".join(f"{np.median(np.abs([r.tilt_deg for r in cells[c]])):.1f}°" for c in keys)
            + " |"
        )
        for m in [models[0], *variants]:
            vals = [np.median(np.abs([r.tilt_deg for r in sims[(*c, m)]])) for c in keys]
            print(f"| {m} | " + " | ".join(f"{v:.1f}°" for v in vals) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
