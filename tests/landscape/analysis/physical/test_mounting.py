"""The IMU's mounting from the two rests (landscape/analysis/physical/mounting.py): the algebra on a pitched
IMU, and the lab's recordings (skipped without ../shared)."""

import pytest

from landscape.analysis.physical.mounting import mounting_from_rests, nose_pitch_deg, rest_mounting_deg
from tests.conftest import LAB_URDF
from tests.landscape.analysis.physical.lab import DATA, needs_data


def test_the_mounting_algebra_recovers_a_pitched_imu():
    """An IMU pitched d about the body's y axis reads the body's pitch + d on its back and - d upright (rolled
    half a turn), so half the difference of the two rests' differences, recorded minus model, is d."""
    from scipy.spatial.transform import Rotation

    from landscape.analysis.physical.recording import pitch_roll_from_quat_deg

    imu = Rotation.from_euler("y", 7.0, degrees=True)
    back = Rotation.from_euler("ZYX", [20.0, -6.0, 0.0], degrees=True)  # body pitch -6 on its back
    upright = Rotation.from_euler("ZYX", [-40.0, 1.5, 180.0], degrees=True)  # body pitch 1.5 upright
    rec = [pitch_roll_from_quat_deg([(r * imu).as_quat()])[0][0] for r in (back, upright)]
    assert rec[0] == pytest.approx(1.0) and rec[1] == pytest.approx(-5.5)
    assert rest_mounting_deg(rec[0], rec[1], -6.0, 1.5) == pytest.approx(7.0)
    assert nose_pitch_deg(-174.0, -180.0) == pytest.approx(-6.0)


@needs_data
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_the_two_rests_measure_a_small_mounting():
    """37 righted trials give both rests; their mounting (median 2.6 deg) is far from the 11.5 deg the open hold
    would need, and the head, which neither closed rest touches, does not move it."""
    from geometry.robots import load_robot

    robot = load_robot(LAB_URDF)
    m = mounting_from_rests(DATA, robot)
    assert m.n == 37 and 1.5 < m.mount_q25_deg < m.mount_deg < m.mount_q75_deg < 4.5
    assert m.model_back_deg == pytest.approx(-6.34, abs=0.05) and abs(m.model_upright_deg) < 1.0
    moved = mounting_from_rests(DATA, robot.with_joint_shift("head_mount", [-0.017, 0.0, 0.0]))
    assert moved.mount_deg == pytest.approx(m.mount_deg, abs=0.1)
