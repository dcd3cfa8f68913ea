"""Why the engines disagree on single attempts: change one part of one engine's model at a time.

pybullet and MuJoCo end 40 of the 100 borderline single attempts differently (docs/concepts/engines.md), while
each engine's default step ends 96-97 of them as at a quarter of the step. The two models differ in three parts
under the same robot: the start (pybullet places the robot by its bounding boxes and drops it about 38 mm onto its
back; MuJoCo places it 0.1 mm above its lowest hull point), the contact (pybullet's spring and damper; MuJoCo's
soft constraint with a 3 ms time constant) and the servos (pybullet's velocity constraint; MuJoCo's position
actuator with a finite velocity gain). This study runs the 100 attempts (the convergence study's:
benchmarks/sim_convergence.py, theta_w 72, theta_l 30, Tw 2 s, Tl 0.6-1.4 s x 20 phases, no noise, one wing opening
each; built-in robot, ``paper`` set, each engine's default step) with one part changed at a time, and counts how
many end as in pybullet's default, as in MuJoCo's default and as in the variant's own engine's default:

- **start**: pybullet placed 0.1 mm above its hull (no drop); MuJoCo dropped from pybullet's height (the drop
  pybullet's placement leaves, measured here);
- **contact**: each engine's contact twice and half as stiff (pybullet's ``stiffness_n_m``; MuJoCo's ``solref``
  time constant half and twice, its stiffness scaling with the inverse square);
- **servo**: MuJoCo's velocity gain ``kv`` halved and 1.5 times (it chatters from twice, docs/sim.md);
- **step**: each engine at a quarter of its step (the convergence study's control).

A part whose ordinary change alone moves as many attempts as the engine swap does is enough to explain the
disagreement; a part that brings MuJoCo closer to pybullet is one cause of it. The start variants patch the
worlds' ``place`` in this process only (the shipped placement is not an option of the product), so every trial
settles afresh (``Numerics(reuse_settled=False)``).

Run:  PYTHONPATH=. .venv/bin/python benchmarks/studies/engine_swap.py [--workers 2] [--only pybullet|mujoco]
(2 cores: about 10 min with the quarter steps, ``--no-quarter`` leaves them out).
"""

from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path
from typing import NamedTuple

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks/ (sim_convergence)

from sim_convergence import borderline_trials  # noqa: E402

HULL_CLEARANCE_M = 1e-4
"""Height of the lowest hull point above the ground at placement, m (MuJoCo's default; ``place``'s default)."""


class Variant(NamedTuple):
    """One engine with one part changed: ``contact``/``mujoco`` are replacements of the set's tables,
    ``drop_m`` a placement height (None: the engine's own placement), ``dt_factor`` a multiple of the step."""

    label: str
    engine: str
    part: str
    contact: tuple = ()
    mujoco: tuple = ()
    drop_m: float | None = None
    dt_factor: float = 1.0


def variants(drop_m: float, *, quarter: bool) -> list[Variant]:
    """The variants of this study, pybullet's then MuJoCo's, each engine's default first."""
    out = [
        Variant("pybullet default", "pybullet", "-"),
        Variant("pybullet placed 0.1 mm above its hull", "pybullet", "start", drop_m=HULL_CLEARANCE_M),
        Variant("pybullet contact twice as stiff (2e4 N/m)", "pybullet", "contact", contact=(("stiffness_n_m", 2e4),)),
        Variant("pybullet contact half as stiff (5e3 N/m)", "pybullet", "contact", contact=(("stiffness_n_m", 5e3),)),
        Variant("mujoco default", "mujoco", "-"),
        Variant(f"mujoco dropped {1e3 * drop_m:.1f} mm (as pybullet)", "mujoco", "start", drop_m=drop_m),
        Variant("mujoco contact solref 1.5 ms (stiffer)", "mujoco", "contact", mujoco=(("solref_time_s", 0.0015),)),
        Variant("mujoco contact solref 6 ms (softer)", "mujoco", "contact", mujoco=(("solref_time_s", 0.006),)),
        Variant("mujoco servo kv 0.05 (looser)", "mujoco", "servo", mujoco=(("servo_kv_n_m_s_rad", 0.05),)),
        Variant("mujoco servo kv 0.15 (tighter)", "mujoco", "servo", mujoco=(("servo_kv_n_m_s_rad", 0.15),)),
    ]  # fmt: skip
    if quarter:
        out.insert(4, Variant("pybullet at a quarter of the step", "pybullet", "step", dt_factor=0.25))
        out.append(Variant("mujoco at a quarter of the step", "mujoco", "step", dt_factor=0.25))
    return out


def _patch_place(drop_m: float | None) -> None:
    """Make both worlds' ``place`` put the robot's lowest hull point ``drop_m`` above the ground (None: undo)."""
    import sim.mujoco_world as mw
    import sim.world as pw

    for cls in (pw.World, mw.MujocoWorld):
        if not hasattr(cls, "_study_place"):
            cls._study_place = cls.place
        cls.place = cls._study_place if drop_m is None else _placer(cls._study_place, drop_m)


def _placer(original, drop_m: float):
    def place(self, pitch_rad, roll_rad, *, joints_rad, clearance_m=HULL_CLEARANCE_M, heading_rad=0.0):
        original(
            self, pitch_rad, roll_rad, joints_rad=joints_rad, clearance_m=drop_m, heading_rad=heading_rad
        )
        if hasattr(
            self, "cid"
        ):  # pybullet: its placement measures bounding boxes; lower it to the hull's height
            _lower_to(self, drop_m - hull_gap_m(self))

    return place


def hull_gap_m(world) -> float:
    """Distance from a pybullet world's robot to its ground by the collision shapes, m (the hull's height)."""
    import pybullet as pb

    pts = pb.getClosestPoints(world.body, world.ground, 1.0, physicsClientId=world.cid)
    return min(p[8] for p in pts)


def _lower_to(world, dz: float) -> None:
    import pybullet as pb

    pos, q = pb.getBasePositionAndOrientation(world.body, physicsClientId=world.cid)
    pb.resetBasePositionAndOrientation(
        world.body, [pos[0], pos[1], pos[2] + dz], q, physicsClientId=world.cid
    )


def pybullet_drop_m() -> float:
    """How far above the ground pybullet's placement leaves the robot's hull at the start of settling, m."""
    import numpy as np

    from sim.engine import open_world
    from sim.model import sim_model
    from sim.model_set import load_model_set
    from sim.trial import default_dt_s

    ms = load_model_set()
    model = sim_model(None, modifiers=ms.modifiers)
    with open_world("pybullet", model, dt_s=default_dt_s(), contact=ms.contact) as w:
        w.place(np.deg2rad(model.rest_pitch_deg), 0.0, joints_rad=np.zeros(len(w.driven)))
        return hull_gap_m(w)


def _one(job) -> tuple[bool, float]:
    from sim.model_set import load_model_set
    from sim.trial import Numerics, default_dt_s, simulate_trial

    variant, k = job
    _patch_place(variant.drop_m)
    ms = load_model_set()
    ms = replace(
        ms,
        contact=replace(ms.contact, **dict(variant.contact)),
        mujoco=replace(ms.mujoco, **dict(variant.mujoco)),
    )
    ms = ms.with_engine(variant.engine)
    dt = default_dt_s(None, variant.engine) * variant.dt_factor
    trial = borderline_trials(ms, dt_s=dt)[k]
    r = simulate_trial(
        trial, model_set=ms, numerics=Numerics(reuse_settled=False)
    )  # the placement is patched
    return r.success, r.cpu_s


def run(vs: list[Variant], workers: int, limit: int | None = None) -> dict[str, tuple[list[bool], float]]:
    """Each variant's outcomes of the 100 attempts (the first ``limit``) and its CPU seconds."""
    from sim_convergence import BORDERLINE_LEG_PERIODS_S, BORDERLINE_PHASES, Progress

    n = len(BORDERLINE_LEG_PERIODS_S) * len(BORDERLINE_PHASES)
    n = min(n, limit or n)
    jobs = [(v, k) for v in vs for k in range(n)]
    progress = Progress(len(jobs))
    pool = ProcessPoolExecutor(workers) if workers > 1 else None
    try:
        res = []
        for r in pool.map(_one, jobs, chunksize=5) if pool else map(_one, jobs):
            res.append(r)
            progress.step()
    finally:
        progress.close()
        if pool:
            pool.shutdown()
    out = {}
    for j, v in enumerate(vs):
        chunk = res[j * n : (j + 1) * n]
        out[v.label] = ([s for s, _ in chunk], sum(c for _, c in chunk))
    return out


def _same(a: list[bool], b: list[bool]) -> int:
    return sum(x == y for x, y in zip(a, b, strict=True))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--no-quarter", action="store_true", help="leave out the runs at a quarter of the step")
    ap.add_argument("--limit", type=int, default=None, help="only the first N attempts (a smoke run)")
    a = ap.parse_args(argv)
    if a.workers < 1 or (a.limit is not None and a.limit < 1):
        print(
            f"error: --workers and --limit must be at least 1; got {a.workers} and {a.limit}", file=sys.stderr
        )
        return 2
    t0 = time.perf_counter()
    drop = pybullet_drop_m()
    vs = variants(drop, quarter=not a.no_quarter)
    res = run(vs, a.workers, a.limit)
    pb0, mj0 = res["pybullet default"][0], res["mujoco default"][0]
    n = len(pb0)
    print(
        f"## One part of one engine changed at a time: {n} of the borderline single attempts\n\n"
        "theta_w 72 deg, theta_l 30 deg, Tw 2 s, Tl 0.6/0.8/1.0/1.2/1.4 s x 20 phases, no noise, one attempt each; "
        f"built-in robot, paper set, each engine's default step; pybullet's placement leaves the hull "
        f"{1e3 * drop:.1f} mm above the ground\n"
    )
    print(
        "| variant | part | righted | same as pybullet default | same as MuJoCo default | same as its engine's default | CPU s |"
    )
    print("|---|---|---:|---:|---:|---:|---:|")
    for v in vs:
        out, cpu = res[v.label]
        own = pb0 if v.engine == "pybullet" else mj0
        print(
            f"| {v.label} | {v.part} | {sum(out)} | {_same(out, pb0)}/{n} | {_same(out, mj0)}/{n} | {_same(out, own)}/{n} | {cpu:.0f} |"
        )
    print(f"\n({time.perf_counter() - t0:.0f} s on {a.workers} workers)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
