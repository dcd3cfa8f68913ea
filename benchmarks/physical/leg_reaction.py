"""The leg's swing as a throw: how far it turns a free body, and how far the robot and the model tilt while it
swings in the first opening (issue #15, the time to right at 75-90 deg).

First table: the lab robot as a free body (no gravity, no ground), its wing joints held where a model set holds
them at each wing command (``ModelSet.wing_joints_deg``), its leg swung from +A to -A by a stiff servo along a
smooth ramp of ``SWING_S`` (the measured swing's duration). Angular momentum is conserved, so the body turns
against the leg about the leg's axis (body z): the table gives that turn and the lateral tilt it would give a
body held at the robot's hold pitch ``p`` (``asin(sin p sin turn)``; positive: towards +roll). This is the most
the swing can throw the body; a body on the ground gets less, by how much its supports resist.

Second table: per cell, the lateral tilt ``asin(cos p sin r)`` at times after the first opening starts, the
robot's (median over its recorded first openings; in the row's last column when its leg command swung down,
the last upward command before the opening plus half the leg period) beside each set's (one simulated first
opening at the protocol's leg phase, no noise; its last column: when its leg crossed zero going down).

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/leg_reaction.py [--data DIR] [--robot URDF]
      [--models physical-offset] [--cells 60:30,75:45,90:15,90:30,90:45] [--phase 0.17]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis.physical.response import (
    PROTOCOL_PHASE,
    lateral_tilt_deg,
    opening_response,
    simulated_openings,
)
from sim.protocol import PAPER_LEG_PERIOD_S

ROOT = Path(__file__).resolve().parents[2]
SWING_S = 0.12
"""Duration of the free body's leg swing from +A to -A, s (the measured profile's +A to -A takes 0.10-0.14 s)."""
TIMES_S = (0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5)
"""Times after the opening starts at which the second table reads the tilt, s."""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--models", default="physical-offset")
    ap.add_argument("--cells", default="60:30,75:45,90:15,90:30,90:45")
    ap.add_argument(
        "--phase", type=float, default=PROTOCOL_PHASE, help="leg phase of the simulated first opening"
    )
    args = ap.parse_args(argv)
    if not 0.0 <= args.phase < 1.0:
        ap.exit(2, f"{ap.prog}: error: --phase must lie in [0, 1); got {args.phase!r}\n")
    if not Path(args.robot).is_file():
        ap.exit(2, f"{ap.prog}: error: --robot {args.robot} not found; give the lab robot's URDF\n")
    try:
        from landscape.analysis.physical.recording import read_recording, trial_files
        from landscape.analysis.physical.validation import parse_cells
        from sim.model_set import load_model_set

        names = args.models.split(",")
        for m in names:
            load_model_set(m)  # every set checked before anything runs
        recs = [read_recording(f) for f in trial_files(args.data)]
        cells = parse_cells(args.cells, {(r.theta_w_cmd_deg, r.theta_l_deg) for r in recs})
        print(free_body_table(args.robot, load_model_set(names[0]), hold_pitch_deg(recs)))
        print()
        print(tilt_table(recs, args.robot, names, cells, args.phase))
    except (UsageError, FileNotFoundError) as exc:  # bad data, cells or sets: one line, as the command does
        ap.exit(2, f"{ap.prog}: error: {exc}\n")
    return 0


def free_turn_deg(urdf: str, wing_joints_deg: dict[str, float], amplitude_deg: float) -> float:
    """The free body's turn about its z axis, degrees, while its leg swings from +A to -A (see the docstring)."""
    import pybullet as pb

    cid = pb.connect(pb.DIRECT)
    try:
        pb.setGravity(0.0, 0.0, 0.0, physicsClientId=cid)
        dt = 1e-3
        pb.setPhysicsEngineParameter(fixedTimeStep=dt, physicsClientId=cid)
        body = pb.loadURDF(urdf, [0, 0, 1], flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=cid)
        names = {
            pb.getJointInfo(body, j, physicsClientId=cid)[1].decode(): j
            for j in range(pb.getNumJoints(body, physicsClientId=cid))
        }
        for k in (-1, *names.values()):
            pb.changeDynamics(body, k, linearDamping=0.0, angularDamping=0.0, physicsClientId=cid)
        missing = sorted((set(wing_joints_deg) | {"leg"}) - set(names))
        if missing:
            raise UsageError(f"the robot has no joint {missing[0]!r}; give the lab robot's URDF with --robot")
        joints = [names[n] for n in wing_joints_deg] + [names["leg"]]
        wing = [math.radians(v) for v in wing_joints_deg.values()]
        a = math.radians(amplitude_deg)
        for j, q in zip(joints, [*wing, a], strict=True):
            pb.resetJointState(body, j, q, physicsClientId=cid)
        r0 = _rotation(pb, body, cid)
        for k in range(int(round((SWING_S + 0.1) / dt))):
            s = min(max((k * dt - 0.05) / SWING_S, 0.0), 1.0)
            leg = a * math.cos(math.pi * s)  # +A to -A, at rest at both ends
            pb.setJointMotorControlArray(
                body, joints, pb.POSITION_CONTROL, targetPositions=[*wing, leg], forces=[1.0] * len(joints),
                physicsClientId=cid,
            )  # fmt: skip
            pb.stepSimulation(physicsClientId=cid)
        d = r0.T @ _rotation(pb, body, cid)  # the turn in the body frame
        return math.degrees(math.atan2(d[1, 0], d[0, 0]))
    finally:
        pb.disconnect(physicsClientId=cid)


def _rotation(pb, body, cid) -> np.ndarray:
    q = pb.getBasePositionAndOrientation(body, physicsClientId=cid)[1]
    return np.array(pb.getMatrixFromQuaternion(q, physicsClientId=cid)).reshape(3, 3)


def hold_pitch_deg(recs) -> dict[float, float]:
    """The robot's hold pitch in its IMU's frame per wing command, degrees: the median over the first openings
    with the leg still (``landscape physical kinematics``' second table), from the recordings ``recs``."""
    holds: dict[float, list[float]] = {}
    for rec in recs:
        if rec.theta_l_deg == 0.0:
            r = opening_response(rec.t_s, rec.pitch_deg, rec.roll_deg, float(rec.openings_s[0]))
            holds.setdefault(rec.theta_w_cmd_deg, []).append(r.hold_pitch_deg)
    return {c: float(np.nanmedian(v)) for c, v in sorted(holds.items())}


def free_body_table(urdf: str, model_set, hold_deg: dict[float, float]) -> str:
    """The first table: per wing command (``hold_deg``: the robot's hold pitch there), the free body's turn and
    the tilt it gives, for leg amplitudes 15, 30 and 45 deg."""
    from geometry.joint_map import JointMap

    wing_names = JointMap().wing
    lines = [
        f"free body (no gravity, no ground), wings where {model_set.name} holds them, leg +A -> -A in "
        f"{SWING_S:g} s: turn about body z / lateral tilt at the robot's hold pitch",
        "| wing cmd | hold pitch | leg 15° | leg 30° | leg 45° |",
        "|---|---|---|---|---|",
    ]
    for cmd, p in hold_deg.items():
        joints = model_set.wing_joints_deg(wing_names, cmd) or dict.fromkeys(wing_names, cmd)
        cells = []
        for amp in (15.0, 30.0, 45.0):
            turn = free_turn_deg(urdf, joints, amp)
            tilt = math.degrees(math.asin(math.sin(math.radians(p)) * math.sin(math.radians(turn))))
            cells.append(f"{turn:+.1f}° / {tilt:+.1f}°")
        lines.append(f"| {cmd:.0f}° | {p:.1f}° | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def tilt_table(recs, urdf: str, sets: list[str], cells, phase: float) -> str:
    """The second table (see the module docstring) from the recordings ``recs``
    (:func:`landscape.analysis.physical.recording.read_recording`) and the model sets ``sets`` (names or files, as given)."""

    ts = np.asarray(TIMES_S)
    head = " | ".join(f"{t:g} s" for t in ts)
    lines = [
        "lateral tilt after the first opening starts (robot: median over its first openings; sets: one first "
        f"opening at leg phase {phase:g}); last column: the leg's downward swing (robot: command; sets: zero crossing)",
        f"| wing cmd | leg | who | {head} | leg swings down |",
        "|---|---|---|" + "---|" * len(ts) + "---|",
    ]
    for w, leg in cells:
        tilts, downs = [], []
        for rec in recs:
            if rec.theta_w_cmd_deg != w or rec.theta_l_deg != leg:
                continue
            s = float(rec.openings_s[0])
            t = rec.t_s - s
            tilts.append(np.interp(ts, t, lateral_tilt_deg(rec.pitch_deg, rec.roll_deg)))
            ups = rec.leg_up_s[rec.leg_up_s <= s + 1e-9]
            if len(ups) and leg > 0:
                downs.append(float(ups[-1]) + PAPER_LEG_PERIOD_S / 2 - s)
        if not tilts:
            continue
        row = " | ".join(f"{v:+.1f}°" for v in np.median(tilts, axis=0))
        down = f"{np.median(downs):.2f} s" if downs else "–"
        lines.append(f"| {w:.0f}° | {leg:.0f}° | robot ({len(tilts)}) | {row} | {down} |")
        for name in sets:
            tr, starts = simulated_openings(w, leg, model_set=name, robot=urdf, seed=0, phase=phase)
            t = tr.t_s - starts[0]
            row = " | ".join(
                f"{v:+.1f}°" for v in np.interp(ts, t, lateral_tilt_deg(tr.pitch_deg, tr.roll_deg))
            )
            legd = np.asarray(tr.leg_deg)
            cross = np.flatnonzero((legd[:-1] > 0) & (legd[1:] <= 0) & (t[1:] > 0))
            down = f"{t[cross[0] + 1]:.2f} s" if len(cross) and leg > 0 else "–"
            lines.append(f"| {w:.0f}° | {leg:.0f}° | {name} | {row} | {down} |")
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())
