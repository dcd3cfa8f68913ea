"""MuJoCo's measured defaults meet the criteria they were chosen by (benchmarks/mujoco_parameters.py), on cheap
cases: no bounce where pybullet's default contact has none, the settled pose within 0.5 deg of the landscape's
metastable minimum at theta_w 0, 60 and 90, and in a whole trial no servo chatter, penetration under the stated
depth and a bounded tracking error; each criterion shown able to fail."""

from dataclasses import replace

import pytest

pytest.importorskip("mujoco")

from sim.engine import MUJOCO_DEFAULTS  # noqa: E402
from sim.protocol import MUJOCO_DT_S  # noqa: E402
from sim.world import Contact  # noqa: E402
from tests.conftest import load_script  # noqa: E402


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/mujoco_parameters.py")


def test_the_dropped_box_does_not_bounce_as_in_pybullets_default_contact(bench):
    e_pb, pen_pb = bench.box_drop_pybullet(Contact(), 5e-4)
    e_mj, pen_mj = bench.box_drop_mujoco(MUJOCO_DEFAULTS, MUJOCO_DT_S)
    assert e_pb == 0.0 and e_mj == 0.0
    assert 0 < pen_mj < 1e-3 and 0 < pen_pb < 1e-3
    # the measure can see a bounce: the rigid contact's e = 0.1, and MuJoCo under-damped
    assert bench.box_drop_pybullet(Contact.rigid(), 5e-4)[0] > 0.05
    assert bench.box_drop_mujoco(replace(MUJOCO_DEFAULTS, solref_dampratio=0.2), MUJOCO_DT_S)[0] > 0.3


def test_the_settled_pose_is_the_landscapes_metastable_minimum(bench):
    targets = bench.pose_targets_deg()
    errors = bench.resting_pose_errors("mujoco", MUJOCO_DEFAULTS, MUJOCO_DT_S, targets)
    assert set(errors) == {0.0, 60.0, 90.0}
    assert bench.worst_pose_error_deg(errors) < bench.MAX_POSE_ERROR_DEG
    assert targets[60.0][0] == pytest.approx(58.84, abs=0.01)  # the wings hold the body up


def test_a_whole_trial_has_no_chatter_a_shallow_penetration_and_a_bounded_tracking_error(bench):
    m = bench.trial_measures("mujoco", MUJOCO_DEFAULTS, MUJOCO_DT_S, bench.CASES[:1])
    assert m["chatter"] == 0
    assert 0 < m["penetration_m"] < bench.MAX_PENETRATION_M
    assert m["max_err_deg"] < 2.5 and m["wing_err_deg"] < 0.2 and m["leg_err_deg"] < 0.2
    assert m["outcomes"] == [1]
    stiff = bench.trial_measures(
        "mujoco", replace(MUJOCO_DEFAULTS, servo_kv_n_m_s_rad=1.0), MUJOCO_DT_S, bench.CASES[:1]
    )
    assert stiff["chatter"] > 0  # a servo gain too high for the step chatters at its effort limit
