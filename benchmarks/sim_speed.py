"""Speed of the self-righting simulation (a benchmark, not a unit test).

1. Core-seconds (process CPU time) per simulated 10 s trial, against the first version's configuration measured
   in the same run (the baseline: servos commanded every physics step, one ``stepSimulation`` call per step,
   50 solver iterations, dt 2e-4 s). The trial (theta_w 70, theta_l 20, phi_1 0.7, no noise) does not right, so
   it runs the full 10 s, plus 0.5 s of settling. The rows run interleaved, ``--repeat`` rounds, and each number
   is the best of its rounds, so load from other jobs affects all rows alike; the ratio to the baseline is the
   number to read.
2. Where the time of one such trial goes at the default dt: CPU time inside pybullet's ``stepSimulation`` (timed
   by wrapping it) and everything else (Python, model and world set-up), best of ``--repeat``.
3. Trials per second of a small sweep on all cores (a local process pool; includes worker start-up), and the
   mean core-seconds per trial of that sweep, on the default robot at its default dt.
4. The two engines side by side (``--engines-only`` runs this alone), interleaved in one run, best of
   ``--repeat``: core-seconds per simulated second (the trial of 1.) and per trial (the mean over a small grid,
   ``ENGINE_GRID``, of trials that stop when decided), each engine at its default dt and both at the dt of the
   other, with MuJoCo's ratio to pybullet at the same dt, MuJoCo also with every trial settling afresh (its trials
   reuse the settled state by default: ``Numerics.reuse_settled``); and where the time of MuJoCo's 10 s trial
   goes (inside ``mj_step`` and elsewhere), the most batching (``mujoco.rollout``) could take off.

Run:  .venv/bin/python benchmarks/sim_speed.py [--lab] [--repeat 3] [--sweep-trials 8] [--workers N]
      [--split-only | --engines-only]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import tempfile
import time
from pathlib import Path

import sim.world as world
from sim.model import default_robot_urdf
from sim.protocol import MUJOCO_DT_S
from sim.sweep import run_sweep, sweep_specs
from sim.trial import DEFAULT_DT_S, OTHER_ROBOT_DT_S, Numerics, run_trial
from sim.world import Contact

LAB_URDF = Path(__file__).resolve().parents[1].parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
CASE = dict(theta_w_deg=70.0, theta_l_deg=20.0, phase=0.7, cv=0.0, rng=1, duration_s=10.0)
BASELINE = (
    "first version (baseline): servo every step, 50 iterations, dt 2e-4",
    dict(numerics=Numerics(control_period_s=None), contact=Contact(solver_iterations=50), dt_s=2e-4),
)
ROWS = {
    "built-in": (
        BASELINE,
        ("servo every 1 ms + sub-steps, 20 iterations, dt 2e-4", dict(dt_s=2e-4)),
        ("dt 5e-4 (the default before the borderline convergence criterion)", dict(dt_s=5e-4)),
        (
            f"**default: dt {DEFAULT_DT_S:g}** (the borderline convergence criterion's; docs/sim.md)",
            dict(dt_s=DEFAULT_DT_S),
        ),
        (
            f"dt {DEFAULT_DT_S:g}, fixed links merged",
            dict(dt_s=DEFAULT_DT_S, numerics=Numerics(merge_fixed_links=True)),
        ),
        (f"dt {DEFAULT_DT_S:g}, full hulls", dict(dt_s=DEFAULT_DT_S, numerics=Numerics(hull_tol_m=0.0))),
    ),
    "lab": (
        BASELINE,
        (f"default for other robots: dt {OTHER_ROBOT_DT_S:g}", dict(dt_s=OTHER_ROBOT_DT_S)),
    ),
}


ENGINE_GRID = tuple((tw, tl, seed) for tw in (70.0, 76.0) for tl in (20.0, 50.0) for seed in (1, 2))
"""(theta_w, theta_l, seed) of the per-trial cost (phi_1 0.7, Cv 0.1): the paper's corners, two seeds each."""


def engine_table(repeat: int) -> list[tuple[str, float, float, float]]:
    """(row, dt, best core-s per simulated s, best mean core-s per trial) of each engine at each default dt, and
    of MuJoCo with every trial settling afresh (``Numerics(reuse_settled=False)``: what the trials cost before
    they reused the settled state), the rows interleaved over ``repeat`` rounds. Per simulated second every
    trial settles (0.5 s simulated too)."""
    fresh = Numerics(reuse_settled=False)
    rows = [
        (label, e, dt, num)
        for dt in sorted({DEFAULT_DT_S, MUJOCO_DT_S}, reverse=True)
        for label, e, num in (
            ("pybullet", "pybullet", Numerics()),
            ("mujoco", "mujoco", Numerics()),
            ("mujoco, every trial settles", "mujoco", fresh),
        )
    ]
    for _, engine, dt, num in rows:
        run_trial(
            **{**CASE, "duration_s": 0.2}, dt_s=dt, engine=engine, numerics=num
        )  # build the model first
    per_s = [float("inf")] * len(rows)
    per_trial = [float("inf")] * len(rows)
    for _ in range(repeat):
        for k, (_, engine, dt, num) in enumerate(rows):
            r = run_trial(**CASE, dt_s=dt, engine=engine, numerics=fresh)
            per_s[k] = min(per_s[k], r.cpu_s / (r.sim_s + 0.5))  # settling is simulated too
            cpu = [
                run_trial(tw, tl, phase=0.7, cv=0.1, rng=seed, dt_s=dt, engine=engine, numerics=num).cpu_s
                for tw, tl, seed in ENGINE_GRID
            ]
            per_trial[k] = min(per_trial[k], sum(cpu) / len(cpu))
    return [(label, dt, a, b) for (label, _, dt, _), a, b in zip(rows, per_s, per_trial, strict=True)]


def mujoco_split(repeat: int) -> tuple[float, float]:
    """(CPU s inside ``mj_step``, CPU s elsewhere) of the trial of 1. in MuJoCo at its default dt, best of
    ``repeat``."""
    from sim.mujoco_world import MujocoWorld

    original = MujocoWorld._step
    inside = [0.0]

    def timed(self, n_steps):
        t = time.process_time()
        try:
            original(self, n_steps)
        finally:
            inside[0] += time.process_time() - t

    run_trial(**{**CASE, "duration_s": 0.2}, engine="mujoco")
    best = None
    try:
        MujocoWorld._step = timed
        for _ in range(repeat):
            inside[0] = 0.0
            r = run_trial(**CASE, engine="mujoco", numerics=Numerics(reuse_settled=False))
            if best is None or r.cpu_s < sum(best):
                best = (inside[0], r.cpu_s - inside[0])
    finally:
        MujocoWorld._step = original
    return best


def _print_engines(repeat: int) -> None:
    print(f"\n## The engines side by side (built-in robot, best of {repeat} interleaved rounds)\n")
    print("| engine | dt (s) | core-s per simulated s | core-s per trial | MuJoCo / pybullet per trial |")
    print("|---|---:|---:|---:|---:|")
    table = engine_table(repeat)
    pb = {dt: t for e, dt, _, t in table if e == "pybullet"}
    for e, dt, s, t in table:
        ratio = f"{t / pb[dt]:.2f}" if e != "pybullet" else "-"
        print(f"| {e} | {dt:g} | {s:.4f} | {t:.3f} | {ratio} |", flush=True)
    inside, other = mujoco_split(repeat)
    print(f"\nMuJoCo at dt {MUJOCO_DT_S:g} s, one 10 s trial: {inside:.3f} core-s inside mj_step, {other:.3f} elsewhere "
          f"({inside / (inside + other):.0%} inside)")  # fmt: skip


def core_s_table(robots: dict[str, Path], repeat: int) -> list[tuple[str, str, float]]:
    """Best core-s per 10 s trial of every (robot, row), the rows interleaved over ``repeat`` rounds."""
    jobs = [
        (rname, name, {"robot": path, **kw}) for rname, path in robots.items() for name, kw in ROWS[rname]
    ]
    for _, _, kw in jobs:
        run_trial(**{**CASE, "duration_s": 0.2}, **kw)  # build and cache the model first
    best = [float("inf")] * len(jobs)
    for _ in range(repeat):
        for k, (_, _, kw) in enumerate(jobs):
            r = run_trial(**CASE, **kw)
            best[k] = min(best[k], r.cpu_s * 10.0 / r.sim_s)
    return [(rname, name, b) for (rname, name, _), b in zip(jobs, best, strict=True)]


def step_split(repeat: int) -> tuple[float, float, int]:
    """(CPU s inside stepSimulation, CPU s elsewhere, physics steps) of one trial, best of ``repeat``."""
    original = world.pb.stepSimulation
    inside = [0.0]

    def timed(*a, **k):
        t = time.process_time()
        try:
            return original(*a, **k)
        finally:
            inside[0] += time.process_time() - t

    run_trial(**{**CASE, "duration_s": 0.2})
    best = None
    try:
        world.pb.stepSimulation = timed
        for _ in range(repeat):
            inside[0] = 0.0
            r = run_trial(**CASE)
            if best is None or r.cpu_s < best[0] + best[1]:
                best = (inside[0], r.cpu_s - inside[0], int(round((r.sim_s + 0.5) / r.dt_s)))
    finally:
        world.pb.stepSimulation = original
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lab", action="store_true", help="also time the lab robot (../shared/ref/lab_robot)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--sweep-trials", type=int, default=8)
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--split-only", action="store_true", help="only section 2")
    ap.add_argument("--engines-only", action="store_true", help="only section 4 (needs the mujoco extra)")
    args = ap.parse_args()
    if args.split_only:
        _print_split(args.repeat)
        return
    if args.engines_only:
        _print_engines(args.repeat)
        return

    robots = {"built-in": default_robot_urdf()}
    if args.lab and LAB_URDF.is_file():
        robots["lab"] = LAB_URDF
    print(f"## Core-seconds per simulated 10 s trial (best of {args.repeat} interleaved rounds)\n")
    print("| robot | configuration | core-s per 10 s trial | ratio to baseline |")
    print("|---|---|---:|---:|")
    table = core_s_table(robots, args.repeat)
    base = {rname: c for rname, name, c in table if name == BASELINE[0]}
    for rname, name, c in table:
        print(f"| {rname} | {name} | {c:.2f} | {c / base[rname]:.2f} |", flush=True)

    _print_split(args.repeat)
    print(
        f"\n## Sweep on {args.workers} worker processes ({args.sweep_trials} trials, theta_w 70/76, theta_l 20/50, "
        f"Cv 0.1, built-in robot, dt {DEFAULT_DT_S:g} s, 10 s)\n"
    )
    n_per = max(1, args.sweep_trials // 4)
    specs = sweep_specs((70.0, 76.0), (20.0, 50.0), (0.1,), trials=n_per)
    with tempfile.TemporaryDirectory() as d:
        s = run_sweep(specs, db=Path(d) / "speed.sqlite", workers=args.workers, progress=False)
    print("| trials | wall s | trials/s | mean core-s per trial |")
    print("|---:|---:|---:|---:|")
    print(f"| {s.ran} | {s.wall_s:.1f} | {s.trials_per_s:.3f} | {s.cpu_s / s.ran:.2f} |")
    if importlib.util.find_spec("mujoco") is not None:
        _print_engines(args.repeat)


def _print_split(repeat: int) -> None:
    inside, other, steps = step_split(repeat)
    print(
        f"\n## Where one 10 s trial's time goes (built-in robot, dt {DEFAULT_DT_S:g} s, best of {repeat})\n"
    )
    print("| inside stepSimulation (core-s) | elsewhere (core-s) | physics steps | µs per step |")
    print("|---:|---:|---:|---:|")
    print(f"| {inside:.3f} | {other:.3f} | {steps} | {inside / steps * 1e6:.1f} |", flush=True)


if __name__ == "__main__":
    main()
