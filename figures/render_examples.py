"""Example figures of `landscape render` for the README, at wing angle 74° and leg angle 30°.

Uses the lab robot (../shared/ref/lab_robot/lab_robot.urdf) when present, else the built-in robot. Writes
figures/landscape_74.png, contour_74.png, robot_start_74.png and robot_saddle_74.png. Needs pyvista and an
off-screen OpenGL (see landscape/viz/render.py).

    python figures/render_examples.py
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

from landscape.cli import main as landscape

ROOT = Path(__file__).resolve().parents[1]
LAB = ROOT.parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
THETA_W_DEG, THETA_L_DEG = 74, 30
FIGURES = {
    "landscape.png": "landscape_74.png",
    "contour.png": "contour_74.png",
    "robot_start.png": "robot_start_74.png",
    "robot_saddle.png": "robot_saddle_74.png",
}


def robot_urdf() -> Path:
    if LAB.is_file():
        return LAB
    try:
        from geometry.builtin import builtin_urdf_path
    except ImportError:
        sys.exit(f"needs {LAB} or the built-in robot (geometry.builtin)")
    return builtin_urdf_path()


def main() -> int:
    urdf = robot_urdf()
    with tempfile.TemporaryDirectory() as tmp:
        code = landscape(
            [
                "render",
                "--theta-w",
                str(THETA_W_DEG),
                "--theta-l",
                str(THETA_L_DEG),
                "--robot",
                str(urdf),
                "--out",
                tmp,
            ]
        )
        if code:
            return code
        for src, dst in FIGURES.items():
            shutil.copyfile(Path(tmp) / src, ROOT / "figures" / dst)
    print(f"{urdf.name}: wrote " + ", ".join(f"figures/{d}" for d in FIGURES.values()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
