"""``landscape models``: the shipped model sets (and files) as a table or JSON, the same list the service's
``GET /api/model-sets`` answers; a bad name is one line and exit status 2."""

import json
from pathlib import Path

from sim.model_set import load_model_set, shipped_model_sets
from tests.conftest import run_cli as run


def test_the_table_names_every_shipped_set_with_its_hash_and_elements(capsys):
    code, out, err = run(capsys, "models")
    assert code == 0 and not err
    rows = [line for line in out.splitlines() if line.startswith("| ") and not line.startswith("| set ")]
    assert [r.split(" | ")[0][2:] for r in rows] == shipped_model_sets()
    for row, name in zip(rows, shipped_model_sets(), strict=True):
        ms = load_model_set(name)
        cells = row.split(" | ")
        assert cells[1:4] == [str(ms.version), ms.model_set_hash, ms.profile]
    offset = next(r for r in rows if r.startswith("| physical-offset "))
    assert "| compliance, mass |" in offset
    assert "| – |" in next(r for r in rows if r.startswith("| paper "))


def test_json_is_the_services_list_and_takes_files(capsys, tmp_path):
    from landscape.service.model_sets import model_set_list

    code, out, _ = run(capsys, "models", "--json")
    assert code == 0 and json.loads(out) == model_set_list()
    f = tmp_path / "mine.toml"
    text = Path(load_model_set("paper").source).read_text().replace('name = "paper"', 'name = "mine"')
    f.write_text(text + "\n[compliance]\nwing_stiffness_n_m_rad = 0.9\nwing_scale = [1, 0.6, 1, 0.6]\n")
    code, out, _ = run(capsys, "models", str(f), "physical", "--json")
    got = json.loads(out)
    assert [s["name"] for s in got] == ["mine", "physical"]
    assert got[0]["model_set_hash"] == load_model_set(f).model_set_hash and got[0]["elements"] == [
        "compliance"
    ]


def test_an_unknown_set_is_one_line_and_status_2(capsys, tmp_path):
    code, out, err = run(capsys, "models", "nope")
    assert code == 2 and not out
    assert err.count("\n") == 1 and "unknown model set 'nope'" in err
    code, _, err = run(capsys, "models", str(tmp_path / "missing.toml"))
    assert code == 2 and "not found" in err and err.count("\n") == 1
