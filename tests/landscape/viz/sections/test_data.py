"""What every section reads (landscape/viz/sections/data.py): the model set's wing poses for the barriers."""

from landscape.viz.sections.data import trials_wing_joints


def test_barriers_pose_the_wings_as_the_trials_model_set_did():
    """A shipped measured set that still hashes as stored poses each servo at its plateau; an idealised set, a
    set not shipped, a changed set or mixed sets pose every joint at theta_w, and the sentence says which."""
    from geometry.robots import load_robot
    from sim.model_set import load_model_set

    robot = load_robot(None)
    phys = load_model_set("physical")
    rows = [{"model_set": "physical", "model_set_hash": phys.model_set_hash}]
    posed, joints, text = trials_wing_joints(rows, robot, {60.0, 75.0})
    assert posed is robot  # physical moves no mass
    assert joints[75.0] == phys.wing_joints_deg(robot.joint_map.wing, 75.0) and set(joints) == {60.0, 75.0}
    assert "measured plateau (model set physical)" in text
    for rows, why in (
        ([{"model_set": "paper", "model_set_hash": "x"}], "idealised"),
        ([{"model_set": "mine", "model_set_hash": "x"}], "not a shipped set"),
        ([{"model_set": "physical", "model_set_hash": "old"}], "changed since the trials ran"),
        ([{"model_set": "physical", "model_set_hash": phys.model_set_hash}, {"model_set": "paper"}], "mix"),
    ):
        posed, joints, text = trials_wing_joints(rows, robot, {75.0})
        assert posed is robot
        assert joints is None and why in text, (rows, text)
