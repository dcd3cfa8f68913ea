"""benchmarks/physical/open_wing_minima.py: with its wings held open at 90 deg, physical-head leaves a 1.9 mJ hold only to
come to rest propped on its head, one wing and the leg's sphere, 9.6 mJ below the next saddle; at 60 deg the
states past the hold are flat."""

import pytest

from tests.conftest import LAB_URDF, load_script


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/open_wing_minima.py")


@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_the_leg_sphere_props_the_body_past_the_hold_at_90_not_at_60(bench, capsys):
    assert bench.main(["--robot", str(LAB_URDF), "--commands", "60,90", "--legs", "0"]) == 0
    out = capsys.readouterr().out
    assert (
        "| 90° | +0° | 251.3, +0.13, head+wing1+wing2; 1.9 mJ | 157.9, +0.27, -44°, head+wing2+pendulum; 9.6 mJ |"
        in out
    )
    assert (
        "| 60° | +0° | 215.5, +0.41, head+wing1+wing2; 28.4 mJ | 174.3, +0.01, +70°, head+wing1; 0.0 mJ |"
        in out
    )
    assert bench.main(["--robot", str(LAB_URDF), "--model", "paper"]) == 2
    assert "give a measured set" in capsys.readouterr().err
    assert bench.main(["--robot", str(LAB_URDF), "--legs", "x"]) == 2
