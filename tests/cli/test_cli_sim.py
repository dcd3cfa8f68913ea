"""The simulation commands end to end, on the lab robot when ../shared holds it, else the built-in one."""

import contextlib
import io
import json
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("pybullet")

from landscape.cli import main  # noqa: E402

simulate, sweep, export = "simulate", "sweep", "export"


def invoke(cmd, *args):
    """Run ``landscape CMD ARGS`` through the real entry point (exit status and error mapping included)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([cmd, *(str(a) for a in args)])
    return SimpleNamespace(
        exit_code=code, output=out.getvalue() + err.getvalue(), stdout=out.getvalue(), stderr=err.getvalue()
    )


def test_simulate_json_and_trace(tmp_path, sim_robot):
    trace = tmp_path / "t.csv"
    r = invoke(
        simulate,
        "--theta-w",
        80,
        "--theta-l",
        50,
        "--phase",
        0.7,
        "--cv",
        0.1,
        "--seed",
        1,
        "--dt",
        1e-3,
        "--duration",
        4,
        "--robot",
        sim_robot.urdf,
        "--json",
        "--trace",
        trace,
    )
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["success"] is True and d["attempt"] == 1 and d["mode"] == "roll"
    assert (
        d["phases"] == pytest.approx([0.7])
        and d["seed"] == 1
        and d["theta_w_deg"] == 80.0
        and d["dt_s"] == 1e-3
    )
    assert set(d) >= {"time_to_right_s", "wall_s", "cv", "phase", "theta_l_deg", "robot"}
    a = np.loadtxt(trace, delimiter=",", skiprows=1)
    assert a.shape[1] == 10 and a[0, 0] == pytest.approx(0.01)
    assert a[-1, 0] == pytest.approx(d["time_to_right_s"] + 0.3, abs=0.011)


def test_simulate_human_summary(sim_robot):
    r = invoke(
        simulate,
        "--theta-w",
        70,
        "--theta-l",
        20,
        "--phase",
        0.2,
        "--seed",
        3,
        "--dt",
        1e-3,
        "--duration",
        2,
        "--robot",
        sim_robot.urdf,
    )
    assert r.exit_code == 0, r.output
    assert "not righted in 2 s (1 attempts)" in r.output and "seed 3" in r.output


@pytest.mark.parametrize(
    "args, message",
    [
        (["--theta-w", "80", "--theta-l", "30", "--phase", "1.2"], "--phase 1.2 is outside [0, 1)"),
        (["--theta-w", "120", "--theta-l", "30"], "--theta-w 120 deg is outside [0, 95] deg"),
        (["--theta-w", "80", "--theta-l", "30", "--robot", "/nonexistent.urdf"], "not found"),
        (["--theta-w", "80", "--theta-l", "30", "--dt", "0"], "--dt 0 s is outside [1e-06, 0.01] s"),
        (["--theta-w", "80", "--theta-l", "30", "--heading", "nan"], "heading must be a finite number"),
    ],
)
def test_simulate_bad_input_one_line_exit_2(sim_robot, args, message):
    if "--robot" not in args:
        args = [*args, "--robot", str(sim_robot.urdf)]
    r = invoke(simulate, *args)
    assert r.exit_code == 2
    assert message in r.output and len(r.output.strip().splitlines()) == 1 and "Traceback" not in r.output


@pytest.mark.parametrize(
    "args, message",
    [
        (["--theta-w", ""], "--theta-w is empty"),
        (["--theta-l", "a,b"], "is not a list of numbers"),
        (["--cv", "-0.1"], "--cv -0.1 is outside [0, 1]"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "not both"),
    ],
)
def test_sweep_bad_input(tmp_path, sim_robot, args, message):
    r = invoke(sweep, "--db", tmp_path / "x.sqlite", "--robot", sim_robot.urdf, *args)
    assert r.exit_code == 2, r.output
    assert message in r.output and len(r.output.strip().splitlines()) == 1


def test_sweep_and_export(tmp_path, sim_robot):
    db, out = tmp_path / "s.sqlite", tmp_path / "s.csv"
    args = [
        "--theta-w",
        "80",
        "--theta-l",
        "50",
        "--cv",
        "0,0.2",
        "--trials",
        "1",
        "--db",
        db,
        "--duration",
        "1.5",
        "--dt",
        "1e-3",
        "--workers",
        "1",
        "--robot",
        sim_robot.urdf,
        "--no-progress",
    ]
    r = invoke(sweep, *args, "--json")
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert (s["total"], s["ran"], s["skipped"]) == (2, 2, 0)
    r = invoke(sweep, *args)
    assert r.exit_code == 0 and "2 already in" in r.output and "ran 0" in r.output
    r = invoke(export, "--db", db, "--csv", out)
    assert r.exit_code == 0 and "wrote 2 trials" in r.output
    assert len(out.read_text().splitlines()) == 3
    r = invoke(export, "--db", tmp_path / "missing.sqlite", "--csv", out)
    assert r.exit_code == 2 and "not found" in r.output


def test_sweep_log_has_no_progress_bar_frames(tmp_path):
    """stderr redirected to a file (not a terminal): no tqdm frames (carriage returns, rates) in the log (#17)."""
    import subprocess
    import sys

    log = tmp_path / "sweep.log"
    with open(log, "w") as f:
        r = subprocess.run(
            [
                sys.executable,
                "-m",
                "landscape",
                "sweep",
                "--theta-w",
                "74",
                "--theta-l",
                "30",
                "--cv",
                "0",
                "--trials",
                "2",
                "--duration",
                "0.1",
                "--workers",
                "1",
                "--db",
                str(tmp_path / "s.sqlite"),
            ],
            stdout=subprocess.PIPE,
            stderr=f,
            text=True,
            timeout=300,
        )
    assert r.returncode == 0, log.read_text()
    assert "2 trials: 0 already in" in r.stdout
    text = log.read_text()
    assert "\r" not in text and "trial/s" not in text and "trial]" not in text, text
