"""benchmarks/physical/opening_transient.py: the first wing opening, robot against model sets, measured by the same
code."""

import pytest

from tests.conftest import LAB_URDF, load_script
from tests.landscape.analysis.physical.lab import DATA, needs_data


@needs_data
@pytest.mark.skipif(not LAB_URDF.is_file(), reason="../shared/ref/lab_robot is absent")
def test_prints_the_closing_table(capsys):
    """benchmarks/physical/opening_transient.py, one cell and one simulated opening: the third table puts the robot's tilt
    at closing, its gyro check and the rigid saddle beside the set's; a bad cell is one line and exit 2."""
    mod = load_script("benchmarks/physical/opening_transient.py")
    argv = ["--data", str(DATA), "--robot", str(LAB_URDF), "--models", "physical", "--trials", "1"]
    assert mod.main([*argv, "--phase", "0.17", "--cells", "60:30"]) == 0
    out = capsys.readouterr().out
    assert "| wing cmd | leg | saddle | robot (n) | gyro | physical |" in out
    assert "| 60° | 30° | 29.0° | +20.9° (20.9°); 4/5 at 1.13 s (5) | 2.7° (3.7°) | " in out
    with pytest.raises(SystemExit) as exc:
        mod.main([*argv, "--cells", "61:30"])
    assert exc.value.code == 2


def test_the_closing_column_counts_openings_without_a_sample_instead_of_printing_nan():
    """A simulated trial stops once the body has righted; an opening that righted before the closing window has
    no tilt there, and the column says how many, not "+nan°"."""
    from dataclasses import replace

    from landscape.analysis.physical.response import OpeningResponse

    mod = load_script("benchmarks/physical/opening_transient.py")
    r = OpeningResponse(0.0, 60.0, 0.0, 0.1, 0.0)
    assert mod.closing([replace(r, closing_tilt_deg=-3.0, rolled_s=1.1), r]) == (
        "-3.0° (3.0°); 1/2 at 1.10 s (1 without a sample)"
    )
    assert mod.closing([r]) == "–; 0/1 (1 without a sample)"
    assert mod.closing([replace(r, closing_tilt_deg=2.0)]) == "+2.0° (2.0°); 0/1"
