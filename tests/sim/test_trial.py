import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

SHARED = Path(__file__).resolve().parents[2].parent / "shared"
LAB_URDF = SHARED / "ref" / "lab_robot" / "lab_robot.urdf"
pytestmark = pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")

pytest.importorskip("pybullet")

from sim import Contact, SimulationDiverged, TrialInputError, run_trial  # noqa: E402
from sim.model import sim_model  # noqa: E402
from sim.world import World  # noqa: E402

FAST_DT = 1e-3


def _strip(r):
    d = r.to_dict()
    for k in ("wall_s", "cpu_s"):
        d.pop(k)
    return d


def test_model_hulls_are_simplified():
    m = sim_model(LAB_URDF)
    assert max(k for _, k in m.vertex_counts.values()) <= 96
    assert m.vertex_counts["head_0"][0] == 1002
    assert m.max_gap_m < 1e-3
    assert m.rest_pitch_deg == pytest.approx(-6.3, abs=0.2)  # the lab robot's rest pitch at theta_w = 0
    assert m.description_hash and len(m.model_hash) == 16


def test_strong_setting_rights_by_rolling_on_first_attempt():
    r = run_trial(80.0, 50.0, phase=0.7, cv=0.0, rng=1, robot=LAB_URDF, dt_s=FAST_DT, trace=True)
    assert r.success and r.attempt == 1 and r.mode == "roll"
    t1 = 0.7 * 0.8
    assert t1 < r.time_to_right_s < t1 + 2.0
    assert r.sim_s == pytest.approx(r.time_to_right_s + 0.3, abs=0.006)  # stops once the outcome is decided
    tr = r.trace
    # metastable: wings lift the body to a steep pitch before it rolls over
    opened = (tr.t_s > t1 + 0.35) & (tr.t_s < r.time_to_right_s - 0.3)
    assert np.median(tr.pitch_deg[opened]) > 60.0
    assert tr.up_z[0] > 0.99 and tr.up_z[-1] < 0.0
    assert tr.energy_j == pytest.approx(0.26 * 9.81 * tr.com_height_m, rel=1e-9)


def test_weak_setting_fails_after_several_attempts():
    r = run_trial(70.0, 20.0, phase=0.7, cv=0.1, rng=1, robot=LAB_URDF, dt_s=FAST_DT)
    assert not r.success and r.time_to_right_s is None and r.attempt is None and r.mode is None
    assert r.sim_s == pytest.approx(10.0)
    assert len(r.phases) == len(r.attempt_starts_s) == 5
    assert r.phases[0] == pytest.approx(0.7)
    assert np.all(np.diff(r.attempt_starts_s) > 1.35)


def test_tracking_error_is_bounded():
    r = run_trial(76.0, 50.0, phase=0.2, cv=0.0, rng=2, robot=LAB_URDF, dt_s=FAST_DT, duration_s=3.0,
                  trace=True)
    assert r.max_tracking_error_deg < 4.0
    tr = r.trace
    assert np.abs(tr.wing_deg - tr.wing_cmd_deg).max() < 4.0
    assert np.abs(tr.leg_deg - tr.leg_cmd_deg).max() < 4.0
    assert np.abs(tr.wing_deg - tr.wing_cmd_deg).mean() < 0.5


def test_deterministic_in_process_and_seed_is_kept():
    kw = dict(phase=0.45, cv=0.2, robot=LAB_URDF, dt_s=FAST_DT, duration_s=4.0)
    a = run_trial(74.0, 40.0, rng=11, **kw)
    b = run_trial(74.0, 40.0, rng=11, **kw)
    assert _strip(a) == _strip(b) and a.seed == 11
    c = run_trial(74.0, 40.0, rng=None, **kw)
    assert _strip(run_trial(74.0, 40.0, rng=c.seed, **kw)) == _strip(c)
    g = run_trial(74.0, 40.0, rng=np.random.default_rng(5), **kw)
    assert g.seed == int(np.random.default_rng(5).integers(0, 2**63 - 1))


def test_deterministic_across_processes():
    kw = dict(phase=0.45, cv=0.2, robot=str(LAB_URDF), dt_s=FAST_DT, duration_s=4.0)
    code = ("import json, sys; from sim import run_trial; "
            f"r = run_trial(74.0, 40.0, rng=11, **{kw!r}); d = r.to_dict(); d.pop('wall_s'); d.pop('cpu_s'); "
            "print(json.dumps(d))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    here = _strip(run_trial(74.0, 40.0, rng=11, **{**kw, "robot": LAB_URDF}))
    assert json.loads(out.strip().splitlines()[-1]) == json.loads(json.dumps(here))


@pytest.mark.parametrize("kw, err, match", [
    (dict(theta_w_deg=120.0), "JointLimitError", "theta_w = 120"),
    (dict(phase=1.0), "TrialInputError", "phase must be in"),
    (dict(cv=-0.1), "TrialInputError", "cv must be >= 0"),
    (dict(dt_s=0.0), "TrialInputError", "dt must be"),
    (dict(rng=-3), "TrialInputError", "rng must be"),
])
def test_bad_input(kw, err, match):
    args = dict(theta_w_deg=74.0, theta_l_deg=30.0, phase=0.2, cv=0.0, robot=LAB_URDF)
    with pytest.raises(ValueError, match=match) as info:
        run_trial(**{**args, **kw})
    assert type(info.value).__name__ == err


def test_diverged_state_raises():
    m = sim_model(LAB_URDF)
    with World(m, dt_s=FAST_DT) as w:
        w.place(0.0, 0.0, joints_rad=np.zeros(len(w.driven)))
        w.check_finite(0.0)
        import pybullet as pb

        pb.resetBaseVelocity(w.body, [1e3, 0, 0], [0, 0, 0], physicsClientId=w.cid)
        with pytest.raises(SimulationDiverged, match="diverged at t = 1.5000 s"):
            w.check_finite(1.5)
        cid = w.cid
    assert w.cid is None
    import pybullet as pb

    with pytest.raises(pb.error):
        pb.getNumBodies(physicsClientId=cid)  # the client was disconnected


def test_rigid_contact_option_runs():
    r = run_trial(80.0, 50.0, phase=0.7, cv=0.0, rng=1, robot=LAB_URDF, dt_s=FAST_DT, duration_s=1.0,
                  contact=replace(Contact.rigid(), restitution=0.1))
    assert r.sim_s == pytest.approx(1.0)


def test_trial_input_error_is_value_error():
    assert issubclass(TrialInputError, ValueError) and issubclass(SimulationDiverged, RuntimeError)
