"""`landscape analyze compare`: two databases of the same settings in two engines, setting by setting."""

import json

import pytest

pytest.importorskip("pybullet")
pytest.importorskip("mujoco")

from sim.sweep import run_sweep, sweep_specs  # noqa: E402
from tests.conftest import csv_rows  # noqa: E402
from tests.conftest import run_cli as run  # noqa: E402

SETTINGS = dict(phase=(0.25, 0.7), duration_s=2.5, dt_s=1e-3)


@pytest.fixture(scope="module")
def dbs(tmp_path_factory):
    """The same multi-attempt trials (two settings x 3) and single attempts (two phases) in each engine."""
    d = tmp_path_factory.mktemp("compare")
    out = []
    for engine in ("pybullet", "mujoco"):
        db = d / f"{engine}.sqlite"
        specs = sweep_specs((74.0,), (30.0, 50.0), (0.1,), trials=3, engine=engine, **SETTINGS)
        specs += sweep_specs((74.0,), (30.0,), (0.0,), trials=1, attempts=1, engine=engine, **SETTINGS)
        run_sweep(specs, db=db, workers=1, progress=False)
        out.append(db)
    return out


@pytest.mark.e2e  # two small sweeps, one per engine (the module fixture)
def test_compare_tests_each_setting_and_names_both_engines(dbs, tmp_path, capsys):
    args = ("analyze", "compare", "--db", dbs[0], "--db", dbs[1], "--min-trials", "3")
    code, stdout, err = run(capsys, *args, "--out", tmp_path)
    assert code == 0, err
    assert "A: " in stdout and "pybullet, paper (" in stdout and "mujoco, paper (" in stdout
    assert (
        "multi-attempt settings in both with at least 3 trials each: 4;" in stdout
    )  # theta_l 30/50 x 0.25/0.7
    assert "fewer trials" not in stdout
    assert "noise-free single attempts in both: 2;" in stdout
    rows = csv_rows(tmp_path / "compare.csv")
    assert (
        len(rows) == 4 and {r["trials_a"] for r in rows} == {"3"} and {r["trials_b"] for r in rows} == {"3"}
    )
    for r in rows:
        assert 0.0 < float(r["fisher_p"]) <= 1.0
    code, stdout, err = run(capsys, *args, "--json")
    doc = json.loads(stdout)
    assert (
        doc["settings"] == 4
        and doc["settings_with_fewer_trials"] == 0
        and 0 <= doc["consistent"] <= 4
        and doc["single_attempts"]["n"] == 2
    )
    assert doc["consistent"] == sum(c["fisher_p"] >= 0.05 for c in doc["cells"])


@pytest.mark.e2e  # two small sweeps, one per engine (the module fixture)
def test_settings_with_too_few_trials_are_counted_not_tested(dbs, tmp_path, capsys):
    """By default a setting needs 20 trials in each database: the fixture's 3 are too few, and it says so."""
    code, stdout, err = run(capsys, "analyze", "compare", "--db", dbs[0], "--db", dbs[1], "--out", tmp_path)
    assert code == 0, err
    assert "Fisher" not in stdout
    assert "multi-attempt settings with fewer trials in either (not tested; --min-trials): 4" in stdout
    assert "noise-free single attempts in both: 2;" in stdout and not csv_rows(tmp_path / "compare.csv")
    code, _, err = run(capsys, "analyze", "compare", "--db", dbs[0], "--db", dbs[1], "--min-trials", "0")
    assert code == 2 and "--min-trials" in err and err.count("\n") == 1


@pytest.mark.e2e  # two small sweeps, one per engine (the module fixture)
def test_compare_against_itself_is_consistent_everywhere(dbs, tmp_path, capsys):
    code, stdout, err = run(
        capsys, "analyze", "compare", "--db", dbs[1], "--db", dbs[1], "--min-trials", "3", "--out", tmp_path
    )
    assert code == 0, err
    assert "in 4 (100.0 %)" in stdout and "the same outcome in 2 " in stdout


@pytest.mark.e2e  # two small sweeps, one per engine (the module fixture)
def test_compare_bad_input_is_one_line(dbs, tmp_path, capsys):
    code, _, err = run(capsys, "analyze", "compare", "--db", dbs[0])
    assert code == 2 and "compare takes two databases" in err and err.count("\n") == 1
    code, _, err = run(capsys, "analyze", "compare", "--db", dbs[0], "--db", tmp_path / "none.sqlite")
    assert code == 2 and "not found" in err and err.count("\n") == 1
    other = tmp_path / "other.sqlite"
    run_sweep(
        sweep_specs((70.0,), (20.0,), (0.0,), trials=1, duration_s=1.0, dt_s=1e-3), db=other, progress=False
    )
    code, _, err = run(capsys, "analyze", "compare", "--db", dbs[0], "--db", other)
    assert code == 2 and "share no setting" in err and err.count("\n") == 1


def test_the_command_line_default_is_the_librarys():
    """--min-trials defaults to landscape.analysis.compare.MIN_TRIALS, so the command and the Python API test the
    same settings."""
    import click

    from landscape.analysis.compare import MIN_TRIALS
    from landscape.cli.analyze import compare_cmd

    (opt,) = [p for p in compare_cmd.params if isinstance(p, click.Option) and p.name == "min_trials"]
    assert opt.default == MIN_TRIALS
