"""Where can the body come to rest while the wings are held open? (issue #15: the time to right at 90 deg)

The robot at 90 deg is upright (world-up's body-z component below zero) 0.33-0.6 s after its first opening starts,
with its wings still open; every model set rights only as its wings close, about 1.1 s. This script asks the
landscape, without dynamics: with the wings held at a set's plateau for a command and the leg at each angle, which
local minima of the energy (1-degree grid, 8 neighbours, refined by descent) lie below the hold, the lowest
upright one (u_z < 0) and the lowest one that is not, with the parts that touch the ground there, and the
righting barrier out of that one (``landscape compute --start-pitch P --start-roll R``) beside the hold's. A body
thrown out of the hold with its wings open that lands in such a state rests there, propped on its side, until
the leg gives it that much or the wings close.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/open_wing_minima.py [--robot URDF] [--model physical-head]
      [--commands 60,75,90] [--legs 0,30,-30]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from geometry.frames import up_vector
from geometry.robots import load_robot
from landscape.analysis.physical.hold import support_links
from landscape.barriers import _flood_kernels
from landscape.computation import compute, posed, start_orientation
from landscape.energy import G_M_S2, energy_landscape, height_at
from landscape.minima import local_descent
from sim.model_set import load_model_set

ROOT = Path(__file__).resolve().parents[2]


def local_minima(pose) -> list[tuple[float, float]]:
    """Every local minimum of the 1-degree landscape (no lower 8-neighbour), refined by descent, without
    repeats: (pitch, roll) in degrees."""
    ls = energy_landscape(pose, step_deg=1.0)
    low = _flood_kernels.local_minima(ls.energy_j, 0.0).reshape(ls.energy_j.shape)
    out: list[tuple[float, float]] = []
    for i, j in np.argwhere(low):
        p, r = local_descent(pose, float(ls.angles_deg[i]), float(ls.angles_deg[j]))
        u = up_vector(math.radians(p), math.radians(r))
        if not any(
            np.dot(u, up_vector(math.radians(a), math.radians(b))) > math.cos(math.radians(1.0))
            for a, b in out
        ):
            out.append((p, r))
    return out


def describe(pose, mass_kg: float, p: float, r: float) -> dict:
    u = up_vector(math.radians(p), math.radians(r))
    return {
        "at_deg": (p, r),
        "energy_mj": float(height_at(pose, p, r)) * mass_kg * G_M_S2 * 1e3,
        "up_z": float(u[2]),
        "tilt_deg": math.degrees(math.asin(max(-1.0, min(1.0, float(u[1]))))),
        "touching": support_links(pose, p, r),
    }


def righting_mj(robot, theta_w: float, leg: float, joints: dict, at_deg: tuple[float, float]) -> float:
    """The righting barrier out of the minimum at ``at_deg`` (pitch, roll), mJ: ``landscape compute --start-pitch
    --start-roll`` with the set's wing joints."""
    comp = compute(
        robot, theta_w_deg=theta_w, theta_l_deg=leg, wing_joints_deg=joints, start_pitch_deg=at_deg[0],
        start_roll_deg=at_deg[1], landscape_grid=False,
    )  # fmt: skip
    return comp.barrier.righting.barrier_j * 1e3


def cell(m: dict | None, *, tilt: bool = True, barrier_mj: float | None = None) -> str:
    """One minimum as a table cell: energy, u_z, lateral tilt, the parts touching, the righting barrier."""
    if m is None:
        return "–"
    out = f"{m['energy_mj']:.1f}, {m['up_z']:+.2f}" + (f", {m['tilt_deg']:+.0f}°" if tilt else "")
    out += f", {'+'.join(m['touching'])}"
    return out + ("" if barrier_mj is None else f"; {barrier_mj:.1f} mJ")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--model", default="physical-head", help="a measured model set (it poses the wings)")
    ap.add_argument("--commands", default="60,75,90", help="wing commands, degrees")
    ap.add_argument("--legs", default="0,30,-30", help="leg angles, degrees")
    a = ap.parse_args(argv)
    try:
        commands = [float(v) for v in a.commands.split(",")]
        legs = [float(v) for v in a.legs.split(",")]
        ms = load_model_set(a.model)
        if ms.measured is None:
            raise UsageError(f"--model {a.model} sets every wing joint to theta_w; give a measured set")
        robot = ms.robot_for(load_robot(a.robot))
        joints = {
            c: ms.wing_joints_deg(robot.joint_map.wing, c) for c in commands
        }  # refuses unmeasured commands
        poses = {
            (c, leg): posed(robot, c, leg, joints[c]) for c in commands for leg in legs
        }  # and leg limits
    except ValueError as exc:  # UsageError is one; float() of a bad list too
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"robot {robot.name}, model set {ms.name}; energies in mJ; tilt = asin(u_y)")
    print(
        "| wing cmd | leg | hold: E, u_z, on; righting barrier | lowest below the hold, not upright: E, u_z, tilt, "
        "on; righting barrier | lowest upright: E, u_z, tilt, on |"
    )
    print("|---|---|---|---|---|")
    for (c, leg), pose in poses.items():
        hold = start_orientation(robot, pose, c, leg, wing_joints_deg=joints[c])
        h = describe(pose, pose.mass_kg, *hold)
        found = [describe(pose, pose.mass_kg, p, r) for p, r in local_minima(pose)]
        below = [m for m in found if m["energy_mj"] < h["energy_mj"] - 0.1]
        side = min((m for m in below if m["up_z"] >= 0), key=lambda m: m["energy_mj"], default=None)
        upright = min((m for m in found if m["up_z"] < 0), key=lambda m: m["energy_mj"], default=None)
        hold_b = righting_mj(robot, c, leg, joints[c], hold)
        side_b = righting_mj(robot, c, leg, joints[c], side["at_deg"]) if side else None
        print(
            f"| {c:g}° | {leg:+g}° | {cell(h, tilt=False, barrier_mj=hold_b)} | {cell(side, barrier_mj=side_b)} | "
            f"{cell(upright)} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
