"""Model parameter sets (sim/model_set.py): the paper set is today's behaviour exactly, sets are validated and
hashed, and a store keeps one set."""

import sqlite3
from pathlib import Path

import numpy as np
import pytest

from sim import store as st
from sim.actuation import Actuation
from sim.model_set import ModelSetError, load_model_set, shipped_model_sets
from sim.store import StoreError, TrialStore
from sim.trial import run_trial
from sim.world import Contact

PAPER_TEXT = (Path(st.__file__).parent / "models" / "paper.toml").read_text()


def test_the_paper_set_holds_the_defaults_of_before():
    ms = load_model_set()
    assert ms.name == "paper" and shipped_model_sets() == [
        "paper",
        "physical",
        "physical-head",
        "physical-offset",
        "physical-posed",
    ]
    assert ms.actuation(74.0, 30.0) == Actuation(74.0, 30.0)
    assert ms.contact == Contact()


def test_default_trials_are_unchanged():
    kw = dict(phase=0.7, cv=0.1, rng=3, duration_s=1.5, trace=True)
    before = run_trial(74.0, 30.0, actuation=Actuation(74.0, 30.0), contact=Contact(), **kw)
    now = run_trial(74.0, 30.0, **kw)
    assert now.model_set == "paper" and now.model_set_hash == load_model_set("paper").model_set_hash
    np.testing.assert_array_equal(now.trace.as_array(), before.trace.as_array())
    phys = run_trial(74.0, 30.0, model_set=load_model_set("physical"), **kw)
    assert phys.model_set == "physical"
    assert not np.array_equal(phys.trace.wing_cmd_deg, now.trace.wing_cmd_deg)  # 270 deg/s, not 300


def test_the_hash_follows_the_values_not_the_comments(tmp_path):
    text = PAPER_TEXT
    (tmp_path / "a.toml").write_text("# another comment\n" + text)
    (tmp_path / "b.toml").write_text(text.replace("wing_open_deg_s = 300.0", "wing_open_deg_s = 301.0"))
    paper = load_model_set("paper")
    assert load_model_set(tmp_path / "a.toml").model_set_hash == paper.model_set_hash
    assert load_model_set(tmp_path / "b.toml").model_set_hash != paper.model_set_hash


def test_friction_axes_body_is_the_default_and_world_changes_the_hash(tmp_path):
    (tmp_path / "w.toml").write_text(
        PAPER_TEXT.replace("solver_iterations = 20", 'solver_iterations = 20\nfriction_axes = "world"')
    )
    (tmp_path / "b.toml").write_text(
        PAPER_TEXT.replace("solver_iterations = 20", 'solver_iterations = 20\nfriction_axes = "body"')
    )
    paper = load_model_set("paper")
    assert paper.contact.friction_axes == "body" == Contact().friction_axes
    assert load_model_set(tmp_path / "b.toml").model_set_hash == paper.model_set_hash
    world = load_model_set(tmp_path / "w.toml")
    assert world.contact.friction_axes == "world" and world.model_set_hash != paper.model_set_hash


@pytest.mark.parametrize(
    "edit,match",
    [
        (
            ("wing_open_deg_s = 300.0", "wing_open_deg_s = 300.0\nwing_open_speed = 2"),
            "unknown key 'wing_open_speed'",
        ),
        (("leg_cross_s = 0.15\n", ""), "missing key 'leg_cross_s'"),
        (("wing_close_deg_s = 250.0", "wing_close_deg_s = -1.0"), "wing_close_deg_s must be > 0"),
        (("restitution = 0.1", "restitution = 1.5"), "restitution must be in"),
        (("damping_n_s_m = 100.0\n", ""), "give both stiffness_n_m and damping_n_s_m"),
        (('profile = "idealised"', 'profile = "tabulated"'), "profile must be one of"),
        (('profile = "idealised"', 'profile = "measured"'), "unknown key 'leg_cross_s'"),
        (
            ("solver_iterations = 20", "solver_iterations = 20\nrolling_friction = -0.1"),
            "rolling_friction must be",
        ),
        (
            ("solver_iterations = 20", 'solver_iterations = 20\nfriction_axes = "ground"'),
            "friction_axes must be one of world, body",
        ),
        (("[contact]", "[contact"), "not valid TOML"),
    ],
)
def test_a_bad_set_is_refused_in_one_line(tmp_path, edit, match):
    f = tmp_path / "bad.toml"
    f.write_text(PAPER_TEXT.replace(*edit))
    with pytest.raises(ModelSetError, match=match):
        load_model_set(f)


def test_an_unknown_name_says_what_exists():
    with pytest.raises(
        ModelSetError,
        match="unknown model set 'papr'.*paper, physical, physical-head, physical-offset, physical-posed",
    ):
        load_model_set("papr")
    with pytest.raises(ModelSetError, match="not found"):
        load_model_set("nothere.toml")


def test_a_sweep_stores_its_set_and_a_resumed_sweep_refuses_another(tmp_path):
    from sim.sweep import run_sweep, sweep_specs

    db = tmp_path / "t.sqlite"
    specs = sweep_specs([74.0], [30.0], [0.0], trials=1, duration_s=0.3)
    run_sweep(specs, db=db, workers=1, progress=False)
    (row,) = st.read_rows(db)
    assert (row["model_set"], row["model_set_hash"]) == ("paper", load_model_set("paper").model_set_hash)
    other = sweep_specs([74.0], [30.0], [0.0], trials=1, duration_s=0.3, model_set="physical")
    with pytest.raises(StoreError, match="holds trials of model set paper"):
        run_sweep(other, db=db, workers=1, progress=False)


@pytest.mark.parametrize(
    "late", [("model_set", "model_set_hash", "side", "engine"), ("side", "engine"), ("engine",)]
)
def test_a_store_made_before_model_sets_reads_as_the_paper_set(tmp_path, late):
    """A store made before model sets (or before the righting side or the engine was stored) gets the late
    columns: its trials are the paper set's, in pybullet."""
    db = tmp_path / "old.sqlite"
    old_cols = [c for c in st.COLUMNS if c not in late]
    con = sqlite3.connect(db)
    con.execute(
        "CREATE TABLE trials ("
        + ", ".join(f"{c} {st._TYPES[c]}" for c in old_cols)
        + f", PRIMARY KEY ({', '.join(st.KEY_COLUMNS)}))"
    )
    con.execute(st.ROBOTS_SCHEMA)
    con.execute(f"PRAGMA application_id = {st.APPLICATION_ID}")
    con.execute(f"PRAGMA user_version = {st.STORE_VERSION}")
    row = {c: 0 for c in old_cols} | {
        "model_set": "paper",
        "model_set_hash": load_model_set("paper").model_set_hash,
        "robot_hash": "h",
        "status": "ok",
        "phases": "[]",
        "attempt_starts_s": "[]",
    }
    con.execute(
        f"INSERT INTO trials ({', '.join(old_cols)}) VALUES ({', '.join('?' * len(old_cols))})",
        [row[c] for c in old_cols],
    )
    con.commit()
    con.close()
    (r,) = st.read_rows(db)  # read-only: nothing written
    assert (r["side"] is None) == ("side" in late) and (r["model_set"] is None) == ("model_set" in late)
    assert r["engine"] is None
    with TrialStore(db) as s:  # opened for a sweep: the columns are added, the trials are the paper set's
        (r,) = s.rows()
        s.check_model_set("paper", load_model_set("paper").model_set_hash)
    assert (r["model_set"], r["model_set_hash"]) == ("paper", load_model_set("paper").model_set_hash)
    assert (r["side"] is None) == ("side" in late) and r["engine"] == "pybullet"
    names = [c[1] for c in sqlite3.connect(db).execute("PRAGMA table_info(trials)")]
    assert names == list(st.COLUMNS)  # the same layout as a new store's, in order


SHIPPED_HASHES = {
    "paper": "f9e7b9717973cf94",
    "physical": "a647e37a39bc20bd",
    "physical-head": "e2a1c88afadbaca1",
    "physical-offset": "12ee2dcaffb82b60",
    "physical-posed": "84d61ac3f25f3910",
}
"""Every shipped set's hash, as stored trials carry it (since friction turns with the robot by default)."""
WORLD_FRICTION_HASHES = {"paper": "63cfd0473108cf16"}
"""The hashes the sets had when pybullet's friction was fixed in the world: a set that asks for it gets them back
(physical-offset's was 19529bcb520bfde4 at version 1; version 2 moved its CoM)."""


@pytest.mark.parametrize("name", sorted(WORLD_FRICTION_HASHES))
def test_a_set_with_world_friction_has_the_hash_of_before(name, tmp_path):
    text = (Path(st.__file__).parent / "models" / f"{name}.toml").read_text()
    (tmp_path / "w.toml").write_text(
        text.replace("solver_iterations = 20", 'solver_iterations = 20\nfriction_axes = "world"')
    )
    world = load_model_set(tmp_path / "w.toml")
    assert world.contact.friction_axes == "world" and load_model_set(name).contact.friction_axes == "body"
    assert world.model_set_hash == WORLD_FRICTION_HASHES[name] != load_model_set(name).model_set_hash


@pytest.mark.parametrize("name", sorted(SHIPPED_HASHES))
def test_every_shipped_set_keeps_its_hash(name):
    assert shipped_model_sets() == sorted(SHIPPED_HASHES)
    assert load_model_set(name).model_set_hash == SHIPPED_HASHES[name]
