"""Sweeps in either engine (sim/sweep.py, sim/store.py): the engine travels in the spec to the workers and keys the
stored row through the set's hash, a row says its engine, and a database holding one engine's trials refuses the
other's in one line."""

import pickle

import pytest

pytest.importorskip("mujoco")

from sim.model_set import load_model_set  # noqa: E402
from sim.protocol import MUJOCO_DT_S  # noqa: E402
from sim.store import StoreError, TrialStore, read_rows  # noqa: E402
from sim.sweep import run_spec, run_sweep, sweep_specs  # noqa: E402
from sim.trial import run_trial  # noqa: E402

FAST = dict(trials=1, duration_s=0.6)


def test_a_mujoco_spec_carries_its_engine_and_its_hash():
    (spec,) = sweep_specs([74.0], [30.0], [0.1], engine="mujoco", **FAST)
    (pb,) = sweep_specs([74.0], [30.0], [0.1], **FAST)
    assert (spec.engine, pb.engine) == ("mujoco", "pybullet")
    assert spec.model_set_hash == load_model_set().with_engine("mujoco").model_set_hash != pb.model_set_hash
    assert spec.dt_s == MUJOCO_DT_S and spec.seed == pb.seed  # the same noise in both engines
    assert pickle.loads(pickle.dumps(spec)) == spec
    row = run_spec(spec)  # what a worker does with it
    r = run_trial(74.0, 30.0, phase=spec.phase, cv=0.1, rng=spec.seed, duration_s=0.6, engine="mujoco")
    assert row["engine"] == "mujoco" and row["model_set_hash"] == spec.model_set_hash
    assert (bool(row["success"]), row["sim_s"], row["max_tracking_error_deg"]) == (
        r.success,
        r.sim_s,
        r.max_tracking_error_deg,
    )


def test_one_database_one_engine(tmp_path):
    db = tmp_path / "t.sqlite"
    mj = sweep_specs([74.0], [30.0], [0.0], engine="mujoco", **FAST)
    assert run_sweep(mj, db=db, workers=1, progress=False).ran == 1
    (row,) = read_rows(db)
    assert row["engine"] == "mujoco" and row["model_set_hash"] == mj[0].model_set_hash
    assert run_sweep(mj, db=db, workers=1, progress=False).skipped == 1  # resumes
    pb = sweep_specs([74.0], [30.0], [0.0], **FAST)
    with pytest.raises(StoreError) as err:
        run_sweep(pb, db=db, workers=1, progress=False)
    assert str(err.value) == (
        f"'{db}' holds mujoco trials, not pybullet ones; mixing engines would pool two models. Sweep into another "
        "--db, or pass --engine mujoco"
    )
    with TrialStore(db) as store:
        store.check_engine("mujoco")
        assert store.count() == 1
    with pytest.raises(ValueError, match=r"the sweep mixes engines \(mujoco, pybullet\)"):
        run_sweep(mj + pb, db=tmp_path / "other.sqlite", workers=1, progress=False)
