"""benchmarks/physical/nose_over.py: at the 90 deg command every first opening of the robot throws its nose past
vertical, even with the leg still, while the set that holds where the robot holds stops short of it; at 60 deg
neither comes near; and the hold, where the set that rests like the robot holds within 1.5 deg of it."""

import pytest

from tests.conftest import LAB_URDF, load_script
from tests.landscape.analysis.physical.lab import DATA, needs_data


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/nose_over.py")


@pytest.mark.e2e  # simulated first openings of the lab robot at its small step
@needs_data
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_the_robot_passes_vertical_at_90_deg_and_the_model_does_not(bench, capsys):
    argv = ["--data", str(DATA), "--robot", str(LAB_URDF), "--cells", "60:0,90:0"]
    assert bench.main([*argv, "--models", "physical-head"]) == 0
    out = capsys.readouterr().out
    assert "body frame (the robot's IMU minus the 2.6 deg mounting its two rests measure)" in out
    peak_table, hold_table = out.split("\n\n")
    rows = {
        ln.split("|")[1].strip() + "/" + ln.split("|")[2].strip(): ln for ln in peak_table.splitlines()[3:]
    }
    holds = {ln.split("|")[1].strip(): ln for ln in hold_table.splitlines()[3:]}
    # the set holds where the robot holds (issue #15's 1.5 deg), in its simulation as on its landscape
    for w in ("60°", "90°"):
        assert abs(float(holds[w].split("|")[4].split("(")[1].split("°")[0])) < 1.5, holds[w]
    assert "| 94.5° [94.0, 95.6], 0.23 s (5/5) |" in rows["90°/0°"]  # rises slower than the set (0.18 s)
    assert "(0/5)" in rows["60°/0°"] and "(short of vertical)" in rows["60°/0°"]
    model = float(rows["90°/0°"].split("|")[4].split("°")[0])
    assert 85.0 < model < 90.0  # the set holds at 82.6 deg and its opening overshoots that by a few degrees
    # soft, lightly damped wing joints throw it past vertical (a catapult); --with without --vary is refused
    spring = [
        "--vary",
        "compliance.wing_stiffness_n_m_rad=0.5",
        "--with",
        "compliance.wing_damping_n_m_s_rad=0.001",
    ]
    assert bench.main([*argv[:-1], "90:0", "--models", "physical-head", *spring]) == 0
    row = capsys.readouterr().out.split("\n\n")[0].splitlines()[-1]
    assert "compliance" not in row and row.split("|")[5].strip().endswith("(past vertical)")
    assert bench.main([*argv, "--models", "physical-head", *spring[2:]]) == 2
    assert "give at least one --vary" in capsys.readouterr().err
    assert bench.main([*argv, "--models", "nosuchset"]) == 2
    assert bench.main([*argv[:-2], "--cells", "90:5", "--models", "paper"]) == 2
    assert "--cells 90:5 is not a recorded cell; the recorded cells are 60:0," in capsys.readouterr().err
