"""A body that twists (sim.compliance.BodyTorsion, sim.urdf_edits.add_body_torsion): values and stability refused in
one line, the model-set table, a joint that changes neither mass nor pose, and the physics: the symmetric load of
the hold does not twist the body (no sag, unlike a spring in each wing joint), a stiff torsion acts rigid, and a
soft one lets the leg's swing rock the body further."""

import numpy as np
import pybullet as pb
import pytest

from sim.compliance import BodyTorsion, ComplianceError, check_spring_stability
from sim.model import sim_model
from sim.model_set import load_model_set
from sim.trial import run_trial
from sim.urdf_edits import TORSION_JOINT, TORSION_LINK
from sim.world import World
from tests.conftest import set_with_table


@pytest.mark.parametrize(
    "k, c, match",
    [(0.0, 0.0, "must be > 0"), (1.0, -1.0, ">= 0"), (float("inf"), 0.0, "finite"), (True, 0.0, "finite")],
)
def test_bad_values_are_refused(k, c, match):
    with pytest.raises(ComplianceError, match=match):
        BodyTorsion(k, c)


def test_stability_bound():
    check_spring_stability(BodyTorsion(1.0, 0.01), 3e-5, 1e-3)  # sqrt(k/I) T = 0.18, c T / I = 0.33
    with pytest.raises(ComplianceError, match=r"give k <= 7\.5 N m/rad"):
        check_spring_stability(BodyTorsion(8.0), 3e-5, 1e-3)
    with pytest.raises(ComplianceError, match=r"damping_n_m_s_rad 0\.02 is too high.*give c <= 0\.015"):
        check_spring_stability(BodyTorsion(1.0, 0.02), 3e-5, 1e-3)


def _link_poses(w: World) -> dict[str, tuple]:
    names = [pb.getJointInfo(w.body, j, physicsClientId=w.cid)[12].decode() for j in range(w.n_joints)]
    states = pb.getLinkStates(w.body, list(range(w.n_joints)), physicsClientId=w.cid)
    return {n: s[0] for n, s in zip(names, states, strict=True)}


def test_the_joint_changes_neither_mass_nor_pose():
    torsion = BodyTorsion(0.05)
    rigid, twisting = sim_model(), sim_model(modifiers=(torsion,))
    assert TORSION_JOINT in twisting.urdf_text and TORSION_JOINT not in rigid.urdf_text
    assert twisting.model_hash != rigid.model_hash
    joints = np.deg2rad([40.0, 40.0, 40.0, 40.0, 20.0])
    with World(rigid, dt_s=5e-4) as w0, World(twisting, dt_s=5e-4) as w1:
        for w in (w0, w1):
            w.place(np.deg2rad(30.0), np.deg2rad(10.0), joints_rad=joints)
        assert w1.mass_kg == pytest.approx(w0.mass_kg, rel=1e-12)
        p0, p1 = _link_poses(w0), _link_poses(w1)
        assert set(p1) == set(p0) | {TORSION_LINK}
        for name, pos in p0.items():
            assert np.allclose(p1[name], pos, atol=1e-12), name
        assert 0 < torsion.inertia_kg_m2(w1) < np.inf
        assert np.isnan(torsion.inertia_kg_m2(w0))


def test_a_torsion_and_the_twisting_model_go_together():
    torsion = BodyTorsion(0.05)
    with pytest.raises(
        ValueError, match=r"URDF \(body_torsion\) must be those the model was built with \(none\)"
    ):
        with World(sim_model(), dt_s=5e-4, modifiers=(torsion,)):
            pass
    with pytest.raises(ValueError, match=r"URDF \(none\) must be those .* \(body_torsion\)"):  # a free hinge
        with World(sim_model(modifiers=(torsion,)), dt_s=5e-4, modifiers=()):
            pass


def _opening(model_set, theta_l_deg: float):
    """One first opening of the built-in robot at 74 deg: (hold pitch, sd of lateral tilt in the hold), degrees."""
    res = run_trial(
        74.0,
        theta_l_deg,
        phase=0.3,
        cv=0.0,
        rng=1,
        model_set=model_set,
        trace=True,
        attempts=1,
        duration_s=1.6,
    )
    tr = res.trace
    t = tr.t_s - res.attempt_starts_s[0]
    hold = (t >= 0.5) & (t <= 0.95)
    tilt = np.degrees(np.arcsin(np.cos(np.radians(tr.pitch_deg)) * np.sin(np.radians(tr.roll_deg))))
    return float(np.median(tr.pitch_deg[hold])), float(np.std(tilt[hold]))


@pytest.mark.e2e  # whole trials of the lab robot, about 6 s (CI runs e2e as a step of its own)
def test_the_hold_does_not_sag_and_the_leg_rocks_a_soft_body_further(tmp_path):
    rigid = load_model_set("paper")
    soft = load_model_set(
        set_with_table(tmp_path, "body_torsion", "stiffness_n_m_rad = 0.03\ndamping_n_m_s_rad = 0.001\n")
    )
    (tmp_path / "s").mkdir()
    stiff = load_model_set(
        set_with_table(tmp_path / "s", "body_torsion", "stiffness_n_m_rad = 5.0\ndamping_n_m_s_rad = 0.005\n")
    )
    pitch_rigid, _ = _opening(rigid, 0.0)
    pitch_soft, _ = _opening(soft, 0.0)
    # the two wings' moments about the long axis cancel: the soft body holds where the rigid one does
    assert abs(pitch_soft - pitch_rigid) < 0.3
    # with the leg swinging 10 deg (the hold rocks but stays), stiff acts rigid and soft rocks further
    _, rock_rigid = _opening(rigid, 10.0)
    _, rock_stiff = _opening(stiff, 10.0)
    _, rock_soft = _opening(soft, 10.0)
    assert abs(rock_stiff - rock_rigid) < 0.3
    assert rock_soft > rock_rigid + 0.5


def test_too_stiff_a_torsion_is_refused_before_the_trial(tmp_path):
    ms = load_model_set(set_with_table(tmp_path, "body_torsion", "stiffness_n_m_rad = 500.0\n"))
    with pytest.raises(ComplianceError, match="too stiff"):
        run_trial(74.0, 0.0, phase=0.0, cv=0.0, rng=0, model_set=ms, duration_s=0.1)
