"""The hold pitch in the model's and the IMU's frame (landscape/analysis/physical/hold.py) on the lab's
recordings (skipped without ../shared)."""

import numpy as np
import pytest

from landscape.analysis.physical.hold import hold_pitch_frames, plateau_hold_deg
from landscape.analysis.physical.recording import PhysicalDataError
from tests.conftest import LAB_URDF
from tests.landscape.analysis.physical.lab import DATA, needs_data


@needs_data
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_hold_frames_on_the_recordings():
    """The recorded hold of first openings is steadier in the IMU frame than relative to each trial's rest
    (the rest carries the spread), and the offset's algebra: residuals sum to zero, and each held-out residual
    is the command's difference minus the mean of the others'."""
    from geometry.robots import load_robot
    from landscape.minima import metastable_orientation

    robot = load_robot(LAB_URDF)
    model = plateau_hold_deg(robot, DATA, (60.0, 75.0, 90.0))
    rows = hold_pitch_frames(DATA, model, metastable_orientation(robot, 0.0, 0.0)[0])
    assert [r.theta_w_cmd_deg for r in rows] == [60.0, 75.0, 90.0]
    assert all(r.n == 5 for r in rows)
    assert all(r.recorded_sd_deg < r.relative_sd_deg for r in rows)
    assert sum(r.residual_deg for r in rows) == pytest.approx(0.0, abs=1e-9)
    diff = {r.theta_w_cmd_deg: r.recorded_deg - r.model_deg for r in rows}
    for r in rows:
        others = [d for c, d in diff.items() if c != r.theta_w_cmd_deg]
        assert r.residual_held_out_deg == pytest.approx(diff[r.theta_w_cmd_deg] - np.mean(others))
    with pytest.raises(PhysicalDataError, match="leg still"):
        hold_pitch_frames(DATA, {65.0: 60.0}, 0.0)
