"""benchmarks/physical/physical_ablation.py: every table a model set may add is a cause the ablation can switch on alone,
and a variant is the base set with that one table taken from the fuller set."""

from pathlib import Path

from sim.model_set import OPTIONAL_KEYS, OPTIONAL_TABLES, load_model_set, read_toml
from tests.conftest import load_script, set_with_table


def test_every_optional_table_is_a_cause():
    bench = load_script("benchmarks/physical/physical_ablation.py")
    assert {k.split(".")[0] for k in OPTIONAL_KEYS} <= set(bench.CAUSES)
    assert set(OPTIONAL_TABLES) <= set(bench.CAUSES)


def test_a_variant_takes_one_table_from_the_fuller_set(tmp_path):
    bench = load_script("benchmarks/physical/physical_ablation.py")
    full = set_with_table(
        tmp_path, "head_compliance", "stiffness_n_m = 25.0\ntravel_mm = 17\n", base="physical"
    )
    base = Path(load_model_set("paper").source)
    path = bench.variant(base, full, ("head_compliance",), "paper+head_compliance", tmp_path / "sets")
    ms = load_model_set(path)
    assert ms.head_compliance.stiffness == 25.0 and ms.profile == "idealised"  # the rest is the base's
    assert read_toml(path)["actuation"] == read_toml(base)["actuation"]
