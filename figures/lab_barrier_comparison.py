"""Righting barrier of the lab robot over theta_w: the lab's published ray method, our grid search, exact.

Reads ../shared/ref (the lab URDF and lab_barrier.mat); writes figures/lab_barrier_comparison.{png,csv} and
prints a markdown table at a few wing angles. Run from the repository root:

    python figures/lab_barrier_comparison.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy.io as sio  # noqa: E402

from geometry import Robot  # noqa: E402
from landscape import compute, sweep_starts  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "ref"


def main() -> int:
    urdf = SHARED / "lab_robot" / "lab_robot.urdf"
    mat = SHARED / "physical_robot" / "lab_barrier.mat"
    if not (urdf.is_file() and mat.is_file()):
        print("needs ../shared/ref (lab URDF and lab_barrier.mat); not found", file=sys.stderr)
        return 1
    t0 = time.perf_counter()
    lab = sio.loadmat(mat, squeeze_me=True, struct_as_record=False)
    lab_mj = np.nanmin(lab["barrier"].val, axis=1)  # lowest first-peak over the 500 rays, mJ
    ws = list(np.round(np.arange(-10, 90.001, 0.5), 6))
    robot = Robot.from_urdf(urdf)
    starts = sweep_starts(robot, ws, [0.0])
    rows = []
    for w, lab_b in zip(ws, lab_mj, strict=True):
        g = compute(
            robot, theta_w_deg=w, theta_l_deg=0.0, step_deg=1.0, method="grid", start_deg=starts[(w, 0.0)]
        )
        e = compute(
            robot, theta_w_deg=w, theta_l_deg=0.0, step_deg=1.0, method="exact", start_deg=starts[(w, 0.0)]
        )
        rows.append(
            (
                w,
                lab_b,
                g.barrier.righting.barrier_j * 1e3,
                e.barrier.righting.barrier_j * 1e3,
                e.barrier.escape.barrier_j * 1e3 if e.barrier.escape else np.nan,
            )
        )
    a = np.array(rows)
    out = ROOT / "figures"
    np.savetxt(
        out / "lab_barrier_comparison.csv",
        a,
        delimiter=",",
        fmt="%.6g",
        header="theta_w_deg,lab_ray_mj,grid_1deg_righting_mj,exact_righting_mj,exact_escape_mj",
        comments="",
    )
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), dpi=120)
    for k, (lab_, style) in enumerate(
        [
            ("lab ray method (lab_barrier.mat)", "k."),
            ("grid 1°, 8-connected", "-"),
            ("exact righting", "-"),
            ("exact escape", "--"),
        ]
    ):
        for axis in (ax, ax2):
            axis.plot(a[:, 0], a[:, k + 1], style, label=lab_, ms=3, lw=1.3)
    ax.set_ylabel("barrier (mJ)")
    ax2.set_xlim(60, 90)
    ax2.set_ylim(0, 30)
    for axis in (ax, ax2):
        axis.set_xlabel("wing angle θw (°)")
        axis.grid(alpha=0.3)
    ax.legend()
    ax.set_title("Lab robot, θl = 0")
    ax2.set_title("zoom: θw 60–90°")
    fig.tight_layout()
    fig.savefig(out / "lab_barrier_comparison.png")
    print(
        "| θw (°) | lab ray method (mJ) | grid 1° righting (mJ) | exact righting (mJ) | exact escape (mJ) |"
    )
    print("|---:|---:|---:|---:|---:|")
    for w in (0, 30, 60, 70, 74, 80, 90):
        r = a[np.argmin(np.abs(a[:, 0] - w))]
        print(f"| {r[0]:g} | {r[1]:.2f} | {r[2]:.2f} | {r[3]:.2f} | {r[4]:.2f} |")
    print(
        f"\n{len(ws)} wing angles in {time.perf_counter() - t0:.1f} s; wrote figures/lab_barrier_comparison.png, .csv"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
