"""landscape/computation.py: the memory estimate that guards big grids, the barrier map's contents, the shared
continuation of a barrier map against its per-pair definition."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from geometry import Robot
from geometry.errors import UsageError
from geometry.robots import load_robot
from landscape.computation import (
    BYTES_PER_CELL,
    barrier_map,
    check_memory,
    compute,
    landscape_memory_bytes,
    sweep_starts,
)
from landscape.minima import metastable_orientation


@pytest.fixture(scope="module")
def robot():
    return load_robot()


@pytest.mark.parametrize("method", ["exact", "grid"])
def test_memory_estimate_matches_the_measured_peak(robot, method):
    """BYTES_PER_CELL is what compute really needs: tracemalloc's peak at a 0.5 deg grid within 15 % for the
    grid method, the hungriest, and below it for the others."""
    compute(robot, theta_w_deg=74.0, step_deg=2.0, method=method)  # compile and cache outside the measurement
    tracemalloc.start()
    try:
        compute(robot, theta_w_deg=74.0, step_deg=0.5, method=method)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    if method == "grid":
        assert peak == pytest.approx(landscape_memory_bytes(0.5), rel=0.15)
    else:
        assert 0.2 * landscape_memory_bytes(0.5) < peak <= landscape_memory_bytes(0.5)
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
    with pytest.raises(
        UsageError, match="a barrier map sweeps joint angles, and mesh is a single rigid body"
    ):
        import trimesh

        barrier_map(Robot.from_trimesh(trimesh.creation.box(extents=(1, 1, 1))), [0.0], [0.0])


def test_sweep_starts_agree_with_metastable_orientation_per_pair(each_robot):
    """One shared continuation (theta_w rising through every requested value, a theta_l branch at each) ends
    where the slow opening of :func:`metastable_orientation` ends, pair by pair, negative theta_w included."""
    robot = Robot.from_urdf(each_robot.urdf)
    theta_w_deg, theta_l_deg = [-5.0, 0.0, 60.0, 90.0], [-60.0, 0.0, 60.0]
    starts = sweep_starts(robot, theta_w_deg, theta_l_deg)
    assert sorted(starts) == sorted((w, tl) for w in theta_w_deg for tl in theta_l_deg)
    for (w, tl), (pitch_deg, roll_deg) in starts.items():
        assert (pitch_deg, roll_deg) == pytest.approx(metastable_orientation(robot, w, tl), abs=1e-9), (w, tl)
    # the grid is one where both joints move the minimum, so a branch taken from the wrong state shows
    assert starts[(90.0, 0.0)][0] - starts[(-5.0, 0.0)][0] > 45.0
    assert len({starts[(0.0, tl)] for tl in theta_l_deg}) > 1
