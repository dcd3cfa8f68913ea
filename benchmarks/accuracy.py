"""Accuracy against time: grid barriers at shrinking steps (4- and 8-connected) and icosphere barriers at rising
levels, versus the exact method (#3).

For the lab robot (../shared/ref/lab_robot when present, else the built-in robot) at theta_w in {60, 74, 90} and
for closed-form shapes, prints a markdown table (method, time, righting and escape barriers, absolute and
relative error against exact) and writes a log-log plot of error against time.

    python benchmarks/accuracy.py [--out figures/accuracy.png] [--steps 4 2 1 0.5 0.25] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import trimesh

from geometry import Robot
from landscape.barriers.exact import exact_barrier
from landscape.barriers.grid import grid_barrier
from landscape.barriers.sphere import sphere_barrier, sphere_graph
from landscape.computation import start_orientation, warm_up
from landscape.energy import energy_landscape
from landscape.minima import grid_minimum

LAB_URDF = Path(__file__).resolve().parents[2] / "shared" / "ref" / "lab_robot" / "lab_robot.urdf"


def _lab_robot() -> tuple[str, Robot] | None:
    if LAB_URDF.is_file():
        return "lab robot", Robot.from_urdf(LAB_URDF)
    try:
        from geometry.builtin import load_builtin_robot  # type: ignore[import-not-found]
    except ImportError:
        return None
    return "built-in robot", load_builtin_robot()


def _cases():
    """(name, pose, start (pitch, roll) deg, closed-form righting barrier J or None)."""
    g = 9.81
    out = []
    lab = _lab_robot()
    if lab is not None:
        name, robot = lab
        for tw in (60.0, 74.0, 90.0):
            pose = robot.pose(tw, 0.0)
            out.append((f"{name} θw={tw:g}", pose, start_orientation(robot, pose, tw, 0.0), None))
    box = Robot.from_trimesh(trimesh.creation.box(extents=(0.3, 0.2, 0.1)), mass_kg=1.0, com=[0, 0, 0])
    out.append(("box 0.3x0.2x0.1", box.pose(), (0.0, 0.0), g * (np.hypot(0.1, 0.05) - 0.05)))
    cube = Robot.from_trimesh(trimesh.creation.box(extents=(0.2,) * 3), mass_kg=1.0, com=[0, 0, 0])
    out.append(("cube 0.2", cube.pose(), (0.0, 0.0), g * 0.1 * (np.sqrt(2) - 1)))
    plate = Robot.from_trimesh(trimesh.creation.box(extents=(0.3, 0.3, 0.01)), mass_kg=1.0, com=[0, 0, 0])
    out.append(("plate 0.3x0.3x0.01", plate.pose(), (0.0, 0.0), g * (np.hypot(0.15, 0.005) - 0.005)))
    skew = Robot.from_trimesh(
        trimesh.creation.box(extents=(0.3, 0.2, 0.1)), mass_kg=1.0, com=[0.03, 0.015, -0.02]
    )
    out.append(("box, off-centre CoM", skew.pose(), (0.0, 0.0), None))
    return out


def _timed(fn, repeat: int):
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _grid(pose, step, conn, start):
    ls = energy_landscape(pose, step_deg=step)
    return grid_barrier(ls, grid_minimum(ls, *start), connectivity=conn)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("figures/accuracy.png"))
    ap.add_argument("--steps", type=float, nargs="+", default=[4.0, 2.0, 1.0, 0.5, 0.25])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--levels", type=int, nargs="+", default=[4, 5, 6, 7], help="icosphere levels")
    args = ap.parse_args(argv)
    warm_up()
    rows = []
    print(
        "| shape | method | time (ms) | righting (mJ) | abs err (mJ) | rel err | escape (mJ) | escape abs err (mJ) |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name, pose, start, closed in _cases():
        _ = pose.hull
        t_ex, ex = _timed(lambda pose=pose, start=start: exact_barrier(pose, *start), args.repeat)
        ref = ex.barrier.righting.barrier_j
        ref_esc = ex.barrier.escape.barrier_j if ex.barrier.escape else np.nan
        note = "" if closed is None else f" (closed form {closed * 1e3:.6f})"
        print(
            f"| {name} | exact{note} | {t_ex * 1e3:.1f} | {ref * 1e3:.6f} | 0 | 0 | {ref_esc * 1e3:.6f} | 0 |"
        )
        rows.append((name, "exact", 0, t_ex, 0.0))
        for conn in (4, 8):
            for step in args.steps:
                t, gb = _timed(
                    lambda pose=pose, step=step, conn=conn, start=start: _grid(pose, step, conn, start),
                    1 if step < 0.5 else args.repeat,
                )
                val = gb.righting.barrier_j
                esc = gb.escape.barrier_j if gb.escape else np.nan
                err = abs(val - ref)
                print(
                    f"| {name} | grid {step:g}° {conn}-conn | {t * 1e3:.1f} | {val * 1e3:.6f} | {err * 1e3:.6f} "
                    f"| {err / ref if ref else np.nan:.2e} | {esc * 1e3:.6f} | {abs(esc - ref_esc) * 1e3:.6f} |"
                )
                rows.append((name, f"grid {conn}", step, t, err / ref if ref else np.nan))
        for level in args.levels:
            sphere_graph(level)
            t, sb = _timed(
                lambda pose=pose, start=start, level=level: sphere_barrier(pose, *start, subdivisions=level),
                1 if level > 6 else args.repeat,
            )
            val = sb.barrier.righting.barrier_j
            esc = sb.barrier.escape.barrier_j if sb.barrier.escape else np.nan
            err = abs(val - ref)
            print(
                f"| {name} | sphere level {level} ({sb.n_vertices} dirs, {sphere_graph(level).spacing_deg:.2f}°) "
                f"| {t * 1e3:.1f} | {val * 1e3:.6f} | {err * 1e3:.6f} | {err / ref if ref else np.nan:.2e} "
                f"| {esc * 1e3:.6f} | {abs(esc - ref_esc) * 1e3:.6f} |"
            )
            rows.append((name, "sphere", level, t, err / ref if ref else np.nan))
    _plot(rows, args.out)
    print(f"\nwrote {args.out}")
    return 0


def _plot(rows, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(r[0] for r in rows))
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    floor = 1e-7  # exact has no discretisation error; drawn at this floor
    for i, name in enumerate(names):
        c = colors[i % len(colors)]
        for conn, ls in (("grid 4", ":"), ("grid 8", "-"), ("sphere", "--")):
            sel = [r for r in rows if r[0] == name and r[1] == conn]
            ax.plot(
                [r[3] for r in sel],
                [max(r[4], floor) for r in sel],
                ls,
                marker="s" if conn == "sphere" else "o",
                ms=3,
                color=c,
                label=f"{name}, {conn}-conn" if conn == "grid 8" else None,
            )
        t_ex = [r[3] for r in rows if r[0] == name and r[1] == "exact"][0]
        ax.plot([t_ex], [floor], "*", ms=11, color=c)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per barrier (s)")
    ax.set_ylabel("relative error of the righting barrier")
    ax.set_title(
        "Grid (solid: 8-conn, dotted: 4-conn), icosphere (dashed) vs exact (stars, at the floor)", fontsize=9
    )
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(True, which="both", alpha=0.3)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
