import json

import numpy as np
import pytest
import trimesh

from landscape.cli import main
from landscape.cli.options import parse_values
from tests.conftest import run_cli as run


@pytest.fixture()
def box_stl(tmp_path):
    f = tmp_path / "box.stl"
    trimesh.creation.box(extents=(40.0, 20.0, 10.0)).export(f)
    return f


def test_compute_mesh_json(capsys, box_stl):
    code, out, err = run(capsys, "compute", "--mesh", str(box_stl), "--units", "mm", "--mass", "2", "--json")
    assert code == 0, err
    s = json.loads(out)
    assert s["theta_w_deg"] is None and s["theta_l_deg"] is None
    assert s["mass_kg"] == 2.0 and s["com_m"] == pytest.approx([0, 0, 0], abs=1e-12)
    assert s["com_source"] == "solid volume centroid"
    assert s["minimum"]["energy_j"] == pytest.approx(2 * 9.81 * 0.005, rel=1e-12)
    roll = 2 * 9.81 * (np.hypot(0.01, 0.005) - 0.005)
    assert s["barrier"]["righting_j"] == pytest.approx(roll, rel=1e-3)
    assert s["barrier"]["direction"] == "roll"
    for key in ("escape_j", "saddle_pitch_deg", "saddle_roll_deg"):
        assert key in s["barrier"]
    assert set(s["timing_s"]) >= {"landscape", "barrier"}


def test_compute_out_files(capsys, box_stl, tmp_path):
    out_dir = tmp_path / "out"
    code, out, err = run(
        capsys, "compute", "--mesh", str(box_stl), "--units", "mm", "--step", "5", "--out", str(out_dir)
    )
    assert code == 0, err
    assert "righting" in out and "mJ" in out
    z = np.load(out_dir / "landscape.npz")
    assert z["energy_j"].shape == (73, 73) and z["pitch_deg"][0] == -180 and z["pitch_deg"][-1] == 180
    rows = np.loadtxt(out_dir / "landscape.csv", delimiter=",", skiprows=1)
    assert rows.shape == (73 * 73, 3)
    assert json.loads((out_dir / "summary.json").read_text())["step_deg"] == 5.0


def test_compute_lab_robot(capsys, lab_robot):
    code, out, err = run(
        capsys, "compute", "--theta-w", "74", "--robot", str(lab_robot.source), "--json", "--method", "grid"
    )
    assert code == 0, err
    s = json.loads(out)
    assert s["minimum"]["pitch_deg"] == pytest.approx(70, abs=1)
    assert s["minimum"]["energy_j"] == pytest.approx(0.26251, abs=2e-5)
    assert 0 < s["barrier"]["righting_j"] < 0.02
    code, out, err = run(capsys, "compute", "--theta-w", "74", "--robot", str(lab_robot.source), "--json")
    exact = json.loads(out)
    assert exact["method"] == "exact"
    assert exact["minimum"]["energy_j"] < s["minimum"]["energy_j"]
    assert exact["barrier"]["righting_j"] == pytest.approx(s["barrier"]["righting_j"], rel=0.05)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["compute", "--robot", "missing.urdf"], "not found"),
        (["compute", "--mesh", "missing.stl"], "not found"),
        (["compute", "--step", "7", "--mesh", "{box}"], "does not divide 360"),
        (["compute", "--theta-w", "nan", "--mesh", "{box}"], "finite"),
        (["compute", "--start-pitch", "inf", "--mesh", "{box}"], "finite"),
        (["compute", "--mesh", "{box}", "--com", "1,2"], "three finite numbers"),
        (["compute", "--mesh", "{box}", "--mass", "-1"], "--mass must be > 0 kg"),
        (["compute", "--mesh", "{box}", "--robot", "builtin"], "not both"),
        (["barrier-map", "--theta-w", "", "--mesh", "{box}"], "empty"),
        (["compute", "--no-such-option"], "No such option"),
    ],
)
def test_bad_input_one_line(capsys, box_stl, argv, message):
    argv = [a.replace("{box}", str(box_stl)) for a in argv]
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert message in err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_lab_robot_bad_angles(capsys, lab_robot):
    code, _, err = run(capsys, "compute", "--theta-w", "120", "--robot", str(lab_robot.source))
    assert (
        code == 2
        and "outside [-10, 95] deg, the wing joints' range of lab_robot" in err
        and err.count("\n") == 1
    )
    code, _, err = run(capsys, "compute", "--robot", str(lab_robot.source), "--joints", "wing=x;leg=leg")
    assert code == 2 and "joint 'x'" in err


def test_open_mesh_solid_refused(capsys, tmp_path):
    box = trimesh.creation.box(extents=(1, 1, 1))
    box.update_faces(np.arange(len(box.faces)) > 1)
    f = tmp_path / "open.ply"
    box.export(f)
    code, _, err = run(capsys, "compute", "--mesh", str(f), "--com-model", "solid")
    assert code == 2 and "watertight=False" in err
    code, out, err = run(capsys, "compute", "--mesh", str(f), "--json", "--step", "10")
    assert code == 0, err
    assert json.loads(out)["com_source"] == "thin-shell area centroid"


def test_barrier_map_lab(capsys, lab_robot, tmp_path):
    code, out, err = run(
        capsys,
        "barrier-map",
        "--theta-w",
        "70:76:2",
        "--theta-l",
        "20,50",
        "--step",
        "2",
        "--robot",
        str(lab_robot.source),
        "--out",
        str(tmp_path),
    )
    assert code == 0, err
    rows = np.genfromtxt(tmp_path / "barrier_map.csv", delimiter=",", names=True, dtype=None, encoding=None)
    assert len(rows) == 8
    assert (tmp_path / "barrier_map.png").stat().st_size > 1000
    b = {(r["theta_w_deg"], r["theta_l_deg"]): r["righting_j"] for r in rows}
    assert b[(76.0, 50.0)] < b[(70.0, 20.0)]


def test_parse_values():
    assert parse_values("-10:90:0.5", "theta-w")[-1] == 90.0
    assert len(parse_values("-10:90:0.5", "theta-w")) == 201
    with pytest.raises(ValueError, match="not a list of numbers"):
        parse_values("a,b", "theta-w")


def test_real_process_clean_streams(box_stl):
    """As a user runs it: stdout is pure JSON (no pybullet banner), an error is exactly one stderr line."""
    import subprocess
    import sys

    ok = subprocess.run(
        [
            sys.executable,
            "-m",
            "landscape",
            "compute",
            "--mesh",
            str(box_stl),
            "--units",
            "mm",
            "--json",
            "--step",
            "10",
        ],
        capture_output=True,
        text=True,
    )
    assert ok.returncode == 0 and ok.stderr == ""
    assert json.loads(ok.stdout)["mass_kg"] == 1.0
    bad = subprocess.run(
        [sys.executable, "-m", "landscape", "compute", "--mesh", "nope.stl"], capture_output=True, text=True
    )
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and bad.stderr.startswith("landscape: error:")


def test_robot_export_round_trip(capsys, tmp_path):
    """The exported built-in robot is the same robot: same files, same barrier as the default."""
    from geometry.builtin import builtin_description

    code, out, err = run(capsys, "robot", "export", "--out", str(tmp_path))
    assert code == 0, err
    files = builtin_description()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(files)
    assert (tmp_path / "robot.urdf").read_bytes() == files["robot.urdf"]
    code, out, err = run(
        capsys, "compute", "--robot", str(tmp_path / "robot.urdf"), "--theta-w", "74", "--json", "--step", "4"
    )
    exported = json.loads(out)
    code, out, err = run(capsys, "compute", "--theta-w", "74", "--json", "--step", "4")
    default = json.loads(out)
    assert exported["barrier"]["righting_j"] == default["barrier"]["righting_j"]
    assert exported["minimum"] == default["minimum"]


def test_unexpected_exception_is_reported_as_a_bug_not_as_bad_input(capsys, monkeypatch):
    """A ValueError from inside the library (a shape bug, not the user's input) is a bug: exit 1, one line saying
    so and how to see the traceback; bad input stays exit 2."""
    import landscape.computation

    def broken(*a, **k):
        raise ValueError("operands could not be broadcast together with shapes (3,) (4,)")

    monkeypatch.delenv("LANDSCAPE_DEBUG", raising=False)
    monkeypatch.setattr(landscape.computation, "compute", broken)
    code, out, err = run(capsys, "compute", "--theta-w", "74")
    assert code == 1
    assert "internal error: ValueError: operands could not be broadcast" in err
    assert "this is a bug" in err and "--debug" in err and "Traceback" not in err
    with pytest.raises(ValueError, match="broadcast"):
        main(["--debug", "compute", "--theta-w", "74"])
    monkeypatch.setenv("LANDSCAPE_DEBUG", "1")
    with pytest.raises(ValueError, match="broadcast"):
        main(["compute", "--theta-w", "74"])


def test_bad_input_is_exit_2_and_one_line(capsys):
    code, out, err = run(capsys, "compute", "--theta-w", "120")
    assert code == 2 and len(err.strip().splitlines()) == 1 and "outside [-10, 95] deg" in err


def test_no_arguments_prints_help_and_exits_0(capsys):
    code, out, err = run(capsys)
    assert code == 0 and "Usage: landscape" in out and "compute" in out and err == ""


def test_every_command_is_registered(capsys):
    """Commands are imported explicitly: none vanishes when a module fails to import."""
    code, out, err = run(capsys, "--help")
    for name in (
        "compute",
        "barrier-map",
        "render",
        "robot",
        "bench",
        "simulate",
        "sweep",
        "export",
        "analyze",
        "report",
    ):
        assert f"  {name} " in out
