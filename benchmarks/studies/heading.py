"""How much the robot's heading on the ground changes a simulated trial (pybullet's friction is not isotropic).

On an isotropic floor a trial turned about the vertical is the same trial. Bullet computes friction along two
directions per contact that are fixed in the world (from the ground's normal), so in the simulation the heading
matters, modulo 90 degrees. This study measures it on the prediction protocol of the source paper's Fig. 8
(theta_w 72 deg, theta_l 30 deg, no noise, Tw x Tl x phases) and prints three tables:

1. The mechanism: a box given 1 m/s along world x, along 30 and 45 degrees, on the ground with mu = 1 (the
   trials' contact and solver settings): how far it slides (Coulomb: v^2 / (2 mu g) = 51 mm) and how far its path
   turns from the push (0 on an isotropic floor).
2. Sensitivity: every trial run again turned by a few headings; how many single attempts (the phase map, each
   (Tl, phase) once) and how many first righting attempts (every trial) change. 90 degrees is the control.
3. How far a failed attempt leaves the robot turned: its heading at each later opening minus its first
   (`landscape analyze prediction` uses the heading at each opening to predict the first righting attempt).

``--friction-axes body`` runs tables 2 and 3 with ``Contact(friction_axes="body")`` (sim.world: the robot is
kept at heading 0, so the friction directions turn with it). ``--engine mujoco`` runs all three in MuJoCo, with its
elliptic cone (the default) or ``--cone pyramidal``.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/studies/heading.py [--workers 2] [--phases 20] [--friction-axes body]
      [--engine mujoco [--cone pyramidal]]
(the full protocol, 300 trials at each of five headings: 313 s on 2 cores in pybullet).
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

THETA_W_DEG, THETA_L_DEG = 72.0, 30.0
WING_PERIODS_S = (2.0, 2.5, 3.0)
LEG_PERIODS_S = (0.6, 0.8, 1.0, 1.2, 1.4)
HEADINGS_DEG = (0.0, 1e-4, 5.0, 45.0, 90.0)
DT_S, DURATION_S = 5e-4, 10.0


def _trial(job):
    """(tw, tl, phase, heading, attempts, trace, friction axes, engine, cone) -> (job, first righting attempt or 0,
    phases, opening headings)."""
    from dataclasses import replace

    from sim.model_set import load_model_set
    from sim.trial import Trial, simulate_trial

    tw, tl, phase, heading, attempts, trace, axes, engine, cone = job
    ms = load_model_set()
    ms = replace(ms, contact=replace(ms.contact, friction_axes=axes), mujoco=replace(ms.mujoco, cone=cone))
    ms = ms.with_engine(engine)
    act = ms.actuation(THETA_W_DEG, THETA_L_DEG, wing_period_s=tw, leg_period_s=tl)
    r = simulate_trial(
        Trial(THETA_W_DEG, THETA_L_DEG, phase, 0.0, rng=0, duration_s=DURATION_S, dt_s=DT_S, attempts=attempts,
              actuation=act, trace=trace, heading_deg=heading),
        model_set=ms,
    )  # fmt: skip
    heads = []
    if trace:
        for t0 in r.attempt_starts_s:
            i = max(0, int(np.searchsorted(r.trace.t_s, t0, side="right")) - 1)
            heads.append(float(r.trace.heading_deg[i]))
    return job, (r.attempt if r.success else 0), list(r.phases), heads


def friction_table(engine: str = "pybullet", cone: str = "elliptic") -> list[tuple[float, float, float]]:
    """(push direction, slide distance mm, path turn deg) of a box pushed along the ground. In pybullet ``cone``
    "elliptic" is its cone friction (``enableConeFriction``, on by default) and "pyramidal" that option off."""
    if engine == "mujoco":
        return [_push_mujoco(deg, cone) for deg in (0.0, 30.0, 45.0)]
    from sim.world import _quiet_import_pybullet

    pb = _quiet_import_pybullet()
    out = []
    for deg in (0.0, 30.0, 45.0):
        cid = pb.connect(pb.DIRECT)
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=cid)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=DT_S,
            numSolverIterations=20,
            enableConeFriction=int(cone == "elliptic"),
            physicsClientId=cid,
        )
        plane = pb.createMultiBody(0.0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid),
                                   physicsClientId=cid)  # fmt: skip
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[0.05, 0.03, 0.01], physicsClientId=cid)
        box = pb.createMultiBody(0.26, shape, basePosition=[0.0, 0.0, 0.0101], physicsClientId=cid)
        for b in (plane, box):
            pb.changeDynamics(b, -1, lateralFriction=1.0, physicsClientId=cid)
        for _ in range(200):
            pb.stepSimulation(physicsClientId=cid)
        a = math.radians(deg)
        pb.resetBaseVelocity(box, [math.cos(a), math.sin(a), 0.0], [0.0, 0.0, 0.0], physicsClientId=cid)
        p0 = np.array(pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0])
        for _ in range(2000):
            pb.stepSimulation(physicsClientId=cid)
        d = np.array(pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0]) - p0
        pb.disconnect(cid)
        out.append((deg, float(np.hypot(d[0], d[1])) * 1e3, math.degrees(math.atan2(d[1], d[0])) - deg))
    return out


def _push_mujoco(deg: float, cone: str) -> tuple[float, float, float]:
    """:func:`friction_table`'s box in MuJoCo, with its default contact and ``cone``."""
    from dataclasses import replace

    import mujoco

    from sim.engine import MUJOCO_DEFAULTS
    from sim.mujoco_world import apply_params
    from sim.world import Contact

    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(pos=[0.0, 0.0, 0.0101])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.05, 0.03, 0.01], mass=0.26)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.0, 0.0, 1.0])
    apply_params(spec, replace(MUJOCO_DEFAULTS, cone=cone), dt_s=DT_S, contact=Contact())
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, nstep=200)
    a = math.radians(deg)
    d.qvel[:] = 0.0
    d.qvel[0:2] = (math.cos(a), math.sin(a))
    p0 = np.array(d.qpos[0:3])
    mujoco.mj_step(m, d, nstep=2000)
    dx = np.array(d.qpos[0:3]) - p0
    return deg, float(np.hypot(dx[0], dx[1])) * 1e3, math.degrees(math.atan2(dx[1], dx[0])) - deg


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument(
        "--phases", type=int, default=20, help="phases per (Tw, Tl) [default: 20, the protocol's]"
    )
    ap.add_argument("--leg-periods", type=float, nargs="+", default=LEG_PERIODS_S)
    ap.add_argument("--wing-periods", type=float, nargs="+", default=WING_PERIODS_S)
    ap.add_argument("--friction-axes", choices=("world", "body"), default="world")
    ap.add_argument("--engine", choices=("pybullet", "mujoco"), default="pybullet")
    ap.add_argument(
        "--cone", choices=("elliptic", "pyramidal"), default="elliptic", help="MuJoCo's friction cone"
    )
    a = ap.parse_args(argv)
    if a.phases < 1 or a.workers < 1:
        ap.error("--phases and --workers must be at least 1")
    t0 = time.perf_counter()
    engine = a.engine if a.engine == "pybullet" else f"mujoco, {a.cone} cone"
    print(
        f"1. A box pushed at 1 m/s along the ground, mu = 1 ({engine}; isotropic Coulomb friction: 51 mm, turn 0)"
    )
    print(f"{'push deg':>9} {'slide mm':>9} {'turn deg':>9}")
    for deg, mm, turn in friction_table(a.engine, a.cone):
        print(f"{deg:9.0f} {mm:9.1f} {turn:9.1f}")
    if a.engine == "pybullet":  # what its cone friction (on above, its default) does: off, a pyramid
        print(
            "   the same with pybullet's enableConeFriction off (friction clamped per direction: a pyramid)"
        )
        for deg, mm, turn in friction_table("pybullet", "pyramidal"):
            print(f"{deg:9.0f} {mm:9.1f} {turn:9.1f}")

    phases = [k / a.phases for k in range(a.phases)]
    cells = [(tw, tl, ph) for tw in a.wing_periods for tl in a.leg_periods for ph in phases]
    ax = a.friction_axes
    jobs = [
        (tw, tl, ph, h, None, h == 0.0, ax, a.engine, a.cone) for h in HEADINGS_DEG for tw, tl, ph in cells
    ]
    with ProcessPoolExecutor(a.workers) if a.workers > 1 else _Inline() as ex:
        res = {job[:4]: (att, phs, heads) for job, att, phs, heads in ex.map(_trial, jobs, chunksize=4)}
        base = {c: res[(*c, 0.0)] for c in cells}
        singles = sorted({(tl, ph) for _, tl, ph in cells})
        first = [c for c in cells if c[0] == a.wing_periods[0]]  # attempt 1 is the same at every Tw
        where = f"friction axes fixed in the {ax}" if a.engine == "pybullet" else engine
        print(f"\n2. Turned on the ground, {where}: changes against heading 0 "
              f"({len(singles)} single attempts, {len(cells)} trials)")  # fmt: skip
        print(f"{'heading deg':>12} {'single attempt':>15} {'first righting attempt':>23}")
        for h in HEADINGS_DEG[1:]:
            n1 = sum((res[(*c, h)][0] == 1) != (base[c][0] == 1) for c in first)
            nk = sum(res[(*c, h)][0] != base[c][0] for c in cells)
            print(f"{h:12g} {n1:>9}/{len(first):<5} {nk:>15}/{len(cells):<7}")

    turn = [hd[k] - hd[0] for _, _, hd in base.values() for k in range(1, len(hd))]
    if turn:
        q = np.percentile(np.abs(turn), [25, 50, 75])
        print(f"\n3. The robot's heading when a later attempt opens, minus its first: |turn| quartiles {q[0]:.1f}, "
              f"{q[1]:.1f}, {q[2]:.1f} deg over {len(turn)} attempts")  # fmt: skip
    print(f"\n{time.perf_counter() - t0:.0f} s")
    return 0


class _Inline:
    """``--workers 1``: run in this process (what a process pool would do, without pickling)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def map(self, fn, jobs, chunksize=1):
        return map(fn, jobs)


if __name__ == "__main__":
    raise SystemExit(main())
