"""landscape/computation.py: the shared continuation of a barrier map against its per-pair definition."""

import pytest

from geometry import Robot
from landscape.computation import sweep_starts
from landscape.minima import metastable_orientation


def test_sweep_starts_agree_with_metastable_orientation_per_pair(each_robot):
    """One shared continuation (theta_w rising through every requested value, a theta_l branch at each) ends
    where the slow opening of :func:`metastable_orientation` ends, pair by pair, negative theta_w included."""
    robot = Robot.from_urdf(each_robot.urdf)
    theta_w_deg, theta_l_deg = [-5.0, 0.0, 60.0, 90.0], [-60.0, 0.0, 60.0]
    starts = sweep_starts(robot, theta_w_deg, theta_l_deg)
    assert sorted(starts) == sorted((w, tl) for w in theta_w_deg for tl in theta_l_deg)
    for (w, tl), (pitch_deg, roll_deg) in starts.items():
        assert (pitch_deg, roll_deg) == pytest.approx(metastable_orientation(robot, w, tl), abs=1e-9), (w, tl)
    # the grid is one where both joints move the minimum, so a branch taken from the wrong state shows
    assert starts[(90.0, 0.0)][0] - starts[(-5.0, 0.0)][0] > 45.0
    assert len({starts[(0.0, tl)] for tl in theta_l_deg}) > 1
