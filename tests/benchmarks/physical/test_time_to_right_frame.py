"""benchmarks/physical/time_to_right_frame.py: world-up's z in a body frame pitched against the IMU's (none: the recorded
value exactly; 10 deg: a body standing at 90 deg by its IMU is 10 deg short of vertical), and the robot's time
to right at 90 deg moving later once its body is pitched below its IMU."""

import numpy as np
import pytest

from landscape.analysis.physical.recording import up_z_mounted
from tests.conftest import load_script
from tests.landscape.analysis.physical.lab import DATA, needs_data


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/time_to_right_frame.py")


def test_the_mounting_turns_world_up_about_the_body_y_axis():
    rng = np.random.default_rng(0)
    q = rng.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    x, y, _, _ = q.T
    assert up_z_mounted(q, 0.0) == pytest.approx(1 - 2 * (x * x + y * y))
    standing = np.array([[0.0, np.sin(np.pi / 4), 0.0, np.cos(np.pi / 4)]])  # pitched 90 deg
    assert up_z_mounted(standing, 10.0)[0] == pytest.approx(np.sin(np.radians(10.0)))


@needs_data
def test_the_robots_rightings_at_90_deg_come_later_in_a_body_pitched_below_its_imu(bench, capsys):
    assert bench.main(["--data", str(DATA), "--mount", "0,11.5"]) == 0
    out = capsys.readouterr().out
    assert "| 90° | 30° | 0.33 s (5/5) | 0.66 s (5/5) |" in out
    assert "| 60° | 30° | 1.18 s (5/5) | 1.19 s (5/5) |" in out
    with pytest.raises(SystemExit) as exc:
        bench.main(["--data", str(DATA), "--mount", "90"])
    assert exc.value.code == 2


@needs_data
def test_physical_trials_judge_uprightness_in_the_mounted_frame():
    from landscape.analysis.physical.outcome import physical_trials
    from landscape.analysis.physical.recording import PhysicalDataError

    imu, body = physical_trials(DATA), physical_trials(DATA, imu_mount_deg=11.5)
    assert [t.name for t in imu] == [t.name for t in body]
    at = {t.name: (a.time_to_right_s, t.time_to_right_s) for a, t in zip(imu, body, strict=True)
          if t.theta_w_cmd_deg == 90.0 and t.theta_l_deg == 30.0}  # fmt: skip
    assert len(at) == 5 and all(b > a + 0.2 for a, b in at.values())  # 0.32-0.34 s -> 0.63-0.90 s
    assert [t.success for t in imu] == [t.success for t in body]
    for bad in (float("nan"), 50.0):
        with pytest.raises(PhysicalDataError, match="IMU's mounting must lie within"):
            physical_trials(DATA, imu_mount_deg=bad)
