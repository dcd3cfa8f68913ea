"""The exact method's compiled kernels (landscape/barriers/_exact_kernels.py) against their NumPy/Python
references (tests/landscape/_references.py): the same numbers, bit for bit, on random inputs and on the
built-in robot, with numba's JIT on and off."""

import numpy as np
import pytest
import trimesh

from geometry import Pose, Robot
from geometry.frames import up_vector
from geometry.hull import convex_hull
from geometry.robots import load_robot
from landscape.barriers import exact
from tests.landscape import _references as ref


@pytest.fixture(scope="module")
def builtin_landscapes():
    robot = load_robot(None)
    return [exact.exact_landscape(robot.pose(w, leg)) for w, leg in ((-10.0, 0.0), (40.0, 30.0), (85.0, 0.0))]


def _random_graph(rng, n: int, m: int, ties: bool):
    eu = rng.integers(0, n, m)
    ev = rng.integers(0, n, m)
    # integer weights force ties in level, which exercise the heap's (level, node) order and the parent rule
    ew = rng.integers(0, 5, m).astype(np.float64) if ties else rng.normal(size=m)
    return eu.astype(np.int64), ev.astype(np.int64), ew


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("stop", [True, False])
def test_minimax_kernel_equals_python_search(seed, stop):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 60))
    eu, ev, ew = _random_graph(rng, n, int(rng.integers(1, 4 * n)), ties=seed % 2 == 0)
    goal = rng.random(n) < 0.15
    sources = sorted(set(rng.integers(0, n, int(rng.integers(1, 3))).tolist()))
    got = ref.minimax_kernel(n, eu, ev, ew, sources, goal, stop)
    want = ref.minimax_reference(n, eu, ev, ew, sources, goal, stop)
    np.testing.assert_array_equal(got[0], want[0])
    np.testing.assert_array_equal(got[1], want[1])
    assert got[2] == want[2]


def test_minimax_kernel_on_a_robot_face_graph(builtin_landscapes):
    for ex in builtin_landscapes:
        n_f = len(ex.face_up)
        goal = np.zeros(n_f, dtype=bool)
        goal[ex.critical.minima_face] = True
        f0 = int(ex.critical.minima_face[0])
        goal[f0] = False
        args = (n_f, ex.arc_faces[:, 0], ex.arc_faces[:, 1], ex.arc_max_m, [f0], goal, False)
        got, want = ref.minimax_kernel(*args), ref.minimax_reference(*args)
        for a, b in zip(got, want, strict=True):
            np.testing.assert_array_equal(a, b)


def test_minimax_hand_graph():
    """A path 0 -1.0- 1 -3.0- 2 and a detour 0 -2.0- 3 -2.0- 2: the bottleneck to 2 is 2.0, via 3."""
    eu, ev, ew = np.array([0, 1, 0, 3]), np.array([1, 2, 3, 2]), np.array([1.0, 3.0, 2.0, 2.0])
    goal = np.array([False, False, True, False])
    level, parent, first = ref.minimax_kernel(4, eu, ev, ew, [0], goal, True)
    assert first == 2 and level[2] == 2.0 and parent[2] == 3 and parent[3] == 2


def test_torus_path_kernel_equals_python(builtin_landscapes):
    rng = np.random.default_rng(3)
    u = rng.normal(size=(400, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    poles = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [1.0, 1e-13, 0.0]])  # pitch -90 and +90
    path = np.concatenate([u[:100], poles, u[100:], up_vector(*np.deg2rad([30.0, 170.0]))[None, :]])
    for start in ((0.0, 0.0), (-45.0, 179.0), (90.0, 12.0), (400.0, -200.0)):
        np.testing.assert_array_equal(exact._torus_path(path, start), ref.torus_path_reference(path, start))
    assert exact._torus_path(path[:0], (0.0, 0.0)).shape == (0, 2)


def test_face_margins_and_exits_kernels_equal_numpy(builtin_landscapes):
    box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0, com=[1.9, 0.0, 0.0])
    for ex in [*builtin_landscapes, exact.exact_landscape(box.pose())]:
        g, pts, n_f = ex._g, ex.vertices_m, len(ex.face_up)
        half_face = np.repeat(np.arange(n_f), np.diff(g.half_ptr))
        normal = -ex.face_up
        got = exact._face_margins(
            pts, normal, g.face_proj, g.face_ptr, g.face_idx, g.half_ptr, g.half_a, g.half_b
        )
        want = ref.face_margins_reference(
            pts, normal, g.face_proj, g.face_ptr, g.face_idx, half_face, g.half_a, g.half_b, n_f
        )
        np.testing.assert_array_equal(got, want)
        args = (pts, g.face_proj, g.half_ptr, g.half_arc, g.half_a, g.half_b, ex.arc_faces, want, ex.tol_m)
        np.testing.assert_array_equal(exact._face_exits(*args), ref.face_exits_reference(*args))


def test_arc_geometry_kernel_equals_numpy(builtin_landscapes, lab_or_builtin_poses):
    """The compiled arc geometry equals the NumPy reference: the same arithmetic, except that the compiled
    arccos, arctan2, hypot, cos and sin may round differently in the last bit. Arcs whose peak lies off the arc
    (the highest point at a face) are among them."""
    box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0, com=[1.9, 0.0, 0.0])
    cases = [*builtin_landscapes, exact.exact_landscape(box.pose())]
    cases += [
        exact.exact_landscape(Pose(None, None, 1.0, v.mean(axis=0), v, {}, ())) for v in lab_or_builtin_poses
    ]
    on_arc = []
    for ex in cases:
        a, b = ex.arc_vertices[:, 0], ex.arc_vertices[:, 1]
        args = (ex.vertices_m, ex.com_m, ex.face_up, ex.face_height_m, ex.arc_faces, a, b)
        got, want = exact._arc_geometry(*args), ref.arc_geometry_reference(*args)
        on_arc += ((want[5] > 0) & (want[5] < want[0])).tolist()
        for g, w in zip(got, want, strict=True):
            np.testing.assert_allclose(g, w, rtol=1e-14, atol=1e-15)
    assert any(on_arc) and not all(on_arc)


def test_box_face_margins_closed_form():
    """A 4 x 2 x 1 box with the CoM at x = 1.9: resting on a 4 x 2 face the projection lies 0.1 m inside the
    x = 2 edge; on the 2 x 1 end face at x = +2 it lies at its centre, 0.5 m from the long edges."""
    box = Robot.from_trimesh(trimesh.creation.box(extents=(4.0, 2.0, 1.0)), mass_kg=1.0, com=[1.9, 0.0, 0.0])
    ex = exact.exact_landscape(box.pose())
    bottom = int(np.argmax(ex.face_up @ np.array([0.0, 0.0, 1.0])))
    end = int(np.argmax(ex.face_up @ np.array([-1.0, 0.0, 0.0])))
    assert ex.face_margin_m[bottom] == pytest.approx(0.1, abs=1e-12)
    assert ex.face_margin_m[end] == pytest.approx(0.5, abs=1e-12)


def test_pieces_points_equal_per_arc_linspace(builtin_landscapes):
    for ex in builtin_landscapes:
        rng = np.random.default_rng(0)
        arcs = rng.integers(0, len(ex.arc_faces), 30)
        theta = ex._g.arc_theta[arcs]
        s0 = rng.uniform(0, 1, 30) * theta
        s1 = np.where(rng.random(30) < 0.3, s0, rng.uniform(0, 1, 30) * theta)  # some empty pieces
        pieces = [(int(a), float(x), float(y), 0.0, None) for a, x, y in zip(arcs, s0, s1, strict=True)]
        want = np.concatenate([ref.arc_points_reference(ex, a, x, y)[1:] for a, x, y, _, _ in pieces])
        np.testing.assert_array_equal(exact._pieces_points(ex, pieces), want)


def test_whole_pieces_equal_one_by_one(builtin_landscapes):
    ex = builtin_landscapes[1]
    arcs = np.arange(0, len(ex.arc_faces), 7)
    forward = arcs % 3 == 0
    batch = exact._whole_pieces(ex, arcs, forward)
    for got, a, f in zip(batch, arcs, forward, strict=True):
        want = ref.piece_reference(ex, int(a), bool(f))
        assert got[:4] == want[:4]
        np.testing.assert_array_equal(got[4], want[4])


def test_cell_step_kernel_matches_numpy(builtin_landscapes):
    """The compiled step agrees with the NumPy one to rounding (BLAS and SIMD sum in another order), and the
    descents it drives end on the same faces."""
    rng = np.random.default_rng(5)
    for ex in builtin_landscapes:
        for _ in range(200):
            u = rng.normal(size=3)
            u /= np.linalg.norm(u)
            k = int(np.argmax(ex._g.d @ u))
            np.testing.assert_allclose(
                exact._cell_step(ex, k, u), ref.cell_step_reference(ex, k, u), rtol=0, atol=1e-14
            )
        k = 0
        balanced = ex._g.d[k] / np.linalg.norm(ex._g.d[k])  # on the vertex: falls onto its lowest face
        np.testing.assert_array_equal(
            exact._cell_step(ex, k, balanced), ref.cell_step_reference(ex, k, balanced)
        )


def test_cell_step_closed_form_on_a_cube():
    """Unit cube, CoM at the centre, up-direction 10 deg off the direction of the vertex (-.5, -.5, -.5): the step
    follows the great circle through that direction and u, away from it, and ends on the vertex's cell boundary,
    where a second vertex is as low."""
    cube = Robot.from_trimesh(trimesh.creation.box(extents=(1.0, 1.0, 1.0)), mass_kg=1.0)
    ex = exact.exact_landscape(cube.pose())
    corner = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)  # d_k = c - v_k for v_k = (-.5, -.5, -.5)
    k = int(np.argmax(ex._g.d @ corner))
    face = np.array([0.0, 0.0, 1.0])
    axis = np.cross(corner, face)
    axis /= np.linalg.norm(axis)
    tilt = np.deg2rad(10.0)
    u = corner * np.cos(tilt) + np.cross(axis, corner) * np.sin(tilt)
    out = exact._cell_step(ex, k, u)
    # the step stays on the great circle through the corner direction and u, moving away from the corner
    np.testing.assert_allclose(np.dot(out, axis), 0.0, atol=1e-12)
    assert np.dot(out, corner) < np.dot(u, corner)
    # and stops on the cell boundary: two vertices are then equally low
    h = ex._g.d @ out
    top = np.sort(h)[-2:]
    assert top[1] - top[0] < 1e-12


def test_merge_coplanar_kernel_equals_scipy_components(builtin_landscapes):
    from scipy.spatial import ConvexHull

    box = trimesh.creation.box(extents=(4.0, 2.0, 1.0)).vertices  # 12 triangles, 6 faces
    rng = np.random.default_rng(2)
    blob = rng.normal(size=(60, 3))
    grid = np.array(
        [(x, y, z) for x in range(3) for y in range(3) for z in range(2)], dtype=float
    )  # coplanar
    for pts in [box, blob, grid, *(ex.vertices_m for ex in builtin_landscapes)]:
        hull = convex_hull(pts)
        qh = ConvexHull(hull.vertices_m)
        tol = 1e-9 * float(np.ptp(pts, axis=0).max())
        eq, tri, nb, got = exact._faces(hull, tol)
        np.testing.assert_array_equal(got, ref.merge_coplanar_reference(hull.vertices_m, tri, eq, nb, tol))
        assert len(tri) == len(qh.simplices)
    assert exact._faces(convex_hull(box), 1e-9)[3].max() + 1 == 6


def test_arcs_kernel_equals_numpy(builtin_landscapes, lab_or_builtin_poses):
    """The compiled face-edge arcs equal the NumPy construction: faces, extreme vertices and the pair lookup."""
    box = trimesh.creation.box(extents=(4.0, 2.0, 1.0)).vertices
    grid = np.array([(x, y, z) for x in range(3) for y in range(3) for z in range(2)], dtype=float)
    blob = np.random.default_rng(3).normal(size=(80, 3))
    clouds = [box, grid, blob, *(ex.vertices_m for ex in builtin_landscapes), *lab_or_builtin_poses]
    for cloud in clouds:
        hull = convex_hull(cloud)
        pts = hull.vertices_m
        tol = 1e-9 * float(np.ptp(pts, axis=0).max())
        _, tri, nb, tri_face = exact._faces(hull, tol)
        n_f = int(tri_face.max()) + 1
        got = exact._arcs(pts, tri, nb, tri_face, n_f)
        want = ref.arcs_reference(pts, tri, nb, tri_face, n_f)
        for g, w in zip(got[:3], want[:3], strict=True):
            np.testing.assert_array_equal(g, w)
        np.testing.assert_array_equal(got[3][0], want[3][0])
        np.testing.assert_array_equal(got[3][1], want[3][1])
    # the box's 12 edges join its 6 faces; the 3 x 3 x 2 grid's collinear sub-edges merge into whole edges
    assert len(exact._arcs(*_box_args(box))[0]) == 12
    assert len(exact._arcs(*_box_args(grid))[0]) == 12


def _box_args(pts):
    hull = convex_hull(pts)
    _, tri, nb, tri_face = exact._faces(hull, 1e-9)
    return hull.vertices_m, tri, nb, tri_face, int(tri_face.max()) + 1


@pytest.fixture(scope="module")
def lab_or_builtin_poses():
    """Hull vertices of the lab robot at a few poses (the built-in robot's when the lab files are absent)."""
    from tests.conftest import HAVE_LAB, LAB_URDF

    robot = Robot.from_urdf(LAB_URDF) if HAVE_LAB else load_robot(None)
    return [robot.pose(w, leg).hull.vertices_m for w, leg in ((-10.0, 0.0), (40.0, 0.0), (74.0, 30.0))]


def test_exact_kernels_match_references_without_jit():
    """The same comparisons with numba's JIT off, on a box with its CoM off-centre and a random blob: the
    kernels' Python source is what the tests check."""
    code = (
        "import numpy as np, trimesh\n"
        "from geometry import Robot\n"
        "from geometry.hull import convex_hull\n"
        "from landscape.barriers import exact\n"
        "from tests.landscape import _references as ref\n"
        "rng = np.random.default_rng(4)\n"
        "box = trimesh.creation.box(extents=(4.0, 2.0, 1.0))\n"
        "blob = trimesh.convex.convex_hull(rng.normal(size=(40, 3)) * [0.1, 0.06, 0.03])\n"
        "for mesh, com in ((box, [1.9, 0.0, 0.0]), (blob, blob.vertices.mean(axis=0) * 0.3)):\n"
        "    ex = exact.exact_landscape(Robot.from_trimesh(mesh, mass_kg=1.0, com=com).pose())\n"
        "    g, pts, n_f = ex._g, ex.vertices_m, len(ex.face_up)\n"
        "    hull = convex_hull(pts)\n"
        "    eq, tri, nb, tri_face = exact._faces(hull, ex.tol_m)\n"
        "    assert (tri_face == ref.merge_coplanar_reference(hull.vertices_m, tri, eq, nb, ex.tol_m)).all()\n"
        "    m = int(tri_face.max()) + 1\n"
        "    got, want = exact._arcs(pts, tri, nb, tri_face, m), ref.arcs_reference(pts, tri, nb, tri_face, m)\n"
        "    assert all(np.array_equal(a, b) for a, b in zip(got[:3] + got[3], want[:3] + want[3]))\n"
        "    a, b = ex.arc_vertices[:, 0], ex.arc_vertices[:, 1]\n"
        "    args = (pts, ex.com_m, ex.face_up, ex.face_height_m, ex.arc_faces, a, b)\n"
        "    for x, y in zip(exact._arc_geometry(*args), ref.arc_geometry_reference(*args)):\n"
        "        assert np.allclose(x, y, rtol=1e-14, atol=1e-15)\n"
        "    half_face = np.repeat(np.arange(n_f), np.diff(g.half_ptr))\n"
        "    fm = (pts, -ex.face_up, g.face_proj, g.face_ptr, g.face_idx)\n"
        "    margin = exact._face_margins(*fm, g.half_ptr, g.half_a, g.half_b)\n"
        "    assert np.array_equal(margin, ref.face_margins_reference(*fm, half_face, g.half_a, g.half_b, n_f))\n"
        "    args = (pts, g.face_proj, g.half_ptr, g.half_arc, g.half_a, g.half_b, ex.arc_faces, margin, ex.tol_m)\n"
        "    assert np.array_equal(exact._face_exits(*args), ref.face_exits_reference(*args))\n"
        "    for u in rng.normal(size=(20, 3)):\n"
        "        u /= np.linalg.norm(u)\n"
        "        k = int(np.argmax(g.d @ u))\n"
        "        assert np.allclose(exact._cell_step(ex, k, u), ref.cell_step_reference(ex, k, u), rtol=0, atol=1e-14)\n"
        "    us = rng.normal(size=(50, 3))\n"
        "    us /= np.linalg.norm(us, axis=1, keepdims=True)\n"
        "    assert np.array_equal(exact._torus_path(us, (10.0, -20.0)), ref.torus_path_reference(us, (10.0, -20.0)))\n"
        "    goal = np.zeros(n_f, dtype=bool)\n"
        "    goal[ex.critical.minima_face[1:]] = True\n"
        "    graph = (n_f, ex.arc_faces[:, 0], ex.arc_faces[:, 1], ex.arc_max_m, [int(ex.critical.minima_face[0])])\n"
        "    got, want = ref.minimax_kernel(*graph, goal, False), ref.minimax_reference(*graph, goal, False)\n"
        "    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1]) and got[2] == want[2]\n"
        "print('ok')\n"
    )
    assert ref.run_without_jit(code) == "ok"
