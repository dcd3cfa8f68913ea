"""Speed of the self-righting simulation (a benchmark, not a unit test).

1. Core-seconds (process CPU time) per simulated 10 s trial at the default dt with the simplified hulls, against
   two baselines measured in the same run: the full, unsimplified convex hulls at the same dt, and dt = 1e-4.
   The trial (theta_w 70, theta_l 20, phi_1 0.7, no noise) does not right, so it runs the full 10 s, plus 0.5 s
   of settling; each number is the best of ``--repeat`` runs.
2. Trials per second of a small sweep on all cores (a local process pool; includes worker start-up), and the
   mean core-seconds per trial of that sweep.

Run:  /work/venv/bin/python benchmarks/sim_speed.py [--repeat 2] [--sweep-trials 8] [--workers N]
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

from sim.sweep import run_sweep, sweep_specs
from sim.trial import DEFAULT_DT_S, run_trial

CASE = dict(theta_w_deg=70.0, theta_l_deg=20.0, phase=0.7, cv=0.0, rng=1, duration_s=10.0)


def core_s(repeat: int, **kw) -> tuple[float, bool]:
    run_trial(**{**CASE, "duration_s": 0.2}, **kw)  # build and cache the model first
    best, success = float("inf"), False
    for _ in range(repeat):
        r = run_trial(**CASE, **kw)
        best, success = min(best, r.cpu_s * 10.0 / r.sim_s), r.success
    return best, success


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--sweep-trials", type=int, default=8)
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    args = ap.parse_args()

    rows = [("simplified hulls, default dt", dict(dt_s=DEFAULT_DT_S)),
            ("full hulls (baseline), default dt", dict(dt_s=DEFAULT_DT_S, hull_tol_m=0.0)),
            ("simplified hulls, dt = 1e-4 (baseline)", dict(dt_s=1e-4)),
            ("simplified hulls, dt = 1e-3 (fast, not converged)", dict(dt_s=1e-3))]
    print(f"## Core-seconds per simulated 10 s trial (default dt = {DEFAULT_DT_S:g} s, best of {args.repeat})\n")
    print("| model | core-s per 10 s trial | ratio to default |")
    print("|---|---:|---:|")
    ref = None
    for name, kw in rows:
        c, _ = core_s(args.repeat, **kw)
        ref = ref or c
        print(f"| {name} | {c:.2f} | {c / ref:.2f} |", flush=True)

    print(f"\n## Sweep on {args.workers} worker processes ({args.sweep_trials} trials, theta_w 70/76, theta_l 20/50, "
          "Cv 0.1, default dt, 10 s)\n")
    n_per = max(1, args.sweep_trials // 4)
    specs = sweep_specs((70.0, 76.0), (20.0, 50.0), (0.1,), trials=n_per)
    with tempfile.TemporaryDirectory() as d:
        s = run_sweep(specs, db=Path(d) / "speed.sqlite", workers=args.workers, progress=False)
    print("| trials | wall s | trials/s | mean core-s per trial |")
    print("|---:|---:|---:|---:|")
    print(f"| {s.ran} | {s.wall_s:.1f} | {s.trials_per_s:.3f} | {s.cpu_s / s.ran:.2f} |")


if __name__ == "__main__":
    main()
