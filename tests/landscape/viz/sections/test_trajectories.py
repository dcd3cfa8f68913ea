"""The report's trajectories section (landscape/viz/sections/trajectories.py) on a tiny trial database made here, and its
physical-robot section on the lab's recordings (skips without them)."""

import re

import numpy as np
import pytest

pytest.importorskip("pybullet")

from landscape.viz import render as rd  # noqa: E402
from landscape.viz import sections  # noqa: E402
from landscape.viz import trajectory as tj  # noqa: E402
from sim.store import read_rows  # noqa: E402
from sim.sweep import run_sweep, sweep_specs  # noqa: E402
from tests.conftest import LAB_URDF, SHARED  # noqa: E402
from tests.conftest import csv_rows as _csv  # noqa: E402

PHYSICAL = SHARED / "ref" / "physical_robot"


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    """Built-in robot, paper protocol, Cv 0.5, 3.5 s trials: at 74 deg every trial rights on its first attempt;
    at 78 deg the first attempt fails and the second rights in time only for some seeds."""
    path = tmp_path_factory.mktemp("db") / "t.sqlite"
    specs = sweep_specs((74.0, 78.0), (30.0,), (0.5,), phase=(0.1,), trials=4, duration_s=3.5, dt_s=1e-3)
    run_sweep(specs, db=path, workers=1, progress=False)
    return path


@pytest.fixture(scope="module")
def section(db, tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    return sections.section_trajectories(sections.load_rows(db), out, db, step_deg=3.0), out


def _colour_pixels(png, hex_colour, tol=30):
    import matplotlib.image as mpimg

    img = (mpimg.imread(png)[:, :, :3] * 255).astype(int)
    rgb = np.array([int(hex_colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(img - rgb).max(axis=2) <= tol).sum()), float(img.std())


def test_trajectories_is_a_report_section():
    assert sections.SECTIONS["trajectories"] is sections.section_trajectories


@pytest.mark.e2e  # reruns stored trials
def test_the_setting_with_mixed_outcomes_is_rerun_and_reproduces_the_stored_outcomes(db, section):
    sec, out = section
    rows = read_rows(db)
    by_setting = {}
    for r in rows:
        by_setting.setdefault(r["theta_w_deg"], []).append(r)
    mixed = [w for w, rs in by_setting.items() if 0 < sum(r["success"] for r in rs) < len(rs)]
    assert mixed == [78.0]  # the database was made so: one setting on the boundary
    assert sec.missing is None
    k = sum(r["success"] for r in by_setting[78.0])
    assert "θw 78°, θl 30°, Cv 50 %, φ1 = 0.1" in sec.paragraphs[0]
    assert f"where {k} of 4 trials righted" in sec.paragraphs[0]
    reruns = _csv(sec.tables[0].csv)
    assert len(reruns) == 4  # fewer trials than the default bound: all of them
    stored = {r["seed"]: r for r in by_setting[78.0]}
    for x in reruns:
        s = stored[int(x["seed"])]
        assert int(x["stored_success"]) == int(s["success"]) == int(x["rerun_success"])
        if s["success"]:
            assert float(x["rerun_time_to_right_s"]) == pytest.approx(s["time_to_right_s"], abs=1e-6)
        else:
            assert x["rerun_time_to_right_s"] == ""
        assert x["reproduced"] == "1"
    assert "Every rerun reproduces its stored outcome" in " ".join(sec.paragraphs)


@pytest.mark.e2e  # reruns stored trials
def test_the_figures_exist_and_draw_both_outcomes(section):
    sec, out = section
    contour = sec.figures[0]
    assert contour.png == out / "trajectories" / "trajectories_contour.png" and contour.svg.is_file()
    n_ok, std = _colour_pixels(contour.png, tj.RIGHTED_COLOUR)
    n_no, _ = _colour_pixels(contour.png, tj.NOT_RIGHTED_COLOUR, tol=8)
    assert std > 30 and n_ok > 100 and n_no > 100
    svg = contour.svg.read_text()
    reruns = _csv(sec.tables[0].csv)
    k = sum(int(x["rerun_success"]) for x in reruns)
    assert len(re.findall(r'id="attempt-\d+-righted"', svg)) == k
    assert len(re.findall(r'id="attempt-\d+-not-righted"', svg)) == len(reruns) - k
    if rd.off_screen_problem() is not None:
        assert len(sec.figures) == 1 and "3-D rendering is unavailable" in sec.paragraphs[-1]
    else:
        assert len(sec.figures) == 2
        n3, std3 = _colour_pixels(sec.figures[1].png, tj.RIGHTED_COLOUR)
        assert std3 > 30 and n3 > 100


@pytest.mark.e2e  # reruns stored trials
def test_the_bound_keeps_both_outcomes_and_3d_off_draws_the_contour_only(db, tmp_path, monkeypatch):
    monkeypatch.setattr(rd, "off_screen_problem", lambda: "no OpenGL (test)")
    sec = sections.section_trajectories(sections.load_rows(db), tmp_path, db, max_trials=2, step_deg=6.0)
    reruns = _csv(sec.tables[0].csv)
    assert sorted(int(x["rerun_success"]) for x in reruns) == [0, 1]
    assert len(sec.figures) == 1 and not (tmp_path / "trajectories" / "trajectories.png").exists()
    assert "3-D rendering is unavailable here (no OpenGL (test))" in sec.paragraphs[-1]
    with pytest.raises(ValueError, match="max_trials must be at least 1"):
        sections.section_trajectories(sections.load_rows(db), tmp_path, db, max_trials=0)


@pytest.mark.e2e  # reruns stored trials
def test_a_rerun_that_differs_from_the_stored_row_is_reported(db, tmp_path):
    rows = sections.load_rows(db)
    for r in rows:
        if r["success"] and r["theta_w_deg"] == 78.0:
            r["time_to_right_s"] += 0.01  # the stored outcome no longer matches the simulation
    sec = sections.section_trajectories(rows, tmp_path, db, step_deg=6.0)
    reruns = _csv(sec.tables[0].csv)
    bad = sum(x["reproduced"] == "0" for x in reruns)
    assert bad == sum(int(x["stored_success"]) for x in reruns) > 0
    assert f"Only {len(reruns) - bad} of {len(reruns)} reruns reproduce" in sec.paragraphs[1]


def test_without_paper_protocol_trials_the_section_says_what_to_run(tmp_path):
    rows = [
        dict(
            status="ok",
            attempts=1,
            theta_w_deg=74.0,
            theta_l_deg=30.0,
            cv=0.0,
            phase=0.1,
            wing_period_s=2.0,
            leg_period_s=0.8,
            duration_s=2.0,
            dt_s=1e-3,
            success=True,
            robot_hash="h",
        )
    ]
    sec = sections.section_trajectories(rows, tmp_path, tmp_path / "x.sqlite")
    assert "run `landscape sweep --db" in sec.missing and not sec.figures


# ------------------------------------------------------------------------------------------------ physical robot
needs_physical = pytest.mark.skipif(
    not (PHYSICAL / "robot_attempts.mat").is_file() or not LAB_URDF.is_file(),
    reason=f"{PHYSICAL} or {LAB_URDF} is absent (set LANDSCAPE_SHARED)",
)


@pytest.mark.shared
@needs_physical
def test_physical_section_draws_each_wing_command_and_tables_the_cells(tmp_path, monkeypatch):
    from landscape.analysis.physical.attempts import physical_attempts
    from landscape.analysis.physical.cells import PhysicalCell
    from landscape.analysis.physical.outcome import physical_trials
    from landscape.analysis.physical.recording import WING_COMMANDS_DEG

    monkeypatch.setattr(rd, "off_screen_problem", lambda: "no OpenGL (test)")  # contour maps only: quick
    sec = sections.section_physical([], tmp_path, tmp_path / "x.sqlite", data_dir=PHYSICAL, robot=LAB_URDF)
    assert sec.missing is None and len(sec.figures) == len(WING_COMMANDS_DEG)
    text = " ".join(sec.paragraphs)
    assert "of the lab's robot, drawn over" not in text  # the landscape is the lab robot's
    for cmd, fig in zip(WING_COMMANDS_DEG, sec.figures, strict=True):
        attempts = physical_attempts(PHYSICAL, theta_w_cmd_deg=cmd, theta_l_deg=0.0)
        n_ok = sum(a.righted for a in attempts)
        assert fig.png == tmp_path / "physical" / f"wing_{cmd:g}" / "trajectories_contour.png"
        assert f"Wing command {cmd:g}°" in text and f"{len(attempts)} attempts of" in text
        svg = fig.svg.read_text()
        assert f"{len(attempts)} physical attempts: {n_ok} righted" in svg
        assert _colour_pixels(fig.png, tj.RIGHTED_COLOUR)[1] > 30
    assert "wing 82.1°" in sec.figures[-1].svg.read_text()  # 90 deg command: the measured plateau
    cells = _csv(sec.tables[0].csv)
    trials = physical_trials(PHYSICAL)
    assert sum(int(c["n"]) for c in cells) == len(trials)
    assert sum(int(c["successes"]) for c in cells) == sum(t.success for t in trials)
    assert list(cells[0]) == list(PhysicalCell.CSV_COLUMNS)
