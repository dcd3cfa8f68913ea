"""``--engine`` on ``simulate``, ``sweep``, ``physical validate`` and ``physical calibrate``: MuJoCo runs the same commands, and an unknown
engine, MuJoCo without its extra, a set the engine cannot express and a database of the other engine each get one
line and exit status 2."""

import json
import sys
from pathlib import Path

import pytest

from sim.engine import MUJOCO_EXTRA
from sim.model_set import load_model_set
from sim.protocol import MUJOCO_DT_S
from tests.conftest import SHARED, run_cli

TRIAL = ("--theta-w", 74, "--theta-l", 30, "--phase", 0.7, "--cv", 0, "--seed", 1, "--duration", 0.6)
SWEEP = ("--theta-w", 74, "--theta-l", 30, "--cv", 0, "--trials", 1, "--duration", 0.6, "--workers", 1)


def _one_line(code: int, err: str, text: str) -> None:
    assert code == 2 and err.count("\n") == 1 and err.startswith("landscape: error: ") and text in err, err


@pytest.mark.parametrize(
    "argv",
    [
        ("simulate", *TRIAL),
        ("sweep", *SWEEP, "--db", "x.sqlite"),
        ("physical", "validate", "--data", "."),
        ("physical", "calibrate", "--data", ".", "--vary", "contact.lateral_friction=1", "--out", "c"),
    ],
    ids=["simulate", "sweep", "validate", "calibrate"],
)
def test_an_unknown_engine_is_one_line(capsys, argv):
    code, _, err = run_cli(capsys, *argv, "--engine", "bullet")
    _one_line(code, err, "Invalid value for '--engine': 'bullet' is not one of 'pybullet', 'mujoco'")


@pytest.mark.parametrize(
    "argv",
    [
        ("simulate", *TRIAL),
        ("sweep", *SWEEP, "--db", "x.sqlite"),
        ("physical", "validate", "--data", "."),
        ("physical", "calibrate", "--data", ".", "--vary", "contact.lateral_friction=1", "--out", "c"),
    ],
    ids=["simulate", "sweep", "validate", "calibrate"],
)
def test_mujoco_without_its_extra_is_one_line(capsys, monkeypatch, tmp_path, argv):
    monkeypatch.setitem(sys.modules, "mujoco", None)
    monkeypatch.delitem(sys.modules, "sim.mujoco_world", raising=False)
    monkeypatch.chdir(tmp_path)
    code, _, err = run_cli(capsys, *argv, "--engine", "mujoco")
    _one_line(code, err, MUJOCO_EXTRA)
    assert not (tmp_path / "x.sqlite").exists() and not (tmp_path / "c").exists()


def test_a_set_the_engine_cannot_express_is_one_line(capsys, tmp_path):
    pytest.importorskip("mujoco")
    text = Path(load_model_set("paper").source).read_text()
    f = tmp_path / "wings.toml"
    f.write_text(
        text.replace(
            "solver_iterations = 20",
            "solver_iterations = 20\nwing_stiffness_n_m = 2000.0\nwing_damping_n_s_m = 20.0",
        )
    )
    for argv in (("simulate", *TRIAL), ("sweep", *SWEEP, "--db", tmp_path / "w.sqlite")):
        code, _, err = run_cli(capsys, *argv, "--model", f, "--engine", "mujoco")
        _one_line(code, err, "the mujoco engine cannot express [contact] wing_stiffness_n_m")
    code, out, _ = run_cli(capsys, "simulate", *TRIAL, "--model", f, "--engine", "pybullet", "--json")
    assert code == 0 and json.loads(out)["engine"] == "pybullet"


def test_simulate_and_sweep_run_in_mujoco(capsys, tmp_path):
    pytest.importorskip("mujoco")
    code, out, err = run_cli(capsys, "simulate", *TRIAL, "--engine", "mujoco", "--json")
    assert code == 0, err
    d = json.loads(out)
    mj = load_model_set().with_engine("mujoco")
    assert d["engine"] == "mujoco" and d["model_set_hash"] == mj.model_set_hash and d["dt_s"] == MUJOCO_DT_S
    code, out, _ = run_cli(capsys, "simulate", *TRIAL, "--engine", "mujoco")
    assert code == 0 and "engine       mujoco\n" in out and f"model set    paper ({mj.model_set_hash})" in out
    db = tmp_path / "mj.sqlite"
    code, out, err = run_cli(capsys, "sweep", *SWEEP, "--db", db, "--engine", "mujoco", "--no-progress")
    assert code == 0 and "ran 1 " in out, err
    code, _, err = run_cli(capsys, "sweep", *SWEEP, "--db", db, "--no-progress")
    _one_line(
        code, err, f"'{db}' holds mujoco trials, not pybullet ones; mixing engines would pool two models"
    )


@pytest.mark.shared
@pytest.mark.skipif(
    not (SHARED / "ref" / "physical_robot" / "robot_attempts.mat").is_file(), reason="needs ../shared/ref"
)
def test_physical_validate_runs_in_mujoco(capsys, tmp_path):
    pytest.importorskip("mujoco")
    out = tmp_path / "val"
    code, stdout, err = run_cli(
        capsys, "physical", "validate", "--data", SHARED / "ref" / "physical_robot", "--cells", "75:15",
        "--trials", 2, "--duration", 2, "--out", out, "--no-progress", "--workers", 1, "--engine", "mujoco",
    )  # fmt: skip
    assert code == 0, err
    doc = json.loads((out / "validation.json").read_text())
    mj = load_model_set().with_engine("mujoco")
    assert doc["engine"] == "mujoco" and doc["model_set_hash"] == mj.model_set_hash
    (db,) = out.glob("trials_*.sqlite")
    assert db.name == f"trials_paper_{mj.model_set_hash}.sqlite"
    from sim.store import read_rows

    assert {r["engine"] for r in read_rows(db)} == {"mujoco"}
