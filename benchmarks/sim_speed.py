"""Speed of the self-righting simulation (a benchmark, not a unit test).

1. Core-seconds (process CPU time) per simulated 10 s trial: the old configuration (the baseline: servos
   commanded every physics step, one ``stepSimulation`` call per step, 50 solver iterations) and the new default
   (servos commanded every 1 ms with pybullet sub-stepping, 20 solver iterations), both at the default dt and
   measured in the same run, with the steps in between and the options that are not the default. The trial
   (theta_w 70, theta_l 20, phi_1 0.7, no noise) does not right, so it runs the full 10 s, plus 0.5 s of
   settling. The rows run interleaved, ``--repeat`` rounds, and each number is the best of its rounds, so load
   from other jobs affects all rows alike; the ratio to the baseline is the number to read.
2. Trials per second of a small sweep on all cores (a local process pool; includes worker start-up), and the
   mean core-seconds per trial of that sweep.

Run:  /work/venv/bin/python benchmarks/sim_speed.py [--robot URDF] [--repeat 3] [--sweep-trials 8] [--workers N]
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

from sim.sweep import run_sweep, sweep_specs
from sim.trial import DEFAULT_DT_S, run_trial
from sim.world import Contact

LAB_URDF = Path(__file__).resolve().parents[1].parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
CASE = dict(theta_w_deg=70.0, theta_l_deg=20.0, phase=0.7, cv=0.0, rng=1, duration_s=10.0)
OLD = dict(control_period_s=None, contact=Contact(solver_iterations=50))
ROWS = (
    ("old configuration (baseline): servo every step, 50 iterations", OLD),
    ("servo every 1 ms + pybullet sub-steps, 50 iterations", dict(contact=Contact(solver_iterations=50))),
    ("new default: servo every 1 ms + sub-steps, 20 iterations", {}),
    ("servo every 1 ms + sub-steps, 10 iterations", dict(contact=Contact(solver_iterations=10))),
    ("new default + fixed links merged (fails the convergence criterion)", dict(merge_fixed_links=True)),
    ("new default, full hulls", dict(hull_tol_m=0.0)),
    ("new default at dt = 5e-4 (fails the convergence criterion)", dict(dt_s=5e-4)),
)


def core_s_table(robots: dict[str, Path], repeat: int) -> list[tuple[str, str, float]]:
    """Best core-s per 10 s trial of every (robot, row), the rows interleaved over ``repeat`` rounds."""
    jobs = [(rname, name, {"robot": path, "dt_s": DEFAULT_DT_S, **kw}) for rname, path in robots.items()
            for name, kw in (ROWS if rname == "lab" else (ROWS[0], ROWS[2]))]
    for _, _, kw in jobs:
        run_trial(**{**CASE, "duration_s": 0.2}, **kw)  # build and cache the model first
    best = [float("inf")] * len(jobs)
    for _ in range(repeat):
        for k, (_, _, kw) in enumerate(jobs):
            r = run_trial(**CASE, **kw)
            best[k] = min(best[k], r.cpu_s * 10.0 / r.sim_s)
    return [(rname, name, b) for (rname, name, _), b in zip(jobs, best, strict=True)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robot", type=Path, default=LAB_URDF, help="URDF (default: the lab robot)")
    ap.add_argument("--builtin", action="store_true", help="also time the built-in robot (geometry.builtin)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--sweep-trials", type=int, default=8)
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    args = ap.parse_args()

    robots = {"lab": args.robot}
    if args.builtin:
        from geometry.builtin import builtin_urdf_path  # type: ignore[import-not-found]

        robots["built-in"] = Path(builtin_urdf_path())
    print(f"## Core-seconds per simulated 10 s trial (dt = {DEFAULT_DT_S:g} s unless stated, best of {args.repeat} "
          "interleaved rounds)\n")
    print("| robot | configuration | core-s per 10 s trial | ratio to old |")
    print("|---|---|---:|---:|")
    table = core_s_table(robots, args.repeat)
    base = {rname: c for rname, name, c in table if name == ROWS[0][0]}
    for rname, name, c in table:
        print(f"| {rname} | {name} | {c:.2f} | {c / base[rname]:.2f} |", flush=True)

    print(f"\n## Sweep on {args.workers} worker processes ({args.sweep_trials} trials, theta_w 70/76, theta_l 20/50, "
          f"Cv 0.1, dt {DEFAULT_DT_S:g} s, 10 s, new default)\n")
    n_per = max(1, args.sweep_trials // 4)
    specs = sweep_specs((70.0, 76.0), (20.0, 50.0), (0.1,), trials=n_per, robot=args.robot)
    with tempfile.TemporaryDirectory() as d:
        s = run_sweep(specs, db=Path(d) / "speed.sqlite", workers=args.workers, progress=False)
    print("| trials | wall s | trials/s | mean core-s per trial |")
    print("|---:|---:|---:|---:|")
    print(f"| {s.ran} | {s.wall_s:.1f} | {s.trials_per_s:.3f} | {s.cpu_s / s.ran:.2f} |")


if __name__ == "__main__":
    main()
