"""The barriers' first-order changes (landscape/gradient.py) against central differences of the barriers themselves.

Tolerance: 1e-6 relative, with an absolute floor where a component is near zero: central differences of a barrier
``B`` carry a rounding error of about ``eps |B| / h`` (2e-16 x 0.08 J / 1e-6 m = 2e-11 J/m for the CoM, 2e-13 J/deg
for 1e-4 deg), so the floors are 1e-9 m g J/m (the gradient's scale is m g) and 1e-12 J/deg, each above that
rounding and far below any component shown (the table prints 1e-4 mJ/mm and 1e-3 mJ/deg).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geometry import Robot
from geometry.robots import load_robot
from landscape.computation import compute
from landscape.gradient import EXIT_NAMES
from landscape.uncertainty import recomputed_barriers

COM_STEP_M = 1e-6
ANGLE_STEP_DEG = 1e-4
RTOL = 1e-6
ANGLE_FLOOR_J_PER_DEG = 1e-12


def _close(analytic, fd, floor):
    return abs(analytic - fd) <= RTOL * abs(fd) + floor


def _com_fd(c, step):
    """Central differences of every exit's barrier along x, y, z: (4, 3), J/m."""
    offsets = np.concatenate([np.eye(3) * step, -np.eye(3) * step])
    b = recomputed_barriers(c, offsets)
    return ((b[:3] - b[3:]) / (2 * step)).T


def _angle_fd(robot, c, angle):
    """Central differences of every exit's barrier along theta_w or theta_l, J/deg (the same start, the same
    sector searches)."""
    out = []
    for sign in (1, -1):
        d = sign * ANGLE_STEP_DEG
        x = compute(
            robot,
            theta_w_deg=c.theta_w_deg + d * (angle == "theta_w"),
            theta_l_deg=c.theta_l_deg + d * (angle == "theta_l"),
            start_deg=c.start_deg,
            landscape_grid=False,
            sector_exits=c.barrier.pitch_wise is not None,
            gradients=False,
        )
        out.append([getattr(x.barrier, k).barrier_j for k in EXIT_NAMES])
    return (np.array(out[0]) - np.array(out[1])) / (2 * ANGLE_STEP_DEG)


def _check_against_differences(robot, c, *, angles=("theta_w", "theta_l")):
    """Every derivative the gradient gives agrees with central differences (within its reach, the CoM step is
    at most half of it); returns how many were compared."""
    reach = min(g.reach_m for g in c.gradient.values() if g is not None and not np.isnan(g.reach_m))
    step = min(COM_STEP_M, reach / 2)
    fd = _com_fd(c, step)
    scale = c.mass_kg * c.g_m_s2
    compared = 0
    for k, name in enumerate(EXIT_NAMES):
        g = c.gradient[name]
        assert g.mass_j_per_kg == getattr(c.barrier, name).barrier_j / c.mass_kg
        if g.com_j_per_m is not None:
            for i in range(3):
                assert _close(g.com_j_per_m[i], fd[k, i], 1e-9 * scale), (name, i, g.com_j_per_m, fd[k])
                compared += 1
    for angle in angles:
        fd_a = _angle_fd(robot, c, angle)
        for k, name in enumerate(EXIT_NAMES):
            v = getattr(c.gradient[name], f"{angle}_j_per_deg")
            if v is not None:
                assert _close(v, fd_a[k], ANGLE_FLOOR_J_PER_DEG), (name, angle, v, fd_a[k])
                compared += 1
    return compared


# ----------------------------------------------------------------------------------------- the built-in robot
@pytest.fixture(scope="module")
def builtin():
    return load_robot()


@pytest.mark.parametrize("theta_w", [60.0, 74.0, 90.0])
def test_builtin_robot_gradients_are_the_barriers_derivatives(builtin, theta_w):
    """With the leg out (theta_l 30 deg) the body is no mirror image of itself: every exit is differentiable."""
    c = compute(builtin, theta_w_deg=theta_w, theta_l_deg=30.0)
    reasons = {k: c.gradient[k].reason for k in EXIT_NAMES}
    assert all(c.gradient[k].differentiable for k in EXIT_NAMES), reasons
    assert _check_against_differences(builtin, c) == 4 * 3 + 4 * 2


@pytest.mark.parametrize("theta_w", [60.0, 74.0, 90.0])
def test_builtin_robot_mirror_saddles_have_no_com_gradient(builtin, theta_w):
    """Leg at 0: the body is its own mirror image, so the righting saddle has a twin at the opposite roll and the
    barrier is the lower of two: no gradient along y, none along theta_l (which moves the leg to one side), but
    along x and z and along theta_w the twins agree. The one-sided gradients are each twin's, and a forward
    difference along +-y follows the lower one."""
    c = compute(builtin, theta_w_deg=theta_w, theta_l_deg=0.0)
    g = c.gradient["righting"]
    assert not g.differentiable and g.com_j_per_m is None and g.theta_l_j_per_deg is None
    assert "2 saddles at the barrier level" in g.reason
    assert g.theta_w_j_per_deg is not None
    two = g.one_sided_com_j_per_m
    assert two.shape == (2, 3) and np.allclose(two[0] * [1, -1, 1], two[1], rtol=0, atol=1e-12)
    assert two[0, 1] > 0  # the reported twin is at positive roll: the first row is its gradient
    # theta_w of the righting exits, the pitch-wise exit's CoM and angles
    assert _check_against_differences(builtin, c) >= 1 + 3 + 2
    # one-sided along +y and -y (Richardson: 2 D(h) - D(2h), error O(h^2)): the barrier follows the lower twin
    h = 1e-6
    b = recomputed_barriers(c, np.array([[0, h, 0], [0, 2 * h, 0], [0, -h, 0], [0, -2 * h, 0]]))[:, 0]
    b0 = c.barrier.righting.barrier_j
    up = 2 * (b[0] - b0) / h - (b[1] - b0) / (2 * h)
    down = 2 * (b[2] - b0) / h - (b[3] - b0) / (2 * h)
    assert up == pytest.approx(min(two[:, 1]), rel=1e-5) and down == pytest.approx(min(-two[:, 1]), rel=1e-5)


@pytest.mark.shared
@pytest.mark.parametrize("theta_w, theta_l", [(60, 30), (74, 30), (90, 30), (74, 0), (90, 0)])
def test_lab_robot_gradients_are_the_barriers_derivatives(lab_robot, theta_w, theta_l):
    c = compute(lab_robot, theta_w_deg=theta_w, theta_l_deg=theta_l)
    assert _check_against_differences(lab_robot, c) >= 3 * 2 + 2


# ----------------------------------------------------------------------------------------- closed-form bodies
def _body(mesh, com) -> Robot:
    return Robot.from_trimesh(mesh, mass_kg=0.26, com=tuple(float(x) for x in com))


BOX = trimesh.creation.box(extents=(0.4, 0.3, 0.2))
CYLINDER = trimesh.creation.cylinder(radius=0.1, height=0.3, sections=24)
HALF = np.array([0.2, 0.15, 0.1])


def _check_body(robot):
    c = compute(robot, landscape_grid=False, start_pitch_deg=20.0, start_roll_deg=10.0)
    for name in EXIT_NAMES:
        g = c.gradient.get(name)
        assert g is None or g.differentiable or g.reason
    _check_rigid(c)


def _check_rigid(c):
    """A rigid body: every differentiable exit against central differences; at a tie, one-sided differences
    (Richardson) along each axis follow the lowest route (Danskin: min over routes of g . e)."""
    exits = [k for k in ("righting", "escape") if getattr(c.barrier, k) is not None]
    reach = min((c.gradient[k].reach_m for k in exits), default=np.inf)
    if not reach > 4e-7:  # a switch within 0.4 um: differences cannot resolve it (the exact method's scale)
        return
    step = min(COM_STEP_M, reach / 4)
    fd = _com_fd(c, step)
    scale = c.mass_kg * c.g_m_s2
    for name in exits:
        k = EXIT_NAMES.index(name)
        g = c.gradient[name]
        if g.com_j_per_m is not None:
            err = np.abs(g.com_j_per_m - fd[k])
            assert np.all(err <= RTOL * np.abs(fd[k]) + 1e-9 * scale), (name, g, fd[k])
        elif len(g.one_sided_com_j_per_m) > 1:
            _check_one_sided(c, name, min(TIE_STEP_M, reach / 4))


TIE_STEP_M = 1e-4


def _check_one_sided(c, name, h):
    """At a tie the barrier is the lowest route: one-sided differences (Richardson, 2 D(h) - D(2h)) along +-x,
    +-y, +-z follow min over routes of g . e. Routes tied within the length tolerance t are apart by up to
    m g t at this CoM, which moves the kink by about t and errs a one-sided difference by up to about
    2 m g t / h (0.03 J/m at h = 0.1 mm on these bodies); hence that tolerance."""
    k = EXIT_NAMES.index(name)
    rows = c.gradient[name].one_sided_com_j_per_m
    scale = c.mass_kg * c.g_m_s2
    size = float(np.linalg.norm(np.ptp(c.pose.hull_points_m, axis=0)))
    tol = 2 * scale * 1e-6 * size / h + 1e-5 * scale
    offsets = np.concatenate([np.eye(3) * h, np.eye(3) * 2 * h])
    b = recomputed_barriers(c, np.concatenate([offsets, -offsets]))[:, k]
    b0 = getattr(c.barrier, name).barrier_j
    for sign, part in ((1, b[:6]), (-1, b[6:])):
        one_sided = 2 * (part[:3] - b0) / h - (part[3:] - b0) / (2 * h)
        want = (sign * rows).min(axis=0)
        assert np.all(np.abs(one_sided - want) <= tol), (name, sign, one_sided, want)


coords = st.floats(-1.0, 1.0, allow_nan=False)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(coords, coords, coords)
def test_box_gradients_hold_for_any_com(x, y, z):
    """A box with its CoM anywhere in its central 10 % (often on a symmetry plane, where saddles tie)."""
    _check_body(_body(BOX, 0.1 * HALF * np.array([x, y, z])))


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(coords, coords, coords)
def test_off_centre_box_gradients_hold_for_any_com(x, y, z):
    """A box with its CoM well off centre (between 20 % and 70 % of the way to each face)."""
    sign = np.sign([x, y, z]) + (np.array([x, y, z]) == 0)
    _check_body(_body(BOX, HALF * sign * (0.2 + 0.5 * np.abs([x, y, z]))))


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.floats(0.0, 0.7), st.floats(0.0, 2 * np.pi), st.floats(-0.7, 0.7))
def test_cylinder_gradients_hold_for_any_com(radius, angle, height):
    """A 24-sided cylinder (radius 0.1 m, height 0.3 m) with its CoM anywhere inside 70 % of it."""
    com = (0.1 * radius * np.cos(angle), 0.1 * radius * np.sin(angle), 0.15 * height)
    _check_body(_body(CYLINDER, com))


def test_box_on_its_face_has_the_closed_form_gradient():
    """Box 0.4 x 0.3 x 0.2 m resting on its largest face, CoM 20 mm towards +y: the righting barrier rolls over
    the +y edge, world-up there is the unit vector w from the edge (y = 0.15, z = -0.1) to the CoM, so
    dB/dc = m g (w - (0, 0, 1)), and dB/dm = B / m."""
    c = compute(_body(BOX, (0.0, 0.02, 0.0)), landscape_grid=False)
    g = c.gradient["righting"]
    w = np.array([0.0, 0.02 - 0.15, 0.1])
    want = c.mass_kg * c.g_m_s2 * (w / np.linalg.norm(w) - [0, 0, 1])
    assert g.differentiable and np.allclose(g.com_j_per_m, want, rtol=1e-12, atol=1e-15)
    assert g.theta_w_j_per_deg is None and g.theta_l_j_per_deg is None  # a rigid body: no joints


def test_box_with_two_equally_high_roll_edges_is_flagged_not_differentiated():
    """The degenerate case: CoM centred, so the two roll edges are equally high. The barrier is the lower of two
    saddles with gradients mirror images of each other: no gradient exists (the output says why), the mass
    derivative does, and each saddle's one-sided gradient is kept. Moving the CoM 1 mm off centre makes it
    differentiable again."""
    c = compute(_body(BOX, (0.0, 0.0, 0.0)), landscape_grid=False)
    g = c.gradient["righting"]
    assert not g.differentiable and g.com_j_per_m is None and "2 saddles" in g.reason
    assert g.mass_j_per_kg == c.barrier.righting.barrier_j / c.mass_kg
    rows = g.one_sided_com_j_per_m
    assert rows.shape == (2, 3) and rows[0, 1] == pytest.approx(-rows[1, 1])
    d = g.steepest_descent()
    assert d is not None and d[1] == pytest.approx(np.linalg.norm(rows[0]))
    assert c.to_dict()["barrier"]["gradient"]["righting"]["com_j_per_m"] is None
    off = compute(_body(BOX, (0.0, 0.001, 0.0)), landscape_grid=False)
    assert off.gradient["righting"].differentiable


@pytest.mark.parametrize("method, step", [("grid", 2.0), ("sphere", 3.0)])
def test_grid_and_sphere_gradients_are_the_derivatives_of_their_own_barriers(method, step):
    """The grid and icosphere methods' exits are fixed up-directions: dB/dc = m g (u_cell - u_start cell), exactly
    the derivative of the method's number while its bottleneck cell stays."""
    c = compute(_body(BOX, (0.03, 0.02, -0.01)), method=method, step_deg=step)
    fd = _com_fd(c, COM_STEP_M)
    scale = c.mass_kg * c.g_m_s2
    for k, name in enumerate(EXIT_NAMES):
        g = c.gradient[name]
        if g is not None and g.com_j_per_m is not None:
            assert np.all(np.abs(g.com_j_per_m - fd[k]) <= RTOL * np.abs(fd[k]) + 1e-9 * scale), name
    assert np.isnan(c.gradient["righting"].reach_m)


def test_a_mass_change_scales_every_barrier():
    c = compute(load_robot(), theta_w_deg=74.0, theta_l_deg=30.0, landscape_grid=False)
    heavier = replace(c, pose=replace(c.pose, mass_kg=c.pose.mass_kg * 1.01))
    b = recomputed_barriers(heavier, np.zeros((1, 3)))[0]
    for k, name in enumerate(EXIT_NAMES):
        x = getattr(c.barrier, name)
        if x is not None:
            assert (b[k] - x.barrier_j) / (0.01 * c.mass_kg) == pytest.approx(
                c.gradient[name].mass_j_per_kg, rel=1e-9
            )
