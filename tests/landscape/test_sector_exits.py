"""Pitch-wise and roll-wise exits of the exact method (issue #12): the single sector flood gives what the full
grid search gives, with the grid given or its energies computed only where the flood reaches, and compute's and
the barrier map's sectors equal the former construction from ``grid_barrier`` on the whole grid (both reported by
the mirror-tie rule, ``positive_roll_twins``)."""

from dataclasses import replace

import numpy as np
import pytest

from geometry import Robot
from geometry.builtin import builtin_urdf_path
from landscape.barriers import method as barrier_method
from landscape.barriers.grid import grid_barrier
from landscape.computation import (
    _in_sector,
    _SectorGrid,
    barrier_map,
    compute,
    positive_roll_twins,
    sweep_starts,
)
from landscape.energy import G_M_S2, energy_landscape
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
        for grid in (_SectorGrid(c.pose, 2.0, G_M_S2, ls), _SectorGrid(c.pose, 2.0, G_M_S2)):
            _same_exit(grid.sector_exit(cell, "pitch", connectivity), full.pitch_wise)
            _same_exit(grid.sector_exit(cell, "roll", connectivity), full.roll_wise)


@pytest.mark.parametrize("tw, tl", [(0.0, 0.0), (74.0, 30.0), (-8.0, 10.0)])
def test_lazy_grid_equals_energy_landscape(robot, tw, tl):
    """Cells computed on first use hold energy_landscape's numbers, and the descent finds grid_minimum's cell."""
    pose = robot.pose(tw, tl)
    ls = energy_landscape(pose, step_deg=1.0)
    grid = _SectorGrid(pose, 1.0, G_M_S2)
    for p, r in [(0.0, 0.0), (37.0, -120.0), (-89.0, 179.0)]:
        assert grid.minimum_cell(p, r) == grid_minimum(ls, p, r)
    grid.sector_exit(grid.minimum_cell(0.0, 0.0), "roll", 8)
    assert 0 < grid.known.sum() < grid.known.size  # only part of the torus was computed
    np.testing.assert_array_equal(grid.energy[grid.known], ls.energy_j[grid.known])


@pytest.mark.parametrize("tw, tl", [(0.0, 0.0), (74.0, 30.0), (90.0, -40.0)])
def test_exact_sectors_equal_former_construction(robot, tw, tl):
    c = compute(robot, theta_w_deg=tw, theta_l_deg=tl, step_deg=2.0, method="exact")
    ls, m, r = c.landscape, c.minimum, c.barrier.righting
    cell = grid_minimum(ls, m.pitch_deg, m.roll_deg)
    gb = grid_barrier(ls, cell)
    shift = ls.at(*cell) - m.energy_j
    wants = []
    for kind, x in (("pitch", gb.pitch_wise), ("roll", gb.roll_wise)):
        if r is not None and _in_sector(r.path_deg, kind):
            wants.append(replace(r, direction=kind))
        else:
            wants.append(None if x is None else replace(x, barrier_j=x.barrier_j + shift))
    want = positive_roll_twins(c.pose, m, replace(c.barrier, pitch_wise=wants[0], roll_wise=wants[1]))
    _same_exit(c.barrier.pitch_wise, want.pitch_wise)
    _same_exit(c.barrier.roll_wise, want.roll_wise)


def _former_map_pose(robot, tw, tl, start_deg):
    """One map pose the unoptimised way: the whole landscape grid, the exact method's barriers, and the
    pitch-wise and roll-wise exits from ``grid_barrier`` on that grid (the full floods), shifted to the exact
    start energy, except where the exact righting path stays in the sector."""
    pose = robot.pose(tw, tl)
    ls = energy_landscape(pose, step_deg=1.0)
    m, b = barrier_method("exact").solve(pose, ls, start_deg, step_deg=1.0, connectivity=8, g_m_s2=G_M_S2)
    cell = grid_minimum(ls, m.pitch_deg, m.roll_deg)
    gb = grid_barrier(ls, cell)
    shift = ls.at(*cell) - m.energy_j
    r, out, searched = b.righting, [], 0
    for kind, x in (("pitch", gb.pitch_wise), ("roll", gb.roll_wise)):
        if r is not None and _in_sector(r.path_deg, kind):
            out.append(replace(r, direction=kind))
        else:
            searched += 1
            out.append(None if x is None else replace(x, barrier_j=x.barrier_j + shift))
    return m, positive_roll_twins(pose, m, replace(b, pitch_wise=out[0], roll_wise=out[1])), searched


def _assert_map_equals_former(robot, ws, ls_):
    bm = barrier_map(robot, ws, ls_, method="exact", workers=1)
    starts = sweep_starts(robot, ws, ls_)
    searched = 0
    for c in bm.computations:
        m, b, k = _former_map_pose(
            robot, c.theta_w_deg, c.theta_l_deg, starts[(c.theta_w_deg, c.theta_l_deg)]
        )
        searched += k
        assert abs(c.minimum.energy_j - m.energy_j) <= 1e-9
        assert (c.minimum.pitch_deg, c.minimum.roll_deg) == (m.pitch_deg, m.roll_deg)
        for name in ("righting", "pitch_wise", "roll_wise", "escape"):
            got, want = getattr(c.barrier, name), getattr(b, name)
            assert (got is None) == (want is None), (c.theta_w_deg, name)
            if got is not None:
                assert abs(got.barrier_j - want.barrier_j) <= 1e-9, (c.theta_w_deg, name)
                _same_exit(replace(got, barrier_j=want.barrier_j), want)
    assert searched > 0  # some poses' righting paths leave a sector: the grid's sector search ran


def test_map_sectors_equal_former_construction_builtin(robot):
    _assert_map_equals_former(robot, [-10.0, 0.0, 20.0, 45.0, 74.0, 90.0], [0.0, 30.0])


def test_map_sectors_equal_former_construction_lab(lab_robot):
    _assert_map_equals_former(lab_robot, [-10.0, -5.0, 10.0, 20.0, 40.0, 60.0, 74.0, 89.5], [0.0, 30.0])
