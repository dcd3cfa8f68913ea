"""Measured actuation (landscape/analysis/physical/measured.py, the measured profile of sim/actuation.py and the physical set)."""

import os
from pathlib import Path

import numpy as np
import pytest

from sim.actuation import leg_profile_deg, wing_joint_profiles_deg
from sim.model_set import ModelSetError, load_model_set
from sim.trial import run_trial
from sim.world import Contact

SHARED = Path(os.environ.get("LANDSCAPE_SHARED", Path(__file__).resolve().parents[2] / ".." / "shared"))
DATA = SHARED / "ref" / "physical_robot"
needs_data = pytest.mark.skipif(not (DATA / "motor_pulse_v2.mat").is_file(), reason="no physical robot data")
PHYSICAL_TEXT = (Path(__file__).resolve().parents[2] / "sim" / "models" / "physical.toml").read_text()


def test_measured_knots_drive_each_wing_joint_its_own_way():
    act = load_model_set("physical").actuation(75.0, 30.0)
    ks, kd = act.measured.wing_knots(75.0)
    # at a knot each joint is at that knot's angle, one attempt later the same again
    for j in range(4):
        a, _ = wing_joint_profiles_deg(ks[j, 2:6] + 0.3, [0.3, 2.3], act, n_wing=4)
        np.testing.assert_allclose(a[:, j], kd[j, 2:6], atol=1e-9)
        b, _ = wing_joint_profiles_deg(ks[j, 2:6] + 2.3, [0.3, 2.3], act, n_wing=4)
        np.testing.assert_allclose(b[:, j], kd[j, 2:6], atol=1e-9)
    a, _ = wing_joint_profiles_deg([0.6], [0.3], act, n_wing=4)
    assert np.ptp(a) > 1.0  # left and right differ
    # between commands each knot is linear in the command
    lo, hi = act.measured.wing_knots(60.0), act.measured.wing_knots(90.0)
    mid = load_model_set("physical").actuation(67.5, 0.0).measured.wing_knots(67.5)
    np.testing.assert_allclose(mid[1], (act.measured.wing_knots(60.0)[1] + kd) / 2, atol=1e-12)
    assert lo[1][:, 4].mean() < kd[:, 4].mean() < hi[1][:, 4].mean()
    # the wings are closed until the first attempt and after the last knot
    a, w = wing_joint_profiles_deg([0.0, 0.29, 0.3 + ks[:, -1].max() + 0.01], [0.3], act, n_wing=4)
    np.testing.assert_allclose(a, np.repeat(kd[None, :, 0], 3, 0), atol=1e-12)
    assert not w.any()


def test_measured_speed_is_the_slope_and_the_leg_is_periodic():
    act = load_model_set("physical").actuation(90.0, 45.0)
    t = np.linspace(0.0, 4.0, 40001)
    a, w = wing_joint_profiles_deg(t, [0.1, 2.1], act, n_wing=4)
    fd = np.diff(a, axis=0) / np.diff(t)[:, None]
    assert (np.isclose(fd, w[:-1], atol=1e-6).mean()) > 0.995  # off only at the kinks
    la, lw = leg_profile_deg(t, act)
    np.testing.assert_allclose(leg_profile_deg(t + 0.8, act)[0], la, atol=1e-9)
    assert la[0] == 0.0 and lw[0] > 0  # upward midline crossing at t = 0, as the idealised leg
    ks, kd = act.measured.leg_knots(22.5)
    np.testing.assert_allclose(kd, (act.measured.leg_knots(15.0)[1] + act.measured.leg_knots(30.0)[1]) / 2)
    np.testing.assert_allclose(act.measured.leg_knots(7.5)[1], act.measured.leg_knots(15.0)[1] / 2)


@pytest.mark.parametrize(
    "tw,tl,match",
    [(59.0, 30.0, r"outside the measured wing commands \[60, 90\]"), (75.0, 46.0, r"leg commands \[0, 45\]")],
)
def test_commands_outside_the_measured_range_are_refused(tw, tl, match):
    with pytest.raises(ValueError, match=match):
        load_model_set("physical").actuation(tw, tl)


@pytest.mark.parametrize(
    "edit,match",
    [
        (("wing_command_deg = [60, 75, 90]", "wing_command_deg = [60, 90, 75]"), "must be increasing"),
        (("[actuation.wing.RR]", "[actuation.wing.XX]"), "unknown key 'XX'"),
        (("knots_s = [[0, 0.0649", "knots_s = [[0.01, 0.0649"), "must start at 0"),
        (('profile = "measured"', 'profile = "measured"\nwing_open_deg_s = 270.0'), "unknown key"),
    ],
)
def test_a_bad_measured_set_is_refused(tmp_path, edit, match):
    f = tmp_path / "bad.toml"
    assert edit[0] in PHYSICAL_TEXT
    f.write_text(PHYSICAL_TEXT.replace(*edit, 1))
    with pytest.raises(ModelSetError, match=match):
        load_model_set(f)


def test_mirrored_servo_sides_put_the_labs_left_servos_on_the_models_right_joints(tmp_path):
    mirrored = load_model_set("physical")
    f = tmp_path / "labelled.toml"
    line = 'servo_sides = "mirrored"'
    assert line in PHYSICAL_TEXT
    f.write_text(PHYSICAL_TEXT.replace(line, 'servo_sides = "as-labelled"'))
    labelled = load_model_set(f)
    m, a = mirrored.measured, labelled.measured
    assert [m.wing_knots_deg[i] for i in (1, 0, 3, 2)] == list(a.wing_knots_deg)
    assert [m.wing_knots_s[i] for i in (1, 0, 3, 2)] == list(a.wing_knots_s)
    assert m.leg_knots_deg == a.leg_knots_deg and mirrored.model_set_hash != labelled.model_set_hash
    # the default is as labelled, and it keeps the hash a set had before the key existed
    f.write_text(
        PHYSICAL_TEXT.replace(line + "  # the lab's left servos drive the model's right joints\n", "")
    )
    assert load_model_set(f).model_set_hash == labelled.model_set_hash
    f.write_text(PHYSICAL_TEXT.replace(line, 'servo_sides = "left"'))
    with pytest.raises(ModelSetError, match="servo_sides must be one of as-labelled, mirrored"):
        load_model_set(f)


def test_wing_extra_opens_each_plateau_further_and_keeps_the_closed_wings(tmp_path):
    base = load_model_set("physical")
    f = tmp_path / "extra.toml"
    line = "servo_sides = \"mirrored\"  # the lab's left servos drive the model's right joints"
    assert line in PHYSICAL_TEXT
    f.write_text(PHYSICAL_TEXT.replace(line, line + "\nwing_extra_deg = 6.0", 1))
    extra = load_model_set(f)
    assert extra.model_set_hash != base.model_set_hash
    for b_servo, e_servo in zip(base.measured.wing_knots_deg, extra.measured.wing_knots_deg, strict=True):
        for b_row, e_row in zip(b_servo, e_servo, strict=True):
            assert max(e_row) == pytest.approx(max(b_row) + 6.0)  # the plateau, 6 deg further open
            assert e_row[0] == b_row[0] and e_row[-1] == b_row[-1] < 0  # closed stays closed
            ratio = [e / b for e, b in zip(e_row, b_row, strict=True) if b > 0]
            assert ratio == pytest.approx([1.0 + 6.0 / max(b_row)] * len(ratio))
    # 0 changes the knots but not the meaning: the same profile under another hash
    f.write_text(PHYSICAL_TEXT.replace(line, line + "\nwing_extra_deg = 0", 1))
    assert load_model_set(f).measured == base.measured
    # one value per wing command (60, 75, 90)
    f.write_text(PHYSICAL_TEXT.replace(line, line + "\nwing_extra_deg = [6.0, 0.0, 3.0]", 1))
    per = load_model_set(f).measured.wing_knots_deg
    for b_servo, p_servo in zip(base.measured.wing_knots_deg, per, strict=True):
        assert [max(r) for r in p_servo] == pytest.approx(
            [max(b_servo[0]) + 6.0, max(b_servo[1]), max(b_servo[2]) + 3.0]
        )
    for bad, match in (
        ("25.0", r"wing_extra_deg must be in \[0, 20\]"),
        ("-1.0", "wing_extra_deg"),
        ("[6.0, 0.0]", r"one number or one per wing command \(3\)"),
    ):
        f.write_text(PHYSICAL_TEXT.replace(line, line + "\nwing_extra_deg = " + bad, 1))
        with pytest.raises(ModelSetError, match=match):
            load_model_set(f)


def test_a_profile_beyond_the_wing_joints_range_is_refused_not_clamped(tmp_path):
    """physical's roll servo plateaus at 83.06 deg at command 90: 15 deg further passes the joints' 95 deg."""
    from geometry.errors import JointLimitError

    line = "servo_sides = \"mirrored\"  # the lab's left servos drive the model's right joints"
    f = tmp_path / "extra.toml"
    f.write_text(PHYSICAL_TEXT.replace(line, line + "\nwing_extra_deg = 15.0", 1))
    ms = load_model_set(f)
    with pytest.raises(
        JointLimitError, match=r"to 98\.0\d deg at wing command 90 deg, outside .* \[-10, 95\]"
    ):
        run_trial(90.0, 0.0, phase=0.0, cv=0.0, rng=0, model_set=ms, duration_s=1.0)
    run_trial(60.0, 0.0, phase=0.0, cv=0.0, rng=0, model_set=ms, duration_s=1.0)  # 74.1 deg at most: fine


def test_the_hash_covers_the_knots_and_the_contact_keys(tmp_path):
    base = load_model_set("physical").model_set_hash
    f = tmp_path / "a.toml"
    f.write_text(PHYSICAL_TEXT.replace("-1.49, 14.77", "-1.49, 14.78", 1))
    assert load_model_set(f).model_set_hash != base
    f.write_text(
        PHYSICAL_TEXT.replace("solver_iterations = 20", "solver_iterations = 20\nrolling_friction = 0.01")
    )
    assert load_model_set(f).contact.rolling_friction == 0.01 and load_model_set(f).model_set_hash != base
    f.write_text(
        PHYSICAL_TEXT.replace("solver_iterations = 20", "solver_iterations = 20\nrolling_friction = 0.0")
    )
    assert load_model_set(f).model_set_hash == base  # 0 is the default: the same model
    f.write_text(
        PHYSICAL_TEXT.replace("solver_iterations = 20", "solver_iterations = 20\nspinning_friction = 0.5")
    )
    with pytest.raises(ModelSetError, match=r"spinning_friction must be in \[0, 0.1\]"):
        load_model_set(f)
    with pytest.raises(ValueError, match="rolling_friction must be a number in"):
        Contact(rolling_friction=-0.1)


def test_the_measured_profile_drives_the_joints():
    ms = load_model_set("physical")
    r = run_trial(75.0, 0.0, phase=0.0, cv=0.0, rng=1, duration_s=1.6, trace=True, model_set=ms)
    assert r.model_set == "physical" and r.model_set_hash == ms.model_set_hash
    tr = r.trace
    act = ms.actuation(75.0, 0.0)
    ref, _ = wing_joint_profiles_deg(tr.t_s, [0.0], act, n_wing=4)
    np.testing.assert_allclose(tr.wing_cmd_deg, ref.mean(axis=1), atol=0.6)  # the command: the fitted profile
    hold = (tr.t_s > 0.5) & (tr.t_s < 1.0)
    # the joints reach the measured plateau (mean of the four servos), not the command 75 or paper's profile
    assert abs(tr.wing_deg[hold].mean() - ref[hold].mean()) < 1.5
    paper = run_trial(75.0, 0.0, phase=0.0, cv=0.0, rng=1, duration_s=1.6, trace=True)
    assert abs(paper.trace.wing_deg[hold].mean() - 75.0) < 1.5
    # the joints follow the fitted profile within the servo's lag (10 ms at up to ~600 deg/s), the paper's do not
    assert np.abs(tr.wing_deg - ref.mean(axis=1)).max() < 2.0
    assert np.abs(paper.trace.wing_deg - ref.mean(axis=1)).max() > 20.0


@needs_data
def test_the_shipped_knots_reproduce_the_traces_and_regenerate():
    from landscape.analysis.physical.measured import (
        _loadmat,
        _wing_samples,
        fit_leg_profiles,
        fit_wing_profiles,
        measured_actuation_toml,
    )

    ms = load_model_set("physical")
    pulse = _loadmat(DATA / "motor_pulse_v2.mat")["pulse"]
    bound = {60.0: 3.0, 75.0: 3.0, 90.0: 7.5}  # at 90 deg the first cycle lags the periodic one by ~40 ms
    # physical.toml mirrors the servos onto the joints: the lab's LP drives the model's right pitch joint, ...
    for servo, j in zip(("LP", "RP", "LR", "RR"), (1, 0, 3, 2), strict=True):
        for c, cmd in enumerate(ms.measured.wing_command_deg):
            ks, kd = ms.measured.wing_knots_s[j][c], ms.measured.wing_knots_deg[j][c]
            _, _, parts = _wing_samples(pulse, int(cmd), servo)
            for tau, y in parts.values():
                assert np.abs(np.interp(tau, ks, kd) - y).max() < bound[cmd], (servo, cmd)
    wing = fit_wing_profiles(DATA / "motor_pulse_v2.mat")
    s = wing["summary"]
    assert [round(x["plateau_deg"], 0) for x in s] == [57.0, 73.0, 80.0]
    assert 260 < s[0]["open_deg_s"] < 280 and 260 < s[1]["open_deg_s"] < 280
    assert all(400 < x["close_deg_s"] < 460 for x in s)
    leg = fit_leg_profiles(DATA / "vib_pulse_v2.mat")
    assert max(leg["max_error_deg"]) < 2.5
    text = measured_actuation_toml(DATA, servo_sides="mirrored")
    assert text in PHYSICAL_TEXT  # the shipped block is what the function generates


def test_the_legs_lag_to_the_midline_is_read_modulo_the_half_period(tmp_path):
    """A leg that crosses the midline 0.05, 0.07 and 0.1 s after each command change (every 0.4 s) gives those
    lags, whatever its shape."""
    from scipy.io import savemat

    from landscape.analysis.physical.measured import leg_crossing_lag_s

    t = np.arange(0.0, 4.0, 0.002)
    traces = {
        f"Vib{a}": a * np.sin(2 * np.pi * (t - lag) / 0.8 + np.pi)
        for a, lag in ((15, 0.05), (30, 0.07), (45, 0.1))
    }
    savemat(tmp_path / "v.mat", {"tVib": t[None, :], **{k: v[:, None] for k, v in traces.items()}})
    got = leg_crossing_lag_s(tmp_path / "v.mat")
    assert got == {
        15.0: pytest.approx(0.05, abs=1e-3),
        30.0: pytest.approx(0.07, abs=1e-3),
        45.0: pytest.approx(0.1, abs=1e-3),
    }


@pytest.mark.skipif(
    not (DATA / "vib_pulse_v2.mat").is_file(), reason="../shared/ref/physical_robot is absent"
)
def test_the_robots_leg_takes_longer_to_the_midline_the_wider_it_swings():
    from landscape.analysis.physical.measured import leg_crossing_lag_s
    from landscape.analysis.physical.response import protocol_phases

    lag = leg_crossing_lag_s(DATA / "vib_pulse_v2.mat")
    assert lag == {
        15.0: pytest.approx(0.044, abs=2e-3),
        30.0: pytest.approx(0.067, abs=2e-3),
        45.0: pytest.approx(0.097, abs=2e-3),
    }
    phases = protocol_phases(DATA)
    assert len(phases) == 9 and all(leg > 0 for _, leg in phases)
    for (_, leg), p in phases.items():  # the command's lead, 0.2 s, minus the lag, over 0.8 s
        assert p == pytest.approx((0.2 - lag[leg]) / 0.8, abs=2e-3)
