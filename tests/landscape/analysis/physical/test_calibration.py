"""Calibration (landscape/analysis/physical/calibration.py): --vary parsing, candidate sets derived from a base set, and
`landscape physical calibrate` end to end on the built-in robot (needs ../shared's physical data)."""

import json
import math

import pytest

from landscape.analysis.physical import calibration as ca
from landscape.cli import main
from sim.model_set import ModelSetError, load_model_set
from tests.landscape.analysis.physical.lab import DATA, needs_data


def test_vary_parses_and_refuses_bad_items():
    assert ca.parse_vary(["contact.lateral_friction=0.5, 1", "contact.restitution=0.1"]) == {
        "contact.lateral_friction": [0.5, 1.0],
        "contact.restitution": [0.1],
    }
    for bad, match in [
        ("friction=0.5", "TABLE.KEY"),
        ("contact.x=a", "numbers"),
        ("contact.x=nan", "finite"),
        ("actuation.wing_extra_deg=15/x/3", "lists of numbers"),
        ("actuation.wing_extra_deg=15/nan/3", "finite"),
    ]:
        with pytest.raises(ca.CalibrationError, match=match):
            ca.parse_vary([bad])
    with pytest.raises(ca.CalibrationError, match="twice"):
        ca.parse_vary(["contact.restitution=0.1", "contact.restitution=0.2"])
    with pytest.raises(ca.CalibrationError, match="nothing to calibrate"):
        ca.parse_vary([])


def test_a_candidate_is_the_base_set_with_the_overrides_only(tmp_path):
    paper = load_model_set("paper")
    ms = ca.candidate_set("paper", {"contact.lateral_friction": 0.5}, "cand", tmp_path / "c.toml")
    assert ms.name == "cand" and ms.contact.friction == 0.5
    assert ms.contact.restitution == paper.contact.restitution and ms.model_set_hash != paper.model_set_hash
    with pytest.raises(ca.CalibrationError, match="has no such key"):
        ca.candidate_set("paper", {"contact.frcition": 0.5}, "c", tmp_path / "d.toml")
    with pytest.raises(ModelSetError):  # out of the set's range: the set's own validation refuses it
        ca.candidate_set("paper", {"contact.lateral_friction": -1.0}, "c", tmp_path / "e.toml")


def test_candidate_set_adds_an_optional_table_the_base_lacks(tmp_path):
    """Compliance is an optional table: a candidate may add it (calibrating wing compliance from a rigid set), and
    the set's own rules still apply (the stiffness is required once the table is there)."""
    ms = ca.candidate_set(
        "paper",
        {"compliance.wing_stiffness_n_m_rad": 2.0, "compliance.wing_damping_n_m_s_rad": 0.005},
        "soft",
        tmp_path / "soft.toml",
    )
    assert ms.compliance.wing_stiffness_n_m_rad == 2.0 and ms.compliance.wing_damping_n_m_s_rad == 0.005
    assert (
        ca.candidate_set(
            "paper", {"contact.rolling_friction": 0.01}, "r", tmp_path / "r.toml"
        ).contact.rolling_friction
        == 0.01
    )
    with pytest.raises(ModelSetError, match="wing_stiffness_n_m_rad"):
        ca.candidate_set("paper", {"compliance.wing_damping_n_m_s_rad": 0.005}, "d", tmp_path / "d.toml")
    with pytest.raises(ca.CalibrationError, match="has no such key"):
        ca.candidate_set("paper", {"compliance.wing_stifness": 1.0}, "t", tmp_path / "t.toml")


def test_a_candidate_may_take_a_list_and_the_mass_table(tmp_path):
    """`--vary actuation.wing_extra_deg=15/12/3` is one candidate with one extra per wing command; the `[mass]` CoM
    offset is an optional table a candidate may add."""
    assert ca.parse_vary(["actuation.wing_extra_deg=15/12/3,15"]) == {
        "actuation.wing_extra_deg": [[15.0, 12.0, 3.0], 15.0]
    }
    over = {"actuation.wing_extra_deg": [15.0, 12.0, 3.0], "mass.com_offset_y_mm": -1.5}
    ms = ca.candidate_set("physical", over, "cand", tmp_path / "c.toml")
    assert ms.com_offset_y_mm == -1.5
    base = load_model_set("physical").measured
    plateau = ms.measured.wing_plateaus_deg(75.0) - base.wing_plateaus_deg(75.0)
    assert plateau == pytest.approx([12.0] * 4, abs=1e-9)
    assert "wing_extra_deg = 15/12/3" in load_model_set(tmp_path / "c.toml").description
    with pytest.raises(ModelSetError, match="wing_extra_deg"):  # one per command: three, not two
        ca.candidate_set("physical", {"actuation.wing_extra_deg": [15.0, 12.0]}, "c", tmp_path / "d.toml")


def test_a_candidate_may_scale_one_wing_and_the_world_refuses_a_wrong_count(tmp_path):
    """`--vary compliance.wing_scale=1/0.6/1/0.6` (README: one softer wing) is one factor per wing joint on the
    base's compliance; a list of another length loads (the set knows no robot) and is refused by the trial."""
    from sim.compliance import ComplianceError
    from sim.trial import run_trial

    assert ca.parse_vary(["compliance.wing_scale=1/0.6/1/0.6"]) == {
        "compliance.wing_scale": [[1.0, 0.6, 1.0, 0.6]]
    }
    ms = ca.candidate_set(
        "physical-posed", {"compliance.wing_scale": [1.0, 0.6, 1.0, 0.6]}, "c", tmp_path / "c.toml"
    )
    base = load_model_set("physical-posed").compliance
    assert ms.compliance.wing_scale == (1.0, 0.6, 1.0, 0.6)
    assert ms.compliance.wing_stiffness_n_m_rad == base.wing_stiffness_n_m_rad
    short = ca.candidate_set("paper", {"compliance.wing_stiffness_n_m_rad": 0.9, "compliance.wing_scale": [1.0, 0.5]},
                             "d", tmp_path / "d.toml")  # fmt: skip
    with pytest.raises(ComplianceError, match="wing_scale has 2 factors for the robot's 4 wing joints"):
        run_trial(75.0, 0.0, phase=0.5, cv=0.0, rng=1, duration_s=0.5, model_set=short)


@pytest.mark.e2e
@needs_data
def test_calibrate_command_picks_the_likeliest_candidate_and_holds_cells_out(tmp_path, capsys):
    args = ["physical", "calibrate", "--data", str(DATA), "--base", "paper"]
    args += ["--vary", "contact.lateral_friction=0.5,1", "--trials", "1", "--validate-trials", "1"]
    args += ["--duration", "2", "--out", str(tmp_path), "--no-progress", "--workers", "2"]
    # every simulated trial at its cell's phase under the lab's protocol (the other calibrations: random phases),
    # the time to right scored too
    assert main([*args, "--phase", "protocol", "--time-to-right"]) == 0
    out = capsys.readouterr().out
    assert "first-attempt phases by the protocol: leg 15° 0.195, leg 30° 0.166, leg 45° 0.129" in out
    assert "[1/2] candidate000" in out and "[2/2] candidate001" in out and "held-out cells:" in out
    assert ", time to right " in out and "(score " in out
    doc = json.loads((tmp_path / "calibration.json").read_text())
    assert doc["phase"] == "protocol" and doc["cell_phases"]["60:30"] == pytest.approx(0.166, abs=1e-3)
    # the candidates' trials themselves ran at those phases (leg still: the protocol's one number)
    from landscape.analysis.physical.response import PROTOCOL_PHASE
    from sim.store import read_rows

    rows = [r for db in tmp_path.glob("trials_candidate*.sqlite") for r in read_rows(db)]
    assert {round(r["phase"], 3) for r in rows if r["theta_l_deg"] == 30.0} == {0.166}
    assert {r["phase"] for r in rows if r["theta_l_deg"] == 0.0} == {PROTOCOL_PHASE}
    times = [c["time_log_likelihood"] for c in doc["candidates"]]
    assert all(t <= 0.0 for t in times)  # finite: 0 without a fit cell where both right
    scores = [c["log_likelihood"] + t for c, t in zip(doc["candidates"], times, strict=True)]
    assert scores == sorted(scores, reverse=True)
    assert all(c["cells"] == 6 for c in doc["candidates"])  # fit cells only: legs 0 and 30
    assert {tuple(c) for c in doc["fit_cells"]} == {
        (w, leg) for w in (60.0, 75.0, 90.0) for leg in (0.0, 30.0)
    }
    assert (
        len(doc["validation"]["cells"]) == 12
        and load_model_set(tmp_path / "best.toml").name == "paper-calibrated"
    )
    assert main(args[:-5] + ["--fit-legs", "0,15", "--out", str(tmp_path)]) == 2
    assert "held-out" in capsys.readouterr().err
    assert main([*args, "--phase", "late"]) == 2
    assert "--phase must be a number in [0, 1) or 'protocol'; got 'late'" in capsys.readouterr().err


@pytest.mark.e2e
@needs_data
def test_calibrate_with_openings_and_side_ranks_by_their_sum(tmp_path, capsys):
    """--openings: each candidate also gets the log-likelihood of its first openings under the robot's (one per
    fit cell); --side: of the side the robot's fit-cell roll-overs went to under the candidate's; candidates rank
    by the sum, which is printed and stored (one run scores both)."""
    args = ["physical", "calibrate", "--data", str(DATA), "--base", "paper", "--openings", "--side"]
    args += ["--vary", "contact.lateral_friction=0.5,1", "--trials", "1", "--validate-trials", "1"]
    args += ["--duration", "2", "--out", str(tmp_path), "--no-progress", "--workers", "2"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "openings -" in out and ", side " in out and "(score -" in out
    doc = json.loads((tmp_path / "calibration.json").read_text())
    scores = [
        c["log_likelihood"] + c["opening_log_likelihood"] + c["side_log_likelihood"]
        for c in doc["candidates"]
    ]
    assert scores == sorted(scores, reverse=True) and all(math.isfinite(s) for s in scores)
    # without --phase the trials' phases are random, whatever phase the scored openings take
    from sim.store import read_rows

    phases = {r["phase"] for db in tmp_path.glob("trials_candidate*.sqlite") for r in read_rows(db)}
    assert len(phases) == 6  # one trial per fit cell, each cell its own random phase
    assert main(args[:-5] + ["--opening-phase", "1.2", "--out", str(tmp_path)]) == 2
    plain = [a for a in args if a != "--openings"]
    assert main([*plain, "--opening-phase", "0.3"]) == 2
    assert "give --openings as well" in capsys.readouterr().err


def test_the_side_score_favours_the_robots_side():
    """The robot's fit-cell roll-overs (17 of 18 to +roll) are likelier under a candidate that rolls to +roll
    more often; no roll-overs on either side are no evidence (0)."""
    from landscape.analysis.physical.validation import SideComparison

    def side(pos, n):
        return ca.side_log_likelihood(SideComparison(17, 18, 0, 0, pos, n, 0, 0, False))

    assert side(36, 40) > side(30, 40) > side(20, 40)
    assert side(0, 0) == 0.0
    assert ca.side_log_likelihood(SideComparison(0, 0, 0, 0, 5, 10, 0, 0, False)) == 0.0
    c = ca.Candidate("c", {}, "h", -5.0, 3, 6, side_log_likelihood=-2.0)
    assert c.score == -7.0 and "side_log_likelihood" in c.CSV_COLUMNS


@pytest.mark.e2e
@needs_data
def test_calibrate_runs_every_trial_in_the_chosen_engine(tmp_path, capsys):
    """--engine mujoco: the candidates' trials, their scored openings and the best one's validation all run in
    MuJoCo, stored under each set's MuJoCo hash; calibration.json names the engine."""
    pytest.importorskip("mujoco")
    from sim.store import read_rows

    args = [
        "physical",
        "calibrate",
        "--data",
        str(DATA),
        "--base",
        "paper",
        "--openings",
        "--engine",
        "mujoco",
    ]
    args += ["--vary", "contact.lateral_friction=1", "--trials", "1", "--validate-trials", "1"]
    args += ["--duration", "2", "--out", str(tmp_path), "--no-progress", "--workers", "1"]
    assert main(args) == 0, capsys.readouterr().err
    doc = json.loads((tmp_path / "calibration.json").read_text())
    cand = load_model_set(tmp_path / "candidates" / "candidate000.toml").with_engine("mujoco")
    best = load_model_set(tmp_path / "best.toml").with_engine("mujoco")
    assert doc["engine"] == "mujoco" and doc["candidates"][0]["model_set_hash"] == cand.model_set_hash
    assert math.isfinite(doc["candidates"][0]["opening_log_likelihood"])
    assert doc["validation"]["model_set_hash"] == best.model_set_hash
    dbs = {db.name: read_rows(db) for db in tmp_path.glob("trials_*.sqlite")}
    assert set(dbs) == {
        f"trials_candidate000_{cand.model_set_hash}.sqlite",
        f"trials_best_{best.model_set_hash}.sqlite",
    }
    assert {r["engine"] for rows in dbs.values() for r in rows} == {"mujoco"}
