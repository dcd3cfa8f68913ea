"""compute and barrier_map: the memory estimate that guards big grids, the barrier map's contents."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from geometry.errors import UsageError
from geometry.robots import load_robot
from landscape.computation import BYTES_PER_CELL, barrier_map, check_memory, compute, landscape_memory_bytes


@pytest.fixture(scope="module")
def robot():
    return load_robot()


@pytest.mark.parametrize("method", ["exact", "grid"])
def test_memory_estimate_matches_the_measured_peak(robot, method):
    """BYTES_PER_CELL is what compute really needs: tracemalloc's peak at a 0.5 deg grid within 15 %."""
    compute(robot, theta_w_deg=74.0, step_deg=2.0, method=method)  # compile and cache outside the measurement
    tracemalloc.start()
    try:
        compute(robot, theta_w_deg=74.0, step_deg=0.5, method=method)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak == pytest.approx(landscape_memory_bytes(0.5), rel=0.15)
    assert landscape_memory_bytes(0.5) == BYTES_PER_CELL * 720**2


def test_a_grid_over_the_budget_is_refused_before_any_work(robot):
    with pytest.raises(UsageError, match=r"0.05 deg grid needs about 3.7 GB .* more than the 2 GiB budget"):
        check_memory(0.05)
    with pytest.raises(UsageError, match="more than the"):
        compute(robot, theta_w_deg=74.0, step_deg=0.5, memory_budget_bytes=1e6)


def test_barrier_map_keeps_the_barriers_not_the_grids(robot):
    bm = barrier_map(robot, [70.0, 74.0], [0.0, 30.0])
    assert bm.righting_j.shape == (2, 2) and np.isfinite(bm.righting_j).all()
    assert [(c.theta_w_deg, c.theta_l_deg) for c in bm.computations] == [(70, 0), (70, 30), (74, 0), (74, 30)]
    assert all(c.landscape is None and c.pose is None for c in bm.computations)
    one = compute(robot, theta_w_deg=74.0, theta_l_deg=30.0)
    assert bm.righting_j[1, 1] == pytest.approx(one.barrier.righting.barrier_j, rel=1e-9)
    with pytest.raises(UsageError, match="needs a robot with joints"):
        import trimesh

        from geometry import Robot

        barrier_map(Robot.from_trimesh(trimesh.creation.box(extents=(1, 1, 1))), [0.0], [0.0])
