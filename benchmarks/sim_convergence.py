"""Convergence of the self-righting simulation with the time step and the solver (a benchmark, not a unit test).

The reference is the most accurate setting: dt = 5e-5 s with pybullet's default 50 solver iterations (soft
contact, servos commanded every 1 ms as in every run). Against it:

1. body orientation: the largest angle between world-up in the body frame of the run and of the reference,
   sampled every 10 ms, over the first 1 s and the first 2 s of actuation (three settings of theta_w,
   theta_l, phi_1, no noise), for dt in {1e-3, 5e-4, 2e-4, 1e-4}: soft contact with the default solver
   iterations, soft contact with 50, and pybullet's rigid contact (against a rigid reference);
2. outcomes (success, succeeding attempt, time to right) over a small grid of 12 trials (soft contact, default
   solver iterations);
3. at the chosen dt: 50, 20 and 10 solver iterations, and fixed links merged into their parents;
4. at the chosen dt: the full, unsimplified collision hulls against the simplified ones;
5. success *rates* near the success boundary over many seeds (``--rate-seeds``, Cv 0.1) at the chosen dt and at
   the next smaller dt, with Wilson 95 % intervals and Fisher's exact test: near the boundary single outcomes are
   chaotic, so this is the comparison that says whether the time step changes the answer.

The chosen dt is the largest with < 0.5 deg orientation difference over the first second and the same success
flags as the reference.

``--borderline`` runs the criterion that sets each engine's default step instead: the 100 single attempts of the
source paper's Fig. 8 protocol that lie near the success boundary (theta_w 72 deg, theta_l 30 deg, Tw 2 s, Tl
0.6 ... 1.4 s x 20 phases, no noise), each at a step dt and at dt / 4; the default step is the largest with at
least 95 of 100 outcomes the same. The same attempts turned on the ground by 0.0001, 5, 45 and 90 degrees at the
default step then show that no engine's outcome depends on the robot's heading (``--engines`` picks the engines,
``--workers`` the processes). Prints markdown tables on stdout and its progress on stderr (trials done of the planned
total, elapsed time and ETA: a bar on a terminal, a line every 30 s in a log).

Run:  .venv/bin/python benchmarks/sim_convergence.py [--robot builtin|lab|URDF] [--quick]
      [--grid-theta-w 70,74,76] [--grid-theta-l 20,30] [--rate-seeds 40]
      .venv/bin/python benchmarks/sim_convergence.py --borderline [--engines pybullet,mujoco] [--workers 2]
"""

from __future__ import annotations

import argparse
import itertools
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from geometry import up_vector
from landscape.analysis.trials import wilson_interval
from sim.model import default_robot_urdf
from sim.trial import DEFAULT_DT_S, Numerics
from sim.trial import run_trial as _run_trial
from sim.world import Contact

LAB_URDF = Path(__file__).resolve().parents[1].parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
REF_DT = 5e-5
REF_ITERATIONS = 50
DTS = (1e-3, 5e-4, 2e-4, 1e-4)
ORIENT_CASES = ((76.0, 40.0, 0.7), (80.0, 30.0, 0.2), (72.0, 50.0, 0.45))
GRID_DEFAULTS = {"lab": ("72,76,80", "30,50"), "builtin": ("70,74,76", "20,30")}
"""Outcome grids that straddle each robot's success boundary (docs/sim.md)."""
PHASES = (0.2, 0.7)
CV, SEED = 0.1, 1
RATE_SETTINGS = {
    "lab": ((74.0, 30.0), (76.0, 30.0), (72.0, 40.0), (70.0, 40.0)),
    "builtin": ((70.0, 30.0), (72.0, 25.0), (74.0, 25.0), (76.0, 25.0)),
}


BORDERLINE_THETA_DEG = (72.0, 30.0)
"""theta_w and theta_l of the borderline single attempts (the source paper's Fig. 8 protocol), degrees."""
BORDERLINE_WING_PERIOD_S = 2.0
BORDERLINE_LEG_PERIODS_S = (0.6, 0.8, 1.0, 1.2, 1.4)
BORDERLINE_PHASES = tuple(k / 20 for k in range(20))
BORDERLINE_DTS = {"pybullet": (1e-3, 5e-4, 2.5e-4, 1.25e-4), "mujoco": (2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4)}
"""The steps tried per engine, each against a quarter of itself, s."""
BORDERLINE_MATCH = 95
"""Outcomes of 100 that must match a run at a quarter of the step."""
HEADINGS_DEG = (1e-4, 5.0, 45.0, 90.0)
"""Headings the borderline attempts are turned to, degrees (against 0)."""


def borderline_trials(model_set, *, dt_s: float | None = None, heading_deg: float = 0.0) -> list:
    """The 100 borderline single attempts (:data:`BORDERLINE_LEG_PERIODS_S` x :data:`BORDERLINE_PHASES`, no noise)
    as :class:`sim.trial.Trial` specs of ``model_set``'s actuation, at ``dt_s`` (None: the engine's default) and
    turned by ``heading_deg``."""
    from sim.trial import Trial

    tw, tl = BORDERLINE_THETA_DEG
    out = []
    for leg_period_s in BORDERLINE_LEG_PERIODS_S:
        act = model_set.actuation(tw, tl, wing_period_s=BORDERLINE_WING_PERIOD_S, leg_period_s=leg_period_s)
        out += [
            Trial(tw, tl, phase, 0.0, rng=0, dt_s=dt_s, attempts=1, actuation=act, heading_deg=heading_deg)
            for phase in BORDERLINE_PHASES
        ]
    return out


def _borderline_one(job) -> tuple[bool, float, float]:
    from sim.trial import simulate_trial

    trial, model_set = job
    r = simulate_trial(trial, model_set=model_set)
    return r.success, r.cpu_s, r.sim_s


def borderline_outcomes(model_set, *, dt_s: float | None = None, heading_deg: float = 0.0, workers: int = 1):
    """(success, CPU s, simulated s) of each borderline attempt (:func:`borderline_trials`), in their order."""
    jobs = [(t, model_set) for t in borderline_trials(model_set, dt_s=dt_s, heading_deg=heading_deg)]
    if workers <= 1:
        out = []
        for job in jobs:
            out.append(_borderline_one(job))
            if PROGRESS is not None:
                PROGRESS.step()
        return out
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(workers) as pool:
        out = []
        for r in pool.map(_borderline_one, jobs, chunksize=4):
            out.append(r)
            if PROGRESS is not None:
                PROGRESS.step()
        return out


def borderline(engines: list[str], workers: int) -> dict[str, float]:
    """Print the step table and the heading table for ``engines``; return each engine's chosen step, s."""
    from sim.model_set import load_model_set
    from sim.trial import default_dt_s

    n = len(BORDERLINE_LEG_PERIODS_S) * len(BORDERLINE_PHASES)
    print(
        f"## The {n} borderline single attempts at a step and at a quarter of it\n\n"
        f"theta_w {BORDERLINE_THETA_DEG[0]:g} deg, theta_l {BORDERLINE_THETA_DEG[1]:g} deg, Tw "
        f"{BORDERLINE_WING_PERIOD_S:g} s, Tl {'/'.join(f'{x:g}' for x in BORDERLINE_LEG_PERIODS_S)} s x "
        f"{len(BORDERLINE_PHASES)} phases, no noise, one attempt each; built-in robot, the paper set\n"
    )
    print(
        "| engine | dt (s) | righted at dt | righted at dt / 4 | same outcome | CPU per attempt at dt (s) |"
    )
    print("|---|---:|---:|---:|---:|---:|")
    chosen = {}
    for engine in engines:
        ms = load_model_set().with_engine(engine)
        ok = []
        for dt in BORDERLINE_DTS[engine]:
            a = borderline_outcomes(ms, dt_s=dt, workers=workers)
            b = borderline_outcomes(ms, dt_s=dt / 4, workers=workers)
            same = sum(x[0] == y[0] for x, y in zip(a, b, strict=True))
            if same >= BORDERLINE_MATCH:
                ok.append(dt)
            cpu = sum(x[1] for x in a) / len(a)
            print(
                f"| {engine} | {dt:g} | {sum(x[0] for x in a)} | {sum(y[0] for y in b)} | {same}/{len(a)} | "
                f"{cpu:.3f} |",
                flush=True,
            )
        chosen[engine] = max(ok) if ok else math.nan
    print()
    for engine in engines:
        print(
            f"{engine}: largest step with >= {BORDERLINE_MATCH} of {n} the same = {chosen[engine]:g} s "
            f"(default {default_dt_s(None, engine):g} s)"
        )
    print("\n## The same attempts turned on the ground, at each engine's default step\n")
    print("| engine | dt (s) | " + " | ".join(f"{h:g} deg: changed" for h in HEADINGS_DEG) + " |")
    print("|---|---:|" + "---:|" * len(HEADINGS_DEG))
    for engine in engines:
        ms = load_model_set().with_engine(engine)
        base = borderline_outcomes(ms, workers=workers)
        changed = []
        for h in HEADINGS_DEG:
            turned = borderline_outcomes(ms, heading_deg=h, workers=workers)
            changed.append(sum(x[0] != y[0] for x, y in zip(base, turned, strict=True)))
        print(
            f"| {engine} | {default_dt_s(None, engine):g} | "
            + " | ".join(f"{c}/{n}" for c in changed)
            + " |",
            flush=True,
        )
    return chosen


LINE_EVERY_S = 30.0
"""Seconds between progress lines when stderr is not a terminal."""


class Progress:
    """Trials done of the planned total with elapsed time and ETA on stderr: a tqdm bar on a terminal, else a
    plain line every ``LINE_EVERY_S`` seconds (and at the end), so a redirected log shows it without bar frames."""

    def __init__(self, total: int, *, stream=None):
        self.total, self.done, self.stream = total, 0, stream or sys.stderr
        self.t0 = self.last = time.perf_counter()
        self.bar = None
        if self.stream.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=total, unit="trial", file=self.stream, smoothing=0.1)

    def step(self) -> None:
        self.done += 1
        if self.bar is not None:
            self.bar.update(1)
            return
        now = time.perf_counter()
        if now - self.last >= LINE_EVERY_S or self.done == self.total:
            self.last = now
            self.stream.write(self.line(now) + "\n")
            self.stream.flush()

    def line(self, now: float) -> str:
        el = now - self.t0
        eta = el / self.done * max(self.total - self.done, 0) if self.done else float("nan")
        return f"progress: {self.done}/{self.total} trials, {el:.0f} s elapsed, ETA {eta:.0f} s"

    def drop(self, n: int) -> None:
        """``n`` planned trials will not run after all."""
        self.total -= n
        if self.bar is not None:
            self.bar.total = self.total
            self.bar.refresh()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


PROGRESS: Progress | None = None


def run_trial(*args, **kw):
    """:func:`sim.trial.run_trial`, counted by the running :class:`Progress`."""
    r = _run_trial(*args, **kw)
    if PROGRESS is not None:
        PROGRESS.step()
    return r


def planned_trials(*, quick: bool, only_rates: bool, grid: int, rate_settings: int, rate_seeds: int) -> int:
    """How many trials :func:`main` runs with these options (the progress total).

    Examples
    --------
    >>> planned_trials(quick=True, only_rates=False, grid=12, rate_settings=4, rate_seeds=40)
    42
    """
    rate = rate_settings * rate_seeds * 2  # at the chosen dt and at the next smaller one
    if only_rates:
        return rate
    n_cases = len(ORIENT_CASES)
    orient = 2 * n_cases + 3 * n_cases * len(DTS)  # two references, then three contact settings per dt
    if quick:
        return orient
    outcome = grid + grid * len(DTS)  # the reference, then each dt
    solver = 4 * (n_cases + grid)  # 50, 20, 10 iterations and merged links: traces and outcomes
    hulls = 2 * grid
    return orient + outcome + solver + hulls + rate


def _up(trace) -> np.ndarray:
    return up_vector(np.deg2rad(trace.pitch_deg), np.deg2rad(trace.roll_deg))


def traces(dt: float, **kw) -> dict:
    out = {}
    for case in ORIENT_CASES:
        r = run_trial(
            case[0], case[1], phase=case[2], cv=0.0, rng=SEED, duration_s=2.0, dt_s=dt, trace=True, **kw
        )
        out[case] = (r.trace.t_s, _up(r.trace))
    return out


def orientation_diff_deg(run: dict, ref: dict) -> tuple[float, float]:
    """Largest world-up angle between two sets of traces over the first 1 s and 2 s, degrees."""
    worst1 = worst2 = 0.0
    for case, (ref_t, ref_u) in ref.items():
        u = run[case][1]
        n = min(len(ref_u), len(u))
        ang = np.rad2deg(np.arccos(np.clip((u[:n] * ref_u[:n]).sum(axis=1), -1.0, 1.0)))
        k1 = int(np.searchsorted(ref_t[:n], 1.0 + 1e-9))
        worst1, worst2 = max(worst1, float(ang[:k1].max())), max(worst2, float(ang.max()))
    return worst1, worst2


def outcomes(dt: float, grid: list, **kw) -> list:
    res = []
    for tw, tl, ph in grid:
        r = run_trial(tw, tl, phase=ph, cv=CV, rng=SEED, dt_s=dt, **kw)
        res.append((r.success, r.attempt, r.time_to_right_s, r.cpu_s, r.sim_s))
    return res


def compare(res, ref) -> tuple[str, str, str]:
    same_success = sum(a[0] == b[0] for a, b in zip(res, ref, strict=True))
    same_attempt = sum(a[0] == b[0] and a[1] == b[1] for a, b in zip(res, ref, strict=True))
    dts = [abs(a[2] - b[2]) for a, b in zip(res, ref, strict=True) if a[0] and b[0] and a[1] == b[1]]
    return (
        f"{same_success}/{len(ref)}",
        f"{same_attempt}/{len(ref)}",
        f"{max(dts) * 1e3:.0f}" if dts else "-",
    )


def _rate(res) -> float:
    return sum(r[3] for r in res) / sum(r[4] for r in res)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robot", default="builtin", help="builtin (default), lab, or a URDF path")
    ap.add_argument("--quick", action="store_true", help="orientation only, no outcome grid")
    ap.add_argument("--grid-theta-w", default=None, help="outcome grid wing angles (default: per robot)")
    ap.add_argument("--grid-theta-l", default=None, help="outcome grid leg amplitudes (default: per robot)")
    ap.add_argument(
        "--rate-seeds", type=int, default=40, help="seeds per setting in the success-rate comparison"
    )
    ap.add_argument(
        "--only-rates",
        action="store_true",
        help="run section 5 only, at the default dt against the next smaller one",
    )
    ap.add_argument(
        "--borderline",
        action="store_true",
        help="only the borderline single attempts: each engine's step against a quarter of it, then headings",
    )
    ap.add_argument("--engines", default="pybullet,mujoco", help="engines of --borderline (default: both)")
    ap.add_argument("--workers", type=int, default=1, help="processes of --borderline (default 1)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    if args.borderline:
        engines = [e.strip() for e in args.engines.split(",") if e.strip()]
        n = len(BORDERLINE_LEG_PERIODS_S) * len(BORDERLINE_PHASES)
        total = sum(2 * n * len(BORDERLINE_DTS[e]) + n * (1 + len(HEADINGS_DEG)) for e in engines)
        global PROGRESS
        PROGRESS = Progress(total)
        try:
            borderline(engines, args.workers)
        finally:
            PROGRESS.close()
            PROGRESS = None
        print(f"\ntotal wall time {time.perf_counter() - t0:.0f} s")
        return
    kind = args.robot if args.robot in ("builtin", "lab") else "lab"
    path = {"builtin": default_robot_urdf(), "lab": LAB_URDF}.get(args.robot, Path(args.robot))
    gw, gl = GRID_DEFAULTS[kind]
    grid = list(
        itertools.product(
            [float(x) for x in (args.grid_theta_w or gw).split(",")],
            [float(x) for x in (args.grid_theta_l or gl).split(",")],
            PHASES,
        )
    )
    robot = dict(robot=path)
    PROGRESS = Progress(
        planned_trials(
            quick=args.quick,
            only_rates=args.only_rates,
            grid=len(grid),
            rate_settings=len(RATE_SETTINGS[kind]),
            rate_seeds=args.rate_seeds,
        )
    )
    try:
        _sections(args, kind, path, grid, robot, t0)
    finally:
        PROGRESS.close()
        PROGRESS = None


def _sections(args, kind, path, grid, robot, t0) -> None:
    if args.only_rates:
        rates(
            DEFAULT_DT_S,
            RATE_SETTINGS[kind],
            args.rate_seeds,
            robot,
            other=max(dt for dt in DTS if dt < DEFAULT_DT_S),
        )
        return
    soft, rigid = Contact(), Contact.rigid()
    ref_soft = replace(soft, solver_iterations=REF_ITERATIONS)
    ref_rigid = replace(rigid, solver_iterations=REF_ITERATIONS)
    print(
        f"robot: {path}; reference dt = {REF_DT:g} s with {REF_ITERATIONS} solver iterations; default "
        f"solver iterations {soft.solver_iterations}\n"
    )

    print("## Orientation vs time step (max angle of world-up vs the reference, three cases)\n")
    print(
        f"| dt (s) | soft, {soft.solver_iterations} iterations: first 1 s (deg) | first 2 s (deg) | "
        f"soft, {REF_ITERATIONS} iterations: first 1 s (deg) | rigid: first 1 s (deg) | rigid: first 2 s (deg) |"
    )
    print("|---:|---:|---:|---:|---:|---:|")
    refs_soft, refs_rigid = (
        traces(REF_DT, contact=ref_soft, **robot),
        traces(REF_DT, contact=ref_rigid, **robot),
    )
    orient = {}
    for dt in DTS:
        s1, s2 = orientation_diff_deg(traces(dt, contact=soft, **robot), refs_soft)
        f1, _ = orientation_diff_deg(traces(dt, contact=ref_soft, **robot), refs_soft)
        r1, r2 = orientation_diff_deg(traces(dt, contact=rigid, **robot), refs_rigid)
        orient[dt] = s1
        print(f"| {dt:g} | {s1:.3f} | {s2:.3f} | {f1:.3f} | {r1:.3f} | {r2:.3f} |", flush=True)
    if args.quick:
        return

    tws = "/".join(f"{x:g}" for x in sorted({g[0] for g in grid}))
    tls = "/".join(f"{x:g}" for x in sorted({g[1] for g in grid}))
    print(
        f"\n## Outcomes vs time step (soft contact, {soft.solver_iterations} solver iterations; {len(grid)} trials: "
        f"theta_w {tws}, theta_l {tls}, phi_1 0.2/0.7, Cv {CV}, seed {SEED})\n"
    )
    ref = outcomes(REF_DT, grid, contact=ref_soft, **robot)
    print(f"reference: successes {sum(r[0] for r in ref)}/{len(ref)}, attempts {[r[1] for r in ref]}\n")
    print(
        "| dt (s) | same success | same success and attempt | max diff time to right (ms) | "
        "core-s per simulated s |"
    )
    print("|---:|---:|---:|---:|---:|")
    same = {}
    for dt in DTS:
        res = outcomes(dt, grid, **robot)
        a, b, c = compare(res, ref)
        same[dt] = a == f"{len(ref)}/{len(ref)}"
        print(f"| {dt:g} | {a} | {b} | {c} | {_rate(res):.3f} |", flush=True)
    ok = [dt for dt in DTS if orient[dt] < 0.5 and same[dt]]
    chosen = max(ok) if ok else min(DTS)
    print(
        f"\nchosen dt = {chosen:g} s (largest with < 0.5 deg over the first second and the same outcomes)\n"
    )

    print(f"## Solver iterations and merged links at dt = {chosen:g} s (against the same reference)\n")
    print(
        "| setting | first 1 s (deg) | first 2 s (deg) | same success | same success and attempt | "
        "max diff time to right (ms) | core-s per simulated s |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    settings = [(f"{n} iterations", dict(contact=replace(soft, solver_iterations=n))) for n in (50, 20, 10)]
    settings.append(
        (
            f"{soft.solver_iterations} iterations, fixed links merged",
            dict(contact=soft, numerics=Numerics(merge_fixed_links=True)),
        )
    )
    for name, kw in settings:
        o1, o2 = orientation_diff_deg(traces(chosen, **kw, **robot), refs_soft)
        res = outcomes(chosen, grid, **kw, **robot)
        a, b, c = compare(res, ref)
        print(f"| {name} | {o1:.3f} | {o2:.3f} | {a} | {b} | {c} | {_rate(res):.3f} |", flush=True)

    print(f"\n## Collision hull simplification at dt = {chosen:g} s\n")
    simp = outcomes(chosen, grid, **robot)
    full = outcomes(chosen, grid, numerics=Numerics(hull_tol_m=0.0), **robot)
    a, b, c = compare(full, simp)
    print(
        "| hulls | successes | same success as simplified | same attempt | max diff time to right (ms) | "
        "core-s per simulated s |"
    )
    print("|---|---:|---:|---:|---:|---:|")
    for name, res in (("simplified (<= 96 vertices, tol 0.1 mm)", simp), ("full", full)):
        row = (a, b, c) if name == "full" else ("-", "-", "-")
        print(
            f"| {name} | {sum(r[0] for r in res)}/{len(res)} | {row[0]} | {row[1]} | {row[2]} | {_rate(res):.3f} |"
        )
    smaller = max([dt for dt in DTS if dt < chosen], default=None)
    rates(chosen, RATE_SETTINGS[kind], args.rate_seeds, robot, other=smaller)
    print(f"\ntotal wall time {time.perf_counter() - t0:.0f} s")


def rates(dt: float, settings, seeds: int, robot: dict, other: float | None = None) -> None:
    """Section 5: success rates over ``seeds`` trials per setting at ``dt`` (and ``other``), Wilson intervals,
    Fisher's exact test between the two."""
    from scipy.stats import fisher_exact

    from sim.sweep import trial_seed

    dts = [dt] + ([other] if other else [])
    if PROGRESS is not None and not other:
        PROGRESS.drop(len(settings) * seeds)  # planned at two time steps
    print(f"\n## Success rates near the boundary ({seeds} seeds per setting, Cv {CV}, phi_1 0.7)\n")
    head = " | ".join(f"dt {d:g}: successes (95 % CI)" for d in dts)
    print(f"| theta_w | theta_l | {head} |" + (" Fisher p |" if other else ""))
    print("|---:|---:|" + "---:|" * len(dts) + ("---:|" if other else ""))
    for tw, tl in settings:
        ks = []
        for d in dts:
            k = sum(
                run_trial(
                    tw, tl, phase=0.7, cv=CV, rng=trial_seed(tw, tl, CV, 0.7, i), dt_s=d, **robot
                ).success
                for i in range(seeds)
            )
            ks.append(k)
        cells = []
        for k in ks:
            lo, hi = wilson_interval(k, seeds)
            cells.append(f"{k}/{seeds} ({lo:.2f}–{hi:.2f})")
        p = f" {fisher_exact([[ks[0], seeds - ks[0]], [ks[1], seeds - ks[1]]])[1]:.2f} |" if other else ""
        print(f"| {tw:g} | {tl:g} | " + " | ".join(cells) + " |" + p, flush=True)


if __name__ == "__main__":
    main()
