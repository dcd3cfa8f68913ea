"""Why does the physical robot rest 3–7° further over than the model while its wings are held open? (issue #15 §0)

For each wing command (60, 75, 90°) the table puts the robot's resting pitch (median over the openings with the
leg still, 0.5–0.95 s after an opening starts, minus the rest before the first opening:
``landscape physical kinematics``) beside candidate explanations, each measured the same way:

- ``model``: the landscape's metastable minimum with every wing joint at the measured plateau (the model of
  ``landscape physical kinematics``);
- ``per-servo``: the four wing servos each at its own measured plateau (the knots of the shipped ``physical``
  set, fitted from motor_pulse_v2.mat by ``landscape physical actuation``): left/right and pitch/roll servos
  differ by up to 5° at command 90;
- ``sim paper``/``sim physical``: the pybullet simulation (friction μ = 1, the set's actuation), leg still,
  pitch during the first and second holds minus the rest before the first opening: does friction hold the body
  above the frictionless minimum, as the robot's history-dependent rest suggests?
- ``sim compliant``: the same with compliant wing joints (``--compliance K,C``, N·m/rad and N·m·s/rad;
  :mod:`sim.compliance`): do wings that give under the load let the body lean further over?

Run:  PYTHONPATH=. .venv/bin/python benchmarks/resting_pose_causes.py [--data DIR] [--robot URDF]
      [--compliance 0.9,0.005]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from geometry.robots import load_robot
from landscape.analysis.opening import per_servo_hold_deg
from landscape.analysis.physical import resting_pitch_table
from landscape.minima import metastable_orientation
from sim.compliance import Compliance
from sim.model_set import load_model_set
from sim.trial import run_trial

ROOT = Path(__file__).resolve().parents[1]


def sim_hold_pitch_deg(
    robot_file: str, set_name: str, command_deg: float, plateau_deg: float, compliance=None
) -> tuple[float, float]:
    """Simulated pitch in the first and second holds (0.5–0.95 s after each opening) minus the rest before the
    first opening, leg still, no noise."""
    ms = load_model_set(set_name)
    w = command_deg if ms.profile == "measured" else plateau_deg
    r = run_trial(
        w, 0.0, phase=0.5, cv=0.0, rng=1, robot=robot_file, duration_s=4.5, trace=True, model_set=ms,
        compliance=compliance,
    )  # fmt: skip
    tr, s = r.trace, r.attempt_starts_s
    before = np.median(tr.pitch_deg[(tr.t_s > s[0] - 0.3) & (tr.t_s < s[0])])
    holds = [np.median(tr.pitch_deg[(tr.t_s > t + 0.5) & (tr.t_s < t + 0.95)]) - before for t in s[:2]]
    return float(holds[0]), float(holds[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument(
        "--compliance", default="0.9,0.005", help="K,C of the compliant column (N m/rad, N m s/rad)."
    )
    args = ap.parse_args(argv)
    comp = Compliance(*(float(x) for x in args.compliance.split(",")))
    robot = load_robot(args.robot)
    measured = load_model_set("physical").measured
    rows = resting_pitch_table(args.data)
    ref = metastable_orientation(robot, 0.0, 0.0)[0]
    print(f"robot {robot.name}; model rest at theta_w 0: pitch {ref:.1f}°; pitch relative to that rest")
    head = ("command", "plateau", "robot", "model", "per-servo", "sim paper 1st/2nd", "sim physical 1st/2nd",
            f"sim physical, k {comp.wing_stiffness_n_m_rad:g} c {comp.wing_damping_n_m_s_rad:g}")  # fmt: skip
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        start = metastable_orientation(robot, r.theta_w_measured_deg, 0.0)
        model = start[0] - ref
        servo = per_servo_hold_deg(robot, measured, [r.theta_w_cmd_deg])[r.theta_w_cmd_deg] - ref
        sp = sim_hold_pitch_deg(args.robot, "paper", r.theta_w_cmd_deg, r.theta_w_measured_deg)
        sf = sim_hold_pitch_deg(args.robot, "physical", r.theta_w_cmd_deg, r.theta_w_measured_deg)
        sc = sim_hold_pitch_deg(args.robot, "physical", r.theta_w_cmd_deg, r.theta_w_measured_deg, comp)
        print(
            f"| {r.theta_w_cmd_deg:g}° | {r.theta_w_measured_deg:.1f}° | {r.median_deg:.1f}° | {model:.1f}° "
            f"({model - r.median_deg:+.1f}) | {servo:.1f}° ({servo - r.median_deg:+.1f}) | "
            f"{sp[0]:.1f}° / {sp[1]:.1f}° | {sf[0]:.1f}° / {sf[1]:.1f}° | {sc[0]:.1f}° / {sc[1]:.1f}° |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
