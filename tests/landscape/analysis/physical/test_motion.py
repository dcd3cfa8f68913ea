"""The robot's recordings as motions (landscape/analysis/physical/motion.py): body rates from differentiated
quaternions, and the gyro against them on the lab's recordings (skipped without ../shared)."""

import numpy as np
import pytest

from landscape.analysis import energy as en
from landscape.analysis.physical.motion import quaternion_rates_rad_s, recorded_motion
from tests.landscape.analysis.physical.lab import DATA as PHYSICAL
from tests.landscape.analysis.physical.lab import needs_data as needs_physical


def test_quaternion_rates_recover_a_constant_body_rate():
    """Quaternions of a body turning at a constant body-frame rate give that rate back to 1e-9."""
    from scipy.spatial.transform import Rotation

    w = np.array([0.4, -1.1, 2.0])
    t = np.linspace(0.0, 1.0, 51)
    q = (Rotation.from_euler("zyx", [0.2, -0.3, 0.1]) * Rotation.from_rotvec(t[:, None] * w)).as_quat()
    tm, rates = quaternion_rates_rad_s(t, q)
    np.testing.assert_allclose(tm, 0.5 * (t[1:] + t[:-1]))
    np.testing.assert_allclose(rates, np.broadcast_to(w, rates.shape), atol=1e-9)


@pytest.mark.shared
@needs_physical
def test_gyro_and_differentiated_quaternions_agree_on_every_recorded_first_opening():
    """Over the first second of each recording's first opening, the rotational kinetic energy integrated over
    time agrees within 15 % between the gyro and the differentiated quaternions (both median-filtered over 3
    samples), and the two series correlate at r > 0.8 in every recording and at r > 0.9 in most."""
    from geometry import Robot
    from landscape.analysis.physical.recording import read_recording, trial_files
    from sim.model_set import load_model_set
    from tests.conftest import lab_sim_robot

    ms = load_model_set("physical-head")
    body = en.body_model(Robot.from_urdf(lab_sim_robot().urdf), ms, theta_w_cmd_deg=75.0)
    inertia = body.pose(70.0, 0.0).inertia_kg_m2
    ratios, corr = [], []
    for f in trial_files(PHYSICAL):
        rec = read_recording(f)
        act = ms.actuation(rec.theta_w_cmd_deg, rec.theta_l_deg)
        gyro = recorded_motion(rec, mount_deg=2.6, actuation=act)
        quat = recorded_motion(rec, mount_deg=2.6, actuation=act, use_gyro=False)
        sel = (gyro.t_s >= 0.0) & (gyro.t_s < 1.0)
        kg = en.rotational_shares_j(gyro.omega_body_rad_s[sel], inertia).sum(axis=1)
        kq = en.rotational_shares_j(quat.omega_body_rad_s[sel], inertia).sum(axis=1)
        ratios.append(np.trapezoid(kg, gyro.t_s[sel]) / np.trapezoid(kq, gyro.t_s[sel]))
        corr.append(np.corrcoef(kg, kq)[0, 1])
    assert len(ratios) == 60
    assert 0.85 <= min(ratios) and max(ratios) <= 1.15
    assert min(corr) > 0.8 and np.median(corr) > 0.9
