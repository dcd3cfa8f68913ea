"""The held body's lean with the leg on each side, robot against simulation (issue #15).

On its back with the wings held open, the robot swings its pendulum leg from side to side; per cell with the
leg moving, this compares how far the held body leans with the leg on + and on - (``hold_leans_deg``: the
median lateral tilt ``asin(cos p sin r)`` of each window from 0.2 s after the leg reaches a side until it leaves
it, 0.4-1.0 s after the opening starts, ending 0.3 s before the body passes a tilt of 40 deg or becomes upright;
the robot's leg reaches its side 0.1 s after the command) between the robot (every opening until it first
becomes upright) and one simulated trial per model set (``--attempts`` openings from the protocol's leg phase,
no noise; the leg's side is the sign of the simulated leg angle). Medians over the windows, with their number.
A second table gives when the openings that roll over leave the level (``departure_s``: the last time the tilt
rose through 5 deg before passing 45 deg), the median over those that rolled, and how many did.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/hold_lean.py [--data DIR] [--robot URDF]
      [--models paper,physical] [--attempts 3] [--seed 0] [--phase 0.17] [--cells W:L,...]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from geometry.errors import UsageError
from landscape.analysis.physical.lean import cell_lean, recorded_leans, simulated_leans
from landscape.analysis.physical.recording import measured_plateaus_deg
from landscape.analysis.physical.response import PROTOCOL_PHASE
from landscape.analysis.physical.validation import parse_cells, simulates_commands
from landscape.viz.physical_plots import departure_text as departure
from landscape.viz.physical_plots import lean_text as lean

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from sim_convergence import Progress  # noqa: E402  (the benchmarks' progress line, #17)

ROOT = Path(__file__).resolve().parents[2]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--models", default="paper,physical")
    ap.add_argument(
        "--attempts", type=int, default=3, help="openings of the simulated trial per cell and set"
    )
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--phase", type=float, default=PROTOCOL_PHASE, help="leg phase of the first opening")
    ap.add_argument("--cells", default=None, help="only these cells, WING:LEG,... [default: all, leg moving]")
    args = ap.parse_args(argv)
    if not 0.0 <= args.phase < 1.0:
        ap.exit(2, f"{ap.prog}: error: --phase must lie in [0, 1); got {args.phase!r}\n")
    if args.attempts < 1:
        ap.exit(2, f"{ap.prog}: error: --attempts must be >= 1; got {args.attempts!r}\n")
    try:
        return _run(args, args.models.split(","))
    except UsageError as exc:  # bad data, cells or sets: one line, as the landscape command does
        ap.exit(2, f"{ap.prog}: error: {exc}\n")


def _run(args, models: list[str]) -> int:
    robot = {cell: cell_lean(*cell, h) for cell, h in recorded_leans(args.data).items()}
    cells = parse_cells(args.cells, robot)
    plateau = measured_plateaus_deg(args.data)
    commands = {m: simulates_commands(m) for m in models}
    sims = {}
    prog = Progress(len(cells) * len(models))
    try:
        for w, leg in cells:
            for m in models:
                wing = w if commands[m] else plateau[w]
                h = simulated_leans(
                    wing, leg, model_set=m, robot=args.robot, seed=args.seed, attempts=args.attempts,
                    phase=args.phase,
                )  # fmt: skip
                sims[(w, leg, m)] = cell_lean(w, leg, h)
                prog.step()
    finally:
        prog.close()
    print(f"robot {Path(args.robot).name}; one simulated trial of {args.attempts} openings a cell and set from "
          f"leg phase {args.phase:g}, seed {args.seed}; median lean (lateral tilt) with the leg on + and on -; "
          "number of windows in brackets")  # fmt: skip
    head = ["wing cmd", "leg", "robot +", "robot −"] + [f"{m} {s}" for m in models for s in "+−"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for w, leg in cells:
        r = robot[(w, leg)]
        row = [f"{w:g}°", f"{leg:g}°", lean(r.plus_deg, r.n_plus), lean(r.minus_deg, r.n_minus)]
        for m in models:
            s = sims[(w, leg, m)]
            row += [lean(s.plus_deg, s.n_plus), lean(s.minus_deg, s.n_minus)]
        print("| " + " | ".join(row) + " |")
    print("\ndeparture from the level of the openings that rolled over (tilt last rising through 5° before "
          "passing 45° within 1.4 s), s after the opening starts: median (rolled/openings)")  # fmt: skip
    head2 = ["wing cmd", "leg", "robot", *models]
    print("| " + " | ".join(head2) + " |")
    print("|" + "---|" * len(head2))
    for w, leg in cells:
        row = [f"{w:g}°", f"{leg:g}°", departure(robot[(w, leg)])]
        row += [departure(sims[(w, leg, m)]) for m in models]
        print("| " + " | ".join(row) + " |")
    shown = [robot[c] for c in cells] + list(sims.values())
    if any(not (c.n_plus and c.n_minus) for c in shown):
        print("\n–: no window on that side (the openings left the hold before the leg settled there)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
