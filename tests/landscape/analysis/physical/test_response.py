"""The first wing opening, recorded and simulated (landscape/analysis/physical/response.py): the measures on
synthetic series with known answers, a simulated opening of the symmetric built-in robot, and the lab's recordings
(skipped without ../shared)."""

import math

import numpy as np
import pytest

from landscape.analysis.physical.recording import sagittal_pitch_deg
from landscape.analysis.physical.response import (
    SWING_WINDOW_S,
    OpeningResponse,
    gyro_tilt_deviation_deg,
    lateral_tilt_deg,
    opening_log_likelihood,
    opening_response,
    recorded_first_openings,
    simulated_opening,
)
from tests.landscape.analysis.physical.lab import DATA, needs_data


def test_tilt_is_the_roll_when_level_and_vanishes_at_the_pole():
    roll = np.array([-40.0, -5.0, 0.0, 12.0, 70.0])
    assert np.allclose(lateral_tilt_deg(np.zeros(5), roll), roll)
    assert np.allclose(lateral_tilt_deg(np.full(5, 90.0), roll), 0.0, atol=1e-12)
    # closed form at pitch 60: sin(tilt) = cos 60 sin r
    assert lateral_tilt_deg(60.0, 30.0) == pytest.approx(math.degrees(math.asin(0.25)), abs=1e-12)


def _series(overshoot_deg=8.0, tilt_roll_deg=-20.0, start_s=0.4):
    t = np.arange(-0.6, 1.4, 0.01)
    tau = t - start_s
    pitch = np.where(tau < 0, 2.0, 2.0 + 60.0 * np.clip(tau / 0.25, 0.0, 1.0))
    pitch = pitch + overshoot_deg * ((tau > 0.3) & (tau < 0.35))
    roll = np.where((tau > 0.3) & (tau < 0.32), tilt_roll_deg, 1.0)
    return t, pitch, roll


def test_opening_response_reads_rest_hold_overshoot_rise_and_signed_tilt():
    t, pitch, roll = _series()
    r = opening_response(t, pitch, roll, 0.4)
    # the nose's pitch atan2(sin p, cos p cos r), at roll 1 deg a few thousandths above the ZYX pitch
    assert r.rest_pitch_deg == pytest.approx(float(sagittal_pitch_deg(2.0, 1.0)))
    assert r.hold_pitch_deg == pytest.approx(float(sagittal_pitch_deg(62.0, 1.0)))
    assert r.hold_pitch_deg == pytest.approx(62.0, abs=0.01)
    # the overshoot's peak is the sample rolled -20 deg at pitch 70: its nose stands at atan2(sin 70, cos 70 cos 20)
    assert r.overshoot_deg == pytest.approx(float(sagittal_pitch_deg(70.0, -20.0)) - r.hold_pitch_deg)
    assert r.rise_s == pytest.approx(0.13, abs=0.011)  # halfway (32 deg) at 0.125 s, sampled every 10 ms
    # the peak roll -20 deg at pitch 62 (+8 inside the overshoot): tilt = asin(cos 70 sin -20)
    assert r.tilt_deg == pytest.approx(
        math.degrees(math.asin(math.cos(math.radians(70)) * math.sin(math.radians(-20))))
    )


def test_wobble_is_the_spread_while_the_wings_hold():
    """A hold that keeps rocking (pitch +-2 deg, roll +-10 deg at pitch 60, a square wave in the hold window) has
    the standard deviations of those swings; a still one has none."""
    t = np.arange(-0.5, 1.2, 0.01)
    square = np.where(np.floor(t / 0.05) % 2 == 0, 1.0, -1.0)
    held = (t >= 0.45) & (t <= 1.0)
    pitch = np.where(t < 0.3, 0.0, 60.0) + np.where(held, 2.0 * square, 0.0)
    roll = np.where(held, 10.0 * square, 0.0)
    r = opening_response(t, pitch, roll, 0.0)
    win = (t >= 0.5) & (t <= 0.95)
    # the nose's pitch: tipped 10 deg sideways the body's nose stands a little higher than its ZYX pitch
    assert r.wobble_pitch_deg == pytest.approx(np.std(sagittal_pitch_deg(pitch[win], roll[win])))
    assert 1.9 < r.wobble_pitch_deg < 2.1
    assert r.wobble_tilt_deg == pytest.approx(np.std(lateral_tilt_deg(pitch[win], roll[win])))
    still = opening_response(t, np.where(t < 0.3, 0.0, 60.0), np.zeros_like(t), 0.0)
    assert still.wobble_pitch_deg == 0.0 and still.wobble_tilt_deg == 0.0


def test_a_nose_past_vertical_is_not_folded_back():
    """At the 90 deg command the robot's opening carries its nose past vertical, where the ZYX pitch folds back
    (nose 96 deg: pitch 84 deg, roll 180 deg). The hold, overshoot and rise read the nose's pitch: an opening that
    peaks 6 deg past vertical over a hold at 86 deg has an overshoot of 10 deg; the ZYX pitch sees a dip."""
    t = np.arange(-0.5, 1.2, 0.01)
    nose = np.where(t < 0, 0.0, 86.0 * np.clip(t / 0.3, 0.0, 1.0)) + 10.0 * ((t > 0.3) & (t < 0.4))
    # the same orientations as ZYX angles on the branch |pitch| <= 90 (what an IMU's quaternion gives)
    over = nose > 90.0
    pitch, roll = np.where(over, 180.0 - nose, nose), np.where(over, 180.0, 0.0)
    assert np.allclose(sagittal_pitch_deg(pitch, roll), nose)
    r = opening_response(t, pitch, roll, 0.0)
    assert r.hold_pitch_deg == pytest.approx(86.0) and r.overshoot_deg == pytest.approx(10.0)
    assert r.rise_s == pytest.approx(0.15, abs=0.011) and r.tilt_deg == pytest.approx(0.0, abs=1e-9)
    # the ZYX pitch reads the 96 deg nose as 84 deg: a dip below the hold, no overshoot at all
    assert float(pitch[(t >= 0.2) & (t <= 0.6)].max()) - 86.0 == pytest.approx(0.0)
    # a body going over on to its belly passes a nose pitch of 180 deg (-180 on the branch atan2 gives): the
    # measures follow it through, without a jump of a turn
    nose = np.where(t < 0.5, 86.0, 170.0 + 40.0 * (t - 0.5))  # 170 -> 188 deg over the hold window
    over = nose > 90.0
    pitch, roll = np.where(over, 180.0 - nose, nose), np.where(over, 180.0, 0.0)
    win = (t >= 0.5) & (t <= 0.95)
    r = opening_response(t, pitch, roll, 0.0)
    assert r.wobble_pitch_deg == pytest.approx(float(np.std(nose[win])), abs=1e-6)
    assert r.hold_pitch_deg == pytest.approx(float(np.median(nose[win])), abs=1e-6)


def test_opening_response_is_nan_where_a_window_is_empty():
    t = np.arange(0.0, 0.3, 0.01)  # no sample before the opening, none in the hold window
    r = opening_response(t, np.zeros_like(t), np.zeros_like(t), 0.0)
    assert math.isnan(r.rest_pitch_deg) and math.isnan(r.hold_pitch_deg) and math.isnan(r.rise_s)
    assert math.isnan(r.wobble_pitch_deg) and math.isnan(r.wobble_tilt_deg)
    assert r.tilt_deg == 0.0


def test_tilt_at_closing_and_the_roll_over_time():
    """A body whose tilt grows at 60 deg/s from 0.6 s (pitch 0, so tilt = roll): at closing (0.95-1.05 s) the
    median is the tilt at about 1.0 s, 24 deg; it passes 45 deg at 0.6 + 45/60 s. One that never tilts has
    neither."""
    t = np.arange(-0.5, 2.0, 0.01)
    roll = np.where(t < 0.6, 0.0, 60.0 * (t - 0.6))
    r = opening_response(t, np.zeros_like(t), roll, 0.0)
    assert r.closing_tilt_deg == pytest.approx(24.0, abs=0.31)  # the window's samples, 10 ms apart
    assert r.rolled_s == pytest.approx(0.6 + 45.0 / 60.0, abs=0.011)
    # beyond SIM_OPENING_S a roll-over does not count: the search ends where the simulation does
    late = opening_response(t, np.zeros_like(t), np.where(t < 1.2, 0.0, 200.0 * (t - 1.2)), 0.0)
    assert math.isnan(late.rolled_s) and late.closing_tilt_deg == 0.0
    flat = opening_response(t, np.zeros_like(t), np.zeros_like(t), 0.0)
    assert flat.closing_tilt_deg == 0.0 and math.isnan(flat.rolled_s)


def _recording(t, rot, gyro_rad_s):
    from landscape.analysis.physical.recording import Recording

    q = rot.as_quat()
    up = rot.inv().apply([0.0, 0.0, 1.0])
    pitch = np.degrees(np.arcsin(np.clip(-up[:, 0], -1, 1)))
    roll = np.degrees(np.arctan2(up[:, 1], up[:, 2]))
    return Recording("x", 60.0, 30.0, 1, t, pitch, roll, up[:, 2], np.zeros(1), quat_xyzw=q, gyro_t_s=t,
                     gyro_rad_s=gyro_rad_s)  # fmt: skip


def test_gyro_deviation_is_zero_when_the_fusion_follows_the_body_and_finds_a_fused_tilt():
    """Pitched 60 deg and rocking about the body's x axis: a gyro measuring that rate agrees with the recorded
    orientation to integration error; a fusion that adds 10 deg of tilt the gyro never saw is found."""
    from scipy.spatial.transform import Rotation

    t = np.arange(-0.5, 1.5, 0.004)
    angle = 0.2 * np.sin(2 * np.pi * 1.25 * t)  # +-11.5 deg at 1.25 Hz
    rate = 0.2 * 2 * np.pi * 1.25 * np.cos(2 * np.pi * 1.25 * t)
    base = Rotation.from_euler("y", 60.0, degrees=True)
    body = base * Rotation.from_rotvec(np.outer(angle, [1.0, 0.0, 0.0]))
    gyro = np.column_stack([rate, np.zeros_like(t), np.zeros_like(t)])
    assert gyro_tilt_deviation_deg(_recording(t, body, gyro), 0.0) < 0.2
    fused = base * Rotation.from_rotvec(np.outer(angle + np.radians(10.0) * (t > 0.5), [1.0, 0.0, 0.0]))
    assert gyro_tilt_deviation_deg(_recording(t, fused, gyro), 0.0) == pytest.approx(5.0, abs=0.3)
    no_gyro = _recording(t, body, gyro)
    object.__setattr__(no_gyro, "gyro_t_s", np.zeros(0))
    assert math.isnan(gyro_tilt_deviation_deg(no_gyro, 0.0))


def test_simulated_opening_of_the_symmetric_robot_holds_at_its_minimum_without_tilt():
    """Built-in robot, leg still, paper set: the body comes to rest at the landscape's metastable pitch (to the
    contact's penetration) and, mirror-symmetric, does not tilt sideways."""
    from geometry.robots import load_robot
    from landscape.minima import metastable_orientation

    r = simulated_opening(74.0, 0.0, phase=0.25, seed=1)
    want = metastable_orientation(load_robot(None), 74.0, 0.0)[0]
    assert r.hold_pitch_deg == pytest.approx(want, abs=1.0)
    assert abs(r.tilt_deg) < 0.5
    assert 0.05 < r.rise_s < 0.35


@needs_data
def test_the_protocol_fixes_the_first_attempts_phase():
    """The servo log: in every trial with the leg moving the leg command last turned positive 0.2 s (0.3 s at
    the log's 10 Hz resolution) before the first opening; with the leg still there is no lead."""
    rows = recorded_first_openings(DATA)
    leads = [o.leg_lead_s for o in rows if o.theta_l_deg > 0]
    assert len(leads) == 45 and all(round(x, 2) in (0.2, 0.3) for x in leads)
    assert sum(round(x, 2) == 0.2 for x in leads) >= 40
    assert all(math.isnan(o.leg_lead_s) and math.isnan(o.leg_swing_s) for o in rows if o.theta_l_deg == 0)
    # the body's reaction to the leg's last swing, timed by the IMU: 0.13 s before the opening (median)
    swings = [o.leg_swing_s for o in rows if o.theta_l_deg > 0]
    assert 0.11 <= float(np.median(swings)) <= 0.15 and all(0 < x <= SWING_WINDOW_S for x in swings)
    # the leg held at its first (negative) command rolls the resting body negative, the more the larger it is
    held = {
        leg: np.median([o.leg_hold_roll_deg for o in rows if o.theta_l_deg == leg]) for leg in (15, 30, 45)
    }
    assert held[45.0] < held[30.0] < held[15.0] < 0


@needs_data
def test_the_robot_rolls_over_from_the_tilt_its_hold_built_and_the_gyro_confirms_it():
    """At 60 deg with the leg at 30-45 deg the robot is tilted about 20 deg to + roll when its wings start to
    close and 9 of 10 first openings roll past 45 deg about 1.1 s after they start; with the leg still it stays
    level. Its gyro alone gives the same tilt to a few degrees where the rocking is moderate."""
    rows = recorded_first_openings(DATA)
    cell = {}
    for o in rows:
        cell.setdefault((o.theta_w_cmd_deg, o.theta_l_deg), []).append(o)
    moving = cell[(60.0, 30.0)] + cell[(60.0, 45.0)]
    assert 15.0 < np.median([o.response.closing_tilt_deg for o in moving]) < 30.0
    rolled = [o.response.rolled_s for o in moving if np.isfinite(o.response.rolled_s)]
    assert len(rolled) == 9 and all(1.0 < x < 1.25 for x in rolled)
    still = cell[(60.0, 0.0)] + cell[(75.0, 0.0)]
    assert all(abs(o.response.closing_tilt_deg) < 2.0 and math.isnan(o.response.rolled_s) for o in still)
    assert all(o.gyro_deviation_deg < 1.5 for o in still)
    assert np.median([o.gyro_deviation_deg for o in moving]) < 5.0


def test_opening_log_likelihood_prefers_the_recorded_behaviour():
    """Against a robot that rocks and rolls at closing (the 60°/30° cell's pattern), a simulated opening that does
    the same scores higher than one that sits still, and one that sits still scores higher against a still robot;
    a simulation that rolled over before the hold (nan wobble and closing tilt) is penalised, not skipped."""
    rng = np.random.default_rng(0)

    def opening(wp, wt, close, rolled):
        return OpeningResponse(0.0, 60.0, 3.0, 0.2, 8.0, wp, wt, close, rolled)

    rocking = [
        opening(2.5 + rng.normal(0, 0.3), 6.8 + rng.normal(0, 1), 21 + rng.normal(0, 5), 1.1)
        for _ in range(5)
    ]
    still = [opening(0.5, 0.3 + 0.1 * k, rng.normal(0, 0.5), math.nan) for k in range(5)]
    like_rocking, like_still = opening(2.4, 7.0, 20.0, 1.12), opening(0.4, 0.3, 0.2, math.nan)
    assert opening_log_likelihood(rocking, like_rocking) > opening_log_likelihood(rocking, like_still) + 5
    assert opening_log_likelihood(still, like_still) > opening_log_likelihood(still, like_rocking) + 5
    early = OpeningResponse(0.0, 60.0, 40.0, 0.2, 60.0, math.nan, math.nan, math.nan, 0.4)
    assert opening_log_likelihood(still, early) < opening_log_likelihood(still, like_rocking)
