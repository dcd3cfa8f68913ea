"""`landscape analyze …` and `landscape report` end to end, on a small real database of simulated trials."""

import pytest

pytest.importorskip("pybullet")

from sim.sweep import run_sweep, sweep_specs  # noqa: E402
from tests.conftest import csv_rows as _csv
from tests.conftest import run_cli as run  # noqa: E402

FAST = dict(dt_s=1e-3, trials=1)


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    """Single-attempt map, a multi-attempt prediction study over (Tw, Tl) and noisy paper-protocol trials,
    all on the built-in robot at a coarse time step (about 30 short trials)."""
    path = tmp_path_factory.mktemp("analysis") / "t.sqlite"
    phases = (0.0, 0.25, 0.5, 0.75)
    specs = sweep_specs((74.0,), (20.0, 30.0), (0.0,), phase=phases, attempts=1, duration_s=10.0, **FAST)
    specs += sweep_specs(
        (74.0,), (30.0,), (0.0,), phase=phases, wing_period_s=(2.0, 2.5), duration_s=5.0, **FAST
    )
    specs += sweep_specs((74.0,), (20.0, 30.0), (0.1,), phase=(0.7,), duration_s=4.0, dt_s=1e-3, trials=3)
    run_sweep(specs, db=path, workers=1, progress=False)
    return path


@pytest.mark.e2e
def test_report_builds_every_analysis_from_a_real_database(capsys, db, tmp_path):
    out = tmp_path / "report"
    code, stdout, err = run(capsys, "report", "--db", db, "--out", out)
    assert code == 0, err
    assert "7/7 analyses" in stdout
    html = (out / "index.html").read_text()
    for title in (
        "Self-righting probability",
        "Single-attempt phase map",
        "Phase-based prediction",
        "Phase evolution",
        "Barrier against outcome",
        "Trajectories of simulated trials",
        "Energy budget of the attempts",
    ):
        assert title in html
    assert "Not enough data" not in html
    for stem in ("probability", "phase_map", "prediction", "evolution", "barrier_outcome"):
        assert (out / f"{stem}.png").stat().st_size > 1000 and (out / f"{stem}.svg").is_file()
    rows = _csv(out / "probability.csv")
    assert {(r["theta_l_deg"], r["n"]) for r in rows} == {("20", "3"), ("30", "3")}
    acc = _csv(out / "prediction_accuracy.csv")
    assert {(r["wing_period_s"], r["n"]) for r in acc if r["cv"] == "0"} == {("2", "4"), ("2.5", "4")}
    stats = _csv(out / "barrier_stats.csv")
    assert len(stats) == 1 and stats[0]["cv"] == "0.1"
    bo = _csv(out / "barrier_outcome.csv")
    assert all(float(r["exact_barrier_mj"]) > 0 and float(r["grid_barrier_mj"]) > 0 for r in bo)
    # theta_l 20 and 30 deg: no mirror symmetry, so the righting barrier's gradients exist (mJ per mm, per deg)
    assert all(
        r["righting_differentiable"] == "True" and float(r["righting_com_y_mj_per_mm"]) != 0 for r in bo
    )
    assert all(float(r["righting_theta_w_mj_per_deg"]) < 0 for r in bo)  # wider wings, lower barrier
    assert "Gradients of the exact righting barrier per setting" in html
    reruns = _csv(out / "trajectories.csv")
    assert len(reruns) == 3 and all(r["reproduced"] == "1" for r in reruns)  # the 3 trials of one setting
    assert (out / "trajectories" / "trajectories_contour.png").stat().st_size > 1000
    energy = _csv(out / "energy.csv")
    assert energy and {r["source"] for r in energy} == {"simulated"}
    assert all(r["reproduced"] == "1" for r in _csv(out / "energy_reruns.csv"))


def test_report_says_which_command_produces_missing_trials(capsys, tmp_path):
    only_map = tmp_path / "map.sqlite"
    specs = sweep_specs((74.0,), (30.0,), (0.0,), phase=(0.0, 0.5), attempts=1, duration_s=10.0, **FAST)
    run_sweep(specs, db=only_map, workers=1, progress=False)
    code, stdout, err = run(capsys, "report", "--db", only_map, "--out", tmp_path / "r")
    assert code == 0, err
    assert "missing data for" in stdout
    html = (tmp_path / "r" / "index.html").read_text()
    assert f"landscape sweep --db {only_map}" in html  # the paper sweep, for probability and barrier


@pytest.mark.e2e  # reruns the study's trials and the single attempts from rest
def test_analyze_prediction_scores_both_predictors_held_out_and_resumes(capsys, db, tmp_path):
    """--json: one object per predictor; the study's 8 trials (74/30, Tw 2 and 2.5 s, 4 phases) are rerun once
    into the states file, the single attempts from rest the second predictor needs are run once into theirs, and
    a second run reads both back instead of running them again."""
    import json

    states = tmp_path / "states.jsonl"
    rest = db.parent / f"{db.name}.from-rest.jsonl"
    rest.unlink(missing_ok=True)
    code, out, err = run(
        capsys, "analyze", "prediction", "--db", db, "--json", "--states", states, "--no-progress"
    )
    assert code == 0, err
    scores = json.loads(out)
    assert [s["name"] for s in scores] == ["phase map", "from rest at each opening", "state"]
    runs = [json.loads(x) for x in rest.read_text().splitlines()]
    assert runs and all("/heading" in r["key"] and "/seed0" in r["key"] for r in runs)
    assert len({r["key"] for r in runs}) == len(runs)
    for s in scores:
        assert set(s) == {"name", "trials", "correct", "accuracy", "ci95", "held_out"}
        assert s["trials"] == 8 and s["held_out"] is True and s["accuracy"] == s["correct"] / 8
        assert s["ci95"][0] <= s["accuracy"] <= s["ci95"][1]
    lines = states.read_text().splitlines()
    assert len(lines) == 8 and all(json.loads(x)["reproduced"] for x in lines)
    stamp = states.stat().st_mtime_ns
    r_stamp = rest.stat().st_mtime_ns
    code, out2, err = run(capsys, "analyze", "prediction", "--db", db, "--json", "--states", states)
    assert code == 0 and json.loads(out2) == scores and states.stat().st_mtime_ns == stamp
    assert rest.stat().st_mtime_ns == r_stamp
    code, out, err = run(
        capsys, "analyze", "prediction", "--db", db, "--out", tmp_path / "p", "--states", states
    )
    assert code == 0, err
    assert "phase map " in out and "state " in out and "held out" in out.lower()
    assert "from rest at each opening " in out and "single attempts)" in out
    assert (tmp_path / "p" / "prediction_scores.csv").is_file()


def test_analyze_commands_write_their_files_and_refuse_bad_input(capsys, db, tmp_path):
    code, out, err = run(capsys, "analyze", "phase-map", "--db", db, "--out", tmp_path)
    assert code == 0, err
    assert (tmp_path / "phase_map.csv").is_file() and "θl 30°" in out
    code, out, err = run(capsys, "analyze", "evolution", "--db", db, "--out", tmp_path, "--cv", "0.2")
    assert code == 0, err
    assert (tmp_path / "evolution.csv").is_file()
    code, out, err = run(capsys, "analyze", "probability", "--db", tmp_path / "absent.sqlite")
    assert code == 2 and "not found" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    code, out, err = run(capsys, "analyze", "evolution", "--db", db, "--phase", "1.5")
    assert code == 2 and "--phase" in err
    code, out, err = run(capsys, "analyze", "evolution", "--db", db, "--theta-w", "60", "--out", tmp_path)
    assert code == 2 and "landscape sweep" in err


@pytest.mark.e2e
def test_report_page_passes_a_headless_browser_check(capsys, db, tmp_path):
    from landscape.viz.report import find_chromium

    if find_chromium() is None:
        pytest.skip("chromium is not installed (apt-get install chromium)")
    out = tmp_path / "report"
    code, stdout, err = run(capsys, "report", "--db", db, "--out", out, "--check")
    assert code == 0, err
    assert "console errors 0" in stdout and (out / "screenshot.png").stat().st_size > 0


@pytest.mark.parametrize("robot", ["lab", "modified builtin"])
def test_barrier_analysis_needs_the_trials_own_robot(capsys, tmp_path, robot):
    import sqlite3
    from dataclasses import replace

    from geometry.builtin import builtin_parameters, builtin_urdf_path
    from tests.conftest import lab_sim_robot

    if robot == "lab":
        urdf = lab_sim_robot().urdf
    else:  # any robot other than the built-in one will do: the generator's with a heavier head
        urdf = builtin_urdf_path(
            cache_dir=tmp_path / "other", params=replace(builtin_parameters(), head_kg=0.02)
        )
    path = tmp_path / "other.sqlite"
    specs = sweep_specs(
        (80.0,), (30.0,), (0.1,), phase=(0.7,), duration_s=1.0, dt_s=1e-3, trials=2, robot=urdf
    )
    run_sweep(specs, db=path, workers=1, progress=False)
    code, out, err = run(
        capsys, "analyze", "barrier", "--db", path, "--out", tmp_path / "a", "--robot", builtin_urdf_path()
    )
    assert code == 2 and "is not the robot of the trials" in err
    con = sqlite3.connect(path)
    con.execute("UPDATE trials SET robot = ?", (str(tmp_path / "moved.urdf"),))
    con.commit()
    con.close()
    code, out, err = run(capsys, "analyze", "barrier", "--db", path, "--out", tmp_path / "a")
    assert code == 2 and "--robot FILE.urdf" in err and len(err.strip().splitlines()) == 1
    code, out, err = run(capsys, "analyze", "barrier", "--db", path, "--out", tmp_path / "a", "--robot", urdf)
    assert code == 0, err
    assert (tmp_path / "a" / "barrier_outcome.csv").is_file()


@pytest.mark.e2e  # times every kernel against its baseline
def test_bench_runs_and_reports_positive_ratios(capsys):
    """``landscape bench --repeat 1`` on the built-in robot: every timing and ratio a positive number, the two
    methods agreeing, and the derived rows consistent with the rows they come from."""
    import re

    code, out, err = run(capsys, "bench", "--repeat", "1")
    assert code == 0, err
    rows = dict(re.findall(r"^\| (.+?) +\| (.+) \|$", out, flags=re.MULTILINE))

    def number(key):
        return float(
            re.search(
                r"\d+(?:\.\d+)?(?:e[-+]?\d+)?", next(v for k, v in rows.items() if k.startswith(key))
            ).group()
        )

    speed_up = number("speed-up, lab / ours")
    lab_ms, ours_ms = number("1° landscape, lab method"), number("1° landscape, ours")
    assert lab_ms > 0 and ours_ms > 0 and speed_up > 0
    assert speed_up == pytest.approx(lab_ms / ours_ms, rel=0.02, abs=0.5)  # rounded to whole times
    assert 0 <= number("agreement") < 1e-9  # the hull walk and the all-vertex method are one landscape
    grid_mj, exact_mj = number("righting barrier, 1° grid"), number("righting barrier, exact")
    assert grid_mj > 0 and exact_mj > 0
    assert number("1° grid error") == pytest.approx(100 * abs(grid_mj - exact_mj) / exact_mj, abs=0.1)
    n_vertices = number("mesh vertices")
    assert number("an orientations x vertices array") == pytest.approx(
        3600**2 * n_vertices * 8 / 2**30, abs=0.5
    )
