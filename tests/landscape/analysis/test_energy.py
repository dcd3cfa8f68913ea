"""The energy budget (landscape.analysis.energy) against closed forms: a free body's rotational energy, a box tipping
over an edge, the body-axis shares, and the barrier table at its nodes."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from landscape.analysis import energy as en

HALF_M = np.array([0.05, 0.03, 0.02])
MASS_KG = 0.3


def _box_inertia() -> np.ndarray:
    a, b, c = HALF_M
    return MASS_KG / 3.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def _box_world(pb, *, dt_s: float, gravity: float, orientation, position, ground: bool):
    cid = pb.connect(pb.DIRECT)
    pb.setGravity(0.0, 0.0, -gravity, physicsClientId=cid)
    pb.setPhysicsEngineParameter(fixedTimeStep=dt_s, physicsClientId=cid)
    bodies = []
    if ground:
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid)
        bodies.append(pb.createMultiBody(0.0, plane, physicsClientId=cid))
    col = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=HALF_M.tolist(), physicsClientId=cid)
    box = pb.createMultiBody(
        MASS_KG, col, basePosition=list(position), baseOrientation=orientation, physicsClientId=cid
    )
    for b in (*bodies, box):
        pb.changeDynamics(
            b,
            -1,
            linearDamping=0.0,
            angularDamping=0.0,
            lateralFriction=1.0,
            restitution=0.0,
            physicsClientId=cid,
        )
    assert np.allclose(pb.getDynamicsInfo(box, -1, physicsClientId=cid)[2], np.diag(_box_inertia()))
    return cid, box, (bodies[0] if bodies else None)


def _state(pb, cid, box):
    """Body-frame angular velocity, CoM velocity, CoM position and the rotation matrix of the box."""
    pos, q = pb.getBasePositionAndOrientation(box, physicsClientId=cid)
    rot = np.array(pb.getMatrixFromQuaternion(q)).reshape(3, 3)
    v, w = pb.getBaseVelocity(box, physicsClientId=cid)
    return rot.T @ np.asarray(w), np.asarray(v), np.asarray(pos), rot


@pytest.mark.parametrize(
    ("omega_body", "dt_s", "duration_s"),
    [([0.0, 0.0, 5.0], 1e-3, 1.0), ([3.0, 1.0, -2.0], 1e-5, 0.03)],
    ids=["principal-axis", "tumbling"],
)
def test_free_body_keeps_its_rotational_energy(omega_body, dt_s, duration_s):
    """No gravity, no contact: 0.5 w^T I w with the engine's angular velocity turned into the body frame stays at
    its closed-form value to 1e-6 (the tumbling box at a small step: pybullet's integrator drifts at first order
    in dt, 3e-3 in 2 s at 1 ms)."""
    pb = pytest.importorskip("pybullet")
    q0 = pb.getQuaternionFromEuler(
        [0.3, 0.2, 0.1]
    )  # tilted, so a world-frame omega would give another energy
    cid, box, _ = _box_world(pb, dt_s=dt_s, gravity=0.0, orientation=q0, position=[0, 0, 1], ground=False)
    try:
        rot0 = np.array(pb.getMatrixFromQuaternion(q0)).reshape(3, 3)
        pb.resetBaseVelocity(
            box, [0.0, 0.0, 0.0], (rot0 @ np.asarray(omega_body)).tolist(), physicsClientId=cid
        )
        exact = 0.5 * np.asarray(omega_body) @ _box_inertia() @ np.asarray(omega_body)
        ke = []
        for i in range(int(round(duration_s / dt_s))):
            pb.stepSimulation(physicsClientId=cid)
            if i % 10 == 0:
                w, *_ = _state(pb, cid, box)
                ke.append(en.rotational_shares_j(w, _box_inertia()).sum())
    finally:
        pb.disconnect(cid)
    assert np.abs(np.asarray(ke) / exact - 1.0).max() <= 1e-6


def test_box_tipping_over_an_edge_turns_its_drop_into_kinetic_energy():
    """A box released at rest on its edge, its CoM 2 deg past the edge, lands on its face with the kinetic
    energy m g dh (rotation about the CoM plus translation) within 1 %."""
    pb = pytest.importorskip("pybullet")
    a, c = HALF_M[0], HALF_M[2]
    tilt = math.atan2(a, c) - math.radians(2.0)
    q = pb.getQuaternionFromEuler([0.0, tilt, 0.0])
    rot = np.array(pb.getMatrixFromQuaternion(q)).reshape(3, 3)
    edge = rot @ np.array([a, 0.0, -c])
    cid, box, _ = _box_world(
        pb, dt_s=2e-4, gravity=9.81, orientation=q, position=[-edge[0], 0.0, -edge[2]], ground=True
    )
    try:
        h0 = pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0][2]
        rows = []
        for _ in range(int(0.5 / 2e-4)):
            pb.stepSimulation(physicsClientId=cid)
            w, v, pos, r = _state(pb, cid, box)
            ke = en.rotational_shares_j(w, _box_inertia()).sum() + en.translational_energy_j(MASS_KG, v)
            rows.append((pos[2], ke, r[2, 2]))
    finally:
        pb.disconnect(cid)
    z, ke, cos_tilt = np.asarray(rows).T
    k = int(np.argmax(ke))  # the last sample before the face strikes
    assert cos_tilt[k] > math.cos(math.radians(1.0))  # at the bottom: the face within a degree of flat
    assert ke[k] == pytest.approx(MASS_KG * 9.81 * (h0 - z[k]), rel=0.01)
    assert ke[k] == pytest.approx(MASS_KG * 9.81 * (h0 - c), rel=0.01)


def _spd(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(3, 3))
    return a @ a.T + 0.1 * np.eye(3)


@given(
    st.lists(st.floats(-50, 50, allow_nan=False), min_size=3, max_size=3),
    st.integers(0, 2**31 - 1),
)
def test_body_axis_shares_sum_to_the_rotational_energy(omega, seed):
    inertia = _spd(seed)
    w = np.asarray(omega)
    shares = en.rotational_shares_j(w, inertia)
    assert shares.sum() == pytest.approx(0.5 * w @ inertia @ w, rel=1e-12, abs=1e-12)


def test_shares_of_a_diagonal_inertia_are_each_axis_energy():
    shares = en.rotational_shares_j([[2.0, -1.0, 3.0]], np.diag([1.0, 2.0, 3.0]))
    np.testing.assert_allclose(shares, [[2.0, 1.0, 13.5]])


def test_the_table_at_its_own_poses_is_the_direct_computation():
    """The interpolated barrier and minimum at every node of a barrier table equal compute()'s, exact method."""
    from geometry.builtin import load_builtin_robot
    from landscape.computation import compute

    robot = load_builtin_robot()
    body = en.BodyModel(robot)
    ws, ls = [60.0, 70.0], [-15.0, 0.0, 15.0]
    table = en.barrier_table(body, ws, ls)
    for w in ws:
        for leg in ls:
            c = compute(robot, theta_w_deg=w, theta_l_deg=leg, method="exact", landscape_grid=False)
            b, m, d, s = table.at(np.array([w]), np.array([leg]))
            assert b[0] == pytest.approx(c.barrier.righting.barrier_j, rel=1e-9)
            assert m[0] == pytest.approx(c.minimum.energy_j, rel=1e-9)
            assert d[0] == c.barrier.righting.direction
            saddle = (
                c.barrier.righting.saddle_roll_deg if d[0] == "roll" else c.barrier.righting.saddle_pitch_deg
            )
            assert s[0] == (1 if saddle >= 0 else -1)
    mid, *_ = table.at(np.array([65.0]), np.array([7.5]))  # halfway between four nodes: their mean
    assert mid[0] == pytest.approx(table.barrier_j[:, 1:].mean(), rel=1e-12)


def test_attempt_rows_from_a_motion_with_known_energies():
    """A body held at its start minimum, turning about x at 2 rad/s during its one attempt: the roll share is
    0.5 I_xx w^2, the height 0, and the margin that share minus the barrier."""
    from geometry.builtin import load_builtin_robot

    body = en.BodyModel(load_builtin_robot())
    table = en.barrier_table(body, [70.0], [0.0])
    pose = body.pose(70.0, 0.0)
    from landscape.computation import compute

    c = compute(body.robot, theta_w_deg=70.0, theta_l_deg=0.0, method="exact", landscape_grid=False)
    n = 50
    t = np.arange(n) * 0.01
    omega = np.zeros((n, 3))
    omega[10:20, 0] = 2.0
    motion = en.Motion(
        "simulated", "1", 70.0, 0.0, t, np.full(n, c.minimum.pitch_deg), np.full(n, c.minimum.roll_deg),
        np.full(n, 70.0), np.zeros(n), omega, np.zeros((n, 3)), np.array([0.0]), np.array([False]),
        np.array([0.25]),
    )  # fmt: skip
    et = en.energy_trace(motion, body, table)
    np.testing.assert_allclose(et.height_j, 0.0, atol=1e-9)
    (row,) = en.attempt_energies(motion, et)
    want = 0.5 * pose.inertia_kg_m2[0, 0] * 4.0 * 1e3
    assert row.direction == c.barrier.righting.direction
    if row.direction == "roll":
        assert row.ke_peak_mj == pytest.approx(want, rel=1e-12)
        assert row.ke_peak_t_s == pytest.approx(0.10)
        assert row.margin_mj == pytest.approx(want - c.barrier.righting.barrier_j * 1e3, rel=1e-9)
    assert row.ke_roll_mj == pytest.approx(want, rel=1e-12)
    assert row.barrier_mj == pytest.approx(c.barrier.righting.barrier_j * 1e3, rel=1e-9)
    assert (row.attempt, row.success, row.phase, row.ke_trans_mj) == (1, False, 0.25, 0.0)
