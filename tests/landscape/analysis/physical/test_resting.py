"""The resting pitch (landscape/analysis/physical/resting.py) on the lab's recordings, beside the lab URDF's
(skipped without ../shared)."""

from landscape.analysis.physical.resting import resting_pitch_table
from tests.landscape.analysis.physical.lab import DATA, needs_data


@needs_data
def test_resting_pitch_reproduces_the_published_table():
    rows = resting_pitch_table(DATA)
    got = [
        (r.theta_w_cmd_deg, round(r.median_deg, 1), round(r.q25_deg, 1), round(r.q75_deg, 1), r.n)
        for r in rows
    ]
    # the table read 85.3 [82.9, 85.7] at 90 deg from the ZYX pitch, which folds back where the robot's
    # nose passes vertical; the nose's pitch (sagittal_pitch_deg) reads 86.7
    assert got == [(60.0, 67.9, 66.9, 69.2, 33), (75.0, 82.8, 80.3, 85.4, 23), (90.0, 86.7, 85.9, 87.9, 16)]
    # the body does not come back to its pre-opening rest when the wings close: the reference is path-dependent
    hist = [(round(r.first_opening_median_deg, 1), round(r.closed_median_deg, 1)) for r in rows]
    assert hist == [(68.2, -10.7), (80.2, -11.0), (86.2, -4.4)]


@needs_data
def test_model_pitch_on_the_lab_urdf(lab_robot):
    """Issue #15's model column: the metastable pitch with every wing joint at the measured plateau, minus the
    rest at theta_w = 0 (as `landscape physical kinematics` and the report compute it)."""
    from landscape.analysis.physical.hold import plateau_hold_deg
    from landscape.minima import metastable_orientation

    rest = metastable_orientation(lab_robot, 0.0, 0.0)[0]
    hold = plateau_hold_deg(lab_robot, DATA, (60.0, 75.0, 90.0))
    assert [round(hold[c] - rest, 1) for c in (60.0, 75.0, 90.0)] == [65.2, 75.7, 81.4]
