"""figures/energy_budget.py: the docs' energy-against-time figure, and the attempts it describes."""

import pytest

from tests.conftest import load_script

pytest.importorskip("pybullet")


@pytest.mark.slow
def test_the_figure_draws_the_simulated_trial_that_rights_in_its_third_attempt(tmp_path, capsys):
    fig = load_script("figures/energy_budget.py")
    assert fig.main(["--out", str(tmp_path / "e.png")]) == 0
    out = capsys.readouterr().out
    sim = [line.split() for line in out.splitlines() if line.startswith("simulated ")]
    assert [(r[1], r[2]) for r in sim] == [("1", "0"), ("2", "0"), ("3", "1")]
    assert float(sim[-1][-1]) > 0  # the righting attempt has a positive margin: necessary, not sufficient
    assert (tmp_path / "e.png").stat().st_size > 10_000 and (tmp_path / "e.svg").is_file()
