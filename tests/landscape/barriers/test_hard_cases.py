"""Hard cases for the exact method: each gives the right answer or a clear refusal."""

import numpy as np
import pytest
import trimesh

from geometry import Robot
from geometry.errors import GeometryError
from landscape.barriers.exact import LENGTH_RTOL, ExactMethodError, exact_barrier, exact_landscape


def _box(extents, com=(0.0, 0.0, 0.0), mass=1.0):
    return Robot.from_trimesh(trimesh.creation.box(extents=extents), mass_kg=mass, com=list(com))


def _barriers(b):
    return [
        np.nan if e is None else e.barrier_j
        for e in (b.barrier.righting, b.barrier.pitch_wise, b.barrier.roll_wise, b.barrier.escape)
    ]


def test_com_nearly_above_an_edge():
    """Box 2 x 1 x 1, CoM shifted toward the x = +1 end. Within LENGTH_RTOL * diameter of being above the bottom
    face's edge the face is not a rest: the body tips onto the end face (as it does when clearly beyond); a CoM
    1 mm inside stays, with the closed-form escape barrier sqrt(dx^2 + 1/4) - 1/2."""
    diam = np.sqrt(6.0)
    assert 1e-9 < LENGTH_RTOL * diam
    on_end = []
    for dx in (1e-9, 1e-12, 0.0):
        b = exact_barrier(_box((2.0, 1.0, 1.0), com=(1.0 - dx, 0.0, 0.0)).pose(), 0.0, 0.0, g_m_s2=1.0)
        assert b.start.pitch_deg == pytest.approx(90.0)  # resting on the x = +1 end face, u = -x
        on_end.append(_barriers(b))
    assert on_end[0] == pytest.approx(on_end[1], nan_ok=True) and on_end[1] == pytest.approx(
        on_end[2], nan_ok=True
    )
    dx = 1e-3
    b = exact_barrier(_box((2.0, 1.0, 1.0), com=(1.0 - dx, 0.0, 0.0)).pose(), 0.0, 0.0, g_m_s2=1.0)
    assert (b.start.pitch_deg, b.start.roll_deg) == (0.0, 0.0)
    assert b.barrier.escape.barrier_j == pytest.approx(np.hypot(dx, 0.5) - 0.5, rel=1e-6)


_CUBE_SADDLES = (
    "import json, trimesh; from geometry import Robot; from landscape.barriers.exact import exact_barrier\n"
    "b = exact_barrier(Robot.from_trimesh(trimesh.creation.box(extents=(1.0, 1.0, 1.0)), mass_kg=1.0, com=[0, 0, 0])"
    ".pose(), 0.0, 0.0, g_m_s2=1.0)\n"
    "print(json.dumps({k: [getattr(b.barrier, k).saddle_pitch_deg, getattr(b.barrier, k).saddle_roll_deg,"
    " getattr(b.barrier, k).path_deg.tolist()] for k in ('righting', 'escape')}))\n"
)


def test_cube_equal_minima_resolve_ties_the_same_way_in_every_process():
    """Six equal minima and twelve equal saddles: the saddle taken is one of the four closed-form ones next to
    the start face (pitch or roll 45 deg), and a fresh process with another hash seed takes the same one."""
    import json
    import os
    import subprocess
    import sys

    b = exact_barrier(_box((1.0, 1.0, 1.0)).pose(), 0.0, 0.0, g_m_s2=1.0)
    assert b.barrier.escape.barrier_j == pytest.approx(0.5 * (np.sqrt(2) - 1))
    here = {}
    for kind in ("righting", "escape"):
        e = getattr(b.barrier, kind)
        assert sorted(np.abs([e.saddle_pitch_deg, e.saddle_roll_deg])) == pytest.approx([0.0, 45.0], abs=1e-9)
        here[kind] = [e.saddle_pitch_deg, e.saddle_roll_deg, np.asarray(e.path_deg).tolist()]
    env = {**os.environ, "PYTHONHASHSEED": "4242"}
    out = subprocess.run(
        [sys.executable, "-c", _CUBE_SADDLES], env=env, capture_output=True, text=True, check=True
    )
    assert json.loads(out.stdout.strip().splitlines()[-1]) == json.loads(json.dumps(here))


def test_sphere_centred_com_is_nearly_flat():
    """CoM at the centre of an icosphere: only facet bumps remain; no hang, finite tiny barriers."""
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    sag = 1.0 - np.abs((sphere.face_normals * sphere.triangles_center).sum(axis=1)).min()
    b = exact_barrier(Robot.from_trimesh(sphere, com=[0, 0, 0]).pose(), 0.0, 0.0, g_m_s2=1.0)
    righting, pitch, roll, escape = _barriers(b)
    for value in (righting, escape):
        assert 0.0 <= value <= sag
    for value in (pitch, roll):  # a sector may hold no whole arc out of the start face (module docstring)
        assert np.isnan(value) or righting <= value <= sag


def test_duplicates_collinear_and_coplanar_points_and_zero_area_faces():
    """A box mesh with duplicate vertices, edge midpoints, face centres and degenerate triangles is the box."""
    box = trimesh.creation.box(extents=(0.4, 0.2, 0.1))
    v = box.vertices
    mids = (v[:, None] + v[None]) / 2
    extra = np.concatenate([v, v + 1e-15, mids.reshape(-1, 3)])
    faces = np.concatenate([box.faces, [[0, 0, 1], [2, 8, 2]]])
    mesh = trimesh.Trimesh(vertices=np.concatenate([v, extra]), faces=faces, process=False)
    com = [0.01, -0.02, 0.005]
    clean = exact_barrier(Robot.from_trimesh(box, com=com).pose(), 0.0, 0.0)
    messy = exact_barrier(Robot.from_trimesh(mesh, com=com).pose(), 0.0, 0.0)
    assert _barriers(messy) == pytest.approx(_barriers(clean), rel=1e-9, nan_ok=True)
    assert len(messy.landscape.critical.minima_face) == 6


def test_nan_vertex_refused():
    mesh = trimesh.creation.box(extents=(1, 1, 1))
    verts = mesh.vertices.copy()
    verts[3, 1] = np.nan
    with pytest.raises(GeometryError, match="not finite"):
        Robot.from_trimesh(trimesh.Trimesh(verts, mesh.faces, process=False), com=[0, 0, 0])


def test_flat_body_refused():
    square = trimesh.Trimesh(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]], process=False
    )
    with pytest.raises(ExactMethodError, match="flat or degenerate"):
        exact_landscape(Robot.from_trimesh(square, com=[0.5, 0.5, 0]).pose())


def test_com_outside_hull_refused():
    with pytest.raises(ExactMethodError, match="outside the convex hull"):
        exact_landscape(_box((1, 1, 1), com=(0.0, 0.0, 0.7)).pose())


def test_non_finite_start_refused():
    with pytest.raises(ValueError, match="finite"):
        exact_barrier(_box((1, 1, 1)).pose(), np.nan, 0.0)


def test_start_exactly_on_saddle_or_vertex():
    """On a saddle the body rolls to the lower side; balanced on a vertex, onto the lowest face there."""
    body = _box((4.0, 2.0, 1.0))
    ex = exact_landscape(body.pose(), g_m_s2=1.0)
    k = int(np.argmin(ex.critical.saddles_energy_j))  # long edge between the big face and a side
    b = exact_barrier(ex, *ex.critical.saddles_deg[k])
    assert b.start.energy_j == pytest.approx(0.5)  # the big (lower) face, not the side (1.0)
    b = exact_barrier(ex, *ex.critical.maxima_deg[0])
    assert b.start.energy_j == pytest.approx(0.5)
    # and twice the same on a tie (cube vertex: three equal faces)
    cube = exact_landscape(_box((1.0, 1.0, 1.0)).pose())
    f = {exact_barrier(cube, *cube.critical.maxima_deg[0]).start_face for _ in range(2)}
    assert len(f) == 1


def test_start_already_upright():
    b = exact_barrier(_box((0.3, 0.2, 0.1)).pose(), 180.0, 0.0)
    assert b.barrier.righting.barrier_j == 0.0
    assert b.barrier.pitch_wise.barrier_j == 0.0 and b.barrier.roll_wise.barrier_j == 0.0
    assert b.barrier.escape.barrier_j > 0


def test_start_at_global_minimum():
    """Upside down on the biggest face (the global minimum): escape and righting are both reported."""
    b = exact_barrier(_box((0.3, 0.2, 0.1)).pose(), 0.0, 0.0, g_m_s2=1.0)
    assert b.start.energy_j == pytest.approx(0.05)
    assert b.barrier.escape.barrier_j == pytest.approx(np.hypot(0.1, 0.05) - 0.05)
    assert b.barrier.righting.barrier_j == pytest.approx(b.barrier.escape.barrier_j)


def test_units_mm_and_m():
    """The same body in mm (declared) gives the same barriers; the numbers read as metres scale by 1000."""
    rng = np.random.default_rng(5)
    hull = trimesh.convex.convex_hull(rng.normal(size=(20, 3)) * [120.0, 80.0, 40.0])  # mm
    com_mm = hull.vertices.mean(axis=0) * 0.5
    in_mm = exact_barrier(Robot.from_trimesh(hull, com=com_mm, units="mm").pose(), 0.0, 0.0)
    in_m = exact_barrier(Robot.from_trimesh(hull, com=com_mm, units="m").pose(), 0.0, 0.0)
    scaled = hull.copy()
    scaled.apply_scale(1e-3)
    ref = exact_barrier(Robot.from_trimesh(scaled, com=com_mm * 1e-3).pose(), 0.0, 0.0)
    assert _barriers(in_mm) == pytest.approx(_barriers(ref), rel=1e-9, nan_ok=True)
    assert _barriers(in_m) == pytest.approx([1e3 * x for x in _barriers(ref)], rel=1e-9, nan_ok=True)
