"""A head whose attachment gives (sim.head_compliance.HeadCompliance, sim.urdf_edits.add_head_compliance, a model set's
``[head_compliance]``): values and tables refused in one line, a joint that changes neither mass nor pose, and the
physics on the built-in robot: the head carries nothing on the robot's back and part of the body in the hold, so
a soft head holds the body further over only once the wings are open, by more the softer it is, and no further
than its stop allows."""

import math

import numpy as np
import pybullet as pb
import pytest

from geometry.errors import RobotDescriptionError, UnknownJointError
from landscape.analysis.physical.calibration import candidate_set
from landscape.analysis.physical.response import simulated_opening
from sim.compliance import ComplianceError
from sim.head_compliance import HeadCompliance, check_head_stability
from sim.model import sim_model
from sim.model_set import ModelSetError, load_model_set
from sim.trial import run_trial
from sim.world import World
from tests.conftest import set_with_table
from tests.sim.test_body_torsion import _link_poses


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"stiffness": 0.0}, "stiffness_n_m must be > 0"),
        ({"stiffness": 1.0, "slide": False, "damping": -1.0}, "damping_n_m_s_rad must be >= 0"),
        ({"stiffness": float("nan")}, "finite"),
        ({"stiffness": 1.0, "travel": 0.031}, "travel_mm must be > 0 and at most 30 mm"),
        (
            {"stiffness": 1.0, "slide": False, "travel": math.radians(50)},
            "travel_deg must be > 0 and at most 45",
        ),
        ({"stiffness": 1.0, "axis": (0.0, 0.0, 0.0)}, "axis must be three finite numbers"),
        ({"stiffness": 1.0, "joint": ""}, "joint must be a joint's name"),
    ],
)
def test_bad_values_are_refused(kwargs, match):
    with pytest.raises(ComplianceError, match=f"head_compliance .*{match}"):
        HeadCompliance(**kwargs)


@pytest.mark.parametrize(
    "text, match",
    [
        ("stiffness_n_m = 25.0\ntravel_deg = 10.0\n", "give a slide .* or a hinge .*not both"),
        ("damping_n_s_m = 0.3\n", "give a slide"),
        ("stiffness_n_m = 25.0\nfoo = 1\n", "unknown key 'foo'"),
        ("stiffness_n_m = 25.0\naxis = 1.0\n", "axis must be a list"),
        ("stiffness_n_m = 25.0\ntravel_mm = 40.0\n", "travel_mm must be > 0 and at most 30 mm"),
    ],
)
def test_a_bad_table_is_refused_in_one_line(tmp_path, text, match):
    with pytest.raises(ModelSetError, match=match):
        load_model_set(set_with_table(tmp_path, "head_compliance", text))


def test_the_table_enters_the_hash_and_the_summary(tmp_path):
    slide = load_model_set(
        set_with_table(tmp_path, "head_compliance", "stiffness_n_m = 25.0\ntravel_mm = 17\n")
    )
    h = slide.head_compliance
    assert (h.slide, h.stiffness, h.damping, h.axis, h.joint) == (
        True,
        25.0,
        0.0,
        (1.0, 0.0, 0.0),
        "head_mount",
    )
    assert h.travel == pytest.approx(0.017)
    assert slide.summary()["elements"] == ["head_compliance"]
    paper = load_model_set("paper")
    assert slide.model_set_hash != paper.model_set_hash
    hinge = load_model_set(
        set_with_table(tmp_path, "head_compliance", "stiffness_n_m_rad = 0.5\naxis = [0, 1, 0]\n")
    )
    assert not hinge.head_compliance.slide and hinge.head_compliance.travel == pytest.approx(math.radians(30))
    assert hinge.model_set_hash not in (slide.model_set_hash, paper.model_set_hash)


def test_a_calibration_may_add_the_table(tmp_path):
    ms = candidate_set(
        "paper",
        {"head_compliance.stiffness_n_m": 25.0, "head_compliance.travel_mm": 17.0},
        "c",
        tmp_path / "c.toml",
    )
    assert ms.head_compliance.stiffness == 25.0 and ms.head_compliance.travel == pytest.approx(0.017)


def test_the_joint_changes_neither_mass_nor_pose_and_needs_its_spring():
    head = HeadCompliance(25.0, 0.3)
    rigid, soft = sim_model(), sim_model(modifiers=(head,))
    assert soft.modifiers == (head,) and rigid.modifiers == ()
    assert soft.model_hash != rigid.model_hash
    joints = np.deg2rad([40.0, 40.0, 40.0, 40.0, 20.0])
    with World(rigid, dt_s=5e-4) as w0, World(soft, dt_s=5e-4) as w1:
        for w in (w0, w1):
            w.place(np.deg2rad(30.0), np.deg2rad(10.0), joints_rad=joints)
        assert w1.mass_kg == pytest.approx(w0.mass_kg, rel=1e-9)
        p0, p1 = _link_poses(w0), _link_poses(w1)
        assert set(p1) == set(p0)
        for name, pos in p0.items():
            assert np.allclose(p1[name], pos, atol=1e-12), name
        assert head.inertia(w1) == pytest.approx(0.0134, rel=0.3)  # the slide moves the head's mass
        assert math.isnan(HeadCompliance(25.0, joint="nose").inertia(w0))
    with pytest.raises(ValueError, match=r"URDF \(none\) must be those"):
        with World(soft, dt_s=5e-4, modifiers=()):  # else the head would slide freely
            pass
    with pytest.raises(ValueError, match=r"URDF \(head_compliance\) must be those .* \(none\)"):
        with World(rigid, dt_s=5e-4, modifiers=(head,)):
            pass


def test_a_joint_that_is_missing_or_moves_is_refused():
    with pytest.raises(UnknownJointError, match="no joint 'nose'.*give the joint that attaches the head"):
        sim_model(modifiers=(HeadCompliance(25.0, joint="nose"),))
    with pytest.raises(RobotDescriptionError, match="joint 'leg' is revolute, not fixed"):
        sim_model(modifiers=(HeadCompliance(25.0, joint="leg"),))


def test_too_stiff_a_head_is_refused_before_the_trial(tmp_path):
    check_head_stability(HeadCompliance(25.0, 0.3), 0.0134, 1e-3)
    ms = load_model_set(set_with_table(tmp_path, "head_compliance", "stiffness_n_m = 1e5\n"))
    with pytest.raises(ComplianceError, match="stiffness_n_m 100000 is too stiff.*give k <= .* N/m"):
        run_trial(75.0, 0.0, phase=0.5, cv=0.0, rng=1, duration_s=0.5, model_set=ms)


def _hold(tmp_path, text: str | None) -> float:
    """The built-in robot's held pitch in its first opening at 75 deg, leg still (paper set), degrees."""
    ms = "paper" if text is None else set_with_table(tmp_path, "head_compliance", text)
    return simulated_opening(75.0, 0.0, phase=0.5, seed=1, model_set=ms).hold_pitch_deg


def _deflection_on_back(text: str, tmp_path) -> float:
    ms = load_model_set(set_with_table(tmp_path, "head_compliance", text))
    head = ms.head_compliance
    with World(sim_model(modifiers=(head,)), dt_s=5e-4) as w:
        w.place(0.0, 0.0, joints_rad=np.zeros(5))
        w.advance(1000)
        return pb.getJointState(w.body, w.joint_index(head.joint), physicsClientId=w.cid)[0]


@pytest.mark.e2e  # whole trials of the lab robot, about 6 s (CI runs e2e as a step of its own)
def test_a_soft_head_holds_the_body_further_over_only_in_the_hold_and_no_further_than_its_stop(tmp_path):
    """On its back the head touches nothing, so even a soft head stays where it is; in the hold it carries part
    of the body and gives along the body: a softer head holds the body further over (here 69.8, 70.1, 71.9 and
    76.7 deg: rigid, 2000, 200 and 100 N/m, damping 1 N s/m), and a stop 2 mm out caps it (70.7 deg)."""
    assert abs(_deflection_on_back("stiffness_n_m = 20.0\ndamping_n_s_m = 0.3\n", tmp_path)) < 1e-3
    rigid = _hold(tmp_path, None)
    held = [_hold(tmp_path, f"stiffness_n_m = {k}\ndamping_n_s_m = 1.0\n") for k in (2000.0, 200.0, 100.0)]
    stopped = _hold(tmp_path, "stiffness_n_m = 100.0\ndamping_n_s_m = 1.0\ntravel_mm = 2.0\n")
    assert abs(held[0] - rigid) < 0.5
    assert held[0] < held[1] < held[2] and held[2] > rigid + 3.0
    assert rigid < stopped < held[2] - 3.0


def test_a_sweep_refuses_a_head_joint_the_robot_lacks_before_any_trial(tmp_path, capsys):
    from landscape.cli import main

    f = set_with_table(tmp_path, "head_compliance", 'stiffness_n_m = 25.0\njoint = "nose"\n')
    args = ["sweep", "--theta-w", "74", "--theta-l", "30", "--cv", "0", "--trials", "1", "--duration", "0.5"]
    assert main([*args, "--model", str(f), "--db", str(tmp_path / "t.sqlite"), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no joint 'nose' for [head_compliance]" in err[0]
