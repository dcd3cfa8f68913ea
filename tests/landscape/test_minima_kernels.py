"""The compiled rolling kernels (landscape/_minima_kernels.py) against their NumPy reference
(tests/landscape/_references.py): the same faces and up-directions, move by move, on random bodies and along
the robots' paths, with numba's JIT on and off."""

from pathlib import Path

import numpy as np
import pytest
import trimesh

from geometry import Robot
from geometry.builtin import builtin_urdf_path
from geometry.errors import UsageError
from landscape import _minima_kernels as kernels
from landscape import minima as m
from tests.landscape import _references as ref

ROOT = Path(__file__).resolve().parents[2]
LAB_URDFS = (
    ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf",
    Path("/work/shared/ref/lab_robot/lab_robot.urdf"),
)


def _body(rng, n=60):
    """Random convex-ish point cloud with the CoM well inside, as d = c - p, and its tolerance."""
    pts = rng.normal(size=(n, 3)) * [0.1, 0.06, 0.03]
    hull = trimesh.convex.convex_hull(pts)
    com = hull.vertices.mean(axis=0) * 0.3
    d = np.ascontiguousarray(com[None, :] - pts)
    return d, m.LENGTH_RTOL * float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))


def _unit(v):
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("seed", range(4))
def test_rest_matches_reference(seed):
    rng = np.random.default_rng(seed)
    d, tol = _body(rng)
    for _ in range(25):
        u = _unit(rng.normal(size=3))
        u_ref, face_ref = ref.rest_reference(d, u, tol)
        u_k, face_k, settled = kernels.rest(d, u, tol, m._MAX_MOVES)
        assert settled
        assert face_k.tolist() == face_ref.tolist()
        np.testing.assert_allclose(u_k, u_ref, rtol=0, atol=1e-12)


def test_rest_on_a_box_with_coplanar_points():
    """Faces with four and more (collinear) corners: the polygon drops collinear points in both."""
    box = trimesh.creation.box(extents=(4.0, 2.0, 1.0))
    pts = np.concatenate([box.vertices, [[0.0, -1.0, -0.5], [1.0, 1.0, -0.5], [2.0, 0.0, -0.5]]])
    d = np.ascontiguousarray(np.array([0.1, 0.05, 0.0]) - pts)
    rng = np.random.default_rng(7)
    for _ in range(30):
        u = _unit(rng.normal(size=3))
        u_ref, face_ref = ref.rest_reference(d, u, 1e-9)
        u_k, face_k, _ = kernels.rest(d, u, 1e-9, m._MAX_MOVES)
        assert sorted(face_k.tolist()) == sorted(face_ref.tolist())
        np.testing.assert_allclose(u_k, u_ref, atol=1e-12)
        assert np.isclose(np.abs(u_k).max(), 1.0)  # rests flat on a box face


@pytest.mark.parametrize("seed", range(3))
def test_first_touch_pruning_matches_reference(seed):
    """The arctangent is skipped only for points that cannot be first; the minimum is the reference's."""
    rng = np.random.default_rng(seed)
    d, _ = _body(rng, 400)
    for _ in range(50):
        u = _unit(rng.normal(size=3))
        k = int(np.argmax(d @ u))
        t = _unit(np.cross(u, rng.normal(size=3)))
        assert kernels._first_touch(d, k, u, t) == pytest.approx(
            ref.first_touch_reference(d, k, u, t), rel=1e-14
        )


@pytest.mark.parametrize("seed", range(3))
def test_polygon_and_margin_match_reference(seed):
    rng = np.random.default_rng(seed)
    for n in (3, 5, 12, 40):
        xy = rng.normal(size=(n, 2))
        xy[: n // 3] = np.round(xy[: n // 3], 1)  # ties in x
        poly_ref = ref.convex_polygon_reference(xy)
        poly_k = kernels._convex_polygon(xy)
        assert poly_k.tolist() == poly_ref.tolist()
        margin_ref = ref.polygon_margin_reference(xy, poly_ref)
        margin_k = kernels._polygon_margin(xy, poly_k)
        assert margin_k[1] == margin_ref[1]
        np.testing.assert_allclose(margin_k[::2], margin_ref[::2], rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("seed", range(3))
def test_still_rests_matches_reference(seed):
    """At rest, after a small random motion of the points (rigid and per point): the same verdict and face as
    the reference."""
    rng = np.random.default_rng(seed)
    d, tol = _body(rng)
    verdicts = set()
    for _ in range(25):
        u, face = ref.rest_reference(d, _unit(rng.normal(size=3)), tol)
        for scale in (1e-4, 3e-3, 3e-2):
            rot = trimesh.transformations.rotation_matrix(scale, _unit(rng.normal(size=3)))[:3, :3]
            moved = np.ascontiguousarray(d @ rot.T + rng.normal(size=d.shape) * scale * 0.1)
            u_ref, f_ref = ref.still_rests_reference(moved, face, u, tol)
            ok, u_k, f_k = kernels.still_rests(moved, face, u, tol)
            assert ok == (u_ref is not None)
            verdicts.add(ok)
            if ok:
                assert f_k.tolist() == f_ref.tolist()
                np.testing.assert_allclose(u_k, u_ref, atol=1e-12)
    assert verdicts == {True, False}  # both branches exercised


def test_posed_points_matches_numpy():
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(30, 3))
    ptr = np.array([0, 10, 10, 30], dtype=np.int64)
    rot = np.stack([trimesh.transformations.random_rotation_matrix(rng.random(3))[:3, :3] for _ in range(3)])
    trans = rng.normal(size=(3, 3))
    com = rng.normal(size=3)
    out = np.zeros((30, 3))
    diag = kernels.posed_points(pts, ptr, rot, trans, com, out)
    want = com - np.concatenate([pts[:10] @ rot[0].T + trans[0], pts[10:] @ rot[2].T + trans[2]])
    np.testing.assert_allclose(out, want, atol=1e-14)
    assert diag == pytest.approx(np.linalg.norm(want.max(axis=0) - want.min(axis=0)), rel=1e-14)


def _robots():
    out = [("builtin", builtin_urdf_path())]
    lab = next((p for p in LAB_URDFS if p.is_file()), None)
    if lab is not None:
        out.append(("lab", lab))
    return out


@pytest.mark.parametrize("name, path", _robots())
@pytest.mark.parametrize("tw, tl", [(74.0, 30.0), (90.0, -40.0), (-8.0, 10.0)])
def test_follow_path_matches_numpy_continuation(name, path, tw, tl):
    """The compiled continuation ends on the face the NumPy reference walk ends on, at every step."""
    robot = Robot.from_urdf(path)
    path_deg = m.opening_path(tw, tl)
    new = np.array(m.follow_minimum(robot, path_deg))
    want = np.array(ref.follow_minimum_reference(robot, path_deg))
    np.testing.assert_allclose(new, want, rtol=0, atol=1e-9)


def test_rest_face_refuses_bad_input():
    with pytest.raises(UsageError, match="shape"):
        m.rest_face(np.zeros((0, 3)), [0, 0, 0], [0, 0, 1])
    with pytest.raises(UsageError, match="finite"):
        m.rest_face(np.eye(3), [0, 0, np.nan], [0, 0, 1])
    with pytest.raises(UsageError, match="non-zero"):
        m.rest_face(np.eye(3), [0, 0, 0], [0, 0, 0])


def test_kernels_match_reference_without_jit():
    """The same comparisons with numba's JIT off: the kernels' Python source is what the tests check."""
    code = (
        "import numpy as np\n"
        "from landscape import _minima_kernels as kernels\n"
        "from tests.landscape import _references as ref\n"
        "rng = np.random.default_rng(5)\n"
        "pts = rng.normal(size=(40, 3)) * [0.1, 0.06, 0.03]\n"
        "d = np.ascontiguousarray(pts.mean(axis=0) * 0.3 - pts)\n"
        "for _ in range(10):\n"
        "    u = rng.normal(size=3); u /= np.linalg.norm(u)\n"
        "    a, fa = ref.rest_reference(d, u, 1e-10)\n"
        "    b, fb, ok = kernels.rest(d, u, 1e-10, 1000)\n"
        "    assert ok and fa.tolist() == fb.tolist() and np.abs(a - b).max() < 1e-12, (fa, fb)\n"
        "    ok, u2, f2 = kernels.still_rests(d, fb, b, 1e-10)\n"
        "    assert ok and f2.tolist() == fb.tolist()\n"
        "print('ok')\n"
    )
    assert ref.run_without_jit(code) == "ok"
