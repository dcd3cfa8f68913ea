"""benchmarks/physical/hold_lean.py: the held body's lean with the leg on each side and when the roll-overs leave
the hold, robot against model sets."""

import pytest

from tests.conftest import LAB_URDF, load_script
from tests.landscape.analysis.physical.lab import DATA, needs_data


@pytest.mark.shared
@needs_data
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_prints_both_tables(capsys):
    """benchmarks/physical/hold_lean.py, one cell and one one-opening trial: the robot's leans and departures beside the
    set's; a bad cell is one line and exit 2."""
    mod = load_script("benchmarks/physical/hold_lean.py")
    argv = ["--data", str(DATA), "--robot", str(LAB_URDF), "--models", "physical", "--attempts", "1"]
    assert mod.main([*argv, "--cells", "60:30"]) == 0
    out = capsys.readouterr().out
    assert "| wing cmd | leg | robot + | robot − | physical + | physical − |" in out
    assert "| 60° | 30° | +7.8° (3) | -1.0° (7) | " in out
    assert "| 60° | 30° | 0.81 s (6/8) | (0/1) |" in out
    with pytest.raises(SystemExit) as exc:
        mod.main([*argv, "--cells", "60:0"])
    assert exc.value.code == 2
