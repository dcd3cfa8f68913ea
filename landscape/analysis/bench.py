"""``landscape bench``: speed and memory of the landscape and barrier search, against the lab's method
(every mesh vertex against every orientation, vectorised NumPy) measured in the same run."""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from geometry import Robot
from landscape.barriers.exact import exact_barrier
from landscape.barriers.grid import grid_barrier
from landscape.energy import brute_force_landscape, energy_landscape
from landscape.minima import grid_minimum, metastable_orientation


def _best_time(fn, repeat: int, *, warm: bool = True) -> tuple[float, object]:
    """Best of ``repeat`` timed runs (as timeit does: the least disturbed by other load), after a warm-up."""
    out = fn() if warm else None  # warm-up (numba compile is cached on disk)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.min(times)), out


def landscape_bench(
    robot: Robot, *, theta_w_deg: float = 74.0, theta_l_deg: float = 0.0, repeat: int = 20
) -> str:
    """Run the benchmark and return a markdown table."""
    pose = robot.pose(theta_w_deg, theta_l_deg) if robot.has_joints else robot.pose()
    points = pose.all_points_m()
    t0 = time.perf_counter()
    hull = pose.hull
    t_hull = time.perf_counter() - t0

    t_lab, lab = _best_time(
        lambda: brute_force_landscape(points, pose.com_m, pose.mass_kg, step_deg=1.0), 2, warm=False
    )
    t_ours, ours = _best_time(lambda: energy_landscape(pose, step_deg=1.0), repeat)
    rel = float(np.abs(ours.energy_j - lab).max() / np.abs(lab).max())

    start = metastable_orientation(robot, theta_w_deg, theta_l_deg) if robot.has_joints else (0.0, 0.0)
    cell = grid_minimum(ours, *start)
    t_bar, bar = _best_time(lambda: grid_barrier(ours, cell), repeat)
    t_exact, ex = _best_time(lambda: exact_barrier(pose, *start, sectors=False), 5)

    tracemalloc.start()
    t0 = time.perf_counter()
    fine = energy_landscape(pose, step_deg=0.1)
    t_fine = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    n_fine = len(fine.angles_deg)
    naive_bytes = n_fine * n_fine * len(points) * 8

    r = bar.righting
    re_ = ex.barrier.righting
    err = abs(r.barrier_j - re_.barrier_j) / re_.barrier_j if re_ and r else float("nan")
    rows = [
        ("robot", f"{robot.name}, theta_w {theta_w_deg:g}°, theta_l {theta_l_deg:g}°"),
        ("mesh vertices (lab method input)", f"{len(points)}"),
        ("hull vertices (ours)", f"{len(hull.vertices_m)} (hull built in {t_hull * 1e3:.1f} ms)"),
        ("1° landscape, lab method (numpy, all vertices, best of 2)", f"{t_lab * 1e3:.1f} ms"),
        (f"1° landscape, ours (hull walk, best of {repeat})", f"{t_ours * 1e3:.2f} ms"),
        ("speed-up, lab / ours", f"{t_lab / t_ours:.0f}x"),
        ("agreement, max |ours - lab| / max |lab|", f"{rel:.1e}"),
        (
            f"1° grid barriers (righting, pitch-, roll-wise, escape; best of {repeat})",
            f"{t_bar * 1e3:.2f} ms",
        ),
        ("righting barrier, 1° grid", f"{r.barrier_j * 1e3:.3f} mJ ({r.direction})" if r else "none"),
        ("exact righting + escape (hull face-edge graph, best of 5)", f"{t_exact * 1e3:.1f} ms"),
        ("righting barrier, exact", f"{re_.barrier_j * 1e3:.3f} mJ ({re_.direction})" if re_ else "none"),
        ("1° grid error against exact", f"{err * 100:.1f} %"),
        ("0.1° landscape (3600 x 3600 cells)", f"{t_fine:.2f} s, peak memory {peak / 2**20:.0f} MiB"),
        (
            "an orientations x vertices array at 0.1°",
            f"would be {naive_bytes / 2**30:.0f} GiB (never formed)",
        ),
    ]
    w = max(len(a) for a, _ in rows)
    lines = [f"| {'quantity':<{w}} | value |", f"|{'-' * (w + 2)}|-------|"]
    lines += [f"| {a:<{w}} | {b} |" for a, b in rows]
    return "\n".join(lines)
