"""benchmarks/gradient_cost.py measures what it says: both variants of compute at every pose, the Monte-Carlo cost
per sample, and a table with the ratio and whether it meets the target."""

from __future__ import annotations

from tests.conftest import load_script


def test_gradient_cost_measures_and_tabulates(monkeypatch):
    mod = load_script("benchmarks/gradient_cost.py")
    monkeypatch.setattr(mod, "POSES", ((74.0, 30.0),))
    new = mod.measure(None, repeat=1, samples=2)
    (row,) = new.values()
    assert set(row) == {"compute", "without", "per_sample"} and all(v > 0 for v in row.values())
    old = {pose: {"compute": t["without"]} for pose, t in new.items()}
    text = mod.table(new, old, "aad7130", 2)
    assert "builtin θw 74 θl 30" in text and "target <= 1.10" in text and "MC/sample" in text
    assert ("yes" in text) == (row["compute"] / row["without"] <= mod.TARGET_RATIO)
