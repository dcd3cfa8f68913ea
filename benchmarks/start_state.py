"""Speed of the start state (the quasi-static continuation that follows the resting face).

For each robot (the built-in one always; the lab robot when ../shared/ref/lab_robot is present):

1. ``metastable_orientation`` at theta_w 74, theta_l 30: best of ``--repeat`` rounds, the end point and its
   energy, and ``dE min``, the energy of that end point minus the energy of the minimum exact rolling reaches
   from it, J (zero when the end point is a minimum).
2. The starts of the lab's barrier map (theta_w -10..90 at 0.5, theta_l 0): ``sweep_starts`` (one shared
   continuation) against ``metastable_orientation`` per pair, and ``max |dE|`` between the minima the two reach,
   J, over the map's starts.

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
    metastable_orientation(robot, tw, tl)  # warm caches (URDF, imports, kernels)
    t, end = _best(lambda: metastable_orientation(robot, tw, tl), repeat)
    e, e_min = _energy(robot, tw, tl, end)
    print(
        f"{name:8s} start θw {tw:g} θl {tl:g}   {1e3 * t:8.1f} ms   (pitch, roll) ({end[0]:.4f}, {end[1]:.4f})   "
        f"E {e:.6e} J   dE min {e - e_min:+.2e} J"
    )
    if not do_map:
        return
    ws = [float(x) for x in np.arange(-10.0, 90.0 + 1e-9, 0.5)]
    t_pair, s_pair = _best(lambda: {(w, 0.0): metastable_orientation(robot, w, 0.0) for w in ws}, 1)
    t_shared, s_shared = _best(lambda: sweep_starts(robot, ws, [0.0]), repeat)
    worst = max(
        abs(_energy(robot, w, 0.0, s_pair[(w, 0.0)])[1] - _energy(robot, w, 0.0, s_shared[(w, 0.0)])[1])
        for w in ws
    )
    print(
        f"{name:8s} map starts θw -10..90 at 0.5 ({len(ws)})   per pair {1e3 * t_pair:8.1f} ms   "
        f"shared {1e3 * t_shared:8.1f} ms   ratio {t_pair / t_shared:6.1f}   max |dE| {worst:.2e} J"
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
