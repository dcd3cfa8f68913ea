"""Pitch-wise and roll-wise exits of the exact method (issue #12): the single sector flood gives what the full
grid search gives, and compute's sectors equal the former construction from ``grid_barrier``."""

from dataclasses import replace

import numpy as np
import pytest

from geometry import Robot
from geometry.builtin import builtin_urdf_path
from landscape.barriers.grid import grid_barrier
from landscape.computation import _grid_sector_exit, _in_sector, compute
from landscape.minima import grid_minimum


@pytest.fixture(scope="module")
def robot():
    return Robot.from_urdf(builtin_urdf_path())


def _same_exit(a, b):
    assert (a is None) == (b is None)
    if a is None:
        return
    assert a.barrier_j == b.barrier_j
    assert (a.saddle_pitch_deg, a.saddle_roll_deg, a.direction) == (
        b.saddle_pitch_deg,
        b.saddle_roll_deg,
        b.direction,
    )
    np.testing.assert_array_equal(a.path_deg, b.path_deg)


@pytest.mark.parametrize("tw, tl", [(0.0, 0.0), (74.0, 30.0), (90.0, -40.0), (-8.0, 10.0)])
@pytest.mark.parametrize("connectivity", [8, 4])
def test_sector_flood_equals_grid_barrier(robot, tw, tl, connectivity):
    c = compute(robot, theta_w_deg=tw, theta_l_deg=tl, step_deg=2.0, method="grid", connectivity=connectivity)
    ls = c.landscape
    for cell in [grid_minimum(ls, c.minimum.pitch_deg, c.minimum.roll_deg), (3, 100), (90, 45)]:
        full = grid_barrier(ls, cell, connectivity=connectivity)
        _same_exit(_grid_sector_exit(ls, cell, "pitch", connectivity), full.pitch_wise)
        _same_exit(_grid_sector_exit(ls, cell, "roll", connectivity), full.roll_wise)


@pytest.mark.parametrize("tw, tl", [(0.0, 0.0), (74.0, 30.0), (90.0, -40.0)])
def test_exact_sectors_equal_former_construction(robot, tw, tl):
    c = compute(robot, theta_w_deg=tw, theta_l_deg=tl, step_deg=2.0, method="exact")
    ls, m, r = c.landscape, c.minimum, c.barrier.righting
    cell = grid_minimum(ls, m.pitch_deg, m.roll_deg)
    gb = grid_barrier(ls, cell)
    shift = ls.at(*cell) - m.energy_j
    for kind, got, x in (
        ("pitch", c.barrier.pitch_wise, gb.pitch_wise),
        ("roll", c.barrier.roll_wise, gb.roll_wise),
    ):
        if r is not None and _in_sector(r.path_deg, kind):
            want = replace(r, direction=kind)
        else:
            want = None if x is None else replace(x, barrier_j=x.barrier_j + shift)
        _same_exit(got, want)
