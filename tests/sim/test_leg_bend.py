"""A leg that bends out of its swing plane (sim.compliance.LegBend, sim.urdf_edits.add_leg_bend, a model set's
``[leg_bend]``): values refused in one line, the table, a joint that changes neither mass nor pose, a stiff bend
that barely sags, and a soft one that sags by its load and rings at its frequency."""

import numpy as np
import pybullet as pb
import pytest

from sim.compliance import ComplianceError, LegBend, check_spring_stability
from sim.model import sim_model
from sim.urdf_edits import BEND_JOINT, BEND_LINK
from sim.world import World
from tests.sim.test_body_torsion import _link_poses


@pytest.mark.parametrize(
    "k, c, match", [(0.0, 0.0, "must be > 0"), (1.0, -1.0, ">= 0"), (float("inf"), 0.0, "finite")]
)
def test_bad_values_are_refused(k, c, match):
    with pytest.raises(ComplianceError, match=f"leg_bend .*{match}"):
        LegBend(k, c)


def test_stability_bound():
    check_spring_stability(LegBend(0.135, 0.00055), 2.25e-4, 1e-3)
    with pytest.raises(ComplianceError, match=r"leg_bend stiffness_n_m_rad 100 is too stiff.*the leg's"):
        check_spring_stability(LegBend(100.0), 2.25e-4, 1e-3)


def test_the_joint_changes_neither_mass_nor_pose():
    bend = LegBend(0.135)
    rigid, bending = sim_model(), sim_model(modifiers=(bend,))
    assert BEND_JOINT in bending.urdf_text and BEND_JOINT not in rigid.urdf_text
    joints = np.deg2rad([40.0, 40.0, 40.0, 40.0, 20.0])
    with World(rigid, dt_s=5e-4) as w0, World(bending, dt_s=5e-4) as w1:
        for w in (w0, w1):
            w.place(np.deg2rad(30.0), np.deg2rad(10.0), joints_rad=joints)
        assert w1.mass_kg == pytest.approx(w0.mass_kg, rel=1e-5)
        p0, p1 = _link_poses(w0), _link_poses(w1)
        assert set(p1) == set(p0) | {BEND_LINK}
        for name, pos in p0.items():
            assert np.allclose(p1[name], pos, atol=1e-12), name
        assert bend.inertia_kg_m2(w1) == pytest.approx(2.25e-4, rel=0.05)  # 55.8 g about 62 mm
    with pytest.raises(
        ValueError, match=r"URDF \(leg_bend\) must be those the model was built with \(none\)"
    ):
        with World(rigid, dt_s=5e-4, modifiers=(LegBend(0.1),)):
            pass
    with pytest.raises(ValueError, match=r"URDF \(none\) must be those .* \(leg_bend\)"):  # a free hinge
        with World(bending, dt_s=5e-4, modifiers=()):
            pass


def _bend_angle(k: float, c: float, *, seconds: float = 1.0, dt: float = 5e-4):
    """The bend joint's angle (rad) over ``seconds`` with the robot placed on its back, wings closed, leg centred."""
    bend = LegBend(k, c)
    with World(sim_model(modifiers=(bend,)), dt_s=dt) as w:
        w.place(0.0, 0.0, joints_rad=np.zeros(5))
        q = []
        for _ in range(int(round(seconds / dt))):
            w.advance(1)
            q.append(pb.getJointState(w.body, w.joint_index(BEND_JOINT), physicsClientId=w.cid)[0])
        return np.asarray(q), bend.inertia_kg_m2(w)


def test_a_soft_bend_sags_by_its_load_and_rings_at_its_frequency():
    """On its back the leg lies level, so gravity loads the bend with m g r (55.8 g at 62 mm: 0.034 N m): a spring
    of 0.135 N m/rad (the robot's 3.9 Hz pitch ringing, k = I (2 pi f)^2) sags by about 0.25 rad and rings at
    about 3.9 Hz; one 40 times stiffer sags 40 times less."""
    dt = 5e-4
    q, inertia = _bend_angle(0.135, 0.00055, dt=dt)
    load = 0.0558 * 9.81 * 0.0622
    settled = q[len(q) // 2 :].mean()
    assert abs(settled) == pytest.approx(load / 0.135, rel=0.3)
    x = q - settled
    crossings = np.flatnonzero(np.diff(np.sign(x)) != 0)
    f_hz = (len(crossings) - 1) / 2 / ((crossings[-1] - crossings[0]) * dt)
    assert f_hz == pytest.approx(np.sqrt(0.135 / inertia) / (2 * np.pi), rel=0.25)
    stiff, _ = _bend_angle(5.4, 0.0035, dt=dt)
    assert abs(stiff[len(stiff) // 2 :].mean()) < abs(settled) / 20
