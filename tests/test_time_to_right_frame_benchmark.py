"""benchmarks/time_to_right_frame.py: world-up's z in a body frame pitched against the IMU's (none: the recorded
value exactly; 10 deg: a body standing at 90 deg by its IMU is 10 deg short of vertical), and the robot's time
to right at 90 deg moving later once its body is pitched below its IMU."""

import numpy as np
import pytest

from tests.conftest import load_script
from tests.landscape.analysis.test_physical import DATA, needs_data


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/time_to_right_frame.py")


def test_the_mounting_turns_world_up_about_the_body_y_axis(bench):
    rng = np.random.default_rng(0)
    q = rng.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    x, y, _, _ = q.T
    assert bench.up_z_mounted(q, 0.0) == pytest.approx(1 - 2 * (x * x + y * y))
    standing = np.array([[0.0, np.sin(np.pi / 4), 0.0, np.cos(np.pi / 4)]])  # pitched 90 deg
    assert bench.up_z_mounted(standing, 10.0)[0] == pytest.approx(np.sin(np.radians(10.0)))


@needs_data
def test_the_robots_rightings_at_90_deg_come_later_in_a_body_pitched_below_its_imu(bench, capsys):
    assert bench.main(["--data", str(DATA), "--mount", "0,11.5"]) == 0
    out = capsys.readouterr().out
    assert "| 90° | 30° | 0.33 s (5/5) | 0.66 s (5/5) |" in out
    assert "| 60° | 30° | 1.18 s (5/5) | 1.19 s (5/5) |" in out
    with pytest.raises(SystemExit) as exc:
        bench.main(["--data", str(DATA), "--mount", "90"])
    assert exc.value.code == 2
