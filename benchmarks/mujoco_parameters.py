"""MuJoCo's contact and servo parameters, chosen by measurement (a benchmark, not a unit test).

MuJoCo has no restitution coefficient, no contact spring in N/m and no velocity-constraint motor, so none of
pybullet's values can be copied; each of ``sim.engine.MujocoParams`` is chosen here against a criterion:

1. Bounce: a 100 x 60 x 20 mm box of the robot's 260 g dropped flat from 20 mm. Restitution = the speed at which
   it leaves the ground again / its impact speed (0 if it never leaves), and its deepest penetration, for
   pybullet's default soft contact and its rigid contact (e = 0.1), and MuJoCo over ``solref`` (time constant,
   damping ratio). pybullet's default contact does not bounce: MuJoCo's damping ratio is chosen to match.
2. Servo: MuJoCo's servo is pybullet's first-order tracker (desired speed = feed-forward speed + error / 10 ms),
   a position actuator whose velocity gain ``kv`` sets how stiffly it holds that speed (pybullet's motor is a
   velocity constraint: infinitely stiff up to its effort limit). Over ``CASES`` (whole trials, no noise), for each
   ``kv``: the largest tracking error (``TrialResult.max_tracking_error_deg``, every 5 ms), the mean error of the
   wing and leg angles against their commands (the trace, every 10 ms), the CPU cost, and *chatter*: physics
   steps at which a servo's force sits at its effort limit with the sign opposite to the step before. MuJoCo's
   implicit integrator linearises the servo's damping ``kv`` even while the effort limit clamps the force, so a
   ``kv`` too high for the step makes a saturated servo flip between its limits every step (a numerical limit
   cycle, not a motion). pybullet's for reference.
3. Contact stiffness: over the same trials, the deepest robot-ground penetration (every physics step; pybullet's
   from its contact points, stepping one physics step per call), and the settled resting pose (pitch, roll, 1 s
   after the wings opened to theta_w 0, 60 and 90 deg, leg still) against the landscape's metastable minimum
   (``landscape.minima.metastable_orientation``), for ``solref`` time constants and ``solimp``.
4. The chosen defaults (``sim.engine.MUJOCO_DEFAULTS``) at several time steps, every criterion: the time step is
   chosen by the convergence study, and the parameters must hold at whichever it picks.
5. Placement and rest, wings closed: the CoM height when the trial places the robot at its rest pitch, after the
   0.5 s of settling, and the landscape's height of that metastable state.

Criteria (docs/sim.md): no bounce, as pybullet's default contact; no chatter; the servo's tracking error as small
as that allows; penetration below ``MAX_PENETRATION_M`` in the trials; resting pose within ``MAX_POSE_ERROR_DEG``.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/mujoco_parameters.py [--quick]
"""

from __future__ import annotations

import argparse
import math
import time
from contextlib import contextmanager
from dataclasses import replace

import numpy as np

from sim.engine import MUJOCO_DEFAULTS, MujocoParams
from sim.model_set import load_model_set
from sim.protocol import DEFAULT_DT_S, MUJOCO_DT_S
from sim.trial import Numerics, run_trial
from sim.world import Contact

BOX_HALF_M = (0.05, 0.03, 0.01)
BOX_MASS_KG = 0.26
DROP_M = 0.02
CASES = ((76.0, 40.0, 0.7), (80.0, 30.0, 0.2), (72.0, 50.0, 0.45), (70.0, 20.0, 0.7))
"""(theta_w, theta_l, phi_1) of the trials: the convergence benchmark's three orientation settings, and a trial
that never rights (10 s of actuation)."""
POSE_THETA_W_DEG = (0.0, 60.0, 90.0)
POSE_AT_S = 1.0
"""When the resting pose is read, s after actuation starts (the wings are open from 0.3 s at the latest)."""
MAX_PENETRATION_M = 2e-3
"""Deepest robot-ground penetration allowed in a trial, m (pybullet's default soft contact reaches 1.6 mm in
``CASES``, table 3)."""
MAX_POSE_ERROR_DEG = 0.5
"""Largest pitch or roll difference of the settled pose from the landscape's metastable minimum, degrees."""
KVS = (0.03, 0.05, 0.1, 0.2, 0.3, 1.0)
TIMECONSTS_S = (0.002, 0.003, 0.004, 0.01, 0.02)
SOLIMPS = ((0.95, 0.99, 0.0005, 0.5, 2.0), (0.99, 0.999, 0.0005, 0.5, 2.0))
"""``solimp`` tried beside MuJoCo's default (0.9, 0.95, 0.001, 0.5, 2): stiffer impedance."""
DAMPRATIOS = (0.2, 0.5, 0.8, 1.0)
DTS = (1e-3, 5e-4, 2.5e-4, 1.25e-4, 1e-4)


# ---------------------------------------------------------------------------------------------- 1. bounce
def box_drop_mujoco(params: MujocoParams, dt_s: float) -> tuple[float, float]:
    """(restitution, deepest penetration m) of the box dropped in MuJoCo with ``params``."""
    import mujoco

    from sim.mujoco_world import apply_params

    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="box", pos=[0.0, 0.0, BOX_HALF_M[2] + DROP_M])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=list(BOX_HALF_M), mass=BOX_MASS_KG)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.0, 0.0, 1.0])
    apply_params(spec, params, dt_s=dt_s, contact=Contact())
    spec.geoms[0].contype, spec.geoms[0].conaffinity = 1, 0
    spec.geoms[1].contype, spec.geoms[1].conaffinity = 0, 1
    m = spec.compile()
    d = mujoco.MjData(m)
    heights = []
    speeds = []
    for _ in range(int(round(0.5 / dt_s))):
        mujoco.mj_step(m, d)
        heights.append(float(d.qpos[2]) - BOX_HALF_M[2])
        speeds.append(float(d.qvel[2]))
    return _rebound(heights, speeds)


def box_drop_pybullet(contact: Contact, dt_s: float) -> tuple[float, float]:
    """(restitution, deepest penetration m) of the box dropped in pybullet with ``contact`` (its world's settings:
    the ground's restitution 1, ``contactProcessingThreshold`` 0)."""
    from sim.world import _quiet_import_pybullet

    pb = _quiet_import_pybullet()
    cid = pb.connect(pb.DIRECT)
    try:
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=cid)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=dt_s, numSolverIterations=contact.solver_iterations, physicsClientId=cid
        )
        plane = pb.createMultiBody(
            0.0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid), physicsClientId=cid
        )
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(BOX_HALF_M), physicsClientId=cid)
        box = pb.createMultiBody(
            BOX_MASS_KG, shape, basePosition=[0.0, 0.0, BOX_HALF_M[2] + DROP_M], physicsClientId=cid
        )
        soft = (
            {}
            if contact.stiffness_n_m is None
            else {"contactStiffness": contact.stiffness_n_m, "contactDamping": contact.damping_n_s_m}
        )
        pb.changeDynamics(plane, -1, lateralFriction=1.0, restitution=1.0, contactProcessingThreshold=0.0,
                          physicsClientId=cid)  # fmt: skip
        pb.changeDynamics(box, -1, lateralFriction=1.0, restitution=contact.restitution,
                          contactProcessingThreshold=0.0, linearDamping=0.0, angularDamping=0.0, **soft,
                          physicsClientId=cid)  # fmt: skip
        heights, speeds = [], []
        for _ in range(int(round(0.5 / dt_s))):
            pb.stepSimulation(physicsClientId=cid)
            heights.append(pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0][2] - BOX_HALF_M[2])
            speeds.append(pb.getBaseVelocity(box, physicsClientId=cid)[0][2])
    finally:
        pb.disconnect(cid)
    return _rebound(heights, speeds)


def _rebound(heights_m, speeds_m_s) -> tuple[float, float]:
    """(restitution, deepest penetration m): the upward speed when the box's bottom first rises above the ground
    after it first went below, over the free-fall impact speed sqrt(2 g h)."""
    h = np.asarray(heights_m)
    below = np.flatnonzero(h < 0.0)
    if not len(below):
        return 0.0, 0.0
    after = np.flatnonzero(h[below[0] :] > 0.0)
    v_out = float(speeds_m_s[below[0] + after[0]]) if len(after) else 0.0
    return v_out / math.sqrt(2.0 * 9.81 * DROP_M), float(-h.min())


# ---------------------------------------------------------------------------------------------- 2-3. trials
@contextmanager
def mujoco_monitor():
    """Watch every MuJoCo physics step inside the block: yields a dict with the deepest robot-ground penetration
    (``penetration_m``) and the chatter count (``chatter``: steps at which a servo's force sits at its effort limit
    with the sign opposite to the step before)."""
    from sim.mujoco_world import MujocoWorld

    original = MujocoWorld._step
    seen = {"penetration_m": 0.0, "chatter": 0}

    def stepped(self, n_steps):
        for _ in range(n_steps):
            before = np.array(self.d.actuator_force)
            original(self, 1)
            seen["penetration_m"] = max(seen["penetration_m"], self.penetration_m())
            after, lim = self.d.actuator_force, self.max_force_n_m - 1e-9
            flips = (np.abs(before) >= lim) & (np.abs(after) >= lim) & (np.sign(before) != np.sign(after))
            seen["chatter"] += int(flips.sum())

    MujocoWorld._step = stepped
    try:
        yield seen
    finally:
        MujocoWorld._step = original


@contextmanager
def pybullet_monitor():
    """Watch every pybullet ``stepSimulation`` call inside the block (run the trials with
    ``Numerics(engine_substeps=False)``: one physics step per call): yields a dict with the deepest penetration
    of its contact points (``penetration_m``) and ``chatter`` 0 (its motors are velocity constraints)."""
    import sim.world as world

    original = world.pb.stepSimulation
    seen = {"penetration_m": 0.0, "chatter": 0}

    def stepped(*a, **kw):
        out = original(*a, **kw)
        points = world.pb.getContactPoints(physicsClientId=kw["physicsClientId"])
        if points:
            seen["penetration_m"] = max(seen["penetration_m"], -min(p[8] for p in points))
        return out

    world.pb.stepSimulation = stepped
    try:
        yield seen
    finally:
        world.pb.stepSimulation = original


def model_set(engine: str, params: MujocoParams | None = None):
    """The ``paper`` set in ``engine`` (MuJoCo with ``params``, default :data:`MUJOCO_DEFAULTS`)."""
    ms = load_model_set("paper")
    if engine == "pybullet":
        return ms
    return replace(ms, mujoco=params or MUJOCO_DEFAULTS).with_engine(engine)


def trial_measures(engine: str, params: MujocoParams | None, dt_s: float, cases=CASES) -> dict:
    """Over ``cases`` (whole trials, no noise, seed 1): the largest tracking error (deg), the mean |wing -
    command| and |leg - command| (deg, every 10 ms), the deepest penetration (m), the chatter count
    (:func:`mujoco_monitor`) and the outcomes (attempt or 0). The monitors step one physics step per call, so these
    runs are no measure of speed (``benchmarks/sim_speed.py`` times both engines)."""
    ms = model_set(engine, params)
    numerics = Numerics(engine_substeps=engine != "pybullet")
    worst, wing, leg, outcomes = 0.0, [], [], []
    with mujoco_monitor() if engine == "mujoco" else pybullet_monitor() as seen:
        for tw, tl, ph in cases:
            r = run_trial(
                tw, tl, phase=ph, cv=0.0, rng=1, dt_s=dt_s, model_set=ms, trace=True, numerics=numerics
            )
            worst = max(worst, r.max_tracking_error_deg)
            wing += list(np.abs(r.trace.wing_deg - r.trace.wing_cmd_deg))
            leg += list(np.abs(r.trace.leg_deg - r.trace.leg_cmd_deg))
            outcomes.append(r.attempt if r.success else 0)
    return {
        "max_err_deg": worst,
        "wing_err_deg": float(np.mean(wing)),
        "leg_err_deg": float(np.mean(leg)),
        "penetration_m": seen["penetration_m"],
        "chatter": seen["chatter"],
        "outcomes": outcomes,
    }


def pose_targets_deg(theta_w_deg=POSE_THETA_W_DEG) -> dict[float, tuple[float, float]]:
    """The landscape's metastable minimum (pitch, roll in degrees) of the built-in robot at each wing angle, leg
    centred."""
    from geometry.builtin import load_builtin_robot
    from landscape.minima import metastable_orientation

    robot = load_builtin_robot()
    return {float(w): metastable_orientation(robot, w, 0.0) for w in theta_w_deg}


def resting_pose_errors(
    engine: str, params: MujocoParams | None, dt_s: float, targets: dict[float, tuple[float, float]]
) -> dict[float, tuple[float, float]]:
    """Per wing angle: (pitch, roll) of the simulated pose ``POSE_AT_S`` after the wings open (one opening at
    phase 0, leg still) minus the landscape's metastable minimum, degrees."""
    ms = model_set(engine, params)
    out = {}
    for w, (pitch, roll) in targets.items():
        r = run_trial(w, 0.0, phase=0.0, cv=0.0, rng=0, attempts=1, dt_s=dt_s, model_set=ms, trace=True,
                      duration_s=POSE_AT_S + 0.05)  # fmt: skip
        i = int(np.argmin(np.abs(r.trace.t_s - POSE_AT_S)))
        out[w] = (float(r.trace.pitch_deg[i] - pitch), float(r.trace.roll_deg[i] - roll))
    return out


def placement_heights_m(engine: str, dt_s: float) -> tuple[float, float]:
    """(CoM height when placed as a trial places it, after settling ``sim.trial.SETTLE_S``), m: wings closed,
    servos holding 0."""
    from sim.engine import open_world
    from sim.model import sim_model
    from sim.trial import SERVO_TAU_S, SETTLE_S

    model = sim_model()
    ms = model_set(engine)
    with open_world(engine, model, dt_s=dt_s, contact=ms.contact, mujoco=ms.mujoco) as w:
        zeros = np.zeros(len(w.driven))
        w.place(np.deg2rad(model.rest_pitch_deg), 0.0, joints_rad=zeros)
        placed = w.com_height_m()
        w.drive(zeros, zeros, kp=dt_s / SERVO_TAU_S, kd=1.0)
        w.advance(int(round(SETTLE_S / dt_s)))
        return placed, w.com_height_m()


def worst_pose_error_deg(errors: dict[float, tuple[float, float]]) -> float:
    """The largest |pitch| or |roll| error over the wing angles, degrees."""
    return max(max(abs(p), abs(r)) for p, r in errors.values())


# ---------------------------------------------------------------------------------------------- tables
def _pose_cells(errors: dict[float, tuple[float, float]]) -> str:
    return " | ".join(f"{p:+.2f} / {r:+.2f}" for p, r in errors.values())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer trials (the first two cases) and settings")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    cases = CASES[:2] if a.quick else CASES
    d = MUJOCO_DEFAULTS

    print(f"## 1. Bounce: a {BOX_MASS_KG * 1e3:g} g box dropped {DROP_M * 1e3:g} mm (dt {MUJOCO_DT_S:g} s)\n")
    print("| engine | contact | restitution | deepest penetration (mm) |")
    print("|---|---|---:|---:|")
    for name, c in (("default soft (1e4 N/m, 100 N s/m)", Contact()), ("rigid, e = 0.1", Contact.rigid())):
        e, pen = box_drop_pybullet(c, DEFAULT_DT_S)
        print(f"| pybullet | {name} | {e:.3f} | {pen * 1e3:.3f} |", flush=True)
    for tc in TIMECONSTS_S:
        for dr in DAMPRATIOS:
            e, pen = box_drop_mujoco(replace(d, solref_time_s=tc, solref_dampratio=dr), MUJOCO_DT_S)
            print(f"| mujoco | solref ({tc:g} s, {dr:g}) | {e:.3f} | {pen * 1e3:.3f} |", flush=True)

    print(
        f"\n## 2. Servo velocity gain ({len(cases)} trials, dt {MUJOCO_DT_S:g} s; pybullet at {DEFAULT_DT_S:g} s)\n"
    )
    print("| engine | kv (N m s/rad) | chatter (steps) | max tracking error (°) | mean wing error (°) | "
          "mean leg error (°) | outcomes (attempt, 0: failed) |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---|")
    pb = trial_measures("pybullet", None, DEFAULT_DT_S, cases)
    print(f"| pybullet | - | - | {pb['max_err_deg']:.2f} | {pb['wing_err_deg']:.3f} | {pb['leg_err_deg']:.3f} | "
          f"{pb['outcomes']} |", flush=True)  # fmt: skip
    for kv in KVS[2:5] if a.quick else KVS:
        m = trial_measures("mujoco", replace(d, servo_kv_n_m_s_rad=kv), MUJOCO_DT_S, cases)
        print(f"| mujoco | {kv:g} | {m['chatter']} | {m['max_err_deg']:.2f} | {m['wing_err_deg']:.3f} | "
              f"{m['leg_err_deg']:.3f} | {m['outcomes']} |", flush=True)  # fmt: skip

    targets = pose_targets_deg()
    head = " | ".join(f"θw {w:g}°: pitch / roll error (°)" for w in targets)
    print(f"\n## 3. Contact time constant (damping ratio {d.solref_dampratio:g}, dt {MUJOCO_DT_S:g} s)\n")
    print("metastable minimum (pitch, roll) from the landscape: "
          + ", ".join(f"θw {w:g}°: ({p:.2f}°, {r:.2f}°)" for w, (p, r) in targets.items()) + "\n")  # fmt: skip
    print(
        f"| engine | solref time constant (s) | solimp | deepest penetration in trials (mm) | {head} | outcomes |"
    )
    print("|---|---:|---|---:|" + "---:|" * len(targets) + "---|")
    pe = resting_pose_errors("pybullet", None, DEFAULT_DT_S, targets)
    print(
        f"| pybullet | - | - | {pb['penetration_m'] * 1e3:.3f} | {_pose_cells(pe)} | {pb['outcomes']} |",
        flush=True,
    )
    rows = [replace(d, solref_time_s=tc) for tc in (TIMECONSTS_S[1:3] if a.quick else TIMECONSTS_S)]
    rows += [replace(d, solimp=si) for si in ([] if a.quick else SOLIMPS)]
    for p in rows:
        m = trial_measures("mujoco", p, MUJOCO_DT_S, cases)
        pe = resting_pose_errors("mujoco", p, MUJOCO_DT_S, targets)
        print(f"| mujoco | {p.solref_time_s:g} | {', '.join(f'{x:g}' for x in p.solimp)} | "
              f"{m['penetration_m'] * 1e3:.3f} | {_pose_cells(pe)} | {m['outcomes']} |", flush=True)  # fmt: skip

    print(f"\n## 4. The defaults ({d}) at each time step\n")
    print(
        f"| dt (s) | restitution | chatter (steps) | max tracking error (°) | deepest penetration (mm) | {head} | "
        "outcomes |"
    )
    print("|---:|---:|---:|---:|---:|" + "---:|" * len(targets) + "---|")
    for dt in DTS[:2] if a.quick else DTS:
        e, _ = box_drop_mujoco(d, dt)
        m = trial_measures("mujoco", d, dt, cases)
        pe = resting_pose_errors("mujoco", d, dt, targets)
        print(f"| {dt:g} | {e:.3f} | {m['chatter']} | {m['max_err_deg']:.2f} | {m['penetration_m'] * 1e3:.3f} | "
              f"{_pose_cells(pe)} | {m['outcomes']} |", flush=True)  # fmt: skip

    from geometry.builtin import load_builtin_robot
    from landscape import compute

    rest = compute(load_builtin_robot(), theta_w_deg=0.0, landscape_grid=False).minimum
    print("\n## 5. Placement and rest, wings closed (CoM height, mm)\n")
    print(
        f"landscape: metastable state at pitch {rest.pitch_deg:.2f}°, CoM {rest.height_m * 1e3:.2f} mm above the ground\n"
    )
    print("| engine | dt (s) | placed | after settling | settled minus landscape |")
    print("|---|---:|---:|---:|---:|")
    for engine, dt in (("pybullet", DEFAULT_DT_S), ("mujoco", MUJOCO_DT_S)):
        placed, settled = placement_heights_m(engine, dt)
        print(f"| {engine} | {dt:g} | {placed * 1e3:.2f} | {settled * 1e3:.2f} | "
              f"{(settled - rest.height_m) * 1e3:+.2f} |", flush=True)  # fmt: skip
    print(f"\n{time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
