import numpy as np
import pytest
import trimesh

from geometry import Robot
from landscape import compute
from landscape.barriers.exact import exact_barrier
from landscape.barriers.sphere import sphere_barrier, sphere_graph, subdivisions_for_step


def test_graph_is_uniform_and_connected():
    g = sphere_graph(5)
    assert len(g.u) == 10 * 4**5 + 2
    assert np.allclose(np.linalg.norm(g.u, axis=1), 1.0)
    deg = np.diff(g.ptr)
    assert set(np.unique(deg)) <= {5, 6}  # icosphere: 12 vertices of degree 5, the rest 6
    lengths = np.rad2deg(
        np.arccos(np.clip((g.u[np.repeat(np.arange(len(g.u)), deg)] * g.u[g.idx]).sum(1), -1, 1))
    )
    assert lengths.max() / lengths.min() < 1.5  # nearly uniform, unlike the torus near its poles


def test_box_closed_form_and_convergence():
    """Box 4 x 2 x 1 (m = g = 1): roll barrier sqrt(1 + 1/4) - 1/2. The saddle sits on the floor of a V-shaped
    valley (the edge's arc), which icosphere vertices straddle, so the error is first order in the spacing:
    it halves with every level (0.081, 0.041, 0.021, 0.010 relative at levels 4..7)."""
    box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), com=[0, 0, 0])
    exact = np.sqrt(1.25) - 0.5
    vals = [
        sphere_barrier(box.pose(), 0.0, 0.0, subdivisions=k, g_m_s2=1.0).barrier.righting.barrier_j
        for k in (4, 5, 6, 7)
    ]
    errs = np.array(vals) - exact
    assert np.all(errs > 0)  # vertices off the valley floor only ever overestimate here
    assert np.allclose(errs[1:] / errs[:-1], 0.5, atol=0.05)
    assert errs[-1] < 0.02 * exact
    b = sphere_barrier(box.pose(), 0.0, 0.0, subdivisions=6, g_m_s2=1.0).barrier
    assert b.righting.direction == "roll" and b.pitch_wise is None and b.roll_wise is None
    # through compute(), the sectors come from the righting path or the grid's sector search
    c = compute(box, method="sphere", step_deg=1.0)
    assert c.barrier.pitch_wise.barrier_j == pytest.approx(9.81 * (np.sqrt(4.25) - 0.5), rel=1e-3)
    assert c.barrier.roll_wise.barrier_j == c.barrier.righting.barrier_j


def test_upright_start_and_step_mapping():
    box = Robot.from_trimesh(trimesh.creation.box(extents=(1.0, 1.0, 1.0)), com=[0, 0, 0])
    assert sphere_barrier(box.pose(), 180.0, 0.0, subdivisions=3).barrier.righting.barrier_j == 0.0
    assert [subdivisions_for_step(s) for s in (4.0, 2.0, 1.0, 0.5)] == [4, 5, 6, 7]
    with pytest.raises(ValueError, match="subdivisions"):
        sphere_barrier(box.pose(), 0.0, 0.0, subdivisions=0)


def test_lab_robot_close_to_exact(lab_robot):
    c = compute(lab_robot, theta_w_deg=74, theta_l_deg=0, method="sphere", step_deg=0.5)
    ex = exact_barrier(c.pose, *c.start_deg).barrier.righting.barrier_j
    assert c.method == "sphere"
    assert c.barrier.righting.barrier_j == pytest.approx(ex, rel=0.06)
    assert c.barrier.righting.direction == "roll"
