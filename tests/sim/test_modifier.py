"""The "Adding a modifier" example of docs/concepts/model_sets.md works as the page says: run as written, its
table is read, hashed and simulated."""

import re
from pathlib import Path

import pytest

from sim import modifier
from sim.model import sim_model
from sim.model_set import ModelSetError, load_model_set
from sim.world import World
from tests.conftest import set_with_table

DOC = Path(__file__).resolve().parents[2] / "docs" / "concepts" / "model_sets.md"


@pytest.fixture
def ballast(monkeypatch):
    """The page's ``Ballast`` class, registered for this test only."""
    monkeypatch.setattr(modifier, "_REGISTRY", dict(modifier._REGISTRY))
    text = DOC.read_text().split("## Adding a modifier", 1)[1]
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    namespace: dict = {"__name__": "model_sets_doc"}
    exec(compile(code, str(DOC), "exec"), namespace)
    return namespace["Ballast"]


def test_the_page_example_is_read_hashed_and_simulated(ballast, tmp_path):
    assert "ballast" in modifier.registered()
    ms = load_model_set(set_with_table(tmp_path, "ballast", "mass_kg = 0.005\n"))
    paper = load_model_set("paper")
    assert ms.modifiers == (ballast(0.005),) and ms.summary()["elements"] == ["ballast"]
    assert ms.model_set_hash != paper.model_set_hash
    with World(sim_model(), dt_s=5e-4) as w0, World(sim_model(modifiers=ms.modifiers), dt_s=5e-4) as w1:
        assert w1.mass_kg - w0.mass_kg == pytest.approx(0.005, abs=1e-12)


def test_the_page_example_refuses_a_bad_value_in_one_line(ballast, tmp_path):
    with pytest.raises(ModelSetError, match=r"\[ballast\]: mass_kg must be in \(0, 0.1\] kg; got 0.5$"):
        load_model_set(set_with_table(tmp_path, "ballast", "mass_kg = 0.5\n"))
    with pytest.raises(ModelSetError, match=r"\[ballast\]: unknown key 'grams'"):
        load_model_set(set_with_table(tmp_path, "ballast", "grams = 5\n"))


def test_without_the_module_the_table_is_refused(tmp_path):
    with pytest.raises(ModelSetError, match="unknown key 'ballast'"):
        load_model_set(set_with_table(tmp_path, "ballast", "mass_kg = 0.005\n"))


def test_the_shipped_modifiers_are_registered_in_reading_order():
    from sim.model_set import OPTIONAL_TABLES

    tables = list(modifier.registered())
    assert (
        tables
        == list(OPTIONAL_TABLES)
        == [
            "compliance",
            "body_torsion",
            "leg_compliance",
            "leg_bend",
            "head_compliance",
            "mass",
            "geometry",
        ]
    )
    assert [t for t, cls in modifier.registered().items() if cls.EDITS_URDF] == [
        "body_torsion",
        "leg_bend",
        "head_compliance",
        "mass",
        "geometry",
    ]


def test_with_modifier_replaces_the_one_of_its_table_in_registry_order():
    from sim.compliance import BodyTorsion, Compliance
    from sim.mass import ComOffset

    mods = (BodyTorsion(0.05), ComOffset(1.0))
    assert modifier.with_modifier(mods, Compliance(2.0)) == (Compliance(2.0), *mods)
    assert modifier.with_modifier(mods, ComOffset(-1.0)) == (BodyTorsion(0.05), ComOffset(-1.0))


def test_a_table_has_one_modifier(monkeypatch):
    from dataclasses import dataclass

    monkeypatch.setattr(modifier, "_REGISTRY", dict(modifier._REGISTRY))

    @dataclass(frozen=True)
    class Other(modifier.Modifier):
        TABLE = "mass"

    with pytest.raises(ValueError, match=r"the table \[mass\] is already ComOffset's"):
        modifier.register(Other)


def test_a_model_keeps_every_modifier_and_the_world_attaches_them():
    from sim.compliance import Compliance, LegBend

    wings, bend = Compliance(1.0), LegBend(0.135)
    plain, soft, bent = sim_model(), sim_model(modifiers=(wings,)), sim_model(modifiers=(wings, bend))
    assert soft.modifiers == (wings,) and soft.model_hash == plain.model_hash  # the wings leave the URDF
    assert bent.model_hash != plain.model_hash
    with World(bent, dt_s=5e-4) as w:
        assert w.modifiers == (wings, bend)
        assert wings.inertia_kg_m2(w) > 0 and bend.inertia_kg_m2(w) > 0
    with pytest.raises(
        ValueError, match=r"URDF \(none\) must be those the model was built with \(leg_bend\)"
    ):
        World(bent, dt_s=5e-4, modifiers=(wings,))
