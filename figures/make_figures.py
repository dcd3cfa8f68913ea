"""Regenerate the figures the README shows for the source paper's Figs. 5-9 and barrier against outcome from a
fresh clone: the barrier map (Fig. 5, `landscape barrier-map` into figures/barrier_map/), the four sweeps into
one database (they resume, so an interrupted run loses nothing), then `landscape report`, and copy its figures
and tables into figures/analysis/.

    python figures/make_figures.py [--db figures/results.sqlite] [--workers N] [--check]

Every step is a `landscape` command, printed before it runs; the table at the end gives each step's wall time.
The database is not committed (it is output); the figures and CSV tables are.
"""

from __future__ import annotations

import argparse
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

from landscape.cli.analyze import PAPER_SWEEP, PHASE_MAP_SWEEP, PHASE_MAP_TL_SWEEP, PREDICTION_SWEEP

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "figures" / "analysis"


def _args(command: str) -> str:
    """A `landscape sweep … --db {db}` command of landscape.cli.analyze as arguments without the program and --db."""
    return command.removeprefix("landscape ").replace(" --db {db}", "")


STEPS = (
    ("single-attempt phase map (320 trials)", _args(PHASE_MAP_SWEEP)),
    ("phase maps at other leg periods (80 trials)", _args(PHASE_MAP_TL_SWEEP)),
    ("multi-attempt prediction study (300 trials)", _args(PREDICTION_SWEEP)),
    ("the paper's sweep (3840 trials)", _args(PAPER_SWEEP)),
)
FIGURES = ("probability", "phase_map", "prediction", "evolution", "barrier_outcome")
TABLES = ("probability", "phase_map", "prediction_accuracy", "evolution", "barrier_outcome", "barrier_stats")


def landscape(args: str) -> float:
    cmd = [sys.executable, "-m", "landscape", *shlex.split(args)]
    print("$ landscape " + args, flush=True)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, cwd=ROOT)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--db", type=Path, default=ROOT / "figures" / "results.sqlite")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--check", action="store_true", help="also open the report in headless Chromium")
    args = ap.parse_args()
    workers = f" --workers {args.workers}" if args.workers else ""
    times = [("barrier map, 96 poses (Fig. 5)",
              landscape("barrier-map --theta-w 60:90:2 --theta-l 0:50:10 --out figures/barrier_map"))]
    for name, step in STEPS:
        times.append((name, landscape(f"{step} --db {args.db}{workers} --no-progress")))
    report = ROOT / "figures" / "report"
    times.append(("report (barriers, statistics, figures)",
                  landscape(f"report --db {args.db} --out {report}" + (" --check" if args.check else ""))))
    OUT.mkdir(parents=True, exist_ok=True)
    for stem in FIGURES:
        shutil.copy2(report / f"{stem}.png", OUT / f"{stem}.png")
    for stem in TABLES:
        shutil.copy2(report / f"{stem}.csv", OUT / f"{stem}.csv")
    print("\n| step | wall time (s) |\n|---|---:|")
    for name, t in times:
        print(f"| {name} | {t:.0f} |")
    print(f"| total | {sum(t for _, t in times):.0f} |")
    print(f"\nfigures and tables in {OUT.relative_to(ROOT)}; the page is {(report / 'index.html').relative_to(ROOT)}")


if __name__ == "__main__":
    main()
