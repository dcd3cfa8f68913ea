"""Simulated against physical (landscape/analysis/physical/validation.py): the statistics on hand-made trials with answers
worked out by hand, then `landscape physical validate` end to end on the built-in robot (needs ../shared's
physical data)."""

import json
import math

import pytest

from landscape.analysis.physical import validation as va
from landscape.analysis.physical.attempts import AttemptCount
from landscape.analysis.physical.outcome import PhysicalTrial
from landscape.cli import main
from tests.landscape.analysis.physical.lab import DATA, needs_data


def _phys(w, leg, k, n, ttr=1.0, side=1):
    return [
        PhysicalTrial(f"{w}_{leg}_{i}", w, w - 1.0, leg, i, i < k, ttr if i < k else math.nan,
                      1 if i < k else 5, side if i < k else 0, (side,) if i < k else (), 1 if i < k else 0, 10.0)
        for i in range(n)
    ]  # fmt: skip


def _row(w_sim, leg, success, *, attempt=1, starts=(0.5, 2.5, 4.5, 6.5, 8.5), ttr=2.0, side=1, ms="paper"):
    return {
        "theta_w_deg": w_sim,
        "theta_l_deg": leg,
        "status": "ok",
        "success": success,
        "attempt": attempt if success else None,
        "attempt_starts_s": list(starts),
        "time_to_right_s": ttr if success else None,
        "side": side if success else None,
        "model_set": ms,
        "model_set_hash": "h",
    }


def test_cells_agree_only_when_each_fraction_is_inside_the_others_interval():
    # physical 5/5 (Wilson [0.566, 1]); simulated 0/3 (Wilson [0, 0.562]): neither inside the other
    phys = _phys(75.0, 15.0, 5, 5) + _phys(60.0, 0.0, 0, 5)
    rows = [_row(74.0, 15.0, False) for _ in range(3)] + [_row(59.0, 0.0, False) for _ in range(3)]
    v = va.compare(phys, rows, [(60.0, 0.0), (75.0, 15.0)], {60.0: 59.0, 75.0: 74.0})
    by = {(c.theta_w_cmd_deg, c.theta_l_deg): c for c in v.cells}
    assert not by[(75.0, 15.0)].agree and by[(60.0, 0.0)].agree
    assert by[(75.0, 15.0)].split == "held-out" and by[(60.0, 0.0)].split == "fit"
    assert v.agree_counts == {"fit": (1, 1), "held-out": (0, 1), "all": (1, 2)}
    # log-likelihood by hand: p = 0.5 / 4 for both cells
    assert v.log_likelihood["held-out"] == pytest.approx(5 * math.log(0.125))
    assert v.log_likelihood["fit"] == pytest.approx(5 * math.log(0.875))
    assert v.log_likelihood["all"] == pytest.approx(v.log_likelihood["fit"] + v.log_likelihood["held-out"])


def test_fishers_test_counts_the_cells_the_trials_cannot_tell_apart():
    """5/5 against 17/20 disagrees by the Wilson rule (100 % lies outside [64, 95] %) but the trials cannot tell
    them apart (Fisher p = 1); 0/5 against 10/10 differs by both (p = 1/3003, the one table as extreme)."""
    from landscape.viz.physical_plots import consistent_text, validation_markdown

    phys = _phys(75.0, 15.0, 5, 5) + _phys(60.0, 0.0, 0, 5)
    rows = [_row(74.0, 15.0, i < 17) for i in range(20)] + [_row(59.0, 0.0, True) for _ in range(10)]
    v = va.compare(phys, rows, [(60.0, 0.0), (75.0, 15.0)], {60.0: 59.0, 75.0: 74.0})
    by = {(c.theta_w_cmd_deg, c.theta_l_deg): c for c in v.cells}
    assert not by[(75.0, 15.0)].agree and by[(75.0, 15.0)].fisher_p == pytest.approx(1.0)
    assert not by[(60.0, 0.0)].agree and by[(60.0, 0.0)].fisher_p == pytest.approx(1 / 3003)
    text = consistent_text(v)
    assert text.startswith("cells the trials cannot tell apart (Fisher's exact test, p >= 0.05): 1 of 2 ")
    assert "(fit 0 of 1, held-out 1 of 1); apart: 60°/0° p = 0.000" in text
    assert text in validation_markdown(v)
    # a validation.json from before the test was stored has no p-values: no line, and it still loads
    doc = {"model_set": "m", "model_set_hash": "h", "attempts": [], "agree_counts": v.agree_counts,
           "log_likelihood": v.log_likelihood, "side": v.side.__dict__,
           "cells": [{k: getattr(c, k) for k in va.CellComparison.CSV_COLUMNS if k != "fisher_p"} for c in v.cells]}  # fmt: skip
    old = va.validation_from_json(doc)
    assert math.isnan(old.cells[0].fisher_p) and consistent_text(old) == ""


def test_robot_attempts_counts_the_robots_rightings_within_its_first_openings_only():
    """Two robot trials right at openings 6 and 8 (the lab kept trying past its 10 s): with robot_attempts 5 they
    count as not righted, with their times to right, and are listed; every other number stays."""
    from dataclasses import replace

    from landscape.viz.physical_plots import validation_markdown

    phys = _phys(60.0, 15.0, 4, 5, ttr=3.0)
    phys = [replace(t, attempts=a, time_to_right_s=10.0 + a) if a > 5 else t
            for t, a in zip(phys, (6, 2, 3, 8, 10), strict=True)]  # fmt: skip
    rows = [_row(59.0, 15.0, i < 3) for i in range(20)]
    every = va.compare(phys, rows, [(60.0, 15.0)], {60.0: 59.0})
    first5 = va.compare(phys, rows, [(60.0, 15.0)], {60.0: 59.0}, robot_attempts=5)
    (a,), (b,) = every.cells, first5.cells
    assert (a.phys_k, b.phys_k, a.phys_n, b.phys_n) == (4, 2, 5, 5)
    assert a.phys_ttr_median_s == pytest.approx(9.5) and b.phys_ttr_median_s == pytest.approx(
        3.0
    )  # 3, 3, 16, 18
    assert every.late_rightings == () and every.robot_attempts is None
    assert first5.late_rightings == ((60.0, 15.0, 6), (60.0, 15.0, 8)) and first5.robot_attempts == 5
    assert a.sim_k == b.sim_k and every.side == first5.side
    text = validation_markdown(first5)
    assert (
        "within their first 5 openings (--robot-attempts): 2 later rightings left out (60°/15° at opening 6, 8)"
        in text
    )
    assert "--robot-attempts" not in validation_markdown(every)
    for bad in (0, 2.5, True):
        with pytest.raises(va.ValidationError, match="robot_attempts must be a whole number"):
            va.compare(phys, rows, [(60.0, 15.0)], {60.0: 59.0}, robot_attempts=bad)
    # the JSON round trip keeps both
    import dataclasses

    doc = json.loads(json.dumps(dataclasses.asdict(first5)))
    back = va.validation_from_json(doc)
    assert back.robot_attempts == 5 and back.late_rightings == first5.late_rightings


def test_time_to_right_counts_from_the_first_opening_and_sides_are_counted():
    phys = _phys(90.0, 30.0, 4, 5, ttr=2.0, side=1)
    rows = [
        _row(89.0, 30.0, True, ttr=3.5, starts=(0.5, 2.5), attempt=2, side=1),
        _row(89.0, 30.0, True, ttr=1.5, starts=(0.5,), side=-1),
        _row(89.0, 30.0, False),
    ]
    v = va.compare(phys, rows, [(90.0, 30.0)], {90.0: 89.0})
    (c,) = v.cells
    assert (c.sim_k, c.sim_n) == (2, 3) and c.agree  # 2/3 vs 4/5
    assert c.sim_ttr_median_s == pytest.approx(2.0)  # (3.0 + 1.0) / 2
    assert c.sim_ttr_sd_s == pytest.approx(math.sqrt(2.0))
    assert c.phys_ttr_median_s == 2.0 and c.phys_ttr_sd_s == 0.0
    s = v.side
    assert (s.phys_positive, s.phys_events, s.sim_positive, s.sim_events) == (4, 4, 1, 2)
    assert not s.sim_inside_phys  # 50 % is below the robot's Wilson interval for 4/4 ([0.51, 1])


def test_per_attempt_rates_only_when_every_leg_of_a_wing_command_ran():
    phys = _phys(60.0, 0.0, 0, 5) + _phys(60.0, 15.0, 2, 5)
    rows = [_row(59.0, 0.0, False, starts=(0.5, 2.5, 4.5, 6.5, 8.5, 9.9))] + [
        _row(59.0, 15.0, True, attempt=3, ttr=5.0)
    ]
    rec = [AttemptCount(60.0, 59.0, 12, 2, 2 / 12, 0.05, 0.45)]
    full = va.compare(phys, rows, [(60.0, 0.0), (60.0, 15.0)], {60.0: 59.0}, rec)
    (a,) = full.attempts
    assert (a.simulated.successes, a.simulated.attempts) == (1, 5 + 3)  # 5 counted of 6 openings, then 3
    part = va.compare(phys, rows, [(60.0, 15.0)], {60.0: 59.0}, rec)
    assert part.attempts == ()  # the record pools leg 0 too, which did not run


def test_one_model_set_at_a_time_and_both_sides_of_a_cell_needed():
    phys = _phys(60.0, 0.0, 0, 5)
    with pytest.raises(va.ValidationError, match="mix model sets"):
        va.compare(
            phys, [_row(59.0, 0.0, False), _row(59.0, 0.0, False, ms="physical")], [(60.0, 0.0)], {60.0: 59.0}
        )
    with pytest.raises(va.ValidationError, match="0 simulated"):
        va.compare(phys, [], [(60.0, 0.0)], {60.0: 59.0})


def test_cells_parse_and_unknown_cells_are_refused():
    avail = [(60.0, 0.0), (75.0, 15.0)]
    assert va.parse_cells(None, avail) == avail
    with pytest.raises(va.ValidationError, match="not a recorded cell; the recorded cells are 60:0, 75:15"):
        va.parse_cells("60:45", avail)
    with pytest.raises(va.ValidationError, match="not WING:LEG"):
        va.parse_cells("60-45", avail)


def test_phases_are_random_reproducible_and_per_cell():
    a = va.cell_phases(60.0, 0.0, 10, 0)
    assert a == va.cell_phases(60.0, 0.0, 10, 0) and a != va.cell_phases(60.0, 15.0, 10, 0)
    assert a != va.cell_phases(60.0, 0.0, 10, 1)
    assert all(0.0 <= x < 1.0 for x in a) and len(set(a)) == 10


def test_a_fixed_phase_gives_every_trial_that_phase_and_its_own_seed():
    specs = va.validation_specs([(75.0, 15.0), (60.0, 0.0)], {75.0: 73.6, 60.0: 59.1}, trials=4, phase=0.17)
    assert len(specs) == 8 and {s.phase for s in specs} == {0.17}
    assert len({(s.theta_w_deg, s.seed) for s in specs}) == 8
    assert {s.theta_w_deg for s in specs} == {73.6, 59.1}  # the paper set runs at the measured plateaus
    random = va.validation_specs([(75.0, 15.0)], {75.0: 73.6}, trials=4)
    assert [s.phase for s in random] == va.cell_phases(75.0, 15.0, 4, 0)
    for bad in (1.0, -0.1, math.nan):
        with pytest.raises(va.ValidationError, match=r"--phase must be a first-attempt phase in \[0, 1\)"):
            va.validation_specs([(75.0, 15.0)], {75.0: 73.6}, phase=bad)


def test_a_phase_per_cell_gives_each_cell_its_own_and_the_leg_still_the_protocols():
    from landscape.analysis.physical.response import PROTOCOL_PHASE

    cells = [(75.0, 15.0), (75.0, 45.0), (60.0, 0.0)]
    specs = va.validation_specs(
        cells, {75.0: 73.6, 60.0: 59.1}, trials=2, phase={(75, 15): 0.195, (75, 45): 0.129}
    )
    by = {(s.theta_w_deg, s.theta_l_deg): s.phase for s in specs}
    assert by == {(73.6, 15.0): 0.195, (73.6, 45.0): 0.129, (59.1, 0.0): PROTOCOL_PHASE} and len(specs) == 6
    with pytest.raises(
        va.ValidationError, match=r"--phase must be a first-attempt phase in \[0, 1\); got 1.2"
    ):
        va.validation_specs(cells, {75.0: 73.6}, phase={(75.0, 15.0): 1.2})


@pytest.mark.e2e  # dozens of simulated attempts at the lab robot's small step
@needs_data
def test_validate_command_end_to_end_and_resumes(tmp_path, capsys):
    args = [
        "physical",
        "validate",
        "--data",
        str(DATA),
        "--cells",
        "75:15",
        "--trials",
        "2",
        "--duration",
        "3",
    ]
    args += ["--out", str(tmp_path), "--no-progress", "--workers", "1"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "2 simulated trials: 0 already in" in out and "75° (73.6°) | 15° | 5/5 [57, 100] %" in out
    doc = json.loads((tmp_path / "validation.json").read_text())
    assert doc["model_set"] == "paper" and len(doc["cells"]) == 1 and doc["cells"][0]["sim_n"] == 2
    assert (tmp_path / "validation.csv").read_text().count("\n") == 2
    assert (tmp_path / "time_to_right.png").stat().st_size > 0 and (tmp_path / "time_to_right.svg").is_file()
    assert main(args) == 0  # rerun: every trial already stored
    assert "2 simulated trials: 2 already in" in capsys.readouterr().out
    # the robot's rightings after its first opening left out: 75°/15° righted at openings 1, 3, 3, 1, 1
    assert main([*args, "--robot-attempts", "1"]) == 0
    out = capsys.readouterr().out
    assert "75° (73.6°) | 15° | 3/5 [23, 88] %" in out
    assert "2 later rightings left out (75°/15° at opening 3, 3)" in out
    doc = json.loads((tmp_path / "validation.json").read_text())
    assert doc["robot_attempts"] == 1 and doc["late_rightings"] == [[75.0, 15.0, 3], [75.0, 15.0, 3]]
    assert main([*args, "--robot-attempts", "0"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert main([*args, "--imu-mounting", "11.5"]) == 0  # the robot judged in a pitched body frame
    assert json.loads((tmp_path / "validation.json").read_text())["imu_mount_deg"] == 11.5
    assert "the robot judged upright in a body frame pitched 11.5° below its IMU's (--imu-mounting)" in (
        capsys.readouterr().out
    )
    assert main([*args, "--imu-mounting", "60"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "IMU's mounting must lie within" in err
    # each cell at the phase the lab's protocol gives it: a new key in the store, so two new trials
    assert main([*args, "--phase", "protocol"]) == 0
    out = capsys.readouterr().out
    assert "first-attempt phases by the protocol: leg 15° 0.195, leg 30° 0.166, leg 45° 0.129" in out
    assert "2 simulated trials: 0 already in" in out
    doc = json.loads((tmp_path / "validation.json").read_text())
    assert doc["phase"] == "protocol" and doc["cell_phases"]["75:15"] == pytest.approx(0.195, abs=1e-3)


@needs_data
def test_validate_command_bad_input_is_one_line(tmp_path, capsys):
    base = ["physical", "validate", "--data", str(DATA), "--out", str(tmp_path), "--no-progress"]
    assert main(base + ["--cells", "61:0"]) == 2
    assert "is not a recorded cell" in capsys.readouterr().err
    assert main(base + ["--model", "nosuchset"]) == 2
    capsys.readouterr()
    assert main(base + ["--phase", "1.5"]) == 2
    err = capsys.readouterr().err
    assert "--phase 1.5 is outside [0, 1): a phase is a fraction of the leg period Tl" in err
    assert "Traceback" not in err and err.count("\n") == 1
    assert main(base + ["--phase", "sideways"]) == 2
    err = capsys.readouterr().err
    assert "--phase must be a number in [0, 1) or 'protocol'; got 'sideways'" in err and err.count("\n") == 1
    assert main(["physical", "validate", "--data", str(tmp_path / "nowhere"), "--out", str(tmp_path)]) == 2


@needs_data
def test_actuation_command_prints_the_shipped_block(tmp_path, capsys):
    from landscape.analysis.physical.measured import measured_actuation_toml

    assert main(["physical", "actuation", "--data", str(DATA), "--out", str(tmp_path / "a.toml")]) == 0
    out = capsys.readouterr().out
    assert "[actuation.wing.LP]" in out and (tmp_path / "a.toml").read_text() == measured_actuation_toml(DATA)
    assert main(["physical", "actuation", "--data", str(tmp_path)]) == 2
    assert "motor_pulse_v2.mat' not found" in capsys.readouterr().err


@needs_data
def test_the_protocols_phase_needs_the_legs_trace(tmp_path, capsys):
    """Without vib_pulse_v2.mat the kinematics say the phase is not measured and print the rest; validate at the
    protocol's phase refuses in one line."""
    for f in [*DATA.glob("run5_*.bag.mat"), DATA / "robot_attempts.mat"]:
        (tmp_path / f.name).symlink_to(f)
    assert main(["physical", "kinematics", "--data", str(tmp_path), "--no-model"]) == 0
    out = capsys.readouterr().out
    assert "the first attempt's leg phase under the protocol: not measured (data file" in out
    assert "roll-overs to + roll: 43 of 46" in out
    args = [
        "physical",
        "validate",
        "--data",
        str(tmp_path),
        "--phase",
        "protocol",
        "--out",
        str(tmp_path / "v"),
    ]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "vib_pulse_v2.mat' not found" in err
