"""Regenerate the figures the README shows for the source paper's Figs. 5-9 and barrier against outcome from a
fresh clone: the barrier map (Fig. 5, `landscape barrier-map` into figures/barrier_map/), the four sweeps into
one database (they resume, so an interrupted run loses nothing), then `landscape report`, and copy its figures
and tables into figures/analysis/.

    python figures/make_figures.py [--db figures/results.sqlite] [--workers N] [--check] [--quick] [--dry-run]
    python figures/make_figures.py --only barrier-map
    python figures/make_figures.py --engine mujoco [--db figures/mujoco/results.sqlite]

Every step is a `landscape` command, printed with its number before it runs ("[2/6] ..."), with the elapsed and
the estimated remaining time after it; the sweeps and the barrier map draw their own progress bars on a terminal.
The table at the end gives each step's wall time. The database is not committed (it is output); the figures and
CSV tables are.

``--quick`` runs a reduced version of every step (a coarse barrier map, a few trials per sweep: minutes, not half
an hour) into figures/quick/ (database, report and figures), leaving the committed figures alone; it checks that
the whole chain works, not the paper's numbers. ``--only barrier-map`` runs the first step alone (seconds): it
regenerates figures/barrier_map/, the heat map of the README and the docs' front page, with the same command and
grid as the README's tour, which writes to barrier-map/ instead. ``--dry-run`` prints the steps without running
them. ``--engine mujoco`` runs the sweeps in MuJoCo instead of pybullet, into figures/mujoco/ (database, report,
figures and tables), the other engine's side of docs/concepts/engines.md.
"""

from __future__ import annotations

import argparse
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import NamedTuple

from landscape.viz.sections import PAPER_SWEEP, PHASE_MAP_SWEEP, PHASE_MAP_TL_SWEEP, PREDICTION_SWEEP

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ("probability", "phase_map", "prediction", "evolution", "barrier_outcome")
TABLES = ("probability", "phase_map", "prediction_accuracy", "evolution", "barrier_outcome", "barrier_stats")


def _args(command: str) -> str:
    """A `landscape sweep … --db {db}` line of landscape.viz.sections as arguments without the program and --db."""
    return command.removeprefix("landscape ").replace(" --db {db}", "")


BARRIER_MAP = "barrier-map --theta-w 60:90:2 --theta-l 0:50:10"
SWEEPS = (
    ("single-attempt phase map (320 trials)", _args(PHASE_MAP_SWEEP)),
    ("phase maps at other leg periods (80 trials)", _args(PHASE_MAP_TL_SWEEP)),
    ("multi-attempt prediction study (300 trials)", _args(PREDICTION_SWEEP)),
    ("the paper's sweep (3840 trials)", _args(PAPER_SWEEP)),
)
QUICK_BARRIER_MAP = "barrier-map --theta-w 60:90:10 --theta-l 0:50:25"
QUICK_SWEEPS = (
    # the same sweeps on fewer values: each option of the full step, a subset of its values
    (
        "single-attempt phase map, reduced (16 trials)",
        "sweep --theta-w 72,76 --theta-l 30,50 --cv 0 --phase 0:0.75:0.25 --trials 1 --attempts 1",
    ),
    (
        "phase maps at other leg periods, reduced (4 trials)",
        "sweep --theta-w 72 --theta-l 30 --cv 0 --phase 0:0.5:0.5 --trials 1 --attempts 1 --leg-period 0.6,1.4",
    ),
    (
        "multi-attempt prediction study, reduced (8 trials)",
        "sweep --theta-w 72 --theta-l 30 --cv 0 --phase 0:0.5:0.5 --trials 1 --wing-period 2,3 --leg-period 0.8,1.2",
    ),
    ("the paper's sweep, reduced (24 trials)", "sweep --theta-w 70,76 --theta-l 20,50 --cv 0,0.2 --trials 3"),
)


class Step(NamedTuple):
    """One `landscape` command of the regeneration."""

    name: str
    args: str


def plan(
    *, quick: bool, db: Path, out: Path, workers: int | None, check: bool, engine: str = "pybullet"
) -> list[Step]:
    """The steps, in order: the barrier map, the four sweeps into ``db`` (in ``engine``), the report into
    ``out / 'report'``."""
    w = (f" --engine {engine}" if engine != "pybullet" else "") + (f" --workers {workers}" if workers else "")
    bm, sweeps = (QUICK_BARRIER_MAP, QUICK_SWEEPS) if quick else (BARRIER_MAP, SWEEPS)
    steps = [
        Step(
            "barrier map, reduced" if quick else "barrier map, 96 poses (Fig. 5)",
            f"{bm} --out {out / 'barrier_map'}",
        )
    ]
    steps += [Step(name, f"{args} --db {db}{w}") for name, args in sweeps]
    steps.append(
        Step(
            "report (barriers, statistics, figures)",
            f"report --db {db} --out {out / 'report'}" + (" --check" if check else ""),
        )
    )
    return steps


def _clock(s: float) -> str:
    return f"{int(s // 60)} min {s % 60:02.0f} s" if s >= 60 else f"{s:.0f} s"


def run(step: Step, k: int, n: int, t_start: float, done_s: list[float]) -> float:
    """Run step ``k`` of ``n``, printing its number before and the elapsed and remaining time after."""
    print(f"\n[{k}/{n}] {step.name}\n$ landscape {step.args}", flush=True)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "landscape", *shlex.split(step.args)], check=True, cwd=ROOT)
    dt = time.perf_counter() - t0
    done_s.append(dt)
    print(
        f"[{k}/{n}] done in {_clock(dt)}; {_clock(time.perf_counter() - t_start)} elapsed, {n - k} step"
        f"{'s' if n - k != 1 else ''} left",
        flush=True,
    )
    return dt


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--db",
        type=Path,
        default=None,
        help="trial database [default: figures/results.sqlite; --quick: figures/quick/results.sqlite]",
    )
    ap.add_argument("--workers", type=int, default=None, help="local worker processes [default: all cores]")
    ap.add_argument("--check", action="store_true", help="also open the report in headless Chromium")
    ap.add_argument(
        "--quick",
        action="store_true",
        help="a reduced version of every step into figures/quick/ (minutes; committed figures untouched)",
    )
    ap.add_argument(
        "--only",
        choices=["barrier-map"],
        default=None,
        help="run one step alone: barrier-map regenerates figures/barrier_map/ (seconds)",
    )
    ap.add_argument(
        "--engine",
        choices=["pybullet", "mujoco"],
        default="pybullet",
        help="the sweeps' engine; mujoco writes into figures/mujoco/ (or figures/quick/mujoco/) [default: pybullet]",
    )
    ap.add_argument("--dry-run", action="store_true", help="print the steps and exit")
    args = ap.parse_args(argv)
    out = ROOT / "figures" / ("quick" if args.quick else "") / ("mujoco" if args.engine == "mujoco" else "")
    db = args.db or out / "results.sqlite"
    steps = plan(quick=args.quick, db=db, out=out, workers=args.workers, check=args.check, engine=args.engine)
    if args.only == "barrier-map":
        steps = steps[:1]
    if args.dry_run:
        for k, s in enumerate(steps, 1):
            print(f"[{k}/{len(steps)}] {s.name}\n$ landscape {s.args}")
        return
    out.mkdir(parents=True, exist_ok=True)
    t_start, times = time.perf_counter(), []
    for k, step in enumerate(steps, 1):
        run(step, k, len(steps), t_start, times)
    if args.only:
        return
    analysis, report = out / "analysis", out / "report"
    analysis.mkdir(parents=True, exist_ok=True)
    missing = []
    for name in [f"{s}.png" for s in FIGURES] + [f"{s}.csv" for s in TABLES]:
        if (report / name).is_file():
            shutil.copy2(report / name, analysis / name)
        elif args.quick:  # a reduced sweep may lack the data of an analysis; the report says which
            missing.append(name)
        else:
            raise SystemExit(f"the report wrote no {name}; see {report / 'index.html'}")
    print("\n| step | wall time (s) |\n|---|---:|")
    for s, t in zip(steps, times, strict=True):
        print(f"| {s.name} | {t:.0f} |")
    print(f"| total | {sum(times):.0f} |")
    print(
        f"\nfigures and tables in {analysis.relative_to(ROOT)}; the page is {(report / 'index.html').relative_to(ROOT)}"
        + (f"; not in the reduced data: {', '.join(missing)}" if missing else "")
    )


if __name__ == "__main__":
    main()
