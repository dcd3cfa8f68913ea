"""Fit the built-in robot's shell to the lab robot's head and wing meshes (wings closed).

The shell is the lower half of an axis-aligned ellipsoid: z = zc - c sqrt(1 - ((x - cx)/a)^2 - (y/b)^2) in the
body frame. Its parameters are fitted to every head and wing vertex of ../shared/ref/lab_robot at
theta_w = theta_l = 0 by least squares on the height residual, and the (x, y) extent of each lab part is
printed: geometry/builtin.py hard-codes the rounded results.

    python benchmarks/fit_builtin_shell.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from geometry import Robot

URDF = Path(__file__).resolve().parents[1].parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"


def main() -> int:
    if not URDF.is_file():
        print(f"needs {URDF}", file=sys.stderr)
        return 1
    pose = Robot.from_urdf(URDF).pose(0.0, 0.0)
    parts = {}
    for part in pose.parts:
        if part.link in ("head", "wing1", "wing2"):
            T = pose.link_transforms[part.link]
            parts[part.link] = (part.points_link_m @ T[:3, :3].T + T[:3, 3]) * 1e3
    pts = np.concatenate(list(parts.values()))

    def height(q, x, y):
        cx, a, b, zc, c = q
        rho2 = ((x - cx) / a) ** 2 + (y / b) ** 2
        return zc - c * np.sqrt(np.clip(1.0 - rho2, 0.0, None))

    fit = least_squares(lambda q: height(q, pts[:, 0], pts[:, 1]) - pts[:, 2], [0, 140, 120, 27, 40])
    rms = float(np.sqrt(np.mean(fit.fun**2)))
    print("shell centre x, semi-axis a, semi-axis b, rim z, depth c (mm):", np.round(fit.x, 2).tolist())
    print(f"rms height residual {rms:.2f} mm over {len(pts)} vertices")
    for name, v in parts.items():
        print(f"{name}: x {v[:, 0].min():.1f}..{v[:, 0].max():.1f} mm, |y| {np.abs(v[:, 1]).min():.1f}.."
              f"{np.abs(v[:, 1]).max():.1f} mm, z {v[:, 2].min():.1f}..{v[:, 2].max():.1f} mm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
