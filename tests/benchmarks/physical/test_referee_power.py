"""benchmarks/physical/referee_power.py against hand counts: the Wilson rule's agreeing simulated counts, the plug-in
and beta-binomial probabilities, and the count distribution's convolution."""

import pytest
from scipy.stats import binom

from tests.conftest import load_script


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/physical/referee_power.py")


def test_a_robot_cell_of_5_of_5_agrees_only_with_a_simulation_that_always_rights(bench):
    assert bench.agreeing_counts(5, 5, 10).tolist() == [10]
    assert bench.agreeing_counts(0, 5, 20).tolist() == [0]
    assert bench.agreeing_counts(4, 5, 10).tolist() == [6, 7, 8, 9]  # 80 % inside [31, 83] % from 6 of 10 on


def test_the_probabilities(bench):
    assert bench.p_agree_plugin(5, 5, 10) == pytest.approx(1.0)
    assert bench.p_agree_plugin(4, 5, 10) == pytest.approx(binom.pmf([6, 7, 8, 9], 10, 0.8).sum())
    # uniform prior on a 5-of-5 cell: E[p^10] under Beta(6, 1) = 6 / 16
    assert bench.p_agree_perfect(5, 5, 10) == pytest.approx(6 / 16)
    assert bench.p_agree_best(4, 5, 10) >= bench.p_agree_plugin(4, 5, 10)
    d = bench.count_distribution([0.5, 0.5, 1.0])
    assert d.tolist() == pytest.approx([0.0, 0.25, 0.5, 0.25])


def test_fishers_test_passes_a_perfect_model_in_at_least_95_percent_of_cells_whatever_the_robot_did(bench):
    for k in range(6):
        for n_sim in (10, 20):
            assert bench.p_consistent_perfect(k, 5, n_sim) >= 0.95
    assert bench.agreeing_counts(5, 5, 10, "fisher").tolist()[-1] == 10  # 10 of 10 is consistent with 5 of 5
    assert len(bench.agreeing_counts(5, 5, 10, "fisher")) > len(bench.agreeing_counts(5, 5, 10))
