"""`landscape analyze energy` and `landscape physical energy` end to end: energy.csv, the figure, the reruns'
check and one-line refusals of bad input."""

import pytest

pytest.importorskip("pybullet")

from sim.store import TrialStore  # noqa: E402
from sim.sweep import run_sweep, sweep_specs  # noqa: E402
from tests.conftest import SHARED, needs_lab  # noqa: E402
from tests.conftest import csv_rows as _csv
from tests.conftest import run_cli as run  # noqa: E402

PHYSICAL = SHARED / "ref" / "physical_robot"
ISSUE_COLUMNS = (
    "source theta_w_deg theta_l_deg trial attempt success phase ke_roll_mj ke_pitch_mj ke_yaw_mj ke_trans_mj "
    "barrier_mj direction margin_mj"
).split()


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    """Three short multi-attempt trials on the built-in robot (coarse step) and one single-attempt trial."""
    path = tmp_path_factory.mktemp("energy") / "t.sqlite"
    specs = sweep_specs((74.0,), (30.0,), (0.0,), phase=(0.0, 0.25, 0.5), duration_s=4.5, dt_s=1e-3, trials=1)
    specs += sweep_specs(
        (74.0,), (30.0,), (0.0,), phase=(0.5,), attempts=1, duration_s=4.0, dt_s=1e-3, trials=1
    )
    run_sweep(specs, db=path, workers=1, progress=False)
    return path


def test_analyze_energy_writes_one_row_per_attempt_and_the_figure(capsys, db, tmp_path):
    out = tmp_path / "e"
    code, stdout, err = run(
        capsys, "analyze", "energy", "--db", db, "--sample", 2, "--out", out, "--no-progress"
    )
    assert code == 0, err
    rows = _csv(out / "energy.csv")
    assert set(ISSUE_COLUMNS) <= set(rows[0])
    assert {r["source"] for r in rows} == {"simulated"}
    assert len({r["trial"] for r in rows}) == 2
    for r in rows:
        assert int(r["attempt"]) >= 1 and r["direction"] in ("roll", "pitch")
        assert float(r["barrier_mj"]) > 0 and float(r["ke_roll_mj"]) >= 0 and float(r["ke_trans_mj"]) >= 0
    reruns = _csv(out / "energy_reruns.csv")
    assert len(reruns) == 2 and all(r["reproduced"] == "1" for r in reruns)
    assert "2 of 2 reproduce their stored outcome" in stdout
    assert (out / "energy.png").stat().st_size > 1000 and (out / "energy.svg").is_file()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--sample", "4"], "not within the 3 multi-attempt trials"),
        (["--sample", "0"], "--sample must be >= 1, a count of stored trials; got 0"),
    ],
)
def test_analyze_energy_refuses_a_sample_outside_the_store(capsys, db, tmp_path, argv, message):
    code, _, err = run(capsys, "analyze", "energy", "--db", db, "--out", tmp_path / "e", *argv)
    assert code == 2
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_analyze_energy_refuses_an_empty_database_and_one_without_multi_attempt_trials(capsys, tmp_path):
    empty = tmp_path / "empty.sqlite"
    with TrialStore(empty):
        pass
    code, _, err = run(capsys, "analyze", "energy", "--db", empty, "--out", tmp_path / "e")
    assert code == 2 and "holds no trials" in err and len(err.strip().splitlines()) == 1
    single = tmp_path / "single.sqlite"
    specs = sweep_specs(
        (74.0,), (30.0,), (0.0,), phase=(0.5,), attempts=1, duration_s=4.0, dt_s=1e-3, trials=1
    )
    run_sweep(specs, db=single, workers=1, progress=False)
    code, _, err = run(capsys, "analyze", "energy", "--db", single, "--out", tmp_path / "e")
    assert code == 2 and "no multi-attempt trials" in err and len(err.strip().splitlines()) == 1


def test_physical_energy_refuses_a_folder_without_trials(capsys, tmp_path):
    code, _, err = run(capsys, "physical", "energy", "--data", tmp_path, "--out", tmp_path / "e")
    assert code == 2 and "holds no trial file" in err and len(err.strip().splitlines()) == 1


@pytest.mark.e2e  # every recorded attempt of the lab's trials
@pytest.mark.shared
@needs_lab
@pytest.mark.skipif(not PHYSICAL.is_dir(), reason=f"{PHYSICAL} is absent")
def test_physical_energy_measures_every_recorded_attempt(capsys, tmp_path):
    """Three recorded trials at 60 deg / leg 30 deg: one row per attempt by the lab's rule, the righting attempt
    of each trial marked, and the margin's sign scored beside the barrier alone."""
    data = tmp_path / "data"
    data.mkdir()
    names = [f"run5_60_60_60_60_30_{k}.bag.mat" for k in (1, 2, 3)]
    for name in names:
        (data / name).symlink_to(PHYSICAL / name)
    out = tmp_path / "e"
    lab = SHARED / "ref" / "lab_robot" / "lab_robot.urdf"
    code, stdout, err = run(
        capsys, "physical", "energy", "--data", data, "--robot", lab, "--out", out, "--no-progress"
    )
    assert code == 0, err
    rows = _csv(out / "energy.csv")
    assert set(ISSUE_COLUMNS) <= set(rows[0])
    assert {r["trial"] for r in rows} == set(names)
    assert {r["source"] for r in rows} == {"recorded"}
    for name in names:  # every one of these trials rights, in its last measured attempt
        mine = [r for r in rows if r["trial"] == name]
        assert [r["success"] for r in mine] == ["0"] * (len(mine) - 1) + ["1"]
    assert "margin > 0 matches the outcome in" in stdout and "barrier <" in stdout
    assert (out / "energy.png").stat().st_size > 1000
