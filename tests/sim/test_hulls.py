"""Simplified collision hulls (sim/hulls.py): closed-form cases of support-gap refinement."""

import numpy as np
import pytest
import trimesh

from sim.hulls import N_DIRECTIONS, fibonacci_directions, hull_obj_text, simplified_hull


def test_directions_are_unit_and_balanced():
    d = fibonacci_directions(N_DIRECTIONS)
    assert d.shape == (N_DIRECTIONS, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(d.mean(axis=0), 0.0, atol=2e-3)  # spread evenly: no direction favoured


def test_a_cube_keeps_its_eight_corners_and_no_gap():
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    inner = np.random.default_rng(0).uniform(-0.9, 0.9, (200, 3))
    s = simplified_hull(np.vstack([box.vertices, inner]), tol=1e-3)
    assert s.n_full == 8 and len(s.vertices) == 8 and s.gap == 0.0
    assert trimesh.Trimesh(s.vertices, s.faces).volume == pytest.approx(8.0, rel=1e-12)


@pytest.mark.parametrize("tol", [0.05, 0.01])
def test_a_sphere_rests_at_most_tol_higher_in_every_direction(tol):
    pts = trimesh.creation.icosphere(subdivisions=4).vertices  # unit sphere, support 1 in every direction
    s = simplified_hull(pts, tol=tol, max_vertices=500)
    support = (s.vertices @ fibonacci_directions(N_DIRECTIONS).T).max(axis=0)
    assert len(s.vertices) < s.n_full
    assert s.gap <= tol
    assert (1.0 - support).max() <= tol + 1e-3  # the icosphere's own facets are within 1e-3 of the sphere


def test_the_obj_text_has_one_line_per_vertex_and_face():
    s = simplified_hull(trimesh.creation.box().vertices, tol=0.0)
    text = hull_obj_text(s)
    assert text.count("\nv ") + text.startswith("v ") == 8 and text.count("\nf ") == 12
