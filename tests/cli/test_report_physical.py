"""`landscape report --physical DIR`: the physical robot's attempts and outcomes as a section of the report."""

import csv
import json

import pytest

pytest.importorskip("pybullet")

from sim.sweep import run_sweep, sweep_specs  # noqa: E402
from tests.conftest import SHARED  # noqa: E402
from tests.conftest import run_cli as run  # noqa: E402

PHYSICAL = SHARED / "ref" / "physical_robot"


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    """Two 2 s paper-protocol trials on the built-in robot."""
    path = tmp_path_factory.mktemp("physical") / "t.sqlite"
    specs = sweep_specs((74.0,), (30.0,), (0.1,), phase=(0.1,), trials=2, duration_s=2.0, dt_s=1e-3)
    run_sweep(specs, db=path, workers=1, progress=False)
    return path


def test_report_refuses_a_physical_directory_that_does_not_exist(capsys, db, tmp_path):
    code, out, err = run(capsys, "report", "--db", db, "--out", tmp_path / "r", "--physical", tmp_path / "no")
    assert code == 2 and "does not exist" in err and len(err.strip().splitlines()) == 1
    code, out, err = run(capsys, "report", "--db", db, "--out", tmp_path / "r", "--physical", tmp_path)
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1  # not the lab's data


@pytest.mark.e2e
@pytest.mark.shared
@pytest.mark.skipif(
    not (PHYSICAL / "robot_attempts.mat").is_file(), reason=f"{PHYSICAL} is absent (set LANDSCAPE_SHARED)"
)
def test_report_with_physical_adds_the_attempts_and_the_cells(capsys, db, tmp_path):
    from landscape.analysis.physical.cells import physical_cells
    from landscape.analysis.physical.outcome import physical_trials
    from landscape.analysis.physical.recording import WING_COMMANDS_DEG

    out = tmp_path / "r"
    code, stdout, err = run(capsys, "report", "--db", db, "--out", out, "--physical", PHYSICAL)
    assert code == 0, err
    html = (out / "index.html").read_text()
    assert "The physical robot&#x27;s attempts over the landscape" in html
    assert "The recorded attempts are of the lab&#x27;s robot, drawn over builtin_robot" in html
    for cmd in WING_COMMANDS_DEG:
        assert (out / "physical" / f"wing_{cmd:g}" / "trajectories_contour.svg").is_file()
    with open(out / "physical_cells.csv", newline="") as f:
        cells = list(csv.DictReader(f))
    assert len(cells) == len(physical_cells(physical_trials(PHYSICAL)))
    assert "physical_cells.csv" in html and str(PHYSICAL.resolve()) in html
    with open(out / "energy.csv", newline="") as f:
        energy = list(csv.DictReader(f))
    assert {r["source"] for r in energy} == {
        "simulated",
        "recorded",
    }  # the robot's attempts beside the sweep's
    assert "Energy budget of the attempts" in html


@pytest.mark.e2e
@pytest.mark.shared
@pytest.mark.skipif(
    not (PHYSICAL / "robot_attempts.mat").is_file(), reason=f"{PHYSICAL} is absent (set LANDSCAPE_SHARED)"
)
def test_report_with_validation_adds_the_simulated_against_physical_section(capsys, db, tmp_path):
    val = tmp_path / "val"
    code, _, err = run(capsys, "physical", "validate", "--data", PHYSICAL, "--cells", "75:15,90:30", "--trials",
                       "2", "--duration", "2", "--out", val, "--no-progress", "--workers", "1")  # fmt: skip
    assert code == 0, err
    # the same trials as if run at the protocol's phases: the page says which phases each validation used
    val2 = tmp_path / "val-protocol"
    val2.mkdir()
    doc = json.loads((val / "validation.json").read_text()) | {
        "phase": "protocol",
        "cell_phases": {"75:15": 0.195},
    }
    (val2 / "validation.json").write_text(json.dumps(doc))
    out = tmp_path / "r"
    code, stdout, err = run(
        capsys,
        "report",
        "--db",
        db,
        "--out",
        out,
        "--validation",
        val,
        "--validation",
        val2,
        "--physical",
        PHYSICAL,
    )
    assert code == 0, err
    html = (out / "index.html").read_text()
    assert "The simulation against the physical robot" in html and "Model set paper (" in html
    assert "of 1 fit cells" in html and "of 1 held-out cells" in html
    assert (out / "validation" / "0_paper" / "time_to_right.svg").is_file()
    with open(out / "validation" / "resting_pitch.csv", newline="") as f:
        rest = list(csv.DictReader(f))
    assert [float(r["wing_command_deg"]) for r in rest] == [60.0, 75.0, 90.0]
    assert "model_builtin_robot_deg" in rest[0]
    assert "random first-attempt phases" in html
    with open(out / "validation" / "hold_frames.csv", newline="") as f:
        frames = list(csv.DictReader(f))
    assert [float(r["theta_w_cmd_deg"]) for r in frames] == [60.0, 75.0, 90.0]
    assert {r["robot"] for r in frames} == {"builtin_robot"} and all(r["n"] == "5" for r in frames)
    with open(out / "validation" / "hold_body_frame.csv", newline="") as f:
        body = list(csv.DictReader(f))
    assert [(r["model_set"], float(r["wing_command_deg"])) for r in body] == [
        ("paper", w) for w in (60, 75, 90)
    ]
    for r in body:
        assert float(r["robot_body_deg"]) == pytest.approx(
            float(r["robot_imu_deg"]) - float(r["imu_mount_deg"])
        )
    assert "measured from the two rests every righted trial records" in html and "paper 60° " in html
    with open(out / "validation" / "first_openings.csv", newline="") as f:
        first = list(csv.DictReader(f))
    assert len(first) == 60 and {r["leg_lead_s"] for r in first if float(r["leg_deg"]) == 0} == {"nan"}
    assert {"leg_swing_s", "closing_tilt_deg", "rolled_s", "gyro_deviation_deg"} <= set(first[0])
    with open(out / "validation" / "hold_leans.csv", newline="") as f:
        leans = {(float(r["theta_w_cmd_deg"]), float(r["theta_l_deg"])): r for r in csv.DictReader(f)}
    assert len(leans) == 9 and leans[(60.0, 30.0)]["n_plus"] == "3"
    assert float(leans[(60.0, 30.0)]["plus_deg"]) > float(leans[(60.0, 30.0)]["minus_deg"]) + 5.0
    assert 0.75 < float(leans[(75.0, 15.0)]["departure_s"]) < 0.85
    assert "each cell&#x27;s phase under the lab&#x27;s protocol" in html  # the second validation
    code, _, err = run(
        capsys, "report", "--db", db, "--out", out, "--validation", tmp_path
    )  # no validation.json
    assert code == 2 and "not found" in err and len(err.strip().splitlines()) == 1
