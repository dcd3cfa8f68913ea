"""Should the grid search keep its own torus flood, or run on the graph flood with the torus as a CSR graph?

Times ``landscape.barriers._flood_kernels.flood`` (neighbours computed on the torus) against ``flood_graph``
(neighbours read from a CSR adjacency listing the same 8 or 4 neighbours in the same order, so every tie breaks
alike) on the built-in robot's landscape at theta_w 74 deg, for the righting search, best of N, and checks that
both return the same levels, cells and search tree.

    .venv/bin/python benchmarks/flood_kernels.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import time
from functools import partial

import numpy as np

from geometry.robots import load_robot
from landscape.barriers import _flood_kernels
from landscape.energy import energy_landscape
from landscape.minima import grid_minimum


def torus_csr(n: int, connectivity: int) -> tuple[np.ndarray, np.ndarray]:
    """The torus grid's adjacency in the order ``flood`` visits it (di, dj from -1 to 1): 8 (or 4) int64 a cell,
    64 bytes a cell at 8-connectivity, on top of the 72 a grid computation needs."""
    offsets = [
        (di, dj)
        for di in (-1, 0, 1)
        for dj in (-1, 0, 1)
        if (di or dj) and (connectivity == 8 or not (di and dj))
    ]
    i, j = np.divmod(np.arange(n * n), n)
    idx = np.stack([((i + di) % n) * n + (j + dj) % n for di, dj in offsets], axis=1).ravel().astype(np.int64)
    ptr = np.arange(0, len(idx) + 1, len(offsets), dtype=np.int64)
    return ptr, idx


def best(fn, repeat: int) -> tuple[float, object]:
    out, times = None, []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    pose = load_robot().pose(74.0, 0.0)
    print(
        "Result: the floods run equally fast and agree exactly, but the graph form needs the CSR adjacency: built per"
    )
    print(
        "grid step (the build column) and held in memory (64 bytes a cell), so the torus keeps its own flood.\n"
    )
    print(
        "| grid | connectivity | torus flood (ms) | graph flood (ms) | CSR build (ms) | ratio graph/torus | same |"
    )
    print("|---|---|---:|---:|---:|---:|---|")
    for step in (1.0, 0.5, 0.25):
        ls = energy_landscape(pose, step_deg=step)
        e = np.ascontiguousarray(ls.energy_j)
        n = e.shape[0]
        i0, j0 = grid_minimum(ls, 69.0, 0.0)
        s = i0 * n + j0
        p, r = np.meshgrid(np.deg2rad(ls.angles_deg), np.deg2rad(ls.angles_deg), indexing="ij")
        target = np.ascontiguousarray((np.cos(p) * np.cos(r) < 0).ravel().astype(np.int8))  # upright: u_z < 0
        none = np.zeros(n * n, dtype=np.bool_)
        is_min = _flood_kernels.local_minima(e, 1e-12)
        for conn in (8, 4):
            t_csr, (ptr, idx) = best(partial(torus_csr, n, conn), 1)
            torus = partial(_flood_kernels.flood, e, s, target, none, is_min, none, 1e-12, conn, False)
            graph = partial(
                _flood_kernels.flood_graph, e.ravel(), ptr, idx, s, target, none, is_min, none, 1e-12, False
            )
            torus(), graph()  # compile or load from the cache outside the timing
            t_a, a = best(torus, args.repeat)
            t_b, b = best(graph, args.repeat)
            same = all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
            print(
                f"| {step:g}° ({n}x{n}) | {conn} | {t_a * 1e3:.2f} | {t_b * 1e3:.2f} | {t_csr * 1e3:.1f} | "
                f"{t_b / t_a:.2f} | {same} |"
            )


if __name__ == "__main__":
    main()
