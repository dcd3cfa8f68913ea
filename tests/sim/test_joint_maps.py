"""Joint maps reach the dynamics and the sweep; the sim reads the robot through geometry's reader (#9, #16).

Every robot is an exported copy of the built-in robot (no ../shared needed)."""

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pybullet")

from geometry import JointMap, Robot, UnknownJointError  # noqa: E402
from geometry.builtin import URDF_NAME  # noqa: E402
from geometry.errors import RobotDescriptionError  # noqa: E402
from sim.model import sim_model  # noqa: E402
from sim.sweep import run_spec, sweep_specs  # noqa: E402
from sim.trial import DEFAULT_DT_S, OTHER_ROBOT_DT_S, default_dt_s, run_trial  # noqa: E402
from tests.robot_files import export  # noqa: E402
from tests.robot_files import rename_joints as rename  # noqa: E402

RENAMED_MAP = "wing=j_wing_pitch_left,j_wing_pitch_right,j_wing_roll_left,j_wing_roll_right;leg=j_leg"


@pytest.fixture(scope="module")
def renamed(tmp_path_factory) -> Path:
    return export(tmp_path_factory.mktemp("renamed"), rename)


def test_renamed_robot_simulates_with_its_joint_map_at_the_default_dt(renamed):
    jm = JointMap.parse(RENAMED_MAP)
    assert (
        default_dt_s(renamed) == OTHER_ROBOT_DT_S
    )  # needs no joint map (it used to load the model without it)
    r = run_trial(74.0, 30.0, phase=0.0, cv=0.0, rng=1, duration_s=0.05, robot=renamed, joint_map=jm)
    assert r.dt_s == OTHER_ROBOT_DT_S
    assert r.robot_hash == Robot.from_urdf(renamed, joint_map=jm).robot_hash


def test_renamed_robot_moves_exactly_like_the_builtin(renamed, tmp_path):
    """Joint names do not enter the physics: the same trial on the renamed copy (with its map) and on the
    built-in robot gives the same trace, so theta_w and theta_l reach the renamed joints."""
    kw = dict(phase=0.3, cv=0.0, rng=2, duration_s=0.6, dt_s=1e-3, trace=True)
    a = run_trial(74.0, 30.0, robot=export(tmp_path / "plain"), **kw)
    b = run_trial(74.0, 30.0, robot=renamed, joint_map=JointMap.parse(RENAMED_MAP), **kw)
    assert np.ptp(a.trace.wing_deg) > 10 and np.ptp(a.trace.leg_deg) > 10  # the joints did move
    np.testing.assert_array_equal(a.trace.as_array(), b.trace.as_array())
    assert a.robot_hash != b.robot_hash


def test_rigid_or_partial_robots_are_refused_by_the_sim(renamed, tmp_path):
    with pytest.raises(RobotDescriptionError, match="none of the default wing/leg joints"):
        sim_model(renamed)
    partial = export(tmp_path, lambda t: rename(t, ("wing_roll_left",), prefix="x"))
    with pytest.raises(UnknownJointError, match="4 of the 5 default joints; missing: wing_roll_left"):
        sim_model(partial)
    with pytest.raises(UnknownJointError, match="4 of the 5 default joints"):
        run_trial(74.0, 30.0, phase=0.0, cv=0.0, rng=1, duration_s=0.05, robot=partial)


def test_sweep_takes_a_joint_map_into_the_trials_and_their_key(renamed):
    specs = sweep_specs(
        [74.0], [30.0], [0.0], trials=1, duration_s=0.05, dt_s=1e-3, robot=renamed, joint_map=RENAMED_MAP
    )
    robot = Robot.from_urdf(renamed, joint_map=JointMap.parse(RENAMED_MAP))
    assert [s.joints for s in specs] == [RENAMED_MAP]
    assert specs[0].robot_hash == robot.robot_hash != robot.description_hash
    row = run_spec(specs[0])
    assert row["status"] == "ok" and row["robot_hash"] == robot.robot_hash
    wings_only = "wing=j_wing_pitch_left,j_wing_pitch_right;leg=j_leg"
    other = sweep_specs(
        [74.0], [30.0], [0.0], trials=1, duration_s=0.05, dt_s=1e-3, robot=renamed, joint_map=wings_only
    )
    assert other[0].robot_hash != specs[0].robot_hash and other[0].key() != specs[0].key()
    with pytest.raises(RobotDescriptionError, match="none of the default"):
        sweep_specs([74.0], [30.0], [0.0], trials=1, duration_s=0.05, dt_s=1e-3, robot=renamed)


def test_sim_model_is_rebuilt_when_a_mesh_changes(tmp_path):
    urdf = export(tmp_path)
    before = sim_model(urdf)
    mesh = tmp_path / "pendulum_sphere.obj"
    mesh.write_text(
        "".join(
            f"v {2 * float(x):.9f} {y} {z}\n" if s.startswith("v ") else s + "\n"
            for s in mesh.read_text().splitlines()
            for _, x, y, z in [(s.split() + ["", "", "", ""])[:4]]
        )
    )
    after = sim_model(urdf)
    assert after.description_hash != before.description_hash
    assert after.model_hash != before.model_hash


def test_sim_resolves_mesh_paths_as_geometry_does(tmp_path):
    """``package://`` mesh names: geometry always read them; the sim now reads them through geometry."""
    plain = sim_model(export(tmp_path / "plain"))
    pkg = export(tmp_path / "pkg", lambda t: t.replace('filename="', 'filename="package://pkg/'))
    assert Robot.from_urdf(pkg).pose(74, 30).com_m == pytest.approx(
        Robot.from_urdf(tmp_path / "plain" / URDF_NAME).pose(74, 30).com_m, abs=0
    )
    model = sim_model(pkg)
    assert model.meshes == plain.meshes and model.vertex_counts == plain.vertex_counts


def test_builtin_copy_keeps_the_builtin_time_step(tmp_path):
    assert default_dt_s(export(tmp_path)) == DEFAULT_DT_S
