"""benchmarks/physical/leg_reaction.py: the free body's turn against its swinging leg conserves angular momentum, so it
is zero without a swing, grows in proportion to the swing (small angles) and turns against the leg (+ for a
swing from +A to -A); a robot without the lab's joints is refused in one line."""

import pytest

from tests.conftest import LAB_URDF, load_script, needs_lab


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/leg_reaction.py")


WINGS = dict.fromkeys(("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right"), 80.0)


@needs_lab
def test_the_free_turn_is_zero_without_a_swing_and_grows_with_it(bench):
    assert bench.free_turn_deg(str(LAB_URDF), WINGS, 0.0) == pytest.approx(0.0, abs=1e-6)
    small, double = (bench.free_turn_deg(str(LAB_URDF), WINGS, a) for a in (10.0, 20.0))
    assert small > 0  # against the leg: the leg turns by -2A about body z
    assert double == pytest.approx(2 * small, rel=0.03)
    # about a third of the swing: the leg's share of the moment of inertia about its axis
    assert 0.2 < small / 20.0 < 0.6


@needs_lab
def test_a_robot_without_the_lab_joints_is_one_line(bench, tmp_path):
    import shutil

    for f in LAB_URDF.parent.iterdir():
        shutil.copy(f, tmp_path / f.name)
    urdf = tmp_path / LAB_URDF.name
    urdf.write_text(urdf.read_text().replace('<joint name="leg"', '<joint name="tail_joint"'))
    with pytest.raises(bench.UsageError, match="has no joint 'leg'"):
        bench.free_turn_deg(str(urdf), WINGS, 10.0)
