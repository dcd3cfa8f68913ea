"""The README tour's pictures (``figures/tour/``): the tour's render, sweep and report commands, exactly as the
README gives them, run in a scratch directory, and the images the README shows copied from their outputs.

Run:  PYTHONPATH=. .venv/bin/python figures/tour_figures.py [--scratch DIR]

``--scratch DIR`` keeps the outputs there (the sweep resumes from ``DIR/builtin_reduced.sqlite`` if it exists);
without it a temporary directory is used and removed.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUT = HERE / "tour"
COMMANDS = (
    "render --theta-w 74 --theta-l 30 --out render/",
    "sweep --cv 0.1 --trials 3 --db builtin_reduced.sqlite --workers 2 --no-progress",
    "report --db builtin_reduced.sqlite --out report",
)
"""The README tour's commands whose outputs it shows, in its order."""
COPIES = {
    "render/landscape.png": "render_landscape.png",
    "render/contour.png": "render_contour.png",
    "render/robot_saddle.png": "render_robot_saddle.png",
    "report/probability.png": "report_probability.png",
    "report/trajectories/trajectories_contour.png": "report_trajectories.png",
}
"""Output (relative to the scratch directory) -> its name in ``figures/tour/``."""


def make(scratch: Path) -> list[Path]:
    for command in COMMANDS:
        print(f"$ landscape {command}", flush=True)
        r = subprocess.run([sys.executable, "-m", "landscape", *command.split()], cwd=scratch)
        if r.returncode != 0:
            raise SystemExit(f"tour_figures: `landscape {command}` failed (exit {r.returncode})")
    missing = [src for src in COPIES if not (scratch / src).is_file()]
    if missing:
        raise SystemExit(
            f"tour_figures: the tour wrote no {', '.join(missing)} in {scratch}; see its output above"
        )
    OUT.mkdir(exist_ok=True)
    written = []
    for src, name in COPIES.items():
        shutil.copyfile(scratch / src, OUT / name)
        written.append(OUT / name)
    return written


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scratch", type=Path, help="keep the tour's outputs in this directory")
    a = ap.parse_args(argv)
    if a.scratch is not None:
        a.scratch.mkdir(parents=True, exist_ok=True)
        written = make(a.scratch)
    else:
        with tempfile.TemporaryDirectory() as d:
            written = make(Path(d))
    print("wrote " + ", ".join(str(p.relative_to(HERE.parent)) for p in written))


if __name__ == "__main__":
    main()
