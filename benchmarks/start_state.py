"""Speed of the start state (the quasi-static continuation), former grid pattern search against face following.

For each robot (the built-in one always; the lab robot when ../shared/ref/lab_robot is present):

1. ``metastable_orientation`` at theta_w 74, theta_l 30: the former method (``baseline=True``: pose the robot
   and pattern-search h on the pitch-roll grid at every 1 deg step) against the new one (follow the resting
   face, roll exactly only where it is lost). Best of ``--repeat`` rounds, the rows interleaved so that load
   from other jobs affects both alike.
2. The starts of the lab's barrier map (theta_w -10..90 at 0.5, theta_l 0) by ``sweep_starts``, both ways.

Energy columns: ``dE raw`` is E(former end point) - E(new end point), J (the former search stops within
0.03 deg of the face, so it sits slightly above it); ``dE min`` compares the minima both reach (the former end
point rolled exactly onto its face), J; ``max |dE min|`` over the map's starts.

Run:  .venv/bin/python benchmarks/start_state.py [--repeat 3] [--no-map]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from geometry import Robot
from geometry.builtin import builtin_urdf_path
from landscape.computation import sweep_starts
from landscape.energy import G_M_S2, height_at
from landscape.minima import local_descent, metastable_orientation

LAB_URDF = Path(__file__).resolve().parents[1].parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
SHARED_LAB_URDF = Path("/work/shared/ref/lab_robot/lab_robot.urdf")


def _best(fn, repeat: int) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _energy(robot: Robot, tw: float, tl: float, pr: tuple[float, float]) -> tuple[float, float]:
    """Energy at an orientation and at the minimum it rolls to, J."""
    pose = robot.pose(tw, tl)
    mg = pose.mass_kg * G_M_S2
    return mg * float(height_at(pose, *pr)), mg * float(height_at(pose, *local_descent(pose, *pr)))


def bench_robot(name: str, robot: Robot, repeat: int, do_map: bool) -> None:
    tw, tl = 74.0, 30.0
    metastable_orientation(robot, tw, tl)  # warm caches (URDF, imports)
    t_old = t_new = np.inf
    for _ in range(repeat):
        dt, old = _best(lambda: metastable_orientation(robot, tw, tl, baseline=True), 1)
        t_old = min(t_old, dt)
        dt, new = _best(lambda: metastable_orientation(robot, tw, tl), 1)
        t_new = min(t_new, dt)
    e_old, e_old_min = _energy(robot, tw, tl, old)
    e_new, e_new_min = _energy(robot, tw, tl, new)
    print(
        f"{name:8s} start θw {tw:g} θl {tl:g}   former {1e3 * t_old:8.1f} ms   new {1e3 * t_new:8.1f} ms   "
        f"ratio {t_old / t_new:6.1f}   dE raw {e_old - e_new:+.2e} J   dE min {e_old_min - e_new_min:+.2e} J   "
        f"(pitch, roll) former ({old[0]:.4f}, {old[1]:.4f}) new ({new[0]:.4f}, {new[1]:.4f})"
    )
    if not do_map:
        return
    ws = [float(x) for x in np.arange(-10.0, 90.0 + 1e-9, 0.5)]
    t_old, s_old = _best(lambda: sweep_starts(robot, ws, [0.0], baseline=True), 1)
    t_new, s_new = _best(lambda: sweep_starts(robot, ws, [0.0]), repeat)
    worst = max(
        abs(_energy(robot, w, 0.0, s_old[(w, 0.0)])[1] - _energy(robot, w, 0.0, s_new[(w, 0.0)])[1])
        for w in ws
    )
    print(
        f"{name:8s} map starts θw -10..90 at 0.5 ({len(ws)})   former {1e3 * t_old:8.1f} ms   "
        f"new {1e3 * t_new:8.1f} ms   ratio {t_old / t_new:6.1f}   max |dE min| {worst:.2e} J"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-map", action="store_true", help="skip the barrier-map starts")
    args = ap.parse_args()
    bench_robot("built-in", Robot.from_urdf(builtin_urdf_path()), args.repeat, not args.no_map)
    lab = LAB_URDF if LAB_URDF.is_file() else SHARED_LAB_URDF
    if lab.is_file():
        bench_robot("lab", Robot.from_urdf(lab), args.repeat, not args.no_map)
    else:
        print("lab robot absent (../shared/ref/lab_robot); skipped")


if __name__ == "__main__":
    main()
