"""The built-in robot side by side with the lab URDF: minimum pitch, minimum energy, righting barrier.

Prints a markdown table and writes figures/builtin_vs_lab.csv. Needs ../shared/ref/lab_robot (skipped without).

    python figures/builtin_vs_lab.py
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

from geometry import Robot
from geometry.builtin import load_builtin_robot
from landscape import compute

ROOT = Path(__file__).resolve().parents[1]
LAB = ROOT.parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
ANGLES = [(w, 0.0) for w in (0, 30, 60, 70, 74, 80, 90)] + [(74, tl) for tl in (20, 30, 40, 50)]


def rows():
    ours, lab = load_builtin_robot(), Robot.from_urdf(LAB)
    for tw, tl in ANGLES:
        a = compute(ours, theta_w_deg=tw, theta_l_deg=tl)
        b = compute(lab, theta_w_deg=tw, theta_l_deg=tl)
        ra, rb = a.barrier.righting.barrier_j * 1e3, b.barrier.righting.barrier_j * 1e3
        yield {
            "theta_w_deg": tw,
            "theta_l_deg": tl,
            "builtin_min_pitch_deg": round(a.minimum.pitch_deg, 2),
            "lab_min_pitch_deg": round(b.minimum.pitch_deg, 2),
            "builtin_min_energy_mj": round(a.minimum.energy_j * 1e3, 2),
            "lab_min_energy_mj": round(b.minimum.energy_j * 1e3, 2),
            "builtin_righting_mj": round(ra, 3),
            "lab_righting_mj": round(rb, 3),
            "barrier_diff_pct": round(100 * (ra - rb) / rb, 1),
        }


def main() -> int:
    if not LAB.is_file():
        print(f"needs {LAB}", file=sys.stderr)
        return 1
    table = list(rows())
    with (ROOT / "figures" / "builtin_vs_lab.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    print(
        "| θw (°) | θl (°) | min pitch built-in / lab (°) | min E built-in / lab (mJ) | "
        "righting barrier built-in / lab (mJ) | barrier diff |"
    )
    print("|---:|---:|---:|---:|---:|---:|")
    for r in table:
        print(
            f"| {r['theta_w_deg']:g} | {r['theta_l_deg']:g} | {r['builtin_min_pitch_deg']:.1f} / "
            f"{r['lab_min_pitch_deg']:.1f} | {r['builtin_min_energy_mj']:.1f} / {r['lab_min_energy_mj']:.1f} | "
            f"{r['builtin_righting_mj']:.2f} / {r['lab_righting_mj']:.2f} | {r['barrier_diff_pct']:+.0f} % |"
        )
    print("\nexact method, continuation start; lab = ../shared/ref/lab_robot/lab_robot.urdf")
    return 0


if __name__ == "__main__":
    sys.exit(main())
