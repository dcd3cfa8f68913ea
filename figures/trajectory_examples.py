"""Trajectory and video figures for the README: six simulated trials of the built-in robot at wing angle 74° and
leg angle 30° drawn on their landscape, the physical robot's recorded attempts at the 75° wing command on the lab
robot's landscape (when ../shared is present), and one frame of a trial video.

    .venv/bin/python figures/trajectory_examples.py

Writes figures/trajectories_sim.png, trajectories_sim_contour.png, trajectories_physical_contour.png and
video_frame.png (every file from the `landscape` commands the README shows).
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

from landscape.cli import main as landscape

HERE = Path(__file__).resolve().parent
DATA = HERE.parent.parent / "shared" / "ref" / "physical_robot"
LAB = HERE.parent.parent / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"
TRIALS = [(0.1, 1), (0.3, 2), (0.5, 3), (0.7, 4), (0.9, 5), (0.2, 6)]  # (phase, seed), Cv 0.1


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        traces = []
        for phase, seed in TRIALS:
            trace = tmp / f"t{seed}.csv"
            code = landscape(
                [
                    "simulate",
                    "--theta-w",
                    "74",
                    "--theta-l",
                    "30",
                    "--phase",
                    str(phase),
                    "--cv",
                    "0.1",
                    "--seed",
                    str(seed),
                    "--duration",
                    "6",
                    "--trace",
                    str(trace),
                ]
            )
            if code:
                return code
            traces += ["--trace", str(trace)]
        if landscape(["render", *traces, "--out", str(tmp / "sim")]):
            return 1
        shutil.copyfile(tmp / "sim" / "trajectories.png", HERE / "trajectories_sim.png")
        shutil.copyfile(tmp / "sim" / "trajectories_contour.png", HERE / "trajectories_sim_contour.png")
        if DATA.is_dir():
            if landscape(
                [
                    "render",
                    "--physical",
                    str(DATA),
                    "--theta-w",
                    "75",
                    "--robot",
                    str(LAB),
                    "--out",
                    str(tmp / "phys"),
                ]
            ):
                return 1
            shutil.copyfile(
                tmp / "phys" / "trajectories_contour.png", HERE / "trajectories_physical_contour.png"
            )
        gif = tmp / "trial.gif"
        if landscape(
            [
                "simulate",
                "--theta-w",
                "74",
                "--theta-l",
                "30",
                "--phase",
                "0.7",
                "--cv",
                "0.1",
                "--seed",
                "4",
                "--duration",
                "3",
                "--video",
                str(gif),
            ]
        ):
            return 1
        from PIL import Image

        with Image.open(gif) as im:
            im.seek(im.n_frames * 2 // 3)
            im.convert("RGB").save(HERE / "video_frame.png")
    print(
        "wrote figures/trajectories_sim.png, trajectories_sim_contour.png, trajectories_physical_contour.png, "
        "video_frame.png"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
