"""The MuJoCo world (sim/mujoco_world.py): the URDF's masses and inertias, placement and orientation in closed
form, the same modifier hooks as pybullet's world, deterministic trials, and single attempts that do not depend on
the robot's heading (the elliptic cone), where the pyramidal cone does."""

from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("mujoco")

from lxml import etree as ET  # noqa: E402

from geometry import up_vector  # noqa: E402
from geometry.urdf import origin_matrix  # noqa: E402
from sim.compliance import BodyTorsion, Compliance  # noqa: E402
from sim.engine import MUJOCO_DEFAULTS, EngineWorld  # noqa: E402
from sim.model import sim_model  # noqa: E402
from sim.model_set import load_model_set, shipped_model_sets  # noqa: E402
from sim.mujoco_world import MujocoWorld  # noqa: E402
from sim.trial import Trial, run_trial, simulate_trial  # noqa: E402
from sim.world import World, model_urdf_file  # noqa: E402

DT = 5e-4


def _urdf_inertials(model) -> dict[str, tuple[float, np.ndarray, np.ndarray]]:
    """Link -> (mass kg, CoM m, 3x3 inertia about the CoM kg m^2), both in the link frame, read from the URDF."""
    out = {}
    for link in ET.parse(str(model_urdf_file(model))).getroot().iter("link"):
        el = link.find("inertial")
        if el is None:
            continue
        t = origin_matrix(el)
        i = {k: float(el.find("inertia").get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        tensor = np.array(
            [[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]]
        )
        out[link.get("name")] = (
            float(el.find("mass").get("value")),
            t[:3, 3],
            t[:3, :3] @ tensor @ t[:3, :3].T,
        )
    return out


@pytest.mark.parametrize("modifiers", [(), (BodyTorsion(0.05),)], ids=["rigid", "twisting"])
def test_every_link_has_the_urdfs_mass_com_and_inertia(modifiers):
    import mujoco

    model = sim_model(modifiers=modifiers)
    with MujocoWorld(model, dt_s=DT) as w:
        m = w.m
        urdf = _urdf_inertials(model)
        assert m.nbody - 1 == len(urdf)  # every link one body (fixed links not fused)
        for name, (mass, com, tensor) in urdf.items():
            b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, m.body_iquat[b])
            rot = rot.reshape(3, 3)
            assert m.body_mass[b] == pytest.approx(mass, rel=1e-12, abs=1e-15), name
            np.testing.assert_allclose(m.body_ipos[b], com, rtol=0, atol=1e-12, err_msg=name)
            scale = max(np.abs(tensor).max(), 1e-30)
            np.testing.assert_allclose(
                rot @ np.diag(m.body_inertia[b]) @ rot.T, tensor, rtol=0, atol=1e-12 * scale, err_msg=name
            )
        assert w.mass_kg == pytest.approx(sum(v[0] for v in urdf.values()), rel=1e-12)


def test_it_implements_the_protocol_and_agrees_with_pybullet_on_the_placed_robot():
    """Orientation, heading, CoM height and the modifiers' inertias: the same in both engines (the same URDF)."""
    model = sim_model()
    joints = np.deg2rad([40.0, 40.0, 20.0, 20.0, 15.0])
    pitch, roll, heading = np.deg2rad([30.0, -12.0, 70.0])
    with MujocoWorld(model, dt_s=DT) as mj, World(model, dt_s=DT) as pb:
        assert isinstance(mj, EngineWorld)
        for w in (mj, pb):
            w.place(pitch, roll, joints_rad=joints, heading_rad=heading)
        np.testing.assert_allclose(mj.up_in_body(), up_vector(pitch, roll), atol=1e-12)
        assert mj.heading_rad() == pytest.approx(heading, abs=1e-12)
        np.testing.assert_allclose(mj.joint_positions_rad(), joints, atol=1e-12)
        assert mj.mass_kg == pytest.approx(pb.mass_kg, rel=1e-12)
        assert mj.child_inertia_kg_m2(mj.wing_joints) == pytest.approx(
            pb.child_inertia_kg_m2(pb.wing_joints), rel=1e-9
        )
        for jm, jp in zip(mj.driven, pb.driven, strict=True):
            assert mj.effective_inertia_kg_m2(jm) == pytest.approx(pb.effective_inertia_kg_m2(jp), rel=1e-6)
            assert mj.link_mass_kg_of(jm) == pytest.approx(pb.link_mass_kg_of(jp), rel=1e-12)
        np.testing.assert_allclose(mj.com_velocity_m_s(), 0.0, atol=1e-12)
        assert mj.penetration_m() == 0.0


def test_the_lowest_hull_point_is_placed_at_the_clearance():
    """CoM height = the landscape's height of the pose (the full hull) + clearance, to the hulls' simplification gap."""
    from geometry import Robot
    from landscape.energy import height_at

    model = sim_model()
    pose = Robot.from_urdf(model.source).pose(0.0, 0.0)
    with MujocoWorld(model, dt_s=DT) as w:
        for pitch_deg, roll_deg in ((-1.4, 0.0), (30.0, 20.0), (75.0, -40.0)):
            w.place(np.deg2rad(pitch_deg), np.deg2rad(roll_deg), joints_rad=np.zeros(5), clearance_m=1e-4)
            h = float(height_at(pose, pitch_deg, roll_deg))
            assert w.com_height_m() - 1e-4 == pytest.approx(h, abs=model.max_gap_m + 1e-9)


def test_modifier_hooks_soft_servos_and_springs():
    """A soft wing servo gets the spring-damper torque instead of its actuator; a passive spring is MuJoCo's joint
    stiffness and damping about 0."""
    k, c = 0.8, 0.01
    model = sim_model(modifiers=(BodyTorsion(0.05, 0.002),))
    with MujocoWorld(model, dt_s=DT, modifiers=(BodyTorsion(0.05, 0.002), Compliance(k, c))) as w:
        m, d = w.m, w.d
        j = w.joint_index("body_torsion")
        assert j is not None and w.joint_index("head_mount") is None  # a fixed joint is no MuJoCo joint
        assert m.jnt_stiffness[j] == 0.05 and m.dof_damping[m.jnt_dofadr[j]] == 0.002
        w.place(0.0, 0.0, joints_rad=np.zeros(5))
        target = np.array([0.1, 0.1, 0.2, 0.2, 0.3])
        speed = np.array([1.0, 1.0, 0.0, 0.0, 0.5])
        w.drive(target, speed, kp=DT / 0.01, kd=1.0)
        dofs = [m.jnt_dofadr[jj] for jj in w.wing_joints]
        np.testing.assert_allclose(d.qfrc_applied[dofs], k * target[:4] + c * speed[:4], rtol=1e-12)
        assert (m.actuator_gainprm[:4, 0] == 0).all() and m.actuator_gainprm[4, 0] > 0  # the leg stays stiff
        kv = MUJOCO_DEFAULTS.servo_kv_n_m_s_rad
        assert m.actuator_gainprm[4, 0] == pytest.approx(kv / 0.01) and m.actuator_biasprm[4, 2] == -kv
        assert d.ctrl[4] == pytest.approx(0.3 + 0.01 * 0.5)  # target + tau * feed-forward speed


def test_a_trial_is_deterministic_and_carries_its_engine():
    ms = load_model_set().with_engine("mujoco")
    a, b = (run_trial(74.0, 30.0, phase=0.7, cv=0.1, rng=3, dt_s=DT, model_set=ms, trace=True) for _ in "ab")
    da, db = a.to_dict(), b.to_dict()
    for d in (da, db):
        d.pop("wall_s"), d.pop("cpu_s")
    assert da == db and a.engine == "mujoco" and a.model_set_hash == ms.model_set_hash
    np.testing.assert_array_equal(a.trace.as_array(), b.trace.as_array())
    assert a.trace.heading_deg.shape == a.trace.t_s.shape and np.isfinite(a.trace.omega_body_rad_s).all()
    assert a.trace.energy_j == pytest.approx(0.26 * 9.81 * a.trace.com_height_m, rel=1e-9)


def test_a_trial_from_a_reused_settled_state_is_the_same_bit_for_bit():
    """Numerics(reuse_settled=True), the default: the second trial of a process restores the settled state the
    first left (another trial's angles, phase and noise; physical-posed's soft wing servos, whose state Python
    holds, as well as MuJoCo's) and ends exactly as a trial that settles afresh."""
    from sim.trial import _SETTLED, Numerics

    ms = load_model_set("physical-posed").with_engine("mujoco")
    kw = dict(cv=0.1, dt_s=DT, model_set=ms, trace=True, heading_deg=20.0, duration_s=3.0)
    _SETTLED.clear()
    run_trial(68.0, 30.0, phase=0.2, rng=1, **kw)  # settles and keeps the state
    assert len(_SETTLED) == 1
    reused = run_trial(64.0, 25.0, phase=0.7, rng=3, **kw)
    fresh = run_trial(64.0, 25.0, phase=0.7, rng=3, numerics=Numerics(reuse_settled=False), **kw)
    assert len(_SETTLED) == 1
    da, db = reused.to_dict(), fresh.to_dict()
    for d in (da, db):
        d.pop("wall_s"), d.pop("cpu_s")
    assert da == db
    np.testing.assert_array_equal(reused.trace.as_array(), fresh.trace.as_array())
    np.testing.assert_array_equal(reused.trace.omega_body_rad_s, fresh.trace.omega_body_rad_s)


BORDER_PHASES = (0.1, 0.15, 0.25, 0.3, 0.6, 0.65, 0.75, 0.8)
"""Phases of single attempts at theta_w 72, theta_l 30 next to the success boundary of the MuJoCo phase map (at
dt 5e-4: the attempts at 0.15, 0.3, 0.65 and 0.8 fail, their neighbours right)."""


def _single_attempts(ms, heading_deg: float) -> list[int]:
    act = ms.actuation(72.0, 30.0)
    return [
        int(
            simulate_trial(
                Trial(
                    72.0, 30.0, ph, 0.0, rng=0, dt_s=DT, attempts=1, actuation=act, heading_deg=heading_deg
                ),
                model_set=ms,
            ).success
        )
        for ph in BORDER_PHASES
    ]


def test_single_attempts_near_the_boundary_do_not_depend_on_the_heading():
    """The elliptic cone is isotropic: turned 0.0001, 5, 45 or 90 degrees, the same outcomes."""
    ms = load_model_set().with_engine("mujoco")
    base = _single_attempts(ms, 0.0)
    assert 0 < sum(base) < len(base)  # near the boundary: some right, some do not
    for h in (1e-4, 5.0, 45.0, 90.0):
        assert _single_attempts(ms, h) == base, h


def test_with_the_pyramidal_cone_they_do():
    """The control: MuJoCo's pyramidal cone (its faces fixed in the contact frame) changes some of them."""
    ms = replace(load_model_set(), mujoco=replace(MUJOCO_DEFAULTS, cone="pyramidal")).with_engine("mujoco")
    base = _single_attempts(ms, 0.0)
    assert any(_single_attempts(ms, h) != base for h in (5.0, 45.0))


MODIFIER_TABLES = {
    "body_torsion": "stiffness_n_m_rad = 0.05\ndamping_n_m_s_rad = 0.001\n",
    "leg_bend": "stiffness_n_m_rad = 0.135\ndamping_n_m_s_rad = 0.00055\n",
    "leg_compliance": "stiffness_n_m_rad = 0.08\ndamping_n_m_s_rad = 0.001\n",
    "head_compliance": "stiffness_n_m = 25.0\ndamping_n_s_m = 0.3\n",
    "compliance": "wing_stiffness_n_m_rad = 1.0\nwing_damping_n_m_s_rad = 0.01\nwing_integral_time_s = 0.05\n",
}


@pytest.mark.parametrize("name", [*shipped_model_sets(), *MODIFIER_TABLES])
def test_every_shipped_set_and_every_modifier_runs_in_mujoco(tmp_path, name):
    """A first opening with the leg swinging, each shipped set and a set with each spring modifier: it runs and the
    wings lift the body."""
    from tests.conftest import set_with_table

    ms = load_model_set(
        set_with_table(tmp_path, name, MODIFIER_TABLES[name]) if name in MODIFIER_TABLES else name
    )
    mj = ms.with_engine("mujoco")
    w = 75.0 if ms.measured is not None else 76.0
    r = run_trial(w, 30.0, phase=0.3, cv=0.0, rng=1, model_set=mj, attempts=1, duration_s=1.0, trace=True)
    assert r.engine == "mujoco" and r.model_set_hash == mj.model_set_hash
    assert r.trace.pitch_deg.max() > 20.0  # the wings lifted the body
    assert np.isfinite(r.trace.as_array()).all()
